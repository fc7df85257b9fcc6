"""Joint-space trajectories: timing laws q(t) of Chapter 4, sampled into a :class:`Trajectory`.

Two layers, as in the book (Sect. 4.2, 4.3):

* a **law** is a callable ``law(t) -> (q, qd, qdd)`` defined on ``[law.t_i, law.t_f]``; the value
  shape is that of the boundary data, so a law built from scalars is a scalar timing law
  ``s(t) -> (s, ṡ, s̈)`` (shared by the operational-space paths of :mod:`planners.paths`), and one
  built from ``(n,)`` vectors is an n-joint law. Outside its interval a law is held at its end
  value with zero velocity and acceleration (the companion files hold q_f until t_d).
* a :class:`Trajectory` holds samples of a law: ``t`` (N,), ``q``, ``qd``, ``qdd`` (N, n),
  time-major (rows are time steps, columns are joints), and can evaluate the law anywhere.

Every law below but the raised cosine is a :class:`PiecewisePolynomial`.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 4.2 (point-to-point: (4.1)–(4.9)), Sect. 4.3 (via points: (4.10)–(4.28));
P. Corke, *Robotics, Vision and Control*, Springer 2017, Sect. 3.3.3 (``mstraj``: multi-segment
trajectories timed by per-axis speed limits), the idea of :func:`multi_segment_law` (not its timing).
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import Any, Callable, Protocol

import numpy as np
from scipy.linalg import solve_banded

from rigid_body.validation import as_array, as_positive, as_scalar, as_vector

__all__ = [
    "TimingLaw", "PiecewisePolynomial", "RaisedCosine", "Trajectory", "sample",
    "polynomial_law", "cubic_law", "quintic_law", "cubic", "quintic",
    "trapezoidal_law", "trapezoidal", "trapezoidal_acceleration_law", "trapezoidal_limits",
    "raised_cosine_law", "raised_cosine",
    "via_point_velocities", "via_point_accelerations", "polynomial_sequence_law", "polynomial_sequence",
    "SplineSystem", "spline_system", "cubic_spline_law", "cubic_spline",
    "BlendCoefficients", "blend_coefficients", "linear_parabolic_blends_law", "linear_parabolic_blends",
    "multi_segment_times", "multi_segment_law", "multi_segment", "time_scaled",
]


class TimingLaw(Protocol):
    """What every law offers: its interval and ``law(t) -> (q, qd, qdd)``."""

    t_i: float
    t_f: float

    def __call__(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]: ...


# --------------------------------------------------------------------------------------------
# Input checks
# --------------------------------------------------------------------------------------------

def _as_value(x: Any, shape: tuple[int, ...] | None, name: str) -> np.ndarray:
    """``x`` as a finite float array (scalar or vector) of the given shape."""
    v = as_array(x, name)
    if v.ndim > 1:
        raise ValueError(f"`{name}` must be a scalar or a 1-D vector, got shape {v.shape}")
    if shape is not None:
        if v.ndim == 0 and shape != ():
            v = np.full(shape, float(v))
        elif v.shape != shape:
            raise ValueError(f"`{name}` must have shape {shape} (like q_i), got {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"`{name}` must be finite, got {v}")
    return v


def _as_interval(t_i: Any, t_f: Any) -> tuple[float, float, float]:
    """(t_i, t_f, T = t_f − t_i) as finite floats with t_f > t_i; ValueError naming the argument."""
    t_i = as_scalar(t_i, "t_i")
    t_f = as_scalar(t_f, "t_f")
    if not t_f > t_i:
        raise ValueError(f"`t_f` must be greater than `t_i`, got t_i = {t_i}, t_f = {t_f}")
    return t_i, t_f, t_f - t_i


def _as_times(t: Any, name: str = "t", minimum: int = 2) -> np.ndarray:
    t = as_vector(t, None, name)
    if t.size < minimum:
        raise ValueError(f"`{name}` must hold at least {minimum} instants, got {t.size}")
    if np.any(np.diff(t) <= 0):
        k = int(np.argmax(np.diff(t) <= 0))
        raise ValueError(f"`{name}` must be strictly increasing, got {name}[{k}] = {t[k]} "
                         f">= {name}[{k + 1}] = {t[k + 1]}")
    return t


def _as_points(q: Any, m: int, name: str = "q") -> np.ndarray:
    """Via points: (m,) for one joint or (m, n) for n joints (one row per instant)."""
    q = as_array(q, name)
    if q.ndim not in (1, 2) or q.shape[0] != m:
        raise ValueError(f"`{name}` must have shape ({m},) or ({m}, n): one row per time instant, "
                         f"got {q.shape}")
    if not np.all(np.isfinite(q)):
        raise ValueError(f"`{name}` must be finite")
    return q


# --------------------------------------------------------------------------------------------
# Laws
# --------------------------------------------------------------------------------------------

def _as_instants(t: Any) -> np.ndarray:
    """Evaluation instants as a float array; ValueError on NaN (±inf is outside the law: end values held)."""
    t = np.asarray(t, dtype=float)
    if np.isnan(t).any():
        raise ValueError(f"`t` must not be NaN, got {t}")
    return t


def _derivative_coefficients(c: np.ndarray) -> np.ndarray:
    """Coefficients (ascending powers, axis 1) of the derivative of each piece."""
    d = c.shape[1] - 1
    scale = np.arange(1, d + 1, dtype=float).reshape((1, d) + (1,) * (c.ndim - 2))
    return c[:, 1:] * scale


@dataclass(frozen=True)
class PiecewisePolynomial:
    """q(t) = Σ_j c[k, j] (t − o_k)^j for t in [breaks[k], breaks[k+1]].

    Parameters
    ----------
    breaks : (K+1,) strictly increasing instants [s].
    coefficients : (K, d+1) for a scalar law or (K, d+1, n) for n joints, ascending powers.
    origins : (K,) the instant o_k each piece's powers are taken about (default: its start,
        ``breaks[:-1]``); the manual writes the blends of Problem 4.6 about the via point.

    Calling it with a float gives (q, qd, qdd) of the value shape; with an (M,) array, arrays of
    shape (M,) + value shape. Outside [t_i, t_f] it holds the end value, with zero derivatives.
    """

    breaks: np.ndarray
    coefficients: np.ndarray
    origins: np.ndarray | None = None
    _c: tuple = field(init=False, repr=False, compare=False)
    _breaks: list = field(init=False, repr=False, compare=False)
    _origins: list = field(init=False, repr=False, compare=False)
    _powers: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        breaks = _as_times(self.breaks, "breaks")
        c = np.asarray(self.coefficients, dtype=float)
        if c.ndim not in (2, 3) or c.shape[0] != breaks.size - 1:
            raise ValueError(f"`coefficients` must have shape ({breaks.size - 1}, d+1[, n]), got {c.shape}")
        if not np.all(np.isfinite(c)):
            raise ValueError("`coefficients` must be finite")
        origins = breaks[:-1].copy() if self.origins is None else as_vector(self.origins, breaks.size - 1, "origins")
        if c.shape[1] < 3:  # pad to degree 2 so that q̈ always exists
            c = np.concatenate([c, np.zeros((c.shape[0], 3 - c.shape[1]) + c.shape[2:])], axis=1)
        dc = _derivative_coefficients(c)
        object.__setattr__(self, "breaks", breaks)
        object.__setattr__(self, "coefficients", c)
        object.__setattr__(self, "origins", origins)
        object.__setattr__(self, "_c", (c, dc, _derivative_coefficients(dc)))
        object.__setattr__(self, "_breaks", breaks.tolist())
        object.__setattr__(self, "_origins", origins.tolist())
        object.__setattr__(self, "_powers", np.arange(c.shape[1], dtype=float))

    @property
    def t_i(self) -> float:
        return float(self.breaks[0])

    @property
    def t_f(self) -> float:
        return float(self.breaks[-1])

    @property
    def value_shape(self) -> tuple[int, ...]:
        return self.coefficients.shape[2:]

    def __call__(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if isinstance(t, (float, int, np.floating, np.integer)):
            return self._at(float(t))
        t = _as_instants(t)
        breaks = self.breaks
        tt = np.clip(t, breaks[0], breaks[-1])
        k = np.clip(np.searchsorted(breaks, tt, side="right") - 1, 0, breaks.size - 2)
        tau = (tt - self.origins[k]).reshape(t.shape + (1,) * len(self.value_shape))
        out = []
        for c in self._c:
            ck = c[k]  # t.shape + (d+1,) + value shape
            p = np.take(ck, -1, axis=t.ndim)
            for j in range(c.shape[1] - 2, -1, -1):  # Horner
                p = p * tau + np.take(ck, j, axis=t.ndim)
            out.append(p)
        outside = ((t < breaks[0]) | (t > breaks[-1])).reshape(tau.shape)
        if np.any(outside):
            out[1] = np.where(outside, 0.0, out[1])
            out[2] = np.where(outside, 0.0, out[2])
        return out[0], out[1], out[2]


    def _at(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Fast path for one instant (controllers call this at 1 kHz)."""
        breaks, (c, dc, ddc) = self._breaks, self._c
        if t <= breaks[0] or t >= breaks[-1]:
            k = 0 if t <= breaks[0] else len(breaks) - 2
            tau = (breaks[0] if t <= breaks[0] else breaks[-1]) - self._origins[k]
            moving = breaks[0] <= t <= breaks[-1]
        elif t != t:
            raise ValueError("`t` must not be NaN")
        else:
            k = bisect.bisect_right(breaks, t) - 1
            tau, moving = t - self._origins[k], True
        powers = tau ** self._powers
        q = powers @ c[k]
        if not moving:
            z = np.zeros_like(q)
            return q, z, z.copy()
        return q, powers[:-1] @ dc[k], powers[:-2] @ ddc[k]


