"""Selection matrices, weighted pseudo-inverses (9.55) and the relative kinematics (9.10)–(9.11)."""

import numpy as np
import pinocchio as pin
import pytest

from rigid_body.rotations import rot_z
from rigid_body.task_space import (contact_wrenches, reciprocal_basis, relative_euler_rate, relative_position_rate,
                                   selection_matrices, selection_projection, selection_pseudo_inverse)


def test_selection_pseudo_inverse_is_weighted_least_squares(rng):
    S = rng.standard_normal((6, 2))
    A = rng.standard_normal((6, 6))
    W = A @ A.T + np.eye(6)
    h = rng.standard_normal(6)
    L = np.linalg.cholesky(W)
    expected = np.linalg.lstsq(L.T @ S, L.T @ h, rcond=None)[0]
    np.testing.assert_allclose(selection_pseudo_inverse(S, W) @ h, expected, atol=1e-12)
    P = selection_projection(S, W)
    np.testing.assert_allclose(P @ P, P, atol=1e-12)
    np.testing.assert_allclose(P @ S, S, atol=1e-12)
    with pytest.raises(ValueError, match="`W`"):
        selection_pseudo_inverse(np.eye(3)[:, :1], np.diag([0.0, 1.0, 1.0]))
    with pytest.raises(ValueError, match="`S`"):
        selection_pseudo_inverse(np.ones((2, 3)))


def test_selection_matrices_complement_and_rotate():
    S_f, S_v = selection_matrices(("x", "rz"))
    assert S_f.shape == (6, 4) and S_v.shape == (6, 2)
    np.testing.assert_array_equal(np.hstack([S_v, S_f]).sum(axis=1), np.ones(6))
    R = rot_z(0.3)
    S_f3, S_v3 = selection_matrices(("x", "rz"), R)
    np.testing.assert_allclose(S_v3[:3, 0], R[:, 0])          # ṗ_x^c in the base frame
    np.testing.assert_allclose(S_v3[3:, 1], R[:, 2])          # ω_z^c in the base frame
    np.testing.assert_allclose(S_f3.T @ S_v3, 0.0, atol=1e-15)
    with pytest.raises(ValueError, match="`velocity_axes`"):
        selection_matrices(("q",))
    with pytest.raises(ValueError, match="`R_c`"):
        selection_matrices(("x",), np.eye(2))
    with pytest.raises(ValueError, match="rotation"):
        selection_matrices(("x",), np.diag([1.0, 1.0, -1.0]))


def test_relative_rates_against_differences(rng):
    """A desired frame spinning about z at ω_d and moving, an end effector moving and rotating."""
    w_d, v_d, v_e = np.array([0.0, 0.0, 0.7]), np.array([0.1, -0.2, 0.05]), np.array([-0.3, 0.2, 0.4])
    w_e = np.array([0.2, -0.1, 0.3])
    R_e0 = pin.exp3(np.array([0.4, 0.9, -0.2]))

    def rel(t):
        R_d, R_e = rot_z(0.7 * t), pin.exp3(w_e * t) @ R_e0
        return R_d.T @ (np.array([0.2, 0.1, 0.3]) + v_e * t - v_d * t), R_d, R_e

    t, h = 0.4, 1e-6
    (o_p, *_), (o_m, *_) = rel(t + h), rel(t - h)
    _, R_d, R_e = rel(t)
    od = relative_position_rate(R_d, v_d * t, v_d, w_d, np.array([0.2, 0.1, 0.3]) + v_e * t, v_e)
    np.testing.assert_allclose(od, (o_p - o_m) / (2 * h), atol=1e-8)
    from rigid_body.rotations import rotation_to_euler_zyz

    phi = lambda tau: rotation_to_euler_zyz(rel(tau)[1].T @ rel(tau)[2]).angles
    np.testing.assert_allclose(relative_euler_rate(R_d, w_d, R_e, w_e), (phi(t + h) - phi(t - h)) / (2 * h), atol=1e-7)
    with pytest.raises(ValueError, match="singular"):
        relative_euler_rate(np.eye(3), np.zeros(3), rot_z(0.3), np.ones(3))


def _spans(A, B, tol=1e-9):
    """The columns of A and B span the same subspace."""
    return np.linalg.matrix_rank(np.hstack([A, B]), tol) == np.linalg.matrix_rank(A, tol) == np.linalg.matrix_rank(B, tol)


def test_a_box_on_a_plane_admits_the_planar_twists_and_exerts_the_normal_wrenches():
    """Four frictionless contacts under a box on the plane z = 0: the box slides and turns in the plane
    (ṗ_x, ṗ_y, ω_z free); the plane pushes along z and twists about x and y (f_z, μ_x, μ_y)."""
    corners = np.array([[1.0, 1.0, 0.0], [-1.0, 1.0, 0.0], [-1.0, -1.0, 0.0], [1.0, -1.0, 0.0]])
    W = contact_wrenches(corners, np.tile([0.0, 0.0, 2.0], (4, 1)))           # normals normalised
    np.testing.assert_allclose(W[:, 0], [0, 0, 1, 1, -1, 0])                  # [n; p × n] at p = (1, 1, 0)
    T = reciprocal_basis(W)
    assert T.shape == (6, 3) and _spans(T, np.eye(6)[:, [0, 1, 5]])
    assert _spans(reciprocal_basis(T), np.eye(6)[:, [2, 3, 4]])
    np.testing.assert_allclose(T.T @ T, np.eye(3), atol=1e-12)                # orthonormal


def test_admissible_twists_keep_the_contacts_to_first_order():
    """A finite motion exp(εξ) (Pinocchio) along an admissible twist changes each contact gap by O(ε²),
    along any other twist by O(ε): the reciprocity of [n; p × n] is that of the geometry."""
    rng = np.random.default_rng(3)
    points, normals = rng.normal(size=(4, 3)), rng.normal(size=(4, 3))
    W = contact_wrenches(points, normals)
    n = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    T, eps = reciprocal_basis(W), 1e-6

    def gaps(xi):
        M = pin.exp6(pin.Motion(eps * xi[:3], eps * xi[3:]))
        moved = np.array([M.act(p) for p in points])
        return np.einsum("ij,ij->i", moved - points, n) / eps

    assert T.shape == (6, 2) and max(np.abs(gaps(t)).max() for t in T.T) < 1e-5
    assert min(np.abs(gaps(x)).max() for x in reciprocal_basis(T).T) > 1e-2


def test_reciprocal_basis_edge_cases_and_errors():
    np.testing.assert_array_equal(reciprocal_basis(np.zeros((6, 2))), np.eye(6))
    assert reciprocal_basis(np.eye(6)).shape == (6, 0)
    assert reciprocal_basis(np.r_[1.0, 0, 0, 0, 0, 0]).shape == (6, 5)
    with pytest.raises(ValueError, match="`S`"):
        reciprocal_basis(np.ones((3, 2)))
    with pytest.raises(ValueError, match="`normals`"):
        contact_wrenches(np.zeros((2, 3)), np.zeros((2, 3)))
    with pytest.raises(ValueError, match="`normals`"):
        contact_wrenches(np.zeros((2, 3)), np.ones((3, 3)))
