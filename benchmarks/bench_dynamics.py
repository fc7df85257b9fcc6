"""Benchmark: the book's Lagrange B(q) and Newton–Euler τ against Pinocchio's CRBA/RNEA, and forward
dynamics with and without motor (mimic) joints.

Per-call times [µs] and ratios against the raw Pinocchio call measured in the same run, on
``planar_2r`` (with motors), ``anthropomorphic_wrist`` (6R) and the Panda (7R, standard DH table of
``rigid_body.book_robots``). Run: ``python benchmarks/bench_dynamics.py``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin

from rigid_body import dynamics as dyn
from rigid_body import lagrange as lg
from rigid_body import newton_euler as ne
from rigid_body.book_robots import book_robot_spec, panda_links, panda_tool
from rigid_body.robots import load, robot_from_dh

from benchtools import per_call


def row(label: str, t: float, ref: float, ref_name: str) -> dict:
    """One table row: time per call [s] shown in µs against the raw Pinocchio call ``ref`` (no target: the
    wrappers' targets are in bench_wrappers.py; the book's algorithms are references, not hot paths)."""
    return dict(measurement=f"{label} [µs]", rmpc=t * 1e6, reference=ref * 1e6, ref_name=ref_name, target=None)


def rows(quick: bool = False) -> list[dict]:
    reps = 4000 if quick else 20000
    rng = np.random.default_rng(0)
    cases = [("planar_2r", load("planar_2r"), lg.serial_model(book_robot_spec("planar_2r"))),
             ("anthropomorphic_wrist", load("anthropomorphic_wrist"),
              lg.serial_model(book_robot_spec("anthropomorphic_wrist"))),
             ("panda", load("panda"), lg.serial_model(panda_links(load("panda").model)))]
    out = []
    for name, robot, model in cases:
        q = robot.random_configuration(rng)
        qd, qdd = rng.normal(size=(2, robot.nv))
        m, d = robot.model, robot.data
        n = max(reps // 10, 20) if robot.nv <= 2 else max(reps // 40, 10)
        t_crba = per_call(lambda: pin.crba(m, d, q), reps)
        out.append(row(f"{name}: lagrange.inertia_matrix (7.32)", per_call(lambda: lg.inertia_matrix(model, q), n),
                       t_crba, "pin.crba"))
        t_cor = per_call(lambda: pin.computeCoriolisMatrix(m, d, q, qd), reps)
        out.append(row(f"{name}: dynamics.coriolis_matrix" + (" (polarised RNEA)" if robot.has_mimic else ""),
                       per_call(lambda: dyn.coriolis_matrix(robot, q, qd), reps // 4), t_cor,
                       "pin.computeCoriolisMatrix"))
        out.append(row(f"{name}: lagrange.coriolis_matrix (7.45)", per_call(lambda: lg.coriolis_matrix(model, q, qd),
                                                                            n // 2), t_cor, "pin.computeCoriolisMatrix"))
        t_rnea = per_call(lambda: pin.rnea(m, d, q, qd, qdd), reps)
        out.append(row(f"{name}: newton_euler.inverse_dynamics (7.107-7.114)",
                       per_call(lambda: ne.inverse_dynamics(model, q, qd, qdd), n), t_rnea, "pin.rnea"))
        out.append(row(f"{name}: lagrange.inverse_dynamics (B q̈ + C q̇ + g)",
                       per_call(lambda: lg.inverse_dynamics(model, q, qd, qdd), n // 2), t_rnea, "pin.rnea"))
    with_motors, without = load("planar_2r"), load("planar_2r", motors=False)
    q, qd, tau = rng.normal(size=(3, 2))
    m0, d0 = without.model, without.data
    t_aba = per_call(lambda: pin.aba(m0, d0, q, qd, tau), reps)
    out.append(row("planar_2r: forward_dynamics, mimic rotors (CRBA + Cholesky)",
                   per_call(lambda: dyn.forward_dynamics(with_motors, q, qd, tau), reps), t_aba, "pin.aba without rotors"))
    links = panda_links(load("panda").model)
    plain = robot_from_dh(links, tool=panda_tool())
    motors = robot_from_dh([dataclasses.replace(l, motor_inertia=1e-4, motor_mass=0.5, gear_ratio=100.0) for l in links],
                           tool=panda_tool())
    q, qd, tau = rng.normal(size=(3, 7))
    m0, d0 = plain.model, plain.data
    t_aba = per_call(lambda: pin.aba(m0, d0, q, qd, tau), reps)
    out.append(row("Panda DH + rotors (I_m 1e-4, k_r 100): forward_dynamics (CRBA + Cholesky)",
                   per_call(lambda: dyn.forward_dynamics(motors, q, qd, tau), reps), t_aba, "pin.aba without rotors"))
    return out


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
