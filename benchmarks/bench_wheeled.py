"""Cost of the chapter-11 closed loops: simulated seconds per wall second of 11.16, 11.18 and the mobile manipulator.

Run: ``python benchmarks/bench_wheeled.py``. Prints the time of one unicycle derivative, one RK4 step and
one controller call (Cartesian regulator, odometry block + posture regulator, mobile-manipulator hold),
then, for the 11.16 and 11.18 runs (10 s simulated, RK4 at h = 0.01 s) and the mobile manipulator driving
1 m (6 s at 0.01 s), the simulated seconds per wall second (the aim is ≥ 20).
"""

from __future__ import annotations

import time

import numpy as np

from controllers.plants import MobileManipulatorPlant, OdometerPosture, Posture, UnicyclePlant
from controllers.simulation import Chain, ZeroOrderHold, rk4_step, simulate
from controllers.wheeled import CartesianRegulator, MobileManipulatorHold, Odometry, PostureRegulator
from rigid_body.robots import load
from rigid_body.wheeled import mobile_manipulator

from benchtools import per_call

Q0 = np.array([-1.0, -2.0, -np.pi / 2])  # companion i11_16 / i11_18


def real_time_factor(label: str, run, t_end: float, rounds: int = 3) -> float:
    best = float("inf")
    for _ in range(rounds):
        t0 = time.perf_counter()
        run()
        best = min(best, time.perf_counter() - t0)
    factor = t_end / best
    print(f"  {label:<62s} {best * 1e3:7.1f} ms wall / {t_end:g} s = {factor:7.0f}x real time")
    return factor


def odometric_regulator(Ts: float) -> Chain:
    return Chain(ZeroOrderHold(Odometry(Q0), Ts), PostureRegulator(1, 2.5, 3, feedback="estimate"), name="estimate")


if __name__ == "__main__":
    plant, x, u = UnicyclePlant(), Q0.copy(), np.array([0.5, 0.3])
    print("per call:")
    print(f"  unicycle derivative            {per_call(lambda: plant.derivative(0.0, x, u)) * 1e6:7.2f} us")
    print(f"  RK4 step                       {per_call(lambda: rk4_step(lambda t, xi: plant.derivative(t, xi, u), 0.0, x, 0.01)) * 1e6:7.2f} us")
    m = Posture(*Q0)
    print(f"  Cartesian regulator call       {per_call(lambda: CartesianRegulator(1, 3, True)(0.0, m)) * 1e6:7.2f} us")
    chain = odometric_regulator(0.01)
    mo = OdometerPosture(*Q0, 0.0, 0.0)
    print(f"  odometry + posture regulator   {per_call(lambda: chain(0.0, mo)) * 1e6:7.2f} us")
    mobile = mobile_manipulator(load("anthropomorphic_wrist"))
    mm_plant = MobileManipulatorPlant(mobile)
    x_mm = mm_plant.initial_state([0.0, 0.0, 0.0], [np.pi / 2, -1.1, -2.8, 0.0, 0.5, 0.0])
    hold = MobileManipulatorHold(mobile, [0.0, 0.6, 0.3], lambda t: (0.2, 0.06))
    meas = mm_plant.measure(0.0, x_mm)
    print(f"  mobile-manipulator hold call   {per_call(lambda: hold(0.0, meas)) * 1e6:7.2f} us")
    print("\nwhole runs (simulated seconds per wall second; the aim is ≥ 20):")
    real_time_factor("11.16 modified Cartesian regulator (h = Ts = 0.01 s)",
                     lambda: simulate(UnicyclePlant(), CartesianRegulator(1, 3, True), (0, 10), Q0, h=0.01, Ts=0.01), 10.0)
    for Ts in (0.01, 0.1):
        real_time_factor(f"11.18 odometry every {Ts:g} s → posture regulator every 0.01 s",
                         lambda: simulate(UnicyclePlant(odometer=True), odometric_regulator(Ts), (0, 10),
                                          np.r_[Q0, 0, 0], h=0.01, Ts=0.01), 10.0)
    real_time_factor("mobile manipulator: base drives, arm holds (h = Ts = 0.01 s)",
                     lambda: simulate(mm_plant, hold, (0, 6), x_mm, h=0.01, Ts=0.01), 6.0)
