"""Chapter 2 — Kinematics: Problems 2.1–2.20.

Each problem builds its data, calls the library (``rigid_body.rotations``, ``rigid_body.kinematics``,
``rigid_body.closed_chain``, ``rigid_body.trees``) and checks the manual's closed forms against an
independent reference: Pinocchio on the URDF models, Pinocchio's exp3/log3/quaternions/SE3, numpy
products of the elementary matrices, many random samples.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Chapter 2,
and its solution manual (Problems 2.1–2.20, Tables S2.1–S2.3, (S2.1)–(S2.7), Fig. S2.4).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin
from matplotlib.path import Path as PolygonPath
from scipy.spatial import cKDTree

from planners.configuration_space import polyline_distance
from problems.common import frames_figure, label_axes, max_error, random_quaternion, random_rotation, subplots, unit
from problems.registry import Solution, problem
from rigid_body import rotations as rot
from rigid_body.closed_chain import (FourLinkClosedChain, closed_chain_direct_kinematics,
                                     closed_chain_joints, loop_constraint_residual)
from rigid_body.dh import dh_transform
from rigid_body.kinematics import (ELBOW_DOWN, ELBOW_UP, direct_kinematics, distinct_solutions,
                                   frame_poses, inverse_kinematics_anthropomorphic,
                                   inverse_kinematics_cylindrical, inverse_kinematics_scara, joint_arc,
                                   planar_3r_workspace_contour, workspace_points)
from rigid_body.robots import load
from rigid_body.trees import Humanoid, robot_from_dh_tree

N_RANDOM = 50  # random samples per closed-form check
N_WORKSPACE = 200_000  # joint samples of the 2.17 workspace
c, s = np.cos, np.sin










# --------------------------------------------------------------------------------------------
# 2.1–2.10: rotations and homogeneous transformations
# --------------------------------------------------------------------------------------------

@problem("2.1", "Rotation matrix of ZXZ Euler angles and its inverse", kind="derivation")
def problem_2_1() -> Solution:
    """Find R(φ) = Rz(φ) Rx'(θ) Rz''(ψ) for ZXZ Euler angles and its inverse (cf. (2.18)–(2.20)).

    The manual's matrix and inverse formulas (both θ ranges) are compared with the product of the
    elementary rotations (2.6), (2.8) and with ``rotation_to_euler_zxz`` at random angles.
    Erratum: the manual labels the third factor R_z''(φ); it is R_z''(ψ).
    """
    sol = Solution()
    rng = np.random.default_rng(21)
    pairs, inv_pairs, back = [], [], []
    for ph, th, ps in rng.uniform(-np.pi, np.pi, (N_RANDOM, 3)):
        manual = np.array([
            [c(ph) * c(ps) - s(ph) * c(th) * s(ps), -c(ph) * s(ps) - s(ph) * c(th) * c(ps), s(ph) * s(th)],
            [s(ph) * c(ps) + c(ph) * c(th) * s(ps), -s(ph) * s(ps) + c(ph) * c(th) * c(ps), -c(ph) * s(th)],
            [s(th) * s(ps), s(th) * c(ps), c(th)]])
        R = rot.euler_zxz_to_rotation([ph, th, ps])
        pairs += [(R, manual), (R, rot.rot_z(ph) @ rot.rot_x(th) @ rot.rot_z(ps))]
        r = R
        n = np.hypot(r[2, 0], r[2, 1])
        manual_pos = [np.arctan2(r[0, 2], -r[1, 2]), np.arctan2(n, r[2, 2]), np.arctan2(r[2, 0], r[2, 1])]
        manual_neg = [np.arctan2(-r[0, 2], r[1, 2]), np.arctan2(-n, r[2, 2]), np.arctan2(-r[2, 0], -r[2, 1])]
        for branch, manual_angles in ((1, manual_pos), (-1, manual_neg)):
            res = rot.rotation_to_euler_zxz(R, branch)
            inv_pairs.append((rot.wrap_angle(res.angles - manual_angles), 0.0))
            back.append((rot.euler_zxz_to_rotation(res.angles), R))
        true = np.array([ph, th, ps]) if th > 0 else np.array([ph + np.pi, -th, ps + np.pi])
        inv_pairs.append((rot.wrap_angle(rot.rotation_to_euler_zxz(R, 1).angles - true), 0.0))
    sol.value("R_example", rot.euler_zxz_to_rotation([0.3, 0.5, -0.2]), unit="1")
    sol.check("zxz_matrix_matches_manual", max_error(pairs) < 1e-12,
              f"max |error| = {max_error(pairs):.2e} over {N_RANDOM} random angle sets "
              "(manual erratum: third factor is R_z''(psi), printed R_z''(varphi))", reference="closed form")
    sol.check("inverse_matches_manual_both_ranges", max_error(inv_pairs) < 1e-9,
              f"theta in (0, pi) and (-pi, 0): max angle error (mod 2pi) = {max_error(inv_pairs):.2e}",
              reference="closed form")
    sol.check("inverse_reproduces_R", max_error(back) < 1e-12, f"max |R(phi(R)) - R| = {max_error(back):.2e}")
    return sol


@problem("2.2", "ZYZ Euler angles: inverse solution when sin θ = 0", kind="derivation")
def problem_2_2() -> Solution:
    """Discuss the ZYZ inverse (2.19)–(2.20) when s_θ = 0: only φ ± ψ = Atan2(−r12, r22) is determined.

    θ = 0 gives R = Rz(φ + ψ), θ = π gives R = [[−c, −s, 0], [−s, c, 0], [0, 0, −1]] with angle φ − ψ.
    The inverse flags the singular set and returns a representative (ψ = 0) that reproduces R.
    """
    sol = Solution()
    rng = np.random.default_rng(22)
    closed, atan, rep, flags = [], [], [], []
    for ph, ps in rng.uniform(-np.pi, np.pi, (N_RANDOM, 2)):
        for th, sign in ((0.0, 1.0), (np.pi, -1.0)):
            g = ph + sign * ps
            manual = ([[c(g), -s(g), 0], [s(g), c(g), 0], [0, 0, 1]] if th == 0.0
                      else [[-c(g), -s(g), 0], [-s(g), c(g), 0], [0, 0, -1]])
            R = rot.euler_zyz_to_rotation([ph, th, ps])
            closed.append((R, manual))
            atan.append((rot.wrap_angle(np.arctan2(-R[0, 1], R[1, 1]) - g), 0.0))
            for branch in (1, -1):
                res = rot.rotation_to_euler_zyz(R, branch)
                flags.append(res.singular)
                rep.append((rot.euler_zyz_to_rotation(res.angles), R))
                atan.append((rot.wrap_angle(res.angles[0] + sign * res.angles[2] - g), 0.0))
    sol.check_error("closed_forms_theta_0_and_pi", max_error(closed), 1e-12, reference="closed form")
    sol.check("phi_pm_psi_is_atan2(-r12, r22)", max_error(atan) < 1e-9,
              f"+ for theta = 0, - for theta = pi; max error (mod 2pi) = {max_error(atan):.2e}")
    sol.check("singularity_flagged", all(flags), f"{sum(flags)}/{len(flags)} inverses flagged singular")
    sol.check_error("representative_reproduces_R", max_error(rep), 1e-12, reference="closed form")
    _zyz_generic_check(sol, np.random.default_rng(2202))
    return sol


def _zyz_generic_check(sol: Solution, rng: np.random.Generator) -> None:
    """(2.19)–(2.20) on generic rotations (every r_ij ≠ 0, unlike the problems' data with r23 = 0):
    R = Rz(φ) Ry(θ) Rz(ψ) composed with ``pin.exp3``; both branches give back [φ, θ, ψ] and
    [φ + π, −θ, ψ + π] (mod 2π), unflagged."""
    worst, flagged = 0.0, False
    z, y = np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])
    for _ in range(N_RANDOM):
        angles = np.array([rng.uniform(-3.0, 3.0), rng.uniform(0.2, 2.9), rng.uniform(-3.0, 3.0)])
        R = pin.exp3(angles[0] * z) @ pin.exp3(angles[1] * y) @ pin.exp3(angles[2] * z)
        for branch, expected in ((1, angles), (-1, angles * [1, -1, 1] + [np.pi, 0.0, np.pi])):
            found = rot.rotation_to_euler_zyz(R, branch)
            flagged |= found.singular
            worst = max(worst, float(np.max(np.abs(rot.wrap_angle(found.angles - expected)))))
    sol.check_error("generic rotations: both ZYZ branches give back the composed angles", worst, 1e-10,
                    reference="second algorithm")
    sol.check("generic rotations: not flagged singular", not flagged)


@problem("2.3", "RPY angles: inverse solution when cos θ = 0", kind="derivation")
def problem_2_3() -> Solution:
    """Discuss the RPY inverse (2.22)–(2.23) when c_θ = 0: only ψ ± φ = Atan2(−r23, r22) is determined.

    θ = π/2: R = [[0, s, c], [0, c, −s], [−1, 0, 0]] of ψ − φ; θ = −π/2: [[0, −s, −c], [0, c, −s], [1, 0, 0]]
    of ψ + φ. Cross-checked with Pinocchio's rpyToMatrix(ψ, θ, φ) = Rz(φ) Ry(θ) Rx(ψ).
    """
    sol = Solution()
    rng = np.random.default_rng(23)
    closed, atan, rep, flags = [], [], [], []
    for ph, ps in rng.uniform(-np.pi, np.pi, (N_RANDOM, 2)):
        for th, sign in ((np.pi / 2, -1.0), (-np.pi / 2, 1.0)):
            g = ps + sign * ph
            manual = ([[0, s(g), c(g)], [0, c(g), -s(g)], [-1, 0, 0]] if th > 0
                      else [[0, -s(g), -c(g)], [0, c(g), -s(g)], [1, 0, 0]])
            R = rot.rpy_to_rotation([ph, th, ps])
            closed += [(R, manual), (R, pin.rpy.rpyToMatrix(ps, th, ph))]
            atan.append((rot.wrap_angle(np.arctan2(-R[1, 2], R[1, 1]) - g), 0.0))
            for branch in (1, -1):
                res = rot.rotation_to_rpy(R, branch)
                flags.append(res.singular)
                rep.append((rot.rpy_to_rotation(res.angles), R))
    sol.check("closed_forms_theta_pm_pi_2", max_error(closed) < 1e-12,
              f"manual matrices and pin.rpy.rpyToMatrix: max |error| = {max_error(closed):.2e}")
    sol.check("psi_pm_phi_is_atan2(-r23, r22)", max_error(atan) < 1e-9,
              f"+ for theta = -pi/2, - for theta = pi/2; max error (mod 2pi) = {max_error(atan):.2e}")
    sol.check("singularity_flagged", all(flags), f"{sum(flags)}/{len(flags)} inverses flagged singular")
    sol.check_error("representative_reproduces_R", max_error(rep), 1e-12, reference="closed form")
    return sol


@problem("2.4", "Rotation about an arbitrary axis (2.25)", kind="derivation")
def problem_2_4() -> Solution:
    """Verify (2.25): R(θ, r) = Rz(α) Ry(β) Rz(θ) Ry(−β) Rz(−α) (2.24) with r = [cα sβ, sα sβ, cβ].

    The five-factor product, the manual's row-by-row expansion, (2.25) and Pinocchio's exp3(θ r)
    are compared at random axes and angles.
    """
    sol = Solution()
    rng = np.random.default_rng(24)
    pairs = []
    for _ in range(N_RANDOM):
        r, th = unit(rng.normal(size=3)), rng.uniform(-np.pi, np.pi)
        al, be = np.arctan2(r[1], r[0]), np.arctan2(np.hypot(r[0], r[1]), r[2])
        product = rot.rot_z(al) @ rot.rot_y(be) @ rot.rot_z(th) @ rot.rot_y(-be) @ rot.rot_z(-al)
        ca, sa, cb, sb, ct, st = c(al), s(al), c(be), s(be), c(th), s(th)
        rows = np.array([
            [(sa**2 + ca**2 * cb**2) * ct + ca**2 * sb**2, sa * ca * sb**2 * (1 - ct) - cb * st,
             ca * sb * cb * (1 - ct) + sa * sb * st],
            [sa * ca * sb**2 * (1 - ct) + cb * st, (sa**2 * cb**2 + ca**2) * ct + sa**2 * sb**2,
             sa * sb * cb * (1 - ct) - ca * sb * st],
            [ca * sb * cb * (1 - ct) - sa * sb * st, sa * sb * cb * (1 - ct) + ca * sb * st, sb**2 * ct + cb**2]])
        R = rot.axis_angle_to_rotation(th, r)
        pairs += [(R, product), (R, rows), (R, pin.exp3(th * r))]
    sol.check("rodrigues_equals_five_factor_product", max_error(pairs) < 1e-12,
              f"(2.25) vs (2.24), the manual's expansion and pin.exp3: max |error| = {max_error(pairs):.2e}")
    sol.value("R_pi_3_about_111", rot.axis_angle_to_rotation(np.pi / 3, unit(np.ones(3))), unit="1")
    return sol


@problem("2.5", "Inverse axis–angle problem, including sin θ = 0", kind="derivation")
def problem_2_5() -> Solution:
    """Prove (2.27)–(2.28) and find the inverse when sin θ = 0.

    θ = acos((r11 + r22 + r33 − 1)/2), r = [r32 − r23, r13 − r31, r21 − r12]/(2 sin θ). At θ = π,
    R = 2 r r^T − I: r from the column of the largest diagonal element (r_x = ±√((r11 + 1)/2) fails at
    r_x = 0); at θ = 0 the axis is arbitrary. Checked against Pinocchio's log3 and by recomposition.
    """
    sol = Solution()
    rng = np.random.default_rng(25)
    pairs, manual = [], []
    for _ in range(N_RANDOM):
        R = random_rotation(rng)
        th, r = rot.rotation_to_axis_angle(R)
        manual_th = np.arccos((np.trace(R) - 1) / 2)
        manual_r = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (2 * np.sin(manual_th))
        manual += [(th, manual_th), (r, manual_r), (th * r, pin.log3(R))]
        pairs.append((rot.axis_angle_to_rotation(th, r), R))
    sol.check_error("general_case_matches_2_27_and_log3", max_error(manual), 1e-8, reference="other library")
    pi_axes = [np.array(v, float) for v in ([0, 1, 0], [0, 1 / np.sqrt(2), 1 / np.sqrt(2)], [1, 0, 0],
                                             [0.6, 0, -0.8])] + [unit(rng.normal(size=3)) for _ in range(10)]
    pi_err = []
    for r in pi_axes:
        R = rot.axis_angle_to_rotation(np.pi, r)
        pairs.append((R, 2 * np.outer(r, r) - np.eye(3)))  # R(π, r) of the manual
        th, r_hat = rot.rotation_to_axis_angle(R)
        pi_err.append(min(np.linalg.norm(r_hat - r), np.linalg.norm(r_hat + r)) + abs(th - np.pi))
    sol.check("theta_pi_returns_plus_minus_r", max(pi_err) < 1e-12,
              f"{len(pi_axes)} axes incl. r_x = 0: max error {max(pi_err):.2e} (largest-diagonal column)")
    th0, r0 = rot.rotation_to_axis_angle(np.eye(3))
    sol.check("theta_zero_any_unit_axis", th0 == 0.0 and abs(np.linalg.norm(r0) - 1) < 1e-15, f"theta = {th0}")
    sol.check_error("recomposition", max_error(pairs), 1e-12, reference="closed form")
    return sol


@problem("2.6", "Rotation matrix of a unit quaternion (2.33)", kind="derivation")
def problem_2_6() -> Solution:
    """Verify (2.33) from (2.25) with η = cos(θ/2), ε = sin(θ/2) r (2.30)–(2.31): c_θ = 2η² − 1,
    r_i s_θ = 2η ε_i, r_i r_j (1 − c_θ) = 2 ε_i ε_j. Compared with Pinocchio's quaternion matrix."""
    sol = Solution()
    rng = np.random.default_rng(26)
    pairs = []
    for _ in range(N_RANDOM):
        r, th = unit(rng.normal(size=3)), rng.uniform(-np.pi, np.pi)
        eta, eps = np.cos(th / 2), np.sin(th / 2) * r
        R = rot.quaternion_to_rotation(np.concatenate([[eta], eps]))
        pairs += [(R, rot.axis_angle_to_rotation(th, r)), (R, pin.Quaternion(eta, *eps).toRotationMatrix()),
                  (np.cos(th), 2 * eta**2 - 1), (r * np.sin(th), 2 * eta * eps),
                  (np.outer(r, r) * (1 - np.cos(th)), 2 * np.outer(eps, eps))]
    sol.check("quaternion_matrix_equals_axis_angle", max_error(pairs) < 1e-12,
              f"(2.33) vs (2.25), pin.Quaternion and the three identities: max |error| = {max_error(pairs):.2e}")
    return sol


@problem("2.7", "ε is invariant under R(η, ε) and its transpose", kind="derivation")
def problem_2_7() -> Solution:
    """Show R(η, ε) ε = R^T(η, ε) ε = ε: ε is parallel to the rotation axis r, and R r = R^T r = r."""
    sol = Solution()
    rng = np.random.default_rng(27)
    pairs = []
    for _ in range(N_RANDOM):
        Q = random_quaternion(rng)
        R = rot.quaternion_to_rotation(Q)
        pairs += [(R @ Q[1:], Q[1:]), (R.T @ Q[1:], Q[1:])]
    sol.check_error("R_eps_equals_eps", max_error(pairs), 1e-12, reference="closed form")
    return sol


@problem("2.8", "Unit quaternion from a rotation matrix (2.34)–(2.35)", kind="derivation")
def problem_2_8() -> Solution:
    """Prove (2.34)–(2.35): r11 + r22 + r33 + 1 = 4η² by (2.32), and ½ sgn(r32 − r23)√(r11 − r22 − r33 + 1) = ε_x.

    Erratum: the manual prints the left-hand side of the first identity as "½√(r11+r22+r33+1)"; the
    identity is r11 + r22 + r33 + 1 = 6η² + 2 εᵀε − 2 (= 4η²). The library's inverse is the robust
    (largest-component) form of (2.34)–(2.35); where η is not small it equals the book's sgn formula.
    """
    sol = Solution()
    rng = np.random.default_rng(28)
    ident, book, trip, signs = [], [], [], []
    sgn = lambda x: 1.0 if x >= 0 else -1.0  # noqa: E731 (the book's sgn)
    for _ in range(N_RANDOM):
        Q = random_quaternion(rng)
        R = rot.quaternion_to_rotation(Q)
        eta, eps = Q[0], Q[1:]
        ident.append((np.trace(R) + 1, 6 * eta**2 + 2 * eps @ eps - 2))
        ident.append((np.trace(R) + 1, 4 * eta**2))
        Q_hat = rot.rotation_to_quaternion(R)
        signs.append(Q_hat[0] >= 0)
        trip.append((rot.quaternion_to_rotation(Q_hat), R))
        trip.append((min(np.linalg.norm(Q_hat - Q), np.linalg.norm(Q_hat + Q)), 0.0))
        pq = pin.Quaternion(R)
        pq_vec = np.array([pq.w, pq.x, pq.y, pq.z])
        trip.append((min(np.linalg.norm(Q_hat - pq_vec), np.linalg.norm(Q_hat + pq_vec)), 0.0))
        if abs(eta) > 0.1:
            e_book = 0.5 * np.array([sgn(R[2, 1] - R[1, 2]) * np.sqrt(max(R[0, 0] - R[1, 1] - R[2, 2] + 1, 0)),
                                     sgn(R[0, 2] - R[2, 0]) * np.sqrt(max(R[1, 1] - R[2, 2] - R[0, 0] + 1, 0)),
                                     sgn(R[1, 0] - R[0, 1]) * np.sqrt(max(R[2, 2] - R[0, 0] - R[1, 1] + 1, 0))])
            book.append((Q_hat, np.concatenate([[0.5 * np.sqrt(np.trace(R) + 1)], e_book])))
    near_pi = [rot.axis_angle_to_rotation(np.pi - e, unit(rng.normal(size=3))) for e in (0.0, 1e-12, 1e-8)]
    trip += [(rot.quaternion_to_rotation(rot.rotation_to_quaternion(R)), R) for R in near_pi]
    sol.check("trace_identity", max_error(ident) < 1e-12,
              f"tr R + 1 = 6 eta^2 + 2 eps'eps - 2 = 4 eta^2; max |error| = {max_error(ident):.2e} "
              "(manual erratum: LHS printed as 1/2 sqrt(r11+r22+r33+1))")
    sol.check("eta_nonnegative", all(signs), "eta >= 0 for every sample")
    sol.check("matches_book_formula_2_34_2_35", max_error(book) < 1e-8,
              f"{len(book)} samples with |eta| > 0.1: max |error| = {max_error(book):.2e}")
    sol.check("round_trip_and_pinocchio", max_error(trip) < 1e-12,
              f"incl. eta ~ 0 (theta = pi - {{0, 1e-12, 1e-8}}): max |error| = {max_error(trip):.2e}")
    return sol


@problem("2.9", "Quaternion product (2.37)", kind="derivation")
def problem_2_9() -> Solution:
    """Show that Q1 ∗ Q2 = {η1η2 − ε1ᵀε2, η1ε2 + η2ε1 + ε1 × ε2} (2.37) is the quaternion of R1 R2.

    The manual's trace identity ¼(r11 + r22 + r33 + 1) = (η1η2 − ε1ᵀε2)² is checked too, and the
    product is compared with Pinocchio's quaternion product.
    """
    sol = Solution()
    rng = np.random.default_rng(29)
    pairs = []
    for _ in range(N_RANDOM):
        Q1, Q2 = random_quaternion(rng), random_quaternion(rng)
        R = rot.quaternion_to_rotation(Q1) @ rot.quaternion_to_rotation(Q2)
        Q = rot.quaternion_product(Q1, Q2)
        pq = pin.Quaternion(*Q1) * pin.Quaternion(*Q2)
        pairs += [(rot.quaternion_to_rotation(Q), R), (0.25 * (np.trace(R) + 1), Q[0] ** 2),
                  (Q, [pq.w, pq.x, pq.y, pq.z])]
    sol.check("product_is_composition", max_error(pairs) < 1e-12,
              f"R(Q1*Q2) = R1 R2, trace identity, pin product: max |error| = {max_error(pairs):.2e}")
    return sol


@problem("2.10", "Inverse of a homogeneous transformation (2.45)", kind="derivation")
def problem_2_10() -> Solution:
    """Prove (2.45) from the block inverse [[A, D], [O, B]]⁻¹ = [[A⁻¹, −A⁻¹ D B⁻¹], [O, B⁻¹]] with
    A = R, D = o, B = 1. Compared with numpy's general inverse and Pinocchio's SE3 inverse."""
    sol = Solution()
    rng = np.random.default_rng(30)
    pairs = []
    for _ in range(N_RANDOM):
        T = rot.homogeneous_transform(random_rotation(rng), rng.uniform(-2, 2, 3))
        Ti = rot.homogeneous_inverse(T)
        pairs += [(Ti, np.linalg.inv(T)), (Ti, pin.SE3(T).inverse().homogeneous), (Ti @ T, np.eye(4))]
    sol.check_error("inverse_matches_linalg_and_se3", max_error(pairs), 1e-12, reference="other library")
    return sol


# --------------------------------------------------------------------------------------------
# 2.11–2.14: direct kinematics
# --------------------------------------------------------------------------------------------

CLOSED_CHAIN = FourLinkClosedChain(a1p=0.2, a2p=0.6, a1pp=0.3, d4=0.1)  # test lengths (spec), a1' + a1'' <= a2'


@problem("2.11", "Direct kinematics of the four-link closed-chain planar arm", kind="derivation")
def problem_2_11() -> Solution:
    """Direct kinematics of the closed-chain planar arm of Fig. 2.38 with joint 4 as cut joint (Table S2.1).

    Both branches are built as one tree URDF (Pinocchio); at random actuated q = [θ1', θ1''] and both
    signs of s3', the joints from (S2.1)–(S2.2) close the loop: the constraints (2.60) on the Pinocchio
    frame poses vanish. The manual's A_{3'}^{2'}, A_{3'}^0 and A_{1''}^0 are compared with Pinocchio.
    Lengths a1' = 0.2, a2' = 0.6, a1'' = 0.3, d4 = 0.1 m are test values (symbolic in the manual).
    """
    sol = Solution()
    rng = np.random.default_rng(211)
    chain = CLOSED_CHAIN
    robot = robot_from_dh_tree(chain.branches(), name="closed_chain_four_link", ee="b1_ee")
    a1p, a2p, a1pp, d4 = sol.given("[a1', a2', a1'', d4]", np.array([chain.a1p, chain.a2p, chain.a1pp, chain.d4]),
                                   unit="m")
    residual, forms = [], []
    for q in rng.uniform(-np.pi, np.pi, (N_RANDOM, 2)):
        for sign in (1, -1):
            th1, th2, th3, th1pp = closed_chain_joints(chain, q, sign)
            T3, T1pp, T4 = frame_poses(robot, [th1, th2, th3, th1pp], ["b1_frame_3", "b2_frame_1", "b1_ee"])
            residual.append(np.max(np.abs(loop_constraint_residual(T3, T1pp))))
            t = th1 + th2 + th3
            A3_0 = np.array([[c(t), 0, s(t), a1p * c(th1) + a2p * c(th1 + th2)],
                             [s(t), 0, -c(t), a1p * s(th1) + a2p * s(th1 + th2)], [0, 1, 0, 0], [0, 0, 0, 1]])
            A1pp_0 = np.array([[c(th1pp), 0, -s(th1pp), a1pp * c(th1pp)], [s(th1pp), 0, c(th1pp), a1pp * s(th1pp)],
                               [0, -1, 0, 0], [0, 0, 0, 1]])
            A32 = np.array([[c(th3), 0, s(th3), 0], [s(th3), 0, -c(th3), 0], [0, 1, 0, 0], [0, 0, 0, 1]])
            A4 = np.eye(4)
            A4[2, 3] = d4
            forms += [(T3, A3_0), (T1pp, A1pp_0), (T4, A3_0 @ A4), (closed_chain_direct_kinematics(chain, q, sign), T4),
                      (dh_transform(0.0, np.pi / 2, 0.0, th3), A32)]
    sol.check("loop_constraints_2_60_hold", max(residual) < 1e-12,
              f"(S2.1)-(S2.2) joints on the Pinocchio tree: max constraint residual {max(residual):.2e}")
    sol.check("A_matrices_match_manual", max_error(forms) < 1e-12,
              f"A_3'^2', A_3'^0, A_1''^0, T_4^0 = A_3'^0 A_4^3' vs Pinocchio: max |error| = {max_error(forms):.2e}",
              reference="closed form")
    grid = np.linspace(-np.pi, np.pi, 25)
    closes = all(np.all(np.isfinite(closed_chain_joints(chain, [x, y]))) for x in grid for y in grid)
    sol.check("solution_exists_everywhere_when_a1p_plus_a1pp_le_a2p", closes,
              f"a1' + a1'' = {a1p + a1pp} <= a2' = {a2p}: the loop closes on a 25x25 grid of q")
    too_long = FourLinkClosedChain(a1p=0.4, a2p=0.6, a1pp=0.3, d4=0.1)
    fails = 0
    for x in grid:
        try:
            closed_chain_joints(too_long, [x, 0.0])
        except ValueError:
            fails += 1
    sol.check("no_solution_somewhere_when_a1p_plus_a1pp_gt_a2p", fails > 0,
              f"a1' + a1'' = 0.7 > a2' = 0.6: the loop cannot close at {fails}/25 values of theta1'")
    sol.value("T_40_at_q0", closed_chain_direct_kinematics(chain, [0.3, 0.5]), unit="1 (R), m (o)")
    return sol


def _random_postures(name: str, seed: int) -> tuple[Any, np.ndarray]:
    """The book robot ``name`` and N_RANDOM configurations drawn (seeded) uniformly within its joint ranges."""
    robot = load(name)
    return robot, np.random.default_rng(seed).uniform(robot.lower, robot.upper, (N_RANDOM, len(robot.lower)))


@problem("2.12", "Direct kinematics of the cylindrical arm", kind="derivation")
def problem_2_12() -> Solution:
    """Direct kinematics of the cylindrical arm of Fig. 2.35 with the DH table S2.2.

    T_3^0 = [[c1, 0, −s1, −d3 s1], [s1, 0, c1, d3 c1], [0, −1, 0, d2], [0, 0, 0, 1]] (manual) vs
    Pinocchio on ``urdf/cylindrical.urdf`` at random q within the joint ranges.
    """
    sol = Solution()
    robot, postures = _random_postures("cylindrical", 212)
    pairs = []
    for q in postures:
        th1, d2, d3 = q
        manual = [[c(th1), 0, -s(th1), -d3 * s(th1)], [s(th1), 0, c(th1), d3 * c(th1)], [0, -1, 0, d2], [0, 0, 0, 1]]
        A1 = [[c(th1), -s(th1), 0, 0], [s(th1), c(th1), 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
        A2 = [[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, d2], [0, 0, 0, 1]]
        A3 = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, d3], [0, 0, 0, 1]]
        T1, T2, T3 = frame_poses(robot, q, ["frame_1", "frame_2", "frame_3"])
        pairs += [(T3, manual), (T1, A1), (T2, np.array(A1) @ A2), (T3, np.array(A1) @ A2 @ A3),
                  (direct_kinematics(robot, q), manual)]
    sol.check("pinocchio_equals_manual_T30", max_error(pairs) < 1e-12,
              f"{N_RANDOM} random q: max |error| = {max_error(pairs):.2e}", reference="closed form")
    sol.figure(frames_figure(robot, [0.5, 0.4, 0.5], "Fig. S2.2 — DH frames of the cylindrical arm (θ1 = 0.5, d2 = 0.4, d3 = 0.5)"))
    return sol


@problem("2.13", "Direct kinematics of the SCARA manipulator", kind="derivation")
def problem_2_13() -> Solution:
    """Direct kinematics of the SCARA of Fig. 2.36 (Table S2.3, axes pointing down), Eq. (S2.3):
    T_4^0 = [[c124, −s124, 0, a1 c1 + a2 c12], [s124, c124, 0, a1 s1 + a2 s12], [0, 0, 1, d3], [0, 0, 0, 1]].
    Compared with Pinocchio on ``urdf/scara.urdf`` (root = DH frame 0, z₀ down); a1 = a2 = 0.5 m."""
    sol = Solution()
    robot, postures = _random_postures("scara", 213)
    a1 = a2 = sol.given("a1 = a2", 0.5, unit="m")
    pairs = []
    for q in postures:
        t1, t2, d3, t4 = q
        t = t1 + t2 + t4
        manual = [[c(t), -s(t), 0, a1 * c(t1) + a2 * c(t1 + t2)], [s(t), c(t), 0, a1 * s(t1) + a2 * s(t1 + t2)],
                  [0, 0, 1, d3], [0, 0, 0, 1]]
        pairs.append((direct_kinematics(robot, q), manual))
    sol.check("pinocchio_equals_S2_3", max_error(pairs) < 1e-12, f"{N_RANDOM} random q: max |error| = "
              f"{max_error(pairs):.2e} (a three-link planar arm with a3 = 0, theta4 for theta3, z = d3)")
    sol.figure(frames_figure(robot, [0.4, 0.8, 0.2, 0.3], "Fig. S2.3 — DH frames of the SCARA (z0 down; q = [0.4, 0.8, 0.2, 0.3])",
                             z_down=True))
    return sol


@problem("2.14", "Complete direct kinematics of the humanoid manipulator", kind="derivation")
def problem_2_14() -> Solution:
    """Direct kinematics of the humanoid of Fig. 2.28: T_lh^0 = T_3^0 T_t^3 T_l^t T_lh^l, T_rh^0 likewise (2.78)–(2.79).

    The torso is the anthropomorphic arm (2.66); T_l^t, T_r^t as in the manual (β, d_l, d_r). The tree
    (torso + two 7-DOF arms) is one URDF; Pinocchio's hand poses are compared with the matrix products.
    Inferred data (not in the manual): the arm table (2.77) is taken as the DLR table with α_i = −π/2, the torso
    frame t as frame 3 rotated (T_t^3 below), and β = π/6, d_l = d_r = 0.3, d3 = d5 = 0.4, d7 = 0.1,
    a2 = a3 = 0.3 are test values.
    """
    sol = Solution()
    rng = np.random.default_rng(214)
    T_t3 = np.eye(4)
    T_t3[:3, :3] = rot.rot_y(np.pi / 2)  # an arbitrary constant torso frame (not given in the manual)
    T_t3[:3, 3] = [0.05, 0.0, 0.0]
    hum = Humanoid(T_t3=sol.given("T_t3", T_t3))
    sol.given("[a2, a3]", np.array([hum.a2, hum.a3]), unit="m")
    T_l, T_r = hum.shoulders()
    robot = hum.robot()
    proper = all(np.allclose(T[:3, :3].T @ T[:3, :3], np.eye(3)) and np.isclose(np.linalg.det(T[:3, :3]), 1.0)
                 for T in (T_l, T_r))
    sol.check("R_lt_R_rt_are_rotations", proper, "orthonormal with det +1 (x × y = z)")
    sol.check("z_l_and_z_r_point_along_the_shoulders",
              np.allclose(T_l[:3, 2], T_l[:3, 3] / hum.d_l) and np.allclose(T_r[:3, 2], T_r[:3, 3] / hum.d_r),
              "z_l ∥ o_tl = d_l [cβ, 0, sβ], z_r ∥ o_tr = d_r [cβ, 0, −sβ]")
    mirror = np.diag([1.0, 1.0, -1.0, 1.0]) @ T_l @ np.diag([1.0, -1.0, 1.0, 1.0])
    sol.check_close("right_shoulder_is_mirror_of_left", mirror, T_r, atol=1e-15, reference="closed form")
    pairs, torso = [], []
    for _ in range(N_RANDOM):
        q = rng.uniform(-np.pi, np.pi, robot.nq)
        T3, T_lh, T_rh = frame_poses(robot, q, ["torso_frame_3", "left_ee", "right_ee"])
        t1, t2, t3 = q[:3]
        a2, a3 = hum.a2, hum.a3
        c23, s23 = c(t2 + t3), s(t2 + t3)
        manual_T3 = [[c(t1) * c23, -c(t1) * s23, s(t1), c(t1) * (a2 * c(t2) + a3 * c23)],
                     [s(t1) * c23, -s(t1) * s23, -c(t1), s(t1) * (a2 * c(t2) + a3 * c23)],
                     [s23, c23, 0, a2 * s(t2) + a3 * s23], [0, 0, 0, 1]]  # (2.66)
        torso.append((T3, manual_T3))
        A_l, A_r = hum.hand_poses(q)
        pairs += [(T_lh, A_l), (T_rh, A_r)]
    sol.check_error("torso_is_anthropomorphic_2_66", max_error(torso), 1e-12, reference="closed form")
    sol.check("hand_poses_equal_2_78_2_79", max_error(pairs) < 1e-12,
              f"Pinocchio tree vs T_3^0 T_t^3 T_l^t T_lh^l and T_3^0 T_t^3 T_r^t T_rh^r: max |error| = "
              f"{max_error(pairs):.2e} ({N_RANDOM} random q, nq = {robot.nq})")
    sol.value("T_lt", T_l, unit="1 (R), m (o)")
    sol.value("T_rt", T_r, unit="1 (R), m (o)")
    return sol


# --------------------------------------------------------------------------------------------
# 2.15–2.17
# --------------------------------------------------------------------------------------------

@problem("2.15", "Non-commutativity of the sum of Euler-angle triplets", kind="numeric")
def problem_2_15() -> Solution:
    """Define the 'sum' of minimal orientation representations by composing rotations and show it is
    not commutative: ZYZ φ1 = [π/2, π/2, 0], φ2 = [−π/2, −π/2, 0] (manual data). R(φ1)R(φ2) ≠ R(φ2)R(φ1),
    with the two ZYZ sets of each from (2.19)–(2.20); the plain sum φ1 + φ2 = 0 gives I."""
    sol = Solution()
    phi1 = sol.given("phi1", np.array([np.pi / 2, np.pi / 2, 0.0]), unit="rad")
    phi2 = sol.given("phi2", np.array([-np.pi / 2, -np.pi / 2, 0.0]), unit="rad")
    R1 = sol.value("R1", rot.euler_zyz_to_rotation(phi1), unit="1")
    R2 = sol.value("R2", rot.euler_zyz_to_rotation(phi2), unit="1")
    R1R2 = sol.value("R1R2", R1 @ R2, unit="1")
    R2R1 = sol.value("R2R1", R2 @ R1, unit="1")
    e12 = sol.value("euler_R1R2", np.array([rot.rotation_to_euler_zyz(R1R2, b).angles for b in (1, -1)]), unit="rad")
    e21 = sol.value("euler_R2R1", np.array([rot.rotation_to_euler_zyz(R2R1, b).angles for b in (1, -1)]), unit="rad")
    h = np.pi / 2
    sol.check_close("R1", R1, [[0, -1, 0], [0, 0, 1], [-1, 0, 0]], atol=1e-15, reference="manual number")
    sol.check_close("R2", R2, [[0, 1, 0], [0, 0, 1], [1, 0, 0]], atol=1e-15, reference="manual number")
    sol.check_close("R1R2_current_frame", R1R2, [[0, 0, -1], [1, 0, 0], [0, -1, 0]], atol=1e-15,
                    reference="manual number")
    sol.check_close("R2R1_fixed_frame", R2R1, [[0, 0, 1], [-1, 0, 0], [0, -1, 0]], atol=1e-15,
                    reference="manual number")
    sol.check_close("euler_R1R2_mod_2pi", rot.wrap_angle(e12 - [[np.pi, h, -h], [0, -h, h]]), np.zeros((2, 3)), atol=1e-12,
                    reference="manual number")
    sol.check_close("euler_R2R1_mod_2pi", rot.wrap_angle(e21 - [[0, h, -h], [np.pi, -h, h]]), np.zeros((2, 3)), atol=1e-12,
                    reference="manual number")
    sol.check("not_commutative", np.max(np.abs(R1R2 - R2R1)) > 0.5, f"max |R1R2 - R2R1| = {np.max(np.abs(R1R2 - R2R1)):g}")
    R_sum = sol.value("R_phi1_plus_phi2", rot.euler_zyz_to_rotation(phi1 + phi2), unit="1")
    sol.check_close("direct_sum_gives_identity", R_sum, np.eye(3), atol=1e-15, reference="closed form")
    _zyz_generic_check(sol, np.random.default_rng(2215))
    return sol


@problem("2.16", "Infinitesimal rotations commute", kind="derivation")
def problem_2_16() -> Solution:
    """Show that rotations by infinitesimal angles commute: Rx(dφx) Ry(dφy) ≈ Ry Rx ≈ I + S(dφ) and
    R(dφ) R(dφ') = R(dφ + dφ') to first order. The neglected terms are checked to be O(ε²): their
    size divided by ε² stays bounded as ε goes from 1e-2 to 1e-4 (random directions)."""
    sol = Solution()
    rng = np.random.default_rng(216)
    ratios = {"commutator": [], "first_order_matrix": [], "composition": []}
    for eps in (1e-2, 1e-3, 1e-4):
        worst = dict.fromkeys(ratios, 0.0)
        for _ in range(20):
            d = eps * unit(rng.normal(size=3))
            dp = eps * unit(rng.normal(size=3))
            Rx, Ry, Rz = rot.rot_x(d[0]), rot.rot_y(d[1]), rot.rot_z(d[2])
            first = np.eye(3) + rot.skew(d)  # R(dφx, dφy, dφz) of the manual
            R_of = lambda v: rot.rot_x(v[0]) @ rot.rot_y(v[1]) @ rot.rot_z(v[2])  # noqa: E731
            worst["commutator"] = max(worst["commutator"], np.max(np.abs(Rx @ Ry - Ry @ Rx)) / eps**2)
            worst["first_order_matrix"] = max(worst["first_order_matrix"], np.max(np.abs(Rx @ Ry @ Rz - first)) / eps**2)
            worst["composition"] = max(worst["composition"], np.max(np.abs(R_of(d) @ R_of(dp) - R_of(d + dp))) / eps**2)
        for k in ratios:
            ratios[k].append(worst[k])
    for k, r in ratios.items():
        sol.check(f"{k}_is_O(eps^2)", max(r) < 2.0 and r[-1] > 1e-3,
                  "max error / eps^2 at eps = 1e-2, 1e-3, 1e-4: " + ", ".join(f"{x:.3f}" for x in r))
    sol.value("error_over_eps2", {k: np.array(v) for k, v in ratios.items()}, unit="1/rad²")
    return sol


@problem("2.17", "Workspace of a three-link planar arm with joint limits", kind="numeric")
def problem_2_17() -> Solution:
    """Draw the reachable workspace of the three-link planar arm of Fig. 2.20 with
    −π/3 ≤ q1 ≤ π/3, −2π/3 ≤ q2 ≤ 2π/3, −π/2 ≤ q3 ≤ π/2 (manual) and a = (0.5, 0.3, 0.2) m
    (recalled from the textbook, not in the manual). The manual's construction: the 18 configurations
    where mobility is lost (joint-limit corners A–H, θ2 = 0: I–L, θ3 = 0: M–P, both: Q, R) joined by
    single-joint arcs; the outer contour AMQRPHEDA delimits the workspace (Fig. S2.4).
    Checks: 200 000 uniform joint samples lie inside the contour, the interior is covered, the maximum
    radius a1 + a2 + a3 is attained on arc QR, H, E, D, A lie on one circle, the region is symmetric.
    """
    sol = Solution()
    rng = np.random.default_rng(217)
    robot = load("planar_3r")
    a = sol.given("a", np.array([0.5, 0.3, 0.2]), unit="m")
    lo, up = sol.given("q_min", robot.lower, unit="rad"), sol.given("q_max", robot.upper, unit="rad")
    names = "ABCDEFGH"
    configs = {names[k]: np.array([[lo[0], up[0]][k >> 2], [lo[1], up[1]][(k >> 1) & 1], [lo[2], up[2]][k & 1]])
               for k in range(8)}
    for name, (q1, q3) in zip("IJKL", [(lo[0], lo[2]), (lo[0], up[2]), (up[0], lo[2]), (up[0], up[2])]):
        configs[name] = np.array([q1, 0.0, q3])
    for name, (q1, q2) in zip("MNOP", [(lo[0], lo[1]), (lo[0], up[1]), (up[0], lo[1]), (up[0], up[1])]):
        configs[name] = np.array([q1, q2, 0.0])
    configs["Q"], configs["R"] = np.array([lo[0], 0.0, 0.0]), np.array([up[0], 0.0, 0.0])
    # (2.63) closed form vs Pinocchio at the 18 configurations
    pts, fk_pairs = {}, []
    for name, q in configs.items():
        cum = np.cumsum(q)
        closed = np.array([a @ np.cos(cum), a @ np.sin(cum)])
        pts[name] = direct_kinematics(robot, q)[:2, 3]
        fk_pairs.append((pts[name], closed))
    sol.check("configurations_fk_match_2_63", max_error(fk_pairs) < 1e-12,
              f"18 configurations: max |error| = {max_error(fk_pairs):.2e}")
    contour = planar_3r_workspace_contour(robot)
    poly = contour.points
    samples = workspace_points(robot, N_WORKSPACE, rng)[:, :2]
    inside = PolygonPath(poly).contains_points(samples)
    outside_dist = polyline_distance(samples[~inside], poly) if np.any(~inside) else np.zeros(1)
    sol.check("samples_inside_contour_AMQRPHEDA", float(np.max(outside_dist)) < 1e-3,
              f"{int(inside.sum())}/{N_WORKSPACE} strictly inside; the others within {np.max(outside_dist):.1e} m of the "
              "contour (arc chords)")
    xs, ys = np.meshgrid(np.linspace(-1, 1, 81), np.linspace(-1, 1, 81))
    grid = np.column_stack([xs.ravel(), ys.ravel()])
    grid = grid[PolygonPath(poly).contains_points(grid)]
    grid = grid[polyline_distance(grid, poly) > 0.015]
    gap = cKDTree(samples).query(grid)[0]
    sol.check("interior_is_covered", float(np.max(gap)) < 0.015,
              f"{len(grid)} grid points inside (> 0.015 m from the contour): nearest sample within {np.max(gap):.4f} m")
    r_contour = np.linalg.norm(poly, axis=1)
    sol.check_close("max_radius_is_a1_a2_a3", np.max(r_contour), a.sum(), atol=1e-12, reference="closed form")
    sol.check("samples_within_max_radius", float(np.max(np.linalg.norm(samples, axis=1))) <= a.sum() + 1e-12,
              f"max sample radius {np.max(np.linalg.norm(samples, axis=1)):.6f} <= {a.sum()}")
    qr = joint_arc(robot, configs["Q"], 0, up[0], 50)[:, :2]
    sol.check_close("arc_QR_has_radius_a1_a2_a3", np.linalg.norm(qr, axis=1), np.full(50, a.sum()), atol=1e-12,
                    reference="closed form")
    radii = [np.linalg.norm(pts[k]) for k in "HEDA"]
    sol.check_close("H_E_D_A_on_one_circle", np.array(radii), np.full(4, radii[0]), atol=1e-12, reference="closed form")
    mirrored = poly * [1.0, -1.0]
    sym = max(float(np.max(polyline_distance(mirrored, poly))), float(np.max(polyline_distance(poly, mirrored))))
    mirrored_inside = PolygonPath(poly).contains_points(samples * [1.0, -1.0])
    sol.check("symmetric_about_x_axis", sym < 1e-3 and mirrored_inside.mean() == inside.mean(),
              f"Hausdorff(contour, mirror) = {sym:.1e} m; mirrored samples inside: {mirrored_inside.mean():.4f} "
              f"vs {inside.mean():.4f}")
    area = 0.5 * abs(np.dot(poly[:-1, 0], poly[1:, 1]) - np.dot(poly[1:, 0], poly[:-1, 1]))
    sol.value("area", area, unit="m²")
    sol.value("corners", {k: v for k, v in pts.items()}, unit="m")
    sol.value("radius_inner_circle", radii[0], unit="m")

    fig, ax = subplots(figsize=(6.5, 6.5))
    ax.plot(samples[::20, 0], samples[::20, 1], ".", ms=1, color="0.75", label="random joint samples")
    for n1, q1 in configs.items():  # all single-joint arcs between the special configurations
        for n2, q2 in configs.items():
            diff = np.flatnonzero(~np.isclose(q1, q2))
            if n1 < n2 and diff.size == 1:
                arc = joint_arc(robot, q1, int(diff[0]), q2[diff[0]], 40)
                ax.plot(arc[:, 0], arc[:, 1], lw=0.6, color="tab:blue", alpha=0.6)
    ax.plot(poly[:, 0], poly[:, 1], lw=2.0, color="tab:red", label="contour AMQRPHEDA")
    for name, p in pts.items():
        ax.annotate(name, p, textcoords="offset points", xytext=(3, 3), fontsize=8)
        ax.plot(*p, "k.", ms=4)
    ax.set_aspect("equal")
    label_axes(ax, "x [m]", "y [m]", legend="lower left", grid=False, fontsize=8)
    sol.figure(fig, "Problem 2.17 / Fig. S2.4: reachable workspace of the three-link planar arm")
    return sol


# --------------------------------------------------------------------------------------------
# 2.18–2.20: inverse kinematics
# --------------------------------------------------------------------------------------------

@problem("2.18", "Anthropomorphic arm IK: solutions in the singular cases", kind="derivation")
def problem_2_18() -> Solution:
    """Number of IK solutions of the anthropomorphic arm (Sect. 2.12.4) when s3 = 0 and p_Wx = p_Wy = 0.

    c3 = 1 (outstretched): θ2,I = θ2,III = Atan2(pWz, √(pWx² + pWy²)) (S2.4), θ2,II = θ2,IV with −√ (S2.5);
    c3 = −1 (retracted): (S2.6)–(S2.7) with the factor (a2 − a3); two distinct solutions off the z0 axis;
    on the axis p_Wz = ±(a2 + a3) or ±|a2 − a3|, θ2 = ±π/2 and θ1 arbitrary; a2 = a3 → p_W = 0 and θ1, θ2
    arbitrary. Test lengths a2 = 0.5, a3 = 0.4 and a2 = a3 = 0.5 (not in the manual); FK by Pinocchio.
    """
    sol = Solution()
    rng = np.random.default_rng(218)
    a2, a3 = sol.given("a2", 0.5, unit="m"), sol.given("a3", 0.4, unit="m")
    robot = load("anthropomorphic", a2=a2, a3=a3)
    counts, fk, manual = [], [], []
    for th3, (fa, fb) in ((0.0, (1.0, 1.0)), (np.pi, (a2 - a3, a2 - a3))):
        for _ in range(10):
            q = np.array([rng.uniform(-np.pi, np.pi), rng.uniform(-1.4, 1.4), th3])
            p = direct_kinematics(robot, q)[:3, 3]
            qs = inverse_kinematics_anthropomorphic(p, a2=a2, a3=a3)
            counts.append(len(distinct_solutions(qs)))
            fk += [(direct_kinematics(robot, qk)[:3, 3], p) for qk in qs]
            rho = np.hypot(p[0], p[1])
            manual += [(rot.wrap_angle(qs[0, 1] - np.arctan2(fa * p[2], fb * rho)), 0.0),  # (S2.4)/(S2.6)
                       (rot.wrap_angle(qs[1, 1] - qs[0, 1]), 0.0),
                       (rot.wrap_angle(qs[2, 1] - np.arctan2(fa * p[2], -fb * rho)), 0.0),  # (S2.5)/(S2.7)
                       (rot.wrap_angle(qs[3, 1] - qs[2, 1]), 0.0)]
    sol.check("s3_zero_gives_two_solutions", set(counts) == {2}, f"distinct solutions: {sorted(set(counts))}")
    sol.check("theta2_matches_S2_4_to_S2_7", max_error(manual) < 1e-9,
              f"theta2,I = theta2,III and theta2,II = theta2,IV as in (S2.4)-(S2.7): max error {max_error(manual):.2e}")
    axis_fk, axis_th2 = [], []
    for p_z, th3 in ((a2 + a3, 0.0), (-(a2 + a3), 0.0), (a2 - a3, np.pi), (-(a2 - a3), np.pi)):
        for th1 in rng.uniform(-np.pi, np.pi, 5):
            qs = inverse_kinematics_anthropomorphic([0.0, 0.0, p_z], theta1=th1, a2=a2, a3=a3)
            axis_fk += [(direct_kinematics(robot, qk)[:3, 3], [0, 0, p_z]) for qk in qs]
            axis_th2.append((np.abs(np.abs(qs[:, 1]) - np.pi / 2), np.zeros(4)))
            axis_fk.append((direct_kinematics(robot, [th1, np.sign(p_z) * np.pi / 2, th3])[:3, 3], [0, 0, p_z]))
    sol.check("on_z_axis_theta1_arbitrary", max_error(axis_fk) < 1e-12,
              f"p_W = [0, 0, ±(a2+a3)] and [0, 0, ±|a2-a3|], 5 random theta1 each: max FK error {max_error(axis_fk):.2e}")
    sol.check("on_z_axis_theta2_is_pm_pi_2", max_error(axis_th2) < 1e-12, f"max ||theta2| - pi/2| = {max_error(axis_th2):.1e}")
    equal = load("anthropomorphic", a2=0.5, a3=0.5)
    zero = []
    for th1, th2 in rng.uniform(-np.pi, np.pi, (10, 2)):
        zero.append((direct_kinematics(equal, [th1, th2, np.pi])[:3, 3], np.zeros(3)))
        qs = inverse_kinematics_anthropomorphic([0, 0, 0], theta1=th1, theta2=th2, a2=0.5, a3=0.5)
        zero += [(direct_kinematics(equal, qk)[:3, 3], np.zeros(3)) for qk in qs]
    sol.check("a2_eq_a3_theta1_theta2_arbitrary", max_error(zero) < 1e-12,
              f"a2 = a3 = 0.5, theta3 = pi: p_W = 0 for 10 random (theta1, theta2); max error {max_error(zero):.2e}")
    regular = len(distinct_solutions(inverse_kinematics_anthropomorphic([0.3, 0.2, 0.4], a2=a2, a3=a3)))
    sol.check("regular_case_four_solutions", regular == 4, f"{regular} distinct solutions at p_W = [0.3, 0.2, 0.4]")
    sol.check("fk_of_every_solution", max_error(fk) < 1e-12, f"max |FK(q) - p_W| = {max_error(fk):.2e}")
    return sol


@problem("2.19", "Inverse kinematics of the cylindrical arm", kind="derivation")
def problem_2_19() -> Solution:
    """Inverse kinematics of the cylindrical arm: from p = [−d3 s1, d3 c1, d2] (Problem 2.12),
    θ1 = Atan2(−px, py), d3 = √(px² + py²), d2 = pz (the manual takes d3 ≥ 0; the other solution
    θ1 + π, −d3 is outside the joint range). Checked by Pinocchio FK and ik(fk(q)) = q."""
    sol = Solution()
    robot, postures = _random_postures("cylindrical", 219)
    pairs = []
    for q in postures:
        p = direct_kinematics(robot, q)[:3, 3]
        q_hat = inverse_kinematics_cylindrical(p)[0]
        manual = [np.arctan2(-p[0], p[1]), p[2], np.hypot(p[0], p[1])]
        pairs += [(direct_kinematics(robot, q_hat)[:3, 3], p), (q_hat, manual),
                  (np.concatenate([[rot.wrap_angle(q_hat[0] - q[0])], q_hat[1:] - q[1:]]), np.zeros(3))]
    sol.check("ik_of_fk_is_identity", max_error(pairs) < 1e-12, f"{N_RANDOM} random q: max error {max_error(pairs):.2e}")
    return sol


@problem("2.20", "Inverse kinematics of the SCARA manipulator", kind="derivation")
def problem_2_20() -> Solution:
    """Inverse kinematics of the SCARA (Problem 2.13): (θ1, θ2) of the two-link arm (2.91)–(2.92) with
    s2 = ±√(1 − c2²), d3 = pz, θ4 = φ − θ1 − θ2, φ = Atan2(r21, r11). Both branches satisfy FK (Pinocchio),
    one returns the configuration the pose came from; the companion file inv_ksu's example checks the
    elbow-up (s2 < 0) convention."""
    sol = Solution()
    robot, postures = _random_postures("scara", 220)
    fk, found = [], []
    for q in postures:
        T = direct_kinematics(robot, q)
        x = [T[0, 3], T[1, 3], T[2, 3], np.arctan2(T[1, 0], T[0, 0])]
        qs = inverse_kinematics_scara(x)
        fk += [(direct_kinematics(robot, qk), T) for qk in qs]
        d = qs - q
        d[:, [0, 1, 3]] = rot.wrap_angle(d[:, [0, 1, 3]])
        found.append(np.min(np.max(np.abs(d), axis=1)))
        px, py = x[0], x[1]
        c2 = (px**2 + py**2 - 0.25 - 0.25) / (2 * 0.5 * 0.5)
        fk.append((np.cos(qs[:, 1]), [c2, c2]))
        fk.append((np.sign(qs[[ELBOW_UP, ELBOW_DOWN], 1]), [-1.0, 1.0]))
    sol.check("both_branches_satisfy_fk", max_error(fk) < 1e-10, f"max error {max_error(fk):.2e}")
    sol.check("one_branch_returns_q", max(found) < 1e-10, f"max distance to the true q: {max(found):.2e}")
    x_example = sol.given("x_companion_example", np.array([1.0, 1.0, 0.5, np.pi / 4]), unit="m, m, m, rad")
    q_up = sol.value("q_companion_example", inverse_kinematics_scara(x_example, a=(1.0, 1.0))[ELBOW_UP],
                   unit="rad (q3 in m)")
    sol.check_close("companion_inv_ksu_example", q_up, [np.pi / 2, -np.pi / 2, 0.5, np.pi / 4], atol=1e-12,
                    reference="manual number")
    return sol
