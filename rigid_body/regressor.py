"""Linearity in the dynamic parameters: regressors, minimum parameters and identification.

The model B(q) q̈ + C(q, q̇) q̇ + g(q) = τ is linear in suitable parameters, τ = Y(q, q̇, q̈) π
(Eq. 7.81). For the book's two-link planar arm (7.82) the eight parameters of (7.83) reduce to the
five minimum parameters π' of Problem 7.4, and for the prismatic–revolute arm of Problem 7.5 to
three. Least squares on a stacked regressor identifies them (dynamic parameter identification).

Parameter bookkeeping of the two-link arm (``convention``):

* ``"manual"`` (default, the solution manual's (S7.2)/(S7.3)): Ī₁ excludes I_m2, and the I_m2
  column of row 1 is y'₁₅ = ϑ̈₁ + k_r2 ϑ̈₂; with the book's data π'₂ = 97.5.
* ``"companion"`` (the authors' ``param.m``): Ī₁ includes I_m2 (textbook (7.83)), y'₁₅ = k_r2 ϑ̈₂;
  π'₂ = 97.51. Both give the same τ.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Eqs. (7.81)–(7.84) and the parameter identification that follows them; solution manual, Problems 7.4 (S7.2, S7.3) and 7.5.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from rigid_body.dh import G, DHLink, as_links
from rigid_body.validation import as_vector

CONVENTIONS = ("manual", "companion")


def _check_convention(convention: str) -> None:
    if convention not in CONVENTIONS:
        raise ValueError(f"`convention` must be one of {CONVENTIONS}, got {convention!r}")


def _finite(value: float, name: str) -> float:
    return float(as_vector(value, 1, name)[0])


def _zz_inertia(inertia: Any) -> float:
    return 0.0 if inertia is None else float(np.asarray(inertia, dtype=float)[2, 2])


def _motor_zz(link: DHLink) -> float:
    """I_m: the rotor's moment about its spin axis (:attr:`DHLink.rotor_inertia`)."""
    return float(link.rotor_inertia[2, 2])


# --------------------------------------------------------------------------------------------
# Two-link planar arm (Sect. 7.3.2, Problem 7.4)
# --------------------------------------------------------------------------------------------

def two_link_regressor(q: Any, qd: Any, qdd: Any, a: Sequence[float] = (1.0, 1.0), k_r2: float = 100.0,
                       g: float = G, convention: str = "manual") -> np.ndarray:
    """Minimum regressor Y'(q, q̇, q̈), (2, 5), of the two-link planar arm, (S7.3): τ = Y' π'.

    Parameters
    ----------
    q, qd, qdd : (2,) joint positions [rad], velocities [rad/s], accelerations [rad/s²].
    a : link lengths (a1, a2) [m].
    k_r2 : gear ratio of motor 2.
    g : gravity acceleration [m/s²] (gravity along −y₀, links along +x₀ at q = 0).
    convention : ``"manual"`` (y'₁₅ = ϑ̈₁ + k_r2 ϑ̈₂) or ``"companion"`` (y'₁₅ = k_r2 ϑ̈₂).

    >>> Y = two_link_regressor([0.0, 0.0], [0.0, 0.0], [0.0, 0.0])
    >>> Y[:, 0].tolist()
    [9.81, 0.0]
    """
    return two_link_reference_regressor(q, qd, qd, qdd, a=a, k_r2=k_r2, g=g, convention=convention)


def two_link_reference_regressor(q: Any, qd: Any, qd_r: Any, qdd_r: Any, a: Sequence[float] = (1.0, 1.0),
                                 k_r2: float = 100.0, g: float = G, convention: str = "manual") -> np.ndarray:
    """Y'(q, q̇, q̇_r, q̈_r) (2, 5) with Y'π' = B(q) q̈_r + C(q, q̇) q̇_r + g(q) (Christoffel C, (7.45)).

    This is the regressor of the adaptive control law (Problem 8.14). With
    h = −a1 s2 π'₃, the velocity terms of row 1 are −a1 s2 (q̇2 q̇_r1 + (q̇1 + q̇2) q̇_r2) and those of
    row 2 are a1 s2 q̇1 q̇_r1. With q̇_r = q̇ and q̈_r = q̈ it is (S7.3).
    """
    _check_convention(convention)
    q1, q2 = as_vector(q, 2, "q")
    qd1, qd2 = as_vector(qd, 2, "qd")
    qr1, qr2 = as_vector(qd_r, 2, "qd_r")
    ar1, ar2 = as_vector(qdd_r, 2, "qdd_r")
    a1, a2 = as_vector(a, 2, "a")
    k_r2, g = _finite(k_r2, "k_r2"), _finite(g, "g")
    c1, c2, s2, c12 = np.cos(q1), np.cos(q2), np.sin(q2), np.cos(q1 + q2)
    Y = np.zeros((2, 5))
    Y[0, 0] = a1 * ar1 + g * c1
    Y[0, 1] = ar1
    Y[0, 2] = ((2 * a1 * c2 + a2) * ar1 + (a1 * c2 + a2) * ar2 - a1 * s2 * (qd2 * qr1 + (qd1 + qd2) * qr2)
               + g * c12)
    Y[0, 3] = ar1 + ar2
    Y[0, 4] = (ar1 if convention == "manual" else 0.0) + k_r2 * ar2
    Y[1, 2] = a2 * ar2 + (a1 * c2 + a2) * ar1 + a1 * s2 * qd1 * qr1 + g * c12
    Y[1, 3] = ar1 + ar2
    Y[1, 4] = k_r2**2 * ar2 + k_r2 * ar1
    return Y


