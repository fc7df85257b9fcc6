"""Cost of the chapter-8 closed loops: wall time per simulated second, and one step against raw Pinocchio.

Run: ``python benchmarks/bench_control.py``. Prints, for the two-link arm with motors (mimic joints,
so the raw reference is CRBA + nonLinearEffects + LAPACK's
Cholesky solve ``dposv``, as rmpc) and for the UR5 (raw ``pin.aba``):
the time of one plant derivative, one RK4 step, one controller call and one closed-loop sample, each
with its ratio to the raw forward-dynamics call measured in the same run — of the same torque, with the
plant's viscous friction (τ − F_v q̇, F_v = :data:`F_V`); then the wall time of the 8.x simulations
divided by their simulated time.
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np
import pinocchio as pin
from scipy.linalg.lapack import dposv

from controllers.joint_space import AdaptivePayloadControl, InverseDynamicsControl, PDGravityCompensation
from controllers.operational_space import OperationalInverseDynamics
from controllers.plants import ArmPlant
from controllers.simulation import rk4_step, simulate
from planners.paths import PathLaw, Segment
from planners.timing import quintic, trapezoidal, trapezoidal_law
from rigid_body.robots import load, with_payload

from benchtools import per_call



F_V = 1.0
"""The plants' viscous friction [N·m·s/rad], in the raw references too."""


def raw_2r_reference(arm_with_payload) -> Callable[[], object]:
    """The two-link arm's forward dynamics of τ − F_v q̇ by raw calls: CRBA, nonLinearEffects, LAPACK posv."""
    m, d = arm_with_payload.model, arm_with_payload.data
    q0, v0, tau0 = np.array([0.3, 0.8]), np.array([0.2, 0.2]), np.array([1.0, 2.0])
    return lambda: dposv(pin.crba(m, d, q0), tau0 - F_V * v0 - pin.nonLinearEffects(m, d, q0, v0))[1]


def step_costs(name: str, robot, plant_robot, controller, raw: Callable[[], object], h: float,
               Ts: float, verbose: bool = True, ref_name: str = "raw forward dynamics") -> list[dict]:
    n = robot.nv
    plant = ArmPlant(plant_robot, viscous_friction=F_V)
    x = np.r_[robot.configurations["neutral"] + 0.3, 0.2 * np.ones(n)]
    meas = plant.measure(0.0, x)
    u = controller(0.0, meas)
    t_raw = per_call(raw)
    t_der = per_call(lambda: plant.derivative(0.0, x, u))
    t_rk4 = per_call(lambda: rk4_step(lambda t, xi: plant.derivative(t, xi, u), 0.0, x, h))
    t_ctl = per_call(lambda: controller(0.5, plant.measure(0.5, x)))
    n_sub = int(round(Ts / h))
    t_sample = t_ctl + n_sub * t_rk4
    if verbose:
        print(f"\n{name} (n = {n}), h = {h * 1e3:g} ms, Ts = {Ts * 1e3:g} ms")
        print(f"  raw forward dynamics          {t_raw * 1e6:8.2f} us   1.0x")
        for label, t in (("plant derivative", t_der), ("RK4 step (4 derivatives)", t_rk4),
                         (f"controller call ({type(controller).__name__})", t_ctl),
                         (f"closed-loop sample (1 call + {n_sub} RK4)", t_sample)):
            print(f"  {label:<45s}{t * 1e6:8.2f} us {t / t_raw:6.1f}x")
    return [dict(measurement=f"{name}: plant derivative [us]", rmpc=t_der * 1e6, reference=t_raw * 1e6,
                 ref_name=ref_name, target=("ratio<=", 2.0))]


def wall_per_simulated_second(label: str, plant, controller, x0, t_end: float, h: float, Ts: float) -> None:
    t0 = time.perf_counter()
    simulate(plant, controller, (0.0, t_end), x0, h=h, Ts=Ts)
    wall = time.perf_counter() - t0
    print(f"  {label:<52s} {wall:6.2f} s wall / {t_end:g} s simulated = {wall / t_end:5.2f}")


