"""Chapter 12 problems: key numbers recomputed independently, and checks that can fail."""

import matplotlib.pyplot as plt
import numpy as np
import pytest

import problems.ch12 as ch12
from planners.configuration_space import euclidean_distance
from problems.registry import solve


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def test_problem_12_1_dimension_is_counted_from_the_model():
    v = solve("12.1").values
    assert v["dim_C"] == 9 and v["nq"] == 10 and v["structure"] == "R^2 x SO(2)^7"


def test_problem_12_2_erratum_numbers():
    v = solve("12.2").values
    assert v["counterexample_d2"] == pytest.approx(1.2 * np.pi) and v["counterexample_d3"] == pytest.approx(0.8 * np.pi)
    assert v["counterexample_d2"] < np.sqrt(2) * np.pi


def test_problem_12_2_check_fails_with_the_euclidean_distance(monkeypatch):
    monkeypatch.setattr(ch12, "torus_distance", lambda a, b, angular=None: euclidean_distance(a, b))
    sol = ch12.problem_12_2()
    assert not sol.passed


def test_problem_12_6_numbers():
    v = solve("12.6").values
    assert v["clearance_midpoint_path"] == 0.0
    assert v["clearance_fixed_path"] == pytest.approx(np.sqrt(1.25))
    assert v["visibility_length"] == pytest.approx(2 * np.hypot(0.5, 2))


def test_problem_12_10_and_12_11_stationary_points():
    v = solve("12.10").values
    np.testing.assert_allclose(v["eig_single"], [-3.0, 33.0], atol=1e-9)
    assert v["minimum_two_discs"][0] == pytest.approx(3.669, abs=1e-3) and v["U_minimum"] == pytest.approx(7.4399, abs=1e-4)
    s = solve("12.11").values["saddles"]
    # on the rays through the centres, beyond distance D + ρ
    assert np.allclose(np.cross(s, [[3, 0], [0, 4], [-3, -3]]), 0)


def test_problem_12_13_lengths():
    v = solve("12.13").values
    assert v["length_2adj"] < v["length_1adj"] <= np.sqrt(2) * v["length_2adj"]
    assert v["path_1adj"][0].tolist() == [1, 1] and v["path_2adj"][-1].tolist() == [7, 7]


def test_problem_12_13_check_fails_on_a_wrong_wavefront(monkeypatch):
    from planners.potentials import wavefront

    def wrong(occ, goal, adj):
        V = wavefront(occ, goal, adj)
        V[np.isfinite(V) & (V > 5)] += 0.5      # a miscounted step
        return V

    monkeypatch.setattr(ch12, "wavefront", wrong)
    assert not ch12.problem_12_13().passed