@dataclass(frozen=True)
class TwoLinkParameters:
    """Augmented-link parameters of the two-link arm, Eq. (7.83), frames at the link tips.

    ``m1 = m_ℓ1 + m_m2``, ``m1_lC1 = m_ℓ1 (ℓ1 − a1)`` (ℓ_Ci < 0), ``I1 = Ī1`` about the origin of frame 1
    (with I_m2 only in the ``companion`` convention), ``m2``, ``m2_lC2``, ``I2``, ``Im1``, ``Im2``,
    the gear ratios and the link lengths.
    """

    a1: float
    a2: float
    m1: float
    m1_lC1: float
    I1: float
    Im1: float
    m2: float
    m2_lC2: float
    I2: float
    Im2: float
    k_r1: float
    k_r2: float


def two_link_parameters(links: Sequence[DHLink | Any], payload: float = 0.0,
                        convention: str = "manual") -> TwoLinkParameters:
    """Augmented-link parameters (7.83) from the DH table of a two-link planar arm with motors.

    ``links`` is the two-row DH table (e.g. ``rigid_body.book_robots.planar_2r().links``); link i's centre of
    mass must lie on the x axis of frame i (planar arm) and ``payload`` is a point mass at the tip.
    """
    _check_convention(convention)
    links = as_links(links)
    if len(links) != 2 or any(l.joint != "revolute" or l.alpha != 0 or l.d != 0 for l in links):
        raise ValueError("`links` must be the DH table of a two-link planar arm (2 revolute, α = d = 0)")
    for i, l in enumerate(links, start=1):
        if abs(l.com[1]) > 1e-12 or abs(l.com[2]) > 1e-12:
            raise ValueError(f"link {i}: the centre of mass must lie on x_{i} for the planar model, got {l.com}")
    if not np.isfinite(payload) or payload < 0:
        raise ValueError(f"`payload` must be a non-negative mass, got {payload!r}")
    l1, l2 = links
    Im2 = _motor_zz(l2)
    I1 = _zz_inertia(l1.inertia) + l1.mass * l1.com[0] ** 2 + (Im2 if convention == "companion" else 0.0)
    return TwoLinkParameters(
        a1=l1.a, a2=l2.a,
        m1=l1.mass + l2.motor_mass, m1_lC1=l1.mass * l1.com[0], I1=I1, Im1=_motor_zz(l1),
        m2=l2.mass + payload, m2_lC2=l2.mass * l2.com[0], I2=_zz_inertia(l2.inertia) + l2.mass * l2.com[0] ** 2,
        Im2=Im2, k_r1=l1.gear_ratio, k_r2=l2.gear_ratio)


def two_link_minimum_parameters(p: TwoLinkParameters) -> np.ndarray:
    """π' (5,) of the two-link arm, (S7.2), from the augmented-link parameters.

    π'₁ = a1 m1 + m1ℓC1 + a1 m2, π'₂ = a1 m1ℓC1 + Ī1 + k_r1² I_m1, π'₃ = a2 m2 + m2ℓC2,
    π'₄ = a2 m2ℓC2 + Ī2, π'₅ = I_m2. A tip payload m_L changes only m2: Δπ'₁ = a1 m_L, Δπ'₃ = a2 m_L.
    """
    return np.array([
        p.a1 * p.m1 + p.m1_lC1 + p.a1 * p.m2,
        p.a1 * p.m1_lC1 + p.I1 + p.k_r1**2 * p.Im1,
        p.a2 * p.m2 + p.m2_lC2,
        p.a2 * p.m2_lC2 + p.I2,
        p.Im2,
    ])


