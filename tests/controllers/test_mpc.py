"""Model predictive control in the simulation loop (controllers/mpc.py)."""

import numpy as np
import pytest

from controllers.compiled import fast_backend
from controllers.mpc import MPCOptions, ModelPredictiveControl
from controllers.plants import ArmPlant
from controllers.simulation import SimulationDiverged, simulate
from planners.optimal_control import OptimalControlProblem, StageCost
from rigid_body.robots import load

TARGET = np.array([0.3, -0.2])


@pytest.fixture(scope="module")
def problem():
    arm = load("planar_2r")
    return OptimalControlProblem(arm, horizon=10, dt=0.02, running=StageCost(q=1e3, qd=1.0, tau=1e-6),
                                 terminal=StageCost(q=1e4, qd=1e2), tau_max=[3000.0, 1500.0])


def run(problem, options=None, t_f=0.4, Ts=0.02, **kw):
    mpc = ModelPredictiveControl(problem, reference=TARGET, options=options, **kw)
    plant = ArmPlant(problem.robot, tau_max=problem.tau_max)
    return mpc, simulate(plant, mpc, (0.0, t_f), np.zeros(4), h=1e-3, Ts=Ts)


def test_regulation_within_the_torque_limits_and_logs(problem):
    mpc, res = run(problem)
    assert np.abs(res.q[-1] - TARGET).max() < 1e-2
    assert np.all(np.abs(res.u) <= problem.tau_max + 1e-9)
    assert np.max(np.abs(res.u[:3]) / problem.tau_max) > 0.999          # the plan uses the whole box at first
    n_samples = len(res.t)
    assert res["q_pred"].shape == (n_samples, problem.horizon + 1, 2)
    np.testing.assert_allclose(res["q_pred"][:, 0], res.q, atol=1e-12)   # each plan starts at the measured state
    for name in ("solve_time", "iterations", "deadline_met", "failed", "converged", "plan_success", "cost"):
        assert res[name].shape == (n_samples,)
    assert res["failed"].sum() == 0 and res["converged"].all() and res["plan_success"].all()
    assert not mpc._plan.verified and np.isnan(mpc._plan.kkt)           # real time: the solver's own account
    assert "(not verified)" in repr(mpc._plan)
    assert np.all(res["iterations"] >= 1)


def test_faster_loop_holds_the_torque_between_samples(problem):
    _, res = run(problem, Ts=0.005, t_f=0.1)
    np.testing.assert_array_equal(res.u[1:4], np.repeat(res.u[:1], 3, axis=0))
    np.testing.assert_array_equal(res["q_pred"][1:4], np.repeat(res["q_pred"][:1], 3, axis=0))
    assert not np.array_equal(res["q_pred"][4], res["q_pred"][0])        # a new plan at the next sample (20 ms)
    changes = np.flatnonzero(np.any(res.u[1:] != res.u[:-1], axis=1)) + 1
    assert changes.size and np.all(changes % 4 == 0)                     # the torque changes only at samples


def test_real_time_iteration_takes_one_sqp_step(problem):
    _, res = run(problem, MPCOptions(real_time_iteration=True))
    assert np.all(res["iterations"] == 1)
    assert np.abs(res.q[-1] - TARGET).max() < 2e-2


def test_computation_delay_applies_the_torque_one_sample_late(problem):
    _, res = run(problem, MPCOptions(delay=True))
    np.testing.assert_allclose(res.u[1:], res["tau_plan"][:-1])
    assert np.abs(res.q[-1] - TARGET).max() < 2e-2