@dataclass(frozen=True)
class RaisedCosine:
    """q̇(t) = k (1 − cos(2π (t − t_i)/T)), T = t_f − t_i: Problem 4.2.

    Integrating, q(t) = k1 + k (τ − T/(2π) sin(2πτ/T)), τ = t − t_i, with k1 = q_i and
    k = (q_f − q_i)/T (null boundary velocity and acceleration).
    """

    q_i: np.ndarray
    q_f: np.ndarray
    t_i: float
    t_f: float

    @property
    def k(self) -> np.ndarray:
        return (np.asarray(self.q_f) - np.asarray(self.q_i)) / (self.t_f - self.t_i)

    @property
    def k1(self) -> np.ndarray:
        return np.asarray(self.q_i)

    @property
    def a(self) -> float:
        """Angular frequency a = 2π/T of the velocity profile."""
        return 2.0 * np.pi / (self.t_f - self.t_i)

    def __call__(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = _as_instants(t)
        vs = np.shape(self.q_i)
        tau = (np.clip(t, self.t_i, self.t_f) - self.t_i).reshape(t.shape + (1,) * len(vs))
        a, k = self.a, self.k
        q = self.k1 + k * (tau - np.sin(a * tau) / a)
        qd = k * (1.0 - np.cos(a * tau))
        qdd = k * a * np.sin(a * tau)
        return q, qd, qdd


def polynomial_law(t_i: float, t_f: float, start: tuple, end: tuple) -> PiecewisePolynomial:
    """The polynomial of degree 2m−1 matching m derivatives (q, q̇[, q̈]) at t_i and t_f.

    ``start`` and ``end`` are (q, q̇) for a cubic, Eq. (4.1)–(4.2), and (q, q̇, q̈) for a quintic,
    Eq. (4.3); each entry a scalar or an (n,) vector.
    """
    t_i, t_f, T = _as_interval(t_i, t_f)
    m = len(start)
    if len(end) != m or m not in (2, 3):
        raise ValueError("`start` and `end` must both be (q, qd) or (q, qd, qdd)")
    shape = np.shape(np.asarray(start[0], dtype=float))
    names = ("q", "qd", "qdd")
    b = np.stack([_as_value(v, shape, f"{names[i]}_i") for i, v in enumerate(start)]
                 + [_as_value(v, shape, f"{names[i]}_f") for i, v in enumerate(end)])
    d = 2 * m - 1
    # Rows: the i-th derivative of τ^j at τ = 0 and at τ = T.
    A = np.zeros((2 * m, d + 1))
    for i in range(m):
        for j in range(i, d + 1):
            f = np.prod(np.arange(j - i + 1, j + 1, dtype=float))  # j!/(j−i)!
            A[i, j] = f if j == i else 0.0
            A[m + i, j] = f * T ** (j - i)
    coeffs = np.linalg.solve(A, b.reshape(2 * m, -1)).reshape((d + 1,) + shape)
    return PiecewisePolynomial(np.array([t_i, t_f], dtype=float), coeffs[None])


def cubic_law(q_i: Any, q_f: Any, t_f: float, qd_i: Any = 0.0, qd_f: Any = 0.0, *,
              t_i: float = 0.0) -> PiecewisePolynomial:
    """Cubic polynomial (4.1) with assigned boundary positions and velocities (4.2)."""
    return polynomial_law(t_i, t_f, (q_i, qd_i), (q_f, qd_f))


def quintic_law(q_i: Any, q_f: Any, t_f: float, qd_i: Any = 0.0, qd_f: Any = 0.0, qdd_i: Any = 0.0,
                qdd_f: Any = 0.0, *, t_i: float = 0.0) -> PiecewisePolynomial:
    """Quintic polynomial (4.3) with assigned boundary positions, velocities and accelerations.

    The coefficients ``law.coefficients[0]`` are [a0, ..., a5] of q(t) = Σ a_j (t − t_i)^j
    (Problem 4.1).
    """
    return polynomial_law(t_i, t_f, (q_i, qd_i, qdd_i), (q_f, qd_f, qdd_f))


# --------------------------------------------------------------------------------------------
# Trapezoidal velocity profile, Eq. (4.8)
# --------------------------------------------------------------------------------------------

def trapezoidal_limits(q_i: Any, q_f: Any, t_f: float, t_i: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Admissible cruise speeds |q̇_c| in (|Δq|/T, 2|Δq|/T] for a trapezoid of duration T, Eq. (4.8)."""
    t_i, t_f, T = _as_interval(t_i, t_f)
    dq = np.abs(_as_value(q_f, None, "q_f") - _as_value(q_i, None, "q_i"))
    return dq / T, 2.0 * dq / T


def _trapezoid(q_i: np.ndarray, q_f: np.ndarray, t_i: float, t_f: float, t_c: np.ndarray,
               qdd_c: np.ndarray) -> PiecewisePolynomial:
    """The three pieces of (4.8), in powers of τ = t − t_i, for each joint's t_c and |q̈_c|.

    Joints with different t_c get the union of their phase boundaries as breaks.
    """
    T = t_f - t_i
    qi, qf, tc, a = (np.atleast_1d(x).astype(float) for x in (q_i, q_f, t_c, qdd_c))
    cuts = np.unique(np.concatenate([[0.0, T], tc, T - tc]))
    cuts = cuts[(cuts >= 0.0) & (cuts <= T)]
    acc = np.sign(qf - qi) * a
    coeffs = np.zeros((cuts.size - 1, 3, qi.size))
    for k in range(cuts.size - 1):
        mid = 0.5 * (cuts[k] + cuts[k + 1])
        rise, fall = mid <= tc, mid >= T - tc
        cruise = ~(rise | fall)
        # rise: q_i + ½ q̈_c τ²; cruise: q_i + q̈_c t_c (τ − t_c/2); fall: q_f − ½ q̈_c (T − τ)²
        coeffs[k, 0] = np.where(rise, qi, np.where(cruise, qi - 0.5 * acc * tc ** 2, qf - 0.5 * acc * T ** 2))
        coeffs[k, 1] = np.where(rise, 0.0, np.where(cruise, acc * tc, acc * T))
        coeffs[k, 2] = np.where(rise, 0.5 * acc, np.where(cruise, 0.0, -0.5 * acc))
    if np.ndim(q_i) == 0:
        coeffs = coeffs[..., 0]
    return PiecewisePolynomial(t_i + cuts, coeffs, origins=np.full(cuts.size - 1, float(t_i)))


def trapezoidal_law(q_i: Any, q_f: Any, t_f: float, qd_c: Any, *, t_i: float = 0.0,
                    triangular: bool = False) -> PiecewisePolynomial:
    """Trapezoidal velocity profile (4.8) given the cruise speed q̇_c and the duration.

    As the companion ``trapez.m``: t_c = T − |Δq|/|q̇_c| and q̈_c = |q̇_c|/t_c (the direction
    of motion is that of q_f − q_i; the sign of ``qd_c`` is ignored). The profile exists iff
    |Δq|/T < |q̇_c| ≤ 2|Δq|/T (equality on the right: triangular profile, t_c = T/2).
    A joint with q_f = q_i stays still whatever q̇_c.

    Parameters
    ----------
    q_i, q_f : scalar or (n,) [rad | m].
    t_f : final instant [s]; the motion lasts T = t_f − t_i.
    qd_c : scalar or (n,) cruise speed [rad/s | m/s].
    triangular : when True, a cruise speed above 2|Δq|/T is lowered to 2|Δq|/T (the triangular
        profile, minimum acceleration 4|Δq|/T²) instead of raising ValueError. A speed at or
        below |Δq|/T always raises: the motion cannot end at t_f.

    Raises
    ------
    ValueError naming the joint and the admissible range of ``qd_c``.
    """
    t_i, t_f, T = _as_interval(t_i, t_f)
    qi = _as_value(q_i, None, "q_i")
    qf = _as_value(q_f, qi.shape, "q_f")
    vc = np.abs(_as_value(qd_c, qi.shape, "qd_c"))
    dq = np.abs(qf - qi)
    lo, hi = dq / T, 2.0 * dq / T
    moving = dq > 0
    too_slow = moving & (vc <= lo)
    too_fast = moving & (vc > hi * (1.0 + 1e-12))
    if triangular:
        vc = np.where(too_fast, hi, vc)
        too_fast = np.zeros_like(too_fast)
    bad = too_slow | too_fast
    if np.any(bad):
        j = int(np.flatnonzero(np.atleast_1d(bad))[0])
        lo1, hi1, v1 = (float(np.atleast_1d(x)[j]) for x in (lo, hi, vc))
        which = f"`qd_c[{j}]`" if qi.ndim else "`qd_c`"
        hint = "" if v1 <= lo1 else " (or pass triangular=True for the triangular profile)"
        raise ValueError(f"{which} must be in (|q_f - q_i|/T, 2|q_f - q_i|/T] = ({lo1:.6g}, {hi1:.6g}] "
                         f"for a trapezoidal profile lasting T = {T:.6g} s, got {v1:.6g}{hint}")
    vc = np.minimum(vc, hi)  # within rounding of the triangular bound
    with np.errstate(divide="ignore", invalid="ignore"):
        t_c = np.where(moving, T - dq / np.where(moving, vc, 1.0), 0.0)  # Eq. (4.8)
        qdd_c = np.where(moving, vc / np.where(moving, t_c, 1.0), 0.0)
    return _trapezoid(qi, qf, t_i, t_f, t_c, qdd_c)


def trapezoidal_acceleration_law(q_i: Any, q_f: Any, t_f: float, qdd_c: Any, *,
                                 t_i: float = 0.0) -> PiecewisePolynomial:
    """Trapezoidal profile given the acceleration: t_c = T/2 − ½ √((T² q̈_c − 4|Δq|)/q̈_c), Sect. 4.2.2.

    Needs |q̈_c| ≥ 4|Δq|/T² (equality: triangular profile); ValueError with that bound otherwise.
    """
    t_i, t_f, T = _as_interval(t_i, t_f)
    qi = _as_value(q_i, None, "q_i")
    qf = _as_value(q_f, qi.shape, "q_f")
    a = np.abs(_as_value(qdd_c, qi.shape, "qdd_c"))
    dq = np.abs(qf - qi)
    lo = 4.0 * dq / T ** 2
    bad = (dq > 0) & (a < lo * (1.0 - 1e-12))
    if np.any(bad):
        j = int(np.flatnonzero(np.atleast_1d(bad))[0])
        raise ValueError(f"`qdd_c[{j}]` must be at least 4|q_f - q_i|/T^2 = {float(np.atleast_1d(lo)[j]):.6g}, "
                         f"got {float(np.atleast_1d(a)[j]):.6g}")
    moving = dq > 0
    a = np.where(moving, np.maximum(a, lo), 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_c = np.where(moving, 0.5 * T - 0.5 * np.sqrt(np.maximum(T ** 2 - 4.0 * dq / np.where(moving, a, 1.0), 0.0)), 0.0)
    return _trapezoid(qi, qf, t_i, t_f, t_c, a)


def raised_cosine_law(q_i: Any, q_f: Any, t_f: float, *, t_i: float = 0.0) -> RaisedCosine:
    """The law with velocity profile k (1 − cos(a t)), a = 2π/T: Problem 4.2."""
    t_i, t_f, _ = _as_interval(t_i, t_f)
    qi = _as_value(q_i, None, "q_i")
    qf = _as_value(q_f, qi.shape, "q_f")
    return RaisedCosine(qi, qf, t_i, t_f)


# --------------------------------------------------------------------------------------------
# Trajectory
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Trajectory:
    """Samples of a joint-space timing law, time-major.

    Attributes
    ----------
    t : (N,) instants [s].
    q, qd, qdd : (N, n) positions, velocities, accelerations; row k is time t[k], column j joint j.
    law : the law ``law(t) -> (q, qd, qdd)`` the samples came from (evaluated by :meth:`evaluate`).
    name : what produced it (e.g. ``"quintic"``).
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    law: Callable[[Any], tuple] = field(repr=False)
    name: str = ""

    def __len__(self) -> int:
        return self.t.shape[0]

    def __str__(self) -> str:
        return (f"Trajectory {self.name or '(unnamed)'}: {len(self)} samples x {self.n} joints "
                f"on [{self.t[0]:.6g}, {self.t[-1]:.6g}] s")

    def __repr__(self) -> str:
        return f"<{self}>"

    @property
    def n(self) -> int:
        """Number of joints (columns)."""
        return self.q.shape[1]

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0])

    def evaluate(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q, q̇, q̈) at one instant, each (n,); held at the end values outside the law's interval."""
        q, qd, qdd = self.law(float(t))
        return (np.reshape(q, self.n), np.reshape(qd, self.n), np.reshape(qdd, self.n))

    def sample(self, t: Any) -> "Trajectory":
        """The same law sampled at the instants ``t`` (any increasing (M,) array)."""
        return sample(self.law, times=t, name=self.name)

    def plot(self, axes: Any = None, labels: Any = None, units: Any = "rad") -> Any:
        """Position, velocity and acceleration against time on three axes (created if None).

        ``units``: the joint variables' unit, ``"rad"`` (default) or ``"m"``, one per joint, or a
        :class:`~rigid_body.robots.Robot` (its joint types); the axes read q [rad], q̇ [rad/s],
        q̈ [rad/s²]. The legend (several joints) sits beside the axes, clear of the curves.
        Returns the three axes; never shows the figure.
        """
        if axes is None:
            import matplotlib.pyplot as plt

            _, axes = plt.subplots(3, 1, sharex=True, figsize=(7.2, 6.4))
        if hasattr(units, "model"):
            from rigid_body.robots import joint_units

            units = joint_units(units)
        units = [units] * self.n if isinstance(units, str) else list(units)
        if len(units) != self.n or not set(units) <= {"rad", "m"}:
            raise ValueError(f"`units` must be 'rad' or 'm', one per joint ({self.n}), got {units}")
        kinds = sorted(set(units), reverse=True)  # rad before m
        labels = labels if labels is not None else [f"joint {j + 1}" for j in range(self.n)]
        names = tuple(f"{y} [{' | '.join(u + suffix for u in kinds)}]"
                      for y, suffix in (("q", ""), ("q̇", "/s"), ("q̈", "/s²")))
        for ax, y, name in zip(axes, (self.q, self.qd, self.qdd), names):
            for j in range(self.n):
                ax.plot(self.t, y[:, j], label=labels[j] if self.n > 1 else None)
            ax.set_ylabel(name)
            ax.grid(True, alpha=0.3)
        axes[-1].set_xlabel("t [s]")
        if self.n > 1:
            axes[0].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
            axes[0].figure.subplots_adjust(right=0.8)
        return axes


