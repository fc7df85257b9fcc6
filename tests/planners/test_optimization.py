"""Optimal trajectories: limits hold between the nodes, a limit is active at minimum time, no slower
than the trapezoid under the same limits, minimum jerk → the quintic."""

import numpy as np
import pinocchio as pin
import pytest

from planners import optimization as opt
from planners.timing import quintic_law
from rigid_body.robots import load

Q_I, Q_F = np.array([0.0, np.pi / 4]), np.array([np.pi / 2, np.pi / 2])


@pytest.fixture(scope="module")
def arm():
    return load("planar_2r")


@pytest.fixture(scope="module")
def arm_limits(arm):
    return opt.JointLimits.from_robot(arm, qdd_max=[20.0, 20.0], qd_max=[3.0, 3.0], tau_max=[3000.0, 1500.0])


def _independent_ratios(robot, law, limits, points=4001):
    """Limits on a grid unrelated to the mesh, torques from Pinocchio's RNEA (not the CasADi one)."""
    t = np.linspace(law.t_i, law.t_f, points)
    q, qd, qdd = law(t)
    tau = np.array([pin.rnea(robot.model, robot.data, a, b, c) for a, b, c in zip(q, qd, qdd)])
    return {"q_lo": np.min(q - limits.q_min), "q_hi": np.max(q - limits.q_max),
            "qd": np.max(np.abs(qd) / limits.qd_max), "qdd": np.max(np.abs(qdd) / limits.qdd_max),
            "tau": np.max(np.abs(tau) / limits.tau_max)}


def _check_rest_to_rest(law, q_i, q_f):
    for t, q_ref in ((law.t_i, q_i), (law.t_f, q_f)):
        q, qd, _ = law(t)
        np.testing.assert_allclose(q, q_ref, atol=1e-8)
        np.testing.assert_allclose(qd, 0.0, atol=1e-8)


def _check_c1(law):
    for b in law.breaks[1:-1]:
        left, right = law(b - 1e-12), law(b + 1e-12)
        np.testing.assert_allclose(left[0], right[0], atol=1e-8)
        np.testing.assert_allclose(left[1], right[1], atol=1e-7)


def test_minimum_time_planar_2r(arm, arm_limits):
    res = opt.minimum_time_trajectory(arm, Q_I, Q_F, arm_limits, opt.OptimizationOptions(nodes=30))
    assert res.success, res.message
    law = res.trajectory.law
    _check_rest_to_rest(law, Q_I, Q_F)
    _check_c1(law)
    r = _independent_ratios(arm, law, arm_limits)
    assert r["q_lo"] >= 0 and r["q_hi"] <= 0
    assert max(r["qd"], r["qdd"], r["tau"]) <= 1 + 1e-6, r
    assert max(r["qd"], r["qdd"], r["tau"]) >= 0.999, r  # a limit is active at the optimum
    trap, trap_tau = opt.trapezoidal_under_limits(arm, Q_I, Q_F, arm_limits)
    assert np.max(np.abs(trap_tau) / arm_limits.tau_max) <= 1.0
    assert res.t_f <= trap.duration
    assert res.t_f < 0.97 * trap.duration  # torque-limited: the optimum exploits B(q), g(q)


def test_minimum_time_order_3_is_c2_and_slower_than_order_2(arm, arm_limits):
    fast = opt.minimum_time_trajectory(arm, Q_I, Q_F, arm_limits, opt.OptimizationOptions(nodes=20))
    smooth = opt.minimum_time_trajectory(arm, Q_I, Q_F, arm_limits, opt.OptimizationOptions(nodes=20, order=3))
    assert smooth.success, smooth.message
    law = smooth.trajectory.law
    for b in law.breaks[1:-1]:
        np.testing.assert_allclose(law(b - 1e-12)[2], law(b + 1e-12)[2], atol=1e-6)
    r = _independent_ratios(arm, law, arm_limits)
    assert max(r["qd"], r["qdd"], r["tau"]) <= 1 + 1e-6
    assert smooth.t_f >= fast.t_f * (1 - 1e-6)  # continuity of q̈ cannot make it faster


def test_minimum_jerk_without_active_limits_tends_to_the_quintic(arm):
    loose = opt.JointLimits.from_robot(arm, qdd_max=[100.0, 100.0])
    ref = quintic_law(Q_I, Q_F, 1.5)
    t = np.linspace(0, 1.5, 301)
    errors = []
    for N in (8, 32):
        res = opt.minimum_jerk_trajectory(arm, Q_I, Q_F, 1.5, loose, opt.OptimizationOptions(nodes=N))
        assert res.success, res.message
        errors.append(np.max(np.abs(res.trajectory.law(t)[0] - ref(t)[0])))
    assert errors[1] < 1e-3 and errors[1] < errors[0] / 8  # O(h²)


