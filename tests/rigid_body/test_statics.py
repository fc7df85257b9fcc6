"""Statics: τ = J^T γ by virtual work, wrench mapping vs Pinocchio's Force action."""

import numpy as np
import pinocchio as pin
import pytest

from rigid_body.kinematics import geometric_jacobian
from rigid_body.robots import load
from rigid_body.statics import joint_torques, transform_wrench


def test_joint_torques_satisfy_virtual_work(rng):
    robot = load("ur5")
    q, qd, gamma = robot.random_configuration(rng), rng.normal(size=6), rng.normal(size=6)
    J = geometric_jacobian(robot, q)
    # power balance: τ^T q̇ = γ^T v_e
    assert joint_torques(J, gamma) @ qd == pytest.approx(gamma @ (J @ qd), rel=1e-12)


def test_transform_wrench_matches_pinocchio_force_action(rng):
    for _ in range(10):
        M = pin.SE3(pin.exp3(rng.normal(size=3)), rng.normal(size=3))
        g = rng.normal(size=6)
        np.testing.assert_allclose(transform_wrench(M.homogeneous, g), M.act(pin.Force(g[:3], g[3:])).vector,
                                   atol=1e-12)


def test_bad_inputs_raise():
    with pytest.raises(ValueError, match="gamma"):
        joint_torques(np.eye(6), np.ones(5))
