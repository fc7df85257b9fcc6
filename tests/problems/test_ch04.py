"""Chapter 4 problems: the value keys of ARCHITECTURE.md and a few numbers recomputed independently."""

import numpy as np
import pytest

from problems.registry import solve


def test_value_keys_and_shapes():
    assert len(solve("4.1").values["coefficients"]) == 6
    v = solve("4.2").values
    assert {"k", "k1"} <= set(v)
    v = solve("4.5").values
    assert np.shape(v["A"]) == (3, 3) and np.shape(v["b"]) == (3,)
    v = solve("4.6").values
    keys = ["a10", "a11", "a20", "a21", "b10", "b11", "b12", "b20", "b21", "b22", "b30", "b31", "b32"]
    assert all(np.isscalar(v[k]) for k in keys)


def test_problem_4_1_coefficients_solve_the_manual_system():
    a = np.array(solve("4.1").values["coefficients"])
    tf = 2.0
    M = np.array([[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 2, 0, 0, 0],
                  [1, tf, tf**2, tf**3, tf**4, tf**5], [0, 1, 2 * tf, 3 * tf**2, 4 * tf**3, 5 * tf**4],
                  [0, 0, 2, 6 * tf, 12 * tf**2, 20 * tf**3]])
    np.testing.assert_allclose(a, np.linalg.solve(M, [1, 0, 0, 4, 0, 0]), atol=1e-12)


def test_problem_4_5_spline_values_by_dense_solve():
    v = solve("4.5").values
    x = np.linalg.solve(np.array(v["A"]), np.array(v["b"]))
    np.testing.assert_allclose(v["accelerations"], x, atol=1e-12)
    # virtual points from (S4.3)/(S4.4) with null boundary data and Δt = 1
    np.testing.assert_allclose(v["virtual_points"], [x[0] / 6, 3 + x[2] / 6], atol=1e-12)


@pytest.mark.parametrize("pid", ["4.7", "4.8"])
def test_trapezoid_on_the_path(pid):
    v = solve(pid).values
    s_f = np.sqrt(2) if pid == "4.7" else np.pi / 2
    assert v["t_c"] == pytest.approx(2.0 - s_f)
    assert v["sdd_c"] == pytest.approx(1.0 / (2.0 - s_f))


def test_problem_4_5_and_4_6_numbers_worked_by_hand():
    """Hand evaluation of the manual's formulas with the problems' data (all Δt = 1 in 4.5, Δt' = 0.2 in 4.6)."""
    v = solve("4.5").values
    # (4.4): a11 = Δt1/2 + Δt2/3 + Δt1²/(6Δt2) = 1, a22 = (Δt2 + Δt3)/3 = 2/3, a21 = Δt2/6 − Δt1²/(6Δt2) = 0, ...
    np.testing.assert_allclose(v["A"], [[1, 1 / 6, 0], [0, 2 / 3, 0], [0, 1 / 6, 1]], atol=1e-15)
    # b1 = (q3 − q_i)/Δt2 = 2, b2 = q_i/Δt2 − (1/Δt3 + 1/Δt2) q3 + q_f/Δt3 = −1, b3 = (q3 − q_f)/Δt3 = −1
    np.testing.assert_allclose(v["b"], [2, -1, -1], atol=1e-15)
    np.testing.assert_allclose(v["accelerations"], [2.25, -1.5, -0.75], atol=1e-12)
    w = solve("4.6").values
    # segment velocities 0, 1, 0.5, 0; b_k0 = q_k + Δv Δt'/8, b_k1 = mean v, b_k2 = Δv/(2Δt')
    expected = {"a10": 0, "a11": 1, "a20": 2, "a21": 0.5, "b10": 0.025, "b11": 0.5, "b12": 2.5,
                "b20": 1.9875, "b21": 0.75, "b22": -1.25, "b30": 2.9875, "b31": 0.25, "b32": -1.25}
    for key, value in expected.items():
        assert w[key] == pytest.approx(value, abs=1e-12), key
