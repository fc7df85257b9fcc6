"""Operational-space paths and orientation interpolation: geometry, finite differences, slerp = angle–axis."""

import numpy as np
import pytest

from planners import paths, timing
from rigid_body.rotations import (axis_angle_to_rotation, quaternion_to_rotation, rotation_to_quaternion,
                                  vee)


def _fd(law, t, h=1e-6):
    """Central differences of the position and velocity returned by a law."""
    return ((law(t + h)[0] - law(t - h)[0]) / (2 * h), (law(t + h)[1] - law(t - h)[1]) / (2 * h))


def _random_rotation(rng):
    axis = rng.normal(size=3)
    return axis_angle_to_rotation(rng.uniform(0, np.pi), axis / np.linalg.norm(axis))


def test_segment_path_with_trapezoid_problem_4_7():
    seg = paths.Segment([0, 0.5, 0], [1, -0.5, 0])
    law = paths.PathLaw(seg, timing.trapezoidal_law(0.0, seg.length, 2.0, 1.0))
    t = np.linspace(0.01, 1.99, 57)
    p, pd, pdd = law(t)
    np.testing.assert_allclose(np.linalg.norm(pd, axis=1), law.timing(t)[1], atol=1e-12)
    np.testing.assert_allclose(np.cross(pd, seg.tangent), 0.0, atol=1e-12)  # along the segment
    fd_v, fd_a = _fd(law, t)
    np.testing.assert_allclose(fd_v, pd, atol=1e-6)
    smooth = np.abs(law.timing(t)[1] - 1.0) > 1e-3  # away from the acceleration jumps
    np.testing.assert_allclose(fd_a[smooth], pdd[smooth], atol=1e-4)
    np.testing.assert_allclose(law(2.0)[0], [1, -0.5, 0], atol=1e-12)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_circle_through_point_geometry_and_derivatives(seed):
    rng = np.random.default_rng(seed)
    axis, point, p_i = rng.normal(size=(3, 3))
    circle = paths.circle_through(p_i, axis, point, length=3.0)
    r = axis / np.linalg.norm(axis)
    s = np.linspace(0, 3.0, 40)
    p, dp, ddp = circle(s)
    np.testing.assert_allclose(p[0], p_i, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(p - circle.center, axis=1), circle.radius, atol=1e-12)
    np.testing.assert_allclose((p - circle.center) @ r, 0.0, atol=1e-12)  # in the plane ⟂ axis
    np.testing.assert_allclose(np.cross(circle.center - point, r), 0.0, atol=1e-12)  # centre on the axis
    np.testing.assert_allclose(np.linalg.norm(dp, axis=1), 1.0, atol=1e-12)  # arc length
    np.testing.assert_allclose(np.cross(p - circle.center, dp) @ r, circle.radius, atol=1e-12)  # ccw
    h = 1e-6
    np.testing.assert_allclose((circle(s + h)[0] - circle(s - h)[0]) / (2 * h), dp, atol=1e-8)
    np.testing.assert_allclose((circle(s + h)[1] - circle(s - h)[1]) / (2 * h), ddp, atol=1e-7)
    law = paths.PathLaw(circle, timing.quintic_law(0.0, 3.0, 1.5))
    t = np.linspace(0.05, 1.45, 20)
    fd_v, fd_a = _fd(law, t)
    np.testing.assert_allclose(fd_v, law(t)[1], atol=1e-6)
    np.testing.assert_allclose(fd_a, law(t)[2], atol=1e-4)


