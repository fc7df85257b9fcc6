"""Motion control of wheeled mobile robots (Sect. 11.6–11.7): tracking, regulation, odometry.

The plants (unicycle, bicycle, chained form, mobile manipulator) live in :mod:`controllers.plants`; their
``measure`` returns named fields (:class:`~controllers.plants.Posture`, ...), never a slice of the state.
Controllers (``__call__(t, measurement) -> u``) derive from
:class:`~controllers.simulation.LoggedController`:

* trajectory tracking of the unicycle: :class:`ApproximateLinearizationTracking` (11.64)–(11.67),
  :class:`NonlinearTracking` (11.68)–(11.70), :class:`InputOutputTracking` (point B ahead, (11.72)–(11.74));
* :class:`ChainedFormTracking` (Problem 11.14) and :class:`BicycleInputOutputTracking` (Problem 11.15);
* regulation: :class:`CartesianRegulator` (11.78)–(11.79) with the backward-motion variant (S11.6) of
  Problem 11.16, :class:`PostureRegulator` (11.80)–(11.82);
* odometric localisation (11.83)–(11.85) — Euler, second-order Runge–Kutta and exact — in
  :func:`odometry_step`, and the block :class:`Odometry`, which reads the wheel encoders of a
  ``UnicyclePlant(odometer=True)`` and outputs the estimate; at its own period it feeds a regulator
  through ``Chain(ZeroOrderHold(Odometry(q0), T_s), PostureRegulator(..., feedback="estimate"),
  name="estimate")`` (Problem 11.18: the regulator only sees the dead-reckoning estimate);
* :class:`MobileManipulatorHold`: the base follows given (v, ω) while the arm holds its end-effector
  position (task-space control through the whole model's Jacobian times the input map).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 11.6–11.7,
Eqs. (11.56)–(11.85); solution manual, Problems 11.14–11.18.
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from controllers.plants import Posture
from controllers.simulation import LoggedController
from planners.wheeled import ReferenceSample
from rigid_body.robots import Robot
from rigid_body.rotations import wrap_angle
from rigid_body.task_space import damped_least_squares_inverse, frame_state
from rigid_body.validation import as_positive, as_scalar, as_vector
from rigid_body.wheeled import front_wheel_point, front_wheel_point_matrix, mobile_manipulator_input_matrix, unicycle_arc

__all__ = [
    "tracking_error", "ApproximateLinearizationTracking", "NonlinearTracking", "InputOutputTracking",
    "ChainedFormTracking", "BicycleInputOutputTracking", "BicycleTracking",
    "CartesianRegulator", "PostureRegulator", "ODOMETRY_METHODS", "odometry_step", "Odometry",
    "MobileManipulatorHold",
]


def _wrap(a: float) -> float:
    return float(wrap_angle(a))


def _pose(m: Any) -> tuple[float, float, float]:
    """(x, y, θ) of a measurement: a :class:`~controllers.plants.Posture`-like object or an array (x, y, θ, …);
    ValueError when it is not finite (a NaN posture would give a NaN command)."""
    x, y, th = (m.x, m.y, m.theta) if hasattr(m, "theta") else (float(m[0]), float(m[1]), float(m[2]))
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(th)):
        raise ValueError(f"the measured posture (x, y, θ) must be finite, got {(x, y, th)}")
    return x, y, th


def _fed_back(measurement: Any, feedback: str | None) -> tuple[float, float, float]:
    """The posture a law acts on: the measurement itself, or its entry ``feedback`` (e.g. the odometric
    ``estimate`` added by a :class:`~controllers.simulation.Chain`)."""
    return _pose(measurement if feedback is None else getattr(measurement, feedback))


# --------------------------------------------------------------------------------------------
# Trajectory tracking of the unicycle, Sect. 11.6.1
# --------------------------------------------------------------------------------------------

def tracking_error(ref: ReferenceSample, x: float, y: float, theta: float) -> np.ndarray:
    """e = [e1, e2, e3] (11.65): the position error in the robot frame and the heading error θ_d − θ (wrapped)."""
    dx, dy = ref.p[0] - x, ref.p[1] - y
    c, s = np.cos(theta), np.sin(theta)
    return np.array([c * dx + s * dy, -s * dx + c * dy, _wrap(ref.theta - theta)])


class _Tracking(LoggedController):
    """Common part of the unicycle trackers: the reference and the logged signals."""

    def __init__(self, reference: Callable[[float], ReferenceSample]):
        self.reference = reference

    def _record(self, e: np.ndarray, point_error: float | None = None) -> None:
        """Log e (11.65), position_error ‖p_d − p‖ and point_error, the error of the point the law controls."""
        d = float(np.hypot(e[0], e[1]))
        self.record(e=e, position_error=d, point_error=d if point_error is None else point_error)

    def _reference_and_error(self, t: float, measurement: Any) -> tuple[ReferenceSample, np.ndarray]:
        """The reference sample at t and the error (11.65) of the robot's posture, logged."""
        ref = self.reference(t)
        e = tracking_error(ref, *_pose(measurement))
        self._record(e)
        return ref, e


