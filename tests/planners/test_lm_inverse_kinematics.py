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


def test_solve_ik_notes_a_start_outside_the_limits_and_prints_in_one_line():
    import re

    from planners.inverse_kinematics import solve_ik
    from rigid_body.kinematics import direct_kinematics
    from rigid_body.robots import load

    panda = load("panda")
    q0 = panda.configurations["ready"].copy()
    q0[3] = 1.0                                        # q4 ≤ −0.0698 rad on the Panda
    res = solve_ik(panda, direct_kinematics(panda, panda.configurations["ready"]), q0)
    assert res.success and "`q0` was outside the joint limits at q[3]" in res.message
    text = repr(res)
    assert "\n" not in text and text.startswith("IKResult(success=True, residual=")
    assert not re.search(r"-0\.(?!\d)", text)        # no "-0." for a zero joint


def test_a_whole_pose_on_a_three_joint_arm_points_to_the_position_task():
    import numpy as np

    from planners.inverse_kinematics import solve_ik
    from rigid_body.kinematics import direct_kinematics
    from rigid_body.robots import load

    arm = load("anthropomorphic")
    T = direct_kinematics(arm, arm.configurations["bent"])
    T[:3, :3] = np.eye(3)                              # an orientation the 3-joint arm cannot take there
    res = solve_ik(arm, T)
    assert not res.success and "TaskSpace(rows=(0, 1, 2))" in res.message