def test_segment_sequence_stops_or_rounds_the_via_point():
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0]], dtype=float)
    laws = [timing.quintic_law(0.0, 1.0, 1.0), timing.quintic_law(0.0, 1.0, 2.0, t_i=1.0)]
    stop = paths.SegmentSequence(pts, laws)
    np.testing.assert_allclose(stop(1.0)[0], pts[1], atol=1e-12)
    np.testing.assert_allclose(stop(1.0)[1], 0.0, atol=1e-12)
    overlap = paths.SegmentSequence(pts, [laws[0], timing.quintic_law(0.0, 1.0, 1.6, t_i=0.6)])
    p, pd, _ = overlap(np.linspace(0, 1.6, 801))
    assert np.min(np.linalg.norm(p - pts[1], axis=1)) > 0.01  # corner is rounded
    assert np.min(np.linalg.norm(pd[200:600], axis=1)) > 0.1  # no stop at the via point
    np.testing.assert_allclose(p[-1], pts[2], atol=1e-12)
    tr = timing.sample(overlap, samples=101)
    assert tr.q.shape == (101, 3)
    with pytest.raises(ValueError, match="laws\\[0\\].*the segment length"):
        paths.SegmentSequence(pts, [timing.quintic_law(0.0, 2.0, 1.0), laws[1]])


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_angle_axis_and_slerp_agree_and_omega_matches_rdot(seed):
    rng = np.random.default_rng(seed)
    R_i, R_f = _random_rotation(rng), _random_rotation(rng)
    law = timing.quintic_law(0.0, 1.0, 2.0)
    aa = paths.AngleAxisInterpolation(R_i, R_f, law)
    sl = paths.Slerp(rotation_to_quaternion(R_i), rotation_to_quaternion(R_f), law)
    t = np.linspace(0.0, 2.0, 15)
    R, w, wd = aa(t)
    Q, w2, wd2 = sl(t)
    np.testing.assert_allclose(R[0], R_i, atol=1e-12)
    np.testing.assert_allclose(R[-1], R_f, atol=1e-10)
    np.testing.assert_allclose(np.array([quaternion_to_rotation(q) for q in Q]), R, atol=1e-10)
    np.testing.assert_allclose(w2, w, atol=1e-10)
    np.testing.assert_allclose(wd2, wd, atol=1e-10)
    h = 1e-6  # S(ω) = Ṙ R^T (3.6)
    Rdot = (aa(t + h)[0] - aa(t - h)[0]) / (2 * h)
    inner = slice(1, -1)
    w_fd = np.array([vee(Rd @ Rk.T) for Rd, Rk in zip(Rdot, R)])
    np.testing.assert_allclose(w_fd[inner], w[inner], atol=1e-6)
    np.testing.assert_allclose(((aa(t + h)[1] - aa(t - h)[1]) / (2 * h))[inner], wd[inner], atol=1e-5)


def test_slerp_takes_the_short_way_and_bad_input():
    Q_i = np.array([1.0, 0, 0, 0])
    Q_f = -rotation_to_quaternion(axis_angle_to_rotation(0.4, [0, 0, 1]))
    mid = paths.slerp(Q_i, Q_f, 0.5)
    np.testing.assert_allclose(quaternion_to_rotation(mid), axis_angle_to_rotation(0.2, [0, 0, 1]), atol=1e-12)
    with pytest.raises(ValueError, match="sigma"):
        paths.slerp(Q_i, Q_f, np.nan)
    with pytest.raises(ValueError, match="arc length"):
        paths.Segment([0, 0, 0], [1, 0, 0])(np.array([0.5, np.nan]))
    with pytest.raises(ValueError, match="p_f"):
        paths.Segment([0, 0, 0], [0, 0, 0])
    with pytest.raises(ValueError, match="on the axis"):
        paths.circle_through([0, 0, 1], [0, 0, 1], [0, 0, 0])
    with pytest.raises(ValueError, match="the path length"):
        paths.PathLaw(paths.Segment([0, 0, 0], [1, 0, 0]), timing.quintic_law(0.0, 2.0, 1.0))
    with pytest.raises(ValueError, match="scalar law"):
        paths.PathLaw(paths.Segment([0, 0, 0], [1, 0, 0]), timing.quintic_law([0.0], [1.0], 1.0))


