"""The cheap per-step paths of the loop keep its semantics: bound test, logging, input checks, gains."""

import numpy as np
import pytest

from controllers.joint_space import PDGravityCompensation
from controllers.plants import ArmPlant
from controllers.simulation import LoggedController, SimulationDiverged, rk4_step, simulate
from rigid_body.dynamics import forward_dynamics, gravity_torques
from rigid_body.robots import load


def test_state_inside_the_bound_but_with_a_larger_norm_is_not_diverged():
    """max |x_i| = 0.9 ≤ bound 1 while ‖x‖₂ = 1.27 > 1: the bound is on max |x_i|."""
    res = simulate(lambda t, x, u: np.zeros(2), lambda t, x: np.zeros(1), (0.0, 0.01), [0.9, 0.9], h=1e-3, bound=1.0)
    assert np.all(res.x == 0.9)


def test_state_beyond_a_huge_bound_still_stops_the_run():
    with pytest.raises(SimulationDiverged, match="exceeded 1e\\+200 at t = 0.001 s"):
        simulate(lambda t, x, u: np.array([1e206]), lambda t, x: np.zeros(1), (0.0, 0.01), [0.0], h=1e-3,
                 bound=1e200)


def test_non_finite_state_and_input_are_told_with_their_time():
    with pytest.raises(SimulationDiverged, match="non-finite at t = 0.002 s"):
        simulate(lambda t, x, u: np.array([np.inf if t >= 0.002 else 0.0]), lambda t, x: np.zeros(1), (0.0, 0.01),
                 [0.0], h=1e-3)
    with pytest.raises(SimulationDiverged, match="controller output became non-finite at t = 0.002 s"):
        simulate(lambda t, x, u: np.zeros(1), lambda t, x: np.array([np.nan if t > 0.0015 else 0.0]),
                 (0.0, 0.01), [0.0], h=1e-3)


def test_huge_finite_input_is_not_mistaken_for_a_non_finite_one():
    res = simulate(lambda t, x, u: np.zeros(1), lambda t, x: np.array([1e200, -1e200]), (0.0, 0.005), [0.0], h=1e-3)
    assert np.all(res.u == [1e200, -1e200])


def test_logged_list_changed_later_is_logged_as_it_was():
    class Counter(LoggedController):
        def reset(self):
            super().reset()
            self.history = [0.0]

        def __call__(self, t, x):
            self.history[0] += 1.0
            self.record(count=self.history, scalar=self.history[0], array=np.array(self.history))
            return np.zeros(1)

    res = simulate(lambda t, x, u: np.zeros(1), Counter(), (0.0, 0.004), [0.0], h=1e-3)
    np.testing.assert_array_equal(res["count"][:, 0], [1, 2, 3, 4, 5])
    np.testing.assert_array_equal(res["scalar"], [1, 2, 3, 4, 5])
    np.testing.assert_array_equal(res["array"][:, 0], [1, 2, 3, 4, 5])


