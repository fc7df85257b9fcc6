"""Optimal control and MPC: rmpc's SQP against Crocoddyl's box-FDDP, MPC solve times at 100 Hz, MPC vs computed
torque under saturation.

(a) The Panda reach of :func:`examples.optimal_control.reach_problem` (N = 50, dt = 10 ms, RK4, the same costs, hard
    torque box, joint limits inactive in both) solved from the same initial guess (the start held, gravity torques)
    by :class:`planners.optimal_control.OptimalControlSolver` and by Crocoddyl 3's ``SolverBoxFDDP`` (single thread,
    as rmpc; its solves interleaved with rmpc's, the least time of each) in its own
    environment (``benchmarks/crocoddyl_reach.py``: set ``RMPC_CROCODDYL_PYTHON`` to that environment's python, or
    let it be found at /tmp/croc/bin/python). Solve-time ratio at equal optimal cost (±1 %); target ≤ 2.
(b) MPC on the Panda reach at 100 Hz with a 0.5 s horizon, in real-time-iteration mode (one SQP step per sample,
    warm-started by shifting: the standard of real-time MPC) and with up to 5 SQP iterations per sample: the median
    and worst time of a sample's whole computation (references, SQP, checks), the share of missed deadlines (time
    > T_s), and the processor time per sample with its two largest parts (the wall time of a loaded machine includes
    waiting for a core; the processor time is what a sample takes on an idle one).
(c) MPC vs inverse dynamics control (8.57) on the two-link arm tracking Chapter 4's minimum-time motion 1.2× faster
    than its torque limits allow: tracking errors and commanded torques beyond the limits.

Times on a shared machine are noisy: compare the ratios measured in one run.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from benchtools import print_rows

from controllers.mpc import MPCOptions, ModelPredictiveControl
from controllers.plants import ArmPlant
from controllers.simulation import simulate
from examples.optimal_control import reach_problem, reach_target, two_link_tracking
from planners.optimal_control import OptimalControlProblem, OptimalControlSolver
from rigid_body.robots import LOCKED_JOINTS, load

CROCODDYL_SCRIPT = Path(__file__).resolve().parent / "crocoddyl_reach.py"
CROCODDYL_HELP = ("python3 -m venv /tmp/croc && /tmp/croc/bin/pip install crocoddyl 'pin<4' 'libpinocchio<4' "
                  "'cmeel-urdfdom<5' 'cmeel-tinyxml2<11', then RMPC_CROCODDYL_PYTHON=/tmp/croc/bin/python")


def crocoddyl_python() -> str | None:
    """The Python of Crocoddyl's environment: $RMPC_CROCODDYL_PYTHON, else /tmp/croc/bin/python if it exists."""
    path = os.environ.get("RMPC_CROCODDYL_PYTHON", "/tmp/croc/bin/python")
    return path if Path(path).exists() else None


def panda_reach(repeats: int = 3) -> list[dict]:
    """Row (a): the Panda reach by rmpc and by Crocoddyl's box-FDDP on the equal problem."""
    robot = load("panda")
    n = robot.nv
    q0 = robot.configurations["ready"]
    x0 = np.r_[q0, np.zeros(n)]
    T_d = reach_target(robot, q0)
    base = reach_problem(robot)
    problem = OptimalControlProblem(robot, base.horizon, base.dt, base.running, base.terminal, q_min=-np.inf,
                                    q_max=np.inf, qd_max=np.inf)        # joint limits inactive, as in Crocoddyl
    solver = OptimalControlSolver(problem)
    result = solver.solve(x0, q_ref=q0, T_d=T_d)                       # the first call loads the compiled code

    cpu = []

    def rmpc_times(count: int) -> list[float]:
        nonlocal result
        out = []
        for _ in range(count):
            start, start_cpu = time.perf_counter(), time.process_time()
            result = solver.solve(x0, q_ref=q0, T_d=T_d)
            out.append(time.perf_counter() - start)
            cpu.append(time.process_time() - start_cpu)
        return out

    times = rmpc_times(repeats)
    rmpc_time = min(times)
    rows = [dict(measurement=f"Panda reach OCP (N=50, RK4), rmpc SQP ({solver.qp_solver}): {result.iterations} "
                             f"iterations, success {result.success}, KKT {result.kkt:.1g} [s]",
                 rmpc=rmpc_time, reference=None, target=None)]
    python = crocoddyl_python()
    if python is None:
        rows.append(dict(measurement=f"Panda reach vs Crocoddyl box-FDDP: skipped (no Crocoddyl environment: "
                                     f"{CROCODDYL_HELP})", rmpc=rmpc_time, reference=None, target=None))
        return rows
    g = pin.computeGeneralizedGravity(robot.model, robot.model.createData(), q0)
    run, ter = problem.running, problem.terminal
    spec = {"urdf": str(robot.urdf_path), "lock": list(LOCKED_JOINTS.get("panda", ())),
            "gravity": list(robot.model.gravity.linear), "frame": robot.model.frames[robot.ee_frame].name,
            "N": problem.horizon, "dt": problem.dt, "x0": list(x0), "p_d": list(T_d[:3, 3]), "R_d": T_d[:3, :3].tolist(),
            "x_ref": list(x0), "tau_max": list(problem.tau_max), "us_init": [list(g)] * problem.horizon,
            "running": {"position": run.position, "orientation": run.orientation,
                        "state": list(np.r_[run.q, run.qd]), "effort": list(run.tau)},
            "terminal": {"position": ter.position, "orientation": ter.orientation, "state": list(np.r_[ter.q, ter.qd])},
            "repeats": 2}
    croc_times, croc_cpu = [], []
    for _ in range(repeats):                        # interleaved (a loaded machine's speed drifts): min of each
        out = subprocess.run([python, str(CROCODDYL_SCRIPT)], input=json.dumps(spec), capture_output=True, text=True)
        if out.returncode != 0:
            raise RuntimeError(f"crocoddyl_reach.py failed: {out.stderr.strip()[-500:]}")
        croc = json.loads(out.stdout)
        croc_times += croc["times"][1:]             # its first solve in a process: warm-up
        croc_cpu += croc["cpu_times"][1:]
        times += rmpc_times(1)
    rmpc_time = min(times)
    croc_time = min(croc_times)
    equal = abs(result.cost - croc["cost"]) <= 0.01 * abs(croc["cost"])
    rows.append(dict(measurement=f"Panda reach: rmpc SQP vs Crocoddyl {croc['crocoddyl']} box-FDDP "
                                 f"({croc['iterations']} iterations), cost {result.cost:.6g} vs {croc['cost']:.6g} "
                                 f"(equal within 1 %: {equal}) [s]",
                     rmpc=rmpc_time, reference=croc_time, ref_name="Crocoddyl box-FDDP",
                     target=("ratio<=", 2.0) if equal else ("ratio<=", 0.0)))
    rows.append(dict(measurement="the same, processor time (less sensitive to a loaded machine's waits) [s]",
                     rmpc=min(cpu), reference=min(croc_cpu), ref_name="Crocoddyl box-FDDP",
                     target=("ratio<=", 2.0) if equal else ("ratio<=", 0.0)))
    return rows


