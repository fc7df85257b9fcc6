"""Every public function taking a frame checks it: an id out of [0, nframes), a negative id or an unknown
name raises ValueError naming ``frame``; numpy integer ids are accepted (the bindings do not check ids: an
id out of range read garbage or crashed, -1 raised OverflowError and np.int64 a Boost ArgumentError)."""

from types import SimpleNamespace

import numpy as np
import pytest

from controllers.force import PegInHoleController, PegInHoleTask
from controllers.joint_space import AdaptivePayloadControl
from controllers.operational_space import (OperationalInverseDynamics, OperationalPDGravity,
                                           operational_inverse_dynamics_steady_state)
from controllers.plants import ArmInContact
from planners.inverse_kinematics import CasadiIK, TwoStageCLIK, manipulability_objective
from rigid_body import kinematics as kin
from rigid_body import symbolic
from rigid_body.camera import PinholeCamera, project_from_robot
from rigid_body.manipulability import end_effector_jacobian
from rigid_body.robots import load, model_frame_id, with_payload
from rigid_body.task_space import TaskSpace, frame_state, joint_rates, pose_error

ARM = load("planar_2r")
WRIST = load("anthropomorphic_wrist")
ARM3 = load("planar_3r")  # the peg-in-hole task is (x, y, φ)
Q, QD = np.array([0.3, -0.5]), np.array([0.2, 0.1])
REF = lambda t: (np.zeros(2), np.zeros(2), np.zeros(2))  # noqa: E731  (a joint reference q, q̇, q̈)


def _rng():
    return np.random.default_rng(0)


# name → (robot, call(frame)); the call returns something comparable, or the constructed object
CALLS = {
    "direct_kinematics": (ARM, lambda f: kin.direct_kinematics(ARM, Q, frame=f)),
    "frame_poses": (ARM, lambda f: kin.frame_poses(ARM, Q, [f])[0]),
    "geometric_jacobian": (ARM, lambda f: kin.geometric_jacobian(ARM, Q, frame=f)),
    "jacobian_derivative_times_qd": (ARM, lambda f: kin.jacobian_derivative_times_qd(ARM, Q, QD, frame=f)),
    "end_effector_velocity": (ARM, lambda f: kin.end_effector_velocity(ARM, Q, QD, frame=f)),
    "analytical_jacobian": (ARM, lambda f: kin.analytical_jacobian(ARM, Q, "rpy", frame=f)),
    "workspace_points": (ARM, lambda f: kin.workspace_points(ARM, 3, _rng(), frame=f)),
    "joint_arc": (ARM, lambda f: kin.joint_arc(ARM, Q, 0, 1.0, 5, frame=f)),
    "end_effector_jacobian": (ARM, lambda f: end_effector_jacobian(ARM, Q, frame=f)),
    "with_payload": (ARM, lambda f: with_payload(ARM, 1.0, f).model.inertias[2].mass),
    "Robot.frame": (ARM, lambda f: ARM.frame(f)),
    "model_frame_id": (ARM, lambda f: model_frame_id(ARM.model, f)),
    "frame_state": (ARM, lambda f: frame_state(ARM, Q, QD, frame=f).T),
    "TaskSpace (pose_error)": (ARM, lambda f: pose_error(ARM, Q, np.eye(4), task=TaskSpace(f, "none")).e),
    "joint_rates": (ARM, lambda f: joint_rates(ARM, Q, [0.1, 0.0], [0.0, 0.0], rows=(0, 1), frame=f)[0]),
    "project_from_robot": (ARM, lambda f: project_from_robot(PinholeCamera(500.0, 500.0), ARM, Q,
                                                             [3.0, 0.5, 2.0], frame=f).p_c),
    "frame_placement_function": (ARM, lambda f: np.array(symbolic.frame_placement_function(ARM, f)(Q)[0])),
    "frame_placement_function(model)": (ARM, lambda f: np.array(
        symbolic.frame_placement_function(ARM.model, f)(Q)[0])),
    "geometric_jacobian_function": (ARM, lambda f: np.array(symbolic.geometric_jacobian_function(ARM, f)(Q))),
    "pose_function": (ARM, lambda f: np.array(symbolic.pose_function(ARM, f)(Q)[2])),
    "manipulability_objective": (ARM, lambda f: manipulability_objective(ARM, frame=f, rows=(0, 1))(Q)),
    "CasadiIK": (ARM, lambda f: CasadiIK(ARM, frame=f).frame),
    "TwoStageCLIK": (WRIST, lambda f: TwoStageCLIK(WRIST, lambda t: (np.eye(4), np.zeros(6)), wrist_frame=f).wrist),
    "PegInHoleController": (ARM3, lambda f: PegInHoleController(ARM3, PegInHoleTask(x_H=1.0), frame=f)),
    "AdaptivePayloadControl": (ARM, lambda f: AdaptivePayloadControl(ARM, [10.0, 10.0], [5.0, 5.0], 1.0, REF,
                                                                     frame=f)),
    "OperationalPDGravity": (ARM, lambda f: OperationalPDGravity(
        ARM, np.eye(2), np.eye(2), lambda t: (np.zeros(2), np.zeros(2), np.zeros(2)), rows=(0, 1), frame=f)),
    "OperationalInverseDynamics": (ARM, lambda f: OperationalInverseDynamics(
        ARM, np.eye(2), np.eye(2), lambda t: (np.zeros(2), np.zeros(2), np.zeros(2)), rows=(0, 1), frame=f)),
    "operational_inverse_dynamics_steady_state": (ARM, lambda f: operational_inverse_dynamics_steady_state(
        ARM, ARM, np.eye(2) * 100.0, [1.2, 0.8], Q, rows=(0, 1), frame=f)),
    "ArmInContact": (ARM, lambda f: ArmInContact(
        ARM, SimpleNamespace(wrench=lambda T, v: np.zeros(6)), frame=f)._fid),
}



@pytest.mark.parametrize("name", sorted(CALLS))
def test_frame_argument_is_checked(name):
    robot, call = CALLS[name]
    n = robot.model.nframes
    for bad in (n, 999, -1, "nope", 2.0, True):
        with pytest.raises(ValueError, match="frame"):
            call(bad)


@pytest.mark.parametrize("name", sorted(CALLS))
def test_numpy_integer_frame_ids_are_accepted(name):
    robot, call = CALLS[name]
    fid = robot.frame_id("frame_2" if robot is ARM else "frame_3")
    for f in (np.int64(fid), np.int32(fid)):
        result = call(f)
        reference = call(int(fid))
        if isinstance(result, (np.ndarray, float, int, np.floating, np.integer)):
            np.testing.assert_allclose(result, reference, atol=1e-12)
