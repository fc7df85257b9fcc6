"""Chapter 6, task and action levels: a task decomposed into actions, and the path of each action.

The task level splits a job into actions (Sect. 6.1); the action level chooses the frames, the
path/via points and the timing laws of each motion (Sect. 6.2). Here: the pick-and-place of
Problems 6.1–6.2 around a box obstacle — :func:`decompose_pick_and_place` gives the action
sequence and the intermediate points C, D, E, F of Fig. S6.1, :func:`pick_and_place_path` their
operational-space motion, stopping at the path points or rounding them as via points (Sect. 4.4),
timed by the laws of :mod:`planners.timing` on a :class:`planners.paths.SegmentSequence`.
Executing actions on an arm is the controllers' job (:mod:`controllers.tasks`).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 6.1–6.2, Sect. 4.4 (via points); solution manual, Problems 6.1–6.2 (Fig. S6.1).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from planners.paths import SegmentSequence
from planners.timing import cubic_law, quintic_law, trapezoidal_law
from rigid_body.validation import as_positive, as_vector

__all__ = ["Action", "PickAndPlacePlan", "decompose_pick_and_place", "pick_and_place_path"]


@dataclass(frozen=True)
class Action:
    """One action of the task level: its name, the points it uses and how it moves."""

    name: str
    points: tuple[str, ...]
    motion: str


@dataclass(frozen=True)
class PickAndPlacePlan:
    """Intermediate points of Fig. S6.1 and the actions that use them.

    C = grasp location (A), D = above A at a safe height, E = above B at the same height,
    F = release location (B); ``actions`` is the task-level sequence of 6.1.
    """

    points: dict[str, np.ndarray]
    actions: tuple[Action, ...]
    safe_height: float


def decompose_pick_and_place(A: Any, B: Any, obstacle: Any, clearance: float) -> PickAndPlacePlan:
    """Task decomposition of 6.1 for a planar pick-and-place from A to B over a box obstacle.

    ``A``, ``B`` are (x, y) on the work surface (y vertical up); ``obstacle`` = (x_min, x_max, top)
    of a box standing on the surface between them (``top`` its upper face); ``clearance`` is the
    safety distance. The safe height of D and E is top + clearance.
    """
    A, B = as_vector(A, 2, "A"), as_vector(B, 2, "B")
    x_min, x_max, top = as_vector(obstacle, 3, "obstacle")
    clearance = as_positive(clearance, "clearance")
    if not x_min < x_max:
        raise ValueError(f"`obstacle` must be (x_min < x_max, top), got {obstacle}")
    if not (A[0] < x_min and B[0] > x_max or B[0] < x_min and A[0] > x_max):
        raise ValueError("the obstacle must stand between A and B along x (else no avoidance is needed)")
    y_safe = top + clearance
    if min(A[1], B[1]) >= y_safe:
        raise ValueError("A and B are already above the obstacle")
    points = {"C": A, "D": np.array([A[0], y_safe]), "E": np.array([B[0], y_safe]), "F": B}
    actions = (
        Action("approach A", ("C",), "slow, vertical end-effector orientation"),
        Action("pick object", ("C",), "grasp at rest (null velocity and acceleration)"),
        Action("move object avoiding obstacle", ("C", "D", "E"), "lift to D, transfer to E above the obstacle"),
        Action("approach B", ("E", "F"), "slow descent, vertical orientation"),
        Action("place object", ("F",), "release at rest (null velocity and acceleration)"),
    )
    return PickAndPlacePlan(points, actions, y_safe)


def pick_and_place_path(plan: PickAndPlacePlan, durations: Sequence[float], via_points: bool = False,
                        overlap: float = 0.0, middle: str = "cubic", t_i: float = 0.0) -> SegmentSequence:
    """The operational-space motion C → D → E → F of 6.2 as a :class:`SegmentSequence` (z = 0).

    Path points: segments CD and EF are timed by quintics (null velocity *and* acceleration at C and
    F: "at least fourth order"), DE by a cubic (``middle="cubic"``) or a trapezoidal velocity profile
    (``"trapezoidal"``), back to back, so the arm stops at D and E. Via points: the same laws, but DE
    and EF start ``overlap`` seconds before the previous segment ends, so the path rounds D and E.
    """
    T1, T2, T3 = (float(v) for v in as_vector(durations, 3, "durations"))
    if min(T1, T2, T3) <= 0:
        raise ValueError(f"`durations` must be positive, got {durations}")
    if via_points and not 0 < overlap < min(T1, T2, T3):
        raise ValueError(f"`overlap` must be in (0, {min(T1, T2, T3)}) for via points, got {overlap}")
    shift = overlap if via_points else 0.0
    pts = np.array([np.append(plan.points[k], 0.0) for k in "CDEF"])
    L = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    t1 = t_i + T1
    t2 = t1 - shift + T2
    laws = [quintic_law(0.0, L[0], t1, t_i=t_i)]
    if middle == "cubic":
        laws.append(cubic_law(0.0, L[1], t2, t_i=t1 - shift))
    elif middle == "trapezoidal":
        laws.append(trapezoidal_law(0.0, L[1], t2, 1.5 * L[1] / T2, t_i=t1 - shift))
    else:
        raise ValueError(f"`middle` must be 'cubic' or 'trapezoidal', got {middle!r}")
    laws.append(quintic_law(0.0, L[2], t2 - shift + T3, t_i=t2 - shift))
    return SegmentSequence(pts, laws)
