"""Inverse kinematics: closed-loop IK (CLIK), two-stage arm/wrist CLIK, CasADi SQP and proxsuite QP IK.

* **CLIK** (Sect. 3.7): ``q̇ = J#(q) (ẋ_d + K e) + (I − J# J) q̇_0`` with J# the inverse (3.70),
  the right pseudo-inverse (3.72) or the damped least-squares inverse (3.59), or ``q̇ = J^T K e``
  (3.76). The error e is the position error and one of the orientation errors of Sect. 3.7.3:
  Euler angles (analytical Jacobian), angle–axis (3.85) with (3.88)–(3.89), unit quaternion (3.91),
  (3.93). :class:`CLIK` is a discrete controller for :func:`controllers.simulation.simulate` on the
  :class:`controllers.plants.JointIntegrator` plant q̇ = u, whose RK4 step of a held input is exactly Euler's (3.48).
* **Two-stage CLIK** for a manipulator with a spherical wrist (Problem 3.14): position of the wrist
  point with the arm joints, then orientation with the wrist joints.
* **Optimisation IK** (:class:`CasadiIK`): Gauss–Newton SQP (CasADi ``sqpmethod``, proxsuite QPs) on
  the symbolic kinematics of :mod:`rigid_body.symbolic`, joint limits as bounds, weighted pose error,
  optional posture cost, restarts from random seeds.
* **Velocity QP IK** (:class:`QPVelocityIK`): one proxsuite QP per step, task error + damping,
  joint position and velocity limits.

The task (:class:`rigid_body.task_space.TaskSpace`), the pose errors and the generalised inverses are
those of :mod:`rigid_body.task_space`, shared with operational-space control.

Every solver returns an :class:`IKResult` with the same semantics: ``success`` is True only when the
residual is below the tolerance AND the configuration is within the joint limits; a start outside the
limits is clipped onto them (the message says so); ``iterations`` is the number of updates actually
made; a failure's message says whether the solver never left its start or stalled, and why (joints at
a limit, a singular Jacobian) before blaming the target. Success rates measured on the Panda from
random starts within the limits (500 reachable targets, ``benchmarks/bench_ik.py``; the seeded
harness of ``tests/planners/ik_harness.py`` checks every reported success independently):
:func:`solve_clik` 196/500 (39 %), :class:`QPVelocityIK` 255/500 (51 %); :class:`CasadiIK` 1000/1000 and
:class:`LMIK` 997/1000 (random starts, up to 50 restarts); no false success.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 3.5 (redundancy, (3.50)–(3.59)), 3.7 (CLIK, (3.68)–(3.97)); Problems 3.10, 3.14, 3.21, 3.22.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
import pinocchio as pin

from rigid_body.manipulability import manipulability
from rigid_body.robots import Robot
from rigid_body.rotations import as_homogeneous, as_rotation, orientation_error_axis_angle
from rigid_body.task_space import PoseError, TaskSpace, damped_least_squares_inverse, pose_error, pose_residual
from rigid_body.validation import as_positive, as_square_matrix, as_vector

__all__ = [
    "IKResult",
    "within_limits",
    "CLIK",
    "TwoStageCLIK",
    "constant_pose",
    "cosine_pose_reference",
    "manipulability_objective",
    "numerical_gradient",
    "gradient_velocity",
    "joint_limit_distance",
    "joint_limit_distance_gradient",
    "solve_clik",
    "solve_ik",
    "CasadiIKOptions",
    "CasadiIK",
    "QPIKOptions",
    "QPVelocityIK",
]

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
LAWS = ("inverse", "pseudo_inverse", "dls", "transpose")


@dataclass(frozen=True)
class IKResult:
    """Outcome of an IK solve.

    Attributes
    ----------
    q : (nq,) the best configuration found (always within the joint limits).
    success : True only when ``residual`` < the solver's tolerance and ``q`` is within the joint limits.
    iterations : updates of q actually made (SQP iterations summed over restarts for :class:`CasadiIK`).
    residual : max(‖p_d − p_e‖ [m], rotation angle of R_e^T R_d [rad]) at ``q``
        (only the controlled components for a reduced task).
    message : a human-readable reason.
    """

    q: np.ndarray
    success: bool
    iterations: int
    residual: float
    message: str = ""

    def __iter__(self):
        return iter((self.q, self.success))

    def __repr__(self) -> str:
        q = np.asarray(self.q, dtype=float)
        q = np.array2string(np.where(np.abs(q) < 5e-5, 0.0, q), precision=4, separator=", ")
        return (f"IKResult(success={self.success}, residual={self.residual:.3g}, iterations={self.iterations}, "
                f"q={q}, message={self.message!r})")


LIMIT_TOL = 1e-9  # [rad | m]: a configuration this close outside a limit still counts as within it


def _few_joints(robot: Robot) -> str:
    """The hint a failed whole-pose solve gives on an arm with fewer than 6 joints."""
    if robot.nv >= 6:
        return ""
    return (f"; this arm has {robot.nv} joints, too few for a whole pose (6 components): for the position "
            "only, use solve_clik(robot, T, q0, task=TaskSpace(rows=(0, 1, 2)))")


def within_limits(robot: Robot, q: np.ndarray, tol: float = LIMIT_TOL) -> bool:
    """True when q_m − tol ≤ q ≤ q_M + tol for every joint."""
    return bool(np.all(q >= robot.lower - tol) and np.all(q <= robot.upper + tol))


def _start(robot: Robot, q0: Any, name: str = "q0") -> tuple[np.ndarray, str]:
    """The start ``q0`` validated and clipped onto the joint limits, and a note when it was clipped."""
    q = as_vector(q0, robot.nq, name)
    lo, hi = robot.lower, robot.upper
    outside = np.flatnonzero((q < lo - LIMIT_TOL) | (q > hi + LIMIT_TOL))
    if outside.size == 0:
        return q.copy(), ""
    return np.clip(q, lo, hi), f"`{name}` was outside the joint limits at q[{', '.join(map(str, outside))}] and was clipped onto them; "


def _count(value: Any, name: str, minimum: int) -> int:
    """An integer option >= ``minimum``; ValueError naming it otherwise."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"`{name}` must be an integer >= {minimum}, got {value!r}")
    return int(value)


