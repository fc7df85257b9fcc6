"""Chapter 9: registration and the required value keys."""

import numpy as np

from problems.registry import all_problems, get


def test_problems_9_1_to_9_11_are_registered():
    kinds = {p.id: p.kind for p in all_problems()}
    for i in range(1, 12):
        assert f"9.{i}" in kinds
    assert kinds["9.3"] == kinds["9.10"] == "simulation"


def test_required_value_keys_of_9_3():
    sol = get("9.3").solve()
    np.testing.assert_allclose(sol.values["f_final"], [0.0, -250.0], atol=0.5)
    np.testing.assert_allclose(sol.values["position_error_final"], [0.0, -0.05], atol=5e-4)
