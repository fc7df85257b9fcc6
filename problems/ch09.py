"""Chapter 9 — Force control: Problems 9.1–9.11.

The simulations (9.3, 9.10) and the closed-loop checks of 9.2 and 9.4 use the two-link arm of
Sect. 7.3.2 with its motors (``load("planar_2r")``, the authors' ``param.m``; joint viscous friction
F_v = diag(100, 100) N·m·s/rad), a controller sampled at T_c = 1 ms with zero-order hold and the plant
integrated by RK4 at 1 ms (the manual's minimum step), for the authors' t_d = 2.5 s.

The environment is the compliant plane of Fig. 9.16 (companion ``i9_3``): a compliant plane through o_r = [1, 0]
at π/4 to x₀, stiffness k_y = 5·10³ N/m along its normal y_c, none along x_c; the constraint ("rotated
base") frame R_c has x_c along the plane and y_c along its outward normal; the material lies on the
side y_c < y_r^c. It is a :class:`controllers.environment.CompliantPlane` (unilateral: it only
pushes; contact is kept in both runs, where it equals the authors' linear spring f_e = K (o_e − o_r)).

Errata of the manual, computed correctly and named in the checks: the sign of the Ṙ_dᵀ term in
(S9.1); the missing c₂₂ in the proportional term of 9.8; the sign of r̈ − r̈_d in 9.11; "y_c" for x_c
in the prose of 9.7.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Ch. 9,
Eqs. (9.10)–(9.11), (9.20)–(9.23), (9.28)–(9.31), (9.41), (9.55), (9.70), (9.77)–(9.85), (9.95),
Example 9.4, Figs. 9.8, 9.16; solution manual 9.1–9.11, Figs. S9.2, S9.5, S9.6.
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
import pinocchio as pin
import sympy as sp

from controllers.environment import CompliantPlane
from controllers.compiled import fast_backend
from controllers.force import (ForceWithInnerLoop, HybridForceMotionControl, compliance_equilibrium,
                               constrained_stiffness, fit_second_order, force_loop_parameters,
                               impedance_parameters, inner_position_loop_equilibrium, pi_velocity_parameters)
from controllers.operational_space import OperationalInverseDynamics, OperationalPDGravity
from controllers.plants import ArmInContact
from controllers.scenes import PLANE_FRAME, PLANE_POINT, PLANE_STIFFNESS, compliant_plane_9_16
from controllers.simulation import SimulationResult, simulate
from planners.paths import PathLaw, Segment
from planners.timing import trapezoidal_law
from problems.common import label_axes, max_abs_error, subplots
from problems.registry import Solution, problem
from rigid_body.kinematics import ELBOW_UP, inverse_kinematics_planar_2r
from rigid_body.robots import Robot, load
from rigid_body.rotations import euler_rate_matrix_zyz, rotation_to_euler_zyz, skew
from rigid_body.task_space import (contact_wrenches, reciprocal_basis, relative_euler_rate, relative_position_rate,
                                   selection_matrices, selection_projection, selection_pseudo_inverse)

T_C = 1e-3             # controller sampling period = integration step [s]
T_D = 2.5              # simulated time of the authors' runs [s]
F_V = 100.0            # joint viscous friction K_r F_m K_r [N·m·s/rad]
K_Y = PLANE_STIFFNESS  # plane stiffness along its normal [N/m] (i9_3): the plane of Fig. 9.16 (controllers.scenes)
O_R = PLANE_POINT      # a point of the undeformed plane [m]
R_C = PLANE_FRAME      # constraint frame: x_c along the plane, y_c normal
PLANAR = ("x", "y")    # the components of a planar position/force task


def _arm() -> Robot:
    return load("planar_2r")


def _plane() -> CompliantPlane:
    """The compliant plane of Fig. 9.16 (:func:`controllers.scenes.compliant_plane_9_16`): through o_r with
    outward normal y_c, stiffness k_y."""
    return compliant_plane_9_16(K_Y)


def _given_plane(sol: Solution) -> None:
    """Declare the compliant plane of 9.3, 9.4 and 9.10 (stiffness, a point, the constraint frame) and
    the joint friction as the problem's data."""
    sol.given("k_y (plane stiffness)", K_Y, unit="N/m"), sol.given("o_r (point of the plane)", O_R, unit="m")
    sol.given("R_c (constraint frame)", R_C), sol.given("F_v", F_V, unit="N·m·s/rad")


def _tra_5(sol: Solution | None = None) -> PathLaw:
    """The companion's tra_5 (9.3, 9.10): p_i = [1 + 0.2 cos(π/4), 0] → p_f = [1.2 + 0.2 cos(π/4), 0.2],
    trapezoidal s(t) with cruise ṡ_c = 0.5 m/s over t_f = 1 s, then held (with ``sol``, declared given)."""
    p_i = np.array([1.0 + 0.2 * np.cos(np.pi / 4), 0.0, 0.0])
    step, t_f, sd_c = np.array([0.2, 0.2, 0.0]), 1.0, 0.5
    if sol is not None:
        sol.given("p_i", p_i, unit="m"), sol.given("p_f − p_i", step, unit="m")
        sol.given("t_f", t_f, unit="s"), sol.given("ṡ_c", sd_c, unit="m/s")
    segment = Segment(p_i, p_i + step)
    return PathLaw(segment, trapezoidal_law(0.0, segment.length, t_f, sd_c))


class _Held:
    """``law`` as a sampled controller sees it: held over [t, t + T_c), so at a switching instant of
    the trapezoid (here t_f = 1 s, a sample) the value of the interval that starts there (right limit).

    The law is evaluated once, vectorised, at the controller's instants k T_c of [0, T_d] (the loop's
    t = k T_c exactly, T_c = ``period``); any other instant is evaluated on the spot. Like the law, it takes
    one instant or an array of them (a timing law: ``t_i``, ``t_f``)."""

    def __init__(self, law: Callable[[Any], Any], period: float = T_C):
        self.law, self.t_i, self.t_f, self.period = law, law.t_i, law.t_f, period
        self.grid = np.arange(int(round(T_D / period)) + 1) * period
        self.table = [np.asarray(v) for v in law(np.nextafter(self.grid, np.inf))]

    def __call__(self, t: Any) -> Any:
        grid, table = self.grid, self.table
        if np.ndim(t) == 0:
            i = int(round(t / self.period))
            if 0 <= i < grid.size and t == grid[i]:
                return table[0][i], table[1][i], table[2][i]
            return self.law(np.nextafter(t, np.inf))
        t = np.asarray(t, dtype=float)
        i = np.clip(np.rint(t / self.period).astype(int), 0, grid.size - 1)
        on_grid = grid[i] == t
        out = [np.array(v[i]) for v in table]
        if not on_grid.all():
            off = self.law(np.nextafter(t[~on_grid], np.inf))
            for o, v in zip(out, off):
                o[~on_grid] = v
        return tuple(out)


def _contact_animation(sol: Solution, res: SimulationResult, title: str, force_scale: float) -> None:
    """Attach the 3-D animation of a run of the two-link arm on the plane (:func:`viewer.contact_animation`): the
    undeformed plane (a 0.2 × 0.8 m patch along x_c) and the force −h_e, ``force_scale`` [m/N]."""
    from viewer import contact_animation

    sol.animation(_arm(), title=title, **contact_animation(_arm(), res, _plane().normal,
                                                           [(np.r_[O_R + 0.2 * R_C[:, 0], 0.0], (0.2, 0.8))],
                                                           force_scale))


def _in_constraint_frame(v: np.ndarray) -> np.ndarray:
    """Planar vectors (N, 2 or more) in the rotated base frame: R_cᵀ v."""
    return np.asarray(v)[:, :2] @ R_C


def _random_spd(rng: np.random.Generator, n: int) -> np.ndarray:
    A = rng.standard_normal((n, n))
    return A @ A.T + n * np.eye(n)


def _overshoot(zeta: float) -> float:
    """The relative overshoot exp(−ζπ/√(1 − ζ²)) of a second-order step response (ζ < 1)."""
    return float(np.exp(-zeta * np.pi / np.sqrt(1.0 - zeta * zeta)))


# --------------------------------------------------------------------------------------------
# 9.1
# --------------------------------------------------------------------------------------------

