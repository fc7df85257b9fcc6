"""Benchmark of the Chapter 12 planners on the book's scenes.

Times, per call: the C-space collision check of the 2R arm of Problem 12.7 (batched over 1000
configurations, and shape by shape), PRM / RRT / RRT-Connect on the 12.7 scene (mean over seeds, with
their success rate and path length), the unicycle RRT of 12.8, the trapezoidal decomposition and channel
path of 12.6, the GVD nodes of a room, the wavefront of 12.13 and of a 200 × 200 random grid, and a
potential-field descent of 12.10.

Beyond the book (:func:`panda_vs_ompl`): the Panda among boxes of :func:`controllers.scenes.panda_shelf`
— the collision check and the certificate's distance computation per configuration (broad phase against
the pairwise check) and, on 50 seeded queries, this project's RRT-Connect with certified edges (the
default) and in its explicit sampled mode beside OMPL's RRTConnect (PyPI ``ompl``, the ``bench`` extra;
skipped when absent) with the same validity checker (``UrdfCSpace.is_valid``), the same sampled
local-path resolution (0.05 rad, Euclidean, ⌈d/h⌉ equal steps in both) and the same extension range
(0.5 rad): success rate, median planning time (target: certified within 2× OMPL's), distance queries per
plan, distance queries and time per edge tested (the certificate's cost), validity checks per plan,
median path length, and every returned path re-checked independently (pairwise narrow phase on the
meshes, 5 mrad grid): certified paths must never fail it; OMPL's sampled paths may.

Run: ``python benchmarks/bench_planning.py`` (``--panda`` for the Panda/OMPL part only); ``rows(quick=True)``
runs 10 queries instead of 50.
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
from controllers.scenes import grid_12_13, panda_shelf, scene_12_7, scene_12_8

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


def book_rows(seeds: int = 5) -> list[dict]:
    """Per-call times of the chapter-12 operations on the book's scenes (ms; no target)."""
    space, qs, qg = scene_12_7()
    rng = np.random.default_rng(0)
    Q = rng.uniform(-np.pi, np.pi, (1000, 2))
    rows = [("2R clearance, batched (per configuration)", per_call(lambda: space.clearance(Q), 5) / 1000, ""),
            ("2R clearance, shape by shape",
             per_call(lambda: space.scene.clearance(space.robot.bodies(Q[0])), 200), "")]
    rows.append(_planner_row("PRM 12.7 (50 → 300 vertices)",
                             lambda g: prm(space, qs, qg, g, n_vertices=50, max_vertices=300), seeds))
    rows.append(_planner_row("RRT 12.7 (step 0.3 rad)", lambda g: rrt(space, qs, qg, g, step=0.3), seeds))
    rows.append(_planner_row("RRT-Connect 12.7 (step 0.3 rad)", lambda g: rrt_connect(space, qs, qg, g, step=0.3),
                             seeds))
    uspace, us, ug = scene_12_8()
    prims = [MotionPrimitive(1.0, 0.0), MotionPrimitive(1.0, 1.3), MotionPrimitive(1.0, -1.3)]
    rows.append(_planner_row("unicycle RRT 12.8 (200 vertices)",
                             lambda g: unicycle_rrt(uspace, us, ug, g, prims, 0.9, max_vertices=200,
                                                    goal_threshold=0.3), min(seeds, 3)))
    diamond = Polygon([[5, 5], [6, 4], [7, 5], [6, 6]])
    rows.append(("trapezoidal decomposition + channel path 12.6",
                 per_call(lambda: channel_path(trapezoidal_decomposition((0, 10, 0, 10), [diamond]),
                                               [5.5, 7], [5.5, 3]), 20), ""))
    room, hole = box(0, 0, 10, 6), Polygon([[4, 2], [6.5, 2.5], [5, 4]])
    rows.append(("GVD nodes, room + triangle (naive algorithm)", per_call(lambda: gvd_nodes(room, [hole]), 3), ""))
    grid = grid_12_13()
    rows.append(("wavefront 7 × 7, 2-adjacency (12.13)", per_call(lambda: wavefront(grid, (6, 6), 2), 200), ""))
    big = np.random.default_rng(1).random((200, 200)) < 0.2
    big[199, 199] = False
    rows.append(("wavefront 200 × 200, 2-adjacency", per_call(lambda: wavefront(big, (199, 199), 2), 1), ""))
    field = PotentialField(AttractivePotential([0.0, 0.0], 1.0),
                           tuple(RepulsivePotential(Disc([3.0, s], 0.5), 1.0, 1.0) for s in (0.8, -0.8)))
    rows.append(("gradient descent 12.10 (to the local minimum)",
                 per_call(lambda: gradient_descent(field.force, [3.67, 0.05], step=0.01, tol=1e-8), 20), ""))
    return [dict(measurement=f"{name} [ms]", rmpc=t * 1e3, reference=None, ref_name=note, target=None)
            for name, t, note in rows]