class ApproximateLinearizationTracking(_Tracking):
    """Tracking by approximate linearisation (11.66)–(11.67): v = v_d cos e3 + k1 e1, ω = ω_d + k2 e2 + k3 e3.

    With k1 = k3 = 2ζa and k2 = (a² − ω_d²)/v_d (a > 0, 0 < ζ < 1; needs v_d ≠ 0) the linearised error
    dynamics, for constant v_d and ω_d, have the poles −2ζa and −ζa ± ja√(1 − ζ²).
    """

    def __init__(self, reference: Callable[[float], ReferenceSample], a: float, zeta: float):
        super().__init__(reference)
        self.a, self.zeta = as_positive(a, "a"), as_positive(zeta, "zeta")

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        ref, e = self._reference_and_error(t, measurement)
        if abs(ref.v) < 1e-9:
            raise ValueError(f"approximate linearisation needs v_d ≠ 0 (gain k2 = (a² − ω_d²)/v_d), v_d = 0 at t = {t:g} s")
        k1 = k3 = 2 * self.zeta * self.a
        k2 = (self.a**2 - ref.omega**2) / ref.v
        return np.array([ref.v * np.cos(e[2]) + k1 * e[0], ref.omega + k2 * e[1] + k3 * e[2]])


AT_REST = ("raise", "stop")


class NonlinearTracking(_Tracking):
    """Nonlinear tracking (11.68)–(11.70): v = v_d cos e3 + k1 e1, ω = ω_d + k2 v_d (sin e3/e3) e2 + k3 e3,

    with k1 = k3 = 2ζ √(ω_d² + b v_d²) and k2 = b > 0 (asymptotic stability when v_d, ω_d do not both vanish).
    Where the reference is at rest (v_d = ω_d = 0) every gain vanishes and the law commands u = 0 whatever the
    error: ``at_rest="raise"`` (default) makes that a ValueError when the error is not zero (use a regulator,
    e.g. :class:`PostureRegulator`, to reach a posture); ``at_rest="stop"`` accepts it (the robot stops where it
    is while the reference rests, e.g. at the ends of a path timed from and to rest).
    """

    def __init__(self, reference: Callable[[float], ReferenceSample], zeta: float, b: float, at_rest: str = "raise"):
        super().__init__(reference)
        self.zeta, self.b = as_positive(zeta, "zeta"), as_positive(b, "b")
        if at_rest not in AT_REST:
            raise ValueError(f"`at_rest` must be one of {AT_REST}, got {at_rest!r}")
        self.at_rest = at_rest

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        ref, e = self._reference_and_error(t, measurement)
        if self.at_rest == "raise" and abs(ref.v) < 1e-12 and abs(ref.omega) < 1e-12 and np.any(np.abs(e) > 1e-12):
            raise ValueError(f"nonlinear tracking needs v_d, ω_d not both zero (its gains k1 = k3 = 2ζ√(ω_d² + b v_d²) "
                             f"and k2 v_d vanish): the reference is at rest at t = {t:g} s with the error e = "
                             f"{np.round(e, 6).tolist()}, which the law would leave uncorrected; use a regulator "
                             "(PostureRegulator) for a posture, or at_rest='stop'")
        k1 = k3 = 2 * self.zeta * np.sqrt(ref.omega**2 + self.b * ref.v**2)
        sinc = np.sinc(e[2] / np.pi)  # sin(e3)/e3, 1 at e3 = 0
        return np.array([ref.v * np.cos(e[2]) + k1 * e[0], ref.omega + self.b * ref.v * sinc * e[1] + k3 * e[2]])


