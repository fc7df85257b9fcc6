"""Wheeled-robot plants and controllers in closed loop with simulate: tracking, regulation, odometry,
the mobile manipulator."""

import numpy as np
import pinocchio as pin
import pytest

from controllers import wheeled as cw
from controllers.plants import MobileManipulatorPlant, OdometerPosture, Posture, UnicyclePlant
from controllers.simulation import Chain, ZeroOrderHold, simulate
from planners.wheeled import FigureEight
from rigid_body.robots import load
from rigid_body.wheeled import mobile_manipulator, mobile_manipulator_input_matrix


@pytest.mark.parametrize("make", [
    lambda ref: cw.ApproximateLinearizationTracking(ref, a=1.5, zeta=0.7),
    lambda ref: cw.NonlinearTracking(ref, zeta=0.7, b=5.0),
    lambda ref: cw.InputOutputTracking(ref, b=0.2, k1=2.0),
])
def test_trackers_converge_on_a_figure_eight(make):
    ref = FigureEight(a=2.0, T=30.0)
    r0 = ref(0.0)
    q0 = np.r_[r0.p + [0.2, -0.2], r0.theta + 0.3]
    res = simulate(UnicyclePlant(), make(ref), (0.0, 20.0), q0, h=0.01, Ts=0.01)
    assert res["position_error"][-1] < 0.21  # IO tracks point B, 0.2 m ahead: the rear point lags by ≤ b
    assert res["position_error"][-1] < res["position_error"][0]


def test_wheel_saturation_keeps_wheels_within_bounds():
    plant = UnicyclePlant(wheel_limits=(0.1, 0.5, 10.0))
    for u in ([3.0, 0.0], [0.5, 6.0], [-2.0, -3.0]):
        v, om = plant.applied(np.array(u))
        assert abs(v) / 1.0 + abs(om) / 4.0 == pytest.approx(1.0)
        assert v * u[1] == pytest.approx(om * u[0])  # curvature kept


def test_odometry_methods_against_each_other():
    q = np.array([0.1, 0.2, 0.3])
    exact = cw.odometry_step(q, 1.0, 0.5, 0.01, "exact")
    assert np.allclose(cw.odometry_step(q, 1.0, 0.5, 0.01, "runge_kutta"), exact, atol=1e-8)
    assert np.allclose(cw.odometry_step(q, 1.0, 0.5, 0.01, "euler"), exact, atol=1e-4)
    with pytest.raises(ValueError, match="`method`"):
        cw.odometry_step(q, 1.0, 0.5, 0.01, "midpoint")
    with pytest.raises(ValueError, match="`Ts`"):
        cw.odometry_step(q, 1.0, 0.5, -0.01)


def _odometric_loop(method, Ts_odometry, Ts_loop, q0=(-1.0, -2.0, -np.pi / 2), t_end=5.0):
    ctrl = Chain(ZeroOrderHold(cw.Odometry(q0, method), Ts_odometry), cw.PostureRegulator(1.0, 2.5, 3.0, "estimate"),
                 name="estimate")
    return simulate(UnicyclePlant(odometer=True), ctrl, (0, t_end), np.r_[q0, 0.0, 0.0], h=0.01, Ts=Ts_loop)


def test_posture_regulator_with_exact_odometry_equals_true_state_feedback():
    """Exact odometry (11.85) from the encoders under ZOH inputs is error-free: the loop equals the one fed by
    the true posture."""
    q0 = [-1.0, -2.0, -np.pi / 2]
    a = _odometric_loop("exact", 0.1, 0.1)
    b = simulate(UnicyclePlant(), cw.PostureRegulator(1.0, 2.5, 3.0), (0, 5), q0, h=0.01, Ts=0.1)
    np.testing.assert_allclose(a.x[:, :3], b.x, atol=1e-7)  # the plant's RK4 error (h = 0.01 s) only
    assert np.max(np.abs(a["q_hat"] - a.x[:, :3])) < 1e-7


def test_odometry_block_runs_at_its_own_period_and_is_not_exact_when_the_input_varies():
    """Odometry every 0.1 s, regulator every 0.01 s: the estimate is held between odometry samples and,
    with (11.84) over inputs that vary inside the period, differs from the truth (but stays close)."""
    res = _odometric_loop("runge_kutta", 0.1, 0.01)
    q_hat = res["q_hat"]
    assert np.all(q_hat[1:10] == q_hat[0]) and np.any(q_hat[10] != q_hat[9])     # held for 10 loop samples
    err = np.hypot(*(res.x[:, :2] - q_hat[:, :2]).T)
    assert 1e-4 < err[-1] < 0.05
    with pytest.raises(AttributeError):              # odometry needs the encoders: a plain Posture has none
        cw.Odometry([0, 0, 0])(0.0, Posture(0.0, 0.0, 0.0))


def test_odometer_plant_integrates_the_applied_inputs():
    plant = UnicyclePlant(wheel_limits=(0.1, 0.5, 10.0), odometer=True)
    res = simulate(plant, lambda t, m: np.array([3.0, 1.0]), (0.0, 1.0), np.zeros(5), h=0.01, Ts=0.01)
    v, om = plant.applied(np.array([3.0, 1.0]))
    assert res["distance"][-1] == pytest.approx(v) and res["rotation"][-1] == pytest.approx(om)
    m = plant.measure(0.0, res.x[-1])
    assert isinstance(m, OdometerPosture) and m.distance == pytest.approx(v)


