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


def test_hybrid_law_without_force_directions_is_the_pi_velocity_loop():
    """S_v = I (k_f = 0), away from the plane: from rest with the integral started at a position error
    e_0 along x, e = ∫(ν_d − ν) obeys ë + k_Pν ė + k_Iν e = 0: the closed-form free response."""
    arm = load("planar_2r")
    plane = CompliantPlane([5.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1e4)            # never reached
    S_f, S_v = selection_matrices(("x", "y"), axes=("x", "y"))
    assert S_f.shape == (2, 0)
    e0 = np.array([0.01, 0.0])

    class Started(HybridForceMotionControl):          # simulate() resets the law: start it at e_0
        def reset(self, motion_error=None):
            super().reset(e0 if motion_error is None else motion_error)

    ctrl = Started(arm, S_f, S_v, [], [0.0, 0.0], 12.0, 100.0, 0.0, 1.0, compliance=np.eye(2) * 1e-3, rows=(0, 1))
    plant = ArmInContact(arm, plane)
    q0 = inverse_kinematics_planar_2r([1.0, 0.5])[ELBOW_UP]
    res = simulate(plant, ctrl, (0.0, 1.0), plant.initial_state(q0), h=1e-3, Ts=1e-3)
    x = res["p_e"][:, 0]
    expected = 1.01 - 0.01 * second_order_free_response(res.t, *pi_velocity_parameters(12.0, 100.0))
    assert np.abs(x - expected).max() < 2e-5                      # 0.2 % of e_0 (forward-Euler integral)
    with pytest.raises(ValueError, match="`S_v`"):
        HybridForceMotionControl(arm, np.eye(2), np.zeros((2, 0)), [0.0, 0.0], [], 1.0, 1.0, 1.0, 1.0,
                                 compliance=np.eye(2), rows=(0, 1))


def test_peg_in_hole_phases_are_hybrid_laws_and_insert_the_peg():
    """6.3's direct scene (hole within the clearance): approach → descend → insert → done, the peg at
    the depth; the phases run HybridForceMotionControl with force along x while inserting."""
    from controllers.environment import SurfaceWithHole
    from controllers.force import PegInHoleTask, run_peg_in_hole
    from rigid_body.kinematics import inverse_kinematics_planar_3r

    robot = load("planar_3r")
    task = PegInHoleTask(x_H=0.6, dy=0.01, v_slow=0.04, T_approach=0.5)
    env = SurfaceWithHole(x_hole=0.602, clearance=0.004, depth=0.05)
    q0 = inverse_kinematics_planar_3r(np.array([0.55, 0.15, task.phi]))[0]
    res, ctrl = run_peg_in_hole(robot, env, task, q0, 2.0)
    assert [s for _, s in ctrl.transitions] == ["approach", "descend", "insert", "done"]
    assert res["x_e"][-1, 1] == pytest.approx(-task.insert_depth, abs=2e-4)
    assert abs(res["x_e"][-1, 0] - env.x_hole) <= env.clearance
    insert = ctrl.laws[("y", "rz")]
    assert isinstance(insert, HybridForceMotionControl)
    assert np.array_equal(insert.S_f, [[1.0], [0.0], [0.0]])    # force-controlled along x


def test_hybrid_law_folded_matrix_is_eqs_9_77_to_9_81_term_by_term(rng):
    """α = M z (the constant products folded once) against (9.77), (9.80), (9.81) written out with full,
    non-diagonal gains and a force reference with λ̇_d, λ̈_d ≠ 0; u = B J⁻¹(α − J̇q̇) + n + Jᵀ h_e by
    CRBA and the Coriolis/gravity vector (not the law's RNEA)."""
    import pinocchio as pin

    robot = load("planar_3r")
    R_C = np.array([[np.cos(0.4), -np.sin(0.4), 0.0], [np.sin(0.4), np.cos(0.4), 0.0], [0.0, 0.0, 1.0]])
    S_f, S_v = R_C[:, :1], R_C[:, 1:]
    K_Pnu, K_Inu = np.array([[40.0, 3.0], [3.0, 30.0]]), np.array([[200.0, -5.0], [-5.0, 150.0]])
    K_Dl, K_Pl = 25.0, 300.0
    C = np.diag([1e-4, 2e-4, 5e-3])
    force = lambda t: ([-20.0 + t], [1.0 + 0.5 * t], [0.5 + t])          # (λ_d, λ̇_d, λ̈_d)
    velocity = lambda t: ([0.1 * np.cos(t), 0.2], [-0.1 * np.sin(t), 0.0])
    law = HybridForceMotionControl(robot, S_f, S_v, force, velocity, K_Pnu, K_Inu, K_Dl, K_Pl, compliance=C,
                                   rows=(0, 1, 5))
    q, qd, h = rng.normal(size=3), rng.normal(size=3), np.array([-15.0, 4.0, 0.3])
    law.reset(motion_error=[0.01, -0.02])
    J, Jdot_qd, T = law.task.state(q, qd)
    law.control(0.0, q, qd, h, J, Jdot_qd, T)                  # starts the integral's clock
    t = 0.3
    u = law.control(t, q, qd, h, J, Jdot_qd, T)
    # the derived matrices from S_f, S_v, C by the book, not the law's: weighted pseudo-inverses
    # S† = (Sᵀ W S)⁻¹ Sᵀ W (9.55) with W = K = C⁻¹ for S_v, W = C for S_f; P_v = S_v S_v†, C' = (I − P_v) C,
    # λ̇ = (S_fᵀ C' S_f)⁻¹ S_fᵀ v_e
    K = np.linalg.inv(C)
    S_v_dagger = np.linalg.inv(S_v.T @ K @ S_v) @ S_v.T @ K
    S_f_dagger = np.linalg.inv(S_f.T @ C @ S_f) @ S_f.T @ C
    C_prime = (np.eye(3) - S_v @ S_v_dagger) @ C
    v_e = J @ qd
    nu_d, nud_d = map(np.asarray, velocity(t))
    e_nu = nu_d - S_v_dagger @ v_e
    integral = np.array([0.01, -0.02]) + t * e_nu
    alpha = S_v @ (nud_d + K_Pnu @ e_nu + K_Inu @ integral)                                  # (9.80)
    lam_d, lamd_d, lamdd_d = map(np.asarray, force(t))
    lam, lam_dot = S_f_dagger @ h, np.linalg.inv(S_f.T @ C_prime @ S_f) @ S_f.T @ v_e
    f_l = lamdd_d + K_Dl * (lamd_d - lam_dot) + K_Pl * (lam_d - lam)                         # (9.81)
    alpha = alpha + C_prime @ S_f @ f_l                                                      # (9.77)
    model, data = robot.model, robot.model.createData()
    B = pin.crba(model, data, q)
    n = pin.nonLinearEffects(model, data, q, qd)
    expected = B @ np.linalg.solve(J, alpha - Jdot_qd) + n + J.T @ h
    np.testing.assert_allclose(u, expected, rtol=1e-9, atol=1e-9)
    assert law.log()["lam"] == pytest.approx(lam)
