"""The per-sample fast paths of the planners agree with their array versions (a second implementation each).

One instant of a :class:`SegmentSequence` (the laws' scalar path) against the same instant in an array;
one shape pair of :func:`shapes_distance` (Python floats) against :func:`batch_distance` (numpy over many
placements); one obstacle of :func:`segment_chain_distance` against :func:`closest_points_on_polyline`.
"""

import numpy as np
import pytest

from planners.configuration_space import (Disc, Polygon, batch_distance, closest_points_on_polyline,
                                          segment_chain_distance, shapes_distance, transform_shape)
from planners.paths import SegmentSequence
from planners.timing import cubic_law, quintic_law


def test_segment_sequence_one_instant_equals_the_array_evaluation():
    pts = np.array([[0.0, 0.0, 0.0], [0.0, 0.3, 0.0], [0.4, 0.3, 0.1], [0.4, 0.0, 0.1]])
    L = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    laws = [quintic_law(0.0, L[0], 1.0), cubic_law(0.0, L[1], 2.1, t_i=0.6), quintic_law(0.0, L[2], 3.0, t_i=1.7)]
    path = SegmentSequence(pts, laws)
    t = np.concatenate([[-0.5, 0.0, 0.6, 1.0, 1.7, 2.1, 3.0, 3.5], np.linspace(0.0, 3.0, 61)])
    P, V, A = path(t)
    for k, tk in enumerate(t):
        for scalar in (float(tk), np.float64(tk)):
            p, v, a = path(scalar)
            assert p.shape == v.shape == a.shape == (3,)
            np.testing.assert_allclose(np.stack([p, v, a]), np.stack([P[k], V[k], A[k]]), rtol=0, atol=1e-14)


def _random_convex(rng, k):
    a = np.sort(rng.uniform(0, 2 * np.pi, k))
    return Polygon(rng.uniform(-0.5, 0.5, 2) + rng.uniform(0.2, 0.8) * np.column_stack([np.cos(a), np.sin(a)]))


@pytest.mark.parametrize("seed", range(3))
def test_shape_pair_distance_equals_the_batched_distance(seed):
    rng = np.random.default_rng(seed)
    part = _random_convex(rng, 4)
    obstacles = [_random_convex(rng, 3), _random_convex(rng, 6), Disc(rng.uniform(-1, 1, 2), 0.3)]
    poses = np.column_stack([rng.uniform(-2, 2, (200, 2)), rng.uniform(-np.pi, np.pi, 200)])
    placed = [transform_shape(part, *pose) for pose in poses]
    batch = ("polygon", np.array([p.vertices for p in placed]))
    discs = [transform_shape(Disc([0.3, 0.1], 0.2), *pose) for pose in poses]
    disc_batch = ("disc", np.array([d.center for d in discs]), 0.2)
    for o in obstacles:
        one = [shapes_distance(p, o) for p in placed]
        np.testing.assert_allclose(one, batch_distance(batch, o), rtol=0, atol=1e-12)
        np.testing.assert_allclose([shapes_distance(d, o) for d in discs], batch_distance(disc_batch, o),
                                   rtol=0, atol=1e-12)
        assert 0 < np.count_nonzero(one) < len(one)  # both overlapping and separated placements were met


def test_segment_chain_distance_equals_the_vectorised_polyline():
    rng = np.random.default_rng(4)
    for _ in range(200):
        P = rng.uniform(-1, 1, (int(rng.integers(2, 6)), 2))
        o = rng.uniform(-1.5, 1.5, 2)
        r = segment_chain_distance(P, o, 0.1)
        closest, s, d = (v[0] for v in closest_points_on_polyline(o[None], P))
        i = int(np.argmin(d))
        assert r.link == i
        np.testing.assert_allclose([r.distance, r.s, *r.point], [d[i] - 0.1, s[i], *closest[i]], rtol=0, atol=1e-15)


def test_closed_form_ik_keeps_the_rows_within_the_joint_limits_shifting_by_two_pi():
    from rigid_body.dh import DHLink
    from rigid_body.kinematics import inverse_kinematics_planar_2r

    p = np.array([0.3, 0.9])
    free = inverse_kinematics_planar_2r(p, [DHLink(a=0.6), DHLink(a=0.5)])      # two rows, angles in (−π, π]
    # joint 1 limited to [π/2, 5π/2): the row whose θ1 is below π/2 comes back shifted by 2π
    limited = inverse_kinematics_planar_2r(p, [DHLink(a=0.6, lower=np.pi / 2, upper=2.5 * np.pi), DHLink(a=0.5)])
    expected = [q + [2 * np.pi * (q[0] < np.pi / 2), 0.0] for q in free]
    np.testing.assert_allclose(limited, expected, rtol=0, atol=1e-12)
    # joint 2 limited to [0, π]: only the elbow with θ2 ≥ 0 is left
    elbow = inverse_kinematics_planar_2r(p, [DHLink(a=0.6), DHLink(a=0.5, lower=0.0, upper=np.pi)])
    np.testing.assert_allclose(elbow, free[free[:, 1] >= 0], rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="joint limits"):
        inverse_kinematics_planar_2r(p, [DHLink(a=0.6, lower=-0.1, upper=0.1), DHLink(a=0.5, lower=-0.1, upper=0.1)])
