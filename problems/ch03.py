"""Chapter 3 — Differential kinematics and statics: Problems 3.1–3.23.

Each problem builds its data, calls the library (``rigid_body.kinematics``, ``rigid_body.rotations``,
``rigid_body.manipulability``, ``planners.inverse_kinematics``, ``planners.configuration_space``) and checks the
manual's closed forms numerically at many random configurations, against an independent reference
(finite differences, a second formula, a QP solver, brute force).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Chapter 3,
and its solution manual; data of 3.21/3.22 from the authors' companion files (i3_21, i3_22).
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
import pinocchio as pin

from controllers.plants import JointIntegrator
from controllers.simulation import simulate
from planners.configuration_space import (planar_arm_obstacle_distance, planar_arm_obstacle_distance_gradient,
                                           segment_chain_distance)
from planners.inverse_kinematics import CLIK, TwoStageCLIK, cosine_pose_reference, gradient_velocity
from problems.common import label_axes, max_error, random_quaternion, random_rotation, subplots
from problems.registry import Solution, problem
from rigid_body.book_robots import book_robot_spec
from rigid_body.kinematics import (analytical_jacobian, direct_kinematics, frame_poses,
                                   geometric_jacobian)
from rigid_body.manipulability import (force_ellipsoid, jacobian_rank, manipulability, plot_ellipse,
                                       singular_values, velocity_ellipsoid)
from rigid_body.robots import load
from rigid_body.rotations import (euler_rate_matrix_rpy, euler_rate_matrix_zyz,
                                  euler_zyz_to_rotation, orientation_error_axis_angle,
                                  orientation_error_matrix, orientation_error_quaternion,
                                  quaternion_angular_velocity, quaternion_product, quaternion_rate,
                                  quaternion_to_rotation, rot_x, rot_y, rot_z, rotation_to_axis_angle,
                                  rotation_to_quaternion, rpy_to_rotation, skew, vee)
from rigid_body.task_space import TaskSpace, damped_least_squares_inverse, weighted_pseudo_inverse

N_RANDOM = 50  # random configurations per closed-form check
H = 1e-6       # finite-difference step








def _fd_jacobian(f, q: np.ndarray, h: float = H) -> np.ndarray:
    """Central-difference Jacobian of f at q (the independent reference of the closed forms)."""
    cols = []
    for k in range(q.size):
        dq = np.zeros(q.size)
        dq[k] = h
        cols.append((np.asarray(f(q + dq)) - np.asarray(f(q - dq))) / (2 * h))
    return np.column_stack(cols)


def _omega_fd(R_of_t, t: float = 0.0, h: float = 1e-6) -> np.ndarray:
    """ω from S(ω) = Ṙ R^T (3.6) with a central-difference Ṙ."""
    Rd = (R_of_t(t + h) - R_of_t(t - h)) / (2 * h)
    return vee(Rd @ R_of_t(t).T)


# --------------------------------------------------------------------------------------------
# 3.1–3.8: Jacobians and singularities
# --------------------------------------------------------------------------------------------

@problem("3.1", "R S(ω) R^T = S(R ω)", kind="derivation")
def problem_3_1() -> Solution:
    """Prove R S(ω) R^T = S(R ω), Eq. (3.11).

    The manual writes R = [x y z]^T; the entry (i, j) of R S(ω) R^T is x_i^T (ω × x_j), skew-symmetric,
    and ω' = [ω^T x, ω^T y, ω^T z] = R ω (S3.1). Checked at random R and ω, entry by entry.
    """
    sol = Solution()
    rng = np.random.default_rng(301)
    pairs, entries = [], []
    for _ in range(N_RANDOM):
        R, w = random_rotation(rng), rng.normal(size=3)
        lhs = R @ skew(w) @ R.T
        pairs.append((lhs, skew(R @ w)))
        rows = R  # rows x^T, y^T, z^T
        entries.append((lhs, [[rows[i] @ np.cross(w, rows[j]) for j in range(3)] for i in range(3)]))
    sol.check("R S(w) R^T == S(R w) (3.11)", max_error(pairs) < 1e-12, f"max error {max_error(pairs):.2e}")
    sol.check("entries x_i^T (w × x_j) (S3.1)", max_error(entries) < 1e-12, f"max error {max_error(entries):.2e}")
    return sol


def _cylindrical_J(q: np.ndarray) -> np.ndarray:
    th1, d2, d3 = q
    s1, c1 = np.sin(th1), np.cos(th1)
    return np.array([[-d3 * c1, 0, -s1], [-d3 * s1, 0, c1], [0, 1, 0], [0, 0, 0], [0, 0, 0], [1, 0, 0]])


@problem("3.2", "Geometric Jacobian of the cylindrical arm", kind="derivation")
def problem_3_2() -> Solution:
    """Geometric Jacobian of the cylindrical arm (Table S2.2), (S3.2).

    Compared with the book-convention Jacobian of the URDF model and with finite differences of
    the direct kinematics; rows 4–5 vanish (no rotation about x0, y0).
    """
    sol = Solution()
    robot = load("cylindrical")
    rng = np.random.default_rng(302)
    qs = [np.array([rng.uniform(-np.pi, np.pi), rng.uniform(0, 1), rng.uniform(0.1, 1)]) for _ in range(N_RANDOM)]
    pairs = [(geometric_jacobian(robot, q), _cylindrical_J(q)) for q in qs]
    fd = [(geometric_jacobian(robot, q)[:3], _fd_jacobian(lambda x: direct_kinematics(robot, x)[:3, 3], q))
          for q in qs]
    sol.value("J_at_q0", _cylindrical_J(qs[0]), unit="m/rad (column θ₁ of J_P), 1 (the rest)")
    sol.check_close("(S3.2) == Pinocchio J (LOCAL_WORLD_ALIGNED)", max_error(pairs), 0.0, atol=1e-12,
                    reference="closed form")
    sol.check_close("J_P == finite difference of p(q)", max_error(fd), 0.0, atol=1e-8, reference="finite differences")
    sol.check("rows 4-5 identically zero", all(np.all(geometric_jacobian(robot, q)[3:5] == 0) for q in qs))
    return sol


def _scara_JA(q: np.ndarray, a1: float, a2: float) -> np.ndarray:
    s1, c1, s12, c12 = np.sin(q[0]), np.cos(q[0]), np.sin(q[0] + q[1]), np.cos(q[0] + q[1])
    return np.array([[-a1 * s1 - a2 * s12, -a2 * s12, 0, 0], [a1 * c1 + a2 * c12, a2 * c12, 0, 0],
                     [0, 0, 1, 0], [1, 1, 0, 1]])


def _scara_x(robot, q: np.ndarray) -> np.ndarray:
    T = direct_kinematics(robot, q)
    return np.concatenate([T[:3, 3], [np.arctan2(T[1, 0], T[0, 0])]])


@problem("3.3", "Geometric and analytical Jacobian of the SCARA", kind="derivation")
def problem_3_3() -> Solution:
    """Geometric Jacobian of the SCARA (Table S2.3, a1 = a2 = 0.5) and its analytical Jacobian for
    x = [p, φ], φ = θ1 + θ2 + θ4 (S3.3). J_A is checked against finite differences of x(q), and
    against the RPY analytical Jacobian (3.66) restricted to [p; φ]."""
    sol = Solution()
    robot = load("scara")
    a1 = a2 = sol.given("a1 = a2", 0.5, unit="m")
    rng = np.random.default_rng(303)
    qs = [np.array([*rng.uniform(-np.pi, np.pi, 2), rng.uniform(0, 1), rng.uniform(-np.pi, np.pi)])
          for _ in range(N_RANDOM)]
    J_closed = [np.vstack([JA[:3], np.zeros((2, 4)), JA[3]]) for JA in (_scara_JA(q, a1, a2) for q in qs)]
    sol.check_close("geometric J == closed form", max_error(
        [(geometric_jacobian(robot, q), J) for q, J in zip(qs, J_closed)]), 0.0, atol=1e-12, reference="closed form")

    def x_of(q):
        x = _scara_x(robot, q)
        x[3] = q[0] + q[1] + q[3] + np.angle(np.exp(1j * (x[3] - q[0] - q[1] - q[3])))  # unwrapped φ
        return x

    fd = max_error([(_fd_jacobian(x_of, q), _scara_JA(q, a1, a2)) for q in qs])
    sol.check_close("(S3.3) == finite-difference dx/dq", fd, 0.0, atol=1e-8, reference="finite differences")
    ana = max_error([(analytical_jacobian(robot, q, "rpy")[[0, 1, 2, 3]], _scara_JA(q, a1, a2)) for q in qs])
    sol.check_close("(S3.3) == analytical_jacobian(rpy) rows [p; phi]", ana, 0.0, atol=1e-12, reference="closed form")
    sol.value("J_A_at_q0", _scara_JA(qs[0], a1, a2), unit="m/rad (rows p, columns θ₁, θ₂, θ₄), 1 (the rest)")
    return sol


def _det_check(sol: Solution, name: str, dets, closed) -> None:
    err = max(abs(d - c) for d, c in zip(dets, closed))
    sol.check_error(name, err, 1e-12, reference="closed form")


def _samples(seed: int, *blocks: tuple) -> np.ndarray:
    """N_RANDOM seeded joint samples, block after block of columns: ``(low, high)`` one column,
    ``(low, high, width)`` several columns uniform in [low, high)."""
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(b[0], b[1], (N_RANDOM, b[2] if len(b) > 2 else 1)) for b in blocks])


def _singularity_checks(sol: Solution, robot: Any, rows: list[int], qs: np.ndarray, det_name: str,
                        closed_det: Callable[[np.ndarray], float], singular: list[list[float]], rank: int) -> None:
    """det of the Jacobian rows ``rows`` against its closed form at ``qs``, and the rank at the
    ``singular`` postures (each must be ``rank``)."""
    _det_check(sol, det_name, [np.linalg.det(geometric_jacobian(robot, q)[rows]) for q in qs], [closed_det(q) for q in qs])
    ranks = [jacobian_rank(geometric_jacobian(robot, np.array(q, dtype=float))[rows]) for q in singular]
    sol.check(f"rank = {rank} at the singular postures {singular}", all(r == rank for r in ranks), f"ranks {ranks}")


@problem("3.4", "Singularities of the three-link planar arm", kind="derivation")
def problem_3_4() -> Solution:
    """Analytical Jacobian of the three-link planar arm (3.35 rows p_x, p_y, φ): det J_A = a1 a2 s2,
    singular only at θ2 = 0, π (rank 2 there, 3 elsewhere). Lengths a = (0.5, 0.3, 0.3) of 3.21."""
    sol = Solution()
    a = tuple(sol.given("a", np.array([0.5, 0.3, 0.3]), unit="m"))
    robot = load("planar_3r", a=a)
    rng = np.random.default_rng(304)
    qs = rng.uniform(-np.pi, np.pi, (N_RANDOM, 3))

    def JA_closed(q):
        s = [np.sin(q[:k + 1].sum()) for k in range(3)]
        c = [np.cos(q[:k + 1].sum()) for k in range(3)]
        return np.array([[-a[0] * s[0] - a[1] * s[1] - a[2] * s[2], -a[1] * s[1] - a[2] * s[2], -a[2] * s[2]],
                         [a[0] * c[0] + a[1] * c[1] + a[2] * c[2], a[1] * c[1] + a[2] * c[2], a[2] * c[2]],
                         [1, 1, 1]])

    JA = [geometric_jacobian(robot, q)[[0, 1, 5]] for q in qs]
    sol.check_close("Pinocchio J rows [x, y, wz] == (3.35)", max_error(zip(JA, map(JA_closed, qs))), 0.0, atol=1e-12,
                    reference="closed form")
    _det_check(sol, "det J_A == a1 a2 sin(q2)", [np.linalg.det(J) for J in JA], [a[0] * a[1] * np.sin(q[1]) for q in qs])
    ranks_sing = [jacobian_rank(geometric_jacobian(robot, np.array([q[0], th2, q[2]]))[[0, 1, 5]])
                  for q in qs[:10] for th2 in (0.0, np.pi)]
    sol.check("rank J_A = 2 at q2 in {0, pi}", set(ranks_sing) == {2}, f"ranks {sorted(set(ranks_sing))}")
    sol.check("rank J_A = 3 elsewhere", all(jacobian_rank(J) == 3 for J in JA))
    return sol


@problem("3.5", "Singularities of the spherical arm", kind="derivation")
def problem_3_5() -> Solution:
    """Geometric Jacobian of the spherical arm (DH (0,−π/2,0,θ1), (0,π/2,d2,θ2), (0,0,d3,0), recalled
    from the textbook; d2 = 0.2): det J_P = −d3² s2, singular at θ2 = 0, π and at d3 = 0."""
    sol = Solution()
    robot = load("spherical")
    d2 = sol.given("d2", 0.2, unit="m")
    qs = _samples(305, (-np.pi, np.pi, 2), (0.1, 1.0))

    def J_closed(q):
        th1, th2, d3 = q
        s1, c1, s2, c2 = np.sin(th1), np.cos(th1), np.sin(th2), np.cos(th2)
        return np.array([[-s1 * s2 * d3 - c1 * d2, c1 * c2 * d3, c1 * s2], [c1 * s2 * d3 - s1 * d2, s1 * c2 * d3, s1 * s2],
                         [0, -s2 * d3, c2], [0, -s1, 0], [0, c1, 0], [1, 0, 0]])

    Js = [geometric_jacobian(robot, q) for q in qs]
    sol.check_close("Pinocchio J == closed form", max_error(zip(Js, map(J_closed, qs))), 0.0, atol=1e-12,
                    reference="closed form")
    fd = max_error([(J[:3], _fd_jacobian(lambda x: direct_kinematics(robot, x)[:3, 3], q)) for J, q in zip(Js, qs)])
    sol.check_close("J_P == dp/dq (finite differences)", fd, 0.0, atol=1e-8, reference="finite differences")
    _singularity_checks(sol, robot, [0, 1, 2], qs, "det J_P == -d3^2 sin(th2)", lambda q: -q[2] ** 2 * np.sin(q[1]),
                        [[0.3, 0.0, 0.5], [0.3, np.pi, 0.5], [0.3, 0.7, 0.0]], 2)
    return sol


@problem("3.6", "Singularities of the cylindrical arm", kind="derivation")
def problem_3_6() -> Solution:
    """J_P of the cylindrical arm: det J_P = d3; singular at d3 = 0 (end effector on the joint-1 axis)."""
    sol = Solution()
    qs = _samples(306, (-np.pi, np.pi), (0.0, 1.0), (0.1, 1.0))
    _singularity_checks(sol, load("cylindrical"), [0, 1, 2], qs, "det J_P == d3", lambda q: q[2], [[0.4, 0.5, 0.0]], 2)
    return sol


@problem("3.7", "Singularities of the SCARA", kind="derivation")
def problem_3_7() -> Solution:
    """det J_A of (S3.3) = a1 a2 s2: singular at θ2 = 0, π; the prismatic joint adds no singularity."""
    sol = Solution()
    robot = load("scara")
    a1 = a2 = sol.given("a1 = a2", 0.5, unit="m")
    qs = _samples(307, (-np.pi, np.pi, 2), (0.0, 1.0), (-np.pi, np.pi))
    _singularity_checks(sol, robot, [0, 1, 2, 5], qs, "det J_A == a1 a2 sin(th2)", lambda q: a1 * a2 * np.sin(q[1]),
                        [[0.2, 0.0, 0.3, 0.1], [0.2, np.pi, 0.3, 0.1]], 3)
    return sol


@problem("3.8", "Manipulability = product of singular values", kind="derivation")
def problem_3_8() -> Solution:
    """w = √det(J J^T) (3.56) equals the product of the singular values of J; for the two-link arm
    w = a1 a2 |s2| (a1 = a2 = 1 m)."""
    sol = Solution()
    rng = np.random.default_rng(308)
    errs = []
    for shape in ((2, 3), (3, 3), (6, 7), (2, 2)):
        for _ in range(20):
            J = rng.normal(size=shape)
            errs.append(abs(manipulability(J) - np.prod(np.linalg.svd(J, compute_uv=False))))
    sol.check_close("sqrt(det(J J^T)) == prod(sigma_i)", max(errs), 0.0, atol=1e-10, reference="closed form")
    robot = load("planar_2r")
    a1 = a2 = sol.given("a1 = a2", 1.0, unit="m")
    qs = rng.uniform(-np.pi, np.pi, (N_RANDOM, 2))
    w = [manipulability(geometric_jacobian(robot, q)[:2]) for q in qs]
    sol.check_close("two-link arm: w == a1 a2 |s2|", np.array(w), a1 * a2 * np.abs(np.sin(qs[:, 1])), atol=1e-12,
                    reference="closed form")
    return sol


# --------------------------------------------------------------------------------------------
# 3.9–3.10: obstacle distance, damped least squares
# --------------------------------------------------------------------------------------------

@problem("3.9", "Distance of a three-link planar arm from a circular obstacle", kind="derivation")
def problem_3_9() -> Solution:
    """Distance of the three-link planar arm from a disc, (S3.4)–(S3.8): projection of the centre on
    each link clamped to the segment. Compared with brute force (10^4 points per link), including
    clamped projections, intersection (d < 0) and contact (d = 0); the analytic gradient used by
    3.21's null-space term is compared with central differences."""
    sol = Solution()
    robot = load("planar_3r", a=sol.given("a", (0.5, 0.3, 0.3), unit="m"))
    rng = np.random.default_rng(309)
    s = np.linspace(0.0, 1.0, 10_000)
    errs, clamped, negative = [], 0, 0
    for _ in range(N_RANDOM):
        q = rng.uniform(-np.pi, np.pi, 3)
        o, R = rng.uniform(-0.8, 0.8, 2), rng.uniform(0.02, 0.2)
        pts = np.array([P[:2, 3] for P in frame_poses(robot, q, ["frame_0", "frame_1", "frame_2", "frame_3"])])
        res = planar_arm_obstacle_distance(robot, q, o, R)
        brute = min(np.min(np.linalg.norm(pts[i] + s[:, None] * (pts[i + 1] - pts[i]) - o, axis=1))
                    for i in range(3)) - R
        errs.append(abs(res.distance - brute))
        clamped += res.s in (0.0, 1.0)
        negative += res.distance < 0
    sol.check_close("(S3.4)-(S3.8) == brute force", max(errs), 0.0, atol=1e-7, reference="closed form")
    sol.check("cases covered: clamped projections and intersections", clamped > 0 and negative > 0,
              f"{clamped} clamped, {negative} intersecting of {N_RANDOM}")
    touch = segment_chain_distance([[0, 0], [1, 0]], [0.5, 0.1], 0.1)
    sol.check_close("touching obstacle: d = 0", touch.distance, 0.0, atol=1e-15, reference="closed form")
    grad_err = []
    for _ in range(20):
        q = rng.uniform(-np.pi, np.pi, 3)
        g = planar_arm_obstacle_distance_gradient(robot, q, [0.3, 0.0], 0.1)
        fd = _fd_jacobian(lambda x: [planar_arm_obstacle_distance(robot, x, [0.3, 0.0], 0.1).distance], q).ravel()
        grad_err.append(np.max(np.abs(g - fd)))
    sol.check_close("analytic gradient == central differences", max(grad_err), 0.0, atol=1e-6,
                    reference="finite differences")
    return sol


