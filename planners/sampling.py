"""Sampling-based planners (Sect. 12.5): PRM, RRT, bidirectional RRT-Connect, the unicycle RRT with
motion primitives, and path shortcutting — every edge certified collision-free.

The planners work in any configuration space that offers the small protocol :class:`PlanningSpace`
(a sampler, a distance, an interpolator, a batched validity check) plus, for the certified edges (the
default), ``clearances(q)`` and ``certify_edge(a, b, ca, cb)``; :class:`planners.configuration_space.PlanarCSpace`
and :class:`planners.collision.UrdfCSpace` are two.

**Edges.** An edge is accepted only when certified free (``edge_check="certified"``): the clearances at
its ends exceed a bound on how far any point of the robot moves along it, else it is bisected
(:func:`planners.configuration_space.certify_by_bisection`; Schwarzer, Saha & Latombe 2004). The
result then says ``certified=True`` and carries the smallest clearance met along the returned path and the
number of distance queries spent. ``edge_check="sampled"`` checks configurations every
``space.resolution`` instead (faster, blind to obstacles thinner than the step): its result says
``certified=False``.

**Effort.** Every planner has a budget — iterations (or vertices), rejected samples, and optionally a
wall-clock ``time_limit`` [s] — and ends with ``success=False`` and a message naming the budget spent.
A time limit makes the outcome depend on the machine's speed; the iteration budgets keep a seeded run
repeatable. ``rng`` is an integer seed or a ``numpy.random.Generator``. The planners keep no state
between calls (all of it lives in the call), so two threads may plan on one space (the URDF checker
keeps its Pinocchio work data per thread).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 12.5
(PRM, Fig. 12.10; RRT, Fig. 12.11; bidirectional RRT; RRT for nonholonomic robots with motion
primitives, Fig. 12.12); Problems 12.7, 12.8; the unicycle's exact integration over a constant-input
interval, Eq. (11.85) [the odometric formulas of Sect. 11.7]; Schwarzer, Saha, Latombe, "Exact
collision checking of robot paths", Algorithmic Foundations of Robotics V (2004).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Any, Protocol, Sequence

import numpy as np

from planners.cells import shortest_path_on_graph
from planners.configuration_space import EdgeCertificate, certify_by_bisection
from rigid_body.rotations import wrap_angle
from rigid_body.validation import as_count, as_generator, as_positive, as_vector

__all__ = [
    "PlanningSpace", "PlanResult", "local_path", "edge_is_free", "certify_path", "path_length",
    "EDGE_CHECKS", "prm", "rrt", "rrt_connect", "shortcut",
    "unicycle_arc", "MotionPrimitive", "certify_arc", "unicycle_rrt",
]

EDGE_CHECKS = ("certified", "sampled")
MAX_REJECTED = 10_000    # default bound on consecutive rejected samples (a free set too small to hit)


class PlanningSpace(Protocol):
    """What a sampling planner needs from a configuration space."""

    resolution: float  # largest C-space distance between two checked configurations of a sampled local path

    @property
    def dim(self) -> int: ...

    def sample(self, rng: np.random.Generator) -> np.ndarray: ...

    def distance(self, a: Any, b: Any) -> np.ndarray: ...  # broadcasts over leading axes

    def interpolate(self, a: Any, b: Any, s: Any) -> np.ndarray: ...  # s (k,) → (k, dim)

    def valid_many(self, Q: Any) -> np.ndarray: ...  # (N, dim) → (N,) bool

    # certified edges: ``clearances(q) -> (P,)`` (≤ 0 in collision or out of bounds) and
    # ``certify_edge(a, b, ca=None, cb=None) -> EdgeCertificate``;
    # sampled edges, optional: ``segment_is_free(a, b) -> bool``, the space's own sampled checker


@dataclass(frozen=True)
class PlanResult:
    """Outcome of a planner.

    Attributes
    ----------
    success : True when ``path`` joins q_s to q_g (or reaches the goal threshold, for the unicycle RRT)
        through edges accepted by the edge check.
    path : (k, dim) configurations of the solution (empty when ``success`` is False).
    length : C-space length of the path (sum of the distances between consecutive configurations).
    nodes : (N, dim) the roadmap / tree vertices.
    edges : (E, 2) vertex index pairs of the roadmap / tree.
    message : what happened, in words (which budget ran out, on failure).
    controls : for the unicycle RRT, the (v, ω) primitive of each path edge; else empty.
    certified : every edge of ``path`` was certified free (``edge_check="certified"``); False for sampled
        edges — a success is then only "free at the sampled configurations".
    min_clearance : the smallest clearance met along the path's edges by their certificates [m]
        (NaN when not certified or no path).
    distance_queries : configurations at which the planner computed clearances (vertices and bisection
        points, accepted and refused edges alike); 0 in the sampled mode.
    validity_checks : configurations checked for validity (samples, and every sampled edge configuration).
    edges_tested : edges submitted to the edge check (accepted or refused).
    """

    success: bool
    path: np.ndarray
    length: float
    nodes: np.ndarray
    edges: np.ndarray
    message: str
    controls: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    certified: bool = False
    min_clearance: float = float("nan")
    distance_queries: int = 0
    validity_checks: int = 0
    edges_tested: int = 0


def local_path(space: PlanningSpace, a: Any, b: Any) -> np.ndarray:
    """The configurations checked on the straight local path a → b in the sampled mode: end points
    included, spaced by at most ``space.resolution`` in C-space distance."""
    n = int(np.ceil(float(space.distance(a, b)) / space.resolution)) + 1
    return space.interpolate(a, b, np.linspace(0.0, 1.0, n + 1))


def _edge_check(check: str) -> str:
    if check not in EDGE_CHECKS:
        raise ValueError(f"`edge_check` must be one of {EDGE_CHECKS}, got {check!r}")
    return check


def _certifying(space: PlanningSpace) -> None:
    for name in ("clearances", "certify_edge"):
        if not callable(getattr(space, name, None)):
            raise ValueError(f"`space` ({type(space).__name__}) has no `{name}`: it cannot certify edges; give it "
                             "one, or pass edge_check='sampled' (then the result says certified=False)")


def edge_is_free(space: PlanningSpace, a: Any, b: Any, edge_check: str = "certified") -> bool:
    """True when the straight edge a → b is certified free (``space.certify_edge``), or, with
    ``edge_check="sampled"``, when every configuration of :func:`local_path` is valid (a space with its own
    sampled checker, ``segment_is_free(a, b)``, is asked directly)."""
    if _edge_check(edge_check) == "certified":
        _certifying(space)
        return bool(space.certify_edge(np.asarray(a, dtype=float), np.asarray(b, dtype=float)).free)
    check = getattr(space, "segment_is_free", None)
    if check is not None:
        return bool(check(a, b))
    return bool(np.all(space.valid_many(local_path(space, a, b))))


def certify_path(space: PlanningSpace, path: Any) -> EdgeCertificate:
    """Certificate of a whole polyline: every straight edge certified (``space.certify_edge``); the
    smallest clearance met and the distance queries summed (the vertices' included)."""
    _certifying(space)
    P = np.asarray(path, dtype=float)
    if P.ndim != 2 or P.shape[0] < 1 or P.shape[1] != space.dim or not np.all(np.isfinite(P)):
        raise ValueError(f"`path` must be a finite (k >= 1, {space.dim}) array, got shape {P.shape}")
    C = [np.asarray(space.clearances(q), dtype=float) for q in P]
    queries, c_min = len(P), float(min(c.min(initial=np.inf) for c in C))
    if any(np.isnan(c).any() for c in C):
        return EdgeCertificate(False, np.nan, queries, "a clearance at a vertex of the path is NaN")
    if not c_min > 0:
        return EdgeCertificate(False, c_min, queries, "a vertex of the path is in collision or out of bounds")
    for k, (a, b) in enumerate(zip(P[:-1], P[1:])):
        cert = space.certify_edge(a, b, C[k], C[k + 1])
        queries += cert.queries
        c_min = min(c_min, cert.min_clearance)
        if not cert.free:
            return EdgeCertificate(False, c_min, queries, f"edge {k}: {cert.message}")
    return EdgeCertificate(True, c_min, queries)


class _EdgeTester:
    """One planner call's edge check: the clearances of its vertices cached (``clear``), the edge test
    (``test``) and the statistics the result reports."""

    def __init__(self, space: PlanningSpace, edge_check: str) -> None:
        self.space = space
        self.certified = _edge_check(edge_check) == "certified"
        if self.certified:
            _certifying(space)
        self.queries = 0
        self.checks = 0
        self.edges = 0

    def clear(self, q: np.ndarray) -> np.ndarray | None:
        """The clearances at a new vertex (certified mode), or None (sampled mode)."""
        if not self.certified:
            return None
        self.queries += 1
        return np.asarray(self.space.clearances(q), dtype=float)

    def test(self, a: np.ndarray, b: np.ndarray, ca: np.ndarray | None, cb: np.ndarray | None) -> float | None:
        """The edge a → b: its smallest clearance met when accepted (NaN in the sampled mode), None when refused."""
        self.edges += 1
        if self.certified:
            cert = self.space.certify_edge(a, b, ca, cb)
            self.queries += cert.queries
            return cert.min_clearance if cert.free else None
        check = getattr(self.space, "segment_is_free", None)
        if check is not None:
            ok = bool(check(a, b))
        else:
            Q = local_path(self.space, a, b)
            self.checks += len(Q)
            ok = bool(np.all(self.space.valid_many(Q)))
        return float("nan") if ok else None

    def result(self, success: bool, path: np.ndarray, nodes: Any, edges: Any, message: str,
               path_clearances: Sequence[float] = (), controls: np.ndarray | None = None) -> PlanResult:
        dim = self.space.dim
        path = np.asarray(path, dtype=float).reshape(-1, dim)
        c_min = float(min(path_clearances)) if (self.certified and success and len(path_clearances)) \
            else float("nan")
        return PlanResult(success, path, path_length(self.space, path) if success else np.inf,
                          np.asarray(nodes, dtype=float).reshape(-1, dim), np.asarray(edges, dtype=int).reshape(-1, 2),
                          message, np.zeros((0, 2)) if controls is None else controls,
                          self.certified and success, c_min, self.queries, self.checks, self.edges)


class _Budget:
    """A planner's wall-clock budget (None: none) and its bound on rejected samples."""

    def __init__(self, time_limit: float | None, max_rejected: int = MAX_REJECTED) -> None:
        self.limit = None if time_limit is None else as_positive(time_limit, "time_limit")
        self.max_rejected = as_count(max_rejected, "max_rejected")
        self.start = time.perf_counter()

    def spent(self) -> bool:
        return self.limit is not None and time.perf_counter() - self.start > self.limit

    def message(self) -> str:
        return f"time limit of {self.limit:g} s reached"

    def exhausted(self, rejected: int) -> str:
        """Which budget is spent ("" when none): the time limit or the rejected samples."""
        if self.spent():
            return self.message()
        if rejected >= self.max_rejected:
            return f"{rejected} samples rejected (the budget `max_rejected`): the free set is too small to sample"
        return ""


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


def _free_ends(space: PlanningSpace, tester: _EdgeTester, q_start: Any, q_goal: Any) -> tuple:
    """q_s, q_g validated (free, in the space) and their clearances (certified mode)."""
    qs, qg = _check_endpoints(space, q_start, q_goal)
    out = []
    for q, name in ((qs, "q_start"), (qg, "q_goal")):
        c = tester.clear(q)
        if c is not None and not c.min(initial=np.inf) > 0:
            raise ValueError(f"`{name}` = {q} is free but its clearance in the certificate's geometry is "
                             f"{c.min():.3g} <= 0 (no edge from it can be certified)")
        out.append(c)
    return qs, qg, out[0], out[1]


def prm(space: PlanningSpace, q_start: Any, q_goal: Any, rng: Any, n_vertices: int = 50,
        max_neighbors: int = 3, max_distance: float = 3.0, max_vertices: int | None = None,
        max_rejected: int = MAX_REJECTED, time_limit: float | None = None,
        edge_check: str = "certified") -> PlanResult:
    """Probabilistic roadmap (Sect. 12.5.1, Fig. 12.10) with the query of Problem 12.7.

    q_s and q_g are the first two vertices; free configurations are then drawn uniformly (colliding ones
    rejected) and each new vertex is joined to at most ``max_neighbors`` of its nearest vertices within
    ``max_distance`` whose local path is certified free. After ``n_vertices`` samples, if q_s and q_g are
    still in different components, the roadmap keeps growing (as the book prescribes) until they are joined
    or it has ``max_vertices`` samples (default ``n_vertices``: no growth). Dijkstra then searches it.
    Budgets: ``max_vertices``, ``max_rejected`` rejected draws in all, ``time_limit`` [s].
    """
    rng = as_generator(rng)
    tester = _EdgeTester(space, edge_check)
    qs, qg, cs, cg = _free_ends(space, tester, q_start, q_goal)
    n_vertices, max_neighbors = as_count(n_vertices, "n_vertices"), as_count(max_neighbors, "max_neighbors")
    as_positive(max_distance, "max_distance")
    max_vertices = n_vertices if max_vertices is None else as_count(max_vertices, "max_vertices")
    budget = _Budget(time_limit, max_rejected)
    nodes: list[np.ndarray] = []
    clear: list[np.ndarray | None] = []
    edges: list[tuple[int, int]] = []
    weights: list[float] = []
    edge_clear: dict[tuple[int, int], float] = {}
    component: list[int] = []                       # union-find over the vertices

    def find(i: int) -> int:
        while component[i] != i:
            component[i] = component[component[i]]
            i = component[i]
        return i

    def attach(q: np.ndarray, c: np.ndarray | None) -> None:
        k_new = len(nodes)
        component.append(k_new)
        if nodes:
            d = space.distance(np.asarray(nodes), q)
            for k in [k for k in np.argsort(d) if d[k] <= max_distance][:max_neighbors]:
                m = tester.test(nodes[k], q, clear[k], c)
                if m is not None:
                    edges.append((int(k), k_new))
                    weights.append(float(d[k]))
                    edge_clear[(int(k), k_new)] = m
                    component[find(int(k))] = find(k_new)
        nodes.append(q)
        clear.append(c)

    attach(qs, cs)
    attach(qg, cg)
    samples = rejected = 0
    stop = ""
    while samples < n_vertices or (find(0) != find(1) and samples < max_vertices):
        stop = budget.exhausted(rejected)
        if stop:
            break
        q = space.sample(rng)
        tester.checks += 1
        ok = bool(space.valid_many(q[None])[0])
        c = tester.clear(q) if ok else None
        if not ok or (c is not None and not c.min(initial=np.inf) > 0):
            rejected += 1
            continue
        attach(q, c)
        samples += 1
    route = shortest_path_on_graph(len(nodes), edges, weights, 0, 1)
    if route is None:
        why = stop or (f"the budget `max_vertices` = {max_vertices} samples" if max_vertices > n_vertices
                       else f"{samples} samples (`n_vertices`; raise `max_vertices` to let it grow)")
        return tester.result(False, np.zeros((0, space.dim)), nodes, edges,
                             f"q_s and q_g are in different components of the {samples}-sample roadmap: {why}")
    path = np.asarray(nodes)[route]
    ms = [edge_clear[(min(i, j), max(i, j))] for i, j in zip(route[:-1], route[1:])]
    return tester.result(True, path, nodes, edges,
                         f"path of {len(route) - 1} edges through a roadmap of {samples} samples + q_s, q_g", ms)


def _steer(space: PlanningSpace, a: np.ndarray, b: np.ndarray, step: float) -> np.ndarray:
    d = float(space.distance(a, b))
    return b.copy() if d <= step else space.interpolate(a, b, np.array([step / d]))[0]


class _Tree:
    """A tree of configurations: vertices, parent indices, the vertices' clearances (certified mode) and
    the smallest clearance met on the edge from each vertex's parent."""

    def __init__(self, root: np.ndarray, c: np.ndarray | None) -> None:
        self.nodes, self.parent, self.clear, self.reach = [root], [-1], [c], [np.inf]

    def add(self, q: np.ndarray, c: np.ndarray | None, parent: int, m: float) -> int:
        self.nodes.append(q)
        self.parent.append(parent)
        self.clear.append(c)
        self.reach.append(m)
        return len(self.nodes) - 1

    def nearest(self, space: PlanningSpace, q: np.ndarray) -> int:
        return int(np.argmin(space.distance(np.asarray(self.nodes), q)))

    def route(self, leaf: int) -> list[int]:
        """Vertex indices root → leaf."""
        route = [leaf]
        while self.parent[route[-1]] >= 0:
            route.append(self.parent[route[-1]])
        return route[::-1]

    def edges(self, offset: int = 0) -> list[tuple[int, int]]:
        return [(p + offset, k + offset) for k, p in enumerate(self.parent) if p >= 0]


def _extend(space: PlanningSpace, tester: _EdgeTester, tree: _Tree, q_target: np.ndarray, step: float,
            near: int | None = None) -> int | None:
    """EXTEND: add q_new, ``step`` from the vertex nearest to q_target (or ``near``) towards it, when the
    edge is accepted; returns its index (None when refused)."""
    near = tree.nearest(space, q_target) if near is None else near
    q_new = _steer(space, tree.nodes[near], q_target, step)
    c_new = tester.clear(q_new)
    m = tester.test(tree.nodes[near], q_new, tree.clear[near], c_new)
    return None if m is None else tree.add(q_new, c_new, near, m)


def rrt(space: PlanningSpace, q_start: Any, q_goal: Any, rng: Any, step: float = 0.3,
        max_iterations: int = 5000, goal_bias: float = 0.05, time_limit: float | None = None,
        edge_check: str = "certified") -> PlanResult:
    """Rapidly-exploring random tree (Sect. 12.5.2, Fig. 12.11).

    Each iteration draws q_rand (q_g with probability ``goal_bias``), finds the nearest vertex q_near and
    adds q_new at distance ``step`` from it towards q_rand when the edge q_near → q_new is certified free.
    The search ends when q_g is joined to a vertex within ``step`` by a certified edge, or when a budget
    (``max_iterations``, ``time_limit`` [s]) is spent.
    """
    rng = as_generator(rng)
    tester = _EdgeTester(space, edge_check)
    qs, qg, cs, cg = _free_ends(space, tester, q_start, q_goal)
    as_positive(step, "step")
    max_iterations = as_count(max_iterations, "max_iterations")
    if not 0.0 <= float(goal_bias) <= 1.0:
        raise ValueError(f"`goal_bias` must lie in [0, 1], got {goal_bias}")
    budget = _Budget(time_limit)
    tree = _Tree(qs, cs)
    stop = f"goal not reached in {max_iterations} iterations (the budget `max_iterations`)"
    for it in range(max_iterations):
        if budget.spent():
            stop = f"goal not reached: {budget.message()} after {it} iterations"
            break
        q_rand = qg if rng.random() < goal_bias else space.sample(rng)
        k = _extend(space, tester, tree, q_rand, step)
        if k is not None and float(space.distance(tree.nodes[k], qg)) <= step:
            m = tester.test(tree.nodes[k], qg, tree.clear[k], cg)
            if m is not None:
                leaf = tree.add(qg, cg, k, m)
                route = tree.route(leaf)
                return tester.result(True, np.asarray(tree.nodes)[route], tree.nodes, tree.edges(),
                                     f"goal reached after {it + 1} iterations, {len(tree.nodes)} vertices",
                                     [tree.reach[i] for i in route[1:]])
    return tester.result(False, np.zeros((0, space.dim)), tree.nodes, tree.edges(), stop)


def rrt_connect(space: PlanningSpace, q_start: Any, q_goal: Any, rng: Any, step: float = 0.3,
                max_iterations: int = 2000, time_limit: float | None = None,
                edge_check: str = "certified") -> PlanResult:
    """Bidirectional RRT with the greedy CONNECT heuristic (Sect. 12.5.2: "two trees rooted at q_s and q_g").

    One tree is extended one step towards a random sample; the other then takes as many certified steps
    as it can towards the new vertex; the roles swap every iteration. Success when the two trees meet;
    failure when a budget (``max_iterations``, ``time_limit`` [s]) is spent.
    """
    rng = as_generator(rng)
    tester = _EdgeTester(space, edge_check)
    qs, qg, cs, cg = _free_ends(space, tester, q_start, q_goal)
    as_positive(step, "step")
    max_iterations = as_count(max_iterations, "max_iterations")
    budget = _Budget(time_limit)
    trees = [_Tree(qs, cs), _Tree(qg, cg)]
    stop = f"trees did not meet in {max_iterations} iterations (the budget `max_iterations`)"
    for it in range(max_iterations):
        if budget.spent():
            stop = f"trees did not meet: {budget.message()} after {it} iterations"
            break
        ta, tb = trees[it % 2], trees[(it + 1) % 2]
        new = _extend(space, tester, ta, space.sample(rng), step)
        if new is None:
            continue
        q_new = ta.nodes[new]
        k = tb.nearest(space, q_new)                                     # CONNECT the other tree
        while True:
            k_next = _extend(space, tester, tb, q_new, step, near=k)
            if k_next is None:
                break
            k = k_next
            if float(space.distance(tb.nodes[k], q_new)) == 0.0:
                ra, rb = ta.route(new), tb.route(k)
                path = [ta.nodes[i] for i in ra] + [tb.nodes[i] for i in rb[::-1][1:]]
                ms = [ta.reach[i] for i in ra[1:]] + [tb.reach[i] for i in rb[1:]]
                if it % 2 == 1:
                    path = path[::-1]
                n_s = len(trees[0].nodes)
                return tester.result(True, np.asarray(path), trees[0].nodes + trees[1].nodes,
                                     trees[0].edges() + trees[1].edges(n_s),
                                     f"trees met after {it + 1} iterations, {n_s + len(trees[1].nodes)} vertices", ms)
    n_s = len(trees[0].nodes)
    return tester.result(False, np.zeros((0, space.dim)), trees[0].nodes + trees[1].nodes,
                         trees[0].edges() + trees[1].edges(n_s), stop)


def shortcut(space: PlanningSpace, path: Any, rng: Any, attempts: int = 100,
             edge_check: str = "certified") -> np.ndarray:
    """Random shortcutting: join two random non-consecutive vertices by a straight edge when it is certified
    free (or, with ``edge_check="sampled"``, free at the sampled configurations) and drop the vertices
    between them. The length never increases; the edges kept from ``path`` are as certified as they were
    (:func:`certify_path` certifies the result as a whole)."""
    rng = as_generator(rng)
    tester = _EdgeTester(space, edge_check)
    P = [np.asarray(q, dtype=float) for q in np.asarray(path, dtype=float)]
    if not P or any(q.shape != (space.dim,) or not np.all(np.isfinite(q)) for q in P):
        raise ValueError(f"`path` must be a finite (k >= 1, {space.dim}) array, got shape {np.shape(path)}")
    C: list[np.ndarray | None] = [None] * len(P)
    for _ in range(as_count(attempts, "attempts", minimum=0)):
        if len(P) < 3:
            break
        i, j = sorted(rng.choice(len(P), size=2, replace=False))
        if j - i < 2:
            continue
        if tester.certified:
            for k in (i, j):
                if C[k] is None:
                    C[k] = tester.clear(P[k])
        if tester.test(P[i], P[j], C[i], C[j]) is not None:
            P, C = P[:i + 1] + P[j:], C[:i + 1] + C[j:]
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

    def __post_init__(self) -> None:
        for name in ("v", "omega"):
            val = getattr(self, name)
            if not isinstance(val, (int, float, np.integer, np.floating)) or not np.isfinite(val):
                raise ValueError(f"`{name}` must be a finite number, got {val!r}")


def _arc_extent(q: np.ndarray, v: float, omega: float, delta: float) -> tuple[np.ndarray, np.ndarray]:
    """The smallest box (lower (2,), upper (2,)) holding the reference point's arc: its ends and the points
    where the heading crosses a multiple of π/2 (where x or y is extreme on the circle)."""
    ts = [0.0, delta]
    if abs(omega) > 1e-12:
        th0, th1 = q[2], q[2] + omega * delta
        lo, hi = min(th0, th1), max(th0, th1)
        for k in range(int(np.ceil(lo / (np.pi / 2))), int(np.floor(hi / (np.pi / 2))) + 1):
            ts.append((k * np.pi / 2 - th0) / omega)
    P = unicycle_arc(q, v, omega, np.asarray(ts))[:, :2]
    return P.min(axis=0), P.max(axis=0)


def certify_arc(space: Any, q: Any, primitive: MotionPrimitive, delta: float,
                c0: np.ndarray | None = None) -> EdgeCertificate:
    """Certificate that the unicycle's arc from q under ``primitive`` for ``delta`` s is collision-free and
    stays within the space's position bounds.

    Over a time τ every point of part p moves by at most (|v| + r_p |ω|) τ (the reference point travels
    |v| τ along the arc and the body turns by |ω| τ), which is linear in τ: the adaptive bisection of
    :func:`planners.configuration_space.certify_by_bisection` applies along the arc. The reference point's
    arc is tested against the bounds exactly (:func:`_arc_extent`). Needs a
    :class:`planners.configuration_space.PlanarCSpace` of a :class:`planners.configuration_space.PlanarBody`.
    """
    radii = getattr(getattr(space, "robot", None), "part_radii", None)
    if radii is None or space.dim != 3:
        raise ValueError("`space` must be a PlanarCSpace of a PlanarBody to certify unicycle arcs "
                         "(or pass edge_check='sampled')")
    q = as_vector(q, 3, "q")
    delta = as_positive(delta, "delta")
    v, w = float(primitive.v), float(primitive.omega)
    lo, hi = _arc_extent(q, v, w, delta)
    if np.any(lo < space.lower[:2] - 1e-12) or np.any(hi > space.upper[:2] + 1e-12):
        return EdgeCertificate(False, -np.inf, 0, "the arc leaves the position bounds")
    end = unicycle_arc(q, v, w, delta)
    c0 = space.clearances(q) if c0 is None else c0
    c1 = space.clearances(end)
    cert = certify_by_bisection(lambda s, idx: space.clearances(unicycle_arc(q, v, w, s * delta), idx),
                                (abs(v) + radii * abs(w)) * delta, c0, c1)
    return EdgeCertificate(cert.free, cert.min_clearance, cert.queries + 1, cert.message)


def unicycle_rrt(space: PlanningSpace, q_start: Any, q_goal: Any, rng: Any,
                 primitives: Sequence[MotionPrimitive], delta: float, max_vertices: int = 200,
                 goal_threshold: float = 0.01, goal_bias: float = 0.2, checks: int = 20,
                 max_iterations: int | None = None, max_rejected: int = MAX_REJECTED,
                 time_limit: float | None = None, edge_check: str = "certified") -> PlanResult:
    """RRT for the unicycle with motion primitives (Sect. 12.5.2, Fig. 12.12; Problem 12.8).

    Each iteration draws q_rand (q_g with probability ``goal_bias``; a colliding sample is rejected),
    takes the nearest vertex that still has unused primitives, applies each unused primitive for
    ``delta`` seconds (closed-form arcs, :func:`unicycle_arc`), discards those whose arc is not certified
    free (:func:`certify_arc`; with ``edge_check="sampled"``: colliding at ``checks`` equally spaced
    instants), and keeps the one ending closest to q_rand; each primitive is used at most once per vertex.
    The search ends when a vertex is within ``goal_threshold`` of q_g, or with ``success=False`` (and the
    path to the closest vertex) once ``max_vertices`` exist, every vertex's primitives are used, or a
    budget is spent: ``max_iterations`` (default 50 × ``max_vertices``), ``max_rejected`` rejected
    samples, ``time_limit`` [s].
    """
    rng = as_generator(rng)
    tester = _EdgeTester(space, edge_check)
    qs, qg, cs, _ = _free_ends(space, tester, q_start, q_goal)
    delta = as_positive(delta, "delta")
    prims = list(primitives)
    if not prims:
        raise ValueError("`primitives` must not be empty")
    for k, p in enumerate(prims):
        if not isinstance(p, MotionPrimitive):
            raise ValueError(f"`primitives[{k}]` must be a MotionPrimitive, got {type(p).__name__}")
    max_vertices = as_count(max_vertices, "max_vertices")
    as_positive(goal_threshold, "goal_threshold")
    if not 0.0 <= float(goal_bias) <= 1.0:
        raise ValueError(f"`goal_bias` must lie in [0, 1], got {goal_bias}")
    max_iterations = 50 * max_vertices if max_iterations is None else as_count(max_iterations, "max_iterations")
    budget = _Budget(time_limit, max_rejected)
    times = np.linspace(0.0, delta, as_count(checks, "checks") + 1)[1:]
    tree = _Tree(qs, cs)
    used: list[set] = [set()]
    via = [-1]
    rejected = 0
    stop = f"{max_vertices} vertices (the budget `max_vertices`)"
    for it in range(max_iterations + 1):
        if len(tree.nodes) >= max_vertices:
            break
        if it == max_iterations:
            stop = f"{max_iterations} iterations (the budget `max_iterations`)"
            break
        spent = budget.exhausted(rejected)
        if spent:
            stop = spent
            break
        q_rand = qg if rng.random() < goal_bias else space.sample(rng)
        tester.checks += 1
        if not space.valid_many(q_rand[None])[0]:
            rejected += 1
            continue
        open_ = [k for k in range(len(tree.nodes)) if len(used[k]) < len(prims)]
        if not open_:
            stop = "every vertex has used all its primitives"
            break
        near = open_[int(np.argmin(space.distance(np.asarray([tree.nodes[k] for k in open_]), q_rand)))]
        best, best_d, best_c, best_m = -1, np.inf, None, np.nan
        for p, prim in enumerate(prims):
            if p in used[near]:
                continue
            tester.edges += 1
            if tester.certified:
                cert = certify_arc(space, tree.nodes[near], prim, delta, tree.clear[near])
                tester.queries += cert.queries
                ok, end, m = cert.free, unicycle_arc(tree.nodes[near], prim.v, prim.omega, delta), cert.min_clearance
            else:
                arc = unicycle_arc(tree.nodes[near], prim.v, prim.omega, times)
                tester.checks += len(arc)
                ok, end, m = bool(np.all(space.valid_many(arc))), arc[-1], np.nan
            if not ok:
                used[near].add(p)
                continue
            d = float(space.distance(end, q_rand))
            if d < best_d:
                best, best_d, best_m = p, d, m
        if best < 0:
            continue
        used[near].add(best)
        q_new = unicycle_arc(tree.nodes[near], prims[best].v, prims[best].omega, delta)
        tree.add(q_new, tester.clear(q_new), near, best_m)
        used.append(set())
        via.append(best)
        if float(space.distance(q_new, qg)) <= goal_threshold:
            break
    N = np.asarray(tree.nodes)
    d_goal = space.distance(N, qg)
    leaf = int(np.argmin(d_goal))
    route = tree.route(leaf)
    controls = np.array([[prims[via[k]].v, prims[via[k]].omega] for k in route[1:]]).reshape(-1, 2)
    ok = bool(d_goal[leaf] <= goal_threshold)
    msg = (f"{'reached' if ok else 'closest'} vertex at distance {d_goal[leaf]:.4g} from q_g "
           f"(threshold {goal_threshold:g}); {len(tree.nodes)} vertices" + ("" if ok else f"; stopped: {stop}"))
    res = tester.result(True, N[route], N, tree.edges(), msg, [tree.reach[k] for k in route[1:]] or [np.nan],
                        controls)
    if not ok:   # the path to the closest vertex is still returned (and certified) on failure
        res = replace(res, success=False)
    return res