def sample(law: Callable[[Any], tuple], *, samples: int | None = None, dt: float | None = None,
           times: Any = None, name: str = "") -> Trajectory:
    """Sample a law into a :class:`Trajectory`.

    Give one of ``samples`` (count, evenly spaced over [law.t_i, law.t_f], default 501), ``dt``
    (step [s]; the grid runs t_i, t_i + dt, ..., up to t_f included when it falls on the grid)
    or ``times`` (explicit increasing instants).
    """
    if sum(x is not None for x in (samples, dt, times)) > 1:
        raise ValueError("give only one of `samples`, `dt`, `times`")
    if times is not None:
        t = _as_times(times, "times", minimum=1)
    else:
        t_i, t_f = float(law.t_i), float(law.t_f)
        if dt is not None:
            dt = as_positive(dt, "dt")
            m = int(np.floor((t_f - t_i) / dt + 1e-9))
            t = t_i + dt * np.arange(m + 1)
        else:
            if samples is not None and (isinstance(samples, bool) or not isinstance(samples, (int, np.integer))):
                raise ValueError(f"`samples` must be an integer, got {samples!r}")
            samples = 501 if samples is None else int(samples)
            if samples < 2:
                raise ValueError(f"`samples` must be at least 2, got {samples}")
            t = np.linspace(t_i, t_f, samples)
    q, qd, qdd = law(t)
    N = t.size
    return Trajectory(t, np.reshape(q, (N, -1)), np.reshape(qd, (N, -1)), np.reshape(qdd, (N, -1)),
                      law, name)


