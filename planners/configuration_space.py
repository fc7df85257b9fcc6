"""Configuration space and obstacle geometry: the one home of what collision avoidance is built on.

* Distances of a robot (or a point of its path) from obstacles, the seed of the C-space (Ch. 3, 6):
  the closest point of a polyline, the distance of a planar arm from a disc and its gradient with
  respect to q (Problems 3.9, 3.21, (S3.4)–(S3.8)), the distance of points from a box standing on the
  floor (Problems 6.1–6.2).
* Exact 2-D geometry of convex shapes (Ch. 12): a :class:`Disc` or a convex :class:`Polygon` (every
  obstacle and robot body of the book's planar scenes is a union of them); point/segment/polygon
  distances (all through one clamped projection on a segment, (S3.5)–(S3.8)), separating-axis
  intersection, ray casting (the range sensor of Problem 12.12).
* Distances in C (Sect. 12.1, Problem 12.2): the Euclidean d₂ (12.2) and the distance on the torus
  (and on R² × SO(2)) that takes the shortest way round every angular coordinate.
* C-obstacles of translating robots as Minkowski sums, CO = O ⊕ (−B) (Sect. 12.2.1, Problem 12.3).
* Planar robots: the n-R arm on a mobile base of the companion files (links = rectangles + discs) and
  a rigid planar body (the unicycle of Problem 12.8); their occupancy, clearance and a bound on how far
  any of their points moves between two configurations (used to certify a path between samples).
* The free configuration space on a grid and its connected components, with wrap-around on angular
  coordinates (Problem 12.4); certificates that a straight C-space path is collision-free.
* The edge certificate every planner uses (:func:`certify_by_bisection`, :class:`EdgeCertificate`): the
  clearances at the ends of a motion against a bound on how far the robot moves along it, bisected where
  that does not suffice (Schwarzer, Saha & Latombe 2004); :meth:`PlanarCSpace.certify_edge` applies it
  with per-part motion bounds (or the exact segment test for a translating disc).

Robots loaded from URDF among boxes (coal through Pinocchio's ``GeometryModel``) are in
:mod:`planners.collision`.

Why in ``planners/`` and not in ``rigid_body/``: distances are only used to plan motions (the
redundancy resolution of 3.21 maximises one, the path of 6.2 keeps one positive, Chapter 12 plans in
C_free), and the geometry and its users belong together; nothing below ``planners`` imports this
module (a Pinocchio arm is read through its frame placements).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 3.5.1 (distance from an obstacle as an objective of redundancy resolution), Sects. 12.1–12.2
(configuration space, distances, C-obstacles); solution manual, Problem 3.9 ((S3.4)–(S3.8)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Callable, Sequence

import numpy as np
import pinocchio as pin
from scipy import ndimage
from scipy.spatial import ConvexHull

from rigid_body.rotations import wrap_angle
from rigid_body.validation import as_generator, as_positive, as_vector

__all__ = [
    # distances of Ch. 3 and 6
    "closest_points_on_polyline", "polyline_distance", "ObstacleDistance", "segment_chain_distance",
    "planar_arm_obstacle_distance", "planar_arm_obstacle_distance_gradient", "distance_to_box",
    # planar shapes and their distances
    "Disc", "Polygon", "Shape", "box", "as_points", "transform_shape",
    "project_on_segments", "point_segment_distance", "point_shape_distance", "shapes_distance",
    "shapes_intersect", "segment_intersects_shape", "segment_shape_distance", "ray_shape_distance",
    "batch_distance",
    # the C-space of Ch. 12
    "angular_difference", "configuration_difference", "euclidean_distance", "torus_distance",
    "minkowski_c_obstacle", "PlanarArm", "PlanarBody", "PlanarCSpace", "Scene",
    "check_bounds", "free_grid", "connected_components", "densify", "certify_motion", "certify_straight_path",
    "EdgeCertificate", "certify_by_bisection", "EDGE_QUERY_BUDGET", "MAX_GRID_NODES",
]


# --------------------------------------------------------------------------------------------
# Distances of a chain of segments from obstacles (Problems 3.9, 3.21, 6.1–6.2)
# --------------------------------------------------------------------------------------------

def _as_polyline(polyline: Any, name: str) -> np.ndarray:
    P = np.asarray(polyline, dtype=float)
    if P.ndim != 2 or P.shape[1] != 2 or P.shape[0] < 2 or not np.all(np.isfinite(P)):
        raise ValueError(f"`{name}` must be a finite (k >= 2, 2) array of segment end points, got {P.shape}")
    return P


def project_on_segments(p: Any, a: Any, b: Any) -> tuple[np.ndarray, np.ndarray]:
    """The closest point of each segment a–b to the point p (all broadcast over leading axes, (…, 2)).

    The closest point of the line is at s* = (p − a)·(b − a) / ‖b − a‖² (S3.7), clamped to the
    segment, s = max{0, min{1, s*}} (S3.8), at a + s (b − a) (S3.5)–(S3.6); a zero-length segment
    gives s = 0. Returns ``s`` (…) and ``closest`` (…, 2). Every point–segment distance of this
    module goes through it.

    >>> s, c = project_on_segments([2.0, 1.0], [0.0, 0.0], [1.0, 0.0])
    >>> float(s), c.tolist()
    (1.0, [1.0, 0.0])
    """
    p, a, b = (np.asarray(v, dtype=float) for v in (p, a, b))
    d = b - a
    w = p - a
    dx, dy = d[..., 0], d[..., 1]
    dd = dx * dx + dy * dy
    with np.errstate(invalid="ignore", divide="ignore"):
        s_star = (w[..., 0] * dx + w[..., 1] * dy) / dd                                # (S3.7)
    s = np.where(dd > 0, s_star, 0.0)
    np.clip(s, 0.0, 1.0, out=s)                                                     # (S3.8)
    return s, a + s[..., None] * d                                                  # (S3.5), (S3.6)


def closest_points_on_polyline(points: Any, polyline: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each planar point (m, 2), its closest point on every segment of ``polyline`` (k, 2).

    Segment i runs from x_i to x_{i+1} (:func:`project_on_segments`, (S3.5)–(S3.8)).
    Returns ``closest`` (m, k−1, 2), ``s`` (m, k−1) and the distances ``d`` (m, k−1).

    >>> closest, s, d = closest_points_on_polyline([[0.5, 1.0], [-1.0, 0.0]], [[0, 0], [1, 0]])
    >>> s.ravel().tolist(), d.ravel().tolist()
    ([0.5, 0.0], [1.0, 1.0])
    """
    P = _as_polyline(polyline, "polyline")
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"`points` must be an (m, 2) array, got shape {p.shape}")
    s, closest = project_on_segments(p[:, None, :], P[None, :-1], P[None, 1:])
    return closest, s, _norm2(p[:, None, :] - closest)


def polyline_distance(points: Any, polyline: Any) -> np.ndarray:
    """Euclidean distance (m,) of each planar point (m, 2) from the polyline (k, 2) (a closed contour
    repeats its first point at the end).

    >>> polyline_distance([[0.25, 2.0], [3.0, 0.0]], [[0, 0], [1, 0], [1, 1]]).tolist()
    [1.25, 2.0]
    """
    return np.min(closest_points_on_polyline(points, polyline)[2], axis=1)


@dataclass(frozen=True)
class ObstacleDistance:
    """Distance of a chain of segments from a circular obstacle, Problem 3.9.

    Attributes
    ----------
    distance : d = min_i d_i − R (negative when the obstacle intersects a link), (S3.4).
    link : index i (0-based) of the closest link.
    s : the clamped segment parameter s_i ∈ [0, 1] of the closest point, (S3.8).
    point : the closest point of the arm (2,).
    """

    distance: float
    link: int
    s: float
    point: np.ndarray


