"""Statics: τ = J^T γ by virtual work."""

import numpy as np
import pytest

from rigid_body.kinematics import geometric_jacobian
from rigid_body.robots import load
from rigid_body.statics import joint_torques


def test_joint_torques_satisfy_virtual_work(rng):
    robot = load("ur5")
    q, qd, gamma = robot.random_configuration(rng), rng.normal(size=6), rng.normal(size=6)
    J = geometric_jacobian(robot, q)
    # power balance: τ^T q̇ = γ^T v_e
    assert joint_torques(J, gamma) @ qd == pytest.approx(gamma @ (J @ qd), rel=1e-12)


def test_bad_inputs_raise():
    with pytest.raises(ValueError, match="gamma"):
        joint_torques(np.eye(6), np.ones(5))
