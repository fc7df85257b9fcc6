"""Cost of the chapter-9 closed loops: simulated seconds per wall second, and one step's parts.

Run: ``python benchmarks/bench_force.py``. Prints, for the two-link arm against the compliant plane
(MODEL-B), the time of one contact-plant derivative (forward dynamics + the environment's wrench),
one measurement and one call of the impedance (9.3) and hybrid (9.10) controllers; then the
simulated seconds per wall second of Problems 9.3 and 9.10 and of the Panda wall run (two 3.5 s
runs: impedance and hybrid force/motion control).
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np

from controllers.force import HybridForceMotionControl
from controllers.operational_space import OperationalInverseDynamics
from controllers.plants import ArmInContact
from examples.panda_wall_contact import T_PANDA, _panda_hybrid, _panda_impedance, _panda_wall_scene
from problems.ch09 import (F_V, K_HAT, K_Y, R_C, T_D, _hybrid_run, _impedance_run, _plane, _tra_5)
from rigid_body.kinematics import ELBOW_UP, inverse_kinematics_planar_2r
from rigid_body.robots import load
from rigid_body.task_space import selection_matrices

from benchtools import per_call


def simulated_per_wall_second(label: str, run: Callable[[], object], simulated: float) -> None:
    t0 = time.perf_counter()
    run()
    wall = time.perf_counter() - t0
    print(f"  {label:<58s} {simulated:5.2f} s simulated in {wall:5.2f} s wall = {simulated / wall:5.2f}x real time")


if __name__ == "__main__":
    arm = load("planar_2r")
    plant = ArmInContact(arm, _plane(), viscous_friction=F_V)
    q0 = inverse_kinematics_planar_2r(_tra_5()(0.0)[0][:2])[ELBOW_UP]
    x = plant.initial_state(q0, [0.1, -0.2])
    u = np.array([10.0, 5.0])
    meas = plant.measure(0.0, x)
    imp = OperationalInverseDynamics(arm, 5000.0, 1600.0, _tra_5(), rows=(0, 1), viscous_friction=F_V,
                                     inertia=100.0, force_feedback=True)
    S_f, S_v = selection_matrices(("x",), R_C, axes=("x", "y"))
    hyb = HybridForceMotionControl(arm, S_f, S_v, [-50.0], [0.1], 16, 100, 16, 100, compliance=np.eye(2) / K_HAT,
                                   rows=(0, 1), viscous_friction=F_V)
    print("two-link arm on the compliant plane: one call")
    for label, f in (("plant derivative (forward dynamics + contact wrench)", lambda: plant.derivative(0.0, x, u)),
                     ("measurement (q, q̇, sensed wrench)", lambda: plant.measure(0.0, x)),
                     ("impedance controller (9.30)–(9.31)", lambda: imp(0.3, meas)),
                     ("hybrid force/motion controller (9.77)–(9.81)", lambda: hyb(0.3, meas))):
        print(f"  {label:<58s} {per_call(f) * 1e6:8.1f} us")
    print("\nWhole simulations (T_c = h = 1 ms):")
    simulated_per_wall_second("9.3 impedance control", lambda: _impedance_run(_tra_5(), q0), T_D)
    simulated_per_wall_second("9.10 hybrid force/motion control", lambda: _hybrid_run(K_HAT), T_D)
    simulated_per_wall_second("9.10 with the exact stiffness", lambda: _hybrid_run(K_Y), T_D)
    scene = _panda_wall_scene()
    simulated_per_wall_second("Panda on the stepped wall, hybrid", lambda: _panda_hybrid(scene), T_PANDA)
    simulated_per_wall_second("Panda on the stepped wall, impedance", lambda: _panda_impedance(scene, 0.021), T_PANDA)
