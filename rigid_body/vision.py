"""Geometric vision: what a camera's measurements tell about poses and points.

* the planar homography of an object by the direct linear transformation, Eq. (10.10), its null vector
  being the right singular vector of the null singular value of A (Problem 10.2), and the object's pose
  from it with the nearest rotation matrix (10.12) (Problem 10.3);
* point-cloud registration (10.55)–(10.57): o = p̄ − R p̄' and R = argmax Tr(Rᵀ K) (Problems 10.6–10.7);
* the homography between the current and the desired view of a plane and the depth ratios of the
  2½-D scheme, Eqs. (10.94)–(10.95) (Problem 10.12);
* beyond the book: camera calibration by DLT of a 3×4 projection matrix, then the intrinsics by an RQ
  split (Hartley–Zisserman Ch. 7), and linear two-view triangulation (ibid. Sect. 12.2).

Image coordinates are normalised (x = p_x/p_z) unless a name says pixels.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 10.3, 10.5,
10.8.3; R. Hartley, A. Zisserman, *Multiple View Geometry*, 2nd ed., CUP 2004.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rigid_body.rotations import nearest_rotation
from rigid_body.validation import as_matrix, as_points, as_positive, as_vector


def _null_vector(A: np.ndarray, name: str, rank: int) -> tuple[np.ndarray, np.ndarray]:
    """(v, σ): the right singular vector of the smallest singular value of ``A`` and the singular values.

    ValueError when A has fewer than ``rank`` significant singular values (degenerate data)."""
    _, sigma, Vt = np.linalg.svd(A)
    if sigma.size < rank or sigma[rank - 1] <= 1e-10 * sigma[0]:
        raise ValueError(f"{name}: the data are degenerate (rank of A below {rank}); "
                         "use more points in general position")
    return Vt[-1], sigma


def _hartley_normalisation(pts: np.ndarray) -> np.ndarray:
    """The similarity moving the centroid to 0 and the mean distance to √dim (conditions the DLT)."""
    dim = pts.shape[1]
    c = pts.mean(axis=0)
    scale = np.sqrt(dim) / max(np.mean(np.linalg.norm(pts - c, axis=1)), 1e-300)
    T = np.eye(dim + 1)
    T[:dim, :dim] *= scale
    T[:dim, dim] = -scale * c
    return T


# --------------------------------------------------------------------------------------------
# Planar homography and pose, Eqs. (10.10)–(10.12)
# --------------------------------------------------------------------------------------------

def homography_dlt_matrix(zeta: Any, s: Any) -> np.ndarray:
    """A (2n×9) of Eq. (10.10), A h = 0, for object points ``zeta`` (n, 2) on the plane z = 0 of the
    object frame and their images ``s`` (n, 2): from λ s̃_i = H ζ̃_i, h = the rows of H stacked."""
    zeta, s = as_points(zeta, 2, "zeta"), as_points(s, 2, "s")
    if zeta.shape != s.shape:
        raise ValueError(f"`zeta` and `s` must hold the same number of points, got {zeta.shape} and {s.shape}")
    A = np.zeros((2 * len(zeta), 9))
    for i, ((u, v), (x, y)) in enumerate(zip(zeta, s)):
        z = np.array([u, v, 1.0])
        A[2 * i, 0:3], A[2 * i, 6:9] = z, -x * z
        A[2 * i + 1, 3:6], A[2 * i + 1, 6:9] = z, -y * z
    return A


def homography_dlt(zeta: Any, s: Any) -> np.ndarray:
    """H (3×3, ‖H‖_F = 1, up to sign) with λ s̃_i = H ζ̃_i from n ≥ 4 point pairs (10.10), by the SVD of A
    (Hartley-normalised): h = v_9, the right singular vector of the null (least) singular value."""
    zeta, s = as_points(zeta, 2, "zeta"), as_points(s, 2, "s")
    if len(zeta) < 4:
        raise ValueError(f"a homography needs at least 4 points, got {len(zeta)}")
    Tz, Ts = _hartley_normalisation(zeta), _hartley_normalisation(s)
    zn = (np.column_stack([zeta, np.ones(len(zeta))]) @ Tz.T)[:, :2]
    sn = (np.column_stack([s, np.ones(len(s))]) @ Ts.T)[:, :2]
    h, _ = _null_vector(homography_dlt_matrix(zn, sn), "homography_dlt", 8)
    H = np.linalg.solve(Ts, h.reshape(3, 3) @ Tz)
    return H / np.linalg.norm(H)


@dataclass(frozen=True)
class PlanarPose:
    """Pose of a planar object in the camera frame: R_o^c (3×3), o_{c,o}^c (3,), and Q before projection."""

    R: np.ndarray
    o: np.ndarray
    Q: np.ndarray


def pose_from_homography(H: Any) -> PlanarPose:
    """R_o^c, o_{c,o}^c from H = k [r_1 r_2 o] (normalised coordinates): scale from ‖r_1‖, ‖r_2‖, sign from
    o_z > 0 (object in front), R = the rotation nearest to Q = [r_1 r_2 r_1×r_2], Eq. (10.12)."""
    H = as_matrix(H, (3, 3), "H")
    k = 0.5 * (np.linalg.norm(H[:, 0]) + np.linalg.norm(H[:, 1]))
    if k == 0:
        raise ValueError("`H` has null first columns: not the homography of a plane seen by a camera")
    M = H / k
    if M[2, 2] < 0:
        M = -M
    Q = np.column_stack([M[:, 0], M[:, 1], np.cross(M[:, 0], M[:, 1])])
    return PlanarPose(R=nearest_rotation(Q), o=M[:, 2].copy(), Q=Q)


def homography_between_views(R_dc: Any, o_cd_c: Any, n_d: Any, d_d: float) -> np.ndarray:
    """H = R_d^c + (1/d_d) o_{c,d}^c n^{dT}: maps a plane point seen from the desired frame d to the current
    frame c (the plane n^{dT} p^d = d_d), Sect. 10.8.3."""
    R = nearest_rotation(as_matrix(R_dc, (3, 3), "R_dc"))
    return R + np.outer(as_vector(o_cd_c, 3, "o_cd_c"), as_vector(n_d, 3, "n_d")) / as_positive(d_d, "d_d")


def depth_ratio(H: Any, n_c: Any, s_c: Any, n_d: Any, s_d: Any) -> float:
    """z_c/z_d of a plane point from the homography, Eqs. (10.94)–(10.95):
    z_c/z_d = det(H) (n^{dT} s̃_d)/(n^{cT} s̃_c), with s̃ = [x, y, 1] its normalised image in c and d."""
    H = as_matrix(H, (3, 3), "H")
    sc, sd = np.append(as_vector(s_c, 2, "s_c"), 1.0), np.append(as_vector(s_d, 2, "s_d"), 1.0)
    den = float(as_vector(n_c, 3, "n_c") @ sc)
    if den == 0:
        raise ValueError("the viewing ray of `s_c` is parallel to the plane: the depth is undefined")
    return float(np.linalg.det(H)) * float(as_vector(n_d, 3, "n_d") @ sd) / den


# --------------------------------------------------------------------------------------------
# Point-cloud registration, Eqs. (10.55)–(10.57)
# --------------------------------------------------------------------------------------------

def registration_cost(p: np.ndarray, p_prime: np.ndarray, R: np.ndarray, o: np.ndarray) -> float:
    """g = Σ ‖p_i − o − R p'_i‖², Eq. (10.55)."""
    return float(np.sum((p - o - p_prime @ R.T) ** 2))


