"""Benchmark: the closed loop on MuJoCo physics against the Pinocchio loops, and MuJoCo's step against ABA.

* Panda PD + gravity compensation (8.51) towards a set point, 2 s at 1 kHz (RK4 at 1 ms, the controller every 1 ms),
  the URDF's joint damping on every plant: :class:`controllers.mujoco.MujocoPlant` (MuJoCo's own RK4, self-collision
  detection included) against :class:`controllers.plants.ArmPlant` in the Python loop and in the compiled loop
  (``backend="casadi"``, its C code built once and cached before timing). Each as a real-time factor (simulated
  seconds per wall second) and as a ratio of run times; the joint paths agree (reported).
* MuJoCo's cost per step against Pinocchio's: ``mj_step`` (RK4: four ``mj_forward``, collision detection among the
  Panda's 17 shapes) against four ``pin.aba``; one ``mj_forward`` against one ``pin.aba``, with and without
  MuJoCo's contact pipeline.

MuJoCo is optional (``pip install 'rmpc[mujoco]'``): without it the table says so. Run:
``python benchmarks/bench_mujoco.py`` (or ``python -m benchmarks --only mujoco``).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from controllers.joint_space import PDGravityCompensation
from controllers.mujoco import INSTALL, mujoco_available
from controllers.plants import ArmPlant
from controllers.simulation import simulate
from rigid_body.robots import load

from benchtools import best_of, best_times

T_END, H = 2.0, 1e-3
K_P = np.r_[100.0, 100.0, 100.0, 100.0, 50.0, 30.0, 10.0]
K_D = np.r_[20.0, 20.0, 20.0, 20.0, 5.0, 3.0, 1.0]
STEP = np.array([0.3, -0.2, 0.2, 0.3, -0.3, 0.2, 0.4])


def loops():
    """(MuJoCo run, Python run, compiled run): the three 2 s Panda PD + g loops as functions to time."""
    from controllers.mujoco import MujocoPlant

    panda = load("panda")
    q0 = panda.configurations["ready"]
    ctrl = PDGravityCompensation(panda, K_P, K_D, q0 + STEP)
    mj = MujocoPlant(panda)
    arm = ArmPlant(panda, friction=panda.friction)
    x0 = arm.initial_state(q0)
    return (lambda: simulate(mj, ctrl, (0.0, T_END), x0, h=H),
            lambda: simulate(arm, ctrl, (0.0, T_END), x0, h=H),
            lambda: simulate(arm, ctrl, (0.0, T_END), x0, h=H, backend="casadi"))


def step_costs() -> tuple[float, float, float, float, float]:
    """(mj_step RK4, four pin.aba, mj_forward, mj_forward without contacts, pin.aba) per call [s] at the Panda's
    ready posture."""
    import mujoco

    from controllers.mujoco import MujocoPlant

    panda = load("panda")
    plant = MujocoPlant(panda)
    m, d = plant.model, plant.data
    q0, v0 = panda.configurations["ready"], np.full(7, 0.3)
    tau = np.zeros(7)
    model, data = panda.model, panda.data

    def mj_step() -> None:
        d.qpos[:] = q0
        d.qvel[:] = v0
        mujoco.mj_step(m, d)

    def four_aba() -> None:
        for _ in range(4):
            pin.aba(model, data, q0, v0, tau)

    d.qpos[:], d.qvel[:] = q0, v0
    forward = lambda: mujoco.mj_forward(m, d)   # noqa: E731
    aba = lambda: pin.aba(model, data, q0, v0, tau)   # noqa: E731
    t_step, t_four, t_forward, t_aba = best_times([mj_step, four_aba, forward, aba], repetitions=200, rounds=31)
    m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    (t_bare,) = best_times([forward], repetitions=200, rounds=31)
    m.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    return t_step, t_four, t_forward, t_bare, t_aba


def rows() -> list[dict]:
    if not mujoco_available():
        return [dict(measurement=f"MujocoPlant: MuJoCo not installed ({INSTALL})", rmpc=float("nan"), reference=None,
                     ref_name="", target=None)]
    run_mj, run_py, run_compiled = loops()
    res_mj, res_py, res_c = run_mj(), run_py(), run_compiled()     # the compiled loop is built (and cached) here
    t_mj = t_py = t_c = float("inf")
    for _ in range(3):       # interleaved, so that a change of the machine's load hits all alike
        t_mj, t_py = min(t_mj, best_of(run_mj, 1)[0]), min(t_py, best_of(run_py, 1)[0])
        t_c = min(t_c, best_of(run_compiled, 1)[0])
    t_step, t_four, t_forward, t_bare, t_aba = step_costs()
    gap = float(max(np.abs(res_mj.q - res_py.q).max(), np.abs(res_c.q - res_py.q).max()))
    return [
        dict(measurement="Panda PD+g 2 s at 1 kHz: MujocoPlant / ArmPlant Python loop [ms]", rmpc=t_mj * 1e3,
             reference=t_py * 1e3, ref_name="ArmPlant, Python loop (ABA, RK4)", target=None),
        dict(measurement="  MujocoPlant / ArmPlant compiled loop [ms]", rmpc=t_mj * 1e3, reference=t_c * 1e3,
             ref_name="ArmPlant, backend='casadi' (cached)", target=None),
        dict(measurement="  real-time factor, MujocoPlant [simulated s / wall s]", rmpc=T_END / t_mj, reference=None,
             ref_name="", target=None),
        dict(measurement="  real-time factor, ArmPlant Python loop [simulated s / wall s]", rmpc=T_END / t_py,
             reference=None, ref_name="", target=None),
        dict(measurement="  real-time factor, ArmPlant compiled loop [simulated s / wall s]", rmpc=T_END / t_c,
             reference=None, ref_name="", target=None),
        dict(measurement="  max |q_MuJoCo − q_Pinocchio| along the runs [rad]", rmpc=gap, reference=None,
             ref_name="", target=("<=", 1e-4)),
        dict(measurement="mj_step (RK4, Panda, self-collision on) / 4 pin.aba [µs]", rmpc=t_step * 1e6,
             reference=t_four * 1e6, ref_name="4 pin.aba (one RK4 step)", target=None),
        dict(measurement="mj_forward / pin.aba [µs]", rmpc=t_forward * 1e6, reference=t_aba * 1e6,
             ref_name="pin.aba", target=None),
        dict(measurement="  mj_forward without the contact pipeline / pin.aba [µs]", rmpc=t_bare * 1e6,
             reference=t_aba * 1e6, ref_name="pin.aba", target=None),
    ]


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
