"""The planning demo beyond the book: URDF arms among boxes, planned, shortcut, timed and re-checked."""

import numpy as np
import pytest

from controllers.scenes import anthropomorphic_pillar, panda_shelf
from examples.planning import plan_and_time, planning_demo, recheck, time_path
from planners.sampling import edge_is_free


@pytest.fixture(scope="module")
def panda():
    return panda_shelf()


def test_anthropomorphic_demo_all_checks_pass():
    sol = planning_demo(anthropomorphic_pillar())
    failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
    assert not failed, failed
    assert len(sol.figures) == 1 and len(sol.animations) == 1
    assert sol.values["rrt_connect_shortcut_length"] <= sol.values["rrt_connect_raw_length"]


def test_the_straight_motion_is_blocked_and_the_recheck_sees_it(panda):
    """The query is not trivial, and the independent re-check can fail: the timed straight line hits."""
    assert not edge_is_free(panda.space, panda.q_start, panda.q_goal)
    assert not edge_is_free(panda.space, panda.q_start, panda.q_goal, edge_check="sampled")
    law = time_path(np.array([panda.q_start, panda.q_goal]), panda.qd_max, panda.qdd_max)
    free, n, t_hit = recheck(panda.space.checker, law)
    assert not free and law.t_i < t_hit < law.t_f


def test_panda_rrt_connect_motion_is_certified_free_and_within_limits(panda):
    m = plan_and_time(panda, "rrt_connect", seed=2)
    assert m.free and m.result.certified and m.motion.certified and m.distance_queries > 0
    # second re-check, independent of the demo's: the broad-phase checker on a 2 mrad grid of the motion
    t = np.linspace(0.0, m.motion.t_f, 6001)
    q = np.reshape(m.motion(t)[0], (t.size, -1))
    assert np.abs(np.diff(q, axis=0)).max() < 0.002
    assert not any(panda.space.checker.in_collision(qk) for qk in q[::3])
    assert np.all(q >= panda.space.lower - 1e-9) and np.all(q <= panda.space.upper + 1e-9)
    h = t[1] - t[0]
    assert np.all(np.abs(np.diff(q, axis=0)) / h <= panda.qd_max * 1.001)
    assert np.all(np.abs(np.diff(q, 2, axis=0)) / h ** 2 <= panda.qdd_max * 1.05)
    np.testing.assert_allclose(q[[0, -1]], [panda.q_start, panda.q_goal], atol=1e-12)