def _failure_reason(robot: Robot, q_start: np.ndarray, q_best: np.ndarray, J: np.ndarray) -> str:
    """Why a local solver did not converge: it never left its start or stalled, at joint limits, at a
    singularity (σ_min of the task Jacobian J at ``q_best``), or in a local minimum / out of reach."""
    at_limit = np.flatnonzero((q_best <= robot.lower + 1e-6) | (q_best >= robot.upper - 1e-6))
    sv = np.linalg.svd(J, compute_uv=False)
    causes = []
    if at_limit.size == 1:
        causes.append(f"q[{at_limit[0]}] at its joint limit")
    elif at_limit.size:
        causes.append(f"q[{', '.join(map(str, at_limit))}] at their joint limits")
    if sv[-1] < 1e-6 * max(sv[0], 1e-12):
        causes.append(f"a singular Jacobian (σ_min = {sv[-1]:.2g})")
    moved = np.max(np.abs(q_best - q_start)) > 1e-9
    what = "stalled" if moved else "never improved on its start"
    others = [name for name, q in getattr(robot, "configurations", {}).items()
              if np.max(np.abs(np.asarray(q) - q_start)) > 1e-9]
    hint = f"; start from another posture, e.g. robot.configurations[{others[0]!r}]" if others and not moved else ""
    return (f"{what} with {' and '.join(causes)}" if causes else f"{what}: a local minimum or an unreachable pose") + hint


# --------------------------------------------------------------------------------------------
# Secondary tasks for the null space (3.55)–(3.58): plain functions q -> q̇_0
# --------------------------------------------------------------------------------------------

def numerical_gradient(w: Callable[[np.ndarray], float], q: np.ndarray, step: float = 1e-6,
                       scheme: str = "forward") -> np.ndarray:
    """∂w/∂q by forward (as the manual's 3.21) or central differences of step ``step``."""
    q = np.asarray(q, dtype=float)
    step = as_positive(step, "step")
    g = np.empty(q.size)
    if scheme == "forward":
        w0 = w(q)
        for k in range(q.size):
            dq = q.copy()
            dq[k] += step
            g[k] = (w(dq) - w0) / step
    elif scheme == "central":
        for k in range(q.size):
            dp, dm = q.copy(), q.copy()
            dp[k] += step
            dm[k] -= step
            g[k] = (w(dp) - w(dm)) / (2 * step)
    else:
        raise ValueError(f"`scheme` must be 'forward' or 'central', got {scheme!r}")
    return g


def gradient_velocity(w: Callable[[np.ndarray], float], k0: float, step: float = 1e-6,
                      scheme: str = "forward",
                      gradient: Callable[[np.ndarray], np.ndarray] | None = None) -> Callable[[np.ndarray], np.ndarray]:
    """q̇_0(q) = k_0 (∂w/∂q)^T, Eq. (3.55): ascend the objective ``w`` (numerically unless ``gradient``)."""
    if gradient is not None:
        return lambda q: k0 * gradient(q)
    return lambda q: k0 * numerical_gradient(w, q, step, scheme)


def joint_limit_distance(robot: Robot, q: np.ndarray) -> float:
    """w(q) = −1/(2n) Σ ((q_i − q̄_i)/(q_iM − q_im))², the distance from the joint limits, Eq. (3.57)."""
    lo, hi = robot.lower, robot.upper
    mid = 0.5 * (lo + hi)
    return float(-0.5 / robot.nq * np.sum(((q - mid) / (hi - lo)) ** 2))


def joint_limit_distance_gradient(robot: Robot, q: np.ndarray) -> np.ndarray:
    """∂w/∂q of :func:`joint_limit_distance`: −(q_i − q̄_i)/(n (q_iM − q_im)²)."""
    lo, hi = robot.lower, robot.upper
    return -(q - 0.5 * (lo + hi)) / (robot.nq * (hi - lo) ** 2)


def manipulability_objective(robot: Robot, frame: str | int | None = None,
                             rows: tuple[int, ...] = tuple(range(6))) -> Callable[[np.ndarray], float]:
    """w(q) = √det(J J^T) (3.56) of the rows ``rows`` of the frame's Jacobian, as a function of q."""
    fid = robot.frame(frame)
    rows = list(rows)
    return lambda q: manipulability(pin.computeFrameJacobian(robot.model, robot.data, q, fid, LWA)[rows])


# --------------------------------------------------------------------------------------------
# CLIK as a discrete controller on the integrator plant
# --------------------------------------------------------------------------------------------

def constant_pose(T_d: Any) -> Callable[[float], tuple[np.ndarray, np.ndarray]]:
    """A reference t ↦ (T_d, 0): regulation to a fixed pose."""
    T_d = as_homogeneous(T_d, "T_d").copy()
    zero = np.zeros(6)
    return lambda t: (T_d, zero)


