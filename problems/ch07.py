"""Chapter 7 — Dynamics: Problems 7.1–7.11.

Each model is computed three ways that do not share code: the book's Lagrange formulation
(:mod:`rigid_body.lagrange`), the book's recursive Newton–Euler (:mod:`rigid_body.newton_euler`) and
Pinocchio (CRBA/RNEA on the URDF with mimic rotors, :mod:`rigid_body.dynamics`). The manual's closed
forms are compared with them at random states.

Data:

* The two-link arm (Sect. 7.3.2) is ``rigid_body.book_robots.planar_2r``, confirmed by the authors'
  ``param.m``: a = 1 m, ℓ = 0.5 m, m_ℓ = 50 kg, I_ℓ = 10 kg·m², k_r = 100, m_m = 5 kg, I_m = 0.01 kg·m²,
  g = 9.81 m/s² along −y₀.
* The minimum parameters use the manual's (S7.2)/(S7.3) bookkeeping (π'₂ = 97.5, Ī₁ without I_m2).
  The companion's π'₂ = 97.51 bookkeeping is checked to give the same torques.
* The symbolic arms of 7.1, 7.3 and 7.5 get illustrative numbers, drawn at random in each check.
* The Example 7.2 trajectories and the tip force f = [500, 500] N of 7.7 are the companion's
  (tra_1/2/3, s7_7).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Ch. 7,
and its solution manual.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from controllers.plants import ArmPlant
from controllers.simulation import simulate
from planners.timing import sample, trapezoidal_law
from problems.common import frames_figure, label_axes, max_abs_error, subplots
from problems.registry import Solution, problem
from rigid_body import dynamics as dyn
from rigid_body import lagrange as lg
from rigid_body import newton_euler as ne
from rigid_body.book_robots import cartesian_skew, planar_2r, planar_3r, planar_pr
from rigid_body.dh import G, DHLink
from rigid_body.kinematics import ELBOW_DOWN, direct_kinematics, geometric_jacobian, inverse_kinematics_planar_2r
from rigid_body.operational_space import (dynamic_manipulability, dynamic_manipulability_ellipsoid,
                                          dynamically_consistent_inverse, minimum_norm_torque,
                                          minimum_norm_torque_qp, operational_space_inertia_rate,
                                          operational_space_model)
from rigid_body.manipulability import plot_ellipse
from rigid_body.regressor import (identify, minimum_parameters, payload_link_parameters,
                                  pr_minimum_parameters, pr_regressor, stack_regressor, two_link_parameters,
                                  two_link_regressor, two_link_textbook_parameters, two_link_textbook_regressor)
from rigid_body.robots import load, robot_from_dh
from rigid_body.task_space import joint_rates

N_STATES = 20  # random states per closed-form comparison




def _arm2_symbols(spec=None) -> dict:
    """The two-link arm's symbols of (7.82) read from its DH table (ℓ_i = a_i + com_x)."""
    l1, l2 = (spec or planar_2r()).links
    return dict(a1=l1.a, a2=l2.a, l1=l1.a + l1.com[0], l2=l2.a + l2.com[0], ml1=l1.mass, ml2=l2.mass,
                Il1=l1.inertia[2][2], Il2=l2.inertia[2][2], kr1=l1.gear_ratio, kr2=l2.gear_ratio,
                mm2=l2.motor_mass, Im1=float(l1.motor_inertia), Im2=float(l2.motor_inertia))


def _arm2_closed_form(s: dict, q) -> tuple[np.ndarray, float, np.ndarray]:
    """B(q), h = −mℓ2 a1 ℓ2 s2 and g(q) of the two-link arm, Eq. (7.82) (gravity along −y₀)."""
    c2, s2 = np.cos(q[1]), np.sin(q[1])
    b11 = (s["Il1"] + s["ml1"] * s["l1"] ** 2 + s["kr1"] ** 2 * s["Im1"] + s["Il2"]
           + s["ml2"] * (s["a1"] ** 2 + s["l2"] ** 2 + 2 * s["a1"] * s["l2"] * c2) + s["Im2"] + s["mm2"] * s["a1"] ** 2)
    b12 = s["Il2"] + s["ml2"] * (s["l2"] ** 2 + s["a1"] * s["l2"] * c2) + s["kr2"] * s["Im2"]
    b22 = s["Il2"] + s["ml2"] * s["l2"] ** 2 + s["kr2"] ** 2 * s["Im2"]
    h = -s["ml2"] * s["a1"] * s["l2"] * s2
    g2 = s["ml2"] * s["l2"] * G * np.cos(q[0] + q[1])
    g1 = (s["ml1"] * s["l1"] + s["mm2"] * s["a1"] + s["ml2"] * s["a1"]) * G * np.cos(q[0]) + g2
    return np.array([[b11, b12], [b12, b22]]), h, np.array([g1, g2])


# --------------------------------------------------------------------------------------------
# 7.1
# --------------------------------------------------------------------------------------------


def _error_checks(sol: Solution, rows: list[tuple[str, float, float, str]]) -> None:
    """One :meth:`Solution.check_error` per row ``(name, error, tolerance, reference)``."""
    for name, error, tol, reference in rows:
        sol.check_error(name, error, tol, reference)

@problem("7.1", "Dynamic model of a two-link Cartesian arm with joint-2 axis at π/4 to joint 1", kind="derivation")
def problem_7_1() -> Solution:
    """Lagrange model of the Cartesian arm of Fig. 7.3 with joint axis 2 at π/4 to axis 1 (Fig. S7.1).

    The arm is ``rigid_body.book_robots.cartesian_skew``: z₀ = [0 0 1], z₁ = [1/√2 0 1/√2], g₀ = [0 0 −g],
    rotor i on axis i at the origin of frame i−1. The manual's link and motor Jacobians
    (7.16)–(7.29), B (7.32), C = O and g (7.39) are checked against the library's Lagrange model
    and against Pinocchio. The masses, rotor inertias and gear ratios are symbols in the manual;
    here they are drawn at random.
    """
    sol = Solution()
    rng = np.random.default_rng(71)
    r2 = 1 / np.sqrt(2)
    worst = dict(jac=0.0, B=0.0, C=0.0, g=0.0, pin=0.0)
    for _ in range(5):
        m_l, m_m, I_m, k_r = rng.uniform(1, 20, 2), rng.uniform(0.5, 5, 2), rng.uniform(1e-3, 1e-2, 2), rng.uniform(10, 100, 2)
        spec = cartesian_skew(m_l=m_l, m_m=m_m, I_m=I_m, k_r=k_r)
        model, robot = lg.serial_model(spec), load("cartesian_skew", m_l=m_l, m_m=m_m, I_m=I_m, k_r=k_r)
        q, qd = rng.uniform(-1, 1, (2, 2))
        bodies = {b.name: b for b in lg.body_jacobians(model, q)}
        manual = {  # (J_P, J_O) of the manual's solution
            "link_1": ([[0, 0], [0, 0], [1, 0]], np.zeros((3, 2))),
            "link_2": ([[0, r2], [0, 0], [1, r2]], np.zeros((3, 2))),
            "motor_1": (np.zeros((3, 2)), [[0, 0], [0, 0], [k_r[0], 0]]),
            "motor_2": ([[0, 0], [0, 0], [1, 0]], [[0, k_r[1] * r2], [0, 0], [0, k_r[1] * r2]]),
        }
        for name, (JP, JO) in manual.items():
            worst["jac"] = max(worst["jac"], max_abs_error(bodies[name].J_P, JP), max_abs_error(bodies[name].J_O, JO))
        B_manual = np.array([[m_l[0] + m_m[1] + k_r[0] ** 2 * I_m[0] + m_l[1], m_l[1] * r2],
                             [m_l[1] * r2, m_l[1] + k_r[1] ** 2 * I_m[1]]])
        g_manual = np.array([(m_l[0] + m_m[1] + m_l[1]) * G, m_l[1] * G * r2])
        B = lg.inertia_matrix(model, q)
        worst["B"] = max(worst["B"], max_abs_error(B, B_manual) / np.abs(B_manual).max())
        worst["C"] = max(worst["C"], np.abs(lg.coriolis_matrix(model, q, qd)).max())
        worst["g"] = max(worst["g"], max_abs_error(lg.gravity_torques(model, q), g_manual))
        worst["pin"] = max(worst["pin"], max_abs_error(dyn.inertia_matrix(robot, q), B_manual) / np.abs(B_manual).max(),
                           max_abs_error(dyn.gravity_torques(robot, q), g_manual) / np.abs(g_manual).max())
    sol.value("B_last", B, unit="kg")
    _error_checks(sol, [("link and motor Jacobians (7.16)-(7.29) equal the manual's", worst["jac"], 1e-12, "closed form"),
                        ("B (7.32) equals the manual's constant matrix (relative)", worst["B"], 1e-12, "closed form"),
                        ("B constant ⇒ C = O (Christoffel symbols vanish)", worst["C"], 1e-12, "closed form"),
                        ("g = [(mℓ1 + mm2 + mℓ2) g, mℓ2 g/√2] (7.39)", worst["g"], 1e-9, "closed form"),
                        ("Pinocchio (URDF with mimic rotors) gives the same B and g (relative)", worst["pin"], 1e-12,
                         "closed form")])
    sol.figure(frames_figure(robot, [0.4, 0.3], "Fig. S7.1 — Cartesian arm, joint axis 2 at π/4 (d1 = 0.4, d2 = 0.3)"))
    return sol