def segment_chain_distance(points: Any, center: Any, radius: float) -> ObstacleDistance:
    """Minimum distance of the polyline through ``points`` (k, 2) from a disc, (S3.4)–(S3.8).

    The closest point of each segment to the centre o (:func:`closest_points_on_polyline`),
    d_i = ‖p_i − o‖, then d = min_i d_i − R (S3.4).

    >>> r = segment_chain_distance([[0, 0], [1, 0], [1, 1]], [2.0, 0.5], 0.25)
    >>> round(r.distance, 12), r.link, r.s
    (0.75, 1, 0.5)
    """
    P = _as_polyline(points, "points")
    x, y = as_vector(center, 2, "center").tolist()
    radius = as_positive(radius, "radius", allow_zero=True)
    best = (math.inf, 0, 0.0, 0.0, 0.0)
    for i, ((ax, ay), (bx, by)) in enumerate(zip(P[:-1].tolist(), P[1:].tolist())):
        s, cx, cy, d = _project_point(x, y, ax, ay, bx, by)
        if d < best[0]:
            best = (d, i, s, cx, cy)
    d, i, s, cx, cy = best
    return ObstacleDistance(d - radius, i, s, np.array([cx, cy]))                     # (S3.4)


def _link_points(robot: Any, q: np.ndarray, frames: list[str] | None) -> tuple[np.ndarray, list]:
    if frames is None:
        frames = [f"frame_{i}" for i in range(robot.nq + 1)]
    ids = [robot.frame(f) for f in frames]
    pin.framesForwardKinematics(robot.model, robot.data, q)
    return np.array([robot.data.oMf[i].translation[:2] for i in ids]), ids


def planar_arm_obstacle_distance(robot: Any, q: Any, center: Any, radius: float,
                                 frames: list[str] | None = None) -> ObstacleDistance:
    """Distance of a planar arm (links = segments between consecutive frame origins) from a disc.

    ``frames`` are the link end frames (default ``frame_0 … frame_n`` of a DH robot), in the x–y plane.
    """
    q = as_vector(q, robot.nq, "q")
    points, _ = _link_points(robot, q, frames)
    return segment_chain_distance(points, center, radius)


def planar_arm_obstacle_distance_gradient(robot: Any, q: Any, center: Any, radius: float,
                                          frames: list[str] | None = None) -> np.ndarray:
    """∂d/∂q (n,) of :func:`planar_arm_obstacle_distance`, analytically.

    The closest point is p = (1 − s) x_{i-1} + s x_i at the optimal s (the derivative with respect
    to s vanishes or s is clamped), so ∂d/∂q = (p − o)^T/‖p − o‖ · ((1 − s) J_{i-1} + s J_i) with
    J_j the position Jacobian (x, y rows) of the frame origins. The manual's Problem 3.21 uses
    forward differences instead: :func:`planners.inverse_kinematics.numerical_gradient`.
    """
    q = as_vector(q, robot.nq, "q")
    points, ids = _link_points(robot, q, frames)
    res = segment_chain_distance(points, center, radius)
    o = as_vector(center, 2, "center")
    diff = res.point - o
    norm = np.linalg.norm(diff)
    if norm == 0.0:
        raise ValueError("the obstacle centre lies on the arm: the distance is not differentiable there")
    LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    pin.computeJointJacobians(robot.model, robot.data, q)
    J0 = pin.getFrameJacobian(robot.model, robot.data, ids[res.link], LWA)[:2]
    J1 = pin.getFrameJacobian(robot.model, robot.data, ids[res.link + 1], LWA)[:2]
    return diff / norm @ ((1.0 - res.s) * J0 + res.s * J1)


def distance_to_box(p: Any, obstacle: Any) -> np.ndarray:
    """Euclidean distance (N,) of planar points p (N, 2) from the box [x_min, x_max] × (−∞, top]
    standing on the floor, ``obstacle = (x_min, x_max, top)`` (the obstacle of Problems 6.1–6.2).

    >>> distance_to_box([[0.0, 2.0], [4.0, 1.0], [1.5, 0.0]], (1.0, 2.0, 1.0)).tolist()
    [1.4142135623730951, 2.0, 0.0]
    """
    x_min, x_max, top = as_vector(obstacle, 3, "obstacle")
    p = np.atleast_2d(np.asarray(p, dtype=float))
    dx = np.maximum(np.maximum(x_min - p[:, 0], p[:, 0] - x_max), 0.0)
    dy = np.maximum(p[:, 1] - top, 0.0)
    return np.hypot(dx, dy)



TWO_PI = 2.0 * np.pi
EDGE_QUERY_BUDGET = 2000   # distance queries one edge may spend before it is refused (an edge grazing an
                           # obstacle over a long stretch needs ~ motion bound / clearance of them)


# --------------------------------------------------------------------------------------------
# Shapes
# --------------------------------------------------------------------------------------------

def as_points(x: Any, name: str) -> np.ndarray:
    """``x`` as a finite (k, 2) array of points; ValueError naming ``name`` otherwise."""
    P = np.asarray(x, dtype=float)
    if P.ndim != 2 or P.shape[1] != 2 or not np.all(np.isfinite(P)):
        raise ValueError(f"`{name}` must be a finite (k, 2) array of points, got shape {P.shape}")
    return P


@dataclass(frozen=True)
class Disc:
    """A disc of centre ``center`` (2,) [m] and radius ``radius`` [m]."""

    center: np.ndarray
    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", as_vector(self.center, 2, "center"))
        object.__setattr__(self, "radius", as_positive(self.radius, "radius", allow_zero=True))


