"""Cost of the chapter-11 closed loops: simulated seconds per wall second of 11.16 and 11.18.

Run: ``python benchmarks/bench_wheeled.py``. Prints the time of one unicycle derivative, one RK4 step and
one controller call (Cartesian regulator, posture regulator with odometry), then, for the 11.16 and 11.18
runs (10 s simulated, RK4 at h = 0.01 s), the simulated seconds per wall second (the aim is ≥ 20).
"""

from __future__ import annotations

import time

import numpy as np

from controllers.simulation import rk4_step, simulate
from controllers.wheeled import CartesianRegulator, OdometricRegulator, Posture, PostureRegulator, UnicyclePlant

from benchtools import per_call

Q0 = np.array([-1.0, -2.0, -np.pi / 2])  # companion i11_16 / i11_18


def real_time_factor(label: str, controller, Ts: float, t_end: float = 10.0, rounds: int = 3) -> float:
    best = float("inf")
    for _ in range(rounds):
        t0 = time.perf_counter()
        simulate(UnicyclePlant(), controller, (0.0, t_end), Q0, h=min(Ts, 0.01), Ts=Ts)
        best = min(best, time.perf_counter() - t0)
    factor = t_end / best
    print(f"  {label:<58s} {best * 1e3:7.1f} ms wall / {t_end:g} s = {factor:7.0f}x real time")
    return factor


if __name__ == "__main__":
    plant, x, u = UnicyclePlant(), Q0.copy(), np.array([0.5, 0.3])
    print("per call:")
    print(f"  unicycle derivative            {per_call(lambda: plant.derivative(0.0, x, u)) * 1e6:7.2f} us")
    print(f"  RK4 step                       {per_call(lambda: rk4_step(lambda t, xi: plant.derivative(t, xi, u), 0.0, x, 0.01)) * 1e6:7.2f} us")
    m = Posture(*Q0)
    print(f"  Cartesian regulator call       {per_call(lambda: CartesianRegulator(1, 3, True)(0.0, m)) * 1e6:7.2f} us")
    odo = OdometricRegulator(PostureRegulator(1, 2.5, 3), Q0)
    print(f"  posture regulator + odometry   {per_call(lambda: odo(0.0, m)) * 1e6:7.2f} us")
    print("\nwhole runs (simulated seconds per wall second; the aim is ≥ 20):")
    real_time_factor("11.16 modified Cartesian regulator (h = Ts = 0.01 s)", CartesianRegulator(1, 3, True), 0.01)
    for Ts in (0.01, 0.1):
        real_time_factor(f"11.18 posture regulator + RK odometry (Ts = {Ts:g} s, h = 0.01 s)",
                         OdometricRegulator(PostureRegulator(1, 2.5, 3), Q0), Ts)
