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
    from controllers.scenes import panda_shelf

    return panda_shelf().space


def _vertices_world(checker, q):
    """World positions of the vertices of every shape of the certificate's geometry (the links' convex hulls,
    box corners) at q, by shape index."""
    import pinocchio as pin

    geom = checker.distance_geom
    data = checker.model.createData()
    gdata = geom.createData()
    pin.updateGeometryPlacements(checker.model, data, geom, gdata, q)
    out = {}
    for i, obj in enumerate(geom.geometryObjects):
        g = obj.geometry
        if callable(getattr(g, "points", None)):
            V = np.asarray(g.points())
        elif hasattr(g, "halfSide"):
            V = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * g.halfSide
        else:
            continue
        M = gdata.oMg[i]
        out[i] = V @ M.rotation.T + M.translation
    return out


def _joint_frames(checker, q):
    import pinocchio as pin

    data = checker.model.createData()
    pin.forwardKinematics(checker.model, data, q)
    return [data.oMi[j].copy() for j in range(checker.model.njoints)]


def _common_ancestor(model, i, j):
    def chain(k):
        out = [k]
        while k > 0:
            k = model.parents[k]
            out.append(k)
        return out
    ci = chain(i)
    return next(k for k in chain(j) if k in ci)


def test_pair_motion_bound_bounds_the_real_displacement(panda_space):
    """Every mesh vertex moves no more than its pair's bound W|Δq| along the edge — in the world for a shape
    against a box; for a self-collision pair, the displacements of both shapes' vertices in the frame of their
    deepest common joint add up to no more than it (the pair's distance is a distance in that frame): checked
    at 12 points of 25 random edges (vertex positions from Pinocchio's placements)."""
    checker = panda_space.checker
    rng = np.random.default_rng(5)
    n_boxes = len(checker.boxes)
    pairs = [(p.first, p.second) for p in checker.distance_geom.collisionPairs]
    worst = {"box": 0.0, "self": 0.0}
    for _ in range(25):
        a, b = panda_space.sample(rng), panda_space.sample(rng)
        b = a + 0.4 * (b - a)
        Va, Ja = _vertices_world(checker, a), _joint_frames(checker, a)
        for s in np.linspace(0.05, 1.0, 12):
            Vs, Js = _vertices_world(checker, a + s * (b - a)), _joint_frames(checker, a + s * (b - a))
            bound = s * panda_space.edge_rates(a, b)
            for k, (g, h) in enumerate(pairs):
                if h >= checker.distance_geom.ngeoms - n_boxes:           # against a box: world motion
                    moved, kind = np.linalg.norm(Vs[g] - Va[g], axis=1).max(), "box"
                else:                                                     # self pair: in the common joint's frame
                    c = _common_ancestor(checker.model, checker.distance_geom.geometryObjects[g].parentJoint,
                                         checker.distance_geom.geometryObjects[h].parentJoint)
                    moved, kind = 0.0, "self"
                    for x in (g, h):
                        rel_a = (Va[x] - Ja[c].translation) @ Ja[c].rotation
                        rel_s = (Vs[x] - Js[c].translation) @ Js[c].rotation
                        moved += np.linalg.norm(rel_s - rel_a, axis=1).max()
                assert moved <= bound[k] + 1e-9, (k, g, h, moved, bound[k])
                worst[kind] = max(worst[kind], moved / bound[k])
    assert worst["box"] > 0.3 and worst["self"] > 0.1        # the bounds are not vacuous


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
    from controllers.scenes import panda_shelf

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


# --------------------------------------------------------------------------------------------
# Obstacles validated, bounded effort, clear errors (issue 25 items 3, 5, 6)
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("vertices, match", [
    ([[0, 0], [1, 0], [1, 0], [1, 1], [0, 1]], "same point"),            # the invisible obstacle of the issue
    ([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], "same point"),            # closed by repeating the first vertex
    ([[0, 0], [1, 0], [2, 0]], "zero area"),
    ([[0, 0], [2, 1], [0, 2], [2, 2], [1, -1]], "convex|self-intersecting"),
    ([[np.cos(a), np.sin(a)] for a in np.arange(5) * 4 * np.pi / 5], "self-intersecting"),   # a pentagram
    ([[0, 0], [2, 0], [1, 0.2], [1, 2]], "convex"),
    ([[0, 0], [1, np.nan], [0, 1]], "finite"),
])
def test_bad_polygons_are_refused(vertices, match):
    with pytest.raises(ValueError, match=match):
        Polygon(vertices)


