"""Operational-space model (7.130)–(7.138), minimum-norm torques (7.10), dynamic manipulability (7.11)."""

import numpy as np
import pytest

from rigid_body import lagrange as lg
from rigid_body.operational_space import (dynamic_manipulability, dynamic_manipulability_ellipsoid,
                                          dynamically_consistent_inverse, minimum_norm_torque,
                                          minimum_norm_torque_qp, operational_space_inertia,
                                          operational_space_inertia_rate, operational_space_model)
from rigid_body.book_robots import planar_2r, planar_3r


def arm_state(spec, rng, r=2):
    """A random state; for a redundant arm q̇ = J̄ ẋ (no null-space motion), as C_A of Problem 7.9 assumes."""
    model = lg.serial_model(spec)
    q = rng.uniform(0.3, 2.5, model.n)
    B = lg.inertia_matrix(model, q)
    qd = dynamically_consistent_inverse(B, lg.geometric_jacobian(model, q)[:r]) @ rng.normal(size=r)
    C = lg.coriolis_matrix(model, q, qd)
    g = lg.gravity_torques(model, q)
    J = lg.geometric_jacobian(model, q)[:r]
    Jd = lg.geometric_jacobian_rate(model, q, qd)[:r]
    return model, q, qd, B, C, g, J, Jd


@pytest.mark.parametrize("spec", [planar_2r(), planar_3r()], ids=["2R", "3R redundant"])
def test_operational_space_model_reproduces_joint_space_dynamics(spec):
    rng = np.random.default_rng(0)
    model, q, qd, B, C, g, J, Jd = arm_state(spec, rng)
    osm = operational_space_model(B, C, g, J, Jd)
    np.testing.assert_allclose(J @ osm.J_bar, np.eye(2), atol=1e-12)
    # For any q̈ of the dynamically consistent form q̈ = J̄ (ẍ − J̇ q̇), γ_A = J̄ᵀ τ satisfies (7.130)–(7.132).
    xdd = rng.normal(size=2)
    qdd = osm.J_bar @ (xdd - Jd @ qd)
    tau = B @ qdd + C @ qd + g
    np.testing.assert_allclose(osm.B_A @ xdd + osm.C_A @ (J @ qd) + osm.g_A, osm.J_bar.T @ tau, atol=1e-9)
    # Problem 7.9: Ḃ_A − 2C_A is skew-symmetric; Ḃ_A by the formula and by finite differences.
    Bd = lg.inertia_matrix_rate(model, q, qd)
    BAd = operational_space_inertia_rate(B, Bd, J, Jd)
    eps = 1e-6

    def BA(t):
        qt = q + t * qd
        return operational_space_inertia(lg.inertia_matrix(model, qt), lg.geometric_jacobian(model, qt)[:2])

    np.testing.assert_allclose(BAd, (BA(eps) - BA(-eps)) / (2 * eps), rtol=1e-6, atol=1e-6)
    N = BAd - 2 * osm.C_A
    np.testing.assert_allclose(N, -N.T, atol=1e-9 * max(1.0, np.abs(N).max()))


def test_minimum_norm_torque_closed_form_equals_proxsuite_qp():
    rng = np.random.default_rng(1)
    _, q, qd, B, C, g, J, Jd = arm_state(planar_3r(), rng)
    gamma, tau_a = rng.normal(size=2), rng.normal(size=3)
    tau = minimum_norm_torque(B, J, gamma, tau_a)
    np.testing.assert_allclose(minimum_norm_torque_qp(B, J, gamma, tau_a), tau, atol=1e-8)
    J_bar = dynamically_consistent_inverse(B, J)
    np.testing.assert_allclose(J_bar.T @ tau, gamma, atol=1e-10)
    np.testing.assert_allclose(J_bar.T @ (np.eye(3) - J.T @ J_bar.T), 0.0, atol=1e-12)
    # Optimality: any feasible perturbation in the null space of J̄ᵀ increases the cost.
    Binv = np.linalg.inv(B)
    cost = lambda t: 0.5 * (t - tau_a) @ Binv @ (t - tau_a)
    null = np.linalg.svd(J_bar.T)[2][-1]
    assert cost(tau + 1e-3 * null) > cost(tau) and cost(tau - 1e-3 * null) > cost(tau)


def test_dynamic_manipulability_square_case():
    rng = np.random.default_rng(2)
    _, q, _, B, _, _, J, _ = arm_state(planar_2r(), rng)
    w = dynamic_manipulability(J, B)
    np.testing.assert_allclose(w, abs(np.linalg.det(J)) / np.linalg.det(B), rtol=1e-12)
    E = dynamic_manipulability_ellipsoid(J, B)
    np.testing.assert_allclose(E.core, np.linalg.inv(J @ np.linalg.inv(B) @ np.linalg.inv(B).T @ J.T), rtol=1e-9)


def test_singular_jacobian_is_reported():
    B = np.eye(2)
    with pytest.raises(ValueError, match="singular"):
        operational_space_inertia(B, [[1.0, 1.0], [2.0, 2.0]])
    with pytest.raises(ValueError, match="positive definite"):
        operational_space_inertia(-np.eye(2), np.eye(2))


def test_non_symmetric_inertia_is_rejected():
    """cho_factor reads one triangle only: a non-symmetric B would otherwise pass silently."""
    with pytest.raises(ValueError, match="not symmetric"):
        operational_space_inertia(np.array([[2.0, 0.5], [0.0, 1.0]]), np.eye(2))
