"""The book's Lagrange formulation for any serial DH arm with motors (Ch. 7).

This module computes the dynamic model straight from the DH table, link inertial data and motor
data with the formulas of the book. It does not use Pinocchio, so it is an independent reference
for ``rigid_body.dynamics`` (CRBA, Christoffel C, RNEA).

* B(q) = Σᵢ m_ℓi J_P^(ℓi)ᵀ J_P^(ℓi) + J_O^(ℓi)ᵀ Rᵢ I_ℓi Rᵢᵀ J_O^(ℓi)
  + m_mi J_P^(mi)ᵀ J_P^(mi) + J_O^(mi)ᵀ R_mi I_mi R_miᵀ J_O^(mi), Eq. (7.32). The link
  Jacobians are (7.16)–(7.19) and the motor Jacobians (7.25)–(7.29): rotor i is carried by link i−1,
  sits at the origin of frame i−1 and spins about z_{i−1} at k_ri q̇ᵢ. A payload is a point mass at
  the origin of frame n.
* ∂B/∂q_k is computed analytically, without finite differences. For a body whose Jacobian columns
  are J_Pj and J_Oj, ∂J_Pj/∂q_k = J_O,min(j,k) × J_P,max(j,k), ∂J_Oj/∂q_k = J_Ok × J_Oj for k < j
  (0 otherwise), and ∂(R I Rᵀ)/∂q_k = S(J_Ok) R I Rᵀ − R I Rᵀ S(J_Ok).
* C(q, q̇) uses the Christoffel symbols c_ijk = ½(∂b_ij/∂q_k + ∂b_ik/∂q_j − ∂b_jk/∂q_i), Eq. (7.45).
  Ḃ − 2C is then skew-symmetric (7.48). :func:`alternative_coriolis_matrix` is the C of
  Problem 7.2, which is not.
* g(q) = −Σ (m_ℓi g₀ᵀ J_P^(ℓi) + m_mi g₀ᵀ J_P^(mi)), Eq. (7.39).

Rotors must be axisymmetric about their spin axis, as in the book: either a scalar I_m, meaning
diag(0, 0, I_m), or a 3×3 tensor diag(I_t, I_t, I_m). Then B does not depend on the rotor angle.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Eqs. (7.16)–(7.19), (7.25)–(7.32), (7.39), (7.41)–(7.48).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rigid_body.dh import GRAVITY, DHLink, as_links
from rigid_body.validation import as_vector


@dataclass(frozen=True)
class SerialModel:
    """A serial DH arm's dynamic data in the book's notation (built by :func:`serial_model`).

    ``links`` the DH table; ``gravity`` g₀ (3,) in frame 0; ``payload`` point mass at the origin of
    frame n. Arrays per link i = 1..n (index i−1): ``mass`` m_ℓi, ``com`` (n, 3) in frame i,
    ``inertia`` (n, 3, 3) about the com in frame i, ``revolute`` (n,) bool, ``motor_mass`` m_mi,
    ``motor_inertia`` (n, 3, 3) in the rotor frame (z = spin axis), ``gear_ratio`` k_ri.
    """

    links: tuple[DHLink, ...]
    gravity: np.ndarray
    payload: float
    mass: np.ndarray
    com: np.ndarray
    inertia: np.ndarray
    revolute: np.ndarray
    motor_mass: np.ndarray
    motor_inertia: np.ndarray
    gear_ratio: np.ndarray

    @property
    def n(self) -> int:
        return len(self.links)


def _rotor_tensor(link: DHLink, i: int) -> np.ndarray:
    """The rotor's inertia (:attr:`DHLink.rotor_inertia`), which this formulation needs axisymmetric."""
    Im = link.rotor_inertia
    axisym = np.diag([Im[0, 0], Im[0, 0], Im[2, 2]])
    if not np.allclose(Im, axisym, atol=1e-12 * max(1.0, np.abs(Im).max())):
        raise ValueError(f"link {i}: the rotor inertia must be axisymmetric about its spin axis z, "
                         f"diag(I_t, I_t, I_m); got {Im.tolist()}")
    return axisym


