"""The compiled closed loop (``simulate(..., backend="casadi")``) against the Python loop and raw Pinocchio.

PD + gravity compensation (K_P = 100, K_D = 20) on the Puma 560 (``load("puma560")``: the Toolbox's DH
table, masses and diagonal rotor armature), 2 s, RK4 at h = 1 ms with the controller at 1 ms. Rows:
the Python loop, the compiled run (compile time reported apart), the bare Python loop of
``bench_loop`` (the same stepper on ``pin.aba`` and the law inline, no checks or logs), and the
Robotics Toolbox's ``fdyn`` on its Puma 560 when ``roboticstoolbox-python`` is installed (the
``bench`` extra).

Run: ``python benchmarks/bench_compiled.py``.
"""

from __future__ import annotations

import numpy as np

from controllers.compiled import CompiledLoop, compiler
from controllers.joint_space import PDGravityCompensation
from controllers.plants import ArmPlant
from controllers.simulation import simulate
from rigid_body.robots import load

from benchtools import best_of

T_END, H, K_P, K_D = 2.0, 1e-3, 100.0, 20.0
Q0 = np.zeros(6)
Q_D = np.array([0.0, np.pi / 4, -np.pi / 2, 0.0, np.pi / 4, 0.0])        # the Toolbox's qn-like set point

def toolbox_fdyn() -> float | None:
    """Wall time [s] of the Robotics Toolbox's ``fdyn`` on the same 2 s run (its Puma 560 without friction,
    the same PD + gravity law, SciPy's RK45 at its default tolerances; best of 3), or None when the
    Toolbox is absent (``bench_loop.toolbox``)."""
    from bench_loop import toolbox

    run = toolbox(q_d=Q_D)
    return None if run is None else best_of(run, 3)[0]


def rows() -> list[dict]:
    from bench_loop import bare_loop

    robot = load("puma560")
    plant = ArmPlant(robot)
    controller = PDGravityCompensation(robot, K_P, K_D, Q_D)
    x0 = plant.initial_state(Q0)
    n_samples = int(round(T_END / H)) + 1
    loop = CompiledLoop(plant, controller, H, 1, n_samples)
    loop.arrays(0.0, x0)
    t_compiled = best_of(lambda: loop.arrays(0.0, x0), 5)[0]
    t_python = best_of(lambda: simulate(plant, controller, (0.0, T_END), x0, h=H), 1)[0]
    t_raw = best_of(bare_loop(Q_D), 1)[0]
    compiled_how = "gcc" if compiler() else "interpreted"
    out = [
        dict(measurement="Puma PD+g 2 s closed loop, Python backend [ms]", rmpc=t_python * 1e3,
             reference=t_raw * 1e3, ref_name="bare Python loop", target=None),
        dict(measurement=f"Puma PD+g 2 s closed loop, compiled ({compiled_how}) [ms]", rmpc=t_compiled * 1e3,
             reference=t_raw * 1e3, ref_name="bare Python loop", target=("<=", 10.0)),
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
