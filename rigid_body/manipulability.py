"""Singularities and manipulability: rank, manipulability measure, velocity and force ellipsoids.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 3.3 (kinematic singularities), 3.5.1 (Eq. (3.56) w(q) = √det(J J^T)), 3.9 (manipulability
ellipsoids, Eqs. (3.123) v^T (J J^T)^{-1} v = 1 and (3.126) γ^T (J J^T) γ = 1).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "singular_values",
    "jacobian_rank",
    "is_singular",
    "manipulability",
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
    """Numerical rank of ``J``: the number of σ_i > tol · max(1, σ_1)."""
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
    c = np.asarray(center, dtype=float)
    t = np.linspace(0.0, 2.0 * np.pi, n)
    pts = ellipsoid.axes @ (ellipsoid.semi_axes[:, None] * np.vstack([np.cos(t), np.sin(t)]))
    (line,) = ax.plot(c[0] + pts[0], c[1] + pts[1], **kwargs)
    return line
