"""Timing laws of Chapter 4: boundary conditions, closed forms, finite differences, bad input."""

import numpy as np
import pytest

from planners import timing
from problems.ch04 import manual_spline_system


def _fd_consistent(tr, tol, acceleration=True):
    """Velocities (and accelerations, where continuous) agree with central differences."""
    t = tr.t
    qd_fd = np.gradient(tr.q, t, axis=0)
    qdd_fd = np.gradient(tr.qd, t, axis=0)
    interior = slice(2, -2)
    assert np.max(np.abs(qd_fd[interior] - tr.qd[interior])) < tol
    if acceleration:
        assert np.max(np.abs(qdd_fd[interior] - tr.qdd[interior])) < 50 * tol


def test_quintic_matches_closed_form_rest_to_rest():
    # Rest-to-rest quintic: q = q_i + Δq (10 s³ − 15 s⁴ + 6 s⁵), s = t/T.
    tr = timing.quintic(1.0, 4.0, 2.0, samples=401)
    s = tr.t / 2.0
    np.testing.assert_allclose(tr.q[:, 0], 1.0 + 3.0 * (10 * s**3 - 15 * s**4 + 6 * s**5), atol=1e-12)
    np.testing.assert_allclose(tr.law.coefficients[0], [1, 0, 0, 3.75, -2.8125, 0.5625], atol=1e-12)
    assert tr.qd.max() == pytest.approx(15 * 3.0 / (8 * 2.0))
    _fd_consistent(tr, 1e-3)


def test_cubic_and_quintic_boundary_conditions_many_joints(rng):
    n = 4
    qi, qf, vi, vf, ai, af = rng.normal(size=(6, n))
    tr = timing.quintic(qi, qf, 3.0, vi, vf, ai, af, t_i=1.0)
    for (q, qd, qdd), (p, v, a) in ((tr.evaluate(1.0), (qi, vi, ai)), (tr.evaluate(3.0), (qf, vf, af))):
        np.testing.assert_allclose(q, p, atol=1e-12)
        np.testing.assert_allclose(qd, v, atol=1e-12)
        np.testing.assert_allclose(qdd, a, atol=1e-11)
    c = timing.cubic(qi, qf, 2.0, vi, vf)
    np.testing.assert_allclose(c.q[[0, -1]], [qi, qf], atol=1e-12)
    np.testing.assert_allclose(c.qd[[0, -1]], [vi, vf], atol=1e-12)
    assert c.q.shape == (501, n) and len(c) == 501
    _fd_consistent(c, 1e-3)


def test_trapezoidal_follows_eq_4_8():
    qi, qf, tf, vc = 0.3, 1.3, 2.0, 0.8
    tr = timing.trapezoidal(qi, qf, tf, vc, samples=2001)
    tc = tf - (qf - qi) / vc
    a = vc / tc
    t = tr.t
    expected = np.where(t <= tc, qi + 0.5 * a * t**2,
                        np.where(t <= tf - tc, qi + a * tc * (t - tc / 2), qf - 0.5 * a * (tf - t) ** 2))
    np.testing.assert_allclose(tr.q[:, 0], expected, atol=1e-12)
    assert tr.qd.max() == pytest.approx(vc)
    assert np.abs(tr.qdd).max() == pytest.approx(a)
    _fd_consistent(tr, 2e-3, acceleration=False)


def test_trapezoidal_tra_4_negative_motion_and_rest():
    tr = timing.trapezoidal([0, np.pi / 4, 1.0, 2.0], [np.pi / 2, np.pi / 2, 1.0, 1.0], 1.0,
                            [3 * np.pi / 4, np.pi / 3, 5.0, 1.5], dt=1e-3)
    np.testing.assert_allclose(tr.q[-1], [np.pi / 2, np.pi / 2, 1.0, 1.0], atol=1e-12)
    np.testing.assert_allclose(tr.q[:, 2], 1.0)  # q_f = q_i: stays still
    np.testing.assert_allclose(np.abs(tr.qd).max(axis=0), [3 * np.pi / 4, np.pi / 3, 0.0, 1.5], atol=1e-12)
    assert np.all(tr.qd[:, 3] <= 0)  # moves downwards
    q, qd, qdd = tr.evaluate(1.5)  # held after t_f
    np.testing.assert_allclose(q, tr.q[-1])
    np.testing.assert_allclose(qd, 0.0)
    np.testing.assert_allclose(qdd, 0.0)


