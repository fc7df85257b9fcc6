"""Chapters 5, 6 and 8.1–8.9: the value keys ARCHITECTURE.md requires, and the designed numbers."""

import matplotlib.pyplot as plt
import numpy as np
import pytest

from problems.registry import solve

KEYS = {"5.3": ["K_I", "T_I"], "5.6": ["f_c", "mu_c"], "5.7": ["T_bc", "lambda", "X_I", "Y_I"],
        "8.4": ["K_P", "poles", "X_R", "T_R"], "8.5": ["K_P", "K_V", "poles", "X_R", "T_R"],
        "8.6": ["K_P", "K_V", "K_A", "X_R", "omega_3"]}


@pytest.mark.parametrize("pid", sorted(KEYS))
def test_required_value_keys(pid):
    sol = solve(pid)
    for fig in sol.figures:
        plt.close(fig)
    assert set(KEYS[pid]) <= set(sol.values), f"{pid}: missing {set(KEYS[pid]) - set(sol.values)}"


def test_designs_of_8_5_and_8_6_follow_from_the_specifications():
    v5, v6 = solve("8.5").values, solve("8.6").values
    # ζ = 0.4, ω_n = 20, k_m = 2, unit transducers: K_P = ω_n/(2ζ), K_V = 2ζω_n/k_m; X_R = 400 ⇒ K_A = 1/2
    assert (v5["K_P"], v5["K_V"], v5["X_R"]) == pytest.approx((25.0, 8.0, 200.0))
    assert (v6["K_P"], v6["K_V"], v6["K_A"]) == pytest.approx((25.0, 32.0, 0.5))
    assert v6["omega_3"] == pytest.approx(27.49, abs=0.01)
    assert np.allclose(np.abs(np.asarray(v5["poles"])), 20.0)
