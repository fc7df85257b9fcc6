"""Multi-segment trajectories with per-axis speed limits or given segment times (after the Toolbox's mstraj,
not its timing).

Expected segment times, blend positions and peak speeds are computed here from the formulas:
Δt_k = max_j |Δq_kj| / q̇_max,j, and a parabolic blend of duration t_acc between the segment
velocities v⁻ and v⁺ misses the via point by (v⁺ − v⁻) t_acc / 8.
"""

import numpy as np
import pytest

from planners.timing import multi_segment, multi_segment_law, multi_segment_times

VIA = np.array([[0.0, 0.0, 0.0],
                [1.0, 2.0, -0.5],
                [3.0, 2.0, 0.5],
                [3.0, -1.0, 0.5],
                [2.0, -1.0, 0.0]])
QD_MAX = np.array([1.0, 2.0, 0.25])
T_ACC = 0.4


def _expected_durations():
    # segment 1: |Δq| = (1, 2, 0.5) → times (1, 1, 2): 2 s (axis 3 is the slowest)
    # segment 2: (2, 0, 1) → (2, 0, 4): 4 s; segment 3: (0, 3, 0) → 1.5 s; segment 4: (1, 0, 0.5) → (1, 0, 2): 2 s
    return np.array([2.0, 4.0, 1.5, 2.0])


def test_segment_durations_are_set_by_the_slowest_axis():
    t = multi_segment_times(VIA, QD_MAX, T_ACC)
    np.testing.assert_allclose(np.diff(t), _expected_durations())
    assert t[0] == pytest.approx(T_ACC / 2)
    law = multi_segment_law(VIA, QD_MAX, T_ACC, t_i=1.0)
    assert law.t_i == pytest.approx(1.0)
    assert law.t_f == pytest.approx(1.0 + _expected_durations().sum() + T_ACC)


def test_short_segment_is_stretched_to_the_blend_time():
    t = multi_segment_times([[0.0], [0.01], [1.0]], 1.0, 0.5)
    np.testing.assert_allclose(np.diff(t), [0.5, 0.99])


def test_speed_limits_respected_and_reached():
    tr = multi_segment(VIA, QD_MAX, T_ACC, dt=1e-3)
    peak = np.abs(tr.qd).max(axis=0)
    assert np.all(peak <= QD_MAX * (1 + 1e-12))
    # the peak speed of each axis is its fastest segment velocity |Δq|/Δt (blends lie between two):
    # axis 1 moves 1, 2, 0, 1 in 2, 4, 1.5, 2 s → 0.5 (never at its limit, always timed by another axis)
    peak_expected = (np.abs(np.diff(VIA, axis=0)) / _expected_durations()[:, None]).max(axis=0)
    np.testing.assert_allclose(peak_expected, [0.5, 2.0, 0.25])
    np.testing.assert_allclose(peak, peak_expected, rtol=1e-12)


def test_ends_at_rest_on_the_first_and_last_points():
    law = multi_segment_law(VIA, QD_MAX, T_ACC)
    for t, q in ((law.t_i, VIA[0]), (law.t_f, VIA[-1])):
        qv, qd, _ = law(t)
        np.testing.assert_allclose(qv, q, atol=1e-14)
        np.testing.assert_allclose(qd, 0.0, atol=1e-14)


def test_passes_near_the_via_points_as_the_blend_predicts():
    law = multi_segment_law(VIA, QD_MAX, T_ACC)
    t = multi_segment_times(VIA, QD_MAX, T_ACC)
    d = _expected_durations()
    v = np.diff(VIA, axis=0) / d[:, None]  # segment velocities
    for k in range(1, len(VIA) - 1):
        expected = VIA[k] + (v[k] - v[k - 1]) * T_ACC / 8
        np.testing.assert_allclose(law(t[k])[0], expected, atol=1e-13)
        # outside the blend the path is on the straight line through the via points
        tk = t[k] + T_ACC / 2 + 0.1
        np.testing.assert_allclose(law(tk)[0], VIA[k] + v[k] * (tk - t[k]), atol=1e-13)


def test_position_and_velocity_are_continuous():
    law = multi_segment_law(VIA, QD_MAX, T_ACC)
    eps = 1e-9
    for b in law.breaks[1:-1]:
        q_minus, qd_minus, _ = law(b - eps)
        q_plus, qd_plus, _ = law(b + eps)
        np.testing.assert_allclose(q_plus, q_minus, atol=1e-8)
        np.testing.assert_allclose(qd_plus, qd_minus, atol=1e-7)
    # velocity is the derivative of position (central differences over the whole law)
    tt = np.linspace(law.t_i + 1e-3, law.t_f - 1e-3, 400)
    h = 1e-6
    fd = (law(tt + h)[0] - law(tt - h)[0]) / (2 * h)
    np.testing.assert_allclose(fd, law(tt)[1], atol=1e-6)


def test_scalar_law_and_plot():
    tr = multi_segment([0.0, 1.0, -1.0], 2.0, 0.2, samples=200)
    assert tr.n == 1 and tr.name == "multi-segment"
    assert tr.duration == pytest.approx(0.5 + 1.0 + 0.2)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    axes = tr.plot()
    assert axes[-1].get_xlabel() == "t [s]"
    plt.close(axes[0].figure)


@pytest.mark.parametrize("args, message", [
    (([[0.0, 1.0]], 1.0, 0.2), "`via_points` must have shape"),
    (([[0.0], [np.nan]], 1.0, 0.2), "`via_points` must be finite"),
    (([[0.0, 0.0], [1.0, 1.0]], [1.0, 0.0], 0.2), "`qd_max` must be positive"),
    (([[0.0, 0.0], [1.0, 1.0]], [1.0, 1.0, 1.0], 0.2), "`qd_max` must have shape"),
    (([[0.0], [1.0]], 1.0, 0.0), "`t_acc` must be a finite positive"),
])
def test_bad_input_names_the_argument(args, message):
    with pytest.raises(ValueError, match=message):
        multi_segment_law(*args)