def test_trapezoidal_infeasible_cruise_speed_is_explained():
    with pytest.raises(ValueError, match=r"qd_c.*\(1, 2\].*got 3.*triangular=True"):
        timing.trapezoidal(0.0, 1.0, 1.0, 3.0)
    with pytest.raises(ValueError, match=r"qd_c\[1\].*got 0.5"):
        timing.trapezoidal([0, 0], [1, 1], 1.0, [1.5, 0.5])
    tri = timing.trapezoidal(0.0, 1.0, 1.0, 3.0, triangular=True)
    assert tri.qd.max() == pytest.approx(2.0)
    assert tri.q[-1, 0] == pytest.approx(1.0)
    np.testing.assert_allclose(tri.law.breaks, [0, 0.5, 1.0])


def test_trapezoidal_given_acceleration_eq_4_9():
    qi, qf, tf, a = 0.0, 1.0, 2.0, 2.0
    law = timing.trapezoidal_acceleration_law(qi, qf, tf, a)
    tc = tf / 2 - 0.5 * np.sqrt((tf**2 * a - 4 * (qf - qi)) / a)
    assert law(tc)[1] == pytest.approx(a * tc)
    assert law(tf)[0] == pytest.approx(qf)
    with pytest.raises(ValueError, match="4\\|q_f - q_i\\|/T\\^2 = 1"):
        timing.trapezoidal_acceleration_law([0.0], [1.0], 2.0, [0.5])


def test_raised_cosine_problem_4_2_closed_form():
    tr = timing.raised_cosine(0.0, 3.0, 2.0, samples=801)
    assert tr.law.k == pytest.approx(1.5) and tr.law.k1 == pytest.approx(0.0)
    t = tr.t
    np.testing.assert_allclose(tr.qd[:, 0], 1.5 * (1 - np.cos(np.pi * t)), atol=1e-12)
    assert tr.q[-1, 0] == pytest.approx(3.0)
    _fd_consistent(tr, 1e-3)


def test_scalar_and_vector_evaluation_agree(rng):
    law = timing.trapezoidal_law([0, np.pi / 4], [np.pi / 2, np.pi / 2], 1.0, [3 * np.pi / 4, np.pi / 3])
    ts = np.concatenate([rng.uniform(-0.5, 1.5, 100), [0.0, 0.25, 1.0]])
    vq, vqd, vqdd = law(ts)
    for k, t in enumerate(ts):
        q, qd, qdd = law(float(t))
        np.testing.assert_allclose([q, qd, qdd], [vq[k], vqd[k], vqdd[k]], atol=1e-12)


def test_sample_and_plot():
    tr = timing.quintic([0, 1], [1, 0], 1.0, dt=0.01)
    assert tr.t[-1] == pytest.approx(1.0) and len(tr) == 101
    sub = tr.sample([0.0, 0.5, 2.0])
    np.testing.assert_allclose(sub.q[1], [0.5, 0.5])
    np.testing.assert_allclose(sub.qd[2], 0.0)
    axes = tr.plot()
    assert len(axes) == 3 and len(axes[0].lines) == 2
    assert "2 joints" in str(tr)


@pytest.mark.parametrize("call, match", [
    (lambda: timing.quintic(0.0, 1.0, 0.0), "t_f"),
    (lambda: timing.quintic([0.0, 1.0], [1.0], 1.0), "q_f"),
    (lambda: timing.cubic(np.nan, 1.0, 1.0), "q_i"),
    (lambda: timing.sample(timing.cubic_law(0, 1, 1), samples=3, dt=0.1), "only one"),
    (lambda: timing.PiecewisePolynomial([0, 1, 1], np.zeros((2, 3))), "increasing"),
    (lambda: timing.quintic_law(0.0, 1.0, 1.0)(np.nan), "NaN"),
    (lambda: timing.quintic_law(0.0, 1.0, 1.0)(np.array([0.5, np.nan])), "NaN"),
    (lambda: timing.raised_cosine_law(0.0, 1.0, 1.0)(np.nan), "NaN"),
])
def test_bad_input_names_the_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# ---------------------------------------------------------------- via points -----------------

