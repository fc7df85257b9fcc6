"""Robots loaded from URDF among box obstacles: collision checking and their configuration space.

Beyond the book's planar scenes (:mod:`planners.configuration_space`), the same sampling planners
(:mod:`planners.sampling`) run on a real arm: the robot's ``<collision>`` shapes (``Robot.collision_model``,
a Pinocchio ``GeometryModel``) and boxes added as ``coal.Box`` geometry objects fixed to the world.

* :class:`Box` — an axis-aligned box obstacle (a table top, a shelf board).
* :class:`CollisionChecker` — the collision pairs (robot–box, and self-collision pairs filtered by the
  robot's SRDF ``<disable_collisions>`` and by adjacency: shapes on the same or on consecutive bodies
  never count), a broad phase (a coal dynamic AABB tree through Pinocchio's ``BroadPhaseManager``)
  in front of the exact narrow phase, and the pairwise check (every active pair) kept as the reference.
* The edge certificate (:meth:`CollisionChecker.clearances`, :meth:`UrdfCSpace.certify_edge`): the
  distance of every active pair (coal's GJK through ``pin.computeDistances``, on one convex hull per link
  of its collision shapes — a hull contains its shapes, so its distance is a lower bound) against a bound on how
  far the pair's two members can move relative to each other along a straight joint-space edge,
  Σ_k r_k |Δq_k| over the joints that move one relative to the other (r_k: the farthest point of the
  shapes beyond joint k from its axis, from the joint placements and the shapes' bounding spheres;
  1 for a prismatic joint); adaptive bisection where it does not suffice.
* :class:`UrdfCSpace` — the planners' space protocol (:class:`planners.sampling.PlanningSpace`) on the
  joint box [q_min, q_max]: a uniform sampler, the Euclidean distance, straight interpolation,
  validity and the certificate; in the explicit sampled mode local paths are checked every
  ``resolution`` rad, in bisection order, stopping at the first collision.

Pinocchio's work data (``Data``, ``GeometryData``, the broad phase) is kept per thread: two threads may
check or plan on one checker at once.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 12.2
(C-obstacles of an articulated robot), Sect. 12.5 (sampling-based planning and its collision checker);
Schwarzer, Saha, Latombe, "Exact collision checking of robot paths" (2004) for the certificate.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace
from typing import Any, Sequence

import coal
import numpy as np
import pinocchio as pin

from planners.configuration_space import EDGE_QUERY_BUDGET, EdgeCertificate, certify_by_bisection
from rigid_body.robots import example_robot_data_dir
from rigid_body.validation import as_generator, as_positive, as_vector

__all__ = ["Box", "CollisionChecker", "UrdfCSpace", "example_robot_srdf", "bisection_order", "DISTANCE_MARGIN"]


@dataclass(frozen=True)
class Box:
    """An axis-aligned box obstacle: centre ``center`` (3,) [m] and full side lengths ``size`` (3,) [m]."""

    center: Any
    size: Any
    name: str = "box"

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "center", as_vector(self.center, 3, "center"))
            size = as_vector(self.size, 3, "size")
        except ValueError as err:
            raise ValueError(f"Box {self.name!r}: {err}") from None
        if np.any(size <= 0):
            raise ValueError(f"Box {self.name!r}: `size` must be positive, got {size}")
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
        self.distance_geom = _convex_hulls(geom, set(box_ids))
        self._local = threading.local()
        self._static_contact_check([i for i in range(n_robot) if parents[i] == 0], box_ids)
        self.pair_rates = self.motion_rates(self.model.lowerPositionLimit, self.model.upperPositionLimit)
        self.calls = 0

    def _work(self) -> SimpleNamespace:
        """This thread's Pinocchio work data: ``data``, ``gdata`` and the broad phase ``manager`` for the
        collision checks, ``ddata`` for the certificate's distances (created on a thread's first call)."""
        w = getattr(self._local, "work", None)
        if w is None:
            gdata = self.geom.createData()
            w = SimpleNamespace(data=self.model.createData(), gdata=gdata, ddata=self.distance_geom.createData(),
                                manager=pin.BroadPhaseManager_DynamicAABBTreeCollisionManager(self.model, self.geom,
                                                                                             gdata))
            self._local.work = w
        return w

    @property
    def data(self) -> Any:
        """This thread's ``pin.Data``."""
        return self._work().data

    @property
    def gdata(self) -> Any:
        """This thread's ``pin.GeometryData`` of the collision model."""
        return self._work().gdata

    @property
    def manager(self) -> Any:
        """This thread's broad phase."""
        return self._work().manager

    def _q(self, q: Any) -> np.ndarray:
        """q as a float vector of size nq (the fast path costs a type and a shape test); ValueError naming ``q``."""
        if type(q) is np.ndarray and q.dtype == np.float64 and q.shape == (self.model.nq,):
            return q
        return as_vector(q, self.model.nq, "q")

    def _adjacent(self, ji: int, jj: int) -> bool:
        """Same body, or bodies joined by one joint (their shapes touch at the joint by construction)."""
        return ji == jj or self.model.parents[ji] == jj or self.model.parents[jj] == ji

    def _static_contact_check(self, static: list[int], box_ids: list[int]) -> None:
        w = self._work()
        pin.updateGeometryPlacements(self.model, w.data, self.geom, w.gdata, pin.neutral(self.model))
        req, res = coal.CollisionRequest(), coal.CollisionResult()
        for i in static:
            for b in box_ids:
                res.clear()
                if coal.collide(self.geom.geometryObjects[i].geometry, w.gdata.oMg[i],
                                self.geom.geometryObjects[b].geometry, w.gdata.oMg[b], req, res):
                    raise ValueError(f"the robot's fixed shape {self.geom.geometryObjects[i].name!r} "
                                     f"touches {self.geom.geometryObjects[b].name!r}: move the obstacle")

    @property
    def n_pairs(self) -> int:
        """Number of active collision pairs (self + robot–box)."""
        return len(self.geom.collisionPairs)

    def in_collision(self, q: np.ndarray) -> bool:
        """Broad phase (dynamic AABB tree) then the narrow phase on the active pairs; stops at the first contact."""
        q = self._q(q)
        self.calls += 1
        w = self._work()
        return bool(pin.computeCollisions(self.model, w.data, w.manager, q, True))

    def in_collision_pairwise(self, q: np.ndarray) -> bool:
        """Reference: every active pair through the narrow phase (``pin.computeCollisions`` on the pair list)."""
        w = self._work()
        return bool(pin.computeCollisions(self.model, w.data, self.geom, w.gdata, self._q(q), True))

    def colliding_pairs(self, q: np.ndarray) -> list[tuple[str, str]]:
        """Names of the geometry pairs in contact at q (all pairs evaluated)."""
        w = self._work()
        pin.computeCollisions(self.model, w.data, self.geom, w.gdata, self._q(q), False)
        names = [g.name for g in self.geom.geometryObjects]
        return [(names[p.first], names[p.second]) for p, r in zip(self.geom.collisionPairs, w.gdata.collisionResults)
                if r.isCollision()]

    def box_clearance(self, q: np.ndarray) -> float:
        """Smallest distance between the robot and the boxes at q [m] (coal's narrow phase on the collision
        meshes; ≤ 0 in contact; ∞ without boxes)."""
        w = self._work()
        pin.computeDistances(self.model, w.data, self.geom, w.gdata, self._q(q))
        n = self.n_self_pairs
        return float(min((r.min_distance for r in list(w.gdata.distanceResults)[n:]), default=np.inf))

    # -- the certificate ---------------------------------------------------------------------------

    def clearances(self, q: Any, pairs: Sequence[int] | None = None) -> np.ndarray:
        """Distances (P,) of every active pair at q [m] (or of the ``pairs`` listed, in that order), on the
        convex hulls of the shapes (lower bounds of the meshes' distances), less ``DISTANCE_MARGIN`` (GJK's
        tolerance); ≤ 0 in contact. All pairs go through ``pin.computeDistances``; a few through
        ``pin.computeDistance`` after one placement update."""
        q = self._q(q)
        w = self._work()
        if pairs is None:
            pin.computeDistances(self.model, w.data, self.distance_geom, w.ddata, q)
            d = np.fromiter((r.min_distance for r in w.ddata.distanceResults), float, len(self.pair_rates))
        else:
            pin.updateGeometryPlacements(self.model, w.data, self.distance_geom, w.ddata, q)
            d = np.fromiter((pin.computeDistance(self.distance_geom, w.ddata, int(k)).min_distance for k in pairs),
                            float, len(pairs))
        return d - DISTANCE_MARGIN

    def motion_rates(self, lower: Any, upper: Any) -> np.ndarray:
        """W (P, nq): the relative motion of pair p's two shapes along a straight step Δq between two
        configurations of the joint box [lower, upper] is at most Σ_k W[p, k] |Δq_k| (module docstring):
        r_k for a revolute joint k between the two shapes (a bound on the distance of the moving shape's
        points from k's axis, over every configuration of the box: a prismatic joint beyond k adds its
        largest |q| in the box), 1 for a prismatic one; ∞ in a pair's row when a joint between its shapes
        is neither (continuous, planar, mimic ...: no certificate for them). :attr:`pair_rates` is W on
        the model's joint limits; :class:`UrdfCSpace` uses its own box."""
        model, geom = self.model, self.distance_geom
        lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
        if lower.shape != (model.nq,) or upper.shape != (model.nq,) or np.isnan(lower).any() or np.isnan(upper).any():
            raise ValueError(f"`lower` and `upper` must be ({model.nq},) joint bounds, got {lower} and {upper}")
        chains = {}
        for j in range(model.njoints):
            chain, k = [], j
            while k > 0:
                chain.append(k)
                k = model.parents[k]
            chains[j] = chain[::-1]

        def points(g: int) -> np.ndarray:
            """Points whose convex hull holds shape g, in its parent joint's frame: the hull's vertices, a box's
            corners, else the corners of its local AABB."""
            obj = geom.geometryObjects[g]
            shape = obj.geometry
            if callable(getattr(shape, "points", None)):
                V = np.asarray(shape.points(), dtype=float)
            else:
                shape.computeLocalAABB()
                lo, hi = np.asarray(shape.aabb_local.min_), np.asarray(shape.aabb_local.max_)
                V = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
            return V @ obj.placement.rotation.T + obj.placement.translation

        def prismatic_range(m: int) -> float:
            if _joint_kind(model, m) != "prismatic":
                return 0.0
            i = model.idx_qs[m]
            return float(max(abs(lower[i]), abs(upper[i])))        # ∞ when the box is unbounded

        def reach(g: int, k: int) -> float:
            """A bound on the distance of any point of shape g from revolute joint k's axis (k on g's chain).

            A point p beyond k: p − o_k = t_{k+1} + (p − o_{k+1}); joint k turns t_{k+1} about its axis, so its
            distance from the axis is the constant |t_{k+1} × a_k|; the rest is bounded along the chain by
            the joint offsets (and prismatic ranges) and the shape's farthest point from its own joint."""
            V = points(g)
            j = geom.geometryObjects[g].parentJoint
            axis = _axis(model, k)
            if j == k:
                return float(np.max(np.linalg.norm(np.cross(V, axis) if axis is not None else V, axis=1)))
            chain = chains[j]
            after = chain[chain.index(k) + 1:]
            t = np.asarray(model.jointPlacements[after[0]].translation, dtype=float)
            r = float(np.linalg.norm(np.cross(t, axis) if axis is not None else t)) + prismatic_range(after[0])
            for m in after[1:]:
                r += float(np.linalg.norm(model.jointPlacements[m].translation)) + prismatic_range(m)
            return r + float(np.max(np.linalg.norm(V, axis=1)))

        W = np.zeros((len(geom.collisionPairs), model.nq))
        for p, pair in enumerate(geom.collisionPairs):
            a, b = pair.first, pair.second
            ca, cb = chains[geom.geometryObjects[a].parentJoint], chains[geom.geometryObjects[b].parentJoint]
            for g, own, other in ((a, ca, cb), (b, cb, ca)):
                for k in own:
                    if k in other:
                        continue          # moves both shapes rigidly: no relative motion
                    kind = _joint_kind(model, k)
                    if kind is None:
                        W[p, :] = np.inf  # a mimic joint has no column of its own: the whole row is unbounded
                        continue
                    W[p, model.idx_qs[k]] += 1.0 if kind == "prismatic" else reach(g, k)
        return W


