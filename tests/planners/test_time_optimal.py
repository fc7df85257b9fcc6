"""TOPP-RA timing of a fixed path: limits hold on the fine grid (Pinocchio's RNEA), and the free
minimum-time motion is no slower than the fixed path."""

import numpy as np
import pinocchio as pin
import pytest

from planners.optimization import JointLimits, OptimizationOptions, minimum_time_trajectory
from planners.time_optimal import time_optimal_path
from rigid_body.robots import load


@pytest.fixture(scope="module")
def setting():
    arm = load("planar_2r")
    limits = JointLimits.from_robot(arm, qdd_max=[20.0, 20.0], qd_max=[3.0, 3.0], tau_max=[3000.0, 1500.0])
    return arm, limits, np.array([0.0, 0.0]), np.array([1.0, -0.5])


def test_fixed_path_timing_respects_limits_and_is_slower_than_free(setting):
    arm, limits, q_i, q_f = setting
    result = time_optimal_path(arm, np.linspace(q_i, q_f, 5), limits)
    np.testing.assert_allclose(result.q[0], q_i, atol=1e-12)
    np.testing.assert_allclose(result.q[-1], q_f, atol=1e-12)
    data = arm.model.createData()
    tau = np.array([pin.rnea(arm.model, data, q, v, a) for q, v, a in zip(result.q, result.qd, result.qdd)])
    assert np.max(np.abs(tau) / limits.tau_max) <= 1.0 + 1e-6
    assert np.max(np.abs(result.qd) / limits.qd_max) <= 1.0 + 1e-6
    assert np.max(np.abs(result.qdd) / limits.qdd_max) <= 1.0 + 1e-6
    assert max(result.ratios.values()) > 0.99                      # some limit is active: time-optimal
    free = minimum_time_trajectory(arm, q_i, q_f, limits, OptimizationOptions(nodes=12))
    assert free.t_f <= result.t_f * (1 + 1e-3)
    # the time law is consistent: q̇ integrates to q (trapezoidal rule on the fine grid)
    increments = 0.5 * (result.qd[1:] + result.qd[:-1]) * np.diff(result.t)[:, None]
    np.testing.assert_allclose(q_i + increments.sum(axis=0), q_f, atol=1e-3)


def test_bad_waypoints_are_refused(setting):
    arm, limits, *_ = setting
    with pytest.raises(ValueError, match="waypoints"):
        time_optimal_path(arm, np.zeros((1, 2)), limits)
    with pytest.raises(ValueError, match="waypoints"):
        time_optimal_path(arm, np.full((3, 2), np.nan), limits)


def test_blended_polyline_is_c1_and_its_derivatives_are_exact():
    from planners.time_optimal import BlendedPolyline

    W = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 2.0]])
    path = BlendedPolyline(W, [0.2, 0.3])
    s = np.linspace(0.0, path.length, 4001)
    q, dq, ddq = path(s), path(s, 1), path(s, 2)
    h = s[1] - s[0]
    smooth = ~np.array([np.any((a < path.breakpoints) & (path.breakpoints < b)) for a, b in zip(s[:-1], s[1:])])
    mid = path(0.5 * (s[1:] + s[:-1]), 1)                  # exact for a quadratic piece: q' integrates to q
    np.testing.assert_allclose((np.diff(q, axis=0) / h)[smooth], mid[smooth], atol=1e-9)
    assert np.abs(np.diff(dq, axis=0)).max() <= np.abs(ddq).max() * h + 1e-12                 # no tangent jump (C¹)
    inner = (ddq[1:-1] == ddq[:-2]).all(axis=1) & (ddq[1:-1] == ddq[2:]).all(axis=1)
    np.testing.assert_allclose(np.diff(dq, axis=0)[1:][inner] / h, ddq[1:-1][inner], atol=1e-9)
    np.testing.assert_allclose(q[[0, -1]], W[[0, -1]], atol=1e-12)
    # the first blend stays in the triangle (v − δu₋, v, v + δu₊): within δ of the corner in every coordinate
    near = (s >= path.breakpoints[1]) & (s <= path.breakpoints[2])            # the first blend
    assert np.abs(path.breakpoints[2] - path.breakpoints[1] - 0.4) < 1e-12
    assert np.all(np.abs(q[near] - W[1]) <= 0.2 + 1e-12)


@pytest.fixture(scope="module")
def panda_scene():
    from controllers.scenes import panda_shelf

    return panda_shelf()


