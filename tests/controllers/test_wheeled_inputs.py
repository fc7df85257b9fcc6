"""Wheeled robots under hostile input (issue 26): regulators at the goal (item 3), NaN at the boundary (item 4),
degenerate references (item 5)."""

import math

import numpy as np
import pytest

from controllers import wheeled as cw
from controllers.plants import OdometerPosture, Posture, UnicyclePlant
from controllers.simulation import simulate
from planners.timing import quintic_law
from planners.wheeled import (ReferenceSample, TimeScaledPath, cartesian_polynomial_path, steering_feasible_path,
                              uniform_time_scaling)


# --------------------------------------------------------------------------------------------
# Item 3: at the goal the command is zero
# --------------------------------------------------------------------------------------------

REGULATORS = [lambda: cw.CartesianRegulator(1.0, 2.0), lambda: cw.CartesianRegulator(1.0, 2.0, backward=True),
              lambda: cw.PostureRegulator(1.0, 2.0, 3.0)]


@pytest.mark.parametrize("make", REGULATORS)
@pytest.mark.parametrize("posture", [(0.0, 0.0, 0.0), (-0.0, 0.0, -0.0), (0.0, -0.0, 2 * math.pi)])
def test_regulators_are_at_rest_at_the_goal(make, posture):
    """(11.79)/(11.82) at (0, 0, 0) used to command ω = k₂π (Atan2(0, 0) = 0): a spin for ever."""
    np.testing.assert_array_equal(make()(0.0, Posture(*posture)), np.zeros(2))


@pytest.mark.parametrize("make", REGULATORS)
def test_regulators_stay_at_the_goal_in_closed_loop(make):
    res = simulate(UnicyclePlant(), make(), (0.0, 5.0), [0.0, 0.0, 0.0], h=0.01, Ts=0.01)
    np.testing.assert_array_equal(res.x, 0.0)


def test_at_the_goal_position_cartesian_regulation_is_done_posture_regulation_turns_in_place():
    np.testing.assert_array_equal(cw.CartesianRegulator(1.0, 2.0)(0.0, Posture(0.0, 0.0, 1.0)), [0.0, 0.0])
    np.testing.assert_allclose(cw.PostureRegulator(1.0, 2.0, 3.0)(0.0, Posture(0.0, 0.0, 1.0)), [0.0, -2.0])
    res = simulate(UnicyclePlant(), cw.PostureRegulator(1.0, 2.0, 3.0), (0.0, 10.0), [0.0, 0.0, 1.0], h=0.01, Ts=0.01)
    assert np.all(res.x[:, :2] == 0.0) and abs(res.x[-1, 2]) < 1e-6      # θ = e^{−k2 t}: 2e−9 at 10 s


def test_goal_tolerance_is_a_radius():
    reg = cw.PostureRegulator(1.0, 2.0, 3.0, tolerance=1e-9)
    np.testing.assert_allclose(reg(0.0, Posture(1e-300, 0.0, 0.0)), 0.0)
    assert np.any(cw.PostureRegulator(1.0, 2.0, 3.0)(0.0, Posture(1e-3, 0.0, 0.0)) != 0.0)
    with pytest.raises(ValueError, match="`tolerance`"):
        cw.CartesianRegulator(1.0, 2.0, tolerance=-1.0)


@pytest.mark.parametrize("make", REGULATORS + [lambda: cw.NonlinearTracking(lambda t: _moving(), 0.7, 2.0)])
@pytest.mark.parametrize("bad", [(np.nan, 0.0, 0.0), (0.0, np.inf, 0.0), (1.0, 0.0, np.nan)])
def test_nan_posture_is_refused(make, bad):
    with pytest.raises(ValueError, match="posture"):
        make()(0.0, Posture(*bad))


def _moving():
    return ReferenceSample(np.zeros(2), np.array([1.0, 0.0]), np.zeros(2), 0.0, 1.0, 0.0)


# --------------------------------------------------------------------------------------------
# Item 4: odometry rejects NaN at the boundary
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, name", [(dict(v=np.nan), "v"), (dict(omega=np.inf), "omega"),
                                          (dict(v="1.0"), "v"), (dict(q=[0, np.nan, 0]), "q")])
@pytest.mark.parametrize("method", cw.ODOMETRY_METHODS)
def test_odometry_step_names_non_finite_input(kwargs, name, method):
    args = dict(q=[0.0, 0.0, 0.0], v=1.0, omega=0.5, Ts=0.1) | kwargs
    with pytest.raises(ValueError, match=f"`{name}`"):
        cw.odometry_step(args["q"], args["v"], args["omega"], args["Ts"], method)


