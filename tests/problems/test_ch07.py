"""Extra assertions on the chapter-7 problems beyond their own checks."""

import numpy as np
import pytest

from problems.ch07 import example_7_2_trajectories
from problems.registry import solve
from rigid_body.dynamics import inverse_dynamics
from rigid_body.regressor import minimum_parameters, two_link_regressor
from rigid_body.robots import load
from rigid_body.book_robots import planar_2r


def test_example_7_2_trajectories_start_and_stop_at_rest():
    for name, (t, q, qd, qdd) in example_7_2_trajectories(dt=2e-3).items():
        np.testing.assert_allclose(qd[0], 0.0, atol=1e-12, err_msg=name)
        np.testing.assert_allclose(qd[-1], 0.0, atol=1e-9, err_msg=name)
        np.testing.assert_allclose(qdd[-1], 0.0, atol=1e-9, err_msg=name)
        # q̇ is the time derivative of q (central differences), q̈ of q̇ away from the switching instants
        np.testing.assert_allclose(np.gradient(q, t, axis=0)[1:-1], qd[1:-1], atol=0.05, err_msg=name)
    t, q, qd, _ = example_7_2_trajectories()["tra_1"]
    # triangular profile: peak velocity 2Δq/T = 2π rad/s at t = 0.25 s
    assert abs(np.abs(qd).max() - 2 * np.pi) < 1e-9
    assert abs(t[np.argmax(np.abs(qd[:, 0]))] - 0.25) < 1e-3


def test_mixed_parameter_bookkeeping_is_detected():
    """The manual's regressor with the companion's π' (I_m2 counted twice) must not match the model."""
    rng = np.random.default_rng(0)
    robot = load("planar_2r")
    q, qd, qdd = rng.normal(size=(3, 2))
    wrong = two_link_regressor(q, qd, qdd) @ minimum_parameters(planar_2r().links, convention="companion")
    assert np.abs(wrong - inverse_dynamics(robot, q, qd, qdd)).max() > 1e-4


@pytest.mark.parametrize("pid", ["7.4", "7.11"])
def test_values_recorded(pid):
    sol = solve(pid)
    if pid == "7.4":
        np.testing.assert_allclose(sol.values["pi_prime"], [80, 97.5, 25, -2.5, 0.01], atol=1e-12)
        assert sol.values["regressor_condition_number"] > 1
    else:
        assert 1.78 < sol.values["q2_peak"] < 1.80