def register_point_clouds(p: Any, p_prime: Any) -> tuple[np.ndarray, np.ndarray]:
    """(R, o) minimising (10.55) for corresponding points p_i ≈ o + R p'_i (n ≥ 3, not collinear).

    R maximises Tr(Rᵀ K), K = Σ p̄_i p̄'_iᵀ (10.57): R = U diag(1, 1, det(U Vᵀ)) Vᵀ from K = U Σ Vᵀ;
    then o = p̄ − R p̄' (10.56).
    """
    p, pp = as_points(p, 3, "p"), as_points(p_prime, 3, "p_prime")
    if p.shape != pp.shape:
        raise ValueError(f"`p` and `p_prime` must hold the same number of points, got {p.shape} and {pp.shape}")
    pbar, ppbar = p.mean(axis=0), pp.mean(axis=0)
    K = (p - pbar).T @ (pp - ppbar)
    if np.linalg.matrix_rank(K, tol=1e-12 * max(1.0, np.abs(K).max())) < 2:
        raise ValueError("the points are collinear (or fewer than 3): the rotation is not determined")
    R = nearest_rotation(K)
    return R, pbar - R @ ppbar


# --------------------------------------------------------------------------------------------
# Beyond the book: calibration and triangulation
# --------------------------------------------------------------------------------------------

