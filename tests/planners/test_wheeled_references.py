"""Wheeled-robot paths against references computed here: derivatives by central differences, the
Reeds–Shepp distance's metric properties (a family missed shows as an asymmetry or a broken triangle
inequality), zero-turn Dubins words, and the geometry of Chapter 11's models (arcs, centre of rotation,
front-wheel point, trailers) rebuilt by rotations and chains of hinges."""

import numpy as np
import pytest

import planners.wheeled as pw
from planners.timing import quintic_law
from rigid_body import wheeled as rw


def _rot(a: float) -> np.ndarray:
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


def test_cartesian_polynomial_path_derivatives_by_central_differences():
    path = pw.cartesian_polynomial_path([0.3, -0.2, 0.4], [2.0, 1.5, 2.2], 1.3, 0.8)
    s, h = np.linspace(0.05, 0.95, 19), 1e-6
    p, dp, ddp = path(s)
    np.testing.assert_allclose((path(s + h)[0] - path(s - h)[0]) / (2 * h), dp, atol=1e-7)
    np.testing.assert_allclose((path(s + h)[1] - path(s - h)[1]) / (2 * h), ddp, atol=1e-7)
    np.testing.assert_allclose(path(np.array([0.0, 1.0]))[0], [[0.3, -0.2], [2.0, 1.5]], atol=1e-15)


def test_time_scaled_reference_derivatives_by_central_differences():
    """ṗ = p' ṡ and p̈ = p'' ṡ² + p' s̈ (11.55) along a quintic timing law: against differences in t."""
    ref = pw.TimeScaledPath(pw.cartesian_polynomial_path([0, 0, 0], [2, 1, 0.5]), law=quintic_law(0.0, 1.0, 5.0))
    h = 1e-5
    for t in (0.7, 2.1, 3.9):
        r = ref(t)
        np.testing.assert_allclose((ref(t + h).p - ref(t - h).p) / (2 * h), r.pd, atol=1e-8)
        np.testing.assert_allclose((ref(t + h).pd - ref(t - h).pd) / (2 * h), r.pdd, atol=1e-7)
        np.testing.assert_allclose(r.v, np.hypot(*r.pd), atol=1e-12)


def test_figure_eight_is_centred_at_the_origin_by_default():
    np.testing.assert_allclose(pw.FigureEight(a=2.0, T=10.0)(0.0).p, [0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(pw.FigureEight(a=2.0, T=10.0, center=(1.0, -1.0))(2.5).p, [3.0, -1.0], atol=1e-12)


def test_reeds_shepp_distance_is_a_metric():
    """d(a, b) = d(b, a) (drive the path backwards) and d(a, c) ≤ d(a, b) + d(b, c): a family or a solution of a
    family left out of the search shows as a longer path one way than the other."""
    rng = np.random.default_rng(11)
    d = lambda a, b: pw.reeds_shepp_path(a, b, 0.8).length            # noqa: E731
    for _ in range(150):
        a, b, c = rng.uniform(-3, 3, (3, 3))
        assert d(a, b) == pytest.approx(d(b, a), abs=1e-9)
        assert d(a, c) <= d(a, b) + d(b, c) + 1e-9


def test_reeds_shepp_finds_the_zero_length_segments():
    """Goals on the start's straight line or circle: one non-zero segment, the others exactly empty."""
    for goal, length in (([3.0, 0.0, 0.0], 3.0), ([-2.0, 0.0, 0.0], 2.0),
                         ([np.sin(1.0), 1 - np.cos(1.0), 1.0], 1.0), ([np.sin(1.0), -(1 - np.cos(1.0)), -1.0], 1.0)):
        assert pw.reeds_shepp_path([0.0, 0.0, 0.0], goal, 1.0).length == pytest.approx(length, abs=1e-9)


def test_dubins_straight_paths_have_no_turn():
    """A goal straight ahead, at any heading: LSL and RSR both reduce to the straight segment (an angle of −1e-17
    from rounding is no turn, not a 2π one)."""
    for th in np.linspace(-np.pi, np.pi, 73):
        for L in (1.0, 4.0):
            q_i = np.array([0.5, -0.2, th])
            q_f = q_i + np.array([L * np.cos(th), L * np.sin(th), 0.0])
            lengths = {p.word: p.length for p in pw.dubins_paths(q_i, q_f, 0.7)}
            assert lengths["LSL"] == pytest.approx(L, abs=1e-9) and lengths["RSR"] == pytest.approx(L, abs=1e-9)


def test_unicycle_arc_straight_limit_and_arc_by_rotation():
    q = np.array([0.4, -0.3, 0.7])
    for omega in (0.0, 1e-12):
        np.testing.assert_allclose(rw.unicycle_arc(q, 1.5, omega, 0.8), q + [1.2 * np.cos(0.7), 1.2 * np.sin(0.7), 0.0],
                                   atol=1e-11)
    # an arc: the centre c = p + R(θ)[0, v/ω] and the point rotated about it by ωt
    v, w, t = 1.5, -0.9, 0.8
    c = q[:2] + _rot(q[2]) @ [0.0, v / w]
    np.testing.assert_allclose(rw.unicycle_arc(q, v, w, t)[:2], c + _rot(w * t) @ (q[:2] - c), atol=1e-12)


def test_bicycle_geometry_rebuilt_by_rotations():
    """The centre of rotation on the rear axle at ℓ/tan φ, the front-wheel point at ℓ then b along the wheel."""
    rng = np.random.default_rng(3)
    for _ in range(10):
        x, y, th = rng.uniform(-2, 2, 3)
        phi, ell, b = rng.uniform(0.2, 1.2) * rng.choice([-1, 1]), rng.uniform(0.5, 2), rng.uniform(-1, 1)
        q = np.array([x, y, th, phi])
        np.testing.assert_allclose(rw.bicycle_icr(q, ell), [x, y] + _rot(th) @ [0.0, ell / np.tan(phi)], atol=1e-12)
        front = np.array([x, y]) + _rot(th) @ [ell, 0.0]
        np.testing.assert_allclose(rw.front_wheel_point(q, ell, b), front + _rot(th + phi) @ [b, 0.0], atol=1e-12)


def test_trailer_axles_as_a_chain_of_hinges():
    """Front wheel ℓ ahead of the rear axle along θ0; trailer i's axle ℓ_i behind the previous axle along θ_i."""
    rng = np.random.default_rng(5)
    lengths, ell = rng.uniform(0.5, 1.5, 3), 0.9
    q = rng.uniform(-1.0, 1.0, 7)
    pts = rw.trailer_axle_midpoints(q, ell, lengths)
    expected = [q[:2] + ell * np.array([np.cos(q[3]), np.sin(q[3])]), q[:2]]
    for i, L in enumerate(lengths, start=1):
        expected.append(expected[-1] - L * np.array([np.cos(q[3 + i]), np.sin(q[3 + i])]))
    np.testing.assert_allclose(pts, expected, atol=1e-12)


def test_reeds_shepp_candidates_include_every_family_solution_with_empty_segments():
    """A goal straight ahead: the LSL and RSR words (first and last arcs empty) are both among the candidates,
    as the closed forms give them; leaving one out would not show in the shortest length."""
    words = {(p.word, round(p.length, 9)) for p in pw.reeds_shepp_paths([0.0, 0.0, 0.0], [3.0, 0.0, 0.0], 1.0)}
    assert ("LSL", 3.0) in words and ("RSR", 3.0) in words
