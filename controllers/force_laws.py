"""Force control, the closed forms: equilibria and closed-loop dynamics of the laws of Chapter 9.

* :func:`compliance_equilibrium` — the rest of compliance control (PD + gravity) against an elastic
  environment, Eqs. (9.22)–(9.23).
* :func:`inner_position_loop_equilibrium` — the rest of force control with an inner position loop
  (Fig. 9.8) and a proportional force regulator C_F (Problem 9.4).
* :func:`impedance_parameters`, :func:`force_loop_parameters`, :func:`pi_velocity_parameters` — ω_n, ζ
  of one axis of impedance control (free or against a spring), of the force loop of hybrid control
  with an estimated compliance (Eqs. (9.84)–(9.85)), and of the PI velocity loop (9.80).
* :func:`constrained_stiffness` — K' = S_f (S_fᵀ C S_f)⁻¹ S_fᵀ, Eq. (9.70) (= P_f K, Problem 9.6).
* :func:`fit_second_order` — ω_n, ζ measured on a transient from rest (the check of the simulations).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 9.2–9.7, Eqs. (9.20)–(9.23), (9.41), (9.70), (9.77)–(9.85), Figs. 9.8–9.9.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.optimize import least_squares

from rigid_body.validation import as_matrix, as_positive, as_vector


def _square(M: Any, n: int, name: str) -> np.ndarray:
    M = np.asarray(M, dtype=float)
    if M.ndim == 0:
        return float(M) * np.eye(n)
    if M.ndim == 1:
        return np.diag(as_vector(M, n, name))
    return as_matrix(M, (n, n), name)


def compliance_equilibrium(K_P: Any, K: Any, dx_rd: Any) -> tuple[np.ndarray, np.ndarray]:
    """(h_e, dx_{e,d}) at the rest of compliance control: h_e = (I + K K_P⁻¹)⁻¹ K dx_{r,d} (9.22) and
    dx_{e,d} = K_P⁻¹ h_e (9.23), from h_e = K_P dx_{e,d} (9.20) and h_e = K dx_{r,e} (9.21).

    K_P : (m, m) active stiffness (invertible); K : (m, m) environment stiffness (may be singular);
    dx_rd : (m,) displacement of the rest position of the environment w.r.t. the desired frame.
    """
    dx = as_vector(dx_rd, None, "dx_rd")
    m = dx.size
    K_P, K = _square(K_P, m, "K_P"), _square(K, m, "K")
    if np.linalg.cond(K_P) > 1e12:
        raise ValueError("`K_P` must be invertible (an active stiffness in every direction)")
    K_Pinv = np.linalg.inv(K_P)
    h_e = np.linalg.solve(np.eye(m) + K @ K_Pinv, K @ dx)  # Eq. (9.22)
    return h_e, K_Pinv @ h_e                                  # Eq. (9.23)


def inner_position_loop_equilibrium(x_d: Any, x_r: Any, K: Any, C_F: Any, f_d: Any) -> np.ndarray:
    """x_e at the rest of force control with inner position loop (Fig. 9.8), proportional C_F:
    x_e = x_d + C_F (K (x_r − x_e) + f_d) (Problem 9.4), i.e. x_e = (I + C_F K)⁻¹ (x_d + C_F (K x_r + f_d)).

    With integral action in C_F the rest is instead f_e = K (x_e − x_r) = f_d.
    """
    x_d = as_vector(x_d, None, "x_d")
    m = x_d.size
    x_r, f_d = as_vector(x_r, m, "x_r"), as_vector(f_d, m, "f_d")
    K, C_F = _square(K, m, "K"), _square(C_F, m, "C_F")
    return np.linalg.solve(np.eye(m) + C_F @ K, x_d + C_F @ (K @ x_r + f_d))


def impedance_parameters(m_d: float, k_D: float, k_P: float, k_env: float = 0.0) -> tuple[float, float]:
    """ω_n = √((k_P + k)/m_d), ζ = k_D / (2 √(m_d (k_P + k))) of one axis of impedance control,
    m_d ẍ + k_D ẋ + (k_P + k) x = k_P x_d + k x_r (Problem 9.3): k = 0 along a free direction, the
    environment stiffness along a constrained one."""
    m = as_positive(m_d, "m_d")
    k = as_positive(k_P, "k_P") + as_positive(k_env, "k_env", allow_zero=True)
    return float(np.sqrt(k / m)), float(as_positive(k_D, "k_D", allow_zero=True) / (2.0 * np.sqrt(m * k)))


def force_loop_parameters(k_D: float, k_P: float, l_f: float = 1.0) -> tuple[float, float]:
    """ω_n = √(l_f k_P), ζ = k_D / (2 √(l_f k_P)) of the force loop of hybrid force/motion control
    (9.84) on a compliant environment: λ̈ + k_D λ̇ + l_f k_P λ = l_f k_P λ_d, with l_f = ĉ/c the ratio of
    the estimated to the true compliance (the rate λ̇ estimated with the same ĉ, Problem 9.10).
    l_f = 1: the known-stiffness loop λ̈ + k_D λ̇ + k_P λ = k_P λ_d (9.81)."""
    k = as_positive(l_f, "l_f") * as_positive(k_P, "k_P")
    return float(np.sqrt(k)), float(as_positive(k_D, "k_D", allow_zero=True) / (2.0 * np.sqrt(k)))


def pi_velocity_parameters(k_P: float, k_I: float) -> tuple[float, float]:
    """ω_n = √k_I, ζ = k_P / (2 √k_I) of the velocity loop with the PI law (9.80): ν̇ = α_ν gives
    ë + k_P ė + k_I e = 0 for e = ∫(ν_d − ν)."""
    k_I = as_positive(k_I, "k_I")
    return float(np.sqrt(k_I)), float(as_positive(k_P, "k_P", allow_zero=True) / (2.0 * np.sqrt(k_I)))


def constrained_stiffness(S_f: Any, C: Any) -> np.ndarray:
    """K' = S_f (S_fᵀ C S_f)⁻¹ S_fᵀ, Eq. (9.70): the stiffness seen along the force-controlled
    subspace; = P_f K with P_f = S_f S_f† (weight C = K⁻¹), Problem 9.6."""
    S = np.asarray(S_f, dtype=float)
    S = S.reshape(-1, 1) if S.ndim == 1 else S
    C = as_matrix(C, (S.shape[0],) * 2, "C")
    A = S.T @ C @ S
    if np.linalg.cond(A) > 1e12:
        raise ValueError("S_fᵀ C S_f is singular: `C` must see every column of `S_f`")
    return S @ np.linalg.solve(A, S.T)


def second_order_free_response(t: Any, omega_n: float, zeta: float) -> np.ndarray:
    """x(t)/x(0) of ẍ + 2ζω_n ẋ + ω_n² x = 0 from rest (ẋ(0) = 0), any ζ > 0 (ζ ≠ 1 exactly):
    x = (s₂ e^{s₁t} − s₁ e^{s₂t})/(s₂ − s₁), s₁,₂ = −ζω_n ± ω_n √(ζ² − 1)."""
    t = np.asarray(t, dtype=float)
    root = omega_n * np.sqrt(complex(zeta * zeta - 1.0))
    if abs(root) < 1e-9 * omega_n:  # critically damped
        return (1.0 + omega_n * t) * np.exp(-omega_n * t)
    s1, s2 = -zeta * omega_n + root, -zeta * omega_n - root
    return np.real((s2 * np.exp(s1 * t) - s1 * np.exp(s2 * t)) / (s2 - s1))


def fit_second_order(t: Any, y: Any, y_final: float, guess: tuple[float, float] = (5.0, 0.7)) -> tuple[float, float]:
    """(ω_n, ζ) measured on a transient that starts at rest at y(t₀) and settles at ``y_final``:
    the least-squares fit of (y − y_final)/(y(t₀) − y_final) by :func:`second_order_free_response`.

    ValueError when the transient is too small to measure (|y(t₀) − y_final| ≈ 0).
    """
    t = as_vector(t, None, "t")
    y = as_vector(y, t.size, "y")
    amplitude = y[0] - float(y_final)
    if abs(amplitude) < 1e-12 * max(1.0, abs(float(y_final))):
        raise ValueError("`y` has no transient to measure: y(t0) equals y_final")
    z, tau = (y - y_final) / amplitude, t - t[0]

    def residual(p: np.ndarray) -> np.ndarray:
        return second_order_free_response(tau, p[0], p[1]) - z

    fit = least_squares(residual, np.asarray(guess, dtype=float), bounds=([1e-6, 1e-3], [np.inf, 50.0]),
                        xtol=1e-14, ftol=1e-14)
    return float(fit.x[0]), float(fit.x[1])
