"""Sampling planners (planners.sampling) on planar C-spaces."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from planners.configuration_space import (Disc, PlanarArm, PlanarBody, PlanarCSpace, Polygon, Scene, box,
                                    certify_straight_path)
from planners.sampling import (MotionPrimitive, edge_is_free, path_length, prm, rrt, rrt_connect, shortcut,
                               unicycle_arc, unicycle_rrt)


@pytest.fixture
def arm_space():
    scene = Scene([Disc([-0.8, 1.2], 0.2), Disc([-1.2, -0.9], 0.3), Disc([1.3, 1.5], 0.2),
                   Disc([-1.2, 0.9], 0.3), Polygon([[0, 0.5], [0.5, 0.5], [0.5, 1], [0, 1]])])
    return PlanarCSpace(PlanarArm((1.0, 1.0), 0.1), scene, [-np.pi] * 2, [np.pi] * 2, resolution=0.02)


QS, QG = np.array([-np.pi / 4, 3 * np.pi / 4]), np.array([5 * np.pi / 8, -np.pi / 2])


@pytest.mark.parametrize("planner", ["prm", "rrt", "rrt_connect"])
def test_planners_find_certified_paths_and_repeat(arm_space, planner):
    run = {"prm": lambda g: prm(arm_space, QS, QG, g, n_vertices=50, max_vertices=300),
           "rrt": lambda g: rrt(arm_space, QS, QG, g, step=0.3, max_iterations=3000),
           "rrt_connect": lambda g: rrt_connect(arm_space, QS, QG, g, step=0.3)}[planner]
    res = run(np.random.default_rng(3))
    assert res.success, res.message
    assert np.allclose(res.path[0], QS) and np.allclose(res.path[-1], QG)
    assert certify_straight_path(arm_space, res.path, 0.02)[0]
    again = run(np.random.default_rng(3))
    assert np.array_equal(res.path, again.path)
    assert res.length == pytest.approx(path_length(arm_space, res.path))


def test_shortcut_never_lengthens(arm_space):
    res = rrt_connect(arm_space, QS, QG, np.random.default_rng(1), step=0.3)
    short = shortcut(arm_space, res.path, np.random.default_rng(1), attempts=100)
    assert path_length(arm_space, short) <= res.length + 1e-12
    assert all(edge_is_free(arm_space, a, b) for a, b in zip(short[:-1], short[1:]))


def test_prm_reports_failure_instead_of_raising(arm_space):
    res = prm(arm_space, QS, QG, np.random.default_rng(0), n_vertices=2, max_neighbors=1, max_distance=0.1)
    assert not res.success and res.path.shape == (0, 2) and "components" in res.message


def test_start_in_collision_is_rejected(arm_space):
    with pytest.raises(ValueError, match="q_start"):
        prm(arm_space, [np.pi / 3, 0.0], QG, np.random.default_rng(0))


@pytest.mark.parametrize("v, w", [(1.0, 0.0), (1.0, 1.3), (-0.5, -2.0)])
def test_unicycle_arc_is_the_exact_integral(v, w):
    q0 = np.array([0.3, -0.2, 2.9])
    t = np.linspace(0, 2, 9)
    ref = solve_ivp(lambda _, x: [v * np.cos(x[2]), v * np.sin(x[2]), w], (0, 2), q0, t_eval=t,
                    rtol=1e-11, atol=1e-12).y.T
    arc = unicycle_arc(q0, v, w, t)
    d = arc - ref
    d[:, 2] = np.angle(np.exp(1j * d[:, 2]))
    assert np.abs(d).max() < 1e-8


def test_unicycle_rrt_edges_are_primitives_and_reach_a_loose_goal():
    scene = Scene([Disc([0, 0], 0.5), box(1.5, -2, 2, -0.5)])
    body = PlanarBody((Polygon([[-0.1, -0.2], [-0.1, 0.2], [0.5, 0.0]]),))
    space = PlanarCSpace(body, scene, [-4, -4, -np.pi], [4, 4, np.pi])
    prims = [MotionPrimitive(1, 0), MotionPrimitive(1, 1.3), MotionPrimitive(1, -1.3)]
    res = unicycle_rrt(space, [-3, 0, 0], [3, 0, 0], np.random.default_rng(0), prims, 0.9,
                       max_vertices=400, goal_threshold=0.5)
    assert res.success, res.message
    for a, b, (v, w) in zip(res.path[:-1], res.path[1:], res.controls):
        assert np.allclose(unicycle_arc(a, v, w, 0.9), b)
    assert float(space.distance(res.path[-1], [3, 0, 0])) <= 0.5