@dataclass(frozen=True)
class Polygon:
    """A convex polygon; ``vertices`` (k ≥ 3, 2) [m] are stored counter-clockwise.

    A non-convex or degenerate vertex list raises ValueError (decompose non-convex obstacles into
    convex pieces, as Sect. 12.6.2 also requires for the repulsive potential).
    """

    vertices: np.ndarray

    def __post_init__(self) -> None:
        V = as_points(self.vertices, "vertices")
        if V.shape[0] < 3:
            raise ValueError(f"`vertices` must have at least 3 points, got {V.shape[0]}")
        e = np.roll(V, -1, axis=0) - V
        length = np.hypot(e[:, 0], e[:, 1])
        scale = float(np.max(np.abs(V - V.mean(axis=0)))) or 1.0
        short = np.flatnonzero(length <= 1e-12 * scale)
        if short.size:
            k = int(short[0])
            raise ValueError(f"`vertices` [{k}] and [{(k + 1) % len(V)}] are the same point {V[k].tolist()}: "
                             "remove repeated vertices")
        area2 = float(np.sum(V[:, 0] * np.roll(V[:, 1], -1) - np.roll(V[:, 0], -1) * V[:, 1]))
        if abs(area2) <= 1e-12 * scale * scale:
            raise ValueError("`vertices` describe a degenerate polygon (zero area)")
        if area2 < 0:
            V = V[::-1].copy()
            e = np.roll(V, -1, axis=0) - V
        cross = e[:, 0] * np.roll(e[:, 1], -1) - e[:, 1] * np.roll(e[:, 0], -1)
        dot = e[:, 0] * np.roll(e[:, 0], -1) + e[:, 1] * np.roll(e[:, 1], -1)
        if np.any(cross < -1e-12 * scale * scale):
            raise ValueError("`vertices` must describe a convex polygon (decompose it into convex pieces)")
        # a convex polygon turns once round: a star (self-intersecting, every turn to the left) turns more
        turning = float(np.sum(np.arctan2(cross, dot)))
        if abs(turning - 2 * np.pi) > 1e-6:
            raise ValueError(f"`vertices` describe a self-intersecting polygon (its edges turn "
                             f"{turning / (2 * np.pi):.3g} times round, a simple convex one once)")
        object.__setattr__(self, "vertices", V)

    @classmethod
    def _moved(cls, vertices: np.ndarray) -> "Polygon":
        """A polygon whose ccw vertices are a rigid motion of a validated polygon's: no re-validation
        (a rotation and a translation keep a convex ccw polygon convex and ccw)."""
        poly = object.__new__(cls)
        object.__setattr__(poly, "vertices", vertices)
        return poly

    @cached_property
    def edges(self) -> tuple[np.ndarray, np.ndarray]:
        """Start and end points (k, 2) of the edges, counter-clockwise."""
        return self.vertices, np.roll(self.vertices, -1, axis=0)

    @cached_property
    def offsets(self) -> np.ndarray:
        """n_k · a_k (k,): edge k's supporting line is {x : n_k · x = n_k · a_k}, the polygon on its ≤ side."""
        a, n = self.vertices, self.normals
        return a[:, 0] * n[:, 0] + a[:, 1] * n[:, 1]

    @cached_property
    def normals(self) -> np.ndarray:
        """Outward unit normals (k, 2) of the edges."""
        a, b = self.edges
        e = b - a
        n = np.column_stack([e[:, 1], -e[:, 0]])
        return n / np.linalg.norm(n, axis=1, keepdims=True)

    @cached_property
    def _edge_list(self) -> list[list[float]]:
        """[a_x, a_y, b_x, b_y, n_x, n_y, n·a] of each edge as Python floats, for the one-pair kernels."""
        a, b = self.edges
        return np.column_stack([a, b, self.normals, self.offsets]).tolist()

    @property
    def centroid(self) -> np.ndarray:
        """Area centroid (2,)."""
        V, W = self.edges
        c = V[:, 0] * W[:, 1] - W[:, 0] * V[:, 1]
        return np.array([np.sum((V[:, 0] + W[:, 0]) * c), np.sum((V[:, 1] + W[:, 1]) * c)]) / (3 * np.sum(c))

    def contains(self, p: Any, tol: float = 0.0) -> np.ndarray:
        """True for the points p (..., 2) inside or on the polygon (within ``tol``)."""
        p = np.asarray(p, dtype=float)
        a, n = self.vertices, self.normals
        s = (p[..., None, 0] - a[:, 0]) * n[:, 0] + (p[..., None, 1] - a[:, 1]) * n[:, 1]
        return np.all(s <= tol, axis=-1)


Shape = Disc | Polygon


def box(x_min: float, y_min: float, x_max: float, y_max: float) -> Polygon:
    """The axis-aligned rectangle [x_min, x_max] × [y_min, y_max] as a :class:`Polygon`."""
    if not (x_max > x_min and y_max > y_min):
        raise ValueError(f"box needs x_max > x_min and y_max > y_min, got {(x_min, y_min, x_max, y_max)}")
    return Polygon(np.array([[x_min, y_min], [x_max, y_min], [x_max, y_max], [x_min, y_max]]))


def transform_shape(shape: Shape, x: float, y: float, theta: float) -> Shape:
    """The shape carried by a frame at position (x, y) and orientation θ (shape given in that frame)."""
    c, s = np.cos(theta), np.sin(theta)
    R = np.array([[c, -s], [s, c]])
    t = np.array([x, y])
    if isinstance(shape, Disc):
        return Disc(R @ shape.center + t, shape.radius)
    return Polygon._moved(shape.vertices @ R.T + t)


# --------------------------------------------------------------------------------------------
# Distances
# --------------------------------------------------------------------------------------------

def _project_point(x: float, y: float, ax: float, ay: float, bx: float, by: float) -> tuple[float, float, float, float]:
    """:func:`project_on_segments` for one point and one segment in Python floats (the loops over a few
    segments: no array overhead): s, the closest point (x, y) and its distance from p."""
    dx, dy = bx - ax, by - ay
    dd = dx * dx + dy * dy
    s = ((x - ax) * dx + (y - ay) * dy) / dd if dd > 0 else 0.0                    # (S3.7)
    s = 0.0 if s < 0.0 else 1.0 if s > 1.0 else s                                  # (S3.8)
    cx, cy = ax + s * dx, ay + s * dy                                              # (S3.5), (S3.6)
    ex, ey = x - cx, y - cy
    return s, cx, cy, math.sqrt(ex * ex + ey * ey)


def point_segment_distance(p: Any, a: Any, b: Any) -> np.ndarray:
    """Distance of points p (..., 2) from the segments a–b (broadcast (…, 2)), by clamped projection
    (:func:`project_on_segments`)."""
    p = np.asarray(p, dtype=float)
    return _norm2(p - project_on_segments(p, a, b)[1])


def _norm2(v: np.ndarray) -> np.ndarray:
    """‖v‖ over the last axis of planar vectors (…, 2), without ``np.linalg.norm``'s overhead."""
    x, y = v[..., 0], v[..., 1]
    return np.sqrt(x * x + y * y)


def point_shape_distance(shape: Shape, p: Any) -> np.ndarray:
    """Distance of the points p (..., 2) from the shape: 0 inside, else the Euclidean distance."""
    p = np.asarray(p, dtype=float)
    if isinstance(shape, Disc):
        return np.maximum(np.linalg.norm(p - shape.center, axis=-1) - shape.radius, 0.0)
    a, b = shape.edges
    d = point_segment_distance(p[..., None, :], a, b).min(axis=-1)
    return np.where(shape.contains(p), 0.0, d)


def _separated_polygons(A: Polygon, B: Polygon) -> bool:
    """Separating-axis theorem: True when an edge normal of A or B separates the two convex polygons."""
    for P, Q in ((A, B), (B, A)):
        V = Q.vertices.tolist()
        # max over P of n·p is attained at the edge start (n·a); Q is separated if min n·q exceeds it
        for *_, nx, ny, offset in P._edge_list:
            if min(x * nx + y * ny for x, y in V) > offset:
                return True
    return False


def _point_edges_distance(x: float, y: float, edges: list[list[float]]) -> tuple[float, bool]:
    """The distance of one point from a polygon's boundary (its ``_edge_list``), and whether the point lies
    inside or on the polygon: the one-pair kernel of :func:`shapes_distance`."""
    best, inside = math.inf, True
    for ax, ay, bx, by, nx, ny, _ in edges:
        if (x - ax) * nx + (y - ay) * ny > 0.0:
            inside = False
        best = min(best, _project_point(x, y, ax, ay, bx, by)[3])
    return best, inside


def shapes_distance(A: Shape, B: Shape) -> float:
    """Euclidean distance between two convex shapes; 0 when they touch or overlap."""
    if isinstance(A, Disc) and isinstance(B, Disc):
        dx, dy = (A.center - B.center).tolist()
        return max(math.sqrt(dx * dx + dy * dy) - A.radius - B.radius, 0.0)
    if isinstance(A, Disc):
        A, B = B, A
    if isinstance(B, Disc):
        d, inside = _point_edges_distance(*B.center.tolist(), A._edge_list)
        return 0.0 if inside else max(d - B.radius, 0.0)
    if not _separated_polygons(A, B):
        return 0.0
    return min(_point_edges_distance(x, y, P._edge_list)[0]
               for P, Q in ((A, B), (B, A)) for x, y in Q.vertices.tolist())


def shapes_intersect(A: Shape, B: Shape) -> bool:
    """True when the two convex shapes share a point (touching counts as contact)."""
    if isinstance(A, Polygon) and isinstance(B, Polygon):
        return not _separated_polygons(A, B)
    return shapes_distance(A, B) <= 0.0


