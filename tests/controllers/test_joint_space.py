"""Joint-space controllers against the two-link arm's closed form (7.82) and the manual's formulas."""

import numpy as np
import pytest

from tests import two_link_closed_form as arm2
from controllers.independent_joint import JointDrive, design_position_velocity
from controllers.joint_space import (AdaptivePayloadControl, ComputedTorqueFeedforward, InverseDynamicsControl,
                                     PDGravityCompensation, RobustControl, as_gain, as_reference,
                                     inverse_dynamics_steady_state, lyapunov_matrix, mean_diagonal_inertia,
                                     with_payload)
from controllers.plants import ArmMeasurement, ArmPlant, VoltageControlledArm
from controllers.simulation import simulate
from planners.timing import quintic, trapezoidal
from rigid_body.dynamics import coriolis_matrix, gravity_torques, inertia_matrix
from rigid_body.robots import load

M_L = 10.0


@pytest.fixture(scope="module")
def arm():
    return load("planar_2r")


@pytest.fixture(scope="module")
def arm_loaded():
    return load("planar_2r", payload=M_L)


def test_with_payload_matches_closed_form_and_urdf_payload(arm, arm_loaded, rng):
    robot = with_payload(arm, M_L)
    for _ in range(10):
        q, qd = rng.uniform(-np.pi, np.pi, 2), rng.uniform(-2, 2, 2)
        np.testing.assert_allclose(inertia_matrix(robot, q), arm2.inertia(q, M_L), atol=1e-9)
        np.testing.assert_allclose(coriolis_matrix(robot, q, qd), arm2.coriolis(q, qd, M_L), atol=1e-9)
        np.testing.assert_allclose(gravity_torques(robot, q), arm2.gravity(q, M_L), atol=1e-9)
        np.testing.assert_allclose(inertia_matrix(robot, q), inertia_matrix(arm_loaded, q), atol=1e-9)
    # the original robot is untouched
    np.testing.assert_allclose(gravity_torques(arm, [0.0, 0.0]), arm2.gravity([0.0, 0.0]), atol=1e-9)


def test_with_payload_rejects_negative_mass(arm):
    with pytest.raises(ValueError, match="mass"):
        with_payload(arm, -1.0)


def test_gains_and_references_validate_input():
    np.testing.assert_allclose(as_gain(3.0, 2, "K_P"), 3 * np.eye(2))
    np.testing.assert_allclose(as_gain([1.0, 2.0], 2, "K_P"), np.diag([1.0, 2.0]))
    with pytest.raises(ValueError, match="K_P"):
        as_gain([1.0, -2.0], 2, "K_P")
    with pytest.raises(ValueError, match="K_D"):
        as_gain(np.ones((3, 3)), 2, "K_D")
    with pytest.raises(ValueError, match="reference"):
        as_reference([1.0, 2.0, 3.0], 2)
    with pytest.raises(ValueError, match="reference"):
        as_reference(quintic([0, 0, 0], [1, 1, 1], 1.0, samples=11), 2)
    q, qd, qdd = as_reference([1.0, 2.0], 2)(0.3)
    np.testing.assert_allclose(np.r_[q, qd, qdd], [1, 2, 0, 0, 0, 0])


def test_pd_gravity_law_is_eq_8_51(arm, rng):
    q_d = np.array([np.pi / 4, -np.pi / 2])
    ctrl = PDGravityCompensation(arm, 3750.0, 750.0, q_d)
    for _ in range(5):
        q, qd = rng.uniform(-np.pi, np.pi, 2), rng.uniform(-1, 1, 2)
        u = ctrl(0.0, ArmMeasurement(q, qd))
        np.testing.assert_allclose(u, arm2.gravity(q) + 3750.0 * (q_d - q) - 750.0 * qd, atol=1e-8)