@problem("3.10", "Damped least-squares inverse", kind="derivation")
def problem_3_10() -> Solution:
    """Minimise ½ k² q̇^T q̇ + ½ ε^T ε with v_e − J q̇ = ε: [q̇; ε] = [J^T; k² I](J J^T + k² I)^{-1} v_e,
    J* = J^T (J J^T + k² I)^{-1} (3.59). Checked against the Lagrangian solution Q^{-1}A^T(AQ^{-1}A^T)^{-1}v,
    a proxsuite QP, (J^T J + k² I)^{-1} J^T, the k → 0 limit (pseudo-inverse) and boundedness near a singularity."""
    import proxsuite

    sol = Solution()
    rng = np.random.default_rng(310)
    e_lagr, e_qp, e_alt, e_eps = [], [], [], []
    for r, n in ((2, 3), (3, 3), (6, 7)):
        for _ in range(10):
            J, v, k = rng.normal(size=(r, n)), rng.normal(size=r), rng.uniform(0.1, 1.0)
            Js = damped_least_squares_inverse(J, k)
            qd = Js @ v
            eps = k * k * np.linalg.solve(J @ J.T + k * k * np.eye(r), v)
            A = np.hstack([J, np.eye(r)])
            Qi = np.diag(np.r_[np.full(n, 1 / k**2), np.ones(r)])
            w = Qi @ A.T @ np.linalg.solve(A @ Qi @ A.T, v)
            e_lagr.append(np.max(np.abs(w - np.r_[qd, eps])))
            qp = proxsuite.proxqp.dense.solve(np.diag(np.r_[np.full(n, k**2), np.ones(r)]), np.zeros(n + r), A, v,
                                              None, None, None, eps_abs=1e-12)
            e_qp.append(np.max(np.abs(qp.x - np.r_[qd, eps])))
            e_alt.append(np.max(np.abs(Js - np.linalg.solve(J.T @ J + k * k * np.eye(n), J.T))))
            e_eps.append(np.max(np.abs(eps - (v - J @ qd))))
    sol.check_close("closed form == Lagrangian (3.50)", max(e_lagr), 0.0, atol=1e-10, reference="closed form")
    sol.check_close("closed form == proxsuite QP", max(e_qp), 0.0, atol=1e-7, reference="other library")
    sol.check_close("J* == (J^T J + k^2 I)^-1 J^T", max(e_alt), 0.0, atol=1e-10, reference="closed form")
    sol.check_close("eps == v - J qdot", max(e_eps), 0.0, atol=1e-10, reference="closed form")
    J = rng.normal(size=(3, 5))
    sol.check_close("k -> 0 gives the pseudo-inverse", damped_least_squares_inverse(J, 1e-8), weighted_pseudo_inverse(J),
                    atol=1e-8, reference="second algorithm")
    J_sing = np.array([[1.0, 1.0], [1.0, 1.0 + 1e-9]])
    norm_dls = np.linalg.norm(damped_least_squares_inverse(J_sing, 0.1) @ np.array([1.0, -1.0]))
    sol.check("near a singularity ||qdot|| stays bounded (<= 1/(2k))", norm_dls <= 1 / (2 * 0.1) + 1e-12,
              f"||qdot|| = {norm_dls:.3g}")
    return sol


