"""Sampling-based planners (Sect. 12.5): PRM, RRT, bidirectional RRT-Connect, the unicycle RRT with
motion primitives, and path shortcutting.

The planners work in any configuration space that offers the small protocol :class:`PlanningSpace`
(a sampler, a distance, an interpolator, a batched validity check and the resolution at which local
paths are checked); :class:`planners.configuration_space.PlanarCSpace` and
:class:`planners.collision.UrdfCSpace` are two. Randomness always comes in as
a seeded ``numpy.random.Generator``, so a run repeats exactly.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 12.5
(PRM, Fig. 12.10; RRT, Fig. 12.11; bidirectional RRT; RRT for nonholonomic robots with motion
primitives, Fig. 12.12); Problems 12.7, 12.8; the unicycle's exact integration over a constant-input
interval, Eq. (11.85) [the odometric formulas of Sect. 11.7].
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol, Sequence

import numpy as np

from planners.cells import shortest_path_on_graph
from rigid_body.rotations import wrap_angle
from rigid_body.validation import as_positive, as_vector

__all__ = [
    "PlanningSpace", "PlanResult", "local_path", "edge_is_free", "path_length",
    "prm", "rrt", "rrt_connect", "shortcut",
    "unicycle_arc", "MotionPrimitive", "unicycle_rrt",
]


class PlanningSpace(Protocol):
    """What a sampling planner needs from a configuration space."""

    resolution: float  # largest C-space distance between two checked configurations of a local path

    @property
    def dim(self) -> int: ...

    def sample(self, rng: np.random.Generator) -> np.ndarray: ...

    def distance(self, a: Any, b: Any) -> np.ndarray: ...  # broadcasts over leading axes

    def interpolate(self, a: Any, b: Any, s: Any) -> np.ndarray: ...  # s (k,) → (k, dim)

    def valid_many(self, Q: Any) -> np.ndarray: ...  # (N, dim) → (N,) bool

    # optional: ``segment_is_free(a, b) -> bool``, the space's own local-path checker (used by edge_is_free)


@dataclass(frozen=True)
class PlanResult:
    """Outcome of a planner.

    Attributes
    ----------
    success : True when ``path`` joins q_s to q_g (or reaches the goal threshold, for the unicycle RRT).
    path : (k, dim) configurations of the solution (empty when ``success`` is False).
    length : C-space length of the path (sum of the distances between consecutive configurations).
    nodes : (N, dim) the roadmap / tree vertices.
    edges : (E, 2) vertex index pairs of the roadmap / tree.
    message : what happened, in words.
    controls : for the unicycle RRT, the (v, ω) primitive of each path edge; else empty.
    """

    success: bool
    path: np.ndarray
    length: float
    nodes: np.ndarray
    edges: np.ndarray
    message: str
    controls: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))


def local_path(space: PlanningSpace, a: Any, b: Any) -> np.ndarray:
    """The configurations checked on the straight local path a → b: end points included, spaced by at
    most ``space.resolution`` in C-space distance."""
    n = int(np.ceil(float(space.distance(a, b)) / space.resolution)) + 1
    return space.interpolate(a, b, np.linspace(0.0, 1.0, n + 1))


def edge_is_free(space: PlanningSpace, a: Any, b: Any) -> bool:
    """True when every configuration of :func:`local_path` is collision-free; a space with its own segment
    checker (``segment_is_free(a, b)``, e.g. one that stops at the first collision) is asked directly."""
    check = getattr(space, "segment_is_free", None)
    if check is not None:
        return bool(check(a, b))
    return bool(np.all(space.valid_many(local_path(space, a, b))))


def path_length(space: PlanningSpace, path: Any) -> float:
    """Σ d(q_k, q_{k+1}) along the path, with the space's distance."""
    P = np.asarray(path, dtype=float)
    return float(np.sum(space.distance(P[:-1], P[1:]))) if len(P) > 1 else 0.0


def _check_endpoints(space: PlanningSpace, q_start: Any, q_goal: Any) -> tuple[np.ndarray, np.ndarray]:
    qs, qg = as_vector(q_start, space.dim, "q_start"), as_vector(q_goal, space.dim, "q_goal")
    for q, name in ((qs, "q_start"), (qg, "q_goal")):
        if not space.valid_many(q[None])[0]:
            raise ValueError(f"`{name}` = {q} is not a free configuration")
    return qs, qg