def minimum_parameters(links: Sequence[DHLink | Any], payload: float = 0.0,
                       convention: str = "manual") -> np.ndarray:
    """π' (5,) of a two-link planar arm given its DH table (S7.2); see :func:`two_link_parameters`.

    >>> from rigid_body.book_robots import planar_2r
    >>> minimum_parameters(planar_2r().links).round(4).tolist()
    [80.0, 97.5, 25.0, -2.5, 0.01]
    """
    return two_link_minimum_parameters(two_link_parameters(links, payload, convention))


def two_link_textbook_parameters(p: TwoLinkParameters) -> np.ndarray:
    """The eight parameters of (7.83): [m1, m1ℓC1, Î1, I_m1, m2, m2ℓC2, Î2, I_m2].

    Î1 must include I_m2 (textbook convention): build ``p`` with ``convention="companion"``.
    """
    return np.array([p.m1, p.m1_lC1, p.I1, p.Im1, p.m2, p.m2_lC2, p.I2, p.Im2])


def two_link_textbook_regressor(q: Any, qd: Any, qdd: Any, a: Sequence[float] = (1.0, 1.0),
                                k_r: Sequence[float] = (100.0, 100.0), g: float = G) -> np.ndarray:
    """The (2, 8) regressor of (7.84) for the parameters of :func:`two_link_textbook_parameters`.

    Its columns are linearly dependent: only 5 combinations (S7.2) are identifiable.
    """
    q1, q2 = as_vector(q, 2, "q")
    qd1, qd2 = as_vector(qd, 2, "qd")
    qdd1, qdd2 = as_vector(qdd, 2, "qdd")
    a1, a2 = as_vector(a, 2, "a")
    kr1, kr2 = as_vector(k_r, 2, "k_r")
    g = _finite(g, "g")
    c1, c2, s2, c12 = np.cos(q1), np.cos(q2), np.sin(q2), np.cos(q1 + q2)
    Y = np.zeros((2, 8))
    Y[0] = [a1**2 * qdd1 + a1 * g * c1,
            2 * a1 * qdd1 + g * c1,
            qdd1,
            kr1**2 * qdd1,
            ((a1**2 + 2 * a1 * a2 * c2 + a2**2) * qdd1 + (a1 * a2 * c2 + a2**2) * qdd2 - 2 * a1 * a2 * s2 * qd1 * qd2
             - a1 * a2 * s2 * qd2**2 + a1 * g * c1 + a2 * g * c12),
            ((2 * a1 * c2 + 2 * a2) * qdd1 + (a1 * c2 + 2 * a2) * qdd2 - 2 * a1 * s2 * qd1 * qd2 - a1 * s2 * qd2**2
             + g * c12),
            qdd1 + qdd2,
            kr2 * qdd2]
    Y[1, 4:] = [(a1 * a2 * c2 + a2**2) * qdd1 + a2**2 * qdd2 + a1 * a2 * s2 * qd1**2 + a2 * g * c12,
                (a1 * c2 + 2 * a2) * qdd1 + 2 * a2 * qdd2 + a1 * s2 * qd1**2 + g * c12,
                qdd1 + qdd2,
                kr2 * qdd1 + kr2**2 * qdd2]
    return Y


# --------------------------------------------------------------------------------------------
# Prismatic–revolute arm (Problem 7.5)
# --------------------------------------------------------------------------------------------

def pr_regressor(q: Any, qd: Any, qdd: Any, g: float = G) -> np.ndarray:
    """Minimum regressor Y' (2, 3) of the PR arm of Fig. S7.2 (Problem 7.5): τ = Y' π'.

    y'₁₁ = d̈1, y'₁₂ = c2 ϑ̈2 − s2 ϑ̇2², y'₂₂ = c2 d̈1 + g s2, y'₂₃ = ϑ̈2 (the others are zero).
    """
    _, q2 = as_vector(q, 2, "q")
    _, qd2 = as_vector(qd, 2, "qd")
    qdd1, qdd2 = as_vector(qdd, 2, "qdd")
    g = _finite(g, "g")
    c2, s2 = np.cos(q2), np.sin(q2)
    return np.array([[qdd1, c2 * qdd2 - s2 * qd2**2, 0.0],
                     [0.0, c2 * qdd1 + g * s2, qdd2]])


