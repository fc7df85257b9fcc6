"""SE(3)/SO(3) exponentials, screws, differential motion and the projection onto SO(3).

References are independent of Pinocchio: scipy's matrix exponential (Padé), the closed form
T = [[R, V v], [0, 1]] with V = I + (1 − cos θ)/θ² S + (θ − sin θ)/θ³ S², hand-written 4×4 screw
motions, central finite differences, and brute-force search over random rotations.
"""

import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

from rigid_body import rotations as rot
from rigid_body import se3

RNG = np.random.default_rng(20261201)


def _hat(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def _twist_hat(xi):
    X = np.zeros((4, 4))
    X[:3, :3] = _hat(xi[3:])
    X[:3, 3] = xi[:3]
    return X


def _random_twist(max_angle=3.0):
    axis = RNG.normal(size=3)
    axis /= np.linalg.norm(axis)
    return np.concatenate([RNG.uniform(-2, 2, 3), RNG.uniform(0.1, max_angle) * axis])


def _rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


# --------------------------------------------------------------------------------------------
# exp / log
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("k", range(10))
def test_exp6_matches_scipy_expm_and_the_closed_form(k):
    xi = _random_twist()
    T = se3.exp6(xi)
    np.testing.assert_allclose(T, expm(_twist_hat(xi)), atol=1e-12)
    w = xi[3:]
    th = np.linalg.norm(w)
    S = _hat(w)
    V = np.eye(3) + (1 - math.cos(th)) / th**2 * S + (th - math.sin(th)) / th**3 * S @ S
    np.testing.assert_allclose(T[:3, 3], V @ xi[:3], atol=1e-12)
    np.testing.assert_allclose(se3.exp3(w), expm(S), atol=1e-12)


@pytest.mark.parametrize("k", range(10))
def test_log6_inverts_exp6_on_the_principal_branch(k):
    xi = _random_twist(max_angle=3.1)
    T = expm(_twist_hat(xi))  # reference pose, not from Pinocchio
    np.testing.assert_allclose(se3.log6(T), xi, atol=1e-10)
    np.testing.assert_allclose(se3.exp6(se3.log6(T)), T, atol=1e-12)
    np.testing.assert_allclose(se3.log3(T[:3, :3]), xi[3:], atol=1e-10)


@pytest.mark.parametrize("theta", [0.0, 1e-12, 1e-8, 1e-4])
def test_log_near_zero_angle(theta):
    axis = np.array([2.0, -1.0, 2.0]) / 3.0
    R = expm(_hat(theta * axis))
    np.testing.assert_allclose(se3.log3(R), theta * axis, atol=1e-15)
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = [0.3, -0.2, 0.1]
    # for θ → 0, V → I: log6 gives v = o to first order (error ≤ θ ‖o‖/2)
    np.testing.assert_allclose(se3.log6(T)[:3], [0.3, -0.2, 0.1], atol=theta + 1e-15)


@pytest.mark.parametrize("delta", [0.0, 1e-10, 1e-6, 1e-3])
def test_log_near_pi(delta):
    axis = np.array([1.0, 2.0, -2.0]) / 3.0
    theta = math.pi - delta
    R = expm(_hat(theta * axis))
    w = se3.log3(R)
    assert abs(np.linalg.norm(w) - theta) < 1e-9
    sign = 1.0 if delta > 0 else np.sign(w @ axis)  # at θ = π, ±axis are the same rotation
    np.testing.assert_allclose(w, sign * theta * axis, atol=1e-8)
    np.testing.assert_allclose(expm(_hat(w)), R, atol=1e-12)


def test_derivative_of_exp_at_zero_is_the_twist_matrix():
    xi = np.array([0.4, -1.2, 0.7, 0.3, 0.9, -0.5])
    h = 1e-6
    dT = (se3.exp6(h * xi) - se3.exp6(-h * xi)) / (2 * h)
    np.testing.assert_allclose(dT, _twist_hat(xi), atol=1e-9)
    np.testing.assert_allclose(se3.twist_matrix(xi), _twist_hat(xi), atol=0)
    np.testing.assert_allclose(se3.twist_vector(_twist_hat(xi)), xi, atol=0)


def test_modern_robotics_published_examples():
    # MatrixExp3 of [ω] with ω = (1, 2, 3) (Modern Robotics, core.py docstring example)
    np.testing.assert_allclose(se3.exp3([1.0, 2.0, 3.0]),
                               [[-0.69492056, 0.71352099, 0.08929286],
                                [-0.19200697, -0.30378504, 0.93319235],
                                [0.69297817, 0.6313497, 0.34810748]], atol=1e-8)
    # MatrixLog6 of a rotation π/2 about x with o = (0, 0, 3): MR gives [ω; v] = (π/2, 0, 0; 0, 3π/4, 3π/4).
    # By hand: v = θ G⁻¹(θ) o, G⁻¹ = I/θ − ½ S(x) + (1/θ − ½ cot(θ/2)) S(x)², θ = π/2 → (0, 1.5, 1.5) θ.
    T = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 3], [0, 0, 0, 1]])
    np.testing.assert_allclose(se3.log6(T), [0, 3 * math.pi / 4, 3 * math.pi / 4, math.pi / 2, 0, 0], atol=1e-12)
    # ScrewToAxis(q = (3, 0, 0), s = (0, 0, 1), h = 2) = [ω; v] = (0, 0, 1, 0, −3, 2) in MR's order
    S_mr = np.array([0.0, 0.0, 1.0, 0.0, -3.0, 2.0])
    np.testing.assert_allclose(se3.screw_to_twist([0, 0, 1], [3, 0, 0], 2.0), np.r_[S_mr[3:], S_mr[:3]])