DISTANCE_MARGIN = 1e-5   # [m] subtracted from coal's GJK distances (its tolerance is 1e-6)


def _joint_kind(model: Any, j: int) -> str | None:
    """"revolute", "prismatic", or None for joints the certificate does not bound (spherical, free, planar,
    continuous (cos, sin) ...)."""
    name = model.joints[j].shortname()
    if model.nqs[j] != 1:
        return None
    if name.startswith("JointModelR") and not name.startswith("JointModelRUB"):
        return "revolute"
    if name.startswith("JointModelP") and not name.startswith("JointModelPlanar"):
        return "prismatic"
    return None


def _axis(model: Any, j: int) -> np.ndarray | None:
    """The unit axis of revolute joint j in its own frame (None when unknown: the bounds then use the distance
    from the joint's origin)."""
    name = model.joints[j].shortname()
    for suffix, a in (("RX", (1.0, 0.0, 0.0)), ("RY", (0.0, 1.0, 0.0)), ("RZ", (0.0, 0.0, 1.0))):
        if name.endswith(suffix):
            return np.array(a)
    try:
        a = np.asarray(model.joints[j].extract().axis, dtype=float)
        return a / np.linalg.norm(a)
    except (AttributeError, TypeError, ValueError):
        return None


def _hull_points(obj: Any) -> np.ndarray | None:
    """Points whose convex hull is the shape (a mesh's or convex's vertices, a box's corners), in the parent
    joint's frame; None for other shapes (spheres, cylinders, ...)."""
    g = obj.geometry
    if isinstance(g, coal.BVHModelBase):
        V = np.asarray(g.vertices(), dtype=float)
    elif callable(getattr(g, "points", None)):
        V = np.asarray(g.points(), dtype=float)
    elif isinstance(g, coal.Box):
        V = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * np.asarray(g.halfSide)
    else:
        return None
    return V @ obj.placement.rotation.T + obj.placement.translation


