"""Issue 25: a planner's success means certified collision-free along every edge (and every timed sample).

Each defect of the issue is reproduced here first (thin walls, invisible obstacles, cells inside
obstacles, unbounded effort, unclear errors), then the fixed behaviour is asserted. The dense re-checks
are independent of the certificate: exact point-in-shape tests (a second algorithm) on samples a fraction
of the obstacle thickness apart.
"""

import threading

import numpy as np
import pytest

from planners.configuration_space import (Disc, PlanarBody, PlanarCSpace, Polygon, Scene, box,
                                          certify_straight_path, densify, free_grid)
from planners.sampling import MotionPrimitive, prm, rrt, rrt_connect, shortcut, unicycle_rrt

WALL = 0.004            # a 4 mm wall
RADIUS = 0.001          # a 1 mm point robot


@pytest.fixture(scope="module")
def thin_wall():
    """A 1 mm disc robot, a 4 mm wall across the square with a gap near the top; start left, goal right."""
    wall = [box(-WALL / 2, -1.0, WALL / 2, 0.7)]
    body = PlanarBody((Disc([0.0, 0.0], RADIUS),))
    space = PlanarCSpace(body, Scene(wall, (-1, 1, -1, 1)), [-1, -1, -np.pi], [1, 1, np.pi], resolution=0.01)
    return space, np.array([-0.5, -0.5, 0.0]), np.array([0.5, -0.5, 0.0])


def dense_collisions(space, path, step=2.5e-4):
    """Samples of the path (at most ``step`` apart in the plane) where the disc's centre is within its radius of
    an obstacle: exact point-in-polygon and point-to-edge tests, independent of the planners' certificate."""
    Q = densify(space, path, step)
    hits = 0
    for o in space.scene.obstacles:
        a, b = o.edges
        inside = o.contains(Q[:, :2])
        d = np.min(np.abs(np.cross(b - a, Q[:, None, :2] - a)) / np.linalg.norm(b - a, axis=1), axis=1)
        hits += int(np.sum(inside | (d < RADIUS) & o.contains(Q[:, :2], RADIUS)))
    return hits, len(Q)


PLANNERS = {
    "prm": lambda s, a, b, g, **kw: prm(s, a, b, g, n_vertices=100, max_neighbors=10, max_distance=1.5,
                                         max_vertices=2000, **kw),
    "rrt": lambda s, a, b, g, **kw: rrt(s, a, b, g, step=0.3, max_iterations=20000, **kw),
    "rrt_connect": lambda s, a, b, g, **kw: rrt_connect(s, a, b, g, step=0.3, max_iterations=20000, **kw),
}


@pytest.mark.parametrize("planner", sorted(PLANNERS))
def test_thin_wall_certified_paths_never_cross(thin_wall, planner):
    space, qs, qg = thin_wall
    for seed in range(3):
        res = PLANNERS[planner](space, qs, qg, seed)
        assert res.success, res.message
        assert res.certified and res.min_clearance > 0 and res.distance_queries > 0
        hits, n = dense_collisions(space, res.path)
        assert hits == 0, f"{planner} seed {seed}: {hits} of {n} dense samples in the wall"
        assert certify_straight_path(space, res.path, 0.01)[0]
        short = shortcut(space, res.path, seed, attempts=50)
        assert dense_collisions(space, short)[0] == 0


def test_sampled_mode_is_explicit_and_says_not_certified(thin_wall):
    space, qs, qg = thin_wall
    crossed = 0
    for seed in range(3):
        res = rrt_connect(space, qs, qg, seed, step=0.3, edge_check="sampled")
        assert res.success and not res.certified
        crossed += dense_collisions(space, res.path)[0] > 0
    assert crossed > 0          # the reason the certified mode is the default


# --------------------------------------------------------------------------------------------
# URDF arms: the pair motion bound and the certificate against dense re-checks
# --------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def panda_space():
    from examples.planning import panda_shelf

    return panda_shelf().space


def _vertices_world(checker, q):
    """World positions of every mesh vertex (and box corner) of the robot at q, by shape index."""
    import pinocchio as pin

    data = checker.model.createData()
    gdata = checker.geom.createData()
    pin.updateGeometryPlacements(checker.model, data, checker.geom, gdata, q)
    out = {}
    for i, obj in enumerate(checker.geom.geometryObjects):
        g = obj.geometry
        if hasattr(g, "vertices"):
            V = np.asarray(g.vertices())
        elif hasattr(g, "halfSide"):
            V = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * g.halfSide
        else:
            continue
        M = gdata.oMg[i]
        out[i] = V @ M.rotation.T + M.translation
    return out


def test_pair_motion_bound_bounds_the_real_displacement(panda_space):
    """Every mesh vertex moves (in the world, against a box) no more than the pair's bound W|Δq| along the
    edge: checked at 20 points of 30 random edges (the vertices' positions by Pinocchio's placements)."""
    checker = panda_space.checker
    rng = np.random.default_rng(5)
    box_pairs = {p.first: k for k, p in enumerate(checker.distance_geom.collisionPairs)
                 if p.second >= checker.geom.ngeoms - len(checker.boxes)}
    worst = 0.0
    for _ in range(30):
        a, b = panda_space.sample(rng), panda_space.sample(rng)
        b = a + 0.4 * (b - a)
        Va = _vertices_world(checker, a)
        for s in np.linspace(0.05, 1.0, 20):
            Vs = _vertices_world(checker, a + s * (b - a))
            bound = s * panda_space.edge_rates(a, b)
            for g, k in box_pairs.items():
                moved = np.linalg.norm(Vs[g] - Va[g], axis=1).max()
                assert moved <= bound[k] + 1e-12
                worst = max(worst, moved / bound[k])
    assert worst > 0.2          # the bound is not vacuous


def test_certified_panda_edges_pass_a_dense_pairwise_recheck(panda_space):
    """Random edges the certificate accepts are free on a 2 mrad grid checked pair by pair (meshes, no broad
    phase); some edges are refused (the certificate is not trivially permissive)."""
    from examples.planning import recheck_path

    rng = np.random.default_rng(11)
    accepted = refused = 0
    while accepted < 15:
        a = panda_space.sample(rng)
        if not panda_space.is_valid(a):
            continue
        b = a + rng.uniform(0.2, 1.0) * (panda_space.sample(rng) - a)
        if not panda_space.is_valid(b):
            continue
        cert = panda_space.certify_edge(a, b)
        if cert.free:
            accepted += 1
            assert cert.min_clearance > 0
            assert recheck_path(panda_space.checker, np.array([a, b]), step=0.002)[0]
        else:
            refused += 1
    assert refused > 0


def test_two_threads_plan_on_one_space_as_one_thread_does(panda_space):
    """Two threads planning on one UrdfCSpace at once get exactly the single-threaded results."""
    from examples.planning import panda_shelf

    sc = panda_shelf()
    alone = [rrt_connect(panda_space, sc.q_start, sc.q_goal, seed, step=0.5, max_iterations=5000)
             for seed in (1, 2)]
    got = {}

    def run(seed):
        got[seed] = rrt_connect(panda_space, sc.q_start, sc.q_goal, seed, step=0.5, max_iterations=5000)

    threads = [threading.Thread(target=run, args=(seed,)) for seed in (1, 2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for seed, res in zip((1, 2), alone):
        assert res.success and got[seed].success
        np.testing.assert_array_equal(res.path, got[seed].path)
