"""Named configurations of the book's robots: inside the joint limits, and IK from each converges nearby."""

import numpy as np
import pytest

from planners.inverse_kinematics import solve_ik
from rigid_body.book_robots import BOOK_ROBOTS
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import load


@pytest.mark.parametrize("name", sorted(BOOK_ROBOTS))
def test_every_named_configuration_lies_within_the_joint_limits(name):
    robot = load(name)
    lo, hi = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    for key, q in robot.configurations.items():
        assert q.shape == (robot.nq,), key
        assert np.all(q >= lo) and np.all(q <= hi), (name, key, q)


def test_the_problem_postures_are_named_and_carried_with_a_payload():
    assert set(load("planar_2r").configurations) >= {"p8_10_target", "p8_15_start"}
    assert "p3_21_within_limits" in load("planar_3r").configurations
    assert "bent" in load("anthropomorphic_wrist", payload=1.0).configurations
    # 8.15's start is inv_k2u([0.4, 0.4]) for a = (1, 1): its tip, by the planar closed form
    q = load("planar_2r").configurations["p8_15_start"]
    tip = [np.cos(q[0]) + np.cos(q.sum()), np.sin(q[0]) + np.sin(q.sum())]
    np.testing.assert_allclose(tip, [0.4, 0.4], atol=1e-4)


@pytest.mark.parametrize("name", ["planar_2r", "planar_3r", "spherical_wrist", "anthropomorphic_wrist"])
def test_ik_from_each_configuration_reaches_a_nearby_pose(name):
    robot = load(name)
    for key, q in robot.configurations.items():
        if key == "neutral":
            continue
        target_q = np.clip(q + 0.05, robot.model.lowerPositionLimit, robot.model.upperPositionLimit)
        T = direct_kinematics(robot, target_q)
        res = solve_ik(robot, T, q0=q, rng=np.random.default_rng(0))
        assert res.success, (name, key)
        np.testing.assert_allclose(direct_kinematics(robot, res.q), T, atol=1e-6)
        assert np.abs(res.q - q).max() < 0.5, (name, key, res.q)  # stayed on the nearby branch
