"""Trees of DH chains (humanoid, 2.14) and the four-link closed chain (2.11): Pinocchio on the tree URDF
against numpy products of the DH matrices and the manual's closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from rigid_body.closed_chain import (FourLinkClosedChain, closed_chain_direct_kinematics, closed_chain_joints,
                                     loop_constraint_residual)
from rigid_body.dh import dh_chain
from rigid_body.dynamics import inertia_matrix
from rigid_body.kinematics import frame_poses
from rigid_body.rotations import rot_x
from rigid_body.trees import DHBranch, Humanoid, robot_from_dh_tree, urdf_tree_from_dh
from rigid_body.book_robots import planar_2r


def test_humanoid_hand_poses_equal_the_matrix_products():
    rng = np.random.default_rng(0)
    T_t3 = np.eye(4)
    T_t3[:3, :3] = rot_x(0.4)
    T_t3[:3, 3] = [0.1, -0.05, 0.02]
    hum = Humanoid(beta=0.3, d_l=0.25, d_r=0.35, T_t3=T_t3)
    robot = hum.robot()
    assert robot.nq == 17
    for _ in range(20):
        q = rng.uniform(-np.pi, np.pi, 17)
        T_lh, T_rh, T_3 = frame_poses(robot, q, ["left_ee", "right_ee", "torso_frame_3"])
        A_l, A_r = hum.hand_poses(q)
        np.testing.assert_allclose(T_lh, A_l, atol=1e-12)
        np.testing.assert_allclose(T_rh, A_r, atol=1e-12)
        np.testing.assert_allclose(T_3, dh_chain(hum.torso_links, q[:3])[-1], atol=1e-12)


def test_tree_keeps_rotor_mimic_joints_per_branch():
    """Two motorised two-link arms on one base: the tree's inertia matrix is block diagonal with the arm's B(q)."""
    arm = planar_2r().links
    mount = np.eye(4)
    mount[1, 3] = 1.0
    tree = robot_from_dh_tree([DHBranch("a_", arm), DHBranch("b_", arm, parent="a_frame_0", mount=mount)])
    single = robot_from_dh_tree([DHBranch("a_", arm)])
    q = np.array([0.3, 0.5, -0.2, 0.9])
    B = inertia_matrix(tree, q)
    np.testing.assert_allclose(B[:2, :2], inertia_matrix(single, q[:2]), atol=1e-9)
    np.testing.assert_allclose(B[2:, 2:], inertia_matrix(single, q[2:]), atol=1e-9)
    np.testing.assert_allclose(B[:2, 2:], 0.0, atol=1e-12)
    # the book's two-link arm with motors at q = (0.3, 0.5) (Sect. 7.3.2 closed form, k_r2 I_m2 coupling included)
    np.testing.assert_allclose(inertia_matrix(single, [0.3, 0.5]), [[243.8891, 45.4396], [45.4396, 122.5]], atol=1e-3)
    assert tree.has_mimic


def test_tree_rejects_unknown_parent_and_missing_root():
    arm = planar_2r().links
    with pytest.raises(ValueError, match="parent link 'nowhere'"):
        urdf_tree_from_dh([DHBranch("a_", arm), DHBranch("b_", arm, parent="nowhere")])
    with pytest.raises(ValueError, match="root branch"):
        urdf_tree_from_dh([DHBranch("b_", arm, parent="a_frame_0")])


def test_closed_chain_constraints_hold_on_the_pinocchio_tree():
    rng = np.random.default_rng(1)
    chain = FourLinkClosedChain(a1p=0.25, a2p=0.7, a1pp=0.35, d4=0.05)
    robot = robot_from_dh_tree(chain.branches(), ee="b1_ee")
    for q in rng.uniform(-np.pi, np.pi, (20, 2)):
        for sign in (1, -1):
            joints = closed_chain_joints(chain, q, sign)
            T3, T1, T4 = frame_poses(robot, joints, ["b1_frame_3", "b2_frame_1", "b1_ee"])
            assert np.max(np.abs(loop_constraint_residual(T3, T1))) < 1e-12
            np.testing.assert_allclose(T4, closed_chain_direct_kinematics(chain, q, sign), atol=1e-12)
    # a configuration that does not close has a non-zero residual
    T3, T1 = frame_poses(robot, [0.1, 0.2, 0.3, 0.4], ["b1_frame_3", "b2_frame_1"])
    assert np.max(np.abs(loop_constraint_residual(T3, T1))) > 1e-3


def test_closed_chain_bad_input():
    with pytest.raises(ValueError, match="positive"):
        FourLinkClosedChain(a1p=-0.1, a2p=0.6, a1pp=0.3, d4=0.1)
    with pytest.raises(ValueError, match="cannot close"):
        closed_chain_joints(FourLinkClosedChain(a1p=0.5, a2p=0.3, a1pp=0.3, d4=0.1), [0.0, np.pi])
    with pytest.raises(ValueError, match="`q` must have shape"):
        closed_chain_joints(FourLinkClosedChain(a1p=0.2, a2p=0.6, a1pp=0.3, d4=0.1), [0.0])
