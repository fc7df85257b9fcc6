"""Benchmark of the Chapter 12 planners on the book's scenes.

Times, per call: the C-space collision check of the 2R arm of Problem 12.7 (batched over 1000
configurations, and shape by shape), PRM / RRT / RRT-Connect on the 12.7 scene (mean over seeds, with
their success rate and path length), the unicycle RRT of 12.8, the trapezoidal decomposition and channel
path of 12.6, the GVD nodes of a room, the wavefront of 12.13 and of a 200 × 200 random grid, and a
potential-field descent of 12.10.

Beyond the book (:func:`panda_vs_ompl`): the Panda among boxes of :func:`examples.planning.panda_shelf`
— the collision check per configuration (broad phase against the pairwise check) and, on 50 seeded
queries, this project's RRT-Connect beside OMPL's RRTConnect (PyPI ``ompl``; skipped when absent)
with the same validity checker (``UrdfCSpace.is_valid``), the same local-path resolution (0.05 rad,
Euclidean, ⌈d/h⌉ equal steps in both) and the same extension range (0.5 rad): success rate, validity
calls per plan, median planning time and path length, every returned path re-checked independently
(pairwise narrow phase on a 5 mrad grid).

Run: ``python benchmarks/bench_planning.py`` (``--panda`` for the Panda/OMPL part only).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from planners.cells import channel_path, gvd_nodes, trapezoidal_decomposition
from planners.configuration_space import Disc, Polygon, box
from planners.potentials import (AttractivePotential, PotentialField, RepulsivePotential, gradient_descent,
                                 wavefront)
from planners.sampling import MotionPrimitive, prm, rrt, rrt_connect, unicycle_rrt
from problems.ch12 import SCENE_12_13, scene_12_7, scene_12_8

from benchtools import per_call

N_QUERIES = 50
OMPL_TIME_LIMIT = 10.0     # [s] per query
RRT_MAX_ITERATIONS = 20000


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


def panda_queries(space, n: int, seed: int = 2024) -> list[tuple[np.ndarray, np.ndarray]]:
    """n (start, goal) pairs of free configurations whose straight segment is blocked (non-trivial
    queries), the first one the shelf query of the example."""
    from planners.sampling import edge_is_free

    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        a, b = space.sample(rng), space.sample(rng)
        if space.is_valid(a) and space.is_valid(b) and not edge_is_free(space, a, b):
            out.append((a, b))
    return out


def _ompl_planner(space, step: float, seed: int = 1):
    """OMPL's RRTConnect on the same joint box, validity checker and resolution; returns plan(qs, qg, query)."""
    from ompl import base as ob, geometric as og, util as ou

    ou.setLogLevel(ou.LOG_ERROR)
    ou.RNG.setSeed(seed)          # once, before any OMPL object (OMPL seeds its generators once; 0 is rejected)
    n = space.dim

    def plan(qs, qg, _query):
        ss_space = ob.RealVectorStateSpace(n)
        bounds = ob.RealVectorBounds(n)
        for i in range(n):
            bounds.setLow(i, float(space.lower[i]))
            bounds.setHigh(i, float(space.upper[i]))
        ss_space.setBounds(bounds)
        ss = og.SimpleSetup(ss_space)
        ss.setStateValidityChecker(lambda s: space.is_valid(np.array([s[i] for i in range(n)])))
        si = ss.getSpaceInformation()
        si.setStateValidityCheckingResolution(space.resolution / ss_space.getMaximumExtent())
        start, goal = ss_space.allocState(), ss_space.allocState()
        for i in range(n):
            start[i], goal[i] = float(qs[i]), float(qg[i])
        ss.setStartAndGoalStates(start, goal)
        planner = og.RRTConnect(si)
        planner.setRange(step)
        ss.setPlanner(planner)
        ss.setup()
        ss.solve(OMPL_TIME_LIMIT)
        if not ss.haveExactSolutionPath():
            return None
        path = ss.getSolutionPath()
        return np.array([[path.getState(k)[i] for i in range(n)] for k in range(path.getStateCount())])

    return plan


def panda_vs_ompl(n_queries: int = N_QUERIES, step: float = 0.5) -> None:
    """Collision check per configuration and RRT-Connect (ours and OMPL's) on the Panda among boxes."""
    from examples.planning import panda_shelf, recheck_path
    from planners.sampling import path_length

    scene = panda_shelf()
    space, checker = scene.space, scene.space.checker
    rng = np.random.default_rng(0)
    Q = np.array([space.sample(rng) for _ in range(2000)])
    print(f"Panda among {len(scene.boxes)} boxes: {checker.n_pairs} active pairs "
          f"({checker.n_self_pairs} self-collision after SRDF + adjacency)")
    for name, f in (("broad phase (dynamic AABB tree)", checker.in_collision),
                    ("pairwise (every active pair)", checker.in_collision_pairwise)):
        t0, c0 = time.perf_counter(), time.process_time()
        hits = sum(f(q) for q in Q)
        wall, cpu = (time.perf_counter() - t0) / len(Q), (time.process_time() - c0) / len(Q)
        print(f"  collision check, {name:34s} {wall * 1e6:7.1f} µs wall, {cpu * 1e6:7.1f} µs CPU "
              f"per configuration ({hits}/{len(Q)} in collision)")
    queries = panda_queries(space, n_queries)
    planners = {"rmpc rrt_connect": lambda qs, qg, k: _ours(space, qs, qg, k, step)}
    try:
        planners["OMPL RRTConnect"] = _ompl_planner(space, step)
    except ImportError:
        print("  (ompl not installed: `pip install ompl` for the side-by-side comparison)")
    print(f"  {n_queries} queries (free start/goal, straight segment blocked), range {step} rad, "
          f"local paths every {space.resolution} rad")
    print(f"  {'planner':18s} {'success':>8s} {'re-check':>9s} {'median t':>10s} {'median CPU':>11s} "
          f"{'calls/plan':>11s} {'median length':>14s}")
    failures = []
    for name, plan in planners.items():
        ok, free, times, cpus, calls, lengths = 0, 0, [], [], [], []
        for k, (qs, qg) in enumerate(queries):
            checker.calls = 0
            t0, c0 = time.perf_counter(), time.process_time()
            path = plan(qs, qg, k + 1)
            times.append(time.perf_counter() - t0)
            cpus.append(time.process_time() - c0)
            calls.append(checker.calls)
            if path is None:
                continue
            ok += 1
            lengths.append(path_length(space, path))
            ends = np.allclose(path[0], qs) and np.allclose(path[-1], qg)
            clear = recheck_path(checker, path)[0]
            free += ends and clear
            if not (ends and clear):
                failures.append(f"{name}, query {k}: " + ("wrong end points" if not ends else
                                "a contact between states its checker accepted (re-check grid 5 mrad)"))
        print(f"  {name:18s} {ok:4d}/{len(queries):<3d} {free:5d}/{ok:<3d} {np.median(times) * 1e3:8.1f} ms "
              f"{np.median(cpus) * 1e3:8.1f} ms {np.median(calls):11.0f} {np.median(lengths):14.2f}")
    for f in failures:
        print(f"  re-check failed: {f}")


def _ours(space, qs, qg, seed, step):
    res = rrt_connect(space, qs, qg, np.random.default_rng(seed), step=step, max_iterations=RRT_MAX_ITERATIONS)
    return res.path if res.success else None


if __name__ == "__main__":
    if "--panda" not in sys.argv:
        main()
    panda_vs_ompl()
