"""Chapter 9: registration, the required value keys, and the Panda companion (not a registered problem)."""

import matplotlib.pyplot as plt
import numpy as np

from problems.ch09 import panda_wall_contact
from problems.registry import all_problems, get


def test_problems_9_1_to_9_11_are_registered():
    kinds = {p.id: p.kind for p in all_problems()}
    for i in range(1, 12):
        assert f"9.{i}" in kinds
    assert kinds["9.3"] == kinds["9.10"] == "simulation"


def test_required_value_keys_of_9_3():
    sol = get("9.3").solve()
    plt.close("all")
    np.testing.assert_allclose(sol.values["f_final"], [0.0, -250.0], atol=0.5)
    np.testing.assert_allclose(sol.values["position_error_final"], [0.0, -0.05], atol=5e-4)


def test_panda_on_a_stepped_wall_with_friction():
    sol = panda_wall_contact()
    try:
        failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
        assert not failed, failed
        v = sol.values
        assert v["hybrid_force_error_sliding"] < 0.5
        assert 2.6 < v["hybrid_contact_regained_at"] < 2.9 and 1.9 < v["hybrid_contact_lost_at"] < 2.1
        assert abs(v["impedance_force_after_step"] - 10.48) < 0.1
        assert abs(v["hybrid_friction_force_sliding"] - 6.0) < 0.1
        assert len(sol.figures) == 2
    finally:
        for fig in sol.figures:
            plt.close(fig)