# --------------------------------------------------------------------------------------------
# Screws
# --------------------------------------------------------------------------------------------

def test_screw_about_z_through_a_point_with_pitch():
    # rotation π/2 about z through p = (1, 2, 0), pitch h = 0.1 m/rad: o = p − Rz p + h θ z
    xi = se3.screw_to_twist([0, 0, 1], [1.0, 2.0, 0.0], 0.1, math.pi / 2)
    np.testing.assert_allclose(xi, [2 * math.pi / 2, -1 * math.pi / 2, 0.1 * math.pi / 2, 0, 0, math.pi / 2],
                               atol=1e-15)  # v = −z × p + h z = (2, −1, 0.1), times θ
    expected = np.array([[0.0, -1.0, 0.0, 3.0],
                         [1.0, 0.0, 0.0, 1.0],
                         [0.0, 0.0, 1.0, 0.05 * math.pi],
                         [0.0, 0.0, 0.0, 1.0]])
    np.testing.assert_allclose(se3.exp6(xi), expected, atol=1e-14)
    screw = se3.twist_to_screw(se3.log6(expected))
    np.testing.assert_allclose(screw.axis, [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(screw.point, [1, 2, 0], atol=1e-12)
    assert screw.pitch == pytest.approx(0.1, abs=1e-12)
    assert screw.magnitude == pytest.approx(math.pi / 2, abs=1e-12)
    np.testing.assert_allclose(screw.twist, xi, atol=1e-12)


def test_screw_point_is_the_closest_to_the_origin_and_lies_on_the_axis():
    axis = np.array([1.0, 1.0, 0.0]) / math.sqrt(2)
    point = np.array([0.0, 0.0, 1.0]) + 5.0 * axis  # any point of the axis
    s = se3.twist_to_screw(se3.screw_to_twist(axis, point, -0.3, 0.8))
    np.testing.assert_allclose(s.point, [0, 0, 1], atol=1e-12)
    # the points of the axis are fixed by the rotation part, up to the translation h θ along the axis
    T = se3.exp6(s.twist)
    np.testing.assert_allclose(T[:3, :3] @ s.point + T[:3, 3], s.point - 0.3 * 0.8 * axis, atol=1e-12)


def test_pure_translation_screw():
    xi = se3.screw_to_twist([0, 0.6, 0.8], [5, 5, 5], math.inf, 2.0)
    np.testing.assert_allclose(xi, [0, 1.2, 1.6, 0, 0, 0])
    T = se3.exp6(xi)
    np.testing.assert_allclose(T[:3, 3], [0, 1.2, 1.6])
    s = se3.twist_to_screw(xi)
    assert s.pitch == math.inf and s.magnitude == pytest.approx(2.0)
    np.testing.assert_allclose(s.axis, [0, 0.6, 0.8])


def test_screw_interpolation_follows_one_screw():
    T_f = np.array([[0.0, -1.0, 0.0, 3.0], [1.0, 0.0, 0.0, 1.0], [0.0, 0.0, 1.0, 0.05 * math.pi], [0, 0, 0, 1]])
    T_i = np.eye(4)
    T_i[:3, 3] = [0.5, 0.0, -1.0]
    T_f_world = T_i @ T_f
    s = np.linspace(0, 1, 5)
    Ts = se3.screw_interpolation(T_i, T_f_world, s)
    assert Ts.shape == (5, 4, 4)
    np.testing.assert_allclose(Ts[0], T_i, atol=1e-14)
    np.testing.assert_allclose(Ts[-1], T_f_world, atol=1e-12)
    p = np.array([1.0, 2.0, 0.0])
    for sk, T in zip(s, Ts):  # rotation sθ about z through p, translation h sθ: written from the screw
        a = sk * math.pi / 2
        rel = np.eye(4)
        rel[:3, :3] = _rz(a)
        rel[:3, 3] = p - _rz(a) @ p + [0, 0, 0.1 * a]
        np.testing.assert_allclose(T, T_i @ rel, atol=1e-12)
    np.testing.assert_allclose(se3.screw_interpolation(T_i, T_f_world, 0.5), Ts[2], atol=0)


# --------------------------------------------------------------------------------------------
# Differential motion
# --------------------------------------------------------------------------------------------

def test_pose_delta_round_trip_and_first_order_agreement_with_log():
    T_0 = expm(_twist_hat(np.array([0.2, 0.1, -0.4, 0.5, -0.3, 0.8])))
    d = np.array([1e-3, -2e-3, 0.5e-3, 2e-4, 1e-4, -1.5e-4])  # ‖δ‖² within ORTHONORMAL_TOL
    T_1 = se3.delta_to_pose(d, T_0)
    np.testing.assert_allclose(se3.pose_delta(T_0, T_1), d, atol=1e-15)
    for eps in (1e-2, 1e-3, 1e-4):
        xi = eps * np.array([1.0, -0.5, 0.3, 0.7, 0.2, -0.4])
        T_1 = T_0 @ expm(_twist_hat(xi))
        err = np.linalg.norm(se3.pose_delta(T_0, T_1) - xi)
        assert err < 2 * eps**2, (eps, err)  # second-order agreement with log6(T_0⁻¹ T_1) = ξ
        assert err > 0.01 * eps**2  # and not better: the first-order formula has a genuine ε² error


def test_spatialmath_published_delta_cases():
    def transl(x, y, z):
        T = np.eye(4)
        T[:3, 3] = [x, y, z]
        return T

    def trot(R):
        T = np.eye(4)
        T[:3, :3] = R
        return T

    np.testing.assert_allclose(se3.pose_delta(np.eye(4), transl(0.1, 0.2, 0.3)), [0.1, 0.2, 0.3, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(se3.pose_delta(transl(0.1, 0.2, 0.3), transl(0.2, 0.4, 0.6)),
                               [0.1, 0.2, 0.3, 0, 0, 0], atol=1e-15)
    Rx = Rotation.from_rotvec
    np.testing.assert_allclose(se3.pose_delta(np.eye(4), trot(Rx([0.001, 0, 0]).as_matrix())),
                               [0, 0, 0, 0.001, 0, 0], atol=1e-9)
    np.testing.assert_allclose(se3.pose_delta(trot(Rx([0.001, 0, 0]).as_matrix()), trot(Rx([0.002, 0, 0]).as_matrix())),
                               [0, 0, 0, 0.001, 0, 0], atol=1e-9)
    np.testing.assert_allclose(se3.delta_to_pose([0.1, 0.2, 0.3, 0.4, 0.5, 0.6]),
                               [[1.0, -0.6, 0.5, 0.1], [0.6, 1.0, -0.4, 0.2], [-0.5, 0.4, 1.0, 0.3], [0, 0, 0, 1]],
                               atol=1e-15)
    np.testing.assert_allclose(se3.delta_to_pose(np.zeros(6)), np.eye(4), atol=0)
    # trinterp's cases where slerp and the screw agree: midpoints of symmetric pure rotations/translations
    R = Rx([0.3, 0, 0]).as_matrix()
    np.testing.assert_allclose(se3.screw_interpolation(trot(R.T), trot(R), 0.5), np.eye(4), atol=1e-14)
    np.testing.assert_allclose(se3.screw_interpolation(transl(-1, -2, -3), transl(1, 2, 3), 0.5), np.eye(4),
                               atol=1e-14)


# --------------------------------------------------------------------------------------------
# Projection onto SO(3)
# --------------------------------------------------------------------------------------------

def test_nearest_rotation_closed_forms():
    # M = diag(2, 3, −1): polar factor diag(1, 1, −1) is a reflection; flip the smallest σ → R = I
    np.testing.assert_allclose(rot.nearest_rotation(np.diag([2.0, 3.0, -1.0])), np.eye(3), atol=1e-15)
    assert rot.distance_from_so3(np.diag([2.0, 3.0, -1.0])) == pytest.approx(3.0)  # ‖diag(1, 2, −2)‖
    np.testing.assert_allclose(rot.nearest_rotation(np.diag([2.0, -3.0, -1.0])), np.diag([1.0, -1.0, -1.0]),
                               atol=1e-15)
    assert rot.distance_from_so3(np.diag([2.0, -3.0, -1.0])) == pytest.approx(math.sqrt(5.0))
    R = Rotation.from_rotvec([0.3, -1.0, 2.0]).as_matrix()
    np.testing.assert_allclose(rot.nearest_rotation(1.7 * R), R, atol=1e-14)  # scaling does not move it
    assert rot.distance_from_so3(R) < 1e-14


@pytest.mark.parametrize("k", range(3))
def test_nearest_rotation_is_optimal_against_random_rotations(k):
    R0 = Rotation.random(random_state=k).as_matrix()
    M = R0 + 0.05 * RNG.normal(size=(3, 3))
    R = rot.nearest_rotation(M)
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-14)
    assert np.linalg.det(R) == pytest.approx(1.0)
    d_best = np.linalg.norm(M - R)
    assert rot.distance_from_so3(M) == pytest.approx(d_best)
    assert d_best <= np.linalg.norm(M - R0)
    Qs = Rotation.random(4000, random_state=100 + k).as_matrix()
    assert d_best <= np.linalg.norm(M - Qs, axis=(1, 2)).min()
    # local optimality: small rotations of R do not get closer
    for w in 1e-3 * RNG.normal(size=(50, 3)):
        assert d_best <= np.linalg.norm(M - expm(_hat(w)) @ R) + 1e-15


# --------------------------------------------------------------------------------------------
# Bad input
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("call, message", [
    (lambda: se3.exp6(np.zeros(5)), "`xi` must have shape"),
    (lambda: se3.exp3([np.nan, 0, 0]), "`omega` must be finite"),
    (lambda: se3.log3(np.diag([1.0, 1.0, -1.0])), "determinant -1"),
    (lambda: se3.log6(np.eye(3)), "`T` must have shape"),
    (lambda: se3.screw_to_twist([1, 1, 0], [0, 0, 0], 0.0), "`axis` must be a unit vector"),
    (lambda: se3.screw_to_twist([1, 0, 0], [0, 0, 0], math.nan), "`pitch`"),
    (lambda: se3.twist_to_screw(np.zeros(6)), "zero twist"),
    (lambda: se3.screw_interpolation(np.eye(4), np.eye(4), [[0.5]]), "`s`"),
    (lambda: se3.pose_delta(np.eye(4), np.ones((4, 4))), "`T_1`"),
    (lambda: rot.nearest_rotation(np.ones((2, 2))), "`M` must have shape"),
])
def test_bad_input_names_the_argument(call, message):
    with pytest.raises(ValueError, match=message):
        call()
