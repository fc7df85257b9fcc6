"""Orientation: elementary rotations, Euler angles, axis–angle, unit quaternion, skew S(·).

Conventions (the book's):

* ``R`` is a (3, 3) rotation matrix R^0_1 whose columns are the unit vectors of frame 1 in frame 0;
* Euler ZYZ (2.18) ``R = Rz(φ) Ry(θ) Rz(ψ)`` and ZXZ ``R = Rz(φ) Rx(θ) Rz(ψ)``, angles ``[φ, θ, ψ]``;
  ``branch=+1`` picks θ ∈ (0, π) (Eq. (2.19)), ``branch=-1`` θ ∈ (−π, 0) (Eq. (2.20));
* Roll–pitch–yaw (2.21) ``R = Rz(φ) Ry(θ) Rx(ψ)``, angles ``[φ, θ, ψ]``; ``branch=+1`` picks
  θ ∈ (−π/2, π/2) (Eq. (2.22)), ``branch=-1`` θ ∈ (π/2, 3π/2) (returned wrapped into (−π, π]);
  the peers' other orders ``"xyz"`` (Rx Ry Rz) and ``"yxz"`` (Ry Rx Rz) through ``order=``;
* unit quaternion ``Q = [η, εx, εy, εz]``, scalar first, as the book's ``{η, ε}`` (Pinocchio's
  ``pin.Quaternion`` coefficients are ``[x, y, z, w]``: mind the order where the two meet);
* homogeneous transform ``T = [[R, o], [0, 1]]`` (2.42).

The exponential coordinates of SO(3) and SE(3) (``exp3``/``log3``, twists, screws) live in
:mod:`rigid_body.se3`; the projection of a nearly orthogonal matrix onto SO(3) is here.

Every function validates its input: wrong shape, non-finite entries, a matrix that is not a rotation
(orthonormal, det +1, within ``ORTHONORMAL_TOL``) or a quaternion that is not unit norm raise a
ValueError naming the argument.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 2.2–2.7, Eqs. (2.5)–(2.45).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from rigid_body.validation import as_matrix, as_scalar, as_tolerance, as_vector

ORTHONORMAL_TOL = 1e-6  # max |R^T R − I| accepted as a rotation; also |‖Q‖ − 1| for quaternions
SINGULAR_TOL = 1e-12  # |sin θ| (ZYZ, ZXZ) or |cos θ| (RPY) below which Euler angles are singular


# --------------------------------------------------------------------------------------------
# Validation
# --------------------------------------------------------------------------------------------

_EYE3 = np.eye(3)


def as_rotation(R: Any, name: str = "R", tol: float = ORTHONORMAL_TOL) -> np.ndarray:
    """``R`` as a (3, 3) rotation matrix: orthonormal and det +1 within ``tol`` (in (0, 1e-3]), else ValueError."""
    if tol is not ORTHONORMAL_TOL:
        tol = as_tolerance(tol)
    if type(R) is not np.ndarray or R.shape != (3, 3) or R.dtype != np.float64:
        R = as_matrix(R, (3, 3), name)
    err = np.abs(R.T @ R - _EYE3).max()
    if not err <= tol:  # also catches NaN
        if not np.isfinite(R).all():
            raise ValueError(f"`{name}` must be finite")
        raise ValueError(f"`{name}` is not orthonormal: max |R^T R - I| = {err:.3g} > {tol:g}")
    (r11, r12, r13), (r21, r22, r23), (r31, r32, r33) = R.tolist()
    if r11 * (r22 * r33 - r23 * r32) - r12 * (r21 * r33 - r23 * r31) + r13 * (r21 * r32 - r22 * r31) < 0:
        raise ValueError(f"`{name}` has determinant -1: a reflection, not a rotation")
    return R


def as_unit_quaternion(Q: Any, name: str = "Q", tol: float = ORTHONORMAL_TOL) -> np.ndarray:
    """``Q`` as a (4,) unit quaternion [η, εx, εy, εz]; ValueError unless |‖Q‖ − 1| ≤ ``tol`` (in (0, 1e-3])."""
    if tol is not ORTHONORMAL_TOL:
        tol = as_tolerance(tol)
    Q = as_vector(Q, 4, name)
    norm = np.linalg.norm(Q)
    if abs(norm - 1.0) > tol:
        raise ValueError(f"`{name}` must be a unit quaternion [eta, eps_x, eps_y, eps_z], got norm {norm:.6g}")
    return Q


def as_homogeneous(T: Any, name: str = "T", tol: float = ORTHONORMAL_TOL) -> np.ndarray:
    """``T`` as a (4, 4) homogeneous transform [[R, o], [0, 1]] (2.42); ValueError otherwise."""
    if tol is not ORTHONORMAL_TOL:
        tol = as_tolerance(tol)
    T = as_matrix(T, (4, 4), name)
    if np.max(np.abs(T[3] - [0.0, 0.0, 0.0, 1.0])) > tol:
        raise ValueError(f"`{name}` must have last row [0, 0, 0, 1], got {T[3]}")
    as_rotation(T[:3, :3], f"{name}[:3, :3]", tol)
    return T


def as_homogeneous_batch(T: Any, name: str = "T", tol: float = ORTHONORMAL_TOL) -> np.ndarray:
    """``T`` as m homogeneous transforms (m, 4, 4), checked at once as :func:`as_homogeneous` checks one: finite,
    last rows [0, 0, 0, 1], rotation blocks (orthonormal within ``tol``, det +1); ValueError naming ``name``."""
    T = np.asarray(T, dtype=float) if not isinstance(T, np.ndarray) or T.dtype != float else T
    if T.ndim != 3 or T.shape[1:] != (4, 4) or not np.all(np.isfinite(T)):
        raise ValueError(f"`{name}` must be finite (4, 4) homogeneous transforms, got shape {T.shape}")
    R = T[:, :3, :3]
    if (np.max(np.abs(T[:, 3] - [0.0, 0.0, 0.0, 1.0]), initial=0.0) > tol
            or np.max(np.abs(R @ np.transpose(R, (0, 2, 1)) - np.eye(3)), initial=0.0) > tol
            or np.any(np.linalg.det(R) < 0)):
        raise ValueError(f"`{name}` must hold homogeneous transforms (rotation block, last row [0, 0, 0, 1])")
    return T


_scalar = as_scalar  # a finite float, ValueError naming the argument


def _singular_tol(tol: float) -> float:
    """The Euler singularity tolerance, checked: in (0, 1e-3] (a larger one returns angles that do not
    reproduce R, a non-positive one misses the exact singular set)."""
    return tol if tol is SINGULAR_TOL else as_tolerance(tol)


def _branch(branch: int) -> int:
    if branch not in (1, -1):
        raise ValueError(f"`branch` must be +1 or -1, got {branch!r}")
    return branch


# --------------------------------------------------------------------------------------------
# Elementary rotations and the skew-symmetric operator
# --------------------------------------------------------------------------------------------

def rot_x(a: float) -> np.ndarray:
    """Rx(γ): elementary rotation about x, Eq. (2.8)."""
    a = _scalar(a, "a")
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(a: float) -> np.ndarray:
    """Ry(β): elementary rotation about y, Eq. (2.7)."""
    a = _scalar(a, "a")
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(a: float) -> np.ndarray:
    """Rz(α): elementary rotation about z, Eq. (2.6)."""
    a = _scalar(a, "a")
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def skew(v: Any) -> np.ndarray:
    """S(v): the skew-symmetric matrix with S(v) p = v × p, Eq. (3.9)."""
    x, y, z = as_vector(v, 3, "v")
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def vee(S: Any) -> np.ndarray:
    """The vector v of a skew-symmetric S = S(v) (the inverse of :func:`skew`; antisymmetric part used)."""
    S = as_matrix(S, (3, 3), "S")
    return 0.5 * np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]])


# --------------------------------------------------------------------------------------------
# Euler angles: ZYZ (2.18)–(2.20), ZXZ, roll–pitch–yaw (2.21)–(2.23)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class EulerResult:
    """Euler angles ``[φ, θ, ψ]`` of a rotation and whether R lies in the representation's singular set.

    When ``singular`` is True only a combination of φ and ψ is determined (φ ± ψ); ``angles`` is
    then the representative with ψ = 0 and θ on the singular set, which reproduces R within the
    singularity tolerance (R is within ``tol`` of the singular set). Away from it the angles
    reproduce R to machine precision: ψ is taken from the residual rotation (R_a(φ) R_b(θ))^T R,
    which equals the book's Atan2 formula and stays exact close to the singular set.
    """

    angles: np.ndarray
    singular: bool


_ELEMENTARY = {"x": rot_x, "y": rot_y, "z": rot_z}


def _euler_to_rotation(angles: Any, axes: str) -> np.ndarray:
    phi, theta, psi = as_vector(angles, 3, "phi")
    return _ELEMENTARY[axes[0]](phi) @ _ELEMENTARY[axes[1]](theta) @ _ELEMENTARY[axes[2]](psi)


def _residual_angle(R: np.ndarray, phi: float, theta: float, axes: str) -> float:
    """ψ from (R_a(φ) R_b(θ))^T R = R_c(ψ): exact reconstruction even close to the singular set."""
    M = (_ELEMENTARY[axes[0]](phi) @ _ELEMENTARY[axes[1]](theta)).T @ R
    i = "xyz".index(axes[2])
    j, k = (i + 1) % 3, (i + 2) % 3  # R_c(ψ) has cos ψ at (j, j) and sin ψ at (k, j)
    return float(np.arctan2(M[k, j], M[j, j]))


def _proper_euler(R: Any, branch: int, tol: float, axes: str) -> EulerResult:
    """Z–(Y or X)–Z Euler angles of R, both branches, with the singular set sin θ = 0 (r13 = r23 = 0).

    θ = atan2(±√(r13² + r23²), r33); φ from the third column (ZYZ: atan2(r23, r13), ZXZ: atan2(r13, −r23));
    ψ by :func:`_residual_angle`. On the singular set the representative with ψ = 0 is returned.
    """
    R = as_rotation(R)
    tol = _singular_tol(tol)
    b = _branch(branch)
    s_theta = np.hypot(R[0, 2], R[1, 2])
    if s_theta < tol:
        theta = 0.0 if R[2, 2] > 0 else b * np.pi
        M = R @ _ELEMENTARY[axes[1]](theta).T  # = Rz(φ) with ψ = 0
        return EulerResult(np.array([np.arctan2(M[1, 0], M[0, 0]), theta, 0.0]), True)
    if axes == "zyz":
        phi = np.arctan2(b * R[1, 2], b * R[0, 2])
    else:
        phi = np.arctan2(b * R[0, 2], -b * R[1, 2])
    theta = np.arctan2(b * s_theta, R[2, 2])
    return EulerResult(np.array([phi, theta, _residual_angle(R, phi, theta, axes)]), False)


def euler_zyz_to_rotation(phi: Any) -> np.ndarray:
    """R(φ) = Rz(φ) Ry(θ) Rz(ψ) of the ZYZ Euler angles ``phi = [φ, θ, ψ]``, Eq. (2.18)."""
    return _euler_to_rotation(phi, "zyz")


def rotation_to_euler_zyz(R: Any, branch: int = 1, tol: float = SINGULAR_TOL) -> EulerResult:
    """ZYZ Euler angles of R, Eq. (2.19) (``branch=+1``, θ ∈ (0, π)) or (2.20) (``branch=-1``).

    Singular when sin θ = 0 (r13 = r23 = 0): then θ ∈ {0, π} and only φ ± ψ is determined; the
    representative with ψ = 0 is returned with ``singular=True``.
    """
    return _proper_euler(R, branch, tol, "zyz")


def euler_zxz_to_rotation(phi: Any) -> np.ndarray:
    """R(φ) = Rz(φ) Rx(θ) Rz(ψ) of the ZXZ Euler angles ``phi = [φ, θ, ψ]`` (Problem 2.1)."""
    return _euler_to_rotation(phi, "zxz")


def rotation_to_euler_zxz(R: Any, branch: int = 1, tol: float = SINGULAR_TOL) -> EulerResult:
    """ZXZ Euler angles of R: φ = atan2(r13, −r23), θ = atan2(√(r13² + r23²), r33), ψ = atan2(r31, r32).

    ``branch=+1`` gives θ ∈ (0, π), ``branch=-1`` θ ∈ (−π, 0). Singular when sin θ = 0
    (r13 = r23 = 0); then the representative with ψ = 0 is returned with ``singular=True``.
    """
    return _proper_euler(R, branch, tol, "zxz")


RPY_ORDERS = ("zyx", "xyz", "yxz")  # the orders the peers use; "zyx" is the book's (2.21)


def _rpy_order(order: str) -> tuple[int, int, int, int]:
    """Axis indices (i, j, k) of R = R_i(φ) R_j(θ) R_k(ψ) and the parity ε (+1 cyclic, −1 not)."""
    if order not in RPY_ORDERS:
        raise ValueError(f"`order` must be one of {RPY_ORDERS}, got {order!r}")
    i, j, k = ("xyz".index(a) for a in order)
    return i, j, k, (1 if (j - i) % 3 == 1 else -1)


def _elementary_angle(M: np.ndarray, axis: int) -> float:
    """γ of M = R_axis(γ): cos γ sits at (a, a) and sin γ at (b, a), with a, b the next two axes."""
    a, b = (axis + 1) % 3, (axis + 2) % 3
    return float(np.arctan2(M[b, a], M[a, a]))


def rpy_to_rotation(phi: Any, order: str = "zyx") -> np.ndarray:
    """R = R_a(φ) R_b(θ) R_c(ψ) of the angles ``phi = [φ, θ, ψ]``, ``order = "abc"``.

    ``"zyx"`` (default) is the book's roll–pitch–yaw (2.21), R = Rz(φ) Ry(θ) Rx(ψ): ψ (yaw) about x,
    then ϑ (pitch) about y, then φ (roll) about z, all about fixed axes. ``"xyz"`` is
    R = Rx(φ) Ry(θ) Rz(ψ) and ``"yxz"`` R = Ry(φ) Rx(θ) Rz(ψ) (the camera-style orders of the
    Robotics Toolbox/spatialmath, whose ``rpy2r([roll, pitch, yaw], order)`` equals
    ``rpy_to_rotation([yaw, pitch, roll], order)``: the same product, angles listed in reverse).
    """
    _rpy_order(order)
    return _euler_to_rotation(phi, order)


def rotation_to_rpy(R: Any, branch: int = 1, tol: float = SINGULAR_TOL, order: str = "zyx") -> EulerResult:
    """Angles [φ, θ, ψ] of R = R_a(φ) R_b(θ) R_c(ψ), ``order = "abc"`` (see :func:`rpy_to_rotation`).

    For ``"zyx"`` these are Eq. (2.22) (``branch=+1``, θ ∈ (−π/2, π/2)) and (2.23) (``branch=-1``,
    θ ∈ (π/2, 3π/2), returned wrapped into (−π, π]). Every order has the same structure: with
    (i, j, k) the axes and ε = +1 for a cyclic order (xyz), −1 otherwise (zyx, yxz),
    r_ik = ε sin θ, the rest of row i gives |cos θ|, and column k gives φ.
    Singular when cos θ = 0: θ = ±π/2, R = R_a(φ + ε sin θ ψ) R_b(θ) and only that sum is determined
    (φ ∓ ψ for zyx); the representative with ψ = 0 is returned with ``singular=True``.
    """
    i, j, k, eps = _rpy_order(order)
    R = as_rotation(R)
    tol = _singular_tol(tol)
    b = _branch(branch)
    c_theta = np.hypot(R[i, i], R[i, j])
    s_theta = eps * R[i, k]
    if c_theta < tol:
        theta = np.copysign(np.pi / 2, s_theta)
        M = R @ _ELEMENTARY[order[1]](theta).T  # = R_i(φ) with ψ = 0
        return EulerResult(np.array([_elementary_angle(M, i), theta, 0.0]), True)
    # column k = R_i(φ) (ε sin θ e_i + cos θ e_k): r_jk = −ε cos θ sin φ, r_kk = cos θ cos φ
    phi = np.arctan2(-eps * b * R[j, k], b * R[k, k])
    theta = np.arctan2(s_theta, b * c_theta)
    return EulerResult(np.array([phi, theta, _residual_angle(R, phi, theta, order)]), False)


# --------------------------------------------------------------------------------------------
# Projection of a nearly orthogonal matrix onto SO(3)
# --------------------------------------------------------------------------------------------

def nearest_rotation(M: Any) -> np.ndarray:
    """The rotation R closest to the (3, 3) matrix ``M`` in the Frobenius norm (orthogonal Procrustes).

    With M = U Σ V^T, R = U diag(1, 1, det(U V^T)) V^T: the orthogonal polar factor, with its last
    axis flipped when U V^T would be a reflection, so that det R = +1. Use it to re-orthonormalise a
    rotation matrix that has drifted (integration, rounding, a measured or first-order matrix).
    """
    M = as_matrix(M, (3, 3), "M")
    U, _, Vt = np.linalg.svd(M)
    d = 1.0 if np.linalg.det(U @ Vt) > 0 else -1.0
    return (U * [1.0, 1.0, d]) @ Vt


def distance_from_so3(M: Any) -> float:
    """‖M − R*‖_F, the Frobenius distance of the (3, 3) matrix ``M`` from SO(3) (R* = :func:`nearest_rotation`)."""
    M = as_matrix(M, (3, 3), "M")
    return float(np.linalg.norm(M - nearest_rotation(M)))


# --------------------------------------------------------------------------------------------
# Angle and axis (2.25)–(2.27)
# --------------------------------------------------------------------------------------------

def axis_angle_to_rotation(theta: float, r: Any) -> np.ndarray:
    """R(θ, r) = I cos θ + (1 − cos θ) r r^T + sin θ S(r): rotation by θ about the unit vector r, Eq. (2.25)."""
    theta = _scalar(theta, "theta")
    r = as_vector(r, 3, "r")
    norm = np.linalg.norm(r)
    if abs(norm - 1.0) > ORTHONORMAL_TOL:
        raise ValueError(f"`r` must be a unit vector, got norm {norm:.6g}")
    c, s = np.cos(theta), np.sin(theta)
    return c * np.eye(3) + (1.0 - c) * np.outer(r, r) + s * skew(r)


def rotation_to_axis_angle(R: Any) -> tuple[float, np.ndarray]:
    """(θ, r) with θ ∈ [0, π] and unit r such that R = R(θ, r), Eqs. (2.26)–(2.27), robust at 0 and π.

    θ = atan2(‖vee(R − R^T)‖/2, (tr R − 1)/2). Away from θ = π the axis is (2.27),
    r = vee(R − R^T) / (2 sin θ). Near θ = π, where (2.27) loses its digits, r is the largest-diagonal
    column of (R + R^T)/2 − cos θ I = (1 − cos θ) r r^T, with its sign taken from vee(R − R^T).
    At θ = 0 the axis is arbitrary: r = [0, 0, 1] is returned.
    """
    R = as_rotation(R)
    w = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])  # vee(R − R^T)/2 = sin θ r
    s = np.linalg.norm(w)
    c = np.clip(0.5 * (np.trace(R) - 1.0), -1.0, 1.0)
    theta = float(np.arctan2(s, c))
    if c > -0.5:  # θ < 2π/3: (2.27) is well conditioned (or θ ≈ 0)
        if s < 1e-15:
            return 0.0, np.array([0.0, 0.0, 1.0])
        return theta, w / s
    B = 0.5 * (R + R.T) - c * np.eye(3)
    k = int(np.argmax(np.diag(B)))
    r = B[:, k] / np.linalg.norm(B[:, k])
    if r @ w < 0:
        r = -r
    return theta, r


# --------------------------------------------------------------------------------------------
# Unit quaternion (2.33)–(2.37)
# --------------------------------------------------------------------------------------------

def quaternion_to_rotation(Q: Any) -> np.ndarray:
    """R(η, ε) of the unit quaternion ``Q = [η, εx, εy, εz]``, Eq. (2.33)."""
    eta, ex, ey, ez = as_unit_quaternion(Q)
    return np.array([
        [2 * (eta**2 + ex**2) - 1, 2 * (ex * ey - eta * ez), 2 * (ex * ez + eta * ey)],
        [2 * (ex * ey + eta * ez), 2 * (eta**2 + ey**2) - 1, 2 * (ey * ez - eta * ex)],
        [2 * (ex * ez - eta * ey), 2 * (ey * ez + eta * ex), 2 * (eta**2 + ez**2) - 1],
    ])


def rotation_to_quaternion(R: Any) -> np.ndarray:
    """Unit quaternion [η, εx, εy, εz] of R with η ≥ 0, Eqs. (2.34)–(2.35).

    The magnitudes are those of (2.34)–(2.35), e.g. η = ½ √(r11 + r22 + r33 + 1). The signs of ε in
    (2.35) come from r32 − r23 etc., which vanish as η → 0; instead the largest of the four magnitudes
    is taken from its square root and the other three from the off-diagonal sums and differences
    (e.g. 4 η εx = r32 − r23, 4 εx εy = r12 + r21), which is exact for every R. Then Q is flipped
    so that η ≥ 0 (Q and −Q are the same rotation).
    """
    (r11, r12, r13), (r21, r22, r23), (r31, r32, r33) = as_rotation(R).tolist()  # Python floats: 3×3 only
    squares = [0.25 * (1 + r11 + r22 + r33), 0.25 * (1 + r11 - r22 - r33), 0.25 * (1 - r11 + r22 - r33),
               0.25 * (1 - r11 - r22 + r33)]  # η², εx², εy², εz²  (2.34)–(2.35)
    d = r32 - r23, r13 - r31, r21 - r12  # 4η ε
    p = r12 + r21, r13 + r31, r23 + r32  # 4 εx εy, 4 εx εz, 4 εy εz
    k = squares.index(max(squares))
    m = math.sqrt(max(squares[k], 0.0))
    f = 0.25 / m
    if k == 0:
        Q = [m, f * d[0], f * d[1], f * d[2]]
    elif k == 1:
        Q = [f * d[0], m, f * p[0], f * p[1]]
    elif k == 2:
        Q = [f * d[1], f * p[0], m, f * p[2]]
    else:
        Q = [f * d[2], f * p[1], f * p[2], m]
    Q = np.array(Q) if Q[0] >= 0 else -np.array(Q)
    return Q / np.linalg.norm(Q)


def quaternion_product(Q1: Any, Q2: Any) -> np.ndarray:
    """Q1 ∗ Q2 = {η1 η2 − ε1^T ε2, η1 ε2 + η2 ε1 + ε1 × ε2}, Eq. (2.37): the quaternion of R(Q1) R(Q2)."""
    Q1 = as_unit_quaternion(Q1, "Q1")
    Q2 = as_unit_quaternion(Q2, "Q2")
    eta1, eps1, eta2, eps2 = Q1[0], Q1[1:], Q2[0], Q2[1:]
    return np.concatenate([[eta1 * eta2 - eps1 @ eps2], eta1 * eps2 + eta2 * eps1 + np.cross(eps1, eps2)])


def quaternion_inverse(Q: Any) -> np.ndarray:
    """Q^{-1} = {η, −ε}: the quaternion of R^T, Eq. (2.36)."""
    Q = as_unit_quaternion(Q)
    return np.concatenate([[Q[0]], -Q[1:]])


# --------------------------------------------------------------------------------------------
# Homogeneous transformations (2.42)–(2.45)
# --------------------------------------------------------------------------------------------

def homogeneous_transform(R: Any, o: Any) -> np.ndarray:
    """A = [[R, o], [0^T, 1]], Eq. (2.42)."""
    T = np.eye(4)
    T[:3, :3] = as_rotation(R)
    T[:3, 3] = as_vector(o, 3, "o")
    return T


def homogeneous_inverse(T: Any) -> np.ndarray:
    """A^{-1} = [[R^T, −R^T o], [0^T, 1]], Eq. (2.45) (never a general 4×4 inverse)."""
    T = as_homogeneous(T)
    R, o = T[:3, :3], T[:3, 3]
    Ti = np.eye(4)
    Ti[:3, :3] = R.T
    Ti[:3, 3] = -R.T @ o
    return Ti


# --------------------------------------------------------------------------------------------
# Orientation errors (Chapter 3): Euler-rate matrices T(φ), orientation errors, quaternion propagation
# --------------------------------------------------------------------------------------------

def euler_rate_matrix_zyz(phi: Any) -> np.ndarray:
    """T(φ) with ω = T(φ) φ̇ for ZYZ angles φ = [φ, θ, ψ], Eq. (3.64); det T = −sin θ."""
    ph, th, _ = as_vector(phi, 3, "phi")
    cp, sp, ct, st = np.cos(ph), np.sin(ph), np.cos(th), np.sin(th)
    return np.array([[0.0, -sp, cp * st], [0.0, cp, sp * st], [1.0, 0.0, ct]])


def euler_rate_matrix_rpy(phi: Any) -> np.ndarray:
    """T(φ) with ω = T(φ) φ̇ for RPY angles φ = [φ, θ, ψ] (R = Rz(φ) Ry(θ) Rx(ψ)), Problem 3.12;
    det T = −cos θ."""
    ph, th, _ = as_vector(phi, 3, "phi")
    cp, sp, ct, st = np.cos(ph), np.sin(ph), np.cos(th), np.sin(th)
    return np.array([[0.0, -sp, cp * ct], [0.0, cp, sp * ct], [1.0, 0.0, -st]])


def wrap_angle(a: Any) -> np.ndarray:
    """Angle(s) ``a`` wrapped into (−π, π] (a − 2πk): compare angles modulo 2π; ±π both give π."""
    return np.pi - (np.pi - np.asarray(a, dtype=float)) % (2.0 * np.pi)


def orientation_error_euler(R_d: Any, R_e: Any, representation: str = "zyz") -> np.ndarray:
    """e_O = φ_d − φ_e (each angle wrapped into (−π, π]): the Euler-angle orientation error, Sect. 3.7.3.

    Both sets are extracted with ``branch=+1``; ``representation`` is ``"zyz"`` or ``"rpy"``.
    ValueError when R_d or R_e is a representation singularity.
    """
    extract = {"zyz": rotation_to_euler_zyz, "rpy": rotation_to_rpy}.get(representation)
    if extract is None:
        raise ValueError(f"`representation` must be 'zyz' or 'rpy', got {representation!r}")
    d, e = extract(R_d), extract(R_e)
    if d.singular or e.singular:
        raise ValueError(f"{representation.upper()} angles are singular at "
                         f"{'R_d' if d.singular else 'R_e'}: the Euler-angle error is undefined")
    return wrap_angle(d.angles - e.angles)


def orientation_error_axis_angle(R_d: Any, R_e: Any) -> np.ndarray:
    """e_O = r sin ϑ = ½ (n_e × n_d + s_e × s_d + a_e × a_d), Eq. (3.85), with R(ϑ, r) = R_d R_e^T (3.84)."""
    return axis_angle_error_kernel(as_rotation(R_d, "R_d"), as_rotation(R_e, "R_e"))


def axis_angle_error_kernel(R_d: np.ndarray, R_e: np.ndarray) -> np.ndarray:
    """The unvalidated kernel of :func:`orientation_error_axis_angle` (hot loops)."""
    # Σ_k e_k × d_k = vee(R_d R_e^T − R_e R_d^T): twice the vee of the antisymmetric part of R_d R_e^T
    M = R_d @ R_e.T
    return 0.5 * np.array([M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]])


def orientation_error_matrix(R_d: Any, R_e: Any) -> np.ndarray:
    """L = −½ (S(n_d) S(n_e) + S(s_d) S(s_e) + S(a_d) S(a_e)), Eq. (3.87): ė_O = L^T ω_d − L ω_e (3.86)."""
    return orientation_error_matrix_kernel(as_rotation(R_d, "R_d"), as_rotation(R_e, "R_e"))


def orientation_error_matrix_kernel(R_d: np.ndarray, R_e: np.ndarray) -> np.ndarray:
    """The unvalidated kernel of :func:`orientation_error_matrix` (hot loops)."""
    # Σ_k S(d_k) S(e_k) = Σ_k (e_k d_k^T − (d_k·e_k) I), with S(x)S(y) = y x^T − x^T y I
    M = R_e @ R_d.T
    return -0.5 * (M - np.trace(M) * np.eye(3))


def orientation_error_quaternion(Q_d: Any, Q_e: Any) -> np.ndarray:
    """e_O = η_e ε_d − η_d ε_e − S(ε_d) ε_e, Eq. (3.91): the vector part of Q_d ∗ Q_e^{-1}."""
    Q_d = as_unit_quaternion(Q_d, "Q_d")
    Q_e = as_unit_quaternion(Q_e, "Q_e")
    return Q_e[0] * Q_d[1:] - Q_d[0] * Q_e[1:] - np.cross(Q_d[1:], Q_e[1:])


def quaternion_rate(Q: Any, omega: Any) -> np.ndarray:
    """Q̇ = [η̇, ε̇] of a unit quaternion rotating at ω (base frame): η̇ = −½ ε^T ω (3.94),
    ε̇ = ½ (η I − S(ε)) ω (3.95)."""
    Q = as_unit_quaternion(Q)
    w = as_vector(omega, 3, "omega")
    eta, eps = Q[0], Q[1:]
    return np.concatenate([[-0.5 * eps @ w], 0.5 * (eta * w - np.cross(eps, w))])


def quaternion_angular_velocity(Q: Any, Q_dot: Any) -> np.ndarray:
    """ω = 2 (η ε̇ − η̇ ε + S(ε) ε̇): the angular velocity from unit-quaternion rates, Problem 3.18 (S3.13)."""
    Q = as_unit_quaternion(Q)
    Qd = as_vector(Q_dot, 4, "Q_dot")
    return 2.0 * (Q[0] * Qd[1:] - Qd[0] * Q[1:] + np.cross(Q[1:], Qd[1:]))