# --------------------------------------------------------------------------------------------
# 3.11–3.13: Euler-angle rates
# --------------------------------------------------------------------------------------------

def _euler_rate_check(sol: Solution, name: str, R_of, T_of, det_of, rng) -> None:
    errs, dets = [], []
    for _ in range(N_RANDOM):
        phi, phid = rng.uniform(-np.pi, np.pi, 3), rng.normal(size=3)
        w = _omega_fd(lambda t: R_of(phi + t * phid))
        errs.append(np.max(np.abs(w - T_of(phi) @ phid)))
        dets.append(abs(np.linalg.det(T_of(phi)) - det_of(phi)))
    sol.check_close(f"{name}: finite-difference w == T(phi) phidot", max(errs), 0.0, atol=1e-8,
                    reference="finite differences")
    sol.check_close(f"{name}: det T closed form", max(dets), 0.0, atol=1e-12, reference="closed form")


@problem("3.11", "Angular velocity vs ZYZ Euler-angle rates (3.64)", kind="derivation")
def problem_3_11() -> Solution:
    """ω = T(φ) φ̇ with T = [[0, −sφ, cφ sθ], [0, cφ, sφ sθ], [1, 0, cθ]] (3.64), from S(ω) = Ṙ R^T;
    det T = −sin θ (singular at θ = 0, π)."""
    sol = Solution()
    _euler_rate_check(sol, "ZYZ", euler_zyz_to_rotation, euler_rate_matrix_zyz, lambda p: -np.sin(p[1]),
                      np.random.default_rng(311))
    return sol


