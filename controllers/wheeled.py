"""Motion control of wheeled mobile robots (Sect. 11.6–11.7): plants, tracking, regulation, odometry.

Plants (for :func:`controllers.simulation.simulate`): :class:`UnicyclePlant` (x, y, θ; inputs v, ω; optional
wheel-speed saturation of a differential drive, Problem 11.9), :class:`BicyclePlant` (x, y, θ, φ; inputs v,
φ̇), :class:`ChainedFormPlant` and :class:`DriftlessPlant` (q̇ = G(q) u). Their ``measure`` returns named
fields (:class:`Posture`, :class:`BicycleState`), never a slice of the state.

Controllers (``__call__(t, measurement) -> u``, ``log()``):

* trajectory tracking of the unicycle: :class:`ApproximateLinearizationTracking` (11.64)–(11.67),
  :class:`NonlinearTracking` (11.68)–(11.70), :class:`InputOutputTracking` (point B ahead, (11.72)–(11.74));
* :class:`ChainedFormTracking` (Problem 11.14) and :class:`BicycleInputOutputTracking` (Problem 11.15);
* regulation: :class:`CartesianRegulator` (11.78)–(11.79) with the backward-motion variant (S11.6) of
  Problem 11.16, :class:`PostureRegulator` (11.80)–(11.82);
* odometric localisation (11.83)–(11.85) — Euler, second-order Runge–Kutta and exact — in
  :func:`odometry_step`, and :class:`OdometricRegulator`, a regulator fed by odometry updated at the period
  at which the loop calls it (Problem 11.18: the controller only sees the dead-reckoning estimate).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 11.6–11.7,
Eqs. (11.56)–(11.85); solution manual, Problems 11.14–11.18.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from planners.wheeled import ReferenceSample
from rigid_body.rotations import wrap_angle
from rigid_body.validation import as_positive, as_vector
from rigid_body.wheeled import (chained_form_velocity, front_wheel_point, front_wheel_point_matrix,
                                saturate_wheel_speeds, unicycle_arc, unicycle_velocity)

__all__ = [
    "Posture", "BicycleState", "UnicyclePlant", "BicyclePlant", "ChainedFormPlant", "DriftlessPlant",
    "tracking_error", "ApproximateLinearizationTracking", "NonlinearTracking", "InputOutputTracking",
    "ChainedFormTracking", "BicycleInputOutputTracking", "BicycleTracking",
    "CartesianRegulator", "PostureRegulator", "ODOMETRY_METHODS", "odometry_step", "OdometricRegulator",
]


def _wrap(a: float) -> float:
    return float(wrap_angle(a))


# --------------------------------------------------------------------------------------------
# Plants
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Posture:
    """What a unicycle's sensors give: x, y [m], θ [rad]; ``p`` = (x, y)."""

    x: float
    y: float
    theta: float

    @property
    def p(self) -> np.ndarray:
        return np.array([self.x, self.y])


@dataclass(frozen=True)
class BicycleState(Posture):
    """Measured bicycle state: the rear contact point's posture (x, y, θ) and the steering angle φ [rad]."""

    phi: float


def _pose(m: Any) -> tuple[float, float, float]:
    """(x, y, θ) of a measurement: a :class:`Posture`-like object or an array (x, y, θ, …)."""
    if hasattr(m, "theta"):
        return m.x, m.y, m.theta
    return float(m[0]), float(m[1]), float(m[2])


class UnicyclePlant:
    """The unicycle (11.13), x = (x, y, θ), u = (v, ω).

    ``wheel_limits = (r, d, ω_RL)`` makes it a differential drive whose wheel speeds saturate at ±ω_RL: the
    applied (v, ω) are scaled into the admissible rhombus of Problem 11.9 keeping the curvature.
    """

    def __init__(self, wheel_limits: tuple[float, float, float] | None = None):
        if wheel_limits is not None:
            r, d, w = wheel_limits
            wheel_limits = (as_positive(r, "r"), as_positive(d, "d"), as_positive(w, "omega_RL"))
        self.wheel_limits = wheel_limits

    def applied(self, u: np.ndarray) -> np.ndarray:
        """The (v, ω) actually applied (saturated when the plant has wheel limits)."""
        if self.wheel_limits is None:
            return u
        return np.array(saturate_wheel_speeds(u[0], u[1], *self.wheel_limits))

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return unicycle_velocity(x, self.applied(u) if self.wheel_limits else u)

    def integrate(self, x: np.ndarray, dx: np.ndarray, h: float) -> np.ndarray:
        """x ⊕ h dx on R² × SO(2): θ wrapped into (−π, π]."""
        y = x + h * dx
        y[2] = _wrap(y[2])
        return y

    def measure(self, t: float, x: np.ndarray) -> Posture:
        return Posture(float(x[0]), float(x[1]), float(x[2]))


