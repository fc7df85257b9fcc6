"""Chapter 11: registration, the JSON keys of 11.13, and the key numbers of the simulations."""

import matplotlib.pyplot as plt
import numpy as np
import pytest

from problems.registry import all_problems, solve


def _solve(pid):
    sol = solve(pid)
    for fig in sol.figures:
        plt.close(fig)
    return sol


def test_problems_11_1_to_11_18_are_registered():
    ids = {p.id for p in all_problems()}
    assert {f"11.{i}" for i in range(1, 19)} <= ids


def test_11_13_values_and_keys():
    v = _solve("11.13").values
    assert (v["alpha_x"], v["beta_x"], v["alpha_y"], v["beta_y"]) == pytest.approx((-6.0, 1.0, -2.0, 0.0))
    assert v["max_omega"] == pytest.approx(10.0, abs=1e-6)
    assert v["max_v"] == pytest.approx(3.0275, abs=1e-3)


def test_11_16_backward_motion():
    sol = _solve("11.16")
    assert sol.passed and len(sol.figures) == 2
    assert sol.values["max_v_modified"] <= 0 < sol.values["max_v_original"]


def test_11_18_threshold_between_tenth_and_fifth_of_a_second():
    sol = _solve("11.18")
    assert sol.passed and len(sol.figures) == 3
    assert 0.1 < sol.values["Ts_threshold"] < 0.2
    assert np.all(np.diff(sol.values["final_distance_grid"][:7]) > 0)


@pytest.mark.parametrize("name", ["tracking_comparison", "parallel_parking", "wheel_saturation", "car_shortest_paths"])
def test_beyond_the_book_companions_pass_their_checks(name):
    import problems.ch11 as ch11

    sol = getattr(ch11, name)()
    try:
        failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
        assert sol.checks and not failed, failed
        assert sol.figures
    finally:
        for fig in sol.figures:
            plt.close(fig)


def test_tracking_comparison_table_has_the_four_metrics():
    import problems.ch11 as ch11

    sol = ch11.tracking_comparison(t_end=20.0)
    for fig in sol.figures:
        plt.close(fig)
    table = sol.values["table"]
    assert len(table) == 3
    for row in table.values():
        assert set(row) == {"settling_time", "peak_abs_v", "peak_abs_omega", "final_error"}
