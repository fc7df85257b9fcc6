"""Benchmark: the Python simulation loop against its Pinocchio floor, the Robotics Toolbox's ``fdyn``, and
the closed loops of the manual in simulated seconds per wall second.

* Puma 560 (``load("puma560")``, armature motors, ABA), PD + gravity compensation (8.51) with
  K_P = 100, K_D = 20 towards a set point, 2 s, RK4 at 1 ms with the controller at 1 ms. The floor is
  the Pinocchio calls alone (4 ``aba`` per RK4 step + 1 gravity per sample) timed in the same process.
  The Toolbox (``pip install rmpc[bench]``; skipped when absent) integrates the same model and law
  (continuous in time) with SciPy's RK45 at its default tolerances. Each side's integration error is
  its final state against a tight solution of its own system: rmpc's sampled loop with RK4 at 1 ms/64,
  the Toolbox's with RK45 at rtol 1e-10.
* Every problem of Chapters 5–12 that simulates (``BOOK_LOOPS``): every ``simulate`` call of the problem,
  wherever it is made (the problem's module or a helper such as ``controllers.tasks``), is timed (the rest
  of the problem — figures, checks — is not); the row is simulated seconds per wall second, target ≥ 20.
  Each problem is solved twice, the first time with an empty compiled-code cache: a problem whose loops
  run on the compiled backend (``backend="casadi"``) is rated on the second run (its compiled code
  cached, as in ``$RMPC_CACHE``) and its first run's extra wall time — CasADi code generation and the C
  compiler — is a row of its own; a Python-only problem is rated on the better of the two.

Run: ``python benchmarks/bench_loop.py`` (or ``python -m benchmarks`` for every table).
"""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin

from controllers.joint_space import PDGravityCompensation
from controllers.plants import ArmPlant
from controllers.simulation import simulate
from rigid_body.robots import load

from benchtools import best_of

K_P, K_D, T_END, H = 100.0, 20.0, 2.0, 1e-3
Q_D = np.array([0.5, -0.6, 0.3, 0.2, -0.4, 0.1])
# the problems of Chapters 5–12 that call ``simulate`` (directly or through controllers.tasks / force)
BOOK_LOOPS = ("5.2", "5.3", "6.1", "6.2", "6.3", "6.4", "7.4", "8.5", "8.7", "8.10", "8.11", "8.12", "8.13", "8.14",
              "8.15", "8.16", "9.2", "9.3", "9.4", "9.10", "9.11", "10.8", "10.9", "10.10", "10.11", "11.2", "11.5",
              "11.6", "11.8", "11.10", "11.11", "11.13", "11.14", "11.15", "11.16", "11.17", "11.18")


def puma_loop(h: float = H):
    robot = load("puma560")
    plant = ArmPlant(robot)
    return lambda: simulate(plant, PDGravityCompensation(robot, K_P, K_D, Q_D), (0.0, T_END),
                            plant.initial_state(np.zeros(6)), h=h, Ts=H)


def floor_calls(xs: np.ndarray):
    """The loop's Pinocchio calls alone along its trajectory ``xs`` (4 aba per RK4 step, 1 gravity per
    sample), as one function to time."""
    robot = load("puma560")
    model, data, tau = robot.model, robot.data, np.zeros(6)
    states = [(x[:6].copy(), x[6:].copy()) for x in xs[:-1]]

    def calls() -> None:
        for q, v in states:
            pin.computeGeneralizedGravity(model, data, q)
            for _ in range(4):
                pin.aba(model, data, q, v, tau)

    return calls


def bare_loop(q_d: np.ndarray = Q_D):
    """The same run (towards ``q_d``, from rest at q = 0) as a bare Python loop: the library's RK4 stepper on ``pin.aba`` and the PD + g law
    inline, without ``simulate``'s checks, logs and measurement objects — what the loop's generality
    costs above it."""
    from functools import partial

    from controllers.simulation import rk4_stepper

    robot = load("puma560")
    model, data = robot.model, robot.data
    step = rk4_stepper(None, H, acceleration=partial(pin.aba, model, data), time_invariant=True)
    n_samples = int(round(T_END / H)) + 1
    gravity, k_p, k_d = pin.computeGeneralizedGravity, np.full(6, K_P), np.full(6, K_D)

    def run() -> np.ndarray:
        xs, x = np.empty((n_samples, 12)), np.zeros(12)
        for k in range(n_samples):
            xs[k] = x
            q, v = x[:6], x[6:]
            u = gravity(model, data, q) + k_p * (q_d - q) - k_d * v
            if k < n_samples - 1:
                x = step(k * H, x, u)
        return xs

    return run


def toolbox(rtol: float | None = None, q_d: np.ndarray = Q_D):
    """The Toolbox's fdyn on its Puma 560 (friction off, as ArmPlant) with the same law towards ``q_d``,
    or None."""
    from benchtools import toolbox_puma_pd

    toolbox = toolbox_puma_pd(K_P, K_D, q_d)
    if toolbox is None:
        return None
    puma, law = toolbox
    args = {} if rtol is None else {"solver_args": {"rtol": rtol, "atol": 1e-12}}
    return lambda: puma.fdyn(T_END, np.zeros(6), law, **args)