def panda_queries(space, n: int, seed: int = 2024) -> list[tuple[np.ndarray, np.ndarray]]:
    """n (start, goal) pairs of free configurations whose straight segment is blocked at the 0.05 rad
    samples (non-trivial queries; the set-up the OMPL comparison has always used)."""
    from planners.sampling import edge_is_free

    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        a, b = space.sample(rng), space.sample(rng)
        if space.is_valid(a) and space.is_valid(b) and not edge_is_free(space, a, b, edge_check="sampled"):
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


def panda_vs_ompl(n_queries: int = N_QUERIES, step: float = 0.5) -> list[dict]:
    """Collision check and clearance per configuration, and RRT-Connect (certified, sampled, OMPL's) on the
    Panda among boxes: rows with OMPL as the reference (none when it is not installed), and the paths
    failing the independent re-check."""
    from examples.planning import recheck_path
    from planners.sampling import path_length

    scene = panda_shelf()
    space, checker = scene.space, scene.space.checker
    rng = np.random.default_rng(0)
    Q = np.array([space.sample(rng) for _ in range(2000)])
    per_q = {}
    for name, f in (("broad", checker.in_collision), ("pairwise", checker.in_collision_pairwise),
                    ("clearances", checker.clearances)):
        t0 = time.perf_counter()
        for q in Q:
            f(q)
        per_q[name] = (time.perf_counter() - t0) / len(Q)
    out = [dict(measurement=f"Panda among {len(scene.boxes)} boxes: collision check, broad phase [µs]",
                rmpc=per_q["broad"] * 1e6, reference=per_q["pairwise"] * 1e6,
                ref_name=f"every active pair ({checker.n_pairs})", target=None),
           dict(measurement=f"Panda: the certificate's clearances, {len(checker.pair_rates)} pairs of link hulls "
                            "(GJK) [µs]",
                rmpc=per_q["clearances"] * 1e6, reference=per_q["broad"] * 1e6,
                ref_name="one collision check (broad phase)", target=None)]
    queries = panda_queries(space, n_queries)
    planners = {"certified": lambda qs, qg, k: _ours(space, qs, qg, k, step, "certified"),
                "sampled": lambda qs, qg, k: _ours(space, qs, qg, k, step, "sampled")}
    try:
        planners["OMPL"] = _ompl_planner(space, step)
    except ImportError:
        pass
    runs = {name: dict(ok=0, times=[], calls=[], queries=[], edges=[], lengths=[], failures=[])
            for name in planners}
    for k, (qs, qg) in enumerate(queries):  # the planners take turns on each query: the load hits both alike
        for name, plan in planners.items():
            run = runs[name]
            checker.calls = 0
            t0 = time.perf_counter()
            got = plan(qs, qg, k + 1)
            run["times"].append(time.perf_counter() - t0)
            run["calls"].append(checker.calls)
            path, res = got if isinstance(got, tuple) else (got, None)
            if res is not None:
                run["queries"].append(res.distance_queries)
                run["edges"].append(res.edges_tested)
            if path is None:
                continue
            run["ok"] += 1
            run["lengths"].append(path_length(space, path))
            ends = np.allclose(path[0], qs) and np.allclose(path[-1], qg)
            if not (ends and recheck_path(checker, path)[0]):
                run["failures"].append(k)
    stats = {name: dict(success=100.0 * run["ok"] / len(queries), time=np.median(run["times"]) * 1e3,
                        calls=np.median(run["calls"]), failures=run["failures"],
                        queries=np.median(run["queries"]) if run["queries"] else float("nan"),
                        per_edge=(np.sum(run["queries"]) / max(np.sum(run["edges"]), 1)) if run["edges"] else np.nan,
                        t_edge=(np.sum(run["times"]) / max(np.sum(run["edges"]), 1)) if run["edges"] else np.nan,
                        length=np.median(run["lengths"]) if run["lengths"] else float("nan"))
             for name, run in runs.items()}
    ref = stats.get("OMPL")
    ref_name = "OMPL RRTConnect, same checker and resolution" if ref else "OMPL not installed (pip install ompl)"
    cert, samp = stats["certified"], stats["sampled"]
    head = f"Panda RRT-Connect, {n_queries} queries"
    out += [
        dict(measurement=f"{head}, certified: median planning time [ms]", rmpc=cert["time"],
             reference=ref["time"] if ref else None, ref_name=ref_name, target=("ratio<=", 2.0) if ref else None),
        dict(measurement=f"{head}, sampled (not certified): median planning time [ms]", rmpc=samp["time"],
             reference=ref["time"] if ref else None, ref_name=ref_name, target=None),
        dict(measurement=f"{head}, certified: success [%]", rmpc=cert["success"],
             reference=ref["success"] if ref else None, ref_name=ref_name,
             target=(">=", ref["success"]) if ref else None),
        dict(measurement=f"{head}, sampled: success [%]", rmpc=samp["success"],
             reference=ref["success"] if ref else None, ref_name=ref_name, target=None),
        dict(measurement=f"{head}, certified: median distance queries per plan", rmpc=cert["queries"],
             reference=None, ref_name="configurations whose pair clearances were computed", target=None),
        dict(measurement=f"{head}, certified: distance queries per edge tested", rmpc=cert["per_edge"],
             reference=None, ref_name="ends + bisection points, accepted and refused edges", target=None),
        dict(measurement=f"{head}, certified: planning time per edge tested [µs]", rmpc=cert["t_edge"] * 1e6,
             reference=samp["t_edge"] * 1e6, ref_name="sampled mode, per edge (0.05 rad steps)", target=None),
        dict(measurement=f"{head}, median validity checks per plan", rmpc=samp["calls"],
             reference=ref["calls"] if ref else None, ref_name=f"rmpc sampled vs {ref_name}; certified: "
             f"{cert['calls']:.0f}", target=None),
        dict(measurement=f"{head}, certified: median path length [rad]", rmpc=cert["length"],
             reference=ref["length"] if ref else None, ref_name=ref_name, target=None),
        dict(measurement="Panda RRT-Connect, certified: returned paths failing the 5 mrad re-check",
             rmpc=float(len(cert["failures"])), reference=len(ref["failures"]) if ref else None,
             ref_name=f"queries {cert['failures']}; OMPL's: {ref['failures'] if ref else '-'}; "
             f"rmpc sampled: {samp['failures']}", target=("<=", 0.0)),
    ]
    return out


def rows(quick: bool = False) -> list[dict]:
    return book_rows(2 if quick else 5) + panda_vs_ompl(10 if quick else N_QUERIES)


def _ours(space, qs, qg, seed, step, edge_check):
    res = rrt_connect(space, qs, qg, seed, step=step, max_iterations=RRT_MAX_ITERATIONS, edge_check=edge_check)
    return (res.path if res.success else None), res


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows((book_rows() if "--panda" not in sys.argv else []) + panda_vs_ompl())
