"""Wheeled-robot controllers in closed loop with simulate: tracking, regulation, odometry."""

import numpy as np
import pytest

from controllers import wheeled as cw
from controllers.simulation import simulate
from planners.wheeled import FigureEight


@pytest.mark.parametrize("make", [
    lambda ref: cw.ApproximateLinearizationTracking(ref, a=1.5, zeta=0.7),
    lambda ref: cw.NonlinearTracking(ref, zeta=0.7, b=5.0),
    lambda ref: cw.InputOutputTracking(ref, b=0.2, k1=2.0),
])
def test_trackers_converge_on_a_figure_eight(make):
    ref = FigureEight(a=2.0, T=30.0)
    r0 = ref(0.0)
    q0 = np.r_[r0.p + [0.2, -0.2], r0.theta + 0.3]
    res = simulate(cw.UnicyclePlant(), make(ref), (0.0, 20.0), q0, h=0.01, Ts=0.01)
    assert res["position_error"][-1] < 0.21  # IO tracks point B, 0.2 m ahead: the rear point lags by ≤ b
    assert res["position_error"][-1] < res["position_error"][0]


def test_wheel_saturation_keeps_wheels_within_bounds():
    plant = cw.UnicyclePlant(wheel_limits=(0.1, 0.5, 10.0))
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


def test_posture_regulator_with_exact_odometry_equals_true_state_feedback():
    """Exact odometry (11.85) under ZOH inputs is error-free: the loop equals the one fed by the true posture."""
    q0 = [-1.0, -2.0, -np.pi / 2]
    reg = cw.PostureRegulator(1.0, 2.5, 3.0)
    a = simulate(cw.UnicyclePlant(), cw.OdometricRegulator(reg, q0, "exact"), (0, 5), q0, h=0.01, Ts=0.1)
    b = simulate(cw.UnicyclePlant(), reg, (0, 5), q0, h=0.01, Ts=0.1)
    np.testing.assert_allclose(a.x, b.x, atol=1e-7)  # the plant's RK4 error (h = 0.01 s) only
    assert np.max(a["odometry_error"]) < 1e-7


def test_plant_measure_and_integrate():
    plant = cw.UnicyclePlant()
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
        tracker(0.0, cw.Posture(0.0, 0.0, 0.0))
