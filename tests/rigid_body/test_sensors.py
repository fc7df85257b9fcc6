"""Gray code, wrench transformation (5.32) and the pinhole camera."""

import numpy as np
import pinocchio as pin
import pytest

from rigid_body.camera import PinholeCamera, project
from rigid_body.rotations import axis_angle_to_rotation, homogeneous_inverse, homogeneous_transform
from rigid_body.sensors import binary_to_gray, bits_to_int, gray_to_binary, int_to_bits, wrench_transform


def _random_rotation(rng):
    r = rng.normal(size=3)
    return axis_angle_to_rotation(rng.uniform(0, np.pi), r / np.linalg.norm(r))


def test_gray_round_trip_and_single_bit_change():
    for n_bits in (1, 5, 9):
        prev = None
        for n in range(2**n_bits):
            g = binary_to_gray(int_to_bits(n, n_bits))
            assert bits_to_int(gray_to_binary(g)) == n
            if prev is not None:
                assert np.sum(g != prev) == 1
            prev = g


def test_gray_rejects_non_bits():
    with pytest.raises(ValueError, match="`gray`"):
        gray_to_binary([0, 2, 1])
    with pytest.raises(ValueError, match="`value`"):
        int_to_bits(16, 4)


def test_wrench_transform_matches_pinocchio_and_composes(rng):
    for _ in range(5):
        R1, R2 = _random_rotation(rng), _random_rotation(rng)
        r1, r2 = rng.normal(size=3), rng.normal(size=3)
        h = rng.normal(size=6)
        F = pin.SE3(R1, r1).act(pin.Force(h[:3], h[3:]))
        np.testing.assert_allclose(wrench_transform(R1, r1) @ h, np.concatenate([F.linear, F.angular]), atol=1e-12)
        np.testing.assert_allclose(wrench_transform(R2, r2) @ wrench_transform(R1, r1),
                                   wrench_transform(R2 @ R1, r2 + R2 @ r1), atol=1e-12)


def test_wrench_transform_validates_rotation():
    with pytest.raises(ValueError):
        wrench_transform(np.ones((3, 3)), [0, 0, 0])


def test_projection_principal_point_and_frame_change(rng):
    cam = PinholeCamera(800.0, 700.0, 320.0, 240.0)
    on_axis = project(cam, [0.0, 0.0, 2.0])
    assert (on_axis.X_I, on_axis.Y_I, on_axis.lam) == pytest.approx((320.0, 240.0, 2.0))
    T = homogeneous_transform(_random_rotation(rng), rng.normal(size=3))
    p_c = np.array([0.1, -0.2, 1.5])
    p_b = (T @ np.append(p_c, 1.0))[:3]
    a, b = project(cam, p_b, T), project(cam, p_c)
    assert (a.X_I, a.Y_I, a.lam) == pytest.approx((b.X_I, b.Y_I, b.lam))
    assert b.X_I == pytest.approx(800.0 * 0.1 / 1.5 + 320.0)
    np.testing.assert_allclose(homogeneous_inverse(T) @ np.append(p_b, 1), np.append(p_c, 1), atol=1e-12)


def test_projection_rejects_points_behind_the_camera():
    with pytest.raises(ValueError, match="behind the camera"):
        project(PinholeCamera(500.0, 500.0), [0.0, 0.0, -1.0])
    with pytest.raises(ValueError, match="`f_alpha_x`"):
        PinholeCamera(-1.0, 500.0)


def test_camera_principal_point_must_be_finite():
    with pytest.raises(ValueError, match="`X0`"):
        PinholeCamera(500.0, 500.0, float("nan"), 0.0)