@problem("3.12", "Angular velocity vs RPY rates; representation singularities", kind="derivation")
def problem_3_12() -> Solution:
    """RPY: T(φ) = [[0, −sφ, cφ cθ], [0, cφ, sφ cθ], [1, 0, −sθ]], det T = −cos θ: singular at θ = ±π/2."""
    sol = Solution()
    _euler_rate_check(sol, "RPY", rpy_to_rotation, euler_rate_matrix_rpy, lambda p: -np.cos(p[1]),
                      np.random.default_rng(312))
    sol.check("T singular at theta = pi/2", jacobian_rank(euler_rate_matrix_rpy([0.3, np.pi / 2, 0.2])) == 2)
    return sol


@problem("3.13", "Euler-angle set for which T(0) = I", kind="derivation")
def problem_3_13() -> Solution:
    """With XYZ angles R = Rx(φ) Ry(θ) Rz(ψ) the rates are about x, y', z'' and at φ = 0 they coincide
    with the base axes: T(0) = I. ZYZ angles are singular there (contrast)."""
    sol = Solution()

    def R_xyz(p):
        return rot_x(p[0]) @ rot_y(p[1]) @ rot_z(p[2])

    T0 = np.column_stack([_omega_fd(lambda t, e=e: R_xyz(t * e)) for e in np.eye(3)])
    sol.value("T_xyz_0", T0, unit="1")
    sol.check_close("XYZ: finite-difference T(0) == I", T0, np.eye(3), atol=1e-9, reference="finite differences")
    T0_zyz = np.column_stack([_omega_fd(lambda t, e=e: euler_zyz_to_rotation(t * e)) for e in np.eye(3)])
    sol.check("ZYZ: T(0) is singular (contrast)", jacobian_rank(T0_zyz, 1e-6) == 2)
    return sol


# --------------------------------------------------------------------------------------------
# 3.14–3.15: two-stage CLIK, transpose error bound
# --------------------------------------------------------------------------------------------

@problem("3.14", "Two-stage CLIK for a manipulator with a spherical wrist", kind="derivation")
def problem_3_14() -> Solution:
    """Position of the wrist point with the arm joints (q̇_P = J_PP^{-1}(ṗ_Wd + K_P e_PW)), then the
    orientation with the wrist joints (q̇_O = J_OO^{-1}(ω_d − J_OP q̇_P + K_O e_O), e_O from (3.85)).
    Test data chosen here (the manual has none): the anthropomorphic arm with spherical wrist,
    a2 = d4 = 0.5, d6 = 0.1; a 2 s pose trajectory (straight line + rotation, sinusoidal timing),
    Euler 1 ms, K_P = K_O = 500 I. Checks: J at the wrist point has a null upper-right block (3.42);
    errors vanish; the result matches the full 6×6 CLIK (3.70) with the (3.88)–(3.89) law."""
    sol = Solution()
    robot = load("anthropomorphic_wrist")
    q0 = sol.given("q0", np.array([0.2, 0.6, 0.3, 0.4, 0.8, -0.3]), unit="rad")
    sol.given("K_P = K_O", 500.0, unit="1/s")
    rng = np.random.default_rng(314)
    blocks = max(np.max(np.abs(geometric_jacobian(robot, q, "frame_4")[:3, 3:])) for q in rng.uniform(-3, 3, (20, 6)))
    sol.check_close("J(p_W) upper-right 3x3 block == 0 (3.42)", blocks, 0.0, atol=1e-12, reference="closed form")
    T0 = direct_kinematics(robot, q0)
    ref = cosine_pose_reference(T0[:3, 3], T0[:3, 3] + [-0.1, 0.15, 0.1], 2.0, 0.0, np.pi / 4,
                                axis=[1.0, 1.0, 0.0], R_0=T0[:3, :3])
    two = simulate(JointIntegrator(), TwoStageCLIK(robot, ref, "frame_4", 3, 500.0, 500.0), (0.0, 2.5), q0, h=1e-3)
    full = simulate(JointIntegrator(), CLIK(robot, ref, TaskSpace(orientation="axis_angle"), K=500.0, law="inverse"),
                    (0.0, 2.5), q0, h=1e-3)
    e_P, e_O = np.linalg.norm(two["e_P"], axis=1), np.linalg.norm(two["e_O"], axis=1)
    sol.value("max_position_error", float(e_P.max()), unit="m")
    sol.value("max_orientation_error", float(e_O.max()), unit="rad")
    sol.check("two-stage: errors small along the path (< 1e-4)", e_P.max() < 1e-4 and e_O.max() < 1e-4,
              f"max ||e_P|| = {e_P.max():.2e}, max ||e_O|| = {e_O.max():.2e}")
    sol.check("two-stage: errors vanish at steady state (< 1e-6)", e_P[-1] < 1e-6 and e_O[-1] < 1e-6,
              f"||e_P(end)|| = {e_P[-1]:.1e}, ||e_O(end)|| = {e_O[-1]:.1e}")
    dq = np.max(np.abs(two.x - full.x))
    sol.check("two-stage == full 6x6 CLIK joint trajectory (< 1e-4 rad)", dq < 1e-4, f"max |dq| = {dq:.2e}")
    return sol