def test_scene_names_the_bad_obstacle_and_field():
    good = box(0, 0, 1, 1)
    bad = box(2, 2, 3, 3)
    object.__setattr__(bad, "vertices", np.array([[2, 2], [3, 2], [3, 2], [2, 3.0]]))   # altered after the check
    with pytest.raises(ValueError, match=r"obstacles\[1\].*vertices"):
        Scene([good, bad])
    with pytest.raises(ValueError, match="radius"):
        Disc([0, 0], -1)
    with pytest.raises(ValueError, match="center"):
        Disc([np.nan, 0], 1)
    with pytest.raises(ValueError, match="bounds"):
        Scene([good], (1, 0, 0, 1))
    with pytest.raises(ValueError, match="bounds"):
        Scene([good], (0, np.inf, 0, 1))
    from planners.collision import Box
    with pytest.raises(ValueError, match="'shelf'.*size"):
        Box([0, 0, 0], [1, 0, 1], "shelf")
    with pytest.raises(ValueError, match="'shelf'.*center"):
        Box([0, np.nan, 0], [1, 1, 1], "shelf")


def test_a_robot_inside_a_repeated_vertex_polygon_is_no_longer_valid():
    """With the repeated vertex removed the obstacle is seen: the robot inside it is in collision."""
    P = Polygon([[0, 0], [1, 0], [1, 1], [0, 1]])
    body = PlanarBody((Disc([0.0, 0.0], 0.01),))
    space = PlanarCSpace(body, Scene([P], (-2, 2, -2, 2)), [-2, -2, -np.pi], [2, 2, np.pi])
    assert not space.is_valid([0.5, 0.5, 0.0]) and space.is_valid([1.5, 0.5, 0.0])


@pytest.fixture(scope="module")
def tiny_free_set():
    """A disc robot in a square almost filled by an obstacle: samples are nearly always rejected."""
    body = PlanarBody((Disc([0.0, 0.0], 0.005),))
    scene = Scene([box(-0.98, -1.2, 1.2, 1.2), box(-1.2, -0.05, -0.9, 0.05)], (-1, 1, -1, 1))   # no way through
    return PlanarCSpace(body, scene, [-1, -1, -np.pi], [1, 1, np.pi]), np.array([-0.99, -0.5, 0]), \
        np.array([-0.99, 0.5, 0])


def test_every_planner_ends_with_a_named_budget(tiny_free_set, thin_wall):
    space, qs, qg = tiny_free_set
    res = prm(space, qs, qg, 0, n_vertices=50, max_rejected=500)
    assert not res.success and "max_rejected" in res.message
    space2, a, b = thin_wall
    res = rrt(space2, a, b, 0, step=0.01, max_iterations=50)
    assert not res.success and "max_iterations" in res.message
    res = rrt_connect(space2, a, b, 0, step=0.001, max_iterations=20)
    assert not res.success and "max_iterations" in res.message
    res = rrt_connect(space2, a, b, 0, step=0.001, max_iterations=10**9, time_limit=0.2)
    assert not res.success and "time limit" in res.message
    prims = [MotionPrimitive(1.0, 0.0), MotionPrimitive(1.0, 1.3)]
    res = unicycle_rrt(space, qs, qg, 0, prims, 0.5, goal_bias=0.0, max_vertices=100, max_rejected=300)
    assert not res.success and ("max_rejected" in res.message or "primitives" in res.message)
    res = unicycle_rrt(space2, a, b, 0, prims, 0.05, goal_bias=0.0, max_vertices=10**6, max_iterations=30)
    assert not res.success and "max_iterations" in res.message


def test_free_grid_refuses_a_grid_beyond_memory(thin_wall):
    space = thin_wall[0]
    axis = np.linspace(-1, 1, 100_000)
    with pytest.raises(ValueError, match="max_nodes"):
        free_grid(space, [axis, axis, axis])
    small = free_grid(space, [np.linspace(-1, 1, 9)] * 3, chunk=50)
    assert small.shape == (9, 9, 9) and small.any() and not small.all()


def test_rng_accepts_a_seed_or_a_generator_and_nothing_else(thin_wall):
    space, qs, qg = thin_wall
    a = rrt(space, qs, qg, 42, step=0.3, max_iterations=20000)
    b = rrt(space, qs, qg, np.random.default_rng(42), step=0.3, max_iterations=20000)
    np.testing.assert_array_equal(a.path, b.path)
    for bad in (None, 1.5, np.random.RandomState(0), -1):
        with pytest.raises(ValueError, match="rng"):
            rrt(space, qs, qg, bad)


