"""Statics: kineto-statics duality (τ = J^T γ).

Conventions: a wrench ``γ = [f; μ]`` (6,) is a force f and a moment μ about the frame origin, both
in the frame's coordinates; the book's geometric Jacobian maps it to joint torques τ = J^T γ.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 3.8 (Eq. (3.111) τ = J^T γ_e; the wrench transformation (3.116)–(3.117) is
:func:`rigid_body.sensors.wrench_transform`). The distance of an arm from an obstacle (Problem 3.9)
lives in :mod:`planners.configuration_space`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rigid_body.validation import as_vector

__all__ = [
    "joint_torques",
]


def joint_torques(J: Any, gamma: Any) -> np.ndarray:
    """τ = J^T(q) γ_e: joint torques balancing the end-effector wrench γ_e at equilibrium, Eq. (3.111).

    ``J`` is (r, n) (e.g. the (6, n) geometric Jacobian), ``gamma`` (r,).
    """
    J = np.asarray(J, dtype=float)
    if J.ndim != 2:
        raise ValueError(f"`J` must be a 2-D Jacobian, got shape {J.shape}")
    return J.T @ as_vector(gamma, J.shape[0], "gamma")


