"""Chapter 11: registration, the JSON keys of 11.13, and the key numbers of the simulations."""

import ast
from pathlib import Path

import numpy as np
import pytest

from problems.registry import all_problems, solve


def _solve(pid):
    return solve(pid)   # bare Figures (problems.common.subplots): nothing to close


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
    """Odometry at T_s feeding a regulator at T_s/n (multi-rate) gives the single-rate loop's numbers: the static
    law on a held estimate outputs a held command. T_s* = 0.1259 s."""
    sol = _solve("11.18")
    assert sol.passed and len(sol.figures) == 3
    assert sol.values["Ts_threshold"] == pytest.approx(0.12593, abs=1e-4)
    assert np.all(np.diff(sol.values["final_distance_grid"][:7]) > 0)


def test_chapter_11_does_not_import_the_examples():
    tree = ast.parse(Path(__file__).parents[2].joinpath("problems", "ch11.py").read_text())
    modules = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    modules |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    assert not any(m and m.split(".")[0] == "examples" for m in modules)
