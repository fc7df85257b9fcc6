"""Orientation errors (3.85), (3.87), (3.91) and quaternion propagation (3.94)-(3.95)."""

import numpy as np
import pinocchio as pin
import pytest

from rigid_body.rotations import (euler_zyz_to_rotation, orientation_error_axis_angle, orientation_error_euler,
                                  orientation_error_matrix, orientation_error_quaternion, quaternion_angular_velocity,
                                  quaternion_inverse, quaternion_product, quaternion_rate, rotation_to_quaternion)


def _R(rng):
    return pin.exp3(rng.normal(size=3))


def test_axis_angle_error_is_sin_theta_r(rng):
    for _ in range(20):
        R_d, R_e = _R(rng), _R(rng)
        w = pin.log3(R_d @ R_e.T)
        theta = np.linalg.norm(w)
        np.testing.assert_allclose(orientation_error_axis_angle(R_d, R_e), np.sin(theta) * w / theta, atol=1e-12)


def test_quaternion_error_is_vector_part_of_relative_quaternion(rng):
    for _ in range(20):
        Q_d, Q_e = rotation_to_quaternion(_R(rng)), rotation_to_quaternion(_R(rng))
        rel = quaternion_product(Q_d, quaternion_inverse(Q_e))
        np.testing.assert_allclose(orientation_error_quaternion(Q_d, Q_e), rel[1:], atol=1e-12)


def test_error_derivative_matches_L(rng):
    R_d, R_e, w_d, w = _R(rng), _R(rng), rng.normal(size=3), rng.normal(size=3)
    h = 1e-6
    e = [orientation_error_axis_angle(pin.exp3(w_d * t) @ R_d, pin.exp3(w * t) @ R_e) for t in (h, -h)]
    L = orientation_error_matrix(R_d, R_e)
    np.testing.assert_allclose((e[0] - e[1]) / (2 * h), L.T @ w_d - L @ w, atol=1e-8)


def test_quaternion_rate_round_trip(rng):
    Q, w = rotation_to_quaternion(_R(rng)), rng.normal(size=3)
    np.testing.assert_allclose(quaternion_angular_velocity(Q, quaternion_rate(Q, w)), w, atol=1e-12)


def test_euler_error_wraps_and_rejects_singular():
    R_d = euler_zyz_to_rotation([3.1, 0.5, 0.2])
    R_e = euler_zyz_to_rotation([-3.1, 0.5, 0.2])
    np.testing.assert_allclose(orientation_error_euler(R_d, R_e), [6.2 - 2 * np.pi, 0, 0], atol=1e-12)
    with pytest.raises(ValueError, match="singular"):
        orientation_error_euler(np.eye(3), R_e)
