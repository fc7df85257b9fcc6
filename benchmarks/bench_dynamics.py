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

def row(label: str, t: float, ref: float) -> None:
    """One line: time per call [s] shown in µs, and its ratio to the raw Pinocchio call ``ref``."""
    print(f"  {label:<44s} {t * 1e6:10.2f} µs   x{t / ref:8.1f}")


def main() -> None:
    rng = np.random.default_rng(0)
    cases = [("planar_2r", load("planar_2r"), lg.serial_model(book_robot_spec("planar_2r"))),
             ("anthropomorphic_wrist", load("anthropomorphic_wrist"),
              lg.serial_model(book_robot_spec("anthropomorphic_wrist"))),
             ("panda", load("panda"), lg.serial_model(panda_links(load("panda").model)))]
    for name, robot, model in cases:
        q = robot.random_configuration(rng)
        qd, qdd = rng.normal(size=(2, robot.nv))
        m, d = robot.model, robot.data
        n = 2000 if robot.nv <= 2 else 500
        print(f"{name} (n = {robot.nv}, mimic rotors: {robot.has_mimic})")
        t_crba = per_call(lambda: pin.crba(m, d, q), 20000)
        row("pin.crba (raw)", t_crba, t_crba)
        row("rigid_body.dynamics.inertia_matrix", per_call(lambda: dyn.inertia_matrix(robot, q), 20000), t_crba)
        row("lagrange.inertia_matrix (7.32)", per_call(lambda: lg.inertia_matrix(model, q), n), t_crba)
        t_cor = per_call(lambda: pin.computeCoriolisMatrix(m, d, q, qd), 20000)
        row("pin.computeCoriolisMatrix (raw)", t_cor, t_cor)
        row("rigid_body.dynamics.coriolis_matrix" + (" (polarised RNEA)" if robot.has_mimic else ""),
            per_call(lambda: dyn.coriolis_matrix(robot, q, qd), 5000), t_cor)
        row("lagrange.coriolis_matrix (7.45, analytic dB/dq)", per_call(lambda: lg.coriolis_matrix(model, q, qd), n // 2),
            t_cor)
        t_rnea = per_call(lambda: pin.rnea(m, d, q, qd, qdd), 20000)
        row("pin.rnea (raw)", t_rnea, t_rnea)
        row("rigid_body.dynamics.inverse_dynamics", per_call(lambda: dyn.inverse_dynamics(robot, q, qd, qdd), 20000),
            t_rnea)
        row("newton_euler.inverse_dynamics (7.107-7.114)", per_call(lambda: ne.inverse_dynamics(model, q, qd, qdd), n),
            t_rnea)
        row("lagrange.inverse_dynamics (B q̈ + C q̇ + g)", per_call(lambda: lg.inverse_dynamics(model, q, qd, qdd), n // 2),
            t_rnea)
    print("forward dynamics, planar_2r")
    with_motors, without = load("planar_2r"), load("planar_2r", motors=False)
    q, qd, tau = rng.normal(size=(3, 2))
    m0, d0 = without.model, without.data
    t_aba = per_call(lambda: pin.aba(m0, d0, q, qd, tau), 20000)
    row("pin.aba (raw, no motors)", t_aba, t_aba)
    row("dynamics.forward_dynamics, no motors (ABA)", per_call(lambda: dyn.forward_dynamics(without, q, qd, tau), 20000),
        t_aba)
    row("dynamics.forward_dynamics, mimic rotors (CRBA+chol)",
        per_call(lambda: dyn.forward_dynamics(with_motors, q, qd, tau), 20000), t_aba)
    print("forward dynamics, Panda DH table without and with rotors (I_m = 1e-4 kg·m², k_r = 100)")
    links = panda_links(load("panda").model)
    plain = robot_from_dh(links, tool=panda_tool())
    motors = robot_from_dh([dataclasses.replace(l, motor_inertia=1e-4, motor_mass=0.5, gear_ratio=100.0) for l in links],
                           tool=panda_tool())
    q, qd, tau = rng.normal(size=(3, 7))
    m0, d0 = plain.model, plain.data
    t_aba = per_call(lambda: pin.aba(m0, d0, q, qd, tau), 20000)
    row("pin.aba (raw, no motors)", t_aba, t_aba)
    row("dynamics.forward_dynamics, no motors (ABA)", per_call(lambda: dyn.forward_dynamics(plain, q, qd, tau), 20000),
        t_aba)
    row("dynamics.forward_dynamics, mimic rotors (CRBA+chol)",
        per_call(lambda: dyn.forward_dynamics(motors, q, qd, tau), 20000), t_aba)


if __name__ == "__main__":
    main()