def test_minimum_effort_beats_the_quintic_and_respects_limits(arm, arm_limits):
    res = opt.minimum_effort_trajectory(arm, Q_I, Q_F, 1.5, arm_limits, opt.OptimizationOptions(nodes=20))
    assert res.success, res.message

    def effort(law):
        t = np.linspace(0, 1.5, 3001)
        q, qd, qdd = law(t)
        tau = np.array([pin.rnea(arm.model, arm.data, a, b, c) for a, b, c in zip(q, qd, qdd)])
        return np.trapezoid(np.sum((tau / arm_limits.tau_max) ** 2, axis=1), t)

    assert effort(res.trajectory.law) < effort(quintic_law(Q_I, Q_F, 1.5))
    r = _independent_ratios(arm, res.trajectory.law, arm_limits)
    assert max(r["qd"], r["qdd"], r["tau"]) <= 1 + 1e-6


def test_minimum_time_ur5_torque_limited():
    import time
    robot = load("ur5")
    limits = opt.JointLimits.from_robot(robot, qdd_max=np.full(6, 8.0), tau_max=[60, 60, 40, 10, 10, 10])
    q_i = np.array([0.0, -1.2, 1.0, -1.2, -1.5, 0.0])
    q_f = np.array([1.5, -0.6, 1.8, -2.0, -1.0, 1.0])
    start = time.perf_counter()
    res = opt.minimum_time_trajectory(robot, q_i, q_f, limits, opt.OptimizationOptions(nodes=20))
    assert time.perf_counter() - start < 40
    assert res.success, res.message
    _check_rest_to_rest(res.trajectory.law, q_i, q_f)
    r = _independent_ratios(robot, res.trajectory.law, limits)
    assert max(r["qd"], r["qdd"], r["tau"]) <= 1 + 1e-6
    assert max(r["qd"], r["qdd"], r["tau"]) >= 0.999
    trap, _ = opt.trapezoidal_under_limits(robot, q_i, q_f, limits)
    assert res.t_f <= trap.duration


def test_bad_input(arm, arm_limits):
    with pytest.raises(ValueError, match="outside the joint limits"):
        opt.minimum_time_trajectory(arm, [4.0, 0.0], Q_F, arm_limits)
    weak = opt.JointLimits.from_robot(arm, qdd_max=[20.0, 20.0], tau_max=[500.0, 500.0])
    with pytest.raises(ValueError, match="gravity torques at `q_i`"):
        opt.minimum_time_trajectory(arm, Q_I, Q_F, weak)
    with pytest.raises(ValueError, match="qd_max"):
        opt.JointLimits([0, 0], [1, 1], [1, -1], 1.0, 1.0)
    with pytest.raises(ValueError, match="t_f"):
        opt.minimum_effort_trajectory(arm, Q_I, Q_F, -1.0, arm_limits)


def test_back_off_repairs_limits_between_the_constraint_points(arm, arm_limits):
    # Few C² intervals: the torque peaks between the constraint points of the first solve.
    honest = opt.minimum_time_trajectory(arm, Q_I, Q_F, arm_limits,
                                         opt.OptimizationOptions(nodes=6, order=3, max_backoff=0))
    assert not honest.success and "exceeded" in honest.message
    assert max(honest.ratios.values()) > 1.0
    repaired = opt.minimum_time_trajectory(arm, Q_I, Q_F, arm_limits, opt.OptimizationOptions(nodes=6, order=3))
    assert repaired.success, repaired.message
    r = _independent_ratios(arm, repaired.trajectory.law, arm_limits)
    assert max(r["qd"], r["qdd"], r["tau"]) <= 1 + 1e-6


def test_kinematic_limits_only_give_the_bang_coast_bang_time(arm):
    # Torques loose: the minimum time is that of the slowest joint's bang-coast-bang profile,
    # T_j = Δq/v + v/a when Δq ≥ v²/a, else 2√(Δq/a) (closed form, independent of the solver).
    limits = opt.JointLimits.from_robot(arm, qdd_max=[6.0, 10.0], qd_max=[2.0, 1.0])
    q_i, q_f = np.array([0.0, 0.0]), np.array([1.2, -1.5])
    dq, v, a = np.abs(q_f - q_i), limits.qd_max, limits.qdd_max
    T = np.where(dq >= v**2 / a, dq / v + v / a, 2 * np.sqrt(dq / a))
    res = opt.minimum_time_trajectory(arm, q_i, q_f, limits, opt.OptimizationOptions(nodes=20))
    assert res.success, res.message
    assert res.t_f == pytest.approx(T.max(), rel=1e-4)


# --------------------------------------------------------------------------------------------
# Infinite limits and options (reliability)
# --------------------------------------------------------------------------------------------

