"""Manipulability measure, rank, velocity/force ellipsoids and the analytical Jacobian."""

import matplotlib.pyplot as plt
import numpy as np
import pytest

from rigid_body.kinematics import analytical_jacobian, direct_kinematics, geometric_jacobian
from rigid_body.manipulability import (force_ellipsoid, is_singular, jacobian_rank, manipulability, plot_ellipse,
                                       velocity_ellipsoid)
from rigid_body.robots import load
from rigid_body.rotations import rotation_to_euler_zyz, rotation_to_rpy


def test_manipulability_is_product_of_singular_values(rng):
    for shape in ((2, 3), (6, 7), (3, 3)):
        J = rng.normal(size=shape)
        assert manipulability(J) == pytest.approx(np.prod(np.linalg.svd(J, compute_uv=False)), rel=1e-10)


def test_rank_and_singularity_of_two_link_arm():
    robot = load("planar_2r")
    assert is_singular(geometric_jacobian(robot, np.array([0.3, 0.0]))[:2])
    assert jacobian_rank(geometric_jacobian(robot, np.array([0.3, 0.0]))[:2]) == 1
    assert not is_singular(geometric_jacobian(robot, np.array([0.3, 1.0]))[:2])


def test_ellipsoids_are_dual_and_satisfy_quadratic_forms(rng):
    J = rng.normal(size=(3, 5))
    v, f = velocity_ellipsoid(J), force_ellipsoid(J)
    A = J @ J.T
    for i in range(3):
        x = v.semi_axes[i] * v.axes[:, i]
        assert x @ np.linalg.solve(A, x) == pytest.approx(1.0)        # (3.123)
        y = f.semi_axes[i] * f.axes[:, i]
        assert y @ A @ y == pytest.approx(1.0)                         # (3.126)
    with pytest.raises(ValueError, match="singular"):
        velocity_ellipsoid(np.array([[1.0, 1.0], [1.0, 1.0]]))
    with pytest.raises(ValueError, match="force ellipsoid"):
        force_ellipsoid(np.array([[1.0, 1.0], [1.0, 1.0]]))
    fig, ax = plt.subplots()
    line = plot_ellipse(ax, velocity_ellipsoid(J[:2, :2]))
    assert line.get_xydata().shape == (100, 2)
    plt.close(fig)


@pytest.mark.parametrize("representation, extract", [("zyz", rotation_to_euler_zyz), ("rpy", rotation_to_rpy)])
def test_analytical_jacobian_is_derivative_of_euler_angles(representation, extract, rng):
    robot = load("ur5")
    q = robot.random_configuration(rng)
    JA = analytical_jacobian(robot, q, representation)

    def x(qq):
        T = direct_kinematics(robot, qq)
        return np.concatenate([T[:3, 3], extract(T[:3, :3]).angles])

    h = 1e-6
    fd = np.column_stack([(x(q + h * e) - x(q - h * e)) / (2 * h) for e in np.eye(6)])
    np.testing.assert_allclose(JA, fd, atol=1e-6)
    with pytest.raises(ValueError, match="representation"):
        analytical_jacobian(robot, q, "xyz")
