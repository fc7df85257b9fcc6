"""Visual servoing (Chapter 10): a camera on the robot, pose estimation, PBVS, IBVS, 2½-D errors.

The blocks are the ones of the book's Simulink schemes, as small callables ``(t, measurement) -> output``
that :func:`controllers.simulation.simulate` runs at their own periods:

* :class:`EyeInHandCamera` — the sensor: from the arm's ``meas.q`` it computes the view of the target
  (:class:`CameraImage`, image points, visibility, noise) — features are named fields, never slices;
* :class:`PoseEstimator` — pose estimation by inversion of the image Jacobian, Eqs. (10.40)–(10.41), a
  discrete (Euler) estimator at its own period T: x̂_{k+1} = x̂_k + T Γ(ô) L_s⁻¹ K_s (s − ŝ(x̂_k));
* :class:`PBVSPDGravity` (Fig. 10.14) and :class:`PBVSResolvedVelocity` (Fig. 10.15), and
  :class:`PBVSPoseResolvedVelocity`, the general 6-DOF form (pose from a planar target's homography);
* :class:`IBVSPDGravity` (Fig. 10.16) and :class:`IBVSResolvedVelocity` (Fig. 10.17), with the depth
  of the interaction matrix known (measured), constant (the desired depth) or estimated;
* :func:`hybrid_error_jacobians` — J_p, J_o of the 2½-D scheme, Eq. (10.96), and :class:`HybridVisualServo`,
  the 2½-D law on them (rotation and depth ratio from the homography).

Poses of the 4-DOF (SCARA) case are x = [x, y, z, φ]: a position and a rotation φ about the common
vertical axis, which is the camera's optical axis z_c (Example 10.3). ``dofs`` selects the camera-twist
components a robot commands: (0, 1, 2, 5) = (v_x, v_y, v_z, ω_z) for the SCARA, all six for the Panda.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 10.3–10.8.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np
import pinocchio as pin

from controllers.laws import ControlLaw, Numeric, as_gain, diagonal_or_matrix, per_joint, rate_options
from controllers.simulation import Chain, LoggedController, ZeroOrderHold
from rigid_body.camera import FieldOfView, SegmentFeatures, TargetView, segment_features, view_points
from rigid_body.robots import Robot
from rigid_body.rotations import as_homogeneous, nearest_rotation
from rigid_body.task_space import RATE_CONDITION, resolved_rates
from rigid_body.validation import as_points, as_positive, as_scalar, as_vector
from rigid_body.vision import depth_ratio, homography_dlt, pose_from_homography

SCARA_DOFS = (0, 1, 2, 5)   # v_x, v_y, v_z, ω_z: the camera twist of Example 10.3
FEATURE_KINDS = ("points", "segment")
_SCARA_ROWS = np.array(SCARA_DOFS)


# --------------------------------------------------------------------------------------------
# 4-DOF poses [x, y, z, φ] (Example 10.3)
# --------------------------------------------------------------------------------------------

def planar_pose(x: Any) -> np.ndarray:
    """T (4×4) of the pose vector x = [x, y, z, φ]: position and rotation φ about z."""
    x = as_vector(x, 4, "x")
    c, s = np.cos(x[3]), np.sin(x[3])
    return np.array([[c, -s, 0.0, x[0]], [s, c, 0.0, x[1]], [0.0, 0.0, 1.0, x[2]], [0.0, 0.0, 0.0, 1.0]])


def planar_pose_vector(T: np.ndarray) -> np.ndarray:
    """[x, y, z, φ] of a pose whose rotation is about z (φ = Atan2(r_21, r_11))."""
    return np.array([T[0, 3], T[1, 3], T[2, 3], np.arctan2(T[1, 0], T[0, 0])])


def relative_pose_vector(T_bc: np.ndarray, T_bo: np.ndarray) -> np.ndarray:
    """x_{c,o} = [o_{c,o}^c, φ_{c,o}]: the pose of the object frame in the camera frame (4-DOF case).

    >>> relative_pose_vector(planar_pose([1, 1, 0.5, np.pi / 4]), planar_pose([1, 1, 1, np.pi / 4])).round(12)
    array([0. , 0. , 0.5, 0. ])
    """
    return planar_pose_vector(np.linalg.solve(T_bc, T_bo))


def gamma_matrix(o: Any, ops: Any = None) -> Any:
    """Γ(o_{c,o}^c) (4×4) with ẋ_{c,o} = Γ [v_c^c; ω_z] for a fixed object, Eq. (10.41), 4-DOF case:
    Γ = [[−I, s_3(o)], [0ᵀ, −1]], s_3(o) = S(o) e_z = [o_y, −o_x, 0]ᵀ (``ops``: the loop's primitives, default
    numeric)."""
    return (ops or Numeric).matrix([[-1.0, 0.0, 0.0, o[1]], [0.0, -1.0, 0.0, -o[0]], [0.0, 0.0, -1.0, 0.0],
                                    [0.0, 0.0, 0.0, -1.0]])


def camera_jacobian(robot: Robot, q: np.ndarray, frame: int) -> np.ndarray:
    """J_c (6×n): the camera twist in the camera frame, [v_c^c; ω_c^c] = J_c q̇ = [R_cᵀ J_P; R_cᵀ J_O] q̇
    (Pinocchio's LOCAL frame Jacobian)."""
    return pin.computeFrameJacobian(robot.model, robot.data, q, frame, pin.LOCAL)


TWIST_NAMES = ("v_x", "v_y", "v_z", "ω_x", "ω_y", "ω_z")


def _configurations(robot: Robot, count: int = 4) -> list[np.ndarray]:
    """The robot's neutral configuration and a few random ones within its limits (seeded): where a
    property of the robot "at some posture" is tested."""
    rng = np.random.default_rng(0)
    qs = [robot.random_configuration(rng) for _ in range(count - 1)]
    if robot.nq != robot.nv:                 # unit-complex coordinates (continuous, planar joints) back on the circle
        qs = [pin.normalize(robot.model, q) for q in qs]
    return [robot.configurations["neutral"]] + qs


def camera_dofs(robot: Robot, frame: str | int | None = None) -> tuple[int, ...]:
    """The camera-twist components [v_x, v_y, v_z, ω_x, ω_y, ω_z] (camera frame) along which the robot can move
    its camera: the rows of J_c (:func:`camera_jacobian`) that are not zero at every posture (sampled: the
    neutral and random configurations). The SCARA's are (0, 1, 2, 5) (:data:`SCARA_DOFS`), a 6-DOF arm's all six."""
    fid = robot.ee_frame if frame is None else robot.frame(frame)
    peak = np.zeros(6)
    for q in _configurations(robot):
        peak = np.maximum(peak, np.abs(camera_jacobian(robot, q, fid)).max(axis=1))
    return tuple(int(i) for i in np.flatnonzero(peak > 1e-9 * max(peak.max(), 1e-300)))


def _as_dofs(dofs: Any) -> tuple[int, ...]:
    """``dofs`` as distinct camera-twist components in 0..5; ValueError naming it."""
    try:
        d = tuple(int(i) for i in dofs)
        if not all(float(i) == j for i, j in zip(dofs, d)):
            raise ValueError
    except (TypeError, ValueError):
        raise ValueError(f"`dofs` must be camera-twist components in 0..5 {TWIST_NAMES}, got {dofs!r}") from None
    if not d or len(set(d)) != len(d) or min(d) < 0 or max(d) > 5:
        raise ValueError(f"`dofs` must be distinct camera-twist components in 0..5 {TWIST_NAMES}, got {dofs!r}")
    return d


# --------------------------------------------------------------------------------------------
# The target and its features
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True, slots=True)
class CameraImage:
    """What the camera gives at a sample: image points ``xy`` (n, 2) (normalised; NaN where not seen),
    ``visible`` (n,) and the points' depths ``z`` (n,), used only by laws told that the depth is known."""

    xy: np.ndarray
    visible: np.ndarray
    z: np.ndarray

    @property
    def segment(self) -> SegmentFeatures | None:
        """Features (10.28) of the segment P_1P_2 (None when an end point is not seen)."""
        if not (self.visible[0] and self.visible[1]):
            return None
        return segment_features(self.xy[0], self.xy[1])


def _points_interaction(ops: Any, x: Any, y: Any, z: Any) -> Any:
    """(2n×6) stack of (10.26) at image points (x_i, y_i) with depths z_i, for either loop (``ops``; unvalidated:
    the checked version is :func:`rigid_body.camera.point_interaction_matrix`)."""
    rows = []
    for i in range(x.shape[0]):
        xi, yi, iz = x[i], y[i], 1.0 / z[i]
        rows.append([-iz, 0.0, xi * iz, xi * yi, -(1.0 + xi * xi), yi])
        rows.append([0.0, -iz, yi * iz, 1.0 + yi * yi, -xi * yi, -xi])
    return ops.matrix(rows)