def test_unbounded_joints_are_supported(arm):
    """q limits ±inf: the old code failed inside CasADi ("LBX = -nan") or blamed the torque limits.
    The result must be the bang-coast-bang time of the slowest joint (closed form)."""
    inf = np.inf
    limits = opt.JointLimits([-inf, -inf], [inf, inf], [2.0, 1.0], [6.0, 10.0], [inf, inf])
    q_i, q_f = np.array([0.0, 0.0]), np.array([1.2, -1.5])
    dq, v, a = np.abs(q_f - q_i), limits.qd_max, limits.qdd_max
    T = np.where(dq >= v**2 / a, dq / v + v / a, 2 * np.sqrt(dq / a))
    first, _ = opt.trapezoidal_under_limits(arm, q_i, q_f, limits)
    assert first.duration >= T.max() * (1 - 1e-4)
    res = opt.minimum_time_trajectory(arm, q_i, q_f, limits, opt.OptimizationOptions(nodes=20))
    assert res.success, res.message
    assert res.t_f == pytest.approx(T.max(), rel=1e-4)
    assert res.ratios["q"] == 0.0


def test_infinite_limits_that_cannot_work_are_refused_by_name(arm):
    inf = np.inf
    with pytest.raises(ValueError, match="`q_min`.*`q_max`.*both infinite"):
        opt.JointLimits([-inf, 0.0], [1.0, 1.0], 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="`q_min` must not be \\+inf"):
        opt.JointLimits([inf, 0.0], [inf, 1.0], 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="`qdd_max` must be finite"):
        opt.JointLimits([0, 0], [1, 1], 1.0, inf, 1.0)
    with pytest.raises(ValueError, match="`q_max`"):
        opt.JointLimits([0, 0], "big", 1.0, 1.0, 1.0)
    limits = opt.JointLimits([-inf, -inf], [inf, inf], 2.0, 6.0, inf)
    with pytest.raises(ValueError, match="`tau_max` must be finite"):
        opt.minimum_effort_trajectory(arm, Q_I, Q_F, 1.0, limits)


@pytest.mark.parametrize("kwargs, name", [({"nodes": 2.5}, "nodes"), ({"max_backoff": -1}, "max_backoff"),
                                          ({"max_iter": 0}, "max_iter"), ({"tol": float("nan")}, "tol"),
                                          ({"regularization": -1.0}, "regularization"),
                                          ({"hessian": "bfgs"}, "hessian")])
def test_optimization_options_are_checked(kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        opt.OptimizationOptions(**kwargs)


def test_repeated_solve_reuses_the_transcription_with_the_same_result():
    """The NLP is built once per (model content, intervals, options): a second solve — also on another robot
    object with the same model — gives the same optimum and builds nothing (the cache holds one transcription)."""
    from planners.optimization import (_TRANSCRIPTIONS, JointLimits, OptimizationOptions,
                                       minimum_time_trajectory)

    arm = load("planar_2r")
    limits = JointLimits.from_robot(arm, qdd_max=[20.0, 20.0], qd_max=[3.0, 3.0], tau_max=[3000.0, 1500.0])
    options = OptimizationOptions(nodes=13, tol=1e-7)          # 13 intervals: no other test builds this one
    before = len(_TRANSCRIPTIONS)
    first = minimum_time_trajectory(arm, [0.0, 0.0], [1.0, -0.5], limits, options)
    assert len(_TRANSCRIPTIONS) == before + 1
    other = minimum_time_trajectory(arm, [0.2, 0.1], [-0.6, 0.4], limits, options)   # same NLP, new data
    again = minimum_time_trajectory(load("planar_2r"), [0.0, 0.0], [1.0, -0.5], limits, options)
    assert len(_TRANSCRIPTIONS) == before + 1
    assert first.success and again.success and other.success
    assert again.t_f == pytest.approx(first.t_f, rel=1e-9)
    assert other.t_f != pytest.approx(first.t_f, rel=1e-3)


@pytest.mark.parametrize("objective", ["time", "effort"])
def test_limited_memory_and_exact_hessians_reach_the_same_optimum(arm, arm_limits, objective):
    """The default L-BFGS Hessian changes the path IPOPT takes, not the optimum: the duration (minimum
    time) or the cost (minimum effort) agrees with the exact-Hessian solve to the solver tolerance."""
    solve = {"time": lambda o: opt.minimum_time_trajectory(arm, Q_I, Q_F, arm_limits, o),
             "effort": lambda o: opt.minimum_effort_trajectory(arm, Q_I, Q_F, 1.5, arm_limits, o)}[objective]
    lbfgs = solve(opt.OptimizationOptions(nodes=20))
    exact = solve(opt.OptimizationOptions(nodes=20, hessian="exact"))
    assert lbfgs.success and exact.success
    assert lbfgs.cost == pytest.approx(exact.cost, rel=1e-6)
    assert lbfgs.t_f == pytest.approx(exact.t_f, rel=1e-6)
