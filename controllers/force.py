"""Force control: tasks where the end effector touches the environment (Ch. 9; Problem 6.3).

* :class:`HybridForceMotionControl` — hybrid force/motion control on a compliant environment
  (Sect. 9.7.1): inverse dynamics with α = S_v α_ν + Ĉ' S_f f_λ (9.77), the PI velocity law (9.80) on
  ν = S_v† v_e and the PD force law (9.81)/(9.84) on λ = S_f† h_e.
* :class:`AdmittanceControl` — the impedance realised through an inner position loop (admittance,
  Fig. 9.7): the compliant frame from M_d z̈ + K_D ż + K_P z = h_e, tracked by inverse dynamics.
* :class:`ForceWithInnerLoop` — force control with an inner position loop (Fig. 9.8; with a PI C_F
  and a motion reference, parallel force/position control, Sect. 9.4.3) or an inner velocity loop
  (Fig. 9.9).
* Compliance control is :class:`~controllers.operational_space.OperationalPDGravity` in contact and
  impedance control :class:`~controllers.operational_space.OperationalInverseDynamics` with a desired
  inertia (and the sensed wrench).
* :class:`PegInHoleController` — the peg-in-hole task of 6.3 (flow chart of Fig. S6.2 as a state
  machine) on :class:`HybridForceMotionControl`: one law per phase from the selection matrices of
  :data:`PEG_VELOCITY_AXES` (pure motion while approaching and descending, the push λ_d = −f_push along
  y while searching, λ_d = 0 along x while inserting).
* :class:`PegInHoleTask` — the data of 6.3; :func:`run_peg_in_hole` runs it on an
  :class:`~controllers.plants.ArmInContact` against a :class:`~controllers.environment.SurfaceWithHole`.

The closed forms of these laws:

* :func:`compliance_equilibrium` — the rest of compliance control (PD + gravity) against an elastic
  environment, Eqs. (9.22)–(9.23).
* :func:`inner_position_loop_equilibrium` — the rest of force control with an inner position loop
  (Fig. 9.8) and a proportional force regulator C_F (Problem 9.4).
* :func:`impedance_parameters`, :func:`force_loop_parameters`, :func:`pi_velocity_parameters` — ω_n, ζ
  of one axis of impedance control (free or against a spring), of the force loop of hybrid control
  with an estimated compliance (Eqs. (9.84)–(9.85)), and of the PI velocity loop (9.80).
* :func:`constrained_stiffness` — K' = S_f (S_fᵀ C S_f)⁻¹ S_fᵀ, Eq. (9.70) (= P_f K, Problem 9.6).
* :func:`fit_second_order` — ω_n, ζ measured on a transient from rest (the check of the simulations).

The controllers read the sensed wrench ``meas.wrench`` (h_e, exerted by the end effector on the
environment, Sect. 9.1) of the :class:`~controllers.plants.ArmMeasurement`.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 6.3,
8.5.2, 9.1–9.7, Eqs. (9.20)–(9.23), (9.41), (9.55), (9.70), (9.77)–(9.85), Figs. 9.8–9.9; solution
manual, Problems 6.3, 9.2–9.10.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np
from scipy.optimize import least_squares

from controllers.environment import SurfaceWithHole
from controllers.laws import (ControlLaw, Numeric, SingularTask, as_friction, as_gain, as_reference, check_redundancy,
                              joined_reference, nonnegative)
from controllers.plants import ArmInContact, ArmMeasurement
from controllers.simulation import LoggedController, SimulationResult, simulate
from planners.timing import quintic_law
from rigid_body.robots import Robot
from rigid_body.rotations import wrap_angle
from rigid_body.task_space import (selection_matrices, selection_projection, selection_pseudo_inverse,
                                  singular_task)
from rigid_body.validation import as_matrix, as_positive, as_scalar, as_square_matrix, as_vector


PEG_STATES = ("approach", "descend", "search", "insert", "done")
PEG_AXES = ("x", "y", "rz")          # the planar task (x, y, φ): rows (0, 1, 5) of the twist
PEG_VELOCITY_AXES = {"approach": PEG_AXES, "descend": PEG_AXES, "search": ("x", "rz"),
                     "insert": ("y", "rz"), "done": ("y", "rz")}


_ZERO3 = np.zeros(3)          # ẍ_d of the constant-speed phases (shared, read-only)
_ZERO3.setflags(write=False)


class PegInHoleController(LoggedController):
    """The flow chart of Fig. S6.2 as a state machine driving a planar arm (x, y, φ task), each phase
    one :class:`HybridForceMotionControl` with its selection matrices (:data:`PEG_VELOCITY_AXES`).

    States: ``approach`` (fast pure motion to (x_H, Δy)), ``descend`` (slow motion along −y until
    y < −Δy, or a contact force |f_y| > ε), ``search`` (x motion-controlled, sliding at ``v_search``
    and inverting when |x − x_H| > Δx; y force-controlled to λ_d = −f_push; until |f_y| < ε),
    ``insert`` (y motion-controlled down to −insert_depth, x force-controlled to λ_d = 0 — the walls of
    the hole guide the peg —, the peg orientation held), ``done``.

    Every phase follows a position reference x_d(t) in its motion-controlled components: ν_d = S_v† ẋ_d,
    and the integral of the PI velocity law (9.80) starts at the position error S_v†(x_d − x_e), so it
    stays the position error. Gains: the velocity loop ë + K_Pν ė + K_Iν e = 0 with ω_n = ``omega_motion``,
    ζ = 1; the force loop (9.81) with ω_n = ``omega_force``, ζ = 1, on the estimated surface
    ``stiffness`` k̂ [N/m] (Ĉ = I/k̂: S_f†, S_v† select the axes).
    """

    def __init__(self, robot: Robot, task: PegInHoleTask, stiffness: float = 2e4, omega_motion: float = 30.0,
                 omega_force: float = 20.0, frame: str | int | None = None, viscous_friction: Any = 0.0):
        self.robot, self.task, self.frame = robot, task, frame
        self._fid = robot.frame(frame)
        k = as_positive(stiffness, "stiffness")
        w_v, w_f = as_positive(omega_motion, "omega_motion"), as_positive(omega_force, "omega_force")
        self._nu_d, self._nud_d = np.zeros(3), np.zeros(3)     # the active phase's (ẋ_d, ẍ_d), full (x, y, φ)
        self._rates = {name: np.array(rate) for name, rate in         # the constant ẋ_d of the slow phases
                       (("down", (0.0, -task.v_slow, 0.0)), ("right", (task.v_search, 0.0, 0.0)),
                        ("left", (-task.v_search, 0.0, 0.0)), ("rest", (0.0, 0.0, 0.0)))}
        for rate in self._rates.values():
            rate.setflags(write=False)
        self.laws: dict[tuple[str, ...], HybridForceMotionControl] = {}
        for axes in set(PEG_VELOCITY_AXES.values()):
            S_f, S_v = selection_matrices(axes, axes=PEG_AXES)
            pick = S_v.T                                        # S_v† for axis-aligned S_v, Ĉ = I/k̂
            push = -task.f_push if "y" not in axes else 0.0    # λ_d: push down while searching, 0 along x
            self.laws[axes] = HybridForceMotionControl(
                robot, S_f, S_v, np.full(S_f.shape[1], push),
                lambda t, pick=pick: (pick.dot(self._nu_d), pick.dot(self._nud_d)),
                2.0 * w_v, w_v**2, 2.0 * w_f, w_f**2, compliance=np.eye(3) / k, rows=(0, 1, 5), frame=frame,
                viscous_friction=viscous_friction)
        self.n = robot.nv
        self._contact = next(iter(self.laws.values())).task
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.state = "approach"
        self.transitions: list[tuple[float, str]] = [(0.0, "approach")]
        self.inversions = 0
        self._law: Any = None
        self._active: HybridForceMotionControl | None = None
        self._t0 = 0.0
        self._y0 = 0.0
        self._x_ref = 0.0
        self._direction = 1.0
        self._last_t = 0.0

    def _switch(self, t: float, state: str) -> None:
        self.state = state
        if state != "done":
            self._t0 = t
        self.transitions.append((t, state))

    def _reference(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x_d, ẋ_d, ẍ_d) of the current phase (motion-controlled components; the others are unused)."""
        task, zero = self.task, _ZERO3
        if self.state == "approach":
            return self._law(t)
        rates = self._rates
        if self.state == "descend":
            return np.array([task.x_H, self._y0 - task.v_slow * (t - self._t0), task.phi]), rates["down"], zero
        if self.state == "search":
            return (np.array([self._x_ref, x[1], task.phi]), rates["right" if self._direction > 0.0 else "left"],
                    zero)
        y_d = max(self._y0 - task.v_slow * (t - self._t0), -task.insert_depth)       # insert, done
        return np.array([x[0], y_d, task.phi]), rates["down" if y_d > -task.insert_depth else "rest"], zero

    def __call__(self, t: float, meas: ArmMeasurement) -> np.ndarray:
        task = self.task
        f = meas.wrench[:2]                                  # f: force of the peg on the environment (h_e)
        q, qd = meas.q, meas.qd
        contact = self._contact                              # every phase's law has the same task rows
        J, Jdot_qd, T = contact.state(q, qd)                 # one kinematics pass for the phase and its law
        x = np.array([T[0, 3], T[1, 3], math.atan2(T[1, 0], T[0, 0])])
        state = self.state
        if self._law is None:                       # plan the fast approach from where the arm is
            self._law = quintic_law(x, np.array([task.x_H, task.dy, task.phi]), t + task.T_approach, t_i=t)
        if self.state == "approach" and t >= self._law.t_f and np.linalg.norm(x[:2] - self._law(t)[0][:2]) < 1e-3:
            self._switch(t, "descend")
            self._y0 = x[1]
        if self.state == "descend":
            if abs(f[1]) > task.eps:
                self._switch(t, "search")
                self._x_ref = x[0]
            elif x[1] < -task.dy:
                self._switch(t, "insert")
                self._y0 = x[1]
        if self.state == "search":
            if abs(f[1]) < task.eps:
                self._switch(t, "insert")
                self._y0 = x[1]
            else:
                beyond = self._x_ref - task.x_H
                if abs(beyond) > task.dx and (beyond > 0.0) == (self._direction > 0.0):     # past Δx, moving away
                    self._direction = -self._direction
                    self.inversions += 1
                self._x_ref += self._direction * task.v_search * (t - self._last_t)
        if self.state == "insert" and x[1] < -task.insert_depth + 1e-3:
            self._switch(t, "done")                 # the insertion's reference and law go on to rest
        self._last_t = t
        x_d, self._nu_d, self._nud_d = self._reference(t, x)
        law = self.laws[PEG_VELOCITY_AXES[self.state]]
        if law is not self._active or self.state != state and self.state != "done":   # a new phase
            e = x_d - x
            e[2] = wrap_angle(e[2])
            law.reset(motion_error=law.S_v_dagger @ e)
            self._active = law
        u = law.control(t, q, qd, contact.wrench(meas), J, Jdot_qd, T, log=False)
        self.record(x_e=x, x_d=x_d, f=f, state=float(PEG_STATES.index(self.state)))
        return u