def _continuity(law, instants, orders=(0, 1, 2), tol=1e-9):
    for t in instants:
        left, right = law(t - 1e-12), law(t + 1e-12)
        for o in orders:
            np.testing.assert_allclose(left[o], right[o], atol=tol, err_msg=f"order {o} at t = {t}")


def test_quintic_sequence_problem_4_3_and_continuity():
    law = timing.polynomial_sequence_law([0, 2, 4], [0, 2, 3])
    np.testing.assert_allclose(law.coefficients[0], [0, 0, 0, 1.75, -1.21875, 0.234375], atol=1e-12)
    np.testing.assert_allclose(law.coefficients[1], [2, 0.75, 0, 0.125, -0.1875, 0.046875], atol=1e-12)
    _continuity(law, [2.0])


def test_via_point_velocity_heuristic_4_12():
    v = timing.via_point_velocities([0, 1, 2, 3, 4], [0, 1, 3, 2, 2.5], qd_i=0.1, qd_f=-0.2)
    np.testing.assert_allclose(v, [0.1, 1.5, 0.0, 0.0, -0.2])  # sign changes at t = 2 and t = 3


def test_cubic_sequence_many_joints_is_c1(rng):
    t = np.cumsum(rng.uniform(0.5, 1.5, 6))
    q = rng.normal(size=(6, 3))
    law = timing.polynomial_sequence_law(t, q, degree=3)
    np.testing.assert_allclose(law(t)[0], q, atol=1e-12)
    _continuity(law, t[1:-1], orders=(0, 1))


@pytest.mark.parametrize("N", [3, 4, 5, 7, 12])
def test_spline_system_equals_manual_formulas_and_spline_is_c2(N, rng):
    t = np.cumsum(np.concatenate([[0.0], rng.uniform(0.5, 2.0, N - 1)]))
    q = rng.normal(size=N)
    vi, vf, ai, af = rng.normal(size=4)
    tv = (t[0] + rng.uniform(0.2, 0.8) * (t[1] - t[0]), t[-2] + rng.uniform(0.2, 0.8) * (t[-1] - t[-2]))
    system = timing.spline_system(t, q, vi, vf, ai, af, t_virtual=tv)
    A, b = manual_spline_system(np.diff(system.knots), q, vi, vf, ai, af)  # the manual's (4.28)
    np.testing.assert_allclose(system.A, A, atol=1e-12)
    np.testing.assert_allclose(system.b, b, atol=1e-12)
    law = timing.cubic_spline_law(t, q, vi, vf, ai, af, t_virtual=tv)
    np.testing.assert_allclose(law(t)[0], q, atol=1e-12)
    q0, v0, a0 = law(t[0])
    q1, v1, a1 = law(t[-1])
    np.testing.assert_allclose([v0, a0, v1, a1], [vi, ai, vf, af], atol=1e-10)
    _continuity(law, system.knots[1:-1], tol=1e-8)


def test_spline_many_joints_and_large_n_is_fast(rng):
    import time
    N = 20000
    t = np.cumsum(rng.uniform(0.5, 1.0, N))
    q = rng.normal(size=(N, 2))
    start = time.perf_counter()
    law = timing.cubic_spline_law(t, q)
    assert time.perf_counter() - start < 2.0  # O(N): a dense solve would need ~N³ flops
    np.testing.assert_allclose(law(t)[0], q, atol=1e-9)


def test_linear_parabolic_blends_problem_4_6():
    c = timing.blend_coefficients([0, 2, 4], [0, 2, 3], 0.2)
    np.testing.assert_allclose(c.a, [[0, 1], [2, 0.5]])
    np.testing.assert_allclose(c.b, [[0.025, 0.5, 2.5], [1.9875, 0.75, -1.25], [2.9875, 0.25, -1.25]])
    tr = timing.linear_parabolic_blends([0, 2, 4], [0, 2, 3], 0.2, samples=4201)
    assert tr.t[0] == pytest.approx(-0.1) and tr.t[-1] == pytest.approx(4.1)
    _continuity(tr.law, [0.1, 1.9, 2.1, 3.9], orders=(0, 1))
    assert tr.q[0, 0] == pytest.approx(0.0) and tr.q[-1, 0] == pytest.approx(3.0)
    assert tr.law(1.0)[1] == pytest.approx(1.0) and tr.law(3.0)[1] == pytest.approx(0.5)
    with pytest.raises(ValueError, match="overlap"):
        timing.linear_parabolic_blends_law([0, 1, 2], [0, 1, 0], 1.5)


