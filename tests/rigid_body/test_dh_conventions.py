"""Modified (Craig) DH and the base transform: Craig's A matrices written out here, the Panda's published
table against example-robot-data's URDF and the Robotics Toolbox's published Panda poses."""

import numpy as np
import pytest

from rigid_body import dynamics as dyn
from rigid_body.book_robots import FLANGE, panda_modified_links, panda_tool
from rigid_body.dh import DHLink, dh_chain, modified_dh_transform, urdf_from_dh
from rigid_body.kinematics import direct_kinematics, frame_poses
from rigid_body.robots import load, robot_from_dh


def _rx(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _rz(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def _tx(x):
    T = np.eye(4)
    T[0, 3] = x
    return T


def _tz(z):
    T = np.eye(4)
    T[2, 3] = z
    return T


def _craig(a_prev, alpha_prev, d, theta):
    """Craig's A_i^{i−1} = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i) Tz(d_i)."""
    return _rx(alpha_prev) @ _tx(a_prev) @ _rz(theta) @ _tz(d)


def test_modified_dh_transform_is_rx_tx_rz_tz(rng):
    for _ in range(20):
        a, alpha, d, theta = rng.normal(size=4)
        np.testing.assert_allclose(modified_dh_transform(a, alpha, d, theta), _craig(a, alpha, d, theta), atol=1e-14)


def test_modified_dh_robot_frames_are_products_of_craigs_matrices(rng):
    rows = [(0.2, 0.4, 0.3, 0.1, "revolute"), (0.5, -1.2, 0.0, 0.7, "prismatic"), (-0.3, 2.0, 0.25, -0.5, "revolute"),
            (0.0, np.pi / 2, 0.1, 0.0, "revolute")]
    links = [DHLink(a=a, alpha=al, d=d, theta=th, joint=j, mass=1.0, inertia=np.eye(3) * 0.01) for a, al, d, th, j in rows]
    robot = robot_from_dh(links, convention="modified")
    for _ in range(5):
        q = rng.uniform(-1.0, 1.0, size=4)
        T = np.eye(4)
        expected = [T]
        for (a, al, d, th, j), qi in zip(rows, q):
            T = T @ (_craig(a, al, d, th + qi) if j == "revolute" else _craig(a, al, d + qi, th))
            expected.append(T)
        got = frame_poses(robot, q, [f"frame_{i}" for i in range(5)])
        for i in range(5):
            np.testing.assert_allclose(got[i], expected[i], atol=1e-12, err_msg=f"frame_{i}")
        np.testing.assert_allclose(dh_chain(links, q, convention="modified")[-1], expected[-1], atol=1e-12)
    with pytest.raises(ValueError, match="convention"):
        robot_from_dh(links, convention="craig")


def test_base_transform_moves_the_arm_and_gravity_acts_in_the_world(rng):
    """With a base T_b, every pose is T_b times the DH product; gravity g₀ (world) acts on the arm as
    R_bᵀ g₀ acts on the arm without base."""
    links = [DHLink(alpha=np.pi / 2, mass=2.0, com=(0, 0.1, 0), inertia=np.eye(3) * 0.02),
             DHLink(a=0.5, mass=3.0, com=(-0.25, 0, 0), inertia=np.eye(3) * 0.05),
             DHLink(a=0.4, mass=1.0, com=(-0.2, 0, 0), inertia=np.eye(3) * 0.01)]
    T_b = _tz(0.672) @ _rz(0.3) @ _rx(0.4) @ _tx(0.1)
    g0 = np.array([0.0, 0.0, -9.81])
    on_base = robot_from_dh(links, base=T_b, gravity=g0)
    free = robot_from_dh(links, gravity=T_b[:3, :3].T @ g0)
    for _ in range(5):
        q = rng.uniform(-2, 2, size=3)
        np.testing.assert_allclose(direct_kinematics(on_base, q), T_b @ dh_chain(links, q)[-1], atol=1e-12)
        np.testing.assert_allclose(dyn.gravity_torques(on_base, q), dyn.gravity_torques(free, q), atol=1e-10)
        np.testing.assert_allclose(dyn.inertia_matrix(on_base, q), dyn.inertia_matrix(free, q), atol=1e-12)
    with pytest.raises(ValueError, match="base"):
        urdf_from_dh(links, base=np.eye(3))


def test_panda_published_modified_dh_table_is_example_robot_data_panda(rng):
    """Franka's modified DH table with the URDF's inertial data: every Craig frame i is the URDF's
    panda_link{i}, the hand is Tz(0.107) Rz(−π/4) after frame 7, and B, RNEA equal the URDF model's."""
    panda = load("panda")
    links = panda_modified_links(panda.model)
    from_table = robot_from_dh(links, convention="modified", tool=panda_tool())
    for _ in range(5):
        q = panda.random_configuration(rng)
        qd, qdd = rng.normal(size=(2, 7))
        mine = frame_poses(from_table, q, [f"frame_{i}" for i in range(1, 8)] + ["ee"])
        urdf = frame_poses(panda, q, [f"panda_link{i}" for i in range(1, 8)] + ["panda_hand"])
        for i, (a, b) in enumerate(zip(mine, urdf), start=1):
            np.testing.assert_allclose(a, b, atol=1e-12, err_msg=f"frame {i}")
        np.testing.assert_allclose(dyn.inertia_matrix(from_table, q), dyn.inertia_matrix(panda, q), atol=1e-12)
        np.testing.assert_allclose(dyn.inverse_dynamics(from_table, q, qd, qdd),
                                   dyn.inverse_dynamics(panda, q, qd, qdd), atol=1e-10)


def test_panda_modified_dh_frames_match_the_robotics_toolbox():
    """The Toolbox's published ``Panda().fkine_all([1, ..., 7])`` (its test suite, 4 decimals): frames 1..7
    (the Toolbox's row 7 carries the flange, d7 = 0.107 m: its frame 7 is ours times Tz(0.107))."""
    q = np.arange(1.0, 8.0)
    toolbox = {
        1: [[0.5403, -0.8415, 0, 0], [0.8415, 0.5403, 0, 0], [0, 0, 1, 0.333]],
        2: [[-0.2248, -0.4913, -0.8415, 0], [-0.3502, -0.7651, 0.5403, 0], [-0.9093, 0.4161, 0, 0.333]],
        3: [[0.1038, 0.8648, 0.4913, 0.1552], [0.4229, -0.4855, 0.7651, 0.2418], [0.9002, 0.1283, -0.4161, 0.2015]],
        4: [[-0.4397, -0.2425, -0.8648, 0.1638], [-0.8555, -0.1801, 0.4855, 0.2767], [-0.2735, 0.9533, -0.1283, 0.2758]],
        5: [[-0.9540, -0.1763, -0.2425, 0.107], [0.2229, -0.9581, -0.1801, 0.2781], [-0.2006, -0.2258, 0.9533, 0.6644]],
        6: [[-0.8482, -0.4994, 0.1763, 0.107], [0.2643, -0.1106, 0.9581, 0.2781], [-0.4590, 0.8593, 0.2258, 0.6644]],
        7: [[-0.5236, 0.6902, 0.4994, 0.08575], [0.8287, 0.5487, 0.1106, 0.3132], [-0.1977, 0.4718, -0.8593, 0.5321]],
    }
    robot = robot_from_dh(panda_modified_links(load("panda").model), convention="modified")
    poses = frame_poses(robot, q, [f"frame_{i}" for i in toolbox])
    poses[-1] = poses[-1] @ _tz(FLANGE)
    for (i, T), got in zip(toolbox.items(), poses):
        np.testing.assert_allclose(got[:3], T, atol=6e-5, err_msg=f"frame {i}")
