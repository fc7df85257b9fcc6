"""Planar C-space geometry (planners.configuration_space): distances, intersections, C-obstacles, the torus."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planners.configuration_space import (Disc, PlanarArm, PlanarBody, PlanarCSpace, Polygon, Scene, box,
                                    certify_motion, certify_straight_path, connected_components, free_grid,
                                    euclidean_distance, minkowski_c_obstacle, point_shape_distance,
                                    ray_shape_distance, segment_intersects_shape, segment_shape_distance,
                                    shapes_distance, shapes_intersect, torus_distance, transform_shape)

angles = st.floats(-20.0, 20.0, allow_nan=False)


def _random_convex(rng, center, r=0.5, k=5):
    a = np.sort(rng.uniform(0, 2 * np.pi, k))
    return Polygon(np.asarray(center) + r * np.column_stack([np.cos(a), np.sin(a)]))


def test_polygon_is_stored_counter_clockwise_and_rejects_non_convex():
    P = Polygon([[0, 0], [0, 1], [1, 1], [1, 0]])
    assert np.allclose(P.vertices[0], [1, 0]) or P.contains([0.5, 0.5])
    with pytest.raises(ValueError, match="convex"):
        Polygon([[0, 0], [2, 0], [1, 0.2], [2, 2], [0, 2]])
    with pytest.raises(ValueError, match="vertices"):
        Polygon([[0, 0], [1, 1]])


def test_shape_distances_match_shapely(rng):
    shapely = pytest.importorskip("shapely")
    from shapely.geometry import Point
    from shapely.geometry import Polygon as SPolygon
    for _ in range(200):
        A = _random_convex(rng, rng.uniform(-2, 2, 2), rng.uniform(0.2, 1.0))
        B = _random_convex(rng, rng.uniform(-2, 2, 2), rng.uniform(0.2, 1.0))
        D = Disc(rng.uniform(-2, 2, 2), rng.uniform(0.1, 0.8))
        sa, sb, sd = SPolygon(A.vertices), SPolygon(B.vertices), Point(D.center).buffer(D.radius, 256)
        assert shapes_distance(A, B) == pytest.approx(sa.distance(sb), abs=1e-9)
        assert shapes_intersect(A, B) == sa.intersects(sb)
        assert shapes_distance(A, D) == pytest.approx(sa.distance(sd), abs=1e-3)
        p = rng.uniform(-3, 3, 2)
        assert point_shape_distance(A, p) == pytest.approx(sa.distance(Point(p)), abs=1e-12)
    assert shapely is not None


def test_segment_interior_test_allows_grazing_a_vertex():
    diamond = Polygon([[5, 5], [6, 4], [7, 5], [6, 6]])
    assert not segment_intersects_shape([5, 7.5], [5, 2.5], diamond)          # touches (5, 5) only
    assert segment_intersects_shape([4, 5], [8, 5], diamond)
    assert not segment_intersects_shape([5, 6], [6, 7], diamond)               # parallel, outside
    assert segment_shape_distance([5, 7.5], [5, 2.5], diamond) == 0.0
    assert segment_shape_distance([3, 0], [3, 10], diamond) == pytest.approx(2.0)


def test_ray_distances_are_exact():
    u = np.array([[1.0, 0.0], [0.0, 1.0], [np.sqrt(0.5), np.sqrt(0.5)]])
    r = ray_shape_distance([0, 0], u, box(2, -1, 3, 1))
    assert r[0] == pytest.approx(2.0) and np.isinf(r[1])
    assert ray_shape_distance([0, 0], u, Disc([3, 0], 1))[0] == pytest.approx(2.0)


def test_minkowski_c_obstacle_agrees_with_placement_test(rng):
    pairs = [(Polygon([[0, 0], [1, 0], [0, 1]]), box(0, 0, 2, 2))]
    pairs += [(_random_convex(rng, rng.uniform(-0.3, 0.3, 2), 0.6), _random_convex(rng, [1, 1], 1.0, 6))
              for _ in range(5)]
    for B, O in pairs:
        CO = minkowski_c_obstacle(O, B)
        for q in rng.uniform(-2, 3, (300, 2)):
            if point_shape_distance(CO, q) > 1e-6 or CO.contains(q, -1e-6):
                assert CO.contains(q) == shapes_intersect(transform_shape(B, q[0], q[1], 0.0), O)


@settings(max_examples=200, deadline=None)
@given(st.tuples(angles, angles), st.tuples(angles, angles), st.tuples(angles, angles))
def test_torus_distance_is_a_metric_respecting_the_topology(a, b, c):
    a, b, c = map(np.array, (a, b, c))
    d = torus_distance(a, b)
    assert d == pytest.approx(torus_distance(b, a), abs=1e-9)
    assert torus_distance(a, c) <= d + torus_distance(b, c) + 1e-9
    assert torus_distance(a + 2 * np.pi, b) == pytest.approx(d, abs=1e-9)
    assert d <= np.sqrt(2) * np.pi + 1e-12
    if np.all(np.abs(a - b) <= np.pi):
        assert d == pytest.approx(euclidean_distance(a, b), abs=1e-9)


def test_erratum_12_2_counterexample():
    qa, qb = np.zeros(2), np.array([1.2 * np.pi, 0.0])
    assert euclidean_distance(qa, qb) < np.sqrt(2) * np.pi
    assert torus_distance(qa, qb) == pytest.approx(0.8 * np.pi)


def test_mixed_distance_wraps_only_angles():
    assert torus_distance([0, 0, 3], [6, 0, -3], [False, False, True]) == pytest.approx(
        np.hypot(6, 2 * np.pi - 6))


def test_batched_clearance_equals_shape_by_shape(rng):
    scene = Scene([Disc([-0.8, 1.2], 0.2), box(0, 0.5, 0.5, 1), Polygon([[1, -1], [1.6, -0.8], [1.2, -0.3]])])
    arm = PlanarArm((1.0, 0.8), 0.1)
    Q = rng.uniform(-np.pi, np.pi, (200, 2))
    batched = scene.clearance_many(arm, Q)
    single = np.array([scene.clearance(arm.bodies(q)) for q in Q])
    assert np.allclose(batched, single, atol=1e-12)
    body = PlanarBody((Polygon([[-0.1, -0.2], [-0.1, 0.2], [0.5, 0.0]]), Disc([0, 0], 0.03)))
    P = np.column_stack([rng.uniform(-2, 2, (200, 2)), rng.uniform(-np.pi, np.pi, 200)])
    assert np.allclose(scene.clearance_many(body, P), [scene.clearance(body.bodies(p)) for p in P], atol=1e-12)


def test_motion_bound_bounds_the_real_displacement(rng):
    arm = PlanarArm((1.0, 0.7, 0.5), 0.1, fixed_base=False)
    for _ in range(100):
        q = rng.uniform(-3, 3, 5)
        dq = rng.normal(scale=0.3, size=5)
        for s in np.linspace(0, 1, 11):
            moved = [np.abs(a.vertices - b.vertices).max() if isinstance(a, Polygon) else 0
                     for a, b in zip(arm.bodies(q), arm.bodies(q + s * dq))]
            P0, P1 = arm.joint_positions(q), arm.joint_positions(q + s * dq)
            assert np.linalg.norm(P1 - P0, axis=1).max() <= s * arm.motion_bound(dq) + 1e-12
            assert max(moved) <= np.sqrt(2) * s * arm.motion_bound(dq) + 1e-12


def test_certificate_accepts_free_and_rejects_colliding_paths():
    scene = Scene([Disc([1.5, 0.0], 0.2)])
    space = PlanarCSpace(PlanarArm((1.0, 1.0), 0.1), scene, [-np.pi] * 2, [np.pi] * 2)
    ok, c_min, _ = certify_straight_path(space, [[1.0, 0.0], [2.0, 0.0]])
    assert ok and c_min > 0
    ok, _, _ = certify_straight_path(space, [[1.0, 0.0], [-1.0, 0.0]])      # sweeps through the disc
    assert not ok
    assert certify_motion([1.0, 1.0], [1.5])[0] and not certify_motion([1.0, 1.0], [2.5])[0]


def test_free_grid_matches_single_checks():
    space = PlanarCSpace(PlanarArm((1.0, 1.0), 0.1), Scene([Disc([1.2, 0.4], 0.3)]), [-np.pi] * 2, [np.pi] * 2)
    axis = np.linspace(-np.pi, np.pi, 24, endpoint=False)
    free = free_grid(space, [axis, axis])
    assert not free.all() and free.any()
    assert all(free[i, j] == (space.scene.clearance(space.robot.bodies([a, b])) > 0)
               for i, a in enumerate(axis) for j, b in enumerate(axis))
    with pytest.raises(ValueError, match="axes"):
        free_grid(space, [axis])


def test_components_glue_the_torus_seams():
    free = np.ones((10, 10), dtype=bool)
    free[:, 4] = False                                           # one wall: the torus stays connected
    assert connected_components(free)[1] == 1
    assert connected_components(free, periodic=[False, False])[1] == 2
    free[:, 8] = False                                           # two walls: two components
    assert connected_components(free)[1] == 2


def test_bad_input_names_the_argument():
    with pytest.raises(ValueError, match="center"):
        Disc([0, np.nan], 1)
    with pytest.raises(ValueError, match="radius"):
        Disc([0, 0], -1)
    with pytest.raises(ValueError, match="q"):
        PlanarArm().bodies([0, 1, 2])
    with pytest.raises(ValueError, match="obstacles"):
        Scene([[0, 0]])
