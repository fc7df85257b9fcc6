"""Asada's inertia-weighted manipulability and the end-effector (body) frame Jacobian.

References: the two-link arm in closed form (tests/two_link_closed_form.py, no Pinocchio), 2×2
eigenvalues by the quadratic formula, hand-worked diagonal examples, the Toolbox's formula
λ_min/λ_max of J^{-T} B J^{-1}, and central finite differences of the direct kinematics.
"""

import math

import numpy as np
import pytest

from rigid_body.dynamics import inertia_matrix
from rigid_body.kinematics import direct_kinematics, geometric_jacobian
from rigid_body.manipulability import asada_manipulability, end_effector_jacobian, jacobian_in_frame
from rigid_body.robots import load
from tests import two_link_closed_form as arm2

Q_SAMPLES = [np.array([0.3, 0.5]), np.array([-1.2, 2.0]), np.array([2.5, -0.8])]


def _eig_ratio_2x2(A):
    tr, det = A[0, 0] + A[1, 1], A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    disc = math.sqrt(tr**2 / 4 - det)
    return (tr / 2 - disc) / (tr / 2 + disc)


def test_asada_hand_worked_examples():
    assert asada_manipulability(np.eye(2), np.diag([2.0, 8.0])) == pytest.approx(0.25)  # B_A = diag(2, 8)
    assert asada_manipulability(np.diag([1.0, 2.0]), np.diag([1.0, 4.0])) == pytest.approx(1.0)  # B_A = I
    # B = I: the ellipsoid of (J J^T)^{-1}, ratio (σ_min/σ_max)²
    J = np.array([[3.0, 0.0], [0.0, 1.0]])
    assert asada_manipulability(J, np.eye(2)) == pytest.approx(1 / 9)


@pytest.mark.parametrize("q", Q_SAMPLES)
def test_asada_on_the_two_link_arm_against_the_closed_form(q):
    J, B = arm2.jacobian(q), arm2.inertia(q)
    expected = _eig_ratio_2x2(J @ np.linalg.inv(B) @ J.T)
    # the Toolbox's form, from the operational-space inertia J^{-T} B J^{-1}: the same ratio
    Ji = np.linalg.inv(J)
    lam = np.linalg.eigvalsh(Ji.T @ B @ Ji)
    assert lam[0] / lam[-1] == pytest.approx(expected, rel=1e-10)
    robot = load("planar_2r")
    J6 = geometric_jacobian(robot, q)
    B_model = inertia_matrix(robot, q)
    np.testing.assert_allclose(B_model, B, rtol=1e-9)
    assert asada_manipulability(J6[:2], B_model) == pytest.approx(expected, rel=1e-9)
    # translational rows x, y, z of a planar arm: no acceleration along z, the ellipsoid degenerates
    assert asada_manipulability(J6, B_model, axes="trans") == pytest.approx(0.0, abs=1e-12)
    # rotational rows: only ω_z moves, also degenerate
    assert asada_manipulability(J6, B_model, axes="rot") == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("name, axes, rows", [("anthropomorphic", "trans", slice(0, 3)),
                                               ("spherical_wrist", "rot", slice(3, 6))])
def test_asada_translational_and_rotational_against_the_toolbox_formula(name, axes, rows):
    # three joints, three task rows: the Toolbox's λ_min/λ_max of J^{-T} B J^{-1} with an explicit inverse
    robot = load(name)
    q = np.array([0.3, 0.7, -0.8])
    J, B = geometric_jacobian(robot, q), inertia_matrix(robot, q)
    Ji = np.linalg.inv(J[rows])
    lam = np.linalg.eigvalsh(Ji.T @ B @ Ji)
    assert 0.01 < lam[0] / lam[-1] < 0.99  # a genuinely anisotropic ellipsoid
    assert asada_manipulability(J, B, axes=axes) == pytest.approx(lam[0] / lam[-1], rel=1e-9)


def test_asada_vanishes_at_a_singularity_and_is_scale_free():
    q = np.array([0.4, 0.0])  # stretched arm
    assert asada_manipulability(arm2.jacobian(q), arm2.inertia(q)) == pytest.approx(0.0, abs=1e-12)
    q = np.array([0.4, 1.0])
    J, B = arm2.jacobian(q), arm2.inertia(q)
    assert asada_manipulability(J, 7.0 * B) == pytest.approx(asada_manipulability(J, B))
    assert asada_manipulability(2.0 * J, B) == pytest.approx(asada_manipulability(J, B))


@pytest.mark.parametrize("q", Q_SAMPLES)
def test_end_effector_jacobian_of_the_two_link_arm_in_closed_form(q):
    # in frame 2 (x along link 2): joint 2 moves the tip by a2 along y_2; joint 1 adds a1 (sin q2, cos q2)
    a1, a2 = arm2.A1, arm2.A2
    s2, c2 = math.sin(q[1]), math.cos(q[1])
    expected = np.array([[a1 * s2, 0.0], [a1 * c2 + a2, a2], [0, 0], [0, 0], [0, 0], [1.0, 1.0]])
    np.testing.assert_allclose(end_effector_jacobian(load("planar_2r"), q), expected, atol=1e-12)


def test_end_effector_jacobian_by_finite_differences():
    robot = load("anthropomorphic_wrist")  # six joints: every column of J^e moves
    rng = np.random.default_rng(7)
    q = rng.uniform(-1.0, 1.0, robot.nq)
    Je = end_effector_jacobian(robot, q)
    T = direct_kinematics(robot, q)
    Ti = np.linalg.inv(T)
    h = 1e-6
    for i in range(robot.nq):
        dq = np.zeros(robot.nq)
        dq[i] = h
        dT = Ti @ (direct_kinematics(robot, q + dq) - direct_kinematics(robot, q - dq)) / (2 * h)  # (ξ_i^e)^
        col = np.concatenate([dT[:3, 3], [dT[2, 1], dT[0, 2], dT[1, 0]]])
        np.testing.assert_allclose(Je[:, i], col, atol=1e-8)


def test_jacobian_in_frame_rotates_both_halves():
    J = np.arange(12.0).reshape(6, 2)
    R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # Rz(π/2): R^T (x, y, z) = (y, −x, z)
    expected = np.array([[2, 3], [0, -1], [4, 5], [8, 9], [-6, -7], [10, 11]], dtype=float)
    np.testing.assert_allclose(jacobian_in_frame(J, R), expected)


@pytest.mark.parametrize("call, message", [
    (lambda: asada_manipulability(np.eye(2), np.eye(3)), "`B` must be a finite"),
    (lambda: asada_manipulability(np.eye(2), -np.eye(2)), "symmetric positive definite"),
    (lambda: asada_manipulability(np.eye(2), np.eye(2), axes="trans"), "6 rows"),
    (lambda: asada_manipulability(np.eye(2), np.eye(2), axes="xyz"), "`axes` must be one of"),
    (lambda: jacobian_in_frame(np.ones((3, 2)), np.eye(3)), "6 rows"),
    (lambda: jacobian_in_frame(np.ones((6, 2)), 2 * np.eye(3)), "not orthonormal"),
])
def test_bad_input_names_the_argument(call, message):
    with pytest.raises(ValueError, match=message):
        call()
