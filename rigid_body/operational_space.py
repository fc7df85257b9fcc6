"""Operational-space dynamics and the dynamic manipulability ellipsoid (Eq. 7.149).

Every function works on arrays (B, C, g, J_A, J̇_A), whichever model produced them: Pinocchio
(:mod:`rigid_body.dynamics`) or the book's Lagrange model (:mod:`rigid_body.lagrange`). J_A is
r × n with r ≤ n and full row rank; for r < n (a redundant arm) the model is the one seen at the
end effector, through the dynamically consistent pseudo-inverse J̄_A.

* B_A = (J_A B⁻¹ J_Aᵀ)⁻¹ (7.130); J̄_A = B⁻¹ J_Aᵀ B_A (7.138);
* C_A = B_A J_A B⁻¹ C J̄_A − B_A J̇_A J̄_A, so that C_A ẋ = B_A J_A B⁻¹ C q̇ − B_A J̇_A q̇ (7.131), the
  matrix of Problem 7.9; g_A = J̄_Aᵀ g = B_A J_A B⁻¹ g;
* for square J_A these reduce to B_A = J_A⁻ᵀ B J_A⁻¹, g_A = J_A⁻ᵀ g (7.134)–(7.136), Problem 7.6.

The kinematic side of the task (pose errors, J, J̇q̇ of a frame in one pass, the kinematic inverses)
lives in :mod:`rigid_body.task_space`; this module keeps the dynamics seen in the task space.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Eqs. (7.130)–(7.138), (7.149); solution manual, Problems 7.6, 7.9, 7.10, 7.11.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from rigid_body.manipulability import Ellipsoid, manipulability, velocity_ellipsoid
from rigid_body.validation import as_matrix, as_vector


def _inertia(B: Any) -> tuple[np.ndarray, Any]:
    B = np.asarray(B, dtype=float)
    if B.ndim != 2 or B.shape[0] != B.shape[1] or not np.all(np.isfinite(B)):
        raise ValueError(f"`B` must be a finite square inertia matrix, got shape {B.shape}")
    if not np.allclose(B, B.T, rtol=1e-9, atol=1e-12 * max(1.0, float(np.abs(B).max()))):
        raise ValueError("`B` must be symmetric positive definite (it is not symmetric)")
    try:
        return B, cho_factor(B)
    except np.linalg.LinAlgError:
        raise ValueError("`B` must be symmetric positive definite") from None


def _task_jacobian(J: Any, n: int) -> np.ndarray:
    J = np.atleast_2d(np.asarray(J, dtype=float))
    if J.ndim != 2 or J.shape[1] != n or J.shape[0] > n or not np.all(np.isfinite(J)):
        raise ValueError(f"`J` must be a finite (r, {n}) Jacobian with r <= {n}, got shape {J.shape}")
    return J


def operational_space_inertia(B: Any, J: Any) -> np.ndarray:
    """B_A = (J_A B⁻¹ J_Aᵀ)⁻¹, (r, r), Eq. (7.130).

    Raises ValueError when J_A loses rank (the operational-space inertia is undefined).
    """
    B, chol = _inertia(B)
    J = _task_jacobian(J, B.shape[0])
    Lambda_inv = J @ cho_solve(chol, J.T)
    s = np.linalg.svd(Lambda_inv, compute_uv=False)
    if s[-1] <= 1e-12 * s[0]:
        raise ValueError("`J` is singular: J_A B⁻¹ J_Aᵀ is not invertible (a kinematic singularity)")
    B_A = np.linalg.inv(Lambda_inv)
    return 0.5 * (B_A + B_A.T)


def dynamically_consistent_inverse(B: Any, J: Any) -> np.ndarray:
    """J̄_A = B⁻¹ J_Aᵀ (J_A B⁻¹ J_Aᵀ)⁻¹, (n, r): the right inverse of J_A weighted by B, Eq. (7.138)."""
    B, chol = _inertia(B)
    J = _task_jacobian(J, B.shape[0])
    return cho_solve(chol, J.T) @ operational_space_inertia(B, J)


@dataclass(frozen=True)
class OperationalSpaceModel:
    """B_A(q) ẍ + C_A(q, q̇) ẋ + g_A(q) = γ_A: ``B_A`` (r, r), ``C_A`` (r, r), ``g_A`` (r,) and
    the dynamically consistent pseudo-inverse ``J_bar`` (n, r), Eqs. (7.130)–(7.138)."""

    B_A: np.ndarray
    C_A: np.ndarray
    g_A: np.ndarray
    J_bar: np.ndarray


def operational_space_model(B: Any, C: Any, g: Any, J: Any, Jdot: Any) -> OperationalSpaceModel:
    """The operational-space model from the joint-space one, Eqs. (7.130), (7.131), (7.138).

    Parameters
    ----------
    B, C : (n, n) inertia and Coriolis matrices at (q, q̇); g : (n,) gravity torques.
    J, Jdot : (r, n) analytical Jacobian J_A(q) and its time derivative J̇_A(q, q̇).

    For a redundant arm C_A ẋ equals the vector of (7.131) when q̇ = J̄_A ẋ (no null-space motion),
    the right inverse used by the manual in Problem 7.9.
    """
    B, chol = _inertia(B)
    n = B.shape[0]
    C = as_matrix(C, (n, n), "C")
    g = as_vector(g, n, "g")
    J = _task_jacobian(J, n)
    Jdot = as_matrix(Jdot, J.shape, "Jdot")
    B_A = operational_space_inertia(B, J)
    J_bar = cho_solve(chol, J.T) @ B_A
    BAJBinv = J_bar.T  # B_A J B⁻¹ = J̄ᵀ (B symmetric)
    C_A = BAJBinv @ C @ J_bar - B_A @ Jdot @ J_bar
    return OperationalSpaceModel(B_A=B_A, C_A=C_A, g_A=BAJBinv @ g, J_bar=J_bar)


def operational_space_inertia_rate(B: Any, Bdot: Any, J: Any, Jdot: Any) -> np.ndarray:
    """Ḃ_A = −B_A (J̇_A B⁻¹ J_Aᵀ − J_A B⁻¹ Ḃ B⁻¹ J_Aᵀ + J_A B⁻¹ J̇_Aᵀ) B_A (Problem 7.9)."""
    B, chol = _inertia(B)
    n = B.shape[0]
    Bdot = as_matrix(Bdot, (n, n), "Bdot")
    J = _task_jacobian(J, n)
    Jdot = as_matrix(Jdot, J.shape, "Jdot")
    B_A = operational_space_inertia(B, J)
    BinvJt = cho_solve(chol, J.T)
    inner = Jdot @ BinvJt - BinvJt.T @ Bdot @ BinvJt + BinvJt.T @ Jdot.T
    return -B_A @ inner @ B_A


def minimum_norm_torque(B: Any, J: Any, gamma: Any, tau_a: Any = None) -> np.ndarray:
    """τ minimising ½(τ − τ_a)ᵀ B⁻¹ (τ − τ_a) subject to J̄_Aᵀ τ = γ_A (Problem 7.10).

    Closed form τ = J_Aᵀ γ_A + (I − J_Aᵀ J̄_Aᵀ) τ_a (the Lagrange multipliers of (S7.7)).
    """
    B = np.asarray(B, dtype=float)
    J = _task_jacobian(J, B.shape[0])
    gamma = as_vector(gamma, J.shape[0], "gamma")
    n = J.shape[1]
    tau_a = np.zeros(n) if tau_a is None else as_vector(tau_a, n, "tau_a")
    J_bar = dynamically_consistent_inverse(B, J)
    return J.T @ gamma + (np.eye(n) - J.T @ J_bar.T) @ tau_a


def minimum_norm_torque_qp(B: Any, J: Any, gamma: Any, tau_a: Any = None, eps_abs: float = 1e-12) -> np.ndarray:
    """The torque of :func:`minimum_norm_torque` as an equality-constrained QP solved by proxsuite.

    min ½ τᵀ B⁻¹ τ − τ_aᵀ B⁻¹ τ  s.t.  J̄_Aᵀ τ = γ_A. Raises RuntimeError when the solver fails.
    """
    import proxsuite

    B, chol = _inertia(B)
    n = B.shape[0]
    J = _task_jacobian(J, n)
    gamma = as_vector(gamma, J.shape[0], "gamma")
    tau_a = np.zeros(n) if tau_a is None else as_vector(tau_a, n, "tau_a")
    H = cho_solve(chol, np.eye(n))
    H = 0.5 * (H + H.T)
    A = dynamically_consistent_inverse(B, J).T
    res = proxsuite.proxqp.dense.solve(H, -H @ tau_a, A, gamma, None, None, None, eps_abs=eps_abs,
                                       eps_rel=0.0, verbose=False)
    if res.info.status != proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED:
        raise RuntimeError(f"proxsuite did not solve the minimum-norm torque QP: {res.info.status}")
    return np.asarray(res.x)


def dynamic_manipulability(J: Any, B: Any) -> float:
    """w'(q) = √det(J B⁻¹ B⁻ᵀ Jᵀ) (Problem 7.11); for square J it equals |det J| / det B.

    >>> round(dynamic_manipulability(np.eye(2), np.diag([2.0, 4.0])), 6)
    0.125
    """
    B, chol = _inertia(B)
    J = _task_jacobian(J, B.shape[0])
    return manipulability(cho_solve(chol, J.T).T)


def dynamic_manipulability_ellipsoid(J: Any, B: Any) -> Ellipsoid:
    """The ellipsoid of end-effector accelerations reached with ‖τ‖ = 1, Eq. (7.149).

    Its core is (J B⁻¹ B⁻ᵀ Jᵀ)⁻¹ = J⁻ᵀ Bᵀ B J⁻¹; the axes are the left singular vectors of J B⁻¹
    and the semi-axes its singular values. The centre, J̇ q̇ − J B⁻¹ (C q̇ + g), is not included.
    """
    B, chol = _inertia(B)
    J = _task_jacobian(J, B.shape[0])
    return velocity_ellipsoid(cho_solve(chol, J.T).T)
