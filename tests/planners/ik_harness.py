"""A seeded set of reachable IK targets that every IK solver runs, and an independent check of its answers.

A solver is any callable ``(robot, T_d, q0) -> IKResult``. The targets are the poses of random
configurations within the joint limits (so every one is reachable), each with a start drawn
independently within the limits. Every success a solver reports is verified here, independently of
the solver's own residual: Pinocchio's forward kinematics at the returned q must reach T_d within
``tol`` (position error [m] and rotation angle of R_e^T R_d [rad]) and q must be within the limits.
Used by ``tests/planners/test_ik_harness.py`` and ``benchmarks/bench_ik.py``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import pinocchio as pin

Solver = Callable[..., object]  # (robot, T_d (4, 4), q0 (nq,)) -> IKResult


@dataclass(frozen=True)
class Target:
    T_d: np.ndarray        # (4, 4) the pose to reach
    q0: np.ndarray         # (nq,) the start given to the solver
    q_source: np.ndarray   # (nq,) the configuration T_d was made from (one solution)


@dataclass
class HarnessResult:
    name: str
    solved: int = 0
    failed: int = 0
    false_successes: list[str] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def rate(self) -> float:
        return self.solved / max(1, self.solved + self.failed)

    def __str__(self) -> str:
        n = self.solved + self.failed
        return (f"{self.name}: {self.solved}/{n} solved ({100 * self.rate:.0f} %), "
                f"{len(self.false_successes)} false successes, {1e3 * self.seconds / max(1, n):.1f} ms per target")


def _pose(robot, q: np.ndarray) -> pin.SE3:
    pin.framesForwardKinematics(robot.model, robot.data, q)
    return robot.data.oMf[robot.ee_frame].copy()


def reachable_targets(robot, n: int, seed: int) -> list[Target]:
    """``n`` targets T_d = FK(q_source) with q_source and the start q0 drawn uniformly within the limits.

    Seeded: the same ``(robot, n, seed)`` always gives the same targets, so rates can be compared."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        q_source = robot.random_configuration(rng)   # uniform within the limits (clipped to ±π)
        q0 = robot.random_configuration(rng)
        out.append(Target(_pose(robot, q_source).homogeneous, q0, q_source))
    return out


def independent_residual(robot, q: np.ndarray, T_d: np.ndarray) -> float:
    """max(‖p_d − p_e‖, ‖log(R_eᵀ R_d)‖) from Pinocchio's forward kinematics at q."""
    T_e = _pose(robot, q)
    dp = np.linalg.norm(T_d[:3, 3] - T_e.translation)
    angle = np.linalg.norm(pin.log3(T_e.rotation.T @ T_d[:3, :3]))
    return float(max(dp, angle))


def run_solver(robot, solver: Solver, targets: list[Target], tol: float, name: str = "solver") -> HarnessResult:
    """Run ``solver`` on every target; count the successes it reports, and record every reported
    success that fails the independent check (FK residual <= tol and q within the limits)."""
    lo, hi = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    out = HarnessResult(name)
    start = time.perf_counter()
    for k, tg in enumerate(targets):
        res = solver(robot, tg.T_d, tg.q0.copy())
        if not res.success:
            out.failed += 1
            continue
        out.solved += 1
        q = np.asarray(res.q, dtype=float)
        r = independent_residual(robot, q, tg.T_d)
        inside = bool(np.all(q >= lo - 1e-9) and np.all(q <= hi + 1e-9))
        if not (r <= tol * (1 + 1e-6) and inside and res.iterations >= 0):
            out.false_successes.append(f"target {k}: residual {r:.3g} (tol {tol:g}), within limits {inside}, "
                                       f"iterations {res.iterations}")
    out.seconds = time.perf_counter() - start
    return out