class BicyclePlant:
    """The bicycle, rear-wheel (11.19) or front-wheel (11.20) drive: x = (x, y, θ, φ), u = (v, ω = φ̇)."""

    def __init__(self, ell: float, drive: str = "rear"):
        self.ell = as_positive(ell, "ell")
        if drive not in ("rear", "front"):
            raise ValueError(f"`drive` must be 'rear' or 'front', got {drive!r}")
        self.drive = drive

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        th, phi, v = x[2], x[3], u[0]
        if self.drive == "rear":
            return np.array([v * np.cos(th), v * np.sin(th), v * np.tan(phi) / self.ell, u[1]])
        c = np.cos(phi)
        return np.array([v * np.cos(th) * c, v * np.sin(th) * c, v * np.sin(phi) / self.ell, u[1]])

    def measure(self, t: float, x: np.ndarray) -> BicycleState:
        return BicycleState(float(x[0]), float(x[1]), float(x[2]), float(x[3]))


class ChainedFormPlant:
    """The (2, n) chained form (11.25), x = z, u = (v1, v2)."""

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return chained_form_velocity(x, u)


class DriftlessPlant:
    """q̇ = G(q) u for any kinematic model (11.10): ``input_matrix(q) -> G`` (n, m)."""

    def __init__(self, input_matrix: Callable[[np.ndarray], np.ndarray]):
        self.input_matrix = input_matrix

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return self.input_matrix(x) @ u


# --------------------------------------------------------------------------------------------
# Trajectory tracking of the unicycle, Sect. 11.6.1
# --------------------------------------------------------------------------------------------

def tracking_error(ref: ReferenceSample, x: float, y: float, theta: float) -> np.ndarray:
    """e = [e1, e2, e3] (11.65): the position error in the robot frame and the heading error θ_d − θ (wrapped)."""
    dx, dy = ref.p[0] - x, ref.p[1] - y
    c, s = np.cos(theta), np.sin(theta)
    return np.array([c * dx + s * dy, -s * dx + c * dy, _wrap(ref.theta - theta)])


class _Tracking:
    """Common part of the unicycle trackers: the reference and the logged signals."""

    def __init__(self, reference: Callable[[float], ReferenceSample]):
        self.reference = reference
        self._e = np.zeros(3)

    def reset(self) -> None:
        self._e = np.zeros(3)

    def log(self) -> dict[str, Any]:
        """e (11.65); position_error ‖p_d − p‖; point_error: the error of the point the law controls."""
        d = float(np.hypot(self._e[0], self._e[1]))
        return {"e": self._e.copy(), "position_error": d, "point_error": getattr(self, "_point_error", d)}


class ApproximateLinearizationTracking(_Tracking):
    """Tracking by approximate linearisation (11.66)–(11.67): v = v_d cos e3 + k1 e1, ω = ω_d + k2 e2 + k3 e3.

    With k1 = k3 = 2ζa and k2 = (a² − ω_d²)/v_d (a > 0, 0 < ζ < 1; needs v_d ≠ 0) the linearised error
    dynamics, for constant v_d and ω_d, have the poles −2ζa and −ζa ± ja√(1 − ζ²).
    """

    def __init__(self, reference: Callable[[float], ReferenceSample], a: float, zeta: float):
        super().__init__(reference)
        self.a, self.zeta = as_positive(a, "a"), as_positive(zeta, "zeta")

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        ref = self.reference(t)
        e = self._e = tracking_error(ref, *_pose(measurement))
        if abs(ref.v) < 1e-9:
            raise ValueError(f"approximate linearisation needs v_d ≠ 0 (gain k2 = (a² − ω_d²)/v_d), v_d = 0 at t = {t:g} s")
        k1 = k3 = 2 * self.zeta * self.a
        k2 = (self.a**2 - ref.omega**2) / ref.v
        return np.array([ref.v * np.cos(e[2]) + k1 * e[0], ref.omega + k2 * e[1] + k3 * e[2]])