def test_planner_shortcut_timing_on_the_panda_never_collides(panda_scene):
    """Issue 25: rrt_connect → shortcut → time_optimal_path(space=...) gives a certified motion on every seed
    where the planner succeeds, and a dense pairwise re-check of the geometric path (≤ 2.5 mrad steps) finds
    no contact; the spline through the same waypoints (no space: not certified) does collide."""
    from planners.sampling import rrt_connect, shortcut

    sc = panda_scene
    space, checker = sc.space, sc.space.checker
    limits = JointLimits.from_robot(sc.robot, qdd_max=5.0)
    spline_hits = 0
    for seed in range(6):
        res = rrt_connect(space, sc.q_start, sc.q_goal, seed, step=0.5, max_iterations=5000)
        assert res.success, res.message
        path = shortcut(space, res.path, seed, attempts=100)
        motion = time_optimal_path(sc.robot, path, limits, space=space)
        assert motion.certified and motion.min_clearance > 0
        assert np.all(np.abs(motion.qd) <= limits.qd_max * (1 + 1e-6))
        np.testing.assert_allclose(motion.q[[0, -1]], [sc.q_start, sc.q_goal], atol=1e-12)
        L = motion.path.length
        S = np.linspace(0.0, L, int(np.ceil(L / 0.0025)) + 1)
        Q = motion.path(S)
        assert np.abs(np.diff(Q, axis=0)).max() <= 0.0025
        assert not any(checker.in_collision_pairwise(q) for q in Q), f"seed {seed}"
        assert not any(checker.in_collision_pairwise(q) for q in motion.q)
        spline = time_optimal_path(sc.robot, path, limits)
        assert not spline.certified
        spline_hits += any(checker.in_collision_pairwise(q) for q in spline.q[::5])
    assert spline_hits >= 1          # the defect the certified blends remove


def test_uncertified_waypoints_are_refused(panda_scene):
    sc = panda_scene
    limits = JointLimits.from_robot(sc.robot, qdd_max=5.0)
    with pytest.raises(ValueError, match="not a certified-free polyline"):
        time_optimal_path(sc.robot, np.array([sc.q_start, sc.q_goal]), limits, space=sc.space)


def test_the_timed_motion_evaluates_exactly_between_samples(setting):
    arm, limits, q_i, q_f = setting
    m = time_optimal_path(arm, np.linspace(q_i, q_f, 5), limits)
    q, qd, qdd = m(m.t)
    np.testing.assert_allclose(q, m.q, atol=1e-12)
    np.testing.assert_allclose(qd, m.qd, atol=1e-9)
    t = np.linspace(0.0, m.t_f, 20001)
    q, qd, _ = m(t)
    np.testing.assert_allclose(np.diff(q, axis=0) / np.diff(t)[:, None], 0.5 * (qd[1:] + qd[:-1]), atol=1e-4)
    assert np.allclose(m(-1.0)[0], q_i) and np.allclose(m(m.t_f + 1)[0], q_f) and not np.any(m(m.t_f + 1)[1])


def test_limits_still_exceeded_after_the_backoffs_are_an_error(setting):
    """Review MED: after `max_backoff` re-solves a ratio above 1 used to come back as a normal result (only
    `ratios` showed it). On a coarse grid the torque exceeds its limit by 0.9 % after the first solve, 0.009 %
    after one back-off; two back-offs meet it."""
    arm, limits, q_i, q_f = setting
    W = np.linspace(q_i, q_f, 5)
    with pytest.raises(ValueError, match=r"after `max_backoff` = 1 re-solves: the torque `limits.tau_max` at 1\.0000"):
        time_optimal_path(arm, W, limits, gridpoints=10, max_backoff=1)
    with pytest.raises(ValueError, match=r"`max_backoff` = 0 .*tau_max` at 1\.009"):
        time_optimal_path(arm, W, limits, gridpoints=10, max_backoff=0)
    ok = time_optimal_path(arm, W, limits, gridpoints=10, max_backoff=2)
    assert ok.backoffs == 2 and max(ok.ratios.values()) <= 1.0 + 1e-6
    for bad in (-1, 1.5, "2", True):
        with pytest.raises(ValueError, match="`max_backoff` must be an integer >= 0"):
            time_optimal_path(arm, W, limits, max_backoff=bad)


def test_blend_arguments_are_validated():
    """Review LOW: δ = 0 at a real corner made a path with a kink (q' jumps, q'' undefined) that TOPP-RA timed
    as if it were C¹; `certified_blends(safety=)` took any value (safety > 1 leaves the certified room)."""
    from planners.configuration_space import Disc, PlanarBody, PlanarCSpace, Scene
    from planners.time_optimal import BlendedPolyline, certified_blends

    W = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 2.0]])
    with pytest.raises(ValueError, match=r"`deltas`\[0\] = 0 at a corner \(waypoint 1 turns by .* = 1.41"):
        BlendedPolyline(W, [0.0, 0.3])
    with pytest.raises(ValueError, match=r"`deltas`\[1\] = 0"):
        BlendedPolyline(W, [0.2, 0.0])
    straight = BlendedPolyline(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), [0.0])    # no corner: allowed
    np.testing.assert_allclose(straight(1.5), [1.5, 0.0])
    with pytest.raises(ValueError, match="`deltas` must be finite"):
        BlendedPolyline(W, [np.nan, 0.3])
    with pytest.raises(ValueError, match="`waypoints` must be a finite"):
        BlendedPolyline(W[:1], [])
    body = PlanarBody((Disc([0.0, 0.0], 0.01),))
    space = PlanarCSpace(body, Scene([], (-3, 3, -3, 3)), [-3, -3, -np.pi], [3, 3, np.pi])
    P = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]])
    assert certified_blends(space, P)[0][0] > 0
    for bad in (0.0, -0.5, 1.5, np.nan, "0.5", True):
        with pytest.raises(ValueError, match=r"`safety` must be a number in \(0, 1\]"):
            certified_blends(space, P, safety=bad)
