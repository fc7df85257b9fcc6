"""Task space: the frame state, pose errors, kinematic inverses and operational → joint references.

One home for what inverse kinematics (Sect. 3.7) and operational-space control (Sect. 8.6,
Chapters 9–10) share:

* :func:`frame_state` — (T, J, J̇q̇) of a frame in one kinematics pass: the pose T(q) (2.50), the
  geometric Jacobian J = [J_P; J_O] (3.30, book convention = Pinocchio LOCAL_WORLD_ALIGNED) and
  J̇(q, q̇) q̇, the frame acceleration at q̈ = 0 (second-order kinematics (3.98)).
* :class:`TaskSpace`, :func:`pose_error`, :func:`pose_residual` — the controlled components and the
  error e = [p_d − p_e; e_O] with an orientation error of Sect. 3.7.3: Euler angles φ_d − φ_e with the
  analytical Jacobian J_A = T_A⁻¹(φ) J (3.66), angle–axis e_O = r sin ϑ (3.85) (with L of (3.87)) or
  unit quaternion e_O = η_e ε_d − η_d ε_e − S(ε_d) ε_e (3.91); both of the latter with the geometric
  Jacobian.
* :func:`damped_least_squares_inverse` (3.59) and :func:`weighted_pseudo_inverse` (3.50)/(3.52).
* :func:`selection_matrices`, :func:`selection_pseudo_inverse` (9.55), :func:`selection_projection`
  (P_f, P_v) — the natural/artificial constraints of a force/motion task (Sects. 9.5–9.6);
  :func:`contact_wrenches` and :func:`reciprocal_basis` derive them from a contact model (the twists a
  pair of bodies admits and the wrenches its contacts exert, each the reciprocal complement of the other).
* :func:`relative_position_rate`, :func:`relative_euler_rate` — the end-effector motion w.r.t. a
  desired frame, Eqs. (9.10)–(9.11).
* :func:`joint_rates` — q̇ = J⁻¹ ẋ, q̈ = J⁻¹ (ẍ − J̇ q̇) (3.51 and 3.99 inverted) and
  :func:`joint_reference`, the operational path → joint reference (q_d, q̇_d, q̈_d)(t) with a
  closed-form inverse kinematics for q_d.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 2.12, 3.1–3.7 (Eqs. (3.30), (3.50)–(3.59), (3.66), (3.84)–(3.99)), 9.2, 9.5–9.6
(Eqs. (9.10), (9.11), (9.55)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np
import pinocchio as pin
from scipy.linalg.lapack import dgesv as _gesv

from rigid_body.kinematics import batch_inverse_kinematics
from rigid_body.robots import Robot, revolute_joints
from rigid_body.rotations import (axis_angle_error_kernel, euler_rate_matrix_rpy, euler_rate_matrix_zyz, orientation_error_quaternion,
                                  orientation_error_matrix_kernel, rotation_to_euler_zyz, rotation_to_quaternion,
                                  rotation_to_rpy, wrap_angle)
from rigid_body.validation import as_matrix, as_points, as_vector

__all__ = [
    "ORIENTATIONS",
    "FrameState",
    "frame_state",
    "frame_state_kernel",
    "TaskSpace",
    "PoseError",
    "orientation_error",
    "pose_error",
    "pose_error_kernel",
    "pose_residual",
    "damped_least_squares_inverse",
    "weighted_pseudo_inverse",
    "SINGULAR_CONDITION",
    "RATE_CONDITION",
    "resolved_rates",
    "solve_task",
    "singular_task",
    "joint_rates",
    "joint_reference",
    "TWIST_AXES",
    "selection_pseudo_inverse",
    "selection_projection",
    "selection_matrices",
    "contact_wrenches",
    "reciprocal_basis",
    "relative_position_rate",
    "relative_euler_rate",
]

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
ORIENTATIONS = ("none", "axis_angle", "quaternion", "euler_zyz", "rpy")


# --------------------------------------------------------------------------------------------
# The frame state (T, J, J̇q̇) in one pass
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class FrameState:
    """Kinematic state of a frame at (q, q̇): ``T`` (4, 4) pose in the base frame (2.50), ``J`` (6, nv)
    geometric Jacobian [J_P; J_O] (3.30) and ``Jdot_qd`` (6,) = J̇ q̇ = [p̈; ω̇] at q̈ = 0 (the linear
    part is the classical acceleration of the origin), None when q̇ was not given."""

    T: np.ndarray
    J: np.ndarray
    Jdot_qd: np.ndarray | None


def frame_state_kernel(model: pin.Model, data: pin.Data, fid: int, q: np.ndarray,
                 qd: np.ndarray | None) -> FrameState:
    """The unvalidated kernel of :func:`frame_state` (hot loops: controllers at 1 kHz, CLIK)."""
    if qd is None:
        pin.computeJointJacobians(model, data, q)                     # also the forward kinematics
    else:
        pin.forwardKinematics(model, data, q, qd, _zero_acceleration(model.nv))
        pin.computeJointJacobians(model, data)                        # from the placements just computed
    T = pin.updateFramePlacement(model, data, fid).homogeneous        # a fresh array
    J = pin.getFrameJacobian(model, data, fid, LWA)
    if qd is None:
        return FrameState(T, J, None)
    a = pin.getFrameClassicalAcceleration(model, data, fid, LWA)
    return FrameState(T, J, a.vector.copy())      # [linear; angular], copied while ``a`` (its owner) lives


_ZERO_ACCELERATIONS: dict[int, np.ndarray] = {}


def _zero_acceleration(nv: int) -> np.ndarray:
    """q̈ = 0 (nv,), read-only and shared (the forward kinematics of :func:`frame_state_kernel` only reads it)."""
    zero = _ZERO_ACCELERATIONS.get(nv)
    if zero is None:
        zero = _ZERO_ACCELERATIONS[nv] = np.zeros(nv)
        zero.setflags(write=False)
    return zero


def frame_state(robot: Robot, q: Any, qd: Any = None, frame: str | int | None = None) -> FrameState:
    """(T, J, J̇q̇) of ``frame`` (default the end effector) at (q, q̇) with one kinematics pass.

    Equals :func:`~rigid_body.kinematics.direct_kinematics`, :func:`~rigid_body.kinematics.geometric_jacobian`
    and :func:`~rigid_body.kinematics.jacobian_derivative_times_qd`, each of which runs its own pass.
    """
    q = as_vector(q, robot.nq, "q")
    qd = None if qd is None else as_vector(qd, robot.nv, "qd")
    return frame_state_kernel(robot.model, robot.data, robot.frame(frame), q, qd)


# --------------------------------------------------------------------------------------------
# Task space and pose errors (Sect. 3.7.3)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class TaskSpace:
    """The controlled quantities of a frame.

    Attributes
    ----------
    frame : the frame (name or id; None = the robot's end effector).
    orientation : ``"none"`` (position only), ``"axis_angle"`` (3.85), ``"quaternion"`` (3.91),
        ``"euler_zyz"`` or ``"rpy"`` (φ_d − φ_e with the analytical Jacobian (3.66)).
    rows : indices (into the 6 components [position; orientation]) that are controlled;
        default all 6, or the 3 position rows when ``orientation="none"``. E.g. (0, 1) for the
        planar position of Problem 3.21, (0, 1, 2, 3) for [p; φ] of the SCARA in Problem 3.22.
    """

    frame: str | int | None = None
    orientation: str = "axis_angle"
    rows: tuple[int, ...] | None = None

    def __post_init__(self):
        if self.orientation not in ORIENTATIONS:
            raise ValueError(f"`orientation` must be one of {ORIENTATIONS}, got {self.orientation!r}")
        rows = self.selected
        if len(rows) == 0 or len(set(rows)) != len(rows) or not all(0 <= r < 6 for r in rows):
            raise ValueError(f"`rows` must be distinct indices in 0..5, got {self.rows}")
        if self.orientation == "none" and any(r >= 3 for r in rows):
            raise ValueError("`rows` may only select position rows (0..2) when orientation='none'")

    @property
    def selected(self) -> tuple[int, ...]:
        """The controlled rows (indices into [position; orientation])."""
        if self.rows is not None:
            return tuple(int(r) for r in self.rows)
        return (0, 1, 2) if self.orientation == "none" else tuple(range(6))

    @property
    def euler(self) -> bool:
        """True for an Euler-angle orientation (analytical Jacobian), False for the geometric one."""
        return self.orientation in ("euler_zyz", "rpy")


@dataclass(frozen=True)
class PoseError:
    """Errors and Jacobians of a task at one configuration (all restricted to the task rows).

    ``e`` the error (3.68 style), ``J`` the task Jacobian (geometric or analytical),
    ``feedforward`` the desired task velocity (ẋ_d), ``L`` the (3.87) matrix for angle–axis, else None,
    ``T_e`` the frame pose, ``Jdot_qd`` J̇q̇ of the task rows (geometric Jacobian only; None when q̇
    was not given).
    """

    e: np.ndarray
    J: np.ndarray
    feedforward: np.ndarray
    L: np.ndarray | None
    T_e: np.ndarray
    Jdot_qd: np.ndarray | None = None


def orientation_error(R_d: np.ndarray, R_e: np.ndarray, orientation: str = "quaternion") -> np.ndarray:
    """e_O (3,) of R_e w.r.t. R_d: ``"axis_angle"`` r sin ϑ (3.85), ``"quaternion"`` (3.91) with Q_d
    and Q_e in the same hemisphere (η_d η_e + ε_dᵀ ε_e ≥ 0: e_O = r sin(ϑ/2), R_d R_eᵀ = R(ϑ, r), ϑ ≤ π),
    ``"euler_zyz"``/``"rpy"`` φ_d − φ_e (wrapped), ``"none"`` zeros. Unvalidated rotations."""
    if orientation == "axis_angle":
        return axis_angle_error_kernel(R_d, R_e)
    if orientation == "quaternion":
        Q_d, Q_e = rotation_to_quaternion(R_d), rotation_to_quaternion(R_e)
        if Q_d @ Q_e < 0.0:  # same R_d, other sign: the error of the short way round, e_O = r sin(ϑ/2), ϑ ≤ π
            Q_d = -Q_d
        return orientation_error_quaternion(Q_d, Q_e)
    if orientation in ("euler_zyz", "rpy"):
        extract = rotation_to_euler_zyz if orientation == "euler_zyz" else rotation_to_rpy
        return wrap_angle(extract(R_d).angles - extract(R_e).angles)
    if orientation == "none":
        return np.zeros(3)
    raise ValueError(f"`orientation` must be one of {ORIENTATIONS}, got {orientation!r}")


def pose_error(robot: Robot, q: np.ndarray, T_d: np.ndarray, v_d: np.ndarray | None = None,
               task: TaskSpace = TaskSpace(), qd: np.ndarray | None = None) -> PoseError:
    """Position and orientation error of ``task``'s frame at ``q`` w.r.t. the desired pose ``T_d``.

    ``v_d`` = [ṗ_d; ω_d] (6,) is the desired velocity (default 0); for Euler-angle errors the
    feed-forward is [ṗ_d; T^{-1}(φ_d) ω_d] and the Jacobian is the analytical one, Eq. (3.66).
    With ``qd`` the same kinematics pass also gives J̇q̇ (geometric Jacobian tasks only).
    Unvalidated (hot loop): q (nq,), T_d (4, 4) homogeneous.
    """
    return pose_error_kernel(robot.model, robot.data, robot.frame(task.frame), q, T_d, task, qd, v_d)


def pose_error_kernel(model: pin.Model, data: pin.Data, fid: int, q: np.ndarray, T_d: np.ndarray,
                      task: TaskSpace = TaskSpace(), qd: np.ndarray | None = None,
                      v_d: np.ndarray | None = None) -> PoseError:
    """The kernel of :func:`pose_error` on a model, its data and a resolved frame id (hot loops)."""
    if qd is not None and task.euler:
        raise ValueError("J̇_A q̇ of an Euler-angle task is not provided: use 'axis_angle' or 'quaternion'")
    state = frame_state_kernel(model, data, fid, q, qd)
    J, T_e = state.J, state.T
    R_e, p_e = T_e[:3, :3], T_e[:3, 3]
    R_d, p_d = T_d[:3, :3], T_d[:3, 3]
    v_d = np.zeros(6) if v_d is None else v_d
    e = np.empty(6)
    e[:3] = p_d - p_e
    ff = np.array(v_d, dtype=float)
    L = None
    kind = task.orientation
    if kind == "axis_angle":
        e[3:] = axis_angle_error_kernel(R_d, R_e)                            # Eq. (3.85)
        L = orientation_error_matrix_kernel(R_d, R_e)                        # Eq. (3.87)
    elif kind == "quaternion":
        e[3:] = orientation_error(R_d, R_e, kind)                      # Eq. (3.91)
    elif task.euler:
        extract, T_of = ((rotation_to_euler_zyz, euler_rate_matrix_zyz) if kind == "euler_zyz"
                         else (rotation_to_rpy, euler_rate_matrix_rpy))
        phi_d, phi_e = extract(R_d), extract(R_e)
        if phi_e.singular or phi_d.singular:
            raise ValueError(f"{kind} representation singularity at the {'current' if phi_e.singular else 'desired'}"
                             " orientation: the analytical Jacobian is not defined")
        e[3:] = wrap_angle(phi_d.angles - phi_e.angles)
        J = J.copy()
        J[3:] = np.linalg.solve(T_of(phi_e.angles), J[3:])             # J_A = T_A^{-1} J, Eq. (3.66)
        ff[3:] = np.linalg.solve(T_of(phi_d.angles), v_d[3:])          # φ̇_d = T^{-1}(φ_d) ω_d
    else:
        e[3:] = 0.0
    rows = list(task.selected)
    Jdq = None if state.Jdot_qd is None else state.Jdot_qd[rows]
    return PoseError(e[rows], J[rows], ff[rows], L, T_e, Jdq)


def pose_residual(T_d: np.ndarray, T_e: np.ndarray, task: TaskSpace = TaskSpace(),
                  e: np.ndarray | None = None) -> float:
    """The IK residual: max(‖p_d − p_e‖ over the task's position rows, orientation error).

    The orientation error is the rotation angle of R_e^T R_d when the three orientation rows are
    controlled, otherwise max |e_i| over the task's orientation rows of the error ``e`` (required then).
    """
    rows = task.selected
    pos = [r for r in rows if r < 3]
    res = float(np.linalg.norm((T_d[:3, 3] - T_e[:3, 3])[pos])) if pos else 0.0
    ori = [i for i, r in enumerate(rows) if r >= 3]
    if task.orientation == "none" or not ori:
        return res
    if len(ori) == 3:
        return max(res, float(np.linalg.norm(pin.log3(T_e[:3, :3].T @ T_d[:3, :3]))))
    if e is None:
        raise ValueError("`e` is required for the residual of a partial orientation task")
    return max(res, float(np.max(np.abs(np.asarray(e)[ori]))))


# --------------------------------------------------------------------------------------------
# Generalised inverses (3.50)–(3.59)
# --------------------------------------------------------------------------------------------

def _finite_jacobian(J: Any) -> np.ndarray:
    J = np.asarray(J, dtype=float)
    if J.ndim != 2 or not np.isfinite(J).all():
        raise ValueError(f"`J` must be a finite 2-D Jacobian, got shape {J.shape}")
    return J


def damped_least_squares_inverse(J: Any, k: float) -> np.ndarray:
    """J* = J^T (J J^T + k² I)^{-1}, the damped least-squares inverse, Eq. (3.59) / Problem 3.10."""
    J = _finite_jacobian(J)
    if not (np.isfinite(k) and k >= 0):
        raise ValueError(f"`k` must be finite and >= 0, got {k}")
    return J.T @ np.linalg.solve(J @ J.T + k * k * np.eye(J.shape[0]), np.eye(J.shape[0]))


def weighted_pseudo_inverse(J: Any, W: Any = None) -> np.ndarray:
    """J† = W^{-1} J^T (J W^{-1} J^T)^{-1}, Eq. (3.50) (right pseudo-inverse (3.52) for W = I).

    ValueError when J J^T is singular (J has not full row rank).
    """
    J = _finite_jacobian(J)
    Wi = np.eye(J.shape[1]) if W is None else np.linalg.inv(as_matrix(W, (J.shape[1],) * 2, "W"))
    A = J @ Wi @ J.T
    if np.linalg.cond(A) > 1e12:
        raise ValueError("`J` is (close to) singular: J W^-1 J^T is not invertible; use the DLS inverse")
    return Wi @ J.T @ np.linalg.inv(A)


# --------------------------------------------------------------------------------------------
# Operational motion → joint motion (inverse differential kinematics, (3.51), (3.99))
# --------------------------------------------------------------------------------------------

def _task_inverse(J: np.ndarray) -> tuple[np.ndarray | None, np.ndarray]:
    """(J⁻¹, singular) of a square task Jacobian (n, n) or of a stack (N, n, n): one SVD gives both the
    singularity test (σ_min ≤ 1e-12 σ_max, or NaN) and J⁻¹ = V Σ⁻¹ Uᵀ (None when any is singular)."""
    U, s, Vt = np.linalg.svd(J)
    singular = ~(s[..., -1] > 1e-12 * s[..., 0])
    if singular.any():
        return None, singular
    return (np.swapaxes(Vt, -1, -2) / s[..., None, :]) @ np.swapaxes(U, -1, -2), singular


SINGULAR_CONDITION = 1e10  # cond(J_A) above which the task is treated as singular
_IDENTITY = tuple(np.eye(m) for m in range(7))   # I_m of the task sizes m ≤ 6 (read by solve_task)


def solve_task(J: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """J_A⁻¹ b (square J_A) or the minimum-norm J_A† b = J_Aᵀ (J_A J_Aᵀ)⁻¹ b (3.52) for a redundant task;
    None at (or numerically at) a kinematic singularity, cond(J_A) > 1e10.

    Hot loop: one LAPACK gesv solves A x = b and A X = I together (A = J_A, or J_A J_Aᵀ whose condition
    number is cond(J_A)²); cond₂(A) ≤ ‖A‖_F ‖A⁻¹‖_F, so below the threshold the SVD is skipped — it
    decides only when that bound is not conclusive."""
    square = J.shape[0] == J.shape[1]
    if square and J.shape[0] == 3:
        x = _solve3(J, b)
        if x is not None:
            return x
    A = J if square else J @ J.T
    m = A.shape[0]
    rhs = np.empty((m, m + 1), order="F")        # LAPACK's layout: gesv works in it without a copy
    rhs[:, 0] = b
    rhs[:, 1:] = _IDENTITY[m] if m < len(_IDENTITY) else np.eye(m)
    _, _, X, info = _gesv(A, rhs, overwrite_b=True)
    limit = SINGULAR_CONDITION if square else SINGULAR_CONDITION**2
    inverse = X[:, 1:].T                         # gesv returns Fortran order: the transpose is contiguous
    if info != 0 or not math.sqrt(np.vdot(A, A) * np.vdot(inverse, inverse)) < limit:
        s = np.linalg.svd(J, compute_uv=False)
        if info != 0 or s[-1] <= s[0] / SINGULAR_CONDITION:
            return None
    return X[:, 0] if square else J.T @ X[:, 0]


def _solve3(J: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """J⁻¹ b = adj(J) b / det J for a 3 × 3 task (the planar arms' (x, y, φ)) on Python floats, a third of
    the cost of the LAPACK call; None when cond_F(J) = ‖J‖_F ‖J⁻¹‖_F does not show cond(J) ≤ 1e10 (the
    general path then decides)."""
    (a, b1, c), (d, e, f), (g, h, i) = J.tolist()
    A, B, C = e * i - f * h, f * g - d * i, d * h - e * g           # cofactors: adj(J) = their transpose
    D, E, F = c * h - b1 * i, a * i - c * g, b1 * g - a * h
    G, H, I = b1 * f - c * e, c * d - a * f, a * e - b1 * d
    det = a * A + b1 * B + c * C
    norm_J = a * a + b1 * b1 + c * c + d * d + e * e + f * f + g * g + h * h + i * i
    norm_adj = A * A + B * B + C * C + D * D + E * E + F * F + G * G + H * H + I * I
    if not math.sqrt(norm_J * norm_adj) < SINGULAR_CONDITION * abs(det):
        return None
    r0, r1, r2 = b.tolist()
    return np.array([(A * r0 + D * r1 + G * r2) / det, (B * r0 + E * r1 + H * r2) / det,
                     (C * r0 + F * r1 + I * r2) / det])


RATE_CONDITION = 1e3
"""cond(J) above which a resolved-velocity law q̇ = J⁻¹ K e refuses to invert J (:func:`resolved_rates`): near a
singular posture a bounded error asks for joint rates of cond(J) times their usual size (1e3: three orders
of magnitude; the exactly singular case of :data:`SINGULAR_CONDITION` is far beyond any physical rate)."""


def resolved_rates(J: np.ndarray, b: np.ndarray, where: str, max_condition: float = RATE_CONDITION,
                   damping: float | None = None, rank: int | None = None) -> np.ndarray:
    """q̇ = J⁻¹ b (square J), else J† b (minimum-norm least squares): the joint rates of a resolved-velocity law,
    refused near a singular posture.

    ``rank``: the rank J has away from singularities (default min of its sizes; less when it is structurally
    deficient, e.g. L_s J_c of 8 point features on a 7-joint arm has rank 6): J† then keeps its ``rank``
    largest singular values. ``damping`` None: ValueError when σ_1/σ_rank > ``max_condition`` (the rates
    would be unphysical), naming ``where`` (the posture), the condition number and the remedies; ``damping``
    = λ > 0: the damped least-squares rates Jᵀ(J Jᵀ + λ² I)⁻¹ b (3.59), defined at every posture
    (|q̇| ≤ |b|/(2λ)), never refused. ValueError naming ``damping`` (not > 0), ``max_condition`` (not ≥ 1) or
    ``rank`` (not an integer in [1, min(m, n)])."""
    m, n = J.shape
    if damping is not None:
        if not (isinstance(damping, (float, int, np.floating, np.integer)) and 0.0 < damping < math.inf) \
                or isinstance(damping, bool):
            raise ValueError(f"`damping` must be a finite number > 0 (λ of the damped least squares) or None, "
                             f"got {damping!r}")
        return J.T @ np.linalg.solve(J @ J.T + damping * damping * np.eye(m), b)
    if not (isinstance(max_condition, (float, int, np.floating, np.integer)) and max_condition >= 1.0) \
            or isinstance(max_condition, bool):
        raise ValueError(f"`max_condition` must be a number >= 1 (a condition number), got {max_condition!r}")
    r = min(m, n) if rank is None else rank
    if rank is not None and (isinstance(rank, bool) or not isinstance(rank, (int, np.integer))
                             or not 1 <= rank <= min(m, n)):
        raise ValueError(f"`rank` must be an integer in [1, min(m, n) = {min(m, n)}] for a {m}×{n} J, got {rank!r}")
    if m == n == r:                              # square: one gesv gives J⁻¹ b and J⁻¹; cond₂ ≤ ‖J‖_F ‖J⁻¹‖_F
        rhs = np.empty((m, m + 1), order="F")
        rhs[:, 0] = b
        rhs[:, 1:] = np.eye(m)
        _, _, X, info = _gesv(J, rhs, overwrite_b=True)
        if info == 0 and math.sqrt(np.vdot(J, J) * np.vdot(X[:, 1:], X[:, 1:])) < max_condition:
            return X[:, 0].copy()
    U, sigma, Vt = np.linalg.svd(J, full_matrices=False)
    if not (r >= 1 and sigma.size >= r and sigma[r - 1] * max_condition > sigma[0] > 0):
        cond = sigma[0] / sigma[r - 1] if sigma.size >= r and sigma[r - 1] > 0 else math.inf
        raise ValueError(f"the Jacobian is (near) singular {where}: cond = {cond:.3g} > max_condition = "
                         f"{max_condition:g}, the joint rates would grow by that factor; move away from the "
                         "singular posture, raise `max_condition`, or pass `damping` (damped least squares, 3.59)")
    return Vt[:r].T @ ((U[:, :r].T @ b) / sigma[:r])


def singular_task(where: str) -> ValueError:
    """The error raised when the task Jacobian J_A cannot be inverted (cond(J_A) > SINGULAR_CONDITION)."""
    return ValueError(f"J_A is singular {where} (condition number > {SINGULAR_CONDITION:g}): "
                      "the task cannot be inverted")


def joint_rates(robot: Robot, q: Any, xd: Any, xdd: Any, rows: Sequence[int] = tuple(range(6)),
                frame: str | int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """q̇ = J⁻¹ ẋ (3.51 inverted) and q̈ = J⁻¹ (ẍ − J̇ q̇) (3.99) at q, J the ``rows`` of the geometric
    Jacobian of ``frame`` (a square, non-redundant task: as many rows as joints).

    ``xd``, ``xdd`` are [ṗ; ω] and [p̈; ω̇] in the ``rows`` components. ValueError at a singularity.
    """
    q = as_vector(q, robot.nq, "q")
    rows = list(rows)
    if len(rows) != robot.nv:
        raise ValueError(f"`rows` must select {robot.nv} components (a square task Jacobian), got {len(rows)}")
    xd, xdd = as_vector(xd, len(rows), "xd"), as_vector(xdd, len(rows), "xdd")
    model, data, fid = robot.model, robot.data, robot.frame(frame)
    J_inv, singular = _task_inverse(frame_state_kernel(model, data, fid, q, None).J[rows])
    if singular:
        raise ValueError(f"the task Jacobian is singular at q = {q}: J⁻¹ is not defined")
    qd = J_inv @ xd
    Jdot_qd = frame_state_kernel(model, data, fid, q, qd).Jdot_qd[rows]    # J̇ q̇ needs the q̇ just found
    return qd, J_inv @ (xdd - Jdot_qd)


def joint_reference(robot: Robot, inverse_kinematics: Callable[[np.ndarray], np.ndarray], law: Any,
                    position_rows: Sequence[int], orientation: Sequence[float], jacobian_rows: Sequence[int],
                    q_near: Any, times: Any = None) -> Callable[[float], tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Joint reference (q_d, q̇_d, q̈_d)(t) of an operational motion with constant orientation.

    q_d: closed-form IK of ``[p[position_rows], *orientation]``, the solution nearest to the previous
    one (starting from ``q_near``; revolute joints shifted by 2π to it); q̇_d, q̈_d by
    :func:`joint_rates` with J the ``jacobian_rows`` of the geometric Jacobian — square for a
    non-redundant task (e.g. x, y, ω_z of a planar three-link arm). ``law`` is ``t -> (p, ṗ, p̈)``.

    ``times`` (the controller's sample instants, increasing): the reference is open loop, so it is
    computed there before the loop in one pass (``law`` at all the times, the vectorised IK of
    :func:`~rigid_body.kinematics.batch_inverse_kinematics` when the solver has one, the same nearest
    branch, :func:`joint_rates_at`); the returned function reads the rows at those instants and
    solves per sample elsewhere (starting from the row of the nearest instant).
    """
    rows = list(position_rows)
    jrows = list(jacobian_rows)
    phi = np.asarray(orientation, dtype=float)
    n_o = phi.size
    if len(jrows) != robot.nv or len(rows) + n_o != len(jrows):
        raise ValueError(f"the task must be square: {len(rows)} positions + {n_o} orientations vs "
                         f"{len(jrows)} Jacobian rows for {robot.nv} joints")
    last = [as_vector(q_near, robot.nq, "q_near").copy()]
    revolute = revolute_joints(robot)
    zero = np.zeros(n_o)

    def nearest(q: np.ndarray) -> np.ndarray:
        """The 2π-equivalent of q (revolute joints only) closest to the previous reference."""
        d = q - last[0]
        d[..., revolute] = wrap_angle(d[..., revolute])
        return last[0] + d

    def reference(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        p, pd, pdd = (np.asarray(v, dtype=float) for v in law(t))
        sols = nearest(np.atleast_2d(inverse_kinematics(np.concatenate([p[rows], phi]))))
        q = sols[np.argmin(np.linalg.norm(sols - last[0], axis=1))]
        last[0] = q
        qd, qdd = joint_rates(robot, q, np.concatenate([pd[rows], zero]), np.concatenate([pdd[rows], zero]), jrows)
        return q, qd, qdd

    if times is None:
        return reference
    ts = as_vector(times, None, "times")
    if ts.size == 0 or np.any(np.diff(ts) <= 0):
        raise ValueError("`times` must be a non-empty increasing vector of sample instants")
    P, Pd, Pdd = (np.asarray(v, dtype=float).reshape(ts.size, -1) for v in law(ts))
    N = ts.size
    X = np.column_stack([P[:, rows], np.broadcast_to(phi, (N, n_o))])
    batch = batch_inverse_kinematics(inverse_kinematics)
    if batch is not None:
        Q_all, valid = batch(X)
        candidates = [Q_all[k][valid[k]] for k in range(N)]
    else:
        candidates = [np.atleast_2d(inverse_kinematics(x)) for x in X]
    Q = np.empty((N, robot.nq))
    for k, sols in enumerate(candidates):                 # the branch nearest the previous one, as above
        sols = nearest(sols)
        last[0] = Q[k] = sols[np.argmin(np.linalg.norm(sols - last[0], axis=1))]
    zeros = np.zeros((N, n_o))
    Qd, Qdd = joint_rates_at(robot, Q, np.hstack([Pd[:, rows], zeros]), np.hstack([Pdd[:, rows], zeros]), jrows)
    t0, span = ts[0], ts[-1] - ts[0]
    step = span / (N - 1) if N > 1 else 1.0

    def sampled(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        k = min(max(int(round((t - t0) / step)), 0), N - 1)
        if abs(ts[k] - t) <= 1e-9 * step:
            return Q[k], Qd[k], Qdd[k]
        last[0] = Q[k]
        return reference(t)

    return sampled


def joint_rates_at(robot: Robot, Q: Any, XD: Any, XDD: Any, rows: Sequence[int] = tuple(range(6)),
                   frame: str | int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`joint_rates` at N configurations Q (N, n) with task rates XD, XDD (N, len(rows)):
    (Q̇, Q̈) each (N, n). ValueError naming the first singular sample."""
    rows = list(rows)
    N = len(Q)
    Q = as_matrix(Q, (N, robot.nq), "Q")
    if len(rows) != robot.nv:
        raise ValueError(f"`rows` must select {robot.nv} components (a square task Jacobian), got {len(rows)}")
    XD, XDD = as_matrix(XD, (N, len(rows)), "XD"), as_matrix(XDD, (N, len(rows)), "XDD")
    model, data, fid = robot.model, robot.data, robot.frame(frame)
    J_inv, singular = _task_inverse(np.array([frame_state_kernel(model, data, fid, q, None).J[rows] for q in Q]))
    if singular.any():
        k = int(np.argmax(singular))
        raise ValueError(f"the task Jacobian is singular at sample {k}, q = {Q[k]}: J⁻¹ is not defined")
    Qd = np.einsum("kij,kj->ki", J_inv, XD)
    Jdot_qd = np.array([frame_state_kernel(model, data, fid, q, qd).Jdot_qd[rows] for q, qd in zip(Q, Qd)])
    return Qd, np.einsum("kij,kj->ki", J_inv, XDD - Jdot_qd)


# --------------------------------------------------------------------------------------------
# Selection matrices of natural/artificial constraints (Sects. 9.5–9.6)
# --------------------------------------------------------------------------------------------

TWIST_AXES = ("x", "y", "z", "rx", "ry", "rz")  # components of a twist [ṗ; ω] or a wrench [f; μ]


def _tall(S: Any, name: str) -> np.ndarray:
    S = np.asarray(S, dtype=float)
    if S.ndim == 1:
        S = S.reshape(-1, 1)
    if S.ndim != 2 or S.shape[1] > S.shape[0] or not np.isfinite(S).all():
        raise ValueError(f"`{name}` must be a finite (n, m) selection matrix with m <= n, got shape {S.shape}")
    return S


def selection_pseudo_inverse(S: Any, W: Any = None) -> np.ndarray:
    """S† = (Sᵀ W S)⁻¹ Sᵀ W, the W-weighted left pseudo-inverse of a selection matrix, Eq. (9.55).

    λ = S_f† h_e is the W-weighted least-squares fit of h_e by S_f λ (Problem 9.5); for a wide
    Jacobian the right inverse is :func:`weighted_pseudo_inverse`. W need only make Sᵀ W S
    invertible (e.g. a singular compliance C' of a partly rigid environment). ValueError otherwise.
    """
    S = _tall(S, "S")
    W = np.eye(S.shape[0]) if W is None else as_matrix(W, (S.shape[0],) * 2, "W")
    A = S.T @ W @ S
    if np.linalg.cond(A) > 1e12:
        raise ValueError("Sᵀ W S is singular: the weight `W` does not see the columns of `S`")
    return np.linalg.solve(A, S.T @ W)


def selection_projection(S: Any, W: Any = None) -> np.ndarray:
    """P = S S†, the projection onto R(S) along the W-orthogonal complement (P_f, P_v of Sect. 9.6); P² = P."""
    S = _tall(S, "S")
    return S @ selection_pseudo_inverse(S, W)


def selection_matrices(velocity_axes: Sequence[str], R_c: Any = None,
                       axes: Sequence[str] = TWIST_AXES) -> tuple[np.ndarray, np.ndarray]:
    """(S_f, S_v) of a task whose artificial motion constraints are along ``velocity_axes`` (Sect. 9.6).

    S_v has a unit column per axis named in ``velocity_axes`` (e.g. ("x", "rz"): ṗ_x and ω_z free to be
    commanded); S_f has the complementary columns (the axes where the environment's natural motion
    constraints hold and a force is commanded), so S_fᵀ S_v = 0 and [S_f S_v] is square and invertible.
    ``axes`` names the components (default the 6 of a twist [ṗ; ω]; ("x", "y") for a planar force
    task). With the constraint frame's rotation ``R_c`` (3 × 3, or 2 × 2 for a planar task) the matrices
    are referred to the base frame: S = diag(R_c, R_c) S^c (S = R_c S^c for a position-only task).
    """
    names = list(axes)
    v = list(velocity_axes)
    unknown = [a for a in v if a not in names]
    if unknown or len(set(v)) != len(v):
        raise ValueError(f"`velocity_axes` must be distinct names from {tuple(names)}, got {tuple(v)}")
    eye = np.eye(len(names))
    S_v = eye[:, [names.index(a) for a in v]]
    S_f = eye[:, [i for i, a in enumerate(names) if a not in v]]
    if R_c is not None:
        R = np.asarray(R_c, dtype=float)
        k = R.shape[0] if R.ndim == 2 else 0
        if k not in (2, 3) or R.shape != (k, k) or len(names) not in (k, 2 * k):
            raise ValueError(f"`R_c` must be a square rotation acting on the {len(names)} components "
                             f"(or on each half of them), got shape {R.shape}")
        R = as_matrix(R, (k, k), "R_c")
        if np.abs(R.T @ R - np.eye(k)).max() > 1e-9 or np.linalg.det(R) < 0:
            raise ValueError("`R_c` must be a rotation matrix")
        T = R if len(names) == k else np.kron(np.eye(2), R)
        S_f, S_v = T @ S_f, T @ S_v
    return S_f, S_v


def contact_wrenches(points: Any, normals: Any) -> np.ndarray:
    """The unit wrenches [n_i; p_i × n_i] (6 × k, moments about the frame's origin) that k frictionless
    point contacts at ``points`` p_i (k, 3) with contact ``normals`` n_i (k, 3, normalised here) can exert.

    A twist ξ = [ṗ; ω] keeps contact i to first order when the contact point's velocity ṗ + ω × p_i
    has no normal component, n_iᵀ(ṗ + ω × p_i) = [n_i; p_i × n_i]ᵀ ξ = 0: the pair's twist space is
    :func:`reciprocal_basis` of these wrenches (Sect. 9.6, natural constraints from the geometry).
    """
    p = as_points(points, 3, "points")
    n = as_points(normals, 3, "normals")
    if n.shape != p.shape:
        raise ValueError(f"`normals` must have the shape of `points` {p.shape}, got {n.shape}")
    norm = np.linalg.norm(n, axis=1, keepdims=True)
    if np.any(norm < 1e-12):
        raise ValueError("`normals` must be non-zero vectors")
    n = n / norm
    return np.vstack([n.T, np.cross(p, n).T])


def reciprocal_basis(S: Any, tol: float = 1e-9) -> np.ndarray:
    """An orthonormal basis (6 × (6 − rank S)) of the screws reciprocal to the columns of ``S`` (6 × k).

    Twists ξ = [ṗ; ω] and wrenches h = [f; μ] pair by the power hᵀξ = fᵀṗ + μᵀω, so the reciprocal
    complement is {x : Sᵀx = 0}: of a pair's contact wrenches (:func:`contact_wrenches`), its admissible
    twists (the natural velocity constraints leave these free, S_v); of those twists, the reaction wrenches
    that do no work on them (S_f, Sect. 9.6: S_fᵀ S_v = 0). ``tol`` is the rank threshold relative to the
    largest singular value of S (a zero matrix has the whole space as complement).
    """
    S = np.asarray(S, dtype=float)
    if S.ndim == 1:
        S = S.reshape(-1, 1)
    if S.ndim != 2 or S.shape[0] != 6 or not np.isfinite(S).all():
        raise ValueError(f"`S` must be a finite (6, k) array of screws, got shape {S.shape}")
    if S.shape[1] == 0 or not S.any():
        return np.eye(6)
    U, sigma, _ = np.linalg.svd(S)
    rank = int(np.sum(sigma > tol * sigma[0]))
    return U[:, rank:]


# --------------------------------------------------------------------------------------------
# Relative kinematics of the end-effector frame w.r.t. a desired frame (Sect. 9.2)
# --------------------------------------------------------------------------------------------

def relative_position_rate(R_d: Any, o_d: Any, od_d: Any, omega_d: Any, o_e: Any, od_e: Any) -> np.ndarray:
    """ȯ^d_{d,e} = R_dᵀ (ȯ_e − ȯ_d) + Sᵀ(ω^d_d) o^d_{d,e}, Eq. (9.10), with o^d_{d,e} = R_dᵀ (o_e − o_d).

    (The chain rule gives R_dᵀ(ȯ_e − ȯ_d) + Ṙ_dᵀ(o_e − o_d) with Ṙ_dᵀ = −S(ω^d_d) R_dᵀ, (S9.2).)
    """
    R_d = as_matrix(R_d, (3, 3), "R_d")
    o_de = R_d.T @ (as_vector(o_e, 3, "o_e") - as_vector(o_d, 3, "o_d"))
    w = R_d.T @ as_vector(omega_d, 3, "omega_d")
    return R_d.T @ (as_vector(od_e, 3, "od_e") - as_vector(od_d, 3, "od_d")) - np.cross(w, o_de)


def relative_euler_rate(R_d: Any, omega_d: Any, R_e: Any, omega_e: Any) -> np.ndarray:
    """φ̇_{d,e} = T⁻¹(φ_{d,e}) R_dᵀ (ω_e − ω_d), Eq. (9.11): ZYZ angles φ_{d,e} of R^d_e = R_dᵀ R_e.

    ValueError at a representation singularity (sin ϑ = 0, T(φ) singular).
    """
    R_d, R_e = as_matrix(R_d, (3, 3), "R_d"), as_matrix(R_e, (3, 3), "R_e")
    phi = rotation_to_euler_zyz(R_d.T @ R_e)
    if phi.singular:
        raise ValueError("R_dᵀ R_e is a ZYZ representation singularity: φ̇_{d,e} is not defined")
    w = R_d.T @ (as_vector(omega_e, 3, "omega_e") - as_vector(omega_d, 3, "omega_d"))  # ω^d_{d,e}
    return np.linalg.solve(euler_rate_matrix_zyz(phi.angles), w)