# --------------------------------------------------------------------------------------------
# 7.2
# --------------------------------------------------------------------------------------------

@problem("7.2", "Another C for the two-link arm: Ḃ − 2C not skew-symmetric, yet q̇ᵀ(Ḃ − 2C)q̇ = 0", kind="derivation")
def problem_7_2() -> Solution:
    """Show that c_ij = Σ_k (∂b_ij/∂q_k − ½ ∂b_jk/∂q_i) q̇_k satisfies (7.43) but not (7.48), Eq. (7.49).

    Two checks of the manual's matrices C, Ḃ and N = Ḃ − 2C:
    (i) sympy differentiates the symbolic b_ij of (7.82);
    (ii) the library's Lagrange model (:func:`rigid_body.lagrange.alternative_coriolis_matrix`, analytic
    ∂B/∂q) is evaluated at random states of the book's arm.
    The Christoffel C of (7.45), from the library and from Pinocchio, keeps N skew-symmetric.
    """
    import sympy as sp

    sol = Solution()
    # (i) symbolic: b_ij of (7.82) with symbols.
    q1, q2, qd1, qd2, a1, l2, ml2, k = sp.symbols("q1 q2 qd1 qd2 a1 l2 m_l2 k", real=True)
    c2 = sp.cos(q2)
    Bs = sp.Matrix([[k + 2 * ml2 * a1 * l2 * c2, sp.Symbol("b12_0") + ml2 * a1 * l2 * c2],
                    [sp.Symbol("b12_0") + ml2 * a1 * l2 * c2, sp.Symbol("b22")]])
    qs, qds = [q1, q2], [qd1, qd2]
    C_alt = sp.Matrix(2, 2, lambda i, j: sum((sp.diff(Bs[i, j], qs[m]) - sp.Rational(1, 2) * sp.diff(Bs[j, m], qs[i]))
                                             * qds[m] for m in range(2)))
    Bdot = sp.Matrix(2, 2, lambda i, j: sum(sp.diff(Bs[i, j], qs[m]) * qds[m] for m in range(2)))
    h = -ml2 * a1 * l2 * sp.sin(q2)
    C_manual = sp.Matrix([[2 * h * qd2, h * qd2], [-h * qd1 + h / 2 * qd2, -h / 2 * qd1]])
    Bdot_manual = sp.Matrix([[2 * h * qd2, h * qd2], [h * qd2, 0]])
    N_manual = sp.Matrix([[-2 * h * qd2, -h * qd2], [2 * h * qd1, h * qd1]])
    N = Bdot - 2 * C_alt
    qdv = sp.Matrix(qds)
    sol.check("sympy: C equals the manual's [[2hϑ̇2, hϑ̇2], [−hϑ̇1 + hϑ̇2/2, −hϑ̇1/2]]",
              sp.simplify(C_alt - C_manual) == sp.zeros(2, 2), reference="closed form")
    sol.check("sympy: Ḃ equals the manual's [[2hϑ̇2, hϑ̇2], [hϑ̇2, 0]]", sp.simplify(Bdot - Bdot_manual) == sp.zeros(2, 2),
              reference="closed form")
    sol.check("sympy: N = Ḃ − 2C equals the manual's [[−2hϑ̇2, −hϑ̇2], [2hϑ̇1, hϑ̇1]]",
              sp.simplify(N - N_manual) == sp.zeros(2, 2), reference="closed form")
    sol.check("sympy: N + Nᵀ ≠ 0 (not skew-symmetric)", sp.simplify(N + N.T) != sp.zeros(2, 2))
    sol.check("sympy: q̇ᵀ N q̇ ≡ 0 (7.49)", sp.simplify((qdv.T * N * qdv)[0, 0]) == 0)

    # (ii) numeric, on the book's arm with motors.
    spec = planar_2r()
    model, robot, s = lg.serial_model(spec), load("planar_2r"), sol.given("two-link arm (7.82)", _arm2_symbols(spec))
    rng = np.random.default_rng(72)
    err_C = err_N = qNq = skew_std = skew_pin = 0.0
    min_asym = np.inf
    for _ in range(N_STATES):
        q, qd = rng.uniform(-np.pi, np.pi, 2), rng.normal(size=2) * 2
        hq = -s["ml2"] * s["a1"] * s["l2"] * np.sin(q[1])
        Ca = lg.alternative_coriolis_matrix(model, q, qd)
        Cm = np.array([[2 * hq * qd[1], hq * qd[1]], [-hq * qd[0] + hq / 2 * qd[1], -hq / 2 * qd[0]]])
        Na = lg.inertia_matrix_rate(model, q, qd) - 2 * Ca
        Nm = np.array([[-2 * hq * qd[1], -hq * qd[1]], [2 * hq * qd[0], hq * qd[0]]])
        err_C = max(err_C, max_abs_error(Ca, Cm), max_abs_error(Ca @ qd, dyn.nonlinear_effects(robot, q, qd) - dyn.gravity_torques(robot, q)))
        err_N = max(err_N, max_abs_error(Na, Nm))
        qNq = max(qNq, abs(qd @ Na @ qd))
        if abs(hq * qd[0]) > 1.0:
            min_asym = min(min_asym, np.abs(Na + Na.T).max())
        Ns = lg.inertia_matrix_rate(model, q, qd) - 2 * lg.coriolis_matrix(model, q, qd)
        skew_std = max(skew_std, np.abs(Ns + Ns.T).max())
        Np = lg.inertia_matrix_rate(model, q, qd) - 2 * dyn.coriolis_matrix(robot, q, qd)
        skew_pin = max(skew_pin, np.abs(Np + Np.T).max())
    sol.check_error("numeric: the alternative C equals the manual's and C q̇ = Pinocchio's h − g", err_C, 1e-9,
                    reference="closed form")
    sol.check_error("numeric: N equals the manual's", err_N, 1e-9, reference="closed form")
    sol.check("numeric: N is not skew-symmetric", min_asym > 1.0, f"min max|N + Nᵀ| = {min_asym:.3g}")
    sol.check("numeric: q̇ᵀ N q̇ = 0 (7.49)", qNq < 1e-9, f"max |q̇ᵀNq̇| = {qNq:.2g}")
    sol.check("Christoffel C (7.45): Ḃ − 2C skew (library and Pinocchio)", max(skew_std, skew_pin) < 1e-9,
              f"library {skew_std:.2g}, Pinocchio {skew_pin:.2g}")
    return sol


# --------------------------------------------------------------------------------------------
# 7.3
# --------------------------------------------------------------------------------------------

def scara_links(m_l3: float, I_l4: float, com_z: float = -0.1) -> tuple[DHLink, ...]:
    """SCARA of Table S2.3 whose first two links are the two-link arm of Sect. 7.3.2 (Problem 7.3).

    Links 3 and 4 form one body of mass m_ℓ3 with its com on axis z₃ (at ``com_z`` in frame 4) and
    I_ℓ4 the zz element of its inertia about the com; motors 3 and 4 are massless.
    """
    arm = planar_2r().links
    return (arm[0], arm[1], DHLink(joint="prismatic", lower=0.0, upper=1.0),
            DHLink(mass=m_l3, com=(0.0, 0.0, com_z), inertia=np.diag([0.3, 0.4, I_l4])))


