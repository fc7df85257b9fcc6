"""Artificial potentials (Sect. 12.6) and navigation functions on grids.

* Attractive potentials: the paraboloid ½k_a‖e‖², the cone k_a‖e‖ and their combination of
  Problem 12.9 (paraboloid within ρ of the goal, cone with k_b = ρk_a outside), with e = q_g − q.
* Repulsive potentials of convex obstacles (discs, convex polygons): U_r = (k_r/γ)(1/η − 1/η₀)^γ within
  the range of influence η₀, force f_r = (k_r/η²)(1/η − 1/η₀)^{γ−1} ∇η, Eq. (12.15).
* The total field, its Hessian, stationary points (local minima and saddles, Problems 12.10–12.11) and
  the discrete-time planner q_{k+1} = q_k + T f(q_k) (Sect. 12.6.3).
* Reactive planning from a simulated laser range finder (Problem 12.12).
* Manipulators: workspace forces on control points mapped to joint space through J_P^T (Sect. 12.6.4).
* Navigation functions on occupancy grids by the wavefront, with 1- and 2-adjacency (Problem 12.13).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 12.6;
Problems 12.9–12.13 and the authors' companion files (s12_13).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np
from scipy.optimize import root

from planners.configuration_space import (Disc, Shape, project_on_segments, ray_shape_distance,
                                          segment_shape_distance)
from rigid_body.validation import as_count, as_positive, as_vector

__all__ = [
    "attractive_paraboloid", "attractive_cone", "AttractivePotential", "repulsive_magnitude", "RepulsivePotential",
    "PotentialField", "DescentResult", "gradient_descent", "stationary_point",
    "closest_point", "range_scan", "scan_segments", "reactive_repulsive_force",
    "arm_joint_forces", "wavefront", "steepest_descent_path", "certify_grid_path", "grid_path_length",
]


def _points(q: Any) -> np.ndarray:
    q = np.asarray(q, dtype=float)
    if q.shape[-1] != 2 or not np.all(np.isfinite(q)):
        raise ValueError(f"`q` must be finite points (..., 2), got shape {q.shape}")
    return q


def attractive_paraboloid(e: Any, k_a: float) -> tuple[np.ndarray, np.ndarray]:
    """U_a = ½ k_a ‖e‖² and f_a = −∇_q U_a = k_a e (e = q_g − q): the paraboloid of Sect. 12.6.1."""
    e = np.asarray(e, dtype=float)
    return 0.5 * k_a * np.sum(e * e, axis=-1), k_a * e


def attractive_cone(e: Any, k_a: float) -> tuple[np.ndarray, np.ndarray]:
    """U_a = k_a ‖e‖ and f_a = k_a e/‖e‖ (unit-magnitude times k_a; 0 at the goal): the conical potential."""
    e = np.asarray(e, dtype=float)
    n = np.linalg.norm(e, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(n > 0, k_a * e / np.where(n > 0, n, 1.0), 0.0)
    return k_a * n[..., 0], f


@dataclass(frozen=True)
class AttractivePotential:
    """Attractive potential towards ``goal``: paraboloid (``rho`` None), or the combination of Problem 12.9.

    With a transition radius ρ: U_a = ½k_a‖e‖² for ‖e‖ ≤ ρ, and k_b‖e‖ − ½k_aρ² beyond, with k_b = ρk_a.
    That choice of k_b is what makes the force continuous at ‖e‖ = ρ (the manual's answer); the offset
    −½k_aρ² (not in the manual, which writes k_b‖e‖) also makes U continuous.
    """

    goal: np.ndarray
    k_a: float = 1.0
    rho: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "goal", as_vector(self.goal, None, "goal"))
        as_positive(self.k_a, "k_a")
        if self.rho is not None:
            as_positive(self.rho, "rho")

    @property
    def k_b(self) -> float:
        """Gain of the conical part, k_b = ρ k_a (Problem 12.9)."""
        if self.rho is None:
            raise ValueError("k_b is defined for the combined potential only (give `rho`)")
        return self.rho * self.k_a

    def potential(self, q: Any) -> np.ndarray:
        e = self.goal - np.asarray(q, dtype=float)
        U_p, _ = attractive_paraboloid(e, self.k_a)
        if self.rho is None:
            return U_p
        U_c, _ = attractive_cone(e, self.k_b)
        return np.where(np.linalg.norm(e, axis=-1) <= self.rho, U_p, U_c - 0.5 * self.k_a * self.rho ** 2)

    def force(self, q: Any) -> np.ndarray:
        e = self.goal - np.asarray(q, dtype=float)
        _, f_p = attractive_paraboloid(e, self.k_a)
        if self.rho is None:
            return f_p
        _, f_c = attractive_cone(e, self.k_b)
        return np.where(np.linalg.norm(e, axis=-1, keepdims=True) <= self.rho, f_p, f_c)


def closest_point(shape: Shape, p: Any) -> np.ndarray:
    """The point of the shape's boundary closest to each point p (..., 2) outside it."""
    p = _points(p)
    if isinstance(shape, Disc):
        d = p - shape.center
        n = np.linalg.norm(d, axis=-1, keepdims=True)
        return shape.center + shape.radius * d / np.where(n > 0, n, 1.0)
    a, b = shape.edges
    c = project_on_segments(p[..., None, :], a, b)[1]                     # (..., k, 2)
    k = np.argmin(np.linalg.norm(p[..., None, :] - c, axis=-1), axis=-1)
    return np.take_along_axis(c, k[..., None, None], axis=-2)[..., 0, :]


def repulsive_magnitude(eta: Any, k_r: float, eta0: float, gamma: float = 2.0) -> np.ndarray:
    """‖f_r‖ = (k_r/η²)(1/η − 1/η₀)^{γ−1} for 0 < η ≤ η₀, 0 beyond η₀, NaN in contact (η ≤ 0), Eq. (12.15).

    >>> float(repulsive_magnitude(0.5, k_r=1.0, eta0=1.0))
    4.0
    """
    eta = np.asarray(eta, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        mag = k_r / eta ** 2 * (1.0 / eta - 1.0 / eta0) ** (gamma - 1.0)                 # (12.15)
    return np.where(eta <= 0, np.nan, np.where(eta <= eta0, mag, 0.0))


@dataclass(frozen=True)
class RepulsivePotential:
    """Repulsive potential of one convex obstacle, Sect. 12.6.2.

    η(q) is the distance of q from the obstacle (for a disc ‖q − c‖ − ρ), ∇η = (q − closest point)/‖·‖;
    U_r = (k_r/γ)(1/η − 1/η₀)^γ for η ≤ η₀, 0 beyond; f_r = −∇U_r = (k_r/η²)(1/η − 1/η₀)^{γ−1} ∇η, Eq. (12.15).
    """

    shape: Shape
    k_r: float = 1.0
    eta0: float = 1.0
    gamma: float = 2.0

    def __post_init__(self) -> None:
        as_positive(self.k_r, "k_r")
        as_positive(self.eta0, "eta0")
        as_positive(self.gamma, "gamma")

    def eta(self, q: Any) -> tuple[np.ndarray, np.ndarray]:
        """η (…,) and ∇η (…, 2) at q (…, 2)."""
        q = _points(q)
        if isinstance(self.shape, Disc):
            d = q - self.shape.center
            n = np.linalg.norm(d, axis=-1)
            return n - self.shape.radius, d / n[..., None]
        d = q - closest_point(self.shape, q)
        n = np.linalg.norm(d, axis=-1)
        inside = self.shape.contains(q)
        return np.where(inside, 0.0, n), d / np.where(n > 0, n, 1.0)[..., None]

    def potential(self, q: Any) -> np.ndarray:
        eta, _ = self.eta(q)
        with np.errstate(divide="ignore", invalid="ignore"):
            U = self.k_r / self.gamma * (1.0 / eta - 1.0 / self.eta0) ** self.gamma
        return np.where(eta <= 0, np.inf, np.where(eta <= self.eta0, U, 0.0))

    def force(self, q: Any) -> np.ndarray:
        eta, grad = self.eta(q)
        return repulsive_magnitude(eta, self.k_r, self.eta0, self.gamma)[..., None] * grad


@dataclass(frozen=True)
class PotentialField:
    """U_t = U_a + Σ U_r,i and f_t = −∇U_t = f_a + Σ f_r,i (Sect. 12.6.3), on points q (…, 2)."""

    attractive: AttractivePotential
    repulsive: tuple = ()

    def __post_init__(self) -> None:
        if not isinstance(self.attractive, AttractivePotential):
            raise ValueError(f"`attractive` must be an AttractivePotential, got {type(self.attractive).__name__}")
        if self.attractive.goal.shape != (2,):
            raise ValueError(f"`attractive.goal` must be a planar point (2,) for a PotentialField on points (…, 2), "
                             f"got shape {self.attractive.goal.shape}")
        rep = tuple(self.repulsive)
        for k, r in enumerate(rep):
            if not isinstance(r, RepulsivePotential):
                raise ValueError(f"`repulsive[{k}]` must be a RepulsivePotential, got {type(r).__name__}")
        object.__setattr__(self, "repulsive", rep)

    def potential(self, q: Any) -> np.ndarray:
        q = _points(q)
        return self.attractive.potential(q) + sum((r.potential(q) for r in self.repulsive), np.zeros(q.shape[:-1]))

    def force(self, q: Any) -> np.ndarray:
        q = _points(q)
        return self.attractive.force(q) + sum((r.force(q) for r in self.repulsive), np.zeros(q.shape))

    def hessian(self, q: Any, h: float = 1e-6) -> np.ndarray:
        """∇²U_t (2, 2) at q, by central differences of the analytic force (H = −∂f/∂q), symmetrised."""
        q = as_vector(q, 2, "q")
        H = np.column_stack([-(self.force(q + dq) - self.force(q - dq)) / (2 * h) for dq in np.eye(2) * h])
        return 0.5 * (H + H.T)


@dataclass(frozen=True)
class DescentResult:
    """Path of the discrete-time planner; ``converged`` when ‖f‖ < tol (a stationary point: goal or not).

    ``certified``: the straight steps between the iterates were certified collision-free (a point or disc
    robot among the ``obstacles`` given to :func:`gradient_descent`, exact segment–shape test), with the
    smallest clearance ``min_clearance``; False (and NaN) when no obstacles were given — the iterates of a
    potential field are not checked against anything by themselves.
    """

    path: np.ndarray
    converged: bool
    message: str
    certified: bool = False
    min_clearance: float = float("nan")


def gradient_descent(force: Any, q0: Any, step: float = 0.01, tol: float = 1e-6,
                     max_iterations: int = 20000, max_move: float | None = None,
                     obstacles: Sequence[Shape] | None = None, robot_radius: float = 0.0) -> DescentResult:
    """The algorithm of Sect. 12.6.3: q_{k+1} = q_k + T f(q_k), until ‖f‖ < tol.

    ``force`` is a callable q → f (a :class:`PotentialField`'s ``force`` or a reactive one); ``max_move``
    optionally caps the length of one step (near obstacles f is large). With ``obstacles`` (planar shapes)
    the polyline of the iterates is certified for a disc robot of radius ``robot_radius`` by the exact
    segment–shape distance (:class:`DescentResult` ``certified``); otherwise it is marked not certified.
    """
    q = as_vector(q0, None, "q0").copy()
    as_positive(step, "step")
    max_iterations = as_count(max_iterations, "max_iterations", minimum=0)
    path = [q.copy()]
    result = None
    for k in range(max_iterations):
        f = np.asarray(force(q), dtype=float)
        if f.shape != q.shape or not np.all(np.isfinite(f)):
            result = (False, f"the force is not a finite vector of shape {q.shape} at step {k}, q = {q}")
            break
        n = float(np.linalg.norm(f))
        if n < tol:
            result = (True, f"‖f‖ < {tol:g} after {k} steps at q = {q}")
            break
        dq = step * f
        if max_move is not None and step * n > max_move:
            dq *= max_move / (step * n)
        q = q + dq
        path.append(q.copy())
    if result is None:
        result = (False, f"no stationary point within {max_iterations} steps (the budget `max_iterations`)")
    P = np.asarray(path)
    if obstacles is None:
        return DescentResult(P, *result)
    r = as_positive(robot_radius, "robot_radius", allow_zero=True)
    if P.shape[1] != 2:
        raise ValueError(f"`obstacles` certify planar paths only; the iterates have {P.shape[1]} coordinates")
    segs = list(zip(P[:-1], P[1:])) or [(P[0], P[0])]
    c = min((segment_shape_distance(a, b, o) for a, b in segs for o in obstacles), default=np.inf) - r
    return DescentResult(P, *result, bool(c > 0), float(c))


def stationary_point(field: PotentialField, q0: Any) -> np.ndarray:
    """A point where f_t = 0 near q0 (scipy.optimize.root on the analytic force); ValueError if none."""
    sol = root(lambda q: field.force(q), as_vector(q0, 2, "q0"), method="hybr", tol=1e-13)
    if not sol.success or not np.all(np.isfinite(sol.x)):
        raise ValueError(f"no stationary point found from q0 = {q0}: {sol.message}")
    return sol.x


# --------------------------------------------------------------------------------------------
# Reactive planning from range data (Problem 12.12)
# --------------------------------------------------------------------------------------------

def range_scan(position: Any, obstacles: Sequence[Shape], n_rays: int = 720,
               max_range: float = 3.0) -> tuple[np.ndarray, np.ndarray]:
    """A rotating laser range finder at ``position``: ray angles (n_rays,) [rad] and ranges [m] (∞ beyond R)."""
    p = as_vector(position, 2, "position")
    as_positive(max_range, "max_range")
    angles = np.linspace(-np.pi, np.pi, int(n_rays), endpoint=False)
    u = np.column_stack([np.cos(angles), np.sin(angles)])
    r = np.full(angles.size, np.inf)
    for o in obstacles:
        r = np.minimum(r, ray_shape_distance(p, u, o))
    return angles, np.where(r <= max_range, r, np.inf)


def scan_segments(position: Any, angles: np.ndarray, ranges: np.ndarray, gap: float = 1.0) -> list[np.ndarray]:
    """The perceived obstacles: maximal runs of consecutive rays with a return whose hit points are less
    than ``gap`` [m] apart (an occlusion edge or empty space breaks a run; the scan is circular).
    Each is an array (k, 2) of hit points."""
    p = as_vector(position, 2, "position")
    hit = np.isfinite(ranges)
    if not hit.any():
        return []
    pts = p + np.where(hit, ranges, 0.0)[:, None] * np.column_stack([np.cos(angles), np.sin(angles)])
    n = ranges.size
    step = np.linalg.norm(pts - np.roll(pts, 1, axis=0), axis=1)
    joined = hit & np.roll(hit, 1) & (step < gap)          # ray k continues the run of ray k − 1
    if joined.all():
        return [pts]
    order = (np.flatnonzero(~joined)[0] + np.arange(n)) % n   # the rays from the first break on, once round
    run = np.cumsum(~joined[order])                         # a new run at every break
    kept = hit[order]
    rays = order[kept]
    return [pts[idx] for idx in np.split(rays, np.flatnonzero(np.diff(run[kept])) + 1)]


def reactive_repulsive_force(position: Any, segments: Sequence[np.ndarray], k_r: float, eta0: float,
                             gamma: float = 2.0, robot_radius: float = 0.0) -> np.ndarray:
    """Σ over perceived obstacles of (12.15), Problem 12.12: η_i is the distance from the robot to the
    polyline through the obstacle's scan points (minus the robot radius ρ) and ∇η_i the unit vector from
    its closest point to the robot."""
    p = as_vector(position, 2, "position")
    f = np.zeros(2)
    for seg in segments:
        a, b = (seg[:-1], seg[1:]) if len(seg) > 1 else (seg, seg)
        c = project_on_segments(p, a, b)[1]
        d = np.linalg.norm(p - c, axis=1)
        k = int(np.argmin(d))
        eta = d[k] - robot_radius
        if eta <= 0:
            raise ValueError(f"the robot at {p} touches a perceived obstacle (η = {eta:.3g})")
        f += float(repulsive_magnitude(eta, k_r, eta0, gamma)) * (p - c[k]) / d[k]
    return f


# --------------------------------------------------------------------------------------------
# Manipulators (Sect. 12.6.4)
# --------------------------------------------------------------------------------------------

def arm_joint_forces(robot: Any, q: Any, frames: Sequence[str], forces: Sequence[Any]) -> np.ndarray:
    """Generalised forces τ = Σ_i J_{P,i}^T(q) f_i of workspace forces f_i applied at the control points
    (frame origins ``frames``); planar forces (2,) act in the x–y plane. J from
    :func:`rigid_body.kinematics.geometric_jacobian` (the book's Jacobian)."""
    from rigid_body.kinematics import geometric_jacobian

    q = as_vector(q, robot.nq, "q")
    if len(frames) != len(forces):
        raise ValueError(f"`frames` and `forces` must have the same length, got {len(frames)} and {len(forces)}")
    tau = np.zeros(robot.nv)
    for frame, f in zip(frames, forces):
        f = as_vector(f, None, "forces[i]")
        if f.size not in (2, 3):
            raise ValueError(f"each force must be (2,) or (3,), got {f.shape}")
        J_P = geometric_jacobian(robot, q, frame)[:f.size]
        tau += J_P.T @ f
    return tau


# --------------------------------------------------------------------------------------------
# Navigation functions on grids (Problem 12.13)
# --------------------------------------------------------------------------------------------

def _neighbours(adjacency: int) -> list[tuple[int, int, float]]:
    if adjacency == 1:
        return [(-1, 0, 1.0), (1, 0, 1.0), (0, -1, 1.0), (0, 1, 1.0)]
    if adjacency == 2:
        s2 = float(np.sqrt(2.0))
        return [(-1, 0, 1.0), (1, 0, 1.0), (0, -1, 1.0), (0, 1, 1.0),
                (-1, -1, s2), (-1, 1, s2), (1, -1, s2), (1, 1, s2)]
    raise ValueError(f"`adjacency` must be 1 (4 neighbours) or 2 (8 neighbours), got {adjacency}")


def _cell(c: Any, shape: tuple[int, int], name: str) -> tuple[int, int]:
    v = as_vector(c, 2, name)
    if np.any(v != np.round(v)):
        raise ValueError(f"`{name}` must be integer (row, column) cell indices, got {v.tolist()}")
    i, j = (int(x) for x in v)
    if not (0 <= i < shape[0] and 0 <= j < shape[1]):
        raise ValueError(f"`{name}` = {c} is outside the {shape} grid")
    return i, j


def wavefront(occupied: Any, goal: Any, adjacency: int = 2) -> np.ndarray:
    """Navigation function on a grid of unit cells, by a wavefront from the goal cell (Sect. 12.4.2).

    The value of a free cell is its cost-to-go: the wave grows from ``goal`` (value 0); a neighbour's value
    is lowered to value + the distance between cell centres (1 for sides, √2 for diagonals with
    2-adjacency) and the neighbour is re-queued whenever it decreases (FIFO, as in the companion file
    s12_13). Obstacle and unreached cells keep ∞. ``occupied`` is a boolean (rows, cols) array;
    cells are 0-based (row, column).
    """
    occ = np.asarray(occupied, dtype=bool)
    if occ.ndim != 2:
        raise ValueError(f"`occupied` must be a 2-D grid, got shape {occ.shape}")
    g = _cell(goal, occ.shape, "goal")
    if occ[g]:
        raise ValueError(f"`goal` = {goal} is an obstacle cell")
    nbrs = _neighbours(adjacency)
    value = np.full(occ.shape, np.inf)
    value[g] = 0.0
    queue = deque([g])
    while queue:
        i, j = queue.popleft()
        for di, dj, c in nbrs:
            a, b = i + di, j + dj
            if 0 <= a < occ.shape[0] and 0 <= b < occ.shape[1] and not occ[a, b] and value[i, j] + c < value[a, b]:
                value[a, b] = value[i, j] + c
                queue.append((a, b))
    return value


def steepest_descent_path(value: Any, start: Any, adjacency: int = 2) -> np.ndarray:
    """Cells (k, 2) from ``start`` to the goal (value 0), each step to the neighbour of least value.

    ValueError when the start cell is an obstacle or cannot reach the goal (value ∞). The cells are free,
    but the path is not certified: a diagonal step (2-adjacency) passes the corner of two side cells that
    may be obstacles — :func:`certify_grid_path` says whether the motion through the cell centres is free.
    """
    V = np.asarray(value, dtype=float)
    s = _cell(start, V.shape, "start")
    if not np.isfinite(V[s]):
        raise ValueError(f"`start` = {start} is an obstacle or cannot reach the goal")
    nbrs = _neighbours(adjacency)
    path = [s]
    while V[path[-1]] > 0:
        i, j = path[-1]
        cand = [(V[i + di, j + dj], (i + di, j + dj)) for di, dj, _ in nbrs
                if 0 <= i + di < V.shape[0] and 0 <= j + dj < V.shape[1]]
        best = min(cand)
        if not best[0] < V[i, j]:
            raise ValueError(f"the navigation function has a local minimum at {path[-1]}")
        path.append(best[1])
    return np.array(path)


def certify_grid_path(occupied: Any, cells: Any) -> tuple[bool, str]:
    """Certificate of the motion of a point through the centres of a cell path (k, 2) on an occupancy grid of
    closed unit squares: a side step stays in its two free cells; a diagonal step passes through the corner
    shared with the two side cells, so it is free only when both are free. Returns (certified, why not)."""
    occ = np.asarray(occupied, dtype=bool)
    C = np.asarray(cells)
    if C.ndim != 2 or C.shape[1] != 2:
        raise ValueError(f"`cells` must be a (k, 2) array of cells, got shape {C.shape}")
    for k, c in enumerate(C):
        i, j = _cell(c, occ.shape, f"cells[{k}]")
        if occ[i, j]:
            return False, f"cell {k} = {(i, j)} is an obstacle"
    for k, (a, b) in enumerate(zip(C[:-1], C[1:])):
        di, dj = (int(x) for x in b - a)
        if max(abs(di), abs(dj)) != 1:
            return False, f"step {k} from {tuple(a)} to {tuple(b)} is not between neighbouring cells"
        if di and dj and (occ[a[0] + di, a[1]] or occ[a[0], a[1] + dj]):
            return False, f"diagonal step {k} from {tuple(a)} to {tuple(b)} touches the corner of an obstacle cell"
    return True, ""


def grid_path_length(cells: Any) -> float:
    """Length of a cell path through the cell centres (unit cells)."""
    C = np.asarray(cells, dtype=float)
    return float(np.sum(np.linalg.norm(np.diff(C, axis=0), axis=1)))