@problem("3.15", "Error bound for the Jacobian-transpose CLIK when xd_dot != 0", kind="derivation")
def problem_3_15() -> Solution:
    """From V̇ = e^T K ẋ_d − e^T K J_A J_A^T K e (3.77), with K = k I the error is ultimately bounded
    by ‖e‖ ≤ ‖ẋ_d‖_max / (k σ_r²(J_A)). Test data chosen here: the two-link arm (a = 1 m), the
    end point moving at constant speed 0.1 m/s along a segment away from singularities, k = 200 and
    400; the steady error is below the bound and scales like 1/k."""
    sol = Solution()
    robot = load("planar_2r")
    p_i = sol.given("p_i", np.array([1.2, 0.4, 0.0]), unit="m")
    p_f = sol.given("p_f", np.array([1.2, 0.6, 0.0]), unit="m")
    t_f = sol.given("t_f", 2.0, unit="s")
    speed = np.linalg.norm(p_f - p_i) / t_f

    def ref(t, v=(p_f - p_i) / t_f):
        T = np.eye(4)
        T[:3, 3] = p_i + v * min(t, t_f)
        return T, np.r_[v if t < t_f else np.zeros(3), np.zeros(3)]

    q0 = sol.given("q0", np.array([-0.3, 1.6]), unit="rad")
    task = TaskSpace(orientation="none", rows=(0, 1))
    finals = []
    for k in (200.0, 400.0):
        res = simulate(JointIntegrator(), CLIK(robot, ref, task, K=k, law="transpose"), (0.0, 1.5), q0, h=1e-3)
        e = np.linalg.norm(res["e"], axis=1)
        sigma = [singular_values(geometric_jacobian(robot, q)[:2])[-1] for q in res.q[::50]]
        bound = speed / (k * min(sigma) ** 2)
        steady = e[res.t > 0.5].max()
        finals.append(steady)
        sol.check(f"k = {k:g}: steady error <= xd_max/(k sigma_r^2)", steady <= bound,
                  f"max ||e|| (t > 0.5 s) = {steady:.3e} <= bound {bound:.3e}")
    ratio = finals[0] / finals[1]
    sol.check("error scales like 1/k (ratio of k = 200 to 400 in [1.5, 2.5])", 1.5 <= ratio <= 2.5, f"ratio {ratio:.3f}")
    return sol


# --------------------------------------------------------------------------------------------
# 3.16–3.20: orientation errors and quaternion kinematics
# --------------------------------------------------------------------------------------------

@problem("3.16", "Orientation error in terms of n, s, a (3.85)", kind="derivation")
def problem_3_16() -> Solution:
    """r sin ϑ of R_d R_e^T (3.84) equals ½ (n_e × n_d + s_e × s_d + a_e × a_d) (3.85): the cross-product
    form, evaluated as written, against the library's angle–axis error and against r sin ϑ of the
    extracted angle and axis, on random pairs of rotations."""
    sol = Solution()
    rng = np.random.default_rng(316)
    errs_library, errs_axis_angle = [], []
    for _ in range(N_RANDOM):
        R_d, R_e = random_rotation(rng), random_rotation(rng)
        e_385 = 0.5 * sum(np.cross(R_e[:, k], R_d[:, k]) for k in range(3))  # (3.85)
        theta, r = rotation_to_axis_angle(R_d @ R_e.T)
        errs_library.append(np.max(np.abs(e_385 - orientation_error_axis_angle(R_d, R_e))))
        errs_axis_angle.append(np.max(np.abs(e_385 - np.sin(theta) * r)))
    sol.check_error("(3.85) 1/2 sum(col_e x col_d) == library e_O", max(errs_library), 1e-12,
                    reference="closed form")
    sol.check_error("(3.85) == r sin(theta) of the extracted angle and axis", max(errs_axis_angle), 1e-12,
                    reference="second algorithm")
    return sol


@problem("3.17", "Time derivative of the orientation error (3.86), (3.87)", kind="derivation")
def problem_3_17() -> Solution:
    """ė_O = L^T ω_d − L ω_e with L = −½ (S(n_d)S(n_e) + S(s_d)S(s_e) + S(a_d)S(a_e)) (3.86)–(3.87),
    checked by finite differences along R_e(t) = exp(S(ω)t) R_e0, R_d(t) = exp(S(ω_d)t) R_d0.
    (The manual's "ε̇_O" is a typo for ė_O.)"""
    sol = Solution()
    rng = np.random.default_rng(317)
    errs, errs_L = [], []
    for _ in range(N_RANDOM):
        R_d0, R_e0, w_d, w = random_rotation(rng), random_rotation(rng), rng.normal(size=3), rng.normal(size=3)

        def e_of(t):
            return orientation_error_axis_angle(pin.exp3(w_d * t) @ R_d0, pin.exp3(w * t) @ R_e0)

        e_dot = (e_of(H) - e_of(-H)) / (2 * H)
        L = orientation_error_matrix(R_d0, R_e0)
        errs.append(np.max(np.abs(e_dot - (L.T @ w_d - L @ w))))
        L_book = -0.5 * sum(skew(R_d0[:, k]) @ skew(R_e0[:, k]) for k in range(3))
        errs_L.append(np.max(np.abs(L - L_book)))
    sol.check_close("finite-difference e_O_dot == L^T w_d - L w", max(errs), 0.0, atol=1e-8,
                    reference="finite differences")
    sol.check_close("L == -1/2 sum S(d_k) S(e_k) (3.87)", max(errs_L), 0.0, atol=1e-14, reference="closed form")
    return sol




