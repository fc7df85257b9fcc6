"""TOPP-RA timing of a fixed path: limits hold on the fine grid (Pinocchio's RNEA), and the free
minimum-time motion is no slower than the fixed path."""

import numpy as np
import pinocchio as pin
import pytest

from planners.optimization import JointLimits, OptimizationOptions, minimum_time_trajectory
from planners.time_optimal import time_optimal_path
from rigid_body.robots import load


@pytest.fixture(scope="module")
def setting():
    arm = load("planar_2r")
    limits = JointLimits.from_robot(arm, qdd_max=[20.0, 20.0], qd_max=[3.0, 3.0], tau_max=[3000.0, 1500.0])
    return arm, limits, np.array([0.0, 0.0]), np.array([1.0, -0.5])


def test_fixed_path_timing_respects_limits_and_is_slower_than_free(setting):
    arm, limits, q_i, q_f = setting
    result = time_optimal_path(arm, np.linspace(q_i, q_f, 5), limits)
    np.testing.assert_allclose(result.q[0], q_i, atol=1e-12)
    np.testing.assert_allclose(result.q[-1], q_f, atol=1e-12)
    data = arm.model.createData()
    tau = np.array([pin.rnea(arm.model, data, q, v, a) for q, v, a in zip(result.q, result.qd, result.qdd)])
    assert np.max(np.abs(tau) / limits.tau_max) <= 1.0 + 1e-6
    assert np.max(np.abs(result.qd) / limits.qd_max) <= 1.0 + 1e-6
    assert np.max(np.abs(result.qdd) / limits.qdd_max) <= 1.0 + 1e-6
    assert max(result.ratios.values()) > 0.99                      # some limit is active: time-optimal
    free = minimum_time_trajectory(arm, q_i, q_f, limits, OptimizationOptions(nodes=12))
    assert free.t_f <= result.t_f * (1 + 1e-3)
    # the time law is consistent: q̇ integrates to q (trapezoidal rule on the fine grid)
    increments = 0.5 * (result.qd[1:] + result.qd[:-1]) * np.diff(result.t)[:, None]
    np.testing.assert_allclose(q_i + increments.sum(axis=0), q_f, atol=1e-3)


def test_bad_waypoints_are_refused(setting):
    arm, limits, *_ = setting
    with pytest.raises(ValueError, match="waypoints"):
        time_optimal_path(arm, np.zeros((1, 2)), limits)
    with pytest.raises(ValueError, match="waypoints"):
        time_optimal_path(arm, np.full((3, 2), np.nan), limits)