def prm(space: PlanningSpace, q_start: Any, q_goal: Any, rng: np.random.Generator, n_vertices: int = 50,
        max_neighbors: int = 3, max_distance: float = 3.0, max_vertices: int | None = None) -> PlanResult:
    """Probabilistic roadmap (Sect. 12.5.1, Fig. 12.10) with the query of Problem 12.7.

    q_s and q_g are the first two vertices; free configurations are then drawn uniformly (colliding ones
    rejected) and each new vertex is joined to at most ``max_neighbors`` of its nearest vertices within
    ``max_distance`` whose local path is free. After ``n_vertices`` samples, if q_s and q_g are still in
    different components, the roadmap keeps growing (as the book prescribes) until they are joined or
    it has ``max_vertices`` samples (default ``n_vertices``: no growth). Dijkstra then searches it.
    """
    qs, qg = _check_endpoints(space, q_start, q_goal)
    if int(n_vertices) < 1 or int(max_neighbors) < 1:
        raise ValueError(f"`n_vertices` and `max_neighbors` must be >= 1, got {n_vertices}, {max_neighbors}")
    as_positive(max_distance, "max_distance")
    max_vertices = int(n_vertices) if max_vertices is None else int(max_vertices)
    nodes: list[np.ndarray] = []
    edges: list[tuple[int, int]] = []
    weights: list[float] = []
    component: list[int] = []                       # union-find over the vertices

    def find(i: int) -> int:
        while component[i] != i:
            component[i] = component[component[i]]
            i = component[i]
        return i

    def attach(q: np.ndarray) -> None:
        k_new = len(nodes)
        component.append(k_new)
        if nodes:
            d = space.distance(np.asarray(nodes), q)
            for k in [k for k in np.argsort(d) if d[k] <= max_distance][:max_neighbors]:
                if edge_is_free(space, nodes[k], q):
                    edges.append((int(k), k_new))
                    weights.append(float(d[k]))
                    component[find(int(k))] = find(k_new)
        nodes.append(q)

    attach(qs)
    attach(qg)
    samples = 0
    while samples < n_vertices or (find(0) != find(1) and samples < max_vertices):
        q = space.sample(rng)
        if space.valid_many(q[None])[0]:
            attach(q)
            samples += 1
    route = shortest_path_on_graph(len(nodes), edges, weights, 0, 1)
    N, E = np.asarray(nodes), np.asarray(edges, dtype=int).reshape(-1, 2)
    if route is None:
        return PlanResult(False, np.zeros((0, space.dim)), np.inf, N, E,
                          f"q_s and q_g are in different components of the {samples}-sample roadmap")
    path = N[route]
    return PlanResult(True, path, path_length(space, path), N, E,
                      f"path of {len(route) - 1} edges through a roadmap of {samples} samples + q_s, q_g")


def _steer(space: PlanningSpace, a: np.ndarray, b: np.ndarray, step: float) -> np.ndarray:
    d = float(space.distance(a, b))
    return b.copy() if d <= step else space.interpolate(a, b, np.array([step / d]))[0]


def _extend(space: PlanningSpace, nodes: list[np.ndarray], parent: list[int], q_target: np.ndarray,
            step: float) -> int | None:
    """EXTEND: add q_new, ``step`` from the vertex nearest to q_target towards it, when the segment is
    free; returns its index (None when blocked)."""
    near = int(np.argmin(space.distance(np.asarray(nodes), q_target)))
    q_new = _steer(space, nodes[near], q_target, step)
    if not edge_is_free(space, nodes[near], q_new):
        return None
    nodes.append(q_new)
    parent.append(near)
    return len(nodes) - 1


def _tree_edges(parent: Sequence[int], offset: int = 0) -> list[tuple[int, int]]:
    return [(p + offset, k + offset) for k, p in enumerate(parent) if p >= 0]


def _tree_path(nodes: list[np.ndarray], parent: list[int], leaf: int) -> list[np.ndarray]:
    route = [leaf]
    while parent[route[-1]] >= 0:
        route.append(parent[route[-1]])
    return [nodes[k] for k in route[::-1]]