def panda_mpc(duration: float = 1.0) -> list[dict]:
    """Row (b): MPC on the Panda reach at 100 Hz, 0.5 s horizon: the time of each sample's whole computation
    (references, SQP, checks), its median, worst and the share of samples over T_s; beside it the processor time
    (what a sample takes on an idle core: the wall time on a loaded machine includes waiting) and its two largest
    parts, the linearisation and HPIPM, with the machine's load."""
    robot = load("panda")
    q0 = robot.configurations["ready"]
    x0 = np.r_[q0, np.zeros(robot.nv)]
    T_d = reach_target(robot, q0)
    problem = reach_problem(robot)
    plant = ArmPlant(robot, tau_max=problem.tau_max)
    rows = []
    for label, options in (("real-time iteration", MPCOptions(real_time_iteration=True)),
                           ("up to 5 SQP iterations", MPCOptions(max_iter=5))):
        mpc = ModelPredictiveControl(problem, reference=q0, target=T_d, options=options)
        simulate(plant, mpc, (0.0, 2 * problem.dt), x0, h=1e-3, Ts=problem.dt)     # loads the compiled code
        run = simulate(plant, mpc, (0.0, duration), x0, h=1e-3, Ts=problem.dt)     # logged once per sample
        solve, cpu = run["solve_time"], run["cpu_time"]
        missed = float(np.mean(run["deadline_met"] == 0))
        parts = ", ".join(f"{name} {np.median(run[key]) * 1e3:.2f} ms"
                          for name, key in (("linearisation", "linearisation_time"), ("HPIPM", "qp_time")))
        load_average = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
        rows.append(dict(measurement=f"Panda MPC 100 Hz, N=50 ({label}): median time per sample [s] "
                                     f"(worst {solve.max() * 1e3:.1f} ms, {100 * missed:.0f} % deadlines missed, "
                                     f"{int(run['failed'].sum())} failed; processor time median "
                                     f"{np.median(cpu) * 1e3:.2f} ms; parts (wall) {parts}; load {load_average:.1f})",
                         rmpc=float(np.median(solve)), reference=problem.dt, ref_name="T_s",
                         target=("ratio<=", 1.0)))
    return rows


def two_link_saturation() -> list[dict]:
    """Row (c): MPC vs computed torque on the two-link arm beyond its torque limits."""
    sol = two_link_tracking(speed=1.2)
    v = sol.values
    ct, mpc = "computed torque (8.57)", "MPC"
    return [dict(measurement=f"2R min-time motion x1.2: max tracking error, MPC vs computed torque [rad] "
                             f"(RMS {v['rms_error ' + mpc]:.3g} vs {v['rms_error ' + ct]:.3g})",
                 rmpc=v["max_error " + mpc], reference=v["max_error " + ct], ref_name="computed torque (8.57)",
                 target=("ratio<=", 1.0)),
            dict(measurement=f"2R min-time motion x1.2: share of samples commanding beyond the torque limits "
                             f"(computed torque: {v['commanded_over_limit ' + ct]:.2f})",
                 rmpc=v["commanded_over_limit " + mpc], reference=None, target=("<=", 0.0))]


def rows(quick: bool = False) -> list[dict]:
    return panda_reach(repeats=1 if quick else 3) + panda_mpc(0.3 if quick else 1.0) + two_link_saturation()


def main() -> None:
    print_rows(rows(quick="--quick" in sys.argv))


if __name__ == "__main__":
    main()
