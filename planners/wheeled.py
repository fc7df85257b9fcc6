"""Paths and trajectories for wheeled mobile robots (Sect. 11.5): flat outputs and chained forms.

* **Flat outputs of the unicycle** (11.45)–(11.47): from a Cartesian path (x(s), y(s)) the heading and the
  geometric inputs follow, θ = Atan2(y', x') (+π backwards), ṽ = ±√(x'² + y'²), ω̃ = (y''x' − x''y')/(x'² + y'²);
  in time, v = ṽ ṡ and ω = ω̃ ṡ (11.54)–(11.55).
* **Cartesian polynomials** (11.52)–(11.53): the cubic path between two postures, and the **uniform time
  scaling** s = t/T that meets velocity bounds (Problem 11.13).
* **Parameterised inputs for the (2, n) chained form** (11.48)–(11.50): ṽ1 = sgn(Δ) (s ∈ [0, |Δ|]) or,
  as modified in Problem 11.11, ṽ1 = Δ (s ∈ [0, 1]); ṽ2 = c0 + c1 s + … + c_{n−2} s^{n−2}; the linear
  system D c = d is built by integrating the polynomials exactly, which gives the manual's D and the
  *corrected* d (Problem 11.10 erratum: d3 = z4f − z4i − z3i Δ − z2i Δ²/2, not "− z2i |Δ|").
* **Interpolating polynomials for the chained form** (scheme B of Problem 11.12): the flat outputs z1
  (linear) and z_n (the Hermite polynomial meeting z_n^{(k)} = Δ^k z_{n−k} at both ends).
* **References for tracking**: :class:`TimeScaledPath` (a Cartesian path at s = t/T) and :class:`FigureEight`,
  both returning a :class:`ReferenceSample` (p_d, ṗ_d, p̈_d, θ_d, v_d, ω_d) from the flat outputs (11.71).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 11.5,
Eqs. (11.38)–(11.55); solution manual, Problems 11.10–11.13.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.polynomial import Polynomial

from rigid_body.validation import as_count, as_positive, as_vector
from rigid_body.wheeled import unicycle_arc

__all__ = [
    "unicycle_flat_inputs", "CartesianPolynomialPath", "cartesian_polynomial_path", "uniform_time_scaling",
    "ReferenceSample", "TimeScaledPath", "FigureEight",
    "ChainedFormPath", "parameterised_path", "parameterised_inputs", "chained_form_system", "chained_form_interpolation",
    "bicycle_flat_inputs", "max_steering_angle", "steering_feasible_path", "DUBINS_WORDS", "DubinsPath", "dubins_path", "dubins_paths",
    "ReedsSheppPath", "reeds_shepp_path", "reeds_shepp_paths",
]


def unicycle_flat_inputs(pd: Any, pdd: Any, forward: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Heading, driving and steering velocity from the flat output's derivatives (11.45)–(11.47), (11.71).

    ``pd``, ``pdd`` : (..., 2) first and second derivatives of (x, y) (w.r.t. s for geometric inputs,
    w.r.t. t for velocity inputs). Returns θ = Atan2(y', x') (+π when not ``forward``),
    v = ±√(x'² + y'²), ω = (y''x' − x''y')/(x'² + y'²). ValueError where the path stops (x' = y' = 0).
    """
    pd, pdd = np.asarray(pd, dtype=float), np.asarray(pdd, dtype=float)
    speed2 = pd[..., 0] ** 2 + pd[..., 1] ** 2
    if np.any(speed2 < 1e-24):
        raise ValueError("the flat output stops (x' = y' = 0): heading and ω are undefined there")
    sign = 1.0 if forward else -1.0
    theta = np.arctan2(sign * pd[..., 1], sign * pd[..., 0])
    v = sign * np.sqrt(speed2)
    omega = (pdd[..., 1] * pd[..., 0] - pdd[..., 0] * pd[..., 1]) / speed2
    return theta, v, omega