def _convex_hulls(geom: Any, obstacles: set) -> Any:
    """The certificate's geometry: one convex hull (coal ``Convex``) per robot link of all that link's shapes
    (a Panda finger's four boxes become one), meshes replaced by their hulls; obstacles and shapes without a
    vertex description kept as they are. A hull contains its shapes, so its distances never exceed theirs;
    fewer shapes make fewer pairs (the Panda's 92 become 50). The pairs are the collision model's, mapped to
    the hulls."""
    groups: dict = {}
    for i, obj in enumerate(geom.geometryObjects):
        pts = None if i in obstacles else _hull_points(obj)
        key = ("link", obj.parentFrame) if pts is not None else ("single", i)
        groups.setdefault(key, []).append((i, pts))
    out = pin.GeometryModel()
    index = {}
    for key, members in groups.items():
        first = geom.geometryObjects[members[0][0]]
        if key[0] == "single":
            shape, placement = first.geometry, first.placement
            name = first.name
        else:
            points = coal.StdVec_Vec3s()
            for p in np.vstack([pts for _, pts in members]):
                points.append(p)
            shape, placement = coal.Convex.convexHull(points, True, "Qt"), pin.SE3.Identity()
            name = first.name if len(members) == 1 else f"{first.name}+{len(members) - 1}"
        k = out.addGeometryObject(pin.GeometryObject(name, first.parentJoint, first.parentFrame, placement, shape))
        for i, _ in members:
            index[i] = k
    done = set()
    for pair in geom.collisionPairs:
        a, b = sorted((index[pair.first], index[pair.second]))
        if a != b and (a, b) not in done:
            done.add((a, b))
            out.addCollisionPair(pin.CollisionPair(a, b))
    return out