@problem("3.18", "Angular velocity from unit-quaternion rates", kind="derivation")
def problem_3_18() -> Solution:
    """(S3.9) R = (2η² − 1) I + 2 εε^T + 2η S(ε) equals (2.33); along R(t) = exp(S(ω)t) R0 the
    quaternion rates satisfy η η̇ + ε^T ε̇ = 0 (S3.12) and ω = 2(η ε̇ − η̇ ε + S(ε) ε̇) (S3.13).
    The manual's text stops after (S3.11) (its last line has η̇ for η, a typo); (S3.12)–(S3.13) are
    reconstructed, and checked here with finite-difference quaternion rates."""
    sol = Solution()
    rng = np.random.default_rng(318)
    e9, e12, e13 = [], [], []
    for _ in range(N_RANDOM):
        Q = random_quaternion(rng, positive_scalar=True)
        eta, eps = Q[0], Q[1:]
        S39 = (2 * eta**2 - 1) * np.eye(3) + 2 * np.outer(eps, eps) + 2 * eta * skew(eps)
        e9.append(np.max(np.abs(S39 - quaternion_to_rotation(Q))))
        R0, w = quaternion_to_rotation(Q), rng.normal(size=3)

        def Q_of(t):
            Qt = rotation_to_quaternion(pin.exp3(w * t) @ R0)
            return Qt if Qt @ Q > 0 else -Qt

        Qd = (Q_of(H) - Q_of(-H)) / (2 * H)
        e12.append(abs(eta * Qd[0] + eps @ Qd[1:]))
        e13.append(np.max(np.abs(quaternion_angular_velocity(Q, Qd) - w)))
    sol.check_close("(S3.9) == (2.33)", max(e9), 0.0, atol=1e-14, reference="closed form")
    sol.check_close("eta etadot + eps^T epsdot = 0 (S3.12)", max(e12), 0.0, atol=1e-8, reference="closed form")
    sol.check_close("w == 2(eta epsdot - etadot eps + S(eps) epsdot) (S3.13)", max(e13), 0.0, atol=1e-7,
                    reference="closed form")
    return sol


@problem("3.19", "Quaternion propagation (3.94), (3.95)", kind="derivation")
def problem_3_19() -> Solution:
    """η̇ = −½ ε^T ω (3.94), ε̇ = ½ (η I − S(ε)) ω (3.95): equal to ½ [0, ω] ∗ Q (Hamilton product,
    scalar first), and integrating them (RK4 through the simulation loop) tracks R(t) = exp(S(ω)t) R0.
    (The manual's intermediate "−2η̇ε" should read −2ηη̇ε; the result is unaffected.)"""
    sol = Solution()
    rng = np.random.default_rng(319)
    errs = []
    for _ in range(N_RANDOM):
        Q, w = random_quaternion(rng, positive_scalar=True), rng.normal(size=3)
        eta_w_eps = np.concatenate([[-Q[1:] @ w], Q[0] * w + np.cross(w, Q[1:])])  # [0, w] * Q
        errs.append(np.max(np.abs(quaternion_rate(Q, w) - 0.5 * eta_w_eps)))
    sol.check_close("(3.94)-(3.95) == 1/2 [0, w] * Q", max(errs), 0.0, atol=1e-14, reference="closed form")
    Q0, w = random_quaternion(rng, positive_scalar=True), np.array([0.3, -1.2, 0.8])
    res = simulate(lambda t, x, u: quaternion_rate(x / np.linalg.norm(x), w), lambda t, x: np.zeros(1),
                   (0.0, 2.0), Q0, h=1e-3)
    R_end = quaternion_to_rotation(res.x[-1] / np.linalg.norm(res.x[-1]))
    R_ref = pin.exp3(w * 2.0) @ quaternion_to_rotation(Q0)
    sol.check_close("integrated quaternion tracks exp(S(w) t) R0", R_end, R_ref, atol=1e-10, reference="closed form")
    sol.check_close("unit norm preserved", np.linalg.norm(res.x[-1]), 1.0, atol=1e-10, reference="closed form")
    Q_ref = quaternion_product(rotation_to_quaternion(pin.exp3(w * 2.0)), Q0)   # (2.37): Q(t) = Q_w(t) * Q0
    sign_err = min(np.max(np.abs(res.x[-1] - Q_ref)), np.max(np.abs(res.x[-1] + Q_ref)))
    sol.check_close("consistent with the product (2.37): Q(t) = ±Q_w(t) * Q0", sign_err, 0.0, atol=1e-10,
                    reference="closed form")
    return sol


@problem("3.20", "Lyapunov derivative for the quaternion-based CLIK (3.97)", kind="derivation")
def problem_3_20() -> Solution:
    """V = (η_d − η)² + ‖ε_d − ε‖² (3.96) has V̇ = e_O^T (ω_d − ω) with e_O of (3.91); with ω = ω_d + K_O e_O
    (3.93) V̇ = −e_O^T K_O e_O (3.97). Finite differences of V along (3.94)/(3.95) for random Q, Q_d, ω, ω_d.
    (The manual prints the row factor transposed — a typo.)"""
    sol = Solution()
    rng = np.random.default_rng(320)
    errs, errs97 = [], []
    for _ in range(N_RANDOM):
        Q, Q_d, w, w_d = random_quaternion(rng, positive_scalar=True), random_quaternion(rng, positive_scalar=True), rng.normal(size=3), rng.normal(size=3)

        def V(t, w=w):
            q = Q + t * quaternion_rate(Q, w)
            qd = Q_d + t * quaternion_rate(Q_d, w_d)
            return np.sum((qd - q) ** 2)

        e_O = orientation_error_quaternion(Q_d, Q)
        errs.append(abs((V(H) - V(-H)) / (2 * H) - e_O @ (w_d - w)))
        K_O = np.diag(rng.uniform(1, 10, 3))
        w_cl = w_d + K_O @ e_O
        errs97.append(abs((V(H, w_cl) - V(-H, w_cl)) / (2 * H) + e_O @ K_O @ e_O))
    sol.check_close("dV/dt == e_O^T (w_d - w)", max(errs), 0.0, atol=1e-8, reference="closed form")
    sol.check_close("with w = w_d + K_O e_O: dV/dt == -e_O^T K_O e_O (3.97)", max(errs97), 0.0, atol=1e-8,
                    reference="closed form")
    return sol


# --------------------------------------------------------------------------------------------
# 3.21–3.22: CLIK simulations (companion data i3_21, i3_22)
# --------------------------------------------------------------------------------------------

def _history_figure(title: str, res, error_panels: list[tuple[str, np.ndarray]], robot: Any):
    """Joint positions and velocities (revolute joints in rad on the left axis, prismatic in m on a
    right axis) and the error panels; a distance panel (label starting "distance") gets its d = 0 line."""
    from rigid_body.robots import joint_kind

    prismatic = [joint_kind(robot.model, i)[0] == "prismatic" for i in range(1, robot.model.njoints)]
    fig, axes = subplots(2, 2, figsize=(10, 6.5))
    for ax, y, (sym, rate) in ((axes[0, 0], res.x, ("q", "")), (axes[0, 1], res.u, ("q̇", "/s"))):
        right = ax.twinx() if any(prismatic) else None
        lines = []
        for k, is_prismatic in enumerate(prismatic):
            target, unit = (right, "m") if is_prismatic else (ax, "rad")
            lines += target.plot(res.t, y[:, k], color=f"C{k}", ls="--" if is_prismatic else "-",
                                 label=f"{sym}{k + 1} [{unit}{rate}]")
        label_axes(ax, "t [s]", f"{sym} revolute [rad{rate}]", title=("joint positions", "joint velocities")[rate != ""],
                   legend=False)
        if right is not None:
            right.set_ylabel(f"{sym} prismatic [m{rate}]")
        ax.legend(lines, [line.get_label() for line in lines], fontsize="small")
    for ax, (label, y) in zip(axes[1], error_panels):
        ax.plot(res.t, y, label=label.split(" [")[0])
        if label.startswith("distance"):
            ax.axhline(0.0, color="k", lw=0.8, ls=":", label="d = 0 (contact)")
        elif np.all(np.asarray(y) > 0):
            ax.set_yscale("log")        # an error norm: its decay over decades is a straight line
        label_axes(ax, "t [s]", label, title=label.split(" [")[0])
    fig.suptitle(title)
    return fig  # laid out by Solution.figure


