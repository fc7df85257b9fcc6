"""Centralised joint-space motion control (Sects. 8.4–8.5): controllers for any :class:`Robot`.

Each controller is a small object called by :func:`controllers.simulation.simulate` every sampling
period with the arm's measurement (``meas.q``, ``meas.qd`` of an
:class:`~controllers.plants.ArmMeasurement`); its output (a torque, or a voltage for the
voltage-controlled arm) is held until the next sample. Controllers that have a state (integrators,
adaptive estimates) reset it in ``reset()``; ``log()`` returns the signals worth plotting
(:class:`~controllers.laws.ControlLaw`: each law is written once, :meth:`law`, for the Python and the
compiled loop).

* :class:`PDGravityCompensation` — u = g(q) + K_P q̃ + K_D q̃̇, Eq. (8.51), Fig. 8.20.
* :class:`ComputedTorqueFeedforward` — independent-joint P/PI servos on the motor side (Fig. 5.11)
  with decentralised feedforward and the computed-torque feedforward of the diagonal inertia and
  gravity, Fig. 8.19, for the voltage-controlled arm of Fig. 8.3.
* :class:`InverseDynamicsControl` — u = B(q) y + n(q, q̇), y = q̈_d + K_D q̃̇ + K_P q̃,
  Eqs. (8.57), (8.60), Fig. 8.22.
* :class:`RobustControl` — constant B̂ and n̂ plus the robust term w of (8.89) with a boundary layer,
  Fig. 8.23.
* :class:`AdaptivePayloadControl` — the adaptive law (8.98) with the update π̂̇ = K_π⁻¹ Yᵀσ when the
  unknown parameter is the mass of a payload at the tip, Fig. 8.26.

A *reference* is a constant posture (n,), a :class:`planners.timing.Trajectory` (its ``evaluate``) or
any callable ``t -> (q_d, q̇_d, q̈_d)``. The tracking error is q̃ = q_d − q (desired minus actual).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 8.3.3, 8.4, 8.5; Eqs. (8.51), (8.57), (8.60), (8.76)–(8.89), (8.92)–(8.98).
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from scipy.linalg import solve_continuous_lyapunov
from scipy.optimize import fsolve

from controllers.independent_joint import JointDesign, JointDrive, Transducers
from controllers.plants import ArmMeasurement
from controllers.laws import ControlLaw, Numeric, as_friction, as_gain, as_reference, diagonal_or_matrix, per_joint
from rigid_body.dynamics import gravity_torques, inertia_matrix
from rigid_body.robots import Robot, with_payload
from rigid_body.validation import as_positive, as_vector


# --------------------------------------------------------------------------------------------
# Shared pieces: references, gains, payload models
# --------------------------------------------------------------------------------------------


def mean_diagonal_inertia(robot: Robot, configurations: np.ndarray) -> np.ndarray:
    """B̄: the average over ``configurations`` (M, n) of the diagonal of B(q), a constant B̂ for (8.76)."""
    qs = np.atleast_2d(np.asarray(configurations, dtype=float))
    if qs.shape[1] != robot.nq:
        raise ValueError(f"`configurations` must have shape (M, {robot.nq}), got {qs.shape}")
    return np.mean([np.diag(inertia_matrix(robot, q)) for q in qs], axis=0)


# --------------------------------------------------------------------------------------------
# Sampled-data stability of a joint PD loop
# --------------------------------------------------------------------------------------------

def sampled_stability(robot: Robot, K_P: Any, K_D: Any, Ts: float, q: Any) -> list[str]:
    """The sampled-stability bounds that PD gains violate at q, one sentence per joint (empty: none).

    Joint i alone is a double integrator b_i q̈_i = u_i driven through a zero-order hold of period Ts;
    with u_i = −K_P,i q_i − K_D,i q̇_i its discrete poles are inside the unit circle iff

        d_i = K_D,i Ts / b_i < 2   and   K_P,i Ts < 2 K_D,i     (p_i = K_P,i Ts² / b_i < 2 d_i),

    (Jury's test on z² − (2 − d − p/2) z + 1 − d + p/2). b_i = 1/(B⁻¹(q))_ii is the inertia joint i
    sees when the other joints move freely (≤ b_ii): a light wrist has a small b_i, so the damping
    the heavy shoulder needs makes the wrist's loop diverge. Only the diagonal of the gain matrices
    is used. A URDF without rotor inertias (the Panda's) understates the real robot's b_i.

    >>> from rigid_body.robots import load
    >>> panda = load("panda")
    >>> print(sampled_stability(panda, 100.0, 20.0, 1e-3, panda.configurations["ready"])[0][:60])
    joint 7: K_D,7·Ts/b_7 = 20 × 0.001 / 0.006521 = 3.067 ≥ 2 (s
    """
    n = robot.nv
    kp = np.diag(as_gain(K_P, n, "K_P"))
    kd = np.diag(as_gain(K_D, n, "K_D"))
    q = as_vector(q, robot.nq, "q")
    b = 1.0 / np.diag(np.linalg.inv(inertia_matrix(robot, q)))
    problems = []
    for i in range(n):
        d = kd[i] * Ts / b[i]
        j = i + 1
        if d >= 2:
            problems.append(f"joint {j}: K_D,{j}·Ts/b_{j} = {kd[i]:.4g} × {Ts:.4g} / {b[i]:.4g} = {d:.4g} ≥ 2 "
                            f"(sampled damping unstable): lower K_D,{j} below {2 * b[i] / Ts:.4g} "
                            f"(≈ {0.5 * b[i] / Ts:.3g} for margin) or shorten Ts below {2 * b[i] / kd[i]:.3g} s")
        elif kp[i] * Ts >= 2 * kd[i]:
            problems.append(f"joint {j}: K_P,{j}·Ts = {kp[i] * Ts:.4g} ≥ 2 K_D,{j} = {2 * kd[i]:.4g} "
                            f"(sampled stiffness unstable): raise K_D,{j} above {kp[i] * Ts / 2:.4g}, "
                            f"lower K_P,{j} or shorten Ts")
    return problems


def sampled_error_poles(K_P: Any, K_D: Any, Ts: float) -> np.ndarray:
    """The discrete poles (n, 2) of q̃̈_i + K_D,i q̃̇_i + K_P,i q̃_i = 0 sampled at Ts, one row per joint.

    Inverse dynamics control (8.57) leaves each joint a unit double integrator q̈_i = y_i; with y_i
    from (8.60) held by a zero-order hold over Ts, the error state x = (q̃_i, q̃̇_i) evolves as
    x⁺ = (A − b k) x with A = [[1, Ts], [0, 1]], b = (Ts²/2, Ts), k = (K_P,i, K_D,i). The loop is
    stable iff both eigenvalues lie inside the unit circle. Only the diagonal of the gains is used.

    >>> bool(np.abs(sampled_error_poles(100.0, 20.0, 1e-3)).max() < 1)
    True
    """
    kp = np.atleast_1d(np.diag(np.atleast_2d(np.asarray(K_P, dtype=float))))
    kd = np.atleast_1d(np.diag(np.atleast_2d(np.asarray(K_D, dtype=float))))
    A = np.array([[1.0, Ts], [0.0, 1.0]])
    b = np.array([[0.5 * Ts**2], [Ts]])
    return np.array([np.linalg.eigvals(A - b @ np.array([[p, d]])) for p, d in zip(kp, kd)])


# --------------------------------------------------------------------------------------------
# PD control with gravity compensation (8.51)
# --------------------------------------------------------------------------------------------

class PDGravityCompensation(ControlLaw):
    """u = g(q) + K_P q̃ + K_D q̃̇ (Eq. 8.51, Fig. 8.20; with q̇_d = 0, K_D q̃̇ = −K_D q̇).

    For a set point the equilibrium q = q_d is globally asymptotically stable (Lyapunov function
    V = ½ q̇ᵀ B q̇ + ½ q̃ᵀ K_P q̃). With a moving reference this is PD + gravity tracking, whose error
    is not zero while the reference accelerates.

    Sampled at a period Ts the loop also needs, per joint, K_D,i Ts / b_i < 2 and K_P,i Ts < 2 K_D,i
    (:func:`sampled_stability`): on a real arm the light wrist bounds the damping. Per-joint gains
    for the Panda's URDF at Ts = 1 ms (no rotor inertias in it, b_7 ≈ 0.0065 kg·m²)::

        PDGravityCompensation(panda, K_P=[600, 600, 600, 600, 250, 150, 50],
                              K_D=[50, 50, 50, 50, 10, 10, 3], reference=q_d, Ts=1e-3)

    and for the UR5 (b_6 ≈ 0.017 kg·m²): K_P = [600, 600, 400, 100, 100, 50], K_D = [60, 60, 40, 10, 10, 8].

    Parameters
    ----------
    robot : the controller's model (its g(q) is compensated).
    K_P, K_D : gains (scalar, (n,) or (n, n)), positive definite.
    reference : set point (n,) or trajectory (see :func:`as_reference`).
    Ts : the sampling period the controller will run at [s], optional: when given, the gains are
        checked against :func:`sampled_stability` at the reference's start (ValueError naming the joint).
    """

    def __init__(self, robot: Robot, K_P: Any, K_D: Any, reference: Any, Ts: float | None = None):
        n = robot.nv
        self.robot, self.n, self.nq, self.nv = robot, n, robot.nq, n
        self.K_P, self.K_D = as_gain(K_P, n, "K_P"), as_gain(K_D, n, "K_D")
        self.set_gains(K_P=self.K_P, K_D=self.K_D)
        self.reference = as_reference(reference, n)
        self.reference_shapes = ((n,), (n,), (n,))
        if Ts is not None:
            problems = sampled_stability(robot, self.K_P, self.K_D, as_positive(Ts, "Ts"), self.reference(0.0)[0])
            if problems:
                raise ValueError(f"PD + gravity gains unstable at Ts = {Ts:g} s: " + "; ".join(problems))
        self._model, self._data = robot.model, robot.data   # g(q) on this thread's data (the law belongs to it)

    def diagnose(self, plant: Any, Ts: float, meas: ArmMeasurement) -> str:
        """Why the loop may have diverged (called by :func:`~controllers.simulation.simulate`)."""
        return "; ".join(sampled_stability(self.robot, self.K_P, self.K_D, Ts, meas.q))

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple) -> tuple[Any, dict]:
        """Eq. (8.51), once for both executors (:class:`~controllers.laws.ControlLaw`)."""
        q_d, qd_d, _ = ref
        e = q_d - q
        times = ops.times
        u = ops.gravity(self._model, self._data, q) + times(K["K_P"], e) + times(K["K_D"], qd_d - qd)
        return u, {"q_d": q_d, "e": e}

# --------------------------------------------------------------------------------------------
# Independent joint servos with computed-torque feedforward (Fig. 8.19 on Fig. 5.11)
# --------------------------------------------------------------------------------------------

class ComputedTorqueFeedforward(ControlLaw):
    """Independent-joint P/PI servos with decentralised and computed-torque feedforward (Fig. 8.19).

    Each motor i (angle θ_mi = k_ri q_i) has the position + velocity loops of Fig. 5.11: a position
    gain K_P, a PI velocity controller K_V (1 + s T_V)/s with T_V = T_m (the zero cancels the motor's
    pole; discretised with a zero-order hold on its input, i.e. forward-Euler integral), transducers
    k_TP, k_TV. The reference of the position loop carries the decentralised feedforward (Sect. 8.3.3)

        r = k_TP θ_md + (k_TV/K_P) θ̇_md + θ̈_md/(k_m K_P K_V),

    which inverts the servo's closed loop, and the voltage is corrected by the computed-torque
    feedforward of the diagonal inertia terms and gravity along the desired trajectory,

        τ_ff,i = (b_ii(q_d) − b̄_i) q̈_d,i + g_i(q_d),       v_ff = K_pr τ_ff,

    where b̄_i = k_ri² I_i is the constant joint-side inertia the servo was designed for and
    K_pr = R_a (k_t K_r)⁻¹ turns a joint torque into the voltage that cancels it (Fig. 8.3).

    Parameters
    ----------
    robot : the controller's model for B(q_d), g(q_d).
    reference : joint trajectory (see :func:`as_reference`).
    gear_ratio : k_r (n,).
    drives : one :class:`controllers.independent_joint.JointDrive` per joint (motor-side average
        inertia I_i, R_a, k_t, k_v): give k_m = 1/k_v, b̄_i = k_ri² I_i and K_pr = R_a/(k_t k_r).
    designs : one position + velocity :class:`~controllers.independent_joint.JointDesign` per joint
        (K_P, K_V, T_V = T_m), e.g. from ``design_position_velocity(drive, zeta, omega_n)``.
    transducers : the :class:`~controllers.independent_joint.Transducers` (k_TP, k_TV), default unit.
    feedforward : False drops the computed-torque feedforward (the independent-joint servos alone).
    """

    def __init__(self, robot: Robot, reference: Any, gear_ratio: Any, drives: Sequence[JointDrive],
                 designs: Sequence[JointDesign], transducers: Transducers = Transducers(),
                 feedforward: bool = True):
        n = robot.nv
        self.robot, self.n, self.nq, self.nv = robot, n, robot.nq, n
        if len(drives) != n or len(designs) != n:
            raise ValueError(f"`drives` and `designs` must have one entry per joint ({n}), "
                             f"got {len(drives)} and {len(designs)}")
        if any(d.K_V is None or d.T_V is None or d.K_A is not None for d in designs):
            raise ValueError("`designs` must be position + velocity designs (K_P, K_V, T_V)")
        self.reference = as_reference(reference, n)
        self.reference_shapes = ((n,), (n,), (n,))
        self.k_r = per_joint(gear_ratio, n, "gear_ratio")
        if np.any(self.k_r <= 0):
            raise ValueError(f"`gear_ratio` must be positive, got {self.k_r}")
        self.K_P = np.array([d.K_P for d in designs])
        self.K_V = np.array([d.K_V for d in designs])
        self.T_V = np.array([d.T_V for d in designs])
        self.k_m = np.array([d.k_m for d in drives])
        self.K_pr = np.array([d.Ra / d.kt for d in drives]) / self.k_r  # R_a (k_t K_r)⁻¹
        self.b_bar = self.k_r**2 * np.array([d.I for d in drives])  # joint-side constant inertia
        self.k_TP, self.k_TV = float(transducers.k_TP), float(transducers.k_TV)
        self._c_p, self._c_v = self.k_TP * self.k_r, self.k_TV * self.k_r  # constant factors of the law
        self.set_gains(K_P=self.K_P[:, None], K_V=self.K_V[:, None])
        self.feedforward = bool(feedforward)
        self._model, self._data = robot.model, robot.data
        self.reset()

    def initial_state(self) -> tuple[np.ndarray, np.ndarray]:
        """(∫ e_v dt, e_v) of the PI velocity controllers: zero at the start."""
        return (np.zeros(self.n), np.zeros(self.n))

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple, state: tuple, dt: Any) -> tuple[Any, dict, tuple]:
        """The servos and the feedforward, once for both executors: the PI integral moves by forward Euler
        with the velocity error held since the previous sample (a zero-order hold on the PI's input)."""
        K_P, K_V = K["K_P"], K["K_V"]
        integral, e_v = state
        integral = integral + dt * e_v                                  # ZOH on the PI's input
        q_d, qd_d, qdd_d = ref
        c_p, c_v = self._c_p, self._c_v                                 # k_TP k_r, k_TV k_r
        # Position-loop reference with the decentralised feedforward (motor side, θ_m = k_r q)
        r = c_p * q_d + c_v * qd_d / K_P + self.k_r * qdd_d / (self.k_m * K_P * K_V)
        e_v = K_P * (r - c_p * q) - c_v * qd
        v = K_V * (self.T_V * e_v + integral)                           # PI: K_V (1 + s T_V)/s
        tau_ff = ops.zeros(self.n)
        if self.feedforward:                                            # b_ii(q_d), g(q_d)
            B_d = ops.inertia(self._model, self._data, q_d)
            tau_ff = (ops.diag(B_d) - self.b_bar) * qdd_d + ops.gravity(self._model, self._data, q_d)
            v = v + self.K_pr * tau_ff
        return v, {"q_d": q_d, "e": q_d - q, "tau_ff": tau_ff}, (integral, e_v)

# --------------------------------------------------------------------------------------------
# Inverse dynamics control (8.57), (8.60)
# --------------------------------------------------------------------------------------------

class InverseDynamicsControl(ControlLaw):
    """u = B(q) y + n(q, q̇), y = q̈_d + K_D q̃̇ + K_P q̃ (Eqs. 8.57, 8.60, Fig. 8.22).

    n(q, q̇) = C(q, q̇) q̇ + F_v q̇ + g(q). With a perfect model the error obeys q̃̈ + K_D q̃̇ + K_P q̃ = 0.
    B y + C q̇ + g is one recursive Newton–Euler pass (RNEA at acceleration y).

    Parameters
    ----------
    robot : the controller's model (e.g. without the payload the real arm carries).
    K_P, K_D : gains, positive definite.
    reference : trajectory (see :func:`as_reference`).
    viscous_friction : F_v of the model, scalar or (n,).
    """

    def __init__(self, robot: Robot, K_P: Any, K_D: Any, reference: Any, viscous_friction: Any = 0.0):
        n = robot.nv
        self.robot, self.n, self.nq, self.nv = robot, n, robot.nq, n
        self.K_P, self.K_D = as_gain(K_P, n, "K_P"), as_gain(K_D, n, "K_D")
        self.set_gains(K_P=self.K_P, K_D=self.K_D)
        self.Fv = as_friction(viscous_friction, n)
        self.reference = as_reference(reference, n)
        self.reference_shapes = ((n,), (n,), (n,))
        self._model, self._data = robot.model, robot.data

    def diagnose(self, plant: Any, Ts: float, meas: ArmMeasurement) -> str:
        """The joints whose sampled error dynamics (:func:`sampled_error_poles`) leave the unit
        circle and what to lower (called by :func:`~controllers.simulation.simulate`); "" if none."""
        poles = np.abs(sampled_error_poles(self.K_P, self.K_D, Ts))
        kp, kd = np.diag(self.K_P), np.diag(self.K_D)
        problems = []
        for i in np.flatnonzero(poles.max(axis=1) >= 1.0):
            j = i + 1
            if kd[i] * Ts >= 2:  # the damping alone overshoots within one sample
                fix = f"lower K_D,{j} below {2 / Ts:.4g} or shorten Ts below {2 / kd[i]:.3g} s"
            else:  # K_P,i Ts² ≥ 2 K_D,i Ts: stiffness too high for the damping
                fix = f"lower K_P,{j} below {2 * kd[i] / Ts:.4g}, raise K_D,{j} or shorten Ts"
            problems.append(f"joint {j}: sampled error poles |z| = {poles[i].max():.4g} ≥ 1 "
                            f"(K_P,{j} = {kp[i]:.4g}, K_D,{j} = {kd[i]:.4g}, Ts = {Ts:.4g} s): {fix}")
        return "; ".join(problems)

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple) -> tuple[Any, dict]:
        """Eqs. (8.57), (8.60), once for both executors; B y + n is one RNEA pass at q̈ = y."""
        q_d, qd_d, qdd_d = ref
        e, ed = q_d - q, qd_d - qd
        y = qdd_d + ops.times(K["K_D"], ed) + ops.times(K["K_P"], e)                      # Eq. (8.60)
        u = ops.rnea(self._model, self._data, q, qd, y) + self.Fv * qd                  # Eq. (8.57)
        return u, {"q_d": q_d, "e": e}

def inverse_dynamics_steady_state(plant_robot: Robot, model_robot: Robot, K_P: Any, q_d: Any,
                                  q0: Any = None) -> np.ndarray:
    """The rest posture q where inverse-dynamics control with a wrong model settles on a set point.

    At rest (q̇ = q̈ = 0) the controller applies B̂(q) K_P (q_d − q) + ĝ(q) and the arm needs g(q):
    the posture solves B̂(q) K_P (q_d − q) = g(q) − ĝ(q) (solved by Newton iterations from q_d).
    """
    n = model_robot.nv
    K_P = as_gain(K_P, n, "K_P")
    q_d = as_vector(q_d, n, "q_d")
    start = q_d if q0 is None else as_vector(q0, n, "q0")

    def residual(q: np.ndarray) -> np.ndarray:
        return (inertia_matrix(model_robot, q) @ K_P @ (q_d - q)
                - gravity_torques(plant_robot, q) + gravity_torques(model_robot, q))

    q, _, _, msg = fsolve(residual, start, full_output=True, xtol=1e-13)
    if np.max(np.abs(residual(q))) > 1e-8:  # judged by the residual (fsolve's ier is pessimistic at a root)
        raise ValueError(f"no steady state of the inverse-dynamics loop found near {start}: {msg}")
    return q


# --------------------------------------------------------------------------------------------
# Robust control (8.76)–(8.89)
# --------------------------------------------------------------------------------------------

def lyapunov_matrix(K_P: Any, K_D: Any, P: Any = None) -> np.ndarray:
    """Q > 0 solving H̃ᵀ Q + Q H̃ = −P with H̃ = [[O, I], [−K_P, −K_D]] (Eq. 8.81); P defaults to I.

    >>> lyapunov_matrix(100.0, 16.0).round(7).tolist()    # one joint, Problem 8.13
    [[3.23625, 0.005], [0.005, 0.0315625]]
    """
    K_P = np.atleast_2d(np.asarray(K_P, dtype=float))
    n = K_P.shape[0]
    K_P, K_D = as_gain(K_P, n, "K_P"), as_gain(K_D, n, "K_D")
    P = np.eye(2 * n) if P is None else as_gain(P, 2 * n, "P")
    H = np.block([[np.zeros((n, n)), np.eye(n)], [-K_P, -K_D]])
    Q = solve_continuous_lyapunov(H.T, -P)
    return 0.5 * (Q + Q.T)


class RobustControl(ControlLaw):
    """u = B̂ y + n̂, y = q̈_d + K_D q̃̇ + K_P q̃ + w, with the robust term (8.89) and a boundary layer.

    z = Dᵀ Q ξ (ξ = [q̃; q̃̇], D = [O; I], Q from :func:`lyapunov_matrix`);
    w = (ρ/‖z‖) z if ‖z‖ ≥ ε, else (ρ/ε) z (Eq. 8.89, continuous within the layer of thickness ε).
    Here B̂ is a constant matrix and n̂ = F_v q̇ + g(q) (the model of Problem 8.13).

    Parameters
    ----------
    robot : the controller's model for g(q).
    B_hat : constant inertia estimate (n,) diagonal or (n, n).
    K_P, K_D : error-dynamics gains; P : the matrix of (8.81) (default I).
    rho : ρ ≥ 0, the bound of the uncertainty the term must dominate; epsilon : ε > 0.
    reference, viscous_friction : as in :class:`InverseDynamicsControl`.
    """

    def __init__(self, robot: Robot, B_hat: Any, K_P: Any, K_D: Any, reference: Any, rho: float,
                 epsilon: float, P: Any = None, viscous_friction: Any = 0.0):
        n = robot.nv
        self.robot, self.n, self.nq, self.nv = robot, n, robot.nq, n
        self.B_hat = as_gain(B_hat, n, "B_hat")
        self.K_P, self.K_D = as_gain(K_P, n, "K_P"), as_gain(K_D, n, "K_D")
        self.set_gains(K_P=self.K_P, K_D=self.K_D)
        if not (np.isfinite(rho) and rho >= 0):
            raise ValueError(f"`rho` must be non-negative, got {rho!r}")
        if not (np.isfinite(epsilon) and epsilon > 0):
            raise ValueError(f"`epsilon` must be positive, got {epsilon!r}")
        self.rho, self.epsilon = float(rho), float(epsilon)
        self.Q = lyapunov_matrix(self.K_P, self.K_D, P)
        self._DtQ = self.Q[n:, :].copy()  # Dᵀ Q
        self.Fv = as_friction(viscous_friction, n)
        self.reference = as_reference(reference, n)
        self.reference_shapes = ((n,), (n,), (n,))
        self._b_hat = diagonal_or_matrix(self.B_hat)
        self._model, self._data = robot.model, robot.data

    def robust_term(self, e: np.ndarray, ed: np.ndarray) -> np.ndarray:
        """w of Eq. (8.89) for the errors q̃, q̃̇."""
        return self._robust_term(Numeric, e, ed)

    def _robust_term(self, ops: Any, e: Any, ed: Any) -> Any:
        z = self._DtQ @ ops.vertcat(e, ed)                                              # z = Dᵀ Q ξ
        return (self.rho / ops.fmax(ops.norm(z), self.epsilon)) * z                     # Eq. (8.89), boundary layer

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple) -> tuple[Any, dict]:
        """Eqs. (8.76), (8.89), once for both executors (Q of (8.81) is held at this controller's value)."""
        q_d, qd_d, qdd_d = ref
        e, ed = q_d - q, qd_d - qd
        w = self._robust_term(ops, e, ed)
        y = qdd_d + ops.times(K["K_D"], ed) + ops.times(K["K_P"], e) + w
        u = ops.times(self._b_hat, y) + self.Fv * qd + ops.gravity(self._model, self._data, q)
        return u, {"q_d": q_d, "e": e, "w": w}

# --------------------------------------------------------------------------------------------
# Adaptive control on the payload mass (8.92)–(8.98)
# --------------------------------------------------------------------------------------------

class AdaptivePayloadControl(ControlLaw):
    """Adaptive control (Fig. 8.26) estimating the mass m_L of a point payload at ``frame``.

    With q̇_r = q̇_d + Λ q̃, q̈_r = q̈_d + Λ q̃̇ and σ = q̇_r − q̇ (Eq. 8.92), the model is linear in
    m_L: B(q) q̈_r + C(q, q̇) q̇_r + g(q) = τ₀ + m_L y_L, where τ₀ is the known arm's (without payload)
    and y_L the payload's column of the regressor. The control law (8.98) and update law are

        u = τ₀ + m̂_L y_L + F_v q̇_r + K_D σ,        m̂̇_L = k_π⁻¹ y_Lᵀ σ,

    the update integrated by forward Euler over the sampling period. ``adaptation_gain`` is k_π⁻¹
    (the manual's k_π = 0.005 must divide, not multiply: erratum of Problem 8.14).

    y_L is computed exactly from two Pinocchio models (the known arm and the arm with a unit payload);
    C is the Christoffel matrix, so y_L equals the manual's a₁y'₁₁ + a₂y'₁₃, a₁y'₂₁ + a₂y'₂₃.

    Parameters
    ----------
    robot : the known arm (without the unknown payload).
    K_D, Lambda : gains, positive definite.
    adaptation_gain : k_π⁻¹ > 0 [kg/(N·m·rad/s·s)].
    reference : trajectory (see :func:`as_reference`).
    viscous_friction : F_v of the model; frame : where the payload sits (default the end effector).
    mass0 : the initial estimate m̂_L(0).
    """

    def __init__(self, robot: Robot, K_D: Any, Lambda: Any, adaptation_gain: float, reference: Any,
                 viscous_friction: Any = 0.0, frame: str | int | None = None, mass0: float = 0.0):
        n = robot.nv
        self.robot, self.n, self.nq, self.nv = robot, n, robot.nq, n
        self.unit = with_payload(robot, 1.0, frame)
        self.K_D, self.Lambda = as_gain(K_D, n, "K_D"), as_gain(Lambda, n, "Lambda")
        if not (np.isfinite(adaptation_gain) and adaptation_gain > 0):
            raise ValueError(f"`adaptation_gain` must be positive (it is k_pi^-1), got {adaptation_gain!r}")
        self.gain = float(adaptation_gain)
        if not np.isfinite(mass0):
            raise ValueError(f"`mass0` must be finite, got {mass0!r}")
        self.mass0 = float(mass0)
        self.Fv = as_friction(viscous_friction, n)
        self.set_gains(K_D=self.K_D, Lambda=self.Lambda, adaptation_gain=self.gain)
        self.reference = as_reference(reference, n)
        self.reference_shapes = ((n,), (n,), (n,))
        self._models = (robot.model, robot.data, self.unit.model, self.unit.data)
        self.reset()

    scalars = ("m_hat",)

    def initial_state(self) -> tuple[float, float]:
        """(m̂_L, m̂̇_L) at the start: the initial estimate, at rest."""
        return (self.mass0, 0.0)

    @property
    def mass(self) -> float:
        """The current estimate m̂_L [kg]."""
        return self._state[0]

    def regressor(self, q: np.ndarray, qd: np.ndarray, qd_r: np.ndarray,
                  qdd_r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(τ₀, y_L): B q̈_r + C(q, q̇) q̇_r + g of the known arm, and the payload column (per kg)."""
        return self._regressor(Numeric, q, qd, qd_r, qdd_r)

    def _regressor(self, ops: Any, q: Any, qd: Any, qd_r: Any, qdd_r: Any) -> tuple[Any, Any]:
        model, data, unit_model, unit_data = self._models
        tau0 = ops.reference_torque(model, data, q, qd, qd_r, qdd_r)
        return tau0, ops.reference_torque(unit_model, unit_data, q, qd, qd_r, qdd_r) - tau0

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple, state: tuple, dt: Any) -> tuple[Any, dict, tuple]:
        """Eqs. (8.92), (8.98) and the update law, once for both executors: the state (m̂_L, m̂̇_L) moves by
        forward Euler over the sampling period."""
        mass, rate = state
        mass = mass + dt * rate                                                          # forward Euler of m̂̇_L
        q_d, qd_d, qdd_d = ref
        e, ed = q_d - q, qd_d - qd
        qd_r = qd_d + ops.times(K["Lambda"], e)                                           # Eq. (8.92)
        qdd_r = qdd_d + ops.times(K["Lambda"], ed)
        sigma = qd_r - qd
        tau0, y_L = self._regressor(ops, q, qd, qd_r, qdd_r)
        u = tau0 + mass * y_L + self.Fv * qd_r + ops.times(K["K_D"], sigma)               # Eq. (8.98)
        rate = K["adaptation_gain"] * ops.dot(y_L, sigma)                                 # π̂̇ = K_π⁻¹ Yᵀ σ
        return u, {"q_d": q_d, "e": e, "m_hat": mass}, (mass, rate)
