"""Roadmaps and cell decompositions (planners.cells)."""

import numpy as np
import pytest

from planners.cells import (channel_path, gvd_nodes, polyline_clearance, quadtree_decomposition, sampled_gvd,
                            trapezoidal_decomposition, visibility_graph)
from planners.configuration_space import Disc, Polygon, box

DIAMOND = Polygon([[5, 5], [6, 4], [7, 5], [6, 6]])


def test_trapezoids_tile_the_free_space():
    obstacles = [DIAMOND, Polygon([[1, 1], [3, 1.5], [2, 3]])]
    dec = trapezoidal_decomposition((0, 10, 0, 10), obstacles)
    area = sum(0.5 * abs(np.cross(c.vertices - c.vertices[0], np.roll(c.vertices, -1, 0) - c.vertices[0]).sum())
               for c in dec.cells)
    obstacle_area = 2.0 + 0.5 * abs(np.cross([2, 0.5], [1, 2]))
    assert area == pytest.approx(100 - obstacle_area, abs=1e-9)
    rng = np.random.default_rng(0)
    for q in rng.uniform(0, 10, (300, 2)):
        inside = sum(c.contains(q, -1e-9) for c in dec.cells)
        assert inside <= 1
        if not any(o.contains(q, 1e-9) for o in obstacles) and inside == 0:
            assert any(c.contains(q, 1e-9) for c in dec.cells)


def test_channel_path_fix_of_problem_12_6():
    dec = trapezoidal_decomposition((0, 10, 0, 10), [DIAMOND])
    naive, chan = channel_path(dec, [5.5, 7], [5.5, 3], centroids=False)
    fixed, _ = channel_path(dec, [5.5, 7], [5.5, 3], centroids=True)
    assert len(chan) == 3 and polyline_clearance(naive, [DIAMOND]) == 0.0
    assert polyline_clearance(fixed, [DIAMOND]) == pytest.approx(np.sqrt(1.25))


def test_quadtree_path_is_free_and_boxes_avoid_obstacles():
    dec = quadtree_decomposition((0, 10, 0, 10), [DIAMOND], min_size=0.3)
    path, _ = channel_path(dec, [5.5, 7], [5.5, 3])
    assert polyline_clearance(path, [DIAMOND]) > 0
    assert all(not c.contains(DIAMOND.centroid) for c in dec.cells)


def test_visibility_graph_shortest_path():
    vis = visibility_graph([5.5, 7], [5.5, 3], [DIAMOND])
    assert vis.length == pytest.approx(2 * np.hypot(0.5, 2))
    with pytest.raises(ValueError, match="Polygon"):
        visibility_graph([0, 0], [1, 1], [Disc([5, 5], 1)])


@pytest.mark.parametrize("a, b", [(4.0, 1.5), (3.0, 2.0)])
def test_gvd_of_a_rectangle_is_its_medial_axis(a, b):
    nodes = gvd_nodes(box(0, 0, a, b))
    inner = nodes[nodes[:, 2] > 1e-9]
    assert np.allclose(inner, [[b / 2, b / 2, b / 2], [a - b / 2, b / 2, b / 2]], atol=1e-9)
    P = sampled_gvd(box(0, 0, a, b), spacing=0.05).reshape(-1, 2)
    d_side = np.minimum.reduce([P[:, 0], a - P[:, 0], P[:, 1], b - P[:, 1]])
    two_nearest = np.sort(np.column_stack([P[:, 0], a - P[:, 0], P[:, 1], b - P[:, 1]]), axis=1)[:, :2]
    assert np.all(d_side > 0) and np.allclose(two_nearest[:, 0], two_nearest[:, 1], atol=1e-9)


def test_gvd_node_of_a_square_is_its_centre():
    nodes = gvd_nodes(box(0, 0, 2, 2))
    assert np.allclose(nodes[nodes[:, 2] > 1e-9], [[1, 1, 1]])