def test_a_failed_solve_keeps_the_previous_plan(problem):
    mpc = ModelPredictiveControl(problem, reference=TARGET)
    solve = mpc.solver.solve
    plans = []

    def flaky(*args, **kw):
        if len(plans) in (3, 4):                        # the solves of samples 3 and 4 fail
            plans.append(None)
            raise RuntimeError("solver fault")
        plans.append(solve(*args, **kw))
        return plans[-1]

    mpc.solver.solve = flaky
    plant = ArmPlant(problem.robot, tau_max=problem.tau_max)
    res = simulate(plant, mpc, (0.0, 0.3), np.zeros(4), h=1e-3, Ts=0.02)
    assert res["failed"][3:5].tolist() == [1.0, 1.0] and res["failed"].sum() == 2
    assert np.all(np.isfinite(res.u))
    # the fallback is the last good plan (made at sample 2) followed on: its torques 1 and 2
    np.testing.assert_array_equal(res.u[3], plans[2].u[1])
    np.testing.assert_array_equal(res.u[4], plans[2].u[2])
    np.testing.assert_array_equal(res.u[5], plans[5].u[0])             # a good solve again
    assert np.abs(res.q[-1] - TARGET).max() < 5e-2


def test_the_compiled_loop_refuses_it_through_the_generic_path(problem):
    mpc = ModelPredictiveControl(problem, reference=TARGET)
    assert fast_backend(mpc) == "python"
    plant = ArmPlant(problem.robot, tau_max=problem.tau_max)
    with pytest.raises(ValueError, match="ModelPredictiveControl has no symbolic"):
        simulate(plant, mpc, (0.0, 0.1), np.zeros(4), h=1e-3, Ts=0.02, backend="casadi")


def test_divergence_names_the_mpc(problem):
    mpc = ModelPredictiveControl(problem, reference=TARGET)
    plant = ArmPlant(problem.robot, tau_max=problem.tau_max)
    with pytest.raises(SimulationDiverged, match="ModelPredictiveControl"):
        simulate(plant, mpc, (0.0, 0.3), np.zeros(4), h=1e-3, Ts=0.02, bound=0.1)


def test_bad_input(problem):
    with pytest.raises(ValueError, match="problem"):
        ModelPredictiveControl("not a problem")
    with pytest.raises(ValueError, match="max_iter"):
        MPCOptions(max_iter=0)
    with pytest.raises(ValueError, match="time_limit"):
        MPCOptions(time_limit=-1.0)
    with pytest.raises(ValueError, match="time_limit"):
        MPCOptions(time_limit=np.nan)
    with pytest.raises(ValueError, match="qp_solver"):
        MPCOptions(qp_solver="quadprog")
    posed = OptimalControlProblem(problem.robot, 5, 0.02, terminal=StageCost(position=1.0))
    with pytest.raises(ValueError, match="target"):
        ModelPredictiveControl(posed)
    with pytest.raises(ValueError, match="target"):
        ModelPredictiveControl(posed, target=np.ones((4, 4)))
    with pytest.raises(ValueError, match="reference"):
        ModelPredictiveControl(problem, reference=[0.0, np.nan])


def test_a_measured_state_beyond_a_hard_limit_is_a_failed_sample(problem):
    """Hard speed limits and a measured state beyond one: no plan can start there (the solver would refuse x0); the
    loop goes on with the fallback torque and logs the failed samples instead of stopping."""
    hard = OptimalControlProblem(problem.robot, problem.horizon, problem.dt, problem.running, problem.terminal,
                                 tau_max=problem.tau_max, qd_max=[1.0, 1.0], state_limits="hard")
    mpc = ModelPredictiveControl(hard, reference=TARGET)
    plant = ArmPlant(problem.robot, tau_max=problem.tau_max)
    res = simulate(plant, mpc, (0.0, 0.1), np.array([0.0, 0.0, 1.5, 0.0]), h=1e-3, Ts=0.02)
    assert np.all(res["failed"] == 1.0) and mpc.failures == mpc.samples == len(res.t)
    assert np.all(np.isfinite(res.u)) and np.all(np.abs(res.u) <= problem.tau_max + 1e-9)
    with pytest.raises(ValueError, match="x0"):                          # the solver alone refuses that start
        mpc.solver.solve(np.array([0.0, 0.0, 1.5, 0.0]))