def cosine_pose_reference(p_i: Any, p_f: Any, t_f: float, phi_i: float = 0.0, phi_f: float = 0.0,
                          axis: Any = (0.0, 0.0, 1.0), R_0: Any = None) -> Callable[[float], tuple[np.ndarray, np.ndarray]]:
    """A straight-line position and a rotation about a fixed ``axis`` with the sinusoidal timing law
    s(t) = ½ (1 − cos(π t / t_f)) on [0, t_f], held afterwards (the manual's 3.21/3.22 references).

    p_d = p_i + s (p_f − p_i), R_d = R(φ_i + s (φ_f − φ_i), axis) R_0, ṗ_d = ṡ (p_f − p_i),
    ω_d = ṡ (φ_f − φ_i) axis. Returns ``t -> (T_d, v_d)``.
    """
    p_i, p_f = as_vector(p_i, 3, "p_i"), as_vector(p_f, 3, "p_f")
    t_f = as_positive(t_f, "t_f")
    r = as_vector(axis, 3, "axis")
    if not np.linalg.norm(r) > 0:
        raise ValueError("`axis` must be a non-zero vector")
    r = r / np.linalg.norm(r)
    R_0 = np.eye(3) if R_0 is None else as_rotation(R_0, "R_0")
    phi_i, phi_f = (float(as_vector(x, 1, name)[0]) for x, name in ((phi_i, "phi_i"), (phi_f, "phi_f")))
    dp, dphi = p_f - p_i, phi_f - phi_i

    def reference(t: float) -> tuple[np.ndarray, np.ndarray]:
        tau = min(max(t, 0.0), t_f)
        s = 0.5 * (1.0 - np.cos(np.pi * tau / t_f))
        sd = 0.5 * np.pi / t_f * np.sin(np.pi * tau / t_f) if t < t_f else 0.0
        T = np.eye(4)
        T[:3, :3] = pin.exp3((phi_i + s * dphi) * r) @ R_0
        T[:3, 3] = p_i + s * dp
        return T, np.concatenate([sd * dp, sd * dphi * r])

    return reference


class CLIK:
    """Closed-loop inverse kinematics, Sect. 3.7: a controller ``(t, q) -> q̇`` for :func:`simulate`.

    Parameters
    ----------
    robot : the robot.
    reference : ``t -> (T_d (4, 4), v_d (6,) = [ṗ_d; ω_d])``.
    task : the controlled quantities (:class:`TaskSpace`).
    K : gain (scalar, (m,) diagonal or (m, m)); for angle–axis and quaternion errors the
        orientation block is K_O of (3.89)/(3.93).
    law : ``"inverse"`` (3.70), ``"pseudo_inverse"`` (3.72), ``"dls"`` (3.59) or ``"transpose"`` (3.76).
    damping : k of the DLS inverse.
    secondary : optional ``q -> q̇_0`` projected in the null space, (3.54)/(3.72) (not with "inverse").

    ``log()`` returns ``e`` (task error), ``qd`` (joint velocity) and ``residual``.
    """

    def __init__(self, robot: Robot, reference: Callable[[float], tuple[np.ndarray, np.ndarray]],
                 task: TaskSpace = TaskSpace(), K: Any = 500.0, law: str = "pseudo_inverse",
                 damping: float = 0.0, secondary: Callable[[np.ndarray], np.ndarray] | None = None):
        if law not in LAWS:
            raise ValueError(f"`law` must be one of {LAWS}, got {law!r}")
        if secondary is not None and law in ("inverse", "transpose"):
            raise ValueError(f"a null-space `secondary` task needs a redundant law, not {law!r}")
        self.robot, self.reference, self.task, self.law = robot, reference, task, law
        self.K = as_square_matrix(K, len(task.selected), "K")
        self.damping = as_positive(damping, "damping", allow_zero=True)
        self.secondary = secondary
        rows = task.selected
        self._ori_rows = [i for i, r in enumerate(rows) if r >= 3]
        self._ori_full = [r - 3 for r in rows if r >= 3]
        self._ori_block = np.ix_(self._ori_full, self._ori_full)
        self._last: dict[str, Any] = {}

    def reset(self) -> None:
        self._last = {}

    def velocity(self, t: float, q: np.ndarray) -> tuple[np.ndarray, PoseError]:
        """q̇ of the CLIK law at (t, q) and the pose error it used."""
        T_d, v_d = self.reference(t)
        err = pose_error(self.robot, q, T_d, v_d, self.task)
        J, e = err.J, err.e
        if self.law == "transpose":
            return J.T @ (self.K @ e), err                                 # Eq. (3.76)
        v = err.feedforward + self.K @ e                                   # ẋ_d + K e
        if err.L is not None and self._ori_rows:                           # Eqs. (3.88)–(3.89)
            o = self._ori_rows
            L = err.L[self._ori_block]
            v[o] = np.linalg.solve(L, L.T @ err.feedforward[o] + (self.K @ e)[o])
        if self.law == "inverse":
            if J.shape[0] != J.shape[1]:
                raise ValueError(f"law 'inverse' needs a square task Jacobian, got {J.shape}")
            return np.linalg.solve(J, v), err                              # Eq. (3.70)
        Jp = (damped_least_squares_inverse(J, self.damping) if self.law == "dls"
              else np.linalg.pinv(J))                                      # Eqs. (3.59), (3.52)
        qd = Jp @ v
        if self.secondary is not None:
            qd0 = self.secondary(q)
            qd = qd + qd0 - Jp @ (J @ qd0)                                 # (I − J† J) q̇_0, Eq. (3.72)
        return qd, err

    def __call__(self, t: float, q: np.ndarray) -> np.ndarray:
        qd, err = self.velocity(t, q)
        self._last = {"e": err.e, "qd": qd}
        return qd

    def log(self) -> dict[str, Any]:
        return self._last