def test_unclear_errors_of_the_issue_now_name_the_argument(thin_wall):
    from planners.potentials import AttractivePotential, PotentialField, wavefront

    space, qs, qg = thin_wall
    ok, c_min, n = certify_straight_path(space, [qs, [-0.5, 0.9, 0.0], [0.5, 0.9, 0.0], qg], 0.05)   # PlanarBody
    assert ok and c_min > 0
    assert not certify_straight_path(space, [qs, qg], 0.05)[0]
    with pytest.raises(ValueError, match="`goal`"):
        wavefront(np.zeros((5, 5), dtype=bool), (np.nan, 2))
    with pytest.raises(ValueError, match="`goal`"):
        wavefront(np.zeros((5, 5), dtype=bool), (2.5, 2))
    with pytest.raises(ValueError, match="goal"):
        PotentialField(AttractivePotential([1.0, 2.0, 3.0]))
    with pytest.raises(ValueError, match="coordinates"):
        space.distance(np.zeros((4, 2)), qs)
    with pytest.raises(ValueError, match="edge_check"):
        rrt(space, qs, qg, 0, edge_check="exact")


def test_panda_checker_names_a_wrong_configuration(panda_space):
    with pytest.raises(ValueError, match="`q`"):
        panda_space.checker.in_collision(np.zeros(3))
    with pytest.raises(ValueError, match="`q`"):
        panda_space.checker.clearances(np.zeros(3))


def test_potential_and_grid_paths_are_certified_or_marked_not():
    from planners.potentials import (AttractivePotential, PotentialField, RepulsivePotential, certify_grid_path,
                                     gradient_descent, steepest_descent_path, wavefront)

    obstacle = Disc([1.5, 0.2], 0.4)
    field = PotentialField(AttractivePotential([3.0, 0.0], 1.0), (RepulsivePotential(obstacle, 0.5, 1.0),))
    plain = gradient_descent(field.force, [0.0, 0.0], step=0.02, tol=1e-4)
    assert plain.converged and not plain.certified
    checked = gradient_descent(field.force, [0.0, 0.0], step=0.02, tol=1e-4, obstacles=[obstacle])
    assert checked.certified and checked.min_clearance > 0
    through = gradient_descent(lambda q: np.array([3.0, 0.0]) - q, [0.0, 0.2], step=0.5, tol=1e-4,
                               obstacles=[obstacle])
    assert through.converged and not through.certified        # the straight descent crosses the disc
    occ = np.zeros((3, 3), dtype=bool)
    occ[0, 1] = occ[1, 0] = True          # the diagonal (0, 0) → (1, 1) squeezes between two obstacle cells
    occ[0, 0] = False
    value = wavefront(occ, (2, 2), adjacency=2)
    cells = steepest_descent_path(value, (0, 0), adjacency=2)
    ok, why = certify_grid_path(occ, cells)
    assert not ok and "corner" in why
    empty = np.zeros((3, 3), dtype=bool)
    assert certify_grid_path(empty, steepest_descent_path(wavefront(empty, (2, 2)), (0, 0)))[0]


def test_unicycle_arcs_are_certified_and_dense_samples_agree():
    """Problem 12.8's scene: every arc of the certified tree's path is free at samples 1 mm of motion apart
    (exact shape distances), and an arc leaving the position bounds is refused by its exact extent."""
    from planners.sampling import certify_arc, unicycle_arc
    from controllers.scenes import scene_12_8

    space, qs, qg = scene_12_8()
    prims = [MotionPrimitive(1.0, 0.0), MotionPrimitive(1.0, 1.3), MotionPrimitive(1.0, -1.3)]
    res = unicycle_rrt(space, qs, qg, 12, prims, 0.9, max_vertices=200, goal_threshold=0.3)
    assert res.success and res.certified and res.min_clearance > 0
    r = space.robot.radius()
    for a, (v, w) in zip(res.path[:-1], res.controls):
        n = int(np.ceil((abs(v) + abs(w) * r) * 0.9 / 0.001))
        arc = unicycle_arc(a, v, w, np.linspace(0.0, 0.9, n + 1))
        assert np.all(space.clearance(arc) > 0)
    near_wall = np.array([4.5, 0.0, 0.0])                 # heading to x = 5 (the bound) on a 0.9 m arc
    assert not certify_arc(space, near_wall, MotionPrimitive(1.0, 0.0), 0.9).free
    assert certify_arc(space, near_wall, MotionPrimitive(1.0, 0.0), 0.4).free
    turning = np.array([4.0, -4.6, -np.pi / 2])           # a left turn dips below y = −5 before coming back
    assert not certify_arc(space, turning, MotionPrimitive(1.0, 1.3), 2.0).free


