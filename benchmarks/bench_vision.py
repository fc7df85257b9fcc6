"""Simulated seconds per wall second of the chapter-10 closed loops (10.8–10.11) and the Panda IBVS.

Run: ``PYTHONPATH=. python benchmarks/bench_vision.py``. Each loop is the problem's own (camera block,
estimator at 1 ms where PBVS needs it, law held over T_c, arm RK4 at 1 ms or an integrator); the
post-processing of the problems (figures, true poses) is not timed. The CPU time is printed beside the
wall time: on a shared, loaded machine it is the better measure of what one idle core would do.
"""

from __future__ import annotations

import time

import numpy as np

from controllers.simulation import simulate
from examples.panda_visual_servoing import run_ibvs, scene, start_configuration
from problems.ch10 import TC_COMPANION, TC_MANUAL, ibvs_setup, pbvs_setup, scara_eye_in_hand

LOOPS = {
    "10.8 PBVS PD+g (Tc 40 ms, estimator 1 ms, arm 1 ms)":
        lambda: simulate(**pbvs_setup(TC_COMPANION, K_P=[500, 500, 10, 10], K_D=[500, 500, 10, 10])),
    "10.9 resolved-velocity PBVS (Tc 40 ms, estimator 1 ms)":
        lambda: simulate(**pbvs_setup(TC_COMPANION, K=np.array([1.0, 1.0, 1.0, 2.0]))),
    "10.10 IBVS PD+g (Tc 4 ms, arm 1 ms)":
        lambda: simulate(**ibvs_setup(TC_MANUAL, "segment", K_Ps=[300, 300, 150, 50], K_Ds=[330, 330, 165, 40])),
    "10.11 resolved-velocity IBVS (Tc 40 ms)":
        lambda: simulate(**ibvs_setup(TC_COMPANION, "segment", K_s=1.0)),
}


def main() -> dict[str, float]:
    scara_eye_in_hand()                                  # build the model once, outside the timing
    sc = scene()
    q0 = start_configuration(sc, np.pi / 3, 0.2 * np.array([0.4, -0.3, -0.85]) / np.linalg.norm([0.4, -0.3, -0.85]))
    runs = dict(LOOPS)
    runs["Panda IBVS, 4 points (Tc 20 ms), 8 s"] = lambda: run_ibvs(sc, q0, 8.0)
    out = {}
    for name, run in runs.items():
        t0, c0 = time.perf_counter(), time.process_time()
        res = run()
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        sim = float(res.t[-1] - res.t[0])
        out[name] = sim / wall
        print(f"{name:58s} {sim:4.1f} s simulated: wall {wall:6.3f} s ({sim / wall:6.1f}× real time), "
              f"CPU {cpu:6.3f} s ({sim / cpu:6.1f}×)")
    return out


if __name__ == "__main__":
    main()
