"""Chapter 8 — Motion Control, decentralised part: Problems 8.1–8.9 (independent joint control).

Data of 8.4–8.6: the single-joint drive [DRV84] I = 6 kg·m², R_a = 0.3 Ω, k_t = 0.5 N·m/A,
k_v = 0.5 V·s/rad, F_m = 0.001 N·m·s/rad, unit transducers — recalled from the textbook statement and
confirmed by the manual's derived k_m = 2 rad/(V·s) and T_m = 7.2 s. 8.9 uses the two-link arm of
Sect. 7.3.2 (``load("planar_2r")``, motors included). Problems 8.10–8.16 are in ``ch08_centralised.py``.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 5.1, 8.3 (Figs. 5.10, 5.11, 8.6–8.17, Eqs. (8.24)–(8.42)), 8.5.3 (Eqs. (8.75)–(8.76)),
and its solution manual.
"""

from __future__ import annotations

from typing import Callable

import control
import numpy as np
import sympy as sp

from controllers.independent_joint import (JointDesign, JointDrive, PositionVelocityController,
                                           Transducers, acceleration_filter, bandwidth,
                                           design_position_feedback, design_position_velocity,
                                           design_position_velocity_acceleration, feedforward_controller_output,
                                           feedforward_reference, feedforward_tracking, inertia_bounds,
                                           position_feedback, position_velocity_acceleration_feedback,
                                           position_velocity_feedback)
from controllers.plants import JointDrivePlant
from controllers.simulation import simulate
from planners.timing import trapezoidal_law
from problems.common import subplots, label_axes
from problems.registry import Solution, problem
from rigid_body.actuators import frequency_samples
from rigid_body.dynamics import inertia_matrix
from rigid_body.robots import load

DRIVE_84 = dict(I=6.0, Ra=0.3, kt=0.5, kv=0.5, Fm=0.001)   # [DRV84]
OMEGA = np.logspace(-3, 3, 61)
ZETA, OMEGA_N, X_R_SPEC = 0.4, 20.0, 400.0                   # specifications of 8.4–8.6


def _random_case(rng: np.random.Generator) -> tuple[JointDrive, Transducers, dict[str, float]]:
    drive = JointDrive(I=rng.uniform(0.5, 10), Ra=rng.uniform(0.1, 2), kt=rng.uniform(0.1, 2),
                       kv=rng.uniform(0.1, 2))
    t = Transducers(*rng.uniform(0.5, 2, 3))
    gains = dict(K_P=rng.uniform(0.5, 50), K_V=rng.uniform(0.5, 50), K_A=rng.uniform(0.1, 5),
                 T_P=rng.uniform(0.1, 20))
    return drive, t, gains


S, KM, TM, RA_KT = sp.symbols("s k_m T_m R_a/k_t", positive=True)
THETA_R, DIST, THETA = sp.symbols("Theta_r D Theta_m")


