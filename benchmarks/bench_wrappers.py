"""Benchmark: the wrappers of ``rigid_body.dynamics`` and ``rigid_body.kinematics`` against their raw
Pinocchio calls (target: ≤ 1.5× on the 7-DOF Panda).

Each wrapper validates its inputs (1-D numeric vectors of the right size, every entry finite; frame id)
and returns an array that is not a view of ``robot.data``; the raw call does neither. The ``floor`` is
the least a validating Python wrapper costs: a function that reads the robot's model and per-thread
data and runs the same checks (one ``tolist`` and ``sum`` per vector, ``math.isfinite``) before the raw
call — no fallback, no messages. A ratio at the floor is all Python allows; the rest of the gap is the
interpreter's call and attribute costs (≈ 0.15 µs) plus ≈ 0.2 µs per checked vector. The 2R
(``planar_2r`` without rotors) and 6R (``anthropomorphic_wrist``) rows have no target: their raw
calls take 0.4–0.8 µs, so the same fixed cost weighs more.
Times are the best of short interleaved windows (the same process, the same inputs).
Run: ``python benchmarks/bench_wrappers.py``.
"""

from __future__ import annotations

from math import isfinite
from typing import Callable

import numpy as np
import pinocchio as pin

from rigid_body import dynamics as dyn
from rigid_body import kinematics as kin
from rigid_body.robots import load

from benchtools import best_times

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
TARGET = 1.5


def cases(robot) -> list[tuple[str, Callable, Callable, Callable]]:
    """(name, rmpc call, raw Pinocchio call, the floor: the least validating Python wrapper) for one robot."""
    rng = np.random.default_rng(0)
    q = robot.random_configuration(rng)
    qd, qdd, tau = rng.normal(size=(3, robot.nv))
    m, d, fid = robot.model, robot.data, robot.ee_frame

    def raw_fk():
        pin.forwardKinematics(m, d, q)
        return pin.updateFramePlacement(m, d, fid).homogeneous

    def least_1(raw):  # checks q, then the raw call on the robot's model and this thread's data
        def wrapper(robot, q):
            if isfinite(sum(q.tolist())):
                return raw(robot.model, robot._local.data, q)
        return lambda: wrapper(robot, q)

    def least_2(raw):
        def wrapper(robot, q, qd):
            if isfinite(sum(q.tolist()) + sum(qd.tolist())):
                return raw(robot.model, robot._local.data, q, qd)
        return lambda: wrapper(robot, q, qd)

    def least_3(raw, third):
        def wrapper(robot, q, qd, x):
            if isfinite(sum(q.tolist()) + sum(qd.tolist()) + sum(x.tolist())):
                return raw(robot.model, robot._local.data, q, qd, x)
        return lambda: wrapper(robot, q, qd, third)

    def least_aba(robot, q, qd, tau):  # with forward_dynamics' check of a singular B(q): a non-finite q̈
        if isfinite(sum(q.tolist()) + sum(qd.tolist()) + sum(tau.tolist())):
            qdd = pin.aba(robot.model, robot._local.data, q, qd, tau)
            if isfinite(sum(qdd.tolist())):
                return qdd

    def least_fk(robot, q):
        if isfinite(sum(q.tolist())):
            model, data = robot.model, robot._local.data
            pin.forwardKinematics(model, data, q)
            return pin.updateFramePlacement(model, data, robot.ee_frame).homogeneous

    def least_jacobian(robot, q):
        if isfinite(sum(q.tolist())):
            return pin.computeFrameJacobian(robot.model, robot._local.data, q, robot.ee_frame, LWA)

    return [
        ("inertia_matrix / crba", lambda: dyn.inertia_matrix(robot, q), lambda: pin.crba(m, d, q), least_1(pin.crba)),
        ("inverse_dynamics / rnea", lambda: dyn.inverse_dynamics(robot, q, qd, qdd), lambda: pin.rnea(m, d, q, qd, qdd),
         least_3(pin.rnea, qdd)),
        ("forward_dynamics / aba", lambda: dyn.forward_dynamics(robot, q, qd, tau), lambda: pin.aba(m, d, q, qd, tau),
         lambda: least_aba(robot, q, qd, tau)),
        ("gravity_torques / computeGeneralizedGravity", lambda: dyn.gravity_torques(robot, q),
         lambda: pin.computeGeneralizedGravity(m, d, q), least_1(pin.computeGeneralizedGravity)),
        ("nonlinear_effects / nonLinearEffects", lambda: dyn.nonlinear_effects(robot, q, qd),
         lambda: pin.nonLinearEffects(m, d, q, qd), least_2(pin.nonLinearEffects)),
        ("direct_kinematics / forwardKinematics + frame", lambda: kin.direct_kinematics(robot, q), raw_fk,
         lambda: least_fk(robot, q)),
        ("geometric_jacobian / computeFrameJacobian", lambda: kin.geometric_jacobian(robot, q),
         lambda: pin.computeFrameJacobian(m, d, q, fid, LWA), lambda: least_jacobian(robot, q)),
    ]


def rows(quick: bool = False) -> list[dict]:
    rounds = 41 if quick else 151
    robots = {"Panda 7R": load("panda"), "2R": load("planar_2r", motors=False), "6R": load("anthropomorphic_wrist")}
    measured = {}
    for label, robot in robots.items():
        for name, wrapper, raw, floor in cases(robot):
            measured[label, name] = best_times([wrapper, raw, floor], rounds=rounds)
    out = []
    for name, *_ in cases(robots["2R"]):
        for label in robots:
            t_wrap, t_raw, t_floor = measured[label, name]
            out.append(dict(measurement=f"{name} [µs], {label}", rmpc=t_wrap * 1e6, reference=t_raw * 1e6,
                            ref_name=f"raw Pinocchio (floor: least validating wrapper {t_floor / t_raw:.2f})",
                            target=("ratio<=", TARGET) if label == "Panda 7R" else None))
    return out


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