def test_certify_straight_path_names_a_space_it_cannot_read(panda_space):
    with pytest.raises(ValueError, match="certify_path"):
        certify_straight_path(panda_space, np.zeros((2, 7)))


def test_the_certificate_geometry_contains_the_collision_shapes(panda_space):
    """One hull per link: at random configurations no hull distance exceeds the distance of the collision shapes
    it stands for (coal on the meshes and boxes, pair by pair), and the Panda's 92 pairs become 50."""
    import pinocchio as pin

    checker = panda_space.checker
    assert checker.n_pairs == 92 and len(checker.distance_geom.collisionPairs) == 50
    names = [o.name for o in checker.geom.geometryObjects]
    hull_of = {}
    for k, obj in enumerate(checker.distance_geom.geometryObjects):
        base, _, extra = obj.name.partition("+")
        start = names.index(base)
        for i in range(start, start + 1 + (int(extra) if extra else 0)):
            hull_of[i] = k
    hull_pairs = {(p.first, p.second): k for k, p in enumerate(checker.distance_geom.collisionPairs)}
    rng = np.random.default_rng(2)
    data, gdata = checker.model.createData(), checker.geom.createData()
    for _ in range(20):
        q = panda_space.sample(rng)
        c = checker.clearances(q)
        pin.computeDistances(checker.model, data, checker.geom, gdata, q)
        for pair, res in zip(checker.geom.collisionPairs, gdata.distanceResults):
            k = hull_pairs[tuple(sorted((hull_of[pair.first], hull_of[pair.second])))]
            assert c[k] <= max(res.min_distance, 0.0) + 1e-6


# -- review findings (issue 26): motion bounds over the space's own box ---------------------------------------

def _cylindrical_with_a_tip_box(upper_limit_3):
    """The book's cylindrical arm (joint 3 prismatic, URDF limit [0.1, 1] m) with joint 3's model limit set to
    ``upper_limit_3`` and a 1 cm box at its tip for q = (0, 0.5, 2.9)."""
    from types import SimpleNamespace

    import pinocchio as pin

    from planners.collision import Box, CollisionChecker
    from rigid_body.robots import load
    r = load("cylindrical")
    model = r.model.copy()
    model.upperPositionLimit[2] = upper_limit_3
    data, gdata = model.createData(), r.collision_model.createData()
    pin.updateGeometryPlacements(model, data, r.collision_model, gdata, np.array([0.0, 0.5, 2.9]))
    tip = gdata.oMg[r.collision_model.ngeoms - 1].translation.copy()
    robot = SimpleNamespace(model=model, collision_model=r.collision_model, name="cylindrical")
    return CollisionChecker(robot, [Box(tip, [0.3, 0.01, 0.3], "thin")])


def test_a_space_beyond_the_joint_limits_is_refused():
    """Review HIGH: the bound used the URDF's prismatic range [0.1, 1] m while the space reached 3 m; the edge
    below was certified free (0 queries) though 225 of 2001 samples collide. Such a box is now refused."""
    from planners.collision import UrdfCSpace
    checker = _cylindrical_with_a_tip_box(1.0)
    with pytest.raises(ValueError, match=r"`upper`\[2\] = 3 lies beyond the robot's joint limit 1 .*joint_3"):
        UrdfCSpace(checker, lower=[-3.0, 0.0, 0.1], upper=[3.0, 1.0, 3.0])
    with pytest.raises(ValueError, match=r"`lower`\[1\]"):
        UrdfCSpace(checker, lower=[-3.0, -0.5, 0.1], upper=[3.0, 1.0, 1.0])


