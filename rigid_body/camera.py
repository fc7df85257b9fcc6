"""The pinhole camera: intrinsic parameters, perspective projection, a camera carried by a robot.

The camera frame has z along the optical axis. A point ``p̃^b`` given in the base frame is expressed in
the camera frame by ``p̃^c = (T_c^b)^{-1} p̃^b`` (5.35), projected to the normalised image plane
``x_I = p_x/p_z``, ``y_I = p_y/p_z`` and to pixels by ``λ [X_I, Y_I, 1]^T = Ω Π p̃^c`` (5.40), with the
intrinsic matrix ``Ω = [[f α_x, 0, X_0], [0, f α_y, Y_0], [0, 0, 1]]`` (5.41) and ``λ = p_z``.

Chapter 10 adds what a visual servo measures and how it moves: normalised ↔ pixel coordinates, the
features of points, of a line segment (10.28) and of a line (ρ, θ), their interaction matrices
(10.26 and the chain rule), image moments and the principal-axes orientation (10.2), and the view of a
target through any frame of a robot, with the points behind the camera or outside the field of view
reported (never silently projected).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 5.2.4 (Eqs. (5.35)–(5.41)), Problem 5.7; Sects. 10.2–10.3 (Eqs. (10.2), (10.26), (10.28));
F. Chaumette, S. Hutchinson, "Visual servo control, Part I", IEEE RAM 2006 (the line's matrix).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rigid_body.rotations import as_homogeneous
from rigid_body.validation import as_points, as_vector


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

    def to_pixels(self, xy: Any) -> np.ndarray:
        """Pixel coordinates (n, 2) of normalised image coordinates ``xy`` (n, 2), Eq. (5.40)."""
        xy = as_points(xy, 2, "xy")
        return np.column_stack([self.f_alpha_x * xy[:, 0] + self.X0, self.f_alpha_y * xy[:, 1] + self.Y0])

    def to_normalised(self, XY: Any) -> np.ndarray:
        """Normalised image coordinates (n, 2) of pixel coordinates ``XY`` (n, 2): the inverse of :meth:`to_pixels`."""
        XY = as_points(XY, 2, "XY")
        return np.column_stack([(XY[:, 0] - self.X0) / self.f_alpha_x, (XY[:, 1] - self.Y0) / self.f_alpha_y])

    def field_of_view(self, width: float, height: float) -> "FieldOfView":
        """The normalised window seen by an image of ``width`` × ``height`` pixels (pixels 0 … width, 0 … height)."""
        lo = self.to_normalised([[0.0, 0.0]])[0]
        hi = self.to_normalised([[float(width), float(height)]])[0]
        return FieldOfView(lo[0], hi[0], lo[1], hi[1])


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
        T = as_homogeneous(T_bc, "T_bc")
        p = to_camera_frame(T[:3, :3], T[:3, 3], p[None])[0]                                     # (5.35)
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


# --------------------------------------------------------------------------------------------
# What a camera sees of a target: projection with visibility reported
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class FieldOfView:
    """The window of the image plane that the sensor covers, in normalised coordinates (x = p_x/p_z)."""

    x_min: float
    x_max: float
    y_min: float
    y_max: float

    def __post_init__(self) -> None:
        if not (self.x_min < self.x_max and self.y_min < self.y_max):
            raise ValueError(f"field of view must have x_min < x_max and y_min < y_max, got {self}")

    def contains(self, xy: np.ndarray, margin: float = 0.0) -> np.ndarray:
        """(n,) True where the normalised point (n, 2) lies inside the window shrunk by ``margin``."""
        return self.contains_xy(xy[:, 0], xy[:, 1], margin)

    def contains_xy(self, x: Any, y: Any, margin: float = 0.0, both: Any = np.logical_and) -> Any:
        """:meth:`contains` of the coordinates x (n,), y (n,); ``both`` is the elementwise "and" (numpy's, or
        CasADi's ``logic_and`` for the compiled loop's masked expressions). NaN (a point not imaged) is outside."""
        return both(both(x >= self.x_min + margin, x <= self.x_max - margin),
                    both(y >= self.y_min + margin, y <= self.y_max - margin))


@dataclass(frozen=True)
class TargetView:
    """Points of a target seen by a camera: ``p_c`` (n, 3) in the camera frame, depths ``z`` (n,),
    normalised coordinates ``xy`` (n, 2) — NaN for a point at or behind the camera plane —, ``in_front``
    (n,) and ``in_view`` (n,) (in front and inside the field of view; = in_front without one)."""

    p_c: np.ndarray
    z: np.ndarray
    xy: np.ndarray
    in_front: np.ndarray
    in_view: np.ndarray

    @property
    def all_visible(self) -> bool:
        return bool(np.all(self.in_view))

    def require_visible(self) -> "TargetView":
        """This view, or ValueError naming the points behind the camera / outside the field of view."""
        if not self.all_visible:
            behind = np.flatnonzero(~self.in_front).tolist()
            outside = np.flatnonzero(self.in_front & ~self.in_view).tolist()
            raise ValueError(f"target not fully visible: points behind the camera {behind}, "
                             f"outside the field of view {outside}")
        return self


def to_camera_frame(R_c: np.ndarray, o_c: np.ndarray, points_b: np.ndarray) -> np.ndarray:
    """p^c = R_cᵀ (p^b − o_c) of points (n, 3) given in the base frame, for a camera at (R_c, o_c) = T_c^b:
    the one (5.35) of rmpc (unvalidated; the compiled loop's symbolic form is
    :meth:`controllers.compiled.Symbolic.to_camera`)."""
    return (points_b - o_c).dot(R_c)                # .dot: the same product, ~1 µs less than @ on (n, 3)


def perspective(X: np.ndarray, Y: np.ndarray, Z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, y, in_front) of (5.40) for camera-frame coordinates (n,) each: x = X/Z, y = Y/Z where Z > 0, NaN for
    a point at or behind the camera plane (never silently projected). Unvalidated."""
    in_front = Z > 0
    if all(in_front.tolist()):                      # (hot path: ndarray.all costs ~1 µs more on a few points)
        return X / Z, Y / Z, in_front
    x, y = np.full(Z.shape, np.nan), np.full(Z.shape, np.nan)
    x[in_front], y[in_front] = X[in_front] / Z[in_front], Y[in_front] / Z[in_front]
    return x, y, in_front


