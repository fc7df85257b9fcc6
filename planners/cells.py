"""Roadmaps and cell decompositions of planar polygonal scenes (Sects. 12.3–12.4).

* Visibility graph (Sect. 12.3.1): the shortest semi-free path between polygonal C-obstacles.
* Generalised Voronoi diagram (Sect. 12.3.2, Problem 12.5): the nodes by the manual's naive algorithm
  (points equidistant from three boundary features, filtered by inclusion, equal characteristic
  distances and clearance), and the diagram itself sampled with scipy's Voronoi of boundary points.
* Exact cell decomposition into trapezoids by vertical lines through the vertices (Sect. 12.4.1),
  approximate decomposition into free quadtree boxes (Sect. 12.4.2), the connectivity graph, the
  channel and the channel-to-path extraction with the fix of Problem 12.6 (cell centroids inserted).

Obstacles are convex polygons (:class:`planners.configuration_space.Polygon`); the visibility graph and
the GVD assume them pairwise disjoint, the cell decompositions accept overlapping obstacles and
obstacles reaching outside the bounds.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 12.3–12.4;
Problems 12.5, 12.6.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import Any, Sequence

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import Voronoi

from planners.configuration_space import (Polygon, box, check_bounds, point_segment_distance,
                                          segment_intersects_shape, segment_shape_distance, shapes_intersect)
from rigid_body.validation import as_positive, as_vector

__all__ = [
    "polyline_clearance", "visibility_graph", "VisibilityGraph", "shortest_path_on_graph",
    "gvd_nodes", "sampled_gvd",
    "CellDecomposition", "trapezoidal_decomposition", "quadtree_decomposition", "channel_path",
]


def _check_obstacles(obstacles: Sequence[Any]) -> tuple[Polygon, ...]:
    obs = tuple(obstacles)
    for k, o in enumerate(obs):
        if not isinstance(o, Polygon):
            raise ValueError(f"`obstacles[{k}]` must be a convex Polygon, got {type(o).__name__}")
    return obs


def polyline_clearance(path: Any, obstacles: Sequence[Any]) -> float:
    """Minimum distance between a polyline (k, 2) and the obstacles, segment by segment (exact)."""
    P = np.asarray(path, dtype=float)
    return min(segment_shape_distance(a, b, o) for a, b in zip(P[:-1], P[1:]) for o in obstacles)


def shortest_path_on_graph(n: int, edges: Sequence[tuple[int, int]], weights: Sequence[float],
                           src: int, dst: int) -> list[int] | None:
    """Vertex indices of the shortest path src → dst on an undirected weighted graph (scipy Dijkstra),
    None when dst cannot be reached."""
    if not len(edges):
        return None
    i, j = np.asarray(edges).T
    G = coo_matrix((np.asarray(weights, dtype=float), (i, j)), shape=(n, n)).tocsr()
    dist, pred = dijkstra(G, directed=False, indices=src, return_predecessors=True)
    if not np.isfinite(dist[dst]):
        return None
    route = [dst]
    while route[-1] != src:
        route.append(int(pred[route[-1]]))
    return route[::-1]


# --------------------------------------------------------------------------------------------
# Visibility graph
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class VisibilityGraph:
    """Nodes (q_s, q_g, then the obstacle vertices) (N, 2), visible pairs (E, 2) and the shortest path."""

    nodes: np.ndarray
    edges: np.ndarray
    path: np.ndarray
    length: float


def visibility_graph(q_start: Any, q_goal: Any, obstacles: Sequence[Any]) -> VisibilityGraph:
    """Visibility graph (Sect. 12.3.1): q_s, q_g and the C-obstacle vertices, joined when the segment
    does not enter the interior of any obstacle; the shortest path by Dijkstra (it may graze vertices:
    a semi-free path). ValueError when no path exists."""
    obs = _check_obstacles(obstacles)
    nodes = np.vstack([as_vector(q_start, 2, "q_start"), as_vector(q_goal, 2, "q_goal")]
                      + [o.vertices for o in obs])
    edges, w = [], []
    for i, j in combinations(range(len(nodes)), 2):
        if not any(segment_intersects_shape(nodes[i], nodes[j], o) for o in obs):
            edges.append((i, j))
            w.append(float(np.linalg.norm(nodes[i] - nodes[j])))
    route = shortest_path_on_graph(len(nodes), edges, w, 0, 1)
    if route is None:
        raise ValueError("q_start and q_goal are not connected in the visibility graph")
    path = nodes[route]
    return VisibilityGraph(nodes, np.asarray(edges), path, float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1))))


# --------------------------------------------------------------------------------------------
# Generalised Voronoi diagram (Problem 12.5)
# --------------------------------------------------------------------------------------------

def _features(region: Polygon, holes: Sequence[Polygon]) -> list[tuple]:
    """Boundary features of the free set: ("vertex", v) and ("side", a, b, n) with n pointing into it."""
    feats: list[tuple] = []
    for poly, sign in [(region, -1.0)] + [(h, 1.0) for h in holes]:
        a, b = poly.edges
        for v in poly.vertices:
            feats.append(("vertex", v))
        for ak, bk, nk in zip(a, b, poly.normals):
            feats.append(("side", ak, bk, sign * nk))   # region: inward = −outward normal
    return feats


def _feature_distance(f: tuple, p: np.ndarray) -> float:
    return float(np.linalg.norm(p - f[1])) if f[0] == "vertex" else float(point_segment_distance(p, f[1], f[2]))


def _equidistant_points(triple: Sequence[tuple]) -> list[tuple[np.ndarray, float]]:
    """Points p with equal distance t ≥ 0 to the three features' vertices / side lines.

    Unknowns x = (p, t). A side gives n·p − t = n·a (linear); a vertex |p − v|² = t²; differences of two
    vertex equations are linear. So 3 linear equations (sides only) or 2 linear + one quadratic.
    """
    A, c, verts = [], [], []
    for f in triple:
        if f[0] == "side":
            A.append([f[3][0], f[3][1], -1.0])
            c.append(float(f[3] @ f[1]))
        else:
            verts.append(f[1])
    for v in verts[1:]:
        v0 = verts[0]
        A.append([-2 * (v0[0] - v[0]), -2 * (v0[1] - v[1]), 0.0])
        c.append(float(v @ v - v0 @ v0))
    A, c = np.asarray(A), np.asarray(c)
    if not verts:
        if abs(np.linalg.det(A)) < 1e-12:
            return []
        x = np.linalg.solve(A, c)
        return [(x[:2], x[2])]
    if np.linalg.matrix_rank(A, tol=1e-10) < 2:
        return []
    x0 = np.linalg.lstsq(A, c, rcond=None)[0]
    w = np.linalg.svd(A)[2][-1]                       # null direction of the 2 × 3 system
    v0 = verts[0]
    m = np.array([1.0, 1.0, -1.0])                    # |p|² − t² metric
    y0 = x0 - np.array([v0[0], v0[1], 0.0])
    qa, qb, qc = w @ (m * w), 2 * y0 @ (m * w), y0 @ (m * y0)
    if abs(qa) < 1e-14:
        roots = [] if abs(qb) < 1e-14 else [-qc / qb]
    else:
        disc = qb * qb - 4 * qa * qc
        if disc < -1e-9 * max(1.0, qb * qb):
            return []
        if abs(disc) < 1e-9 * max(1.0, qb * qb):
            disc = 0.0                                 # a double root (e.g. a corner, t = 0)
        roots = [(-qb + sgn * np.sqrt(disc)) / (2 * qa) for sgn in (1, -1)]
    return [((x0 + s * w)[:2], (x0 + s * w)[2]) for s in roots]


def _clearance(p: np.ndarray, region: Polygon, holes: Sequence[Polygon]) -> float:
    d = float(point_segment_distance(p, *region.edges).min())
    for h in holes:
        d = min(d, float(point_segment_distance(p, *h.edges).min()))
    return d


def gvd_nodes(region: Polygon, holes: Sequence[Polygon] = (), tol: float = 1e-9) -> np.ndarray:
    """Nodes of the generalised Voronoi diagram of the free set region ∖ holes (Problem 12.5's algorithm).

    Steps 1–2: intersections of equidistance curves of feature pairs (bisectors, parabolas, angle
    bisectors) whose characteristic distances agree are the points equidistant from three features,
    found in closed form; step 3 keeps those in the free set, step 4 those whose distance to each of the
    three features (as segments and points) is the common value t, step 5 those whose clearance equals t.
    Returns the distinct nodes (k, 3) as rows (x, y, clearance); clearance-0 rows are convex corners.
    """
    holes = _check_obstacles(holes)
    feats = _features(region, holes)
    found: list[np.ndarray] = []
    for triple in combinations(feats, 3):
        for p, t in _equidistant_points(triple):
            if t < -tol or not region.contains(p, tol) or any(h.contains(p, -tol) for h in holes):
                continue                                                             # step 3
            if any(abs(_feature_distance(f, p) - t) > 1e-7 for f in triple):
                continue                                                             # step 4
            if abs(_clearance(p, region, holes) - t) > 1e-7:
                continue                                                             # step 5
            row = np.array([p[0], p[1], max(t, 0.0)])
            if not any(np.linalg.norm(row[:2] - r[:2]) < 1e-5 for r in found):
                found.append(row)
    return np.array(sorted(found, key=lambda r: (r[0], r[1]))).reshape(-1, 3)


def sampled_gvd(region: Polygon, holes: Sequence[Polygon] = (), spacing: float = 0.05) -> np.ndarray:
    """The GVD as segments (k, 2, 2): Voronoi ridges (scipy.spatial.Voronoi) between boundary samples
    lying on different sides, both ends inside the free set — points with two nearest boundary features."""
    holes = _check_obstacles(holes)
    as_positive(spacing, "spacing")
    pts, label = [], []
    side = 0
    for poly in [region, *holes]:
        for a, b in zip(*poly.edges):
            n = max(int(np.ceil(np.linalg.norm(b - a) / spacing)), 1)
            s = (np.arange(n) + 0.5) / n                       # avoid the shared corners
            pts.append(a + s[:, None] * (b - a))
            label += [side] * n
            side += 1
    P, label = np.vstack(pts), np.asarray(label)
    vor = Voronoi(P)
    segs = []
    for (i, j), (u, v) in zip(vor.ridge_points, vor.ridge_vertices):
        if u < 0 or v < 0 or label[i] == label[j]:
            continue
        a, b = vor.vertices[u], vor.vertices[v]
        if all(region.contains(x) and not any(h.contains(x) for h in holes) for x in (a, b)):
            segs.append((a, b))
    return np.asarray(segs).reshape(-1, 2, 2)


# --------------------------------------------------------------------------------------------
# Cell decompositions (Problem 12.6)
# --------------------------------------------------------------------------------------------

def _common_boundary(A: Polygon, B: Polygon, tol: float = 1e-9) -> tuple[np.ndarray, np.ndarray] | None:
    """The segment shared by two cells with disjoint interiors (collinear overlapping edges), or None."""
    for a1, b1 in zip(*A.edges):
        d1 = b1 - a1
        L = float(np.linalg.norm(d1))
        u = d1 / L
        for a2, b2 in zip(*B.edges):
            cross = lambda w: u[0] * w[1] - u[1] * w[0]  # noqa: E731
            if abs(cross(a2 - a1)) > tol or abs(cross(b2 - a1)) > tol:
                continue
            s = sorted([float(u @ (a2 - a1)), float(u @ (b2 - a1))])
            lo, hi = max(0.0, s[0]), min(L, s[1])
            if hi - lo > tol:
                return a1 + lo * u, a1 + hi * u
    return None


@dataclass(frozen=True)
class CellDecomposition:
    """Free cells (convex polygons) and their connectivity graph: ``adjacent`` (E, 2) index pairs with the
    common boundary segment ``boundaries`` (E, 2, 2) of each."""

    cells: tuple
    adjacent: np.ndarray
    boundaries: np.ndarray

    def locate(self, q: Any) -> int:
        """Index of a cell containing q; ValueError when q is in no free cell."""
        q = as_vector(q, 2, "q")
        for k, c in enumerate(self.cells):
            if c.contains(q, 1e-12):
                return k
        raise ValueError(f"q = {q} is not in a free cell")

    def channel(self, c_start: int, c_goal: int) -> list[int]:
        """The channel: the sequence of adjacent cells from c_start to c_goal with fewest cells (BFS)."""
        route = shortest_path_on_graph(len(self.cells), [tuple(e) for e in self.adjacent],
                                       np.ones(len(self.adjacent)), c_start, c_goal)
        if route is None:
            raise ValueError(f"cells {c_start} and {c_goal} are not connected")
        return route


def _build(cells: list[Polygon]) -> CellDecomposition:
    adj, bnd = [], []
    for i, j in combinations(range(len(cells)), 2):
        seg = _common_boundary(cells[i], cells[j])
        if seg is not None:
            adj.append((i, j))
            bnd.append(seg)
    return CellDecomposition(tuple(cells), np.asarray(adj, dtype=int).reshape(-1, 2), np.asarray(bnd).reshape(-1, 2, 2))


def _extent(poly: Polygon, x: float) -> tuple[float, float] | None:
    """[y_min, y_max] of the vertical line x through a convex polygon, or None."""
    a, b = poly.edges
    ys = []
    for p, q in zip(a, b):
        if (p[0] - x) * (q[0] - x) <= 0 and p[0] != q[0]:
            ys.append(p[1] + (x - p[0]) / (q[0] - p[0]) * (q[1] - p[1]))
    return (min(ys), max(ys)) if ys else None


def _crossings_x(obs: Sequence[Polygon], y0: float, y1: float) -> list[float]:
    """The x of every point where edges of two different obstacles cross, or an edge crosses y = y0 or
    y = y1: between consecutive such abscissae (and the vertices') the boundary of the free set is made of
    straight pieces in a fixed vertical order."""
    xs = []
    edges = [(k, a, b) for k, o in enumerate(obs) for a, b in zip(*o.edges)]
    for (k1, a1, b1), (k2, a2, b2) in combinations(edges, 2):
        if k1 == k2:
            continue
        d1, d2, w = b1 - a1, b2 - a2, a2 - a1
        den = d1[0] * d2[1] - d1[1] * d2[0]
        if abs(den) < 1e-15:
            continue
        t = (w[0] * d2[1] - w[1] * d2[0]) / den
        u = (w[0] * d1[1] - w[1] * d1[0]) / den
        if -1e-12 <= t <= 1 + 1e-12 and -1e-12 <= u <= 1 + 1e-12:
            xs.append(float(a1[0] + t * d1[0]))
    for _, a, b in edges:
        for y in (y0, y1):
            if (a[1] - y) * (b[1] - y) < 0:
                xs.append(float(a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0])))
    return xs


def trapezoidal_decomposition(bounds: Sequence[float], obstacles: Sequence[Any]) -> CellDecomposition:
    """Exact decomposition of the free part of the rectangle ``bounds`` = (x_min, x_max, y_min, y_max) into
    trapezoids (or triangles) by vertical lines through every obstacle vertex (Sect. 12.4.1).

    Obstacles may overlap and may reach outside the rectangle: vertical lines also go through the points
    where two obstacles' edges cross and where an edge crosses the rectangle's top or bottom, so that
    within each slab the obstacles' extents are straight and keep their order; overlapping extents are
    merged and clipped to the rectangle before the free intervals between them become cells.
    """
    obs = _check_obstacles(obstacles)
    x0, x1, y0, y1 = check_bounds(bounds)
    xs = np.unique(np.concatenate([[x0, x1]] + [o.vertices[:, 0] for o in obs] + [_crossings_x(obs, y0, y1)]))
    xs = xs[(xs >= x0) & (xs <= x1)]
    scale = max(x1 - x0, y1 - y0)
    xs = xs[np.r_[True, np.diff(xs) > 1e-12 * scale]]
    xs[-1] = x1
    cells: list[Polygon] = []
    for xa, xb in zip(xs[:-1], xs[1:]):
        # boundaries are straight across a slab: evaluate inside and extrapolate to its ends
        x_in = (xa + 0.25 * (xb - xa), xa + 0.75 * (xb - xa))

        def at(ends: tuple[float, float], x: float) -> float:
            return ends[0] + (x - x_in[0]) / (x_in[1] - x_in[0]) * (ends[1] - ends[0])

        blocks = []
        for o in obs:
            e = [_extent(o, x) for x in x_in]
            if e[0] is None or e[1] is None:
                continue
            lo = (max(e[0][0], y0), max(e[1][0], y0))        # clipped to the rectangle (no crossing inside)
            hi = (min(e[0][1], y1), min(e[1][1], y1))
            if hi[0] > lo[0] or hi[1] > lo[1]:
                blocks.append((lo, hi))
        blocks.sort(key=lambda b: (b[0][0], b[0][1]))
        merged: list[list] = []
        for lo, hi in blocks:                                 # union of overlapping extents
            if merged and lo[0] <= merged[-1][1][0] + 1e-12 and lo[1] <= merged[-1][1][1] + 1e-12:
                top = merged[-1][1]
                merged[-1][1] = hi if (hi[0] + hi[1]) > (top[0] + top[1]) else top
            else:
                merged.append([lo, hi])
        # (value at x_in[0], value at x_in[1]) of the lower and upper boundary of each free interval
        lower = [(y0, y0)] + [m[1] for m in merged]
        upper = [m[0] for m in merged] + [(y1, y1)]
        for lo, hi in zip(lower, upper):
            verts = [(xa, at(lo, xa)), (xb, at(lo, xb)), (xb, at(hi, xb)), (xa, at(hi, xa))]
            if verts[3][1] - verts[0][1] <= 1e-12 * scale and verts[2][1] - verts[1][1] <= 1e-12 * scale:
                continue                                      # no free interval here (obstacles touch)
            uniq = [v for k, v in enumerate(verts) if np.hypot(v[0] - verts[k - 1][0], v[1] - verts[k - 1][1])
                    > 1e-12 * scale]
            cells.append(Polygon(np.array(uniq)))
    return _build(cells)


def quadtree_decomposition(bounds: Sequence[float], obstacles: Sequence[Any], min_size: float) -> CellDecomposition:
    """Approximate decomposition (Sect. 12.4.2): boxes split in four while *mixed* (touching an obstacle
    without lying inside it) and larger than ``min_size``; the free boxes are the cells (mixed boxes
    at the smallest size count as occupied, so the decomposition is conservative)."""
    obs = _check_obstacles(obstacles)
    as_positive(min_size, "min_size")
    x0, x1, y0, y1 = check_bounds(bounds)
    free: list[Polygon] = []
    stack = [(x0, y0, x1, y1)]
    while stack:
        a, b, c, d = stack.pop()
        cell = box(a, b, c, d)
        hit = [o for o in obs if shapes_intersect(cell, o)]
        if not hit:
            free.append(cell)
            continue
        if any(np.all(o.contains(cell.vertices)) for o in hit) or min(c - a, d - b) / 2 < min_size:
            continue
        xm, ym = (a + c) / 2, (b + d) / 2
        stack += [(a, b, xm, ym), (xm, b, c, ym), (a, ym, xm, d), (xm, ym, c, d)]
    return _build(free)


def channel_path(dec: CellDecomposition, q_start: Any, q_goal: Any,
                 centroids: bool = True) -> tuple[np.ndarray, list[int]]:
    """Path from a channel (Sect. 12.4.1): q_s, the midpoints of the common boundaries of consecutive
    channel cells, q_g. With ``centroids`` (the fix of Problem 12.6) the centroid of every channel cell
    except c_s and c_g is inserted between its two boundary midpoints, so no edge runs along a boundary.
    Returns the path (k, 2) and the channel."""
    qs, qg = as_vector(q_start, 2, "q_start"), as_vector(q_goal, 2, "q_goal")
    chan = dec.channel(dec.locate(qs), dec.locate(qg))
    index = {tuple(sorted(e)): k for k, e in enumerate(dec.adjacent.tolist())}
    pts = [qs]
    for k, (ci, cj) in enumerate(zip(chan[:-1], chan[1:])):
        if centroids and k > 0:
            pts.append(dec.cells[ci].centroid)
        seg = dec.boundaries[index[tuple(sorted((ci, cj)))]]
        pts.append(seg.mean(axis=0))
    pts.append(qg)
    return np.asarray(pts), chan

