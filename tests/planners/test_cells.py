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


def test_bad_input_names_the_argument():
    with pytest.raises(ValueError, match="bounds"):
        trapezoidal_decomposition((0, -1, 0, 1), [DIAMOND])
    with pytest.raises(ValueError, match="obstacles"):
        quadtree_decomposition((0, 10, 0, 10), [Disc([5, 5], 1)], 0.5)
    with pytest.raises(ValueError, match="free cell"):
        trapezoidal_decomposition((0, 10, 0, 10), [DIAMOND]).locate([6, 5])
