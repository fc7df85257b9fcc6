"""Benchmark of the IK solvers on the Panda (7 DOF), relative to one raw Pinocchio frame Jacobian.

Times one CLIK step (pose error + Jacobian + pseudo-inverse law, Sect. 3.7), one CasADi (Gauss–Newton SQP) IK
solve of a random reachable pose (restarts included), and one proxsuite QP velocity-IK step, each
with its ratio to one ``pin.computeFrameJacobian`` call measured in the same run.

Then the success rates of every solver (reported successes verified independently) on the seeded
reachable targets of ``tests/planners/ik_harness.py``: poses of random configurations within the
limits, each solver started from another random configuration within the limits.

Run: ``python benchmarks/bench_ik.py N_TARGETS`` for the success rates (e.g. 500), without an argument for ``rows()``.

``rows()`` measures the Levenberg–Marquardt solver (:class:`LMIK`) and :class:`CasadiIK` on random
reachable targets from random starts (median time, success rate, false successes verified by
Pinocchio's forward kinematics and the limits).

"""

from __future__ import annotations

import sys
import time

import numpy as np
import pinocchio as pin

from planners.inverse_kinematics import CLIK, LMIK, CasadiIK, QPVelocityIK, constant_pose, solve_clik
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import load
from rigid_body.task_space import TaskSpace

from benchtools import per_call
from tests.planners.ik_harness import reachable_targets, run_solver


def ik_statistics(solver, robot, n_targets: int, seed: int = 0) -> tuple[float, float, int, int]:
    """(median solve time [s], median CPU time [s], successes, false successes) over ``n_targets`` random
    reachable targets from random starts; a success is verified independently (Pinocchio FK in a fresh
    data, the limits). The CPU time shows what the wall time is on a machine without other load."""
    rng = np.random.default_rng(seed)
    data = robot.model.createData()
    times, cpus, solved, false = [], [], 0, 0
    for _ in range(n_targets):
        T_d = direct_kinematics(robot, robot.random_configuration(rng))
        q0 = robot.random_configuration(rng)
        t0, c0 = time.perf_counter(), time.process_time()
        result = solver.solve(T_d, q0, rng=rng)
        times.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
        if result.success:
            solved += 1
            pin.framesForwardKinematics(robot.model, data, result.q)
            T = data.oMf[robot.ee_frame]
            angle = np.linalg.norm(pin.log3(T.rotation.T @ T_d[:3, :3]))
            inside = np.all(result.q >= robot.lower) and np.all(result.q <= robot.upper)
            false += not (np.linalg.norm(T.translation - T_d[:3, 3]) < 1e-6 and angle < 1e-6 and inside)
    return float(np.median(times)), float(np.median(cpus)), solved, false


def rows(n_lm: int = 1000, n_casadi: int = 1000, quick: bool = False) -> list[dict]:
    """The IK rows on ``n_lm``/``n_casadi`` random reachable Panda targets (100/20 with ``quick``)."""
    if quick:
        n_lm, n_casadi = min(n_lm, 100), min(n_casadi, 20)
    robot = load("panda")
    model, data = robot.model, robot.data
    q = robot.random_configuration(np.random.default_rng(1))
    LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    t_jac = per_call(lambda: pin.computeFrameJacobian(model, data, q, robot.ee_frame, LWA), 20000)
    ref = "pin.computeFrameJacobian"
    t_lm, cpu_lm, ok_lm, false_lm = ik_statistics(LMIK(robot), robot, n_lm)
    t_ca, cpu_ca, ok_ca, false_ca = ik_statistics(CasadiIK(robot), robot, n_casadi)
    return [
        dict(measurement=f"Panda LM IK median solve, {n_lm} targets [ms] (CPU {cpu_lm * 1e3:.2f})", rmpc=t_lm * 1e3,
             reference=t_jac * 1e3,
             ref_name=ref, target=("<=", 1.0)),
        dict(measurement="Panda LM IK success [%]", rmpc=100.0 * ok_lm / n_lm, reference=None, target=(">=", 99.5)),
        dict(measurement="Panda LM IK false successes", rmpc=float(false_lm), reference=None, target=("<=", 0)),
        dict(measurement=f"Panda CasadiIK median solve, {n_casadi} targets [ms] (CPU {cpu_ca * 1e3:.2f})", rmpc=t_ca * 1e3,
             reference=t_jac * 1e3, ref_name=ref, target=("<=", 10.0)),
        dict(measurement="Panda CasadiIK success [%]", rmpc=100.0 * ok_ca / n_casadi, reference=None,
             target=(">=", 99.5)),
        dict(measurement="Panda CasadiIK false successes", rmpc=float(false_ca), reference=None, target=("<=", 0)),
    ]


def main() -> None:
    robot = load("panda")
    rng = np.random.default_rng(0)
    model, data = robot.model, robot.data
    q = robot.random_configuration(rng)
    T_d = direct_kinematics(robot, robot.random_configuration(rng))
    LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

    t_jac = per_call(lambda: pin.computeFrameJacobian(model, data, q, robot.ee_frame, LWA), 20000)
    clik = CLIK(robot, constant_pose(T_d), TaskSpace(orientation="axis_angle"), K=50.0, law="pseudo_inverse")
    t_clik = per_call(lambda: clik(0.0, q), 2000)
    qp = QPVelocityIK(robot)
    t_qp = per_call(lambda: qp.step(q, T_d), 1000)
    ik = CasadiIK(robot)
    targets = [direct_kinematics(robot, robot.random_configuration(rng)) for _ in range(30)]
    solved = 0
    t0 = time.perf_counter()
    for T in targets:
        solved += ik.solve(T, rng=rng).success
    t_ik = (time.perf_counter() - t0) / len(targets)

    print(f"Panda, {model.nq} DOF (pinocchio {pin.__version__})")
    print(f"{'operation':42s} {'per call':>12s} {'ratio':>10s}")
    rows = [("pin.computeFrameJacobian (reference)", t_jac),
            ("CLIK step (pseudo-inverse, angle-axis)", t_clik),
            ("QP velocity-IK step (proxsuite)", t_qp),
            (f"CasADi SQP IK solve ({solved}/{len(targets)} solved)", t_ik)]
    for name, t in rows:
        print(f"{name:42s} {t * 1e6:10.1f} us {t / t_jac:10.1f}x")


def success_rates(n: int = 500, seed: int = 1) -> None:
    """Every solver on the same ``n`` reachable Panda targets; false successes must be 0."""
    robot = load("panda")
    targets = reachable_targets(robot, n, seed)
    casadi, qp = CasadiIK(robot), QPVelocityIK(robot)
    solvers = {
        "solve_clik": lambda r, T, q0: solve_clik(r, T, q0),
        "QPVelocityIK": lambda r, T, q0: qp.solve(T, q0),
        "CasadiIK": lambda r, T, q0: casadi.solve(T, q0, rng=np.random.default_rng(0)),
    }
    print(f"\nsuccess rates, {n} reachable Panda targets from random starts within the limits (tol 1e-6)")
    for name, solver in solvers.items():
        print(run_solver(robot, solver, targets, 1e-6, name), flush=True)


if __name__ == "__main__":
    from benchtools import print_rows

    main()
    if len(sys.argv) > 1:
        success_rates(int(sys.argv[1]))
    else:
        print_rows(rows())