class InputOutputTracking(_Tracking):
    """Input–output linearisation of the point B at distance b ahead (11.72)–(11.74).

    y_B = p + b[cos θ, sin θ]; u = ẏ_d + K(y_d − y_B); v = cos θ u1 + sin θ u2, ω = (−sin θ u1 + cos θ u2)/b.
    Point B tracks y_d = p_d(t) exponentially; the heading is not controlled.
    """

    def __init__(self, reference: Callable[[float], ReferenceSample], b: float, k1: float, k2: float | None = None):
        super().__init__(reference)
        self.b = as_positive(b, "b")
        self.k = np.array([as_positive(k1, "k1"), as_positive(k1 if k2 is None else k2, "k2")])

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        ref = self.reference(t)
        x, y, th = _pose(measurement)
        c, s = np.cos(th), np.sin(th)
        err = ref.p - np.array([x + self.b * c, y + self.b * s])
        self._record(tracking_error(ref, x, y, th), float(np.hypot(err[0], err[1])))
        u = ref.pd + self.k * err
        return np.array([c * u[0] + s * u[1], (-s * u[0] + c * u[1]) / self.b])


class ChainedFormTracking(LoggedController):
    """Linearisation-based tracking of the (2, 3) chained form (Problem 11.14).

    e = z_d − z, u = v_d − v with u1 = −k1 e1, u2 = −k2 e2 − (k3/v1d) e3 ⇒ v = v_d + [k1 e1, k2 e2 + k3 e3/v1d];
    the linearised closed loop has p(λ) = (λ + k1)(λ² + k2 λ + k3). ``reference(t) -> (z_d (3,), v_d (2,))``.
    """

    def __init__(self, reference: Callable[[float], tuple[np.ndarray, np.ndarray]], k1: float, k2: float, k3: float):
        self.reference = reference
        self.k = (as_positive(k1, "k1"), as_positive(k2, "k2"), as_positive(k3, "k3"))

    def __call__(self, t: float, z: np.ndarray) -> np.ndarray:
        z_d, v_d = self.reference(t)
        if abs(v_d[0]) < 1e-9:
            raise ValueError(f"the chained-form tracker needs v1d ≠ 0 (gain k3/v1d), v1d = 0 at t = {t:g} s")
        e = np.asarray(z_d, dtype=float) - z
        self.record(e=e)
        k1, k2, k3 = self.k
        return np.array([v_d[0] + k1 * e[0], v_d[1] + k2 * e[1] + k3 * e[2] / v_d[0]])


