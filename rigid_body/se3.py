"""Rigid motions as exponentials: SO(3)/SE(3) logarithm and exponential, twists, screws.

The home of the exponential coordinates of rotations and poses in rmpc (the rotation matrices,
Euler angles, quaternions and the projection onto SO(3) stay in :mod:`rigid_body.rotations`).
Built on Pinocchio's ``pin.exp3``, ``pin.log3``, ``pin.exp6``, ``pin.log6``; arrays in, arrays out.

Conventions:

* a rotation is a (3, 3) array R, a pose a (4, 4) homogeneous transform T = [[R, o], [0, 1]] (2.42);
* a **twist** is the 6-vector ξ = [v; ω] — linear part first, as the book's [J_P; J_O] (3.4) and
  Pinocchio's ``pin.Motion`` — with matrix form ξ^ = [[S(ω), v], [0, 0]]. Modern Robotics
  (Lynch & Park) writes the same twist as [ω; v]: swap the halves when comparing;
* exp3(ω) = exp(S(ω)) = R(‖ω‖, ω/‖ω‖) of Eq. (2.25); log3 returns ω = θ r with θ ∈ [0, π];
* exp6(ξ) = exp(ξ^) ∈ SE(3); log6 returns ξ with ‖ω‖ ∈ [0, π];
* a screw of unit axis ``axis`` through ``point`` with ``pitch`` h (translation per radian) and
  magnitude θ is the twist θ [−axis × point + h axis; axis]; a pure translation has infinite pitch
  and twist θ [axis; 0].

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 2.5 (angle and axis), 2.7 (homogeneous transformations), 3.1 (linear and angular velocity);
K. Lynch, F. Park, *Modern Robotics*, Cambridge 2017, Sects. 3.2.3 (exponential coordinates of
rotation), 3.3.2–3.3.3 (twists, screws, exponential coordinates of rigid-body motion);
P. Corke, *Robotics, Vision and Control*, Springer 2017, Sect. 3.1.2 (``tr2delta``/``delta2tr``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from rigid_body.rotations import as_homogeneous, as_rotation, homogeneous_inverse, skew, vee
from rigid_body.validation import as_matrix, as_vector

__all__ = [
    "exp3", "log3", "exp6", "log6", "twist_matrix", "twist_vector",
    "Screw", "screw_to_twist", "twist_to_screw", "screw_interpolation", "pose_delta", "delta_to_pose",
]

ZERO_ROTATION_TOL = 1e-12  # ‖ω‖ below which a twist is a pure translation (infinite pitch)


# --------------------------------------------------------------------------------------------
# Exponential and logarithm
# --------------------------------------------------------------------------------------------

def exp3(omega: Any) -> np.ndarray:
    """R = exp(S(ω)): rotation by θ = ‖ω‖ about ω/θ (Rodrigues, Eq. (2.25)); ``omega`` (3,)."""
    return pin.exp3(as_vector(omega, 3, "omega"))


def log3(R: Any) -> np.ndarray:
    """ω = θ r with exp(S(ω)) = R and θ ∈ [0, π]: the exponential coordinates of a rotation (3,)."""
    return np.asarray(pin.log3(as_rotation(R)), dtype=float)


def exp6(xi: Any) -> np.ndarray:
    """T = exp(ξ^) (4, 4) of the twist ``xi`` = [v; ω] (6,)."""
    return pin.exp6(as_vector(xi, 6, "xi")).homogeneous


def log6(T: Any) -> np.ndarray:
    """ξ = [v; ω] with exp(ξ^) = T and ‖ω‖ ∈ [0, π]: the exponential coordinates of a pose (6,)."""
    return pin.log6(as_homogeneous(T)).vector.copy()


def twist_matrix(xi: Any) -> np.ndarray:
    """ξ^ = [[S(ω), v], [0, 0]] (4, 4) of the twist ``xi`` = [v; ω]; Ṫ T⁻¹ = ξ^ for a spatial twist."""
    xi = as_vector(xi, 6, "xi")
    X = np.zeros((4, 4))
    X[:3, :3] = skew(xi[3:])
    X[:3, 3] = xi[:3]
    return X


def twist_vector(X: Any) -> np.ndarray:
    """[v; ω] (6,) of the (4, 4) ``X`` = ξ^ (inverse of :func:`twist_matrix`; antisymmetric part of X[:3, :3])."""
    X = as_matrix(X, (4, 4), "X")
    return np.concatenate([X[:3, 3], vee(X[:3, :3])])


# --------------------------------------------------------------------------------------------
# Screws
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Screw:
    """A screw motion: rotation ``magnitude`` θ [rad] about the unit ``axis`` through ``point`` and
    translation h θ along it (``pitch`` h [m/rad]); a pure translation has ``pitch = inf`` and moves
    ``magnitude`` [m] along ``axis`` (``point`` is then the origin). ``point`` is the axis point
    closest to the origin when the screw comes from :func:`twist_to_screw`."""

    axis: np.ndarray
    point: np.ndarray
    pitch: float
    magnitude: float

    @property
    def twist(self) -> np.ndarray:
        """The twist [v; ω] of this screw (see :func:`screw_to_twist`)."""
        return screw_to_twist(self.axis, self.point, self.pitch, self.magnitude)


def screw_to_twist(axis: Any, point: Any, pitch: float, magnitude: float = 1.0) -> np.ndarray:
    """ξ = θ [−â × p + h â; â] of the screw with unit ``axis`` â through ``point`` p, ``pitch`` h, θ = ``magnitude``.

    ``pitch = inf`` gives the pure translation θ [â; 0]. exp6 of the result is the screw motion.
    """
    a = as_vector(axis, 3, "axis")
    norm = np.linalg.norm(a)
    if not abs(norm - 1.0) <= 1e-6:
        raise ValueError(f"`axis` must be a unit vector, got norm {norm:.6g}")
    p = as_vector(point, 3, "point")
    try:
        h = float(pitch)
    except (TypeError, ValueError):
        raise ValueError(f"`pitch` must be a number, got {type(pitch).__name__}") from None
    if math.isnan(h) or h == -math.inf:
        raise ValueError(f"`pitch` must be finite or +inf (pure translation), got {pitch}")
    theta = float(as_vector(magnitude, 1, "magnitude")[0])
    if h == math.inf:
        return theta * np.concatenate([a, np.zeros(3)])
    return theta * np.concatenate([-np.cross(a, p) + h * a, a])


def twist_to_screw(xi: Any) -> Screw:
    """The screw of the twist ``xi`` = [v; ω]: â = ω/‖ω‖, θ = ‖ω‖, h = â·v/θ, p = â × v/θ (closest to the origin).

    With ‖ω‖ ≤ ``ZERO_ROTATION_TOL`` the twist is a pure translation: â = v/‖v‖, θ = ‖v‖, h = inf.
    ValueError for the zero twist (no axis).
    """
    xi = as_vector(xi, 6, "xi")
    v, w = xi[:3], xi[3:]
    theta = float(np.linalg.norm(w))
    if theta <= ZERO_ROTATION_TOL:
        d = float(np.linalg.norm(v))
        if d == 0.0:
            raise ValueError("`xi` is the zero twist: it has no screw axis")
        return Screw(v / d, np.zeros(3), math.inf, d)
    a, u = w / theta, v / theta
    return Screw(a, np.cross(a, u), float(a @ u), theta)


def screw_interpolation(T_i: Any, T_f: Any, s: Any) -> np.ndarray:
    """T(s) = T_i exp(s log(T_i⁻¹ T_f)^): the screw motion from ``T_i`` (s = 0) to ``T_f`` (s = 1).

    The relative motion is one screw (constant axis, rotation and translation in proportion), the
    SE(3) analogue of the axis–angle interpolation of Sect. 4.5. ``s`` a scalar gives (4, 4), an
    (M,) array (M, 4, 4). The rotation part rotates by less than π (log6's principal value).
    """
    T_i = as_homogeneous(T_i, "T_i")
    T_f = as_homogeneous(T_f, "T_f")
    s_arr = np.asarray(s, dtype=float)
    if s_arr.ndim > 1 or not np.all(np.isfinite(s_arr)):
        raise ValueError(f"`s` must be a finite scalar or 1-D array, got {s!r}")
    xi = pin.log6(homogeneous_inverse(T_i) @ T_f).vector
    start = pin.SE3(T_i)
    out = np.array([(start * pin.exp6(float(sk) * xi)).homogeneous for sk in np.atleast_1d(s_arr)])
    return out[0] if s_arr.ndim == 0 else out


# --------------------------------------------------------------------------------------------
# Differential motion (the Toolbox's tr2delta / delta2tr)
# --------------------------------------------------------------------------------------------

def pose_delta(T_0: Any, T_1: Any) -> np.ndarray:
    """Δ = [d; δ] (6,), the differential motion from ``T_0`` to the nearby ``T_1``, in frame T_0.

    With T_0⁻¹ T_1 = [[R, d], [0, 1]], δ = vee(R − I) (= ½ vee(R − R^T) to first order), i.e.
    T_1 ≈ T_0 (I + Δ^). For small motions Δ ≈ log6(T_0⁻¹ T_1) (error of second order); it is the
    Toolbox's ``tr2delta(T0, T1)``, ordered [v; ω] like a twist.
    """
    D = homogeneous_inverse(as_homogeneous(T_0, "T_0")) @ as_homogeneous(T_1, "T_1")
    return twist_vector(D - np.eye(4))


def delta_to_pose(delta: Any, T_0: Any = None) -> np.ndarray:
    """T_0 (I + Δ^) (4, 4): the pose displaced by the differential motion ``delta`` = [d; δ] in frame T_0.

    First order, as the Toolbox's ``delta2tr``: its rotation part I + S(δ) is orthonormal only to
    first order in ‖δ‖ (|R^T R − I| ≈ ‖δ‖²: rmpc accepts it as a rotation only while that stays below
    ``ORTHONORMAL_TOL``; re-orthonormalise with :func:`rigid_body.rotations.nearest_rotation`, or use
    :func:`exp6` for an exact pose). ``T_0`` defaults to the identity.
    """
    D = np.eye(4) + twist_matrix(as_vector(delta, 6, "delta"))
    return D if T_0 is None else as_homogeneous(T_0, "T_0") @ D
