"""The compiled closed loop at the call users make: ``simulate(..., backend="casadi")`` against the bare
compiled run, the Python loop and the Robotics Toolbox's ``fdyn``.

PD + gravity compensation (K_P = 100, K_D = 20) on the Puma 560 (``load("puma560")``: the Toolbox's DH
table, masses and diagonal rotor armature), 2 s, RK4 at h = 1 ms with the controller at 1 ms. Rows:

* the user's call ``simulate(plant, controller, (0, 2), x0, h=1e-3, Ts=1e-3, backend="casadi")``, repeated with
  the same plant and controller (the loop built once and reused: its key is a digest of the blocks'
  structure, computed at each call) against the bare compiled run (the compiled code on inputs already
  sampled: :meth:`controllers.compiled.CompiledLoop._call`) — target ≤ 1.3;
* the same call against the Toolbox's ``fdyn`` on its Puma 560 (``roboticstoolbox-python``, the ``bench``
  extra; SciPy's RK45 at its default tolerances) — target ≥ 5× faster — and against the Python loop;
* apart, the first call of a new process: with an empty cache (symbolic build, C generation and the C
  compiler) and with the run on disk (the key, loading the library: nothing symbolic is built).

Run: ``python benchmarks/bench_compiled.py``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from controllers.compiled import compiled_loop
from controllers.joint_space import PDGravityCompensation
from controllers.plants import ArmPlant
from controllers.simulation import simulate
from rigid_body.codegen import compiler
from rigid_body.robots import load

from benchtools import best_of, best_times

T_END, H, K_P, K_D = 2.0, 1e-3, 100.0, 20.0
Q0 = np.zeros(6)
Q_D = np.array([0.0, np.pi / 4, -np.pi / 2, 0.0, np.pi / 4, 0.0])        # the Toolbox's qn-like set point
ROOT = Path(__file__).resolve().parents[1]

_FIRST_CALL = """
import json, sys, time
t0 = time.perf_counter()
sys.path.insert(0, {root!r})
import numpy as np
from controllers.compiled import compiled_loop
from controllers.joint_space import PDGravityCompensation
from controllers.plants import ArmPlant
from controllers.simulation import simulate
from rigid_body.robots import load
robot = load("puma560")
plant, controller = ArmPlant(robot), PDGravityCompensation(robot, {K_P}, {K_D}, np.array({Q_D}))
x0 = plant.initial_state(np.zeros(6))
t1 = time.perf_counter()
simulate(plant, controller, (0.0, {T_END}), x0, h={H}, Ts={H}, backend="casadi")
t2 = time.perf_counter()
loop = compiled_loop(plant, controller, {H}, 1, {N})
print(json.dumps(dict(call=t2 - t1, build=loop.build_time, lookup=loop.lookup_time)))
"""


def toolbox_fdyn() -> float | None:
    """Wall time [s] of the Robotics Toolbox's ``fdyn`` on the same 2 s run (its Puma 560 without friction,
    the same PD + gravity law, SciPy's RK45 at its default tolerances; best of 3), or None when the
    Toolbox is absent (``bench_loop.toolbox``)."""
    from bench_loop import toolbox

    run = toolbox(q_d=Q_D)
    return None if run is None else best_of(run, 3)[0]


def first_calls() -> tuple[dict, dict]:
    """The first ``simulate(..., backend="casadi")`` of a new process, (empty cache, cache holding the run)."""
    script = _FIRST_CALL.format(root=str(ROOT), K_P=K_P, K_D=K_D, Q_D=Q_D.tolist(), T_END=T_END, H=H,
                                N=int(round(T_END / H)) + 1)
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "RMPC_CACHE": cache}
        runs = [json.loads(subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, check=True,
                                          text=True).stdout) for _ in range(2)]
    return runs[0], runs[1]


def rows() -> list[dict]:
    robot = load("puma560")
    plant = ArmPlant(robot)
    controller = PDGravityCompensation(robot, K_P, K_D, Q_D)
    x0 = plant.initial_state(Q0)

    def user_call():
        return simulate(plant, controller, (0.0, T_END), x0, h=H, Ts=H, backend="casadi")

    user_call()                                              # built (or loaded) once, then reused
    loop = compiled_loop(plant, controller, H, 1, int(round(T_END / H)) + 1)
    R, p, _ = loop.inputs(0.0)
    t_user, t_bare = best_times([user_call, lambda: loop._call(x0, R, p)], repetitions=2, rounds=61)
    t_key = best_times([lambda: compiled_loop(plant, controller, H, 1, loop.n_samples)], 20, 15)[0]
    t_python = best_of(lambda: simulate(plant, controller, (0.0, T_END), x0, h=H, Ts=H), 3)[0]
    how = "gcc" if compiler() else "no compiler: the Python loop"
    out = [
        dict(measurement=f"Puma PD+g 2 s, simulate(..., backend='casadi') repeated ({how}) [ms]", rmpc=t_user * 1e3,
             reference=t_bare * 1e3, ref_name="the bare compiled run (inputs ready)", target=("ratio<=", 1.3)),
        dict(measurement="  the same call / the Python loop [ms]", rmpc=t_user * 1e3, reference=t_python * 1e3,
             ref_name="simulate(..., backend='python')", target=None),
        dict(measurement="  its key and loop lookup (structure digest, no code generated) [ms]", rmpc=t_key * 1e3,
             reference=None, ref_name="per call", target=None),
    ]
    cold, warm = first_calls()
    out += [
        dict(measurement="  first call of a new process, empty cache: build + C compiler [s]", rmpc=cold["call"],
             reference=None, ref_name=f"of which building and compiling {cold['build']:.2f} s", target=None),
        dict(measurement="  first call of a new process, run on disk: key + load [ms]", rmpc=warm["call"] * 1e3,
             reference=None, ref_name=f"lookup {warm['lookup'] * 1e3:.1f} ms, nothing built", target=None),
    ]
    t_rtb = toolbox_fdyn()
    if t_rtb is not None:
        out.append(dict(measurement="Puma PD+g 2 s, simulate(..., backend='casadi') vs Toolbox fdyn [ms]",
                        rmpc=t_user * 1e3, reference=t_rtb * 1e3,
                        ref_name="roboticstoolbox fdyn (RK45), the same 2 s run", target=("ratio<=", 0.2)))
    return out


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
