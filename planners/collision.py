"""Robots loaded from URDF among box obstacles: collision checking and their configuration space.

Beyond the book's planar scenes (:mod:`planners.configuration_space`), the same sampling planners
(:mod:`planners.sampling`) run on a real arm: the robot's ``<collision>`` shapes (``Robot.collision_model``,
a Pinocchio ``GeometryModel``) and boxes added as ``coal.Box`` geometry objects fixed to the world.

* :class:`Box` — an axis-aligned box obstacle (a table top, a shelf board).
* :class:`CollisionChecker` — the collision pairs (robot–box, and self-collision pairs filtered by the
  robot's SRDF ``<disable_collisions>`` and by adjacency: shapes on the same or on consecutive bodies
  never count), a broad phase (a coal dynamic AABB tree through Pinocchio's ``BroadPhaseManager``)
  in front of the exact narrow phase, and the pairwise check (every active pair) kept as the reference.
* :class:`UrdfCSpace` — the planners' space protocol (:class:`planners.sampling.PlanningSpace`) on the
  joint box [q_min, q_max]: a uniform sampler, the Euclidean distance, straight interpolation and
  validity; local paths are checked every ``resolution`` rad, in bisection order, stopping at the
  first collision.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 12.2
(C-obstacles of an articulated robot), Sect. 12.5 (sampling-based planning and its collision checker).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import coal
import numpy as np
import pinocchio as pin

from rigid_body.robots import example_robot_data_dir
from rigid_body.validation import as_positive, as_vector

__all__ = ["Box", "CollisionChecker", "UrdfCSpace", "example_robot_srdf", "bisection_order"]


@dataclass(frozen=True)
class Box:
    """An axis-aligned box obstacle: centre ``center`` (3,) [m] and full side lengths ``size`` (3,) [m]."""

    center: Any
    size: Any
    name: str = "box"

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", as_vector(self.center, 3, "center"))
        size = as_vector(self.size, 3, "size")
        if np.any(size <= 0):
            raise ValueError(f"`size` must be positive, got {size}")
        object.__setattr__(self, "size", size)

    @property
    def corners(self) -> tuple[np.ndarray, np.ndarray]:
        """(lower, upper) corners (3,)."""
        return self.center - self.size / 2, self.center + self.size / 2


def example_robot_srdf(robot_name: str) -> Path | None:
    """The SRDF example-robot-data ships for ``robot_name`` (e.g. ``panda``), or None."""
    path = example_robot_data_dir() / f"{robot_name}_description" / "srdf" / f"{robot_name}.srdf"
    return path if path.is_file() else None


def bisection_order(n: int) -> np.ndarray:
    """Indices 0 … n−1 in the order a segment is best checked: both ends, then mid-points of ever finer
    halvings (a collision somewhere inside is met after few checks on average).

    >>> bisection_order(5).tolist()
    [0, 4, 2, 1, 3]
    """
    if n <= 2:
        return np.arange(n)
    order, seen, queue = [0, n - 1], {0, n - 1}, [(0, n - 1)]
    while queue:
        nxt = []
        for a, b in queue:
            m = (a + b) // 2
            if m not in seen:
                seen.add(m)
                order.append(m)
            if m - a > 1:
                nxt.append((a, m))
            if b - m > 1:
                nxt.append((m, b))
        queue = nxt
    return np.array(order)


class CollisionChecker:
    """Is the robot at q in collision with the boxes or with itself?

    Parameters
    ----------
    robot : a :class:`rigid_body.robots.Robot` with ``<collision>`` shapes.
    boxes : the obstacles, fixed to the world.
    srdf : an SRDF whose ``<disable_collisions>`` pairs are removed (``pin.removeCollisionPairs``);
        None keeps every non-adjacent self-collision pair.
    self_collision : include the robot's self-collision pairs.

    Shapes attached to the world (the robot's base) are never paired with a box: they do not move, so
    such a contact would be a property of the scene; the constructor refuses it (ValueError).
    ``calls`` counts the configurations checked.
    """

    def __init__(self, robot: Any, boxes: Sequence[Box], srdf: str | Path | None = None,
                 self_collision: bool = True) -> None:
        self.robot = robot
        self.model = robot.model
        self.data = robot.model.createData()
        geom = robot.collision_model.clone()
        n_robot = geom.ngeoms
        if n_robot == 0:
            raise ValueError(f"robot {robot.name!r} has no collision shapes")
        self.boxes = tuple(boxes)
        box_ids = []
        for k, b in enumerate(self.boxes):
            if not isinstance(b, Box):
                raise ValueError(f"`boxes[{k}]` must be a Box, got {type(b).__name__}")
            obj = pin.GeometryObject(f"{b.name}_{k}", 0, 0, pin.SE3(np.eye(3), b.center), coal.Box(*b.size))
            box_ids.append(geom.addGeometryObject(obj))
        parents = [geom.geometryObjects[i].parentJoint for i in range(n_robot)]
        if self_collision:
            geom.addAllCollisionPairs()
            if srdf is not None:
                pin.removeCollisionPairs(self.model, geom, str(srdf))
            pairs = [(p.first, p.second) for p in geom.collisionPairs]   # copies: removal shifts the vector
            for i, j in pairs:
                if i >= n_robot or j >= n_robot or self._adjacent(parents[i], parents[j]):
                    geom.removeCollisionPair(pin.CollisionPair(i, j))
        else:
            geom.removeAllCollisionPairs()
        self.n_self_pairs = len(geom.collisionPairs)
        moving = [i for i in range(n_robot) if parents[i] != 0]
        for i in moving:
            for b in box_ids:
                geom.addCollisionPair(pin.CollisionPair(i, b))
        self.geom = geom
        self.gdata = geom.createData()
        self.manager = pin.BroadPhaseManager_DynamicAABBTreeCollisionManager(self.model, geom, self.gdata)
        self._static_contact_check([i for i in range(n_robot) if parents[i] == 0], box_ids)
        self.calls = 0

    def _adjacent(self, ji: int, jj: int) -> bool:
        """Same body, or bodies joined by one joint (their shapes touch at the joint by construction)."""
        return ji == jj or self.model.parents[ji] == jj or self.model.parents[jj] == ji

    def _static_contact_check(self, static: list[int], box_ids: list[int]) -> None:
        pin.updateGeometryPlacements(self.model, self.data, self.geom, self.gdata, pin.neutral(self.model))
        req, res = coal.CollisionRequest(), coal.CollisionResult()
        for i in static:
            for b in box_ids:
                res.clear()
                if coal.collide(self.geom.geometryObjects[i].geometry, self.gdata.oMg[i],
                                self.geom.geometryObjects[b].geometry, self.gdata.oMg[b], req, res):
                    raise ValueError(f"the robot's fixed shape {self.geom.geometryObjects[i].name!r} "
                                     f"touches {self.geom.geometryObjects[b].name!r}: move the obstacle")

    @property
    def n_pairs(self) -> int:
        """Number of active collision pairs (self + robot–box)."""
        return len(self.geom.collisionPairs)

    def in_collision(self, q: np.ndarray) -> bool:
        """Broad phase (dynamic AABB tree) then the narrow phase on the active pairs; stops at the first contact."""
        self.calls += 1
        return bool(pin.computeCollisions(self.model, self.data, self.manager, q, True))

    def in_collision_pairwise(self, q: np.ndarray) -> bool:
        """Reference: every active pair through the narrow phase (``pin.computeCollisions`` on the pair list)."""
        return bool(pin.computeCollisions(self.model, self.data, self.geom, self.gdata, q, True))

    def colliding_pairs(self, q: np.ndarray) -> list[tuple[str, str]]:
        """Names of the geometry pairs in contact at q (all pairs evaluated)."""
        pin.computeCollisions(self.model, self.data, self.geom, self.gdata, q, False)
        names = [g.name for g in self.geom.geometryObjects]
        return [(names[p.first], names[p.second]) for p, r in zip(self.geom.collisionPairs, self.gdata.collisionResults)
                if r.isCollision()]

    def box_clearance(self, q: np.ndarray) -> float:
        """Smallest distance between the robot and the boxes at q [m] (coal's narrow phase; ≤ 0 in
        contact; ∞ without boxes)."""
        pin.computeDistances(self.model, self.data, self.geom, self.gdata, as_vector(q, self.model.nq, "q"))
        n = self.n_self_pairs
        return float(min((r.min_distance for r in list(self.gdata.distanceResults)[n:]), default=np.inf))


@dataclass
class UrdfCSpace:
    """The configuration space of a URDF robot among boxes, as the sampling planners see it.

    ``lower``/``upper`` default to the robot's joint limits; ``resolution`` [rad] is the largest
    (Euclidean) step between two checked configurations of a straight local path. Implements
    :class:`planners.sampling.PlanningSpace` and its optional ``all_valid`` (stops at the first
    collision, in :func:`bisection_order`).
    """

    checker: CollisionChecker
    resolution: float = 0.05
    lower: Any = None
    upper: Any = None

    def __post_init__(self) -> None:
        model = self.checker.model
        lo = np.array(model.lowerPositionLimit) if self.lower is None else as_vector(self.lower, model.nq, "lower")
        hi = np.array(model.upperPositionLimit) if self.upper is None else as_vector(self.upper, model.nq, "upper")
        if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(hi > lo)):
            raise ValueError(f"`lower` and `upper` must be finite with upper > lower, got {lo}, {hi}")
        self.lower, self.upper = lo, hi
        as_positive(self.resolution, "resolution")

    @property
    def dim(self) -> int:
        return self.checker.model.nq

    def sample(self, rng: np.random.Generator) -> np.ndarray:
        """A configuration drawn uniformly in [lower, upper]."""
        return rng.uniform(self.lower, self.upper)

    def distance(self, a: Any, b: Any) -> np.ndarray:
        """‖b − a‖ (Euclidean in joint space); broadcasts over leading axes."""
        return np.linalg.norm(np.asarray(b, dtype=float) - np.asarray(a, dtype=float), axis=-1)

    def interpolate(self, a: Any, b: Any, s: Any) -> np.ndarray:
        """a + s (b − a); ``s`` scalar → (dim,), ``s`` (k,) → (k, dim)."""
        a = np.asarray(a, dtype=float)
        return a + np.asarray(s, dtype=float)[..., None] * (np.asarray(b, dtype=float) - a)

    def in_bounds(self, q: np.ndarray) -> bool:
        return bool(np.all(q >= self.lower) and np.all(q <= self.upper))

    def is_valid(self, q: Any) -> bool:
        """Within the joint limits and collision-free."""
        q = np.asarray(q, dtype=float)
        if q.shape != self.lower.shape:
            raise ValueError(f"`q` must have shape {self.lower.shape}, got {q.shape}")
        return self.in_bounds(q) and not self.checker.in_collision(q)

    def valid_many(self, Q: Any) -> np.ndarray:
        """:meth:`is_valid` for each row of Q (N, dim)."""
        return np.array([self.is_valid(q) for q in np.atleast_2d(np.asarray(Q, dtype=float))])

    def all_valid(self, Q: Any) -> bool:
        """True when every row of Q is valid; rows checked in :func:`bisection_order`, stopping at the first failure."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        return all(self.is_valid(Q[k]) for k in bisection_order(len(Q)))

    def local_path(self, a: Any, b: Any, resolution: float | None = None) -> np.ndarray:
        """Configurations of the segment a → b, end points included: ⌈‖b − a‖ / resolution⌉ equal steps
        (as OMPL's discrete motion validator does with the same resolution)."""
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        h = self.resolution if resolution is None else as_positive(resolution, "resolution")
        n = max(int(np.ceil(float(self.distance(a, b)) / h)), 1)
        return self.interpolate(a, b, np.linspace(0.0, 1.0, n + 1))

    def segment_is_free(self, a: Any, b: Any) -> bool:
        """The segment checker: every configuration of :meth:`local_path` valid."""
        return self.all_valid(self.local_path(a, b))
