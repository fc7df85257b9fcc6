"""Benchmark of the IK solvers on the Panda (7 DOF), relative to one raw Pinocchio frame Jacobian.

Times one CLIK step (pose error + Jacobian + pseudo-inverse law, Sect. 3.7), one CasADi/IPOPT IK
solve of a random reachable pose (restarts included), and one proxsuite QP velocity-IK step, each
with its ratio to one ``pin.computeFrameJacobian`` call measured in the same run.

Run: ``python benchmarks/bench_ik.py``.
"""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin

from planners.inverse_kinematics import CLIK, CasadiIK, QPVelocityIK, constant_pose
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import load
from rigid_body.task_space import TaskSpace

from benchtools import per_call


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


if __name__ == "__main__":
    main()