@problem("7.3", "Dynamic model of the SCARA manipulator", kind="derivation")
def problem_7_3() -> Solution:
    """Dynamic model of the SCARA of Fig. 2.36 (frames of Fig. S2.3), links 1–2 as the arm of Sect. 7.3.2.

    The manual writes B = B' + B'' (S7.1): B' is the two-link inertia (7.82) and B'' the last link
    (mass m_ℓ3, com on z₃, moment I_ℓ4). It also gives the Christoffel symbols c112 = c122 = −c211 = k,
    with k = −mℓ2 a1 ℓ2 s2 − mℓ3 a1 a2 s2, and g3 = mℓ3 g. These are checked against the library's
    Lagrange model and Pinocchio at random states; m_ℓ3 and I_ℓ4 are drawn at random.

    Erratum: with the manual's own convention (Fig. S2.3, joint axes pointing down,
    so gravity is +g along z₀) the gravity term is g3 = −mℓ3 g. The manual's +mℓ3 g holds with
    gravity along −z₀, that is, with the axes pointing up. Both are checked. Second erratum: the
    manual refers the frames to "Fig. S7.1"; they are those of Fig. 2.36 / Fig. S2.3 (used here).
    """
    sol = Solution()
    rng = np.random.default_rng(73)
    s = _arm2_symbols()
    worst = dict(B=0.0, C=0.0, c=0.0, g_down=0.0, g_up=0.0, pin=0.0)
    for _ in range(N_STATES // 4):
        m3, I4 = rng.uniform(1, 10), rng.uniform(0.05, 1)
        links = scara_links(m3, I4)
        down = lg.serial_model(links, gravity=(0, 0, G))
        up = lg.serial_model(links, gravity=(0, 0, -G))
        robot = robot_from_dh(links, gravity=(0, 0, G))
        for _ in range(4):
            q = np.array([*rng.uniform(-np.pi, np.pi, 2), rng.uniform(0, 1), rng.uniform(-np.pi, np.pi)])
            qd = rng.normal(size=4)
            B2, _, _ = _arm2_closed_form(s, q)
            c2, s2 = np.cos(q[1]), np.sin(q[1])
            a1, a2 = s["a1"], links[1].a
            Bm = np.zeros((4, 4))
            Bm[:2, :2] = B2
            Bm[0, 0] += m3 * (a1**2 + a2**2 + 2 * a1 * a2 * c2) + I4
            Bm[0, 1] += m3 * (a2**2 + a1 * a2 * c2) + I4
            Bm[1, 1] += m3 * a2**2 + I4
            Bm[0, 3] = Bm[1, 3] = Bm[3, 3] = I4
            Bm[2, 2] = m3
            Bm = np.triu(Bm) + np.triu(Bm, 1).T
            k = -s["ml2"] * a1 * s["l2"] * s2 - m3 * a1 * a2 * s2
            Cm = np.zeros((4, 4))
            Cm[0, 0], Cm[0, 1], Cm[1, 0] = k * qd[1], k * (qd[0] + qd[1]), -k * qd[0]
            cs = lg.christoffel_symbols(down, q)
            c_m = np.zeros((4, 4, 4))
            c_m[0, 0, 1] = c_m[0, 1, 0] = c_m[0, 1, 1] = k
            c_m[1, 0, 0] = -k
            worst["B"] = max(worst["B"], max_abs_error(lg.inertia_matrix(down, q), Bm))
            worst["C"] = max(worst["C"], max_abs_error(lg.coriolis_matrix(down, q, qd), Cm))
            worst["c"] = max(worst["c"], max_abs_error(cs, c_m))
            worst["g_down"] = max(worst["g_down"], max_abs_error(lg.gravity_torques(down, q), [0, 0, -m3 * G, 0]))
            worst["g_up"] = max(worst["g_up"], max_abs_error(lg.gravity_torques(up, q), [0, 0, m3 * G, 0]))
            worst["pin"] = max(worst["pin"], max_abs_error(dyn.inertia_matrix(robot, q), Bm),
                               max_abs_error(dyn.coriolis_matrix(robot, q, qd), Cm),
                               max_abs_error(dyn.gravity_torques(robot, q), [0, 0, -m3 * G, 0]))
    sol.value("B_example", lg.inertia_matrix(down, q), unit="kg·m² (θ₁, θ₂, θ₄), kg (d₃)")
    sol.check_error("B = B' + B'' equals the manual's b11 ... b44", worst["B"], 1e-9, reference="closed form")
    sol.check_error("Christoffel symbols: only c112 = c121 = c122 = k, c211 = −k", worst["c"], 1e-9,
                    reference="closed form")
    sol.check_error("C equals the manual's [[kϑ̇2, k(ϑ̇1+ϑ̇2), 0, 0], [−kϑ̇1, 0, 0, 0], 0, 0]", worst["C"], 1e-9,
                    reference="closed form")
    sol.check_error("axes up (gravity −z₀): g = [0, 0, mℓ3 g, 0] as in the manual", worst["g_up"], 1e-9,
                    reference="closed form")
    sol.check("erratum: axes down as in Fig. S2.3 (gravity +z₀) ⇒ g3 = −mℓ3 g", worst["g_down"] < 1e-9,
              f"max |error| = {worst['g_down']:.2g}; the manual's +mℓ3 g assumes z₀ up")
    sol.check_error("Pinocchio (URDF with mimic rotors) agrees with the manual's B, C and g3 = −mℓ3 g", worst["pin"], 1e-9,
                    reference="closed form")
    return sol


# --------------------------------------------------------------------------------------------
# 7.4
# --------------------------------------------------------------------------------------------

def _excitation(t: float, amplitude: np.ndarray, omega: np.ndarray, phase: np.ndarray) -> np.ndarray:
    """Open-loop sum-of-sines joint torques [N·m] (rows: joints, columns: harmonics)."""
    return np.sum(amplitude * np.sin(omega * t + phase), axis=1)


@problem("7.4", "Minimum parameterisation of the two-link arm model and identification", kind="derivation")
def problem_7_4() -> Solution:
    """Find a minimum set of dynamic parameters π' of the two-link arm (7.82) from (7.83)–(7.84).

    The manual's five parameters (S7.2) and regressor Y' (S7.3) are checked: Y'π' equals the
    Lagrange model, the Newton–Euler model and Pinocchio's RNEA at random states, and the stacked
    regressor has rank 5. The bookkeeping is the manual's: Ī₁ excludes I_m2 and y'₁₅ = ϑ̈₁ + k_r2 ϑ̈₂,
    so π'₂ = 97.5. The companion file ``param.m`` (π'₂ = 97.51, Ī₁ with I_m2, y'₁₅ = k_r2 ϑ̈₂) is
    checked to give the same torques. Manual erratum: its intermediate expansion of τ1, τ2 in π1..π8
    writes the coupling term of b12 as k_r²π8 instead of k_r2 π8 (checked against B(q)), and "k_r²π4"
    for k_r1²π4 (the rotor of joint 1; the same check covers it); only (S7.2),
    (S7.3) are used. The eight-parameter regressor (7.84), recalled from the textbook
    (not printed in the manual), reproduces the model but has rank 5, and the manual's combinations (S7.2) of its
    parameters give π'. With the 10 kg payload of ``load_m.m`` only π'₁ and π'₃ change.

    Identification (the book's least-squares parameter identification), an addition to the manual: ``planar_2r`` (viscous friction
    F_v = 100 N·m·s/rad, companion) is driven by open-loop sum-of-sines torques for 4 s and sampled
    every 10 ms. Noise is added to the measured τ (σ = 2 N·m) and q̈ (σ = 0.02 rad/s²). π' and F_v
    are then estimated by least squares on the regressor augmented with diag(q̇).
    """
    sol = Solution()
    spec = planar_2r()
    sol.given("two-link arm (7.82)", _arm2_symbols(spec))
    pi = sol.value("pi_prime", minimum_parameters(spec.links), unit="kg·m, kg·m², kg·m, kg·m², kg·m²")
    pi_c = sol.value("pi_prime_companion", minimum_parameters(spec.links, convention="companion"), unit="kg·m, kg·m², kg·m, kg·m², kg·m²")
    p = two_link_parameters(spec.links)
    s = _arm2_symbols(spec)
    # Physical meaning in the manual: π'1 = mm2 a1 + mℓ1 ℓ1 + mℓ2 a1, π'3 = mℓ2 ℓ2.
    sol.check_close("π'1 = mm2 a1 + mℓ1 ℓ1 + mℓ2 a1", pi[0], s["mm2"] * s["a1"] + s["ml1"] * s["l1"] + s["ml2"] * s["a1"],
                    reference="closed form")
    sol.check_close("π'3 = mℓ2 ℓ2", pi[2], s["ml2"] * s["l2"], reference="closed form")
    sol.check_close("π' (companion param.m convention) = [80, 97.51, 25, −2.5, 0.01]", pi_c, [80, 97.51, 25, -2.5, 0.01],
                    atol=1e-9, reference="manual number")
    sol.check_close("manual convention differs only by π'2 − I_m2", pi_c - pi, [0, p.Im2, 0, 0, 0], atol=1e-12,
                    reference="closed form")
    model, robot = lg.serial_model(spec), load("planar_2r")
    rng = np.random.default_rng(74)
    err = 0.0
    for _ in range(N_STATES):
        q, qd, qdd = rng.uniform(-3, 3, (3, 2))
        tau = two_link_regressor(q, qd, qdd) @ pi
        B, h, g = _arm2_closed_form(s, q)
        tau_782 = B @ qdd + np.array([h * qd[1] * qd[0] + h * (qd[0] + qd[1]) * qd[1], -h * qd[0] ** 2]) + g
        err = max(err, max_abs_error(tau, tau_782), max_abs_error(tau, lg.inverse_dynamics(model, q, qd, qdd)),
                  max_abs_error(tau, ne.inverse_dynamics(model, q, qd, qdd)), max_abs_error(tau, dyn.inverse_dynamics(robot, q, qd, qdd)),
                  max_abs_error(tau, two_link_regressor(q, qd, qdd, convention="companion") @ pi_c))
    sol.check("Y'π' (S7.3) = (7.82) = Lagrange = Newton–Euler = Pinocchio RNEA (both conventions)", err < 1e-9,
              f"max |error| = {err:.2g} N·m over {N_STATES} random states")
    # The manual's intermediate expansion of (7.82) in π1..π8 (π3 = Ī1 without I_m2): its b12 prints
    # "π7 + k_r² π8" (in τ1's ϑ̈2 and τ2's ϑ̈1 terms); the model needs π7 + k_r2 π8.
    P = two_link_textbook_parameters(p)
    a1, a2, kr1, kr2 = p.a1, p.a2, p.k_r1, p.k_r2
    err_fixed = err_printed = 0.0
    for q2 in np.random.default_rng(740).uniform(-np.pi, np.pi, N_STATES):
        c2 = np.cos(q2)
        b11 = (a1**2 * P[0] + 2 * a1 * P[1] + P[2] + kr1**2 * P[3] + (a1**2 + 2 * a1 * a2 * c2 + a2**2) * P[4]
               + (2 * a1 * c2 + 2 * a2) * P[5] + P[6] + P[7])
        b12 = (a1 * a2 * c2 + a2**2) * P[4] + (a1 * c2 + 2 * a2) * P[5] + P[6]
        b22 = a2**2 * P[4] + 2 * a2 * P[5] + P[6] + kr2**2 * P[7]
        B = lg.inertia_matrix(model, [0.0, q2])
        err_fixed = max(err_fixed, max_abs_error([[b11, b12 + kr2 * P[7]], [b12 + kr2 * P[7], b22]], B))
        err_printed = max(err_printed, abs(b12 + kr2**2 * P[7] - B[0, 1]))
    sol.check("manual erratum: in the intermediate τ1, τ2 of 7.4 the coupling b12 reads π7 + k_r²π8; with "
              "π7 + k_r2 π8 the expansion equals B(q) of the Lagrange model", err_fixed < 1e-9 and err_printed > 1.0,
              f"corrected: max |error| = {err_fixed:.2g}; as printed: b12 off by (k_r2² − k_r2) I_m2 = {err_printed:.4g} kg·m²")
    qs = rng.uniform(-3, 3, (3, 60, 2))
    Ybar = stack_regressor(two_link_regressor, *qs)
    sol.check("the stacked regressor has rank 5 (π' is minimal and identifiable)", np.linalg.matrix_rank(Ybar) == 5)
    # From the eight parameters of (7.83)-(7.84) (textbook convention Î1 = Ī1 + I_m2) to π' by (S7.2).
    p8 = two_link_parameters(spec.links, convention="companion")
    pi8 = two_link_textbook_parameters(p8)
    a1, a2, kr1 = p8.a1, p8.a2, p8.k_r1
    sol.check_close("(S7.2): π' = [a1π1 + π2 + a1π5, a1π2 + π3 + kr1²π4, a2π5 + π6, a2π6 + π7, π8]",
                    [a1 * pi8[0] + pi8[1] + a1 * pi8[4], a1 * pi8[1] + pi8[2] + kr1**2 * pi8[3], a2 * pi8[4] + pi8[5],
                     a2 * pi8[5] + pi8[6], pi8[7]], pi_c, atol=1e-12, reference="closed form")
    Y8 = stack_regressor(two_link_textbook_regressor, *qs)
    sv = np.linalg.svd(Y8 / np.abs(Y8).max(axis=0), compute_uv=False)
    sol.check("the 8-column regressor (7.84) reproduces RNEA but has rank 5 (columns scaled)",
              max_abs_error(Y8 @ pi8, Ybar @ pi) < 1e-9 and sv[4] > 1e-6 * sv[0] and sv[5] < 1e-12 * sv[0],
              f"singular values {np.array2string(sv, precision=2)}")
    pi_L = minimum_parameters(spec.links, payload=sol.given("m_L", 10.0, unit="kg"))
    sol.check_close("payload m_L = 10 kg: Δπ' = [a1 m_L, 0, a2 m_L, 0, 0]", pi_L - pi, [10.0, 0, 10.0, 0, 0], atol=1e-12,
                    reference="closed form")
    robot_L = load("planar_2r", payload=10.0)
    q, qd, qdd = rng.uniform(-3, 3, (3, 2))
    sol.check_close("with payload: Y'π'_L = Pinocchio RNEA of the arm with the payload",
                    two_link_regressor(q, qd, qdd) @ pi_L, dyn.inverse_dynamics(robot_L, q, qd, qdd), atol=1e-9,
                        reference="closed form")

    # Identification on a simulated run.
    Fv = sol.given("F_v", 100.0, unit="N·m·s/rad")
    plant = ArmPlant(robot, viscous_friction=Fv)
    amp = sol.given("excitation amplitudes", np.array([[600.0, 300.0, 200.0], [200.0, 150.0, 100.0]]), unit="N·m")
    omega = sol.given("excitation frequencies", np.array([[1.3, 3.1, 7.3], [2.2, 4.7, 9.1]]), unit="rad/s")
    phase = rng.uniform(0, 2 * np.pi, (2, 3))
    controller = lambda t, x: _excitation(t, amp, omega, phase)  # noqa: E731
    res = simulate(plant, controller, (0.0, 4.0), np.array([-np.pi / 2, 0.0, 0.0, 0.0]), h=1e-3, Ts=1e-2,
                   log=lambda t, x, u: {"qdd": plant.derivative(t, x, u)[2:]})
    q, qd, qdd, tau = res.q, res.qd, res["qdd"], res.u
    tau_meas = tau + rng.normal(scale=2.0, size=tau.shape)
    qdd_meas = qdd + rng.normal(scale=0.02, size=qdd.shape)
    Yf = np.vstack([np.hstack([two_link_regressor(q[k], qd[k], qdd_meas[k]), np.diag(qd[k])]) for k in range(len(q))])
    ident = identify(Yf, tau_meas)
    truth = np.concatenate([pi, [Fv, Fv]])
    rel = np.abs(ident.estimate - truth) / np.abs(truth)
    sol.value("pi_hat", ident.estimate[:5], unit="kg·m, kg·m², kg·m, kg·m², kg·m²")
    sol.value("Fv_hat", ident.estimate[5:], unit="N·m·s/rad")
    sol.value("identification_relative_error", rel, unit="1")
    sol.value("regressor_condition_number", ident.condition_number, unit="1")
    norm_rel = float(np.linalg.norm(ident.estimate - truth) / np.linalg.norm(truth))
    sol.value("identification_norm_error", norm_rel, unit="1")
    sol.check("identification: ‖π̂ − π‖/‖π‖ < 0.5 % and every parameter within 5 % despite noise",
              norm_rel < 5e-3 and np.all(rel < 0.05),
              f"norm {norm_rel:.2g}; per parameter {np.array2string(rel, precision=4)}; cond(Ȳ) = {ident.condition_number:.3g}")
    sol.check("identification: exact data recover π' to 1e-8",
              np.allclose(identify(np.vstack([np.hstack([two_link_regressor(q[k], qd[k], qdd[k]), np.diag(qd[k])])
                                              for k in range(len(q))]), tau).estimate, truth, rtol=1e-8))
    fig, axes = subplots(2, 1, sharex=True, figsize=(7, 5))
    tau_hat = (Yf @ ident.estimate).reshape(-1, 2)
    for j, ax in enumerate(axes):
        ax.plot(res.t, tau_meas[:, j], ".", ms=2, label="measured τ (noisy)")
        ax.plot(res.t, tau_hat[:, j], lw=1, label="Ȳ π̂")
        label_axes(ax, "t [s]" if j == len(axes) - 1 else None, f"τ{j + 1} [N·m]", legend=j == 0)
    sol.figure(fig, "Problem 7.4 — least-squares identification of π' and F_v (two-link arm)")
    return sol


# --------------------------------------------------------------------------------------------
# 7.5 / 7.8: the PR arm
# --------------------------------------------------------------------------------------------

def pr_arm(rng: np.random.Generator) -> tuple[DHLink, ...]:
    """``planar_pr`` with random link data and motors (the manual's data are symbols)."""
    spec = planar_pr(a2=rng.uniform(0.3, 1.0), l2=rng.uniform(0.1, 0.3), m_l=rng.uniform(2, 20, 2),
                     I_l2=rng.uniform(0.05, 0.5))
    l1, l2 = spec.links
    return (dataclasses.replace(l1, motor_inertia=rng.uniform(1e-3, 1e-2), motor_mass=rng.uniform(0.5, 3),
                                gear_ratio=rng.uniform(10, 100)),
            dataclasses.replace(l2, motor_inertia=rng.uniform(1e-3, 1e-2), motor_mass=rng.uniform(0.5, 3),
                                gear_ratio=rng.uniform(10, 100)))


def _pr_symbols(links) -> dict:
    l1, l2 = links
    return dict(ml1=l1.mass, ml2=l2.mass, mm2=l2.motor_mass, l2=l2.a + l2.com[0], a2=l2.a, Il2=l2.inertia[2][2],
                kr1=l1.gear_ratio, kr2=l2.gear_ratio, Im1=float(l1.motor_inertia), Im2=float(l2.motor_inertia))


@problem("7.5", "Dynamic model of the prismatic–revolute arm, with a tip payload and minimum parameters",
         kind="derivation")
def problem_7_5() -> Solution:
    """Lagrange model of the PR arm of Fig. S7.2; then a tip payload m_L and a minimum parameterisation.

    The arm is ``rigid_body.book_robots.planar_pr`` (z₁ = y₀, g₀ = [−g 0 0]) with motors added. Its link
    data and motors are drawn at random, because the manual's are symbols. Checked against the
    library's Lagrange model and Pinocchio: the manual's Jacobians, B, the Christoffel symbols
    (only c122 ≠ 0), N = Ḃ − 2C (skew), g, (S7.4)–(S7.5), the payload-modified parameters and the
    regressor Y'π'.

    Erratum: I_ℓ2 is described as the inertia "about Joint 2 axis", but the formulas
    (and 7.8, Ī_2zz = I_ℓ2) use the moment about the centre of mass. That meaning is used here.
    """
    sol = Solution()
    rng = np.random.default_rng(75)
    worst = dict(p=0.0, jac=0.0, B=0.0, c=0.0, N=0.0, g=0.0, eom=0.0, payload=0.0, Y=0.0)
    for _ in range(5):
        links = pr_arm(rng)
        s = _pr_symbols(links)
        model = lg.serial_model(links, gravity=(-G, 0, 0))
        d1, th2 = rng.uniform(-1, 1), rng.uniform(-np.pi, np.pi)
        q = np.array([d1, th2])
        qd, qdd = rng.normal(size=(2, 2))
        c2, s2 = np.cos(th2), np.sin(th2)
        R, o = lg.frames(model, q)
        worst["p"] = max(worst["p"], max_abs_error(o[1], [0, 0, d1]),
                         max_abs_error(o[2] + R[2] @ links[1].com, [-s["l2"] * c2, 0, d1 + s["l2"] * s2]), max_abs_error(R[1][:, 2], [0, 1, 0]))
        bodies = {b.name: b for b in lg.body_jacobians(model, q)}
        manual = {"link_1": ([[0, 0], [0, 0], [1, 0]], np.zeros((3, 2))),
                  "link_2": ([[0, s["l2"] * s2], [0, 0], [1, s["l2"] * c2]], [[0, 0], [0, 1], [0, 0]]),
                  "motor_1": (np.zeros((3, 2)), [[0, 0], [0, 0], [s["kr1"], 0]]),
                  "motor_2": ([[0, 0], [0, 0], [1, 0]], [[0, 0], [0, s["kr2"]], [0, 0]])}
        for name, (JP, JO) in manual.items():
            worst["jac"] = max(worst["jac"], max_abs_error(bodies[name].J_P, JP), max_abs_error(bodies[name].J_O, JO))
        b11 = s["ml1"] + s["mm2"] + s["ml2"] + s["kr1"] ** 2 * s["Im1"]
        b12 = s["ml2"] * s["l2"] * c2
        b22 = s["Il2"] + s["ml2"] * s["l2"] ** 2 + s["kr2"] ** 2 * s["Im2"]
        worst["B"] = max(worst["B"], max_abs_error(lg.inertia_matrix(model, q), [[b11, b12], [b12, b22]]))
        c_m = np.zeros((2, 2, 2))
        c_m[0, 1, 1] = -s["ml2"] * s["l2"] * s2
        worst["c"] = max(worst["c"], max_abs_error(lg.christoffel_symbols(model, q), c_m))
        N = lg.inertia_matrix_rate(model, q, qd) - 2 * lg.coriolis_matrix(model, q, qd)
        n12 = s["ml2"] * s["l2"] * s2 * qd[1]
        worst["N"] = max(worst["N"], max_abs_error(N, [[0, n12], [-n12, 0]]))
        worst["g"] = max(worst["g"], max_abs_error(lg.gravity_torques(model, q), [0, s["ml2"] * s["l2"] * G * s2]))
        tau_S74 = b11 * qdd[0] + b12 * qdd[1] - s["ml2"] * s["l2"] * s2 * qd[1] ** 2
        tau_S75 = b12 * qdd[0] + b22 * qdd[1] + s["ml2"] * s["l2"] * G * s2
        robot = robot_from_dh(links, gravity=(-G, 0, 0))
        worst["eom"] = max(worst["eom"], max_abs_error(lg.inverse_dynamics(model, q, qd, qdd), [tau_S74, tau_S75]),
                           max_abs_error(dyn.inverse_dynamics(robot, q, qd, qdd), [tau_S74, tau_S75]))
        # Payload m_L at the tip: the same formal model with m'ℓ2, ℓ'2, I'ℓ2.
        mL = rng.uniform(1, 10)
        m2p, l2p, I2p = payload_link_parameters(s["ml2"], s["l2"], s["Il2"], s["a2"], mL)
        b11p = s["ml1"] + s["mm2"] + m2p + s["kr1"] ** 2 * s["Im1"]
        b12p = m2p * l2p * c2
        b22p = I2p + m2p * l2p ** 2 + s["kr2"] ** 2 * s["Im2"]
        tau_p = [b11p * qdd[0] + b12p * qdd[1] - m2p * l2p * s2 * qd[1] ** 2,
                 b12p * qdd[0] + b22p * qdd[1] + m2p * l2p * G * s2]
        model_L = lg.serial_model(links, gravity=(-G, 0, 0), payload=mL)
        worst["payload"] = max(worst["payload"], max_abs_error(lg.inverse_dynamics(model_L, q, qd, qdd), tau_p))
        pi = pr_minimum_parameters(links, payload=mL)
        worst["Y"] = max(worst["Y"], max_abs_error(pr_regressor(q, qd, qdd) @ pi, tau_p),
                         max_abs_error(pi, [b11p, m2p * l2p, b22p]))
    sol.value("pi_prime_last", pi, unit="kg, kg·m, kg·m²")
    sol.check_error("frames of Fig. S7.2: z₁ = y₀, p₁ = [0 0 d1], p_ℓ2 = [−ℓ2c2, 0, d1 + ℓ2s2]", worst["p"], 1e-12,
                    reference="closed form")
    sol.check_error("link and motor Jacobians equal the manual's", worst["jac"], 1e-12, reference="closed form")
    sol.check_error("B = [[mℓ1+mm2+mℓ2+kr1²Im1, mℓ2ℓ2c2], [·, Iℓ2+mℓ2ℓ2²+kr2²Im2]] (Iℓ2 about the com, erratum)", worst["B"], 1e-10,
                    reference="closed form")
    sol.check_error("Christoffel symbols: only c122 = −mℓ2ℓ2s2", worst["c"], 1e-10, reference="closed form")
    sol.check_error("N = [[0, mℓ2ℓ2s2ϑ̇2], [−mℓ2ℓ2s2ϑ̇2, 0]] is skew-symmetric", worst["N"], 1e-10,
                    reference="closed form")
    sol.check_error("g = [0, mℓ2ℓ2 g s2]", worst["g"], 1e-10, reference="closed form")
    sol.check_error("(S7.4)–(S7.5) = Lagrange model = Pinocchio RNEA", worst["eom"], 1e-9, reference="closed form")
    sol.check_error("payload: m'ℓ2, ℓ'2, I'ℓ2 in the same formal model = Lagrange model with the payload", worst["payload"], 1e-9,
                    reference="closed form")
    sol.check_error("minimum parameters π' and regressor Y' reproduce the model with payload", worst["Y"], 1e-9,
                    reference="closed form")
    sol.figure(frames_figure(load("planar_pr"), [0.4, 0.6], "Fig. S7.2 — frames of the PR arm (d1 = 0.4, ϑ2 = 0.6)"))
    return sol


# --------------------------------------------------------------------------------------------
# 7.6
# --------------------------------------------------------------------------------------------

@problem("7.6", "Two-link arm model in absolute link angles", kind="derivation")
def problem_7_6() -> Solution:
    """Model of the two-link arm in the absolute angles x1 = ϑ1, x2 = ϑ1 + ϑ2, from (7.134)–(7.136).

    With J_A = [[1, 0], [1, 1]], the operational-space model of the library (B_A = J_A⁻ᵀ B J_A⁻¹,
    C_A ẋ, g_A) is compared with the manual's closed forms, including (1 − k_r2)² I_m2 in b_A11 and
    k_r2(1 − k_r2) I_m2 in b_A12. The diagonal of B_A does not depend on the configuration, and
    C_A ẋ = [h ẋ2², −h ẋ1²] has no Coriolis term (h = −mℓ2 a1 ℓ2 sin(x2 − x1)).

    Errata: "Sect. 4.3.2" should read Sect. 7.3.2, and the manual's displayed
    "C_A ẋ" matrix is garbled (a matrix is printed where a vector is meant).
    """
    sol = Solution()
    spec = planar_2r()
    model, robot, s = lg.serial_model(spec), load("planar_2r"), sol.given("two-link arm (7.82)", _arm2_symbols(spec))
    J_A = sol.given("J_A", np.array([[1.0, 0.0], [1.0, 1.0]]))
    rng = np.random.default_rng(76)
    err = dict(B=0.0, C=0.0, g=0.0, pin=0.0, diag=0.0)
    diag0 = None
    for _ in range(N_STATES):
        q, qd = rng.uniform(-np.pi, np.pi, 2), rng.normal(size=2) * 2
        x, xd = J_A @ q, J_A @ qd
        osm = operational_space_model(lg.inertia_matrix(model, q), lg.coriolis_matrix(model, q, qd),
                                      lg.gravity_torques(model, q), J_A, np.zeros((2, 2)))
        bA11 = (s["Il1"] + s["ml1"] * s["l1"] ** 2 + s["kr1"] ** 2 * s["Im1"] + s["ml2"] * s["a1"] ** 2
                + (1 - s["kr2"]) ** 2 * s["Im2"] + s["mm2"] * s["a1"] ** 2)
        bA12 = s["ml2"] * s["a1"] * s["l2"] * np.cos(x[1] - x[0]) + s["kr2"] * (1 - s["kr2"]) * s["Im2"]
        bA22 = s["Il2"] + s["ml2"] * s["l2"] ** 2 + s["kr2"] ** 2 * s["Im2"]
        hA = -s["ml2"] * s["a1"] * s["l2"] * np.sin(x[1] - x[0])
        gA = [(s["ml1"] * s["l1"] + s["mm2"] * s["a1"] + s["ml2"] * s["a1"]) * G * np.cos(x[0]),
              s["ml2"] * s["l2"] * G * np.cos(x[1])]
        err["B"] = max(err["B"], max_abs_error(osm.B_A, [[bA11, bA12], [bA12, bA22]]))
        err["C"] = max(err["C"], max_abs_error(osm.C_A @ xd, [hA * xd[1] ** 2, -hA * xd[0] ** 2]))
        err["g"] = max(err["g"], max_abs_error(osm.g_A, gA))
        pin_osm = operational_space_model(dyn.inertia_matrix(robot, q), dyn.coriolis_matrix(robot, q, qd),
                                          dyn.gravity_torques(robot, q), J_A, np.zeros((2, 2)))
        err["pin"] = max(err["pin"], max_abs_error(pin_osm.B_A, osm.B_A), max_abs_error(pin_osm.C_A @ xd, osm.C_A @ xd))
        diag0 = np.diag(osm.B_A) if diag0 is None else diag0
        err["diag"] = max(err["diag"], max_abs_error(np.diag(osm.B_A), diag0))
    sol.value("B_A_diagonal", diag0, unit="kg·m²")
    sol.check_error("B_A equals the manual's (with (1 − kr2)²Im2 and kr2(1 − kr2)Im2)", err["B"], 1e-9,
                    reference="closed form")
    sol.check("diagonal of B_A is configuration-invariant", err["diag"] < 1e-9, f"max variation {err['diag']:.2g}")
    sol.check_error("C_A ẋ = [h ẋ2², −h ẋ1²]: no Coriolis term (erratum: the manual's display is garbled)", err["C"], 1e-9,
                    reference="closed form")
    sol.check_error("g_A = [(mℓ1ℓ1 + mm2a1 + mℓ2a1) g cos x1, mℓ2ℓ2 g cos x2] (erratum: Sect. 4.3.2 → 7.3.2)", err["g"], 1e-9,
                    reference="closed form")
    sol.check_error("Pinocchio's B, C give the same B_A and C_A ẋ", err["pin"], 1e-9, reference="other library")
    direct = planar_2r(k_r=(100.0, 1.0))
    osm1 = operational_space_model(lg.inertia_matrix(lg.serial_model(direct), [0.3, 0.4]), np.zeros((2, 2)),
                                   np.zeros(2), J_A, np.zeros((2, 2)))
    no_motor = planar_2r(k_r=(100.0, 1.0), I_m=(0.01, 0.0))
    osm0 = operational_space_model(lg.inertia_matrix(lg.serial_model(no_motor), [0.3, 0.4]), np.zeros((2, 2)),
                                   np.zeros(2), J_A, np.zeros((2, 2)))
    sol.check_close("k_r2 = 1 (direct drive): I_m2 leaves b_A11 and b_A12", osm1.B_A[0], osm0.B_A[0], atol=1e-12,
                    reference="closed form")
    return sol


# --------------------------------------------------------------------------------------------
# 7.7
# --------------------------------------------------------------------------------------------

TIP_FORCE = np.array([500.0, 500.0])  # N, companion s7_7


def example_7_2_trajectories(dt: float = 1e-3) -> dict:
    """The three trajectories of Example 7.2 as the companion files tra_1, tra_2 and tra_3 build them.

    Returns {name: (t, q, qd, qdd)} with (N, 2) arrays; the initial posture puts the tip at
    (0.2, 0) m with the lower elbow (s2 > 0, ``inv_k2d``).
    """
    q_i = inverse_kinematics_planar_2r([0.2, 0.0])[ELBOW_DOWN]
    q_f = inverse_kinematics_planar_2r([1.8, 0.0])[ELBOW_DOWN]
    out = {}
    # tra_1: both joints +π/2 in 0.5 s, triangular velocity (q̇_M = 2π rad/s); held until 0.6 s.
    law = trapezoidal_law(q_i, q_i + np.pi / 2, 0.5, 2 * np.pi, triangular=True)
    tr = sample(law, times=np.arange(0.0, 0.6 + dt / 2, dt))
    out["tra_1"] = (tr.t, tr.q, tr.qd, tr.qdd)
    # tra_2: per joint q̇_M = 5 rad/s, t_a = 0.15 s, t_f,i = |Δq_i|/5 + 0.15; held until 0.66 s.
    t = np.arange(0.0, 0.66 + dt / 2, dt)
    cols = [sample(trapezoidal_law(q_i[j], q_f[j], abs(q_f[j] - q_i[j]) / 5.0 + 0.15, 5.0), times=t) for j in range(2)]
    out["tra_2"] = (t, *(np.hstack([getattr(c, k) for c in cols]) for k in ("q", "qd", "qdd")))
    # tra_3: tip along x from 0.2 to 1.8 m, ẋ_M = 5 m/s, t_a = 0.15 s (t_f = 0.47 s); inverse kinematics
    # for q and the inverse analytic Jacobian for q̇ = J⁻¹ẋ, q̈ = J⁻¹(ẍ − J̇q̇).
    t = np.arange(0.0, 0.6 + dt / 2, dt)
    xs = sample(trapezoidal_law(0.2, 1.8, 1.6 / 5.0 + 0.15, 5.0), times=t)
    robot = load("planar_2r")
    q = np.array([inverse_kinematics_planar_2r([x, 0.0])[ELBOW_DOWN] for x in xs.q[:, 0]])
    qd, qdd = np.zeros_like(q), np.zeros_like(q)
    for k in range(t.size):
        qd[k], qdd[k] = joint_rates(robot, q[k], [xs.qd[k, 0], 0.0], [xs.qdd[k, 0], 0.0], rows=(0, 1))
    out["tra_3"] = (t, q, qd, qdd)
    return out


@problem("7.7", "Joint torques of the two-link arm along the trajectories of Example 7.2, with tip forces",
         kind="programming")
def problem_7_7() -> Solution:
    """Compute the joint torques of the arm of Example 7.2 along its three trajectories with a tip force.

    The model is the manual's: τ = Y'(q, q̇, q̈) π' + Jᵀ(q) f (S7.3, (7.42)), with f = [500, 500] N the
    force the end effector exerts on the environment (companion s7_7). Two independent routes must
    agree with it: Newton–Euler with f_{n+1} = f (7.111), and Pinocchio RNEA + Jᵀf. The trajectories
    are built by the companion files tra_1/2/3; they are checked to reach their end points, and the
    torques are plotted (Figs. S7.3–S7.5).

    Caution: the companion's ``inv_d`` codes the tip-force torques inconsistently
    with Jᵀf (row 2 contains a1 c1 f_x). The correct (7.42) is used here, so the manual's figures may
    differ in the force part.
    """
    sol = Solution()
    spec = planar_2r()
    model, robot = lg.serial_model(spec), load("planar_2r")
    sol.given("two-link arm (7.82)", _arm2_symbols(spec))
    sol.given("tip positions x_i, x_f (y = 0)", np.array([0.2, 1.8]), unit="m")
    pi = minimum_parameters(spec.links)
    f3 = np.array([*sol.given("tip force", TIP_FORCE, unit="N"), 0.0])
    trajectories = example_7_2_trajectories()
    q_i = inverse_kinematics_planar_2r([0.2, 0.0])[ELBOW_DOWN]
    sol.check_close("lower-elbow initial posture q(0) = [−1.4706, 2.9413] rad (derived value)", q_i,
                    [-1.4706, 2.9413], atol=5e-5, reference="independent derivation")
    titles = {"tra_1": "S7.3: trajectory 1 (joints, triangular velocity)",
              "tra_2": "S7.4: trajectory 2 (joints, trapezoidal velocity)",
              "tra_3": "S7.5: trajectory 3 (straight tip path)"}
    for name, (t, q, qd, qdd) in trajectories.items():
        tau, tau_free = np.empty_like(q), np.empty_like(q)
        err_ne = err_pin = 0.0
        for k in range(t.size):
            J = geometric_jacobian(robot, q[k])[:2]
            tau_free[k] = two_link_regressor(q[k], qd[k], qdd[k]) @ pi
            tau[k] = tau_free[k] + J.T @ TIP_FORCE
            err_ne = max(err_ne, max_abs_error(ne.inverse_dynamics(model, q[k], qd[k], qdd[k], f_tip=f3), tau[k]))
            err_pin = max(err_pin, max_abs_error(dyn.inverse_dynamics(robot, q[k], qd[k], qdd[k]) + J.T @ TIP_FORCE, tau[k]))
        scale = np.abs(tau).max()
        sol.value(f"{name}_tau_peak", np.abs(tau).max(axis=0), unit="N·m")
        sol.check(f"{name}: Y'π' + Jᵀf = Newton–Euler with tip force = Pinocchio RNEA + Jᵀf",
                  max(err_ne, err_pin) < 1e-10 * scale, f"NE {err_ne:.2g}, Pinocchio {err_pin:.2g} N·m (peak {scale:.4g})")
        tip = direct_kinematics(robot, q[-1])[:2, 3]
        if name == "tra_1":
            sol.check_close("tra_1: both joints moved by +π/2", q[-1] - q[0], [np.pi / 2, np.pi / 2], atol=1e-12,
                            reference="closed form")
        else:
            sol.check_close(f"{name}: the tip ends at (1.8, 0) m", tip, [1.8, 0.0], atol=1e-9, reference="closed form")
        # After the motion (hold), the torque is static: τ = g(q_f) + Jᵀf.
        J = geometric_jacobian(robot, q[-1])[:2]
        sol.check_close(f"{name}: at rest at the end τ = g(q_f) + Jᵀ(q_f) f", tau[-1],
                        lg.gravity_torques(model, q[-1]) + J.T @ TIP_FORCE, atol=1e-9 * scale, reference="closed form")
        fig, ax = subplots(figsize=(6.4, 3.6))
        for j in range(2):
            ax.plot(t, tau[:, j], c=f"C{j}", label=f"τ{j + 1}")
            ax.plot(t, tau_free[:, j], c=f"C{j}", ls=":", lw=1, label=f"τ{j + 1} without tip force (Example 7.2)")
        label_axes(ax, "t [s]", "joint torque [N·m]", legend=True, fontsize="x-small")
        fig.suptitle(f"Problem 7.7 — Fig. {titles[name]}\ntip force f = [500, 500] N", fontsize="medium")
        sol.figure(fig)
    sol.animation(robot, trajectories["tra_3"][:2], "trajectory 3: straight tip path", speed=0.5)
    t, q, qd, qdd = trajectories["tra_2"]
    durations = [abs(d) / 5.0 + 0.15 for d in inverse_kinematics_planar_2r([1.8, 0.0])[ELBOW_DOWN] - q_i]
    sol.value("tra_2_durations", np.array(durations), unit="s")
    sol.check_close("tra_2 durations ≈ 0.354 s and 0.558 s (derived values)", durations, [0.354, 0.558], atol=1e-3,
                    reference="independent derivation")
    sol.check("tra_2: joint velocities never exceed 5 rad/s", np.abs(qd).max() <= 5.0 + 1e-9,
              f"max |q̇| = {np.abs(qd).max():.6g}")
    return sol


# --------------------------------------------------------------------------------------------
# 7.8
# --------------------------------------------------------------------------------------------

@problem("7.8", "Newton–Euler model of the PR arm and comparison with the Lagrange model", kind="derivation")
def problem_7_8() -> Solution:
    """Derive the model of the PR arm of 7.5 with the recursive Newton–Euler algorithm (7.107)–(7.114).

    The library's recursion (:mod:`rigid_body.newton_euler`, frames of Fig. S7.2: R⁰₁ =
    [[−1,0,0],[0,0,1],[0,1,0]], z^{i−1}_{mi} = z₀) is compared, quantity by quantity, with the
    manual's forward and backward recursions at random states. Its torques are also compared with
    the Lagrange model (S7.4)–(S7.5) and Pinocchio. The same code reproduces the two-link arm (7.82),
    including the k_r2 I_m2 coupling of the rotor. m_1 = m_ℓ1 + m_m2, m_2 = m_ℓ2, ℓ_C2 = ℓ2 − a2 < 0.
    """
    sol = Solution()
    rng = np.random.default_rng(78)
    worst = dict(R=0.0, fwd=0.0, bwd=0.0, tau=0.0, lag=0.0, arm2=0.0)
    for _ in range(5):
        links = pr_arm(rng)
        s = _pr_symbols(links)
        model = lg.serial_model(links, gravity=(-G, 0, 0))
        robot = robot_from_dh(links, gravity=(-G, 0, 0))
        q = np.array([rng.uniform(-1, 1), rng.uniform(-np.pi, np.pi)])
        qd, qdd = rng.normal(size=(2, 2))
        c2, s2 = np.cos(q[1]), np.sin(q[1])
        m1, m2 = s["ml1"] + s["mm2"], s["ml2"]
        a2, lC2 = s["a2"], s["l2"] - s["a2"]
        L = lC2 + a2
        R, _ = lg.frames(model, q)
        worst["R"] = max(worst["R"], max_abs_error(R[1], [[-1, 0, 0], [0, 0, 1], [0, 1, 0]]),
                         max_abs_error(R[1].T @ R[2], [[c2, -s2, 0], [s2, c2, 0], [0, 0, 1]]))
        r = ne.newton_euler(model, q, qd, qdd)
        fwd = [(r.omega[0], [0, 0, 0]), (r.omega_dot[0], [0, 0, 0]), (r.p_ddot[0], [-G, qdd[0], 0]),
               (r.pc_ddot[0], [-G, qdd[0], 0]), (r.omega_dot_m[0], [0, 0, s["kr1"] * qdd[0]]),
               (r.omega[1], [0, 0, qd[1]]), (r.omega_dot[1], [0, 0, qdd[1]]),
               (r.p_ddot[1], [s2 * qdd[0] - a2 * qd[1] ** 2 - G * c2, c2 * qdd[0] + a2 * qdd[1] + G * s2, 0]),
               (r.pc_ddot[1], [s2 * qdd[0] - L * qd[1] ** 2 - G * c2, c2 * qdd[0] + L * qdd[1] + G * s2, 0]),
               (r.omega_dot_m[1], [0, 0, s["kr2"] * qdd[1]])]
        worst["fwd"] = max(worst["fwd"], max(max_abs_error(a, b) for a, b in fwd))
        mu2z = m2 * L * c2 * qdd[0] + (s["Il2"] + m2 * L ** 2) * qdd[1] + m2 * L * G * s2
        f1 = [-m2 * L * s2 * qdd[1] - m2 * L * c2 * qd[1] ** 2 - (m1 + m2) * G,
              (m1 + m2) * qdd[0] + m2 * L * c2 * qdd[1] - m2 * L * s2 * qd[1] ** 2, 0]
        bwd = [(r.f[1], [m2 * s2 * qdd[0] - m2 * L * qd[1] ** 2 - m2 * G * c2, m2 * c2 * qdd[0] + m2 * L * qdd[1] + m2 * G * s2, 0]),
               (r.mu[1][2], mu2z), (r.f[0], f1)]
        worst["bwd"] = max(worst["bwd"], max(max_abs_error(a, b) for a, b in bwd))
        tau2 = m2 * L * c2 * qdd[0] + (s["Il2"] + m2 * L ** 2 + s["kr2"] ** 2 * s["Im2"]) * qdd[1] + m2 * L * G * s2
        tau1 = (m1 + m2 + s["kr1"] ** 2 * s["Im1"]) * qdd[0] + m2 * L * c2 * qdd[1] - m2 * L * s2 * qd[1] ** 2
        worst["tau"] = max(worst["tau"], max_abs_error(r.tau, [tau1, tau2]))
        worst["lag"] = max(worst["lag"], max_abs_error(r.tau, lg.inverse_dynamics(model, q, qd, qdd)),
                           max_abs_error(r.tau, dyn.inverse_dynamics(robot, q, qd, qdd)))
    arm2 = lg.serial_model(planar_2r())
    s = _arm2_symbols()
    for _ in range(N_STATES):
        q, qd, qdd = rng.uniform(-3, 3, (3, 2))
        B, h, g = _arm2_closed_form(s, q)
        tau_782 = B @ qdd + np.array([h * qd[1] * qd[0] + h * (qd[0] + qd[1]) * qd[1], -h * qd[0] ** 2]) + g
        worst["arm2"] = max(worst["arm2"], max_abs_error(ne.inverse_dynamics(arm2, q, qd, qdd), tau_782))
    sol.check_error("rotations R⁰₁ and R¹₂ of Fig. S7.2", worst["R"], 1e-12, reference="closed form")
    sol.check_error("forward recursion: ω, ω̇, p̈, p̈_C, ω̇_m of links 1 and 2 equal the manual's", worst["fwd"], 1e-10,
                    reference="closed form")
    sol.check_error("backward recursion: f²₂, μ²₂,z, f¹₁ equal the manual's", worst["bwd"], 1e-10,
                    reference="closed form")
    sol.check_error("τ1, τ2 of the recursion equal the manual's", worst["tau"], 1e-10, reference="closed form")
    sol.check_error("Newton–Euler = Lagrange (S7.4)–(S7.5) = Pinocchio RNEA", worst["lag"], 1e-10,
                    reference="closed form")
    sol.check_error("Newton–Euler reproduces (7.82) of the two-link arm, with the k_r2 I_m2 coupling", worst["arm2"], 1e-9,
                    reference="closed form")
    return sol


# --------------------------------------------------------------------------------------------
# 7.9–7.11: operational space
# --------------------------------------------------------------------------------------------

def _planar_state(spec, rng, r: int = 2):
    """B, Ḃ, C, g, J (position rows), J̇ at a random state of a planar arm, q̇ = J̄ ẋ (Lagrange model)."""
    model = lg.serial_model(spec)
    q = rng.uniform(0.2, 2.5, model.n)
    B = lg.inertia_matrix(model, q)
    J = lg.geometric_jacobian(model, q)[:r]
    qd = dynamically_consistent_inverse(B, J) @ rng.normal(size=r)
    return (model, q, qd, B, lg.inertia_matrix_rate(model, q, qd), lg.coriolis_matrix(model, q, qd),
            lg.gravity_torques(model, q), J, lg.geometric_jacobian_rate(model, q, qd)[:r])


@problem("7.9", "Skew-symmetry of Ḃ_A − 2C_A in the operational-space model", kind="derivation")
def problem_7_9() -> Solution:
    """Show that Ḃ_A − 2C_A is skew-symmetric, with C_A = B_A J_A B⁻¹ C J̄_A − B_A J̇_A J̄_A.

    Checked at random states of the two-link arm (square J_A) and of the redundant three-link arm
    ``planar_3r`` (2-D position task, q̇ = J̄_A ẋ):
    * Ḃ_A from the manual's formula equals a central finite difference of B_A along the motion;
    * the manual's decomposition J̄_Aᵀ(Ḃ − 2C)J̄_A + B_A J̇_A J̄_A − J̄_Aᵀ J̇_Aᵀ B_A holds;
    * the sum is skew-symmetric.
    """
    sol = Solution()
    rng = np.random.default_rng(79)
    for label, spec in (("two-link", planar_2r()), ("three-link redundant", planar_3r())):
        err_fd = err_dec = skew = 0.0
        for _ in range(N_STATES // 2):
            model, q, qd, B, Bd, C, g, J, Jd = _planar_state(spec, rng)
            osm = operational_space_model(B, C, g, J, Jd)
            BAd = operational_space_inertia_rate(B, Bd, J, Jd)
            eps = 1e-6

            def B_A(t):
                qt = q + t * qd
                return operational_space_model(lg.inertia_matrix(model, qt), C, g, lg.geometric_jacobian(model, qt)[:2],
                                               Jd).B_A

            fd = (B_A(eps) - B_A(-eps)) / (2 * eps)
            err_fd = max(err_fd, max_abs_error(BAd, fd) / np.abs(fd).max())
            N = BAd - 2 * osm.C_A
            Jb = osm.J_bar
            dec = Jb.T @ (Bd - 2 * C) @ Jb + osm.B_A @ Jd @ Jb - Jb.T @ Jd.T @ osm.B_A
            err_dec = max(err_dec, max_abs_error(N, dec) / max(1.0, np.abs(N).max()))
            skew = max(skew, np.abs(N + N.T).max() / max(1.0, np.abs(N).max()))
        sol.check(f"{label}: Ḃ_A (manual's formula) = finite difference of B_A", err_fd < 1e-6, f"relative {err_fd:.2g}")
        sol.check(f"{label}: Ḃ_A − 2C_A = J̄ᵀ(Ḃ − 2C)J̄ + B_A J̇ J̄ − J̄ᵀ J̇ᵀ B_A", err_dec < 1e-10, f"relative {err_dec:.2g}")
        sol.check(f"{label}: Ḃ_A − 2C_A is skew-symmetric", skew < 1e-10, f"relative max |N + Nᵀ| = {skew:.2g}")
    return sol


@problem("7.10", "Minimum-B⁻¹-norm joint torques producing a given end-effector force", kind="derivation")
def problem_7_10() -> Solution:
    """Find τ with J̄_Aᵀ τ = γ_A minimising ½(τ − τ_a)ᵀ B⁻¹ (τ − τ_a) (redundant arm).

    On the three-link arm ``planar_3r`` (2-D position task), at random states, the manual's two forms
    of the solution are compared: the Lagrange-multiplier form
    B J̄(J̄ᵀ B J̄)⁻¹ γ + (I − B J̄(J̄ᵀ B J̄)⁻¹ J̄ᵀ) τ_a and the simplified J_Aᵀ γ_A + (I − J_Aᵀ J̄_Aᵀ) τ_a.
    Both are compared with the library's closed form and with the equality-constrained QP solved by
    proxsuite. J̄_Aᵀ (I − J_Aᵀ J̄_Aᵀ) = O is also checked: the null space is dynamically consistent.
    """
    sol = Solution()
    rng = np.random.default_rng(710)
    err = dict(forms=0.0, qp=0.0, cons=0.0, null=0.0)
    for _ in range(N_STATES // 2):
        _, q, _, B, _, _, _, J, _ = _planar_state(planar_3r(), rng)
        gamma, tau_a = rng.normal(size=2) * 10, rng.normal(size=3) * 10
        Jb = dynamically_consistent_inverse(B, J)
        M = B @ Jb @ np.linalg.inv(Jb.T @ B @ Jb)
        tau_lagrange = M @ gamma + (np.eye(3) - M @ Jb.T) @ tau_a
        tau_simple = J.T @ gamma + (np.eye(3) - J.T @ Jb.T) @ tau_a
        tau = minimum_norm_torque(B, J, gamma, tau_a)
        err["forms"] = max(err["forms"], max_abs_error(tau_lagrange, tau_simple), max_abs_error(tau, tau_simple))
        err["qp"] = max(err["qp"], max_abs_error(minimum_norm_torque_qp(B, J, gamma, tau_a), tau))
        err["cons"] = max(err["cons"], max_abs_error(Jb.T @ tau, gamma))
        err["null"] = max(err["null"], np.abs(Jb.T @ (np.eye(3) - J.T @ Jb.T)).max())
    sol.value("tau_last", tau, unit="N·m")
    _error_checks(sol, [("Lagrange-multiplier form = J_Aᵀγ_A + (I − J_AᵀJ̄_Aᵀ)τ_a = library", err["forms"], 1e-9,
                         "closed form"),
                        ("proxsuite QP gives the closed-form torque", err["qp"], 1e-7, "other library"),
                        ("the constraint J̄_Aᵀ τ = γ_A holds", err["cons"], 1e-9, "property"),
                        ("J̄_Aᵀ (I − J_Aᵀ J̄_Aᵀ) = O (dynamically consistent null space)", err["null"], 1e-12,
                         "property")])
    return sol


@problem("7.11", "Dynamic manipulability measure of a nonredundant manipulator", kind="derivation")
def problem_7_11() -> Solution:
    """Define the dynamic manipulability measure by analogy with (3.56): w'(q) = √det(J B⁻¹ B⁻ᵀ Jᵀ).

    For square J and det B > 0, w' = |det J| / det B = w / det B. This is checked on the two-link arm
    (position Jacobian, det J = a1 a2 s2) at random postures. w'(q2) is then swept; the numbers
    derived for this arm are a peak w' ≈ 4.273e-5 at q2 ≈ 1.790 rad, and w' = 4.176e-5 with det B = 23948.98
    at q2 = π/2. The dynamic manipulability ellipsoids (7.149) are drawn at three postures.
    """
    sol = Solution()
    spec = planar_2r()
    model = lg.serial_model(spec)
    sol.given("two-link arm (7.82)", _arm2_symbols(spec))
    a1, a2 = spec.links[0].a, spec.links[1].a
    rng = np.random.default_rng(711)
    err = 0.0
    for _ in range(N_STATES):
        q = rng.uniform(-np.pi, np.pi, 2)
        B, J = lg.inertia_matrix(model, q), lg.geometric_jacobian(model, q)[:2]
        w = dynamic_manipulability(J, B)
        err = max(err, abs(w - abs(np.linalg.det(J)) / np.linalg.det(B)) / w,
                  abs(w - a1 * a2 * abs(np.sin(q[1])) / np.linalg.det(B)) / w)
    sol.check("w' = √det(J B⁻¹B⁻ᵀJᵀ) = |det J|/det B = a1a2|s2|/det B", err < 1e-12, f"relative {err:.2g}")
    q2 = np.linspace(0.01, np.pi - 0.01, 2001)
    wq = np.array([dynamic_manipulability(lg.geometric_jacobian(model, [0.0, x])[:2], lg.inertia_matrix(model, [0.0, x]))
                   for x in q2])
    k = int(np.argmax(wq))
    sol.value("q2_peak", q2[k], unit="rad")
    sol.value("w_prime_max", wq[k], unit="1/(kg²·m²)")
    Bh = lg.inertia_matrix(model, [0.0, np.pi / 2])
    sol.value("det_B_half_pi", np.linalg.det(Bh), unit="kg²·m⁴")
    sol.check_close("peak of w' at q2 ≈ 1.790 rad (derived value)", q2[k], 1.790, atol=2e-3,
                    reference="independent derivation")
    sol.check_close("w'max ≈ 4.273e-5 (derived value)", wq[k], 4.273e-5, rtol=1e-3, reference="independent derivation")
    sol.check_close("det B(π/2) = 23948.98 (derived value)", np.linalg.det(Bh), 23948.98, atol=0.01,
                    reference="independent derivation")
    sol.check("w' depends on q2 only (q1 does not change it)",
              abs(dynamic_manipulability(lg.geometric_jacobian(model, [1.0, 1.0])[:2], lg.inertia_matrix(model, [1.0, 1.0]))
                  - dynamic_manipulability(lg.geometric_jacobian(model, [0.0, 1.0])[:2], lg.inertia_matrix(model, [0.0, 1.0])))
              < 1e-15)
    fig, (ax1, ax2) = subplots(1, 2, figsize=(10, 4))
    ax1.plot(q2, wq, label="w'(q2)")
    ax1.axvline(q2[k], ls="--", c="gray", label="maximum")
    label_axes(ax1, "q2 [rad]", "w'(q) [1/(kg²·m²)]", legend=True)
    for j, q in enumerate(([-0.8, 0.6], [-1.0, np.pi / 2], [-1.4, 2.4])):
        pts = lg.frames(model, q)[1][:, :2]  # origins of frames 0, 1, 2
        ax2.plot(pts[:, 0], pts[:, 1], "o-", c="k", lw=2, label="arm" if j == 0 else None)
        E = dynamic_manipulability_ellipsoid(lg.geometric_jacobian(model, q)[:2], lg.inertia_matrix(model, q))
        plot_ellipse(ax2, dataclasses.replace(E, semi_axes=E.semi_axes * 40.0), center=pts[-1], c="C0",
                     label="ellipse (7.149)" if j == 0 else None)
    ax2.set_aspect("equal")
    ax2.set_title("ellipses (7.149), semi-axes × 40", fontsize="small")
    label_axes(ax2, "x [m]", "y [m]", legend=True)
    sol.figure(fig, "Problem 7.11 — dynamic manipulability of the two-link arm")
    return sol