# --------------------------------------------------------------------------------------------
# No extrapolation: a timing law leaving its range is refused (reliability)
# --------------------------------------------------------------------------------------------

def _Rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_orientation_interpolation_refuses_a_timing_beyond_one():
    """The old AngleAxisInterpolation with σ: 0 → 2 ended at Rz(2) instead of R_f = Rz(1)."""
    from planners.paths import AngleAxisInterpolation, Slerp, slerp
    from planners.timing import cubic_law

    with pytest.raises(ValueError, match="`timing` must stay within \\[0, 1\\]"):
        AngleAxisInterpolation(np.eye(3), _Rz(1.0), cubic_law(0.0, 2.0, 1.0))
    with pytest.raises(ValueError, match="`timing` must stay within \\[0, 1\\]"):
        Slerp([1.0, 0.0, 0.0, 0.0], [np.cos(0.5), 0.0, 0.0, np.sin(0.5)], cubic_law(0.0, 3.0, 1.0))
    with pytest.raises(ValueError, match="`timing` must end at 1"):
        AngleAxisInterpolation(np.eye(3), _Rz(1.0), cubic_law(0.0, 0.5, 1.0))
    with pytest.raises(ValueError, match="`timing` must start at 0"):
        Slerp([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0], cubic_law(0.2, 1.0, 1.0))
    # an overshooting law (cubic with a large initial velocity) leaves [0, 1] inside the interval
    with pytest.raises(ValueError, match="`timing` must stay within"):
        AngleAxisInterpolation(np.eye(3), _Rz(1.0), cubic_law(0.0, 1.0, 1.0, qd_i=6.0))
    for sigma in (2.0, -0.1, np.nan):
        with pytest.raises(ValueError, match="`sigma`"):
            slerp([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0], sigma)
    # within the range the end point is R_f exactly (closed form: Rz(1))
    interp = AngleAxisInterpolation(np.eye(3), _Rz(1.0), cubic_law(0.0, 1.0, 1.0))
    np.testing.assert_allclose(interp(1.0)[0], _Rz(1.0), atol=1e-12)


def test_path_law_refuses_a_timing_that_leaves_the_path():
    """The old PathLaw with s: −0.5 → 1 started 0.5 m before the segment."""
    from planners.paths import PathLaw, Segment
    from planners.timing import cubic_law

    seg = Segment([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="`timing` must stay within \\[0, 1\\]"):
        PathLaw(seg, cubic_law(-0.5, 1.0, 1.0))
    with pytest.raises(ValueError, match="`timing` must stay within"):
        PathLaw(seg, cubic_law(0.0, 1.5, 1.0))
    with pytest.raises(ValueError, match="scalar law"):
        PathLaw(seg, cubic_law([0.0, 0.0], [1.0, 1.0], 1.0))
    np.testing.assert_allclose(PathLaw(seg, cubic_law(0.0, 0.5, 1.0))(1.0)[0], [0.5, 0.0, 0.0])


def test_circle_arguments_are_named():
    from planners.paths import Circle

    with pytest.raises(ValueError, match="`radius`"):
        Circle(np.zeros(3), "one", np.eye(3))
    with pytest.raises(ValueError, match="`radius`"):
        Circle(np.zeros(3), -1.0, np.eye(3))
    with pytest.raises(ValueError, match="`length`"):
        Circle(np.zeros(3), 1.0, np.eye(3), length=-2.0)


def test_segment_sequence_refuses_an_overshooting_segment_law():
    from planners.paths import SegmentSequence
    from planners.timing import cubic_law

    pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]
    ok = cubic_law(0.0, 1.0, 2.0, t_i=1.0)
    with pytest.raises(ValueError, match=r"`laws\[0\]` must stay within \[0, 1\]"):
        SegmentSequence(pts, [cubic_law(0.0, 1.0, 1.0, qd_i=6.0), ok])