def view_points(p_c: Any, fov: FieldOfView | None = None) -> TargetView:
    """Perspective view (5.40) of points ``p_c`` (n, 3) already in the camera frame."""
    p = as_points(p_c, 3, "p_c")
    z = p[:, 2].copy()
    x, y, in_front = perspective(p[:, 0], p[:, 1], z)
    xy = np.column_stack((x, y))
    in_view = in_front.copy() if fov is None else in_front & fov.contains(xy)
    return TargetView(p_c=p, z=z, xy=xy, in_front=in_front, in_view=in_view)


def view_target(T_bc: Any, points_b: Any, fov: FieldOfView | None = None) -> TargetView:
    """View of target points ``points_b`` (n, 3), given in the base frame, from a camera at ``T_bc`` = T_c^b (5.35)."""
    T = as_homogeneous(T_bc, "T_bc")
    p = as_points(points_b, 3, "points_b")
    return view_points(to_camera_frame(T[:3, :3], T[:3, 3], p), fov)


def view_target_from_robot(robot: Any, q: Any, points_b: Any, frame: str | int | None = None,
                           fov: FieldOfView | None = None) -> TargetView:
    """View of ``points_b`` (base frame) from a camera on ``frame`` of ``robot`` (default: end effector) at ``q``."""
    from rigid_body.kinematics import direct_kinematics

    return view_target(direct_kinematics(robot, q, frame), points_b, fov)


# --------------------------------------------------------------------------------------------
# Interaction matrices: ṡ = L_s [v_c^c; ω_c^c] for a fixed object and a moving camera
# --------------------------------------------------------------------------------------------

def point_interaction_matrix(x: float, y: float, z: float) -> np.ndarray:
    """L_s (2×6) of an image point with normalised coordinates (x, y) at depth z > 0, Eq. (10.26).

    Columns: camera linear velocity v_c^c then angular velocity ω_c^c (camera frame).

    >>> point_interaction_matrix(0.0, 0.0, 0.5)[0]        # a point on the optical axis, 0.5 m away
    array([-2.,  0.,  0.,  0., -1.,  0.])
    """
    if not z > 0:
        raise ValueError(f"`z` (depth of the point) must be positive, got {z}")
    return np.array([[-1.0 / z, 0.0, x / z, x * y, -(1.0 + x * x), y],
                     [0.0, -1.0 / z, y / z, 1.0 + y * y, -x * y, -x]])


