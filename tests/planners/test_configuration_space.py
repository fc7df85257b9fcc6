"""Obstacle distances: polylines vs brute force, the arm distance gradient vs finite differences, the box."""

import numpy as np
import pytest

from planners.configuration_space import (distance_to_box, planar_arm_obstacle_distance,
                                          planar_arm_obstacle_distance_gradient, polyline_distance,
                                          segment_chain_distance)
from planners.inverse_kinematics import numerical_gradient
from rigid_body.robots import load

def test_segment_distance_brute_force_and_clamping(rng):
    s = np.linspace(0, 1, 20001)
    for _ in range(30):
        pts, o, R = rng.uniform(-1, 1, (4, 2)), rng.uniform(-1, 1, 2), rng.uniform(0, 0.3)
        res = segment_chain_distance(pts, o, R)
        brute = min(np.min(np.linalg.norm(pts[i] + s[:, None] * (pts[i + 1] - pts[i]) - o, axis=1))
                    for i in range(3)) - R
        assert res.distance == pytest.approx(brute, abs=1e-8)
    # projection before the segment start: clamped to s = 0
    res = segment_chain_distance([[0, 0], [1, 0]], [-1.0, 1.0], 0.5)
    assert res.s == 0.0 and res.distance == pytest.approx(np.sqrt(2) - 0.5)


def test_distance_gradient_analytic_vs_forward():
    robot = load("planar_3r", a=(0.5, 0.3, 0.3))
    q = np.array([0.51469, -1.55168, 1.82239])
    g = planar_arm_obstacle_distance_gradient(robot, q, [0.3, 0.0], 0.1)
    g_fd = numerical_gradient(lambda x: planar_arm_obstacle_distance(robot, x, [0.3, 0.0], 0.1).distance, q,
                              scheme="forward")  # as the manual's 3.21
    np.testing.assert_allclose(g, g_fd, atol=1e-5)
    assert planar_arm_obstacle_distance(robot, q, [0.3, 0.0], 0.1).distance == pytest.approx(0.0477, abs=1e-4)


def test_polyline_distance_brute_force(rng):
    s = np.linspace(0, 1, 20001)
    poly, pts = rng.uniform(-1, 1, (5, 2)), rng.uniform(-1.5, 1.5, (40, 2))
    dense = np.concatenate([poly[i] + s[:, None] * (poly[i + 1] - poly[i]) for i in range(4)])
    brute = np.min(np.linalg.norm(pts[:, None] - dense[None], axis=2), axis=1)
    np.testing.assert_allclose(polyline_distance(pts, poly), brute, atol=1e-8)
    # a repeated vertex (zero-length segment) is harmless
    np.testing.assert_allclose(polyline_distance(pts, np.repeat(poly, 2, axis=0)), brute, atol=1e-8)


def test_distance_to_box_against_sampled_box(rng):
    box = (0.2, 0.5, 0.1)
    xs, ys = np.meshgrid(np.linspace(0.2, 0.5, 601), np.linspace(-0.5, 0.1, 1201))
    dense = np.column_stack([xs.ravel(), ys.ravel()])
    pts = rng.uniform([-0.5, -0.2], [1.0, 0.8], (30, 2))
    brute = np.min(np.linalg.norm(pts[:, None] - dense[None], axis=2), axis=1)
    outside = (pts[:, 1] > 0.1) | (pts[:, 0] < 0.2) | (pts[:, 0] > 0.5)
    np.testing.assert_allclose(distance_to_box(pts, box)[outside], brute[outside], atol=1e-3)
    assert np.all(distance_to_box(pts[~outside], box) == 0.0)


def test_bad_inputs_raise():
    with pytest.raises(ValueError, match="points"):
        segment_chain_distance([[0, 0]], [0, 0], 0.1)
    with pytest.raises(ValueError, match="radius"):
        segment_chain_distance([[0, 0], [1, 0]], [0, 0], -1.0)
    with pytest.raises(ValueError, match="polyline"):
        polyline_distance([[0, 0]], [[0, 0]])
    with pytest.raises(ValueError, match="obstacle"):
        distance_to_box([[0, 0]], (0, 1))