@pytest.mark.parametrize("upper_limit_3", [3.0, np.inf])
def test_motion_bounds_hold_over_the_spaces_box(upper_limit_3):
    """The prismatic ranges of the bound come from the space's box, not the model's limits (an unbounded URDF
    joint used to make the certificate refuse everything; a narrower model range made it unsound). Certified
    edges are re-checked densely with the collision shapes (coal's narrow phase, a second geometry)."""
    from planners.collision import UrdfCSpace
    checker = _cylindrical_with_a_tip_box(upper_limit_3)
    space = UrdfCSpace(checker, lower=[-3.0, 0.0, 0.1], upper=[3.0, 1.0, 3.0])
    assert np.all(np.isfinite(space.pair_rates)) and space.pair_rates.max() >= 3.0   # the 3 m reach counts
    a, b = np.array([-0.5, 0.5, 2.9]), np.array([0.5, 0.5, 2.9])
    cert = space.certify_edge(a, b)
    Q = space.interpolate(a, b, np.linspace(0.0, 1.0, 2001))
    assert sum(checker.in_collision(q) for q in Q) == 225 and not cert.free
    rng = np.random.default_rng(4)
    accepted = 0
    for _ in range(25):
        a = space.sample(rng)
        b = space.interpolate(a, space.sample(rng), 0.2)
        if space.is_valid(a) and space.is_valid(b) and space.certify_edge(a, b).free:
            accepted += 1
            assert not any(checker.in_collision(q) for q in space.interpolate(a, b, np.linspace(0, 1, 401)))
    assert accepted >= 10


def test_a_shape_on_a_mimic_joint_has_no_motion_bound():
    """A mimic joint (the book's rotors) has no coordinate of its own: a shape it carries used to get no bound
    for its spin (an edge moving only the mimicked joint was certified at once); its pairs are now unbounded
    and the certificate says so."""
    from types import SimpleNamespace

    import coal
    import pinocchio as pin

    from planners.collision import Box, CollisionChecker, UrdfCSpace
    from rigid_body.robots import load
    r = load("planar_2r")                                          # joint 3 (a rotor) mimics joint 2
    geom = r.collision_model.clone()
    geom.addGeometryObject(pin.GeometryObject("rotor_arm", 3, 0, pin.SE3(np.eye(3), np.array([0.3, 0, 0])),
                                              coal.Box(0.6, 0.02, 0.02)))
    robot = SimpleNamespace(model=r.model, collision_model=geom, name="planar_2r")
    checker = CollisionChecker(robot, [Box([2.0, 2.0, 0.0], [0.1, 0.1, 0.1], "far")], self_collision=False)
    assert np.isinf(checker.pair_rates).any()
    space = UrdfCSpace(checker)
    with pytest.raises(ValueError, match="no motion bound"):
        space.certify_edge(np.zeros(2), np.array([0.0, 0.5]))


def test_nan_clearances_are_never_certified():
    """Review LOW: every comparison with NaN is False, so a NaN clearance used to pass `c <= 0` and `ca + cb <= M`
    as certified. A NaN at an end, at a bisection point, or a NaN rate now refuses the edge."""
    from planners.configuration_space import certify_by_bisection
    ok = certify_by_bisection(lambda s, idx: np.full(len(idx), 0.5), [1.0, 1.0], [0.5, 0.5], [0.5, 0.5])
    assert ok.free                                                 # the reference: clearance 0.5 everywhere
    for c0 in ([np.nan, 0.5], [0.5, np.nan]):
        cert = certify_by_bisection(lambda s, idx: np.full(len(idx), 0.5), [1.0, 1.0], c0, [0.5, 0.5])
        assert not cert.free and cert.queries == 0 and "NaN" in cert.message
    mid = certify_by_bisection(lambda s, idx: np.full(len(idx), np.nan), [3.0, 3.0], [0.5, 0.5], [0.5, 0.5])
    assert not mid.free and mid.queries == 1 and "NaN" in mid.message
    rate = certify_by_bisection(lambda s, idx: np.full(len(idx), 0.5), [np.nan, 1.0], [0.5, 0.5], [0.5, 0.5])
    assert not rate.free
    # a NaN in the pair of ends that needs no split (0.5 + NaN > 0.1 is False, NaN <= 0.1 too)
    small = certify_by_bisection(lambda s, idx: np.full(len(idx), 0.5), [0.1, 0.1], [0.5, 0.5], [np.nan, 0.5])
    assert not small.free


def test_certify_path_refuses_a_nan_vertex_clearance(thin_wall):
    """A path of one vertex has no edge to refuse it: a NaN clearance there used to certify it."""
    import dataclasses

    from planners.sampling import certify_path

    @dataclasses.dataclass(frozen=True)
    class NaNSpace(PlanarCSpace):
        def clearances(self, q, parts=None):
            return np.full(super().clearances(q, parts).shape, np.nan)

    space, q_start, _ = thin_wall
    assert certify_path(space, [q_start]).free
    nan_space = NaNSpace(space.robot, space.scene, space.lower, space.upper, space.resolution)
    cert = certify_path(nan_space, [q_start])
    assert not cert.free and "NaN" in cert.message
