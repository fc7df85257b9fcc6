"""CasADi kinematics generated from a pin.Model, checked against Pinocchio's own algorithms."""

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest

from rigid_body.robots import joint_kind, load
from rigid_body.symbolic import frame_placement_function, geometric_jacobian_function, pose_function

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def _random_q(model, rng):
    lo = np.maximum(model.lowerPositionLimit, -np.pi)
    hi = np.minimum(model.upperPositionLimit, np.pi)
    return pin.randomConfiguration(model, lo, hi)


def _compare(model, frame_id, f, rng, n=15):
    data = model.createData()
    for _ in range(n):
        q = _random_q(model, rng)
        R, p, J = (x.full() for x in f(q))
        pin.framesForwardKinematics(model, data, q)
        oMf = data.oMf[frame_id]
        J_ref = pin.computeFrameJacobian(model, data, q, frame_id, LWA)
        np.testing.assert_allclose(R, oMf.rotation, atol=1e-12)
        np.testing.assert_allclose(p.ravel(), oMf.translation, atol=1e-12)
        np.testing.assert_allclose(J, J_ref, atol=1e-12)


@pytest.mark.parametrize("name", ["panda", "ur5", "scara", "planar_2r", "planar_3r", "cylindrical",
                                  "spherical", "anthropomorphic_wrist"])
def test_pose_and_jacobian_match_pinocchio(name):
    robot = load(name)
    _compare(robot.model, robot.ee_frame, pose_function(robot), np.random.default_rng(1))


def test_intermediate_frame_of_panda():
    robot = load("panda")
    fid = robot.frame_id("panda_link4")
    fk = frame_placement_function(robot, "panda_link4")
    jac = geometric_jacobian_function(robot, fid)
    model = robot.model

    def f(q):
        R, p = fk(q)
        return R, p, jac(q)

    _compare(model, fid, f, np.random.default_rng(2), n=5)


def _unaligned_model():
    """RevoluteUnaligned, PrismaticUnaligned, RUBZ, PX and a fixed frame, with random placements."""
    rng = np.random.default_rng(3)
    model = pin.Model()
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    joints = [pin.JointModelRevoluteUnaligned(axis), pin.JointModelPrismaticUnaligned(axis[::-1].copy()),
              pin.JointModelRUBZ(), pin.JointModelPX(), pin.JointModelRY()]
    parent = 0
    for k, jm in enumerate(joints):
        placement = pin.SE3(pin.exp3(rng.normal(size=3)), rng.normal(size=3))
        parent = model.addJoint(parent, jm, placement, f"j{k}")
        model.appendBodyToJoint(parent, pin.Inertia.Random(), pin.SE3.Identity())
        model.addJointFrame(parent)
    model.addFrame(pin.Frame("tool", parent, pin.SE3(pin.exp3(rng.normal(size=3)), rng.normal(size=3)),
                             pin.FrameType.OP_FRAME))
    return model


def test_unaligned_and_unbounded_joints_match_pinocchio():
    model = _unaligned_model()
    fid = model.getFrameId("tool")
    assert joint_kind(model, 1)[0] == "revolute" and joint_kind(model, 2)[0] == "prismatic"
    assert model.nq == model.nv + 1  # the continuous joint has q = [cos, sin]
    _compare(model, fid, pose_function(model, fid), np.random.default_rng(4))


def test_jacobian_equals_finite_difference_of_position():
    robot = load("ur5")
    f = pose_function(robot)
    q = _random_q(robot.model, np.random.default_rng(5))
    J = f(q)[2].full()
    q_sym = ca.SX.sym("q", robot.nq)
    _, p, _ = f(q_sym)
    Jp = ca.Function("Jp", [q_sym], [ca.jacobian(p, q_sym)])(q).full()
    np.testing.assert_allclose(J[:3], Jp, atol=1e-12)
    h = 1e-6
    fd = np.column_stack([(f(q + h * e)[1].full().ravel() - f(q - h * e)[1].full().ravel()) / (2 * h)
                          for e in np.eye(robot.nq)])
    np.testing.assert_allclose(J[:3], fd, atol=1e-8)


def test_bad_frame_and_mimic_frame_are_refused():
    robot = load("planar_2r")
    with pytest.raises(ValueError, match="no frame"):
        frame_placement_function(robot, "nope")
    rotor = [f.name for f in robot.model.frames if "rotor" in f.name][0]
    with pytest.raises(ValueError, match="mimic"):
        frame_placement_function(robot, rotor)
    with pytest.raises(ValueError, match="frame"):
        frame_placement_function(robot.model)