def test_gvd_nodes_around_a_square_hole_by_hand():
    """Room [0, 4]², hole [1.5, 2.5]²: on each diagonal the node equidistant from two walls and the hole's corner,
    s = √2 (1.5 − s) ⇒ s = 1.5√2/(1 + √2); beside each hole corner the node midway between a wall and the hole's
    side, at the corner's height (clearance 0.75). The first kind comes from the vertex–side–side equations."""
    nodes = gvd_nodes(box(0, 0, 4, 4), [box(1.5, 1.5, 2.5, 2.5)])
    s = 1.5 * np.sqrt(2) / (1 + np.sqrt(2))
    expected = [[x, y, s] for x in (s, 4 - s) for y in (s, 4 - s)]
    expected += [[x, y, 0.75] for x, y in ((0.75, 1.5), (0.75, 2.5), (3.25, 1.5), (3.25, 2.5),
                                           (1.5, 0.75), (2.5, 0.75), (1.5, 3.25), (2.5, 3.25))]
    inner = nodes[nodes[:, 2] > 1e-9]
    key = lambda rows: np.array(sorted(map(tuple, np.round(rows, 9))))  # noqa: E731
    np.testing.assert_allclose(key(inner), key(np.array(expected)), atol=1e-9)

def test_bad_input_names_the_argument():
    with pytest.raises(ValueError, match="bounds"):
        trapezoidal_decomposition((0, -1, 0, 1), [DIAMOND])
    with pytest.raises(ValueError, match="obstacles"):
        quadtree_decomposition((0, 10, 0, 10), [Disc([5, 5], 1)], 0.5)
    with pytest.raises(ValueError, match="free cell"):
        trapezoidal_decomposition((0, 10, 0, 10), [DIAMOND]).locate([6, 5])


def _check_cells_against_scene(dec, bounds, obstacles, rng, per_cell=40, n_free=3000):
    """Random points of every free cell lie outside every obstacle (strictly inside one would be an error)
    and inside the bounds; random free points of the rectangle lie in some cell (the cells cover C_free)."""
    x0, x1, y0, y1 = bounds
    for k, cell in enumerate(dec.cells):
        V = cell.vertices
        w = rng.dirichlet(np.ones(len(V)), per_cell)
        P = w @ V
        for o in obstacles:
            assert not np.any(o.contains(P, -1e-9)), f"cell {k} centred at {V.mean(axis=0)} is inside an obstacle"
        assert np.all((P[:, 0] >= x0 - 1e-9) & (P[:, 0] <= x1 + 1e-9) & (P[:, 1] >= y0 - 1e-9) & (P[:, 1] <= y1 + 1e-9))
    P = rng.uniform([x0, y0], [x1, y1], (n_free, 2))
    free = ~np.any([o.contains(P, 1e-9) for o in obstacles], axis=0)
    for p in P[free]:
        assert any(c.contains(p, 1e-9) for c in dec.cells), f"free point {p} in no cell"


@pytest.mark.parametrize("scene", ["overlapping boxes", "crossing the bounds", "random overlapping"])
def test_trapezoidal_cells_are_free_and_cover_any_scene(scene):
    """Issue 25: overlapping obstacles gave a "free" cell centred at [4, 4] inside the box [2, 5]²; a box reaching
    outside the bounds gave cells outside the rectangle."""
    rng = np.random.default_rng(4)
    bounds = (0.0, 10.0, 0.0, 10.0)
    if scene == "overlapping boxes":
        obstacles = [box(2, 2, 5, 5), box(3, 4, 7, 6)]
    elif scene == "crossing the bounds":
        obstacles = [box(-1, 3, 4, 5), box(6, 8, 12, 12), Polygon([[5, -2], [8, 1], [6, 3]])]
    else:
        obstacles = []
        for _ in range(6):
            a = np.sort(rng.uniform(0, 2 * np.pi, 5))
            obstacles.append(Polygon(rng.uniform(-1, 11, 2) + rng.uniform(1, 3) * np.column_stack([np.cos(a), np.sin(a)])))
    dec = trapezoidal_decomposition(bounds, obstacles)
    _check_cells_against_scene(dec, bounds, obstacles, rng)
    quad = quadtree_decomposition(bounds, obstacles, min_size=0.3)
    _check_cells_against_scene(quad, bounds, obstacles, rng, n_free=0)