def cubic(q_i: Any, q_f: Any, t_f: float, qd_i: Any = 0.0, qd_f: Any = 0.0, *, t_i: float = 0.0,
          samples: int | None = None, dt: float | None = None) -> Trajectory:
    """Cubic joint trajectory, Eqs. (4.1)–(4.2), sampled (see :func:`sample`)."""
    return sample(cubic_law(q_i, q_f, t_f, qd_i, qd_f, t_i=t_i), samples=samples, dt=dt, name="cubic")


def quintic(q_i: Any, q_f: Any, t_f: float, qd_i: Any = 0.0, qd_f: Any = 0.0, qdd_i: Any = 0.0,
            qdd_f: Any = 0.0, *, t_i: float = 0.0, samples: int | None = None,
            dt: float | None = None) -> Trajectory:
    """Quintic joint trajectory, Eq. (4.3), sampled (see :func:`sample`).

    >>> tr = quintic(1.0, 4.0, 2.0, dt=0.01)          # Problem 4.1
    >>> round(float(tr.evaluate(1.0)[1][0]), 12)       # peak velocity 15 Δq / (8 T)
    2.8125
    """
    return sample(quintic_law(q_i, q_f, t_f, qd_i, qd_f, qdd_i, qdd_f, t_i=t_i),
                  samples=samples, dt=dt, name="quintic")


