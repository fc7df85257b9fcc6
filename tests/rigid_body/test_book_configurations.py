"""Named configurations of the book's robots: inside the joint limits, and IK from each converges nearby."""

import numpy as np
import pytest

from planners.inverse_kinematics import solve_ik
from rigid_body.book_robots import BOOK_ROBOTS
from rigid_body.kinematics import direct_kinematics, geometric_jacobian
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


def test_the_book_figures_postures_are_named():
    # Problem 5.7's camera posture: the SCARA's tip at (a1 + a2 c2, a2 s2, d3) by (S2.3), a1 = a2 = 0.5 m
    q = load("scara").configurations["p5_7_camera"]
    np.testing.assert_allclose(direct_kinematics(load("scara"), q)[:3, 3],
                               [0.5 + 0.5 * np.cos(np.pi / 4), 0.5 * np.sin(np.pi / 4), 0.1], atol=1e-12)
    # Fig. S7.2's PR posture: its tip where the figure's frames put it, [−a2 c2, 0, d1 + a2 s2] (a2 = 0.5 m)
    pr = load("planar_pr")
    d1, th2 = pr.configurations["fig_s7_2"]
    np.testing.assert_allclose(direct_kinematics(pr, [d1, th2])[:3, 3],
                               [-0.5 * np.cos(th2), 0.0, d1 + 0.5 * np.sin(th2)], atol=1e-12)


@pytest.mark.parametrize("name", sorted(BOOK_ROBOTS))
def test_every_book_robot_has_a_non_singular_named_posture(name):
    """Beyond ``neutral`` (often singular: the SCARA stretched, the spherical arm with θ2 = 0), each book robot
    names a posture where its Jacobian has the rank it has at generic configurations."""
    robot = load(name)
    named = {k: q for k, q in robot.configurations.items() if k != "neutral"}
    assert named, name
    rng = np.random.default_rng(7)
    generic = max(np.linalg.matrix_rank(geometric_jacobian(robot, robot.random_configuration(rng)))
                  for _ in range(20))
    for key, q in named.items():
        sv = np.linalg.svd(geometric_jacobian(robot, q), compute_uv=False)
        assert sv[generic - 1] > 0.1, (name, key, sv)  # the generic rank, well conditioned


def test_a_changed_stroke_leaves_out_the_postures_it_puts_outside_the_limits():
    assert "p5_7_camera" not in load("scara", d3_range=(0.2, 1.0)).configurations  # its d3 = 0.1 m
    q = load("cylindrical", d3_range=(0.3, 0.5)).configurations["mid_stroke"]  # follows the stroke
    assert q[2] == pytest.approx(0.4)


@pytest.mark.parametrize("name", sorted(BOOK_ROBOTS))
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
