"""The planners' outputs against what they are by definition, computed here: trees are trees, RRT-Connect's
path is made of tree steps, shortcutting joins the ends of a path seen straight, a primitive's arc stays in
its bounding box, polygon centroids and disc distances by hand, the robot's first moving link paired with the
obstacles, the certificate's motion bound never below the true motion of the hulls, the wavefront's costs on
an empty grid, and a trapezoidal decomposition that tiles the free space exactly."""

import numpy as np
import pinocchio as pin
import pytest

from planners.cells import trapezoidal_decomposition
from planners.collision import Box, CollisionChecker, UrdfCSpace
from planners.configuration_space import (Disc, PlanarArm, PlanarBody, PlanarCSpace, Polygon, Scene, box,
                                          certify_straight_path, point_shape_distance)
from planners.potentials import wavefront
from planners.sampling import MotionPrimitive, certify_arc, prm, rrt, rrt_connect, shortcut, unicycle_arc, unicycle_rrt
from rigid_body.robots import load


@pytest.fixture(scope="module")
def arm_space():
    obstacles = [Disc([-0.8, 1.2], 0.2), Disc([1.3, 1.5], 0.2), Polygon([[0, 0.5], [0.5, 0.5], [0.5, 1], [0, 1]])]
    space = PlanarCSpace(PlanarArm((1.0, 1.0), 0.1), Scene(obstacles, (-2.2, 2.2, -2.2, 2.2)),
                         [-np.pi, -np.pi], [np.pi, np.pi], resolution=0.01)
    return space, np.array([-np.pi / 4, 3 * np.pi / 4]), np.array([5 * np.pi / 8, -np.pi / 2])


def _is_forest(n_nodes: int, edges: np.ndarray, trees: int) -> bool:
    """Every vertex but the ``trees`` roots has exactly one parent edge, and there are no others."""
    children = [int(j) for _, j in np.asarray(edges).reshape(-1, 2)]
    return len(children) == n_nodes - trees and len(set(children)) == len(children)


def test_trees_are_trees_and_rrt_connect_paths_are_tree_steps(arm_space):
    space, qs, qg = arm_space
    one = rrt(space, qs, qg, 1, step=0.3, max_iterations=300)
    assert _is_forest(len(one.nodes), one.edges, 1)
    two = rrt_connect(space, qs, qg, 2, step=0.3)
    assert two.success and _is_forest(len(two.nodes), two.edges, 2)
    steps = space.distance(two.path[:-1], two.path[1:])
    assert steps.max() <= 0.3 + 1e-9                      # each path edge one step of a tree (the join included)
    assert certify_straight_path(space, two.path, 0.05)[0]
    road = prm(space, qs, qg, 3, n_vertices=60)
    assert road.controls.shape == (0, 2)                  # controls belong to the unicycle's tree only


def test_shortcut_joins_the_ends_of_a_three_vertex_path_seen_straight(arm_space):
    space, qs, _ = arm_space
    end = qs + np.array([0.2, -0.1])
    detour = np.array([qs, qs + np.array([0.3, 0.4]), end])
    out = shortcut(space, detour, 0, attempts=20)
    np.testing.assert_allclose(out, [qs, end])


def test_unicycle_trees_are_trees_and_goal_bias_is_a_probability():
    body = PlanarBody((Polygon([[-0.1, -0.2], [-0.1, 0.2], [0.5, 0.0]]),))
    space = PlanarCSpace(body, Scene([Disc([0.0, 0.5], 0.3)], (-3, 3, -3, 3)), [-3, -3, -np.pi], [3, 3, np.pi])
    prims = [MotionPrimitive(1.0, 0.0), MotionPrimitive(1.0, 1.3), MotionPrimitive(1.0, -1.3)]
    res = unicycle_rrt(space, [-2.0, 0.0, 0.0], [2.0, -1.0, 0.0], 4, prims, 0.5, max_vertices=80)
    assert _is_forest(len(res.nodes), res.edges, 1)
    with pytest.raises(ValueError, match="goal_bias"):
        unicycle_rrt(space, [-2.0, 0.0, 0.0], [2.0, -1.0, 0.0], 4, prims, 0.5, goal_bias=1.5)


def test_an_arc_bulging_out_of_the_bounds_between_its_ends_is_refused():
    """The reference point's arc of radius 0.55 from (4.5, 0) heading +x to heading π: its ends are inside
    x ≤ 5, its extreme x = 5.05 (heading π/2) is not; one of radius 0.45 stays inside. Dense samples agree."""
    body = PlanarBody((Disc([0.0, 0.0], 0.01),))
    space = PlanarCSpace(body, Scene([], (-5, 5, -5, 5)), [-5, -5, -np.pi], [5, 5, np.pi])
    q = np.array([4.5, 0.0, 0.0])
    for radius, inside in ((0.55, False), (0.45, True)):
        prim = MotionPrimitive(radius, 1.0)
        x = unicycle_arc(q, prim.v, prim.omega, np.linspace(0.0, np.pi, 2001))[:, 0]
        assert bool(x.max() <= 5.0) == inside
        assert certify_arc(space, q, prim, np.pi).free == inside