def bicycle_flat_inputs(pd: Any, pdd: Any, ell: float, forward: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """θ, v and the steering angle φ = atan(ℓ ω / v) of a rear-drive bicycle (11.19) whose rear axle follows p.

    The rear-axle midpoint is a flat output: θ̇ = v tan φ / ℓ ⇒ tan φ = ℓ κ with κ = ω/v the path curvature.
    """
    ell = as_positive(ell, "ell")
    theta, v, omega = unicycle_flat_inputs(pd, pdd, forward)
    return theta, v, np.arctan(ell * omega / v)


# --------------------------------------------------------------------------------------------
# Cartesian polynomials, (11.52)–(11.55)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class CartesianPolynomialPath:
    """The cubic path (11.52) from q_i to q_f, s ∈ [0, 1]; α, β from (11.53). ``k`` < 0 runs it backwards."""

    q_i: np.ndarray
    q_f: np.ndarray
    k_i: float
    k_f: float
    alpha: np.ndarray  # [α_x, α_y]
    beta: np.ndarray   # [β_x, β_y]

    @property
    def forward(self) -> bool:
        return self.k_i > 0

    def __call__(self, s: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(p, p', p'') at s, each (..., 2): x(s) = s³x_f − (s−1)³x_i + α_x s²(s−1) + β_x s(s−1)², same for y."""
        s = np.asarray(s, dtype=float)[..., None]
        pf, pi, a, b = self.q_f[:2], self.q_i[:2], self.alpha, self.beta
        p = s**3 * pf - (s - 1) ** 3 * pi + a * s**2 * (s - 1) + b * s * (s - 1) ** 2
        dp = 3 * s**2 * pf - 3 * (s - 1) ** 2 * pi + a * (3 * s**2 - 2 * s) + b * (3 * s**2 - 4 * s + 1)
        ddp = 6 * s * pf - 6 * (s - 1) * pi + a * (6 * s - 2) + b * (6 * s - 4)
        return p, dp, ddp

    def geometric_inputs(self, s: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(θ(s), ṽ(s), ω̃(s)) along the path, (11.45)–(11.47)."""
        _, dp, ddp = self(s)
        return unicycle_flat_inputs(dp, ddp, self.forward)

    def velocity_polynomials(self) -> np.ndarray:
        """(2, 3): the coefficients [c_2, c_1, c_0] of x'(s) and y'(s) = c_2 s² + c_1 s + c_0 (from (11.52))."""
        pf, pi, a, b = self.q_f[:2], self.q_i[:2], self.alpha, self.beta
        return np.column_stack([3 * pf - 3 * pi + 3 * a + 3 * b, 6 * pi - 2 * a - 4 * b, -3 * pi + b])

    def slowest_points(self) -> np.ndarray:
        """The s ∈ [0, 1] where the speed ‖p'(s)‖ is least (the ends and the real roots in [0, 1] of
        d‖p'‖²/ds, a cubic): where a near-cusp puts the peak of ω̃."""
        c = self.velocity_polynomials()
        d = sum(np.convolve(ci, [2 * ci[0], ci[1]]) for ci in c)     # ½ d‖p'‖²/ds = x'x'' + y'y''
        roots = np.roots(np.trim_zeros(d, "f")) if np.any(d) else np.zeros(0)
        real = roots[np.abs(roots.imag) <= 1e-12 * (1 + np.abs(roots.real))].real
        return np.unique(np.r_[0.0, 1.0, real[(real >= 0.0) & (real <= 1.0)]])

    def cusps(self) -> np.ndarray:
        """The s ∈ [0, 1] where the path stops, p'(s) = 0 (relative to its largest speed, 1e-9): its heading jumps
        by π there, a cusp that a unicycle moving one way cannot follow."""
        s = self.slowest_points()
        _, dp, _ = self(np.r_[s, np.linspace(0.0, 1.0, 65)])
        speed = np.hypot(dp[:, 0], dp[:, 1])
        return s[speed[:len(s)] <= 1e-9 * speed.max()]


def cartesian_polynomial_path(q_i: Any, q_f: Any, k_i: float = 1.0, k_f: float = 1.0) -> CartesianPolynomialPath:
    """The cubic Cartesian path (11.52) between postures (x, y, θ), with (11.53):

    α = [k cos θ_f − 3x_f, k sin θ_f − 3y_f],  β = [k cos θ_i + 3x_i, k sin θ_i + 3y_i],  k_i = k_f = k ≠ 0 in the
    book (k > 0 forward, k < 0 backward); the speeds ṽ(0) = k_i, ṽ(1) = k_f.
    """
    q_i, q_f = as_vector(q_i, 3, "q_i"), as_vector(q_f, 3, "q_f")
    if k_i == 0 or k_f == 0 or np.sign(k_i) != np.sign(k_f):
        raise ValueError(f"`k_i`, `k_f` must be non-zero and of the same sign, got {k_i}, {k_f}")
    alpha = k_f * np.array([np.cos(q_f[2]), np.sin(q_f[2])]) - 3 * q_f[:2]
    beta = k_i * np.array([np.cos(q_i[2]), np.sin(q_i[2])]) + 3 * q_i[:2]
    path = CartesianPolynomialPath(q_i, q_f, float(k_i), float(k_f), alpha, beta)
    cusps = path.cusps()
    if cusps.size:
        raise ValueError(f"`q_f`: the cubic path (11.52) from q_i = {q_i.tolist()} to q_f = {q_f.tolist()} with k = "
                         f"{k_i:g} stops at s = {np.round(cusps, 4).tolist()} (x' = y' = 0): its heading jumps by π there "
                         "(a cusp), which a unicycle cannot follow; choose other postures or another k")
    return path


def max_steering_angle(path: CartesianPolynomialPath, ell: float, samples: int = 2001) -> float:
    """max |φ| [rad] of a rear-drive bicycle (wheelbase ℓ) whose rear axle follows the path (tan φ = ℓ κ)."""
    _, dp, ddp = path(np.linspace(0.0, 1.0, samples))
    return float(np.max(np.abs(bicycle_flat_inputs(dp, ddp, ell, path.forward)[2])))


def steering_feasible_path(q_i: Any, q_f: Any, ell: float, phi_max: float, forward: bool = True) -> CartesianPolynomialPath:
    """The cubic path (11.52) whose k = k_i = k_f minimises the peak steering angle of a car of wheelbase ℓ.

    ValueError when even the best k needs |φ| > φ_max (the manoeuvre is too tight for this car).
    """
    from scipy.optimize import minimize_scalar

    q_i, q_f = as_vector(q_i, 3, "q_i"), as_vector(q_f, 3, "q_f")
    ell, phi_max = as_positive(ell, "ell"), as_positive(phi_max, "phi_max")
    sign = 1.0 if forward else -1.0
    dist = max(float(np.hypot(*(q_f[:2] - q_i[:2]))), 1e-3)

    def peak(k: float) -> float:
        try:
            return max_steering_angle(cartesian_polynomial_path(q_i, q_f, sign * k, sign * k), ell, 401)
        except ValueError:                      # a cusp for this k: the worst
            return np.pi / 2

    best = minimize_scalar(peak, bounds=(0.1 * dist, 4.0 * dist), method="bounded", options={"xatol": 1e-4})
    path = cartesian_polynomial_path(q_i, q_f, sign * best.x, sign * best.x)
    phi = max_steering_angle(path, ell)
    if phi > phi_max:
        raise ValueError(f"`q_f`: the best cubic path needs |φ| = {phi:.3f} rad > phi_max = {phi_max:.3f} rad")
    return path


def uniform_time_scaling(path: CartesianPolynomialPath, v_max: float, omega_max: float,
                         samples: int = 4001) -> float:
    """The shortest duration T of s = t/T meeting |v| ≤ v_max and |ω| ≤ ω_max (11.54)–(11.55).

    v(t) = ṽ(s)/T and ω(t) = ω̃(s)/T, so T = max(max|ṽ|/v_max, max|ω̃|/ω_max) over s ∈ [0, 1] (sampled).
    """
    v_max, omega_max = as_positive(v_max, "v_max"), as_positive(omega_max, "omega_max")
    samples = as_count(samples, "samples", 2)
    cusps = path.cusps()
    if cusps.size:
        raise ValueError(f"`path` stops at s = {np.round(cusps, 4).tolist()} (a cusp): ω would be infinite there")
    slow = path.slowest_points()                    # ω̃ peaks where the speed is least: sampled densely around them
    near = (slow[:, None] + np.linspace(-1e-3, 1e-3, 201)[None, :]).ravel()
    s = np.unique(np.clip(np.r_[np.linspace(0.0, 1.0, samples), near], 0.0, 1.0))
    _, v, w = path.geometric_inputs(s)
    return float(max(np.max(np.abs(v)) / v_max, np.max(np.abs(w)) / omega_max))


@dataclass(frozen=True)
class ReferenceSample:
    """A unicycle reference at one instant: p_d, ṗ_d, p̈_d (2,), θ_d [rad], v_d [m/s], ω_d [rad/s]."""

    p: np.ndarray
    pd: np.ndarray
    pdd: np.ndarray
    theta: float
    v: float
    omega: float


class _FlatReference:
    """A unicycle trajectory given by its flat output p(t): ``reference(t) -> ReferenceSample``."""

    forward = True

    def flat(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        raise NotImplementedError

    def __call__(self, t: float) -> ReferenceSample:
        p, pd, pdd = self.flat(t)
        theta, v, omega = unicycle_flat_inputs(pd, pdd, self.forward)
        return ReferenceSample(p, pd, pdd, float(theta), float(v), float(omega))


class TimeScaledPath:
    """A Cartesian path run along a timing law s(t) (11.54): a reference for the trackers.

    ṗ = p' ṡ, p̈ = p'' ṡ² + p' s̈, θ = θ(s), v = ṽ(s) ṡ, ω = ω̃(s) ṡ (11.55). With ``T`` only: the uniform
    scaling s = t/T (ṡ = 1/T, the robot stops abruptly at T); with ``law``: any scalar timing law
    ``law(t) -> (s, ṡ, s̈)`` from 0 to 1 (e.g. :func:`planners.timing.quintic_law`, which starts and stops
    at rest). After the end the final posture is held.
    """

    def __init__(self, path: CartesianPolynomialPath, T: float | None = None, law: Any = None):
        if (T is None) == (law is None):
            raise ValueError("give either `T` (uniform scaling) or `law` (a timing law s(t))")
        self.path, self.law = path, law
        self.T = as_positive(T, "T") if law is None else float(law.t_f)
        self.forward = path.forward

    def timing(self, t: float) -> tuple[float, float, float]:
        """(s, ṡ, s̈) at t."""
        if self.law is None:
            return (min(max(t / self.T, 0.0), 1.0), 1.0 / self.T if 0.0 <= t < self.T else 0.0, 0.0)
        s, sd, sdd = self.law(t)
        return float(s), float(sd), float(sdd)

    def __call__(self, t: float) -> ReferenceSample:
        s, sd, sdd = self.timing(t)
        p, dp, ddp = self.path(s)
        theta, v, omega = self.path.geometric_inputs(s)
        return ReferenceSample(p, dp * sd, ddp * sd**2 + dp * sdd, float(theta), float(v * sd), float(omega * sd))


class FigureEight(_FlatReference):
    """The figure-eight (Gerono lemniscate) p(t) = c + [a sin(2πt/T), (a/2) sin(4πt/T)]: never stops, ω_d varies."""

    def __init__(self, a: float = 1.0, T: float = 20.0, center: Any = (0.0, 0.0)):
        self.a, self.T = as_positive(a, "a"), as_positive(T, "T")
        self.center = as_vector(center, 2, "center")

    def flat(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        w = 2 * np.pi / self.T
        a, s1, c1, s2, c2 = self.a, np.sin(w * t), np.cos(w * t), np.sin(2 * w * t), np.cos(2 * w * t)
        p = self.center + np.array([a * s1, 0.5 * a * s2])
        pd = np.array([a * w * c1, a * w * c2])
        pdd = np.array([-a * w**2 * s1, -2 * a * w**2 * s2])
        return p, pd, pdd


# --------------------------------------------------------------------------------------------
# Chained form: parameterised inputs (11.48)–(11.50) and interpolating polynomials
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class ChainedFormPath:
    """A geometric path of the (2, n) chained form, z_k(s) polynomials on s ∈ [0, s_f]; inputs ṽ1 = z1', ṽ2 = z2'."""

    polynomials: tuple[Polynomial, ...]
    s_f: float
    coefficients: np.ndarray  # c_0 … c_{n−2} of ṽ2 (scheme A) or z_n's coefficients (scheme B)

    def z(self, s: Any) -> np.ndarray:
        """(…, n) the path at s."""
        return np.stack([P(np.asarray(s, dtype=float)) for P in self.polynomials], axis=-1)

    @cached_property
    def _input_coefficients(self) -> tuple[np.ndarray, np.ndarray]:
        return self.polynomials[0].deriv().coef[::-1], self.polynomials[1].deriv().coef[::-1]

    def inputs(self, s: Any) -> np.ndarray:
        """(…, 2) the geometric inputs (ṽ1, ṽ2) = (z1', z2') at s."""
        a, b = self._input_coefficients
        if isinstance(s, (float, int, np.floating)):      # one arc length (a simulated loop): Horner on floats
            s = float(s)
            return np.array([_horner(self._input_lists[0], s), _horner(self._input_lists[1], s)])
        s = np.asarray(s, dtype=float)
        return np.stack([np.polyval(a, s), np.polyval(b, s)], axis=-1)

    @cached_property
    def _input_lists(self) -> tuple[list[float], list[float]]:
        return tuple(c.tolist() for c in self._input_coefficients)


def _horner(coefficients: list[float], s: float) -> float:
    """Σ c_k s^(d−k) (highest degree first), as ``np.polyval`` evaluates it."""
    y = 0.0
    for c in coefficients:
        y = y * s + c
    return y


def _chained_state(z_i: np.ndarray, v1: float, c: np.ndarray) -> list[Polynomial]:
    """z_k(s) for ṽ1 = v1 (constant) and ṽ2 = Σ c_k s^k, integrated exactly from z_i."""
    polys = [Polynomial([z_i[0], v1])]
    polys.append(Polynomial(c).integ(lbnd=0.0, k=z_i[1]))
    for k in range(2, z_i.size):
        polys.append((v1 * polys[-1]).integ(lbnd=0.0, k=z_i[k]))
    return polys


def _boundary(z_i: Any, z_f: Any, unit_interval: bool) -> tuple[np.ndarray, np.ndarray, float, float]:
    z_i = as_vector(z_i, None, "z_i")
    z_f = as_vector(z_f, z_i.size, "z_f")
    if z_i.size < 3:
        raise ValueError(f"a (2, n) chained form needs n ≥ 3, got z_i of size {z_i.size}")
    delta = z_f[0] - z_i[0]
    if abs(delta) < 1e-12:
        raise ValueError("`z_f`: z1f = z1i (Δ = 0) — the parameterised inputs need a change of z1 "
                         "(plan through an intermediate point)")
    if unit_interval:  # Problem 11.11: ṽ1 = Δ, s ∈ [0, 1]
        return z_i, z_f, delta, 1.0
    return z_i, z_f, float(np.sign(delta)), abs(delta)  # (11.48): ṽ1 = sgn Δ, s ∈ [0, |Δ|]


def chained_form_system(z_i: Any, z_f: Any, unit_interval: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(D, d) of the linear system D c = d (11.50) for ṽ2 = c_0 + … + c_{n−2} s^{n−2}.

    Column k of D is the change of (z_2 … z_n)(s_f) caused by c_k, d = z_f − (z_2 … z_n)(s_f) at c = 0: exact
    polynomial integration, valid for any n (for n = 4 it gives the manual's D and the corrected d3).
    """
    z_i, z_f, v1, s_f = _boundary(z_i, z_f, unit_interval)
    m = z_i.size - 1
    free = np.array([P(s_f) for P in _chained_state(z_i, v1, np.zeros(m))[1:]])
    D = np.empty((m, m))
    for k in range(m):
        e = np.zeros(m)
        e[k] = 1.0
        D[:, k] = np.array([P(s_f) for P in _chained_state(z_i, v1, e)[1:]]) - free
    return D, z_f[1:] - free


def parameterised_path(z_i: Any, delta: float, c: Any, unit_interval: bool = False) -> ChainedFormPath:
    """The path of the (2, n) chained form from z_i under ṽ1 = sgn Δ (or Δ) and ṽ2 = Σ c_k s^k, for given c."""
    z_i = as_vector(z_i, None, "z_i")
    c = as_vector(c, z_i.size - 1, "c")
    if delta == 0:
        raise ValueError("`delta` must be non-zero")
    v1, s_f = (float(delta), 1.0) if unit_interval else (float(np.sign(delta)), abs(float(delta)))
    return ChainedFormPath(tuple(_chained_state(z_i, v1, c)), s_f, c)


def parameterised_inputs(z_i: Any, z_f: Any, unit_interval: bool = False) -> ChainedFormPath:
    """Plan z_i → z_f for the (2, n) chained form with the parameterised inputs (11.48)–(11.49), solving (11.50).

    ``unit_interval=False``: ṽ1 = sgn(Δ), s ∈ [0, |Δ|] (the book); ``True``: ṽ1 = Δ, s ∈ [0, 1] (Problem 11.11).
    """
    D, d = chained_form_system(z_i, z_f, unit_interval)
    z_i, z_f = np.asarray(z_i, dtype=float), np.asarray(z_f, dtype=float)
    if np.linalg.cond(D) > 1e12:
        raise ValueError(f"`z_f`: the system (11.50) is singular for Δ = {z_f[0] - z_i[0]:g}")
    return parameterised_path(z_i, z_f[0] - z_i[0], np.linalg.solve(D, d), unit_interval)


def chained_form_interpolation(z_i: Any, z_f: Any) -> ChainedFormPath:
    """Scheme B of Problem 11.12: interpolate the flat outputs z1 (linear) and z_n (Hermite), s ∈ [0, 1].

    z1 = z1i + Δ s; z_n has degree 2n − 3 and meets z_n^{(k)} = Δ^k z_{n−k} (k = 0 … n−2) at s = 0 and 1;
    then z_{n−k} = z_n^{(k)} / Δ^k (since z_k' = z_{k−1} z1').
    """
    z_i, z_f, delta, _ = _boundary(z_i, z_f, True)
    n = z_i.size
    deg = 2 * n - 3
    rows, rhs = [], []
    for s, z in ((0.0, z_i), (1.0, z_f)):
        for k in range(n - 1):  # k-th derivative of Σ a_j s^j at s
            row = np.zeros(deg + 1)
            for j in range(k, deg + 1):
                row[j] = np.prod(np.arange(j - k + 1, j + 1)) * s ** (j - k)  # d^k s^j / ds^k
            rows.append(row)
            rhs.append(delta**k * z[n - 1 - k])
    a = np.linalg.solve(np.array(rows), np.array(rhs))
    zn = Polynomial(a)
    polys = [Polynomial([z_i[0], delta])] + [zn.deriv(n - 1 - k) / delta ** (n - 1 - k) for k in range(1, n - 1)] + [zn]
    return ChainedFormPath(tuple(polys), 1.0, a)


# --------------------------------------------------------------------------------------------
# Dubins shortest paths of the car that only moves forward (minimum turning radius ρ)
# --------------------------------------------------------------------------------------------

DUBINS_WORDS = ("LSL", "RSR", "LSR", "RSL", "RLR", "LRL")
_TURN = {"L": 1.0, "S": 0.0, "R": -1.0}


@dataclass(frozen=True)
class CarPath:
    """A path of a car of turning radius ρ: a word of primitives (L left arc, R right arc, S straight) with
    signed lengths in units of ρ (arc angles [rad] for L/R, length/ρ for S; negative: backwards)."""

    q_i: np.ndarray
    rho: float
    word: str
    segments: np.ndarray

    @property
    def length(self) -> float:
        """Path length [m]."""
        return float(self.rho * np.sum(np.abs(self.segments)))

    def end(self) -> np.ndarray:
        """The final posture, by exact integration of the primitives (11.85)."""
        return self.sample(np.inf)[-1]

    def sample(self, step: float) -> np.ndarray:
        """(N, 3) postures every ``step`` metres of arc length (and at the segment ends), exact arcs."""
        q = self.q_i.copy()
        out = [q]
        for kind, length in zip(self.word, self.segments):
            L, v = abs(length) * self.rho, float(np.sign(length))
            n = 1 if not np.isfinite(step) else max(1, int(np.ceil(L / step)))
            for _ in range(n):  # speed ±1: v = ±1, ω = ±1/ρ or 0
                q = unicycle_arc(q, v, v * _TURN[kind] / self.rho, L / n)
                out.append(q)
        return np.array(out)


class DubinsPath(CarPath):
    """A Dubins path: a word of three forward segments (non-negative lengths in units of ρ)."""


def _mod2pi(a: float) -> float:
    """a in [0, 2π); values within 1e-9 of 2π are 0 (an arc of 2π − ε from rounding is no turn at all)."""
    r = float(np.mod(a, 2 * np.pi))
    return 0.0 if r > 2 * np.pi - 1e-9 else r


def _dubins_word(word: str, a: float, b: float, d: float) -> np.ndarray | None:
    """Normalised segment lengths (t, p, q) of one word, start heading a, end heading b, distance d (in ρ)."""
    sa, sb, ca, cb, cab = np.sin(a), np.sin(b), np.cos(a), np.cos(b), np.cos(a - b)
    if word in ("LSL", "RSR"):
        turn = 1.0 if word == "LSL" else -1.0
        p2 = max(0.0, 2 + d * d - 2 * cab + 2 * turn * d * (sa - sb))  # squared distance of the circle centres
        if p2 < 1e-18:  # one circle: a single arc (the tangent direction is undefined)
            return np.array([_mod2pi(turn * (b - a)), 0.0, 0.0])
        tmp = np.arctan2(turn * (cb - ca), d + turn * (sa - sb))
        return np.array([_mod2pi(turn * (tmp - a)), np.sqrt(p2), _mod2pi(turn * (b - tmp))])
    if word == "LSR":
        p2 = -2 + d * d + 2 * cab + 2 * d * (sa + sb)
        if p2 < -1e-12:
            return None
        p2 = max(p2, 0.0)
        p = np.sqrt(p2)
        tmp = np.arctan2(-ca - cb, d + sa + sb) - np.arctan2(-2.0, p)
        return np.array([_mod2pi(-a + tmp), p, _mod2pi(-_mod2pi(b) + tmp)])
    if word == "RSL":
        p2 = -2 + d * d + 2 * cab - 2 * d * (sa + sb)
        if p2 < -1e-12:
            return None
        p2 = max(p2, 0.0)
        p = np.sqrt(p2)
        tmp = np.arctan2(ca + cb, d - sa - sb) - np.arctan2(2.0, p)
        return np.array([_mod2pi(a - tmp), p, _mod2pi(b - tmp)])
    if word == "RLR":
        c = (6 - d * d + 2 * cab + 2 * d * (sa - sb)) / 8
        if abs(c) > 1:
            return None
        p = _mod2pi(2 * np.pi - np.arccos(c))
        t = _mod2pi(a - np.arctan2(ca - cb, d - sa + sb) + p / 2)
        return np.array([t, p, _mod2pi(a - b - t + p)])
    if word == "LRL":
        c = (6 - d * d + 2 * cab + 2 * d * (sb - sa)) / 8
        if abs(c) > 1:
            return None
        p = _mod2pi(2 * np.pi - np.arccos(c))
        t = _mod2pi(-a - np.arctan2(ca - cb, d + sa - sb) + p / 2)
        return np.array([t, p, _mod2pi(_mod2pi(b) - a - t + p)])
    raise ValueError(f"`word` must be one of {DUBINS_WORDS}, got {word!r}")


def dubins_paths(q_i: Any, q_f: Any, rho: float) -> list[DubinsPath]:
    """Every feasible Dubins word (CSC and CCC) from q_i to q_f with turning radius ρ, shortest first.

    In the frame of the segment q_i → q_f scaled by 1/ρ, each word's lengths are closed forms (Dubins 1957;
    the formulas of Shkel & Lumelsky 2001).
    """
    q_i, q_f = as_vector(q_i, 3, "q_i"), as_vector(q_f, 3, "q_f")
    rho = as_positive(rho, "rho")
    dx, dy = q_f[0] - q_i[0], q_f[1] - q_i[1]
    d = np.hypot(dx, dy) / rho
    phi = np.arctan2(dy, dx) if d > 0 else 0.0
    a, b = _mod2pi(q_i[2] - phi), _mod2pi(q_f[2] - phi)
    paths = [DubinsPath(q_i, rho, w, seg) for w in DUBINS_WORDS if (seg := _dubins_word(w, a, b, d)) is not None]
    return sorted(paths, key=lambda p: p.length)


def dubins_path(q_i: Any, q_f: Any, rho: float) -> DubinsPath:
    """The shortest path of a car moving forward with turning radius ≥ ρ from q_i to q_f (Dubins)."""
    return dubins_paths(q_i, q_f, rho)[0]


# --------------------------------------------------------------------------------------------
# Reeds–Shepp shortest paths of the car that moves forward and backward (turning radius ρ)
# --------------------------------------------------------------------------------------------

class ReedsSheppPath(CarPath):
    """A Reeds–Shepp path: segments (L, R, S) with signed lengths in units of ρ (negative: backwards)."""


def _pi_mod(a: float) -> float:
    """a wrapped into (−π, π]."""
    return float(np.pi - np.mod(np.pi - a, 2 * np.pi))


def _polar(x: float, y: float) -> tuple[float, float]:
    return float(np.hypot(x, y)), float(np.arctan2(y, x))


def _tau_omega(u: float, v: float, xi: float, eta: float, phi: float) -> tuple[float, float]:
    delta = _pi_mod(u - v)
    A, B = np.sin(u) - np.sin(delta), np.cos(u) - np.cos(delta) - 1.0
    t1 = np.arctan2(eta * A - xi * B, xi * A + eta * B)
    t2 = 2.0 * (np.cos(delta) - np.cos(v) - np.cos(u)) + 3.0
    tau = _pi_mod(t1 + np.pi) if t2 < 0 else _pi_mod(t1)
    return tau, _pi_mod(tau - u + v - phi)


_EPS = 1e-10


def _lsl(x: float, y: float, phi: float) -> list[float] | None:  # Reeds & Shepp (8.1): L+ S+ L+
    u, t = _polar(x - np.sin(phi), y - 1.0 + np.cos(phi))
    v = _pi_mod(phi - t)
    return [t, u, v] if t >= -_EPS and v >= -_EPS else None


def _lsr(x: float, y: float, phi: float) -> list[float] | None:  # (8.2): L+ S+ R+
    u1, t1 = _polar(x + np.sin(phi), y - 1.0 - np.cos(phi))
    if u1 * u1 < 4.0:
        return None
    u = np.sqrt(u1 * u1 - 4.0)
    t = _pi_mod(t1 + np.arctan2(2.0, u))
    v = _pi_mod(t - phi)
    return [t, u, v] if t >= -_EPS and v >= -_EPS else None


def _lrl(x: float, y: float, phi: float) -> list[float] | None:  # (8.3): L+ R− L
    u1, theta = _polar(x - np.sin(phi), y - 1.0 + np.cos(phi))
    if u1 > 4.0:
        return None
    u = -2.0 * np.arcsin(u1 / 4.0)
    t = _pi_mod(theta + u / 2.0 + np.pi)
    v = _pi_mod(phi - t + u)
    return [t, u, v] if t >= -_EPS and u <= _EPS else None


def _lrlr_a(x: float, y: float, phi: float) -> list[float] | None:  # (8.7): L+ R+u L−u R−
    xi, eta = x + np.sin(phi), y - 1.0 - np.cos(phi)
    rho = 0.25 * (2.0 + np.hypot(xi, eta))
    if rho > 1.0:
        return None
    u = np.arccos(rho)
    t, v = _tau_omega(u, -u, xi, eta, phi)
    return [t, u, -u, v] if t >= -_EPS and v <= _EPS else None


def _lrlr_b(x: float, y: float, phi: float) -> list[float] | None:  # (8.8): L+ R−u L−u R+
    xi, eta = x + np.sin(phi), y - 1.0 - np.cos(phi)
    rho = (20.0 - xi * xi - eta * eta) / 16.0
    if not 0.0 <= rho <= 1.0:
        return None
    u = -np.arccos(rho)
    if u < -np.pi / 2:
        return None
    t, v = _tau_omega(u, u, xi, eta, phi)
    return [t, u, u, v] if t >= -_EPS and v >= -_EPS else None


def _lrsl(x: float, y: float, phi: float) -> list[float] | None:  # (8.9): L+ R−(π/2) S− L−
    xi, eta = x - np.sin(phi), y - 1.0 + np.cos(phi)  # centre of the final (left) circle
    rho, theta = _polar(-eta, xi)
    if rho < 2.0:
        return None
    r = np.sqrt(rho * rho - 4.0)  # (−η, ξ) = R(t)(r, −2) with r = 2 − u
    u = 2.0 - r
    t = _pi_mod(theta + np.arctan2(2.0, r))
    v = _pi_mod(phi - np.pi / 2 - t)
    return [t, -np.pi / 2, u, v] if t >= -_EPS and u <= _EPS and v <= _EPS else None


def _lrsr(x: float, y: float, phi: float) -> list[float] | None:  # (8.10): L+ R−(π/2) S− R−
    xi, eta = x + np.sin(phi), y - 1.0 - np.cos(phi)
    rho, theta = _polar(-eta, xi)
    if rho < 2.0:
        return None
    t, u = theta, 2.0 - rho
    v = _pi_mod(t + np.pi / 2 - phi)
    return [t, -np.pi / 2, u, v] if t >= -_EPS and u <= _EPS and v <= _EPS else None


def _lrslr(x: float, y: float, phi: float) -> list[float] | None:  # (8.11): L+ R−(π/2) S− L−(π/2) R+
    xi, eta = x + np.sin(phi), y - 1.0 - np.cos(phi)
    rho, _ = _polar(xi, eta)
    if rho < 2.0:
        return None
    u = 4.0 - np.sqrt(rho * rho - 4.0)
    if u > _EPS:
        return None
    t = _pi_mod(np.arctan2((4.0 - u) * xi - 2.0 * eta, -2.0 * xi + (u - 4.0) * eta))
    v = _pi_mod(t - phi)
    return [t, -np.pi / 2, u, -np.pi / 2, v] if t >= -_EPS and v >= -_EPS else None


# (formula, word, use the "backwards" symmetry too)
_RS_FAMILIES = ((_lsl, "LSL", False), (_lsr, "LSR", False), (_lrl, "LRL", True), (_lrlr_a, "LRLR", False),
                (_lrlr_b, "LRLR", False), (_lrsl, "LRSL", True), (_lrsr, "LRSR", True), (_lrslr, "LRSLR", False))
_SWAP = str.maketrans("LR", "RL")


def reeds_shepp_paths(q_i: Any, q_f: Any, rho: float) -> list[ReedsSheppPath]:
    """Candidate Reeds–Shepp paths (CSC, CCC, CCCC, CCSC, CCSCC families) from q_i to q_f, shortest first.

    Each family's closed form (Reeds & Shepp 1990, formulas 8.1–8.11) gives the base word; the time-flip
    (x, y, φ) → (−x, y, −φ), the reflection (x, −y, −φ) (L ↔ R) and, for CCC and CCSC, the backwards
    reading of the path cover the 48 words.
    """
    q_i, q_f = as_vector(q_i, 3, "q_i"), as_vector(q_f, 3, "q_f")
    rho = as_positive(rho, "rho")
    dx, dy = (q_f[:2] - q_i[:2]) / rho
    c, s = np.cos(q_i[2]), np.sin(q_i[2])
    x, y, phi = c * dx + s * dy, -s * dx + c * dy, _pi_mod(q_f[2] - q_i[2])  # goal in the start frame
    xb, yb = x * np.cos(phi) + y * np.sin(phi), x * np.sin(phi) - y * np.cos(phi)
    found = []
    for formula, word, backwards in _RS_FAMILIES:
        for back in (False, True) if backwards else (False,):
            bx, by = (xb, yb) if back else (x, y)
            for flip in (False, True):
                for refl in (False, True):
                    seg = formula(-bx if flip else bx, -by if refl else by, -phi if flip != refl else phi)
                    if seg is None:
                        continue
                    seg = -np.array(seg) if flip else np.array(seg)
                    w = word.translate(_SWAP) if refl else word
                    if back:
                        w, seg = w[::-1], seg[::-1]
                    found.append(ReedsSheppPath(q_i, rho, w, seg.astype(float)))
    return sorted(found, key=lambda p: p.length)


def reeds_shepp_path(q_i: Any, q_f: Any, rho: float) -> ReedsSheppPath:
    """The shortest path of a car moving forward and backward with turning radius ≥ ρ (Reeds–Shepp)."""
    return reeds_shepp_paths(q_i, q_f, rho)[0]