def rrt(space: PlanningSpace, q_start: Any, q_goal: Any, rng: np.random.Generator, step: float = 0.3,
        max_iterations: int = 5000, goal_bias: float = 0.05) -> PlanResult:
    """Rapidly-exploring random tree (Sect. 12.5.2, Fig. 12.11).

    Each iteration draws q_rand (q_g with probability ``goal_bias``), finds the nearest vertex q_near and
    adds q_new at distance ``step`` from it towards q_rand when the segment q_near → q_new is free. The
    search ends when q_g is joined to a vertex within ``step`` by a free segment.
    """
    qs, qg = _check_endpoints(space, q_start, q_goal)
    as_positive(step, "step")
    nodes, parent = [qs], [-1]
    for it in range(int(max_iterations)):
        q_rand = qg if rng.random() < goal_bias else space.sample(rng)
        k = _extend(space, nodes, parent, q_rand, step)
        if k is not None and float(space.distance(nodes[k], qg)) <= step and edge_is_free(space, nodes[k], qg):
            nodes.append(qg)
            parent.append(k)
            path = np.asarray(_tree_path(nodes, parent, len(nodes) - 1))
            return PlanResult(True, path, path_length(space, path), np.asarray(nodes), np.array(_tree_edges(parent)),
                              f"goal reached after {it + 1} iterations, {len(nodes)} vertices")
    return PlanResult(False, np.zeros((0, space.dim)), np.inf, np.asarray(nodes),
                      np.array(_tree_edges(parent)).reshape(-1, 2), f"goal not reached in {max_iterations} iterations")


def rrt_connect(space: PlanningSpace, q_start: Any, q_goal: Any, rng: np.random.Generator, step: float = 0.3,
                max_iterations: int = 2000) -> PlanResult:
    """Bidirectional RRT with the greedy CONNECT heuristic (Sect. 12.5.2: "two trees rooted at q_s and q_g").

    One tree is extended one step towards a random sample; the other then takes as many free steps as
    it can towards the new vertex; the roles swap every iteration. Success when the two trees meet.
    """
    qs, qg = _check_endpoints(space, q_start, q_goal)
    as_positive(step, "step")
    trees = [([qs], [-1]), ([qg], [-1])]
    for it in range(int(max_iterations)):
        (na, pa), (nb, pb) = trees[it % 2], trees[(it + 1) % 2]
        new = _extend(space, na, pa, space.sample(rng), step)
        if new is None:
            continue
        q_new = na[new]
        k = int(np.argmin(space.distance(np.asarray(nb), q_new)))          # CONNECT the other tree
        while True:
            q_next = _steer(space, nb[k], q_new, step)
            if not edge_is_free(space, nb[k], q_next):
                break
            nb.append(q_next)
            pb.append(k)
            k = len(nb) - 1
            if float(space.distance(q_next, q_new)) == 0.0:
                first = _tree_path(na, pa, len(na) - 1)
                second = _tree_path(nb, pb, k)[::-1][1:]
                path = np.asarray(first + second)
                if it % 2 == 1:
                    path = path[::-1]
                n_s = len(trees[0][0])
                nodes = np.asarray(trees[0][0] + trees[1][0])
                edges = _tree_edges(trees[0][1]) + _tree_edges(trees[1][1], n_s)
                return PlanResult(True, path, path_length(space, path), nodes, np.array(edges),
                                  f"trees met after {it + 1} iterations, {len(nodes)} vertices")
    nodes = np.asarray(trees[0][0] + trees[1][0])
    return PlanResult(False, np.zeros((0, space.dim)), np.inf, nodes, np.zeros((0, 2), dtype=int),
                      f"trees did not meet in {max_iterations} iterations")


def shortcut(space: PlanningSpace, path: Any, rng: np.random.Generator, attempts: int = 100) -> np.ndarray:
    """Random shortcutting: join two random non-consecutive vertices by a straight local path when it is
    free and drop the vertices between them. The length never increases."""
    P = [np.asarray(q, dtype=float) for q in np.asarray(path, dtype=float)]
    for _ in range(int(attempts)):
        if len(P) < 3:
            break
        i, j = sorted(rng.choice(len(P), size=2, replace=False))
        if j - i >= 2 and edge_is_free(space, P[i], P[j]):
            P = P[:i + 1] + P[j:]
    return np.asarray(P)


# --------------------------------------------------------------------------------------------
# Unicycle RRT with motion primitives (Sect. 12.5.2, Problem 12.8)
# --------------------------------------------------------------------------------------------

