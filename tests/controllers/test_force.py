"""Force control (Ch. 9): the closed forms and the controllers' contracts."""

import numpy as np
import pytest

from controllers.environment import CompliantPlane
from controllers.force import (ForceWithInnerLoop, HybridForceMotionControl, compliance_equilibrium,
                               constrained_stiffness, fit_second_order, force_loop_parameters, impedance_parameters,
                               inner_position_loop_equilibrium, pi_velocity_parameters, second_order_free_response)
from controllers.operational_space import OperationalInverseDynamics
from controllers.plants import ArmInContact, ArmMeasurement
from controllers.simulation import simulate
from rigid_body.kinematics import ELBOW_UP, inverse_kinematics_planar_2r
from rigid_body.robots import load
from rigid_body.task_space import selection_matrices

R_C = np.array([[1.0, -1.0], [1.0, 1.0]]) / np.sqrt(2.0)


def test_compliance_equilibrium_one_axis_is_springs_in_series(rng):
    """One axis: h = k_P k/(k_P + k) Δx, the two springs in series; x_d − x_e = h/k_P."""
    h, dx = compliance_equilibrium([[2000.0]], [[5000.0]], [0.1])
    assert h[0] == pytest.approx(2000.0 * 5000.0 / 7000.0 * 0.1)
    assert dx[0] == pytest.approx(h[0] / 2000.0)
    with pytest.raises(ValueError, match="`K_P`"):
        compliance_equilibrium(np.zeros((2, 2)), np.eye(2), [0.1, 0.0])


def test_inner_position_loop_equilibrium_scalar_case():
    """x = x_d + c(k(x_r − x) + f_d) ⇒ x = (x_d + c(k x_r + f_d))/(1 + c k)."""
    x = inner_position_loop_equilibrium([0.2], [0.3], 1000.0, 1e-3, [-5.0])
    assert x[0] == pytest.approx((0.2 + 1e-3 * (1000.0 * 0.3 - 5.0)) / 2.0)


def test_closed_loop_parameters_of_the_manual():
    assert impedance_parameters(100, 1600, 5000) == pytest.approx((np.sqrt(50), 1600 / (2 * np.sqrt(5e5))))
    assert impedance_parameters(100, 1600, 5000, 5000) == pytest.approx((10.0, 0.8))
    assert force_loop_parameters(16, 100, 1.25) == pytest.approx((np.sqrt(125), 16 / (2 * np.sqrt(125))))
    assert pi_velocity_parameters(16, 100) == pytest.approx((10.0, 0.8))
    with pytest.raises(ValueError, match="`m_d`"):
        impedance_parameters(0.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="`l_f`"):
        force_loop_parameters(1.0, 1.0, -1.0)


def test_fit_second_order_recovers_under_and_over_damped_responses():
    from scipy.signal import lsim

    t = np.linspace(0, 3, 3001)
    for w, z in ((10.0, 0.3), (7.07, 1.13), (4.0, 0.8)):
        # reference response by scipy's lsim of ẍ + 2ζω ẋ + ω² x = 0 from x(0) = 1 (state space)
        A = np.array([[0.0, 1.0], [-w * w, -2 * z * w]])
        _, y, _ = lsim((A, np.zeros((2, 1)), np.array([[1.0, 0.0]]), np.zeros((1, 1))), np.zeros_like(t), t,
                       X0=[1.0, 0.0])
        np.testing.assert_allclose(second_order_free_response(t, w, z), y, atol=1e-6)
        assert fit_second_order(t, 3.0 + 2.0 * y, 3.0) == pytest.approx((w, z), rel=1e-6)
    with pytest.raises(ValueError, match="no transient"):
        fit_second_order(t, np.ones_like(t), 1.0)


def test_constrained_stiffness_is_the_spring_seen_along_s_f(rng):
    """Diagonal K, S_f = e_1: K' = k_11 e_1 e_1ᵀ (the stiffness of the force-controlled direction)."""
    K = np.diag([3.0, 5.0, 7.0])
    K1 = constrained_stiffness([1.0, 0.0, 0.0], np.linalg.inv(K))
    np.testing.assert_allclose(K1, np.diag([3.0, 0.0, 0.0]), atol=1e-12)
    with pytest.raises(ValueError, match="singular"):
        constrained_stiffness([1.0, 0.0, 0.0], np.diag([0.0, 1.0, 1.0]))