@dataclass(frozen=True)
class PegInHoleTask:
    """Data of 6.3: estimated hole abscissa ``x_H``, approach height ``dy`` (Δy), search limit ``dx``
    (Δx), force threshold ``eps`` (ε) [N], pushing force ``f_push`` [N] during the search, insertion
    depth ``insert_depth`` [m], speeds ``v_slow`` (descent, insertion) and ``v_search`` [m/s], duration
    of the fast approach ``T_approach`` [s], peg orientation ``phi`` (vertical, pointing down)."""

    x_H: float
    dy: float = 0.02
    dx: float = 0.03
    eps: float = 3.0
    f_push: float = 10.0
    insert_depth: float = 0.03
    v_slow: float = 0.02
    v_search: float = 0.02
    T_approach: float = 1.0
    phi: float = -np.pi / 2

    def __post_init__(self) -> None:
        checked = {"x_H": as_scalar(self.x_H, "x_H"), "phi": as_scalar(self.phi, "phi")}
        for name in ("dy", "dx", "eps", "f_push", "insert_depth", "v_slow", "v_search", "T_approach"):
            checked[name] = as_positive(getattr(self, name), name)
        for name, value in checked.items():
            object.__setattr__(self, name, value)


def run_peg_in_hole(robot: Robot, environment: SurfaceWithHole, task: PegInHoleTask, q0: Any,
                    duration: float, Ts: float = 1e-3, h: float = 1e-3,
                    viscous_friction: Any = 0.0) -> tuple[SimulationResult, PegInHoleController]:
    """Simulate the peg-in-hole state machine on ``robot`` against ``environment`` from ``q0``.

    Returns the :class:`~controllers.simulation.SimulationResult` (signals ``x_e``, ``x_d``, ``f``,
    ``state``) and the controller (its ``transitions`` and ``inversions``).
    """
    plant = ArmInContact(robot, environment, viscous_friction)
    controller = PegInHoleController(robot, task, stiffness=environment.stiffness, viscous_friction=viscous_friction)
    res = simulate(plant, controller, (0.0, duration), plant.initial_state(q0), h=h, Ts=Ts)
    return res, controller


