"""Statics: τ = J^T γ by virtual work, obstacle distance."""

import numpy as np
import pinocchio as pin
import pytest

from planners.inverse_kinematics import numerical_gradient
from rigid_body.kinematics import geometric_jacobian
from rigid_body.robots import load
from rigid_body.statics import (joint_torques, planar_arm_obstacle_distance, planar_arm_obstacle_distance_gradient,
                                segment_chain_distance)


def test_joint_torques_satisfy_virtual_work(rng):
    robot = load("ur5")
    q, qd, gamma = robot.random_configuration(rng), rng.normal(size=6), rng.normal(size=6)
    J = geometric_jacobian(robot, q)
    # power balance: τ^T q̇ = γ^T v_e
    assert joint_torques(J, gamma) @ qd == pytest.approx(gamma @ (J @ qd), rel=1e-12)


def test_segment_distance_brute_force_and_clamping(rng):
    s = np.linspace(0, 1, 20001)
    for _ in range(30):
        pts, o, R = rng.uniform(-1, 1, (4, 2)), rng.uniform(-1, 1, 2), rng.uniform(0, 0.3)
        res = segment_chain_distance(pts, o, R)
        brute = min(np.min(np.linalg.norm(pts[i] + s[:, None] * (pts[i + 1] - pts[i]) - o, axis=1))
                    for i in range(3)) - R
        assert res.distance == pytest.approx(brute, abs=1e-8)
    # projection before the segment start: clamped to s = 0
    res = segment_chain_distance([[0, 0], [1, 0]], [-1.0, 1.0], 0.5)
    assert res.s == 0.0 and res.distance == pytest.approx(np.sqrt(2) - 0.5)


def test_distance_gradient_analytic_vs_forward():
    robot = load("planar_3r", a=(0.5, 0.3, 0.3))
    q = np.array([0.51469, -1.55168, 1.82239])
    g = planar_arm_obstacle_distance_gradient(robot, q, [0.3, 0.0], 0.1)
    g_fd = numerical_gradient(lambda x: planar_arm_obstacle_distance(robot, x, [0.3, 0.0], 0.1).distance, q,
                              scheme="forward")  # as the manual's 3.21
    np.testing.assert_allclose(g, g_fd, atol=1e-5)
    assert planar_arm_obstacle_distance(robot, q, [0.3, 0.0], 0.1).distance == pytest.approx(0.0477, abs=1e-4)


def test_bad_inputs_raise():
    with pytest.raises(ValueError, match="points"):
        segment_chain_distance([[0, 0]], [0, 0], 0.1)
    with pytest.raises(ValueError, match="radius"):
        segment_chain_distance([[0, 0], [1, 0]], [0, 0], -1.0)
    with pytest.raises(ValueError, match="gamma"):
        joint_torques(np.eye(6), np.ones(5))