def points_interaction_matrix(xy: Any, z: Any) -> np.ndarray:
    """The (2n×6) stack of the point matrices (10.26) for points ``xy`` (n, 2) at depths ``z`` (n,)."""
    xy = as_points(xy, 2, "xy")
    z = as_vector(z, xy.shape[0], "z")
    if np.any(z <= 0):
        raise ValueError(f"`z` (depths of the points) must be positive, got {z}")
    L = np.empty((2 * xy.shape[0], 6))
    for i, ((x, y), zi) in enumerate(zip(xy, z)):
        L[2 * i:2 * i + 2] = point_interaction_matrix(x, y, zi)
    return L


@dataclass(frozen=True)
class SegmentFeatures:
    """Features of an image line segment, Eq. (10.28): midpoint (x_m, y_m), length L, orientation α."""

    x_m: float
    y_m: float
    L: float
    alpha: float

    def as_array(self) -> np.ndarray:
        return np.array([self.x_m, self.y_m, self.L, self.alpha])


def segment_features(xy1: Any, xy2: Any) -> SegmentFeatures:
    """s = [x_m, y_m, L, α] of the segment from image point ``xy1`` to ``xy2`` (normalised), Eq. (10.28).

    >>> segment_features([0.0, 0.0], [0.2, 0.0]).as_array()
    array([0.1, 0. , 0.2, 0. ])
    """
    p1, p2 = as_vector(xy1, 2, "xy1"), as_vector(xy2, 2, "xy2")
    d = p2 - p1
    L = float(np.hypot(d[0], d[1]))
    if L == 0:
        raise ValueError("the segment's end points coincide: its orientation α is undefined")
    m = 0.5 * (p1 + p2)
    return SegmentFeatures(float(m[0]), float(m[1]), L, float(np.arctan2(d[1], d[0])))


def segment_feature_jacobian(xy1: Any, xy2: Any) -> np.ndarray:
    """∂s/∂[x1, y1, x2, y2] (4×4) of the segment features (10.28)."""
    p1, p2 = as_vector(xy1, 2, "xy1"), as_vector(xy2, 2, "xy2")
    dx, dy = p2 - p1
    L2 = dx * dx + dy * dy
    if L2 == 0:
        raise ValueError("the segment's end points coincide: its orientation α is undefined")
    L = np.sqrt(L2)
    return np.array([[0.5, 0.0, 0.5, 0.0],
                     [0.0, 0.5, 0.0, 0.5],
                     [-dx / L, -dy / L, dx / L, dy / L],
                     [dy / L2, -dx / L2, -dy / L2, dx / L2]])


def segment_interaction_matrix(xy1: Any, xy2: Any, z1: float, z2: float) -> np.ndarray:
    """L_s (4×6) of the segment features (10.28): ∂s/∂(end points) times the two point matrices (10.26)."""
    p1, p2 = as_vector(xy1, 2, "xy1"), as_vector(xy2, 2, "xy2")
    return segment_feature_jacobian(p1, p2) @ np.vstack([point_interaction_matrix(p1[0], p1[1], z1),
                                                         point_interaction_matrix(p2[0], p2[1], z2)])


@dataclass(frozen=True)
class LineFeatures:
    """An image line x cos θ + y sin θ = ρ (normalised coordinates)."""

    rho: float
    theta: float

    def as_array(self) -> np.ndarray:
        return np.array([self.rho, self.theta])


def line_features(xy1: Any, xy2: Any) -> LineFeatures:
    """(ρ, θ) of the image line through two distinct image points; the normal [cos θ, sin θ] is the
    segment direction turned by +π/2."""
    p1, p2 = as_vector(xy1, 2, "xy1"), as_vector(xy2, 2, "xy2")
    d = p2 - p1
    if not np.any(d):
        raise ValueError("the two image points coincide: the line is undefined")
    theta = float(np.arctan2(d[0], -d[1]))
    return LineFeatures(float(p1[0] * np.cos(theta) + p1[1] * np.sin(theta)), theta)