# --------------------------------------------------------------------------------------------
# Closed forms: equilibria and closed-loop dynamics (Sects. 9.2–9.7)
# --------------------------------------------------------------------------------------------

def compliance_equilibrium(K_P: Any, K: Any, dx_rd: Any) -> tuple[np.ndarray, np.ndarray]:
    """(h_e, dx_{e,d}) at the rest of compliance control: h_e = (I + K K_P⁻¹)⁻¹ K dx_{r,d} (9.22) and
    dx_{e,d} = K_P⁻¹ h_e (9.23), from h_e = K_P dx_{e,d} (9.20) and h_e = K dx_{r,e} (9.21).

    K_P : (m, m) active stiffness (invertible); K : (m, m) environment stiffness (may be singular);
    dx_rd : (m,) displacement of the rest position of the environment w.r.t. the desired frame.
    """
    dx = as_vector(dx_rd, None, "dx_rd")
    m = dx.size
    K_P, K = as_square_matrix(K_P, m, "K_P"), as_square_matrix(K, m, "K")
    if np.linalg.cond(K_P) > 1e12:
        raise ValueError("`K_P` must be invertible (an active stiffness in every direction)")
    K_Pinv = np.linalg.inv(K_P)
    A = np.eye(m) + K @ K_Pinv
    if np.linalg.cond(A) > 1e12:
        raise ValueError("I + K K_P⁻¹ is singular (K K_P⁻¹ has the eigenvalue −1): no unique rest; `K` must be a "
                         "stiffness (positive semi-definite) and `K_P` positive definite")
    h_e = np.linalg.solve(A, K @ dx)  # Eq. (9.22)
    return h_e, K_Pinv @ h_e                                  # Eq. (9.23)


def inner_position_loop_equilibrium(x_d: Any, x_r: Any, K: Any, C_F: Any, f_d: Any) -> np.ndarray:
    """x_e at the rest of force control with inner position loop (Fig. 9.8), proportional C_F:
    x_e = x_d + C_F (K (x_r − x_e) + f_d) (Problem 9.4), i.e. x_e = (I + C_F K)⁻¹ (x_d + C_F (K x_r + f_d)).

    With integral action in C_F the rest is instead f_e = K (x_e − x_r) = f_d.
    """
    x_d = as_vector(x_d, None, "x_d")
    m = x_d.size
    x_r, f_d = as_vector(x_r, m, "x_r"), as_vector(f_d, m, "f_d")
    K, C_F = as_square_matrix(K, m, "K"), as_square_matrix(C_F, m, "C_F")
    A = np.eye(m) + C_F @ K
    if np.linalg.cond(A) > 1e12:
        raise ValueError(f"I + C_F K is singular (C_F K has the eigenvalue −1: {np.round(np.linalg.eigvals(C_F @ K), 6)}): "
                         "the loop has no unique rest position; change `C_F` (a proportional force gain, positive "
                         "definite) or `K` (the environment stiffness, positive semi-definite)")
    return np.linalg.solve(A, x_d + C_F @ (K @ x_r + f_d))


def impedance_parameters(m_d: float, k_D: float, k_P: float, k_env: float = 0.0) -> tuple[float, float]:
    """ω_n = √((k_P + k)/m_d), ζ = k_D / (2 √(m_d (k_P + k))) of one axis of impedance control,
    m_d ẍ + k_D ẋ + (k_P + k) x = k_P x_d + k x_r (Problem 9.3): k = 0 along a free direction, the
    environment stiffness along a constrained one."""
    m = as_positive(m_d, "m_d")
    k = as_positive(k_P, "k_P") + as_positive(k_env, "k_env", allow_zero=True)
    return float(np.sqrt(k / m)), float(as_positive(k_D, "k_D", allow_zero=True) / (2.0 * np.sqrt(m * k)))


def force_loop_parameters(k_D: float, k_P: float, l_f: float = 1.0) -> tuple[float, float]:
    """ω_n = √(l_f k_P), ζ = k_D / (2 √(l_f k_P)) of the force loop of hybrid force/motion control
    (9.84) on a compliant environment: λ̈ + k_D λ̇ + l_f k_P λ = l_f k_P λ_d, with l_f = ĉ/c the ratio of
    the estimated to the true compliance (the rate λ̇ estimated with the same ĉ, Problem 9.10).
    l_f = 1: the known-stiffness loop λ̈ + k_D λ̇ + k_P λ = k_P λ_d (9.81)."""
    k = as_positive(l_f, "l_f") * as_positive(k_P, "k_P")
    return float(np.sqrt(k)), float(as_positive(k_D, "k_D", allow_zero=True) / (2.0 * np.sqrt(k)))


