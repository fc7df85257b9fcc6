"""Independent joint control of one electric drive (Sect. 8.3): P, P+V, P+V+A feedback and feedforward.

The drive (Sect. 5.1, 8.3) is the voltage-controlled DC motor with the joint's average inertia ``I``:
``M(s) = k_m/(s(1 + s T_m))`` with ``k_m = 1/k_v`` and ``T_m = R_a I/(k_v k_t)`` (F_m neglected when
``F_m ≪ k_v k_t/R_a``); a disturbance torque ``D`` enters through the gain ``R_a/k_t`` at the input of
``M``. Transducer constants are ``k_TP, k_TV, k_TA``. The closed loops are reduced from the blocks with
python-control (``control.feedback``), not typed in; the manual's closed forms check them.

* position feedback (Fig. 5.10): ``C_P(s) = K_P(1 + s T_P)/s``;
* position and velocity feedback (Fig. 5.11): ``K_P`` and ``C_V(s) = K_V(1 + s T_V)/s``, (8.30)–(8.33);
* position, velocity and acceleration feedback (Figs. 8.6/8.9): ``K_P, K_V`` and
  ``C_A(s) = K_A(1 + s T_A)/s``, (8.39)–(8.42); acceleration reconstruction filter (Fig. 8.11);
* decentralised feedforward (Figs. 8.12–8.17): the equivalent reference ``Θ'_r(s)`` that makes
  ``Θ_m ≡ Θ_d`` (Problems 8.7–8.8).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 8.3 (Eqs. (8.24)–(8.42), Figs. 8.6–8.17), Sect. 5.1 (Figs. 5.10, 5.11), Problems 8.1–8.9.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import control
import numpy as np
from scipy.optimize import brentq

from controllers.simulation import LoggedController
from rigid_body.validation import as_positive


_s = control.tf("s")


@dataclass(frozen=True)
class JointDrive:
    """A joint's electric drive as seen by independent joint control (Sect. 8.3).

    ``I`` [kg·m²] average inertia at the motor side, ``Ra`` [Ω], ``kt`` [N·m/A], ``kv`` [V·s/rad],
    ``Fm`` [N·m·s/rad] (neglected in M(s) when ``Fm ≪ kv kt/Ra``).
    """

    I: float
    Ra: float
    kt: float
    kv: float
    Fm: float = 0.0

    def __post_init__(self) -> None:
        for name in ("I", "Ra", "kt", "kv"):
            as_positive(getattr(self, name), name)
        if not (np.isfinite(self.Fm) and self.Fm >= 0):
            raise ValueError(f"`Fm` must be non-negative, got {self.Fm}")

    @property
    def k_m(self) -> float:
        """k_m = 1/k_v [rad/(V·s)]."""
        return 1.0 / self.kv

    @property
    def T_m(self) -> float:
        """T_m = R_a I/(k_v k_t) [s]."""
        return self.Ra * self.I / (self.kv * self.kt)

    @property
    def disturbance_gain(self) -> float:
        """R_a/k_t: the disturbance torque D in volts at the input of M(s)."""
        return self.Ra / self.kt

    def friction_ratio(self) -> float:
        """F_m/(k_v k_t/R_a): the approximation M(s) = k_m/(s(1 + sT_m)) needs it ≪ 1."""
        return self.Fm * self.Ra / (self.kv * self.kt)

    def motor_tf(self) -> control.TransferFunction:
        """M(s) = Θ_m/V = k_m/(s(1 + s T_m))."""
        return control.tf([self.k_m], [self.T_m, 1.0, 0.0])


@dataclass(frozen=True)
class Transducers:
    """Transducer constants of position, velocity and acceleration (unit by default)."""

    k_TP: float = 1.0
    k_TV: float = 1.0
    k_TA: float = 1.0

    def __post_init__(self) -> None:
        for name in ("k_TP", "k_TV", "k_TA"):
            as_positive(getattr(self, name), name)


@dataclass(frozen=True)
class ClosedLoop:
    """Closed-loop transfer functions of an independent joint scheme.

    ``reference`` = Θ_m/Θ_r, ``disturbance`` = Θ_m/D, and the forward path ``P`` and return path ``H``
    of the reduced single-loop scheme (``reference = P/(1 + P H)``).
    """

    reference: control.TransferFunction
    disturbance: control.TransferFunction
    P: control.TransferFunction
    H: control.TransferFunction


def _pi(K: float, T: float) -> control.TransferFunction:
    return control.tf([K * T, K], [1.0, 0.0])


def _min(G: control.TransferFunction) -> control.TransferFunction:
    return control.minreal(G, tol=1e-9, verbose=False)


def position_feedback(drive: JointDrive, K_P: float, T_P: float,
                      transducers: Transducers = Transducers()) -> ClosedLoop:
    """Fig. 5.10: Θ_m = M(C_P(Θ_r − k_TP Θ_m) − (R_a/k_t) D), C_P = K_P(1 + sT_P)/s (Problem 8.1)."""
    M, C = drive.motor_tf(), _pi(as_positive(K_P, "K_P"), as_positive(T_P, "T_P", allow_zero=True))
    k_TP = transducers.k_TP
    P = C * M
    return ClosedLoop(_min(control.feedback(P, k_TP)),
                      _min(-drive.disturbance_gain * control.feedback(M, C * k_TP)), P,
                      control.tf([k_TP], [1.0]))


def position_velocity_feedback(drive: JointDrive, K_P: float, K_V: float, T_V: float,
                               transducers: Transducers = Transducers()) -> ClosedLoop:
    """Fig. 5.11: Θ_m = M(C_V(K_P(Θ_r − k_TP Θ_m) − k_TV sΘ_m) − (R_a/k_t) D) (Problem 8.2)."""
    K_P = as_positive(K_P, "K_P")
    M, C = drive.motor_tf(), _pi(as_positive(K_V, "K_V"), as_positive(T_V, "T_V", allow_zero=True))
    t = transducers
    feedback_path = K_P * t.k_TP + t.k_TV * _s                       # what multiplies −Θ_m at C_V
    reference = K_P * control.feedback(C * M, feedback_path)
    disturbance = -drive.disturbance_gain * control.feedback(M, C * feedback_path)
    return ClosedLoop(_min(reference), _min(disturbance), K_P * C * M, feedback_path / K_P)


def position_velocity_acceleration_feedback(drive: JointDrive, K_P: float, K_V: float, K_A: float,
                                            T_A: float, transducers: Transducers = Transducers()
                                            ) -> ClosedLoop:
    """Figs. 8.6/8.9: Θ_m = M(C_A(K_V(K_P(Θ_r − k_TP Θ_m) − k_TV sΘ_m) − k_TA s²Θ_m) − (R_a/k_t) D) (Problem 8.3)."""
    K_P, K_V = as_positive(K_P, "K_P"), as_positive(K_V, "K_V")
    M, C = drive.motor_tf(), _pi(as_positive(K_A, "K_A"), as_positive(T_A, "T_A", allow_zero=True))
    t = transducers
    feedback_path = K_V * K_P * t.k_TP + K_V * t.k_TV * _s + t.k_TA * _s**2
    reference = K_V * K_P * control.feedback(C * M, feedback_path)
    disturbance = -drive.disturbance_gain * control.feedback(M, C * feedback_path)
    return ClosedLoop(_min(reference), _min(disturbance), K_P * K_V * C * M, feedback_path / (K_P * K_V))


# ---------------------------------------------------------------------------------------------
# Designs from specifications
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class JointDesign:
    """Gains of an independent joint loop and its disturbance-rejection figures.

    ``X_R`` disturbance rejection factor, ``T_R`` [s] output recovery time, ``poles`` of Θ_m/Θ_r.
    Gains not used by the scheme are ``None``.
    """

    K_P: float
    T_P: float | None
    K_V: float | None
    T_V: float | None
    K_A: float | None
    T_A: float | None
    X_R: float
    T_R: float
    poles: np.ndarray
    closed_loop: ClosedLoop


def damping_of_complex_poles(poles: np.ndarray) -> float:
    """ζ = −Re p/|p| of the complex-conjugate pair (nan if all poles are real)."""
    complex_ = [p for p in np.atleast_1d(poles) if abs(p.imag) > 1e-12 * max(1.0, abs(p))]
    if not complex_:
        return float("nan")
    p = complex_[0]
    return float(-p.real / abs(p))


def design_position_feedback(drive: JointDrive, zeta: float, T_P: float,
                             transducers: Transducers = Transducers()) -> JointDesign:
    """Position feedback (Fig. 5.10) with the largest K_P whose complex poles have damping ``zeta``.

    The characteristic polynomial ``T_m s³ + s² + k_m K_P k_TP (T_P s + 1)`` is scanned over K_P (the
    root locus of Fig. S8.4); along the locus the damping of the complex pair first rises, then falls
    as K_P grows: the largest gain with ζ ≥ ``zeta`` is the design (best disturbance rejection).
    ``X_R = K_P k_TP`` and ``T_R = T_P``.
    """
    zeta = as_positive(zeta, "zeta")
    T_P = as_positive(T_P, "T_P")
    if zeta >= 1:
        raise ValueError(f"`zeta` must be < 1 for a complex pair, got {zeta}")
    k = drive.k_m * transducers.k_TP

    def damping(log_K: float) -> float:
        K = np.exp(log_K)
        z = damping_of_complex_poles(np.roots([drive.T_m, 1.0, k * K * T_P, k * K]))
        return 1.0 if np.isnan(z) else z

    grid = np.linspace(np.log(1e-9), np.log(1e6), 1500)
    values = np.array([damping(g) for g in grid]) - zeta
    crossings = np.nonzero((values[:-1] >= 0) & (values[1:] < 0))[0]
    if crossings.size == 0:
        raise ValueError(f"no gain K_P gives damping {zeta} with T_P = {T_P} s (see the root locus)")
    i = crossings[-1]
    K_P = float(np.exp(brentq(lambda g: damping(g) - zeta, grid[i], grid[i + 1], xtol=1e-13)))
    loop = position_feedback(drive, K_P, T_P, transducers)
    return JointDesign(K_P, T_P, None, None, None, None, X_R=K_P * transducers.k_TP, T_R=T_P,
                       poles=np.sort_complex(control.poles(loop.reference)), closed_loop=loop)


def design_position_velocity(drive: JointDrive, zeta: float, omega_n: float,
                             transducers: Transducers = Transducers()) -> JointDesign:
    """Position and velocity feedback with T_V = T_m, gains from (8.30)–(8.31).

    ``W(s) = (1/k_TP)/(1 + 2ζ s/ω_n + s²/ω_n²)`` requires ``K_P k_TP = ω_n k_TV/(2ζ)`` and
    ``k_m K_V k_TV = 2ζ ω_n``; then ``X_R = K_P k_TP K_V`` and ``T_R = T_V`` (8.32)–(8.33).

    >>> d = design_position_velocity(JointDrive(I=6.0, Ra=0.3, kt=0.5, kv=0.5), zeta=0.4, omega_n=20.0)
    >>> round(d.K_P, 9), round(d.K_V, 9), round(d.X_R, 9)
    (25.0, 8.0, 200.0)
    """
    zeta, omega_n = as_positive(zeta, "zeta"), as_positive(omega_n, "omega_n")
    t = transducers
    K_P = omega_n * t.k_TV / (2 * zeta * t.k_TP)
    K_V = 2 * zeta * omega_n / (drive.k_m * t.k_TV)
    T_V = drive.T_m
    loop = position_velocity_feedback(drive, K_P, K_V, T_V, t)
    return JointDesign(K_P, None, K_V, T_V, None, None, X_R=K_P * t.k_TP * K_V, T_R=T_V,
                       poles=np.sort_complex(control.poles(loop.reference)), closed_loop=loop)


def design_position_velocity_acceleration(drive: JointDrive, zeta: float, omega_n: float, X_R: float,
                                          transducers: Transducers = Transducers()) -> JointDesign:
    """Position, velocity and acceleration feedback with T_A = T_m, gains from (8.39)–(8.41).

    ``2ζ/ω_n = k_TV/(K_P k_TP)``, ``ω_n² = k_m X_R/(1 + k_m K_A k_TA)``, ``X_R = K_P k_TP K_V K_A``;
    ``T_R = max(T_A, T_m/(k_m K_A k_TA))`` (8.42) [recalled from the textbook].
    """
    zeta, omega_n, X_R = as_positive(zeta, "zeta"), as_positive(omega_n, "omega_n"), as_positive(X_R, "X_R")
    t = transducers
    k_m = drive.k_m
    if k_m * X_R <= omega_n**2:
        raise ValueError(f"`X_R` must exceed ω_n²/k_m = {omega_n**2 / k_m:g} for a positive K_A, got {X_R}")
    K_P = omega_n * t.k_TV / (2 * zeta * t.k_TP)
    K_A = (k_m * X_R / omega_n**2 - 1.0) / (k_m * t.k_TA)
    K_V = X_R / (K_P * t.k_TP * K_A)
    T_A = drive.T_m
    loop = position_velocity_acceleration_feedback(drive, K_P, K_V, K_A, T_A, t)
    T_R = max(T_A, drive.T_m / (k_m * K_A * t.k_TA))
    return JointDesign(K_P, None, K_V, None, K_A, T_A, X_R=X_R, T_R=T_R,
                       poles=np.sort_complex(control.poles(loop.reference)), closed_loop=loop)


def bandwidth(W: control.TransferFunction) -> float:
    """ω_3 [rad/s]: the frequency where |W(jω)| falls 3 dB (1/√2) below its static gain."""
    w3 = float(control.bandwidth(W, dbdrop=-20 * np.log10(np.sqrt(2.0))))
    if not np.isfinite(w3):
        raise ValueError("`W` has no −3 dB bandwidth: it is unstable, or |W(jω)| never falls 3 dB below its "
                         "static gain")
    return w3


def acceleration_filter(k_f: float) -> control.TransferFunction:
    """Fig. 8.11: acceleration reconstructed from velocity, ``Â/Ω = k_f s/(s + k_f)`` (bandwidth k_f)."""
    k_f = as_positive(k_f, "k_f")
    return control.tf([k_f, 0.0], [1.0, k_f])


# ---------------------------------------------------------------------------------------------
# Decentralised feedforward (Figs. 8.12–8.17)
# ---------------------------------------------------------------------------------------------

def feedforward_reference(drive: JointDrive, design: JointDesign,
                          transducers: Transducers = Transducers()) -> control.TransferFunction:
    """Θ'_r/Θ_d: the equivalent reference of the feedforward schemes of Figs. 8.12–8.14 (Problem 8.7).

    The feedforward signals of each figure are moved onto the reference input of the loop:

    * Fig. 8.12 (position): ``(T_m/k_m) θ̈_d + (1/k_m) θ̇_d`` enter at the output of C_P, so
      ``Θ'_r = k_TP Θ_d + (s²T_m/k_m + s/k_m) s Θ_d / (K_P(1 + sT_P))``;
    * Fig. 8.13 (position + velocity): ``k_TV θ̇_d`` and ``θ̈_d/(k_m K_V)`` enter at the input of C_V;
    * Fig. 8.14 (+ acceleration): ``k_TV θ̇_d`` at the input of K_V and ``(k_TA + 1/(k_m K_A)) θ̈_d`` at
      the input of C_A.

    The result is an improper (polynomial) transfer function of Θ_d.
    """
    t = transducers
    km, Tm = drive.k_m, drive.T_m
    if design.K_V is None:                                   # position feedback, Fig. 8.12
        C_P = _pi(design.K_P, design.T_P)
        return _min(t.k_TP + (Tm * _s**2 + _s) / km * (1 / C_P))
    if design.K_A is None:                                   # Fig. 8.13, moved through K_P
        return _min(t.k_TP + (t.k_TV * _s + _s**2 / (km * design.K_V)) / design.K_P)
    # Fig. 8.14: k_TV θ̇_d at the input of K_V, (k_TA + 1/(k_m K_A)) θ̈_d at the input of C_A
    return _min(t.k_TP + t.k_TV * _s / design.K_P
                + (t.k_TA + 1.0 / (km * design.K_A)) * _s**2 / (design.K_V * design.K_P))


def feedforward_tracking(drive: JointDrive, design: JointDesign,
                         transducers: Transducers = Transducers()) -> control.TransferFunction:
    """Θ_m/Θ_d with the decentralised feedforward: ``W(s) Θ'_r(s)/Θ_d(s)`` (≡ 1: perfect tracking)."""
    return _min(design.closed_loop.reference * feedforward_reference(drive, design, transducers))