@problem("3.21", "CLIK with pseudo-inverse and obstacle avoidance on a three-link planar arm", kind="simulation")
def problem_3_21() -> Solution:
    """Three-link planar arm (a = 0.5, 0.3, 0.3 m) tracking the segment (0.8, 0.2) → (0.8, −0.2) in 2 s
    (sinusoidal timing, held until 2.5 s) with the pseudo-inverse CLIK (3.72), K = diag(500, 500),
    q̇_0 = k_0 ∂w/∂q (3.55) with w the distance from the disc o = (0.3, 0), R = 0.1 (Problem 3.9,
    gradient by forward differences of step 1e-6), k_0 = 0 (Fig. S3.4) and 35 (Fig. S3.5); Euler
    integration 1 ms (3.48); q(0) from the closed-form IK, elbow-up (s2 < 0), φ = π/4.
    Data: companion file i3_21. The manual's "Problem 3.11" for the distance is a typo for 3.9.
    """
    from rigid_body.kinematics import ELBOW_UP, inverse_kinematics_planar_3r

    sol = Solution()
    arm = dict(a=(0.5, 0.3, 0.3), lower=(-np.pi,) * 3, upper=(np.pi,) * 3)  # not 2.17's limits: θ3(0) = 1.82
    robot = load("planar_3r", **arm)
    sol.given("a", np.array(arm["a"]), unit="m")
    o, R = sol.given("obstacle centre o", np.array([0.3, 0.0]), unit="m"), sol.given("obstacle radius", 0.1, unit="m")
    p_i = sol.given("p_i", np.array([0.8, 0.2, 0.0]), unit="m")
    p_f = sol.given("p_f", np.array([0.8, -0.2, 0.0]), unit="m")
    q0 = inverse_kinematics_planar_3r([0.8, 0.2, np.pi / 4], **arm)[ELBOW_UP]
    sol.value("q0", q0, unit="rad")
    sol.check_close("q(0) (i3_21)", q0, [0.51469, -1.55168, 1.82239], atol=5e-6, reference="independent derivation")
    ref = cosine_pose_reference(p_i, p_f, 2.0)
    task = TaskSpace(orientation="none", rows=(0, 1))

    def distance(q):
        return planar_arm_obstacle_distance(robot, q, o, R).distance

    results = {}
    for k0, fig_name in ((0.0, "Fig. S3.4 (unconstrained, k0 = 0)"), (35.0, "Fig. S3.5 (constrained, k0 = 35)")):
        secondary = gradient_velocity(distance, k0, step=1e-6, scheme="forward") if k0 else None
        clik = CLIK(robot, ref, task, K=[500.0, 500.0], law="pseudo_inverse", secondary=secondary)
        res = simulate(JointIntegrator(), clik, (0.0, 2.5), q0, h=1e-3, log=lambda t, x, u: {"d": distance(x)})
        e = np.linalg.norm(res["e"], axis=1)
        results[k0] = (res, e)
        sol.figure(_history_figure(f"Problem 3.21 — {fig_name}", res,
                                   [("||e|| [m]", e), ("distance from the obstacle [m]", res["d"])], robot))
    (res0, e0), (res1, e1) = results[0.0], results[35.0]
    d0, d1 = sol.value("min_distance_unconstrained", float(res0["d"].min()), unit="m"), \
        sol.value("min_distance_constrained", float(res1["d"].min()), unit="m")
    sol.value("final_error", float(max(e0[-1], e1[-1])), unit="m")
    sol.check("unconstrained: the arm crosses the obstacle (min d < 0)", d0 < 0, f"min d = {d0:.4f} m")
    sol.check("constrained: the arm never touches the obstacle (min d > 0)", d1 > 0, f"min d = {d1:.4f} m")
    sol.check_close("unconstrained min d (indicative -0.0644 m)", d0, -0.0644, atol=1e-3,
                    reference="independent derivation")
    for name, e in (("unconstrained", e0), ("constrained", e1)):
        sol.check(f"{name}: ||e|| small along the path (< 1e-4 m)", e.max() < 1e-4, f"max ||e|| = {e.max():.2e}")
        sol.check(f"{name}: ||e|| vanishes at steady state (< 1e-6 m)", e[-1] < 1e-6, f"||e(2.5)|| = {e[-1]:.1e}")
    v0, v1 = np.linalg.norm(res0.u, axis=1).max(), np.linalg.norm(res1.u, axis=1).max()
    sol.check("constrained: large initial joint velocities (>= 5x unconstrained max)",
              v1 >= 5 * v0 and np.argmax(np.linalg.norm(res1.u, axis=1)) < 50,
              f"max ||qdot|| {v1:.2f} rad/s at t = {res1.t[np.argmax(np.linalg.norm(res1.u, axis=1))]:.3f} s "
              f"vs {v0:.2f} rad/s")
    sol.animation(robot, res1, "k0 = 35: the arm keeps clear of the obstacle", speed=0.5,
                  overlays=lambda s: (s.polyline("path", np.array([p_i, p_f]), radius=0.005),
                                      s.cylinder("obstacle", [*o, 0.0], R, 0.02, color="#d62728")))
    return sol