def serial_model(links: Any, gravity: Any = None, payload: float | None = None) -> SerialModel:
    """Collect a DH table's inertial and motor data for :mod:`lagrange` and :mod:`newton_euler`.

    Parameters
    ----------
    links : a DH table (sequence of :class:`~rigid_body.dh.DHLink` or dicts) or a
        ``rigid_body.book_robots.BookRobot`` (its links, gravity and payload are used).
    gravity : g₀ (3,) [m/s²] in frame 0; default the book robot's, else (0, 0, −9.81).
    payload : point mass [kg] at the origin of frame n; default the book robot's, else 0.
    """
    if hasattr(links, "links") and hasattr(links, "gravity"):
        gravity = links.gravity if gravity is None else gravity
        payload = links.payload if payload is None else payload
        links = links.links
    links = tuple(as_links(links))
    gravity = as_vector(GRAVITY if gravity is None else gravity, 3, "gravity")
    payload = 0.0 if payload is None else float(payload)
    if not np.isfinite(payload) or payload < 0:
        raise ValueError(f"`payload` must be a non-negative mass, got {payload!r}")
    n = len(links)
    inertia = np.zeros((n, 3, 3))
    for i, l in enumerate(links):
        if l.inertia is not None:
            inertia[i] = np.asarray(l.inertia, dtype=float)
    return SerialModel(
        links=links, gravity=gravity, payload=payload,
        mass=np.array([l.mass for l in links]), com=np.array([l.com for l in links], dtype=float),
        inertia=inertia, revolute=np.array([l.joint == "revolute" for l in links]),
        motor_mass=np.array([l.motor_mass if l.has_motor else 0.0 for l in links]),
        motor_inertia=np.array([_rotor_tensor(l, i + 1) for i, l in enumerate(links)]),
        gear_ratio=np.array([l.gear_ratio if l.has_motor else 0.0 for l in links]))


def frames(model: SerialModel, q: Any) -> tuple[np.ndarray, np.ndarray]:
    """Rotations R_i (n+1, 3, 3) and origins o_i (n+1, 3) of the DH frames 0..n in frame 0 (2.52)."""
    q = as_vector(q, model.n, "q")
    R = np.empty((model.n + 1, 3, 3))
    o = np.empty((model.n + 1, 3))
    T = np.eye(4)
    R[0], o[0] = T[:3, :3], T[:3, 3]
    for i, (link, qi) in enumerate(zip(model.links, q), start=1):
        T = T @ link.transform(qi)
        R[i], o[i] = T[:3, :3], T[:3, 3]
    return R, o


@dataclass(frozen=True)
class Body:
    """One rigid body of the Lagrange model at a configuration: a link, a rotor or the payload.

    ``name`` ("link_i", "motor_i", "payload"), ``mass``, ``inertia`` (3, 3) about its com in frame 0,
    ``J_P``, ``J_O`` (3, n): the Jacobians of its centre of mass, Eqs. (7.16)–(7.19), (7.25)–(7.29).
    """

    name: str
    mass: float
    inertia: np.ndarray
    J_P: np.ndarray
    J_O: np.ndarray


def body_jacobians(model: SerialModel, q: Any) -> list[Body]:
    """Every body of the arm with its com Jacobians (7.16)–(7.19) and (7.25)–(7.29) at q.

    Bodies with zero mass and inertia are omitted.
    """
    R, o = frames(model, q)
    n = model.n
    z = R[:n, :, 2]  # z_{j-1}, j = 1..n, as rows
    axes_O = z * model.revolute[:, None]  # J_O columns of a body moved by joint j (as rows)

    def jacobians(p: np.ndarray, last: int) -> tuple[np.ndarray, np.ndarray]:
        JP = np.zeros((n, 3))
        JO = np.zeros((n, 3))
        if last > 0:
            rev = model.revolute[:last, None]
            JP[:last] = np.where(rev, np.cross(z[:last], p - o[:last]), z[:last])
            JO[:last] = axes_O[:last]
        return JP, JO

    bodies = []
    for i in range(1, n + 1):
        m, I = model.mass[i - 1], model.inertia[i - 1]
        if m > 0 or np.any(I):
            p = o[i] + R[i] @ model.com[i - 1]
            JP, JO = jacobians(p, i)
            bodies.append(Body(f"link_{i}", m, R[i] @ I @ R[i].T, JP.T, JO.T))
        mm, Im = model.motor_mass[i - 1], model.motor_inertia[i - 1]
        if mm > 0 or np.any(Im):
            JP, JO = jacobians(o[i - 1], i - 1)  # carried by link i-1, at the origin of frame i-1
            JO[i - 1] = model.gear_ratio[i - 1] * z[i - 1]  # Eq. (7.29): column i = k_ri z_{m_i}
            bodies.append(Body(f"motor_{i}", mm, R[i - 1] @ Im @ R[i - 1].T, JP.T, JO.T))
    if model.payload > 0:
        JP, JO = jacobians(o[n], n)
        bodies.append(Body("payload", model.payload, np.zeros((3, 3)), JP.T, JO.T))
    return bodies