def test_polygon_centroid_and_disc_distance_by_hand():
    tri = Polygon([[0.0, 0.0], [3.0, 0.0], [0.0, 3.0]])
    np.testing.assert_allclose(tri.centroid, [1.0, 1.0], atol=1e-12)
    trapezoid = Polygon([[0, 0], [4, 0], [3, 2], [1, 2]])     # parallel sides a = 4, b = 2, height h = 2
    np.testing.assert_allclose(trapezoid.centroid, [2.0, 2 * (4 + 2 * 2) / (3 * (4 + 2))], atol=1e-12)
    disc = Disc([1.0, -2.0], 0.5)
    p = np.array([[4.0, 2.0], [1.2, -2.1]])
    np.testing.assert_allclose(point_shape_distance(disc, p), [5.0 - 0.5, 0.0], atol=1e-12)


@pytest.fixture(scope="module")
def panda_space():
    boxes = [Box([0.55, 0.0, 0.25], [0.08, 0.6, 0.5], "shelf"), Box([0.0, 0.5, 0.6], [0.3, 0.05, 0.3], "board")]
    return UrdfCSpace(CollisionChecker(load("panda"), boxes))


def test_the_first_moving_link_is_checked_against_the_obstacles():
    """A 2 cm cube inside panda_link1's hull (above the fixed link0): a collision for the broad phase, for the
    pairwise check and for the certificate's clearances (which only see the pairs made with the boxes)."""
    robot = load("panda")
    geom, data = robot.collision_model, robot.model.createData()
    q = pin.neutral(robot.model)
    gdata = geom.createData()
    pin.updateGeometryPlacements(robot.model, data, geom, gdata, q)
    k = next(i for i, o in enumerate(geom.geometryObjects) if o.parentJoint == 1)
    centre = gdata.oMg[k].translation + np.array([0.0, 0.0, 0.05])
    checker = CollisionChecker(robot, [Box(centre, [0.02, 0.02, 0.02], "cube")])
    assert checker.in_collision(q) and checker.in_collision_pairwise(q)
    assert checker.box_clearance(q) <= 0 and checker.clearances(q).min() <= 0


@pytest.fixture(scope="module")
def ur5_space():
    """The UR5: joints about their y axes as well as z (the Panda's are all about z)."""
    return UrdfCSpace(CollisionChecker(load("ur5"), [Box([0.5, 0.0, 0.3], [0.1, 0.6, 0.6], "wall")]))


@pytest.mark.parametrize("robot_space", ["panda_space", "ur5_space"])
def test_the_motion_bound_is_never_below_the_true_motion_of_the_hulls(robot_space, request):
    """Along straight edges (random, 0.6 rad long), every robot hull's vertices move at most the certificate's
    bound for each robot–box pair (the box is fixed): the bound of Schwarzer et al. is sound."""
    space = request.getfixturevalue(robot_space)
    checker = space.checker
    model, geom = checker.model, checker.distance_geom
    data, gdata = model.createData(), geom.createData()
    rng = np.random.default_rng(8)
    pairs = [(k, p.first if geom.geometryObjects[p.first].parentJoint else p.second)
             for k, p in enumerate(geom.collisionPairs)
             if (geom.geometryObjects[p.first].parentJoint == 0) != (geom.geometryObjects[p.second].parentJoint == 0)]
    assert pairs
    for _ in range(10):
        a = space.sample(rng)
        b = np.clip(a + 0.6 * rng.normal(size=a.size) / np.sqrt(a.size), space.lower, space.upper)
        rates = space.edge_rates(a, b)
        moved = {}
        for s in np.linspace(0.0, 1.0, 41):
            pin.updateGeometryPlacements(model, data, geom, gdata, a + s * (b - a))
            for _, g in pairs:
                V = np.asarray(geom.geometryObjects[g].geometry.points())
                W = V @ gdata.oMg[g].rotation.T + gdata.oMg[g].translation
                moved.setdefault(g, (W, 0.0))
                moved[g] = (moved[g][0], max(moved[g][1], float(np.linalg.norm(W - moved[g][0], axis=1).max())))
        for k, g in pairs:
            assert moved[g][1] <= rates[k] + 1e-9, (geom.geometryObjects[g].name, moved[g][1], rates[k])


