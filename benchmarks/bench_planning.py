"""Benchmark of the Chapter 12 planners on the book's scenes.

Times, per call: the C-space collision check of the 2R arm of Problem 12.7 (batched over 1000
configurations, and shape by shape), PRM / RRT / RRT-Connect on the 12.7 scene (mean over seeds, with
their success rate and path length), the unicycle RRT of 12.8, the trapezoidal decomposition and channel
path of 12.6, the GVD nodes of a room, the wavefront of 12.13 and of a 200 × 200 random grid, and a
potential-field descent of 12.10.

Run: ``python benchmarks/bench_planning.py``.
"""

from __future__ import annotations

import time

import numpy as np

from planners.cells import channel_path, gvd_nodes, trapezoidal_decomposition
from planners.configuration_space import Disc, Polygon, box
from planners.potentials import (AttractivePotential, PotentialField, RepulsivePotential, gradient_descent,
                                 wavefront)
from planners.sampling import MotionPrimitive, prm, rrt, rrt_connect, unicycle_rrt
from problems.ch12 import SCENE_12_13, scene_12_7, scene_12_8

from benchtools import per_call


def _planner_row(name: str, plan, seeds: int = 5) -> tuple[str, float, str]:
    t, ok, lengths = 0.0, 0, []
    for seed in range(seeds):
        t0 = time.perf_counter()
        res = plan(np.random.default_rng(seed))
        t += time.perf_counter() - t0
        ok += res.success
        if res.success:
            lengths.append(res.length)
    note = f"{ok}/{seeds} solved, mean length {np.mean(lengths):.2f}" if lengths else f"{ok}/{seeds} solved"
    return name, t / seeds, note


def main() -> None:
    space, qs, qg = scene_12_7()
    rng = np.random.default_rng(0)
    Q = rng.uniform(-np.pi, np.pi, (1000, 2))
    rows = [("2R clearance, batched (per configuration)", per_call(lambda: space.clearance(Q), 5) / 1000, ""),
            ("2R clearance, shape by shape",
             per_call(lambda: space.scene.clearance(space.robot.bodies(Q[0])), 200), "")]
    rows.append(_planner_row("PRM 12.7 (50 → 300 vertices)",
                             lambda g: prm(space, qs, qg, g, n_vertices=50, max_vertices=300)))
    rows.append(_planner_row("RRT 12.7 (step 0.3 rad)", lambda g: rrt(space, qs, qg, g, step=0.3)))
    rows.append(_planner_row("RRT-Connect 12.7 (step 0.3 rad)", lambda g: rrt_connect(space, qs, qg, g, step=0.3)))
    uspace, us, ug = scene_12_8()
    prims = [MotionPrimitive(1.0, 0.0), MotionPrimitive(1.0, 1.3), MotionPrimitive(1.0, -1.3)]
    rows.append(_planner_row("unicycle RRT 12.8 (200 vertices)",
                             lambda g: unicycle_rrt(uspace, us, ug, g, prims, 0.9, max_vertices=200,
                                                    goal_threshold=0.3), seeds=3))
    diamond = Polygon([[5, 5], [6, 4], [7, 5], [6, 6]])
    rows.append(("trapezoidal decomposition + channel path 12.6",
                 per_call(lambda: channel_path(trapezoidal_decomposition((0, 10, 0, 10), [diamond]),
                                               [5.5, 7], [5.5, 3]), 20), ""))
    room, hole = box(0, 0, 10, 6), Polygon([[4, 2], [6.5, 2.5], [5, 4]])
    rows.append(("GVD nodes, room + triangle (naive algorithm)", per_call(lambda: gvd_nodes(room, [hole]), 3), ""))
    rows.append(("wavefront 7 × 7, 2-adjacency (12.13)", per_call(lambda: wavefront(SCENE_12_13, (6, 6), 2), 200), ""))
    big = np.random.default_rng(1).random((200, 200)) < 0.2
    big[199, 199] = False
    rows.append(("wavefront 200 × 200, 2-adjacency", per_call(lambda: wavefront(big, (199, 199), 2), 1), ""))
    field = PotentialField(AttractivePotential([0.0, 0.0], 1.0),
                           tuple(RepulsivePotential(Disc([3.0, s], 0.5), 1.0, 1.0) for s in (0.8, -0.8)))
    rows.append(("gradient descent 12.10 (to the local minimum)",
                 per_call(lambda: gradient_descent(field.force, [3.67, 0.05], step=0.01, tol=1e-8), 20), ""))
    print(f"{'operation':48s} {'per call':>12s}  notes")
    for name, t, note in rows:
        print(f"{name:48s} {t * 1e3:9.3f} ms  {note}")


if __name__ == "__main__":
    main()
