"""Simulated seconds per wall second of the chapter-10 closed loops (10.8–10.11) and the Panda IBVS.

Run: ``PYTHONPATH=. python benchmarks/bench_vision.py``. Each loop is the problem's own (camera block,
estimator at 1 ms where PBVS needs it, law held over T_c, arm RK4 at 1 ms or an integrator); the
post-processing of the problems (figures, true poses) is not timed. The CPU time is printed beside the
wall time: on a shared, loaded machine it is the better measure of what one idle core would do.

Measured on the loaded 2-core machine (CPU seconds; before → after the hot-path work of the vision blocks):
10.8 8.7× → 12.6× real time, 10.9 11.5× → 22.8×, 10.10 17.5× → 18.5–19.6×, 10.11 381× → 420–460×.
What is left in 10.8/10.10 is mostly the arm (ArmPlant: CRBA + RNEA + Cholesky, four RK4 stages per 1 ms)
and the loop's per-sample bookkeeping (controllers/simulation.py).
"""

from __future__ import annotations

import time

import numpy as np

import benchtools  # noqa: F401  first: it puts the source tree (examples/) on sys.path
from controllers.scenes import scara_eye_in_hand, scara_ibvs, scara_pbvs
from controllers.simulation import simulate
from examples.panda_visual_servoing import run_hybrid, run_ibvs, run_pbvs, scene, start_configuration

TC_COMPANION, TC_MANUAL = 0.04, 0.004    # the controller periods of Problems 10.8–10.11: companion files, manual's text

LOOPS = {
    "10.8 PBVS PD+g (Tc 40 ms, estimator 1 ms, arm 1 ms)":
        lambda: simulate(**scara_pbvs(TC_COMPANION, K_P=[500, 500, 10, 10], K_D=[500, 500, 10, 10])),
    "10.9 resolved-velocity PBVS (Tc 40 ms, estimator 1 ms)":
        lambda: simulate(**scara_pbvs(TC_COMPANION, K=np.array([1.0, 1.0, 1.0, 2.0]))),
    "10.10 IBVS PD+g (Tc 4 ms, arm 1 ms)":
        lambda: simulate(**scara_ibvs(TC_MANUAL, "segment", K_Ps=[300, 300, 150, 50], K_Ds=[330, 330, 165, 40])),
    "10.11 resolved-velocity IBVS (Tc 40 ms)":
        lambda: simulate(**scara_ibvs(TC_COMPANION, "segment", K_s=1.0)),
}


def rows() -> list[dict]:
    """Simulated seconds per wall second of each loop on the Python backend, the CPU figure beside it. No
    target here: the manual's 10.8–10.11 run as the problems run them (10.8 and 10.10 compiled) in
    ``bench_loop.py``, whose rows carry the ≥ 20× real-time target."""
    scara_eye_in_hand()                                  # build the model once, outside the timing
    sc = scene()
    q0 = start_configuration(sc, np.pi / 3, 0.2 * np.array([0.4, -0.3, -0.85]) / np.linalg.norm([0.4, -0.3, -0.85]))
    runs = dict(LOOPS)
    runs["Panda IBVS, 4 points (Tc 20 ms), 8 s"] = lambda: run_ibvs(sc, q0, 8.0)
    runs["Panda 2½-D (homography each sample, Tc 20 ms)"] = lambda: run_hybrid(sc, q0, 8.0)
    runs["Panda 6-DOF PBVS (homography pose, Tc 20 ms)"] = lambda: run_pbvs(sc, q0, 8.0)
    out = []
    for name, run in runs.items():
        t0, c0 = time.perf_counter(), time.process_time()
        res = run()
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        sim = float(res.t[-1] - res.t[0])
        out.append(dict(measurement=f"{name}, Python backend [simulated s / wall s]", rmpc=sim / wall,
                        reference=None, ref_name=f"{sim / cpu:.1f} per CPU s", target=None))
    return out


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