def trapezoidal(q_i: Any, q_f: Any, t_f: float, qd_c: Any, *, t_i: float = 0.0, triangular: bool = False,
                samples: int | None = None, dt: float | None = None) -> Trajectory:
    """Trapezoidal velocity profile (4.8) given q̇_c and t_f, sampled; see :func:`trapezoidal_law`.

    >>> tr = trapezoidal([0, np.pi/4], [np.pi/2, np.pi/2], 1.0, [3*np.pi/4, np.pi/3])  # tra_4
    >>> np.round(tr.evaluate(1.0)[0], 6).tolist()
    [1.570796, 1.570796]
    """
    return sample(trapezoidal_law(q_i, q_f, t_f, qd_c, t_i=t_i, triangular=triangular),
                  samples=samples, dt=dt, name="trapezoidal")


def raised_cosine(q_i: Any, q_f: Any, t_f: float, *, t_i: float = 0.0, samples: int | None = None,
                  dt: float | None = None) -> Trajectory:
    """Raised-cosine velocity profile k(1 − cos(2π t/T)) (Problem 4.2), sampled."""
    return sample(raised_cosine_law(q_i, q_f, t_f, t_i=t_i), samples=samples, dt=dt, name="raised cosine")


# --------------------------------------------------------------------------------------------
# Sequences of polynomials through via points (Sect. 4.3)
# --------------------------------------------------------------------------------------------

def via_point_velocities(t: Any, q: Any, qd_i: Any = 0.0, qd_f: Any = 0.0) -> np.ndarray:
    """Velocities at the via points by the book's heuristic (Sect. 4.3.1).

    v_k = 0 where the slopes v_{k−1,k}, v_{k,k+1} of the adjacent segments have opposite signs,
    else their mean; ``qd_i``, ``qd_f`` at the ends. Returns the shape of ``q``.
    """
    t = _as_times(t, "t")
    q = _as_points(q, t.size)
    slope = np.diff(q, axis=0) / np.diff(t).reshape((-1,) + (1,) * (q.ndim - 1))
    v = np.empty_like(q)
    v[0] = _as_value(qd_i, q.shape[1:], "qd_i")
    v[-1] = _as_value(qd_f, q.shape[1:], "qd_f")
    same = np.sign(slope[:-1]) == np.sign(slope[1:])
    v[1:-1] = np.where(same, 0.5 * (slope[:-1] + slope[1:]), 0.0)
    return v


def via_point_accelerations(t: Any, qd: Any, qdd_i: Any = 0.0, qdd_f: Any = 0.0) -> np.ndarray:
    """Accelerations at the via points as the mean of the adjacent velocity slopes (Problem 4.3).

    q̈_k = ½ ((q̇_k − q̇_{k−1})/Δt_{k−1} + (q̇_{k+1} − q̇_k)/Δt_k); ``qdd_i``, ``qdd_f`` at the ends.
    """
    t = _as_times(t, "t")
    qd = _as_points(qd, t.size, "qd")
    slope = np.diff(qd, axis=0) / np.diff(t).reshape((-1,) + (1,) * (qd.ndim - 1))
    a = np.empty_like(qd)
    a[0] = _as_value(qdd_i, qd.shape[1:], "qdd_i")
    a[-1] = _as_value(qdd_f, qd.shape[1:], "qdd_f")
    a[1:-1] = 0.5 * (slope[:-1] + slope[1:])
    return a


def polynomial_sequence_law(t: Any, q: Any, qd: Any = None, qdd: Any = None, *, degree: int = 5,
                            qd_i: Any = 0.0, qd_f: Any = 0.0, qdd_i: Any = 0.0,
                            qdd_f: Any = 0.0) -> PiecewisePolynomial:
    """Polynomials through the points (t_k, q_k) joined with continuous velocity (and acceleration).

    ``degree=3``: cubics with velocities ``qd`` at the points (default: the
    book's heuristic, :func:`via_point_velocities`), continuous velocity.
    ``degree=5``: quintics with velocities and accelerations at the points (default accelerations:
    :func:`via_point_accelerations`), continuous velocity and acceleration (Problem 4.3).

    Parameters
    ----------
    t : (m,) strictly increasing instants [s], m ≥ 2.
    q : (m,) or (m, n) positions, one row per instant.
    qd, qdd : same shape, the velocities/accelerations at the points (ends included), or None.
    """
    t = _as_times(t, "t")
    q = _as_points(q, t.size)
    if degree not in (3, 5):
        raise ValueError(f"`degree` must be 3 (cubic) or 5 (quintic), got {degree}")
    qd = via_point_velocities(t, q, qd_i, qd_f) if qd is None else _as_points(qd, t.size, "qd")
    if qd.shape != q.shape:
        raise ValueError(f"`qd` must have the shape of `q` {q.shape}, got {qd.shape}")
    pieces = []
    if degree == 5:
        qdd = via_point_accelerations(t, qd, qdd_i, qdd_f) if qdd is None else _as_points(qdd, t.size, "qdd")
        if qdd.shape != q.shape:
            raise ValueError(f"`qdd` must have the shape of `q` {q.shape}, got {qdd.shape}")
    for k in range(t.size - 1):
        if degree == 5:
            law = polynomial_law(t[k], t[k + 1], (q[k], qd[k], qdd[k]), (q[k + 1], qd[k + 1], qdd[k + 1]))
        else:
            law = polynomial_law(t[k], t[k + 1], (q[k], qd[k]), (q[k + 1], qd[k + 1]))
        pieces.append(law.coefficients[0][: degree + 1])
    return PiecewisePolynomial(t, np.stack(pieces))


