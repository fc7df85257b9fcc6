"""The compiled closed loop (``simulate(..., backend="casadi")``) against the Python loop and raw Pinocchio.

PD + gravity compensation (K_P = 100, K_D = 20) on a Puma-560-like 6-DOF arm (the Toolbox's DH
table, masses and diagonal rotor armature), 2 s, RK4 at h = 1 ms with the controller at 1 ms. Rows:
the Python loop, the compiled run (compile time reported apart), the floor of the same loop written
with raw Pinocchio calls in a Python loop (``pin.aba`` + ``pin.computeGeneralizedGravity``), and the
Robotics Toolbox's ``fdyn`` on its Puma 560 when ``roboticstoolbox-python`` is installed (the
``bench`` extra).

Run: ``python benchmarks/bench_compiled.py``.
"""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin

from controllers.compiled import CompiledLoop, compiler
from controllers.joint_space import PDGravityCompensation
from controllers.plants import ArmPlant
from controllers.simulation import simulate
from rigid_body.dh import DHLink
from rigid_body.robots import Robot, load, robot_from_dh

T_END, H, K_P, K_D = 2.0, 1e-3, 100.0, 20.0
Q0 = np.zeros(6)
Q_D = np.array([0.0, np.pi / 4, -np.pi / 2, 0.0, np.pi / 4, 0.0])        # the Toolbox's qn-like set point

# Corke's Puma 560 (standard DH): a, alpha, d; mass, centre of mass, principal inertias; motor inertia
# J_m and gear ratio G (armature J_m G² on the joint side, the Toolbox's diagonal model).
_PUMA = [
    (0.0, np.pi / 2, 0.0, 0.0, (0, 0, 0), (0, 0.35, 0), 200e-6, -62.6111),
    (0.4318, 0.0, 0.0, 17.4, (-0.3638, 0.006, 0.2275), (0.13, 0.524, 0.539), 200e-6, 107.815),
    (0.0203, -np.pi / 2, 0.15005, 4.8, (-0.0203, -0.0141, 0.070), (0.066, 0.086, 0.0125), 200e-6, -53.7063),
    (0.0, np.pi / 2, 0.4318, 0.82, (0, 0.019, 0), (1.8e-3, 1.3e-3, 1.8e-3), 33e-6, 76.0364),
    (0.0, -np.pi / 2, 0.0, 0.34, (0, 0, 0), (0.3e-3, 0.4e-3, 0.3e-3), 33e-6, 71.923),
    (0.0, 0.0, 0.0, 0.09, (0, 0, 0.032), (0.15e-3, 0.15e-3, 0.04e-3), 33e-6, 76.686),
]


def puma560() -> Robot:
    """``load("puma560")`` when rmpc has it, else a Puma-560-like arm from its DH table with armature."""
    try:
        return load("puma560")
    except ValueError:
        pass
    links = [DHLink(a=a, alpha=al, d=d, mass=max(m, 1e-3), com=c, inertia=np.diag(np.maximum(I, 1e-6)))
             for a, al, d, m, c, I, _, _ in _PUMA]
    robot = robot_from_dh(links, name="puma560_like")
    robot.model.armature[:] = [Jm * G**2 for *_, Jm, G in _PUMA]
    robot.data = robot.model.createData()
    return robot


def raw_pinocchio_loop(robot: Robot, x0: np.ndarray) -> np.ndarray:
    """The floor: the same RK4 + ZOH loop with raw Pinocchio calls (no validation, no logging)."""
    m, d, n = robot.model, robot.data, robot.nv
    Kp, Kd = K_P * np.eye(n), K_D * np.eye(n)

    def f(x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return np.concatenate([x[n:], pin.aba(m, d, x[:n], x[n:], u)])

    x = x0.copy()
    for _ in range(int(round(T_END / H))):
        u = pin.computeGeneralizedGravity(m, d, x[:n]) + Kp @ (Q_D - x[:n]) - Kd @ x[n:]
        k1 = f(x, u)
        k2 = f(x + 0.5 * H * k1, u)
        k3 = f(x + 0.5 * H * k2, u)
        k4 = f(x + H * k3, u)
        x = x + (H / 6.0) * (k1 + 2 * k2 + 2 * k3 + k4)
    return x


def toolbox_fdyn() -> float | None:
    """Wall time [s] of the Robotics Toolbox's ``fdyn`` on the same 2 s run (its Puma 560 without friction,
    the same PD + gravity law, SciPy's RK45 at its default tolerances; best of 3), or None when the
    Toolbox is absent (``bench_loop.toolbox``)."""
    from bench_loop import toolbox

    run = toolbox(q_d=Q_D)
    return None if run is None else best_of(run, 3)


def best_of(f, rounds: int = 3) -> float:
    best = float("inf")
    for _ in range(rounds):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def rows() -> list[dict]:
    robot = puma560()
    plant = ArmPlant(robot)
    controller = PDGravityCompensation(robot, K_P, K_D, Q_D)
    x0 = plant.initial_state(Q0)
    n_samples = int(round(T_END / H)) + 1
    loop = CompiledLoop(plant, controller, H, 1, n_samples)
    loop.arrays(0.0, x0)
    t_compiled = best_of(lambda: loop.arrays(0.0, x0), 5)
    t_python = best_of(lambda: simulate(plant, controller, (0.0, T_END), x0, h=H), 1)
    t_raw = best_of(lambda: raw_pinocchio_loop(robot, x0), 1)
    compiled_how = "gcc" if compiler() else "interpreted"
    out = [
        dict(measurement="Puma PD+g 2 s closed loop, Python backend [ms]", rmpc=t_python * 1e3,
             reference=t_raw * 1e3, ref_name="raw Pinocchio loop", target=None),
        dict(measurement=f"Puma PD+g 2 s closed loop, compiled ({compiled_how}) [ms]", rmpc=t_compiled * 1e3,
             reference=t_raw * 1e3, ref_name="raw Pinocchio loop", target=("<=", 10.0)),
        dict(measurement="  its build + compile time (once) [s]", rmpc=loop.compile_time, reference=None,
             ref_name="", target=None),
    ]
    t_rtb = toolbox_fdyn()
    if t_rtb is not None:
        out.append(dict(measurement="Puma PD+g 2 s, compiled vs Toolbox fdyn [ms]", rmpc=t_compiled * 1e3,
                        reference=t_rtb * 1e3, ref_name="roboticstoolbox fdyn (RK45), the same 2 s run",
                        target=("ratio<=", 0.2)))            # at least 5× faster
    return out


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