def segment_intersects_shape(p: Any, q: Any, shape: Shape, tol: float = 1e-9) -> bool:
    """True when the segment p–q enters the *interior* of the shape (grazing a vertex or edge is allowed).

    Exact for convex shapes: a disc by the distance of its centre from the segment, a polygon by
    Cyrus–Beck clipping (the part of the segment inside every edge half-plane, shrunk by ``tol``).
    """
    p, q = np.asarray(p, dtype=float), np.asarray(q, dtype=float)
    if isinstance(shape, Disc):
        return bool(point_segment_distance(shape.center, p, q) < shape.radius - tol)
    a, _ = shape.edges
    n = shape.normals
    d = q - p
    t0, t1 = 0.0, 1.0
    for ak, nk in zip(a, n):
        num = float(nk @ (ak - p)) - tol        # inside: n·(x − a) < −tol
        den = float(nk @ d)
        if abs(den) < 1e-15:
            if num <= 0:
                return False
            continue
        t = num / den
        if den > 0:
            t1 = min(t1, t)
        else:
            t0 = max(t0, t)
        if t0 >= t1:
            return False
    return t1 - t0 > 1e-12


def ray_shape_distance(origin: Any, directions: Any, shape: Shape) -> np.ndarray:
    """Distance along each unit ray (…, 2) from ``origin`` to the shape's boundary (∞ on a miss)."""
    o = np.asarray(origin, dtype=float)
    u = np.asarray(directions, dtype=float)
    if isinstance(shape, Disc):
        m = o - shape.center
        b = u @ m
        disc = b ** 2 - (m @ m - shape.radius ** 2)
        with np.errstate(invalid="ignore"):
            t = -b - np.sqrt(disc)
        return np.where((disc >= 0) & (t >= 0), t, np.inf)
    a, b = shape.edges
    e = b - a                                                     # (k, 2)
    w = a - o                                                     # (k, 2)
    den = u[..., None, 0] * e[:, 1] - u[..., None, 1] * e[:, 0]   # (…, k) = u × e
    with np.errstate(invalid="ignore", divide="ignore"):
        t = (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]) / den          # ray parameter: (w × e)/(u × e)
        s = (w[:, 0] * u[..., None, 1] - w[:, 1] * u[..., None, 0]) / den   # edge parameter: (w × u)/(u × e)
    hit = (np.abs(den) > 1e-15) & (t >= 0) & (s >= 0) & (s <= 1)
    return np.where(hit, t, np.inf).min(axis=-1)



# --------------------------------------------------------------------------------------------
# Batched geometry: many placements of a body part against one obstacle (numpy broadcasting)
# --------------------------------------------------------------------------------------------

def _next_vertices(P: np.ndarray) -> np.ndarray:
    """The vertex after each vertex of N polygons P (N, m, 2): the edge ends, ``np.roll(P, -1, axis=1)``."""
    return np.concatenate([P[:, 1:], P[:, :1]], axis=1)


def _batch_polygons_polygon(P: np.ndarray, Q: Polygon) -> np.ndarray:
    """Distances (N,) between N convex ccw polygons P (N, m, 2) and the convex polygon Q (0 on overlap)."""
    aQ, bQ = Q.edges
    nQ = Q.normals
    Px, Py = P[..., 0, None], P[..., 1, None]                                   # (N, m, 1)
    gap_Q = ((Px * nQ[:, 0] + Py * nQ[:, 1]).min(axis=1) - Q.offsets).max(axis=1)
    Pn = _next_vertices(P)
    e = Pn - P
    ex, ey = e[..., 0], e[..., 1]
    length = np.sqrt(ey * ey + ex * ex)
    nx, ny = (ey / length)[..., None], (-ex / length)[..., None]                # outward normals of P
    V = Q.vertices
    gap_P = ((V[:, 0] * nx + V[:, 1] * ny).min(axis=2) - (Px * nx + Py * ny)[..., 0]).max(axis=1)
    separated = (gap_Q > 0) | (gap_P > 0)
    d1 = point_segment_distance(P[:, :, None, :], aQ, bQ).min(axis=(1, 2))
    d2 = point_segment_distance(V[None, :, None, :], P[:, None], Pn[:, None]).min(axis=(1, 2))
    return np.where(separated, np.minimum(d1, d2), 0.0)


def _batch_polygons_disc(P: np.ndarray, D: Disc) -> np.ndarray:
    """Distances (N,) between N convex ccw polygons P (N, m, 2) and the disc D."""
    Pn = _next_vertices(P)
    e = Pn - P
    w = D.center - P
    inside = np.all(w[..., 0] * e[..., 1] + w[..., 1] * -e[..., 0] <= 0, axis=1)
    d = point_segment_distance(D.center, P, Pn).min(axis=1)
    return np.where(inside, 0.0, np.maximum(d - D.radius, 0.0))


def batch_distance(part: tuple, obstacle: Shape) -> np.ndarray:
    """Distances (N,) between N placements of one robot part and an obstacle.

    ``part`` is ``("disc", centres (N, 2), radius)`` or ``("polygon", vertices (N, m, 2))`` (ccw).
    """
    if part[0] == "disc":
        C, r = part[1], part[2]
        if isinstance(obstacle, Disc):
            return np.maximum(_norm2(C - obstacle.center) - r - obstacle.radius, 0.0)
        return np.maximum(point_shape_distance(obstacle, C) - r, 0.0)
    if isinstance(obstacle, Disc):
        return _batch_polygons_disc(part[1], obstacle)
    return _batch_polygons_polygon(part[1], obstacle)


def _bounding_circle(part: tuple) -> tuple[np.ndarray, np.ndarray]:
    """Centres (N, 2) and radii of circles enclosing N placed parts."""
    if part[0] == "disc":
        return part[1], np.full(len(part[1]), part[2])
    c = part[1].mean(axis=1)
    return c, _norm2(part[1] - c[:, None, :]).max(axis=1)


def _placed(shape: Shape, p: np.ndarray, phi: np.ndarray) -> tuple:
    """A part ``shape`` (in its frame) placed at N frames (positions (N, 2), angles (N,)), batched."""
    c, s = np.cos(phi)[:, None], np.sin(phi)[:, None]                     # R = [[c, −s], [s, c]]
    V = shape.center[None] if isinstance(shape, Disc) else shape.vertices
    placed = np.stack([c * V[:, 0] - s * V[:, 1], s * V[:, 0] + c * V[:, 1]], axis=-1) + p[:, None, :]
    if isinstance(shape, Disc):
        return ("disc", placed[:, 0], shape.radius)
    return ("polygon", placed)

# --------------------------------------------------------------------------------------------
# Distances in C (Problem 12.2)
# --------------------------------------------------------------------------------------------

def angular_difference(a: Any, b: Any) -> np.ndarray:
    """The shortest signed angle b − a on the circle, in (−π, π]."""
    return wrap_angle(np.asarray(b, dtype=float) - np.asarray(a, dtype=float))


def configuration_difference(qa: Any, qb: Any, angular: Sequence[bool]) -> np.ndarray:
    """qb − qa with the angular coordinates (mask ``angular``) taken the short way round the circle."""
    qa, qb = np.asarray(qa, dtype=float), np.asarray(qb, dtype=float)
    mask = np.asarray(angular, dtype=bool)
    d = qb - qa
    return np.where(mask, wrap_angle(d), d)


def euclidean_distance(qa: Any, qb: Any) -> np.ndarray:
    """d₂(q_A, q_B) = ‖q_A − q_B‖, Eq. (12.2): blind to the identification q ~ q + 2π."""
    return np.linalg.norm(np.asarray(qb, dtype=float) - np.asarray(qa, dtype=float), axis=-1)