def _segment(ops: Any, x1: Any, y1: Any, x2: Any, y2: Any) -> Any:
    """[x_m, y_m, L, α] of (10.28), for either loop (coincident end points: α undefined, a ValueError — NaN in
    the compiled loop)."""
    dx, dy = x2 - x1, y2 - y1
    alpha = ops.unless(ops.logic_and(dx == 0.0, dy == 0.0), lambda: ops.atan2(dy, dx),
                       lambda: "the segment's end points coincide in the image: α is undefined")
    return ops.vector(0.5 * (x1 + x2), 0.5 * (y1 + y2), ops.hypot(dx, dy), alpha)


def _segment_jacobian(ops: Any, x1: Any, y1: Any, x2: Any, y2: Any) -> Any:
    """∂s/∂[x1, y1, x2, y2] of (10.28), for either loop (the checked version is in rigid_body.camera)."""
    dx, dy = x2 - x1, y2 - y1
    L2 = dx * dx + dy * dy
    L = ops.sqrt(L2)
    return ops.matrix([[0.5, 0.0, 0.5, 0.0], [0.0, 0.5, 0.0, 0.5], [-dx / L, -dy / L, dx / L, dy / L],
                       [dy / L2, -dx / L2, -dy / L2, dx / L2]])


def _segment_interaction(ops: Any, x1: Any, y1: Any, iz1: Any, x2: Any, y2: Any, iz2: Any) -> tuple[Any, Any]:
    """(s, L_s) of the segment (10.28) with end points (x_i, y_i) at inverse depths iz_i, L_s restricted to
    the SCARA's v_x, v_y, v_z, ω_z: the chain rule ∂s/∂(x, y) · (10.26) in closed form (ω_z turns α at
    −1 rad/rad and leaves L unchanged)."""
    dx, dy = x2 - x1, y2 - y1
    L2 = dx * dx + dy * dy
    L = ops.unless(L2 == 0.0, lambda: ops.sqrt(L2),
                   lambda: "the segment's end points coincide in the image (seen end-on): α and L_s are undefined")
    a1, a2 = x1 * iz1, x2 * iz2
    b1, b2 = y1 * iz1, y2 * iz2
    di = iz1 - iz2
    s = ops.vector(0.5 * (x1 + x2), 0.5 * (y1 + y2), L, ops.atan2(dy, dx))
    J = ops.matrix([[-0.5 * (iz1 + iz2), 0.0, 0.5 * (a1 + a2), 0.5 * (y1 + y2)],
                    [0.0, -0.5 * (iz1 + iz2), 0.5 * (b1 + b2), -0.5 * (x1 + x2)],
                    [dx * di / L, dy * di / L, (dx * (a2 - a1) + dy * (b2 - b1)) / L, 0.0],
                    [-dy * di / L2, dx * di / L2, (dy * (a1 - a2) + dx * (b2 - b1)) / L2, -1.0]])
    return s, J


def _wrapped_difference(ops: Any, a: Any, b: Any) -> Any:
    """a − b of 4-DOF vectors (poses, segment features) with the last entry wrapped to (−π, π]."""
    e = a - b
    return ops.vector(e[0], e[1], e[2], ops.atan2(ops.sin(e[3]), ops.cos(e[3])))