def _smooth_pose(rng: np.random.Generator) -> Callable[[float], tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """A random smooth motion t -> (R, ω, o, ȯ): R = exp(S(φ(t))), o(t) cubic; ω = R J_r(φ) φ̇ from the
    right Jacobian of exp (pin.Jexp3), not from a difference quotient."""
    a, b = rng.standard_normal((3, 3)), rng.standard_normal((4, 3))

    def at(t: float):
        phi, phid = a[0] + a[1] * t + a[2] * t**2, a[1] + 2 * a[2] * t
        R = pin.exp3(phi)
        o = b[0] + b[1] * t + b[2] * t**2 + b[3] * t**3
        od = b[1] + 2 * b[2] * t + 3 * b[3] * t**2
        return R, R @ pin.Jexp3(phi) @ phid, o, od

    return at


@problem("9.1", "Derive the rates (9.10), (9.11) of the end-effector position and Euler angles w.r.t. the "
         "desired frame", kind="derivation")
def problem_9_1() -> Solution:
    """Show that o^d_{d,e} = R_dᵀ(o_e − o_d) has the rate (9.10) ȯ^d_{d,e} = R_dᵀ(ȯ_e − ȯ_d) +
    Sᵀ(ω^d_d) o^d_{d,e} and the ZYZ angles φ_{d,e} of R^d_e = R_dᵀ R_e the rate (9.11)
    φ̇_{d,e} = T⁻¹(φ_{d,e}) R_dᵀ(ω_e − ω_d).

    Checked on random smooth motions of both frames against central differences (h = 10⁻⁵) of
    o^d_{d,e}(t) and of the extracted angles. Erratum: the manual's (S9.1) prints −Ṙ_dᵀ(o_e − o_d);
    the chain rule gives +Ṙ_dᵀ(o_e − o_d), which with (S9.2) yields (9.10) — the misprinted sign is
    shown to disagree with the differences.
    """
    sol = Solution()
    rng = np.random.default_rng(901)
    h = 1e-5
    err_p, err_phi, err_printed, err_S92 = [], [], [], []
    n_cases = 0
    while n_cases < 20:
        desired, actual = _smooth_pose(rng), _smooth_pose(rng)
        t = float(rng.uniform(0.0, 1.0))
        R_d, w_d, o_d, od_d = desired(t)
        R_e, w_e, o_e, od_e = actual(t)
        phi = rotation_to_euler_zyz(R_d.T @ R_e)
        if phi.singular or abs(np.sin(phi.angles[1])) < 0.2:   # keep away from sin ϑ = 0
            continue
        n_cases += 1

        def rel(tau: float) -> tuple[np.ndarray, np.ndarray]:
            Rd, _, od, _ = desired(tau)
            Re, _, oe, _ = actual(tau)
            return Rd.T @ (oe - od), rotation_to_euler_zyz(Rd.T @ Re).angles

        (p_plus, a_plus), (p_minus, a_minus) = rel(t + h), rel(t - h)
        fd_p, fd_phi = (p_plus - p_minus) / (2 * h), (a_plus - a_minus) / (2 * h)
        err_p.append(max_abs_error(relative_position_rate(R_d, o_d, od_d, w_d, o_e, od_e), fd_p))
        err_phi.append(max_abs_error(relative_euler_rate(R_d, w_d, R_e, w_e), fd_phi))
        # (S9.2): Ṙ_dᵀ = −S(ω^d_d) R_dᵀ, against the difference quotient of R_dᵀ
        Rdot_T = (desired(t + h)[0].T - desired(t - h)[0].T) / (2 * h)
        err_S92.append(max_abs_error(Rdot_T, -skew(R_d.T @ w_d) @ R_d.T))
        printed = R_d.T @ (od_e - od_d) - Rdot_T @ (o_e - o_d)      # the manual's (S9.1)
        err_printed.append(max_abs_error(printed, fd_p))
    sol.value("max_error_9_10", max(err_p), unit="m/s")
    sol.value("max_error_9_11", max(err_phi), unit="rad/s")
    sol.check_error("(9.10) matches central differences of R_dᵀ(o_e − o_d) (20 random motions)", max(err_p), 1e-6,
                    reference="finite differences")
    sol.check_error("(9.11) with the ZYZ T(φ) of (3.64) matches differences of the extracted angles", max(err_phi),
                    1e-6, reference="finite differences")
    sol.check_error("(S9.2): Ṙ_dᵀ = −S(ω^d_d) R_dᵀ (central differences of R_dᵀ)", max(err_S92), 1e-6,
                    reference="finite differences")
    sol.check_bound("erratum (S9.1): the printed sign −Ṙ_dᵀ(o_e − o_d) misses the differences (chain rule: +); "
                    "smallest miss over the 20 motions", min(err_printed), 1e-3, ">", reference="finite differences",
                    detail=f"{min(err_printed):.3g} > 1e-3 (the corrected one misses by at most {max(err_p):.1e})")
    # ω^d_{d,e} = T(φ_{d,e}) φ̇_{d,e} with the book's T: the ZYZ rate matrix at a known angle (3.64)
    T0 = euler_rate_matrix_zyz([0.3, 0.7, -0.4])
    sol.check_close("T(φ) of (3.64) at φ = [0.3, 0.7, −0.4]", T0[:, 2],
                    [np.cos(0.3) * np.sin(0.7), np.sin(0.3) * np.sin(0.7), np.cos(0.7)], atol=1e-15,
                    reference="closed form")
    return sol


# --------------------------------------------------------------------------------------------
# 9.2
# --------------------------------------------------------------------------------------------

@problem("9.2", "Equilibrium of compliance control: Eqs. (9.22)–(9.23)", kind="derivation")
def problem_9_2() -> Solution:
    """Show that with h_e = K_P dx_{e,d} (9.20), h_e = K dx_{r,e} (9.21) and dx_{r,e} = dx_{r,d} − dx_{e,d}
    the rest of compliance control is h_e = (I₆ + K K_P⁻¹)⁻¹ K dx_{r,d} (9.22),
    dx_{e,d} = K_P⁻¹(I₆ + K K_P⁻¹)⁻¹ K dx_{r,d} (9.23).

    Checks: the closed forms against a direct solve of the 12 × 12 linear system for random SPD K_P and
    PSD K of every rank 1–6; and the rest of a simulated compliance controller (operational-space PD
    with gravity compensation, Eq. 8.110) pressing the two-link arm into the plane of Fig. 9.16.
    """
    sol = Solution()
    rng = np.random.default_rng(902)
    errs = []
    for rank in range(1, 7):
        K_P = _random_spd(rng, 6)
        A = rng.standard_normal((6, rank))
        K = A @ A.T                                  # PSD of rank `rank`
        dx_rd = rng.standard_normal(6)
        # unknowns [h_e; dx_ed]:  h_e − K_P dx_ed = 0,  h_e + K dx_ed = K dx_rd
        M = np.block([[np.eye(6), -K_P], [np.eye(6), K]])
        direct = np.linalg.solve(M, np.r_[np.zeros(6), K @ dx_rd])
        h_e, dx_ed = compliance_equilibrium(K_P, K, dx_rd)
        errs.append(max_abs_error(np.r_[h_e, dx_ed], direct) / max(1.0, np.abs(direct).max()))
    sol.value("max_relative_error", max(errs), unit="1")
    sol.check_error("(9.22)–(9.23) = direct solution (numpy) of the 12 × 12 system {h = K_P dx_ed, h = K (dx_rd − "
                    "dx_ed)}, K of rank 1..6 (relative)", max(errs), 1e-10, reference="second algorithm")

    # Closed loop: PD + gravity (8.110) of the two-link arm pushing into the plane of Fig. 9.16
    _given_plane(sol)
    arm = _arm()
    K_P, K_D = sol.given("K_P", 5000.0, unit="N/m"), sol.given("K_D", 3000.0, unit="N·s/m")
    n = np.r_[R_C[:, 1]]
    x_d = O_R + R_C @ sol.given("x_d^c − o_r^c (5 cm inside the plane)", np.array([0.15, -0.05]), unit="m")
    q0 = inverse_kinematics_planar_2r(O_R + R_C @ np.array([0.15, 0.0]))[ELBOW_UP]
    plant = ArmInContact(arm, _plane(), viscous_friction=F_V)
    res = simulate(plant, OperationalPDGravity(arm, K_P, K_D, x_d, rows=(0, 1)), (0.0, T_D), plant.initial_state(q0),
                   h=T_C, Ts=T_C, backend=fast_backend(), log=lambda t, x, u: {"h_e": plant.wrench(x[:2], x[2:])[0][:2]})
    h_pred, dx_ed_pred = compliance_equilibrium(K_P * np.eye(2), K_Y * np.outer(n, n), x_d - O_R)
    sol.value("h_e_simulated", res["h_e"][-1], unit="N")
    sol.value("h_e_9_22", h_pred, unit="N")
    sol.check_close("simulated compliance control rests at h_e of (9.22) [N]", res["h_e"][-1], h_pred, atol=0.01,
                    reference="simulation vs prediction")
    sol.check_close("… and at x_d − x_e of (9.23) [m]", res["e"][-1], dx_ed_pred, atol=1e-5,
                    reference="simulation vs prediction")
    return sol


# --------------------------------------------------------------------------------------------
# 9.3
# --------------------------------------------------------------------------------------------

M_D, K_D_IMP, K_P_IMP = 100.0, 1600.0, 5000.0   # the impedance of 9.3 (equal along x_c and y_c)


def _impedance_run(reference: Any, q0: np.ndarray, period: float = T_C) -> SimulationResult:
    arm = _arm()
    plant = ArmInContact(arm, _plane(), viscous_friction=F_V)
    ctrl = OperationalInverseDynamics(arm, K_P_IMP, K_D_IMP, reference, rows=(0, 1), viscous_friction=F_V,
                                      inertia=M_D, force_feedback=True)
    return simulate(plant, ctrl, (0.0, T_D), plant.initial_state(q0), h=period, Ts=period, backend=fast_backend())


@problem("9.3", "Impedance control of the two-link arm in contact with a compliant plane inclined by π/4",
         kind="simulation")
def problem_9_3() -> Solution:
    """Impedance control with force measurement (9.30)–(9.31) of the two-link arm against the compliant
    plane of Fig. 9.16; M_d = 100 I, K_D = 1600 I, K_P = 5000 I (equal in the rotated frame, so isotropic in the
    base frame). The tip follows tra_5 (companion ``i9_3``): the segment from p_i = [1 + 0.1√2, 0] to
    p_f = [1.2 + 0.1√2, 0.2] m along x_c, 0.1 m inside the undeformed plane, trapezoidal with ṡ_c =
    0.5 m/s, t_f = 1 s, from q(0) = inv_k2u(p_i). Fig. S9.2.

    Along y_c the loop is m_d ÿ + k_D ẏ + (k_P + k_y) y = k_y y_r + k_P y_d: ω_n = 10 rad/s, ζ = 0.8,
    measured on the −500 → −250 N force transient; along x_c (free) ω_n = 7.07 rad/s, ζ = 1.13,
    measured on a second run that starts 2 cm off the (constant) reference along x_c.
    """
    sol = Solution()
    _given_plane(sol)
    sol.given("M_d, K_D, K_P (impedance)", np.array([M_D, K_D_IMP, K_P_IMP]), unit="kg, N·s/m, N/m")
    law = _tra_5(sol)
    p_i = law(0.0)[0]
    q0 = inverse_kinematics_planar_2r(p_i[:2])[ELBOW_UP]
    sol.check_close("initial posture = companion's inv_k2u(p_i) [0.96343, −1.92685] rad (not printed in the manual)",
                    q0, [0.96343, -1.92685], atol=1e-5, reference="independent derivation")
    res = _impedance_run(_Held(law), q0)
    f_c, e_c = _in_constraint_frame(res["h_e"]), _in_constraint_frame(res["e"])
    e_base = res["e"]
    f_end, e_end = sol.value("f_final", f_c[-1], unit="N"), sol.value("position_error_final", e_c[-1], unit="m")

    # closed forms of the rest along y_c, from the data
    y_dr = float((R_C.T @ (p_i[:2] - O_R))[1])                 # y_d^c − y_r^c = −0.1 m
    f_inf = K_Y * K_P_IMP / (K_P_IMP + K_Y) * y_dr             # −250 N
    e_inf = y_dr - f_inf / K_Y                                  # ỹ = y_d − y_e = −0.05 m
    sol.check_close("f_y^c(0) = k_y (y_e − y_r) = −500 N (tip 0.1 m inside)", f_c[0, 1], K_Y * y_dr, atol=1e-6,
                    reference="closed form")
    sol.check_close("f_y^c(t_d) = k_y k_P/(k_P + k_y)(y_d − y_r) = −250 N [N]", f_end[1], f_inf, rtol=1e-6,
                    reference="simulation vs prediction")
    sol.check_close("x̃_y^c(t_d) = y_d − y_r − f_∞/k_y = −0.05 m [m]", e_end[1], e_inf, rtol=1e-6,
                    reference="simulation vs prediction")
    # along x_c the continuous loop m_d x̃̈ + k_D x̃̇ + k_P x̃ = 0 from x̃(0) = 0 keeps x̃ ≡ 0 (the manual: "null");
    # the sampled law leaves an error of first order in T_c: a run at T_c/2 halves it
    ex_max = sol.value("x_tilde_x_max", float(np.abs(e_c[:, 0]).max()), unit="m")
    half = _impedance_run(_Held(law, T_C / 2), q0, T_C / 2)
    ex_half = sol.value("x_tilde_x_max_half_period", float(np.abs(_in_constraint_frame(half["e"])[:, 0]).max()), unit="m")
    sol.value("f_x_max", float(np.abs(f_c[:, 0]).max()), unit="N")
    sol.check_close("x̃_x^c null but for sampling: max|x̃_x^c| is first order in T_c (ratio 1 ms / 0.5 ms = 2)",
                    ex_max / ex_half, 2.0, rtol=0.15, reference="simulation vs prediction")
    sol.check_bound("… and small: max|x̃_x^c| at T_c = 1 ms [m]", ex_max, 1e-4)
    sol.check_close("base-frame rest: f_e = R_c [0, f_∞] = [176.78, −176.78] N", res["h_e"][-1, :2], R_C @ [0.0, f_inf],
                    atol=1e-3, reference="simulation vs prediction")

    w_y, z_y = impedance_parameters(M_D, K_D_IMP, K_P_IMP, K_Y)
    w_x, z_x = impedance_parameters(M_D, K_D_IMP, K_P_IMP)
    sol.check_close("manual: ω_nx = 7.07 rad/s, ζ_x = 1.13", [w_x, z_x], [7.07, 1.13], atol=0.005,
                    reference="manual number")
    sol.check_close("manual: ω_ny = 10 rad/s, ζ_y = 0.8", [w_y, z_y], [10.0, 0.8], atol=1e-12,
                    reference="manual number")
    fit_y = fit_second_order(res.t, f_c[:, 1], f_inf, guess=(5.0, 0.5))
    sol.value("omega_zeta_y_measured", np.array(fit_y), unit="rad/s, 1")
    sol.check_close("ω_n, ζ along y_c measured on the force transient", fit_y, [w_y, z_y], rtol=0.01,
                    reference="simulation vs prediction")
    least = float(f_c[:, 1].max())
    sol.value("force_least_negative", least, unit="N")
    sol.check_close("small overshoot: least-negative force = f_∞ − (f_0 − f_∞) e^{−ζπ/√(1−ζ²)} ≈ −246.2 N [N]",
                    least, f_inf - (K_Y * y_dr - f_inf) * _overshoot(z_y), atol=0.1, reference="simulation vs prediction")

    # x_c: a separate regulation run from 2 cm off along the plane
    offset = 0.02
    q_off = inverse_kinematics_planar_2r(p_i[:2] + R_C[:, 0] * offset)[ELBOW_UP]
    free = _impedance_run(p_i[:2], q_off)
    ex = _in_constraint_frame(free["e"])[:, 0]
    fit_x = fit_second_order(free.t, ex, 0.0, guess=(5.0, 1.5))
    sol.value("omega_zeta_x_measured", np.array(fit_x), unit="rad/s, 1")
    sol.check_close("ω_n, ζ along x_c measured on a 2 cm offset run", fit_x, [w_x, z_x], rtol=0.01,
                    reference="simulation vs prediction")

    fig, axes = subplots(2, 2, sharex=True, figsize=(10, 6))
    for row, (e, f, names) in enumerate(((e_base, res["h_e"][:, :2], ("x", "y")), (e_c, f_c, ("x_c", "y_c")))):
        for j, style in enumerate(("C0-", "C1--")):
            axes[row, 0].plot(res.t, e[:, j], style, label=f"x̃ along {names[j]}")
            axes[row, 1].plot(res.t, f[:, j], style, label=f"f along {names[j]}")
        axes[row, 0].set_ylim(-0.06, 0.06)
        axes[row, 1].set_ylim(-550, 550)
        frame = "base frame" if row == 0 else "rotated base frame"
        xlabel = "t [s]" if row == 1 else None
        label_axes(axes[row, 0], xlabel, "position error [m]", title=frame)
        label_axes(axes[row, 1], xlabel, "contact force [N]", title=frame)
    sol.figure(fig, "Fig. S9.2: impedance control against the compliant plane")
    _contact_animation(sol, res, "impedance control: the tip 0.1 m inside the plane, force −h_e (0.4 m per 500 N)", 8e-4)
    return sol


# --------------------------------------------------------------------------------------------
# 9.4
# --------------------------------------------------------------------------------------------

@problem("9.4", "Equilibrium of force control with inner position loop (Fig. 9.8)", kind="derivation")
def problem_9_4() -> Solution:
    """At the rest of Fig. 9.8 the input of K_P is null, x_d + x_F − x_e = 0, so with (9.21) and (9.41)
    x_e = x_d + C_F(K(x_r − x_e) + f_d).

    Checked on the closed loop: the two-link arm against the plane of Fig. 9.16, inverse dynamics with the
    position loop M_d = I, K_D = 40 I, K_P = 400 I, a proportional C_F = 10⁻⁴ m/N (rest compared with
    (I + C_F K)⁻¹(x_d + C_F(K x_r + f_d)), where f_e ≠ f_d) and a PI C_F (integral gain 10⁻³ m/(N·s):
    f_e → f_d). f_d = −40 N along y_c, x_d 2 cm inside the plane.
    """
    sol = Solution()
    _given_plane(sol)
    arm = _arm()
    n = R_C[:, 1]
    K = K_Y * np.outer(n, n)
    x_d = O_R + R_C @ sol.given("x_d^c", np.array([0.15, -0.02]), unit="m")
    f_d = sol.given("f_d", -40.0 * n, unit="N")
    c_F = sol.given("c_F", 1e-4, unit="m/N")
    q0 = inverse_kinematics_planar_2r(O_R + R_C @ np.array([0.15, 0.0]))[ELBOW_UP]
    plant = ArmInContact(arm, _plane(), viscous_friction=F_V)
    x_pred = inner_position_loop_equilibrium(x_d, O_R, K, c_F, f_d)
    sol.value("x_e_predicted", x_pred, unit="m")
    residual = x_pred - (x_d + c_F * (K @ (O_R - x_pred) + f_d))
    sol.check_error("(I + C_F K)⁻¹(x_d + C_F(K x_r + f_d)) satisfies the equilibrium x_e = x_d + C_F(K(x_r − x_e) + f_d)",
                    np.abs(residual).max(), 1e-12, reference="closed form")
    K_P, K_D, M_d = sol.given("K_P, K_D, M_d (position loop)", np.array([400.0, 40.0, 1.0]))
    runs = {}
    for name, K_I in (("P", 0.0), ("PI", sol.given("integral gain of the PI C_F", 1e-3, unit="m/(N·s)"))):
        ctrl = ForceWithInnerLoop(arm, K_P, K_D, M_d, c_F, x_d, f_d, K_I=K_I, rows=(0, 1), viscous_friction=F_V)
        runs[name] = simulate(plant, ctrl, (0.0, 3.0), plant.initial_state(q0), h=T_C, Ts=T_C, backend=fast_backend())
    p_run, pi_run = runs["P"], runs["PI"]
    sol.value("x_e_simulated", p_run["x_e"][-1], unit="m")
    sol.check_close("proportional C_F: simulated rest = x_e of Problem 9.4 [m]", p_run["x_e"][-1], x_pred, atol=1e-6,
                    reference="simulation vs prediction")
    f_rest = K @ (x_pred - O_R)
    sol.check_close(f"proportional C_F: the force error does not vanish: simulated rest force = K(x_e − x_r) of the "
                    f"predicted x_e, f_e·y_c = {f_rest @ n:.3f} N, not f_d·y_c = {f_d @ n:.1f} N [N]", p_run["f_e"][-1],
                    f_rest, atol=1e-6, reference="simulation vs prediction")
    sol.check_close("PI C_F: f_e → f_d [N]", pi_run["f_e"][-1], f_d, atol=0.05, reference="simulation vs prediction")
    fig, ax = subplots(figsize=(6.4, 3.4))
    for name, r in runs.items():
        ax.plot(r.t, r["f_e"] @ n, label=f"{name} force regulator")
    ax.axhline(f_d @ n, color="k", ls=":", label="f_d")
    label_axes(ax, "t [s]", "f_e along y_c [N]")
    sol.figure(fig, "Force control with inner position loop (Fig. 9.8) on the compliant plane")
    return sol


# --------------------------------------------------------------------------------------------
# 9.5 – 9.9: selection matrices
# --------------------------------------------------------------------------------------------

@problem("9.5", "λ minimising the W-weighted norm of h_e − S_f λ", kind="derivation")
def problem_9_5() -> Solution:
    """Minimising g = ½ εᵀ W ε, ε = h_e − S_f λ, gives −S_fᵀ W (h_e − S_f λ) = 0, i.e.
    λ = (S_fᵀ W S_f)⁻¹ S_fᵀ W h_e, the weighted pseudo-inverse (9.55).

    Checked for random SPD W, full-rank S_f (6 × m, m = 1..5) and h_e: against ordinary least squares
    of W^{1/2} S_f λ ≈ W^{1/2} h_e (Cholesky factor, numpy lstsq), the zero gradient, and no random
    perturbation of λ lowering g.
    """
    sol = Solution()
    rng = np.random.default_rng(905)
    err_ls, grad, worse = [], [], 0
    for m in range(1, 6):
        W = _random_spd(rng, 6)
        S_f = rng.standard_normal((6, m))
        h_e = rng.standard_normal(6)
        lam = selection_pseudo_inverse(S_f, W) @ h_e
        L = np.linalg.cholesky(W)                 # W = L Lᵀ: ‖ε‖²_W = ‖Lᵀ ε‖²
        lam_ls = np.linalg.lstsq(L.T @ S_f, L.T @ h_e, rcond=None)[0]
        err_ls.append(max_abs_error(lam, lam_ls))
        grad.append(float(np.abs(-S_f.T @ W @ (h_e - S_f @ lam)).max()))
        g = lambda l: 0.5 * (h_e - S_f @ l) @ W @ (h_e - S_f @ l)
        worse += sum(g(lam + 1e-3 * rng.standard_normal(m)) < g(lam) for _ in range(50))
    sol.value("max_error_vs_lstsq", max(err_ls), unit="N")
    sol.check_error("λ = (S_fᵀWS_f)⁻¹S_fᵀW h_e = least squares of W^½ S_f λ ≈ W^½ h_e (numpy lstsq)", max(err_ls),
                    1e-10, reference="other library")
    sol.check_error("the gradient −S_fᵀW(h_e − S_f λ) vanishes", max(grad), 1e-10, reference="closed form")
    sol.check("no perturbation of λ lowers ‖ε‖_W (250 random trials)", worse == 0, f"{worse} lower")
    return sol


@problem("9.6", "Show that (9.70) equals K' = P_f K", kind="derivation")
def problem_9_6() -> Solution:
    """With C K = K C = I₆, K' = S_f(S_fᵀ C S_f)⁻¹S_fᵀ (9.70) = S_f(S_fᵀ C S_f)⁻¹S_fᵀ C K = S_f S_f† K = P_f K
    (S_f† weighted by C, (9.55)).

    Checked for random SPD K, C = K⁻¹ and S_f of rank 1..5: K' = P_f K; and K' is the stiffness of the
    compliant environment seen through S_f: a displacement dx splits into the elastic part C S_f λ of a
    reaction h = S_f λ and a free motion S_v ν (S_fᵀ S_v = 0), and the reaction S_f λ (one linear solve of
    [C S_f, S_v][λ; ν] = dx) equals K' dx.
    """
    sol = Solution()
    rng = np.random.default_rng(906)
    err, split = [], []
    for m in range(1, 6):
        K = _random_spd(rng, 6)
        C = np.linalg.inv(K)
        S_f = rng.standard_normal((6, m))
        K1 = constrained_stiffness(S_f, C)
        P_f = selection_projection(S_f, C)
        err.append(max_abs_error(K1, P_f @ K) / np.abs(K1).max())
        S_v = reciprocal_basis(S_f)                                  # S_fᵀ S_v = 0
        dx = rng.standard_normal(6)
        lam_nu = np.linalg.solve(np.hstack([C @ S_f, S_v]), dx)
        split.append(max_abs_error(S_f @ lam_nu[:m], K1 @ dx) / np.abs(K1 @ dx).max())
    sol.value("max_relative_error", max(err), unit="1")
    sol.check_error("K' of (9.70) = P_f K (P_f = S_f S_f†, weight C) (relative)", max(err), 1e-10,
                    reference="closed form")
    sol.check_error("K' dx = the reaction S_f λ of the split dx = C S_f λ + S_v ν (one linear solve) (relative)",
                    max(split), 1e-9, reference="second algorithm")
    return sol


AXES = ("x", "y", "z", "rx", "ry", "rz")            # twist [ṗ; ω] and wrench [f; μ] components
TWIST_NAMES = ("ṗ_x", "ṗ_y", "ṗ_z", "ω_x", "ω_y", "ω_z")
WRENCH_NAMES = ("f_x", "f_y", "f_z", "μ_x", "μ_y", "μ_z")


def _blade_in_slot(blade: float, slot_length: float, depth: float) -> tuple[np.ndarray, np.ndarray]:
    """Contacts of the screwdriver's blade in the slot (constraint frame at the blade tip's centre on the
    slot bottom, x_c along the slot, z_c along the screw axis out of the hole): each wall (y = ±blade/2)
    touches the blade at two depths near both ends of the slot, the bottom (z = 0) at both ends;
    (points (k, 3), normals (k, 3): the direction of the force the slot exerts on the blade)."""
    a = 0.4 * slot_length
    pts, nrm = [], []
    for side in (1.0, -1.0):                          # the wall at y = ±blade/2 pushes towards ∓y
        for x in (a, -a):
            for z in (0.25 * depth, 0.75 * depth):
                pts.append([x, side * blade / 2, z])
                nrm.append([0.0, -side, 0.0])
    for x in (a, -a):                                 # the bottom pushes the blade out of the slot
        pts.append([x, 0.0, 0.0])
        nrm.append([0.0, 0.0, 1.0])
    return np.array(pts), np.array(nrm)


def _screw_in_hole(shank: float, lead: float) -> tuple[np.ndarray, np.ndarray]:
    """Contacts of the screw in its threaded hole: the shank (radius ``shank``) against the hole wall at two
    depths, four points each (radial normals), and the thread's flanks (radius 0.9·shank, three points
    120° apart) on the helicoid z = (lead/2π)φ + c, whose normal at (ρ, φ) is (h sin φ, −h cos φ, ρ),
    h = lead/2π; a null lead is a circular groove (normal z_c): the screw turns without advancing."""
    h = lead / (2 * np.pi)
    pts, nrm = [], []
    for z in (-2.0 * shank, -5.0 * shank):
        for phi in np.arange(4) * np.pi / 2:
            pts.append([shank * np.cos(phi), shank * np.sin(phi), z])
            nrm.append([-np.cos(phi), -np.sin(phi), 0.0])
    rho = 0.9 * shank
    for phi in np.arange(3) * 2 * np.pi / 3:
        pts.append([rho * np.cos(phi), rho * np.sin(phi), -3.0 * shank + h * phi])
        nrm.append([h * np.sin(phi), -h * np.cos(phi), rho])
    return np.array(pts), np.array(nrm)


def _screwdriver_twists(geometry: dict) -> tuple[np.ndarray, np.ndarray]:
    """(twist space T (6 × 2), reaction-wrench space W (6 × 4)) of the screwdriver: the blade slides in the
    slot (the blade–slot pair's twists) and turns with the screw (the screw–hole pair's), T the sum of the
    two pairs' twist spaces (both about the constraint frame's origin), W its reciprocal complement."""
    blade = reciprocal_basis(contact_wrenches(*_blade_in_slot(geometry["blade"], geometry["slot_length"],
                                                              geometry["depth"])))
    screw = reciprocal_basis(contact_wrenches(*_screw_in_hole(geometry["shank"], geometry["lead"])))
    U, sigma, _ = np.linalg.svd(np.hstack([blade, screw]))
    T = U[:, :int(np.sum(sigma > 1e-9 * sigma[0]))]
    return T, reciprocal_basis(T)


def _vanishing(S: np.ndarray) -> np.ndarray:
    """Mask of the components that vanish on every column of S (a natural constraint on that component)."""
    return np.all(np.abs(S) < 1e-9, axis=1)


def _contact_gap_rates(geometry: dict, xi: np.ndarray, eps: float = 1e-7) -> float:
    """max over the contacts of |ġ_i|: the rate at which the screwdriver moving along the twist ξ (its finite
    motion exp(εξ) by Pinocchio, central differences in ε) opens or closes a contact. The blade slides in
    the slot by the part of ξ the screw cannot take: the screw first turns/advances by the helical part."""
    h = geometry["lead"] / (2 * np.pi)
    axis = np.array([0.0, 0.0, h, 0.0, 0.0, 1.0]) / np.hypot(h, 1.0)
    screw_part = (xi @ axis) * axis                    # ξ = screw motion + blade's motion in the slot
    pairs = []
    for twist, (pts, nrm), surface in ((xi - screw_part, _blade_in_slot(geometry["blade"], geometry["slot_length"],
                                                                        geometry["depth"]), "planes"),
                                       (screw_part, _screw_in_hole(geometry["shank"], geometry["lead"]), "hole")):
        def gaps(e: float) -> np.ndarray:
            M = pin.exp6(pin.Motion(e * twist[:3], e * twist[3:]))
            moved = np.array([M.act(p) for p in pts])
            if surface == "planes":                     # signed distances from the wall and bottom planes
                return np.einsum("ij,ij->i", moved - pts, nrm / np.linalg.norm(nrm, axis=1, keepdims=True))
            radial = np.hypot(moved[:8, 0], moved[:8, 1]) - geometry["shank"]          # the hole's wall
            phase = moved[8:, 2] - h * np.unwrap(np.arctan2(moved[8:, 1], moved[8:, 0])) - (pts[8:, 2]
                                                                                         - h * np.arctan2(pts[8:, 1], pts[8:, 0]))
            return np.r_[radial, phase]                   # the flank's helicoid z − hφ = const
        pairs.append(np.abs(gaps(eps) - gaps(-eps)).max() / (2 * eps))
    return float(max(pairs))


@problem("9.7", "Natural and artificial constraints for driving a screw into a hole", kind="derivation")
def problem_9_7() -> Solution:
    """Constraint frame on the screwdriver (Fig. S9.3): it slides along the slot (x_c) and turns about
    the screw axis z_c. Natural constraints (Table S9.1): ṗ_y^c = ṗ_z^c = ω_x^c = ω_y^c = 0 and
    f_x^c = μ_z^c = 0; artificial: f_y^c, f_z^c, μ_x^c, μ_y^c, ṗ_x^c, ω_z^c.

    Derived from a contact model rather than typed: the blade in the slot (blade 1 mm thick, slot 8 mm long
    and 2 mm deep: frictionless point contacts on both walls and the bottom) and the screw in its hole
    (shank of radius 3 mm against the hole's wall, the thread's flanks); the twists each pair admits are
    the reciprocal complement of its contact wrenches [n; p × n], the screwdriver's twist space their sum,
    and the reaction wrenches the reciprocal complement of that. A natural constraint is a component that
    vanishes on the whole space. Checked against Table S9.1 and against finite motions of the geometry.
    The manual's remark: with the thread's lead p (1 mm) the screw advances ṗ_z = (p/2π) ω_z as it turns,
    so once ω_z is specified ṗ_z is determined. Erratum: the manual's prose puts the natural force
    constraint "along axis y_c"; the table and the contact model give x_c.
    """
    sol = Solution()
    geometry = dict(blade=sol.given("blade thickness = slot width", 1e-3, unit="m"),
                    slot_length=sol.given("slot length", 8e-3, unit="m"),
                    depth=sol.given("slot depth", 2e-3, unit="m"),
                    shank=sol.given("shank radius", 3e-3, unit="m"), lead=0.0)
    lead = sol.given("thread lead p (the remark's pitch)", 1e-3, unit="m")
    T, W = _screwdriver_twists(geometry)
    natural_v, natural_f = _vanishing(T), _vanishing(W)
    sol.value("twist_space_dimension", T.shape[1], unit="1")
    sol.value("natural_constraints", [n for n, z in zip(TWIST_NAMES, natural_v) if z]
              + [n for n, z in zip(WRENCH_NAMES, natural_f) if z])
    sol.value("artificial_constraints", [n for n, z in zip(WRENCH_NAMES, natural_v) if z]
              + [n for n, z in zip(TWIST_NAMES, natural_f) if z])
    # Table S9.1: natural ṗ_y, ṗ_z, ω_x, ω_y | f_x, μ_z (1 = the component is naturally constrained)
    sol.check_close("natural velocity constraints = Table S9.1: ṗ_y^c = ṗ_z^c = ω_x^c = ω_y^c = 0",
                    natural_v.astype(float), [0.0, 1, 1, 1, 1, 0], atol=0, reference="manual number")
    sol.check_close("natural force constraints = Table S9.1: f_x^c = μ_z^c = 0", natural_f.astype(float),
                    [1.0, 0, 0, 0, 0, 1], atol=0, reference="manual number")
    S_f, S_v = selection_matrices(tuple(a for a, z in zip(AXES, natural_f) if z))
    sol.value("S_v", S_v, unit="1")
    sol.value("S_f", S_f, unit="1")
    in_span = lambda A, B: np.linalg.norm(A - B @ (B.T @ A)) < 1e-9    # noqa: E731 (B orthonormal)
    sol.check("selection_matrices(('x', 'rz')) (the library's S_v, S_f of the artificial axes) span the derived "
              "twist and wrench spaces", S_v.shape == T.shape and S_f.shape == W.shape and in_span(S_v, T)
              and in_span(S_f, W), f"dim T = {T.shape[1]}, dim W = {W.shape[1]}", reference="second algorithm")
    admissible = max(_contact_gap_rates(geometry, t) for t in T.T)
    blocked = min(_contact_gap_rates(geometry, w) for w in W.T)
    sol.check_error("finite motions (Pinocchio exp6) along the derived twists keep every contact: max |ġ_i| "
                    "[m/s per unit twist]", admissible, 1e-8, reference="finite differences",
                    detail=f"along each reaction-wrench direction some contact opens at ≥ {blocked:.2g}")
    sol.check_bound("… and a motion along any reaction-wrench direction opens a contact (min over the 4 "
                    "directions of max |ġ_i|)", blocked, 1e-4, ">=", reference="finite differences")
    sol.check("erratum: the natural force constraint is along x_c, not y_c as the prose says (the walls' "
              "reactions have an f_y component, none has f_x)", natural_f[0] and not natural_f[1]
              and np.abs(W[1]).max() > 0.5, f"max |f_y| over the reaction-wrench basis {np.abs(W[1]).max():.2f}")
    # the manual's remark: a thread of lead p turns the revolute screw–hole pair into a helical one
    T_p, W_p = _screwdriver_twists(geometry | dict(lead=lead))
    turn = T_p @ np.linalg.lstsq(T_p[[0, 5]], [0.0, 1.0], rcond=None)[0]   # the admissible twist ṗ_x = 0, ω_z = 1
    sol.value("pitch_twist", turn, unit="m/s, rad/s (per rad/s of ω_z)")
    sol.check_close("with the thread (lead p): ω_z^c specified ⇒ ṗ_z^c = (p/2π) ω_z^c (manual's remark) [m/rad]",
                    turn[2], lead / (2 * np.pi), atol=1e-12, reference="closed form")
    reaction = W_p[:, np.argmax(np.abs(W_p[2]))]
    sol.value("pitch_reaction_mu_z_over_f_z", float(reaction[5] / reaction[2]), unit="m")
    sol.check("with the thread: ṗ_z^c and μ_z^c no longer vanish alone (ṗ_z − (p/2π)ω_z = 0 and "
              "μ_z + (p/2π) f_z = 0 are the natural constraints); ṗ_y, ω_x, ω_y, f_x still do",
              np.array_equal(_vanishing(T_p), [0, 1, 0, 1, 1, 0]) and np.array_equal(_vanishing(W_p), [1, 0, 0, 0, 0, 0])
              and abs(reaction[5] / reaction[2] + lead / (2 * np.pi)) < 1e-12,
              f"μ_z/f_z = {reaction[5] / reaction[2]:.4g} m")
    sol.check_error("with the thread the finite motions keep every contact too", max(_contact_gap_rates(
        geometry | dict(lead=lead), t) for t in T_p.T), 1e-8, reference="finite differences")
    return sol


@problem("9.8", "Force-controlled subspace of Example 9.4 = proportional force control with inner velocity loop",
         kind="derivation")
def problem_9_8() -> Solution:
    """With S_f^c = [0 1]ᵀ, S_v^c = [1 0]ᵀ and C'^c = diag(0, c₂₂) (Example 9.4), (9.77) gives α_x^c = α_ν and
    α_y^c = c₂₂ f_λ; with (9.81) at constant λ_d, δ̇_y^c = c₂₂ λ̇ and λ = f_y^c:
    α_y^c = −k_Dλ δ̇_y^c + c₂₂ k_Pλ (λ_d − f_y^c): P force control with an inner velocity loop.

    Derived with sympy. Erratum: the manual drops c₂₂ from the proportional term (in both its lines).
    """
    sol = Solution()
    c22, kD, kP, lam_d, f_y, d_dot, a_nu = sp.symbols("c22 k_Dlambda k_Plambda lambda_d f_y delta_dot alpha_nu")
    lam, lam_dot = sp.symbols("lambda lambda_dot")
    S_f, S_v = sp.Matrix([0, 1]), sp.Matrix([1, 0])
    C1 = sp.diag(0, c22)
    f_lambda = -kD * lam_dot + kP * (lam_d - lam)                   # (9.81), λ̇_d = λ̈_d = 0
    alpha = S_v * a_nu + C1 * S_f * f_lambda                         # (9.77)
    alpha = alpha.subs({lam_dot: d_dot / c22, lam: f_y})             # δ̇_y = c22 λ̇, λ = f_y
    derived = sp.expand(alpha[1])
    corrected = -kD * d_dot + c22 * kP * (lam_d - f_y)
    printed = -kD * d_dot + kP * (lam_d - f_y)
    sol.value("alpha_y", str(derived))
    sol.check("sympy: α_x^c of (9.77) = α_ν (manual)", sp.simplify(alpha[0] - a_nu) == 0, str(alpha[0]),
              reference="closed form")
    sol.check("sympy: α_y^c of (9.77), (9.81) = −k_Dλ δ̇_y^c + c₂₂ k_Pλ (λ_d − f_y^c) (the manual's, corrected)",
              sp.simplify(derived - corrected) == 0, str(derived), reference="closed form")
    sol.check("erratum: the manual's α_y^c (no c₂₂ on k_Pλ) differs", sp.simplify(derived - printed) != 0,
              f"difference = {sp.factor(derived - printed)}")
    return sol


@problem("9.9", "Weighted pseudo-inverses S_f†, S_v† in the constraint and base frames (Example 9.4)",
         kind="derivation")
def problem_9_9() -> Solution:
    """With C^c = [[c₁₁, c₁₂], [c₁₂, c₂₂]]: S_f^{c†} = [c₁₂/c₂₂, 1] and, with C = R_c C^c R_cᵀ and
    S_f = R_c S_f^c, S_f† = (1/√2)[(c₁₂ − c₂₂)/c₂₂, (c₁₂ + c₂₂)/c₂₂] = S_f^{c†} R_cᵀ; λ = (c₁₂/c₂₂) f_x^c + f_y^c
    in either frame (= f_y^c when f_x^c = 0, whatever the weight). Weighted by K^c: S_v^{c†} = [1, k₁₂/k₁₁],
    S_v† = (1/√2)[(k₁₁ − k₁₂)/k₁₁, (k₁₁ + k₁₂)/k₁₁].

    Symbolic (sympy) and numeric (random SPD C^c, K^c through the library's selection_pseudo_inverse).
    """
    sol = Solution()
    c11, c12, c22, k11, k12, k22, fx, fy = sp.symbols("c11 c12 c22 k11 k12 k22 f_x f_y", real=True)
    Rc = sp.Matrix([[1, -1], [1, 1]]) / sp.sqrt(2)
    Cc, Kc = sp.Matrix([[c11, c12], [c12, c22]]), sp.Matrix([[k11, k12], [k12, k22]])
    Sfc, Svc = sp.Matrix([0, 1]), sp.Matrix([1, 0])

    def pinv(S, W):
        return sp.simplify((S.T * W * S).inv() * S.T * W)

    Sf_c, Sf = pinv(Sfc, Cc), pinv(Rc * Sfc, Rc * Cc * Rc.T)
    Sv_c, Sv = pinv(Svc, Kc), pinv(Rc * Svc, Rc * Kc * Rc.T)
    cf = dict(reference="closed form")     # sympy's (9.55) against the manual's printed closed forms
    sol.check("sympy: S_f^{c†} = [c₁₂/c₂₂, 1]", sp.simplify(Sf_c - sp.Matrix([[c12 / c22, 1]])) == sp.zeros(1, 2),
              str(Sf_c), **cf)
    book_Sf = sp.Matrix([[(c12 - c22) / c22, (c12 + c22) / c22]]) / sp.sqrt(2)
    sol.check("sympy: S_f† = (1/√2)[(c₁₂ − c₂₂)/c₂₂, (c₁₂ + c₂₂)/c₂₂]", sp.simplify(Sf - book_Sf) == sp.zeros(1, 2),
              str(Sf), **cf)
    sol.check("sympy: S_f† = S_f^{c†} R_cᵀ", sp.simplify(Sf - Sf_c * Rc.T) == sp.zeros(1, 2), **cf)
    lam_c, lam_b = (Sf_c * sp.Matrix([fx, fy]))[0], (Sf * Rc * sp.Matrix([fx, fy]))[0]
    sol.check("sympy: λ = (c₁₂/c₂₂) f_x^c + f_y^c in both frames", sp.simplify(lam_c - lam_b) == 0
              and sp.simplify(lam_c - (c12 / c22 * fx + fy)) == 0, str(lam_c), **cf)
    sol.check("sympy: λ = f_y^c when f_x^c = 0, whatever the weight", sp.simplify(lam_c.subs(fx, 0) - fy) == 0, **cf)
    sol.check("sympy: S_v^{c†} = [1, k₁₂/k₁₁]", sp.simplify(Sv_c - sp.Matrix([[1, k12 / k11]])) == sp.zeros(1, 2),
              str(Sv_c), **cf)
    book_Sv = sp.Matrix([[(k11 - k12) / k11, (k11 + k12) / k11]]) / sp.sqrt(2)
    sol.check("sympy: S_v† = (1/√2)[(k₁₁ − k₁₂)/k₁₁, (k₁₁ + k₁₂)/k₁₁] = S_v^{c†} R_cᵀ",
              sp.simplify(Sv - book_Sv) == sp.zeros(1, 2) and sp.simplify(Sv - Sv_c * Rc.T) == sp.zeros(1, 2), str(Sv),
              **cf)
    # numeric: the library's (9.55) against the closed forms evaluated at random SPD matrices
    rng = np.random.default_rng(909)
    errs = []
    for _ in range(10):
        C, K = _random_spd(rng, 2), _random_spd(rng, 2)
        S_f, S_v = selection_matrices(("x",), R_C, axes=PLANAR)
        got_f = selection_pseudo_inverse(S_f, R_C @ C @ R_C.T)
        got_v = selection_pseudo_inverse(S_v, R_C @ K @ R_C.T)
        ref_f = np.array([[(C[0, 1] - C[1, 1]) / C[1, 1], (C[0, 1] + C[1, 1]) / C[1, 1]]]) / np.sqrt(2)
        ref_v = np.array([[(K[0, 0] - K[0, 1]) / K[0, 0], (K[0, 0] + K[0, 1]) / K[0, 0]]]) / np.sqrt(2)
        errs.append(max(max_abs_error(got_f, ref_f), max_abs_error(got_v, ref_v)))
    sol.value("max_numeric_error", max(errs), unit="1")
    sol.check_error("numeric S_f†, S_v† (9.55, the library) = the closed forms (10 random SPD C^c, K^c)", max(errs),
                    1e-12, reference="closed form")
    return sol


# --------------------------------------------------------------------------------------------
# 9.10
# --------------------------------------------------------------------------------------------

K_P_NU, K_I_NU, K_D_LAMBDA, K_P_LAMBDA = 16.0, 100.0, 16.0, 100.0
LAMBDA_D = -50.0          # desired force along y_c [N]
K_HAT = 4e3               # estimated plane stiffness ĉ₂₂⁻¹ [N/m]


def _hybrid_run(stiffness_estimate: float) -> SimulationResult:
    """9.10 with Ĉ = diag(1/k̂, 1/k̂) (weight of S_f†), K̂ = diag(k̂, k̂) (weight of S_v†),
    Ĉ' = diag(0, 1/k̂) in the constraint frame (companion ``i9_10``)."""
    arm = _arm()
    plant = ArmInContact(arm, _plane(), viscous_friction=F_V)
    law = _Held(_tra_5())

    def nu_reference(t: float) -> tuple[np.ndarray, np.ndarray]:
        _, pd, pdd = law(t)
        return (R_C.T @ pd[:2])[:1], (R_C.T @ pdd[:2])[:1]            # ν_d, ν̇_d along x_c

    S_f, S_v = selection_matrices(("x",), R_C, axes=PLANAR)
    C_hat = R_C @ np.diag([1.0, 1.0]) @ R_C.T / stiffness_estimate
    ctrl = HybridForceMotionControl(arm, S_f, S_v, [LAMBDA_D], nu_reference, K_P_NU, K_I_NU, K_D_LAMBDA, K_P_LAMBDA,
                                    compliance=C_hat, stiffness=np.linalg.inv(C_hat),
                                    compliance_prime=R_C @ np.diag([0.0, 1.0 / stiffness_estimate]) @ R_C.T,
                                    rows=(0, 1), viscous_friction=F_V)
    q0 = inverse_kinematics_planar_2r(O_R)[ELBOW_UP]
    return simulate(plant, ctrl, (0.0, T_D), plant.initial_state(q0), h=T_C, Ts=T_C, backend=fast_backend())


@problem("9.10", "Hybrid force/motion control of the two-link arm on the compliant plane", kind="simulation")
def problem_9_10() -> Solution:
    """Hybrid force/motion control (Example 9.4): velocity along x_c by the PI law (9.80) (k_Pν = 16,
    k_Iν = 100: ω_n = 10 rad/s, ζ = 0.8), force along y_c by (9.84) (k_Dλ = 16, k_Pλ = 100) with the plane
    stiffness known only through ĉ₂₂⁻¹ = 4·10³ N/m (true 5·10³: l_f = ĉ₂₂/c₂₂ = 1.25, ω_nλ = 11.18 rad/s,
    ζ_λ = 0.71). Tip from o_e(0) = [1, 0] on the undeformed plane, ν_d the x_c velocity of tra_5 (9.3),
    λ_d = −50 N. Figs. S9.5 (velocity error, force) and S9.6 (path and the plane at rest).

    A second run with the true stiffness (l_f = 1) gives ω = 10 rad/s, ζ = 0.8 and a smaller overshoot.
    """
    sol = Solution()
    _given_plane(sol)
    sol.given("k̂ (estimated stiffness)", K_HAT, unit="N/m"), sol.given("λ_d", LAMBDA_D, unit="N")
    sol.given("K_Pν, K_Iν, K_Dλ, K_Pλ", np.array([K_P_NU, K_I_NU, K_D_LAMBDA, K_P_LAMBDA]))
    _tra_5(sol)                                                     # its data declared; _hybrid_run follows it
    q0 = inverse_kinematics_planar_2r(O_R)[ELBOW_UP]
    sol.check_close("q(0) = [π/3, −2π/3] puts the tip at o_e(0) = [1, 0] (a₁ = a₂ = ‖o_e‖: an equilateral triangle)",
                    q0, [np.pi / 3, -2 * np.pi / 3], atol=1e-12, reference="closed form")
    res, exact = _hybrid_run(K_HAT), _hybrid_run(K_Y)
    lam, lam_x = res["lam"][:, 0], exact["lam"][:, 0]
    e_nu = res["nu_d"][:, 0] - res["nu"][:, 0]
    sol.value("force_final", float(lam[-1]), unit="N")
    sol.value("force_peak", float(lam.min()), unit="N")
    sol.value("velocity_error_max", float(np.abs(e_nu).max()), unit="m/s")

    l_f = (1.0 / K_HAT) / (1.0 / K_Y)
    w, z = force_loop_parameters(K_D_LAMBDA, K_P_LAMBDA, l_f)
    w1, z1 = force_loop_parameters(K_D_LAMBDA, K_P_LAMBDA)
    sol.check_close("manual: l_f = 1.25, ω_nλ = 11.18 rad/s, ζ_λ = 0.71", [l_f, w, z], [1.25, 11.18, 0.71], atol=0.006,
                    reference="manual number")
    sol.check_close("velocity loop: ω_nν = 10 rad/s, ζ_ν = 0.8", pi_velocity_parameters(K_P_NU, K_I_NU), [10.0, 0.8],
                    atol=1e-12, reference="manual number")
    sol.check_close("λ(t_d) = λ_d = −50 N [N]", lam[-1], LAMBDA_D, atol=1e-3, reference="simulation vs prediction")
    fit = fit_second_order(res.t, lam, LAMBDA_D, guess=(8.0, 0.6))
    sol.value("omega_zeta_measured", np.array(fit), unit="rad/s, 1")
    sol.check_close("ω_nλ, ζ_λ measured on the force transient = √(l_f k_Pλ), k_Dλ/(2√(l_f k_Pλ))", fit, [w, z],
                    rtol=0.02, reference="simulation vs prediction")
    peak = LAMBDA_D * (1.0 + _overshoot(z))
    sol.check_close("force peak = λ_d (1 + e^{−ζπ/√(1−ζ²)}) ≈ −52.0 N (4 % overshoot) [N]", lam.min(), peak, atol=0.1,
                    reference="simulation vs prediction")
    sol.check_close("velocity along x_c tracked: max |ν_d − ν| ≈ 7.8e-4 m/s (the catalogue's reference simulation)",
                    np.abs(e_nu).max(), 7.8e-4, rtol=0.05, reference="independent derivation")
    # the plane complies: deflection λ_d/k_y, the path parallel to the plane once the force has settled
    defl = _in_constraint_frame(res["p_e"][:, :2] - O_R)[:, 1]
    sol.value("deflection_final", float(defl[-1]), unit="m")
    sol.check_close("plane deflection y_e^c − y_r^c = λ_d/k_y = −0.01 m [m]", defl[-1], LAMBDA_D / K_Y, atol=1e-7,
                    reference="simulation vs prediction")
    # parallel to the plane once the force has settled: |λ − λ_d| ≤ |λ_d| e^{−ζω t}/√(1 − ζ²) (the envelope of
    # the second-order step response), so the deflection's deviation is at most that over k_y after 0.6 s
    settled = res.t > 0.6
    envelope = abs(LAMBDA_D) * np.exp(-z * w * 0.6) / np.sqrt(1 - z * z) / K_Y
    sol.check_bound("path parallel to the undeformed plane after 0.6 s: max |deflection − λ_d/k_y| ≤ the force "
                    "transient's envelope |λ_d| e^{−ζω t}/(√(1−ζ²) k_y) [m]", np.abs(defl[settled] - LAMBDA_D / K_Y).max(),
                    envelope, reference="simulation vs prediction")
    tip_end = O_R + R_C @ np.array([_tra_5().path.length, LAMBDA_D / K_Y])
    sol.check_close("final tip = o_r + R_c [D_s, λ_d/k_y] ≈ [1.20707, 0.19293] m", res["p_e"][-1, :2], tip_end,
                    atol=1e-5,
                    reference="simulation vs prediction")
    fit1 = fit_second_order(exact.t, lam_x, LAMBDA_D, guess=(8.0, 0.6))
    sol.value("omega_zeta_measured_known_stiffness", np.array(fit1), unit="rad/s, 1")
    sol.check_close("known stiffness: ω = 10 rad/s, ζ = 0.8 measured", fit1, [w1, z1], rtol=0.02,
                    reference="simulation vs prediction")
    sol.check_close("known stiffness: force peak = λ_d (1 + e^{−ζπ/√(1−ζ²)}), ζ = 0.8: −50.76 N, a smaller overshoot "
                    "than the estimate's [N]", lam_x.min(), LAMBDA_D * (1.0 + _overshoot(z1)), atol=0.1,
                    reference="simulation vs prediction")

    fig, axes = subplots(2, 1, sharex=True, figsize=(6.4, 5.0))
    axes[0].plot(res.t, e_nu, label="ĉ₂₂⁻¹ = 4·10³ N/m")
    axes[0].plot(exact.t, exact["nu_d"][:, 0] - exact["nu"][:, 0], "--", label="exact stiffness")
    axes[1].plot(res.t, lam, label="ĉ₂₂⁻¹ = 4·10³ N/m")
    axes[1].plot(exact.t, lam_x, "--", label="exact stiffness")
    axes[1].axhline(LAMBDA_D, color="k", ls=":", lw=1, label="λ_d")
    label_axes(axes[0], None, "velocity error along x_c [m/s]")
    label_axes(axes[1], "t [s]", "contact force along y_c [N]")
    sol.figure(fig, "Fig. S9.5: hybrid force/motion control")
    fig2, ax = subplots(figsize=(5.0, 5.0))
    ax.plot(res["p_e"][:, 0], res["p_e"][:, 1], "C0-", label="end-effector path")
    s = np.linspace(-0.1, 0.4, 2)
    plane = O_R[:, None] + R_C[:, :1] * s
    ax.plot(plane[0], plane[1], "k--", label="plane at rest")
    ax.set_aspect("equal")
    label_axes(ax, "x [m]", "y [m]")
    sol.figure(fig2, "Fig. S9.6: tip path and undeformed plane")
    _contact_animation(sol, res, "hybrid force/motion control (k̂ = 4·10³ N/m): force −h_e (0.25 m per 50 N)", 5e-3)
    return sol


# --------------------------------------------------------------------------------------------
# 9.11
# --------------------------------------------------------------------------------------------

class _PointOnCircle:
    """A unit point mass in the plane constrained to the circle ‖p‖ = ρ (rigid environment): x = [p, ṗ],
    m p̈ = u + Aᵀ μ with A = pᵀ/ρ and the multiplier μ keeping A p̈ = −ṗᵀṗ/ρ (KKT solve)."""

    def __init__(self, rho: float):
        self.rho = rho

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        p, v = x[:2], x[2:]
        A = p / self.rho
        mu = (-v @ v / self.rho - A @ u) / (A @ A)
        return np.concatenate((v, u + A * mu))


@problem("9.11", "Control law (9.95) achieves tracking of r_d(t)", kind="derivation")
def problem_9_11() -> Solution:
    """With q̇ = J_ρ(r) ṙ and (9.63), v_e = J q̇ = S_v ṙ, so ν = S_v† v_e = ṙ and ν̇ = r̈; the law (9.95),
    α_ν = r̈_d + K_Dr(ṙ_d − ṙ) + K_Pr(r_d − r), gives r̃̈ + K_Dr r̃̇ + K_Pr r̃ = 0 with r̃ = r_d − r.

    Checked on a constrained-motion toy: a point mass on a rigid circle of radius ρ = 0.5 m (r the arc
    length, S_v the unit tangent), simulated with its constraint force, driven by α_ν through
    y = S_v α_ν + Ṡ_v ν; r̃(t) follows the solution of the corrected closed loop. Erratum: the manual's
    "r̈ − r̈_d + K_Dr(ṙ_d − ṙ) + K_Pr(r_d − r) = 0" is r̃̈ = K_Dr r̃̇ + K_Pr r̃, unstable.
    """
    sol = Solution()
    rho = sol.given("ρ (circle radius)", 0.5, unit="m")
    K_P, K_D = sol.given("K_Pr", 25.0, unit="1/s²"), sol.given("K_Dr", 10.0, unit="1/s")   # critically damped:
    # r̃ = (r̃₀ + (r̃̇₀ + 5 r̃₀) t) e^{−5t}
    amplitude, w = sol.given("r_d amplitude", 0.3, unit="m"), sol.given("r_d frequency", 2.0, unit="rad/s")
    r_d = lambda t: (amplitude * np.sin(w * t), amplitude * w * np.cos(w * t), -amplitude * w * w * np.sin(w * t))
    plant = _PointOnCircle(rho)

    def control(t: float, x: np.ndarray) -> np.ndarray:
        p, v = x[:2], x[2:]
        theta = np.arctan2(p[1], p[0])
        tangent = np.array([-np.sin(theta), np.cos(theta)])      # S_v = dp/dr
        r, nu = rho * theta, tangent @ v                         # ν = S_v† v_e (unit tangent)
        rd, rdd, rddd = r_d(t)
        alpha_nu = rddd + K_D * (rdd - nu) + K_P * (rd - r)      # (9.95)
        S_v_dot_nu = -p / rho * (nu / rho) * nu                  # Ṡ_v ν = −(ν²/ρ) p/ρ
        return tangent * alpha_nu + S_v_dot_nu

    r0 = sol.given("r(0)", 0.2, unit="m")
    x0 = np.r_[rho * np.cos(r0 / rho), rho * np.sin(r0 / rho), 0.0, 0.0]
    res = simulate(plant, control, (0.0, 3.0), x0, h=1e-3, Ts=1e-3)
    r = rho * np.unwrap(np.arctan2(res.x[:, 1], res.x[:, 0]))
    e = np.array([r_d(t)[0] for t in res.t]) - r
    e0, ed0 = e[0], r_d(0.0)[1] - 0.0
    predicted = (e0 + (ed0 + 5.0 * e0) * res.t) * np.exp(-5.0 * res.t)
    sol.value("max_deviation_from_closed_loop", max_abs_error(e, predicted), unit="m")
    sol.value("final_error", float(e[-1]), unit="m")
    sol.check_error(f"r̃(t) = solution of r̃̈ + K_Dr r̃̇ + K_Pr r̃ = 0 (sampled law, 1 ms; r̃₀ = {e0:.2f} m, "
                    f"r̃̇₀ = {ed0:.2f} m/s) [m]", max_abs_error(e, predicted), 2e-4, reference="simulation vs prediction")
    sol.check_error("the constraint holds: ‖p‖ = ρ [m]", np.abs(np.hypot(res.x[:, 0], res.x[:, 1]) - rho).max(), 1e-6,
                    reference="simulation vs prediction")
    printed = np.roots([1.0, -K_D, -K_P])      # r̃̈ − K_D r̃̇ − K_P r̃ = 0, the manual's printed signs
    sol.check("erratum: the printed closed loop (r̈ − r̈_d first) would be unstable", printed.real.max() > 0,
              f"its roots {np.round(printed, 3)}; the corrected one has the double root −5")
    return sol