def test_loop_rk4_equals_a_hand_written_classical_step():
    """The loop's RK4 (the Butcher-tableau products of ``rk4_stepper``) against the classical stages
    written out, k_1 … k_4 and x + h/6 (k_1 + 2 k_2 + 2 k_3 + k_4), on a nonlinear time-varying plant."""
    def f(t, x, u):
        return np.array([x[1], -np.sin(x[0]) + u[0] * np.cos(t)])

    u, h = np.array([0.3]), 0.01
    x = np.array([1.0, 0.0])
    for k in range(100):
        t = k * h
        k1 = f(t, x, u)
        k2 = f(t + h / 2, x + h / 2 * k1, u)
        k3 = f(t + h / 2, x + h / 2 * k2, u)
        k4 = f(t + h, x + h * k3, u)
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    res = simulate(f, lambda t, x: u, (0.0, 1.0), [1.0, 0.0], h=h)
    np.testing.assert_allclose(res.x[-1], x, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(rk4_step(lambda t, xi: f(t, xi, u), 0.0, np.array([1.0, 0.0]), h),
                               res.x[1], rtol=1e-13, atol=1e-15)


def test_arm_derivative_fast_path_equals_forward_dynamics():
    robot = load("planar_2r", motors=False)
    rng = np.random.default_rng(3)
    x, u = rng.normal(size=4), rng.normal(size=2) * 20
    plain = ArmPlant(robot).derivative(0.0, x, u)
    np.testing.assert_array_equal(plain[:2], x[2:])
    np.testing.assert_allclose(plain[2:], forward_dynamics(robot, x[:2], x[2:], u), rtol=1e-12)
    limits = np.array([5.0, 50.0])
    saturated = ArmPlant(robot, tau_max=limits, viscous_friction=0.5).derivative(0.0, x, u)
    expected = forward_dynamics(robot, x[:2], x[2:], np.clip(u, -limits, limits) - 0.5 * x[2:])
    np.testing.assert_allclose(saturated[2:], expected, rtol=1e-12)
    np.testing.assert_array_equal(ArmPlant(robot).derivative(0.0, x, list(u)), plain)  # a list input
    with pytest.raises(ValueError, match="needs 2 joint torques"):
        ArmPlant(robot).derivative(0.0, x, np.ones(3))


@pytest.mark.parametrize("K_P", [100.0, [100.0, 60.0], [[100.0, 10.0], [10.0, 60.0]]])
def test_pd_gravity_gains_as_scalar_vector_or_matrix(K_P):
    robot = load("planar_2r")
    q_d, q, qd = np.array([0.4, -0.3]), np.array([0.1, 0.2]), np.array([0.5, -1.0])
    ctrl = PDGravityCompensation(robot, K_P, 20.0, q_d)
    meas = ArmPlant(robot).measure(0.0, np.r_[q, qd])
    K = np.diag(np.broadcast_to(K_P, 2)) if np.ndim(K_P) < 2 else np.array(K_P)
    np.testing.assert_allclose(ctrl(0.0, meas), gravity_torques(robot, q) + K @ (q_d - q) - 20.0 * qd, rtol=1e-14)


def _pendulum_plant(with_acceleration: bool):
    """q̈ = −sin q − 0.1 q̇ + u cos t (time-varying, so that every stage time counts)."""
    def acceleration(t, q, v, u):
        return -np.sin(q) - 0.1 * v + u * np.cos(t)

    class Pendulum:
        def derivative(self, t, x, u):
            return np.r_[x[1:], acceleration(t, x[:1], x[1:], u)]

    plant = Pendulum()
    if with_acceleration:
        plant.acceleration = acceleration
    return plant


def test_nystrom_steps_are_the_classical_rk4_steps():
    """The loop's RK4 on ``acceleration`` (Nyström form) reproduces the classical RK4 on ``derivative``,
    and both are fourth order: halving h divides the error at t = 2 s by ≈ 16."""
    def final(h, with_acceleration):
        res = simulate(_pendulum_plant(with_acceleration), lambda t, x: np.array([0.5]), (0.0, 2.0), [1.0, 0.0],
                       h=h, Ts=0.1)
        return res.x[-1]

    np.testing.assert_allclose(final(0.01, True), final(0.01, False), rtol=1e-13, atol=1e-15)
    exact = final(0.1 / 64, False)
    e1, e2 = (np.max(np.abs(final(h, True) - exact)) for h in (0.1, 0.05))
    assert 13.0 < e1 / e2 < 19.0


def test_arm_acceleration_is_the_forward_dynamics_of_the_applied_torque():
    robot = load("planar_2r", motors=False)
    rng = np.random.default_rng(5)
    q, qd, u = rng.normal(size=2), rng.normal(size=2), rng.normal(size=2) * 20
    limits = np.array([5.0, 50.0])
    plant = ArmPlant(robot, tau_max=limits, viscous_friction=0.5)
    expected = forward_dynamics(robot, q, qd, np.clip(u, -limits, limits) - 0.5 * qd)
    np.testing.assert_allclose(plant.acceleration(0.0, q, qd, u), expected, rtol=1e-12)
    np.testing.assert_array_equal(plant.derivative(0.0, np.r_[q, qd], u)[2:], plant.acceleration(0.0, q, qd, u))


def test_a_step_that_turns_non_finite_is_repeated_through_the_plants_derivative():
    """The fast path (``acceleration``) returns NaN; the plant's ``derivative`` says why: its error wins."""
    class Breaking:
        def acceleration(self, t, q, v, u):
            return np.full(1, np.nan) if t > 0.0025 else np.zeros(1)

        def derivative(self, t, x, u):
            if t > 0.0025:
                raise ValueError("B(q) is singular at q = [0.]")
            return np.zeros(2)

    with pytest.raises(ValueError, match="B\\(q\\) is singular"):
        simulate(Breaking(), lambda t, x: np.zeros(1), (0.0, 0.01), [0.0, 0.0], h=1e-3)
    quiet = Breaking()
    quiet.derivative = lambda t, x, u: np.r_[x[1:], quiet.acceleration(t, x[:1], x[1:], u)]
    with pytest.raises(SimulationDiverged, match="non-finite at t = 0.003 s"):
        simulate(quiet, lambda t, x: np.zeros(1), (0.0, 0.01), [0.0, 0.0], h=1e-3)


def test_pd_gravity_set_point_path_equals_the_trajectory_path():
    robot = load("puma560")
    q_d, rng = np.array([0.5, -0.6, 0.3, 0.2, -0.4, 0.1]), np.random.default_rng(2)
    meas = ArmPlant(robot).measure(0.0, rng.normal(size=12))
    fixed = PDGravityCompensation(robot, [100.0, 90, 80, 70, 60, 50], 20.0, q_d)
    moving = PDGravityCompensation(robot, [100.0, 90, 80, 70, 60, 50], 20.0, lambda t: (q_d, np.zeros(6), np.zeros(6)))
    np.testing.assert_array_equal(fixed(0.0, meas), moving(0.0, meas))
    assert fixed.log().keys() == moving.log().keys() == {"q_d", "e"}


def test_time_invariant_acceleration_takes_the_same_steps_as_the_plants_acceleration():
    """A plain arm's stages call ABA directly (``time_invariant_acceleration``); a subclass redefining
    ``acceleration`` (here only to pass through it) gets the method path. Both runs agree bit for bit, and
    against the classical RK4 on ``derivative`` (the stepper without ``acceleration``)."""
    class ThroughTheMethod(ArmPlant):
        def acceleration(self, t, q, qd, u):
            return super().acceleration(t, q, qd, u)

    robot = load("puma560")
    plain, through = ArmPlant(robot), ThroughTheMethod(robot)
    assert plain.time_invariant_acceleration is not None and through.time_invariant_acceleration is None
    assert ArmPlant(robot, viscous_friction=0.1).time_invariant_acceleration is None
    assert ArmPlant(robot, tau_max=np.full(6, 100.0)).time_invariant_acceleration is None
    q_d = np.array([0.5, -0.6, 0.3, 0.2, -0.4, 0.1])
    runs = [simulate(p, PDGravityCompensation(robot, 100.0, 20.0, q_d), (0.0, 0.3), p.initial_state(np.zeros(6)),
                     h=1e-3) for p in (plain, through)]
    np.testing.assert_array_equal(runs[0].x, runs[1].x)
    x, u = runs[0].x[100], runs[0].u[100]
    classical = rk4_step(lambda t, xi: plain.derivative(t, xi, u), 0.1, x, 1e-3)
    np.testing.assert_allclose(runs[0].x[101], classical, rtol=1e-12, atol=1e-14)


def test_a_controller_changing_its_output_size_mid_run_is_an_error():
    """The first sample's size is checked by the loop; a later one by Pinocchio (the plain arm's ABA)."""
    robot = load("planar_2r", motors=False)
    plant = ArmPlant(robot)
    with pytest.raises(ValueError, match="size"):
        simulate(plant, lambda t, m: np.zeros(2 if t < 0.005 else 3), (0.0, 0.01), plant.initial_state(np.zeros(2)),
                 h=1e-3)


def test_hold_instants_are_where_a_zero_order_hold_calls_its_block():
    """``ZeroOrderHold.instants`` (the compiled visual-servo loop's reference row) against a hold called on
    the same grid, counting its block's calls — with a period that is not a float multiple of the step."""
    from controllers.simulation import ZeroOrderHold

    calls = []
    hold = ZeroOrderHold(lambda t, m: calls.append(t) or t, 0.04)
    times = 0.0 + np.arange(201) * 1e-3
    for t in times.tolist():
        hold(t, None)
    np.testing.assert_array_equal(times[ZeroOrderHold.instants(times, 0.04)], calls)
    assert len(calls) == 6 and calls[1] == pytest.approx(0.04)