def pi_velocity_parameters(k_P: float, k_I: float) -> tuple[float, float]:
    """ω_n = √k_I, ζ = k_P / (2 √k_I) of the velocity loop with the PI law (9.80): ν̇ = α_ν gives
    ë + k_P ė + k_I e = 0 for e = ∫(ν_d − ν)."""
    k_I = as_positive(k_I, "k_I")
    return float(np.sqrt(k_I)), float(as_positive(k_P, "k_P", allow_zero=True) / (2.0 * np.sqrt(k_I)))


def constrained_stiffness(S_f: Any, C: Any) -> np.ndarray:
    """K' = S_f (S_fᵀ C S_f)⁻¹ S_fᵀ, Eq. (9.70): the stiffness seen along the force-controlled
    subspace; = P_f K with P_f = S_f S_f† (weight C = K⁻¹), Problem 9.6."""
    S = np.asarray(S_f, dtype=float)
    S = S.reshape(-1, 1) if S.ndim == 1 else S
    C = as_matrix(C, (S.shape[0],) * 2, "C")
    A = S.T @ C @ S
    if np.linalg.cond(A) > 1e12:
        raise ValueError("S_fᵀ C S_f is singular: `C` must see every column of `S_f`")
    return S @ np.linalg.solve(A, S.T)


def second_order_free_response(t: Any, omega_n: float, zeta: float) -> np.ndarray:
    """x(t)/x(0) of ẍ + 2ζω_n ẋ + ω_n² x = 0 from rest (ẋ(0) = 0), any ζ > 0 (ζ ≠ 1 exactly):
    x = (s₂ e^{s₁t} − s₁ e^{s₂t})/(s₂ − s₁), s₁,₂ = −ζω_n ± ω_n √(ζ² − 1)."""
    t = np.asarray(t, dtype=float)
    root = omega_n * np.sqrt(complex(zeta * zeta - 1.0))
    if abs(root) < 1e-9 * omega_n:  # critically damped
        return (1.0 + omega_n * t) * np.exp(-omega_n * t)
    s1, s2 = -zeta * omega_n + root, -zeta * omega_n - root
    return np.real((s2 * np.exp(s1 * t) - s1 * np.exp(s2 * t)) / (s2 - s1))


def fit_second_order(t: Any, y: Any, y_final: float, guess: tuple[float, float] = (5.0, 0.7)) -> tuple[float, float]:
    """(ω_n, ζ) measured on a transient that starts at rest at y(t₀) and settles at ``y_final``:
    the least-squares fit of (y − y_final)/(y(t₀) − y_final) by :func:`second_order_free_response`.

    ValueError when the transient is too small to measure (|y(t₀) − y_final| ≈ 0).
    """
    t = as_vector(t, None, "t")
    y = as_vector(y, t.size, "y")
    amplitude = y[0] - float(y_final)
    if abs(amplitude) < 1e-12 * max(1.0, abs(float(y_final))):
        raise ValueError("`y` has no transient to measure: y(t0) equals y_final")
    z, tau = (y - y_final) / amplitude, t - t[0]

    def residual(p: np.ndarray) -> np.ndarray:
        return second_order_free_response(tau, p[0], p[1]) - z

    fit = least_squares(residual, np.asarray(guess, dtype=float), bounds=([1e-6, 1e-3], [np.inf, 50.0]),
                        xtol=1e-14, ftol=1e-14)
    return float(fit.x[0]), float(fit.x[1])


# --------------------------------------------------------------------------------------------
# The laws of Chapter 9 on any arm: inverse dynamics in the task rows of one frame
# --------------------------------------------------------------------------------------------

class _ContactTask:
    """The rows of one frame's twist/wrench a force law works in: (J, J̇q̇, T_e) in one pass, the
    sensed wrench in those rows, and the inverse-dynamics step u = B y + n + F_v q̇ + Jᵀ h_e with
    y = J†(a − J̇ q̇) (+ null-space damping −K_N q̇ for a redundant arm)."""

    def __init__(self, robot: Robot, rows: Sequence[int] | None, frame: str | int | None,
                 viscous_friction: Any, null_space_damping: Any):
        self.robot, self.n = robot, robot.nv
        self.fid = robot.frame(frame)
        self._model, self._data = robot.model, robot.data     # this thread's data (the law belongs to it)
        self.rows = np.arange(6) if rows is None else np.asarray(rows, dtype=int).ravel()
        if (self.rows.size == 0 or len(set(self.rows.tolist())) != self.rows.size
                or np.any((self.rows < 0) | (self.rows > 5))):
            raise ValueError(f"`rows` must be distinct twist components in 0..5, got {rows!r}")
        self.m = self.rows.size
        first = int(self.rows[0])
        if np.array_equal(self.rows, np.arange(first, first + self.m)):     # contiguous rows: views, not copies
            self._pick: Any = slice(first, first + self.m)
        else:
            self._pick = self.rows
        check_redundancy(self.m, self.n)
        self.Fv = as_friction(viscous_friction, self.n)
        self.K_N = nonnegative(null_space_damping, self.n, "null_space_damping")
        self.redundant = self.m < self.n
        self._viscous = bool(np.any(self.Fv))          # F_v q̇ only when there is friction

    def state(self, q: Any, qd: Any, ops: Any = Numeric) -> tuple[Any, Any, Any]:
        """(J, J̇q̇, T_e) of the task rows, for either executor (``ops``)."""
        st = ops.frame_state(self._model, self._data, self.fid, q, qd)
        pick = ops.index(self._pick)
        return st.J[pick, :], st.Jdot_qd[pick], st.T

    def wrench(self, meas: Any) -> np.ndarray:
        w = getattr(meas, "wrench", None)
        if w is None:
            raise ValueError("a force controller needs a force sensor: the plant's measurement has no "
                             "`wrench` (use controllers.plants.ArmInContact)")
        return w[self._pick]

    def torques(self, ops: Any, q: Any, qd: Any, J: Any, a: Any, h: Any) -> Any:
        """u = B(q) y + n(q, q̇) + Jᵀ h_e with v̇_e = a (inverse dynamics in the task space), y = J†(a)
        (+ (I − J†J) y_0, y_0 = −K_N q̇ for a redundant task)."""
        y = ops.solve_task(J, a)
        if self.redundant:
            y0 = -self.K_N * qd
            y = y + (y0 - ops.solve_task(J, J @ y0))
        u = ops.rnea(self._model, self._data, q, qd, y)
        if self._viscous:
            u = u + self.Fv * qd
        return u + J.T @ h


