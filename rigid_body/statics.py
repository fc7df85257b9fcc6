"""Statics: kineto-statics duality and the distance of a planar arm from an obstacle.

Conventions: a wrench ``γ = [f; μ]`` (6,) is a force f and a moment μ about the frame origin, both
in the frame's coordinates; the book's geometric Jacobian maps it to joint torques τ = J^T γ.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 3.8 (Eq. (3.111) τ = J^T γ_e; the wrench transformation (3.116)–(3.117) is
:func:`rigid_body.sensors.wrench_transform`), Problem 3.9 ((S3.4)–(S3.8)).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rigid_body.validation import as_matrix, as_vector

__all__ = [
    "joint_torques",
    "ObstacleDistance",
    "segment_chain_distance",
    "planar_arm_obstacle_distance",
    "planar_arm_obstacle_distance_gradient",
]


def joint_torques(J: Any, gamma: Any) -> np.ndarray:
    """τ = J^T(q) γ_e: joint torques balancing the end-effector wrench γ_e at equilibrium, Eq. (3.111).

    ``J`` is (r, n) (e.g. the (6, n) geometric Jacobian), ``gamma`` (r,).
    """
    J = np.asarray(J, dtype=float)
    if J.ndim != 2:
        raise ValueError(f"`J` must be a 2-D Jacobian, got shape {J.shape}")
    return J.T @ as_vector(gamma, J.shape[0], "gamma")


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

    For each segment i from x_{i-1} to x_i: s_i* = −(x_{i-1} − o)·(x_i − x_{i-1}) / a_i² (S3.7),
    s_i = max{0, min{1, s_i*}} (S3.8), p_i = x_{i-1} + s_i (x_i − x_{i-1}) (S3.5)–(S3.6),
    d_i = ‖p_i − o‖; then d = min_i d_i − R (S3.4).
    """
    P = np.asarray(points, dtype=float)
    if P.ndim != 2 or P.shape[1] != 2 or P.shape[0] < 2 or not np.all(np.isfinite(P)):
        raise ValueError(f"`points` must be a finite (k >= 2, 2) array of segment end points, got {P.shape}")
    o = as_vector(center, 2, "center")
    if not (np.isfinite(radius) and radius >= 0):
        raise ValueError(f"`radius` must be finite and >= 0, got {radius}")
    start, delta = P[:-1], np.diff(P, axis=0)
    a2 = np.einsum("ij,ij->i", delta, delta)
    with np.errstate(invalid="ignore", divide="ignore"):
        s_star = -np.einsum("ij,ij->i", start - o, delta) / a2          # (S3.7)
    s = np.clip(np.where(a2 > 0, s_star, 0.0), 0.0, 1.0)               # (S3.8)
    closest = start + s[:, None] * delta                                # (S3.5), (S3.6)
    d = np.linalg.norm(closest - o, axis=1)
    i = int(np.argmin(d))
    return ObstacleDistance(float(d[i] - radius), i, float(s[i]), closest[i].copy())   # (S3.4)


def _link_points(robot: Any, q: np.ndarray, frames: list[str] | None) -> tuple[np.ndarray, list]:
    import pinocchio as pin

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
    import pinocchio as pin

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
