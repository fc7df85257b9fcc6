"""Cost of the chapter-11 closed loops: simulated seconds per wall second of 11.16, 11.18 and the mobile manipulator.

Run: ``python benchmarks/bench_wheeled.py``. The table gives the time of one unicycle derivative, one RK4 step and
one controller call (Cartesian regulator, odometry block + posture regulator, mobile-manipulator hold),
then, for the 11.16 and 11.18 runs (10 s simulated, RK4 at h = 0.01 s) and the mobile manipulator driving
1 m (6 s at 0.01 s), the simulated seconds per wall second (the aim is ≥ 20).
"""

from __future__ import annotations


import numpy as np

from controllers.plants import MobileManipulatorPlant, OdometerPosture, Posture, UnicyclePlant
from controllers.simulation import Chain, ZeroOrderHold, rk4_step, simulate
from controllers.wheeled import CartesianRegulator, MobileManipulatorHold, Odometry, PostureRegulator
from rigid_body.robots import load
from rigid_body.wheeled import mobile_manipulator

from benchtools import best_of, per_call

Q0 = np.array([-1.0, -2.0, -np.pi / 2])  # companion i11_16 / i11_18


def real_time_factor(label: str, run, t_end: float, rounds: int = 3, target: bool = True) -> dict:
    """A row: simulated seconds per wall second of ``run`` (best of ``rounds``); target ≥ 20 for the manual's."""
    best = best_of(run, rounds)[0]
    return dict(measurement=f"{label} [simulated s / wall s]", rmpc=t_end / best, reference=None, ref_name="",
                target=(">=", 20.0) if target else None)


def odometric_regulator(Ts: float) -> Chain:
    return Chain(ZeroOrderHold(Odometry(Q0), Ts), PostureRegulator(1, 2.5, 3, feedback="estimate"), name="estimate")


def rows() -> list[dict]:
    plant, x, u = UnicyclePlant(), Q0.copy(), np.array([0.5, 0.3])
    m = Posture(*Q0)
    chain = odometric_regulator(0.01)
    mo = OdometerPosture(*Q0, 0.0, 0.0)
    mobile = mobile_manipulator(load("anthropomorphic_wrist"))
    mm_plant = MobileManipulatorPlant(mobile)
    x_mm = mm_plant.initial_state([0.0, 0.0, 0.0], [np.pi / 2, -1.1, -2.8, 0.0, 0.5, 0.0])
    hold = MobileManipulatorHold(mobile, [0.0, 0.6, 0.3], lambda t: (0.2, 0.06))
    meas = mm_plant.measure(0.0, x_mm)
    calls = (("unicycle derivative", lambda: plant.derivative(0.0, x, u)),
             ("RK4 step of the unicycle", lambda: rk4_step(lambda t, xi: plant.derivative(t, xi, u), 0.0, x, 0.01)),
             ("Cartesian regulator call", lambda: CartesianRegulator(1, 3, True)(0.0, m)),
             ("odometry + posture regulator call", lambda: chain(0.0, mo)),
             ("mobile-manipulator hold call", lambda: hold(0.0, meas)))
    out = [dict(measurement=f"11.x {label} [µs]", rmpc=per_call(f) * 1e6, reference=None, ref_name="", target=None)
           for label, f in calls]
    out.append(real_time_factor("11.16 modified Cartesian regulator (h = Ts = 0.01 s)",
                                lambda: simulate(UnicyclePlant(), CartesianRegulator(1, 3, True), (0, 10), Q0, h=0.01,
                                                 Ts=0.01), 10.0))
    for Ts in (0.01, 0.1):
        out.append(real_time_factor(f"11.18 odometry every {Ts:g} s, posture regulator every 0.01 s",
                                    lambda: simulate(UnicyclePlant(odometer=True), odometric_regulator(Ts), (0, 10),
                                                     np.r_[Q0, 0, 0], h=0.01, Ts=0.01), 10.0))
    out.append(real_time_factor("mobile manipulator: base drives, arm holds (h = Ts = 0.01 s)",
                                lambda: simulate(mm_plant, hold, (0, 6), x_mm, h=0.01, Ts=0.01), 6.0, target=False))
    return out


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