def test_pd_gravity_regulates_posture_of_8_10(arm):
    q_d = np.array([-np.pi, -3 * np.pi / 4])
    res = simulate(ArmPlant(arm, viscous_friction=100.0), PDGravityCompensation(arm, 3750.0, 750.0, q_d),
                   (0.0, 5.0), np.r_[q_d - 0.1, 0, 0], h=1e-3, Ts=1e-3)
    assert np.abs(res.q[-1] - q_d).max() < 1e-4
    assert np.abs(res.qd[-1]).max() < 1e-3


def test_inverse_dynamics_torque_is_model_7_82(arm_loaded, rng):
    tra = quintic([0.0, 0.0], [1.0, -1.0], 1.0, samples=101)
    ctrl = InverseDynamicsControl(arm_loaded, 100.0, 16.0, tra, viscous_friction=100.0)
    for t in (0.0, 0.3, 0.7):
        q, qd = rng.uniform(-np.pi, np.pi, 2), rng.uniform(-1, 1, 2)
        q_d, qd_d, qdd_d = tra.evaluate(t)
        y = qdd_d + 16.0 * (qd_d - qd) + 100.0 * (q_d - q)
        expected = arm2.inertia(q, M_L) @ y + arm2.coriolis(q, qd, M_L) @ qd + 100.0 * qd + arm2.gravity(q, M_L)
        np.testing.assert_allclose(ctrl(t, ArmMeasurement(q, qd)), expected, atol=1e-8)


def test_inverse_dynamics_with_exact_model_follows_linear_error_dynamics(arm_loaded):
    """q̃̈ + K_D q̃̇ + K_P q̃ = 0 from an initial error, for a set point (closed form, critically damped)."""
    q_d = np.array([0.5, -0.5])
    e0 = np.array([0.05, -0.02])
    kp, kd = 100.0, 20.0  # ω_n = 10, ζ = 1
    res = simulate(ArmPlant(arm_loaded, viscous_friction=100.0),
                   InverseDynamicsControl(arm_loaded, kp, kd, q_d, viscous_friction=100.0),
                   (0.0, 1.0), np.r_[q_d - e0, 0, 0], h=1e-4, Ts=1e-4)
    t = res.t[:, None]
    e_exact = e0 * (1 + 10 * t) * np.exp(-10 * t)
    np.testing.assert_allclose(q_d - res.q, e_exact, atol=2e-5)  # ZOH: O(T_s ω_n) of 0.05


def test_inverse_dynamics_steady_state_solves_the_fixed_point(arm, arm_loaded):
    q_d = np.array([np.pi / 2, np.pi / 2])
    q = inverse_dynamics_steady_state(arm_loaded, arm, 100.0, q_d)
    residual = arm2.inertia(q) @ (100.0 * (q_d - q)) - arm2.gravity(q, M_L) + arm2.gravity(q)
    assert np.abs(residual).max() < 1e-7
    np.testing.assert_allclose(inverse_dynamics_steady_state(arm, arm, 100.0, q_d), q_d, atol=1e-12)


def test_lyapunov_matrix_closed_form():
    """Per joint, H̃ᵀQ + QH̃ = −I with H̃ = [[0, 1], [−k_p, −k_d]] has a closed-form solution."""
    kp, kd = 100.0, 16.0
    q12 = 1 / (2 * kp)
    q22 = (1 + 2 * q12) / (2 * kd)
    q11 = kp * q22 + kd * q12
    Q = lyapunov_matrix(kp * np.eye(2), kd * np.eye(2))
    np.testing.assert_allclose(Q[np.ix_([0, 2], [0, 2])], [[q11, q12], [q12, q22]], atol=1e-12)
    np.testing.assert_allclose(Q[np.ix_([0, 2], [0, 2])], [[3.23625, 0.005], [0.005, 0.0315625]], atol=1e-9)
    assert Q[0, 1] == pytest.approx(0.0, abs=1e-14)