class NonlinearTracking(_Tracking):
    """Nonlinear tracking (11.68)–(11.70): v = v_d cos e3 + k1 e1, ω = ω_d + k2 v_d (sin e3/e3) e2 + k3 e3,

    with k1 = k3 = 2ζ √(ω_d² + b v_d²) and k2 = b > 0 (asymptotic stability when v_d, ω_d do not both vanish).
    """

    def __init__(self, reference: Callable[[float], ReferenceSample], zeta: float, b: float):
        super().__init__(reference)
        self.zeta, self.b = as_positive(zeta, "zeta"), as_positive(b, "b")

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        ref = self.reference(t)
        e = self._e = tracking_error(ref, *_pose(measurement))
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
        self._e = tracking_error(ref, x, y, th)
        c, s = np.cos(th), np.sin(th)
        err = ref.p - np.array([x + self.b * c, y + self.b * s])
        self._point_error = float(np.hypot(err[0], err[1]))
        u = ref.pd + self.k * err
        return np.array([c * u[0] + s * u[1], (-s * u[0] + c * u[1]) / self.b])


class ChainedFormTracking:
    """Linearisation-based tracking of the (2, 3) chained form (Problem 11.14).

    e = z_d − z, u = v_d − v with u1 = −k1 e1, u2 = −k2 e2 − (k3/v1d) e3 ⇒ v = v_d + [k1 e1, k2 e2 + k3 e3/v1d];
    the linearised closed loop has p(λ) = (λ + k1)(λ² + k2 λ + k3). ``reference(t) -> (z_d (3,), v_d (2,))``.
    """

    def __init__(self, reference: Callable[[float], tuple[np.ndarray, np.ndarray]], k1: float, k2: float, k3: float):
        self.reference = reference
        self.k = (as_positive(k1, "k1"), as_positive(k2, "k2"), as_positive(k3, "k3"))
        self._e = np.zeros(3)

    def reset(self) -> None:
        self._e = np.zeros(3)

    def __call__(self, t: float, z: np.ndarray) -> np.ndarray:
        z_d, v_d = self.reference(t)
        if abs(v_d[0]) < 1e-9:
            raise ValueError(f"the chained-form tracker needs v1d ≠ 0 (gain k3/v1d), v1d = 0 at t = {t:g} s")
        e = self._e = np.asarray(z_d, dtype=float) - z
        k1, k2, k3 = self.k
        return np.array([v_d[0] + k1 * e[0], v_d[1] + k2 * e[1] + k3 * e[2] / v_d[0]])

    def log(self) -> dict[str, Any]:
        return {"e": self._e.copy()}


class BicycleInputOutputTracking:
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
        self._e = np.zeros(2)

    def reset(self) -> None:
        self._e = np.zeros(2)

    def __call__(self, t: float, m: Any) -> np.ndarray:
        if abs(np.cos(m.phi)) < 1e-9:
            raise ValueError(f"steering angle |φ| = π/2 at t = {t:g} s: T(θ, φ) is singular")
        y_d, yd_d = self.reference(t)
        q = np.array([m.x, m.y, m.theta, m.phi])
        self._e = np.asarray(y_d, dtype=float) - front_wheel_point(q, self.ell, self.b)
        u = np.asarray(yd_d, dtype=float) + self.k * self._e
        return np.linalg.solve(front_wheel_point_matrix(m.theta, m.phi, self.ell, self.b), u)

    def log(self) -> dict[str, Any]:
        return {"e": self._e.copy()}


class BicycleTracking:
    """A rear-drive bicycle (11.19) tracking a unicycle reference: a cascade.

    An outer unicycle tracker (e.g. :class:`NonlinearTracking`) acting on the rear-axle posture gives (v, ω);
    the steering angle realising ω, φ_d = atan(ℓ ω v / (v² + ε)) (= atan(ℓω/v) away from v = 0, → 0 when the car
    stops), clipped to ±φ_max, is tracked by the steering rate φ̇ = k_φ (φ_d − φ).
    """

    def __init__(self, tracker: Any, ell: float, phi_max: float, k_phi: float, eps: float = 1e-3):
        self.tracker, self.ell = tracker, as_positive(ell, "ell")
        self.phi_max, self.k_phi = as_positive(phi_max, "phi_max"), as_positive(k_phi, "k_phi")
        self.eps = as_positive(eps, "eps")
        self._phi_d = 0.0

    def reset(self) -> None:
        if hasattr(self.tracker, "reset"):
            self.tracker.reset()
        self._phi_d = 0.0

    def __call__(self, t: float, m: Any) -> np.ndarray:
        v, omega = self.tracker(t, m)
        phi_d = np.arctan(self.ell * omega * v / (v * v + self.eps))
        self._phi_d = float(np.clip(phi_d, -self.phi_max, self.phi_max))
        return np.array([v, self.k_phi * (self._phi_d - m.phi)])

    def log(self) -> dict[str, Any]:
        out = dict(self.tracker.log()) if hasattr(self.tracker, "log") else {}
        out["phi_d"] = self._phi_d
        return out