class TwoStageCLIK:
    """Two-stage CLIK for a manipulator with a spherical wrist, Problem 3.14.

    Stage 1 (arm joints q_P): q̇_P = J_PP^{-1}(ṗ_Wd + K_P e_PW), with p_Wd = p_d + R_d o_W, the
    wrist point located by the constant offset o_W of the wrist frame in the end-effector frame
    (−d6 z_e for the book's wrist, (2.93)) and ṗ_Wd = ṗ_d + ω_d × R_d o_W.
    Stage 2 (wrist joints q_O): q̇_O = J_OO^{-1}(ω_d − J_OP q̇_P + K_O e_O), e_O from (3.85).
    J_PP, J_OP, J_OO are the blocks of (3.42) (the wrist joints do not move p_W).
    """

    def __init__(self, robot: Robot, reference: Callable[[float], tuple[np.ndarray, np.ndarray]],
                 wrist_frame: str | int, n_arm: int = 3, K_P: Any = 500.0, K_O: Any = 500.0):
        self.robot, self.reference, self.n_arm = robot, reference, _count(n_arm, "n_arm", 1)
        if self.n_arm >= robot.nv:
            raise ValueError(f"`n_arm` must leave wrist joints: < {robot.nv}, got {n_arm}")
        self.wrist = robot.frame(wrist_frame)
        self.ee = robot.ee_frame
        self.K_P, self.K_O = as_square_matrix(K_P, 3, "K_P"), as_square_matrix(K_O, 3, "K_O")
        model, data = robot.model, robot.data
        pin.framesForwardKinematics(model, data, pin.neutral(model))
        oMe, oMw = data.oMf[self.ee], data.oMf[self.wrist]
        self.offset = oMe.rotation.T @ (oMw.translation - oMe.translation)   # o_W in the ee frame
        self._last: dict[str, Any] = {}

    def reset(self) -> None:
        self._last = {}

    def __call__(self, t: float, q: np.ndarray) -> np.ndarray:
        model, data, n = self.robot.model, self.robot.data, self.n_arm
        T_d, v_d = self.reference(t)
        R_d, p_d = T_d[:3, :3], T_d[:3, 3]
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        J_W = pin.getFrameJacobian(model, data, self.wrist, LWA)
        J_E = pin.getFrameJacobian(model, data, self.ee, LWA)
        r_W = R_d @ self.offset
        e_PW = p_d + r_W - data.oMf[self.wrist].translation
        pd_W = v_d[:3] + np.cross(v_d[3:], r_W)
        qd_P = np.linalg.solve(J_W[:3, :n], pd_W + self.K_P @ e_PW)            # stage 1
        e_O = orientation_error_axis_angle(R_d, data.oMf[self.ee].rotation)     # Eq. (3.85)
        qd_O = np.linalg.solve(J_E[3:, n:], v_d[3:] - J_E[3:, :n] @ qd_P + self.K_O @ e_O)  # stage 2
        e_P = p_d - data.oMf[self.ee].translation
        self._last = {"e_PW": e_PW, "e_P": e_P, "e_O": e_O}
        return np.concatenate([qd_P, qd_O])

    def log(self) -> dict[str, Any]:
        return self._last


def solve_clik(robot: Robot, T_d: Any, q0: Any, task: TaskSpace = TaskSpace(), damping: float = 1e-3,
               tol: float = 1e-6, max_iterations: int = 500,
               secondary: Callable[[np.ndarray], np.ndarray] | None = None,
               step: float = 1.0) -> IKResult:
    """Regulate to a fixed pose by CLIK iterations q ← q + α J*(e) (+ null-space q̇_0): IK of one pose.

    Each iteration is one step of the CLIK law with unit gain (a damped Gauss–Newton step, J* the
    DLS inverse (3.59) of damping ``damping``, α = ``step``); the configuration is clipped onto the
    joint limits after every step (a start outside them too). ``success`` when the residual is below
    ``tol`` within the limits. A local method: it converges from a nearby guess (tracking, a previous
    solution); from an arbitrary guess on a 7-DOF arm with limits it often stalls at a joint limit
    (measured on the Panda: 196 of 500 reachable targets solved from random starts within the limits)
    and reports it with ``success=False`` — use :class:`CasadiIK` (restarts) then.
    """
    T_d = as_homogeneous(T_d, "T_d")
    damping = as_positive(damping, "damping", allow_zero=True)
    tol = as_positive(tol, "tol")
    step = as_positive(step, "step")
    max_iterations = _count(max_iterations, "max_iterations", 0)
    q, note = _start(robot, q0)
    q_start = q.copy()
    lo, hi = robot.lower, robot.upper
    best_q, best, best_J = q.copy(), np.inf, None
    for it in range(max_iterations + 1):
        err = pose_error(robot, q, T_d, None, task)
        res = pose_residual(T_d, err.T_e, task, err.e)
        if res < best or best_J is None:
            best, best_q, best_J = res, q.copy(), err.J
        if res < tol and within_limits(robot, q):
            return IKResult(q, True, it, res, note + "converged")
        if it == max_iterations:
            break
        Jp = damped_least_squares_inverse(err.J, damping)
        dq = Jp @ err.e
        if secondary is not None:
            dq0 = secondary(q)
            dq = dq + dq0 - Jp @ (err.J @ dq0)
        q = np.clip(pin.integrate(robot.model, q, step * dq), lo, hi)
    return IKResult(best_q, False, max_iterations, best,
                    note + f"not converged in {max_iterations} iterations (best residual {best:.3g}): "
                    + _failure_reason(robot, q_start, best_q, best_J))


