"""Extra assertions on the chapter-3 problems beyond their own checks."""

import numpy as np
import pytest

from problems.registry import all_problems, solve


def test_all_chapter_3_problems_registered():
    ids = {p.id for p in all_problems() if p.id.startswith("3.")}
    assert ids == {f"3.{i}" for i in range(1, 24)}


def test_3_21_value_keys_and_figures():
    sol = solve("3.21")
    assert sol.passed
    assert {"min_distance_unconstrained", "min_distance_constrained", "final_error"} <= set(sol.values)
    assert sol.values["min_distance_unconstrained"] < 0 < sol.values["min_distance_constrained"]
    assert sol.values["final_error"] < 1e-6
    assert len(sol.figures) == 2 and all(f._suptitle is not None for f in sol.figures)


def test_3_22_transpose_errors_larger_than_inverse():
    sol = solve("3.22")
    assert sol.passed and len(sol.figures) == 2
    assert sol.values["max_position_error_transpose"] > 100 * sol.values["max_position_error_inverse"]


@pytest.mark.parametrize("pid", ["3.4", "3.9", "3.10", "3.17"])
def test_derivation_checks_can_fail(pid, monkeypatch):
    """Perturbing the library the check relies on must make the problem fail (the checks are live)."""
    import problems.ch03 as ch03

    targets = {"3.4": "geometric_jacobian", "3.9": "planar_arm_obstacle_distance",
               "3.10": "damped_least_squares_inverse", "3.17": "orientation_error_matrix"}
    name = targets[pid]
    original = getattr(ch03, name)

    def perturbed(*args, **kwargs):
        out = original(*args, **kwargs)
        if hasattr(out, "distance"):
            return type(out)(out.distance + 1e-3, out.link, out.s, out.point)
        return np.asarray(out) * (1 + 1e-3)

    monkeypatch.setattr(ch03, name, perturbed)
    assert not solve(pid).passed
