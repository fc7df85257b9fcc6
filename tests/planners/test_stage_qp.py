"""The step QP's solvers (planners/stage_qp.py): HPIPM's library is checked before use, and when it is missing,
unloadable, of another interface or solving a test QP wrongly, the optimal control solver falls back to the sparse
QP (PIQP through CasADi) with one warning — or, asked for HPIPM, raises an error naming what is missing. Whatever
solves the QPs, success is still the independent check's (KKT residual, defects, hard limits)."""

import json
import subprocess
import warnings
from pathlib import Path

import numpy as np
import pytest

import planners.stage_qp as stage_qp
from controllers.mpc import MPCOptions, ModelPredictiveControl
from controllers.plants import ArmPlant
from controllers.simulation import simulate
from planners.optimal_control import OptimalControlOptions, OptimalControlProblem, OptimalControlSolver, StageCost
from rigid_body.robots import load


@pytest.fixture(scope="module")
def problems():
    arm = load("planar_2r")
    return {limits: OptimalControlProblem(arm, horizon=20, dt=0.02, running=StageCost(q=1e3, qd=1.0, tau=1e-6),
                                          terminal=StageCost(q=1e4, qd=1e2), tau_max=[3000.0, 1500.0],
                                          qd_max=[2.0, 2.0], state_limits=limits)
            for limits in ("hard", "soft")}


@pytest.fixture
def fresh(monkeypatch):
    """A process state in which HPIPM's library has not been loaded or refused yet, nor the fallback announced."""
    monkeypatch.setattr(stage_qp, "_HPIPM", None)
    monkeypatch.setattr(stage_qp, "_WARNED", False)
    return monkeypatch


@pytest.mark.parametrize("limits", ["hard", "soft"])
@pytest.mark.parametrize("solver", ["piqp", "proxsuite"])
def test_the_fallback_solves_the_problem_hpipm_solves(problems, limits, solver):
    """The same optimum (torque box and speed limits active) with every QP solver, each verified by the KKT check."""
    problem = problems[limits]
    x0, q_ref = np.zeros(4), [1.3, -1.2]
    ref = OptimalControlSolver(problem, OptimalControlOptions(qp_solver="hpipm")).solve(x0, q_ref=q_ref)
    fallback = OptimalControlSolver(problem, OptimalControlOptions(qp_solver=solver))
    res = fallback.solve(x0, q_ref=q_ref)
    assert fallback.qp_solver == solver
    assert ref.success and res.success, (ref.message, res.message)
    assert res.kkt <= 1e-6 and res.ratios["tau"] == pytest.approx(1.0, abs=1e-9)
    assert res.ratios["qd"] == pytest.approx(1.0, abs=1e-6)             # a speed limit binds
    assert res.cost == pytest.approx(ref.cost, rel=1e-8)
    np.testing.assert_allclose(res.x, ref.x, atol=1e-6)


def missing(monkeypatch, tmp_path):
    monkeypatch.setenv("RMPC_HPIPM_LIBRARY", str(tmp_path / "libhpipm.so"))


def another_library(monkeypatch, tmp_path):
    """A loadable shared library that is not HPIPM (CasADi's own extension module)."""
    import casadi
    monkeypatch.setenv("RMPC_HPIPM_LIBRARY", str(Path(casadi.__file__).parent / "_casadi.so"))


def not_a_library(monkeypatch, tmp_path):
    (tmp_path / "libhpipm.so").write_bytes(b"\x7fELF but not really")
    monkeypatch.setenv("RMPC_HPIPM_LIBRARY", str(tmp_path / "libhpipm.so"))


@pytest.mark.parametrize("break_it, why", [(missing, "not a file"), (another_library, "lacks d_ocp_qp"),
                                           (not_a_library, "cannot be loaded")])
def test_a_missing_or_foreign_library_falls_back_with_one_warning(problems, fresh, tmp_path, break_it, why):
    break_it(fresh, tmp_path)
    problem = problems["hard"]
    with pytest.warns(stage_qp.QPFallbackWarning, match=why) as caught:
        solver = OptimalControlSolver(problem)
    assert len(caught) == 1 and "piqp" in str(caught[0].message)
    assert solver.qp_solver == "piqp"
    res = solver.solve(np.zeros(4), q_ref=[0.3, -0.2])
    assert res.success and res.kkt <= 1e-6, res.message
    with warnings.catch_warnings():                                     # once per process
        warnings.simplefilter("error")
        OptimalControlSolver(problem)
    with pytest.raises(stage_qp.QPUnavailable, match=why):              # asked for HPIPM: the reason, no fallback
        OptimalControlSolver(problem, OptimalControlOptions(qp_solver="hpipm"))


def test_a_library_that_crashes_or_answers_wrongly_on_the_test_qp_is_refused(fresh):
    """The test QP runs in another process: a crash there (an ABI mismatch) or a wrong solution is a refusal with
    the reason, never a crash of the caller or a silent wrong step."""
    real_run = subprocess.run
    fresh.setattr(stage_qp.subprocess, "run",
                  lambda *a, **k: subprocess.CompletedProcess(a[0], -11, "", ""))
    with pytest.raises(stage_qp.QPUnavailable, match="crashed \\(signal 11\\) on a test QP"):
        stage_qp.load_hpipm()

    def wrong(*args, **kwargs):                                         # the real library's answer, one sign flipped
        out = real_run(*args, **kwargs)
        cases = json.loads(out.stdout.strip().splitlines()[-1])
        cases[1]["pi"][0][0] *= -1.0
        return subprocess.CompletedProcess(out.args, 0, json.dumps(cases), "")
    fresh.setattr(stage_qp, "_HPIPM", None)
    fresh.setattr(stage_qp.subprocess, "run", wrong)
    with pytest.raises(stage_qp.QPUnavailable, match="solved a test QP wrongly"):
        stage_qp.load_hpipm()
    with pytest.warns(stage_qp.QPFallbackWarning, match="solved a test QP wrongly"):
        qp = stage_qp.stage_qp(3, 2, 1, np.array([0]), False, OptimalControlOptions())
    assert qp.name == "piqp"


def test_the_installed_library_passes_its_checks(fresh):
    """Here (CasADi >= 3.8 with its libhpipm) HPIPM is used: the test QPs agree with the fallback's."""
    lib = stage_qp.load_hpipm()
    assert hasattr(lib, "d_ocp_qp_ipm_solve")
    assert stage_qp.stage_qp(3, 2, 1, np.array([0]), True, OptimalControlOptions()).name == "HPIPM"


def test_unknown_qp_solver_is_refused():
    with pytest.raises(ValueError, match="qp_solver"):
        OptimalControlOptions(qp_solver="qpoases")


def test_mpc_runs_on_the_fallback(problems):
    problem = problems["hard"]
    mpc = ModelPredictiveControl(problem, reference=[0.3, -0.2], options=MPCOptions(qp_solver="piqp"))
    assert mpc.solver.qp_solver == "piqp"
    res = simulate(ArmPlant(problem.robot, tau_max=problem.tau_max), mpc, (0.0, 0.3), np.zeros(4), h=1e-3, Ts=0.02)
    assert int(res["failed"].sum()) == 0 and np.all(np.isfinite(res.u))
