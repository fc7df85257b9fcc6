"""Geometric Jacobian and J̇q̇ against central finite differences of the direct kinematics."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rigid_body.kinematics import (direct_kinematics, end_effector_velocity, geometric_jacobian,
                                   jacobian_derivative_times_qd)
from rigid_body.robots import load

ROBOTS = ["planar_2r", "planar_3r", "scara", "cylindrical", "spherical", "anthropomorphic",
          "anthropomorphic_wrist", "cartesian_skew", "planar_pr", "panda", "ur5"]


def _fd_jacobian(robot, q, eps=1e-6):
    """Column j: [ṗ; ω] for q̇ = e_j, from central differences of T(q) (ω from the log of R(q+)R(q−)ᵀ)."""
    J = np.zeros((6, robot.nv))
    for j in range(robot.nv):
        dq = np.zeros(robot.nv)
        dq[j] = eps
        Tp, Tm = direct_kinematics(robot, q + dq), direct_kinematics(robot, q - dq)
        J[:3, j] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * eps)
        J[3:, j] = Rotation.from_matrix(Tp[:3, :3] @ Tm[:3, :3].T).as_rotvec() / (2 * eps)
    return J


@pytest.mark.parametrize("name", ROBOTS)
def test_geometric_jacobian_matches_finite_differences(name, rng):
    robot = load(name)
    for _ in range(5):
        q = robot.random_configuration(rng)
        np.testing.assert_allclose(geometric_jacobian(robot, q), _fd_jacobian(robot, q), atol=1e-7)


@pytest.mark.parametrize("name", ["planar_2r", "anthropomorphic_wrist", "cylindrical", "panda"])
def test_jdot_qd_matches_finite_differences(name, rng):
    robot = load(name)
    eps = 1e-6
    for _ in range(3):
        q = robot.random_configuration(rng)
        qd = rng.normal(size=robot.nv)
        # d/dt (J(q) q̇) at q̈ = 0 = (J(q + ε q̇) − J(q − ε q̇)) q̇ / 2ε
        fd = (geometric_jacobian(robot, q + eps * qd) - geometric_jacobian(robot, q - eps * qd)) @ qd / (2 * eps)
        np.testing.assert_allclose(jacobian_derivative_times_qd(robot, q, qd), fd, atol=1e-6)


def test_two_link_planar_closed_form(rng):
    """T and J of the two-link arm against the book's planar closed forms (2.63), (3.35)."""
    robot = load("planar_2r")
    for _ in range(10):
        q1, q2 = rng.uniform(-np.pi, np.pi, 2)
        q = np.array([q1, q2])
        T = direct_kinematics(robot, q)
        p = [np.cos(q1) + np.cos(q1 + q2), np.sin(q1) + np.sin(q1 + q2), 0.0]
        np.testing.assert_allclose(T[:3, 3], p, atol=1e-12)
        J = geometric_jacobian(robot, q)
        J_P = [[-np.sin(q1) - np.sin(q1 + q2), -np.sin(q1 + q2)], [np.cos(q1) + np.cos(q1 + q2), np.cos(q1 + q2)]]
        np.testing.assert_allclose(J[:2], J_P, atol=1e-12)
        np.testing.assert_allclose(J[5], [1.0, 1.0], atol=1e-12)
        np.testing.assert_allclose(end_effector_velocity(robot, q, [1.0, 0.0])[:2], np.array(J_P)[:, 0])


def test_bad_inputs_name_the_argument():
    robot = load("planar_2r")
    with pytest.raises(ValueError, match=r"`q` must have shape \(2,\), got \(3,\)"):
        direct_kinematics(robot, np.zeros(3))
    with pytest.raises(ValueError, match="`q` must be finite"):
        geometric_jacobian(robot, [np.nan, 0.0])
    with pytest.raises(ValueError, match="no frame 'tool'"):
        direct_kinematics(robot, np.zeros(2), frame="tool")
