"""Benchmark: the wrappers of ``rigid_body.dynamics`` and ``rigid_body.kinematics`` against their raw
Pinocchio calls (target: ≤ 1.5× on the 7-DOF Panda).

Each wrapper validates its inputs (float vector of the right size, finite; frame id) and returns an
array that is not a view of ``robot.data``; the raw call does neither. The 2R (``planar_2r`` without
rotors) and 6R (``anthropomorphic_wrist``) rows are shown beside the Panda without a target: their raw
calls take well under a microsecond, so the fixed cost of the checks (the ``floor`` column: the
wrapper's validation alone, added to the raw call) bounds their ratio from below.
Times are the best of interleaved rounds (the same process, the same inputs).
Run: ``python benchmarks/bench_wrappers.py``.
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np
import pinocchio as pin

from rigid_body import dynamics as dyn
from rigid_body import kinematics as kin
from rigid_body.robots import load
from rigid_body.validation import as_vector

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
TARGET = 1.5


def best_times(functions: list[Callable[[], object]], repetitions: int = 3000, rounds: int = 7) -> list[float]:
    """Per-call wall time [s] of each function: the best of ``rounds`` interleaved means (machine noise
    hits every function alike)."""
    best = [float("inf")] * len(functions)
    for f in functions:
        f()
    for _ in range(rounds):
        for i, f in enumerate(functions):
            t0 = time.perf_counter()
            for _ in range(repetitions):
                f()
            best[i] = min(best[i], (time.perf_counter() - t0) / repetitions)
    return best


def cases(robot) -> list[tuple[str, Callable, Callable, Callable]]:
    """(name, rmpc call, raw Pinocchio call, the wrapper's validation alone) for one robot."""
    rng = np.random.default_rng(0)
    q = robot.random_configuration(rng)
    qd, qdd, tau = rng.normal(size=(3, robot.nv))
    m, d, nq, nv, fid = robot.model, robot.data, robot.nq, robot.nv, robot.ee_frame

    def check(*vectors):
        return lambda: [as_vector(v, n, "x") for v, n in vectors]

    def raw_fk():
        pin.forwardKinematics(m, d, q)
        return pin.updateFramePlacement(m, d, fid).homogeneous

    return [
        ("inertia_matrix / crba", lambda: dyn.inertia_matrix(robot, q), lambda: pin.crba(m, d, q), check((q, nq))),
        ("inverse_dynamics / rnea", lambda: dyn.inverse_dynamics(robot, q, qd, qdd), lambda: pin.rnea(m, d, q, qd, qdd),
         check((q, nq), (qd, nv), (qdd, nv))),
        ("forward_dynamics / aba", lambda: dyn.forward_dynamics(robot, q, qd, tau), lambda: pin.aba(m, d, q, qd, tau),
         check((q, nq), (qd, nv), (tau, nv))),
        ("gravity_torques / computeGeneralizedGravity", lambda: dyn.gravity_torques(robot, q),
         lambda: pin.computeGeneralizedGravity(m, d, q), check((q, nq))),
        ("nonlinear_effects / nonLinearEffects", lambda: dyn.nonlinear_effects(robot, q, qd),
         lambda: pin.nonLinearEffects(m, d, q, qd), check((q, nq), (qd, nv))),
        ("direct_kinematics / forwardKinematics + frame", lambda: kin.direct_kinematics(robot, q), raw_fk,
         check((q, nq))),
        ("geometric_jacobian / computeFrameJacobian", lambda: kin.geometric_jacobian(robot, q),
         lambda: pin.computeFrameJacobian(m, d, q, fid, LWA), check((q, nq))),
    ]


def rows() -> list[dict]:
    robots = {"Panda 7R": load("panda"), "2R": load("planar_2r", motors=False), "6R": load("anthropomorphic_wrist")}
    measured = {}
    for label, robot in robots.items():
        for name, wrapper, raw, checks in cases(robot):
            measured[label, name] = best_times([wrapper, raw, checks])
    out = []
    for name, *_ in cases(robots["2R"]):
        for label in robots:
            t_wrap, t_raw, t_check = measured[label, name]
            floor = (t_raw + t_check) / t_raw
            out.append(dict(measurement=f"{name} [µs], {label}", rmpc=t_wrap * 1e6, reference=t_raw * 1e6,
                            ref_name=f"raw Pinocchio (checks alone {t_check * 1e6:.2f} µs: floor {floor:.2f})",
                            target=("ratio<=", TARGET) if label == "Panda 7R" else None))
    return out


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
