"""Every named configuration of every robot lies within its joint limits; the real robots' start poses
are away from singularities, so a local IK started there moves."""

import numpy as np
import pytest

from planners.inverse_kinematics import solve_clik
from rigid_body.kinematics import direct_kinematics, geometric_jacobian
from rigid_body.robots import available, load


@pytest.mark.parametrize("name", available())
def test_named_configurations_are_within_the_joint_limits(name):
    robot = load(name)
    assert "neutral" in robot.configurations
    for key, q in robot.configurations.items():
        assert q.shape == (robot.nq,), key
        assert np.all(q >= robot.lower - 1e-12) and np.all(q <= robot.upper + 1e-12), (key, q)


@pytest.mark.parametrize("name, key", [("panda", "ready"), ("ur5", "home"), ("ur3", "home"), ("ur10", "home")])
def test_real_robot_start_poses_are_regular_and_clik_converges_from_them(name, key):
    robot = load(name)
    q0 = robot.configurations[key]
    sv = np.linalg.svd(geometric_jacobian(robot, q0), compute_uv=False)
    assert sv[-1] > 0.1  # well away from a singularity (σ_min of the 6×n Jacobian)
    T = direct_kinematics(robot, q0)
    T[:3, 3] += [0.05, -0.05, -0.1]  # a reachable pose 12 cm away
    res = solve_clik(robot, T, q0)
    assert res.success and res.iterations > 0, res.message


def test_panda_ready_is_frankas_start_pose():
    """Franka's start pose puts the hand straight down in front of the base, in the base's x–z plane, fingers
    across its y axis; Franka documents the hand's TCP there at (0.307, 0, 0.487) m (O_T_EE, the hand's
    F_T_EE being 0.1034 m along its z axis)."""
    panda = load("panda")
    T = direct_kinematics(panda, panda.configurations["ready"], frame="panda_hand")
    np.testing.assert_allclose(T[:3, :3], np.diag([1.0, -1.0, -1.0]), atol=1e-9)
    tcp = T[:3, 3] + T[:3, :3] @ [0.0, 0.0, 0.1034]
    np.testing.assert_allclose(tcp, [0.307, 0.0, 0.487], atol=1e-3)