def polynomial_sequence(t: Any, q: Any, qd: Any = None, qdd: Any = None, *, degree: int = 5,
                        qd_i: Any = 0.0, qd_f: Any = 0.0, qdd_i: Any = 0.0, qdd_f: Any = 0.0,
                        samples: int | None = None, dt: float | None = None) -> Trajectory:
    """Sampled :func:`polynomial_sequence_law`."""
    law = polynomial_sequence_law(t, q, qd, qdd, degree=degree, qd_i=qd_i, qd_f=qd_f, qdd_i=qdd_i, qdd_f=qdd_f)
    return sample(law, samples=samples, dt=dt, name=f"{'quintic' if degree == 5 else 'cubic'} sequence")


# --------------------------------------------------------------------------------------------
# Cubic spline with two virtual points, Eq. (4.28)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class SplineSystem:
    """The tridiagonal system A x = b of (4.28), x = [Π̈_2(t_2), ..., Π̈_{N+1}(t_{N+1})].

    ``A_banded`` is A in the (3, N) LAPACK band layout (upper diagonal, diagonal, lower diagonal);
    :attr:`A` is the dense matrix (for display). ``knots`` are the N+2 instants t_1, ..., t_{N+2}
    (virtual points at t_2 and t_{N+1}).
    """

    knots: np.ndarray
    A_banded: np.ndarray
    b: np.ndarray
    positions: np.ndarray  # q at the N+2 knots, the two virtual ones set to α of (S4.3), (S4.4)
    beta: tuple[float, float]  # Δt_1²/6 and Δt_{N+1}²/6: q_2 = α_2 + β_2 x_1, q_{N+1} = α + β x_N

    def knot_positions(self, x: np.ndarray) -> np.ndarray:
        """q at all N+2 knots once the accelerations x are known (virtual points by (S4.3), (S4.4))."""
        q = self.positions.copy()
        q[1] = q[1] + self.beta[0] * x[0]
        q[-2] = q[-2] + self.beta[1] * x[-1]
        return q

    @property
    def A(self) -> np.ndarray:
        return (np.diag(self.A_banded[1]) + np.diag(self.A_banded[0, 1:], 1)
                + np.diag(self.A_banded[2, :-1], -1))


def _spline_knots(t: np.ndarray, t_virtual: Any) -> np.ndarray:
    if t_virtual is None:
        t_virtual = (0.5 * (t[0] + t[1]), 0.5 * (t[-2] + t[-1]))
    tv = as_vector(t_virtual, 2, "t_virtual")
    if not (t[0] < tv[0] < t[1] and t[-2] < tv[1] < t[-1]):
        raise ValueError(f"`t_virtual` must lie in ({t[0]}, {t[1]}) and ({t[-2]}, {t[-1]}), got {tv}")
    return np.concatenate([[t[0], tv[0]], t[1:-1], [tv[1], t[-1]]])


def spline_system(t: Any, q: Any, qd_i: Any = 0.0, qd_f: Any = 0.0, qdd_i: Any = 0.0, qdd_f: Any = 0.0,
                  t_virtual: Any = None) -> SplineSystem:
    """Assemble (4.28) for the cubic spline through N ≥ 3 points with two virtual points.

    The equations are (S4.2) for k = 1, ..., N with q_2 and q_{N+1} replaced by (S4.3), (S4.4),
    which are linear in the first and last unknowns: this reproduces the a_ij, b_i of
    Problem 4.4 (including the special b_2 for N = 3).

    Parameters
    ----------
    t : (N,) instants of the given points t_1, t_3, ..., t_N, t_{N+2} (book numbering).
    q : (N,) or (N, n) positions at those instants.
    qd_i, qd_f, qdd_i, qdd_f : boundary velocities and accelerations.
    t_virtual : instants (t_2, t_{N+1}) of the virtual points; default the midpoints of the first
        and last intervals.
    """
    t = _as_times(t, "t", minimum=3)
    q = _as_points(q, t.size)
    N = t.size
    shape = q.shape[1:]
    vi, vf = _as_value(qd_i, shape, "qd_i"), _as_value(qd_f, shape, "qd_f")
    ai, af = _as_value(qdd_i, shape, "qdd_i"), _as_value(qdd_f, shape, "qdd_f")
    knots = _spline_knots(t, t_virtual)
    dt = np.diff(knots)  # Δt_1, ..., Δt_{N+1}
    # Positions at the N+2 knots; the two virtual ones are α + β x (S4.3), (S4.4).
    qk = np.concatenate([q[:1], np.zeros((1,) + shape), q[1:-1], np.zeros((1,) + shape), q[-1:]])
    alpha2 = q[0] + vi * dt[0] + ai * dt[0] ** 2 / 3.0
    beta2 = dt[0] ** 2 / 6.0
    alphaN1 = q[-1] - vf * dt[-1] + af * dt[-1] ** 2 / 3.0
    betaN1 = dt[-1] ** 2 / 6.0
    qk[1], qk[N] = alpha2, alphaN1
    sub, diag, sup = np.zeros(N), np.zeros(N), np.zeros(N)
    b = np.zeros((N,) + shape)
    for r in range(N):  # row r ↔ (S4.2) with k = r + 1 (book), knots r, r+1, r+2 (0-based)
        d0, d1 = dt[r], dt[r + 1]
        sub[r], diag[r], sup[r] = d0 / 6.0, (d0 + d1) / 3.0, d1 / 6.0
        w = (1.0 / d0, -(1.0 / d1 + 1.0 / d0), 1.0 / d1)  # weights of q at knots r, r+1, r+2
        b[r] = w[0] * qk[r] + w[1] * qk[r + 1] + w[2] * qk[r + 2]
        for j, wj in zip((r, r + 1, r + 2), w):  # move the virtual points' x-terms to the left
            if j == 1:
                _add(sub, diag, sup, r, 0, -wj * beta2)
            elif j == N:
                _add(sub, diag, sup, r, N - 1, -wj * betaN1)
    b[0] -= dt[0] / 6.0 * ai  # Π̈_1 = q̈_i (4.19)
    b[-1] -= dt[-1] / 6.0 * af  # Π̈_{N+2} = q̈_f (4.22)
    banded = np.zeros((3, N))
    banded[0, 1:] = sup[:-1]
    banded[1] = diag
    banded[2, :-1] = sub[1:]
    return SplineSystem(knots, banded, b, qk, (beta2, betaN1))


def _add(sub: np.ndarray, diag: np.ndarray, sup: np.ndarray, row: int, col: int, value: float) -> None:
    """A[row, col] += value on the three diagonals of a tridiagonal matrix."""
    if col == row:
        diag[row] += value
    elif col == row - 1:
        sub[row] += value
    elif col == row + 1:
        sup[row] += value
    else:  # pragma: no cover - the structure of (4.28) never reaches here
        raise AssertionError("(4.28) is tridiagonal")