# --------------------------------------------------------------------------------------------
# Optimisation IK with CasADi (Gauss–Newton SQP)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class CasadiIKOptions:
    """Options of :class:`CasadiIK`.

    position_weights : (3,) weights of ‖p − p_d‖² components [1/m²].
    orientation_weight : weight of ‖R − R_d‖_F² = 2 (3 − tr R_d^T R).
    posture_weight : weight of ‖q − q_posture‖² (0 = no posture cost).
    tol : success tolerance on the pose residual (max of position [m] and angle [rad]).
    restarts : number of random seeds tried after the initial guess.
    max_iter : SQP iterations per attempt.
    """

    position_weights: tuple[float, float, float] = (1.0, 1.0, 1.0)
    orientation_weight: float = 1.0
    posture_weight: float = 0.0
    tol: float = 1e-6
    restarts: int = 50
    max_iter: int = 30

    def __post_init__(self):
        w = as_vector(self.position_weights, 3, "position_weights")
        if np.any(w < 0):
            raise ValueError(f"`position_weights` must be >= 0, got {w}")
        as_positive(self.orientation_weight, "orientation_weight", allow_zero=True)
        as_positive(self.posture_weight, "posture_weight", allow_zero=True)
        as_positive(self.tol, "tol")
        _count(self.restarts, "restarts", 0)
        _count(self.max_iter, "max_iter", 1)


def _residual_at(robot: Robot, data: pin.Data, frame: int, q: np.ndarray, T_d: np.ndarray) -> float:
    """max(position error [m], rotation angle [rad]) of ``frame`` at ``q`` from Pinocchio's forward kinematics
    on ``data``: how both solvers check a result, independently of their iterations."""
    pin.framesForwardKinematics(robot.model, data, q)
    return pose_residual(T_d, data.oMf[frame].homogeneous, TaskSpace())