def _symbolic_loop(equation: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """(Θ_m/Θ_r, Θ_m/D) from a block equation ``Θ_m = f(Θ_m, Θ_r, D)`` solved with sympy (the check's reference)."""
    theta = sp.solve(sp.Eq(THETA, equation), THETA)[0]
    return sp.diff(theta, THETA_R), sp.diff(theta, DIST)


def _rel(G: control.TransferFunction, manual: np.ndarray, w: np.ndarray = OMEGA) -> float:
    return float(np.max(np.abs(frequency_samples(G, w) - manual) / np.abs(manual)))


def _worst_over_random_drives(seed: int, pairs: Callable) -> list[float]:
    """The largest relative errors, over 5 random drives, transducers and gains at the 61 frequencies, of
    the pairs (library transfer function, manual's closed form at s = jω) that ``pairs(d, t, g, s)`` lists."""
    rng = np.random.default_rng(seed)
    worst: list[float] = []
    for _ in range(5):
        d, t, g = _random_case(rng)
        errors = [_rel(G, manual) for G, manual in pairs(d, t, g, 1j * OMEGA)]
        worst = [max(a, b) for a, b in zip(worst, errors)] if worst else errors
    return worst


@problem("8.1", "Transfer functions of independent joint control with position feedback", kind="derivation")
def problem_8_1() -> Solution:
    """Forward path, return path and closed-loop transfer functions of Fig. 5.10 (PI position control).

    The library reduces the blocks Θ_m = M(C_P(Θ_r − k_TP Θ_m) − (R_a/k_t) D); the manual's closed
    forms are compared at 61 frequencies for 5 random drives, gains and transducers. Manual erratum:
    the intermediate "Θ_m/D = −M/(1 + PH)" omits the disturbance gain R_a/k_t; the final expression
    (with R_a/k_t) is the one checked.
    """
    sol = Solution()
    def pairs(d, t, g, s):
        loop = position_feedback(d, g["K_P"], g["T_P"], t)
        km, Tm, KP, TP, kTP = d.k_m, d.T_m, g["K_P"], g["T_P"], t.k_TP
        den = 1 + s**2 * (1 + s * Tm) / (km * KP * kTP * (1 + s * TP))
        return [(loop.reference, (1 / kTP) / den),
                (loop.disturbance, -(s * d.Ra / (d.kt * KP * kTP * (1 + s * TP))) / den),
                (loop.P, km * KP * (1 + s * TP) / (s**2 * (1 + s * Tm)))]

    worst = _worst_over_random_drives(81, pairs)
    K_P, T_P, k_TP = sp.symbols("K_P T_P k_TP", positive=True)
    M = KM / (S * (1 + S * TM))
    ref, dist = _symbolic_loop(M * (K_P * (1 + S * T_P) / S * (THETA_R - k_TP * THETA) - RA_KT * DIST))
    den = 1 + S**2 * (1 + S * TM) / (KM * K_P * k_TP * (1 + S * T_P))
    sol.check("sympy: block equation of Fig. 5.10 solved = manual's Θ_m/Θ_r and Θ_m/D",
              sp.simplify(ref - (1 / k_TP) / den) == 0
              and sp.simplify(dist + (S * RA_KT / (K_P * k_TP * (1 + S * T_P))) / den) == 0, "simplify(difference) = 0",
              reference="closed form")
    sol.check("P(s) = k_m K_P(1 + sT_P)/(s²(1 + sT_m)), H(s) = k_TP", worst[2] < 1e-9, f"max rel. error {worst[2]:.2e}")
    sol.check("Θ_m/Θ_r = (1/k_TP)/(1 + s²(1 + sT_m)/(k_m K_P k_TP(1 + sT_P)))", worst[0] < 1e-9,
              f"max relative error {worst[0]:.2e} (61 frequencies × 5 random cases)")
    sol.check("Θ_m/D = −(sR_a/(k_t K_P k_TP(1 + sT_P)))/(same denominator) — manual erratum: the intermediate "
              "−M/(1 + PH) omits R_a/k_t", worst[1] < 1e-9, f"max relative error {worst[1]:.2e}")
    return sol


@problem("8.2", "Transfer functions with position and velocity feedback", kind="derivation")
def problem_8_2() -> Solution:
    """Closed-loop transfer functions of Fig. 5.11 (position loop K_P, PI velocity loop C_V) with T_V = T_m.

    Library block reduction vs the manual's closed forms, 5 random cases at 61 frequencies; the
    reduced return path H(s) = k_TP(1 + s k_TV/(K_P k_TP)) of Fig. S8.1 is checked too.
    """
    sol = Solution()
    def pairs(d, t, g, s):
        km, KP, KV = d.k_m, g["K_P"], g["K_V"]
        loop = position_velocity_feedback(d, KP, KV, d.T_m, t)
        den = 1 + s * t.k_TV / (KP * t.k_TP) + s**2 / (km * KP * t.k_TP * KV)
        return [(loop.reference, (1 / t.k_TP) / den),
                (loop.disturbance, -(s * d.Ra / (d.kt * KP * t.k_TP * KV * (1 + s * d.T_m))) / den),
                (loop.H, t.k_TP * (1 + s * t.k_TV / (KP * t.k_TP)))]

    worst = _worst_over_random_drives(82, pairs)
    K_P, K_V, k_TP, k_TV = sp.symbols("K_P K_V k_TP k_TV", positive=True)
    M = KM / (S * (1 + S * TM))
    C_V = K_V * (1 + S * TM) / S                                          # T_V = T_m
    ref, dist = _symbolic_loop(M * (C_V * (K_P * (THETA_R - k_TP * THETA) - k_TV * S * THETA) - RA_KT * DIST))
    den = 1 + S * k_TV / (K_P * k_TP) + S**2 / (KM * K_P * k_TP * K_V)
    sol.check("sympy: block equation of Fig. 5.11 (T_V = T_m) solved = manual's Θ_m/Θ_r and Θ_m/D",
              sp.simplify(ref - (1 / k_TP) / den) == 0
              and sp.simplify(dist + (S * RA_KT / (K_P * k_TP * K_V * (1 + S * TM))) / den) == 0,
              "simplify(difference) = 0", reference="closed form")
    sol.check("H(s) = k_TP(1 + s k_TV/(K_P k_TP)) (Fig. S8.1)", worst[2] < 1e-9, f"max rel. error {worst[2]:.2e}")
    sol.check("Θ_m/Θ_r = (1/k_TP)/(1 + s k_TV/(K_P k_TP) + s²/(k_m K_P k_TP K_V)) for T_V = T_m", worst[0] < 1e-9,
              f"max relative error {worst[0]:.2e}")
    sol.check("Θ_m/D = −(sR_a/(k_t K_P k_TP K_V(1 + sT_m)))/(same denominator)", worst[1] < 1e-9,
              f"max relative error {worst[1]:.2e}")
    return sol


@problem("8.3", "Transfer functions with position, velocity and acceleration feedback", kind="derivation")
def problem_8_3() -> Solution:
    """Closed-loop transfer functions of Fig. 8.9 (from Fig. 8.6) with T_A = T_m.

    Library block reduction vs the manual's closed forms, 5 random cases at 61 frequencies; the
    innermost loop sM(s) = k_m/(1 + sT_m) (Fig. S8.2) is checked against the motor blocks
    k_t/(sR_a I) closed by k_v.
    """
    sol = Solution()
    def pairs(d, t, g, s):
        km, KP, KV, KA = d.k_m, g["K_P"], g["K_V"], g["K_A"]
        loop = position_velocity_acceleration_feedback(d, KP, KV, KA, d.T_m, t)
        den = 1 + s * t.k_TV / (KP * t.k_TP) + s**2 * (1 + km * KA * t.k_TA) / (km * KP * t.k_TP * KV * KA)
        inner = (d.kt / (s * d.Ra * d.I)) / (1 + d.kt * d.kv / (s * d.Ra * d.I))
        return [(loop.reference, (1 / t.k_TP) / den),
                (loop.disturbance, -(s * d.Ra / (d.kt * KP * t.k_TP * KV * KA * (1 + s * d.T_m))) / den),
                (control.tf([1.0, 0.0], [1.0]) * d.motor_tf(), inner)]

    worst = _worst_over_random_drives(83, pairs)
    K_P, K_V, K_A, k_TP, k_TV, k_TA = sp.symbols("K_P K_V K_A k_TP k_TV k_TA", positive=True)
    G = KM / (1 + S * TM)                                                   # sM(s)
    C_A = K_A * (1 + S * TM) / S                                            # T_A = T_m
    omega = S * THETA
    ref, dist = _symbolic_loop(G * (C_A * (K_V * (K_P * (THETA_R - k_TP * THETA) - k_TV * omega) - k_TA * S * omega)
                                    - RA_KT * DIST) / S)
    den = 1 + S * k_TV / (K_P * k_TP) + S**2 * (1 + KM * K_A * k_TA) / (KM * K_P * k_TP * K_V * K_A)
    sol.check("sympy: block equation of Figs. 8.6/8.9 (T_A = T_m) solved = manual's Θ_m/Θ_r and Θ_m/D",
              sp.simplify(ref - (1 / k_TP) / den) == 0
              and sp.simplify(dist + (S * RA_KT / (K_P * k_TP * K_V * K_A * (1 + S * TM))) / den) == 0,
              "simplify(difference) = 0", reference="closed form")
    sol.check("sM(s) = (k_t/(sR_a I))/(1 + k_t k_v/(sR_a I)) = k_m/(1 + sT_m) (Fig. S8.2)", worst[2] < 1e-9,
              f"max rel. error {worst[2]:.2e}")
    sol.check("Θ_m/Θ_r = (1/k_TP)/(1 + s k_TV/(K_P k_TP) + s²(1 + k_m K_A k_TA)/(k_m K_P k_TP K_V K_A)), T_A = T_m",
              worst[0] < 1e-9, f"max relative error {worst[0]:.2e}")
    sol.check("Θ_m/D = −(sR_a/(k_t K_P k_TP K_V K_A(1 + sT_A)))/(same denominator)", worst[1] < 1e-9,
              f"max relative error {worst[1]:.2e}")
    return sol


def _drive_checks(sol: Solution, drive: JointDrive) -> None:
    sol.check_close("k_m = 1/k_v = 2 rad/(V·s)", drive.k_m, 2.0, atol=1e-12, reference="manual number")
    sol.check_close("T_m = R_a I/(k_v k_t) = 7.2 s", drive.T_m, 7.2, atol=1e-12, reference="manual number")


def _measured_X_R(design: JointDesign, drive: JointDrive, w: float = 1e-7) -> float:
    """X_R read off the disturbance transfer function: at low frequency |Θ_m/D(jω)| ≈ ω R_a/(k_t X_R)."""
    return w * drive.Ra / (drive.kt * abs(frequency_samples(design.closed_loop.disturbance, [w])[0]))


def _recovery_time(t: np.ndarray, theta: np.ndarray, t_from: float) -> float:
    """T_R measured on a disturbance response: the time constant of the slow decay of |ϑ| after
    ``t_from`` (a least-squares line through log |ϑ|)."""
    window = t >= t_from
    slope = np.polyfit(t[window], np.log(np.abs(theta[window])), 1)[0]
    return -1.0 / slope


def _disturbance_checks(sol: Solution, design: JointDesign, drive: JointDrive, T_R_predicted: float,
                        T_R_formula: str, t: np.ndarray, theta: np.ndarray, t_from: float, rtol: float,
                        X_R_spec: float | None = None) -> None:
    """X_R from the low-frequency gain of Θ_m/D (python-control) and T_R from a simulated disturbance
    response, against the manual's formulas (or, given ``X_R_spec``, X_R against the specification).
    ``T_R_predicted`` is the recovery time the formula ``T_R_formula`` gives (the manual withholds the value)."""
    X_R = sol.value("X_R measured (low-frequency gain of Θ_m/D)", _measured_X_R(design, drive), unit="V/(rad·s)")
    if X_R_spec is None:
        sol.check_close("X_R from the low-frequency gain of Θ_m/D = the manual's formula", X_R, design.X_R,
                        rtol=1e-6, reference="closed form")
    else:
        sol.check_close(f"X_R from the low-frequency gain of Θ_m/D = the specification {X_R_spec:g}", X_R, X_R_spec,
                        rtol=1e-6, reference="specification met")
    T_R = sol.value("T_R measured (decay of the disturbance response) [s]", _recovery_time(t, theta, t_from), unit="s")
    sol.check_close(f"T_R measured on the disturbance step response ≈ the predicted {T_R_formula} = "
                    f"{T_R_predicted:g} s", T_R, T_R_predicted, rtol=rtol, reference="simulation vs prediction")


def _damping_checks(sol: Solution, design: JointDesign, omega_n: float | None = None) -> None:
    """ζ (and ω_n) of the complex closed-loop poles, computed by python-control from the closed loop W(s)."""
    poles = control.poles(design.closed_loop.reference)
    pair = poles[np.abs(poles.imag) > 1e-9]
    sol.check_close("ζ of the closed-loop poles (python-control) = 0.4", -pair.real / np.abs(pair), [ZETA, ZETA],
                    atol=1e-6, reference="second algorithm")
    if omega_n is not None:
        sol.check_close(f"ω_n of the closed-loop poles (python-control) = {omega_n:g} rad/s", np.abs(pair),
                        [omega_n, omega_n], atol=1e-6, reference="second algorithm")


@problem("8.4", "Position-feedback design for a single-joint drive (ζ = 0.4)", kind="numeric")
def problem_8_4() -> Solution:
    """Find the PI position controller of Fig. 5.10 for the drive [DRV84] (unit transducer) giving
    closed-loop damping ζ = 0.4 with T_P = 10 T_m, draw the root locus (Fig. S8.4, gain K' = 20 K_P)
    and evaluate the disturbance rejection factor X_R = K_P k_TP and recovery time T_R = T_P.

    The gain is the largest one whose complex poles have ζ ≥ 0.4 (root locus scanned, then refined);
    the manual rounds it (withheld there, computed here).
    """
    sol = Solution()
    drive = JointDrive(**sol.given("drive", DRIVE_84))
    _drive_checks(sol, drive)
    T_P = 10 * drive.T_m
    design = design_position_feedback(drive, sol.given("ζ", ZETA), T_P)
    K_P = sol.value("K_P", design.K_P, unit="1/s")            # C_P(s) = K_P (1 + sT_P)/s, volts to volts
    poles = sol.value("poles", design.poles, unit="1/s")
    sol.value("X_R", design.X_R, unit="V/(rad·s)")
    sol.value("T_R", design.T_R, unit="s")
    K_prime = sol.value("K_prime", drive.k_m * K_P * T_P / drive.T_m, unit="1/s²")
    sol.value("T_P", T_P, unit="s")
    # Independent: the manual's W(s) denominator 1 + sT_P + s²(1 + sT_m)/(k_m K_P k_TP) → numpy roots.
    char = np.array([drive.T_m, 1.0, drive.k_m * K_P * T_P, drive.k_m * K_P]) / (drive.k_m * K_P)
    roots = np.sort_complex(np.roots(char))
    sol.check_close("closed-loop poles = roots of the manual's W(s) denominator", poles, roots, atol=1e-9,
                    reference="closed form")
    _damping_checks(sol, design)
    sol.check("two complex poles and a real pole", int(np.sum(np.abs(roots.imag) > 1e-9)) == 2,
              f"poles {np.round(roots, 5)}")
    L = control.tf([1.0, 1.0 / T_P], [1.0, 1.0 / drive.T_m, 0.0, 0.0])   # K' (s + 1/T_P)/(s²(s + 1/T_m))
    loop_gain = frequency_samples(design.closed_loop.P * design.closed_loop.H, OMEGA)
    gap = float(np.max(np.abs(20 * K_P * frequency_samples(L, OMEGA) - loop_gain) / np.abs(loop_gain)))
    sol.check("root-locus gain K' = 20 K_P: 20 K_P (s + 1/T_P)/(s²(s + 1/T_m)) is the loop gain P(s)H(s)",
              gap < 1e-9 and np.isclose(K_prime, 20 * K_P, rtol=1e-12), f"max relative error {gap:.2e}")
    locus = control.root_locus_map(L, gains=np.array([K_prime]))
    sol.check_close("python-control's root locus at K' passes through the designed poles",
                    np.sort_complex(locus.loci[0]), poles, atol=1e-9, reference="other library")
    larger = design_position_feedback(drive, ZETA * 0.9, T_P).K_P
    sol.check("ζ decreases along the locus beyond the design (K_P is the largest gain with ζ ≥ 0.4)",
              larger > K_P, f"K_P(ζ = 0.36) = {larger:.4g} > K_P(ζ = 0.4) = {K_P:.4g}")
    # Disturbance step (python-control); after the complex pair has decayed (5/(ζω_n) ≈ 80 s) the slow
    # real pole near −1/T_P remains: T_R = T_P = 72 s (the formula; the manual withholds the value) is that
    # pole's approximation.
    t_d = np.linspace(0.0, 600.0, 6001)
    theta_d = control.step_response(design.closed_loop.disturbance, t_d).outputs
    _disturbance_checks(sol, design, drive, T_P, "T_R = T_P", t_d, theta_d, t_from=100.0, rtol=0.1)
    sol.check("poor disturbance rejection: X_R ≪ 1", sol.values["X_R measured (low-frequency gain of Θ_m/D)"] < 0.01,
              f"X_R = {design.X_R:.4g}")
    fig, ax = subplots(figsize=(6, 5))
    full = control.root_locus_map(L, gains=np.logspace(-5, 1, 800))
    for branch in full.loci.T:
        ax.plot(branch.real, branch.imag, "b-", lw=1)
    ax.plot([0, 0, -1 / drive.T_m], [0, 0, 0], "kx", ms=8, label="open-loop poles")
    ax.plot([-1 / T_P], [0], "ko", mfc="none", label="zero −1/T_P")
    ax.plot(poles.real, poles.imag, "rs", label=f"ζ = 0.4, K' = {K_prime:.4f}")
    wn = abs(roots[np.abs(roots.imag) > 0][0])
    ray = np.linspace(0, 1.5 * wn, 10)
    ax.plot(-ZETA * ray, np.sqrt(1 - ZETA**2) * ray, "g--", lw=0.8, label="ζ = 0.4")
    ax.set_xlim(-0.2, 0.02)
    ax.set_ylim(-0.25, 0.25)
    label_axes(ax, "Re s [rad/s]", "Im s [rad/s]", legend=True)
    sol.figure(fig, "Fig. S8.4 — root locus of position feedback control (gain K' = 20 K_P)")
    return sol


@problem("8.5", "Position and velocity feedback design (ζ = 0.4, ω_n = 20 rad/s)", kind="numeric")
def problem_8_5() -> Solution:
    """Gains of the position + velocity scheme (Fig. 5.11) for [DRV84], unit transducers, T_V = T_m,
    from (8.30)–(8.31) for ζ = 0.4 and ω_n = 20 rad/s; disturbance rejection X_R = K_P K_V, T_R = T_m.

    A unit step disturbance torque is simulated on the sampled loop (1 ms) and compared with
    python-control's response of the disturbance transfer function.
    """
    sol = Solution()
    drive = JointDrive(**sol.given("drive", DRIVE_84))
    _drive_checks(sol, drive)
    design = design_position_velocity(drive, sol.given("ζ", ZETA), sol.given("ω_n", OMEGA_N, unit="rad/s"))
    K_P, K_V = sol.value("K_P", design.K_P, unit="1"), sol.value("K_V", design.K_V, unit="1/s")   # C_V = K_V(1 + sT_V)/s
    poles = sol.value("poles", design.poles, unit="1/s")
    sol.value("X_R", design.X_R, unit="V/(rad·s)")
    T_R = sol.value("T_R", design.T_R, unit="s")
    # Independent: the manual's W(s) = 1/(1 + s/K_P + s²/(2 K_P K_V)) with the designed gains.
    _damping_checks(sol, design, OMEGA_N)
    manual = 1 / (1 + 1j * OMEGA / K_P - OMEGA**2 / (2 * K_P * K_V))
    sol.check("library closed loop = manual's W(s)", _rel(design.closed_loop.reference, manual) < 1e-9,
              f"max rel. error {_rel(design.closed_loop.reference, manual):.2e}", reference="closed form")
    sol.check_close("poles −ζω_n ± jω_n√(1−ζ²)", poles,
                    np.sort_complex(np.roots([1 / (2 * K_P * K_V), 1 / K_P, 1])), atol=1e-9, reference="closed form")
    # Sampled-data simulation of a unit disturbance step at t = 0.1 s, θ_d = 0.
    step_time = 0.1
    ctrl = PositionVelocityController(design, drive, lambda t: (0.0, 0.0, 0.0), Ts=1e-3,
                                      disturbance=lambda t: 1.0 if t >= step_time else 0.0)
    res = simulate(JointDrivePlant(drive), ctrl, (0.0, 2.0), [0.0, 0.0], h=2.5e-4, Ts=1e-3)
    t_after = res.t[res.t >= step_time] - step_time
    ref = control.forced_response(design.closed_loop.disturbance, t_after, np.ones_like(t_after)).outputs
    theta = res.q[res.t >= step_time, 0]
    err = float(np.max(np.abs(theta - ref)))
    sol.value("disturbance_peak", float(np.max(np.abs(theta))), unit="rad")
    sol.check_error("simulated disturbance response (1 ms sampling) ≈ python-control's Θ_m/D step response "
                    "(max |difference| relative to the peak, within 5 %)", err / np.max(np.abs(ref)), 0.05,
                    "simulation vs prediction",
                    detail=f"max |difference| = {err:.2e} rad, peak {np.max(np.abs(ref)):.2e} rad")
    # T_R = T_m: after the fast pair (ζω_n = 8 rad/s) the simulated response decays with T_m = 7.2 s.
    _disturbance_checks(sol, design, drive, T_R, "T_R = T_m (design.T_R)", t_after, theta, t_from=1.0, rtol=0.02)
    fig, ax = subplots(figsize=(7, 3.5))
    ax.plot(res.t, res.q[:, 0] * 1e3, label="simulated (Ts = 1 ms)")
    ax.plot(t_after + step_time, ref * 1e3, "--", label="Θ_m/D step (python-control)")
    label_axes(ax, "t [s]", "ϑ_m [mrad]", legend=True)
    sol.figure(fig, "8.5 — position + velocity feedback: response to a unit disturbance step")
    return sol


@problem("8.6", "Position, velocity and acceleration feedback design and acceleration filter", kind="numeric")
def problem_8_6() -> Solution:
    """Gains of the P + V + A scheme (Fig. 8.9) for [DRV84], unit transducers, T_A = T_m, from
    (8.39)–(8.41) for ζ = 0.4, ω_n = 20 rad/s, X_R = 400; bandwidth ω_3 of the closed loop and a
    first-order acceleration-reconstruction filter (Fig. 8.11) with k_f = 400 rad/s (the manual's choice).

    Manual erratum: the manual gives ω_3 = 26.84 rad/s; the −3 dB bandwidth of
    W(s) = 1/(1 + 0.04 s + 0.0025 s²) is 27.49 rad/s (computed here two ways).
    """
    sol = Solution()
    drive = JointDrive(**sol.given("drive", DRIVE_84))
    _drive_checks(sol, drive)
    design = design_position_velocity_acceleration(drive, sol.given("ζ", ZETA), sol.given("ω_n", OMEGA_N, unit="rad/s"),
                                                   sol.given("X_R", X_R_SPEC))
    K_P, K_V, K_A = (sol.value("K_P", design.K_P, unit="1"), sol.value("K_V", design.K_V, unit="1"),
                     sol.value("K_A", design.K_A, unit="1/s"))     # C_A = K_A(1 + sT_A)/s
    sol.value("X_R", design.X_R, unit="V/(rad·s)")
    sol.value("T_R", design.T_R, unit="s")
    sol.value("poles", design.poles, unit="1/s")
    W = design.closed_loop.reference
    omega_3 = sol.value("omega_3", bandwidth(W), unit="rad/s")
    # The manual's W(s) = 1/(1 + s/K_P + s²(1 + 2K_A)/(2 K_P K_V K_A)) with the designed gains.
    a1, a2 = 1 / K_P, (1 + 2 * K_A) / (2 * K_P * K_V * K_A)
    _damping_checks(sol, design, OMEGA_N)
    manual = 1 / (1 + a1 * 1j * OMEGA - a2 * OMEGA**2)
    sol.check("library closed loop = manual's W(s)", _rel(W, manual) < 1e-9, f"max rel. error {_rel(W, manual):.2e}",
              "closed form")
    t_d = np.linspace(0.0, 5.0, 5001)
    theta_d = control.step_response(design.closed_loop.disturbance, t_d).outputs
    _disturbance_checks(sol, design, drive, drive.T_m, "T_R = T_m", t_d, theta_d, t_from=1.0, rtol=0.02,
                        X_R_spec=X_R_SPEC)
    W5 = design_position_velocity(drive, ZETA, OMEGA_N).closed_loop.reference
    diff = float(np.max(np.abs(frequency_samples(W, OMEGA) - frequency_samples(W5, OMEGA))))
    sol.check("W(s) is the same transfer function as in 8.5", diff < 1e-9, f"max |difference| {diff:.2e}")
    z = ZETA
    closed_form = OMEGA_N * np.sqrt(1 - 2 * z**2 + np.sqrt(2 - 4 * z**2 + 4 * z**4))
    sol.check_close("ω_3 = ω_n √(1 − 2ζ² + √(2 − 4ζ² + 4ζ⁴)) = 27.49 rad/s", omega_3, closed_form, atol=1e-6,
                    reference="closed form")
    sol.check("manual erratum: the manual's ω_3 = 26.84 rad/s is not the −3 dB bandwidth",
              abs(omega_3 - 26.84) > 0.5 and abs(abs(frequency_samples(W, [26.84])[0]) - 1 / np.sqrt(2)) > 0.01,
              f"computed ω_3 = {omega_3:.2f} rad/s; |W(j26.84)| = {abs(frequency_samples(W, [26.84])[0]):.4f} ≠ 0.7071")
    k_f = sol.value("k_f", sol.given("k_f", 400.0, unit="rad/s"))
    F = acceleration_filter(k_f)
    at_w3 = frequency_samples(F, [omega_3])[0] / (1j * omega_3)        # relative to the ideal s Ω
    sol.check("reconstructed acceleration accurate up to ω_3 (gain ≥ 0.99, lag < 5°)",
              abs(at_w3) >= 0.99 and abs(np.degrees(np.angle(at_w3))) < 5,
              f"|Â/(sΩ)| = {abs(at_w3):.4f}, phase {np.degrees(np.angle(at_w3)):.2f}°")
    sol.check_close("filter −3 dB bandwidth (python-control) = k_f",
                    bandwidth(control.minreal(F * control.tf([1], [1, 0]), verbose=False)), k_f, rtol=1e-6,
                    reference="specification met")
    return sol


@problem("8.7", "Decentralised feedforward: equivalent reference input Θ'_r(s)", kind="derivation")
def problem_8_7() -> Solution:
    """For the feedforward schemes of Figs. 8.12–8.14 (saturation neglected), relate Θ_d to the
    equivalent reference Θ'_r. The library moves the feedforward blocks onto the reference; checks:
    the manual's three closed forms (5 random cases, 61 frequencies), perfect tracking
    W(s)Θ'_r(s)/Θ_d(s) ≡ 1, and a sampled simulation of a trapezoidal move with and without feedforward.
    """
    sol = Solution()
    rng = np.random.default_rng(87)
    s = 1j * OMEGA
    worst = [0.0, 0.0, 0.0]
    tracking = 0.0
    for _ in range(5):
        d, t, g = _random_case(rng)
        km, Tm = d.k_m, d.T_m
        cases = [
            (design_position_feedback(d, 0.4, 10 * Tm, t),
             lambda D: t.k_TP + s**2 * (1 + s * Tm) / (km * D.K_P * (1 + s * D.T_P))),
            (design_position_velocity(d, 0.5, rng.uniform(5, 30), t),
             lambda D: t.k_TP + s * t.k_TV / D.K_P + s**2 / (km * D.K_P * D.K_V)),
            (design_position_velocity_acceleration(d, 0.5, 10.0, rng.uniform(200, 500) / km, t),
             lambda D: t.k_TP + s * t.k_TV / D.K_P + (1 + km * D.K_A * t.k_TA) * s**2 / (km * D.K_P * D.K_V * D.K_A)),
        ]
        for i, (D, manual) in enumerate(cases):
            worst[i] = max(worst[i], _rel(feedforward_reference(d, D, t), manual(D)))
            tracking = max(tracking, float(np.max(np.abs(frequency_samples(feedforward_tracking(d, D, t), OMEGA) - 1))))
    labels = ["Fig. 8.12: Θ'_r = (k_TP + s²(1 + sT_m)/(k_m K_P(1 + sT_P)))Θ_d",
              "Fig. 8.13: Θ'_r = (k_TP + s k_TV/K_P + s²/(k_m K_P K_V))Θ_d",
              "Fig. 8.14: Θ'_r = (k_TP + s k_TV/K_P + (1 + k_m K_A k_TA)s²/(k_m K_P K_V K_A))Θ_d"]
    for label, w in zip(labels, worst):
        sol.check(label, w < 1e-9, f"max relative error {w:.2e}")
    sol.check("perfect tracking: W(s) Θ'_r/Θ_d ≡ 1 in the three schemes", tracking < 1e-9,
              f"max |W Θ'_r/Θ_d − 1| = {tracking:.2e}")
    # Time domain: [DRV84], position + velocity design of 8.5, trapezoidal move of 1 rad in 1 s.
    drive = JointDrive(**sol.given("drive", DRIVE_84))
    design = design_position_velocity(drive, sol.given("ζ", ZETA), sol.given("ω_n", OMEGA_N, unit="rad/s"))
    sol.given("move Δq, t_f, q̇_c", np.array([1.0, 1.0, 1.5]), unit="rad, s, rad/s")
    law = trapezoidal_law(0.0, 1.0, 1.0, 1.5)

    def reference(time: float) -> tuple[float, float, float]:
        q, qd, qdd = law(time)
        return float(q), float(qd), float(qdd)

    runs = {}
    for ff in (True, False):
        ctrl = PositionVelocityController(design, drive, reference, Ts=1e-3, feedforward=ff)
        runs[ff] = simulate(JointDrivePlant(drive), ctrl, (0.0, 1.5), [0.0, 0.0], h=2.5e-4, Ts=1e-3)
    e_ff, e_no = (float(np.max(np.abs(runs[k]["e"]))) for k in (True, False))
    sol.value("max_error_feedforward", e_ff, unit="rad")
    sol.value("max_error_feedback_only", e_no, unit="rad")
    sol.check("sampled simulation: feedforward reduces the tracking error by more than 20×", e_ff < e_no / 20,
              f"max |ϑ_d − ϑ_m| = {e_ff:.2e} rad with feedforward vs {e_no:.2e} rad without")
    fig, ax = subplots(figsize=(8, 3.5))
    for ff, style in ((True, "-"), (False, "--")):
        ax.plot(runs[ff].t, runs[ff]["e"] * 1e3, style, label="with feedforward" if ff else "feedback only")
    label_axes(ax, "t [s]", "ϑ_d − ϑ_m [mrad]", legend=True)
    sol.figure(fig, "8.7 — decentralised feedforward on a trapezoidal move (position + velocity feedback)")
    return sol


@problem("8.8", "Equivalence of the feedforward schemes of Figs. 8.15–8.17 and 8.12–8.14", kind="derivation")
def problem_8_8() -> Solution:
    """Show that the schemes of Figs. 8.15–8.17 are equivalent to those of Figs. 8.12–8.14: the output Y
    of the innermost PI block of Fig. 8.13 (8.14) equals that of Fig. 8.16 (8.17) with E = k_TP(Θ_d − Θ_m).

    Manual erratum: it refers to "Fig. 8.28" and "Fig. 8.29"; these are Figs. 8.13 and 8.14.
    Checked for 5 random cases at 61 frequencies.
    """
    sol = Solution()
    rng = np.random.default_rng(88)
    s = 1j * OMEGA
    w_815, w_PV, w_PVA = 0.0, 0.0, 0.0
    for _ in range(5):
        d, t, g = _random_case(rng)
        km, Tm = d.k_m, d.T_m
        KP, KV, KA, TP = g["K_P"], g["K_V"], g["K_A"], g["T_P"]
        C_P = frequency_samples(position_feedback(d, KP, TP, t).P, OMEGA) / frequency_samples(d.motor_tf(), OMEGA)
        w_815 = max(w_815, float(np.max(np.abs(C_P - (KP * TP + KP / s)) / np.abs(C_P))))
        base = design_position_velocity(d, 0.4, 20.0, t)
        D_PV = JointDesign(KP, None, KV, Tm, None, None, base.X_R, base.T_R, base.poles, base.closed_loop)
        G_E, G_d = feedforward_controller_output(d, D_PV, t)
        manual_E = KP * KV * Tm + KV * t.k_TV / t.k_TP + KP * KV / s + KV * Tm * t.k_TV * s / t.k_TP
        manual_d = s / km + Tm * s**2 / km
        w_PV = max(w_PV, _rel(G_E, manual_E), _rel(G_d, manual_d))
        D_PVA = JointDesign(KP, None, KV, None, KA, Tm, base.X_R, base.T_R, base.poles, base.closed_loop)
        G_E, G_d = feedforward_controller_output(d, D_PVA, t)
        manual_E = (KP * KV * KA * Tm + KV * t.k_TV * KA / t.k_TP + KP * KV * KA / s
                    + (KV * t.k_TV * KA * Tm + KA * t.k_TA) / t.k_TP * s + KA * Tm * t.k_TA / t.k_TP * s**2)
        w_PVA = max(w_PVA, _rel(G_E, manual_E), _rel(G_d, manual_d))
    K_P, K_V, K_A, k_TP, k_TV, k_TA = sp.symbols("K_P K_V K_A k_TP k_TV k_TA", positive=True)
    E, TH_D = sp.symbols("E Theta_d")
    U_pv = K_P * (1 + k_TV * S / (K_P * k_TP)) * E + S**2 * TH_D / (KM * K_V)
    Y_pv = K_V * (1 + S * TM) / S * U_pv
    manual_pv = ((K_P * K_V * TM + K_V * k_TV / k_TP + K_P * K_V / S + K_V * TM * k_TV * S / k_TP) * E
                 + S * TH_D / KM + TM * S**2 * TH_D / KM)
    U_pva = (K_P * K_V + K_V * k_TV / k_TP * S + k_TA / k_TP * S**2) * E + S**2 * TH_D / (KM * K_A)
    Y_pva = K_A * (1 + S * TM) / S * U_pva
    manual_pva = ((K_P * K_V * K_A * TM + K_V * k_TV * K_A / k_TP + K_P * K_V * K_A / S
                   + (K_V * k_TV * K_A * TM + K_A * k_TA) / k_TP * S + K_A * TM * k_TA / k_TP * S**2) * E
                  + S * TH_D / KM + TM * S**2 * TH_D / KM)
    sol.check("sympy: K_V(1 + sT_V)/s · U and K_A(1 + sT_A)/s · U expand to the manual's Y (T_V = T_A = T_m)",
              sp.expand(Y_pv - manual_pv) == 0 and sp.expand(Y_pva - manual_pva) == 0, "expand(difference) = 0",
              reference="closed form")
    sol.check("Fig. 8.15 ≡ Fig. 8.12: K_P(1 + sT_P)/s = K_P T_P + K_P/s", w_815 < 1e-9, f"max rel. error {w_815:.2e}")
    sol.check("Fig. 8.16 ≡ Fig. 8.13 (manual: 'Fig. 8.28', erratum): Y = (K_P K_V T_V + K_V k_TV/k_TP + K_P K_V/s "
              "+ K_V T_V k_TV s/k_TP)E + Θ̇_d/k_m + T_m Θ̈_d/k_m", w_PV < 1e-9, f"max rel. error {w_PV:.2e}")
    sol.check("Fig. 8.17 ≡ Fig. 8.14 (manual: 'Fig. 8.29', erratum): Y = (...)E + Θ̇_d/k_m + T_m Θ̈_d/k_m",
              w_PVA < 1e-9, f"max rel. error {w_PVA:.2e}")
    return sol


@problem("8.9", "Prove ‖B⁻¹B̂ − I‖ ≤ α < 1 (8.76)", kind="derivation")
def problem_8_9() -> Solution:
    """With B_m I ≤ B⁻¹(q) ≤ B_M I (8.75) and B̂ = 2/(B_M + B_m) I, show ‖B⁻¹B̂ − I‖ ≤ α = (B_M − B_m)/(B_M + B_m) < 1.

    Numerically on the two-link arm of Sect. 7.3.2 (with and without a 10 kg payload [recalled]):
    B_m, B_M from B(q) on a grid of q_2 (B depends on q_2 only), and the bound checked on a finer grid
    and at random postures. The library's B(q) (Pinocchio, rotors as mimic joints) is checked against
    the closed form (7.82): b11 = 200.01 + 50 c2, b12 = 23.5 + 25 c2, b22 = 122.5.
    """
    sol = Solution()
    rng = np.random.default_rng(89)
    for label, payload in (("", 0.0), ("_payload", sol.given("m_L", 10.0, unit="kg"))):
        robot = load("planar_2r", payload=payload)
        q2 = np.linspace(-np.pi, np.pi, 721)
        Bs = np.array([inertia_matrix(robot, np.array([0.0, a])) for a in q2])
        bounds = inertia_bounds(Bs)
        alpha = sol.value(f"alpha{label}", bounds.alpha, unit="1")
        sol.value(f"B_m{label}", bounds.B_m, unit="1/(kg·m²)")
        sol.value(f"B_M{label}", bounds.B_M, unit="1/(kg·m²)")
        sol.value(f"B_hat{label}", bounds.B_hat, unit="kg·m²")
        q_test = np.column_stack([rng.uniform(-np.pi, np.pi, 200), rng.uniform(-np.pi, np.pi, 200)])
        norms = [np.linalg.norm(np.linalg.solve(inertia_matrix(robot, q), bounds.B_hat) - np.eye(2), 2)
                 for q in np.vstack([q_test, np.column_stack([np.zeros(721), q2])])]
        sol.check(f"‖B⁻¹B̂ − I‖₂ ≤ α at 921 postures{' (payload)' if payload else ''}",
                  max(norms) <= alpha + 1e-12, f"max norm {max(norms):.6f} ≤ α = {alpha:.6f} (tight: "
                  f"attained at the extreme postures)")
        if payload == 0.0:
            c2 = np.cos(q2)
            closed = np.array([[[200.01 + 50 * c, 23.5 + 25 * c], [23.5 + 25 * c, 122.5]] for c in c2])
            sol.check_close("B(q) = closed form (7.82) on the grid", Bs, closed, atol=1e-9, reference="closed form")
            ref = inertia_bounds(closed)
            sol.check_close("α from the closed-form B(q) (independent reference) = 0.43009", alpha, ref.alpha, atol=1e-9,
                            reference="closed form")
            sol.check_close("α ≈ 0.43009, B̂ ≈ 151.80 I (derived values)", [alpha, bounds.B_hat[0, 0]],
                            [0.43009, 151.80], rtol=2e-4, reference="independent derivation")
        else:
            sol.check_close("payload: α ≈ 0.49408, B̂ ≈ 159.68 I (derived values)", [alpha, bounds.B_hat[0, 0]],
                            [0.49408, 159.68], rtol=2e-4, reference="independent derivation")
    return sol