class TargetFeatures:
    """The feature model of a target with points ``points_o`` (n, 3) in the object frame.

    ``kind = "points"``: s = [x_1, y_1, …, x_n, y_n]; ``kind = "segment"``: s = [x_m, y_m, L, α] of P_1P_2 (10.28).
    The features, their interaction matrix and error are written once (``*_law(ops, …)``) for both loops.
    """

    def __init__(self, points_o: Any, kind: str = "segment"):
        pts = np.asarray(points_o, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3 or not np.all(np.isfinite(pts)):
            raise ValueError(f"`points_o` must be a finite (n, 3) array, got shape {pts.shape}")
        if kind not in FEATURE_KINDS:
            raise ValueError(f"`kind` must be one of {FEATURE_KINDS}, got {kind!r}")
        if kind == "segment" and len(pts) != 2:
            raise ValueError(f"segment features need exactly 2 points, got {len(pts)}")
        gaps = np.linalg.norm(pts[:, None, :] - pts[None, :, :], axis=2) + np.eye(len(pts))
        if np.any(gaps == 0):
            i, j = np.argwhere(gaps == 0)[0]
            raise ValueError(f"`points_o` {i} and {j} coincide: their images would too (a zero-length segment, "
                             "a rank-deficient L_s); give distinct points")
        self.points_o, self.kind = pts, kind

    @property
    def size(self) -> int:
        return 4 if self.kind == "segment" else 2 * len(self.points_o)

    def view_from_pose(self, T_co: np.ndarray, fov: FieldOfView | None = None) -> TargetView:
        """The view of the target when the object frame is at T_co (pose in the camera frame)."""
        return view_points(self.points_o @ T_co[:3, :3].T + T_co[:3, 3], fov)

    def _image_points(self, xy: Any) -> np.ndarray:
        xy = as_points(xy, 2, "xy")
        if len(xy) != len(self.points_o):
            raise ValueError(f"`xy` must hold the {len(self.points_o)} image points of the target, got {len(xy)}")
        return xy

    def features(self, xy: Any) -> np.ndarray:
        """s of the image points ``xy`` (n, 2) (finite; ValueError naming them)."""
        return self._features(self._image_points(xy))

    def _features(self, xy: np.ndarray) -> np.ndarray:
        """:meth:`features` of checked points (the laws' hot path)."""
        return self.features_law(Numeric, xy[:, 0], xy[:, 1])

    def features_law(self, ops: Any, x: Any, y: Any) -> Any:
        """s of the image points (x (n,), y (n,)), for either loop."""
        if self.kind == "segment":
            return _segment(ops, x[0], y[0], x[1], y[1])
        return ops.interleave(x, y)

    def interaction_matrix(self, xy: Any, z: Any) -> np.ndarray:
        """L_s (k×6) at image points ``xy`` with depths ``z`` > 0 (10.26; segments: chain rule through (10.28));
        ValueError naming them (a point at or behind the camera, coincident segment ends)."""
        xy = self._image_points(xy)
        z = as_vector(z, len(xy), "z")
        if np.any(z <= 0):
            raise ValueError(f"`z` (depths of the points) must be positive: a point at or behind the camera has no "
                             f"image, got {z}")
        if self.kind == "segment" and not np.any(xy[1] != xy[0]):
            raise ValueError("the segment's end points coincide in the image: α and its interaction matrix are undefined")
        return self.interaction_law(Numeric, xy[:, 0], xy[:, 1], z)

    def interaction_law(self, ops: Any, x: Any, y: Any, z: Any) -> Any:
        """L_s of (x, y) at depths z, for either loop (unvalidated)."""
        L = _points_interaction(ops, x, y, z)
        return _segment_jacobian(ops, x[0], y[0], x[1], y[1]) @ L if self.kind == "segment" else L

    def error(self, s_d: np.ndarray, s: np.ndarray) -> np.ndarray:
        """e_s = s_d − s, with the segment angle difference wrapped to (−π, π]."""
        return self.error_law(Numeric, s_d, s)

    def error_law(self, ops: Any, s_d: Any, s: Any) -> Any:
        return _wrapped_difference(ops, s_d, s) if self.kind == "segment" else s_d - s


class EyeInHandCamera:
    """Sensor block: the camera on ``frame`` of ``robot`` looking at target points ``points_b`` (base frame).

    Called with the arm's measurement (``meas.q``), it returns a :class:`CameraImage`. ``noise`` adds
    zero-mean Gaussian noise of that standard deviation to the normalised coordinates (``rng`` required);
    ``fov`` marks points outside the field of view as not seen; ``lost`` = {point index: (t_from, t_to)}
    hides points over a time interval (an occlusion).

    The image is one body, :meth:`image_law` (the projection (5.35), (5.40), the field of view and the
    occlusion as masks): the Python loop evaluates it at every call, the compiled loop once on symbols, with
    the noise and the occlusion — functions of time only — sampled before the run and fed as inputs
    (:meth:`inputs_at`: the same draws of ``rng``, in the same order, as the Python loop's calls).
    """

    def __init__(self, robot: Robot, points_b: Any, frame: str | int | None = None, fov: FieldOfView | None = None,
                 noise: float = 0.0, rng: np.random.Generator | None = None,
                 lost: dict[int, tuple[float, float]] | None = None):
        self.robot = robot
        self.frame = robot.ee_frame if frame is None else robot.frame(frame)
        self.points_b = as_points(points_b, 3, "points_b")
        if np.ndim(points_b) != 2:
            raise ValueError(f"`points_b` must have shape (n, 3), got {np.shape(points_b)}")
        self.fov, self.noise = fov, as_positive(noise, "noise", allow_zero=True)
        if self.noise > 0 and rng is None:
            raise ValueError("`rng` (a numpy Generator) is required when `noise` > 0")
        self.rng, self.lost = rng, dict(lost or {})
        self._model, self._data = robot.model, robot.data

    @property
    def n_points(self) -> int:
        return len(self.points_b)

    @property
    def n_inputs(self) -> int:
        """The number of rows of :meth:`inputs_at`: 2n for the noise, n for the occlusion."""
        return (2 * self.n_points if self.noise > 0 else 0) + (self.n_points if self.lost else 0)

    def pose(self, q: np.ndarray) -> np.ndarray:
        """T_c^b of the camera at q."""
        R, o = Numeric.frame_pose(self._model, self._data, self.frame, q)
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = R, o
        return T

    def image_law(self, ops: Any, q: Any, noise: tuple | None = None, hidden: Any = None) -> tuple:
        """(x (n), y (n), z (n), seen (n)) of the image at q, for either loop: p^c = R_cᵀ (p − o_c) (5.35),
        x = p_x/p_z, y = p_y/p_z (5.40) for the points in front of the camera, within the field of view and not
        ``hidden`` (a mask), plus the ``noise`` (dx, dy); x, y are NaN where a point is not seen."""
        R, o = ops.frame_pose(self._model, self._data, self.frame, q)
        X, Y, Z = ops.to_camera(R, o, self.points_b)                               # (5.35)
        x, y, seen = ops.perspective(X, Y, Z)                                       # (5.40): NaN behind the camera
        if self.fov is not None:
            seen = ops.logic_and(seen, self.fov.contains_xy(x, y, both=ops.logic_and))
        if hidden is not None:
            seen = ops.logic_and(seen, ops.logic_not(hidden))
        if noise is not None:
            x, y = x + noise[0], y + noise[1]
        if self.fov is None and hidden is None:
            return x, y, Z, seen
        return ops.where(seen, x, np.nan), ops.where(seen, y, np.nan), Z, seen

    def hidden_at(self, t: float) -> np.ndarray | None:
        """The occlusion at t: (n,) True for the points hidden then (``lost``), None without occlusions."""
        if not self.lost:
            return None
        hidden = np.zeros(self.n_points, dtype=bool)
        for i, (t0, t1) in self.lost.items():
            if t0 <= t < t1:
                hidden[i] = True
        return hidden

    def inputs_at(self, times: np.ndarray) -> np.ndarray:
        """The camera's inputs of a compiled run at its sample ``times``: rows [noise x (n); noise y (n);
        hidden (n)] (those the camera has) per column — the noise drawn from ``rng`` as the Python loop's calls
        draw it (one (n, 2) sample per call, in order)."""
        rows = []
        if self.noise > 0:
            draws = self.noise * self.rng.standard_normal((len(times), self.n_points, 2))
            rows += [draws[:, :, 0].T, draws[:, :, 1].T]
        if self.lost:
            rows.append(np.column_stack([self.hidden_at(float(t)) for t in times]).astype(float))
        return np.vstack(rows) if rows else np.zeros((0, len(times)))

    def split_inputs(self, r: Any) -> tuple[tuple | None, Any]:
        """(noise, hidden) from the rows of :meth:`inputs_at` (symbols of the compiled loop)."""
        n, k = self.n_points, 0
        noise = hidden = None
        if self.noise > 0:
            noise, k = (r[0:n], r[n:2 * n]), 2 * n
        if self.lost:
            hidden = r[k:k + n] > 0.5
        return noise, hidden

    def __call__(self, t: float, meas: Any) -> CameraImage:
        noise = None
        if self.noise > 0:
            draws = self.noise * self.rng.standard_normal((self.n_points, 2))
            noise = (draws[:, 0], draws[:, 1])
        x, y, z, seen = self.image_law(Numeric, meas.q, noise, self.hidden_at(t))
        xy = np.empty((len(z), 2))
        xy[:, 0], xy[:, 1] = x, y
        return CameraImage(xy=xy, visible=seen, z=z)


# --------------------------------------------------------------------------------------------
# Pose estimation by inversion of the image Jacobian, Eqs. (10.40)–(10.41) (4-DOF case)
# --------------------------------------------------------------------------------------------

_NAN4 = np.full(4, np.nan)          # the estimator's log while the feature is lost (shared, read-only)
_NAN4.setflags(write=False)


class PoseEstimator(LoggedController):
    """x̂_{c,o} ← x̂ + T Γ(ô) L_s⁻¹(ŝ) K_s (s − ŝ): the discrete estimator of Fig. 10.11 / S10.1 at period ``T``.

    ``target`` gives ŝ(x̂) and L_s(x̂) (its 4 columns v_x, v_y, v_z, ω_z, square for two points or a
    segment). Called with a measurement carrying ``image`` (:class:`CameraImage`), or directly with the
    measured feature vector ``s`` through :meth:`update`. Logs ``x_hat``, ``e_s``, ``s_hat``. One body for
    both loops: :meth:`step_law` (a lost feature holds the estimate: a masked branch in the compiled loop).
    """

    def __init__(self, target: TargetFeatures, x0: Any, K_s: Any, T: float):
        self.target, self.T = target, as_positive(T, "T")
        self.x0 = as_vector(x0, 4, "x0").copy()
        self.K_s = as_gain(K_s, 4, "K_s")
        if target.size != 4:
            raise ValueError(f"the inverse-Jacobian estimator needs 4 features (a square L_s), got {target.size}")
        self._points = target.points_o.tolist()
        self._K_s = diagonal_or_matrix(self.K_s)
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.x_hat = self.x0.copy()

    def predicted(self, x_hat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(ŝ, L_s) at the estimate: the features and the 4×4 interaction matrix of the estimated pose
        (columns v_x, v_y, v_z, ω_z of (10.26); segments through (10.28))."""
        return self.predicted_law(Numeric, x_hat)

    def predicted_law(self, ops: Any, x_hat: Any) -> tuple[Any, Any]:
        x, y, z, phi = ops.entries(x_hat)
        c, s = ops.cos(phi), ops.sin(phi)
        xy, rows = [], []
        for X, Y, Z in self._points:                     # p^c = o + R_z(φ) P, then (5.40)
            pz = Z + z
            iz = ops.unless(pz <= 0.0, lambda pz=pz: 1.0 / pz,
                            lambda: f"the estimate x̂ = {np.asarray(x_hat)} puts target points behind the camera: "
                                    "diverged")
            u, v = (c * X - s * Y + x) * iz, (s * X + c * Y + y) * iz
            xy.append((u, v, iz))
            rows.append([-iz, 0.0, u * iz, v])
            rows.append([0.0, -iz, v * iz, -u])
        if self.target.kind == "segment":
            return _segment_interaction(ops, *xy[0], *xy[1])
        return ops.vector(*[w for u, v, _ in xy for w in (u, v)]), ops.matrix(rows)

    def step_law(self, ops: Any, x_hat: Any, s: Any) -> tuple[Any, Any, Any]:
        """(x̂_{k+1}, e_s, ŝ) from the measured features s: (10.40), then (10.41) by forward Euler."""
        s_hat, L = self.predicted_law(ops, x_hat)
        e_s = self.target.error_law(ops, s, s_hat)
        v_hat = ops.solve(L, ops.times(self._K_s, e_s),
                          lambda: f"the interaction matrix is singular at x̂ = {np.asarray(x_hat)}")    # (10.40)
        return x_hat + self.T * (gamma_matrix(x_hat, ops) @ v_hat), e_s, s_hat                               # (10.41)

    def update(self, s: Any) -> np.ndarray:
        """One step with the measured features ``s`` (4,): returns x̂_{k+1} (``x_hat`` then holds it)."""
        s = as_vector(s, 4, "s")
        x_next, e_s, s_hat = self.step_law(Numeric, self.x_hat, s)
        self.record(x_hat=self.x_hat, e_s=e_s, s_hat=s_hat)
        self.x_hat = x_next
        return self.x_hat

    def estimator_law(self, ops: Any, x_hat: Any, x: Any, y: Any, seen: Any) -> tuple[Any, dict]:
        """(x̂_{k+1}, log) from the image (x, y, seen): the estimate is held while an end point is not seen."""
        def step() -> tuple:
            return self.step_law(ops, x_hat, self.target.features_law(ops, x, y))

        x_next, e_s, s_hat = ops.cond(ops.logic_and(seen[0], seen[1]), step, lambda: (x_hat, _NAN4, _NAN4))
        return x_next, {"x_hat": x_hat, "e_s": e_s, "s_hat": s_hat}

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        """The discrete block: outputs x̂_k, then steps to x̂_{k+1} with the image of sample k (a unit
        delay, as Simulink's discrete integrator: at t = 0 the output is x̂(0)). ``x_hat`` is replaced,
        never modified in place, so the output is not copied."""
        image = meas.image
        x_k = self.x_hat
        self.x_hat, signals = self.estimator_law(Numeric, x_k, image.xy[:, 0], image.xy[:, 1], image.visible)
        self.record(**signals)
        return x_k


# --------------------------------------------------------------------------------------------
# Position-based visual servoing (4-DOF, Sect. 10.7.1)
# --------------------------------------------------------------------------------------------

class _CameraLaw(ControlLaw):
    """A law on the camera carried by ``frame`` of ``robot`` that models the camera twist components ``dofs``
    (None: those the robot moves its camera along, :func:`camera_dofs`). ValueError when the robot's camera
    also moves along a component the law leaves out (the law would not see part of the motion it commands).

    It reads ``meas.image`` (and ``meas.estimate`` after an estimator). Those with one body,
    ``servo_law(ops, K, q, qd, image, estimate)`` (``image`` = (x, y, z, seen)), run in either loop; the compiled
    one composes them inside :class:`VisualServo` (``symbolic()`` of the chain)."""

    servo = False        # whether servo_law is the law (it runs compiled inside a VisualServo)

    def __init__(self, robot: Robot, frame: str | int | None, dofs: Sequence[int] | None):
        self.robot = robot
        self.nq, self.nv = robot.nq, robot.nv
        self.frame = robot.ee_frame if frame is None else robot.frame(frame)
        moving = camera_dofs(robot, self.frame)
        self.dofs = list(moving if dofs is None else _as_dofs(dofs))
        left_out = [i for i in moving if i not in self.dofs]
        if left_out:
            raise ValueError(
                f"`dofs` {tuple(self.dofs)} leaves out {', '.join(TWIST_NAMES[i] for i in left_out)}, along which the "
                f"camera of {robot.name!r} moves: {type(self).__name__} would not see part of the motion it "
                f"commands (the error stalls). " + self._dofs_remedy(moving))
        self._model, self._data = robot.model, robot.data

    def _dofs_remedy(self, moving: tuple[int, ...]) -> str:
        return f"Use dofs={moving} (the default, derived from the robot)."

    damping_twist = 1e-6

    @staticmethod
    def _image(meas: Any) -> tuple:
        image = meas.image
        return image.xy[:, 0], image.xy[:, 1], image.z, image.visible

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        u, signals = self.servo_law(Numeric, self._K, meas.q, meas.qd, self._image(meas),
                                    getattr(meas, "estimate", None))
        self.record(**signals)
        return u

    def symbolic(self) -> Any:
        from controllers.compiled import no_symbolic_form

        raise no_symbolic_form(self, "a camera law runs compiled inside visual_servo(camera, law, Tc)")

    def joint_rates(self, q: np.ndarray, twist: np.ndarray) -> np.ndarray:
        """q̇ = J_c^† [v_c; ω_c]: the joint rates of a camera twist (camera frame), damped least squares
        (3.59) on the 6×n camera Jacobian."""
        Jc = camera_jacobian(self.robot, q, self.frame)
        return Jc.T @ np.linalg.solve(Jc @ Jc.T + self.damping_twist * np.eye(6), twist)

    def pbvs_jacobian(self, q: np.ndarray, x_co: np.ndarray) -> np.ndarray:
        """J_Ad = ∂x_{c,o}/∂q = Γ(o_{c,o}) [R_cᵀ J_P; ω_z rows] (4×n), 4-DOF case of (10.67)."""
        return self._pbvs_jacobian(Numeric, q, x_co)

    def _pbvs_jacobian(self, ops: Any, q: Any, x_co: Any) -> Any:
        Jc = ops.camera_jacobian(self._model, self._data, self.frame, q)
        return gamma_matrix(x_co, ops) @ Jc[ops.index(_SCARA_ROWS), :]


class _PlanarPoseLaw(_CameraLaw):
    """The 4-DOF PBVS laws (poses [x, y, z, φ], Example 10.3): for a camera that turns only about its optical axis."""

    def __init__(self, robot: Robot, frame: str | int | None):
        super().__init__(robot, frame, SCARA_DOFS)

    def _dofs_remedy(self, moving: tuple[int, ...]) -> str:
        return ("This law is the 4-DOF case (poses [x, y, z, φ] about the optical axis): for a camera that also "
                "turns about x_c, y_c use PBVSPoseResolvedVelocity (6-DOF) or an IBVS law.")


class PBVSPDGravity(_PlanarPoseLaw):
    """u = g(q) + J_Adᵀ(K_P x̃ − K_D J_Ad q̇), x̃ = x_{d,o} − x̂_{c,o} (Fig. 10.14), reading ``meas.q``,
    ``meas.qd`` and the estimate ``meas.estimate``. Logs ``x_tilde``."""

    servo = True

    def __init__(self, robot: Robot, x_do: Any, K_P: Any, K_D: Any, frame: str | int | None = None):
        super().__init__(robot, frame)
        self.x_do = as_vector(x_do, 4, "x_do")
        self.K_P = np.diag(as_vector(K_P, 4, "K_P"))
        self.K_D = np.diag(as_vector(K_D, 4, "K_D"))
        self.set_gains(K_P=np.diag(self.K_P)[:, None], K_D=np.diag(self.K_D)[:, None])

    def servo_law(self, ops: Any, K: dict, q: Any, qd: Any, image: tuple, estimate: Any) -> tuple[Any, dict]:
        """The law (Fig. 10.14), once for both loops (``image`` unused: the estimate carries it)."""
        J = self._pbvs_jacobian(ops, q, estimate)
        x_tilde = _wrapped_difference(ops, self.x_do, estimate)
        g = ops.gravity(self._model, self._data, q)                                    # g(q), (7.39)
        return g + J.T @ (K["K_P"] * x_tilde - K["K_D"] * (J @ qd)), {"x_tilde": x_tilde}


class PBVSResolvedVelocity(_PlanarPoseLaw):
    """q̇_r = J_Ad⁻¹ K x̃ (Fig. 10.15): x̃̇ = −K x̃ for a robot that follows its velocity reference.

    Near a singular posture (the SCARA stretched or folded, θ₂ = 0 or π) J_Ad⁻¹ turns a bounded error into
    unphysical joint rates: the law raises a ValueError naming the posture when cond(J_Ad) > ``max_condition``
    (default :data:`~rigid_body.task_space.RATE_CONDITION`), unless ``damping`` λ > 0 is given: then
    q̇_r = J_Adᵀ(J_Ad J_Adᵀ + λ² I)⁻¹ K x̃ (damped least squares, 3.59) at every posture."""

    def __init__(self, robot: Robot, x_do: Any, K: Any, frame: str | int | None = None,
                 max_condition: float = RATE_CONDITION, damping: float | None = None):
        super().__init__(robot, frame)
        self.x_do = as_vector(x_do, 4, "x_do")
        self.K = np.diag(per_joint(K, 4, "K"))
        if np.any(np.diag(self.K) <= 0):
            raise ValueError(f"`K` must be positive gains, got {np.diag(self.K)}")
        self._k = np.diag(self.K).copy()
        self.max_condition, self.damping = rate_options(max_condition, damping)

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        x_hat = meas.estimate
        x_tilde = _wrapped_difference(Numeric, self.x_do, x_hat)
        self.record(x_tilde=x_tilde)
        return resolved_rates(self.pbvs_jacobian(meas.q, x_hat), self._k * x_tilde,
                              f"(J_Ad at q = {np.round(meas.q, 6).tolist()}, t = {t:.4g} s)", self.max_condition,
                              self.damping)


class PBVSPoseResolvedVelocity(_CameraLaw):
    """Position-based visual servoing of a 6-DOF camera, resolved velocity (Sect. 10.7.1, general form).

    The object's pose T_o^c is estimated at each image from a planar target (points ``zeta`` (n ≥ 4, 2) on
    the plane z = 0 of the object frame) by the homography and (10.12) (``rigid_body.vision``); the pose of
    the desired camera frame in the current one, T_d^c = T_o^c (T_o^d)⁻¹ with ``T_do`` the desired pose of
    the object in the camera frame, gives the error [o_{c,d}^c; θ r of R_d^c]. The law v_c = K_p o_{c,d}^c,
    ω_c = K_o θ r moves the camera's origin along the straight line to the desired one (ȯ_c = R_c v_c =
    K_p (o_d − o_c) in the base frame, the distance decaying as e^{−K_p t}) and turns it about a fixed axis,
    θ decaying as e^{−K_o t}; q̇ = J_c^† [v_c; ω_c]. Logs ``o_cd`` (position error [m]) and ``theta`` [rad].
    """

    def __init__(self, robot: Robot, zeta: Any, T_do: Any, K_p: float, K_o: float, frame: str | int | None = None):
        super().__init__(robot, frame, range(6))
        self.zeta = np.asarray(zeta, dtype=float)
        if self.zeta.ndim != 2 or self.zeta.shape[1] != 2 or len(self.zeta) < 4 or not np.all(np.isfinite(self.zeta)):
            raise ValueError(f"`zeta` must be a finite (n ≥ 4, 2) array of plane points, got {self.zeta.shape}")
        _general_position(self.zeta, "zeta")
        T = as_homogeneous(T_do, "T_do")
        self.T_od = np.linalg.inv(T)                          # (T_o^d)⁻¹
        self.K_p, self.K_o = as_positive(K_p, "K_p"), as_positive(K_o, "K_o")

    def estimate(self, xy: np.ndarray) -> np.ndarray:
        """T_o^c (4×4) from the current image points ``xy`` (n, 2): homography and (10.12)."""
        pose = pose_from_homography(homography_dlt(self.zeta, xy))
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = pose.R, pose.o
        return T

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        image = meas.image
        if not image.visible.all():
            self.record(o_cd=np.full(3, np.nan), theta=np.nan)
            return np.zeros(self.robot.nv)        # a point not seen: no pose estimate, stop and wait
        T_cd = self.estimate(image.xy) @ self.T_od
        o = T_cd[:3, 3]
        theta_r = pin.log3(T_cd[:3, :3])
        w = self.K_o * theta_r
        self.record(o_cd=o.copy(), theta=float(np.linalg.norm(theta_r)))
        return self.joint_rates(meas.q, np.concatenate([self.K_p * o, w]))


def _general_position(points: np.ndarray, name: str) -> None:
    """ValueError naming ``name`` unless the plane points (n ≥ 4, 2) determine a homography (no three of four
    collinear, no coincident points): the laws estimate one from them at every image."""
    try:
        homography_dlt(points, points)
    except ValueError:
        raise ValueError(f"`{name}` must hold plane points in general position (a homography needs 4 of them, no 3 "
                         f"collinear), got {points.tolist()}") from None


# --------------------------------------------------------------------------------------------
# Image-based visual servoing (Sect. 10.7.2)
# --------------------------------------------------------------------------------------------

class _IBVSLaw(_CameraLaw):
    """Shared part of the IBVS laws: e_s = s_d − s and J_L = L̂_s(s, ẑ)[:, dofs] J_c[dofs] from ``meas.image``.

    ``depth``: a number = the same depth for every point (e.g. the desired one, z_d); None = the measured
    depths (known depth); :func:`depth_from_segment` or any function ``image -> z (n,)`` = an estimate (a plain
    function runs on the Python loop only). Points not seen drop their rows (point features: zero rows in
    :meth:`features_and_jacobian`, the one body); with none left the command is zero.

    ``dofs``: the camera-twist components the law commands (default: those the robot moves its camera along,
    :func:`camera_dofs`). Refused at construction (ValueError) when the robot's camera also moves along a
    component left out, or when L_s(s_d)[:, dofs] J_c[dofs] has a rank below min(k features, len(dofs)) at
    every sampled posture (the chosen components cannot reduce the feature error). A servo that stalls —
    J_Lᵀ K e_s ≈ 0 with e_s not small: the law commands (almost) nothing while the error remains (a local
    minimum) — is reported once per run by a ``RuntimeWarning`` and kept in ``stall`` ((t, ‖e_s‖) or None; the
    Python loop's diagnosis).
    """

    runtime_attributes = ("stall",)          # the Python loop's diagnosis: not part of the compiled loop's key

    STALL_ERROR = 1e-4         # ‖e_s‖ (normalised image units, 0.06 px at f α = 600 px) below which the servo has converged
    STALL_GRADIENT = 1e-3      # ‖J_Lᵀ K e_s‖ / (‖J_L‖ ‖K e_s‖) below which the error is out of the law's reach

    def __init__(self, robot: Robot, target: TargetFeatures, s_d: Any, depth: Any,
                 frame: str | int | None, dofs: Sequence[int] | None):
        super().__init__(robot, frame, dofs)
        self.target = target
        self.s_d = as_vector(s_d, target.size, "s_d")
        if depth is None or callable(depth):
            self.depth = depth
        else:
            self.depth = as_positive(depth, "depth")
        self._depths = np.full(len(target.points_o), self.depth if isinstance(self.depth, float) else np.nan)
        self._dofs = np.array(self.dofs)
        self._check_reach()
        self.stall: tuple[float, float] | None = None

    @property
    def signal_components(self) -> dict[str, list[tuple[str, str]]]:
        """The columns of the logged e_s: x₁, y₁ … of points or x_m, y_m, L, α of a segment (normalised units)."""
        from controllers.signals import SEGMENT_FEATURES, point_features

        return {"e_s": list(SEGMENT_FEATURES) if self.target.kind == "segment" else point_features(self.target.size)}

    def reset(self) -> None:
        super().reset()
        self.stall = None
    def _estimated_depths(self, image: CameraImage) -> np.ndarray:
        """The depth estimate ``depth(image)``, checked where a point is seen: (n,), finite and positive."""
        z = np.asarray(self.depth(image), dtype=float)
        if z.shape != image.visible.shape:
            raise ValueError(f"`depth` must return one depth per point ({len(image.visible)},), got shape {z.shape}")
        seen = z[image.visible]
        if not np.all(np.isfinite(seen) & (seen > 0)):
            raise ValueError(f"`depth` estimated non-positive or non-finite depths {z} for points seen in the image")
        return z

    def _check_reach(self) -> None:
        """ValueError when J_L = L_s(s_d, ẑ)[:, dofs] J_c[dofs] is degenerate at every sampled posture: its rank
        below min(k features, rank J_c[dofs]) — some feature directions out of the camera's reach while some
        camera motions leave the features unchanged (coincident desired points, a segment seen end-on)."""
        xy = self._desired_points()
        z = np.full(len(xy), self.depth if isinstance(self.depth, float) else 1.0)
        L = self.target.interaction_law(Numeric, xy[:, 0], xy[:, 1], z)
        L = L[:, self._dofs]
        k, best = L.shape[0], None
        for q in _configurations(self.robot):
            Jc = camera_jacobian(self.robot, q, self.frame)[self._dofs]
            motions = int(np.linalg.matrix_rank(Jc, tol=1e-9 * max(1.0, np.abs(Jc).max())))
            JL = L @ Jc
            rank = int(np.linalg.matrix_rank(JL, tol=1e-9 * max(1.0, np.abs(JL).max())))
            if best is None or (rank - min(k, motions), rank) > (best[0] - min(k, best[1]), best[0]):
                best = (rank, motions)                   # the least deficient posture, the generic rank on ties
        rank, motions = best
        self._rank = max(rank, 1)            # the rank of J_L with every feature seen (kept by resolved_rates)
        if rank < min(k, motions):
            raise ValueError(
                f"`s_d`/`dofs` {tuple(self.dofs)}: J_L = L_s J_c has rank {rank} < min({k} features, {motions} "
                f"independent camera motions) at every sampled posture of {self.robot.name!r}: the servo cannot "
                "reduce the feature error in every direction (degenerate desired features: coincident points, a "
                "segment seen end-on?); choose other `s_d`, features or `dofs`")

    def _desired_points(self) -> np.ndarray:
        """The desired image points (n, 2): s_d itself for points, the segment's ends from [x_m, y_m, L, α]."""
        if self.target.kind == "points":
            return self.s_d.reshape(-1, 2)
        x_m, y_m, length, alpha = self.s_d.tolist()
        if not length > 0:
            raise ValueError(f"`s_d` must have a positive segment length L, got {length}")
        h = 0.5 * length * np.array([math.cos(alpha), math.sin(alpha)])
        return np.array([[x_m, y_m] - h, [x_m, y_m] + h])

    def _watch_stall(self, t: float, e: np.ndarray, J: np.ndarray, Ke: np.ndarray) -> None:
        """Report (once per run) a servo whose law no longer reduces the error: J_Lᵀ K e_s ≈ 0, e_s not small."""
        if self.stall is not None or not math.sqrt(float(e @ e)) > self.STALL_ERROR:
            return
        gradient = J.T @ Ke
        if math.sqrt(float(gradient @ gradient)) <= self.STALL_GRADIENT * np.linalg.norm(J, 2) * np.linalg.norm(Ke):
            import warnings

            self.stall = (t, float(np.linalg.norm(e)))
            warnings.warn(f"{type(self).__name__}: the servo stalls at t = {t:.4g} s with ‖e_s‖ = {self.stall[1]:.3g}: "
                          "J_Lᵀ K e_s ≈ 0, the remaining feature error is out of reach of the commanded twist (a local "
                          f"minimum of IBVS, or `dofs` {tuple(self.dofs)} that miss the camera's motion)",
                          RuntimeWarning, stacklevel=2)

    def features_and_jacobian(self, ops: Any, q: Any, image: tuple) -> tuple[Any, Any, Any]:
        """(e_s, J_L, used) at the image (x, y, z, seen), for either loop: the rows of the features not seen are
        zero in e_s and J_L (``used`` False there), which is the law without them."""
        x, y, z, seen = image
        Jc = ops.camera_jacobian(self._model, self._data, self.frame, q)
        if self.depth is None:
            z_used = ops.where(seen, z, 1.0)                          # measured (unseen rows are dropped)
        elif callable(self.depth):
            z_used = self._estimated_depth(ops, x, y, z, seen)
        else:
            z_used = self._depths
        if self.target.kind == "segment":
            both = ops.logic_and(seen[0], seen[1])
            used = ops.repeat(ops.vector(both), 4)
            xs, ys = ops.where(used[:2], x, _SPARE_ENDS), ops.where(used[:2], y, 0.0)   # a valid segment when lost
            s = self.target.features_law(ops, xs, ys)
            L = self.target.interaction_law(ops, xs, ys, ops.where(used[:2], z_used, 1.0))
            e = self.target.error_law(ops, self.s_d, s)
        else:
            used = ops.repeat(seen, 2)
            xs, ys = ops.where(seen, x, 0.0), ops.where(seen, y, 0.0)
            e = self.s_d - ops.interleave(xs, ys)
            L = _points_interaction(ops, xs, ys, z_used)
        J = ops.columns(L, self._dofs) @ Jc[ops.index(self._dofs), :]
        return ops.where(used, e, 0.0), ops.where(used, J, 0.0), used

    def _estimated_depth(self, ops: Any, x: Any, y: Any, z: Any, seen: Any) -> Any:
        law = getattr(self.depth, "depth_law", None)
        if law is not None:
            return law(ops, x, y, seen)
        if ops.symbolic:
            from controllers.compiled import no_symbolic_form

            raise no_symbolic_form(self.depth, "a depth estimate needs depth_law(ops, x, y, seen)")
        return self._estimated_depths(CameraImage(xy=np.column_stack((x, y)), visible=seen, z=z))

    def error_and_jacobian(self, q: np.ndarray, image: CameraImage) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(e_s, J_L, rows used) at the current image; rows of unseen points are removed."""
        e, J, used = self.features_and_jacobian(Numeric, q, (image.xy[:, 0], image.xy[:, 1], image.z,
                                                              image.visible))
        rows = np.flatnonzero(used)
        if self.target.kind == "segment" and rows.size == 0:
            return np.zeros(0), np.zeros((0, len(q))), rows
        return e[rows], J[rows], rows


class IBVSPDGravity(_IBVSLaw):
    """u = g(q) + J_Lᵀ(K_Ps e_s − K_Ds J_L q̇), e_s = s_d − s (Fig. 10.16). Logs ``e_s``."""

    servo = True

    def __init__(self, robot: Robot, target: TargetFeatures, s_d: Any, K_Ps: Any, K_Ds: Any,
                 depth: Any = None, frame: str | int | None = None, dofs: Sequence[int] | None = None):
        super().__init__(robot, target, s_d, depth, frame, dofs)
        self.K_Ps = _positive_gains(K_Ps, target.size, "K_Ps")
        self.K_Ds = _positive_gains(K_Ds, target.size, "K_Ds")
        self.set_gains(K_Ps=self.K_Ps[:, None], K_Ds=self.K_Ds[:, None])

    def servo_law(self, ops: Any, K: dict, q: Any, qd: Any, image: tuple, estimate: Any) -> tuple[Any, dict]:
        """The law (Fig. 10.16), once for both loops: the rows of the features not seen are zero."""
        return self._pd(ops, K, q, qd, *self.features_and_jacobian(ops, q, image))

    def _pd(self, ops: Any, K: dict, q: Any, qd: Any, e: Any, J: Any, used: Any) -> tuple[Any, dict]:
        g = ops.gravity(self._model, self._data, q)                                    # g(q), (7.39)
        return g + J.T @ (K["K_Ps"] * e - K["K_Ds"] * (J @ qd)), {"e_s": ops.where(used, e, np.nan)}

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        e, J, used = self.features_and_jacobian(Numeric, meas.q, self._image(meas))
        u, signals = self._pd(Numeric, self._K, meas.q, meas.qd, e, J, used)
        self._watch_stall(t, e, J, self._K["K_Ps"] * e)        # the zero rows change no norm nor Jᵀ K e
        self.record(**signals)
        return u


class IBVSResolvedVelocity(_IBVSLaw):
    """q̇_r = J_L⁻¹ K_s e_s (Fig. 10.17): ė_s = −K_s e_s; J_L† (minimum norm, or least squares for more features
    than joints) when J_L is not square.

    Near a singular J_L the law raises a ValueError naming the posture when cond(J_L) > ``max_condition``
    (:func:`rigid_body.task_space.resolved_rates`), unless ``damping`` λ > 0 is given: then the damped
    least-squares q̇_r = J_Lᵀ(J_L J_Lᵀ + λ² I)⁻¹ K_s e_s (3.59) at every posture."""

    def __init__(self, robot: Robot, target: TargetFeatures, s_d: Any, K_s: Any, depth: Any = None,
                 frame: str | int | None = None, dofs: Sequence[int] | None = None,
                 max_condition: float = RATE_CONDITION, damping: float | None = None):
        super().__init__(robot, target, s_d, depth, frame, dofs)
        self.K_s = _positive_gains(K_s, target.size, "K_s")
        self.max_condition, self.damping = rate_options(max_condition, damping)

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        e, J, rows = self.error_and_jacobian(meas.q, meas.image)
        self.record(e_s=_full(e, rows, self.target.size))
        if rows.size == 0:
            return np.zeros(len(meas.q))        # nothing seen: stop and wait
        Ke = self.K_s[rows] * e
        self._watch_stall(t, e, J, Ke)
        return resolved_rates(J, Ke, f"(J_L = L_s J_c at q = {np.round(meas.q, 6).tolist()}, t = {t:.4g} s)",
                              self.max_condition, self.damping, min(J.shape[0], self._rank))


def _positive_gains(K: Any, size: int, name: str) -> np.ndarray:
    """Per-feature gains: a scalar or (size,), finite and positive."""
    k = per_joint(K, size, name)
    if np.any(k <= 0):
        raise ValueError(f"`{name}` must be positive gains, got {k}")
    return k


_SPARE_ENDS = np.array([0.0, 1.0])      # x of a unit segment standing in for a segment not seen (rows masked)


class SegmentDepth:
    """The depth estimate of :func:`depth_from_segment`: z ≈ ℓ/L for both end points, a function of the image
    (``__call__``) and of its coordinates for either loop (:meth:`depth_law`)."""

    def __init__(self, length: float):
        self.length = as_positive(length, "length")

    def depth_law(self, ops: Any, x: Any, y: Any, seen: Any) -> Any:
        L = ops.hypot(x[1] - x[0], y[1] - y[0])
        z = self.length / ops.unless(L == 0.0, lambda: L, lambda: "depth_from_segment: the segment's end points "
                                     "coincide in the image (the segment is seen end-on): its depth ℓ/L is undefined")
        return ops.vector(*([z] * x.shape[0]))

    def __call__(self, image: CameraImage) -> np.ndarray:
        return self.depth_law(Numeric, image.xy[:, 0], image.xy[:, 1], image.visible)


def depth_from_segment(length: float) -> SegmentDepth:
    """A depth estimate for a segment of known ``length`` [m] parallel to the image plane: z ≈ ℓ/L, with L
    the segment's image length (10.28) — both end points get it (NaN when an end point is not seen)."""
    return SegmentDepth(length)


def _full(e: np.ndarray, rows: np.ndarray, size: int) -> np.ndarray:
    out = np.full(size, np.nan)
    out[rows] = e
    return out


def visual_servo(camera: EyeInHandCamera, law: Any, Tc: float, estimator: PoseEstimator | None = None) -> Chain:
    """The controller of an eye-in-hand loop: camera → [pose estimator at the loop's period →] law held
    over ``Tc`` (the vision/controller period). The law reads ``meas.image`` and, after an estimator,
    ``meas.estimate``; ``simulate(..., Ts=estimator period)`` runs it (``backend="casadi"`` too, when the
    law has a symbolic form: :class:`VisualServo`)."""
    inner: Any = ZeroOrderHold(law, Tc)
    if estimator is not None:
        inner = Chain(estimator, inner, name="estimate")
    return VisualServo(camera, inner, name="image")


class VisualServo(Chain):
    """The chain of :func:`visual_servo` (camera → [estimator →] law held over ``Tc``), with its symbolic
    form for ``simulate(..., backend="casadi")``: the blocks' one bodies (:meth:`EyeInHandCamera.image_law`,
    :meth:`PoseEstimator.estimator_law`, the law's ``servo_law``) composed on symbols; the estimate x̂, the held
    torque and the held log of the law are the law's state; the instants where the hold samples the law are
    found by the rule of :class:`~controllers.simulation.ZeroOrderHold` on the run's grid and fed as a
    reference row, with the camera's noise and occlusion (:meth:`EyeInHandCamera.inputs_at`)."""

    def __call__(self, t: float, measurement: Any) -> Any:
        if isinstance(measurement, np.ndarray):    # a JointIntegrator's bare state q: read it as the encoders
            from controllers.plants import ArmMeasurement

            measurement = ArmMeasurement(measurement, None)
        return super().__call__(t, measurement)

    def _blocks(self) -> tuple[EyeInHandCamera, PoseEstimator | None, ZeroOrderHold]:
        inner = self.second
        if isinstance(inner, Chain):
            return self.first, inner.first, inner.second
        return self.first, None, inner

    @property
    def compilable(self) -> bool:
        """Whether :meth:`symbolic` can build the chain: its law is written once (``servo_law``)."""
        return getattr(self._blocks()[2].block, "servo", False)

    def symbolic(self) -> Any:
        """The chain as a :class:`controllers.compiled.SymbolicLaw` (laws with a ``servo_law``:
        :class:`PBVSPDGravity`, :class:`IBVSPDGravity`); the parameters are the law's gains."""
        import casadi as ca

        from controllers.compiled import SymbolicLaw, no_symbolic_form

        camera, estimator, hold = self._blocks()
        law = hold.block
        if not getattr(law, "servo", False):
            raise no_symbolic_form(law, "a camera law needs its one body servo_law")
        robot = camera.robot
        n = robot.nv
        gains = {name: ca.DM(value) for name, value in law.gains.items()}
        q_sym, qd_sym = ca.SX.sym("q", robot.nq), ca.SX.sym("qd", n)
        _, _, probe = self._parts(law, estimator, camera, q_sym, qd_sym, ca.SX.sym("x_hat", 4), gains,
                                  ca.SX.sym("r", camera.n_inputs))
        held_sizes = [probe["law"][name].shape[0] for name in sorted(probe["law"])]

        def parts(q: Any, qd: Any, r: Any, K: dict, state: Any, dt: Any) -> tuple[Any, dict, Any]:
            x_hat = state[:4] if estimator is not None else None
            u_law, x_next, logs = self._parts(law, estimator, camera, q, qd, x_hat, K, r[1:])
            sample = r[0] > 0.5                                             # the hold samples the law now
            k = 4 if estimator is not None else 0
            u = ca.if_else(sample, u_law, state[k:k + n])
            signals, held, k = dict(logs["estimator"]), [], k + n
            for name, size in zip(sorted(logs["law"]), held_sizes):
                value = ca.if_else(sample, logs["law"][name], state[k:k + size])
                signals[name], k = value, k + size
                held.append(value)
            next_state = ca.vertcat(*([x_next] if estimator is not None else []), u, *held)
            return u, signals, next_state

        x0 = [estimator.x_hat] if estimator is not None else []
        state = np.concatenate(x0 + [np.zeros(n)] + [np.zeros(size) for size in held_sizes])
        return SymbolicLaw.build(robot.nq, n, 1 + camera.n_inputs, law.gains, parts,
                                 _ChainInputs(hold.Ts, camera), state=state)

    def compiled_inputs(self, n_state: int) -> tuple[np.ndarray, np.ndarray, Any]:
        """(p, c_0, reference) of a compiled run of this chain (:func:`controllers.compiled.law_inputs`): the law's
        gains, the estimate after ``reset()`` then zeros (the held torque and log), the hold and camera rows."""
        camera, estimator, hold = self._blocks()
        p = np.concatenate([np.atleast_2d(np.asarray(v, dtype=float)).ravel(order="F") for v in hold.block.gains.values()])
        x0 = [estimator.x_hat] if estimator is not None else []
        c0 = np.concatenate(x0 + [np.zeros(n_state - (4 if estimator is not None else 0))])
        return p, c0, _ChainInputs(hold.Ts, camera)

    @staticmethod
    def _parts(law: Any, estimator: Any, camera: EyeInHandCamera, q: Any, qd: Any, x_hat: Any, K: dict,
               inputs: Any) -> tuple[Any, Any, dict]:
        from controllers.compiled import Symbolic

        x, y, z, seen = camera.image_law(Symbolic, q, *camera.split_inputs(inputs))
        x_next, est_log = (None, {}) if estimator is None else estimator.estimator_law(Symbolic, x_hat, x, y, seen)
        u, law_log = law.servo_law(Symbolic, K, q, qd, (x, y, z, seen), x_hat)
        return u, x_next, {"estimator": est_log, "law": law_log}


class _ChainInputs:
    """The reference rows of :class:`VisualServo`: 1 at the samples where a :class:`ZeroOrderHold` of period
    ``Ts`` evaluates its block (:meth:`ZeroOrderHold.instants`, from the first sample of the run), else 0; then
    the camera's inputs (:meth:`EyeInHandCamera.inputs_at`: noise, occlusion)."""

    def __init__(self, Ts: float, camera: EyeInHandCamera):
        self.Ts, self.camera = Ts, camera

    def __call__(self, t: float) -> np.ndarray:
        raise ValueError("the hold instants depend on the run's first sample: sample them with at_times")

    def at_times(self, times: np.ndarray) -> np.ndarray:
        return np.vstack([ZeroOrderHold.instants(times, self.Ts).astype(float)[None], self.camera.inputs_at(times)])


# --------------------------------------------------------------------------------------------
# Hybrid (2½-D) visual servoing, Eq. (10.96)
# --------------------------------------------------------------------------------------------

def hybrid_error_jacobians(x: float, y: float, z_c: float) -> tuple[np.ndarray, np.ndarray]:
    """(J_p, J_o) with ė_p = J_p v_c^c + J_o ω_c^c for e_p = [x − x_d, y − y_d, ln(z_c/z_d)] (10.96):
    J_p = (1/z_c)[[−1, 0, x], [0, −1, y], [0, 0, −1]], J_o = [[xy, −1−x², y], [1+y², −xy, −x], [−y, x, 0]]
    (z_d ρ_z = z_c, Problem 10.13)."""
    z_c = as_positive(z_c, "z_c")
    x, y = as_scalar(x, "x"), as_scalar(y, "y")
    J_p = np.array([[-1.0, 0.0, x], [0.0, -1.0, y], [0.0, 0.0, -1.0]]) / z_c
    J_o = np.array([[x * y, -1.0 - x * x, y], [1.0 + y * y, -x * y, -x], [-y, x, 0.0]])
    return J_p, J_o


class HybridVisualServo(_CameraLaw):
    """2½-D (hybrid) visual servoing, Sect. 10.8, resolved velocity on a 6-DOF camera: q̇_r = J_c^† [v_c; ω_c].

    From the current image of n ≥ 4 coplanar points and their desired image ``xy_d`` the homography
    H ∝ R_d^c + o_{c,d}^c n^{dT}/d_d (``rigid_body.vision.homography_dlt``) gives, with the plane's normal
    ``n_d`` in the desired camera frame: R_d^c (H a, H b on two directions a, b of the plane, R n_d = Ha × Hb,
    the scale from ‖Ha‖ = 1) and the depth ratio ρ_z = z_c/z_d of the reference point (10.94)–(10.95).
    The reference point is a point of the plane given by its desired image ``reference`` (default: the
    centroid of ``xy_d``, near the optical axis); its current image is H s̃_d (normalised). The error is
    e_o = θ r of R_d^c and e_p = [x − x_d, y − y_d, ln ρ_z] (10.96); the law
    ω_c = K_o θ r (θ r is an eigenvector of L_ω: θ decays as e^{−K_o t} about a fixed axis) and
    v_c = −J_p⁻¹(K_p e_p + J_o ω_c), so ė_p = −K_p e_p: the reference point moves straight in the image and
    its depth never overshoots — no camera retreat. ``z_d`` is the reference point's desired depth (J_p
    needs z_c = ρ_z z_d). Logs ``e_p``, ``theta``.
    """

    def __init__(self, robot: Robot, xy_d: Any, n_d: Any, z_d: float, K_p: Any, K_o: Any,
                 frame: str | int | None = None, reference: Any = None):
        super().__init__(robot, frame, range(6))
        self.xy_d = np.asarray(xy_d, dtype=float)
        if self.xy_d.ndim != 2 or self.xy_d.shape[1] != 2 or len(self.xy_d) < 4 or not np.all(np.isfinite(self.xy_d)):
            raise ValueError(f"`xy_d` must be a finite (n ≥ 4, 2) array of desired image points, got {self.xy_d.shape}")
        _general_position(self.xy_d, "xy_d")
        n = as_vector(n_d, 3, "n_d")
        if not np.linalg.norm(n) > 0:
            raise ValueError(f"`n_d` (the plane's normal) must be a non-zero vector, got {n_d!r}")
        self.n_d = n / np.linalg.norm(n)
        self.z_d = as_positive(z_d, "z_d")
        self.K_p = as_vector(K_p, 3, "K_p") if np.ndim(K_p) else np.full(3, as_positive(K_p, "K_p"))
        self.K_o = as_positive(K_o, "K_o")
        self.reference = self.xy_d.mean(axis=0) if reference is None else as_vector(reference, 2, "reference")
        a = np.cross(self.n_d, [1.0, 0.0, 0.0] if abs(self.n_d[0]) < 0.9 else [0.0, 1.0, 0.0])
        a /= np.linalg.norm(a)
        self._plane = np.column_stack([a, np.cross(self.n_d, a), self.n_d])   # [a, b, n], a × b = n

    def rotation_and_depth_ratio(self, xy: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
        """(R_d^c, ρ_z, the reference point's current image) from the current image points ``xy`` (n, 2)
        through the homography."""
        H = homography_dlt(self.xy_d, xy)
        s_d = np.append(self.reference, 1.0)
        if float(H[2] @ s_d) < 0:                              # λ s̃ = H s̃_d with λ = z_d/z_c > 0
            H = -H
        s_c = H @ s_d
        s_c = s_c[:2] / s_c[2]
        a, b = self._plane[:, 0], self._plane[:, 1]
        Ha, Hb = H @ a, H @ b
        H = H / np.linalg.norm(Ha)
        Ha, Hb = Ha / np.linalg.norm(Ha), Hb / np.linalg.norm(Ha)
        R = nearest_rotation(np.column_stack([Ha, Hb, np.cross(Ha, Hb)]) @ self._plane.T)
        rho = depth_ratio(H, R @ self.n_d, s_c, self.n_d, self.reference)
        return R, rho, s_c

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        image = meas.image
        if not image.visible.all():
            self.record(e_p=np.full(3, np.nan), theta=np.nan)
            return np.zeros(self.robot.nv)        # a point not seen: no homography, stop and wait
        R, rho, (x, y) = self.rotation_and_depth_ratio(image.xy)
        theta_r = pin.log3(R)                                   # e_o = θ r
        e_p = np.array([x - self.reference[0], y - self.reference[1], math.log(rho)])
        J_p, J_o = hybrid_error_jacobians(x, y, rho * self.z_d)
        w = self.K_o * theta_r
        v = -np.linalg.solve(J_p, self.K_p * e_p + J_o @ w)
        self.record(e_p=e_p, theta=float(np.linalg.norm(theta_r)))
        return self.joint_rates(meas.q, np.concatenate([v, w]))


# --------------------------------------------------------------------------------------------
# Set-up in one call: an eye-in-hand camera servoed to a desired pose by IBVS (Fig. 10.17)
# --------------------------------------------------------------------------------------------

def desired_point_features(T_d: Any, points_b: Any) -> tuple[TargetFeatures, np.ndarray]:
    """The point features a camera at the desired pose ``T_d`` (= T_c^b, 4×4) sees of ``points_b`` (n, 3, base
    frame): the target (its points in the desired camera frame, (5.35)) and s_d = [x₁, y₁, …, x_n, y_n] (10.26),
    normalised image coordinates. ValueError when a point is not in front of that camera."""
    T = as_homogeneous(T_d, "T_d")
    points = as_points(points_b, 3, "points_b")
    view = view_points((points - T[:3, 3]) @ T[:3, :3])
    if not view.all_visible:
        hidden = np.flatnonzero(~view.in_front).tolist()
        raise ValueError(f"`points_b` {hidden} are not in front of the camera at `T_desired`: no desired image")
    target = TargetFeatures((points - T[:3, 3]) @ T[:3, :3], kind="points")
    return target, target.features(view.xy)


@dataclass
class EyeInHandLoop:
    """An eye-in-hand IBVS loop built by :func:`eye_in_hand_ibvs`: the ``camera`` block, the ``law``
    (:class:`IBVSResolvedVelocity`), their chain ``controller`` (:func:`visual_servo`), the ``plant``
    (:class:`~controllers.plants.KinematicArm`, q̇ = u), the desired features ``s_d``, the vision period ``Tc`` [s]
    and the field of view ``fov`` (None: unbounded image)."""

    robot: Robot
    camera: EyeInHandCamera
    law: IBVSResolvedVelocity
    controller: Any
    plant: Any
    s_d: np.ndarray
    Tc: float
    fov: FieldOfView | None = None

    def run(self, q0: Any, t_f: float, **options: Any) -> Any:
        """``simulate`` the loop from the joint positions ``q0`` for ``t_f`` seconds (step and sampling ``Tc``);
        ``options`` go to :func:`controllers.simulation.simulate` (``backend=`` …). The result logs ``e_s``."""
        from controllers.simulation import simulate

        return simulate(self.plant, self.controller, (0.0, t_f), q0, h=self.Tc, Ts=self.Tc, **options)

    def image(self, q: Any) -> np.ndarray:
        """The noise-free image points (n, 2) (normalised coordinates; NaN where not seen) at joint positions q."""
        x, y, _, _ = self.camera.image_law(Numeric, as_vector(q, self.robot.nq, "q"))
        return np.column_stack((x, y))

    def image_error(self, res: Any) -> np.ndarray:
        """max |s − s_d| of the noise-free image at every sample of a run (NaN while a point is not seen)."""
        return np.array([np.max(np.abs(self.image(q).ravel() - self.s_d)) for q in res.q])

    def __repr__(self) -> str:
        return (f"EyeInHandLoop({self.robot.name!r}, {self.camera.n_points} points, K_s = "
                f"{np.unique(self.law.K_s).tolist()}, Tc = {self.Tc:g} s)")


def eye_in_hand_ibvs(robot: Robot, points_b: Any, T_desired: Any, *, frame: str | int | None = None,
                     camera: Any = None, image_size: tuple[float, float] | None = None, K_s: Any = 1.0,
                     Tc: float = 0.02, depth: Any = None, damping: float | None = 1e-2, noise: float = 0.0,
                     rng: np.random.Generator | None = None, lost: dict[int, tuple[float, float]] | None = None,
                     dofs: Sequence[int] | None = None) -> EyeInHandLoop:
    """Resolved-velocity IBVS (Fig. 10.17) of a camera on ``frame`` of ``robot`` (default: its end effector, z the
    optical axis) looking at the points ``points_b`` (n, 3, base frame), to bring their image to the one seen from
    the desired camera pose ``T_desired`` (4×4, base frame): builds the :class:`EyeInHandCamera`, the desired point
    features (:func:`desired_point_features`), the law q̇_r = J_L^† K_s e_s, its chain at the vision period ``Tc``
    and the kinematic plant. ``camera`` (a :class:`rigid_body.camera.PinholeCamera`) with ``image_size`` (width,
    height) [pixel] bounds the field of view (points outside are not seen); ``depth`` None uses the measured depths,
    a number a constant one (e.g. the desired depth); ``damping`` λ of the damped least squares (None: the plain
    pseudo-inverse, refused near a singular J_L); ``noise`` σ [normalised units] with ``rng``, ``lost`` = {point:
    (t_from, t_to)} an occlusion; ``dofs`` the camera-twist components commanded (default: all it moves along).

    >>> import numpy as np
    >>> from rigid_body.robots import load
    >>> from rigid_body.kinematics import direct_kinematics
    >>> panda = load("panda")
    >>> q_d = panda.configurations["ready"]
    >>> T_d = direct_kinematics(panda, q_d, "panda_hand")                 # the hand camera looks down along z
    >>> square = T_d[:3, 3] + 0.5 * T_d[:3, 2] + 0.1 * np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]) @ T_d[:3, :3].T
    >>> loop = eye_in_hand_ibvs(panda, square, T_d, frame="panda_hand", K_s=2.0)
    >>> res = loop.run(q_d + 0.1, 4.0)                                  # from 0.1 rad off at every joint
    >>> bool(loop.image_error(res)[-1] < 1e-3)
    True
    """
    from controllers.plants import KinematicArm

    fov = None
    if camera is not None:
        if image_size is None:
            raise ValueError("`image_size` (width, height) [pixel] is required with `camera`: it bounds the field of view")
        fov = camera.field_of_view(*image_size)
    elif image_size is not None:
        raise ValueError("`image_size` needs `camera` (a PinholeCamera) to give its field of view")
    target, s_d = desired_point_features(T_desired, points_b)
    Tc = as_positive(Tc, "Tc")
    sensor = EyeInHandCamera(robot, points_b, frame, fov=fov, noise=noise, rng=rng, lost=lost)
    law = IBVSResolvedVelocity(robot, target, s_d, K_s, depth=depth, frame=frame, dofs=dofs, damping=damping)
    return EyeInHandLoop(robot, sensor, law, visual_servo(sensor, law, Tc), KinematicArm(), s_d, Tc, fov)
