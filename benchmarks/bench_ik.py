"""Benchmark of the IK solvers on the Panda (7 DOF), relative to one raw Pinocchio frame Jacobian.

Times one CLIK step (pose error + Jacobian + pseudo-inverse law, Sect. 3.7), one CasADi/IPOPT IK
solve of a random reachable pose (restarts included), and one proxsuite QP velocity-IK step, each
with its ratio to one ``pin.computeFrameJacobian`` call measured in the same run.

Then the success rates of every solver (reported successes verified independently) on the seeded
reachable targets of ``tests/planners/ik_harness.py``: poses of random configurations within the
limits, each solver started from another random configuration within the limits.

Run: ``python benchmarks/bench_ik.py [N_TARGETS]`` (default 500) from the repository root.
"""

from __future__ import annotations

import sys
import time

import numpy as np
import pinocchio as pin

from planners.inverse_kinematics import CLIK, CasadiIK, QPVelocityIK, constant_pose, solve_clik
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import load
from rigid_body.task_space import TaskSpace

from benchtools import per_call
from tests.planners.ik_harness import reachable_targets, run_solver


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
            (f"CasADi/IPOPT IK solve ({solved}/{len(targets)} solved)", t_ik)]
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
    main()
    success_rates(int(sys.argv[1]) if len(sys.argv) > 1 else 500)
