"""Operational-space controllers against the two-link arm's closed-form kinematics and dynamics."""

import numpy as np
import pytest

from tests import two_link_closed_form as arm2
from controllers.operational_space import (OperationalInverseDynamics, OperationalPDGravity,
                                           operational_inverse_dynamics_steady_state, task_reference)
from controllers.plants import ArmMeasurement, ArmPlant
from controllers.simulation import simulate
from planners.paths import PathLaw, Segment
from planners.timing import trapezoidal_law
from rigid_body.robots import load

M_L = 10.0


@pytest.fixture(scope="module")
def arm_loaded():
    return load("planar_2r", payload=M_L)


def test_pd_gravity_law_is_eq_8_110(arm_loaded, rng):
    p_d = np.array([0.5, 0.5])
    ctrl = OperationalPDGravity(arm_loaded, 16250.0, 3250.0, p_d, rows=(0, 1))
    for _ in range(5):
        q, qd = rng.uniform(-np.pi, np.pi, 2), rng.uniform(-1, 1, 2)
        J = arm2.jacobian(q)
        expected = arm2.gravity(q, M_L) + J.T @ (16250.0 * (p_d - arm2.tip(q)) - 3250.0 * J @ qd)
        np.testing.assert_allclose(ctrl(0.0, ArmMeasurement(q, qd)), expected, atol=1e-7)


def test_inverse_dynamics_imposes_the_task_acceleration(arm_loaded, rng):
    """With the exact model the tip acceleration J q̈ + J̇ q̇ is ẍ_d + K_D x̃̇ + K_P x̃ (Eq. 8.114)."""
    law = PathLaw(Segment([0.7, 0.2, 0.0], [0.1, -0.6, 0.0]), trapezoidal_law(0.0, 1.0, 1.0, 1.5))
    ctrl = OperationalInverseDynamics(arm_loaded, 100.0, 16.0, law, rows=(0, 1), viscous_friction=100.0)
    for t in (0.1, 0.5, 0.9):
        q = np.array([1.2, -2.2]) + rng.uniform(-0.2, 0.2, 2)
        qd = rng.uniform(-1, 1, 2)
        u = ctrl(t, ArmMeasurement(q, qd))
        qdd = arm2.forward_dynamics(q, qd, u - 100.0 * qd, M_L)
        acc = arm2.jacobian(q) @ qdd + arm2.jacobian_derivative_times_qd(q, qd)
        x_d, xd_d, xdd_d = (v[:2] for v in law(t))
        expected = xdd_d + 16.0 * (xd_d - arm2.jacobian(q) @ qd) + 100.0 * (x_d - arm2.tip(q))
        np.testing.assert_allclose(acc, expected, atol=1e-8)


def test_pd_gravity_reaches_a_tip_position(arm_loaded):
    p_d = np.array([0.6, -0.2])
    res = simulate(ArmPlant(arm_loaded, viscous_friction=100.0),
                   OperationalPDGravity(arm_loaded, 16250.0, 3250.0, p_d, rows=(0, 1)),
                   (0.0, 2.5), np.r_[0.73453, -2.54990, 0, 0], h=1e-3, Ts=1e-3)
    np.testing.assert_allclose(arm2.tip(res.q[-1]), p_d, atol=1e-5)


def test_steady_state_fixed_point_residual(arm_loaded):
    arm = load("planar_2r")
    p_f = np.array([0.1, -0.6])
    q = operational_inverse_dynamics_steady_state(arm_loaded, arm, 100.0, p_f, [-0.15, -2.5], rows=(0, 1))
    y = np.linalg.solve(arm2.jacobian(q), 100.0 * (p_f - arm2.tip(q)))
    np.testing.assert_allclose(arm2.inertia(q) @ y, arm2.gravity(q, M_L) - arm2.gravity(q), atol=1e-7)


def test_task_reference_restricts_three_dimensional_references():
    f = task_reference(lambda t: (np.array([1.0, 2.0, 3.0]), np.zeros(3), np.ones(3)), (0, 1))
    np.testing.assert_allclose(np.array(f(0.0)), [[1, 2], [0, 0], [1, 1]])
    np.testing.assert_allclose(task_reference([1.0, 2.0, 3.0], (1, 2)), [2.0, 3.0])


def test_bad_task_definitions_raise(arm_loaded):
    with pytest.raises(ValueError, match="rows"):
        OperationalInverseDynamics(arm_loaded, 100.0, 16.0, [0.5, 0.5, 0.0])  # 3 rows, 2 joints
    with pytest.raises(ValueError, match="rows"):
        OperationalPDGravity(arm_loaded, 1.0, 1.0, [0.5, 0.5], rows=(0, 4))
    ctrl = OperationalInverseDynamics(arm_loaded, 100.0, 16.0, [0.5, 0.5], rows=(0, 1))
    with pytest.raises(ValueError, match="singular"):
        ctrl(0.0, ArmMeasurement(np.array([0.3, 0.0]), np.zeros(2)))  # stretched arm: J singular


def test_nearly_singular_jacobian_raises_instead_of_huge_torques(arm_loaded):
    ctrl = OperationalInverseDynamics(arm_loaded, 100.0, 16.0, [0.5, 0.5], rows=(0, 1))
    with pytest.raises(ValueError, match="J_A is singular at t = 0 s"):
        ctrl(0.0, ArmMeasurement(np.array([0.3, 1e-14]), np.zeros(2)))  # numerically stretched: cond(J) ~ 1e14
    assert np.all(np.isfinite(ctrl(0.0, ArmMeasurement(np.array([0.3, 1e-3]), np.zeros(2)))))  # near the singularity, not at it
    arm = load("planar_2r")
    with pytest.raises(ValueError, match="J_A is singular at q"):
        operational_inverse_dynamics_steady_state(arm_loaded, arm, 100.0, [2.0, 0.0], [0.0, 0.0], rows=(0, 1))