@dataclass
class UrdfCSpace:
    """The configuration space of a URDF robot among boxes, as the sampling planners see it.

    ``lower``/``upper`` default to the robot's joint limits and must lie within them (ValueError naming
    the bound otherwise); the certificate's motion bounds (``pair_rates``,
    :meth:`CollisionChecker.motion_rates`) hold over this box. ``resolution`` [rad] is the largest
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
        for name, box, beyond in (("lower", lo, lo < model.lowerPositionLimit),
                                  ("upper", hi, hi > model.upperPositionLimit)):
            if beyond.any():
                i = int(np.flatnonzero(beyond)[0])
                limit = (model.lowerPositionLimit if name == "lower" else model.upperPositionLimit)[i]
                raise ValueError(f"`{name}`[{i}] = {box[i]:g} lies beyond the robot's joint limit {limit:g} "
                                 f"(joint {self._joint_name(i)!r}): the space must stay within the joint limits")
        self.lower, self.upper = lo, hi
        as_positive(self.resolution, "resolution")
        # the motion bounds must hold over every configuration this space can produce: its own box
        self.pair_rates = self.checker.motion_rates(lo, hi)

    def _joint_name(self, i: int) -> str:
        """Name of the joint owning configuration coordinate i."""
        model = self.checker.model
        return next((model.names[j] for j in range(1, model.njoints)
                     if model.idx_qs[j] <= i < model.idx_qs[j] + model.nqs[j]), "?")

    @property
    def dim(self) -> int:
        return self.checker.model.nq

    def sample(self, rng: Any) -> np.ndarray:
        """A configuration drawn uniformly in [lower, upper]."""
        return as_generator(rng).uniform(self.lower, self.upper)

    def distance(self, a: Any, b: Any) -> np.ndarray:
        """‖b − a‖ (Euclidean in joint space); broadcasts over leading axes."""
        return np.linalg.norm(np.asarray(b, dtype=float) - np.asarray(a, dtype=float), axis=-1)

    def interpolate(self, a: Any, b: Any, s: Any) -> np.ndarray:
        """a + s (b − a); ``s`` scalar → (dim,), ``s`` (k,) → (k, dim)."""
        a = np.asarray(a, dtype=float)
        return a + np.asarray(s, dtype=float)[..., None] * (np.asarray(b, dtype=float) - a)

    def in_bounds(self, q: np.ndarray) -> bool:
        return bool((q >= self.lower).all() and (q <= self.upper).all())

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
        """The sampled segment checker: every configuration of :meth:`local_path` valid (not a certificate)."""
        return self.all_valid(self.local_path(a, b))

    # -- the edge certificate -------------------------------------------------------------------

    def clearances(self, q: Any, pairs: Sequence[int] | None = None) -> np.ndarray:
        """The certificate's clearances at q: :meth:`CollisionChecker.clearances`; −∞ for every pair when q
        is outside the joint box."""
        q = self.checker._q(q)
        c = self.checker.clearances(q, pairs)
        return c if self.in_bounds(q) else np.full(c.shape, -np.inf)

    def edge_rates(self, a: Any, b: Any) -> np.ndarray:
        """Bounds (P,) on the relative motion of each pair's shapes along the straight edge a → b."""
        with np.errstate(invalid="ignore"):           # an unbounded row (∞ · 0) gives NaN: refused by the caller
            return self.pair_rates @ np.abs(np.asarray(b, dtype=float) - np.asarray(a, dtype=float))

    def certify_edge(self, a: Any, b: Any, ca: np.ndarray | None = None, cb: np.ndarray | None = None,
                     max_queries: int = EDGE_QUERY_BUDGET) -> EdgeCertificate:
        """Certificate that the straight edge a → b is collision-free: adaptive bisection
        (:func:`planners.configuration_space.certify_by_bisection`) with the pairs' clearances and motion
        bounds; ``ca``, ``cb`` the clearances at the ends when known. The joint box is convex, so ends inside
        it keep the whole edge inside."""
        a, b = self.checker._q(a), self.checker._q(b)
        rates = self.edge_rates(a, b)
        if not np.all(np.isfinite(rates)):
            bad = [self.checker.model.names[j] for j in range(1, self.checker.model.njoints)
                   if _joint_kind(self.checker.model, j) is None]
            raise ValueError(f"no motion bound for the joints {bad} (only revolute and prismatic joints are "
                             "certified): use edge_check='sampled'")
        ca = self.clearances(a) if ca is None else ca
        cb = self.clearances(b) if cb is None else cb
        d = b - a
        clear = self.checker.clearances                 # the box is convex: the midpoints need no bounds test
        return certify_by_bisection(lambda s, idx: clear(a + s * d, idx), rates, ca, cb, max_queries=max_queries)
