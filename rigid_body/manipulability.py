"""Singularities and manipulability: rank, manipulability measures, velocity and force ellipsoids.

Yoshikawa's measure w = √det(J J^T) (3.56) is kinematic; Asada's measure (:func:`asada_manipulability`)
weighs the Jacobian with the inertia B(q). The end-effector (body) frame Jacobian lives here for now
(:func:`jacobian_in_frame`, :func:`end_effector_jacobian`), beside the base-frame one of
:mod:`rigid_body.kinematics`.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 3.1.3 (the Jacobian in a different frame), 3.3 (kinematic singularities), 3.5.1 (Eq. (3.56)
w(q) = √det(J J^T)), 3.9 (manipulability ellipsoids, Eqs. (3.123) v^T (J J^T)^{-1} v = 1 and
(3.126) γ^T (J J^T) γ = 1), 7.8 (operational-space inertia B_A = (J B⁻¹ J^T)⁻¹, Eq. (7.130));
H. Asada, "A geometrical representation of manipulator dynamics and its application to arm design",
ASME J. Dyn. Sys. Meas. Control 105, 1983 (the generalized inertia ellipsoid).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rigid_body.kinematics import direct_kinematics, geometric_jacobian
from rigid_body.robots import Robot
from rigid_body.rotations import as_rotation
from rigid_body.validation import as_count, as_tolerance, as_vector

__all__ = [
    "singular_values",
    "jacobian_rank",
    "is_singular",
    "manipulability",
    "asada_manipulability",
    "jacobian_in_frame",
    "end_effector_jacobian",
    "Ellipsoid",
    "velocity_ellipsoid",
    "force_ellipsoid",
    "plot_ellipse",
]

RANK_TOL = 1e-9  # singular values below RANK_TOL · σ_max (and below RANK_TOL absolutely) count as zero


def _jacobian(J: Any) -> np.ndarray:
    J = np.asarray(J, dtype=float)
    if J.ndim != 2 or J.size == 0 or not np.all(np.isfinite(J)):
        raise ValueError(f"`J` must be a finite, non-empty 2-D Jacobian, got shape {J.shape}")
    return J


def singular_values(J: Any) -> np.ndarray:
    """σ_1 ≥ … ≥ σ_r of the (r, n) Jacobian ``J`` (r of them, zeros included when r > n)."""
    J = _jacobian(J)
    s = np.linalg.svd(J, compute_uv=False)
    return np.concatenate([s, np.zeros(J.shape[0] - s.size)]) if s.size < J.shape[0] else s


def jacobian_rank(J: Any, tol: float = RANK_TOL) -> int:
    """Numerical rank of ``J``: the number of σ_i > tol · max(1, σ_1) (``tol`` in (0, 1e-3])."""
    tol = tol if tol is RANK_TOL else as_tolerance(tol)
    s = singular_values(J)
    return int(np.sum(s > tol * max(1.0, s[0])))


def is_singular(J: Any, tol: float = RANK_TOL) -> bool:
    """True when ``J`` (r, n) has rank below min(r, n): a kinematic singularity, Sect. 3.3."""
    J = _jacobian(J)
    return jacobian_rank(J, tol) < min(J.shape)


def manipulability(J: Any) -> float:
    """w = √det(J J^T), Eq. (3.56); equal to the product of the singular values (Problem 3.8)."""
    J = _jacobian(J)
    return float(np.sqrt(max(np.linalg.det(J @ J.T), 0.0)))


_AXES = {"all": slice(None), "trans": slice(0, 3), "rot": slice(3, 6)}


def asada_manipulability(J: Any, B: Any, axes: str = "all") -> float:
    """Asada's measure λ_min/λ_max of the operational-space inertia B_A = (J B⁻¹ J^T)⁻¹ (7.130), in [0, 1].

    The generalized inertia ellipsoid x^T B_A x = 1 tells how uniformly the end effector can be
    accelerated; the measure is the ratio of its smallest to largest eigenvalue (1: isotropic), as the
    Robotics Toolbox's ``manipulability(method="asada")``. It is computed from the eigenvalues of
    J B⁻¹ J^T (the same ratio, without inverting), so it tends to 0 at a singularity instead of failing.

    ``axes``: ``"all"`` uses the rows of ``J`` as given (e.g. ``J[:2]`` for a planar arm's x, y),
    ``"trans"`` the translational rows J[:3], ``"rot"`` the rotational rows J[3:6] of a 6-row J.
    ``B`` is the (n, n) inertia matrix, symmetric positive definite. For a square J this equals the
    Toolbox's J^{-T} B J^{-1}; for a J with fewer rows than joints B_A is the dynamically consistent
    operational-space inertia (7.130), whereas the Toolbox uses pinv(J)^T B pinv(J).
    """
    J = _jacobian(J)
    if axes not in _AXES:
        raise ValueError(f"`axes` must be one of {tuple(_AXES)}, got {axes!r}")
    if axes != "all":
        if J.shape[0] != 6:
            raise ValueError(f"`J` must have 6 rows [J_P; J_O] for axes={axes!r}, got shape {J.shape}")
        J = J[_AXES[axes]]
    B = np.asarray(B, dtype=float)
    if B.shape != (J.shape[1], J.shape[1]) or not np.all(np.isfinite(B)):
        raise ValueError(f"`B` must be a finite ({J.shape[1]}, {J.shape[1]}) inertia matrix, got shape {B.shape}")
    try:
        L = np.linalg.cholesky(0.5 * (B + B.T))
    except np.linalg.LinAlgError:
        raise ValueError("`B` must be symmetric positive definite") from None
    W = np.linalg.solve(L, J.T)  # J B⁻¹ J^T = W^T W
    lam = np.linalg.eigvalsh(W.T @ W)
    return float(max(lam[0], 0.0) / lam[-1]) if lam[-1] > 0 else 0.0


def jacobian_in_frame(J: Any, R: Any) -> np.ndarray:
    """J^u = [[R^T, 0], [0, R^T]] J: the (6, n) geometric Jacobian ``J`` (base frame) expressed in the
    frame u of orientation ``R`` = R_u (Sect. 3.1.3). With R = R_e it is the end-effector (body) frame
    Jacobian: ``J^e q̇`` is [v_e; ω_e] in frame e (Pinocchio's ``LOCAL``; Modern Robotics' J_b, ordered [ω; v])."""
    J = _jacobian(J)
    if J.shape[0] != 6:
        raise ValueError(f"`J` must have 6 rows [J_P; J_O], got shape {J.shape}")
    Rt = as_rotation(R).T
    return np.vstack([Rt @ J[:3], Rt @ J[3:]])


def end_effector_jacobian(robot: Robot, q: Any, frame: str | int | None = None) -> np.ndarray:
    """J^e(q) (6, nv): the geometric Jacobian of ``frame`` (default the end effector) expressed in that
    frame, :func:`jacobian_in_frame` of the base-frame :func:`rigid_body.kinematics.geometric_jacobian`."""
    T = direct_kinematics(robot, q, frame)
    return jacobian_in_frame(geometric_jacobian(robot, q, frame), T[:3, :3])


@dataclass(frozen=True)
class Ellipsoid:
    """An ellipsoid x^T A^{-1} x = 1: principal axes ``axes[:, i]`` (unit) and ``semi_axes[i]`` lengths."""

    axes: np.ndarray
    semi_axes: np.ndarray

    @property
    def core(self) -> np.ndarray:
        """The matrix A^{-1} of the quadratic form x^T A^{-1} x = 1."""
        return self.axes @ np.diag(self.semi_axes ** -2.0) @ self.axes.T


def velocity_ellipsoid(J: Any) -> Ellipsoid:
    """Velocity manipulability ellipsoid v^T (J J^T)^{-1} v = 1, Eq. (3.123): axes u_i, semi-axes σ_i.

    Raises ValueError at a singularity (the ellipsoid degenerates; J J^T is not invertible).
    """
    U, s = _principal_axes(J, "velocity ellipsoid degenerates: a zero semi-axis")
    return Ellipsoid(U, s)


def force_ellipsoid(J: Any) -> Ellipsoid:
    """Force manipulability ellipsoid γ^T (J J^T) γ = 1, Eq. (3.126): same axes u_i, semi-axes 1/σ_i.

    Raises ValueError at a singularity (a semi-axis 1/σ_i would be infinite).
    """
    U, s = _principal_axes(J, "force ellipsoid degenerates: an infinite semi-axis 1/sigma_i")
    return Ellipsoid(U, 1.0 / s)


def _principal_axes(J: Any, what: str) -> tuple[np.ndarray, np.ndarray]:
    """U and σ_1 ≥ … ≥ σ_r (zeros included) of J = U Σ V^T; ValueError naming ``what`` at a singularity."""
    J = _jacobian(J)
    U, s, _ = np.linalg.svd(J, full_matrices=True)
    s = np.concatenate([s, np.zeros(J.shape[0] - s.size)]) if s.size < J.shape[0] else s
    if s[-1] <= RANK_TOL * max(1.0, s[0]):
        raise ValueError(f"`J` is singular: the {what} (J J^T not invertible)")
    return U, s


def plot_ellipse(ax: Any, ellipsoid: Ellipsoid, center: Any = (0.0, 0.0), n: int = 100, **kwargs: Any) -> Any:
    """Draw a 2-D ellipsoid (e.g. of the position rows of a planar arm) on ``ax``; returns the line."""
    if ellipsoid.axes.shape != (2, 2):
        raise ValueError(f"`ellipsoid` must be 2-D to be drawn, got axes of shape {ellipsoid.axes.shape}")
    c = as_vector(center, 2, "center")
    t = np.linspace(0.0, 2.0 * np.pi, as_count(n, "n", minimum=3))
    pts = ellipsoid.axes @ (ellipsoid.semi_axes[:, None] * np.vstack([np.cos(t), np.sin(t)]))
    (line,) = ax.plot(c[0] + pts[0], c[1] + pts[1], **kwargs)
    return line
