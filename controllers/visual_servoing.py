"""Visual servoing (Chapter 10): a camera on the robot, pose estimation, PBVS, IBVS, 2½-D errors.

The blocks are the ones of the book's Simulink schemes, as small callables ``(t, measurement) -> output``
that :func:`controllers.simulation.simulate` runs at their own periods:

* :class:`EyeInHandCamera` — the sensor: from the arm's ``meas.q`` it computes the view of the target
  (:class:`CameraImage`, image points, visibility, noise) — features are named fields, never slices;
* :class:`PoseEstimator` — pose estimation by inversion of the image Jacobian, Eqs. (10.40)–(10.41), a
  discrete (Euler) estimator at its own period T: x̂_{k+1} = x̂_k + T Γ(ô) L_s⁻¹ K_s (s − ŝ(x̂_k));
* :class:`PBVSPDGravity` (Fig. 10.14) and :class:`PBVSResolvedVelocity` (Fig. 10.15);
* :class:`IBVSPDGravity` (Fig. 10.16) and :class:`IBVSResolvedVelocity` (Fig. 10.17), with the depth
  of the interaction matrix known (measured), constant (the desired depth) or estimated;
* :func:`hybrid_error_jacobians` — J_p, J_o of the 2½-D scheme, Eq. (10.96).

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

from controllers.simulation import Chain, LoggedController, ZeroOrderHold
from rigid_body.camera import FieldOfView, SegmentFeatures, TargetView, segment_features, view_points
from rigid_body.dynamics import gravity_torques
from rigid_body.robots import Robot
from rigid_body.validation import as_matrix, as_positive, as_vector

SCARA_DOFS = (0, 1, 2, 5)   # v_x, v_y, v_z, ω_z: the camera twist of Example 10.3
FEATURE_KINDS = ("points", "segment")


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


def gamma_matrix(o: np.ndarray) -> np.ndarray:
    """Γ(o_{c,o}^c) (4×4) with ẋ_{c,o} = Γ [v_c^c; ω_z] for a fixed object, Eq. (10.41), 4-DOF case:
    Γ = [[−I, s_3(o)], [0ᵀ, −1]], s_3(o) = S(o) e_z = [o_y, −o_x, 0]ᵀ."""
    return np.array([[-1.0, 0.0, 0.0, o[1]], [0.0, -1.0, 0.0, -o[0]], [0.0, 0.0, -1.0, 0.0], [0.0, 0.0, 0.0, -1.0]])


def camera_jacobian(robot: Robot, q: np.ndarray, frame: int) -> np.ndarray:
    """J_c (6×n): the camera twist in the camera frame, [v_c^c; ω_c^c] = J_c q̇ = [R_cᵀ J_P; R_cᵀ J_O] q̇
    (Pinocchio's LOCAL frame Jacobian)."""
    return pin.computeFrameJacobian(robot.model, robot.data, q, frame, pin.LOCAL)


# --------------------------------------------------------------------------------------------
# The target and its features
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
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


def _points_interaction(xy: np.ndarray, z: np.ndarray) -> np.ndarray:
    """(2n×6) stack of (10.26) for trusted inputs (hot loops; the checked version is in rigid_body.camera)."""
    rows = []
    for (x, y), zi in zip(xy.tolist(), z.tolist()):
        iz = 1.0 / zi
        rows.append([-iz, 0.0, x * iz, x * y, -(1.0 + x * x), y])
        rows.append([0.0, -iz, y * iz, 1.0 + y * y, -x * y, -x])
    return np.array(rows).reshape(-1, 6)


def _segment(xy: np.ndarray) -> np.ndarray:
    """[x_m, y_m, L, α] of (10.28) for trusted inputs."""
    x1, y1, x2, y2 = xy.ravel().tolist()
    dx, dy = x2 - x1, y2 - y1
    return np.array([0.5 * (x1 + x2), 0.5 * (y1 + y2), math.hypot(dx, dy), math.atan2(dy, dx)])


def _segment_jacobian(xy: np.ndarray) -> np.ndarray:
    """∂s/∂[x1, y1, x2, y2] of (10.28) for trusted inputs (the checked version is in rigid_body.camera)."""
    x1, y1, x2, y2 = xy.ravel().tolist()
    dx, dy = x2 - x1, y2 - y1
    L2 = dx * dx + dy * dy
    L = math.sqrt(L2)
    return np.array([[0.5, 0.0, 0.5, 0.0], [0.0, 0.5, 0.0, 0.5], [-dx / L, -dy / L, dx / L, dy / L],
                     [dy / L2, -dx / L2, -dy / L2, dx / L2]])


class TargetFeatures:
    """The feature model of a target with points ``points_o`` (n, 3) in the object frame.

    ``kind = "points"``: s = [x_1, y_1, …, x_n, y_n]; ``kind = "segment"``: s = [x_m, y_m, L, α] of P_1P_2 (10.28).
    """

    def __init__(self, points_o: Any, kind: str = "segment"):
        pts = np.asarray(points_o, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3 or not np.all(np.isfinite(pts)):
            raise ValueError(f"`points_o` must be a finite (n, 3) array, got shape {pts.shape}")
        if kind not in FEATURE_KINDS:
            raise ValueError(f"`kind` must be one of {FEATURE_KINDS}, got {kind!r}")
        if kind == "segment" and len(pts) != 2:
            raise ValueError(f"segment features need exactly 2 points, got {len(pts)}")
        self.points_o, self.kind = pts, kind

    @property
    def size(self) -> int:
        return 4 if self.kind == "segment" else 2 * len(self.points_o)

    def view_from_pose(self, T_co: np.ndarray, fov: FieldOfView | None = None) -> TargetView:
        """The view of the target when the object frame is at T_co (pose in the camera frame)."""
        return view_points(self.points_o @ T_co[:3, :3].T + T_co[:3, 3], fov)

    def features(self, xy: np.ndarray) -> np.ndarray:
        """s of the image points ``xy`` (n, 2)."""
        if self.kind == "segment":
            if xy[1, 0] == xy[0, 0] and xy[1, 1] == xy[0, 1]:
                raise ValueError("the segment's end points coincide in the image: α is undefined")
            return _segment(xy)
        return xy.reshape(-1).copy()

    def interaction_matrix(self, xy: np.ndarray, z: np.ndarray) -> np.ndarray:
        """L_s (k×6) at image points ``xy`` with depths ``z`` (10.26; segments: chain rule through (10.28))."""
        L = _points_interaction(xy, z)
        return _segment_jacobian(xy) @ L if self.kind == "segment" else L

    def error(self, s_d: np.ndarray, s: np.ndarray) -> np.ndarray:
        """e_s = s_d − s, with the segment angle difference wrapped to (−π, π]."""
        e = s_d - s
        if self.kind == "segment":
            a = float(e[3])
            e[3] = math.atan2(math.sin(a), math.cos(a))
        return e


class EyeInHandCamera:
    """Sensor block: the camera on ``frame`` of ``robot`` looking at target points ``points_b`` (base frame).

    Called with the arm's measurement (``meas.q``), it returns a :class:`CameraImage`. ``noise`` adds
    zero-mean Gaussian noise of that standard deviation to the normalised coordinates (``rng`` required);
    ``fov`` marks points outside the field of view as not seen; ``lost`` = {point index: (t_from, t_to)}
    hides points over a time interval (an occlusion).
    """

    def __init__(self, robot: Robot, points_b: Any, frame: str | int | None = None, fov: FieldOfView | None = None,
                 noise: float = 0.0, rng: np.random.Generator | None = None,
                 lost: dict[int, tuple[float, float]] | None = None):
        self.robot = robot
        self.frame = robot.ee_frame if frame is None else robot.frame(frame)
        self.points_b = np.asarray(points_b, dtype=float)
        if self.points_b.ndim != 2 or self.points_b.shape[1] != 3:
            raise ValueError(f"`points_b` must have shape (n, 3), got {self.points_b.shape}")
        self.fov, self.noise = fov, as_positive(noise, "noise", allow_zero=True)
        if self.noise > 0 and rng is None:
            raise ValueError("`rng` (a numpy Generator) is required when `noise` > 0")
        self.rng, self.lost = rng, dict(lost or {})

    def pose(self, q: np.ndarray) -> np.ndarray:
        """T_c^b of the camera at q."""
        pin.framesForwardKinematics(self.robot.model, self.robot.data, q)
        M = self.robot.data.oMf[self.frame]
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = M.rotation, M.translation
        return T

    def __call__(self, t: float, meas: Any) -> CameraImage:
        pin.framesForwardKinematics(self.robot.model, self.robot.data, meas.q)
        M = self.robot.data.oMf[self.frame]
        p = (self.points_b - M.translation) @ M.rotation            # p^c = R_cᵀ (p − o_c), (5.35)
        z = p[:, 2]
        visible = z > 0
        all_in_front = visible.all()
        if all_in_front:
            xy = p[:, :2] / z[:, None]
        else:
            xy = np.full((len(z), 2), np.nan)
            xy[visible] = p[visible, :2] / z[visible, None]
        if self.fov is not None:
            visible &= self.fov.contains(xy if all_in_front else np.where(visible[:, None], xy, 0.0))
        for i, (t0, t1) in self.lost.items():
            if t0 <= t < t1:
                visible[i] = False
        if self.noise > 0:
            xy = xy + self.noise * self.rng.standard_normal(xy.shape)
        if not visible.all():
            xy[~visible] = np.nan
        return CameraImage(xy=xy, visible=visible, z=z)


# --------------------------------------------------------------------------------------------
# Pose estimation by inversion of the image Jacobian, Eqs. (10.40)–(10.41) (4-DOF case)
# --------------------------------------------------------------------------------------------

class PoseEstimator(LoggedController):
    """x̂_{c,o} ← x̂ + T Γ(ô) L_s⁻¹(ŝ) K_s (s − ŝ): the discrete estimator of Fig. 10.11 / S10.1 at period ``T``.

    ``target`` gives ŝ(x̂) and L_s(x̂) (its 4 columns v_x, v_y, v_z, ω_z, square for two points or a
    segment). Called with a measurement carrying ``image`` (:class:`CameraImage`), or directly with the
    measured feature vector ``s`` through :meth:`update`. Logs ``x_hat``, ``e_s``, ``s_hat``.
    """

    def __init__(self, target: TargetFeatures, x0: Any, K_s: Any, T: float):
        self.target, self.T = target, as_positive(T, "T")
        self.x0 = as_vector(x0, 4, "x0").copy()
        self.K_s = as_matrix(K_s, (4, 4), "K_s") if np.ndim(K_s) == 2 else float(K_s) * np.eye(4)
        if target.size != 4:
            raise ValueError(f"the inverse-Jacobian estimator needs 4 features (a square L_s), got {target.size}")
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.x_hat = self.x0.copy()

    def predicted(self, x_hat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(ŝ, L_s) at the estimate: the features and the 4×4 interaction matrix of the estimated pose."""
        x, y, z, phi = x_hat.tolist()
        c, s = math.cos(phi), math.sin(phi)
        xy, depth = [], []
        for X, Y, Z in self.target.points_o.tolist():    # p^c = o + R_z(φ) P, then (5.40)
            pz = Z + z
            if pz <= 0:
                raise ValueError(f"the estimate x̂ = {x_hat} puts target points behind the camera: diverged")
            xy.append([(c * X - s * Y + x) / pz, (s * X + c * Y + y) / pz])
            depth.append(pz)
        xy_a, z_a = np.array(xy), np.array(depth)
        L = self.target.interaction_matrix(xy_a, z_a)[:, SCARA_DOFS]
        return self.target.features(xy_a), L

    def update(self, s: np.ndarray) -> np.ndarray:
        """One step with the measured features ``s``: returns x̂_{k+1} (``x_hat`` then holds it)."""
        s_hat, L = self.predicted(self.x_hat)
        e_s = self.target.error(s, s_hat)
        try:
            v_hat = np.linalg.solve(L, self.K_s @ e_s)                       # (10.40)
        except np.linalg.LinAlgError:
            raise ValueError(f"the interaction matrix is singular at x̂ = {self.x_hat}") from None
        self.record(x_hat=self.x_hat.copy(), e_s=e_s, s_hat=s_hat)
        self.x_hat = self.x_hat + self.T * gamma_matrix(self.x_hat[:3]) @ v_hat   # (10.41), Euler
        return self.x_hat

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        """The discrete block: outputs x̂_k, then steps to x̂_{k+1} with the image of sample k (a unit
        delay, as Simulink's discrete integrator: at t = 0 the output is x̂(0))."""
        image = meas.image
        x_k = self.x_hat.copy()
        if not np.all(image.visible[:2]):
            self.record(x_hat=x_k, e_s=np.full(4, np.nan), s_hat=np.full(4, np.nan))
            return x_k                          # feature lost: the estimate is held
        self.update(self.target.features(image.xy))
        return x_k


# --------------------------------------------------------------------------------------------
# Position-based visual servoing (4-DOF, Sect. 10.7.1)
# --------------------------------------------------------------------------------------------

class _CameraLaw(LoggedController):
    def __init__(self, robot: Robot, frame: str | int | None, dofs: Sequence[int]):
        self.robot = robot
        self.frame = robot.ee_frame if frame is None else robot.frame(frame)
        self.dofs = list(dofs)

    def pbvs_jacobian(self, q: np.ndarray, x_co: np.ndarray) -> np.ndarray:
        """J_Ad = ∂x_{c,o}/∂q = Γ(o_{c,o}) [R_cᵀ J_P; ω_z rows] (4×n), 4-DOF case of (10.67)."""
        return gamma_matrix(x_co[:3]) @ camera_jacobian(self.robot, q, self.frame)[SCARA_DOFS, :]


class PBVSPDGravity(_CameraLaw):
    """u = g(q) + J_Adᵀ(K_P x̃ − K_D J_Ad q̇), x̃ = x_{d,o} − x̂_{c,o} (Fig. 10.14), reading ``meas.q``,
    ``meas.qd`` and the estimate ``meas.estimate``. Logs ``x_tilde``."""

    def __init__(self, robot: Robot, x_do: Any, K_P: Any, K_D: Any, frame: str | int | None = None):
        super().__init__(robot, frame, SCARA_DOFS)
        self.x_do = as_vector(x_do, 4, "x_do")
        self.K_P = np.diag(as_vector(K_P, 4, "K_P"))
        self.K_D = np.diag(as_vector(K_D, 4, "K_D"))

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        x_hat = meas.estimate
        J = self.pbvs_jacobian(meas.q, x_hat)
        x_tilde = self.x_do - x_hat
        x_tilde[3] = np.arctan2(np.sin(x_tilde[3]), np.cos(x_tilde[3]))
        self.record(x_tilde=x_tilde)
        return gravity_torques(self.robot, meas.q) + J.T @ (self.K_P @ x_tilde - self.K_D @ (J @ meas.qd))


class PBVSResolvedVelocity(_CameraLaw):
    """q̇_r = J_Ad⁻¹ K x̃ (Fig. 10.15): x̃̇ = −K x̃ for a robot that follows its velocity reference."""

    def __init__(self, robot: Robot, x_do: Any, K: Any, frame: str | int | None = None):
        super().__init__(robot, frame, SCARA_DOFS)
        self.x_do = as_vector(x_do, 4, "x_do")
        self.K = np.diag(as_vector(K, 4, "K"))

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        x_hat = meas.estimate
        x_tilde = self.x_do - x_hat
        x_tilde[3] = np.arctan2(np.sin(x_tilde[3]), np.cos(x_tilde[3]))
        self.record(x_tilde=x_tilde)
        try:
            return np.linalg.solve(self.pbvs_jacobian(meas.q, x_hat), self.K @ x_tilde)
        except np.linalg.LinAlgError:
            raise ValueError(f"J_Ad is singular at q = {meas.q} (t = {t:.4g} s)") from None


# --------------------------------------------------------------------------------------------
# Image-based visual servoing (Sect. 10.7.2)
# --------------------------------------------------------------------------------------------

class _IBVSLaw(_CameraLaw):
    """Shared part of the IBVS laws: e_s = s_d − s and J_L = L̂_s(s, ẑ)[:, dofs] J_c[dofs] from ``meas.image``.

    ``depth``: a number = the same depth for every point (e.g. the desired one, z_d); None = the measured
    depths (known depth); a function ``image -> z (n,)`` = an estimate (e.g. :func:`depth_from_segment`). Points not seen drop their rows (point features); with too few rows left the
    damped least-squares inverse keeps the law defined, and with none the command is zero.
    """

    damping = 1e-4

    def __init__(self, robot: Robot, target: TargetFeatures, s_d: Any, depth: Any,
                 frame: str | int | None, dofs: Sequence[int]):
        super().__init__(robot, frame, dofs)
        self.target = target
        self.s_d = as_vector(s_d, target.size, "s_d")
        if depth is None or callable(depth):
            self.depth = depth
        else:
            self.depth = as_positive(depth, "depth")

    def error_and_jacobian(self, q: np.ndarray, image: CameraImage) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(e_s, J_L, rows used) at the current image; rows of unseen points are removed."""
        Jc = camera_jacobian(self.robot, q, self.frame)
        seen = image.visible
        if self.depth is None:
            z = image.z
        elif callable(self.depth):
            z = self.depth(image)
        else:
            z = np.full(len(seen), self.depth)
        if self.target.kind == "segment":
            if not (seen[0] and seen[1]):
                return np.zeros(0), np.zeros((0, len(q))), np.zeros(0, dtype=int)
            rows = np.arange(4)
            s = self.target.features(image.xy)
            L = self.target.interaction_matrix(image.xy, z)
        else:
            rows = np.flatnonzero(np.repeat(seen, 2))
            s = image.xy.reshape(-1)[rows]
            L = _points_interaction(image.xy[seen], z[seen])
        e = self.target.error(self.s_d, s) if self.target.kind == "segment" else self.s_d[rows] - s
        return e, L[:, self.dofs] @ Jc[self.dofs, :], rows

    def inverse(self, J: np.ndarray) -> np.ndarray:
        """J⁻¹ when J is square and well conditioned, else the damped least-squares inverse (3.59)."""
        if J.shape[0] == J.shape[1] and np.linalg.cond(J) < 1e8:
            return np.linalg.inv(J)
        return J.T @ np.linalg.inv(J @ J.T + self.damping * np.eye(J.shape[0]))


class IBVSPDGravity(_IBVSLaw):
    """u = g(q) + J_Lᵀ(K_Ps e_s − K_Ds J_L q̇), e_s = s_d − s (Fig. 10.16). Logs ``e_s``."""

    def __init__(self, robot: Robot, target: TargetFeatures, s_d: Any, K_Ps: Any, K_Ds: Any,
                 depth: Any = None, frame: str | int | None = None, dofs: Sequence[int] = SCARA_DOFS):
        super().__init__(robot, target, s_d, depth, frame, dofs)
        self.K_Ps = as_vector(K_Ps, target.size, "K_Ps")
        self.K_Ds = as_vector(K_Ds, target.size, "K_Ds")

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        e, J, rows = self.error_and_jacobian(meas.q, meas.image)
        self.record(e_s=_full(e, rows, self.target.size))
        return gravity_torques(self.robot, meas.q) + J.T @ (self.K_Ps[rows] * e - self.K_Ds[rows] * (J @ meas.qd))


class IBVSResolvedVelocity(_IBVSLaw):
    """q̇_r = J_L⁻¹ K_s e_s (Fig. 10.17; damped least-squares inverse when J_L is not square): ė_s = −K_s e_s."""

    def __init__(self, robot: Robot, target: TargetFeatures, s_d: Any, K_s: Any, depth: Any = None,
                 frame: str | int | None = None, dofs: Sequence[int] = SCARA_DOFS):
        super().__init__(robot, target, s_d, depth, frame, dofs)
        self.K_s = as_vector(K_s, target.size, "K_s") if np.ndim(K_s) else np.full(target.size, float(K_s))

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        e, J, rows = self.error_and_jacobian(meas.q, meas.image)
        self.record(e_s=_full(e, rows, self.target.size))
        if rows.size == 0:
            return np.zeros(len(meas.q))        # nothing seen: stop and wait
        return self.inverse(J) @ (self.K_s[rows] * e)


def depth_from_segment(length: float) -> Any:
    """A depth estimate for a segment of known ``length`` [m] parallel to the image plane: z ≈ ℓ/L, with L
    the segment's image length (10.28) — both end points get it (NaN when an end point is not seen)."""
    length = as_positive(length, "length")

    def estimate(image: CameraImage) -> np.ndarray:
        d = image.xy[1] - image.xy[0]
        return np.full(len(image.visible), length / math.hypot(d[0], d[1]))

    return estimate


def _full(e: np.ndarray, rows: np.ndarray, size: int) -> np.ndarray:
    out = np.full(size, np.nan)
    out[rows] = e
    return out


def visual_servo(camera: EyeInHandCamera, law: Any, Tc: float, estimator: PoseEstimator | None = None) -> Chain:
    """The controller of an eye-in-hand loop: camera → [pose estimator at the loop's period →] law held
    over ``Tc`` (the vision/controller period). The law reads ``meas.image`` and, after an estimator,
    ``meas.estimate``; ``simulate(..., Ts=estimator period)`` runs it."""
    inner: Any = ZeroOrderHold(law, Tc)
    if estimator is not None:
        inner = Chain(estimator, inner, name="estimate")
    return Chain(camera, inner, name="image")


# --------------------------------------------------------------------------------------------
# Hybrid (2½-D) visual servoing, Eq. (10.96)
# --------------------------------------------------------------------------------------------

def hybrid_error_jacobians(x: float, y: float, z_c: float) -> tuple[np.ndarray, np.ndarray]:
    """(J_p, J_o) with ė_p = J_p v_c^c + J_o ω_c^c for e_p = [x − x_d, y − y_d, ln(z_c/z_d)] (10.96):
    J_p = (1/z_c)[[−1, 0, x], [0, −1, y], [0, 0, −1]], J_o = [[xy, −1−x², y], [1+y², −xy, −x], [−y, x, 0]]
    (z_d ρ_z = z_c, Problem 10.13)."""
    z_c = as_positive(z_c, "z_c")
    J_p = np.array([[-1.0, 0.0, x], [0.0, -1.0, y], [0.0, 0.0, -1.0]]) / z_c
    J_o = np.array([[x * y, -1.0 - x * x, y], [1.0 + y * y, -x * y, -x], [-y, x, 0.0]])
    return J_p, J_o