def line_interaction_matrix(line: LineFeatures, p1_c: Any, p2_c: Any) -> np.ndarray:
    """L (2×6) of the image line (ρ, θ) of the 3-D line through ``p1_c``, ``p2_c`` (camera frame).

    With a plane a x + b y + c z + d = 0 (d ≠ 0) containing the 3-D line: λ_ρ = (a ρ cos θ + b ρ sin θ + c)/d,
    λ_θ = (a sin θ − b cos θ)/d, and rows
    L_ρ = [λ_ρ c, λ_ρ s, −λ_ρ ρ, (1+ρ²) s, −(1+ρ²) c, 0], L_θ = [λ_θ c, λ_θ s, −λ_θ ρ, −ρ c, −ρ s, −1].
    """
    P1, P2 = as_vector(p1_c, 3, "p1_c"), as_vector(p2_c, 3, "p2_c")
    direction, m = P2 - P1, np.cross(P1, P2)           # m: normal of the interpretation plane (through 0)
    if np.linalg.norm(m) < 1e-12 * max(1.0, np.linalg.norm(P1) * np.linalg.norm(P2)):
        raise ValueError("the 3-D line passes through the optical centre: its image is a point")
    n = np.cross(direction, m)                          # a plane containing the line, not through 0
    a, b, c = n
    d = -float(n @ P1)
    rho, th = line.rho, line.theta
    ct, st = np.cos(th), np.sin(th)
    lam_rho = (a * rho * ct + b * rho * st + c) / d
    lam_theta = (a * st - b * ct) / d
    return np.array([[lam_rho * ct, lam_rho * st, -lam_rho * rho, (1 + rho**2) * st, -(1 + rho**2) * ct, 0.0],
                     [lam_theta * ct, lam_theta * st, -lam_theta * rho, -rho * ct, -rho * st, -1.0]])


def point_velocity_in_camera(p_c: Any, v_c: Any, omega_c: Any) -> np.ndarray:
    """ṗ^c = −v_c^c − ω_c^c × p^c: how a fixed point moves in the frame of a camera moving with twist (v, ω)."""
    p = as_points(p_c, 3, "p_c")
    return -as_vector(v_c, 3, "v_c") - np.cross(as_vector(omega_c, 3, "omega_c"), p)


# --------------------------------------------------------------------------------------------
# Image moments of a region, Eq. (10.2)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class RegionMoments:
    """Area m_00, centroid (x̄, ȳ) and central moments μ_20, μ_02, μ_11 of a binary image region."""

    m00: float
    x_bar: float
    y_bar: float
    mu20: float
    mu02: float
    mu11: float

    @property
    def orientation(self) -> float:
        """α = ½ Atan2(2 μ_11, μ_20 − μ_02): the angle of the principal axis of the larger moment, Eq. (10.2)."""
        return 0.5 * float(np.arctan2(2.0 * self.mu11, self.mu20 - self.mu02))

    @property
    def principal_moments(self) -> tuple[float, float]:
        """(λ, λ') with λ ≥ λ', the eigenvalues of the inertia matrix [[μ20, μ11], [μ11, μ02]]."""
        root = np.sqrt(4.0 * self.mu11**2 + (self.mu02 - self.mu20) ** 2)
        return 0.5 * (self.mu20 + self.mu02 + root), 0.5 * (self.mu20 + self.mu02 - root)


def region_moments(mask: Any, x: Any, y: Any) -> RegionMoments:
    """Moments (10.1) of the region ``mask`` (rows × cols booleans) on pixel centres ``x`` (cols,), ``y`` (rows,)."""
    mask = np.asarray(mask, dtype=bool)
    x, y = as_vector(x, None, "x"), as_vector(y, None, "y")
    if mask.ndim != 2 or mask.shape != (y.size, x.size):
        raise ValueError(f"`mask` must have shape (len(y), len(x)) = {(y.size, x.size)}, got {mask.shape}")
    X, Y = np.meshgrid(x, y)
    m00 = float(mask.sum())
    if m00 == 0:
        raise ValueError("`mask` is empty: the region has no moments")
    xb, yb = float(X[mask].mean()), float(Y[mask].mean())
    dx, dy = X[mask] - xb, Y[mask] - yb
    return RegionMoments(m00, xb, yb, float(dx @ dx), float(dy @ dy), float(dx @ dy))
