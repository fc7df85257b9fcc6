"""Roll–pitch–yaw in the peers' orders zyx (the book's (2.21)), xyz and yxz.

References: the elementary rotations written out below (not rmpc's), their products in each order,
and scipy's intrinsic Euler sequences ('ZYX', 'XYZ', 'YXZ' = R_a(φ) R_b(θ) R_c(ψ)).
"""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rigid_body import rotations as rot


def Rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def Ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def Rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


PRODUCT = {
    "zyx": lambda f, t, p: Rz(f) @ Ry(t) @ Rx(p),
    "xyz": lambda f, t, p: Rx(f) @ Ry(t) @ Rz(p),
    "yxz": lambda f, t, p: Ry(f) @ Rx(t) @ Rz(p),
}
GENERIC = [(0.3, -0.7, 1.9), (-2.5, 1.2, -0.4), (3.0, 0.05, -3.0), (1.0, -1.5, 2.2)]


@pytest.mark.parametrize("order", rot.RPY_ORDERS)
@pytest.mark.parametrize("angles", GENERIC)
def test_rpy_to_rotation_is_the_product_of_elementary_rotations(order, angles):
    R = rot.rpy_to_rotation(angles, order=order)
    np.testing.assert_allclose(R, PRODUCT[order](*angles), atol=1e-15)
    np.testing.assert_allclose(R, Rotation.from_euler(order.upper(), angles).as_matrix(), atol=1e-14)


def test_default_order_is_the_books_zyx():
    a = GENERIC[0]
    np.testing.assert_allclose(rot.rpy_to_rotation(a), Rz(a[0]) @ Ry(a[1]) @ Rx(a[2]), atol=1e-15)


@pytest.mark.parametrize("order", rot.RPY_ORDERS)
@pytest.mark.parametrize("angles", GENERIC)
@pytest.mark.parametrize("branch", [1, -1])
def test_round_trip_on_generic_rotations(order, angles, branch):
    R = PRODUCT[order](*angles)
    res = rot.rotation_to_rpy(R, branch, order=order)
    assert not res.singular
    np.testing.assert_allclose(PRODUCT[order](*res.angles), R, atol=1e-14)
    theta = res.angles[1]
    if branch == 1:
        assert -math.pi / 2 < theta < math.pi / 2
        np.testing.assert_allclose(res.angles, angles, atol=1e-13)  # the generic angles have |θ| < π/2
    else:  # θ ∈ (π/2, 3π/2) wrapped: |θ| > π/2
        assert abs(theta) > math.pi / 2
    # the other branch: (φ + π, π − θ, ψ + π)
    other = rot.rotation_to_rpy(R, -branch, order=order).angles
    np.testing.assert_allclose(rot.wrap_angle(other - [res.angles[0] + math.pi, math.pi - theta,
                                                       res.angles[2] + math.pi]), 0.0, atol=1e-12)


@pytest.mark.parametrize("order", rot.RPY_ORDERS)
@pytest.mark.parametrize("theta", [math.pi / 2, -math.pi / 2])
@pytest.mark.parametrize("phi, psi", [(0.4, 1.1), (-2.0, 0.7)])
def test_singular_set_returns_the_psi_zero_representative(order, theta, phi, psi):
    R = PRODUCT[order](phi, theta, psi)
    res = rot.rotation_to_rpy(R, order=order)
    assert res.singular
    assert res.angles[2] == 0.0
    assert res.angles[1] == pytest.approx(theta)
    np.testing.assert_allclose(PRODUCT[order](*res.angles), R, atol=1e-12)
    # R_b(θ) e_c = ε sin θ e_a at cos θ = 0, so R = R_a(φ + ε sin θ ψ) R_b(θ): only that sum is determined
    eps = {"zyx": -1, "xyz": 1, "yxz": -1}[order]  # +1 for a cyclic order of the axes
    assert abs(rot.wrap_angle(res.angles[0] - (phi + eps * math.copysign(1, theta) * psi))) < 1e-12


@pytest.mark.parametrize("order", rot.RPY_ORDERS)
def test_near_singular_rotation_is_still_reproduced(order):
    R = PRODUCT[order](0.8, math.pi / 2 - 1e-9, -0.3)
    res = rot.rotation_to_rpy(R, order=order)
    assert not res.singular
    np.testing.assert_allclose(PRODUCT[order](*res.angles), R, atol=1e-14)


def test_unknown_order_is_rejected():
    with pytest.raises(ValueError, match="`order` must be one of"):
        rot.rpy_to_rotation([0, 0, 0], order="zyz")
    with pytest.raises(ValueError, match="`order` must be one of"):
        rot.rotation_to_rpy(np.eye(3), order="xzy")


def test_spatialmath_published_cases():
    # spatialmath tests: rpy2tr(0.1, 0.2, 0.3, order) is Rz(0.3) Ry(0.2) Rx(0.1), Rx(0.3) Ry(0.2) Rz(0.1),
    # Ry(0.3) Rx(0.2) Rz(0.1): rmpc lists the same angles in reverse
    for order, expected in (("zyx", Rz(0.3) @ Ry(0.2) @ Rx(0.1)), ("xyz", Rx(0.3) @ Ry(0.2) @ Rz(0.1)),
                            ("yxz", Ry(0.3) @ Rx(0.2) @ Rz(0.1))):
        np.testing.assert_allclose(rot.rpy_to_rotation([0.3, 0.2, 0.1], order=order), expected, atol=1e-15)
        np.testing.assert_allclose(rot.rotation_to_rpy(expected, order=order).angles, [0.3, 0.2, 0.1], atol=1e-14)
    # their corner cases: a half turn about each axis, and pitch ±π/2, must round-trip
    for order in rot.RPY_ORDERS:
        for ang in ([math.pi, 0, 0], [0, math.pi, 0], [0, 0, math.pi], [0, math.pi / 2, 0], [0, -math.pi / 2, 0]):
            R = PRODUCT[order](*ang)
            np.testing.assert_allclose(PRODUCT[order](*rot.rotation_to_rpy(R, order=order).angles), R, atol=1e-12)
