"""The optimal-control demo beyond the book: computed torque vs MPC on the two-link arm beyond its torque limits."""

import numpy as np

from examples.optimal_control import two_link_tracking


def test_two_link_mpc_respects_the_limits_and_tracks_better_than_computed_torque():
    sol = two_link_tracking(speed=1.2)
    failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
    assert not failed, failed
    v = sol.values
    assert v["commanded_over_limit MPC"] == 0.0 and v["commanded_over_limit computed torque (8.57)"] > 0.5
    assert v["max_error MPC"] < 0.6 * v["max_error computed torque (8.57)"]
    assert v["final_error MPC"] < 1e-3 < v["final_error computed torque (8.57)"]
    assert v["mpc_failed_solves"] == 0
    assert len(sol.figures) == 1


def test_an_unknown_payload_degrades_both_but_mpc_stays_within_the_limits():
    sol = two_link_tracking(speed=1.2, payload=10.0)
    failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
    assert not failed, failed
    assert np.isfinite(sol.values["max_error MPC"])
