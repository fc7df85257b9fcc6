"""Direct kinematics and the geometric Jacobian on any :class:`~rigid_body.robots.Robot`.

Conventions: the book's geometric Jacobian ``J = [J_P; J_O]`` (linear velocity of the frame origin
and angular velocity, both in the base frame, Eq. (3.4)) is Pinocchio's ``LOCAL_WORLD_ALIGNED``
frame Jacobian. Frames are given by name or id; the default is the robot's end effector.
Returned arrays are copies: Pinocchio's ``data`` is overwritten by the next call.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 2.8–2.12 (direct and inverse kinematics), 3.1–3.3 (geometric Jacobian).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rigid_body.robots import Robot
from rigid_body.validation import as_vector

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def _frame(robot: Robot, frame: str | int | None) -> int:
    return robot.ee_frame if frame is None else robot.frame(frame)


def direct_kinematics(robot: Robot, q: np.ndarray, frame: str | int | None = None) -> np.ndarray:
    """T_e^0(q): (4, 4) pose of ``frame`` (default the end effector) in the base frame, Eq. (2.50)."""
    q = as_vector(q, robot.nq, "q")
    fid = _frame(robot, frame)
    pin.forwardKinematics(robot.model, robot.data, q)
    return pin.updateFramePlacement(robot.model, robot.data, fid).homogeneous.copy()


def frame_poses(robot: Robot, q: np.ndarray, frames: list[str | int]) -> list[np.ndarray]:
    """Poses (4×4) of several frames at ``q`` with one forward-kinematics pass."""
    q = as_vector(q, robot.nq, "q")
    pin.framesForwardKinematics(robot.model, robot.data, q)
    return [robot.data.oMf[robot.frame(f)].homogeneous.copy() for f in frames]


def geometric_jacobian(robot: Robot, q: np.ndarray, frame: str | int | None = None) -> np.ndarray:
    """J(q) = [J_P; J_O], (6, nv): book convention (Pinocchio LOCAL_WORLD_ALIGNED), Eq. (3.30)."""
    q = as_vector(q, robot.nq, "q")
    fid = _frame(robot, frame)
    return pin.computeFrameJacobian(robot.model, robot.data, q, fid, LWA).copy()


def jacobian_derivative_times_qd(robot: Robot, q: np.ndarray, qd: np.ndarray,
                                 frame: str | int | None = None) -> np.ndarray:
    """J̇(q, q̇) q̇ (6,): the end-effector acceleration at q̈ = 0 (book convention), cf. Eq. (3.29)/(7.132).

    The linear part is the classical acceleration of the frame origin (it includes ω × v).
    """
    q = as_vector(q, robot.nq, "q")
    qd = as_vector(qd, robot.nv, "qd")
    fid = _frame(robot, frame)
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q, qd, np.zeros(model.nv))
    pin.updateFramePlacements(model, data)
    a = pin.getFrameClassicalAcceleration(model, data, fid, LWA)
    return np.concatenate([a.linear, a.angular])


def end_effector_velocity(robot: Robot, q: np.ndarray, qd: np.ndarray,
                          frame: str | int | None = None) -> np.ndarray:
    """v_e = J(q) q̇ = [ṗ_e; ω_e] (6,), Eq. (3.2)."""
    return geometric_jacobian(robot, q, frame) @ as_vector(qd, robot.nv, "qd")


# --------------------------------------------------------------------------------------------
# Analytical Jacobian (Chapter 3)
# --------------------------------------------------------------------------------------------

def analytical_jacobian(robot: Robot, q: np.ndarray, representation: str = "zyz",
                        frame: str | int | None = None) -> np.ndarray:
    """J_A(q) = T_A^{-1}(φ_e) J(q), (6, nv): ẋ_e = [ṗ_e; φ̇_e] for Euler angles φ_e, Eqs. (3.64)–(3.66).

    ``representation`` is ``"zyz"`` (T from (3.64)) or ``"rpy"`` (Problem 3.12); φ_e is extracted
    with ``branch=+1``. ValueError at a representation singularity (sin θ = 0 for ZYZ, cos θ = 0 for RPY).
    """
    from rigid_body.rotations import (euler_rate_matrix_rpy, euler_rate_matrix_zyz, rotation_to_euler_zyz,
                                      rotation_to_rpy)

    pair = {"zyz": (rotation_to_euler_zyz, euler_rate_matrix_zyz),
            "rpy": (rotation_to_rpy, euler_rate_matrix_rpy)}.get(representation)
    if pair is None:
        raise ValueError(f"`representation` must be 'zyz' or 'rpy', got {representation!r}")
    J = geometric_jacobian(robot, q, frame)
    phi = pair[0](direct_kinematics(robot, q, frame)[:3, :3])
    if phi.singular:
        raise ValueError(f"{representation.upper()} representation singularity at q = {q}: T(φ) is not invertible")
    J[3:] = np.linalg.solve(pair[1](phi.angles), J[3:])
    return J