def projection_matrix_dlt(points: Any, pixels: Any) -> np.ndarray:
    """The 3×4 projection matrix P (‖P‖_F = 1, det P[:, :3] > 0) with λ [X, Y, 1]ᵀ = P [p; 1] from n ≥ 6 known
    3-D points (n, 3) and their pixels (n, 2), not all coplanar: DLT (Hartley-normalised)."""
    pts, pix = as_points(points, 3, "points"), as_points(pixels, 2, "pixels")
    if len(pts) != len(pix):
        raise ValueError(f"`points` and `pixels` must hold the same number of points, got {len(pts)} and {len(pix)}")
    if len(pts) < 6:
        raise ValueError(f"calibration by DLT needs at least 6 points, got {len(pts)}")
    T3, T2 = _hartley_normalisation(pts), _hartley_normalisation(pix)
    Pn = np.column_stack([pts, np.ones(len(pts))]) @ T3.T
    xn = (np.column_stack([pix, np.ones(len(pix))]) @ T2.T)[:, :2]
    A = np.zeros((2 * len(pts), 12))
    for i, (P, (x, y)) in enumerate(zip(Pn, xn)):
        A[2 * i, 0:4], A[2 * i, 8:12] = P, -x * P
        A[2 * i + 1, 4:8], A[2 * i + 1, 8:12] = P, -y * P
    p, _ = _null_vector(A, "projection_matrix_dlt (coplanar points?)", 11)
    M = np.linalg.solve(T2, p.reshape(3, 4) @ T3)
    M /= np.linalg.norm(M)
    return M if np.linalg.det(M[:, :3]) > 0 else -M


@dataclass(frozen=True)
class Calibration:
    """Intrinsic matrix Ω (5.41) (skew kept in Ω[0, 1]) and the camera's extrinsics: a point p of the
    calibration frame is p^c = R p + o in the camera frame."""

    Omega: np.ndarray
    R: np.ndarray
    o: np.ndarray


def decompose_projection_matrix(P: Any) -> Calibration:
    """Ω, R, o from P ∝ Ω [R o] by an RQ split of P[:, :3] with a positive diagonal of Ω."""
    from scipy.linalg import rq

    P = as_matrix(P, (3, 4), "P")
    K, R = rq(P[:, :3])
    D = np.diag(np.sign(np.diag(K)))
    K, R = K @ D, D @ R
    if np.linalg.det(R) < 0:   # P was given with the opposite overall sign
        R, P = -R, -P
    o = np.linalg.solve(K, P[:, 3])
    return Calibration(Omega=K / K[2, 2], R=R, o=o)


def triangulate(P1: Any, P2: Any, xy1: Any, xy2: Any) -> np.ndarray:
    """Points (n, 3) seen at ``xy1`` (n, 2) by the camera of projection matrix ``P1`` (3×4) and at ``xy2`` by
    ``P2``: the linear (DLT) two-view triangulation (null vector of a 4×4 system per point)."""
    P1, P2 = as_matrix(P1, (3, 4), "P1"), as_matrix(P2, (3, 4), "P2")
    a, b = as_points(xy1, 2, "xy1"), as_points(xy2, 2, "xy2")
    if a.shape != b.shape:
        raise ValueError(f"`xy1` and `xy2` must hold the same number of points, got {a.shape} and {b.shape}")
    out = np.empty((len(a), 3))
    for i, ((x1, y1), (x2, y2)) in enumerate(zip(a, b)):
        A = np.array([x1 * P1[2] - P1[0], y1 * P1[2] - P1[1], x2 * P2[2] - P2[0], y2 * P2[2] - P2[1]])
        X, _ = _null_vector(A, "triangulate (the two centres and the point are aligned?)", 3)
        if abs(X[3]) < 1e-12:
            raise ValueError(f"triangulate: point {i} is at infinity (parallel viewing rays)")
        out[i] = X[:3] / X[3]
    return out