def _velocity_reference(reference: Any, k: int) -> Callable[[float], tuple[np.ndarray, np.ndarray]]:
    """``t -> (ν_d, ν̇_d)`` from a constant ν_d (k,) or such a callable (checked at t = 0)."""
    if not callable(reference):
        nu = as_vector(reference, k, "velocity_reference").copy()
        zero = np.zeros(k)
        return lambda t: (nu, zero)
    try:
        nu, nud = reference(0.0)
        as_vector(np.reshape(nu, -1), k, "ν_d")
        as_vector(np.reshape(nud, -1), k, "ν̇_d")
    except (TypeError, ValueError) as err:
        raise ValueError(f"`velocity_reference` must give (ν_d ({k},), ν̇_d ({k},)) at t = 0: {err}") from None
    shape = (k,)

    def sampled(t: float) -> tuple[np.ndarray, np.ndarray]:
        nu, nud = reference(t)
        if (type(nu) is np.ndarray and type(nud) is np.ndarray and nu.shape == shape == nud.shape
                and nu.dtype == nud.dtype == np.float64):
            return nu, nud                      # already (k,) floats: as they are
        return np.asarray(nu, dtype=float).reshape(k), np.asarray(nud, dtype=float).reshape(k)

    return sampled


def _compliance_and_stiffness(compliance: Any, stiffness: Any, m: int) -> tuple[np.ndarray, np.ndarray]:
    """(Ĉ, K̂) of hybrid force/motion control: Ĉ (m, m) finite, symmetric, positive semi-definite; K̂ given, or
    Ĉ⁻¹ when Ĉ is invertible — a rigid direction (Ĉ rank-deficient, the book's Ĉ = R diag(0, c) Rᵀ, or Ĉ = 0)
    has no Ĉ⁻¹: ValueError asking for ``stiffness``."""
    C = as_matrix(compliance, (m, m), "compliance")
    if np.abs(C - C.T).max() > 1e-9 * max(1.0, np.abs(C).max()) or np.linalg.eigvalsh(0.5 * (C + C.T)).min() < \
            -1e-12 * max(1.0, np.abs(C).max()):
        raise ValueError(f"`compliance` Ĉ must be symmetric positive semi-definite (a compliance), got {C.tolist()}")
    if stiffness is not None:
        return C, as_matrix(stiffness, (m, m), "stiffness")
    sigma = np.linalg.svd(C, compute_uv=False)
    if not sigma[-1] > 1e-12 * sigma[0]:
        rank = int(np.sum(sigma > 1e-12 * sigma[0])) if sigma[0] > 0 else 0
        raise ValueError(f"`compliance` Ĉ is singular (rank {rank} < {m}: the environment is rigid along some "
                         "directions): Ĉ⁻¹, the default weight K̂ of S_v†, does not exist; pass `stiffness=` K̂ "
                         "(e.g. the stiffness of the free directions, as in Problem 9.10)")
    return C, np.linalg.inv(C)


def _weighted_selection(S: np.ndarray, W: np.ndarray, weight: str, columns: str, kind: str) -> np.ndarray:
    """S† = (Sᵀ W S)⁻¹ Sᵀ W (9.55), the error naming the weight ``weight`` when Sᵀ W S is singular."""
    try:
        return selection_pseudo_inverse(S, W)
    except ValueError:
        raise ValueError(f"`{weight}` gives a singular {columns}ᵀ W {columns} (W = the {weight}): it must be positive "
                         f"along every {kind} direction (the columns of `{columns}`)"
                         + (", e.g. Ĉ = R_c diag(0, c) R_cᵀ with c > 0 along the constrained direction"
                            if weight == "compliance" else "")) from None