def feedforward_controller_output(drive: JointDrive, design: JointDesign,
                                  transducers: Transducers = Transducers()
                                  ) -> tuple[control.TransferFunction, control.TransferFunction]:
    """Output Y of the innermost PI block of Figs. 8.13/8.14 as ``Y = G_E(s) E + G_d(s) Θ_d`` (Problem 8.8).

    ``E = k_TP(Θ_d − Θ_m)``; with it ``k_TV(sΘ_d − sΘ_m) = (k_TV/k_TP) s E`` (and likewise for k_TA), so
    the feedback part of the regulator input is a function of E alone: Figs. 8.16/8.17 follow.
    Returns ``(G_E, G_d)``.
    """
    t = transducers
    km = drive.k_m
    if design.K_V is None:
        raise ValueError("`design` must have velocity feedback (Figs. 8.13/8.14)")
    if design.K_A is None:                                   # Fig. 8.13: U into C_V
        C = _pi(design.K_V, design.T_V)
        U_E = design.K_P + t.k_TV / t.k_TP * _s
        U_d = _s**2 / (km * design.K_V)
    else:                                                    # Fig. 8.14: U into C_A
        C = _pi(design.K_A, design.T_A)
        U_E = design.K_V * (design.K_P + t.k_TV / t.k_TP * _s) + t.k_TA / t.k_TP * _s**2
        U_d = _s**2 / (km * design.K_A)
    return C * U_E, _min(C * U_d)