def torus_distance(qa: Any, qb: Any, angular: Sequence[bool] | None = None) -> np.ndarray:
    """d₃ of Problem 12.2: √(Σ Δ_i²), Δ_i = min(|q_{i,A} − q_{i,B}|, 2π − |q_{i,A} − q_{i,B}|) (mod 2π).

    ``angular`` masks the coordinates living on SO(2) (default: all, the torus of the nR arm); the
    others (x, y of a mobile base) use the plain difference, so the same function is the
    R² × SO(2) distance of the unicycle (Problem 12.8). Broadcasts over leading axes.
    """
    qa, qb = np.asarray(qa, dtype=float), np.asarray(qb, dtype=float)
    if angular is None:
        angular = [True] * qa.shape[-1]
    return np.linalg.norm(configuration_difference(qa, qb, angular), axis=-1)


# --------------------------------------------------------------------------------------------
# C-obstacles of translating robots (Problem 12.3)
# --------------------------------------------------------------------------------------------

def minkowski_c_obstacle(obstacle: Polygon, robot: Polygon) -> Polygon:
    """CO = O ⊕ (−B): the configurations (reference point positions) where the translating robot B
    touches the convex obstacle O, as the convex hull of all vertex differences o − b (Sect. 12.2.1).

    ``robot`` is given in its own frame, whose origin is the reference point.
    """
    D = (obstacle.vertices[:, None, :] - robot.vertices[None, :, :]).reshape(-1, 2)
    hull = ConvexHull(D)
    return Polygon(D[hull.vertices])


