"""The mobile-robot demos beyond the book (examples/mobile_robots.py): each passes its own checks, and the
key numbers they report."""

import numpy as np
import pytest

from examples import mobile_robots as mr


@pytest.mark.parametrize("name", ["tracking_comparison", "parallel_parking", "wheel_saturation", "car_shortest_paths"])
def test_mobile_robot_demos_pass_their_checks(name):
    sol = getattr(mr, name)()
    failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
    assert sol.checks and not failed, failed
    assert sol.figures and all(fig.axes[0].get_xlabel() for fig in sol.figures)


def test_tracking_comparison_table_has_the_four_metrics():
    table = mr.tracking_comparison(t_end=20.0).values["table"]
    assert len(table) == 3
    for row in table.values():
        assert set(row) == {"settling_time", "peak_abs_v", "peak_abs_omega", "final_error"}


def test_mobile_manipulator_drives_one_metre_without_slipping_and_holds_the_end_effector():
    sol = mr.mobile_manipulator_hold()
    assert sol.passed, [(c.name, c.detail) for c in sol.checks if not c.passed]
    v = sol.values
    assert (v["nq"], v["nv"], v["configuration_space_dimension"]) == (10, 9, 9)
    assert v["max_lateral_velocity"] < 1e-9                 # every sampling interval
    assert v["max_end_effector_error"] < 1e-3
    assert abs(v["path_length"] - 1.0) < 2e-3


def test_lateral_velocity_measure_sees_a_sliding_base():
    """The no-slip measure can fail: a base moving sideways at 0.1 m/s is reported at 0.1 m/s."""
    t = np.linspace(0.0, 1.0, 101)
    base = np.c_[-0.1 * t * np.sin(0.15), 0.1 * t * np.cos(0.15), np.full_like(t, 0.15)]   # heading 0.15 rad
    np.testing.assert_allclose(mr.lateral_velocities(t, base), 0.1, atol=1e-12)
