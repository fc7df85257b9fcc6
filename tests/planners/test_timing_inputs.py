"""Timing laws under hostile input and what the multi-segment law claims (issue 26, items 12 and 13)."""

import numpy as np
import pytest

from planners.timing import cubic, multi_segment, multi_segment_law, multi_segment_times, quintic, trapezoidal

VIA = np.array([[4.0, 1.0], [4.0, 4.0], [5.0, 2.0], [2.0, 5.0]])      # the via points of mstraj's documentation


@pytest.mark.parametrize("call, name", [
    (lambda: cubic(0.0, 1.0, "2"), "t_f"),
    (lambda: cubic(0.0, 1.0, 2.0, t_i="0"), "t_i"),
    (lambda: cubic("0", 1.0, 2.0), "q_i"),
    (lambda: cubic([0.0, "1"], [1.0, 1.0], 2.0), "q_i"),
    (lambda: quintic(0.0, 1.0, b"2"), "t_f"),
    (lambda: trapezoidal(0.0, 1.0, 2.0, "1"), "qd_c"),
    (lambda: cubic(0.0, 1.0, 2.0, dt="0.1"), "dt"),
])
def test_numbers_given_as_text_are_refused(call, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        call()


def test_given_segment_times_are_kept():
    law = multi_segment_law(VIA, t_acc=1.0, tsegment=[3.0, 2.0, 4.0])
    t = multi_segment_times(VIA, t_acc=1.0, tsegment=[3.0, 2.0, 4.0])
    np.testing.assert_allclose(np.diff(t), [3.0, 2.0, 4.0])
    assert law.t_f == pytest.approx(0.5 + 9.0 + 0.5)
    # on the straight part of segment 2 the velocity is the segment's Δq / Δt
    np.testing.assert_allclose(law(t[1] + 1.0)[1], (VIA[2] - VIA[1]) / 2.0, atol=1e-12)
    tr = multi_segment(VIA, t_acc=1.0, tsegment=[3.0, 2.0, 4.0], dt=0.01)
    np.testing.assert_allclose(tr.q[-1], VIA[-1], atol=1e-12)


@pytest.mark.parametrize("kwargs, message", [
    (dict(qd_max=[2.0, 1.0], tsegment=[3.0, 2.0, 4.0]), "one of `qd_max`"),
    (dict(), "one of `qd_max`"),
    (dict(tsegment=[3.0, 2.0]), r"`tsegment` must have shape \(3,\)"),
    (dict(tsegment=[3.0, 0.5, 4.0]), r"`tsegment`\[1\] = 0.5 s is shorter than the blend time"),
    (dict(tsegment=[3.0, np.nan, 4.0]), "`tsegment` must be finite"),
])
def test_segment_time_arguments_are_checked(kwargs, message):
    with pytest.raises(ValueError, match=message):
        multi_segment_law(VIA, t_acc=1.0, **kwargs)


def test_the_multi_segment_law_is_not_the_toolbox_mstraj():
    """What the docstring says of the Toolbox's mstraj, measured on the Toolbox itself (the `bench` extra): its
    duration depends on its sampling step (8 s at dt = 1 s, 10.5 s at dt = 1 ms) where this law's is 9 s."""
    rtb = pytest.importorskip("roboticstoolbox")
    assert multi_segment_law(VIA, [2.0, 1.0], 1.0).t_f == pytest.approx(9.0)
    assert rtb.mstraj(VIA, dt=1.0, tacc=1.0, qdmax=[2.0, 1.0]).t[-1] == pytest.approx(8.0)
    assert rtb.mstraj(VIA, dt=1e-3, tacc=1.0, qdmax=[2.0, 1.0]).t[-1] == pytest.approx(10.499)
    import planners.timing as timing

    assert "not this law" in timing.multi_segment_law.__doc__