def test_via_point_bad_input():
    with pytest.raises(ValueError, match="strictly increasing"):
        timing.cubic_spline_law([0, 2, 2, 4], [0, 1, 2, 3])
    with pytest.raises(ValueError, match=r"`q` must have shape \(3,\)"):
        timing.polynomial_sequence_law([0, 1, 2], [0, 1])
    with pytest.raises(ValueError, match="at least 3"):
        timing.spline_system([0, 1], [0, 1])
    with pytest.raises(ValueError, match="t_virtual"):
        timing.cubic_spline_law([0, 2, 4], [0, 1, 2], t_virtual=(3, 3.5))


# ---------------------------------------------------------------- properties -----------------

from hypothesis import given, settings, strategies as st  # noqa: E402

finite = st.floats(-10, 10, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(q_i=finite, dq=st.floats(-5, 5).filter(lambda x: abs(x) > 1e-3), t_f=st.floats(0.1, 10),
       fraction=st.floats(1e-3, 1.0))
def test_trapezoid_property(q_i, dq, t_f, fraction):
    lo, hi = abs(dq) / t_f, 2 * abs(dq) / t_f
    vc = lo + fraction * (hi - lo)
    law = timing.trapezoidal_law(q_i, q_i + dq, t_f, vc)
    t = np.linspace(0, t_f, 257)
    q, qd, qdd = law(t)
    assert law(0.0)[0] == pytest.approx(q_i, abs=1e-9)
    assert law(t_f)[0] == pytest.approx(q_i + dq, abs=1e-9 * (1 + abs(dq)))
    assert np.max(np.abs(qd)) <= vc * (1 + 1e-9)
    assert law(t_f / 2)[1] == pytest.approx(np.sign(dq) * vc, rel=1e-9)
    assert np.all(np.sign(dq) * qd >= -1e-12)  # monotone motion
    # position is the integral of velocity (trapezoid rule on a fine grid)
    tt = np.linspace(0, t_f, 20001)
    integral = np.trapezoid(law(tt)[1], tt)
    assert integral == pytest.approx(dq, abs=1e-6 * (1 + abs(dq)))


# --------------------------------------------------------------------------------------------
# Reliability: arguments named, no inf/NaN coefficients
# --------------------------------------------------------------------------------------------

def test_blend_durations_must_be_positive():
    """The old blend_coefficients(blend=0) returned ±inf in b_k2 and accepted a negative blend."""
    from planners.timing import blend_coefficients, linear_parabolic_blends_law

    for bad in (0.0, -1.0, np.nan, [0.2, 0.0, 0.2], [0.2, 0.2]):
        with pytest.raises(ValueError, match="`blend`"):
            blend_coefficients([0.0, 1.0, 2.0], [0.0, 1.0, 0.0], bad)
        with pytest.raises(ValueError, match="`blend`"):
            linear_parabolic_blends_law([0.0, 1.0, 2.0], [0.0, 1.0, 0.0], bad)
    b = blend_coefficients([0.0, 1.0, 2.0], [0.0, 1.0, 0.0], 0.2).b
    # the blend about t_2 = 1: velocities +1 → −1 over 0.2 s, b_22 = (−1 − 1)/(2·0.2) = −5
    assert b[1, 2] == pytest.approx(-5.0)


@pytest.mark.parametrize("call, name", [
    (lambda: __import__("planners.timing", fromlist=["x"]).cubic_law(0.0, 1.0, "two"), "t_f"),
    (lambda: __import__("planners.timing", fromlist=["x"]).quintic_law(0.0, 1.0, 1.0, t_i=[0.0, 1.0]), "t_i"),
    (lambda: __import__("planners.timing", fromlist=["x"]).trapezoidal_law(0.0, 1.0, None, 1.5), "t_f"),
    (lambda: __import__("planners.timing", fromlist=["x"]).raised_cosine_law(0.0, 1.0, float("inf")), "t_f"),
    (lambda: __import__("planners.timing", fromlist=["x"]).cubic(0.0, 1.0, 1.0, dt="x"), "dt"),
    (lambda: __import__("planners.timing", fromlist=["x"]).cubic(0.0, 1.0, 1.0, samples=2.5), "samples"),
])
def test_timing_arguments_are_named(call, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        call()
