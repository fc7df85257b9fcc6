"""Environments an end effector can touch: each gives the contact wrench from the end-effector motion.

An environment has ``wrench(T_e, v_e) -> h_e``: from the end-effector pose ``T_e`` (a ``pin.SE3`` or
(4, 4) in the base frame) and twist ``v_e = [ṗ_e; ω_e]`` (6,), the wrench h_e = [f_e; μ_e] (6,) exerted
BY the end effector ON the environment, in the base frame (the book's convention, Sect. 9.1: the arm
feels −h_e, whence the −Jᵀ h_e of Eq. (7.42)). An environment with its own dynamics keeps its state
itself. :class:`controllers.plants.ArmInContact` puts an arm in contact with one.

* :class:`CompliantPlane` — a frictionless elastic plane, h_e = K δ (−n) with δ the penetration
  (the compliant environment of Sect. 9.2, reaction only while pushed).
* :class:`SurfaceWithHole` — the planar compliant surface with a hole of the peg-in-hole task (6.3).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 9.1–9.2, Eq. (7.42); Problem 6.3.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from rigid_body.validation import as_positive, as_vector


class Environment(Protocol):
    """``wrench(T_e, v_e) -> h_e`` (6,): the wrench exerted by the end effector on the environment."""

    def wrench(self, T_e: Any, v_e: np.ndarray) -> np.ndarray: ...


def _position(T_e: Any) -> np.ndarray:
    return T_e.translation if hasattr(T_e, "translation") else np.asarray(T_e)[:3, 3]


class CompliantPlane:
    """The half-space n·(p − p_0) ≤ 0 of elastic material, stiffness K [N/m] and damping D [N·s/m].

    With penetration δ = n·(p_0 − p) > 0 the material pushes back along its outward normal n with
    max(K δ + D δ̇, 0) (it only pushes), so the end effector exerts h_e = −max(K δ + D δ̇, 0) n, no moment.
    """

    def __init__(self, point: Any, normal: Any, stiffness: float, damping: float = 0.0):
        self.point = as_vector(point, 3, "point").copy()
        n = as_vector(normal, 3, "normal")
        norm = float(np.linalg.norm(n))
        if not norm > 0:
            raise ValueError(f"`normal` must be a non-zero vector, got {normal!r}")
        self.normal = n / norm
        self.stiffness = as_positive(stiffness, "stiffness")
        self.damping = as_positive(damping, "damping", allow_zero=True)

    def penetration(self, p: np.ndarray) -> float:
        """δ = n·(p_0 − p) [m] (positive inside the material)."""
        return float(self.normal @ (self.point - p))

    def wrench(self, T_e: Any, v_e: np.ndarray) -> np.ndarray:
        h = np.zeros(6)
        delta = self.penetration(_position(T_e))
        if delta > 0.0:
            push = max(self.stiffness * delta - self.damping * float(self.normal @ v_e[:3]), 0.0)
            h[:3] = -push * self.normal
        return h


@dataclass(frozen=True)
class SurfaceWithHole:
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

    def force(self, p: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Force (f_x, f_y) exerted by the environment on the peg tip at position p, velocity v."""
        x, y = p
        if y >= 0.0:
            return np.zeros(2)
        offset = x - self.x_hole
        into_wall = abs(offset) - self.clearance
        if into_wall <= 0.0:                                        # inside the hole opening
            pen = -self.depth - y
            if pen <= 0.0:
                return np.zeros(2)
            return np.array([0.0, max(self.stiffness * pen - self.damping * v[1], 0.0)])
        if -y <= into_wall:                                         # on the top surface
            return np.array([0.0, max(self.stiffness * (-y) - self.damping * v[1], 0.0)])
        sign = np.sign(offset)                                      # against a hole wall
        return np.array([-sign * max(self.stiffness * into_wall + self.damping * v[0] * sign, 0.0), 0.0])

    def wrench(self, T_e: Any, v_e: np.ndarray) -> np.ndarray:
        """h_e (6,): minus the reaction :meth:`force` at the tip, in the base frame."""
        h = np.zeros(6)
        h[:2] = -self.force(_position(T_e)[:2], v_e[:2])
        return h
