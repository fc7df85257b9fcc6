"""Environments an end effector can touch: each gives the contact wrench from the end-effector motion.

An environment has ``wrench(T_e, v_e) -> h_e``: from the end-effector pose ``T_e`` (a ``pin.SE3`` or
(4, 4) in the base frame) and twist ``v_e = [ṗ_e; ω_e]`` (6,), the wrench h_e = [f_e; μ_e] (6,) exerted
BY the end effector ON the environment, in the base frame (the book's convention, Sect. 9.1: the arm
feels −h_e, whence the −Jᵀ h_e of Eq. (7.42)). An environment with its own dynamics keeps its state
itself. :class:`controllers.plants.ArmInContact` puts an arm in contact with one.

* :class:`CompliantPlane` — an elastic plane, h_e = K δ (−n) with δ the penetration (the compliant
  environment of Sect. 9.2): unilateral (reaction only while pushed; contact can be lost) or bilateral
  (a linear spring), with optional damping and regularised Coulomb friction.
* :class:`SteppedPlane` — the same with a recess: the surface steps back beyond an edge.
* :class:`SurfaceWithHole` — the planar compliant surface with a hole of the peg-in-hole task (6.3).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 9.1–9.2, Eq. (7.42); Problem 6.3.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from controllers.laws import Numeric
from rigid_body.rotations import as_homogeneous
from rigid_body.validation import as_positive, as_scalar, as_vector


class Environment(Protocol):
    """``wrench(T_e, v_e) -> h_e`` (6,): the wrench exerted by the end effector on the environment."""

    def wrench(self, T_e: Any, v_e: np.ndarray) -> np.ndarray: ...


NO_CONTACT = np.zeros(6)   # the wrench of an environment not touched (shared, read-only)
NO_CONTACT.setflags(write=False)


def _position(T_e: Any) -> np.ndarray:
    """The origin of the end-effector pose ``T_e`` (a ``pin.SE3`` or a (4, 4) homogeneous transform),
    checked: ValueError naming ``T_e`` (a (3,) position is not a pose: ``wrench_at`` takes one)."""
    if hasattr(T_e, "translation") and hasattr(T_e, "rotation"):
        T_e = T_e.homogeneous
    if np.shape(T_e) != (4, 4):
        raise ValueError(f"`T_e` must be the end-effector pose, a pin.SE3 or a (4, 4) homogeneous transform, "
                         f"got shape {np.shape(T_e)} (for a position p_e (3,) call wrench_at(p_e, v_e))")
    return as_homogeneous(T_e, "T_e")[:3, 3]


class ContactEnvironment:
    """An environment whose wrench depends on the end-effector position only (not its orientation):
    subclasses give ``wrench_at(p_e, v_e)`` on plain arrays (position (3,), twist (6,)) — what
    :class:`controllers.plants.ArmInContact` calls in its hot loop — and inherit ``wrench(T_e, v_e)``.
    Without contact ``wrench_at`` returns :data:`NO_CONTACT` (read-only zeros)."""

    def wrench_at(self, p_e: np.ndarray, v_e: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def contact_modes(self) -> list[tuple[np.ndarray, float, float]]:
        """The springs of the contact, (direction d (3,), stiffness k [N/m], damping c [N·s/m]) in the base
        frame: what limits the integration step (:meth:`controllers.plants.ArmInContact.check_step`)."""
        return []

    def wrench(self, T_e: Any, v_e: np.ndarray) -> np.ndarray:
        """h_e (6,) at the pose T_e (``pin.SE3`` or (4, 4)) and twist v_e (6,), both checked (ValueError
        naming them); ``wrench_at`` is the unchecked form on plain arrays."""
        return self.wrench_at(_position(T_e), as_vector(v_e, 6, "v_e"))


class CompliantPlane(ContactEnvironment):
    """The half-space n·(p − p_0) ≤ 0 of elastic material, stiffness K [N/m] and damping D [N·s/m].

    With penetration δ = n·(p_0 − p) > 0 the material pushes back along its outward normal n with
    N = max(K δ + D δ̇, 0) (it only pushes), so the end effector exerts h_e = −N n, no moment: the
    compliant environment of Sect. 9.2, K = k n nᵀ in the base frame (the plane of Fig. 9.16, Problems 9.3, 9.10, for
    a planar arm). Contact is lost when δ ≤ 0 (:meth:`in_contact`; the sensed wrench is then zero).

    Options
    -------
    bilateral : the linear spring h_e = −(K δ + D δ̇) n on both sides (the authors' f_e = K (o_e − o_r)):
        it also pulls, contact is never lost.
    friction : Coulomb coefficient μ ≥ 0: while in contact the surface resists sliding with a tangential
        force of magnitude μ N against the tangential velocity v_t, regularised as
        μ N tanh(‖v_t‖/v_s) v_t/‖v_t‖ (``slip_velocity`` v_s [m/s]: a smooth right-hand side for RK4); the
        end effector exerts its opposite, + μ N tanh(‖v_t‖/v_s) v_t/‖v_t‖.

    A "rigid-ish" wall for a 3-D arm is this plane with a high stiffness and some damping (e.g. 10⁵ N/m,
    10³ N·s/m); its time constant D/K must stay above the integration step.
    """

    def __init__(self, point: Any, normal: Any, stiffness: float, damping: float = 0.0, bilateral: bool = False,
                 friction: float = 0.0, slip_velocity: float = 1e-3):
        self.point = as_vector(point, 3, "point").copy()
        n = as_vector(normal, 3, "normal")
        norm = float(np.linalg.norm(n))
        if not norm > 0:
            raise ValueError(f"`normal` must be a non-zero vector, got {normal!r}")
        self.normal = n / norm
        self.stiffness = as_positive(stiffness, "stiffness")
        self.damping = as_positive(damping, "damping", allow_zero=True)
        self.bilateral = bool(bilateral)
        self.friction = as_positive(friction, "friction", allow_zero=True)
        self.slip_velocity = as_positive(slip_velocity, "slip_velocity")
        self._n = tuple(float(c) for c in self.normal)             # plain floats for the hot loop
        self._offset = float(self.normal @ self.point)             # n·p_0
        self._normal_twist = np.concatenate([self.normal, np.zeros(3)])   # v_n = [n; 0]·v_e, h_e = −N [n; 0]

    def contact_modes(self) -> list[tuple[np.ndarray, float, float]]:
        """One spring along the normal: (n, K, D). (Friction's regularised slope μN/v_s is not counted.)"""
        return [(self.normal.copy(), self.stiffness, self.damping)]

    def penetration(self, p: np.ndarray) -> float:
        """δ = n·(p_0 − p) [m] (positive inside the material)."""
        return self.penetration_law(Numeric, p if isinstance(p, np.ndarray) else np.asarray(p, dtype=float))

    def penetration_law(self, ops: Any, p: Any) -> Any:
        """δ = n·(p_0 − p), for either loop."""
        n0, n1, n2 = self._n
        return self._offset - (n0 * p[0] + n1 * p[1] + n2 * p[2])

    def in_contact(self, T_e: Any) -> bool:
        """True when the end effector is inside the material (always for a bilateral spring)."""
        return self.bilateral or self.penetration(_position(T_e)) > 0.0

    def wrench_at(self, p_e: np.ndarray, v_e: np.ndarray) -> np.ndarray:
        return self.wrench_law(Numeric, p_e, v_e)

    def wrench_law(self, ops: Any, p_e: Any, v_e: Any) -> Any:
        """h_e at the position p_e and twist v_e: the one body of the plane for both loops (no contact:
        :data:`NO_CONTACT`; the branches are masked expressions in the compiled loop)."""
        delta = self.penetration_law(ops, p_e)

        def pushed() -> Any:
            v_n = ops.dot(self._normal_twist, v_e)
            push = self.stiffness * delta - self.damping * v_n
            if self.bilateral:
                return self._reaction(ops, push, v_n, v_e)
            return ops.cond(push <= 0.0, lambda: NO_CONTACT, lambda: self._reaction(ops, push, v_n, v_e))

        if self.bilateral:
            return pushed()
        return ops.cond(delta <= 0.0, lambda: NO_CONTACT, pushed)

    def _reaction(self, ops: Any, push: Any, v_n: Any, v_e: Any) -> Any:
        """−N [n; 0] with N = K δ + D δ̇, plus the regularised Coulomb friction μ N tanh(‖v_t‖/v_s) v_t/‖v_t‖."""
        h = self._normal_twist * -push
        if self.friction <= 0.0:
            return h

        def sliding() -> Any:
            v_t = v_e[:3] - v_n * self.normal
            speed = ops.norm(v_t)
            tangential = lambda: self.friction * push * ops.tanh(speed / self.slip_velocity) / speed * v_t
            return ops.cond(speed > 0.0, lambda: h + ops.vertcat(tangential(), ops.zeros(3)), lambda: h)

        return ops.cond(push > 0.0, sliding, lambda: h)


class SteppedPlane(CompliantPlane):
    """A :class:`CompliantPlane` whose surface steps back by ``depth`` [m] (along −n) beyond
    ``step_at`` [m] measured from ``point`` along the tangent ``direction``: a wall with a recess.

    An end effector sliding along ``direction`` leaves the surface at the edge (contact lost) and must
    move ``depth`` further to touch it again. The riser of the step is not modelled (it is met only when
    sliding back).
    """

    def __init__(self, point: Any, normal: Any, direction: Any, step_at: float, depth: float, stiffness: float,
                 damping: float = 0.0, friction: float = 0.0, slip_velocity: float = 1e-3):
        super().__init__(point, normal, stiffness, damping, friction=friction, slip_velocity=slip_velocity)
        d = as_vector(direction, 3, "direction")
        d = d - float(d @ self.normal) * self.normal
        if not np.linalg.norm(d) > 1e-9:
            raise ValueError("`direction` must have a component along the plane (not parallel to `normal`)")
        self.direction = d / np.linalg.norm(d)
        self.step_at = as_scalar(step_at, "step_at")
        self.depth = as_positive(depth, "depth")
        self._edge = float(self.direction @ self.point) + self.step_at      # d·p beyond which the recess lies

    def penetration_law(self, ops: Any, p: Any) -> Any:
        delta = super().penetration_law(ops, p)
        return ops.cond(ops.dot(self.direction, p) - self._edge > 0.0, lambda: delta - self.depth, lambda: delta)


@dataclass(frozen=True)
class SurfaceWithHole(ContactEnvironment):
    """A compliant horizontal surface y ≤ 0 (in the x–y plane of a planar arm) with a hole (penalty
    contact, frictionless).

    The hole is centred at ``x_hole`` with half-width ``clearance`` (hole radius minus peg radius:
    the peg tip is a point), ``depth`` deep. The material reacts with stiffness ``stiffness`` [N/m]
    and damping ``damping`` [N·s/m] along the normal of the nearest face (top surface, hole walls,
    hole bottom); it only pushes.
    """

    x_hole: float
    clearance: float
    depth: float
    stiffness: float = 2e4
    damping: float = 50.0

    def __post_init__(self) -> None:
        checked = {"x_hole": as_scalar(self.x_hole, "x_hole"), "clearance": as_positive(self.clearance, "clearance"),
                   "depth": as_positive(self.depth, "depth"), "stiffness": as_positive(self.stiffness, "stiffness"),
                   "damping": as_positive(self.damping, "damping", allow_zero=True)}
        for name, value in checked.items():
            object.__setattr__(self, name, value)

    def contact_modes(self) -> list[tuple[np.ndarray, float, float]]:
        """The faces' springs: the hole walls along x, the top surface and the bottom along y."""
        return [(np.array([1.0, 0.0, 0.0]), self.stiffness, self.damping),
                (np.array([0.0, 1.0, 0.0]), self.stiffness, self.damping)]

    def force(self, p: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Force (f_x, f_y) exerted by the environment on the peg tip at position p, velocity v."""
        h = self.wrench_at(np.array([p[0], p[1], 0.0]), np.array([v[0], v[1], 0.0, 0.0, 0.0, 0.0]))
        return -h[:2]

    def wrench_at(self, p_e: np.ndarray, v_e: np.ndarray) -> np.ndarray:
        """h_e (6,): minus the reaction :meth:`force` at the tip, in the base frame (:data:`NO_CONTACT`
        when there is none). Scalar arithmetic on floats: the hot path of ArmInContact."""
        x, y, _ = p_e.tolist()
        if y >= 0.0:
            return NO_CONTACT
        offset = x - self.x_hole
        into_wall = abs(offset) - self.clearance
        if into_wall > 0.0 and -y > into_wall:                      # against a hole wall
            sign = 1.0 if offset > 0.0 else -1.0
            push = self.stiffness * into_wall + self.damping * float(v_e[0]) * sign
            return NO_CONTACT if push <= 0.0 else np.array([sign * push, -0.0, 0.0, 0.0, 0.0, 0.0])
        pen = -y if into_wall > 0.0 else -self.depth - y            # the top surface, else the hole's bottom
        if pen <= 0.0:
            return NO_CONTACT
        push = self.stiffness * pen - self.damping * float(v_e[1])
        return NO_CONTACT if push <= 0.0 else np.array([-0.0, -push, 0.0, 0.0, 0.0, 0.0])