def test_robust_term_has_norm_rho_outside_the_boundary_layer(arm):
    ctrl = RobustControl(arm, [200.0, 120.0], 100.0, 16.0, [0.0, 0.0], rho=70.0, epsilon=1e-3)
    Q = lyapunov_matrix(100 * np.eye(2), 16 * np.eye(2))
    e, ed = np.array([0.1, -0.2]), np.array([0.3, 0.1])
    w = ctrl.robust_term(e, ed)
    z = Q[2:, :] @ np.r_[e, ed]
    np.testing.assert_allclose(w, 70.0 * z / np.linalg.norm(z), atol=1e-12)
    small = ctrl.robust_term(1e-5 * e, 1e-5 * ed)  # inside the layer: (ρ/ε) z
    np.testing.assert_allclose(small, 70.0 / 1e-3 * (Q[2:, :] @ np.r_[1e-5 * e, 1e-5 * ed]), atol=1e-12)
    assert np.linalg.norm(small) < 70.0
    with pytest.raises(ValueError, match="epsilon"):
        RobustControl(arm, 200.0, 100.0, 16.0, [0.0, 0.0], rho=70.0, epsilon=0.0)


def test_mean_diagonal_inertia_is_the_average_of_7_82(arm_loaded):
    q2 = np.linspace(-np.pi, np.pi, 64, endpoint=False)
    B_bar = mean_diagonal_inertia(arm_loaded, np.c_[np.zeros_like(q2), q2])
    expected = np.mean([np.diag(arm2.inertia([0.0, v], M_L)) for v in q2], axis=0)
    np.testing.assert_allclose(B_bar, expected, atol=1e-9)
    np.testing.assert_allclose(B_bar, [220.01, 132.5], atol=1e-9)


def test_adaptive_regressor_matches_the_manuals_y_prime_with_erratum_fixed(arm, rng):
    """y_L = [a1 y'11 + a2 y'13; a2 y'23] with y'13's velocity term −a1 s2 (q̇2 q̇r1 + q̇1 q̇r2 + q̇2 q̇r2)."""
    ctrl = AdaptivePayloadControl(arm, 1e4, 10.0, 200.0, [0.0, 0.0])
    a1, a2, g = arm2.A1, arm2.A2, arm2.G
    for _ in range(10):
        q, qd, v, a = rng.uniform(-2, 2, (4, 2))
        c1, c2, s2, c12 = np.cos(q[0]), np.cos(q[1]), np.sin(q[1]), np.cos(q.sum())
        y11 = a1 * a[0] + g * c1
        y13 = ((2 * a1 * c2 + a2) * a[0] + (a1 * c2 + a2) * a[1]
               - a1 * s2 * (qd[1] * v[0] + qd[0] * v[1] + qd[1] * v[1]) + g * c12)
        y23 = (a1 * c2 + a2) * a[0] + a2 * a[1] + a1 * s2 * qd[0] * v[0] + g * c12
        tau0, y_L = ctrl.regressor(q, qd, v, a)
        np.testing.assert_allclose(y_L, [a1 * y11 + a2 * y13, a2 * y23], atol=1e-9)
        np.testing.assert_allclose(tau0, arm2.inertia(q) @ a + arm2.coriolis(q, qd) @ v + arm2.gravity(q), atol=1e-9)


def test_adaptive_estimate_converges_and_reset_restores_it(arm, arm_loaded):
    tra = trapezoidal([0, np.pi / 4], [np.pi / 2, np.pi / 2], 1.0, [3 * np.pi / 4, np.pi / 3], dt=1e-3)
    ctrl = AdaptivePayloadControl(arm, 1e4, 10.0, 200.0, tra, viscous_friction=100.0)
    res = simulate(ArmPlant(arm_loaded, viscous_friction=100.0), ctrl, (0.0, 2.0), np.r_[0, np.pi / 4, 0, 0],
                   h=1e-3, Ts=1e-3)
    assert abs(res["m_hat"][-1] - M_L) < 0.05
    assert res["m_hat"][0] == 0.0
    ctrl.reset()
    assert ctrl.mass == 0.0
    with pytest.raises(ValueError, match="adaptation_gain"):
        AdaptivePayloadControl(arm, 1e4, 10.0, 0.0, tra)


