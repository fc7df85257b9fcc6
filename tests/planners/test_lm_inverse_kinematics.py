"""Levenberg–Marquardt IK on the Panda: 100 seeded random reachable targets from random starts."""

import numpy as np
import pinocchio as pin
import pytest

from planners.inverse_kinematics import LMIK, LMIKOptions, solve_ik_lm
from rigid_body.robots import load


@pytest.fixture(scope="module")
def panda():
    return load("panda")


def _fk(robot, q):
    """Independent check of a returned q: Pinocchio's forward kinematics in a fresh data."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, q)
    return data.oMf[robot.ee_frame].homogeneous.copy()


def test_lm_ik_solves_random_reachable_panda_targets(panda):
    rng = np.random.default_rng(2024)
    ik = LMIK(panda)
    solved = false_successes = 0
    for _ in range(100):
        T_d = _fk(panda, panda.random_configuration(rng))
        result = ik.solve(T_d, panda.random_configuration(rng), rng=rng)
        if not result.success:
            continue
        solved += 1
        T = _fk(panda, result.q)
        position = np.linalg.norm(T[:3, 3] - T_d[:3, 3])
        angle = np.arccos(np.clip((np.trace(T[:3, :3].T @ T_d[:3, :3]) - 1) / 2, -1, 1))
        inside = np.all(result.q >= panda.lower) and np.all(result.q <= panda.upper)
        false_successes += not (position < 1e-6 and angle < 1e-6 and inside)
    assert solved >= 99
    assert false_successes == 0


def test_lm_ik_reports_an_unreachable_pose(panda):
    T_far = np.eye(4)
    T_far[:3, 3] = [3.0, 0.0, 0.5]                         # beyond the Panda's reach (≈ 0.86 m)
    result = solve_ik_lm(panda, T_far, options=LMIKOptions(restarts=3), rng=np.random.default_rng(0))
    assert not result.success and result.residual > 1.0
    assert np.all(result.q >= panda.lower) and np.all(result.q <= panda.upper)


def test_lm_ik_rejects_bad_input(panda):
    with pytest.raises(ValueError, match="T_d"):
        LMIK(panda).solve(np.full((4, 4), np.nan))
    with pytest.raises(ValueError, match="q0"):
        LMIK(panda).solve(np.eye(4), q0=np.zeros(3))
    with pytest.raises(ValueError, match="LMIKOptions"):
        LMIKOptions(tol=0.0)


@pytest.mark.parametrize("kwargs", [{"tol": -1e-6}, {"max_iterations": 0}, {"restarts": -1}, {"damping": 0.0},
                                    {"stall": 0}])
def test_lm_ik_options_are_checked_one_by_one(kwargs):
    """Each condition alone rejects its bad value (the others at their defaults)."""
    with pytest.raises(ValueError, match="LMIKOptions"):
        LMIKOptions(**kwargs)
