"""Distances to obstacles: the one home of the geometry that collision avoidance is built on.

Everything that measures how far a robot (or a point of its path) is from an obstacle lives here,
the seed of the configuration space of Ch. 12: the closest point of a polyline (a planar arm's
links, a workspace contour), the distance of a planar arm from a circular obstacle and its gradient
with respect to q (Problems 3.9, 3.21), and the distance of points from a box standing on the floor
(the obstacle of Problems 6.1–6.2).

Why in ``planners/`` and not in ``rigid_body/``: distances are only used to plan motions (the
redundancy resolution of 3.21 maximises one, the path of 6.2 keeps one positive), and the geometry
and its users belong together; ``rigid_body`` needs none of it, so nothing below ``planners``
imports this module (the arm is read through :mod:`rigid_body.kinematics`' frame placements).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 3.5.1 (distance from an obstacle as an objective of redundancy resolution), Sect. 12.1 (configuration
space, distances); solution manual, Problem 3.9 ((S3.4)–(S3.8)).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from rigid_body.validation import as_positive, as_vector

__all__ = [
    "closest_points_on_polyline",
    "polyline_distance",
    "ObstacleDistance",
    "segment_chain_distance",
    "planar_arm_obstacle_distance",
    "planar_arm_obstacle_distance_gradient",
    "distance_to_box",
]


def _as_polyline(polyline: Any, name: str) -> np.ndarray:
    P = np.asarray(polyline, dtype=float)
    if P.ndim != 2 or P.shape[1] != 2 or P.shape[0] < 2 or not np.all(np.isfinite(P)):
        raise ValueError(f"`{name}` must be a finite (k >= 2, 2) array of segment end points, got {P.shape}")
    return P


def closest_points_on_polyline(points: Any, polyline: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each planar point (m, 2), its closest point on every segment of ``polyline`` (k, 2).

    Segment i runs from x_i to x_{i+1}; the closest point of the line is at
    s* = (p − x_i)·(x_{i+1} − x_i) / a_i² (S3.7), clamped to the segment, s = max{0, min{1, s*}}
    (S3.8), at x_i + s (x_{i+1} − x_i) (S3.5)–(S3.6); a zero-length segment gives s = 0.
    Returns ``closest`` (m, k−1, 2), ``s`` (m, k−1) and the distances ``d`` (m, k−1).

    >>> closest, s, d = closest_points_on_polyline([[0.5, 1.0], [-1.0, 0.0]], [[0, 0], [1, 0]])
    >>> s.ravel().tolist(), d.ravel().tolist()
    ([0.5, 0.0], [1.0, 1.0])
    """
    P = _as_polyline(polyline, "polyline")
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"`points` must be an (m, 2) array, got shape {p.shape}")
    start, delta = P[:-1], np.diff(P, axis=0)
    a2 = np.einsum("kj,kj->k", delta, delta)
    with np.errstate(invalid="ignore", divide="ignore"):
        s_star = np.einsum("mkj,kj->mk", p[:, None, :] - start[None], delta) / a2     # (S3.7)
    s = np.clip(np.where(a2 > 0, s_star, 0.0), 0.0, 1.0)                            # (S3.8)
    closest = start[None] + s[..., None] * delta[None]                              # (S3.5), (S3.6)
    return closest, s, np.linalg.norm(p[:, None, :] - closest, axis=2)


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
    o = as_vector(center, 2, "center")
    radius = as_positive(radius, "radius", allow_zero=True)
    closest, s, d = (v[0] for v in closest_points_on_polyline(o[None], P))
    i = int(np.argmin(d))
    return ObstacleDistance(float(d[i] - radius), i, float(s[i]), closest[i].copy())   # (S3.4)


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
