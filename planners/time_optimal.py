"""Time-optimal timing of a fixed joint-space path (TOPP-RA) under velocity, acceleration and torque limits.

Two geometric paths q(s):

* a **planner's polyline** (``space`` given): the certified polyline itself with a parabolic blend at each
  corner (:class:`BlendedPolyline`), every blend only as wide as the corner's certified clearance allows.
  The timed motion then never leaves certified free space: the straight pieces are parts of certified
  edges, and every point of a blend lies, coordinate by coordinate, within δ max(|u₋|, |u₊|) of its
  corner, a displacement the clearance at the corner covers (the pair motion bound of the space's
  certificate). The result says ``certified=True`` — for any timing law along q(s), so also for the
  torque-limited one.
* a chapter-4 path (no ``space``): the cubic spline through the waypoints (``certified=False``: a spline
  leaves the polyline between its knots, by up to 0.35 rad measured on a planner's Panda path).

Along q(s), q̇ = q'(s) ṡ, q̈ = q'(s) s̈ + q''(s) ṡ² and the torque τ = B q̈ + C q̇ + g is affine in
(s̈, ṡ²), so every limit is a linear constraint on (s̈, ṡ²) at each grid point: TOPP-RA (Pham & Pham 2018,
the ``toppra`` package) finds the fastest ṡ(s) by reachability analysis. rmpc's dynamics
(:func:`rigid_body.dynamics.inverse_dynamics`) give the torque constraint.

Output: **constant path acceleration** between grid points (ṡ² linear in s, the exact solution of
TOPP-RA's discretisation), not the package's spline of ṡ, which exceeded the torque limits by up to
11 % between grid points (measured). The limits are then re-checked on a fine time grid; when one is
exceeded, the limits given to TOPP-RA are tightened by the excess and the problem re-solved.

The one call sequence from a query to a motion that cannot collide::

    res = rrt_connect(space, q_s, q_g, seed)                     # certified edges
    path = shortcut(space, res.path, seed)                        # certified shortcuts
    motion = time_optimal_path(robot, path, limits, space=space)  # certified blends; motion.certified

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 4.1
(trajectory timing), Sect. 4.2.2 (linear segments with parabolic blends) and 7.1; Pham, Pham, "A new
approach to time-optimal path parameterization based on reachability analysis", IEEE T-RO 34 (2018).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from planners.optimization import JointLimits
from rigid_body.dynamics import inverse_dynamics
from rigid_body.robots import Robot
from rigid_body.validation import as_count

__all__ = ["TimeOptimalPath", "BlendedPolyline", "certified_blends", "time_optimal_path"]

BLEND_SAFETY = 0.9    # a blend uses at most this fraction of the clearance its corner certifies


class BlendedPolyline:
    """The polyline through ``waypoints`` (K, n) with a parabolic blend of half-width δ_k at each interior
    corner, parametrised by s ∈ [0, L] (L = the polyline's length): unit speed on the straight pieces; over
    a blend (parameter length 2δ_k) the quadratic Bézier v_k − δ_k u₋ → v_k → v_k + δ_k u₊, whose tangent
    dq/ds = (1 − τ) u₋ + τ u₊ joins the pieces' (C¹), with constant q'' = (u₊ − u₋)/(2δ_k) (Sect. 4.2.2's
    blend, in space rather than time). δ_k = 0 keeps the corner (allowed only where the path is straight).
    Implements toppra's geometric-path interface: ``path(s, order)``, ``eval``/``evald``/``evaldd``, ``dof``,
    ``path_interval``.
    """

    def __init__(self, waypoints: Any, deltas: Any) -> None:
        W = np.asarray(waypoints, dtype=float)
        if W.ndim != 2 or W.shape[0] < 2 or not np.all(np.isfinite(W)):
            raise ValueError(f"`waypoints` must be a finite (K >= 2, n) array, got shape {W.shape}")
        d = np.diff(W, axis=0)
        lengths = np.linalg.norm(d, axis=1)
        if np.any(lengths <= 0):
            raise ValueError(f"`waypoints` {int(np.argmin(lengths))} and {int(np.argmin(lengths)) + 1} coincide: "
                             "remove repeated waypoints")
        U = d / lengths[:, None]
        deltas = np.concatenate([[0.0], np.asarray(deltas, dtype=float), [0.0]])
        if deltas.size != W.shape[0]:
            raise ValueError(f"`deltas` must give one value per interior waypoint ({W.shape[0] - 2})")
        if not np.all(np.isfinite(deltas)):
            raise ValueError(f"`deltas` must be finite, got {deltas[1:-1]}")
        if np.any(deltas[1:] + deltas[:-1] > lengths * (1 + 1e-12)) or np.any(deltas < 0):
            raise ValueError("blends must not overlap: δ_k + δ_{k+1} <= |edge k| and δ >= 0")
        turn = np.linalg.norm(np.diff(U, axis=0), axis=1)              # |u₊ − u₋| at each interior corner
        sharp = (deltas[1:-1] == 0) & (turn > 1e-12)
        if sharp.any():
            k = int(np.flatnonzero(sharp)[0])
            raise ValueError(f"`deltas`[{k}] = 0 at a corner (waypoint {k + 1} turns by |u₊ − u₋| = {turn[k]:.3g}): "
                             "the path would not be C¹ there; give δ > 0 (δ = 0 only where the path runs straight)")
        self._W, self._U, self.deltas = W, U, deltas[1:-1]
        # pieces: (kind, s0, s1, k) — "line" along edge k, "blend" at corner k
        pieces, s = [], 0.0
        for k in range(len(lengths)):
            if k > 0 and deltas[k] > 0:
                pieces.append(("blend", s, s + 2 * deltas[k], k))
                s += 2 * deltas[k]
            run = lengths[k] - deltas[k] - deltas[k + 1]
            if run > 0 or not pieces:
                pieces.append(("line", s, s + max(run, 0.0), k))
                s += max(run, 0.0)
        self._pieces = pieces
        self._starts = np.array([p[1] for p in pieces])
        self.length = s

    @property
    def dof(self) -> int:
        return self._W.shape[1]

    @property
    def path_interval(self) -> np.ndarray:
        return np.array([0.0, self.length])

    @property
    def waypoints(self) -> None:
        return None

    @property
    def breakpoints(self) -> np.ndarray:
        """The s where a piece starts or ends (q'' may jump there)."""
        return np.append(self._starts, self.length)

    def __call__(self, s: Any, order: int = 0) -> np.ndarray:
        s_arr = np.asarray(s, dtype=float)
        S = np.atleast_1d(s_arr)
        out = np.empty((S.size, self.dof))
        idx = np.clip(np.searchsorted(self._starts, S, side="right") - 1, 0, len(self._pieces) - 1)
        for i in np.unique(idx):
            rows = idx == i
            kind, s0, s1, k = self._pieces[i]
            if kind == "line":
                u = self._U[k]
                start = self._W[k] + self._deltas_full(k) * u
                x = (S[rows] - s0)[:, None]
                out[rows] = start + x * u if order == 0 else (u if order == 1 else 0.0)
            else:
                dlt = self.deltas[k - 1]
                um, up, v = self._U[k - 1], self._U[k], self._W[k]
                t = np.clip((S[rows] - s0) / (2 * dlt), 0.0, 1.0)[:, None]
                if order == 0:
                    out[rows] = v + dlt * (-(1 - t) ** 2 * um + t ** 2 * up)
                elif order == 1:
                    out[rows] = (1 - t) * um + t * up
                else:
                    out[rows] = (up - um) / (2 * dlt)
        return out if s_arr.ndim else out[0]

    def eval(self, s: Any) -> np.ndarray:
        return self(s, 0)

    def evald(self, s: Any) -> np.ndarray:
        return self(s, 1)

    def evaldd(self, s: Any) -> np.ndarray:
        return self(s, 2)

    def _deltas_full(self, k: int) -> float:
        return 0.0 if k == 0 else float(self.deltas[k - 1])


def certified_blends(space: Any, waypoints: np.ndarray, safety: float = BLEND_SAFETY) -> tuple[np.ndarray, float]:
    """Blend half-widths δ_k (K − 2,) for the corners of a polyline whose edges the space certifies, and the
    smallest clearance certified along the polyline.

    Every edge is certified first (:func:`planners.sampling.certify_path`; ValueError naming the edge
    otherwise). At corner k a blend point is v_k + Δ with |Δ_j| ≤ δ max(|u₋,j|, |u₊,j|) (the blend lies in
    the triangle of its control points), so the relative motion of every pair from the corner is at most
    δ · m_p, m_p = ``space.edge_rates(0, max(|u₋|, |u₊|))``; δ_k = ``safety`` · min_p c_p(v_k)/m_p, and at
    most half of each adjacent edge. ``safety`` ∈ (0, 1].
    """
    from planners.sampling import certify_path

    if isinstance(safety, bool) or not isinstance(safety, (int, float, np.integer, np.floating)) \
            or not 0.0 < float(safety) <= 1.0:
        raise ValueError(f"`safety` must be a number in (0, 1] (the fraction of the certified room a blend "
                         f"uses), got {safety!r}")

    cert = certify_path(space, waypoints)
    if not cert.free:
        raise ValueError(f"`waypoints` are not a certified-free polyline in `space`: {cert.message}")
    W = np.asarray(waypoints, dtype=float)
    d = np.diff(W, axis=0)
    lengths = np.linalg.norm(d, axis=1)
    U = d / lengths[:, None]
    deltas = np.zeros(max(len(W) - 2, 0))
    for k in range(1, len(W) - 1):
        um, up = U[k - 1], U[k]
        if np.linalg.norm(up - um) < 1e-12:
            continue                                   # straight on: no corner
        m = np.asarray(space.edge_rates(np.zeros_like(um), np.maximum(np.abs(um), np.abs(up))), dtype=float)
        c = np.asarray(space.clearances(W[k]), dtype=float)
        with np.errstate(divide="ignore"):
            room = float(np.min(np.where(m > 0, c / m, np.inf)))
        deltas[k - 1] = min(safety * room, 0.5 * lengths[k - 1], 0.5 * lengths[k])
    return deltas, cert.min_clearance


@dataclass(frozen=True)
class TimeOptimalPath:
    """t (M,), q, qd, qdd, tau (M, n) on the fine check grid; t_f [s]; ``ratios`` the largest |value|/limit
    of velocity, acceleration and torque on that grid; ``solve_time`` [s]; ``backoffs`` re-solves;
    ``path`` the geometric path q(s) and ``s`` (M,) its parameter at the samples; ``certified`` (the
    motion stays in certified free space at every instant, not only at the samples), with the smallest
    clearance certified along the polyline ``min_clearance`` [m] (NaN when not certified). Calling it,
    ``motion(t)``, gives q, q̇, q̈ at any instants (the exact timing law, like the laws of
    :mod:`planners.timing`)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray
    t_f: float
    ratios: dict
    solve_time: float
    backoffs: int
    path: Any = None
    s: np.ndarray | None = None
    certified: bool = False
    min_clearance: float = float("nan")
    knots: tuple = ()          # (t_k, s_k, ṡ_k, s̈_k) at the TOPP-RA grid points: the timing law s(t)

    @property
    def t_i(self) -> float:
        return 0.0

    def __repr__(self) -> str:
        """One line: duration, size, the certificate and the limit ratios (not the arrays)."""
        cert = f"certified, min clearance {self.min_clearance:.3g} m" if self.certified else "not certified"
        ratios = ", ".join(f"{k} {v:.3g}" for k, v in self.ratios.items())
        return (f"TimeOptimalPath(t_f = {self.t_f:.4g} s, {self.q.shape[1]} joints, {len(self.t)} samples, {cert}; "
                f"limit ratios: {ratios})")

    def __call__(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """q, q̇, q̈ at the instants t (scalar → (n,), (N,) → (N, n)), exactly: s(t) is piecewise quadratic
        (constant s̈ between grid points) and q = q(s(t)); t is clamped to [0, t_f] (rest outside)."""
        tk, sk, sdk, sddk = self.knots
        t_arr = np.asarray(t, dtype=float)
        T = np.clip(np.atleast_1d(t_arr), 0.0, self.t_f)
        i = np.clip(np.searchsorted(tk, T, side="right") - 1, 0, len(sddk) - 1)
        tau = T - tk[i]
        s = np.minimum(sk[i] + sdk[i] * tau + 0.5 * sddk[i] * tau ** 2, sk[-1])
        sd = np.maximum(sdk[i] + sddk[i] * tau, 0.0)
        sdd = np.where(T >= self.t_f, 0.0, sddk[i])
        dq, ddq = self.path(s, 1), self.path(s, 2)
        out = self.path(s, 0), dq * sd[:, None], dq * sdd[:, None] + ddq * (sd ** 2)[:, None]
        return out if t_arr.ndim else tuple(x[0] for x in out)


LIMIT_NAMES = {"qd": "the velocity `limits.qd_max`", "qdd": "the acceleration `limits.qdd_max`",
               "tau": "the torque `limits.tau_max`"}


def time_optimal_path(robot: Robot, waypoints: np.ndarray, limits: JointLimits, gridpoints: int = 200,
                      subsamples: int = 10, max_backoff: int = 4, space: Any = None) -> TimeOptimalPath:
    """The time-optimal rest-to-rest timing of a path through ``waypoints`` (K, n) within ``limits``.

    With ``space`` (a planner's space that certifies edges: :class:`planners.collision.UrdfCSpace`,
    :class:`planners.configuration_space.PlanarCSpace`) the path is the certified polyline with certified
    blends (:class:`BlendedPolyline`, :func:`certified_blends`) and the result is ``certified``; without it,
    the cubic spline through the waypoints (not certified: use it for paths that are not a planner's).
    TOPP-RA meets the limits at its grid points; the timing is re-checked on a grid ``subsamples`` times
    finer and re-solved with the exceeded limits scaled down, at most ``max_backoff`` times (≥ 0); a limit
    still exceeded then is a ValueError naming it and its ratio.
    """
    import toppra
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    start = time.perf_counter()
    n = robot.nv
    W = np.asarray(waypoints, dtype=float)
    if W.ndim != 2 or W.shape[1] != n or W.shape[0] < 2 or not np.all(np.isfinite(W)):
        raise ValueError(f"`waypoints` must be a finite (K >= 2, {n}) array, got shape {W.shape}")
    if not isinstance(limits, JointLimits):
        raise ValueError(f"`limits` must be a JointLimits, got {type(limits).__name__}")
    if limits.n != n:
        raise ValueError(f"`limits` are for {limits.n} joints, the robot has {n}")
    gridpoints = as_count(gridpoints, "gridpoints", minimum=2)
    subsamples = as_count(subsamples, "subsamples")
    max_backoff = as_count(max_backoff, "max_backoff", minimum=0)
    certified, c_min = False, float("nan")
    if space is not None:
        if getattr(space, "dim", None) != n:
            raise ValueError(f"`space` has dimension {getattr(space, 'dim', None)}, the robot {n} joints")
        diff = getattr(space, "difference", None)
        if diff is not None:                                       # angles unwrapped along the space's edges
            W = np.cumsum(np.vstack([W[:1], np.asarray(diff(W[:-1], W[1:]), dtype=float)]), axis=0)
        keep = np.r_[True, np.linalg.norm(np.diff(W, axis=0), axis=1) > 0]
        W = W[keep]                                                # repeated waypoints add nothing
        if W.shape[0] < 2:
            raise ValueError("`waypoints` must contain two distinct configurations")
        deltas, c_min = certified_blends(space, W)
        path = BlendedPolyline(W, deltas)
        s = np.union1d(np.linspace(0.0, path.length, gridpoints + 1),
                       np.concatenate([np.linspace(a, b, 5) for a, b in zip(path.breakpoints[:-1],
                                                                             path.breakpoints[1:])]))
        certified = True
    else:
        path = toppra.SplineInterpolator(np.linspace(0.0, 1.0, W.shape[0]), W)
        s = np.linspace(0.0, 1.0, gridpoints + 1)
    scale = {"qd": 1.0, "qdd": 1.0, "tau": 1.0}

    def inv_dyn(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
        return inverse_dynamics(robot, q, qd, qdd)

    for backoff in range(max_backoff + 1):
        v, a, u = limits.qd_max * scale["qd"], limits.qdd_max * scale["qdd"], limits.tau_max * scale["tau"]
        constraints = [constraint.JointVelocityConstraint(np.c_[-v, v]),
                       constraint.JointAccelerationConstraint(np.c_[-a, a]),
                       constraint.JointTorqueConstraint(inv_dyn, np.c_[-u, u], np.zeros(n))]
        instance = algo.TOPPRA(constraints, path, gridpoints=s, parametrizer="ParametrizeConstAccel")
        _, sd, _ = instance.compute_parameterization(0.0, 0.0)
        if sd is None:
            raise ValueError("no timing of the path satisfies the limits (TOPP-RA found it infeasible)")
        sd = np.maximum(np.asarray(sd, dtype=float), 0.0)
        ds = np.diff(s)
        sdd = (sd[1:] ** 2 - sd[:-1] ** 2) / (2 * ds)               # constant on each interval
        dt = 2 * ds / np.maximum(sd[1:] + sd[:-1], 1e-12)
        tau_in = np.linspace(0.0, 1.0, subsamples, endpoint=False)[None, :] * dt[:, None]
        S = s[:-1, None] + sd[:-1, None] * tau_in + 0.5 * sdd[:, None] * tau_in**2
        SD = sd[:-1, None] + sdd[:, None] * tau_in
        t = np.concatenate([[0.0], np.cumsum(dt)])
        T = np.append((t[:-1, None] + tau_in).ravel(), t[-1])
        S, SD = np.append(S.ravel(), s[-1]), np.append(SD.ravel(), 0.0)
        S = np.minimum(S, s[-1])
        SDD = np.append(np.repeat(sdd, subsamples), sdd[-1])
        q, dq, ddq = path(S), path(S, 1), path(S, 2)
        qd = dq * SD[:, None]
        qdd = dq * SDD[:, None] + ddq * (SD**2)[:, None]
        tau = np.array([inverse_dynamics(robot, *z) for z in zip(q, qd, qdd)])
        ratios = {"qd": float(np.max(np.abs(qd) / limits.qd_max)), "qdd": float(np.max(np.abs(qdd) / limits.qdd_max)),
                  "tau": float(np.max(np.abs(tau) / limits.tau_max))}
        if all(r <= 1.0 + 1e-6 for r in ratios.values()):
            break
        for k, r in ratios.items():
            if r > 1.0 + 1e-6:
                scale[k] *= (1.0 - 1e-4) / r
    else:
        over = ", ".join(f"{LIMIT_NAMES[k]} at {r:.6g} × its limit" for k, r in ratios.items() if r > 1.0 + 1e-6)
        raise ValueError(f"the timed path exceeds the limits on the fine check grid after `max_backoff` = "
                         f"{max_backoff} re-solves: {over} (raise `max_backoff` or `gridpoints`)")
    return TimeOptimalPath(T, q, qd, qdd, tau, float(t[-1]), ratios, time.perf_counter() - start, backoff,
                           path, S, certified, c_min, (t, s, sd, sdd))