class HybridForceMotionControl(ControlLaw):
    """Hybrid force/motion control on a compliant environment (Sect. 9.7.1, Example 9.4).

    Inverse dynamics u = B y + n + Jᵀ h_e, y = J⁻¹(α − J̇ q̇) makes v̇_e = α, and
    α = S_v α_ν + Ĉ' S_f f_λ (9.77) with
    α_ν = ν̇_d + K_Pν (ν_d − ν) + K_Iν ∫(ν_d − ν) (9.80), ν = S_v† v_e (weight K̂), and
    f_λ = λ̈_d + K_Dλ (λ̇_d − λ̇) + K_Pλ (λ_d − λ) (9.81), λ = S_f† h_e (weight Ĉ) from the force sensor
    and λ̇ = (S_fᵀ Ĉ' S_f)⁻¹ S_fᵀ v_e from the motion (the deflection rate over the estimated compliance).
    With the true compliance the loops are ν̇ = α_ν and λ̈ = f_λ; with an estimate ĉ = l_f c the force loop
    is λ̈ + K_Dλ λ̇ + l_f K_Pλ λ = l_f K_Pλ λ_d ((9.84)–(9.85), Problem 9.10;
    :func:`controllers.force.force_loop_parameters`).

    Parameters
    ----------
    robot : the controller's model.
    S_f, S_v : (m, k_f), (m, m − k_f) selection matrices in the base frame (rows of the task twist),
        e.g. from :func:`rigid_body.task_space.selection_matrices` with the constraint frame's rotation.
    force_reference : λ_d: a constant (k_f,), or a trajectory/callable ``t -> (λ_d, λ̇_d, λ̈_d)``.
    velocity_reference : ν_d: a constant or a callable ``t -> (ν_d, ν̇_d)`` ((m − k_f,) each).
    K_Pnu, K_Inu, K_Dlambda, K_Plambda : gains (scalars, vectors or matrices), K_Pν, K_Iν, K_Pλ positive definite.
    compliance : Ĉ (m, m), the estimated environment compliance: weight of S_f† (9.55).
    stiffness : K̂ (m, m), weight of S_v† (default Ĉ⁻¹).
    compliance_prime : Ĉ' (m, m), the compliance of the force-controlled subspace (default (I − P_v) Ĉ).
    rows, frame : the task rows of the frame's twist (default all six) and the frame (default ee).
    viscous_friction, null_space_damping : as in :class:`~controllers.operational_space.OperationalInverseDynamics`.
    """

    def __init__(self, robot: Robot, S_f: Any, S_v: Any, force_reference: Any, velocity_reference: Any,
                 K_Pnu: Any, K_Inu: Any, K_Dlambda: Any, K_Plambda: Any, compliance: Any, stiffness: Any = None,
                 compliance_prime: Any = None, rows: Sequence[int] | None = None, frame: str | int | None = None,
                 viscous_friction: Any = 0.0, null_space_damping: Any = 0.0):
        self.task = task = _ContactTask(robot, rows, frame, viscous_friction, null_space_damping)
        self.nq, self.nv = robot.nq, robot.nv
        m = task.m
        S_f, S_v = np.asarray(S_f, dtype=float), np.asarray(S_v, dtype=float)
        S_f, S_v = (S.reshape(-1, 1) if S.ndim == 1 else S for S in (S_f, S_v))
        if S_f.ndim != 2 or S_v.ndim != 2 or S_f.shape[0] != m or S_v.shape[0] != m or S_f.shape[1] + S_v.shape[1] != m:
            raise ValueError(f"`S_f`, `S_v` must be (m, k) and (m, m − k) with m = {m} task rows, "
                             f"got {S_f.shape} and {S_v.shape}")
        if S_v.shape[1] == 0:
            raise ValueError("`S_v` must have at least one column (a motion-controlled direction)")
        if S_f.size and np.abs(S_f.T @ S_v).max() > 1e-9:
            raise ValueError("`S_f` and `S_v` must be reciprocal: S_fᵀ S_v = 0")
        self.S_f, self.S_v = S_f, S_v
        k_f, k_v = S_f.shape[1], S_v.shape[1]
        C, K = _compliance_and_stiffness(compliance, stiffness, m)
        self.S_v_dagger = _weighted_selection(S_v, K, "stiffness", "S_v", "motion-controlled")     # ν = S_v† v_e
        self.K_Pnu, self.K_Inu = as_gain(K_Pnu, k_v, "K_Pnu"), as_gain(K_Inu, k_v, "K_Inu")
        self.velocity_reference = _velocity_reference(velocity_reference, k_v)
        self.motion_only = k_f == 0          # S_v = I: inverse dynamics with the PI velocity law (9.80) alone
        if not self.motion_only:
            self.S_f_dagger = _weighted_selection(S_f, C, "compliance", "S_f", "force-controlled")   # λ = S_f† h_e (9.55)
            P_v = selection_projection(S_v, K)
            C1 = ((np.eye(m) - P_v) @ C if compliance_prime is None
                  else as_matrix(compliance_prime, (m, m), "compliance_prime"))
            self.C_prime_S_f = C1 @ S_f
            A = S_f.T @ C1 @ S_f
            if np.linalg.cond(A) > 1e12:
                raise ValueError(f"`compliance_prime` Ĉ' gives a singular S_fᵀ Ĉ' S_f (condition {np.linalg.cond(A):.3g}): "
                                 "Ĉ' must be positive along every force-controlled direction (the columns of `S_f`)"
                                 + ("" if compliance_prime is not None else "; pass `compliance_prime`"))
            self.G_f = np.linalg.solve(A, S_f.T)     # λ̇ = G_f v_e
            self.K_Plambda = as_gain(K_Plambda, k_f, "K_Plambda")
            K_D = np.asarray(K_Dlambda, dtype=float)
            self.K_Dlambda = as_gain(K_D, k_f, "K_Dlambda") if np.any(K_D) else np.zeros((k_f, k_f))
            self.force_reference = as_reference(force_reference, k_f, "force_reference")
            self.set_gains(K_Pnu=self.K_Pnu, K_Inu=self.K_Inu, K_Plambda=self.K_Plambda, K_Dlambda=self.K_Dlambda)
            self.reference = joined_reference((self.velocity_reference, (0, 1)), (self.force_reference, (0, 1, 2)))
            self.reference_shapes = ((k_v,), (k_v,), (k_f,), (k_f,), (k_f,))
        else:
            self.set_gains(K_Pnu=self.K_Pnu, K_Inu=self.K_Inu)
            self.reference, self.reference_shapes = self.velocity_reference, ((k_v,), (k_v,))
        self._M = self._fold(Numeric, self.gains)
        self.reset()

    measurements = (("wrench", 6),)

    def _fold(self, ops: Any, K: dict) -> Any:
        """The constant products of (9.77), (9.80), (9.81) in one matrix M: α = M z with
        z = (ν̇_d, ν_d − ν, ∫(ν_d − ν), v_e, λ, λ̈_d, λ̇_d, λ_d) (the last five with a force-controlled
        subspace), M = [S_v, S_v K_Pν, S_v K_Iν, −Ĉ'S_f K_Dλ G_f, −Ĉ'S_f K_Pλ, Ĉ'S_f, Ĉ'S_f K_Dλ, Ĉ'S_f K_Pλ]
        (``K`` the gains as matrices; the numeric law folds them once, at construction)."""
        S_v = self.S_v
        blocks = [S_v, S_v @ K["K_Pnu"], S_v @ K["K_Inu"]]
        if not self.motion_only:
            CS = self.C_prime_S_f
            CS_D, CS_P = CS @ K["K_Dlambda"], CS @ K["K_Plambda"]
            blocks += [-CS_D @ self.G_f, -CS_P, CS, CS_D, CS_P]
        return ops.horzcat(*blocks)

    def initial_state(self) -> tuple[np.ndarray]:
        """(∫(ν_d − ν),): the integral of the PI velocity law (9.80), zero at the start."""
        return (np.zeros(self.S_v.shape[1]),)

    def reset(self, motion_error: Any = None) -> None:
        """Restart the law; the integral ∫(ν_d − ν) of (9.80) starts at ``motion_error`` (k_v,) (default 0):
        when ν_d is the rate of a position reference, the position error along S_v at the start."""
        super().reset()
        if motion_error is not None:
            self._state = (as_vector(motion_error, self.S_v.shape[1], "motion_error").copy(),)

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple, wrench: Any, state: tuple,
            dt: Any) -> tuple[Any, dict, tuple]:
        """Eqs. (9.77), (9.80), (9.81), once for both executors: the integral ∫(ν_d − ν) moves by forward
        Euler, h_e is the sensed wrench in the task rows."""
        J, Jdot_qd, T_e = self.task.state(q, qd, ops)
        return self._control(ops, K, q, qd, wrench[ops.index(self.task._pick)], J, Jdot_qd, T_e, ref, state, dt)

    def _control(self, ops: Any, K: dict, q: Any, qd: Any, h: Any, J: Any, Jdot_qd: Any, T_e: Any, ref: tuple,
                 state: tuple, dt: Any) -> tuple[Any, dict, tuple]:
        v_e = J @ qd
        nu = self.S_v_dagger @ v_e
        nu_d, nud_d = ref[0], ref[1]
        e_nu = nu_d - nu
        integral = state[0] + dt * e_nu                                                       # ∫(ν_d − ν)
        M = self._fold(ops, K) if ops.symbolic else self._M
        if self.motion_only:                                                                   # (9.80)
            alpha = M @ ops.vertcat(nud_d, e_nu, integral)
            signals = {"nu": nu, "nu_d": nu_d}
        else:
            lam = self.S_f_dagger @ h
            lam_d, lamd_d, lamdd_d = ref[2], ref[3], ref[4]
            alpha = M @ ops.vertcat(nud_d, e_nu, integral, v_e, lam, lamdd_d, lamd_d, lam_d)   # (9.77)–(9.81)
            signals = {"nu": nu, "nu_d": nu_d, "lam": lam, "lam_d": lam_d}
        u = self.task.torques(ops, q, qd, J, alpha - Jdot_qd, h)
        signals.update(h_e=h, p_e=ops.copy(T_e[:3, 3]))
        return u, signals, (integral,)

    def control(self, t: float, q: np.ndarray, qd: np.ndarray, h: np.ndarray, J: np.ndarray,
                Jdot_qd: np.ndarray, T_e: np.ndarray, log: bool = True) -> np.ndarray:
        """The law at (q, q̇) given the sensed wrench h (task rows) and ``task.state(q, q̇)`` (J, J̇q̇, T_e):
        for a caller that already has them (:class:`PegInHoleController`, which keeps its own log: ``log=False``
        skips this law's)."""
        dt = 0.0 if self._t_last is None else t - self._t_last
        self._t_last = t
        try:
            u, signals, self._state = self._control(Numeric, self._K, q, qd, h, J, Jdot_qd, T_e, self.reference(t),
                                                    self._state, dt)
        except SingularTask:
            raise singular_task(f"at t = {t:.6g} s, q = {q}") from None
        if log:
            self.record(**signals)
        return u


