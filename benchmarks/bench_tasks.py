"""Timing of the chapter 5/6 hot loops against raw Pinocchio calls measured in the same run.

Per-call times of: the servomotor plant derivative, the arm-in-contact derivative (planar 3R in
contact), the peg-in-hole state-machine controller, and one simulated second of a SCARA MOVETO
(inverse-dynamics control at 2 ms); each compared with a raw Pinocchio call on the same robot.
Run: ``python benchmarks/bench_tasks.py``.
"""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin

from controllers.environment import SurfaceWithHole
from controllers.force import PegInHoleController, PegInHoleTask
from controllers.plants import ArmInContact, ServomotorPlant
from controllers.tasks import ActionExecutor, Workcell, moveto
from rigid_body.actuators import DCServomotor, PIRegulator
from rigid_body.kinematics import inverse_kinematics_planar_3r, inverse_kinematics_scara
from rigid_body.robots import load

from benchtools import per_call


def rows() -> list[dict]:
    """The chapter 5/6 hot calls against a raw Pinocchio call on the same robot (no target), and the SCARA
    MOVETO's wall time per 2 ms sample against raw RNEA."""
    r3 = load("planar_3r")
    q = inverse_kinematics_planar_3r(np.array([0.6, -0.001, -np.pi / 2]))[0]
    x = np.concatenate([q, np.zeros(3)])
    raw_jac = per_call(lambda: pin.computeFrameJacobian(r3.model, r3.data, q, r3.ee_frame, pin.LOCAL_WORLD_ALIGNED))
    raw_rnea = per_call(lambda: pin.rnea(r3.model, r3.data, q, x[3:], x[3:]))

    motor = DCServomotor(Ra=0.2, La=2e-3, kt=0.2, kv=0.2, Im=0.0014, Fm=0.01, Tv=1e-4, ki=1.0)
    plant_m = ServomotorPlant(motor, PIRegulator(2e4, 4e-4))
    xm, um = np.zeros(5), np.array([1.0, 0.0])
    t_motor = per_call(lambda: plant_m.derivative(0.0, xm, um))

    env = SurfaceWithHole(x_hole=0.59, clearance=0.004, depth=0.05)
    arm = ArmInContact(r3, env)
    u = np.zeros(3)
    t_arm = per_call(lambda: arm.derivative(0.0, x, u))
    ctrl = PegInHoleController(r3, PegInHoleTask(x_H=0.6))
    meas = arm.measure(0.0, x)
    t_ctrl = per_call(lambda: ctrl(0.0, meas))

    scara = load("scara")
    home = np.array([0.5, -0.3, 0.3, 0.0])
    q0 = inverse_kinematics_scara(home)[0]
    raw_scara = per_call(lambda: pin.rnea(scara.model, scara.data, q0, np.zeros(4), np.zeros(4)))
    ex = ActionExecutor(scara, inverse_kinematics_scara, Workcell((0.7, -0.3, 0.8)), q0)
    t0 = time.perf_counter()
    ex.run([moveto((0.4, 0.3, 0.7, 0.3), 0.5)])
    wall = time.perf_counter() - t0
    simulated = ex.t
    steps = simulated / 2e-3

    def row(label: str, t: float, ref: float, ref_name: str) -> dict:
        return dict(measurement=f"{label} [µs]", rmpc=t * 1e6, reference=ref * 1e6, ref_name=ref_name, target=None)

    return [row("ServomotorPlant.derivative", t_motor, raw_rnea, "raw pin.rnea, planar 3R"),
            row("ArmInContact.derivative (planar 3R in contact)", t_arm, raw_rnea, "raw pin.rnea, planar 3R"),
            row("PegInHoleController call", t_ctrl, raw_jac, "raw pin.computeFrameJacobian, planar 3R"),
            row("SCARA MOVETO, wall time per 2 ms sample", wall / steps, raw_scara, "raw pin.rnea, SCARA")]


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