def book_loops(pid: str) -> tuple[float, float, bool]:
    """(simulated seconds, wall seconds inside ``simulate``, whether a loop ran compiled) of problem ``pid``."""
    import sys

    import controllers.simulation as simulation
    from problems.registry import get

    prob = get(pid)
    original = simulation.simulate
    spent = [0.0, 0.0, False]

    def timed(plant, controller, t_span, *args, **kwargs):
        t0 = time.perf_counter()
        res = original(plant, controller, t_span, *args, **kwargs)
        spent[1] += time.perf_counter() - t0
        spent[0] += t_span[1] - t_span[0]
        spent[2] = spent[2] or kwargs.get("backend", "python") != "python"
        return res

    holders = [m for m in list(sys.modules.values()) if getattr(m, "simulate", None) is original]
    for module in holders:
        module.simulate = timed
    try:
        prob.solve()
    finally:
        for module in holders:
            module.simulate = original
    return spent[0], spent[1], spent[2]


def book_loop_rows(pids: tuple[str, ...] = BOOK_LOOPS) -> list[dict]:
    """One row per problem (simulated s / wall s, target ≥ 20) and, for compiled loops, their compile time."""
    import tempfile
    from pathlib import Path

    import controllers.compiled as compiled
    import rigid_body.codegen as codegen

    out = []
    with tempfile.TemporaryDirectory() as cache:
        saved = codegen.CACHE
        codegen.CACHE = Path(cache)                            # cold: nothing compiled yet
        try:
            for pid in pids:
                codegen._loaded.clear()
                compiled._LOOPS.clear()
                simulated, cold, uses_compiled = book_loops(pid)
                codegen._loaded.clear()                        # warm: the libraries are on disk (a new process)
                compiled._LOOPS.clear()
                warm = book_loops(pid)[1]
                name = f"problem {pid} closed loops{' (compiled)' if uses_compiled else ''} [sim s / wall s]"
                out.append(dict(measurement=name, rmpc=simulated / (warm if uses_compiled else min(cold, warm)),
                                reference=None, ref_name="", target=(">=", 20.0)))
                if uses_compiled:
                    out.append(dict(measurement=f"  {pid}: code generation + C compiler, first run [s]",
                                    rmpc=max(cold - warm, 0.0), reference=None, ref_name="cached afterwards",
                                    target=None))
        finally:
            codegen.CACHE = saved
    return out


def rows() -> list[dict]:
    loop = puma_loop()
    res = loop()
    floor = floor_calls(res.x)
    bare = bare_loop()
    if not np.array_equal(bare(), res.x):
        raise AssertionError("the bare loop left the simulated trajectory")
    t_loop = t_floor = t_bare = float("inf")
    for _ in range(5):       # interleaved, so that a change of the machine's load hits all alike
        t_loop, t_floor = min(t_loop, best_of(loop, 1)[0]), min(t_floor, best_of(floor, 1)[0])
        t_bare = min(t_bare, best_of(bare, 1)[0])
    tight = puma_loop(H / 64)()
    err_rmpc = float(np.max(np.abs(res.x[-1] - tight.x[-1])))
    out = [
        dict(measurement="Puma PD+g 2 s, RK4 1 ms, Python loop [ms]", rmpc=t_loop * 1e3, reference=t_floor * 1e3,
             ref_name="its Pinocchio calls alone", target=("ratio<=", 2.0)),
        dict(measurement="  bare Python loop: the same stepper and law, no checks or logs [ms]", rmpc=t_bare * 1e3,
             reference=t_floor * 1e3, ref_name="its Pinocchio calls alone", target=None),
        dict(measurement="  final max |q_d - q| [rad]", rmpc=float(np.max(np.abs(Q_D - res.q[-1]))), reference=None,
             ref_name="", target=None),
        dict(measurement="  integration error at 2 s [rad, rad/s]", rmpc=err_rmpc, reference=None,
             ref_name="vs RK4 at 1 ms/64", target=None),
    ]
    run = toolbox()
    if run is None:
        out.append(dict(measurement="  Robotics Toolbox fdyn: not installed (pip install rmpc[bench])", rmpc=t_loop * 1e3,
                        reference=None, ref_name="", target=None))
    else:
        t_rtb, tg = best_of(run)
        ref = toolbox(1e-10)()
        x_rtb, x_ref = np.r_[tg.q[-1], tg.qd[-1]], np.r_[ref.q[-1], ref.qd[-1]]
        out += [
            dict(measurement="Puma PD+g 2 s, Python loop vs Toolbox fdyn [ms]", rmpc=t_loop * 1e3,
                 reference=t_rtb * 1e3, ref_name="roboticstoolbox fdyn (RK45)", target=("ratio<=", 1.0)),
            dict(measurement="  Toolbox final max |q_d - q| [rad]", rmpc=float(np.max(np.abs(Q_D - tg.q[-1]))),
                 reference=None, ref_name="", target=None),
            dict(measurement="  Toolbox integration error at 2 s [rad, rad/s]",
                 rmpc=float(np.max(np.abs(x_rtb - x_ref))), reference=None, ref_name="vs RK45 at rtol 1e-10",
                 target=None),
        ]
    return out + book_loop_rows()


if __name__ == "__main__":
    import sys

    from benchtools import print_rows

    # ``python benchmarks/bench_loop.py 8.12 9.3``: only those problems' loops
    print_rows(book_loop_rows(tuple(sys.argv[1:])) if len(sys.argv) > 1 else rows())
