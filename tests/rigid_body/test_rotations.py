"""Property tests of rigid_body.rotations against independent references (Pinocchio's exp3/log3,
quaternions, SE3, rpyToMatrix; the manual's closed forms; plain matrix products)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rigid_body import rotations as rot

ANGLE = st.floats(-np.pi, np.pi, allow_nan=False)
settings.register_profile("rmpc", max_examples=150, deadline=None)
settings.load_profile("rmpc")


def wrap(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def assert_angles_equal(a, b, atol=1e-9):
    np.testing.assert_allclose(wrap(np.asarray(a) - np.asarray(b)), 0.0, atol=atol)


@st.composite
def unit_vectors(draw):
    v = np.array(draw(st.tuples(*[st.floats(-1, 1, allow_nan=False)] * 3)))
    if np.linalg.norm(v) < 1e-3:
        v = np.array([0.0, 0.0, 1.0])
    return v / np.linalg.norm(v)


@st.composite
def unit_quaternions(draw):
    Q = np.array(draw(st.tuples(*[st.floats(-1, 1, allow_nan=False)] * 4)))
    if np.linalg.norm(Q) < 1e-3:
        Q = np.array([1.0, 0.0, 0.0, 0.0])
    return Q / np.linalg.norm(Q)


@st.composite
def rotations(draw):
    return rot.quaternion_to_rotation(draw(unit_quaternions()))


# ----------------------------------------------------------------------------- elementary rotations

@given(ANGLE)
def test_elementary_rotations_are_exp_of_axis(a):
    for R, axis in ((rot.rot_x(a), [1, 0, 0]), (rot.rot_y(a), [0, 1, 0]), (rot.rot_z(a), [0, 0, 1])):
        np.testing.assert_allclose(R, pin.exp3(a * np.array(axis, float)), atol=1e-12)


@given(unit_vectors(), unit_vectors())
def test_skew_is_cross_product_and_vee_inverts_it(v, p):
    np.testing.assert_allclose(rot.skew(v) @ p, np.cross(v, p), atol=1e-14)
    np.testing.assert_allclose(rot.vee(rot.skew(v)), v, atol=1e-15)
    np.testing.assert_allclose(rot.skew(v), pin.skew(v), atol=0)


# ----------------------------------------------------------------------------- Euler angles

EULER = {
    "zyz": (rot.euler_zyz_to_rotation, rot.rotation_to_euler_zyz, lambda p, t, s: rot.rot_z(p) @ rot.rot_y(t) @ rot.rot_z(s)),
    "zxz": (rot.euler_zxz_to_rotation, rot.rotation_to_euler_zxz, lambda p, t, s: rot.rot_z(p) @ rot.rot_x(t) @ rot.rot_z(s)),
    "rpy": (rot.rpy_to_rotation, rot.rotation_to_rpy, lambda p, t, s: pin.rpy.rpyToMatrix(s, t, p)),
}


@pytest.mark.parametrize("kind", EULER)
@given(phi=ANGLE, theta=ANGLE, psi=ANGLE)
def test_euler_matrix_matches_product_of_elementary_rotations(kind, phi, theta, psi):
    forward, _, reference = EULER[kind]
    np.testing.assert_allclose(forward([phi, theta, psi]), reference(phi, theta, psi), atol=1e-12)


def test_zxz_matrix_is_the_manuals_closed_form():
    rng = np.random.default_rng(1)
    for ph, th, ps in rng.uniform(-np.pi, np.pi, (50, 3)):
        c, s = np.cos, np.sin
        expected = [[c(ph) * c(ps) - s(ph) * c(th) * s(ps), -c(ph) * s(ps) - s(ph) * c(th) * c(ps), s(ph) * s(th)],
                    [s(ph) * c(ps) + c(ph) * c(th) * s(ps), -s(ph) * s(ps) + c(ph) * c(th) * c(ps), -c(ph) * s(th)],
                    [s(th) * s(ps), s(th) * c(ps), c(th)]]
        np.testing.assert_allclose(rot.euler_zxz_to_rotation([ph, th, ps]), expected, atol=1e-12)


@pytest.mark.parametrize("kind", EULER)
@pytest.mark.parametrize("branch", [1, -1])
@given(R=rotations())
def test_euler_inverse_reproduces_any_rotation(kind, branch, R):
    forward, inverse, _ = EULER[kind]
    res = inverse(R, branch)
    np.testing.assert_allclose(forward(res.angles), R, atol=1e-12)
    theta = res.angles[1]
    if not res.singular:  # the branch's interval for θ
        if kind == "rpy":
            assert (abs(theta) < np.pi / 2) == (branch == 1)
        else:
            assert (theta > 0) == (branch == 1)


@pytest.mark.parametrize("kind", EULER)
@given(phi=ANGLE, theta=st.floats(0.01, np.pi - 0.01), psi=ANGLE)
def test_euler_inverse_recovers_the_angles_on_each_branch(kind, phi, theta, psi):
    forward, inverse, _ = EULER[kind]
    if kind == "rpy":  # θ ∈ (−π/2, π/2) for branch +1, (π/2, 3π/2) for branch −1
        theta = theta - np.pi / 2
        other = [phi + np.pi, np.pi - theta, psi + np.pi]
    else:  # θ ∈ (0, π) for branch +1, (−π, 0) for branch −1
        other = [phi + np.pi, -theta, psi + np.pi]
    R = forward([phi, theta, psi])
    assert_angles_equal(inverse(R, 1).angles, [phi, theta, psi])
    assert_angles_equal(inverse(R, -1).angles, other)
    np.testing.assert_allclose(forward(other), R, atol=1e-12)


@pytest.mark.parametrize("branch", [1, -1])
@given(phi=ANGLE, psi=ANGLE, theta=st.sampled_from([0.0, np.pi]))
def test_zyz_singular_set_only_sum_or_difference_is_determined(branch, phi, psi, theta):
    """Problem 2.2: θ = 0 → R = Rz(φ+ψ); θ = π → R = Rz(φ−ψ) diag(−1, 1, −1); φ ± ψ = Atan2(−r12, r22)."""
    R = rot.euler_zyz_to_rotation([phi, theta, psi])
    sign = 1.0 if theta == 0.0 else -1.0
    g = phi + sign * psi
    c, s = np.cos(g), np.sin(g)
    closed = [[c, -s, 0], [s, c, 0], [0, 0, 1]] if theta == 0.0 else [[-c, -s, 0], [-s, c, 0], [0, 0, -1]]
    np.testing.assert_allclose(R, closed, atol=1e-12)
    assert_angles_equal(np.arctan2(-R[0, 1], R[1, 1]), g)
    res = rot.rotation_to_euler_zyz(R, branch)
    assert res.singular
    np.testing.assert_allclose(rot.euler_zyz_to_rotation(res.angles), R, atol=1e-12)
    assert_angles_equal(res.angles[0] + sign * res.angles[2], g)


@pytest.mark.parametrize("branch", [1, -1])
@given(phi=ANGLE, psi=ANGLE, theta=st.sampled_from([0.0, np.pi]))
def test_zxz_singular_set_is_flagged_and_reproduced(branch, phi, psi, theta):
    R = rot.euler_zxz_to_rotation([phi, theta, psi])
    res = rot.rotation_to_euler_zxz(R, branch)
    assert res.singular
    np.testing.assert_allclose(rot.euler_zxz_to_rotation(res.angles), R, atol=1e-12)


@pytest.mark.parametrize("branch", [1, -1])
@given(phi=ANGLE, psi=ANGLE, theta=st.sampled_from([np.pi / 2, -np.pi / 2]))
def test_rpy_singular_set_psi_pm_phi_is_atan2(branch, phi, psi, theta):
    """Problem 2.3: c_θ = 0 → only ψ ± φ = Atan2(−r23, r22) (+ for θ = −π/2, − for θ = π/2)."""
    R = rot.rpy_to_rotation([phi, theta, psi])
    sign = 1.0 if theta < 0 else -1.0
    g = psi + sign * phi
    c, s = np.cos(g), np.sin(g)
    closed = ([[0, s, c], [0, c, -s], [-1, 0, 0]] if theta > 0 else [[0, -s, -c], [0, c, -s], [1, 0, 0]])
    np.testing.assert_allclose(R, closed, atol=1e-12)
    assert_angles_equal(np.arctan2(-R[1, 2], R[1, 1]), g)
    res = rot.rotation_to_rpy(R, branch)
    assert res.singular
    np.testing.assert_allclose(rot.rpy_to_rotation(res.angles), R, atol=1e-12)


@pytest.mark.parametrize("kind", EULER)
@given(phi=ANGLE, psi=ANGLE, eps=st.floats(1e-13, 1e-6))
def test_euler_inverse_is_accurate_next_to_the_singular_set(kind, phi, psi, eps):
    forward, inverse, _ = EULER[kind]
    theta = np.pi / 2 - eps if kind == "rpy" else eps
    R = forward([phi, theta, psi])
    for branch in (1, -1):
        np.testing.assert_allclose(forward(inverse(R, branch).angles), R, atol=1e-12)


# ----------------------------------------------------------------------------- axis–angle

@given(theta=ANGLE, r=unit_vectors())
def test_axis_angle_matrix_is_exp3(theta, r):
    np.testing.assert_allclose(rot.axis_angle_to_rotation(theta, r), pin.exp3(theta * r), atol=1e-12)


@given(theta=ANGLE, r=unit_vectors())
def test_axis_angle_is_the_five_factor_product_2_24(theta, r):
    """Problem 2.4: Rz(α) Ry(β) Rz(θ) Ry(−β) Rz(−α) with r = [c_α s_β, s_α s_β, c_β]."""
    alpha, beta = np.arctan2(r[1], r[0]), np.arctan2(np.hypot(r[0], r[1]), r[2])
    R = rot.rot_z(alpha) @ rot.rot_y(beta) @ rot.rot_z(theta) @ rot.rot_y(-beta) @ rot.rot_z(-alpha)
    np.testing.assert_allclose(rot.axis_angle_to_rotation(theta, r), R, atol=1e-12)


@given(R=rotations())
def test_axis_angle_inverse_reproduces_and_matches_log3(R):
    theta, r = rot.rotation_to_axis_angle(R)
    assert 0.0 <= theta <= np.pi
    assert abs(np.linalg.norm(r) - 1.0) < 1e-12
    np.testing.assert_allclose(rot.axis_angle_to_rotation(theta, r), R, atol=1e-12)
    if theta < np.pi - 1e-6:
        np.testing.assert_allclose(theta * r, pin.log3(R), atol=1e-9)


@pytest.mark.parametrize("r", [[0, 1, 0], [0, 1 / np.sqrt(2), 1 / np.sqrt(2)], [1, 0, 0], [0, 0, 1],
                               [0.6, 0.0, -0.8]])
def test_axis_angle_inverse_at_pi_returns_plus_or_minus_r(r):
    """Problem 2.5: θ = π, including r_x = 0 where the first-column formula fails."""
    r = np.asarray(r, float)
    theta, r_hat = rot.rotation_to_axis_angle(rot.axis_angle_to_rotation(np.pi, r))
    assert theta == pytest.approx(np.pi, abs=1e-12)
    assert min(np.linalg.norm(r_hat - r), np.linalg.norm(r_hat + r)) < 1e-12


@given(r=unit_vectors(), eps=st.floats(1e-12, 1e-4))
def test_axis_angle_inverse_next_to_pi_and_zero(r, eps):
    for theta in (np.pi - eps, eps):
        R = rot.axis_angle_to_rotation(theta, r)
        th, r_hat = rot.rotation_to_axis_angle(R)
        np.testing.assert_allclose(rot.axis_angle_to_rotation(th, r_hat), R, atol=1e-12)


def test_axis_angle_inverse_at_zero_is_zero_with_a_unit_axis():
    theta, r = rot.rotation_to_axis_angle(np.eye(3))
    assert theta == 0.0 and np.linalg.norm(r) == pytest.approx(1.0)


# ----------------------------------------------------------------------------- unit quaternion

@given(Q=unit_quaternions())
def test_quaternion_matrix_matches_pinocchio(Q):
    eta, ex, ey, ez = Q
    np.testing.assert_allclose(rot.quaternion_to_rotation(Q), pin.Quaternion(eta, ex, ey, ez).toRotationMatrix(),
                               atol=1e-12)


@given(theta=ANGLE, r=unit_vectors())
def test_quaternion_of_axis_angle_2_30_2_31(theta, r):
    """Problem 2.6: η = cos(θ/2), ε = sin(θ/2) r gives (2.33) = (2.25)."""
    Q = np.concatenate([[np.cos(theta / 2)], np.sin(theta / 2) * r])
    np.testing.assert_allclose(rot.quaternion_to_rotation(Q), rot.axis_angle_to_rotation(theta, r), atol=1e-12)


@given(Q=unit_quaternions())
def test_eps_is_invariant_under_R_and_RT(Q):
    """Problem 2.7."""
    R = rot.quaternion_to_rotation(Q)
    np.testing.assert_allclose(R @ Q[1:], Q[1:], atol=1e-12)
    np.testing.assert_allclose(R.T @ Q[1:], Q[1:], atol=1e-12)


@given(Q=unit_quaternions())
def test_quaternion_inverse_formula_has_eta_nonnegative_and_round_trips(Q):
    """Problem 2.8: (2.34)–(2.35) give η ≥ 0 and Q up to sign."""
    Q_hat = rot.rotation_to_quaternion(rot.quaternion_to_rotation(Q))
    assert Q_hat[0] >= 0.0
    assert min(np.linalg.norm(Q_hat - Q), np.linalg.norm(Q_hat + Q)) < 1e-12


@given(Q=unit_quaternions())
def test_quaternion_inverse_matches_book_formula_where_it_is_well_conditioned(Q):
    R = rot.quaternion_to_rotation(Q)
    sgn = lambda x: 1.0 if x >= 0 else -1.0  # the book's sgn
    eta = 0.5 * np.sqrt(max(np.trace(R) + 1, 0))
    if eta < 0.1:
        return
    eps = 0.5 * np.array([sgn(R[2, 1] - R[1, 2]) * np.sqrt(max(R[0, 0] - R[1, 1] - R[2, 2] + 1, 0)),
                          sgn(R[0, 2] - R[2, 0]) * np.sqrt(max(R[1, 1] - R[2, 2] - R[0, 0] + 1, 0)),
                          sgn(R[1, 0] - R[0, 1]) * np.sqrt(max(R[2, 2] - R[0, 0] - R[1, 1] + 1, 0))])
    np.testing.assert_allclose(rot.rotation_to_quaternion(R), np.concatenate([[eta], eps]), atol=1e-7)


@given(r=unit_vectors(), eps=st.sampled_from([0.0, 1e-12, 1e-8]))
def test_quaternion_inverse_is_robust_when_eta_vanishes(r, eps):
    """θ = π − ε: η ≈ 0, where the signs of (2.35) come from vanishing differences."""
    R = rot.axis_angle_to_rotation(np.pi - eps, r)
    Q = rot.rotation_to_quaternion(R)
    np.testing.assert_allclose(rot.quaternion_to_rotation(Q), R, atol=1e-12)


@given(Q1=unit_quaternions(), Q2=unit_quaternions())
def test_quaternion_product_is_matrix_product(Q1, Q2):
    """Problem 2.9: R(Q1 ∗ Q2) = R(Q1) R(Q2) and ¼ (tr + 1) = (η1 η2 − ε1ᵀ ε2)²."""
    Q = rot.quaternion_product(Q1, Q2)
    R = rot.quaternion_to_rotation(Q1) @ rot.quaternion_to_rotation(Q2)
    np.testing.assert_allclose(rot.quaternion_to_rotation(Q), R, atol=1e-12)
    assert 0.25 * (np.trace(R) + 1) == pytest.approx(Q[0] ** 2, abs=1e-12)
    np.testing.assert_allclose(rot.quaternion_to_rotation(rot.quaternion_inverse(Q1)),
                               rot.quaternion_to_rotation(Q1).T, atol=1e-12)


# ----------------------------------------------------------------------------- homogeneous transforms

@given(R=rotations(), o=st.tuples(*[st.floats(-10, 10, allow_nan=False)] * 3))
def test_homogeneous_inverse_matches_linalg_and_se3(R, o):
    """Problem 2.10."""
    T = rot.homogeneous_transform(R, o)
    Ti = rot.homogeneous_inverse(T)
    np.testing.assert_allclose(Ti, np.linalg.inv(T), atol=1e-11)
    np.testing.assert_allclose(Ti, pin.SE3(T).inverse().homogeneous, atol=1e-12)


# ----------------------------------------------------------------------------- input validation

@pytest.mark.parametrize("call, message", [
    (lambda: rot.rotation_to_euler_zyz(np.eye(2)), "`R` must have shape"),
    (lambda: rot.rotation_to_rpy(np.full((3, 3), np.nan)), "`R` must be finite"),
    (lambda: rot.rotation_to_axis_angle(2 * np.eye(3)), "`R` is not orthonormal"),
    (lambda: rot.rotation_to_quaternion(np.diag([1.0, 1.0, -1.0])), "reflection"),
    (lambda: rot.quaternion_to_rotation([1.0, 1.0, 0.0, 0.0]), "`Q` must be a unit quaternion"),
    (lambda: rot.quaternion_product([1, 0, 0, 0], [1, 0, 0]), "`Q2` must have shape"),
    (lambda: rot.axis_angle_to_rotation(1.0, [1.0, 1.0, 0.0]), "`r` must be a unit vector"),
    (lambda: rot.homogeneous_inverse(np.ones((4, 4))), "last row"),
    (lambda: rot.rotation_to_euler_zxz(np.eye(3), branch=0), "`branch`"),
    (lambda: rot.rot_z([1.0, 2.0]), "`a` must have shape"),
    (lambda: rot.euler_zyz_to_rotation([1.0, np.inf, 0.0]), "must be finite"),
])
def test_bad_input_raises_value_error_naming_the_argument(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_wrap_angle_maps_into_minus_pi_pi():
    """wrap_angle(a) ∈ (−π, π] and differs from a by a multiple of 2π (one home for angle wrapping)."""
    a = np.array([-7.0, -np.pi, -3.0, 0.0, np.pi, 3.5, 10.0])
    w = rot.wrap_angle(a)
    assert np.all(w > -np.pi) and np.all(w <= np.pi)
    k = (a - w) / (2 * np.pi)
    np.testing.assert_allclose(k, np.round(k), atol=1e-12)
    np.testing.assert_allclose(w[[1, 4, 5]], [np.pi, np.pi, 3.5 - 2 * np.pi], atol=1e-15)