FORCE_LOOPS = ("position", "velocity")


class ForceWithInnerLoop(ControlLaw):
    """Force control through a motion loop closed by inverse dynamics (Sect. 9.4), x_F = C_F (f_d − f_e):

    * ``inner="position"`` (Fig. 9.8): y = J⁻¹ M_d⁻¹(−K_D ẋ_e + K_P (x_d + x_F − x_e) − M_d J̇ q̇), at rest
      x_e = x_d + C_F (K (x_r − x_e) + f_d) (Problem 9.4), f_e = f_d only with integral action in C_F.
      With a PI C_F this is parallel force/position control (Sect. 9.4.3): the force loop prevails
      along the constrained directions (f_e = f_d) and x̃ → 0 along the free ones;
    * ``inner="velocity"`` (Fig. 9.9): y = J⁻¹ M_d⁻¹(−K_D ẋ_e + K_P x_F − M_d J̇ q̇): f_e = f_d at rest
      already with a proportional C_F;
    with u = B y + n + Jᵀ h_e. C_F = K_F + K_I/s (``K_I=0``: proportional). Positions are the frame's
    origin in the ``rows`` components (default x, y, z); ``reference`` x_d (constant or trajectory),
    ``force_reference`` f_d (constant or ``t -> (f_d, ḟ_d, f̈_d)``).
    """

    def __init__(self, robot: Robot, K_P: Any, K_D: Any, inertia: Any, K_F: Any, reference: Any,
                 force_reference: Any, K_I: Any = 0.0, inner: str = "position", rows: Sequence[int] = (0, 1, 2),
                 frame: str | int | None = None, viscous_friction: Any = 0.0, null_space_damping: Any = 0.0):
        if inner not in FORCE_LOOPS:
            raise ValueError(f"`inner` must be one of {FORCE_LOOPS}, got {inner!r}")
        self.inner = inner
        self.task = task = _ContactTask(robot, rows, frame, viscous_friction, null_space_damping)
        self.nq, self.nv = robot.nq, robot.nv
        if np.any(task.rows > 2):
            raise ValueError(f"`rows` must select position components 0..2, got {rows!r}")
        m = task.m
        self.K_P, self.K_D = as_gain(K_P, m, "K_P"), as_gain(K_D, m, "K_D")
        self.M_d_inv = np.linalg.inv(as_gain(inertia, m, "inertia"))
        self.K_F = as_gain(K_F, m, "K_F")
        K_I = np.asarray(K_I, dtype=float)
        self.K_I = as_gain(K_I, m, "K_I") if np.any(K_I) else None
        gains = {"K_P": self.K_P, "K_D": self.K_D, "K_F": self.K_F}
        self.set_gains(**gains, **({} if self.K_I is None else {"K_I": self.K_I}))
        self.motion_reference = as_reference(reference, m)
        self.force_reference = as_reference(force_reference, m, "force_reference")
        self.reference = joined_reference((self.motion_reference, (0,)), (self.force_reference, (0,)))
        self.reference_shapes = ((m,), (m,))
        self.reset()

    measurements = (("wrench", 6),)

    def initial_state(self) -> tuple[np.ndarray] | None:
        """(∫(f_d − f_e),) of the PI regulator C_F (with ``K_I``), zero at the start; None without."""
        return None if self.K_I is None else (np.zeros(self.task.m),)

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple, wrench: Any, state: tuple | None = None,
            dt: Any = None) -> tuple:
        """Eq. (9.41) and the inner position or velocity loop, once for both executors (the integral of C_F
        by forward Euler)."""
        task = self.task
        f = wrench[ops.index(task._pick)]
        J, Jdot_qd, T_e = task.state(q, qd, ops)
        x_e, xd_e = T_e[ops.index(task.rows), 3], J @ qd
        x_d, f_d = ref
        x_F = ops.times(K["K_F"], f_d - f)                                                 # (9.41)
        if state is not None:
            integral = state[0] + dt * (f_d - f)
            x_F = x_F + ops.times(K["K_I"], integral)
        w = ops.times(K["K_P"], x_d + x_F - x_e) if self.inner == "position" else ops.times(K["K_P"], x_F)
        a = self.M_d_inv @ (w - ops.times(K["K_D"], xd_e))
        u = task.torques(ops, q, qd, J, a - Jdot_qd, f)
        signals = {"x_e": x_e, "x_d": x_d, "x_F": x_F, "f_e": f, "f_d": f_d}
        return (u, signals) if state is None else (u, signals, (integral,))