def _arm_on_plane():
    arm = load("planar_2r")
    plane = CompliantPlane([1.0, 0.0, 0.0], [-R_C[1, 1], R_C[1, 1], 0.0], 5e3)
    return arm, ArmInContact(arm, plane, viscous_friction=100.0)


def test_hybrid_controller_validates_its_selection_matrices():
    arm = load("planar_2r")
    S_f, S_v = selection_matrices(("x",), R_C, axes=("x", "y"))
    common = dict(force_reference=[-50.0], velocity_reference=[0.0], K_Pnu=16, K_Inu=100, K_Dlambda=16,
                  K_Plambda=100, compliance=np.eye(2) / 4e3, rows=(0, 1))
    HybridForceMotionControl(arm, S_f, S_v, **common)
    with pytest.raises(ValueError, match="reciprocal"):
        HybridForceMotionControl(arm, S_f, S_f, **common)
    with pytest.raises(ValueError, match="task rows"):
        HybridForceMotionControl(arm, np.ones((3, 1)), S_v, **common)
    ctrl = HybridForceMotionControl(arm, S_f, S_v, **common)
    with pytest.raises(ValueError, match="force sensor"):
        ctrl(0.0, ArmMeasurement(np.array([np.pi / 3, -2 * np.pi / 3]), np.zeros(2)))


def test_impedance_needs_an_inertia_and_a_sensor():
    arm = load("planar_2r")
    with pytest.raises(ValueError, match="inertia"):
        OperationalInverseDynamics(arm, 1.0, 1.0, [1.0, 0.0], rows=(0, 1), force_feedback=True)
    ctrl = OperationalInverseDynamics(arm, 1.0, 1.0, [1.0, 0.0], rows=(0, 1), inertia=1.0, force_feedback=True)
    with pytest.raises(ValueError, match="force sensor"):
        ctrl(0.0, ArmMeasurement(np.array([np.pi / 3, -2 * np.pi / 3]), np.zeros(2)))


def test_force_control_with_inner_velocity_loop_reaches_f_d_with_a_proportional_regulator():
    """Fig. 9.9: at rest x_F = C_F (f_d − f_e) = 0, so f_e = f_d without integral action."""
    arm, plant = _arm_on_plane()
    n = R_C[:, 1]
    f_d = -30.0 * n
    q0 = inverse_kinematics_planar_2r(np.array([1.0, 0.0]) + R_C @ np.array([0.1, -0.001]))[ELBOW_UP]
    ctrl = ForceWithInnerLoop(arm, 100.0, 14.0, 1.0, 1e-4, [0.0, 0.0], f_d, inner="velocity", rows=(0, 1),
                              viscous_friction=100.0)
    res = simulate(plant, ctrl, (0.0, 1.5), plant.initial_state(q0), h=1e-3, Ts=1e-3)
    np.testing.assert_allclose(res["f_e"][-1], f_d, atol=0.05)
    with pytest.raises(ValueError, match="`inner`"):
        ForceWithInnerLoop(arm, 1.0, 1.0, 1.0, 1.0, [0.0, 0.0], [0.0, 0.0], inner="admittance", rows=(0, 1))


def test_admittance_control_shows_the_impedance_of_9_3():
    """Admittance (inner position loop, stiff) with the impedance of 9.3 held at p_i: the same rest
    force −250 N as impedance control, k_y k_P/(k_P + k_y)(y_d − y_r), and no error along x_c."""
    from controllers.force import AdmittanceControl

    arm, plant = _arm_on_plane()
    p_i = np.array([1.0 + 0.1 * np.sqrt(2.0), 0.0])
    q0 = inverse_kinematics_planar_2r(p_i)[ELBOW_UP]
    ctrl = AdmittanceControl(arm, 100.0, 1600.0, 5000.0, 2 * 50.0, 50.0**2, p_i, rows=(0, 1), viscous_friction=100.0)
    res = simulate(plant, ctrl, (0.0, 1.5), plant.initial_state(q0), h=1e-3, Ts=1e-3)
    f_c = res["h_e"][-1] @ R_C
    np.testing.assert_allclose(f_c, [0.0, -250.0], atol=0.5)
    np.testing.assert_allclose(res["e"][-1] @ R_C, [0.0, -0.05], atol=2e-4)
    with pytest.raises(ValueError, match="`rows`"):
        AdmittanceControl(arm, 1.0, 1.0, 1.0, 1.0, 1.0, [0.0, 0.0, 0.0, 0.0], rows=(0, 1, 3))