@pytest.mark.parametrize("reading", [(np.nan, 0.0), (0.1, np.nan), (np.inf, 0.0)])
def test_odometry_block_refuses_a_bad_encoder_reading(reading):
    """One NaN reading used to leave the estimate NaN for ever."""
    odo = cw.Odometry([0.0, 0.0, 0.0])
    odo(0.0, OdometerPosture(0.0, 0.0, 0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="encoders"):
        odo(0.1, OdometerPosture(0.0, 0.0, 0.0, *reading))
    assert np.all(np.isfinite(odo.q_hat))


def test_mobile_manipulator_hold_checks_its_damping():
    from rigid_body.robots import load
    from rigid_body.wheeled import mobile_manipulator

    robot = mobile_manipulator(load("planar_2r"))
    for damping in (np.nan, -1e-4, "1e-4"):
        with pytest.raises(ValueError, match="`damping`"):
            cw.MobileManipulatorHold(robot, [0.5, 0.0, 0.0], lambda t: (0.1, 0.0), damping=damping)


# --------------------------------------------------------------------------------------------
# Item 5: degenerate references
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("q_i, q_f, k, where", [
    ([0, 0, 0], [0, 0, 0], 1.0, [0.2113, 0.7887]),       # the issue: the same posture twice, two cusps
    ([0, 0, 0], [-1, 0, 0], 1.0, [0.0918, 0.9082]),      # the goal behind, on the heading line
    ([0, 0, 0], [0, 0, math.pi], 1.0, [0.5]),            # turn on the spot
    ([0, 0, 0], [1, 0, math.pi], 1.0, [0.8604]),
    ([1, 2, 0.3], [1, 2, 0.3], -2.0, None),              # backwards too
])
def test_paths_with_a_cusp_are_refused(q_i, q_f, k, where):
    with pytest.raises(ValueError, match="cusp") as err:
        cartesian_polynomial_path(q_i, q_f, k, k)
    if where is not None:
        assert str(np.round(where, 4).tolist()) in str(err.value)


def test_cusps_are_where_the_flat_output_stops():
    """A cusp found by the closed form is a zero of p'(s) (checked on the path itself), and a path without one
    has none: the heading of the cusp-free path is continuous on a fine grid."""
    path = cartesian_polynomial_path([0, 0, 0], [1, 1, 0.5])
    assert path.cusps().size == 0
    s = np.linspace(0, 1, 100001)
    theta, _, _ = path.geometric_inputs(s)
    assert np.max(np.abs(np.diff(np.unwrap(theta)))) < 1e-3


def test_time_scaling_finds_the_peak_of_a_near_cusp():
    """Off the heading line by 1e-7 m the path nearly stops; ω̃ peaks at the slowest point, between samples: the
    duration must meet |ω| ≤ ω_max there too (dense check on a local grid of 2e5 points)."""
    path = cartesian_polynomial_path([0, 0, 0], [-1, 1e-7, 0])
    T = uniform_time_scaling(path, 1.0, 1.0)
    s0 = path.slowest_points()
    s = np.concatenate([np.linspace(max(c - 1e-6, 0), min(c + 1e-6, 1), 200001) for c in s0])
    _, v, w = path.geometric_inputs(s)
    assert max(np.abs(v).max(), np.abs(w).max()) <= T * (1 + 1e-9)
    assert T > 1e8


def test_time_scaling_of_a_regular_path_is_unchanged():
    path = cartesian_polynomial_path([0, 0, 0], [1, 1, 0.5])
    s = np.linspace(0, 1, 4001)
    _, v, w = path.geometric_inputs(s)
    assert uniform_time_scaling(path, 0.5, 1.0) == pytest.approx(max(np.abs(v).max() / 0.5, np.abs(w).max()), rel=1e-6)


def test_steering_feasible_path_still_found_around_cusps():
    path = steering_feasible_path([0, 0, 0], [-7.0, -2.5, 0.0], 1.0, 0.6, forward=False)
    assert path.cusps().size == 0


def test_nonlinear_tracking_refuses_a_reference_at_rest_with_an_error():
    """The issue: v_d = ω_d = 0 and a 0.5 m error gave u = 0 (all gains vanish)."""
    rest = ReferenceSample(np.zeros(2), np.zeros(2), np.zeros(2), 0.0, 0.0, 0.0)
    law = cw.NonlinearTracking(lambda t: rest, zeta=0.7, b=2.0)
    with pytest.raises(ValueError, match="at rest at t = 1.5 s.*PostureRegulator"):
        law(1.5, Posture(0.5, 0.0, 0.0))
    np.testing.assert_array_equal(law(1.5, Posture(0.0, 0.0, 0.0)), 0.0)          # no error: nothing to do
    stop = cw.NonlinearTracking(lambda t: rest, zeta=0.7, b=2.0, at_rest="stop")
    np.testing.assert_array_equal(stop(1.5, Posture(0.5, 0.0, 0.0)), 0.0)
    with pytest.raises(ValueError, match="`at_rest`"):
        cw.NonlinearTracking(lambda t: rest, zeta=0.7, b=2.0, at_rest="ignore")


def test_a_path_timed_from_rest_needs_at_rest_stop():
    path = cartesian_polynomial_path([0, 0, 0], [2, 1, 0.3])
    ref = TimeScaledPath(path, law=quintic_law(0.0, 1.0, 5.0))
    with pytest.raises(ValueError, match="at rest at t = 0 s"):
        simulate(UnicyclePlant(), cw.NonlinearTracking(ref, 0.7, 2.0), (0.0, 6.0), [0.1, -0.1, 0.0], h=0.01, Ts=0.01)
    res = simulate(UnicyclePlant(), cw.NonlinearTracking(ref, 0.7, 2.0, at_rest="stop"), (0.0, 6.0),
                   [0.1, -0.1, 0.0], h=0.01, Ts=0.01)
    assert res["position_error"][-1] < res["position_error"][0]