def unicycle_arc(q: Any, v: float, omega: float, t: Any) -> np.ndarray:
    """Unicycle pose after time(s) t under constant (v, ω) from q = [x, y, θ], in closed form.

    θ(t) = θ + ω t; for ω ≠ 0 x(t) = x + (v/ω)(sin θ(t) − sin θ), y(t) = y − (v/ω)(cos θ(t) − cos θ),
    and the straight line for ω = 0 — the exact integration of (11.85) over a constant-input interval.
    Returns (3,) for scalar t, (k, 3) for t (k,). θ is wrapped into (−π, π].
    """
    x, y, th = as_vector(q, 3, "q")
    t = np.asarray(t, dtype=float)
    th_t = th + omega * t
    if abs(omega) < 1e-12:
        xs, ys = x + v * t * np.cos(th), y + v * t * np.sin(th)
    else:
        xs = x + v / omega * (np.sin(th_t) - np.sin(th))
        ys = y - v / omega * (np.cos(th_t) - np.cos(th))
    return np.stack([xs, ys, wrap_angle(th_t)], axis=-1)


@dataclass(frozen=True)
class MotionPrimitive:
    """Constant driving and steering velocities (v [m/s], ω [rad/s]) held for Δ [s]."""

    v: float
    omega: float


def unicycle_rrt(space: PlanningSpace, q_start: Any, q_goal: Any, rng: np.random.Generator,
                 primitives: Sequence[MotionPrimitive], delta: float, max_vertices: int = 200,
                 goal_threshold: float = 0.01, goal_bias: float = 0.2, checks: int = 20) -> PlanResult:
    """RRT for the unicycle with motion primitives (Sect. 12.5.2, Fig. 12.12; Problem 12.8).

    Each iteration draws q_rand (q_g with probability ``goal_bias``; a colliding sample is rejected),
    takes the nearest vertex that still has unused primitives, applies each unused primitive for
    ``delta`` seconds (closed-form arcs, :func:`unicycle_arc`), discards those whose arc collides at
    ``checks`` equally spaced instants, and keeps the one ending closest to q_rand; each primitive is
    used at most once per vertex. The search ends when a vertex is within ``goal_threshold`` of q_g,
    or with ``success=False`` (and the path to the closest vertex) once ``max_vertices`` exist.
    """
    qs, qg = _check_endpoints(space, q_start, q_goal)
    as_positive(delta, "delta")
    prims = list(primitives)
    if not prims:
        raise ValueError("`primitives` must not be empty")
    times = np.linspace(0.0, delta, int(checks) + 1)[1:]
    nodes, parent, used, via = [qs], [-1], [set()], [-1]
    while len(nodes) < max_vertices:
        q_rand = qg if rng.random() < goal_bias else space.sample(rng)
        if not space.valid_many(q_rand[None])[0]:
            continue
        open_ = [k for k in range(len(nodes)) if len(used[k]) < len(prims)]
        if not open_:
            break
        near = open_[int(np.argmin(space.distance(np.asarray([nodes[k] for k in open_]), q_rand)))]
        best, best_d = -1, np.inf
        for p, prim in enumerate(prims):
            if p in used[near]:
                continue
            arc = unicycle_arc(nodes[near], prim.v, prim.omega, times)
            if not np.all(space.valid_many(arc)):
                used[near].add(p)
                continue
            d = float(space.distance(arc[-1], q_rand))
            if d < best_d:
                best, best_d = p, d
        if best < 0:
            continue
        used[near].add(best)
        nodes.append(unicycle_arc(nodes[near], prims[best].v, prims[best].omega, delta))
        parent.append(near)
        used.append(set())
        via.append(best)
        if float(space.distance(nodes[-1], qg)) <= goal_threshold:
            break
    N = np.asarray(nodes)
    d_goal = space.distance(N, qg)
    leaf = int(np.argmin(d_goal))
    route = [leaf]
    while parent[route[-1]] >= 0:
        route.append(parent[route[-1]])
    route = route[::-1]
    path = N[route]
    controls = np.array([[prims[via[k]].v, prims[via[k]].omega] for k in route[1:]]).reshape(-1, 2)
    ok = bool(d_goal[leaf] <= goal_threshold)
    edges = np.array(_tree_edges(parent)).reshape(-1, 2)
    msg = (f"{'reached' if ok else 'closest'} vertex at distance {d_goal[leaf]:.4g} from q_g "
           f"(threshold {goal_threshold:g}); {len(nodes)} vertices")
    return PlanResult(ok, path, path_length(space, path), N, edges, msg, controls)