def cubic_spline_law(t: Any, q: Any, qd_i: Any = 0.0, qd_f: Any = 0.0, qdd_i: Any = 0.0, qdd_f: Any = 0.0,
                     t_virtual: Any = None) -> PiecewisePolynomial:
    """Cubic spline through N ≥ 3 points with assigned boundary velocities and accelerations.

    Two virtual points (at ``t_virtual``) free the spline's first and last intervals so that the
    four boundary conditions hold (Sect. 4.3, Problem 4.4). The N accelerations at the knots
    t_2, ..., t_{N+1} solve the tridiagonal (4.28) in O(N) (``scipy.linalg.solve_banded``); each
    interval is then the cubic (4.27) in those accelerations.
    """
    system = spline_system(t, q, qd_i, qd_f, qdd_i, qdd_f, t_virtual)
    q = np.asarray(q, dtype=float)
    shape = q.shape[1:]
    x = solve_banded((1, 1), system.A_banded, system.b)
    ai, af = _as_value(qdd_i, shape, "qdd_i"), _as_value(qdd_f, shape, "qdd_f")
    M = np.concatenate([ai[None], x, af[None]])  # Π̈ at the N+2 knots
    dt = np.diff(system.knots)
    d = dt.reshape((-1,) + (1,) * len(shape))
    qk = system.knot_positions(x)
    # (4.27) in powers of τ = t − t_k.
    c0 = qk[:-1]
    c1 = (qk[1:] - qk[:-1]) / d - d * (2 * M[:-1] + M[1:]) / 6.0
    c2 = M[:-1] / 2.0
    c3 = (M[1:] - M[:-1]) / (6.0 * d)
    return PiecewisePolynomial(system.knots, np.stack([c0, c1, c2, c3], axis=1))


def cubic_spline(t: Any, q: Any, qd_i: Any = 0.0, qd_f: Any = 0.0, qdd_i: Any = 0.0, qdd_f: Any = 0.0,
                 t_virtual: Any = None, *, samples: int | None = None, dt: float | None = None) -> Trajectory:
    """Sampled :func:`cubic_spline_law`."""
    return sample(cubic_spline_law(t, q, qd_i, qd_f, qdd_i, qdd_f, t_virtual), samples=samples, dt=dt,
                  name="cubic spline")


# --------------------------------------------------------------------------------------------
# Linear segments with parabolic blends (Sect. 4.3, Problem 4.6)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class BlendCoefficients:
    """The book's coefficients of Problem 4.6 (one row per segment/blend, columns the joints).

    a[k] = (a_k0, a_k1) of the linear segment k (k = 1..N−1): q = a_k1 (t − t_k) + a_k0;
    b[k] = (b_k0, b_k1, b_k2) of the blend about t_k (k = 1..N): q = b_k2 (t − t_k)² + b_k1 (t − t_k) + b_k0.
    """

    a: np.ndarray
    b: np.ndarray


def _as_blend(blend: Any, N: int) -> np.ndarray:
    """Blend durations Δt'_k: a scalar (the same at every point) or (N,), finite and positive."""
    d = np.full(N, as_positive(blend, "blend")) if np.ndim(blend) == 0 else as_vector(blend, N, "blend")
    if np.any(d <= 0):
        raise ValueError(f"`blend` durations must be positive, got {d}")
    return d


def linear_parabolic_blends_law(t: Any, q: Any, blend: Any, qd_i: Any = 0.0,
                                qd_f: Any = 0.0) -> PiecewisePolynomial:
    """Linear segments joined by parabolic blends of duration Δt'_k centred on the points t_k.

    Segment velocities q̇_{k,k+1} = (q_{k+1} − q_k)/Δt_k (q̇_i, q̇_f at the ends); each blend has
    constant acceleration (q̇_{k,k+1} − q̇_{k−1,k})/Δt'_k. As the companion ``lin_par.m``, the
    blends are centred on the knots, so the law runs on [t_1 − Δt'_1/2, t_N + Δt'_N/2] and
    passes *near*, not through, the interior points (Problem 4.6). The pieces keep the book's
    form, powers of (t − t_k); :func:`blend_coefficients` returns a_k0, a_k1, b_k0, b_k1, b_k2.
    """
    t = _as_times(t, "t")
    q = _as_points(q, t.size)
    N = t.size
    shape = q.shape[1:]
    d = _as_blend(blend, N)
    gaps = np.diff(t) - 0.5 * (d[:-1] + d[1:])
    if np.any(gaps < -1e-12):
        k = int(np.argmax(gaps < -1e-12))
        raise ValueError(f"`blend` durations overlap between t[{k}] = {t[k]} and t[{k + 1}] = {t[k + 1]}: "
                         f"need (blend[{k}] + blend[{k + 1}])/2 <= {t[k + 1] - t[k]}")
    coef = blend_coefficients(t, q, d, qd_i, qd_f)
    breaks, origins, pieces = [], [], []
    for k in range(N):
        breaks.append(t[k] - d[k] / 2)
        origins.append(t[k])
        pieces.append(coef.b[k])
        if k < N - 1 and gaps[k] > 1e-12:
            breaks.append(t[k] + d[k] / 2)
            origins.append(t[k])
            pieces.append(np.concatenate([coef.a[k], np.zeros((1,) + shape)]))
    breaks.append(t[-1] + d[-1] / 2)
    return PiecewisePolynomial(np.array(breaks), np.stack(pieces), origins=np.array(origins))


def blend_coefficients(t: Any, q: Any, blend: Any, qd_i: Any = 0.0, qd_f: Any = 0.0) -> BlendCoefficients:
    """a_k0 = q_k, a_k1 = q̇_{k,k+1}; b_k1 = (q̇_{k,k+1} + q̇_{k−1,k})/2,
    b_k2 = (q̇_{k,k+1} − q̇_{k−1,k})/(2Δt'_k), b_k0 = q_k + (q̇_{k,k+1} − q̇_{k−1,k}) Δt'_k/8 (Problem 4.6)."""
    t = _as_times(t, "t")
    q = _as_points(q, t.size)
    N = t.size
    shape = q.shape[1:]
    d = _as_blend(blend, N).reshape((N,) + (1,) * len(shape))
    v = np.concatenate([_as_value(qd_i, shape, "qd_i")[None],
                        np.diff(q, axis=0) / np.diff(t).reshape((-1,) + (1,) * len(shape)),
                        _as_value(qd_f, shape, "qd_f")[None]])  # q̇_{k−1,k}, k = 1..N+1
    before, after = v[:-1], v[1:]
    a = np.stack([q[:-1], after[:-1]], axis=1)
    b = np.stack([q + (after - before) * d / 8.0, (after + before) / 2.0, (after - before) / (2.0 * d)], axis=1)
    return BlendCoefficients(a, b)