def pr_minimum_parameters(links: Sequence[DHLink | Any], payload: float = 0.0) -> np.ndarray:
    """π' (3,) of the PR arm from its DH table (``rigid_body.book_robots.planar_pr``) and a tip payload.

    With m'ℓ2 = mℓ2 + m_L, ℓ'2 = (mℓ2 ℓ2 + m_L a2)/m'ℓ2 and I'ℓ2 = Iℓ2 + mℓ2(ℓ'2 − ℓ2)² + m_L(a2 − ℓ'2)²:
    π'₁ = mℓ1 + m_m2 + m'ℓ2 + k_r1² I_m1, π'₂ = m'ℓ2 ℓ'2, π'₃ = I'ℓ2 + m'ℓ2 ℓ'2² + k_r2² I_m2.
    """
    l1, l2 = as_links(links)
    if l1.joint != "prismatic" or l2.joint != "revolute":
        raise ValueError("`links` must be the DH table of a prismatic–revolute arm")
    if not np.isfinite(payload) or payload < 0:
        raise ValueError(f"`payload` must be a non-negative mass, got {payload!r}")
    m2p, ell2p, I2p = payload_link_parameters(l2.mass, l2.a + l2.com[0], _zz_inertia(l2.inertia), l2.a, payload)
    return np.array([
        l1.mass + l2.motor_mass + m2p + l1.gear_ratio**2 * _motor_zz(l1),
        m2p * ell2p,
        I2p + m2p * ell2p**2 + l2.gear_ratio**2 * _motor_zz(l2),
    ])


def payload_link_parameters(mass: float, ell: float, inertia: float, a: float,
                            payload: float) -> tuple[float, float, float]:
    """Link parameters with a point payload m_L at distance ``a`` from the joint (Problem 7.5).

    Returns (m', ℓ', I') with m' = m + m_L, ℓ' = (m ℓ + m_L a)/m' and
    I' = I + m (ℓ' − ℓ)² + m_L (a − ℓ')² (moment about the new centre of mass).
    """
    mass, ell, inertia, a, payload = (_finite(v, name) for v, name in
                                      ((mass, "mass"), (ell, "ell"), (inertia, "inertia"), (a, "a"), (payload, "payload")))
    if mass < 0 or payload < 0 or inertia < 0:
        raise ValueError(f"`mass`, `payload` and `inertia` must be non-negative, got {mass}, {payload}, {inertia}")
    m_new = mass + payload
    if m_new <= 0:
        raise ValueError("the link with its payload must have a positive mass")
    ell_new = (mass * ell + payload * a) / m_new
    return m_new, ell_new, inertia + mass * (ell_new - ell) ** 2 + payload * (a - ell_new) ** 2


# --------------------------------------------------------------------------------------------
# Identification (least squares on a stacked regressor)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Identification:
    """Least-squares estimate of π from stacked measurements Ȳ π = τ̄.

    ``estimate`` (p,), ``residual`` = ‖Ȳ π̂ − τ̄‖/√N (N = number of torque samples),
    ``condition_number`` of the stacked regressor Ȳ, ``rank`` of Ȳ, ``samples`` = number of states.
    """

    estimate: np.ndarray
    residual: float
    condition_number: float
    rank: int
    samples: int


def stack_regressor(regressor: Any, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, **kwargs: Any) -> np.ndarray:
    """Ȳ = [Y(q_1, q̇_1, q̈_1); ...; Y(q_N, ...)] for (N, n) samples."""
    q, qd, qdd = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (q, qd, qdd))
    if not (q.shape == qd.shape == qdd.shape):
        raise ValueError(f"`q`, `qd`, `qdd` must have the same (N, n) shape, got {q.shape}, {qd.shape}, {qdd.shape}")
    return np.vstack([regressor(q[k], qd[k], qdd[k], **kwargs) for k in range(q.shape[0])])


def identify(Y: np.ndarray, tau: np.ndarray) -> Identification:
    """π̂ = (Ȳᵀ Ȳ)⁻¹ Ȳᵀ τ̄ by an SVD least-squares solve of the stacked regressor.

    Parameters
    ----------
    Y : (N·n, p) stacked regressor; tau : (N, n) or (N·n,) measured torques.

    Raises
    ------
    ValueError : when Ȳ is rank-deficient (the trajectory is not exciting enough).
    """
    Y = np.asarray(Y, dtype=float)
    tau = np.asarray(tau, dtype=float).reshape(-1)
    if Y.ndim != 2 or Y.shape[0] != tau.size:
        raise ValueError(f"`Y` must be (N·n, p) with N·n = {tau.size} rows, got {Y.shape}")
    if not (np.all(np.isfinite(Y)) and np.all(np.isfinite(tau))):
        raise ValueError("`Y` and `tau` must be finite")
    sv = np.linalg.svd(Y, compute_uv=False)
    rank = int(np.sum(sv > sv[0] * max(Y.shape) * np.finfo(float).eps))
    if rank < Y.shape[1]:
        raise ValueError(f"the stacked regressor has rank {rank} < {Y.shape[1]} parameters: "
                         "the trajectory is not exciting enough")
    estimate, *_ = np.linalg.lstsq(Y, tau, rcond=None)
    residual = float(np.linalg.norm(Y @ estimate - tau) / np.sqrt(tau.size))
    return Identification(estimate=estimate, residual=residual, condition_number=float(sv[0] / sv[-1]),
                          rank=rank, samples=tau.size)