# --------------------------------------------------------------------------------------------
# Robots and scenes
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Scene:
    """Convex obstacles in the plane; ``bounds`` = (x_min, x_max, y_min, y_max) of the drawing [m].

    Every obstacle is re-validated here (a :class:`Polygon` or :class:`Disc` altered after construction is
    caught), and a bad one is named: ``obstacles[k]`` and the field.
    """

    obstacles: tuple
    bounds: tuple[float, float, float, float] = (-5.0, 5.0, -5.0, 5.0)

    def __post_init__(self) -> None:
        obs = tuple(self.obstacles)
        for k, o in enumerate(obs):
            if not isinstance(o, (Disc, Polygon)):
                raise ValueError(f"`obstacles[{k}]` must be a Disc or a Polygon, got {type(o).__name__}")
            try:
                Disc(o.center, o.radius) if isinstance(o, Disc) else Polygon(o.vertices)
            except ValueError as err:
                raise ValueError(f"`obstacles[{k}]` ({type(o).__name__}): {err}") from None
        object.__setattr__(self, "obstacles", obs)
        object.__setattr__(self, "bounds", check_bounds(self.bounds))

    def clearance(self, bodies: Sequence[Shape]) -> float:
        """Minimum distance between the bodies and the obstacles, shape by shape (0 in contact)."""
        return min((shapes_distance(b, o) for b in bodies for o in self.obstacles), default=np.inf)

    def clearance_many(self, robot: "PlanarArm | PlanarBody", Q: Any) -> np.ndarray:
        """Clearances (N,) of the robot at the N configurations Q (N, dof), batched over Q."""
        return self.part_clearances(robot, Q).min(axis=1, initial=np.inf)

    def part_clearances(self, robot: "PlanarArm | PlanarBody", Q: Any, parts: Sequence[int] | None = None
                        ) -> np.ndarray:
        """Distances (N, P) of each robot part (``robot.placed_parts`` order, or only ``parts``) from the
        nearest obstacle at the N configurations Q (N, dof); ∞ without obstacles, 0 in contact."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        placed = robot.placed_parts(Q)
        idx = range(len(placed)) if parts is None else parts
        out = np.full((Q.shape[0], len(idx)), np.inf)
        for col, p in enumerate(idx):
            part = placed[p]
            c, r = _bounding_circle(part)
            best = out[:, col]
            for o, (oc, orad) in zip(self.obstacles, self._bounding_circles):
                # exact distances only where the bounding circles could beat the running minimum
                rows = np.flatnonzero(_norm2(c - oc) - r - orad < best)
                if rows.size:
                    sub = (part[0], part[1][rows]) + tuple(part[2:])
                    best[rows] = np.minimum(best[rows], batch_distance(sub, o))
        return out

    @cached_property
    def _bounding_circles(self) -> list[tuple[np.ndarray, float]]:
        out = []
        for o in self.obstacles:
            if isinstance(o, Disc):
                out.append((o.center, o.radius))
            else:
                c = o.vertices.mean(axis=0)
                out.append((c, float(np.max(np.linalg.norm(o.vertices - c, axis=1)))))
        return out


def check_bounds(bounds: Any) -> tuple[float, float, float, float]:
    """``bounds`` = (x_min, x_max, y_min, y_max) as finite floats with x_max > x_min and y_max > y_min;
    ValueError naming ``bounds`` otherwise."""
    try:
        x0, x1, y0, y1 = (float(v) for v in bounds)
    except (TypeError, ValueError):
        raise ValueError(f"`bounds` must be (x_min, x_max, y_min, y_max), got {bounds!r}") from None
    if not (np.isfinite([x0, x1, y0, y1]).all() and x1 > x0 and y1 > y0):
        raise ValueError(f"`bounds` must be finite with x_max > x_min and y_max > y_min, got {bounds!r}")
    return x0, x1, y0, y1


@dataclass(frozen=True)
class PlanarArm:
    """Planar arm of the companion files (12.7): two prismatic base joints (x, y) then n revolute joints.

    Each link i is the rectangle (0, −w/2)–(a_i, w/2) in its frame plus a disc of radius w/2 at its
    origin (the joint). With ``fixed_base`` q = [θ1 … θn] and the base sits at ``base``; otherwise
    q = [x, y, θ1 … θn].
    """

    lengths: tuple[float, ...] = (1.0, 1.0)
    width: float = 0.1
    fixed_base: bool = True
    base: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        lengths = tuple(as_positive(a, f"lengths[{i}]") for i, a in enumerate(self.lengths))
        if not lengths:
            raise ValueError("`lengths` must give at least one link")
        object.__setattr__(self, "lengths", lengths)
        as_positive(self.width, "width")
        object.__setattr__(self, "base", tuple(as_vector(self.base, 2, "base").tolist()))

    @property
    def dof(self) -> int:
        return len(self.lengths) + (0 if self.fixed_base else 2)

    @property
    def angular(self) -> np.ndarray:
        """Mask of the revolute (SO(2)) coordinates of q."""
        m = np.ones(self.dof, dtype=bool)
        if not self.fixed_base:
            m[:2] = False
        return m

    def _frames(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint positions (N, n + 1, 2) (the last row is the tip) and link angles φ_i = Σ_{j≤i} θ_j (N, n)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        if Q.shape[-1] != self.dof or not np.all(np.isfinite(Q)):
            raise ValueError(f"`q` must be finite with {self.dof} coordinates, got shape {Q.shape}")
        if self.fixed_base:
            p0, theta = np.broadcast_to(np.asarray(self.base, dtype=float), (Q.shape[0], 2)), Q
        else:
            p0, theta = Q[:, :2], Q[:, 2:]
        phi = np.cumsum(theta, axis=1)
        steps = np.stack([np.cos(phi), np.sin(phi)], axis=-1) * np.asarray(self.lengths)[:, None]
        P = np.concatenate([p0[:, None, :], p0[:, None, :] + np.cumsum(steps, axis=1)], axis=1)
        return P, phi

    def joint_positions(self, q: Any) -> np.ndarray:
        """Positions (n + 1, 2) of the joints and of the tip (direct kinematics of the planar chain)."""
        return self._frames(as_vector(q, self.dof, "q")[None])[0][0]

    @cached_property
    def _templates(self) -> list[tuple[int, Shape]]:
        """(link index, shape in the link frame) of every rectangle and joint disc."""
        w = self.width / 2
        return [item for i, a in enumerate(self.lengths)
                for item in ((i, box(0.0, -w, a, w)), (i, Disc(np.zeros(2), w)))]

    def placed_parts(self, Q: Any) -> list[tuple]:
        """Every link rectangle and joint disc at the N configurations Q, batched (see :func:`batch_distance`)."""
        P, phi = self._frames(Q)
        return [_placed(shape, P[:, i], phi[:, i]) for i, shape in self._templates]

    def bodies(self, q: Any) -> list[Shape]:
        """The link rectangles and joint discs occupying the workspace at q, B(q)."""
        P, phi = self._frames(as_vector(q, self.dof, "q")[None])
        return [transform_shape(shape, P[0, i, 0], P[0, i, 1], phi[0, i]) for i, shape in self._templates]

    def reach(self) -> np.ndarray:
        """R_i: an upper bound on the distance of any point of links i … n from joint i."""
        a = np.asarray(self.lengths)
        r_tip = np.hypot(a[-1], self.width / 2)
        return np.cumsum(a[::-1])[::-1] - a[-1] + r_tip

    def motion_bound(self, dq: Any) -> float:
        """Upper bound on the displacement of any point of the arm along a straight C-space step dq.

        Joint i turns every point beyond it at speed |θ̇_i|·(distance from joint i) ≤ |θ̇_i| R_i, and the
        base translation adds ‖Δ(x, y)‖.
        """
        dq = np.abs(as_vector(dq, self.dof, "dq"))
        base = 0.0 if self.fixed_base else float(np.hypot(dq[0], dq[1]))
        theta = dq if self.fixed_base else dq[2:]
        return base + float(theta @ self.reach())

    @cached_property
    def _part_reach(self) -> np.ndarray:
        """R[p, k] (P, n): a bound on the distance of any point of part p from joint k (0 for joints beyond
        the part's link), by the triangle inequality along the chain."""
        a = np.asarray(self.lengths)
        w = self.width / 2
        R = np.zeros((len(self._templates), len(a)))
        for p, (i, shape) in enumerate(self._templates):
            far = np.hypot(a[i], w) if isinstance(shape, Polygon) else w
            for k in range(i + 1):
                R[p, k] = a[k:i].sum() + far
        return R

    def part_motion_bounds(self, dq: Any) -> np.ndarray:
        """Bounds (P,) on the displacement of every point of each part along the straight step dq:
        Σ_{k ≤ link} R[p, k] |Δθ_k| (+ ‖Δ(x, y)‖ of a mobile base); linear in dq, as the certificate needs."""
        dq = np.abs(np.asarray(dq, dtype=float))
        base = 0.0 if self.fixed_base else float(np.hypot(dq[0], dq[1]))
        return base + self._part_reach @ (dq if self.fixed_base else dq[2:])


@dataclass(frozen=True)
class PlanarBody:
    """A rigid planar robot made of convex ``parts`` (in its own frame); q = [x, y, θ] ∈ R² × SO(2)."""

    parts: tuple

    def __post_init__(self) -> None:
        parts = tuple(self.parts)
        if not parts:
            raise ValueError("`parts` must give at least one Disc or Polygon")
        for k, s in enumerate(parts):
            if not isinstance(s, (Disc, Polygon)):
                raise ValueError(f"`parts[{k}]` must be a Disc or a Polygon, got {type(s).__name__}")
        object.__setattr__(self, "parts", parts)

    @property
    def dof(self) -> int:
        return 3

    @property
    def angular(self) -> np.ndarray:
        return np.array([False, False, True])

    def placed_parts(self, Q: Any) -> list[tuple]:
        """Every part at the N poses Q (N, 3), batched (see :func:`batch_distance`)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        if Q.shape[-1] != 3 or not np.all(np.isfinite(Q)):
            raise ValueError(f"`q` must be finite (N, 3) poses [x, y, θ], got shape {Q.shape}")
        return [_placed(s, Q[:, :2], Q[:, 2]) for s in self.parts]

    def bodies(self, q: Any) -> list[Shape]:
        """The parts occupying the workspace at the pose q = [x, y, θ], B(q)."""
        x, y, th = as_vector(q, 3, "q")
        return [transform_shape(s, x, y, th) for s in self.parts]

    @cached_property
    def part_radii(self) -> np.ndarray:
        """Largest distance (P,) of a point of each part from the body's reference point."""
        return np.array([float(np.linalg.norm(s.center)) + s.radius if isinstance(s, Disc)
                         else float(np.max(np.linalg.norm(s.vertices, axis=1))) for s in self.parts])

    def radius(self) -> float:
        """Largest distance of a point of the body from its reference point."""
        return float(self.part_radii.max())

    @property
    def is_translating_disc(self) -> bool:
        """True when every part is a disc centred on the reference point: the body is a disc whatever θ, and
        a straight edge sweeps a stadium (the exact segment test applies)."""
        return all(isinstance(s, Disc) and not np.any(s.center) for s in self.parts)

    def motion_bound(self, dq: Any) -> float:
        """Upper bound on the displacement of any point along the straight step dq = (Δx, Δy, Δθ):
        ‖Δp‖ + r_max |Δθ| (a point at distance r from the reference point turns by at most r |Δθ|)."""
        dq = as_vector(dq, 3, "dq")
        return float(np.hypot(dq[0], dq[1]) + self.radius() * abs(dq[2]))

    def part_motion_bounds(self, dq: Any) -> np.ndarray:
        """Bounds (P,) per part along the straight step dq: ‖Δp‖ + r_p |Δθ|."""
        dq = np.asarray(dq, dtype=float)
        return float(np.hypot(dq[0], dq[1])) + self.part_radii * abs(float(dq[2]))


@dataclass(frozen=True)
class PlanarCSpace:
    """The configuration space of a planar robot among a scene's obstacles, as the planners see it.

    Implements the sampling-planner protocol of :mod:`planners.sampling`: ``sample(rng)``,
    ``distance(a, b)`` (the d₃ of Problem 12.2 on the angular coordinates), ``interpolate(a, b, s)``
    (straight along the shortest wrapped difference), ``is_valid(q)`` and ``valid_many(Q)``, the edge
    certificate (``clearances(q)``, ``certify_edge(a, b)``: :func:`certify_by_bisection` with the robot's
    per-part motion bounds, or the exact segment test for a disc robot) and ``resolution``, the C-space
    step of the explicit sampled mode.
    """

    robot: PlanarArm | PlanarBody
    scene: Scene
    lower: np.ndarray
    upper: np.ndarray
    resolution: float = 0.01

    def __post_init__(self) -> None:
        if not isinstance(self.robot, (PlanarArm, PlanarBody)):
            raise ValueError(f"`robot` must be a PlanarArm or a PlanarBody, got {type(self.robot).__name__}")
        if not isinstance(self.scene, Scene):
            raise ValueError(f"`scene` must be a Scene, got {type(self.scene).__name__}")
        n = self.robot.dof
        lo, hi = as_vector(self.lower, n, "lower"), as_vector(self.upper, n, "upper")
        if np.any(hi < lo):
            raise ValueError(f"`upper` must be >= `lower`, got {lo} and {hi}")
        object.__setattr__(self, "lower", lo)
        object.__setattr__(self, "upper", hi)
        as_positive(self.resolution, "resolution")

    @property
    def dim(self) -> int:
        return self.robot.dof

    @property
    def angular(self) -> np.ndarray:
        return self.robot.angular

    def _configs(self, q: Any, name: str) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        if q.ndim == 0 or q.shape[-1] != self.dim:
            raise ValueError(f"`{name}` must have {self.dim} coordinates (last axis), got shape {q.shape}")
        return q

    def sample(self, rng: Any) -> np.ndarray:
        """A configuration drawn uniformly within [lower, upper]."""
        return as_generator(rng).uniform(self.lower, self.upper)

    def difference(self, a: Any, b: Any) -> np.ndarray:
        """b ⊖ a: the shortest difference, angles wrapped (:func:`configuration_difference`)."""
        return configuration_difference(self._configs(a, "a"), self._configs(b, "b"), self.angular)

    def distance(self, a: Any, b: Any) -> np.ndarray:
        """d₃ of Problem 12.2 on the angular coordinates, Euclidean on the others; broadcasts."""
        return torus_distance(self._configs(a, "a"), self._configs(b, "b"), self.angular)

    def interpolate(self, a: Any, b: Any, s: Any) -> np.ndarray:
        """a + s (b ⊖ a), angles wrapped into (−π, π]; ``s`` scalar → (dim,), ``s`` (k,) → (k, dim)."""
        a = np.asarray(a, dtype=float)
        s = np.asarray(s, dtype=float)
        q = a + s[..., None] * self.difference(a, b)
        return np.where(self.angular, wrap_angle(q), q)

    def in_bounds(self, Q: Any) -> np.ndarray:
        """True for the rows of Q whose non-angular coordinates lie within [lower, upper]."""
        Q = np.atleast_2d(Q)
        lin = ~self.angular
        return np.all((Q[:, lin] >= self.lower[lin] - 1e-12) & (Q[:, lin] <= self.upper[lin] + 1e-12), axis=1)

    def clearance(self, Q: Any) -> np.ndarray:
        """Distances (N,) of the robot from the obstacles at the configurations Q (N, dim)."""
        return self.scene.clearance_many(self.robot, self._configs(Q, "Q"))

    def valid_many(self, Q: Any) -> np.ndarray:
        """Collision-free and within the ranges, for each row of Q (N, dim)."""
        Q = np.atleast_2d(self._configs(Q, "Q"))
        return self.in_bounds(Q) & (self.clearance(Q) > 0.0)

    def is_valid(self, q: Any) -> bool:
        """Collision-free and within the ranges."""
        return bool(self.valid_many(q)[0])

    # -- the edge certificate -------------------------------------------------------------------

    def clearances(self, q: Any, parts: Sequence[int] | None = None) -> np.ndarray:
        """The certificate's clearances at q: distance (P,) of each robot part from the nearest obstacle
        (or of the ``parts`` listed); −∞ for every part when q lies outside [lower, upper]."""
        q = self._configs(q, "q")
        c = self.scene.part_clearances(self.robot, q[None], parts)[0]
        return c if self.in_bounds(q[None])[0] else np.full(c.shape, -np.inf)

    def edge_rates(self, a: Any, b: Any) -> np.ndarray:
        """Per-part bounds (P,) on how far any point of the part moves along the straight edge a → b (the
        bound over a fraction s of the edge is s times it)."""
        return self.robot.part_motion_bounds(self.difference(a, b))

    def certify_edge(self, a: Any, b: Any, ca: np.ndarray | None = None, cb: np.ndarray | None = None,
                     max_queries: int = EDGE_QUERY_BUDGET) -> "EdgeCertificate":
        """Certificate that the straight (wrapped) edge a → b is collision-free (:class:`EdgeCertificate`).

        A disc robot that only translates (:attr:`PlanarBody.is_translating_disc`) gets the exact
        segment–shape test: free iff the segment of its centre keeps more than its radius from every obstacle.
        Otherwise adaptive bisection (:func:`certify_by_bisection`) with the per-part motion bounds.
        ``ca``, ``cb`` are the clearances at the ends when already known (a planner caches its vertices').
        """
        a, b = self._configs(a, "a"), self._configs(b, "b")
        robot = self.robot
        if isinstance(robot, PlanarBody) and robot.is_translating_disc:
            ends_in = bool(np.all(self.in_bounds(np.stack([a, b]))))
            r = float(robot.part_radii.max())
            d = min((segment_shape_distance(a[:2], b[:2], o) for o in self.scene.obstacles), default=np.inf)
            c = d - r if ends_in else -np.inf
            return EdgeCertificate(c > 0, c, 1, "" if c > 0 else "the disc's segment touches an obstacle")
        if ca is None:
            ca = self.clearances(a)
        if cb is None:
            cb = self.clearances(b)
        return certify_by_bisection(lambda s, idx: self.clearances(self.interpolate(a, b, s), idx),
                                    self.edge_rates(a, b), ca, cb, max_queries=max_queries)


# --------------------------------------------------------------------------------------------
# The free C-space on a grid (Problem 12.4)
# --------------------------------------------------------------------------------------------

MAX_GRID_NODES = 20_000_000   # free_grid refuses larger grids (~ 0.5 GB of work arrays for a 3-D C-space)


def free_grid(space: "PlanarCSpace", axes: Sequence[np.ndarray], max_nodes: int = MAX_GRID_NODES,
              chunk: int = 100_000) -> np.ndarray:
    """Boolean array: is the configuration at each node of the grid ``axes`` (one 1-D array of values per
    coordinate, "ij" indexing) free? Checked with ``space.valid_many`` in chunks of ``chunk`` nodes; a grid of
    more than ``max_nodes`` nodes is refused (ValueError) before anything is allocated."""
    if len(axes) != space.dim:
        raise ValueError(f"`axes` must give {space.dim} coordinate arrays, got {len(axes)}")
    axes = [as_vector(a, None, f"axes[{k}]") for k, a in enumerate(axes)]
    shape = tuple(len(a) for a in axes)
    nodes = math.prod(shape)
    if nodes > max_nodes:
        raise ValueError(f"`axes` give a grid of {' x '.join(map(str, shape))} = {nodes:.3g} nodes, more than "
                         f"`max_nodes` = {max_nodes:.3g} (about {nodes * (space.dim + 1) * 8 / 2**30:.3g} GiB of "
                         "configurations): use coarser axes")
    out = np.empty(nodes, dtype=bool)
    for start in range(0, nodes, chunk):
        idx = np.unravel_index(np.arange(start, min(start + chunk, nodes)), shape)
        out[start:start + chunk] = space.valid_many(np.stack([a[i] for a, i in zip(axes, idx)], axis=1))
    return out.reshape(shape)


def connected_components(free: np.ndarray, periodic: Sequence[bool] | None = None) -> tuple[np.ndarray, int]:
    """Label the connected components of a boolean grid (side-adjacency), with wrap-around on the
    ``periodic`` axes (the torus of an arm's angles). Returns (labels, count); labels are 0 on obstacles.

    scipy.ndimage.label labels the grid; labels touching across a periodic seam are then merged.
    """
    free = np.asarray(free, dtype=bool)
    periodic = [True] * free.ndim if periodic is None else list(periodic)
    labels, n = ndimage.label(free)
    parent = list(range(n + 1))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for ax, wrap in enumerate(periodic):
        if not wrap:
            continue
        first = np.take(labels, 0, axis=ax)
        last = np.take(labels, -1, axis=ax)
        for a, b in zip(first.ravel(), last.ravel()):
            if a and b:
                parent[find(a)] = find(b)
    roots = {find(i) for i in range(1, n + 1)}
    remap = np.zeros(n + 1, dtype=int)
    for k, r in enumerate(sorted(roots), start=1):
        for i in range(1, n + 1):
            if find(i) == r:
                remap[i] = k
    return remap[labels], len(roots)


# --------------------------------------------------------------------------------------------
# Certifying a motion between samples
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class EdgeCertificate:
    """The answer of an edge certificate: ``free`` (certified collision-free), the smallest clearance met
    (at the ends and at the bisection points evaluated) and the number of distance ``queries`` spent
    (configurations evaluated besides the ends); ``message`` says why an edge is refused."""

    free: bool
    min_clearance: float
    queries: int
    message: str = ""

    def __bool__(self) -> bool:
        return self.free


def certify_by_bisection(clearances: Callable[[float, np.ndarray], np.ndarray], rates: Any, c0: Any, c1: Any,
                         max_queries: int = EDGE_QUERY_BUDGET, min_bound: float = 1e-9) -> EdgeCertificate:
    """Adaptive bisection certificate of a motion q(s), s ∈ [0, 1] (Schwarzer, Saha & Latombe 2004).

    ``clearances(s, idx)`` gives the distances (len(idx),) of the pairs ``idx`` (robot part–obstacle, or
    the self-collision pairs) at q(s); ``rates`` (P,) bound how far the two members of each pair can move
    relative to each other over the whole motion, and over [s_a, s_b] by rates·(s_b − s_a) (true for a
    straight C-space edge and for a constant-input arc); ``c0``, ``c1`` the clearances (P,) at the ends.
    A pair is certified on [s_a, s_b] when c(s_a) + c(s_b) > rates·(s_b − s_a): a point that closes the
    gap at s has moved at least c(s_a) from s_a and c(s_b) from s_b. Uncertified pairs are evaluated at
    a split point — the middle of the widest uncovered stretch [c(s_a)/M, 1 − c(s_b)/M] of the worst pair
    (the midpoint when the ends are alike) — and both parts recurse; a contact (clearance ≤ 0) refuses the edge, and so does an
    interval whose bound is below ``min_bound`` still uncertified (the motion grazes an obstacle) or a
    spent ``max_queries``. Refusing is always safe: only ``free=True`` is a promise.
    """
    rates = np.asarray(rates, dtype=float)
    c0, c1 = np.asarray(c0, dtype=float), np.asarray(c1, dtype=float)
    c_min = float(min(c0.min(initial=np.inf), c1.min(initial=np.inf)))
    if np.isnan(c0).any() or np.isnan(c1).any():
        return EdgeCertificate(False, np.nan, 0, "a clearance at an end of the edge is NaN")
    if not c_min > 0:
        return EdgeCertificate(False, c_min, 0, "an end of the edge is in collision or out of bounds")
    if not np.all(np.isfinite(rates)):
        return EdgeCertificate(False, c_min, 0, "the motion bound is not finite")
    queries = 0
    stack = [(0.0, 1.0, np.arange(rates.size), c0, c1)]
    while stack:
        s0, s1, idx, ca, cb = stack.pop()
        M = rates[idx] * (s1 - s0)
        bad = ~(ca + cb > M)                   # NaN (a clearance or a rate) is never certified
        if not bad.any():
            continue
        idx, ca, cb, M = idx[bad], ca[bad], cb[bad], M[bad]
        if not M.max() > min_bound:
            return EdgeCertificate(False, c_min, queries, f"grazes an obstacle near s = {s0:.6g} (clearance → 0)")
        if queries >= max_queries:
            return EdgeCertificate(False, c_min, queries, f"certificate budget of {max_queries} queries spent")
        # split where the worst pair's ends leave the widest uncovered gap [c_a/M, 1 − c_b/M], at its middle
        lo, hi = ca / M, 1.0 - cb / M
        w = int(np.argmax(hi - lo))
        sm = s0 + (s1 - s0) * min(max(0.5 * (lo[w] + hi[w]), 0.05), 0.95)
        cm = np.asarray(clearances(sm, idx), dtype=float)
        queries += 1
        if np.isnan(cm).any():
            return EdgeCertificate(False, np.nan, queries, f"a clearance at s = {sm:.6g} is NaN")
        c_min = min(c_min, float(cm.min()))
        if not cm.min() > 0:
            return EdgeCertificate(False, c_min, queries, f"collision at s = {sm:.6g}")
        stack.append((sm, s1, idx, cm, cb))
        stack.append((s0, sm, idx, ca, cm))
    return EdgeCertificate(True, c_min, queries)


def densify(space: PlanarCSpace, path: Any, step: float) -> np.ndarray:
    """Configurations along the straight (wrapped) C-space segments of ``path``, at most ``step`` apart."""
    P = np.asarray(path, dtype=float)
    out = [P[:1]]
    for a, b in zip(P[:-1], P[1:]):
        n = max(int(np.ceil(float(space.distance(a, b)) / step)), 1)
        out.append(space.interpolate(a, b, np.linspace(0.0, 1.0, n + 1)[1:]))
    return np.vstack(out)


def certify_motion(clearances: Any, motion_bounds: Any) -> tuple[bool, float]:
    """Certificate that a continuous motion sampled at N configurations stays collision-free.

    ``clearances`` (N,) are the distances of the robot from the obstacles at the samples and
    ``motion_bounds`` (N − 1,) bound how far any robot point moves between consecutive samples (M_k).
    At a fraction s of step k a point is within s·M_k of its place at sample k and (1 − s)·M_k of its place
    at sample k + 1, so it cannot touch an obstacle when c_k + c_{k+1} > M_k. Returns (certified, the
    smallest margin min_k (c_k + c_{k+1} − M_k)).
    """
    c = np.asarray(clearances, dtype=float)
    M = np.asarray(motion_bounds, dtype=float)
    if M.shape != (c.size - 1,):
        raise ValueError(f"`motion_bounds` must have shape ({c.size - 1},), got {M.shape}")
    margin = c[:-1] + c[1:] - M
    worst = float(margin.min()) if margin.size else float(c.min())
    return bool(np.all(c > 0) and worst > 0), worst


def segment_shape_distance(p: Any, q: Any, shape: Shape) -> float:
    """Distance between the segment p–q and a convex shape (0 when they touch or overlap)."""
    p, q = as_vector(p, 2, "p"), as_vector(q, 2, "q")
    if isinstance(shape, Disc):
        return max(float(point_segment_distance(shape.center, p, q)) - shape.radius, 0.0)
    if segment_intersects_shape(p, q, shape, tol=0.0) or shape.contains(p) or shape.contains(q):
        return 0.0
    d_ends = float(min(point_shape_distance(shape, p), point_shape_distance(shape, q)))
    return min(d_ends, float(point_segment_distance(shape.vertices, p, q).min()))


def certify_straight_path(space: PlanarCSpace, path: Any, step: float = 0.01,
                          max_depth: int = 12) -> tuple[bool, float, int]:
    """Certify that the robot moving along the straight (wrapped) C-space segments of ``path`` never
    touches an obstacle, independently of the planner's own sampled check.

    The path is re-sampled every ``step``; clearances are computed shape by shape (``Scene.clearance``)
    and the robot's ``motion_bound`` bounds the motion between samples (:func:`certify_motion`).
    Intervals where the certificate is inconclusive are bisected, up to ``max_depth`` times.
    Returns (certified, smallest clearance met, number of configurations evaluated).
    """
    if not isinstance(space, PlanarCSpace):
        raise ValueError(f"`space` must be a PlanarCSpace (shape-by-shape geometry), got {type(space).__name__}; "
                         "certify any space's path with planners.sampling.certify_path")
    as_positive(step, "step")

    def clear(q: np.ndarray) -> float:
        return space.scene.clearance(space.robot.bodies(q))

    Q = densify(space, path, step)
    stack = [(a, b, clear(a), clear(b), 0) for a, b in zip(Q[:-1], Q[1:])]
    c_min, evaluated = min(s[2] for s in stack), len(Q)
    while stack:
        a, b, ca, cb, depth = stack.pop()
        c_min = min(c_min, ca, cb)
        if ca <= 0 or cb <= 0:
            return False, 0.0, evaluated
        if ca + cb > space.robot.motion_bound(space.difference(a, b)):
            continue
        if depth >= max_depth:
            return False, c_min, evaluated
        m = space.interpolate(a, b, 0.5)
        cm = clear(m)
        evaluated += 1
        stack += [(a, m, ca, cm, depth + 1), (m, b, cm, cb, depth + 1)]
    return True, c_min, evaluated