class BicycleInputOutputTracking(LoggedController):
    """Input–output linearisation of the rear-drive bicycle (Problem 11.15).

    Output y = front_wheel_point(q, ℓ, b); [v, ω] = T(θ, φ)⁻¹ u with u = ẏ_d + K(y_d − y) (det T = b/cos φ,
    |φ| < π/2). ``reference(t) -> (y_d (2,), ẏ_d (2,))``. θ and φ are not controlled (zero dynamics).
    """

    def __init__(self, ell: float, b: float, reference: Callable[[float], tuple[np.ndarray, np.ndarray]],
                 k1: float, k2: float | None = None):
        self.ell, self.b = as_positive(ell, "ell"), float(b)
        if self.b == 0:
            raise ValueError("`b` must be non-zero (T(θ, φ) is singular for b = 0)")
        self.reference = reference
        self.k = np.array([as_positive(k1, "k1"), as_positive(k1 if k2 is None else k2, "k2")])

    def __call__(self, t: float, m: Any) -> np.ndarray:
        if abs(np.cos(m.phi)) < 1e-9:
            raise ValueError(f"steering angle |φ| = π/2 at t = {t:g} s: T(θ, φ) is singular")
        y_d, yd_d = self.reference(t)
        q = np.array([m.x, m.y, m.theta, m.phi])
        e = np.asarray(y_d, dtype=float) - front_wheel_point(q, self.ell, self.b)
        self.record(e=e)
        u = np.asarray(yd_d, dtype=float) + self.k * e
        return np.linalg.solve(front_wheel_point_matrix(m.theta, m.phi, self.ell, self.b), u)


class BicycleTracking(LoggedController):
    """A rear-drive bicycle (11.19) tracking a unicycle reference: a cascade.

    An outer unicycle tracker (e.g. :class:`NonlinearTracking`) acting on the rear-axle posture gives (v, ω);
    the steering angle realising ω, φ_d = atan(ℓ ω v / (v² + ε)) (= atan(ℓω/v) away from v = 0, → 0 when the car
    stops), clipped to ±φ_max, is tracked by the steering rate φ̇ = k_φ (φ_d − φ).
    """

    def __init__(self, tracker: Any, ell: float, phi_max: float, k_phi: float, eps: float = 1e-3):
        self.tracker, self.ell = tracker, as_positive(ell, "ell")
        self.phi_max, self.k_phi = as_positive(phi_max, "phi_max"), as_positive(k_phi, "k_phi")
        self.eps = as_positive(eps, "eps")

    def reset(self) -> None:
        super().reset()
        if hasattr(self.tracker, "reset"):
            self.tracker.reset()

    def __call__(self, t: float, m: Any) -> np.ndarray:
        v, omega = self.tracker(t, m)
        phi_d = float(np.clip(np.arctan(self.ell * omega * v / (v * v + self.eps)), -self.phi_max, self.phi_max))
        self.record(**(self.tracker.log() if hasattr(self.tracker, "log") else {}), phi_d=phi_d)
        return np.array([v, self.k_phi * (phi_d - m.phi)])


# --------------------------------------------------------------------------------------------
# Regulation, Sect. 11.6.2
# --------------------------------------------------------------------------------------------

class CartesianRegulator(LoggedController):
    """Cartesian regulation to the origin (11.78)–(11.79): v = k1 nᵀe_p = −k1(x cos θ + y sin θ), ω = k2 γ.

    γ = Atan2(y, x) − θ + π (pointing error, wrapped). ``backward=True`` is the modification (S11.6) of
    Problem 11.16: ω = k2(γ − sign(γ)π) when nᵀe_p ≤ 0, so the robot aligns with −e_p and backs to the goal.
    ``feedback``: the measurement's entry holding the posture (None: the measurement itself). At the goal
    (ρ = ‖p‖ ≤ ``tolerance``, default exactly 0) γ is undefined and the command is zero.
    """

    def __init__(self, k1: float, k2: float, backward: bool = False, feedback: str | None = None,
                 tolerance: float = 0.0):
        self.k1, self.k2, self.backward = as_positive(k1, "k1"), as_positive(k2, "k2"), bool(backward)
        self.feedback = feedback
        self.tolerance = as_positive(tolerance, "tolerance", allow_zero=True)

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        x, y, th = _fed_back(measurement, self.feedback)
        if math.hypot(x, y) <= self.tolerance:  # at the goal: γ = Atan2(0, 0) − θ + π is undefined; nothing to do
            self.record(gamma=0.0)
            return np.zeros(2)
        n_e = -(x * np.cos(th) + y * np.sin(th))  # nᵀ e_p, e_p = −p
        gamma = _wrap(np.arctan2(y, x) - th + np.pi)
        self.record(gamma=gamma)
        if self.backward and n_e <= 0:
            gamma = gamma - np.sign(gamma) * np.pi  # (S11.6)
        return np.array([self.k1 * n_e, self.k2 * gamma])


