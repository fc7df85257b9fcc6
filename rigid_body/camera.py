"""The pinhole camera: intrinsic parameters, perspective projection, a camera carried by a robot.

The camera frame has z along the optical axis. A point ``p̃^b`` given in the base frame is expressed in
the camera frame by ``p̃^c = (T_c^b)^{-1} p̃^b`` (5.35), projected to the normalised image plane
``x_I = p_x/p_z``, ``y_I = p_y/p_z`` and to pixels by ``λ [X_I, Y_I, 1]^T = Ω Π p̃^c`` (5.40), with the
intrinsic matrix ``Ω = [[f α_x, 0, X_0], [0, f α_y, Y_0], [0, 0, 1]]`` (5.41) and ``λ = p_z``.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 5.2.4 (Eqs. (5.35)–(5.41)), Problem 5.7; interaction matrices (ch. 10) build on this module.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rigid_body.rotations import as_homogeneous, homogeneous_inverse
from rigid_body.validation import as_vector


@dataclass(frozen=True)
class PinholeCamera:
    """Intrinsic parameters in pixels: ``f_alpha_x`` = f α_x, ``f_alpha_y`` = f α_y, principal point ``X0``, ``Y0``."""

    f_alpha_x: float
    f_alpha_y: float
    X0: float = 0.0
    Y0: float = 0.0

    def __post_init__(self) -> None:
        for name in ("f_alpha_x", "f_alpha_y"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"`{name}` must be a positive number of pixels, got {value}")
        for name in ("X0", "Y0"):
            if not np.isfinite(getattr(self, name)):
                raise ValueError(f"`{name}` (principal point) must be finite, got {getattr(self, name)}")

    @property
    def intrinsic_matrix(self) -> np.ndarray:
        """Ω (3×3), Eq. (5.41)."""
        return np.array([[self.f_alpha_x, 0.0, self.X0], [0.0, self.f_alpha_y, self.Y0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class Projection:
    """Result of a perspective projection: the point in the camera frame ``p_c``, normalised image
    coordinates ``x_I``, ``y_I``, the scale ``lam`` (λ = depth) and the pixel coordinates ``X_I``, ``Y_I``."""

    p_c: np.ndarray
    x_I: float
    y_I: float
    lam: float
    X_I: float
    Y_I: float


def project(camera: PinholeCamera, p_b: Any, T_bc: Any | None = None) -> Projection:
    """Project a point given in the base frame through a camera whose pose in the base frame is ``T_bc``.

    ``T_bc`` (4×4) = T_c^b; None means the point is already in the camera frame. A point at or behind
    the camera plane (p_z ≤ 0) cannot be imaged: ValueError.
    """
    p = as_vector(p_b, 3, "p_b")
    if T_bc is not None:
        p = (homogeneous_inverse(as_homogeneous(T_bc, "T_bc")) @ np.append(p, 1.0))[:3]   # (5.35)
    if p[2] <= 0:
        raise ValueError(f"point is behind the camera (depth p_z = {p[2]:.4g} m ≤ 0); it cannot be imaged")
    Pi = np.hstack([np.eye(3), np.zeros((3, 1))])
    h = camera.intrinsic_matrix @ Pi @ np.append(p, 1.0)                                      # (5.40)
    lam = float(h[2])
    return Projection(p_c=p, x_I=float(p[0] / p[2]), y_I=float(p[1] / p[2]), lam=lam,
                      X_I=float(h[0] / lam), Y_I=float(h[1] / lam))


def project_from_robot(camera: PinholeCamera, robot: Any, q: Any, p_b: Any,
                       frame: str | int | None = None) -> Projection:
    """Project ``p_b`` (base frame) through a camera mounted on ``frame`` (default: end effector) at ``q``."""
    from rigid_body.kinematics import direct_kinematics

    return project(camera, p_b, direct_kinematics(robot, q, frame))
