"""The book's recursive Newton–Euler algorithm with motors, in the DH link frames (Sect. 7.5).

Every vector of link i is expressed in DH frame i, as in (7.107)–(7.114). Link i is the *augmented*
link: link i, rotor i+1 (carried by link i at the origin of frame i, spin axis z_i) and, for i = n,
the payload. The rotor's spin adds the terms k_r,i+1 q̈_{i+1} I_m,i+1 z_m,i+1 and
k_r,i+1 q̇_{i+1} I_m,i+1 ω_i × z_m,i+1 to the moment balance (7.112) and k_ri I_mi ω̇_miᵀ z_mi to the
joint torque (7.113)/(7.114). Gravity enters through the initial condition p̈₀ − g₀ (7.107).

This module does not use Pinocchio. It is a second independent reference, besides
:mod:`rigid_body.lagrange`. The data come from :func:`rigid_body.lagrange.serial_model`.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Eqs. (7.107)–(7.114); solution manual, Problem 7.8.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rigid_body.lagrange import SerialModel
from rigid_body.validation import as_vector

EZ = np.array([0.0, 0.0, 1.0])


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b for 3-vectors (several times faster than ``np.cross`` on single vectors)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


@dataclass(frozen=True)
class AugmentedLink:
    """Augmented link i in frame i: mass m_i, com r^i_{i,Ci} (3,), inertia Ī_i (3, 3) about the com.

    Rotor i+1 (at the origin of frame i) and, for the last link, the payload are included rigidly;
    ``rotor_axial`` I_m,i+1 gives the spin terms of (7.112). (For an axisymmetric rotor the
    transverse moment adds I_t k_r q̇ (ω×z) through I ω̇_m and removes it through the rotation of the
    tensor, so (7.112) is exact for diag(I_t, I_t, I_m) too.)
    """

    mass: float
    com: np.ndarray
    inertia: np.ndarray
    rotor_axial: float


def augmented_links(model: SerialModel) -> list[AugmentedLink]:
    """The augmented links 1..n of (7.107)–(7.114): link i + rotor i+1 (+ payload on link n)."""
    n = model.n
    out = []
    for i in range(n):
        parts = [(model.mass[i], model.com[i], model.inertia[i])]
        Im = np.zeros((3, 3))
        if i + 1 < n:
            Im = model.motor_inertia[i + 1]
            parts.append((model.motor_mass[i + 1], np.zeros(3), Im))
        if i == n - 1 and model.payload > 0:
            parts.append((model.payload, np.zeros(3), np.zeros((3, 3))))
        m = sum(p[0] for p in parts)
        com = sum(p[0] * p[1] for p in parts) / m if m > 0 else np.zeros(3)
        I = np.zeros((3, 3))
        for mk, ck, Ik in parts:  # parallel-axis (Steiner) theorem about the augmented com
            r = ck - com
            I += Ik + mk * (r @ r * np.eye(3) - np.outer(r, r))
        out.append(AugmentedLink(m, com, I, Im[2, 2]))
    return out


@dataclass(frozen=True)
class NewtonEulerResult:
    """Joint torques and the recursion's intermediate quantities, each in its link frame (index i−1).

    ``omega``, ``omega_dot``, ``p_ddot``, ``pc_ddot`` (n, 3): ω^i_i, ω̇^i_i, p̈^i_i, p̈^i_Ci;
    ``omega_dot_m`` (n, 3): ω̇^{i−1}_{mi}; ``f``, ``mu`` (n, 3): f^i_i, μ^i_i; ``tau`` (n,).
    """

    tau: np.ndarray
    omega: np.ndarray
    omega_dot: np.ndarray
    p_ddot: np.ndarray
    pc_ddot: np.ndarray
    omega_dot_m: np.ndarray
    f: np.ndarray
    mu: np.ndarray


def newton_euler(model: SerialModel, q: Any, qd: Any, qdd: Any, f_tip: Any = None, mu_tip: Any = None,
                 gravity: bool = True) -> NewtonEulerResult:
    """Recursive Newton–Euler (7.107)–(7.114) with motors; all quantities in the DH link frames.

    Parameters
    ----------
    model : from :func:`rigid_body.lagrange.serial_model`.
    q, qd, qdd : (n,) joint positions, velocities, accelerations.
    f_tip, mu_tip : optional force and moment (3,) exerted by the end effector on the environment,
        in frame 0 (the moment about the origin of frame n); they enter as f_{n+1}, μ_{n+1}.
    gravity : include g₀ through p̈₀ − g₀ (set False for C q̇ + B q̈ only).
    """
    n = model.n
    q = as_vector(q, n, "q")
    qd = as_vector(qd, n, "qd")
    qdd = as_vector(qdd, n, "qdd")
    links = augmented_links(model)
    # Relative rotations R^{i-1}_i and r^i_{i-1,i} from the DH transforms (2.52).
    R = np.empty((n, 3, 3))
    r = np.empty((n, 3))
    for i, (link, qi) in enumerate(zip(model.links, q)):
        A = link.transform(qi)
        R[i] = A[:3, :3]
        r[i] = A[:3, :3].T @ A[:3, 3]
    kr = model.gear_ratio
    Im = model.motor_inertia[:, 2, 2]

    omega = np.zeros((n, 3))
    omega_dot = np.zeros((n, 3))
    p_ddot = np.zeros((n, 3))
    pc_ddot = np.zeros((n, 3))
    omega_dot_m = np.zeros((n, 3))
    w, wd = np.zeros(3), np.zeros(3)  # ω_0, ω̇_0
    a = -model.gravity if gravity else np.zeros(3)  # p̈_0 − g_0, Eq. (7.107)
    for i in range(n):
        Rt = R[i].T
        # Rotor i on link i-1, Eq. (7.108) for the motor: ω̇^{i-1}_{mi}.
        omega_dot_m[i] = wd + kr[i] * qdd[i] * EZ + kr[i] * qd[i] * _cross(w, EZ)
        if model.revolute[i]:
            w_new = Rt @ (w + qd[i] * EZ)  # (7.107)
            wd_new = Rt @ (wd + qdd[i] * EZ + qd[i] * _cross(w, EZ))  # (7.108)
            a_new = Rt @ a + _cross(wd_new, r[i]) + _cross(w_new, _cross(w_new, r[i]))  # (7.109)
        else:
            w_new = Rt @ w
            wd_new = Rt @ wd
            a_new = (Rt @ (a + qdd[i] * EZ) + 2.0 * qd[i] * _cross(w_new, Rt @ EZ)
                     + _cross(wd_new, r[i]) + _cross(w_new, _cross(w_new, r[i])))
        rc = links[i].com
        pc_ddot[i] = a_new + _cross(wd_new, rc) + _cross(w_new, _cross(w_new, rc))  # (7.110)
        omega[i], omega_dot[i], p_ddot[i] = w_new, wd_new, a_new
        w, wd, a = w_new, wd_new, a_new

    f = np.zeros((n, 3))
    mu = np.zeros((n, 3))
    tau = np.zeros(n)
    Rn = np.eye(3)  # R^0_n, to bring the tip force and moment into frame n
    if f_tip is not None or mu_tip is not None:
        for Ri in R:
            Rn = Rn @ Ri
    f_next = np.zeros(3) if f_tip is None else Rn.T @ as_vector(f_tip, 3, "f_tip")  # in frame n+1 = n
    mu_next = np.zeros(3) if mu_tip is None else Rn.T @ as_vector(mu_tip, 3, "mu_tip")
    R_next = np.eye(3)
    for i in range(n - 1, -1, -1):
        L = links[i]
        w, wd, rc = omega[i], omega_dot[i], L.com
        Rf = R_next @ f_next
        f[i] = Rf + L.mass * pc_ddot[i]  # (7.111)
        m_i = (-_cross(f[i], r[i] + rc) + R_next @ mu_next + _cross(Rf, rc)
               + L.inertia @ wd + _cross(w, L.inertia @ w))  # (7.112)
        if i + 1 < n:  # spin of rotor i+1 carried by link i
            m_i += (kr[i + 1] * qdd[i + 1] * L.rotor_axial * EZ
                    + kr[i + 1] * qd[i + 1] * L.rotor_axial * _cross(w, EZ))
        mu[i] = m_i
        z_prev = R[i].T @ EZ  # z_{i-1} in frame i
        tau[i] = (m_i if model.revolute[i] else f[i]) @ z_prev + kr[i] * Im[i] * omega_dot_m[i] @ EZ  # (7.113)/(7.114)
        f_next, mu_next, R_next = f[i], mu[i], R[i]
    return NewtonEulerResult(tau, omega, omega_dot, p_ddot, pc_ddot, omega_dot_m, f, mu)


def inverse_dynamics(model: SerialModel, q: Any, qd: Any, qdd: Any, f_tip: Any = None,
                     mu_tip: Any = None) -> np.ndarray:
    """τ (n,) by the recursive Newton–Euler algorithm (7.107)–(7.114); see :func:`newton_euler`.

    >>> from rigid_body.lagrange import serial_model
    >>> from rigid_body.book_robots import planar_2r
    >>> inverse_dynamics(serial_model(planar_2r()), [0, 0], [0, 0], [0, 0]).round(4).tolist()  # g(q), (7.82)
    [1030.05, 245.25]
    """
    return newton_euler(model, q, qd, qdd, f_tip, mu_tip).tau