def rows() -> list[dict]:
    """The plant-derivative rows of the planar arm with motors and of the UR5 against raw Pinocchio."""
    arm, armL = load("planar_2r"), load("planar_2r", payload=10.0)
    raw_2r = raw_2r_reference(armL)
    tra = trapezoidal([0, np.pi / 4], [np.pi / 2, np.pi / 2], 1.0, [3 * np.pi / 4, np.pi / 3], dt=1e-3)
    out = step_costs("planar_2r + motors", arm, armL, InverseDynamicsControl(arm, 100, 16, tra, 100.0),
                     raw_2r, h=1e-4, Ts=1e-3, verbose=False, ref_name="raw CRBA + nonLinearEffects + LAPACK posv")
    ur5 = load("ur5")
    real = with_payload(ur5, 5.0)
    qu, vu, tu = np.full(6, 0.3), np.full(6, 0.2), np.ones(6)
    q_i = np.array([0.0, -np.pi / 2, np.pi / 2, 0.0, np.pi / 2, 0.0])
    out += step_costs("UR5 + 5 kg", ur5, real, InverseDynamicsControl(ur5, 400, 40, quintic(q_i, q_i + 0.5, 1.5, dt=1e-3)),
                      lambda: pin.aba(real.model, real.data, qu, vu, tu - F_V * vu), h=1e-3, Ts=1e-3, verbose=False,
                      ref_name="raw pin.aba")
    return out


if __name__ == "__main__":
    arm, armL = load("planar_2r"), load("planar_2r", payload=10.0)
    raw_2r = raw_2r_reference(armL)
    tra = trapezoidal([0, np.pi / 4], [np.pi / 2, np.pi / 2], 1.0, [3 * np.pi / 4, np.pi / 3], dt=1e-3)
    step_costs("planar_2r + motors + 10 kg (8.12)", arm, armL, InverseDynamicsControl(arm, 100, 16, tra, 100.0),
               raw_2r, h=1e-4, Ts=1e-3)

    ur5 = load("ur5")
    real = with_payload(ur5, 5.0)
    qu, vu, tu = np.full(6, 0.3), np.full(6, 0.2), np.ones(6)
    raw_ur5 = lambda: pin.aba(real.model, real.data, qu, vu, tu - F_V * vu)  # noqa: E731
    q_i = np.array([0.0, -np.pi / 2, np.pi / 2, 0.0, np.pi / 2, 0.0])
    tra_u = quintic(q_i, q_i + 0.5, 1.5, dt=1e-3)
    step_costs("UR5 + 5 kg", ur5, real, InverseDynamicsControl(ur5, 400, 40, tra_u), raw_ur5, h=1e-3, Ts=1e-3)
    step_costs("UR5 + 5 kg", ur5, real, AdaptivePayloadControl(ur5, 10.0, 10.0, 20.0, tra_u), raw_ur5, h=1e-3, Ts=1e-3)

    print("\nWhole simulations (wall time per simulated second; the aim is well under 1):")
    x0 = np.r_[0.0, np.pi / 4, 0.0, 0.0]
    plantL = ArmPlant(armL, viscous_friction=100.0)
    q_d = np.array([np.pi / 4, -np.pi / 2])
    wall_per_simulated_second("8.10 PD + gravity (h = 1 ms)", ArmPlant(arm, viscous_friction=100.0),
                              PDGravityCompensation(arm, 3750, 750, q_d), np.r_[q_d - 0.1, 0, 0], 2.5, 1e-3, 1e-3)
    wall_per_simulated_second("8.12 inverse dynamics (h = 0.1 ms)", plantL,
                              InverseDynamicsControl(armL, 100, 16, tra, 100.0), x0, 2.5, 1e-4, 1e-3)
    wall_per_simulated_second("8.14 adaptive (h = 1 ms)", plantL,
                              AdaptivePayloadControl(arm, 1e4, 10, 200.0, tra, 100.0), x0, 2.5, 1e-3, 1e-3)
    law = PathLaw(Segment([0.7, 0.2, 0.0], [0.1, -0.6, 0.0]), trapezoidal_law(0.0, 1.0, 1.0, 1.5))
    wall_per_simulated_second("8.16 operational-space inverse dynamics (h = 1 ms)", plantL,
                              OperationalInverseDynamics(armL, 100, 16, law, rows=(0, 1), viscous_friction=100.0),
                              np.r_[1.47653, -2.39646, 0, 0], 2.5, 1e-3, 1e-3)
    wall_per_simulated_second("UR5 adaptive (h = 1 ms)", ArmPlant(real, tau_max=ur5.model.effortLimit),
                              AdaptivePayloadControl(ur5, 10.0, 10.0, 20.0, tra_u), np.r_[q_i, np.zeros(6)],
                              2.5, 1e-3, 1e-3)