# ---------------------------------------------------------------------------------------------
# A single-joint servo in the simulation loop (its plant: controllers.plants.JointDrivePlant)
# ---------------------------------------------------------------------------------------------

class PositionVelocityController(LoggedController):
    """Position + velocity feedback with decentralised feedforward (Fig. 8.13), sampled with period ``Ts``.

    ``u = K_P k_TP (ϑ_d − ϑ) + k_TV (ϑ̇_d − ϑ̇) + ϑ̈_d/(k_m K_V)`` (feedforward terms optional) drives the
    PI velocity regulator ``v = K_V (T_V u + ∫u)``. ``reference(t) -> (ϑ_d, ϑ̇_d, ϑ̈_d)``;
    ``disturbance(t)`` is passed through as the plant's second input.
    """

    def __init__(self, design: JointDesign, drive: JointDrive, reference: Callable[[float], Any],
                 Ts: float, feedforward: bool = True, transducers: Transducers = Transducers(),
                 disturbance: Callable[[float], float] | None = None):
        if design.K_V is None or design.K_A is not None:
            raise ValueError("`design` must be a position + velocity design")
        self.d, self.k_m, self.t = design, drive.k_m, transducers
        self.reference, self.Ts, self.feedforward = reference, as_positive(Ts, "Ts"), feedforward
        self.disturbance = disturbance
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.integral = 0.0

    def __call__(self, time: float, meas: Any) -> np.ndarray:
        theta, omega = meas.q[0], meas.qd[0]
        theta_d, omega_d, alpha_d = self.reference(time)
        d, t = self.d, self.t
        u = d.K_P * t.k_TP * (theta_d - theta) + t.k_TV * ((omega_d if self.feedforward else 0.0) - omega)
        if self.feedforward:
            u += alpha_d / (self.k_m * d.K_V)
        v = d.K_V * (d.T_V * u + self.integral)
        self.integral += u * self.Ts
        self.record(e=theta_d - theta)
        dist = 0.0 if self.disturbance is None else float(self.disturbance(time))
        return np.array([v, dist])


