"""Beyond the book: the sampling planners of Ch. 12 on URDF arms among boxes, then timed and re-checked.

Two scenes (:mod:`controllers.scenes`): the Panda (example-robot-data, its SRDF's self-collision filter) reaching
from inside a shelf (a table, a shelf board and a back panel) to above the board (``panda_shelf``), and the book's
anthropomorphic arm (Sect. 2.9.4, DH table, cylinders) swinging over a pillar standing on a table
(``anthropomorphic_pillar``). For each, the one call
sequence that cannot produce a colliding motion (:func:`plan_and_time`): RRT-Connect or PRM (Sect. 12.5)
in :class:`planners.collision.UrdfCSpace` with certified edges, certified random shortcutting, then the
time-optimal timing of the certified polyline with certified blends
(:func:`planners.time_optimal.time_optimal_path` with ``space``) under velocity, acceleration and torque
limits — and an independent re-check of the *timed* motion on a fine grid with the pairwise narrow phase
on the collision meshes (no broad phase, no certificate). The multi-segment law (:func:`time_path`, after
the Toolbox's ``mstraj``) is kept for comparison: its blends cut the polyline's corners unchecked, and the
re-check catches them.
Not a problem of the book: run it from a notebook or ``python -m examples.planning``; each scene returns
a :class:`problems.registry.Solution`.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 12.5 (PRM, bidirectional RRT), Sect. 4.2.2 (linear segments with parabolic blends, Problem 4.6).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from controllers.scenes import Scenario, anthropomorphic_pillar, panda_shelf
from rmpc import (CollisionChecker, JointLimits, PlanResult, prm, rrt_connect, shortcut, time_optimal_path,
                  TimeOptimalPath)
from planners.sampling import path_length
from planners.timing import PiecewisePolynomial, multi_segment_law
from problems.common import label_axes, subplots
from problems.registry import Solution
from rigid_body.validation import as_positive
from viewer import box_overlays, frame_path

__all__ = ["TimedMotion", "plan", "limits", "time_path", "recheck", "recheck_path", "plan_and_time", "planning_demo"]

RECHECK_STEP = 0.005     # fine grid of the independent re-check [rad, max-norm]


def plan(scenario: Scenario, planner: str, seed: int, edge_check: str = "certified") -> PlanResult:
    """RRT-Connect (step 0.5 rad) or PRM (10 neighbours within 5 rad) from q_start to q_goal, edges certified."""
    if planner == "rrt_connect":
        return rrt_connect(scenario.space, scenario.q_start, scenario.q_goal, seed, step=0.5, max_iterations=5000,
                           edge_check=edge_check)
    if planner == "prm":
        return prm(scenario.space, scenario.q_start, scenario.q_goal, seed, n_vertices=100, max_neighbors=10,
                   max_distance=5.0, max_vertices=1000, edge_check=edge_check)
    raise ValueError(f"`planner` must be 'rrt_connect' or 'prm', got {planner!r}")


def limits(scenario: Scenario) -> JointLimits:
    """The timing limits: the scenario's q̇_max and q̈_max, the URDF's torque limits (none where it gives 0)."""
    model = scenario.robot.model
    tau = np.where(np.asarray(model.effortLimit) > 0, np.asarray(model.effortLimit), np.inf)
    return JointLimits(np.asarray(model.lowerPositionLimit), np.asarray(model.upperPositionLimit),
                       scenario.qd_max, scenario.qdd_max, tau)


def time_path(path: Any, qd_max: Any, qdd_max: Any) -> PiecewisePolynomial:
    """The multi-segment law (:func:`planners.timing.multi_segment_law`) through the waypoints under |q̇_j| ≤ q̇_max,j and |q̈_j| ≤ q̈_max,j.

    Each segment runs at its slowest joint's speed limit (so |q̇_j| ≤ q̇_max,j); a blend of duration
    t_acc changes the velocity by at most 2 q̇_max,j, so t_acc = max_j 2 q̇_max,j / q̈_max,j keeps
    |q̈_j| = |Δq̇_j| / t_acc ≤ q̈_max,j.
    """
    qd_max, qdd_max = np.asarray(qd_max, dtype=float), np.asarray(qdd_max, dtype=float)
    if np.any(qd_max <= 0) or np.any(qdd_max <= 0):
        raise ValueError(f"`qd_max` and `qdd_max` must be positive, got {qd_max}, {qdd_max}")
    t_acc = float(np.max(2.0 * qd_max / qdd_max))
    return multi_segment_law(path, qd_max, t_acc)


def recheck(checker: CollisionChecker, law: Callable[[Any], tuple], step: float = RECHECK_STEP
            ) -> tuple[bool, int, float]:
    """Independent re-check of a timed motion (a law or a :class:`planners.time_optimal.TimeOptimalPath`,
    callable t → (q, q̇, q̈) with ``t_i``, ``t_f``): the motion sampled so that no joint moves more than
    ``step`` rad between samples, each sample tested with the pairwise narrow phase (every active pair,
    no broad phase). Returns (collision-free, samples checked, instant of the first contact or NaN)."""
    as_positive(step, "step")
    t = np.linspace(law.t_i, law.t_f, 201)
    q = np.reshape(law(t)[0], (t.size, -1))
    # refine each interval so that max_j |Δq_j| <= step (q is Lipschitz: refine by the chord, then verify)
    counts = np.maximum(np.ceil(np.abs(np.diff(q, axis=0)).max(axis=1) / step), 1).astype(int) * 2
    fine = np.concatenate([np.linspace(a, b, n, endpoint=False) for a, b, n in zip(t[:-1], t[1:], counts)]
                          + [t[-1:]])
    Q = np.reshape(law(fine)[0], (fine.size, -1))
    if np.abs(np.diff(Q, axis=0)).max() > step:
        raise RuntimeError("re-check grid coarser than `step` (refine the sampling)")
    k = _first_contact(checker, Q)
    return k is None, len(Q), float("nan") if k is None else float(fine[k])


def _first_contact(checker: CollisionChecker, Q: np.ndarray) -> int | None:
    """Index of the first row of Q in contact by the pairwise narrow phase, or None."""
    for k, q in enumerate(Q):
        if checker.in_collision_pairwise(q):
            return k
    return None


def recheck_path(checker: CollisionChecker, path: Any, step: float = RECHECK_STEP) -> tuple[bool, int]:
    """Independent re-check of a planned polyline in C: each straight segment sampled so that no joint
    moves more than ``step`` rad, every sample tested with the pairwise narrow phase.
    Returns (collision-free, samples checked)."""
    as_positive(step, "step")
    P = np.asarray(path, dtype=float)
    pieces = [P[:1]]
    for a, b in zip(P[:-1], P[1:]):
        n = max(int(np.ceil(np.abs(b - a).max() / step)), 1)
        pieces.append(a + np.linspace(0.0, 1.0, n + 1)[1:, None] * (b - a))
    Q = np.vstack(pieces)
    return _first_contact(checker, Q) is None, len(Q)


@dataclass
class TimedMotion:
    """A planned, shortcut and timed motion and its independent re-check."""

    result: PlanResult
    path: np.ndarray                  # the shortcut waypoints
    motion: TimeOptimalPath           # certified (motion.certified) time-optimal motion along them
    free: bool                        # the independent re-check of the timed motion
    samples_checked: int
    distance_queries: int             # of the planner (its result's count)


def plan_and_time(scenario: Scenario, planner: str = "rrt_connect", seed: int = 1,
                  shortcut_attempts: int = 100) -> TimedMotion:
    """The documented call sequence: plan (certified edges), :func:`planners.sampling.shortcut` (certified),
    :func:`planners.time_optimal.time_optimal_path` with the space (certified blends), then the independent
    re-check (:func:`recheck`) of the timed motion. RuntimeError when the planner fails (its message)."""
    res = plan(scenario, planner, seed)
    if not res.success:
        raise RuntimeError(f"{planner} failed on {scenario.name!r}: {res.message}")
    path = shortcut(scenario.space, res.path, seed, shortcut_attempts)
    motion = time_optimal_path(scenario.robot, path, limits(scenario), space=scenario.space)
    free, n, _ = recheck(scenario.space.checker, motion)
    return TimedMotion(res, path, motion, free, n, res.distance_queries)


def planning_demo(scenario: Scenario, seed: int = 1) -> Solution:
    """RRT-Connect and PRM on ``scenario``: path lengths, distance queries, certified timed motion, its
    independent re-check; a figure of the joint trajectories of the RRT-Connect motion with the limits."""
    sol = Solution(id="", title=f"Planning among boxes — {scenario.name}", kind="programming")
    space = scenario.space
    sol.check("q_s and q_g are free (pairwise narrow phase)",
              not space.checker.in_collision_pairwise(scenario.q_start)
              and not space.checker.in_collision_pairwise(scenario.q_goal))
    motions = {}
    lim = limits(scenario)
    for planner in ("rrt_connect", "prm"):
        m = plan_and_time(scenario, planner, seed)
        motions[planner] = m
        sol.value(f"{planner}_raw_length", m.result.length)
        sol.value(f"{planner}_shortcut_length", path_length(space, m.path))
        sol.value(f"{planner}_distance_queries", m.distance_queries)
        sol.value(f"{planner}_duration", m.motion.t_f)
        sol.value(f"{planner}_min_clearance", m.motion.min_clearance)
        sol.check(f"{planner}: planned path and timed motion certified (clearance vs motion bound)",
                  m.result.certified and m.motion.certified, f"min clearance {m.motion.min_clearance:.4f} m")
        sol.check(f"{planner}: shortcut path no longer than the planned one",
                  path_length(space, m.path) <= m.result.length + 1e-12)
        sol.check(f"{planner}: timed motion collision-free on a {RECHECK_STEP} rad grid "
                  f"({m.samples_checked} samples, pairwise narrow phase on the meshes)", m.free)
        t = np.linspace(0.0, m.motion.t_f, 2001)
        q = np.reshape(m.motion(t)[0], (t.size, -1))
        h = t[1] - t[0]
        qd = np.diff(q, axis=0) / h                             # finite differences, not the motion's q̇
        qdd = np.diff(q, 2, axis=0) / h ** 2
        sol.check(f"{planner}: |q̇| ≤ q̇_max and |q̈| ≤ q̈_max (finite differences of the sampled motion)",
                  np.all(np.abs(qd) <= lim.qd_max * (1 + 1e-3))
                  and np.all(np.abs(qdd) <= lim.qdd_max * (1 + 0.05)),
                  f"max |q̇|/q̇_max {np.max(np.abs(qd) / lim.qd_max):.3f}, "
                  f"max |q̈|/q̈_max {np.max(np.abs(qdd) / lim.qdd_max):.3f}")
        sol.check(f"{planner}: starts at q_s and ends at q_g",
                  np.allclose(q[0], scenario.q_start) and np.allclose(q[-1], scenario.q_goal))
    m = motions["rrt_connect"]
    t = np.linspace(0.0, m.motion.t_f, 600)
    q, qd, _ = m.motion(t)
    fig, axes = subplots(2, 1, figsize=(7, 5.5), sharex=True)
    for j in range(q.shape[1]):
        axes[0].plot(t, q[:, j], label=f"q{j + 1}")
        axes[1].plot(t, qd[:, j] / scenario.qd_max[j], label=f"q̇{j + 1}/q̇max")
    label_axes(axes[0], None, "q [rad]", legend="upper right", ncol=2)
    label_axes(axes[1], "t [s]", "q̇ / q̇_max [–]", legend=False)
    sol.figure(fig, f"{scenario.name}: RRT-Connect + shortcut + certified time-optimal timing")
    t_anim = np.linspace(0.0, m.motion.t_f, int(30 * m.motion.t_f) + 2)
    q_anim = np.reshape(m.motion(t_anim)[0], (t_anim.size, -1))
    sol.animation(scenario.robot, (t_anim, q_anim), f"{scenario.name} (RRT-Connect, timed)",
                  overlays=box_overlays(scenario.boxes, (frame_path(scenario.robot, q_anim),)))
    return sol


if __name__ == "__main__":  # pragma: no cover
    for make in (anthropomorphic_pillar, panda_shelf):
        s = planning_demo(make())
        print(s.title)
        for c in s.checks:
            print(("  ok  " if c.passed else "  FAIL") + f" {c.name} {c.detail}")
        print("  ", {k: v for k, v in s.values.items()})