@problem("3.22", "CLIK with Jacobian inverse and Jacobian transpose on the SCARA", kind="simulation")
def problem_3_22() -> Solution:
    """SCARA (a1 = a2 = 0.5 m) tracking x = [p, φ] from [0.7, 0, 0, 0] to [0, 0.8, 0.5, π/2] in 2 s
    (sinusoidal timing, held until 2.5 s; the manual's "x_dy" is the whole x_d), with the analytical
    Jacobian (S3.3), K = diag(500, 500, 500, 100); (A) the inverse law (3.70) (Fig. S3.7), (B) the
    transpose law (3.76) (Fig. S3.9); Euler 1 ms; q(0) from the closed-form IK (2.20), elbow-up.
    Data: companion file i3_22 (p_z = d3 directly in DH frame 0). Figs. S3.6/S3.8 are Simulink block
    diagrams: here the loop is :class:`CLIK` on :func:`simulate`.
    """
    from rigid_body.kinematics import ELBOW_UP, inverse_kinematics_scara

    sol = Solution()
    robot = load("scara")
    x_i = sol.given("x_i = [p, φ]", np.array([0.7, 0.0, 0.0, 0.0]), unit="m, rad")
    x_f = sol.given("x_f = [p, φ]", np.array([0.0, 0.8, 0.5, np.pi / 2]), unit="m, rad")
    q0 = inverse_kinematics_scara(x_i)[ELBOW_UP]
    sol.value("q0", q0, unit="rad (q3 in m)")
    sol.check_close("q(0) (i3_22)", q0, [0.79540, -1.59080, 0.0, 0.79540], atol=5e-6,
                    reference="independent derivation")
    ref = cosine_pose_reference(x_i[:3], x_f[:3], 2.0, x_i[3], x_f[3])
    task = TaskSpace(orientation="rpy", rows=(0, 1, 2, 3))
    out = {}
    for law, fig_name in (("inverse", "Fig. S3.7 (Jacobian inverse)"), ("transpose", "Fig. S3.9 (Jacobian transpose)")):
        res = simulate(JointIntegrator(), CLIK(robot, ref, task, K=[500.0, 500.0, 500.0, 100.0], law=law),
                       (0.0, 2.5), q0, h=1e-3)
        e = res["e"]
        e_P, e_phi = np.linalg.norm(e[:, :3], axis=1), np.abs(e[:, 3])
        out[law] = (res, e_P, e_phi)
        sol.figure(_history_figure(f"Problem 3.22 — {fig_name}", res,
                                   [("‖e_P‖ [m]", e_P), ("|e_φ| [rad]", e_phi)], robot))
        sol.value(f"max_position_error_{law}", float(e_P.max()), unit="m")
        sol.value(f"max_orientation_error_{law}", float(e_phi.max()), unit="rad")
        sol.value(f"q_final_{law}", res.q[-1], unit="rad (q3 in m)")
    (rA, ePA, eoA), (rB, ePB, eoB) = out["inverse"], out["transpose"]
    eA, eB = max(ePA.max(), eoA.max()), max(ePB.max(), eoB.max())
    sol.check("(A) tracking satisfactory (max error < 1e-4)", eA < 1e-4, f"max error {eA:.2e}")
    sol.check("(A) errors vanish at steady state (< 1e-8)", max(ePA[-1], eoA[-1]) < 1e-8,
              f"final {max(ePA[-1], eoA[-1]):.1e}")
    sol.check("(B) errors larger than (A) (> 10x) but bounded (< 5e-2)", eB > 10 * eA and eB < 5e-2,
              f"max error B {eB:.2e} vs A {eA:.2e}")
    sol.check("(B) steady state satisfactory (final error < 1e-8)", max(ePB[-1], eoB[-1]) < 1e-8,
              f"final {max(ePB[-1], eoB[-1]):.1e}")
    sol.check_close("both end at the same configuration", rA.q[-1], rB.q[-1], atol=1e-6, reference="second algorithm")
    sol.check_close("final q (indicative [2.21430, -1.28700, 0.5, 0.64350])", rA.q[-1],
                    [2.21430, -1.28700, 0.5, 0.64350], atol=1e-4, reference="independent derivation")
    s2 = np.abs(np.sin(rA.q[:, 1]))
    # Closed form: with the SCARA's a1, a2 (Table S2.3), cos ϑ2 = (r² − a1² − a2²)/(2 a1 a2) depends on the
    # planar distance r of the wrist from the base axis; |sin ϑ2| is least where r is least along the line.
    links = book_robot_spec("scara").links
    a1, a2 = links[0].a, links[1].a
    a, b = x_i[:2], x_f[:2]
    lam = np.clip(-a @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
    r_min = np.linalg.norm(a + lam * (b - a))
    sin_min = np.sqrt(1 - ((r_min**2 - a1**2 - a2**2) / (2 * a1 * a2)) ** 2)
    sol.check_close("J_A non-singular: min |sin ϑ2| along the path = the closed form at the point nearest the "
                    "base axis (0.896; the manual's 0.9 is above it)", s2.min(), sin_min, atol=1e-3,
                    reference="closed form")
    sol.animation(robot, rA, "(A) Jacobian-inverse CLIK along the segment", speed=0.5,
                  overlays=lambda s: s.polyline("path", np.array([x_i[:3], x_f[:3]]), radius=0.005))
    return sol


# --------------------------------------------------------------------------------------------
# 3.23: manipulability ellipsoids
# --------------------------------------------------------------------------------------------

@problem("3.23", "Force and velocity manipulability ellipsoids share axes", kind="derivation")
def problem_3_23() -> Solution:
    """The core of the velocity ellipsoid (3.123) is (J J^T)^{-1}, that of the force ellipsoid (3.126)
    is J J^T: same eigenvectors, reciprocal eigenvalues — same principal axes, dimensions in inverse
    proportion (semi-axes σ_i and 1/σ_i). Checked on the two-link arm (a = 1 m) at random q; the figure
    draws both ellipses at several postures."""
    sol = Solution()
    robot = load("planar_2r")
    sol.given("a1 = a2", 1.0, unit="m")
    rng = np.random.default_rng(323)
    axis_err, eig_err, semi_err = [], [], []
    for _ in range(N_RANDOM):
        q = np.array([rng.uniform(-np.pi, np.pi), rng.uniform(0.2, np.pi - 0.2) * rng.choice([-1, 1])])
        J = geometric_jacobian(robot, q)[:2]
        A = J @ J.T
        lam, U = np.linalg.eigh(A)
        lam_i, U_i = np.linalg.eigh(np.linalg.inv(A))
        axis_err.append(np.max(np.abs(np.abs(U.T @ U_i[:, ::-1]) - np.eye(2))))
        eig_err.append(np.max(np.abs(lam * lam_i[::-1] - 1.0)))
        v, f = velocity_ellipsoid(J), force_ellipsoid(J)
        s = np.linalg.svd(J, compute_uv=False)
        semi_err.append(max(np.max(np.abs(v.semi_axes - s)), np.max(np.abs(f.semi_axes - 1 / s)),
                            np.max(np.abs(v.core - np.linalg.inv(A))), np.max(np.abs(f.core - A))))
    sol.check_close("eigenvectors of JJ^T and (JJ^T)^-1 coincide", max(axis_err), 0.0, atol=1e-9,
                    reference="closed form")
    sol.check_close("eigenvalues reciprocal", max(eig_err), 0.0, atol=1e-9, reference="closed form")
    sol.check_close("semi-axes sigma_i (velocity) and 1/sigma_i (force); cores (3.123)/(3.126)", max(semi_err), 0.0,
                    atol=1e-9, reference="closed form")
    fig, ax = subplots(figsize=(7, 5))
    for k, (q1, q2) in enumerate(((np.pi / 6, np.pi / 2), (np.pi / 3, 2 * np.pi / 3), (-np.pi / 8, np.pi / 3))):
        q = np.array([q1, q2])
        pts = np.array([P[:2, 3] for P in frame_poses(robot, q, ["frame_0", "frame_1", "frame_2"])])
        J = geometric_jacobian(robot, q)[:2]
        first = k == 0
        ax.plot(pts[:, 0], pts[:, 1], "k-o", lw=2, label="arm" if first else None)
        plot_ellipse(ax, velocity_ellipsoid(J), pts[-1], color="tab:blue", label="velocity ellipse" if first else None)
        plot_ellipse(ax, force_ellipsoid(J), pts[-1], color="tab:red", ls="--", label="force ellipse" if first else None)
    ax.set_aspect("equal")
    label_axes(ax, "x [m]", "y [m]", title="velocity (solid) and force (dashed) ellipses", legend=True, grid=False)
    sol.figure(fig, "Problem 3.23 — manipulability ellipsoids of the two-link arm")
    return sol