def test_plant_measure_and_integrate():
    plant = UnicyclePlant()
    m = plant.measure(0.0, np.array([1.0, 2.0, 3.0]))
    assert (m.x, m.y, m.theta) == (1.0, 2.0, 3.0) and np.array_equal(m.p, [1.0, 2.0])
    y = plant.integrate(np.array([0.0, 0.0, 3.1]), np.array([1.0, 0.0, 1.0]), 0.1)
    assert y[2] == pytest.approx(3.2 - 2 * np.pi)


def test_controllers_reject_bad_gains_and_singular_references():
    with pytest.raises(ValueError, match="`k2`"):
        cw.CartesianRegulator(1.0, 0.0)
    with pytest.raises(ValueError, match="`b`"):
        cw.BicycleInputOutputTracking(1.0, 0.0, lambda t: (np.zeros(2), np.zeros(2)), 1.0)
    tracker = cw.ApproximateLinearizationTracking(lambda t: FigureEight()(t).__class__(np.zeros(2), np.zeros(2),
                                                                                      np.zeros(2), 0.0, 0.0, 0.0), 1, 0.5)
    with pytest.raises(ValueError, match="v_d"):
        tracker(0.0, Posture(0.0, 0.0, 0.0))


def test_unicycle_plant_labels_its_axes():
    res = simulate(UnicyclePlant(), lambda t, m: np.array([1.0, 0.5]), (0.0, 1.0), np.zeros(3), h=0.01, Ts=0.01)
    from problems.common import subplots

    _, ax = subplots()
    res.plot("x", "y", ax=ax)
    assert ax.get_ylabel() == "x, y [m]"
    assert res["theta"][-1] == pytest.approx(0.5)


@pytest.fixture(scope="module")
def mobile():
    return mobile_manipulator(load("anthropomorphic_wrist"))


def test_mobile_manipulator_model_dimensions_and_input_map(mobile):
    assert (mobile.nq, mobile.nv) == (10, 9)
    G = mobile_manipulator_input_matrix(mobile)
    assert G.shape == (9, 8) and np.linalg.matrix_rank(G) == 8
    with pytest.raises(ValueError, match="planar root"):
        mobile_manipulator_input_matrix(load("anthropomorphic_wrist"))
    with pytest.raises(ValueError, match="`arm`"):
        mobile_manipulator(mobile)                       # nq ≠ nv: not an arm of revolute/prismatic joints
    with pytest.raises(ValueError, match="`mount`"):
        mobile_manipulator(load("anthropomorphic_wrist"), mount=[0.0, np.nan, 0.3])
    with pytest.raises(ValueError, match="`q_arm`"):
        MobileManipulatorPlant(mobile).initial_state([0, 0, 0], np.zeros(5))
    with pytest.raises(ValueError, match="`method`"):
        cw.Odometry([0, 0, 0], "midpoint")


def test_mobile_manipulator_plant_rolls_without_sliding_and_matches_the_unicycle(mobile, rng):
    """Base under (v, ω) held: the same posture as the unicycle (11.13) integrated on its own; the arm's joints
    move by q̇ t; cos θ, sin θ stay a unit pair."""
    plant = MobileManipulatorPlant(mobile)
    q_arm = rng.uniform(-1, 1, 6)
    u = np.r_[0.4, -0.7, rng.uniform(-1, 1, 6)]
    res = simulate(plant, lambda t, m: u, (0.0, 2.0), plant.initial_state([0.2, -0.1, 0.5], q_arm), h=0.01, Ts=0.01)
    uni = simulate(UnicyclePlant(), lambda t, m: u[:2], (0.0, 2.0), [0.2, -0.1, 0.5], h=0.001, Ts=0.001)
    x = res.x[-1]
    np.testing.assert_allclose([x[0], x[1], np.arctan2(x[3], x[2])], uni.x[-1], atol=1e-10)
    np.testing.assert_allclose(x[4:], q_arm + 2.0 * u[2:], atol=1e-12)
    assert abs(x[2] ** 2 + x[3] ** 2 - 1) < 1e-12


def test_mobile_manipulator_jacobian_times_input_map_by_finite_differences(mobile, rng):
    """J_P Γ u = d/dt p_e along q ⊕ t Γ u (the model's Jacobian in Pinocchio's planar tangent space)."""
    from rigid_body.kinematics import direct_kinematics
    from rigid_body.task_space import frame_state

    q = pin.integrate(mobile.model, pin.neutral(mobile.model), rng.uniform(-1, 1, 9))
    G = mobile_manipulator_input_matrix(mobile)
    u = rng.uniform(-1, 1, 8)
    eps = 1e-6
    p = [direct_kinematics(mobile, pin.integrate(mobile.model, q, s * eps * G @ u))[:3, 3] for s in (1, -1)]
    np.testing.assert_allclose(frame_state(mobile, q).J[:3] @ G @ u, (p[0] - p[1]) / (2 * eps), atol=1e-8)