class AdmittanceControl(ControlLaw):
    """Impedance through an inner position loop — admittance control (Sect. 9.3, Fig. 9.7).

    The compliant frame x_t = x_d − z obeys the desired impedance driven by the sensed force,
    M_d z̈ + K_D z ż + K_P z = h_e (integrated at the controller's samples, semi-implicit Euler), and
    a stiff inverse-dynamics position loop tracks it:
    u = B y + n + Jᵀ h_e, y = J⁻¹(ẍ_t + K_Dp (ẋ_t − ẋ_e) + K_Pp (x_t − x_e) − J̇ q̇).
    With a fast inner loop the end effector shows the impedance M_d, K_D, K_P (Eqs. 9.30–9.31)
    while the motion loop rejects the arm's own disturbances (e.g. friction) with K_Pp, K_Dp.

    Position task: the ``rows`` (0..2) of the frame's origin; ``reference`` x_d (constant or trajectory).
    """

    def __init__(self, robot: Robot, inertia: Any, K_D: Any, K_P: Any, K_Dp: Any, K_Pp: Any, reference: Any,
                 rows: Sequence[int] = (0, 1, 2), frame: str | int | None = None, viscous_friction: Any = 0.0,
                 null_space_damping: Any = 0.0):
        self.task = task = _ContactTask(robot, rows, frame, viscous_friction, null_space_damping)
        self.nq, self.nv = robot.nq, robot.nv
        if np.any(task.rows > 2):
            raise ValueError(f"`rows` must select position components 0..2, got {rows!r}")
        m = task.m
        self.M_d_inv = np.linalg.inv(as_gain(inertia, m, "inertia"))
        self.K_D, self.K_P = as_gain(K_D, m, "K_D"), as_gain(K_P, m, "K_P")
        self.K_Dp, self.K_Pp = as_gain(K_Dp, m, "K_Dp"), as_gain(K_Pp, m, "K_Pp")
        self.set_gains(K_D=self.K_D, K_P=self.K_P, K_Dp=self.K_Dp, K_Pp=self.K_Pp)
        self.reference = as_reference(reference, m)
        self.reference_shapes = ((m,), (m,), (m,))
        self.reset()

    measurements = (("wrench", 6),)

    def initial_state(self) -> tuple[np.ndarray, np.ndarray]:
        """(z, ż) of the compliant frame, at rest at the start."""
        return (np.zeros(self.task.m), np.zeros(self.task.m))

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple, wrench: Any, state: tuple,
            dt: Any) -> tuple[Any, dict, tuple]:
        """The admittance (semi-implicit Euler over the sampling period) and the inner inverse-dynamics position
        loop, once for both executors."""
        task = self.task
        h = wrench[ops.index(task._pick)]
        z, zd = state
        zdd = self.M_d_inv @ (h - ops.times(K["K_D"], zd) - ops.times(K["K_P"], z))     # the admittance
        zd = zd + dt * zdd
        z = z + dt * zd
        zdd = self.M_d_inv @ (h - ops.times(K["K_D"], zd) - ops.times(K["K_P"], z))
        x_d, xd_d, xdd_d = ref
        x_t, xd_t, xdd_t = x_d - z, xd_d - zd, xdd_d - zdd                                # the compliant frame
        J, Jdot_qd, T_e = task.state(q, qd, ops)
        x_e = T_e[ops.index(task.rows), 3]
        a = xdd_t + ops.times(K["K_Dp"], xd_t - J @ qd) + ops.times(K["K_Pp"], x_t - x_e)
        u = task.torques(ops, q, qd, J, a - Jdot_qd, h)
        return u, {"x_e": x_e, "x_d": x_d, "x_t": x_t, "e": x_d - x_e, "h_e": h}, (z, zd)
