"""Tests written for the survivors of the mutation run (benchmarks/mutation.py): each pins a behaviour
the suite did not measure before, against a reference computed another way."""

import numpy as np
import pinocchio as pin
import pytest
from scipy.interpolate import CubicSpline

from planners.inverse_kinematics import cosine_pose_reference
from planners.timing import cubic_spline_law
from rigid_body.rotations import (euler_rate_matrix_rpy, euler_rate_matrix_zyz, euler_zyz_to_rotation,
                                  rotation_to_euler_zyz, rpy_to_rotation)


def _omega_by_differences(R_of, phi, phi_dot, h=1e-6):
    """ω from S(ω) = Ṙ Rᵀ, Ṙ by central differences along φ(t) = φ + t φ̇."""
    Rd = (R_of(phi + h * phi_dot) - R_of(phi - h * phi_dot)) / (2 * h)
    S = Rd @ R_of(phi).T
    return np.array([S[2, 1], S[0, 2], S[1, 0]])


@pytest.mark.parametrize("seed", range(4))
def test_euler_rate_matrices_against_finite_differences(seed):
    """ω = T(φ) φ̇ (3.64) for ZYZ and RPY (Problem 3.12) — every entry of T matters."""
    rng = np.random.default_rng(seed)
    phi, phi_dot = rng.uniform(-np.pi, np.pi, 3), rng.normal(size=3)
    assert np.allclose(euler_rate_matrix_zyz(phi) @ phi_dot, _omega_by_differences(euler_zyz_to_rotation, phi, phi_dot),
                       atol=1e-8)
    assert np.allclose(euler_rate_matrix_rpy(phi) @ phi_dot,
                       _omega_by_differences(lambda a: rpy_to_rotation(a, "zyx"), phi, phi_dot), atol=1e-8)


@pytest.mark.parametrize("seed", range(6))
def test_zyz_angles_of_a_generic_rotation(seed):
    """A rotation with every entry non-zero (r23 ≠ 0): the extracted ZYZ angles rebuild R and equal the
    product Rz(φ) Ry(θ) Rz(ψ) written out — a sign flip in the extraction cannot hide behind r23 = 0."""
    rng = np.random.default_rng(100 + seed)
    angles = np.array([rng.uniform(-3, 3), rng.uniform(0.2, 2.9), rng.uniform(-3, 3)])
    R = pin.exp3(angles[0] * np.array([0, 0, 1.0])) @ pin.exp3(angles[1] * np.array([0, 1.0, 0])) \
        @ pin.exp3(angles[2] * np.array([0, 0, 1.0]))
    assert np.all(np.abs(R) > 1e-3)
    found = rotation_to_euler_zyz(R)
    assert not found.singular and np.allclose(found.angles, angles, atol=1e-12)


def test_cubic_spline_defaults_to_rest_and_matches_scipy_on_unequal_intervals():
    """Unequal intervals (an off-by-one in the spline system is invisible with unit intervals): the
    default spline interpolates, is C² and at rest at both ends, and equals scipy's clamped cubic spline
    through its own knots (a C² cubic spline with given end slopes is unique)."""
    t, q = np.array([0.0, 0.7, 2.0, 2.4, 4.0]), np.array([0.1, 1.0, -0.4, 0.3, 1.2])
    law = cubic_spline_law(t, q)                     # defaults: q̇ = q̈ = 0 at both ends
    pos, vel, acc = law(t)
    assert np.allclose(pos, q, atol=1e-12)
    assert np.allclose([vel[0], vel[-1], acc[0], acc[-1]], 0.0, atol=1e-10)
    knots = law.breaks
    eps = 1e-9
    for k in knots[1:-1]:
        assert abs(law(k + eps)[2] - law(k - eps)[2]) < 1e-6
    # scipy: the cubic spline through the law's own knot values with clamped ends is the same curve
    reference = CubicSpline(knots, law(knots)[0], bc_type=((1, 0.0), (1, 0.0)))
    grid = np.linspace(knots[0], knots[-1], 97)
    assert np.allclose(law(grid)[0], reference(grid), atol=1e-9)


def test_cosine_pose_reference_goes_from_the_initial_to_the_final_point():
    p_i, p_f = np.array([0.7, 0.0, 0.0]), np.array([0.0, 0.8, 0.5])
    ref = cosine_pose_reference(p_i, p_f, 2.0, 0.0, np.pi / 2)
    assert ref(0.0)[0].shape == (4, 4) and ref(0.0)[1].shape == (6,)
    assert np.allclose(ref(0.0)[0][:3, 3], p_i) and np.allclose(ref(2.0)[0][:3, 3], p_f)
    assert np.allclose(ref(1.0)[0][:3, 3], 0.5 * (p_i + p_f))
    assert np.allclose(ref(1.0)[1][:3], 0.5 * np.pi / 2.0 * (p_f - p_i))   # ṡ(t_f/2) = π/(2 t_f)
