"""Operational-space paths p(s) and orientation interpolation, timed by a scalar law s(t).

A **path** maps its arc length s ∈ [0, length] to (p(s), dp/ds, d²p/ds²) (Sect. 4.4): a segment
(4.34), a circle in 3-D (4.39), a sequence of segments through via points. A scalar timing
law from :mod:`planners.timing` (``trapezoidal_law(0, path.length, t_f, sd_c)`` …) gives s(t);
:class:`PathLaw` composes them (the general form of (4.42) and (4.44)):

    ṗ = ṡ dp/ds,    p̈ = s̈ dp/ds + ṡ² d²p/ds²,

and :func:`planners.timing.sample` turns it into a :class:`~planners.timing.Trajectory` whose
columns are x, y, z. Orientation: angle–axis interpolation (Sect. 4.5) and the
quaternion *slerp*, both timed by a law ϑ(t) ∈ [0, 1] (fraction of the rotation).

Conventions: positions (3,) [m]; rotations (3, 3); quaternions scalar-first {η, ε} as in the book
(Pinocchio's ``coeffs()`` is [x, y, z, w]).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 4.4 ((4.34), (4.39), (4.42), (4.44)), Sect. 4.5; (2.25)–(2.37) for the rotations used.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol, Sequence

import numpy as np

from planners.timing import TimingLaw, Trajectory, sample
from rigid_body.rotations import (
    as_rotation,
    as_unit_quaternion,
    axis_angle_to_rotation,
    quaternion_inverse,
    quaternion_product,
    quaternion_to_rotation,
    rotation_to_axis_angle,
)
from rigid_body.validation import as_positive, as_vector

__all__ = [
    "Path", "Segment", "Circle", "circle_through", "SegmentSequence", "PathLaw", "path_trajectory",
    "AngleAxisInterpolation", "Slerp", "slerp",
]


class Path(Protocol):
    """A curve parametrised by arc length: ``path(s) -> (p, dp/ds, d²p/ds²)``."""

    length: float

    def __call__(self, s: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]: ...


def _is_nan(x: Any) -> bool:
    return isinstance(x, (float, np.floating)) and np.isnan(x)


def _column(s: Any) -> tuple[np.ndarray, np.ndarray]:
    s = np.asarray(s, dtype=float)
    if not np.all(np.isfinite(s)):
        raise ValueError(f"the arc length `s` must be finite, got {s}")
    return s, s[..., None]


@dataclass(frozen=True)
class Segment:
    """p(s) = p_i + s (p_f − p_i)/‖p_f − p_i‖, s ∈ [0, ‖p_f − p_i‖], Eq. (4.34)."""

    p_i: np.ndarray
    p_f: np.ndarray

    def __post_init__(self) -> None:
        p_i = as_vector(self.p_i, 3, "p_i")
        p_f = as_vector(self.p_f, 3, "p_f")
        if np.linalg.norm(p_f - p_i) == 0.0:
            raise ValueError("`p_f` must differ from `p_i`: a segment needs a positive length")
        object.__setattr__(self, "p_i", p_i)
        object.__setattr__(self, "p_f", p_f)

    @property
    def length(self) -> float:
        return float(np.linalg.norm(self.p_f - self.p_i))

    @property
    def tangent(self) -> np.ndarray:
        """The unit tangent t̂ = (p_f − p_i)/‖p_f − p_i‖ (constant)."""
        return (self.p_f - self.p_i) / self.length

    def __call__(self, s: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        s, sc = _column(s)
        t_hat = self.tangent
        p = self.p_i + sc * t_hat
        return p, np.broadcast_to(t_hat, p.shape).copy(), np.zeros(p.shape)


@dataclass(frozen=True)
class Circle:
    """p(s) = c + R [ρ cos(s/ρ), ρ sin(s/ρ), 0]^T, Eq. (4.39).

    ``R = [x' y' z']`` is the circle frame: z' the axis (motion counter-clockwise about it), x'
    pointing from the centre to p(0). ``length`` is the arc to travel (default a full turn 2πρ).
    """

    center: np.ndarray
    radius: float
    R: np.ndarray
    length: float = float("nan")

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", as_vector(self.center, 3, "center"))
        object.__setattr__(self, "R", as_rotation(self.R, "R"))
        radius = as_positive(self.radius, "radius")
        length = 2.0 * np.pi * radius if _is_nan(self.length) else as_positive(self.length, "length")
        object.__setattr__(self, "radius", radius)
        object.__setattr__(self, "length", length)

    def __call__(self, s: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        s, _ = _column(s)
        rho, a = self.radius, s / self.radius
        c, sn, z = np.cos(a), np.sin(a), np.zeros_like(a)
        local = np.stack([rho * c, rho * sn, z], axis=-1)
        d1 = np.stack([-sn, c, z], axis=-1)
        d2 = np.stack([-c / rho, -sn / rho, z], axis=-1)
        R = self.R
        return self.center + local @ R.T, d1 @ R.T, d2 @ R.T


def circle_through(p_i: Any, axis: Any, point: Any, length: float | None = None) -> Circle:
    """The circle through ``p_i`` about the axis of unit direction ``axis`` through ``point``.

    As in Sect. 4.4: δ = p_i − point, centre c = point + (δ^T r) r, radius ρ = ‖p_i − c‖;
    x' = (p_i − c)/ρ, z' = r, y' = z' × x'. The motion is counter-clockwise about ``axis``.
    ``length`` is the arc to travel (default a full turn).
    """
    p_i = as_vector(p_i, 3, "p_i")
    r = as_vector(axis, 3, "axis")
    if np.linalg.norm(r) == 0:
        raise ValueError("`axis` must be a non-zero vector")
    r = r / np.linalg.norm(r)
    d = as_vector(point, 3, "point")
    c = d + ((p_i - d) @ r) * r
    rho = float(np.linalg.norm(p_i - c))
    if rho < 1e-12:
        raise ValueError("`p_i` lies on the axis: the circle would have zero radius")
    x = (p_i - c) / rho
    R = np.column_stack([x, np.cross(r, x), r])
    return Circle(c, rho, R, float("nan") if length is None else length)


@dataclass(frozen=True)
class SegmentSequence:
    """Straight segments through via points p_0, ..., p_m, each timed by its own law.

    p(t) = p_0 + Σ_j s_j(t)/‖p_j − p_{j−1}‖ (p_j − p_{j−1}) (Sect. 4.4, via points): the law
    s_j(t) of segment j goes from 0 to ‖p_j − p_{j−1}‖ (and is held outside its interval). If
    segment j+1 starts before segment j ends, the two motions overlap and the path rounds the
    via point p_j instead of stopping there; with no overlap it passes through it at rest.
    Calling it with t gives (p, ṗ, p̈) directly: it is a law on time, not on arc length.
    """

    points: np.ndarray
    laws: Sequence[TimingLaw]
    _tangents: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3 or pts.shape[0] < 2:
            raise ValueError(f"`points` must have shape (m+1, 3) with m >= 1, got {pts.shape}")
        if not np.all(np.isfinite(pts)):
            raise ValueError("`points` must be finite")
        if len(self.laws) != pts.shape[0] - 1:
            raise ValueError(f"`laws` must hold one law per segment ({pts.shape[0] - 1}), got {len(self.laws)}")
        lengths = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        if np.any(lengths == 0):
            raise ValueError("consecutive `points` must differ")
        for j, (law, L) in enumerate(zip(self.laws, lengths)):
            _law_range(law, 0.0, float(L), name=f"laws[{j}]", ends=(0.0, float(L)),
                       what=" (from 0 to the segment length)")
        object.__setattr__(self, "points", pts)
        steps = np.diff(pts, axis=0)
        object.__setattr__(self, "_tangents", tuple(step / np.linalg.norm(step) for step in steps))

    @property
    def t_i(self) -> float:
        return min(float(law.t_i) for law in self.laws)

    @property
    def t_f(self) -> float:
        return max(float(law.t_f) for law in self.laws)

    def __call__(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if isinstance(t, (float, int, np.floating, np.integer)):
            return self._at(float(t))
        t = np.asarray(t, dtype=float)
        p = np.broadcast_to(self.points[0], t.shape + (3,)).copy()
        pd, pdd = np.zeros_like(p), np.zeros_like(p)
        for law, t_hat in zip(self.laws, self._tangents):
            s, sd, sdd = (np.asarray(x)[..., None] for x in law(t))
            p += s * t_hat
            pd += sd * t_hat
            pdd += sdd * t_hat
        return p, pd, pdd

    def _at(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """One instant (a controller's reference at every sample): the laws' scalar fast path."""
        p, pd, pdd = self.points[0].copy(), np.zeros(3), np.zeros(3)
        for law, t_hat in zip(self.laws, self._tangents):
            s, sd, sdd = law(t)
            p += s * t_hat
            pd += sd * t_hat
            pdd += sdd * t_hat
        return p, pd, pdd


def _law_range(timing: TimingLaw, lo: float, hi: float, name: str = "timing",
               ends: tuple[float, float] | None = None, what: str = "") -> None:
    """Check that the scalar law ``timing`` stays within [lo, hi] on [t_i, t_f] (201 samples, ends
    included) and, with ``ends``, starts and ends at those values: ValueError naming ``name``.
    A law leaving the range would extrapolate the path or the rotation past its end points."""
    t_i, t_f = float(timing.t_i), float(timing.t_f)
    if np.ndim(timing(t_i)[0]) != 0:
        raise ValueError(f"`{name}` must be a scalar law (built from scalar boundary values)")
    values = np.asarray(timing(np.linspace(t_i, t_f, 201))[0], dtype=float)
    slack = 1e-9 * max(1.0, abs(hi - lo))
    if not np.all(np.isfinite(values)) or values.min() < lo - slack or values.max() > hi + slack:
        raise ValueError(f"`{name}` must stay within [{lo:.6g}, {hi:.6g}]{what} on [t_i, t_f] = [{t_i:g}, {t_f:g}], "
                         f"goes from {values.min():.6g} to {values.max():.6g}")
    if ends is not None:
        for which, v, want in (("start", values[0], ends[0]), ("end", values[-1], ends[1])):
            if abs(v - want) > slack:
                raise ValueError(f"`{name}` must {which} at {want:g}, {which}s at {v:.6g}")


class _TimedByLaw:
    """Start and end times of an object timed by its scalar law ``self.timing``."""

    timing: TimingLaw

    @property
    def t_i(self) -> float:
        return float(self.timing.t_i)

    @property
    def t_f(self) -> float:
        return float(self.timing.t_f)


@dataclass(frozen=True)
class PathLaw(_TimedByLaw):
    """A path timed by a scalar law s(t): ``law(t) -> (p, ṗ, p̈)``: ṗ = ṡ p', p̈ = s̈ p' + ṡ² p'' ((4.42), (4.44))."""

    path: Path
    timing: TimingLaw

    def __post_init__(self) -> None:
        _law_range(self.timing, 0.0, float(self.path.length), what=" (s from 0 to the path length)")

    def __call__(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        s, sd, sdd = self.timing(t)
        p, dp, ddp = self.path(s)
        sd, sdd = np.asarray(sd)[..., None], np.asarray(sdd)[..., None]
        return p, sd * dp, sdd * dp + sd**2 * ddp


def path_trajectory(path: Path, timing: TimingLaw, *, samples: int | None = None, dt: float | None = None,
                    name: str = "path") -> Trajectory:
    """Sample ``PathLaw(path, timing)``: a Trajectory whose q, qd, qdd columns are x, y, z."""
    return sample(PathLaw(path, timing), samples=samples, dt=dt, name=name)


# --------------------------------------------------------------------------------------------
# Orientation
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class AngleAxisInterpolation(_TimedByLaw):
    """R(t) = R_i R^i(ϑ(t) θ_f, r^i), Sect. 4.5: rotate about the fixed axis of R_i^T R_f.

    ``timing`` is a scalar law σ(t) from 0 to 1 (the fraction of the angle θ_f ∈ [0, π] of
    R_i^T R_f = R(θ_f, r^i), (2.26)–(2.27)), staying within [0, 1] (ValueError otherwise). Calling it gives (R (…, 3, 3), ω, ω̇) with
    ω = σ̇ θ_f R_i r^i and ω̇ = σ̈ θ_f R_i r^i in the base frame.
    """

    R_i: np.ndarray
    R_f: np.ndarray
    timing: TimingLaw
    theta_f: float = field(init=False)
    axis: np.ndarray = field(init=False)  # r^i, in the frame of R_i

    def __post_init__(self) -> None:
        _law_range(self.timing, 0.0, 1.0, ends=(0.0, 1.0))
        R_i, R_f = as_rotation(self.R_i, "R_i"), as_rotation(self.R_f, "R_f")
        theta, r = rotation_to_axis_angle(R_i.T @ R_f)
        object.__setattr__(self, "R_i", R_i)
        object.__setattr__(self, "R_f", R_f)
        object.__setattr__(self, "theta_f", float(theta))
        object.__setattr__(self, "axis", r)

    def __call__(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        sigma, sd, sdd = (np.asarray(x, dtype=float) for x in self.timing(t))
        w_axis = self.R_i @ self.axis
        R = np.array([self.R_i @ axis_angle_to_rotation(a * self.theta_f, self.axis) for a in sigma.ravel()])
        R = R.reshape(sigma.shape + (3, 3))
        return R, (sd * self.theta_f)[..., None] * w_axis, (sdd * self.theta_f)[..., None] * w_axis


def slerp(Q_i: Any, Q_f: Any, sigma: float) -> np.ndarray:
    """Spherical linear interpolation of unit quaternions {η, ε}, σ ∈ [0, 1], on the shorter arc.

    Q(σ) = sin((1 − σ)Ω)/sin Ω Q_i + sin(σΩ)/sin Ω Q_f, cos Ω = Q_i·Q_f ≥ 0 (Q_f flipped if needed).
    σ outside [0, 1] would extrapolate past Q_i or Q_f: ValueError.
    """
    Q_i = as_unit_quaternion(Q_i, "Q_i")
    Q_f = as_unit_quaternion(Q_f, "Q_f")
    sigma = float(as_vector(sigma, 1, "sigma")[0])
    if not -1e-12 <= sigma <= 1 + 1e-12:
        raise ValueError(f"`sigma` must be in [0, 1], got {sigma}")
    sigma = min(max(sigma, 0.0), 1.0)
    d = float(Q_i @ Q_f)
    if d < 0:
        Q_f, d = -Q_f, -d
    omega = np.arccos(min(d, 1.0))
    if omega < 1e-9:
        return Q_i.copy()
    Q = (np.sin((1 - sigma) * omega) * Q_i + np.sin(sigma * omega) * Q_f) / np.sin(omega)
    return Q / np.linalg.norm(Q)


@dataclass(frozen=True)
class Slerp(_TimedByLaw):
    """Quaternion interpolation Q(t) = slerp(Q_i, Q_f, σ(t)) timed by a scalar law σ: 0 → 1.

    Calling it gives (Q (…, 4) scalar-first, ω, ω̇); σ must stay within [0, 1] (ValueError otherwise). Slerp rotates about the fixed axis of
    Q_i^{-1} * Q_f at constant rate per unit σ: ω = σ̇ θ_f R_i r, the angle θ_f = 2Ω.
    """

    Q_i: np.ndarray
    Q_f: np.ndarray
    timing: TimingLaw
    theta_f: float = field(init=False)
    omega_axis: np.ndarray = field(init=False)  # unit axis in the base frame

    def __post_init__(self) -> None:
        _law_range(self.timing, 0.0, 1.0, ends=(0.0, 1.0))
        Q_i, Q_f = as_unit_quaternion(self.Q_i, "Q_i"), as_unit_quaternion(self.Q_f, "Q_f")
        if Q_i @ Q_f < 0:
            Q_f = -Q_f
        rel = quaternion_product(quaternion_inverse(Q_i), Q_f)  # Q_i^{-1} * Q_f, (2.36)-(2.37)
        eta, eps = float(np.clip(rel[0], -1.0, 1.0)), rel[1:]
        theta = 2.0 * np.arctan2(np.linalg.norm(eps), eta)
        r = eps / np.linalg.norm(eps) if np.linalg.norm(eps) > 0 else np.array([0.0, 0.0, 1.0])
        object.__setattr__(self, "Q_i", Q_i)
        object.__setattr__(self, "Q_f", Q_f)
        object.__setattr__(self, "theta_f", float(theta))
        object.__setattr__(self, "omega_axis", quaternion_to_rotation(Q_i) @ r)

    def __call__(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        sigma, sd, sdd = (np.asarray(x, dtype=float) for x in self.timing(t))
        Q = np.array([slerp(self.Q_i, self.Q_f, a) for a in sigma.ravel()]).reshape(sigma.shape + (4,))
        w = self.omega_axis
        return Q, (sd * self.theta_f)[..., None] * w, (sdd * self.theta_f)[..., None] * w