def inertia_matrix(model: SerialModel, q: Any) -> np.ndarray:
    """B(q) (n, n), Eq. (7.32), from the link and motor Jacobians.

    >>> from rigid_body.book_robots import planar_2r
    >>> inertia_matrix(serial_model(planar_2r()), [0.0, 0.0]).round(4).tolist()   # Sect. 7.3.2 arm
    [[250.01, 48.5], [48.5, 122.5]]
    """
    B = np.zeros((model.n, model.n))
    for b in body_jacobians(model, q):
        B += b.mass * b.J_P.T @ b.J_P + b.J_O.T @ b.inertia @ b.J_O
    return B


def _skew_rows(v: np.ndarray) -> np.ndarray:
    """S(v_k) for each row v_k of v (n, 3) → (n, 3, 3)."""
    S = np.zeros(v.shape[:-1] + (3, 3))
    S[..., 0, 1], S[..., 0, 2], S[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    S[..., 1, 0], S[..., 2, 0], S[..., 2, 1] = v[..., 2], -v[..., 1], v[..., 0]
    return S


def inertia_matrix_derivatives(model: SerialModel, q: Any) -> np.ndarray:
    """∂B/∂q_k for k = 1..n, as an (n, n, n) array D with D[k] = ∂B/∂q_k (analytic).

    Uses ∂J_Pj/∂q_k = J_O,min(j,k) × J_P,max(j,k), ∂J_Oj/∂q_k = J_Ok × J_Oj (k < j) and
    ∂(R I Rᵀ)/∂q_k = S(J_Ok) R I Rᵀ − R I Rᵀ S(J_Ok) for every body of (7.32).
    """
    n = model.n
    idx = np.arange(n)
    lo = np.minimum.outer(idx, idx)  # [k, j] -> min(j, k)
    hi = np.maximum.outer(idx, idx)
    upper = idx[:, None] < idx[None, :]  # k < j
    D = np.zeros((n, n, n))
    for b in body_jacobians(model, q):
        JP, JO, I = b.J_P.T, b.J_O.T, b.inertia  # columns as rows (n, 3)
        dJP = np.cross(JO[lo], JP[hi])  # [k, j, :] = ∂J_Pj/∂q_k
        dJO = np.cross(JO[:, None, :], JO[None, :, :]) * upper[..., None]
        SJ = _skew_rows(JO)
        dI = SJ @ I - I @ SJ  # [k] = ∂I/∂q_k
        if b.mass:
            t = b.mass * np.einsum("kja,al->kjl", dJP, JP.T)
            D += t + t.transpose(0, 2, 1)
        t = np.einsum("kja,ab,lb->kjl", dJO, I, JO)
        D += t + t.transpose(0, 2, 1) + np.einsum("ja,kab,lb->kjl", JO, dI, JO)
    return D


def christoffel_symbols(model: SerialModel, q: Any) -> np.ndarray:
    """c_ijk = ½(∂b_ij/∂q_k + ∂b_ik/∂q_j − ∂b_jk/∂q_i), (n, n, n) indexed [i, j, k], Eq. (7.45)."""
    D = inertia_matrix_derivatives(model, q)  # D[k, i, j] = ∂b_ij/∂q_k
    return 0.5 * (D.transpose(1, 2, 0) + D.transpose(1, 0, 2) - D)


def coriolis_matrix(model: SerialModel, q: Any, qd: Any) -> np.ndarray:
    """C(q, q̇) with c_ij = Σ_k c_ijk q̇_k (Christoffel symbols, Eq. 7.45)."""
    qd = as_vector(qd, model.n, "qd")
    return christoffel_symbols(model, q) @ qd


def alternative_coriolis_matrix(model: SerialModel, q: Any, qd: Any) -> np.ndarray:
    """The C of Problem 7.2: c_ij = Σ_k (∂b_ij/∂q_k − ½ ∂b_jk/∂q_i) q̇_k.

    It gives the same C q̇ as (7.45), so it satisfies (7.43) and q̇ᵀ(Ḃ − 2C)q̇ = 0 (7.49), but
    Ḃ − 2C is not skew-symmetric in general.
    """
    qd = as_vector(qd, model.n, "qd")
    D = inertia_matrix_derivatives(model, q)
    return np.einsum("kij,k->ij", D, qd) - 0.5 * np.einsum("ijk,k->ij", D, qd)


def inertia_matrix_rate(model: SerialModel, q: Any, qd: Any) -> np.ndarray:
    """Ḃ(q, q̇) = Σ_k ∂B/∂q_k q̇_k."""
    qd = as_vector(qd, model.n, "qd")
    return np.einsum("kij,k->ij", inertia_matrix_derivatives(model, q), qd)


def gravity_torques(model: SerialModel, q: Any) -> np.ndarray:
    """g(q) = −Σ m g₀ᵀ J_P over links, rotors and payload, Eq. (7.39)."""
    g = np.zeros(model.n)
    for b in body_jacobians(model, q):
        g -= b.mass * (model.gravity @ b.J_P)
    return g


def inverse_dynamics(model: SerialModel, q: Any, qd: Any, qdd: Any) -> np.ndarray:
    """τ = B(q) q̈ + C(q, q̇) q̇ + g(q), Eq. (7.42) without friction and contact forces."""
    qd = as_vector(qd, model.n, "qd")
    qdd = as_vector(qdd, model.n, "qdd")
    return inertia_matrix(model, q) @ qdd + coriolis_matrix(model, q, qd) @ qd + gravity_torques(model, q)


def _point_jacobian(model: SerialModel, R: np.ndarray, o: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """J_P, J_O as rows (n, 3) for a point p attached to link n."""
    z = R[:model.n, :, 2]
    rev = model.revolute[:, None]
    return np.where(rev, np.cross(z, p - o[:model.n]), z), z * rev


def geometric_jacobian(model: SerialModel, q: Any, tool: Any = None) -> np.ndarray:
    """J = [J_P; J_O] (6, n) of the origin of frame n (or of ``tool`` (3,), a point in frame n), Eq. (3.30)."""
    R, o = frames(model, q)
    p = o[-1] if tool is None else o[-1] + R[-1] @ as_vector(tool, 3, "tool")
    JP, JO = _point_jacobian(model, R, o, p)
    return np.vstack([JP.T, JO.T])


def geometric_jacobian_rate(model: SerialModel, q: Any, qd: Any, tool: Any = None) -> np.ndarray:
    """J̇(q, q̇) (6, n) = Σ_k ∂J/∂q_k q̇_k, with the column derivatives used for (7.32) above."""
    qd = as_vector(qd, model.n, "qd")
    R, o = frames(model, q)
    p = o[-1] if tool is None else o[-1] + R[-1] @ as_vector(tool, 3, "tool")
    JP, JO = _point_jacobian(model, R, o, p)
    idx = np.arange(model.n)
    lo, hi = np.minimum.outer(idx, idx), np.maximum.outer(idx, idx)
    dJP = np.cross(JO[lo], JP[hi])  # [k, j]
    dJO = np.cross(JO[:, None, :], JO[None, :, :]) * (idx[:, None] < idx[None, :])[..., None]
    return np.vstack([np.einsum("kja,k->aj", dJP, qd), np.einsum("kja,k->aj", dJO, qd)])