class PostureRegulator(LoggedController):
    """Posture regulation to (0, 0, 0) in polar coordinates (11.80)–(11.82).

    ρ = √(x² + y²), γ = Atan2(y, x) − θ + π, δ = γ + θ (wrapped);
    v = k1 ρ cos γ,  ω = k2 γ + k1 (sin γ cos γ / γ)(γ + k3 δ).
    ``feedback``: the measurement's entry holding the posture (e.g. ``"estimate"`` behind an
    :class:`Odometry` block in a :class:`~controllers.simulation.Chain`; None: the measurement itself).
    At ρ ≤ ``tolerance`` (default exactly 0) γ and δ are undefined: the robot turns in place to θ = 0,
    v = 0, ω = −k2 θ (wrapped) — zero at the goal (0, 0, 0), where (11.82) would spin it for ever.
    """

    def __init__(self, k1: float, k2: float, k3: float, feedback: str | None = None, tolerance: float = 0.0):
        self.k1, self.k2, self.k3 = as_positive(k1, "k1"), as_positive(k2, "k2"), as_positive(k3, "k3")
        self.feedback = feedback
        self.tolerance = as_positive(tolerance, "tolerance", allow_zero=True)

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        x, y, th = _fed_back(measurement, self.feedback)
        rho = np.hypot(x, y)
        if rho <= self.tolerance:               # ρ = 0: γ, δ undefined (Atan2(0, 0)); v = k1 ρ cos γ ≈ 0 anyway
            heading = _wrap(th)                 # turn in place to θ = 0: zero at the goal (0, 0, 0)
            self.record(rho=rho, gamma=0.0, delta=-heading)
            return np.array([0.0, -self.k2 * heading])
        gamma = _wrap(np.arctan2(y, x) - th + np.pi)
        delta = _wrap(gamma + th)
        self.record(rho=rho, gamma=gamma, delta=delta)
        sinc = np.sinc(gamma / np.pi)  # sin γ / γ
        return np.array([self.k1 * rho * np.cos(gamma),
                         self.k2 * gamma + self.k1 * sinc * np.cos(gamma) * (gamma + self.k3 * delta)])


# --------------------------------------------------------------------------------------------
# Odometric localisation, Sect. 11.7
# --------------------------------------------------------------------------------------------

ODOMETRY_METHODS = ("euler", "runge_kutta", "exact")


def odometry_step(q: Any, v: float, omega: float, Ts: float, method: str = "runge_kutta") -> np.ndarray:
    """One odometric prediction q_{k+1} from q_k under constant (v_k, ω_k) over T_s.

    "euler" (11.83): x + v T_s cos θ; "runge_kutta" (11.84): x + v T_s cos(θ + ω T_s/2);
    "exact" (11.85): x + (v/ω)(sin θ_{k+1} − sin θ_k), y − (v/ω)(cos θ_{k+1} − cos θ_k) — the Runge–Kutta
    formula when |ω T_s| < 1e-9 (the limit ω → 0); θ_{k+1} = θ_k + ω T_s in all three.
    """
    q = as_vector(q, 3, "q")
    Ts = as_positive(Ts, "Ts")
    v, omega = as_scalar(v, "v"), as_scalar(omega, "omega")
    if method not in ODOMETRY_METHODS:
        raise ValueError(f"`method` must be one of {ODOMETRY_METHODS}, got {method!r}")
    return _odometry_step(q, v, omega, Ts, method)


def _odometry_step(q: np.ndarray, v: float, omega: float, Ts: float, method: str) -> np.ndarray:
    if method == "exact":
        return unicycle_arc(q, v, omega, Ts)  # (11.85)
    x, y, th = q
    dth = omega * Ts
    heading = th if method == "euler" else th + dth / 2  # (11.83) or (11.84)
    return np.array([x + v * Ts * np.cos(heading), y + v * Ts * np.sin(heading), th + dth])