# ---------------------------------------------------------------------------------------------
# Inertia bounds (8.75)–(8.76)
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class InertiaBounds:
    """Bounds ``B_m I ≤ B⁻¹(q) ≤ B_M I`` over sampled configurations (8.75), and the constant estimate
    ``B̂ = 2/(B_M + B_m) I`` with ``‖B⁻¹B̂ − I‖ ≤ α = (B_M − B_m)/(B_M + B_m) < 1`` (8.76)."""

    B_m: float
    B_M: float
    B_hat: np.ndarray
    alpha: float


def inertia_bounds(inertia_matrices: Any) -> InertiaBounds:
    """Eigenvalue bounds of B⁻¹ over a set of inertia matrices (N, n, n), and B̂, α of (8.76)."""
    B = np.asarray(inertia_matrices, dtype=float)
    if B.ndim != 3 or B.shape[1] != B.shape[2] or B.shape[0] == 0:
        raise ValueError(f"`inertia_matrices` must have shape (N, n, n), got {B.shape}")
    if not np.all(np.isfinite(B)):
        raise ValueError("`inertia_matrices` must be finite")
    eig = np.linalg.eigvalsh(B)               # of B; those of B⁻¹ are the reciprocals
    if np.any(eig <= 0):
        raise ValueError("`inertia_matrices` must be positive definite")
    B_m, B_M = float(np.min(1.0 / eig)), float(np.max(1.0 / eig))
    n = B.shape[1]
    return InertiaBounds(B_m, B_M, 2.0 / (B_M + B_m) * np.eye(n), (B_M - B_m) / (B_M + B_m))