def linear_parabolic_blends(t: Any, q: Any, blend: Any, qd_i: Any = 0.0, qd_f: Any = 0.0, *,
                            samples: int | None = None, dt: float | None = None) -> Trajectory:
    """Sampled :func:`linear_parabolic_blends_law`."""
    return sample(linear_parabolic_blends_law(t, q, blend, qd_i, qd_f), samples=samples, dt=dt,
                  name="linear with parabolic blends")


# --------------------------------------------------------------------------------------------
# Multi-segment trajectories timed by per-axis speed limits (in the spirit of the Toolbox's mstraj)
# --------------------------------------------------------------------------------------------

def multi_segment_times(via_points: Any, qd_max: Any = None, t_acc: float = 0.0, *, t_i: float = 0.0,
                        tsegment: Any = None) -> np.ndarray:
    """Instants t_1, ..., t_m of the via points of :func:`multi_segment_law`.

    With ``qd_max``, each segment lasts Δt_k = max(max_j |q_{k+1,j} − q_{k,j}| / q̇_max,j, t_acc): the slowest
    axis runs at its speed limit, the others slower, so that all arrive together; a segment shorter than the
    blend time (a repeated via point among them) is stretched to ``t_acc`` (blends may not overlap). With
    ``tsegment`` (m − 1 durations, each ≥ t_acc) the segments last as given. Give one of the two. The first
    blend starts at ``t_i``, so t_1 = t_i + t_acc/2.
    """
    q = _as_via_points(via_points)
    t_acc = as_positive(t_acc, "t_acc")
    t_i = as_scalar(t_i, "t_i")
    if (qd_max is None) == (tsegment is None):
        raise ValueError("give one of `qd_max` (speed limits) and `tsegment` (segment durations)")
    if tsegment is not None:
        durations = as_vector(tsegment, q.shape[0] - 1, "tsegment")
        if np.any(durations < t_acc):
            k = int(np.argmax(durations < t_acc))
            raise ValueError(f"`tsegment`[{k}] = {durations[k]:g} s is shorter than the blend time t_acc = {t_acc:g} s: "
                             "the blends would overlap")
    else:
        vmax = _as_value(qd_max, q.shape[1:], "qd_max")
        if np.any(vmax <= 0):
            raise ValueError(f"`qd_max` must be positive, got {vmax}")
        durations = np.maximum((np.abs(np.diff(q, axis=0)) / vmax).max(axis=1), t_acc)
    return t_i + 0.5 * t_acc + np.concatenate([[0.0], np.cumsum(durations)])


def multi_segment_law(via_points: Any, qd_max: Any = None, t_acc: float = 0.0, *, t_i: float = 0.0,
                      tsegment: Any = None) -> PiecewisePolynomial:
    """Linear segments through the via points, joined by parabolic blends of duration ``t_acc`` (Sect. 4.3),
    each segment timed by its slowest axis or given its duration (``tsegment``).

    The segment times are :func:`multi_segment_times`; the law is then :func:`linear_parabolic_blends_law`
    with those instants, blends of ``t_acc`` centred on the via points and rest at both ends. It starts at
    q_1 at ``t_i``, ends at q_m at t_m + t_acc/2, never exceeds |q̇_j| ≤ q̇_max,j (the blends move between two
    admissible segment velocities), and passes near each interior via point:
    q(t_k) = q_k + (q̇_{k,k+1} − q̇_{k−1,k}) t_acc/8 (Problem 4.6).

    The multi-segment trajectory of the Robotics Toolbox (``mstraj``, Corke Sect. 3.3.3) has the same idea but is
    not this law: it is sampled, rounds every time up to a multiple of its step dt, makes each segment last at
    least 2 t_acc, starts with half a blend and blends with quintics, so its timing depends on dt (for the via
    points of its documentation, (4, 1), (4, 4), (5, 2), (2, 5) at q̇_max = (2, 1) and t_acc = 1 s: 8 s at
    dt = 1 s and 10.5 s at dt = 1 ms; this law: 9 s).

    Parameters
    ----------
    via_points : (m, n) positions, one row per via point (the first is the start, the last the goal),
        m ≥ 2; or (m,) for a scalar law.
    qd_max : scalar or (n,) positive speed limits [rad/s | m/s]; or
    tsegment : (m − 1,) durations of the segments [s] (each ≥ t_acc).
    t_acc : blend (acceleration) time [s], the same at every via point.
    """
    q = _as_via_points(via_points)
    t = multi_segment_times(q, qd_max, t_acc, t_i=t_i, tsegment=tsegment)
    return linear_parabolic_blends_law(t, q[:, 0] if np.ndim(via_points) == 1 else q, t_acc)


def multi_segment(via_points: Any, qd_max: Any = None, t_acc: float = 0.0, *, t_i: float = 0.0,
                  tsegment: Any = None, samples: int | None = None, dt: float | None = None) -> Trajectory:
    """Sampled :func:`multi_segment_law`."""
    return sample(multi_segment_law(via_points, qd_max, t_acc, t_i=t_i, tsegment=tsegment), samples=samples, dt=dt,
                  name="multi-segment")


def _as_via_points(via_points: Any) -> np.ndarray:
    q = as_array(via_points, "via_points")
    if q.ndim == 1:
        q = q[:, None]
    if q.ndim != 2 or q.shape[0] < 2:
        raise ValueError(f"`via_points` must have shape (m, n) with m >= 2 points, got {np.shape(via_points)}")
    if not np.all(np.isfinite(q)):
        raise ValueError("`via_points` must be finite")
    return q


def time_scaled(law: PiecewisePolynomial, speed: float) -> PiecewisePolynomial:
    """The same path run ``speed`` times faster: q_s(t) = q(speed · t), so q̇_s = speed · q̇ and q̈_s = speed² · q̈
    (the time scaling of Sect. 4.2; the torques' inertial part grows like speed²). Exact for a piecewise polynomial:
    its breaks and origins divided by ``speed``, its j-th coefficients multiplied by speedʲ.

    >>> fast = time_scaled(cubic_law([0.0], [1.0], 2.0), 2.0)
    >>> fast.t_f, [round(float(v[0]), 6) for v in fast(0.5)]
    (1.0, [0.5, 1.5, 0.0])
    """
    if not isinstance(law, PiecewisePolynomial):
        raise ValueError(f"`law` must be a PiecewisePolynomial (e.g. a Trajectory's law), got {type(law).__name__}")
    speed = as_positive(speed, "speed")
    powers = speed ** np.arange(law.coefficients.shape[1])
    c = law.coefficients * powers.reshape((1, -1) + (1,) * (law.coefficients.ndim - 2))
    return PiecewisePolynomial(law.breaks / speed, c, law.origins / speed)