class Odometry(LoggedController):
    """Odometric localisation (Sect. 11.7) as a block: the estimate q̂ from the wheel encoders.

    Each call reads the encoders of an :class:`~controllers.plants.OdometerPosture` (``distance`` s,
    ``rotation`` ψ) and advances q̂ by :func:`odometry_step` with v_k T_s = Δs and ω_k T_s = Δψ, the increments
    since the previous call (T_s = the period at which it is called: wrap it in a
    :class:`~controllers.simulation.ZeroOrderHold`). Output: the estimate as a
    :class:`~controllers.plants.Posture` (θ̂ wrapped); logged as ``q_hat``. The true posture is not read.
    """

    def __init__(self, q0_estimate: Any, method: str = "runge_kutta"):
        if method not in ODOMETRY_METHODS:
            raise ValueError(f"`method` must be one of {ODOMETRY_METHODS}, got {method!r}")
        self.method = method
        self.q0_estimate = as_vector(q0_estimate, 3, "q0_estimate").copy()
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.q_hat = self.q0_estimate.copy()
        self._last: tuple[float, float, float] | None = None

    def __call__(self, t: float, measurement: Any) -> Posture:
        s, psi = measurement.distance, measurement.rotation
        if not (math.isfinite(s) and math.isfinite(psi)):
            raise ValueError(f"the wheel encoders' readings (distance, rotation) must be finite, got {(s, psi)} at "
                             f"t = {t:g} s: one would leave the odometric estimate NaN for ever")
        if self._last is not None and t > self._last[0]:
            Ts = t - self._last[0]
            ds, dpsi = s - self._last[1], psi - self._last[2]
            self.q_hat = _odometry_step(self.q_hat, ds / Ts, dpsi / Ts, Ts, self.method)
            self.q_hat[2] = _wrap(self.q_hat[2])
        self._last = (t, s, psi)
        self.record(q_hat=self.q_hat.copy())
        return Posture(*self.q_hat)


# --------------------------------------------------------------------------------------------
# Mobile manipulator: the base drives, the arm holds its end effector
# --------------------------------------------------------------------------------------------

class MobileManipulatorHold(LoggedController):
    """The base follows ``base_velocity(t) -> (v, ω)``; the arm keeps the end effector at ``p_d`` (3,).

    Kinematic task-space control through the whole model: with J_P (3, nv) the end-effector position
    Jacobian (3.30) and Γ the input map ([G 0; 0 I], :func:`rigid_body.wheeled.mobile_manipulator_input_matrix`),
    ṗ = J_P Γ u = J_b u_b + J_a q̇_a, and q̇_a = J_a^† (K (p_d − p) − J_b u_b) (damped least squares (3.59))
    cancels the base's motion at the end effector (feedforward) and corrects the error e = p_d − p.
    Logs ``e`` (3,) and ``base`` (x, y, θ).
    """

    def __init__(self, robot: Robot, p_d: Any, base_velocity: Callable[[float], Any], K: float = 10.0,
                 damping: float = 1e-4):
        self.robot = robot
        self.Gamma = mobile_manipulator_input_matrix(robot)
        self.p_d = as_vector(p_d, 3, "p_d").copy()
        self.base_velocity, self.K = base_velocity, as_positive(K, "K")
        self.damping = as_positive(damping, "damping", allow_zero=True)

    def __call__(self, t: float, m: Any) -> np.ndarray:
        fs = frame_state(self.robot, m.q)
        e = self.p_d - fs.T[:3, 3]
        J = fs.J[:3] @ self.Gamma                     # (3, 2 + n_arm)
        u_b = np.asarray(self.base_velocity(t), dtype=float)
        qd_a = damped_least_squares_inverse(J[:, 2:], self.damping) @ (self.K * e - J[:, :2] @ u_b)
        self.record(e=e, base=np.array([m.posture.x, m.posture.y, m.posture.theta]))
        return np.concatenate([u_b, qd_a])