def test_wavefront_costs_on_an_empty_grid():
    """Cost-to-go from the goal: Manhattan distance with side moves (1-adjacency); with diagonals
    (2-adjacency) √2 min(|Δi|, |Δj|) + ||Δi| − |Δj||."""
    free = np.zeros((5, 7), dtype=bool)
    i, j = np.indices(free.shape)
    di, dj = np.abs(i - 1), np.abs(j - 5)
    np.testing.assert_allclose(wavefront(free, (1, 5), 1), di + dj, atol=1e-12)
    np.testing.assert_allclose(wavefront(free, (1, 5), 2), np.sqrt(2) * np.minimum(di, dj) + np.abs(di - dj),
                               atol=1e-12)


def test_trapezoidal_cells_tile_the_free_space_of_overlapping_obstacles():
    """A diamond and a box that overlap (their edges cross at x = 5, no vertex's abscissa) and a triangle: the
    cells' areas add up to the free area (box − union, by inclusion–exclusion: the overlap is 2 m²), no cell
    overlaps an obstacle, every free sample lies in a cell."""
    A, B = Polygon([[2, 4], [4, 2], [6, 4], [4, 6]]), box(4.5, 3, 8, 5)
    T = Polygon([[1, 7], [3, 8.5], [1.5, 9]])
    dec = trapezoidal_decomposition((0, 10, 0, 10), [A, B, T])

    def area(P):
        x, y = P.vertices.T
        return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))

    free = 100.0 - (area(A) + area(B) - 2.0 + area(T))     # A ∩ B: 1 over x ∈ [4.5, 5] and 1 over [5, 6]
    assert sum(area(c) for c in dec.cells) == pytest.approx(free, abs=1e-9)
    for c in dec.cells:
        assert not any(o.contains(c.centroid) for o in (A, B, T))
    pts = np.random.default_rng(1).uniform(0, 10, (400, 2))
    pts = pts[~(A.contains(pts) | B.contains(pts) | T.contains(pts))]
    assert all(any(c.contains(p, 1e-9) for c in dec.cells) for p in pts)


def test_cone_force_vanishes_at_the_goal_and_disc_closest_point_by_hand():
    from planners.potentials import attractive_cone, closest_point

    U, f = attractive_cone(np.array([[0.0, 0.0], [3.0, 4.0]]), 2.0)
    np.testing.assert_allclose(U, [0.0, 10.0])
    np.testing.assert_allclose(f, [[0.0, 0.0], [1.2, 1.6]], atol=1e-15)     # k_a e/‖e‖, zero at the goal
    np.testing.assert_allclose(closest_point(Disc([1.0, 1.0], 0.5), np.array([[4.0, 5.0]])), [[1.3, 1.4]], atol=1e-12)


def test_box_corners_are_its_centre_minus_and_plus_half_its_size():
    lower, upper = Box([0.5, -0.2, 1.0], [0.2, 0.4, 1.0]).corners
    np.testing.assert_allclose(lower, [0.4, -0.4, 0.5], atol=1e-15)
    np.testing.assert_allclose(upper, [0.6, 0.0, 1.5], atol=1e-15)


@pytest.mark.parametrize("edge_check", ["certified", "sampled"])
def test_validity_checks_count_every_configuration_the_planner_checks(arm_space, edge_check):
    """PlanResult.validity_checks against a space that counts what it is asked (q_s and q_g, checked before
    planning, are not the planner's); a sampled-mode run computes no clearance."""

    class Counting(PlanarCSpace):
        asked = 0

        def valid_many(self, Q):
            self.asked += len(Q)
            return super().valid_many(Q)

    space, qs, qg = arm_space
    counting = Counting(space.robot, space.scene, space.lower, space.upper, resolution=space.resolution)
    for planner, options in ((prm, dict(n_vertices=60)), (rrt, dict(max_iterations=300))):
        counting.asked = 0
        res = planner(counting, qs, qg, 3, edge_check=edge_check, **options)
        assert res.validity_checks == counting.asked - 2
        assert res.validity_checks > 0 or (planner is rrt and edge_check == "certified")  # certified RRT: clearances only
        assert (res.distance_queries > 0) == (edge_check == "certified")


def test_the_certificate_bounds_only_revolute_and_prismatic_joints():
    """A helical joint (one coordinate, neither revolute nor prismatic) and multi-coordinate joints get no
    revolute/prismatic motion bound."""
    from planners.collision import _joint_kind

    model = pin.Model()
    joints = {"revolute": [pin.JointModelRZ(), pin.JointModelRevoluteUnaligned(0.0, 0.6, 0.8)],
              "prismatic": [pin.JointModelPX(), pin.JointModelPrismaticUnaligned(1.0, 0.0, 0.0)],
              None: [pin.JointModelHZ(0.1), pin.JointModelPlanar(), pin.JointModelSpherical(), pin.JointModelRUBZ()]}
    for kind, models in joints.items():
        for joint in models:
            j = model.addJoint(0, joint, pin.SE3.Identity(), f"{joint.shortname()}_{model.njoints}")
            assert _joint_kind(model, j) == kind, joint.shortname()