def _mid_range(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The default first guess: the middle of the joint ranges (infinite or revolute ranges cut at ±π)."""
    return 0.5 * (np.maximum(lo, -np.pi) + np.minimum(hi, np.pi))


_CASADI_IK_SOLVERS: dict[tuple, Any] = {}


def _least_squares_sqp(robot: Robot, frame: int, o: CasadiIKOptions) -> Any:
    """The SQP solver of :class:`CasadiIK` for (robot, frame, weights, max_iter, tol), built once and cached.

    The cost is ‖r(q)‖² with the residual r = [√w_p (p − p_d); √w_O vec(R − R_d); √w_q (q − q_posture)];
    the Hessian given to the SQP is Gauss–Newton's 2 J_rᵀ J_r (J_r = ∂r/∂q): positive semidefinite, so
    every QP is convex, and equal to the exact Hessian at a zero-residual solution (quadratic
    convergence there). Without a posture cost it stops when the gradient 2 J_rᵀ r is below ``tol``: a
    residual of the order of the tolerance, which :meth:`CasadiIK.solve` then checks independently
    (measured on the Panda: 0.15 iterations past the first iterate within tolerance, against 1.8 with a
    1e-14 stop); with one, at a gradient below 10⁻³ w_q, well inside the posture term's own scale.
    Box QPs by proxsuite (CasADi's qrqp wrote out of bounds on the singular QPs of a redundant arm).
    Parameters: [p_d; vec(R_d); q_posture]."""
    import casadi as ca

    from rigid_body.symbolic import frame_placement_function, model_digest

    key = (model_digest(robot.model), frame, tuple(float(w) for w in o.position_weights),
           float(o.orientation_weight), float(o.posture_weight), o.max_iter, float(o.tol))
    solver = _CASADI_IK_SOLVERS.get(key)
    if solver is not None:
        return solver

    q = ca.SX.sym("q", robot.nq)
    p_d, R_d, q_post = ca.SX.sym("p_d", 3), ca.SX.sym("R_d", 3, 3), ca.SX.sym("q_posture", robot.nq)
    R, p = frame_placement_function(robot, frame)(q)
    r = ca.vertcat(np.sqrt(np.asarray(o.position_weights, dtype=float)) * (p - p_d),
                   np.sqrt(o.orientation_weight) * ca.vec(R - R_d))
    if o.posture_weight > 0:
        r = ca.vertcat(r, np.sqrt(o.posture_weight) * (q - q_post))
    params = ca.vertcat(p_d, ca.vec(R_d), q_post)
    J_r = ca.jacobian(r, q)
    sigma = ca.SX.sym("lam_f")
    gauss_newton = ca.Function("nlp_hess_l", [q, params, sigma, ca.SX.sym("lam_g", 0)],
                               [sigma * (2 * ca.mtimes(J_r.T, J_r))],
                               ["x", "p", "lam_f", "lam_g"], ["hess_gamma_x_x"])
    quiet = {"print_header": False, "print_iteration": False, "print_status": False, "print_time": False}
    solver = ca.nlpsol("ik", "sqpmethod", {"x": q, "f": ca.sumsqr(r), "p": params}, {
        **quiet, "error_on_fail": False, "max_iter": o.max_iter,
        "tol_du": o.tol if o.posture_weight == 0 else min(o.tol, 1e-3 * o.posture_weight),
        "qpsol": "proxqp", "qpsol_options": {"error_on_fail": False,
                                             "proxqp": {"eps_abs": 1e-12, "eps_rel": 0.0, "max_iter": 200}},
        "cache": {"nlp_hess_l": gauss_newton}})
    _CASADI_IK_SOLVERS[key] = solver
    return solver


class CasadiIK:
    """IK as a nonlinear least-squares program on the symbolic kinematics of the robot:

    min_q  Σ w_p,i (p_i(q) − p_d,i)² + w_O ‖R(q) − R_d‖_F² + w_q ‖q − q_posture‖²   s.t.  q_m ≤ q ≤ q_M,

    solved by CasADi's SQP method (``sqpmethod``) with the Gauss–Newton Hessian and proxsuite's QP
    solver (joint limits as bounds of each QP). The problem is built once per (robot, frame, options);
    :meth:`solve` tries the initial guess, then up to ``restarts`` random configurations within the
    limits (``rng``), and stops at the first whose residual is below ``tol`` — judged independently,
    by Pinocchio's forward kinematics at the returned q. With a posture cost the optimum trades pose
    accuracy for posture, so keep its weight small. Measured on the Panda (``benchmarks/bench_ik.py``,
    1000 reachable targets from random starts within the limits): 1000 solved, median ≈ 2 ms, no false
    success. IPOPT on the same cost (the previous solver) took a median of 250–400 ms: ~35–100 interior-point
    iterations per attempt at ~0.25 ms each (IPOPT's own overhead; the function evaluations were
    < 10 %), where the Gauss–Newton SQP converges quadratically in ~12 iterations of ~0.1 ms.
    """

    def __init__(self, robot: Robot, frame: str | int | None = None,
                 options: CasadiIKOptions | None = None):
        self.robot = robot
        self.options = options or CasadiIKOptions()
        self.frame = robot.frame(frame)
        self._solver = _least_squares_sqp(robot, self.frame, self.options)
        self._lo = np.array(robot.lower)
        self._hi = np.array(robot.upper)
        self._data = robot.model.createData()                 # its own workspace for the check

    def _residual(self, q: np.ndarray, T_d: np.ndarray) -> float:
        """The pose residual at ``q`` from Pinocchio's forward kinematics (not the solver's model)."""
        return _residual_at(self.robot, self._data, self.frame, q, T_d)

    def solve(self, T_d: Any, q0: Any = None, rng: np.random.Generator | None = None,
              q_posture: Any = None) -> IKResult:
        """Solve for the pose ``T_d`` (4, 4); ``q0`` the first guess (default: mid-range)."""
        T_d = as_homogeneous(T_d, "T_d")
        robot, o = self.robot, self.options
        lo, hi = self._lo, self._hi
        mid = _mid_range(lo, hi)
        q0, note = (mid, "") if q0 is None else _start(robot, q0)
        q_post = mid if q_posture is None else as_vector(q_posture, robot.nq, "q_posture")
        rng = np.random.default_rng(0) if rng is None else rng
        params = np.concatenate([T_d[:3, 3], T_d[:3, :3].ravel(order="F"), q_post])
        best_q, best, iterations = q0, np.inf, 0
        for attempt in range(o.restarts + 1):
            guess = q0 if attempt == 0 else robot.random_configuration(rng)
            sol = self._solver(x0=guess, p=params, lbx=lo, ubx=hi)
            stats = self._solver.stats()
            iterations += int(stats.get("iter_count", 0))
            q = np.clip(sol["x"].full().ravel(), lo, hi)
            res = self._residual(q, T_d)
            if res < best:
                best, best_q = res, q
            if best < o.tol and within_limits(robot, best_q):
                return IKResult(best_q, True, iterations, best, note + f"converged (attempt {attempt + 1})")
        return IKResult(best_q, False, iterations, best,
                        note + f"no solution within tol {o.tol:g} after {o.restarts + 1} attempts "
                        f"(best residual {best:.3g}): the pose is unreachable or outside the joint limits"
                        + _few_joints(robot))


# --------------------------------------------------------------------------------------------
# The recommended entry point
# --------------------------------------------------------------------------------------------

def _default_solver(robot: Robot, frame: int) -> "LMIK | CasadiIK":
    """The default solver of ``robot`` for ``frame``, built once per robot and kept with it (it lives as
    long as the robot): :class:`LMIK` (CasadiIK for a model with nq ≠ nv)."""
    key = ("default IK", frame)
    solver = robot.derived.get(key)
    if solver is None:
        solver = robot.derived[key] = LMIK(robot, frame) if robot.nq == robot.nv else CasadiIK(robot, frame)
    return solver


def solve_ik(robot: Robot, T: Any, q0: Any = None, frame: str | int | None = None,
             rng: np.random.Generator | None = None) -> IKResult:
    """Inverse kinematics of one pose: the configuration q with k(q) = ``T`` (4, 4) within the joint limits.

    The recommended default: a global, reliable solver (today :class:`LMIK`, Levenberg–Marquardt with
    random restarts: 997 of 1000 reachable Panda targets from random starts, median ≈ 1 ms, no success
    outside tolerance or limits; :class:`CasadiIK` when posture costs or constraints are needed)
    started from ``q0`` (default mid-range)
    for ``frame`` (default the end effector). Check ``result.success``; ``result.q`` is the best
    configuration found either way. For tracking a moving reference use :class:`CLIK`; for one step
    from a nearby guess :func:`solve_clik`.

    >>> import numpy as np
    >>> from rigid_body.robots import load
    >>> from rigid_body.kinematics import direct_kinematics
    >>> arm = load("planar_3r")
    >>> res = solve_ik(arm, direct_kinematics(arm, [0.3, 0.4, -0.2]))
    >>> res.success, res.residual < 1e-6
    (True, True)
    """
    return _default_solver(robot, robot.frame(frame)).solve(T, q0, rng=rng)


# --------------------------------------------------------------------------------------------
# Velocity IK as a QP (proxsuite)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class QPIKOptions:
    """Options of :class:`QPVelocityIK`.

    gain : K of the task velocity v = v_d + K e [1/s]; dt : step [s] used for the position limits
    and by :meth:`QPVelocityIK.solve`; damping : λ of ½ λ ‖q̇‖²; velocity_limit : (nv,) or scalar
    [rad/s] (None: the model's); task : :class:`TaskSpace` (angle–axis error by default).
    """

    gain: float = 1.0 / 0.05
    dt: float = 0.05
    damping: float = 1e-4
    velocity_limit: Any = None
    task: TaskSpace = field(default_factory=TaskSpace)
    tol: float = 1e-6
    max_iterations: int = 500

    def __post_init__(self):
        for name in ("gain", "dt", "tol"):
            as_positive(getattr(self, name), f"QPIKOptions.{name}")
        as_positive(self.damping, "QPIKOptions.damping", allow_zero=True)
        _count(self.max_iterations, "QPIKOptions.max_iterations", 0)
        if self.velocity_limit is not None:
            v = np.asarray(self.velocity_limit, dtype=float) if np.ndim(self.velocity_limit) else \
                as_positive(self.velocity_limit, "QPIKOptions.velocity_limit")
            if not np.all(np.isfinite(v) & (v > 0)):
                raise ValueError(f"`QPIKOptions.velocity_limit` must be finite and positive, got {v}")


class QPVelocityIK:
    """Velocity IK as a QP solved by proxsuite at every step:

    min_q̇ ½ ‖J q̇ − v‖² + ½ λ ‖q̇‖²  s.t.  max(−q̇_M, (q_m − q)/Δt) ≤ q̇ ≤ min(q̇_M, (q_M − q)/Δt),

    with v = v_d + K e the task velocity (the CLIK velocity of (3.70) with the limits as constraints).
    A local method like :func:`solve_clik`: from random starts within the limits of the Panda it
    solved 255 of 500 reachable targets (the others stall with joints held at a limit).
    """

    def __init__(self, robot: Robot, options: QPIKOptions | None = None):
        self.robot = robot
        self.options = options or QPIKOptions()
        o = self.options
        vmax = robot.model.velocityLimit if o.velocity_limit is None else o.velocity_limit
        if np.ndim(vmax) == 0:
            vmax = np.full(robot.nv, as_positive(vmax, "velocity_limit"))
        self.qd_max = as_vector(vmax, robot.nv, "velocity_limit").copy()
        if np.any(self.qd_max <= 0):
            raise ValueError(f"`velocity_limit` must be positive, got {self.qd_max}")

    def step(self, q: np.ndarray, T_d: np.ndarray, v_d: np.ndarray | None = None) -> tuple[np.ndarray, PoseError]:
        """The joint velocity q̇ of one QP step at q, and the pose error."""
        import proxsuite

        o, robot = self.options, self.robot
        err = pose_error(robot, q, T_d, v_d, o.task)
        J = err.J
        v = err.feedforward + o.gain * err.e
        H = J.T @ J + o.damping * np.eye(robot.nv)
        g = -J.T @ v
        lo = np.maximum(-self.qd_max, (robot.lower - q) / o.dt)
        hi = np.minimum(self.qd_max, (robot.upper - q) / o.dt)
        res = proxsuite.proxqp.dense.solve(H, g, None, None, np.eye(robot.nv), lo, hi,
                                           eps_abs=1e-10, verbose=False)
        return np.asarray(res.x), err

    def solve(self, T_d: Any, q0: Any) -> IKResult:
        """Iterate q ← q + Δt q̇ (QP steps toward the fixed pose T_d) until the residual < tol."""
        T_d = as_homogeneous(T_d, "T_d")
        o, robot = self.options, self.robot
        q, note = _start(robot, q0)
        q_start = q.copy()
        best, best_q, best_J = np.inf, q.copy(), None
        for it in range(o.max_iterations + 1):
            qd, err = self.step(q, T_d)
            res = pose_residual(T_d, err.T_e, o.task, err.e)
            if res < best or best_J is None:
                best, best_q, best_J = res, q.copy(), err.J
            if res < o.tol and within_limits(robot, q):
                return IKResult(q, True, it, res, note + "converged")
            if it < o.max_iterations:
                q = np.clip(pin.integrate(robot.model, q, o.dt * qd), robot.lower, robot.upper)
        return IKResult(best_q, False, o.max_iterations, best,
                        note + f"not converged in {o.max_iterations} QP steps (best residual {best:.3g}): "
                        + _failure_reason(robot, q_start, best_q, best_J))


# --------------------------------------------------------------------------------------------
# Position IK by Levenberg–Marquardt (damped least squares with adaptive damping)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class LMIKOptions:
    """Options of :class:`LMIK`.

    tol : success tolerance on the pose residual (max of position [m] and angle [rad]).
    max_iterations : iterations per attempt; restarts : random seeds tried after the first guess.
    damping : the constant part λ₀ of the damping λ = ‖e‖² + λ₀ (Sugihara's rule).
    stall : an attempt ends when the error has not halved over this many iterations.
    """

    tol: float = 1e-6
    max_iterations: int = 60
    restarts: int = 50
    damping: float = 1e-6
    stall: int = 8

    def __post_init__(self):
        if not (self.tol > 0 and self.max_iterations >= 1 and self.restarts >= 0 and self.damping > 0
                and self.stall >= 1):
            raise ValueError("LMIKOptions: tol > 0, max_iterations >= 1, restarts >= 0, damping > 0 and "
                             f"stall >= 1 are required, got {self}")


class LMIK:
    """Pose IK by Levenberg–Marquardt on Pinocchio's frame Jacobian, with joint clamping and restarts.

    One iteration, with the pose error e = log(T_e⁻¹ T_d) (the twist, in the end-effector frame, that
    takes T_e to T_d) and J the frame Jacobian in the same (local) frame:

        Δq = Jᵀ (J Jᵀ + λ I)⁻¹ e,   λ = ‖e‖² + λ₀,   q ← clamp(q + Δq, q_m, q_M),

    the damped least-squares step of (3.59) whose damping shrinks as the error does (Sugihara 2011:
    far from the solution a short, safe step; near it Gauss–Newton, quadratic convergence). An attempt
    that stalls (the error does not halve in ``stall`` iterations) restarts from a random configuration
    within the limits. Success is judged independently at the end: Pinocchio's forward kinematics at
    the returned q, the pose residual of :func:`rigid_body.task_space.pose_residual` below ``tol`` and
    q within the joint limits.

    >>> from rigid_body.robots import load
    >>> panda = load("panda"); rng = np.random.default_rng(1)
    >>> from rigid_body.kinematics import direct_kinematics
    >>> T_d = direct_kinematics(panda, panda.random_configuration(rng))
    >>> LMIK(panda).solve(T_d, rng=rng).success
    True
    """

    def __init__(self, robot: Robot, frame: str | int | None = None, options: LMIKOptions | None = None):
        self.robot = robot
        self.options = options or LMIKOptions()
        self.frame = robot.frame(frame)
        if robot.nq != robot.nv:
            raise ValueError(f"LMIK needs nq = nv (revolute and prismatic joints), got nq = {robot.nq}, nv = {robot.nv}")
        self._lo, self._hi = robot.lower, robot.upper
        self._data = robot.model.createData()                 # its own workspace

    def residual(self, q: np.ndarray, T_d: np.ndarray) -> float:
        """max(position error [m], rotation angle [rad]) of the frame at ``q`` (Pinocchio FK)."""
        return _residual_at(self.robot, self._data, self.frame, q, T_d)

    def solve(self, T_d: Any, q0: Any = None, rng: np.random.Generator | None = None) -> IKResult:
        """Solve for the pose ``T_d`` (4, 4) from ``q0`` (default: mid-range), restarting from random
        configurations drawn with ``rng`` (default seed 0)."""
        T_d = as_homogeneous(T_d, "T_d")
        robot, o = self.robot, self.options
        lo, hi = self._lo, self._hi
        q, note = (_mid_range(lo, hi), "") if q0 is None else _start(robot, q0)
        rng = np.random.default_rng(0) if rng is None else rng
        model, data, fid = robot.model, self._data, self.frame
        oMd = pin.SE3(T_d[:3, :3].copy(), T_d[:3, 3].copy())
        tol2 = (0.1 * o.tol) ** 2                          # stop on the twist, judged on the residual
        eye = np.eye(6)
        iterations = 0
        best_q, best = q, np.inf
        for attempt in range(o.restarts + 1):
            if attempt:
                q = robot.random_configuration(rng)
            reference = np.inf
            since = 0
            for _ in range(o.max_iterations):
                pin.computeJointJacobians(model, data, q)     # FK and joint Jacobians in one pass
                J = pin.getFrameJacobian(model, data, fid, pin.LOCAL)
                e = pin.log6(pin.updateFramePlacement(model, data, fid).actInv(oMd)).vector
                e2 = float(e @ e)
                iterations += 1
                if e2 < tol2:
                    break
                if e2 < 0.25 * reference:
                    reference, since = e2, 0
                else:
                    since += 1
                    if since >= o.stall:
                        break
                step = J.T @ np.linalg.solve(J @ J.T + (e2 + o.damping) * eye, e)
                q = np.minimum(np.maximum(q + step, lo), hi)
            residual = self.residual(q, T_d)
            if residual < best:
                best, best_q = residual, q
            if best < o.tol:
                break
        inside = bool(np.all(best_q >= lo) and np.all(best_q <= hi))
        if best < o.tol and inside:
            return IKResult(best_q, True, iterations, best, note + f"converged (attempt {attempt + 1})")
        return IKResult(best_q, False, iterations, best,
                        note + f"no solution within tol {o.tol:g} after {attempt + 1} attempts (best residual "
                        f"{best:.3g}): the pose is unreachable or outside the joint limits" + _few_joints(robot))


def solve_ik_lm(robot: Robot, T_d: Any, q0: Any = None, frame: str | int | None = None,
                options: LMIKOptions | None = None, rng: np.random.Generator | None = None) -> IKResult:
    """One Levenberg–Marquardt IK solve (:class:`LMIK`); build an :class:`LMIK` once for many targets."""
    return LMIK(robot, frame, options).solve(T_d, q0, rng)


__all__ += ["LMIKOptions", "LMIK", "solve_ik_lm"]