def test_computed_torque_feedforward_holds_a_posture_against_gravity(arm_loaded):
    """At rest on the reference, the voltage is K_pr g(q_d) and the motors deliver exactly g(q_d)."""
    drives = [JointDrive(I=0.0128, Ra=10.0, kt=2.0, kv=2.0) for _ in range(2)]
    designs = [design_position_velocity(d, 0.8, 10.0) for d in drives]
    q_d = np.array([0.3, 0.9])
    ctrl = ComputedTorqueFeedforward(arm_loaded, q_d, 100.0, drives, designs)
    plant = VoltageControlledArm(arm_loaded, 100.0, drives, viscous_friction=100.0)
    x = np.r_[q_d, 0.0, 0.0]
    v = ctrl(0.0, plant.measure(0.0, x))
    np.testing.assert_allclose(plant.torque(x, v), arm2.gravity(q_d, M_L), atol=1e-9)
    np.testing.assert_allclose(plant.derivative(0.0, x, v), 0.0, atol=1e-9)
    with pytest.raises(ValueError, match="drives"):
        ComputedTorqueFeedforward(arm_loaded, q_d, 100.0, drives[:1], designs)


def test_voltage_controlled_arm_torque_is_eq_8_3(arm):
    drives = [JointDrive(I=0.0128, Ra=10.0, kt=2.0, kv=2.0) for _ in range(2)]
    plant = VoltageControlledArm(arm, 100.0, drives, viscous_friction=100.0)
    x = np.array([0.1, 0.2, 0.5, -0.25])
    v = np.array([3.0, -1.0])
    np.testing.assert_allclose(plant.torque(x, v), 20.0 * v - 4000.0 * x[2:], atol=1e-12)
    qdd = plant.derivative(0.0, x, v)[2:]
    tau = 20.0 * v - 4000.0 * x[2:] - 100.0 * x[2:]
    np.testing.assert_allclose(qdd, arm2.forward_dynamics(x[:2], x[2:], tau), atol=1e-9)
    np.testing.assert_allclose(plant.acceleration(0.0, x[:2], x[2:], v), qdd, rtol=1e-14)  # the loop's fast path


def test_short_initial_states_and_non_finite_references_are_rejected(arm):
    ctrl = PDGravityCompensation(arm, 3750.0, 750.0, [0.0, 0.0])
    with pytest.raises(ValueError, match=r"`x0` must have 4 entries for ArmPlant"):
        simulate(ArmPlant(arm), ctrl, (0.0, 0.1), np.zeros(3), h=1e-3)
    with pytest.raises(ValueError, match="`reference` must be finite"):
        InverseDynamicsControl(arm, 100.0, 16.0, lambda t: (np.array([np.nan, 0.0]), np.zeros(2), np.zeros(2)))


def test_per_joint_gear_ratios_name_the_argument(arm):
    drives = [JointDrive(I=0.0128, Ra=10.0, kt=2.0, kv=2.0) for _ in range(2)]
    designs = [design_position_velocity(d, 0.8, 10.0) for d in drives]
    with pytest.raises(ValueError, match="`gear_ratio` must have shape"):
        ComputedTorqueFeedforward(arm, [0.0, 0.0], [100.0, 100.0, 100.0], drives, designs)
    with pytest.raises(ValueError, match="`gear_ratio` must have shape"):
        VoltageControlledArm(arm, [100.0, 100.0, 100.0], drives)
    with pytest.raises(ValueError, match="`gear_ratio` must be finite"):
        VoltageControlledArm(arm, np.nan, drives)
    np.testing.assert_allclose(VoltageControlledArm(arm, 100.0, drives).voltage_gain, [20.0, 20.0])
