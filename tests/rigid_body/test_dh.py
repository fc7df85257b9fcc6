"""DH tables: (2.52) against elementary transforms, and the URDF → Pinocchio frames against DH products."""

import numpy as np
import pinocchio as pin
import pytest

from rigid_body.dh import DHLink, as_links, dh_chain, dh_transform
from rigid_body.robots import robot_from_dh
from rigid_body.kinematics import frame_poses
from rigid_body.robots import load
from rigid_body.book_robots import BOOK_ROBOTS, book_robot_spec


def _rz(t):
    T = np.eye(4)
    T[:2, :2] = [[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]]
    return T


def _rx(t):
    T = np.eye(4)
    T[1:3, 1:3] = [[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]]
    return T


def _trans(x, y, z):
    T = np.eye(4)
    T[:3, 3] = [x, y, z]
    return T


def test_dh_transform_is_rz_tz_tx_rx(rng):
    for _ in range(20):
        a, alpha, d, theta = rng.normal(size=4)
        expected = _rz(theta) @ _trans(0, 0, d) @ _trans(a, 0, 0) @ _rx(alpha)
        np.testing.assert_allclose(dh_transform(a, alpha, d, theta), expected, atol=1e-14)


@pytest.mark.parametrize("name", sorted(BOOK_ROBOTS))
def test_pinocchio_frames_equal_dh_products(name, rng):
    """data.oMf[frame_i] = A_1^0 ... A_i^{i-1} at random q, for every book robot."""
    robot = load(name)
    spec = book_robot_spec(name)
    n = len(spec.links)
    frames = [f"frame_{i}" for i in range(n + 1)]
    for _ in range(10):
        q = rng.uniform(np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi))
        expected = dh_chain(spec.links, q)
        got = frame_poses(robot, q, frames)
        for i in range(n + 1):
            np.testing.assert_allclose(got[i], expected[i], atol=1e-12, err_msg=f"{name} frame_{i}")


def test_robot_from_dh_accepts_dicts_and_rejects_unknown_keys(rng):
    arm = robot_from_dh([dict(a=1.0, alpha=0.3, d=0.2), dict(a=0.5, joint="prismatic", theta=0.4)])
    q = rng.normal(size=2)
    T = frame_poses(arm, q, ["ee"])[0]
    np.testing.assert_allclose(T, dh_transform(1.0, 0.3, 0.2, q[0]) @ dh_transform(0.5, 0, q[1], 0.4), atol=1e-12)
    with pytest.raises(TypeError, match="unrecognized key"):
        as_links([dict(a=1.0, lenght=2.0)])
    with pytest.raises(ValueError, match="joint"):
        DHLink(joint="spherical")
    with pytest.raises(ValueError, match="finite"):
        DHLink(a=float("nan"))


def test_dh_chain_rejects_wrong_q_shape():
    with pytest.raises(ValueError, match=r"`q` must have shape \(2,\)"):
        dh_chain([DHLink(a=1.0), DHLink(a=1.0)], [0.1, 0.2, 0.3])


def test_user_built_6dof_arm_with_motors_has_rotor_mimic_joints():
    links = [DHLink(alpha=np.pi / 2, mass=3.0, motor_inertia=1e-3, motor_mass=1.0, gear_ratio=50.0)] * 6
    arm = robot_from_dh(links)
    assert arm.nq == 6 and arm.has_mimic
    # the rotor of joint 1 spins at k_r q̇_1: its kinetic energy adds k_r² I_m to b_11
    arm0 = robot_from_dh([DHLink(alpha=np.pi / 2, mass=3.0)] * 6)
    q = np.zeros(6)
    B = pin.crba(arm.model, arm.data, q)
    B0 = pin.crba(arm0.model, arm0.data, q)
    assert B[0, 0] - B0[0, 0] > 50.0**2 * 1e-3 * 0.999


def test_a_bad_joint_type_names_the_link():
    with pytest.raises(ValueError, match=r"DH link 2: .*`joint` must be one of .*'rotary'"):
        robot_from_dh([dict(a=1.0), dict(a=1.0, joint="rotary")])
    with pytest.raises(ValueError, match=r"DH link 'elbow': `joint`"):
        DHLink(a=1.0, joint="rotary", name="elbow")


def test_default_gravity_is_minus_z0_so_a_planar_dh_arm_has_no_gravity_torque():
    """The trap the docstring warns of: −z₀ gravity leaves a planar arm weightless; the book's −y₀ does not."""
    from rigid_body.dynamics import gravity_torques

    links = [DHLink(a=1.0, mass=5.0, com=(-0.5, 0.0, 0.0)), DHLink(a=1.0, mass=5.0, com=(-0.5, 0.0, 0.0))]
    np.testing.assert_allclose(gravity_torques(robot_from_dh(links), np.zeros(2)), 0.0, atol=1e-12)
    vertical = robot_from_dh(links, gravity=[0.0, -9.81, 0.0])
    np.testing.assert_allclose(gravity_torques(vertical, np.zeros(2)), [9.81 * 5 * (0.5 + 1.5), 9.81 * 5 * 0.5])