# --------------------------------------------------------------------------------------------
# Regulation, Sect. 11.6.2
# --------------------------------------------------------------------------------------------

class CartesianRegulator:
    """Cartesian regulation to the origin (11.78)–(11.79): v = k1 nᵀe_p = −k1(x cos θ + y sin θ), ω = k2 γ.

    γ = Atan2(y, x) − θ + π (pointing error, wrapped). ``backward=True`` is the modification (S11.6) of
    Problem 11.16: ω = k2(γ − sign(γ)π) when nᵀe_p ≤ 0, so the robot aligns with −e_p and backs to the goal.
    """

    def __init__(self, k1: float, k2: float, backward: bool = False):
        self.k1, self.k2, self.backward = as_positive(k1, "k1"), as_positive(k2, "k2"), bool(backward)
        self._gamma = 0.0

    def reset(self) -> None:
        self._gamma = 0.0

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        x, y, th = _pose(measurement)
        n_e = -(x * np.cos(th) + y * np.sin(th))  # nᵀ e_p, e_p = −p
        gamma = self._gamma = _wrap(np.arctan2(y, x) - th + np.pi)
        if self.backward and n_e <= 0:
            gamma = gamma - np.sign(gamma) * np.pi  # (S11.6)
        return np.array([self.k1 * n_e, self.k2 * gamma])

    def log(self) -> dict[str, Any]:
        return {"gamma": self._gamma}


class PostureRegulator:
    """Posture regulation to (0, 0, 0) in polar coordinates (11.80)–(11.82).

    ρ = √(x² + y²), γ = Atan2(y, x) − θ + π, δ = γ + θ (wrapped);
    v = k1 ρ cos γ,  ω = k2 γ + k1 (sin γ cos γ / γ)(γ + k3 δ).
    """

    def __init__(self, k1: float, k2: float, k3: float):
        self.k1, self.k2, self.k3 = as_positive(k1, "k1"), as_positive(k2, "k2"), as_positive(k3, "k3")

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        x, y, th = _pose(measurement)
        rho = np.hypot(x, y)
        gamma = _wrap(np.arctan2(y, x) - th + np.pi)
        delta = _wrap(gamma + th)
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


class OdometricRegulator:
    """A regulator fed by odometric localisation only (Problem 11.18, Fig. S11.4).

    At each call the estimate q̂ is advanced from the previous call with the command then applied (held
    constant by the loop's zero-order hold), by :func:`odometry_step`; the regulator then acts on q̂. The
    odometry period is therefore the period at which the loop calls this controller (``Ts`` of
    :func:`~controllers.simulation.simulate`). The measurement is used only to log the localisation error.
    """

    def __init__(self, regulator: Callable[[float, Any], np.ndarray], q0_estimate: Any,
                 method: str = "runge_kutta"):
        if method not in ODOMETRY_METHODS:
            raise ValueError(f"`method` must be one of {ODOMETRY_METHODS}, got {method!r}")
        self.regulator, self.method = regulator, method
        self.q0_estimate = as_vector(q0_estimate, 3, "q0_estimate").copy()
        self.reset()

    def reset(self) -> None:
        self.q_hat = self.q0_estimate.copy()
        self._t: float | None = None
        self._u = np.zeros(2)
        self._error = 0.0

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        if self._t is not None and t > self._t:
            self.q_hat = _odometry_step(self.q_hat, self._u[0], self._u[1], t - self._t, self.method)
        self._t = t
        x, y, th = _pose(measurement)
        self._error = float(np.hypot(x - self.q_hat[0], y - self.q_hat[1]))
        self._u = np.asarray(self.regulator(t, Posture(*self.q_hat)), dtype=float)
        return self._u

    def log(self) -> dict[str, Any]:
        return {"q_hat": self.q_hat.copy(), "odometry_error": self._error}
