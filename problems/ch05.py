"""Chapter 5 — Actuators and Sensors: Problems 5.1–5.7.

Data: the DC servomotor of 5.2/5.3 is [MOT52] (I_m = 0.0014 kg·m², F_m = 0.01 N·m·s/rad, L_a = 2 mH,
R_a = 0.2 Ω, k_t = 0.2 N·m/A, k_v = 0.2 V·s/rad, G_v = 1, T_v = 0.1 ms), confirmed by the authors'
companion file i5_2 (which integrates at 0.1 ms); 5.6 and 5.7 data are the manual's; the point P of 5.7,
p^b = [0.8, 0.5, 0.9] m, is recalled from the textbook statement (not in the manual).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Ch. 5,
and its solution manual.
"""

from __future__ import annotations

import control
import numpy as np
import pinocchio as pin
import sympy as sp
from matplotlib.figure import Figure

from controllers.compiled import ConstantInput, fast_backend
from controllers.plants import ServomotorPlant
from controllers.simulation import simulate
from problems.common import label_axes, max_relative_error, subplots
from problems.registry import Solution, problem
from rigid_body.actuators import (DCServomotor, HydraulicMotor, design_pi_current_loop,
                                  frequency_samples, hydraulic_transfer_functions,
                                  servomotor_transfer_functions)
from rigid_body.camera import PinholeCamera, project_from_robot
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import load
from rigid_body.sensors import binary_to_gray, bits_to_int, gray_to_binary, int_to_bits, wrench_transform

# [MOT52] — the motor of Problems 5.2 and 5.3 (companion file i5_2).
MOTOR_52 = dict(Ra=0.2, La=2e-3, kt=0.2, kv=0.2, Im=0.0014, Fm=0.01, Gv=1.0, Tv=1e-4)
OMEGA = np.logspace(-2, 5, 60)          # test frequencies [rad/s] for transfer-function identities


def _random_motor(rng: np.random.Generator, **overrides: float) -> DCServomotor:
    p = dict(Ra=rng.uniform(0.1, 2), La=rng.uniform(1e-4, 1e-2), kt=rng.uniform(0.05, 1),
             kv=rng.uniform(0.05, 1), Im=rng.uniform(1e-4, 1e-2), Fm=rng.uniform(1e-3, 0.1),
             Gv=1.0, Tv=0.0, ki=0.0)
    p.update(overrides)
    return DCServomotor(**p)




@problem("5.1", "Steady state and transfer functions of the velocity- and torque-controlled servomotor",
         kind="derivation")
def problem_5_1() -> Solution:
    """Prove the steady-state relations (5.7)–(5.8) and the transfer functions of Figs. 5.3 and 5.4.

    The library's steady state (Eqs. (S5.1)–(S5.5) solved) and its transfer functions (block reduction
    of Fig. 5.2 with python-control) are compared with the manual's closed forms for random motors,
    at 60 frequencies each. Fig. 5.3: k_i = 0, L_a = 0, T_v = 0; Fig. 5.4: a current loop of gain
    K = C_i G_v → ∞ (1e8 here), so that K k_i ≫ R_a.
    """
    sol = Solution()
    rng = np.random.default_rng(51)
    w, s = OMEGA, 1j * OMEGA
    worst_ss, worst_53, worst_53_approx, worst_54, worst_cm = 0.0, 0.0, 0.0, 0.0, 0.0
    for _ in range(5):
        m = _random_motor(rng)
        K, v = rng.uniform(0.5, 3), rng.uniform(-2, 2)
        omega, i_a = m.steady_state(v, 0.0, K)
        # manual: K v'_c = (F_m R_a/k_t + k_v) ω_m  (k_i = 0, c_r = 0)
        worst_ss = max(worst_ss, abs(omega - K * v / (m.Fm * m.Ra / m.kt + m.kv)) / abs(omega))
        # manual (k_i ≠ 0): K v'_c = ((R_a + K k_i)/k_t) c_m + k_v ω_m
        mi = _random_motor(rng, ki=rng.uniform(0.5, 2))
        c_r = rng.uniform(-1, 1)
        om_i, ia_i = mi.steady_state(v, c_r, K)
        worst_cm = max(worst_cm, abs(K * v - ((mi.Ra + K * mi.ki) / mi.kt * mi.kt * ia_i + mi.kv * om_i)))
        # Fig. 5.3: velocity-controlled generator (L_a, T_v neglected)
        m3 = _random_motor(rng, La=0.0)
        tf = servomotor_transfer_functions(m3, K)
        load_ = s * m3.Im + m3.Fm
        den = 1 + m3.kv * m3.kt / (m3.Ra * load_)
        manual_v = (K * m3.kt / (m3.Ra * load_)) / den
        manual_c = -(1 / load_) / den
        worst_53 = max(worst_53, max_relative_error(frequency_samples(tf.velocity_input, w), manual_v),
                       max_relative_error(frequency_samples(tf.velocity_load, w), manual_c))
        # ... and its F_m → 0 form, exact at F_m = 0
        m0 = _random_motor(rng, La=0.0, Fm=0.0)
        tf0 = servomotor_transfer_functions(m0, K)
        Tm = m0.Ra * m0.Im / (m0.kv * m0.kt)
        worst_53_approx = max(worst_53_approx,
                              max_relative_error(frequency_samples(tf0.velocity_input, w), (K / m0.kv) / (1 + s * Tm)),
                              max_relative_error(frequency_samples(tf0.velocity_load, w),
                                       -(m0.Ra / (m0.kv * m0.kt)) / (1 + s * Tm)))
        # Fig. 5.4: torque-controlled generator, high-gain current loop
        m4 = _random_motor(rng, La=0.0, ki=rng.uniform(0.5, 2))
        tf4 = servomotor_transfer_functions(m4, 1e8)
        manual4_v = (m4.kt / (m4.ki * m4.Fm)) / (1 + s * m4.Im / m4.Fm)
        manual4_c = -(1 / m4.Fm) / (1 + s * m4.Im / m4.Fm)
        worst_54 = max(worst_54, max_relative_error(frequency_samples(tf4.velocity_input, w[:40]), manual4_v[:40]),
                       max_relative_error(frequency_samples(tf4.velocity_load, w[:40]), manual4_c[:40]))
    sol.check("steady state (k_i = 0): K v'_c = (F_m R_a/k_t + k_v) ω_m", worst_ss < 1e-12,
              f"max relative error {worst_ss:.2e} over 5 random motors")
    sol.check("steady state (k_i ≠ 0): K v'_c = ((R_a + K k_i)/k_t) c_m + k_v ω_m", worst_cm < 1e-12,
              f"max residual {worst_cm:.2e}")
    m = DCServomotor(**sol.given("motor [MOT52]", MOTOR_52))
    omega_fm, _ = m.steady_state(1.0)
    ratio = m.Fm * m.Ra / (m.kv * m.kt)
    sol.value("omega_ss_unit_step", omega_fm, unit="rad/s")
    sol.check("F_m ≪ k_v k_t/R_a ⇒ ω_m ≈ (K/k_v) v'_c (5.7)",
              abs(omega_fm - 1.0 / m.kv) / (1.0 / m.kv) <= 1.01 * ratio / (1 + ratio),
              f"[MOT52]: ω_m = {omega_fm:.5f} vs K/k_v = {1 / m.kv:.5f}; relative gap = "
              f"F_m R_a/(k_v k_t)/(1 + ·) = {ratio / (1 + ratio):.4f}")
    big = _random_motor(np.random.default_rng(7), ki=1.0)
    om_b, ia_b = big.steady_state(1.0, 0.05, K=1e7)
    approx = big.kt / big.ki * (1.0 - big.kv / 1e7 * om_b)
    sol.check("K k_i ≫ R_a ⇒ c_m ≈ (k_t/k_i)(v'_c − (k_v/K) ω_m) (5.8)",
              abs(big.kt * ia_b - approx) / abs(approx) < 1e-6,
              f"c_m = {big.kt * ia_b:.9f} vs {approx:.9f} at K = 1e7")
    # Symbolic: (S5.1)–(S5.5) solved with sympy; the two relations and their limits.
    Ra, kt, kv, Fm, ki, K = sp.symbols("R_a k_t k_v F_m k_i K", positive=True)
    va, ia, vg, om, cm, vc, cr = sp.symbols("v_a i_a v_g omega_m c_m v_c c_r")
    steady = sp.solve([sp.Eq(va, Ra * ia + vg), sp.Eq(vg, kv * om), sp.Eq(cm, Fm * om + cr), sp.Eq(cm, kt * ia),
                       sp.Eq(va, K * (vc - ki * ia))], [va, ia, vg, om, cm], dict=True)[0]
    om0 = steady[om].subs({ki: 0, cr: 0})
    rel_1 = sp.simplify(K * vc - (Fm * Ra / kt + kv) * om0) == 0 and sp.limit(om0, Fm, 0) == K * vc / kv
    rel_2 = sp.simplify(K * vc - ((Ra + K * ki) / kt * steady[cm] + kv * steady[om])) == 0
    ratio = sp.simplify(steady[cm] / (kt / ki * (vc - kv / K * steady[om])))   # exact: K k_i/(R_a + K k_i) → 1
    gap = sp.simplify(ratio - K * ki / (Ra + K * ki))
    sol.check("sympy: (S5.1)–(S5.5) give K v'_c = (F_m R_a/k_t + k_v) ω_m → ω_m = (K/k_v) v'_c as F_m → 0, and "
              "K v'_c = ((R_a + K k_i)/k_t) c_m + k_v ω_m → c_m = (k_t/k_i)(v'_c − (k_v/K) ω_m) as K → ∞",
              rel_1 and rel_2 and gap == 0 and sp.limit(ratio, K, sp.oo) == 1,
              f"c_m/((k_t/k_i)(v'_c − (k_v/K) ω_m)) = {ratio} → 1")
    sol.check("Fig. 5.3 transfer functions Ω_m/V'_c and Ω_m/C_r (block reduction vs manual)", worst_53 < 1e-9,
              f"max relative error {worst_53:.2e} at 60 frequencies × 5 motors", reference="closed form")
    sol.check("Fig. 5.3 with F_m → 0: (K/k_v)/(1 + s R_a I_m/(k_v k_t)) and −(R_a/(k_v k_t))/(1 + ·)",
              worst_53_approx < 1e-9, f"max relative error {worst_53_approx:.2e}")
    sol.check("Fig. 5.4 torque-controlled generator: (k_t/(k_i F_m))/(1 + s I_m/F_m), −(1/F_m)/(1 + ·)",
              worst_54 < 1e-5, f"max relative error {worst_54:.2e} with a current-loop gain of 1e8")
    return sol


def _servomotor_figure(title: str, runs: list[tuple[str, np.ndarray, np.ndarray, np.ndarray]]) -> Figure:
    fig, axes = subplots(len(runs), 2, figsize=(9, 3.2 * len(runs)), squeeze=False)
    for row, (label, t, i_a, omega) in zip(axes, runs):
        row[0].plot(t * 1e3, i_a)
        row[0].set_ylabel("current [A]")
        row[1].plot(t * 1e3, omega)
        row[1].set_ylabel("velocity [rad/s]")
        for ax in row:
            ax.set_title(label, fontsize="small")
            label_axes(ax, "t [ms]", legend=False)
    fig.suptitle(title)
    return fig  # laid out by Solution.figure


@problem("5.2", "Current and velocity step response of a DC servomotor", kind="simulation")
def problem_5_2() -> Solution:
    """Simulate the current and velocity responses of the servomotor of Fig. 5.2 to a unit step V'_c
    (k_i = 0, C_r = 0), Fig. S5.2.

    Data [MOT52] (companion file i5_2); RK4 with the companion's 0.1 ms step over 0.2 s. The
    simulated state (:class:`ServomotorPlant`) is checked against python-control's step response of
    the block-reduced transfer functions, and the steady state against the closed form
    ω = K k_t/(R_a F_m + k_v k_t) that (5.7) approximates by K/k_v = 5 rad/s.
    """
    sol = Solution()
    m = DCServomotor(**sol.given("motor [MOT52]", MOTOR_52))
    sol.given("V'_c step", 1.0, unit="V")
    plant = ServomotorPlant(m, 1.0)
    res = simulate(plant, ConstantInput([1.0, 0.0], plant), (0.0, 0.2), plant.x0, h=1e-4, backend=fast_backend())
    t, i_a, omega = res.t, res["i_a"], res["omega"]
    omega_ss = sol.value("omega_ss", float(omega[-1]), unit="rad/s")
    i_ss = sol.value("i_ss", float(i_a[-1]), unit="A")
    sol.value("omega_peak", float(omega.max()), unit="rad/s")
    sol.value("i_peak", float(i_a.max()), unit="A")
    sol.value("t_i_peak", float(t[np.argmax(i_a)]), unit="s")
    K = 1.0
    den = m.Ra * m.Fm + m.kv * m.kt
    sol.check_close("ω(0.2 s) = K k_t/(R_a F_m + k_v k_t) = 4.7619 rad/s", omega_ss, K * m.kt / den, atol=1e-3,
                    reference="closed form")
    sol.check_close("i_a(0.2 s) = K F_m/(R_a F_m + k_v k_t) = 0.2381 A", i_ss, K * m.Fm / den, atol=1e-3,
                    reference="closed form")
    sol.check("steady-state velocity slightly below 5 rad/s (the (5.7) value) because of F_m",
              4.5 < omega_ss < 1.0 / m.kv, f"ω_ss = {omega_ss:.4f} rad/s < K/k_v = {1 / m.kv:g}")
    sol.check("underdamped: the velocity overshoots", omega.max() > 1.05 * omega_ss,
              f"peak {omega.max():.3f} rad/s at {t[np.argmax(omega)] * 1e3:.1f} ms")
    tf = servomotor_transfer_functions(m, 1.0)
    ref_w = control.step_response(tf.velocity_input, t).outputs
    ref_i = control.step_response(tf.current_input, t).outputs
    err = max(np.max(np.abs(ref_w - omega)), np.max(np.abs(ref_i - i_a)))
    sol.check("simulation = python-control step response of the transfer functions", err < 1e-3,
              f"max |difference| = {err:.2e} (RK4, h = 0.1 ms)")
    plant = ServomotorPlant(DCServomotor(**{**MOTOR_52, "Tv": 0.0}), 1.0)
    fast = simulate(plant, ConstantInput([1.0, 0.0], plant), (0.0, 0.2), plant.x0, h=1e-4, backend=fast_backend())
    dev = float(np.max(np.abs(fast["omega"] - omega)))
    sol.check("the amplifier time constant (0.1 ms) has no appreciable effect", dev < 0.05 * omega_ss,
              f"max velocity difference with T_v = 0: {dev:.3g} rad/s")
    sol.figure(_servomotor_figure("Fig. S5.2 — step response of the DC servomotor (k_i = 0)",
                                  [("unit step V'_c", t, i_a, omega)]))
    return sol


@problem("5.3", "PI current loop with 2 ms settling time; velocity compared with 5.2", kind="simulation")
def problem_5_3() -> Solution:
    """Design C_i(s) = K_I(1 + sT_I)/s so that the current responds to a unit step V'_c with a 1 %
    settling time of 2 ms (ζ = 0.7, t_s = 4.6/(ζω_n)), simulate (Fig. S5.4) and compare the velocity with 5.2.

    Motor [MOT52] with k_i = 1. Two runs as in the companion file i5_3: 5 ms at 0.5 µs and 1 s at
    0.1 ms. Manual erratum: the velocity is dominated by the time constant I_m/F_m = 0.14 s (the
    manual prints "I_m/T_m"). The design neglects T_v (overshoot ≈ 20 %, from the zero −1/T_I); the
    simulation keeps the amplifier lag T_v = 0.1 ms of the companion data, which at ω_n ≈ 3300 rad/s
    raises the current overshoot to ≈ 40 % while the 1 % settling still happens before 2.5 ms.
    """
    sol = Solution()
    m = DCServomotor(**sol.given("motor [MOT52]", MOTOR_52), ki=sol.given("k_i", 1.0, unit="V/A"))
    zeta, t_s = sol.given("zeta", 0.7), sol.given("t_s", 2e-3, unit="s")
    pi, omega_n = design_pi_current_loop(m, zeta, t_s)
    K_I, T_I = sol.value("K_I", pi.K, unit="1/s"), sol.value("T_I", pi.T, unit="s")
    sol.value("omega_n", omega_n, unit="rad/s")
    # The manual's closed loop (Ω_m = 0, T_v ≈ 0): (1 + sT_I)/(1 + s(0.2 + K_I T_I)/K_I + s² 0.002/K_I)
    a1, a2 = (0.2 + K_I * T_I) / K_I, 0.002 / K_I
    wn = 1 / np.sqrt(a2)
    z = a1 * wn / 2
    sol.check_close("the manual's denominator with the designed K_I, T_I has ζ = 0.7", z, zeta,
                    atol=1e-9, reference="specification met")
    lib = servomotor_transfer_functions(DCServomotor(**{**MOTOR_52, "Tv": 0.0, "kv": 1e-12}, ki=1.0), pi)
    manual = (1 + 1j * OMEGA * T_I) / (1 + 1j * OMEGA * a1 - OMEGA**2 * a2)
    err = max_relative_error(frequency_samples(lib.current_input, OMEGA), manual)
    sol.check("current loop I_a/V'_c (block reduction, Ω_m ≈ 0, T_v = 0) = manual's transfer function",
              err < 1e-6, f"max relative error {err:.2e}", reference="closed form")
    info = control.step_info(lib.current_input, SettlingTimeThreshold=0.01)
    sol.value("design_current_overshoot_percent", float(info["Overshoot"]), unit="%")
    sol.check_bound("design model (T_v = 0, python-control step_info): current settles within 1 % in ≤ 2 ms",
                    info["SettlingTime"], t_s, detail=f"settling time {info['SettlingTime'] * 1e3:.2f} ms, overshoot "
                    f"{info['Overshoot']:.1f} % (caused by the zero −1/T_I)")

    plant = ServomotorPlant(m, pi)
    step = ConstantInput([1.0, 0.0], plant)                  # unit step V'_c, C_r = 0
    fast = simulate(plant, step, (0.0, 5e-3), plant.x0, h=5e-7, Ts=1e-5, backend=fast_backend())
    slow = simulate(plant, step, (0.0, 1.0), plant.x0, h=1e-4, backend=fast_backend())
    ref = simulate(ServomotorPlant(DCServomotor(**MOTOR_52), 1.0), step, (0.0, 1.0), plant.x0, h=1e-4,
                   backend=fast_backend())
    t, i_a = fast.t, fast["i_a"]
    after = t > 2.5e-3
    sol.check("current settled: |i_a − 1| < 0.01 after 2.5 ms", np.max(np.abs(i_a[after] - 1)) < 0.01,
              f"max |i_a − 1| after 2.5 ms = {np.max(np.abs(i_a[after] - 1)):.4f} A")
    tfs = servomotor_transfer_functions(m, pi)
    ref_i = control.step_response(tfs.current_input, t).outputs
    sol.value("simulated_current_overshoot_percent", float(100 * (i_a.max() - 1.0)), unit="%")
    sol.check("simulated current = python-control step response", np.max(np.abs(ref_i - i_a)) < 1e-4,
              f"max |difference| = {np.max(np.abs(ref_i - i_a)):.2e} A")
    omega = slow["omega"]
    tau_m = m.Im / m.Fm
    sol.value("omega_final", float(omega[-1]), unit="rad/s")
    sol.check_close("ω(1 s) → k_t/(k_i F_m) = 20 rad/s", omega[-1], m.kt / (m.ki * m.Fm), atol=0.1,
                    reference="closed form")
    k = int(round(tau_m / 1e-4))
    sol.check_close("velocity dominated by I_m/F_m = 0.14 s: ω(0.14 s) ≈ 20 (1 − e⁻¹) "
                    "(manual erratum: printed 'I_m/T_m')", omega[k], 20 * (1 - np.exp(-1)), atol=0.2,
                        reference="closed form")

    def rise(y: np.ndarray, tt: np.ndarray) -> float:
        return float(tt[np.argmax(y >= 0.632 * y[-1])])

    r3, r2 = rise(omega, slow.t), rise(ref["omega"], ref.t)
    sol.check("velocity slowed down with respect to Fig. S5.2", r3 > 5 * r2,
              f"63 % rise time {r3 * 1e3:.1f} ms (PI current loop) vs {r2 * 1e3:.1f} ms (Problem 5.2)")
    sol.value("v_a_final", float(plant.armature_voltage(slow.x[-1], 1.0)), unit="V")
    sol.figure(_servomotor_figure("Fig. S5.4 — servomotor with PI current loop",
                                  [("current transient (h = 0.5 µs)", t, i_a, fast["omega"]),
                                   ("velocity (h = 0.1 ms); dashed: Problem 5.2", slow.t, slow["i_a"], omega)]))
    ax = sol.figures[-1].axes[3]
    ax.get_lines()[0].set_label("PI current loop")
    ax.plot(ref.t * 1e3, ref["omega"], "--", color="gray", label="Problem 5.2 (no current loop)")
    ax.legend(fontsize="small")
    return sol


@problem("5.4", "Transfer functions of a hydraulic motor with servovalve and distributor", kind="derivation")
def problem_5_4() -> Solution:
    """Reduce the block scheme of the hydraulic drive (Fig. S5.5) to Θ_m(V_c, C_r).

    The library reduces the blocks with python-control; the manual's closed form is evaluated at 60
    frequencies for 5 random positive parameter sets (the manual's equation labels are garbled —
    erratum — but the final expressions are right).
    """
    sol = Solution()
    rng = np.random.default_rng(54)
    s = 1j * OMEGA[:45]
    worst_v, worst_c = 0.0, 0.0
    for _ in range(5):
        p = HydraulicMotor(*rng.uniform(0.2, 3.0, 10))
        G_v, G_c = hydraulic_transfer_functions(p)
        kk = p.kt * p.kr * p.kq
        chamber = 1 + p.kr * p.kl + s * p.kr * p.kc
        common = 1 + p.Fm / kk * (1 + s * p.Im / p.Fm) * chamber
        manual_v = (p.kx * p.Gs / (p.kr * p.kq)) / (s * (1 + s * p.Ts) * common)
        manual_c = -(chamber / kk) / (s * common)
        worst_v = max(worst_v, max_relative_error(frequency_samples(G_v, OMEGA[:45]), manual_v))
        worst_c = max(worst_c, max_relative_error(frequency_samples(G_c, OMEGA[:45]), manual_c))
    sol.check("Θ_m/V_c = (k_x G_s/(k_r k_q))/(s(1+sT_s)(1 + F_m/(k_t k_r k_q)(1+sI_m/F_m)(1+k_r k_l+s k_r k_c)))",
              worst_v < 1e-8, f"max relative error {worst_v:.2e}")
    sol.check("Θ_m/C_r = −((1+k_r k_l+s k_r k_c)/(k_t k_r k_q))/(s(1 + ...))", worst_c < 1e-8,
              f"max relative error {worst_c:.2e}")
    sol.value("max_relative_error", max(worst_v, worst_c), unit="1")
    # Symbolic: the five relations of Fig. S5.5 solved with sympy against the manual's closed form.
    sym = sp.symbols("s k_t k_x k_r k_q k_c k_l G_s T_s I_m F_m", positive=True)
    s_, kt, kx, kr, kq, kc, kl, Gs, Ts, Im, Fm = sym
    Vc, Cr, Th, Om, Cm, P, X = sp.symbols("V_c C_r Theta_m Omega_m C_m P X")
    relations = [sp.Eq(Th, Om / s_), sp.Eq(Om, (Cm - Cr) / (s_ * Im + Fm)), sp.Eq(Cm, kt * P),
                 sp.Eq(P, (kx / kr * (X - P / kx) - kq * Om) / (s_ * kc + kl)), sp.Eq(X, Gs / (1 + s_ * Ts) * Vc)]
    theta = sp.solve(relations, [Th, Om, Cm, P, X], dict=True)[0][Th]
    ch = 1 + kr * kl + s_ * kr * kc
    common = 1 + Fm / (kt * kr * kq) * (1 + s_ * Im / Fm) * ch
    manual = (kx * Gs / (kr * kq)) / (s_ * (1 + s_ * Ts) * common) * Vc - (ch / (kt * kr * kq)) / (s_ * common) * Cr
    sol.check("sympy: the relations of Fig. S5.5 solved for Θ_m equal the manual's closed form",
              sp.simplify(theta - manual) == 0, "simplify(Θ_m − manual) = 0 (manual erratum: garbled equation "
              "labels '(S5.6) into (S5.6)')", reference="closed form")
    return sol


# Table S5.1 of the manual: Gray code x1x2x3x4 → binary y1y2y3y4, rows 0..15.
TABLE_S5_1 = ["0000", "0001", "0011", "0010", "0110", "0111", "0101", "0100",
              "1100", "1101", "1111", "1110", "1010", "1011", "1001", "1000"]


@problem("5.5", "Gray-code to binary-code interconversion logic", kind="derivation")
def problem_5_5() -> Solution:
    """Design the logic circuit converting the Gray code of an absolute encoder into binary.

    y_1 = x_1 and y_k = y_{k−1} ⊕ x_k (Fig. S5.6), implemented for any word length and checked on
    Table S5.1 and on every word of 1–12 bits.
    """
    sol = Solution()
    sol.given("Table S5.1 (Gray codes of 0–15)", TABLE_S5_1)
    decoded = [bits_to_int(gray_to_binary([int(c) for c in g])) for g in TABLE_S5_1]
    sol.value("table_S5_1_binary", decoded, unit="1")
    sol.check("XOR cascade reproduces Table S5.1 (16 codes)", decoded == list(range(16)),
              f"decoded {decoded}")
    x = np.array([[int(c) for c in g] for g in TABLE_S5_1])
    y = np.array([int_to_bits(n, 4) for n in range(16)])
    sol.check("y1 = x1, y2 = x̄1x2 + x1x̄2, y3 = y2 ⊕ x3, y4 = y3 ⊕ x4 on every row",
              np.array_equal(y[:, 0], x[:, 0]) and np.array_equal(y[:, 1], (1 - x[:, 0]) & x[:, 1] | x[:, 0] & (1 - x[:, 1]))
              and np.array_equal(y[:, 2], y[:, 1] ^ x[:, 2]) and np.array_equal(y[:, 3], y[:, 2] ^ x[:, 3]),
              "truth table of Fig. S5.6")
    ok_roundtrip, ok_adjacent = True, True
    for n_bits in range(1, 13):
        prev = None
        for n in range(2**n_bits):
            g = binary_to_gray(int_to_bits(n, n_bits))
            ok_roundtrip &= bits_to_int(g) == (n ^ (n >> 1)) and bits_to_int(gray_to_binary(g)) == n
            if prev is not None:
                ok_adjacent &= int(np.sum(g != prev)) == 1
            prev = g
    sol.check("Gray ↔ binary round trip equals n ⊕ (n >> 1), 1–12 bits", ok_roundtrip, "all words")
    sol.check("consecutive Gray codes differ in exactly one bit (absolute encoder property)", ok_adjacent,
              "all words of 1–12 bits")
    return sol


@problem("5.6", "Wrist force/torque sensor: wrench in the contact frame", kind="numeric")
def problem_5_6() -> Solution:
    """Express the wrench measured by a wrist sensor, [f_s^s; μ_s^s] = [20, 0, 0, 0, 6, 0], in the
    contact frame with (5.32); R_s^c and S(r_cs^c) are the manual's (r_cs^c = [−0.3, 0, 0.2] m read
    off S). Cross-checked with Pinocchio's SE3 action on a force.
    """
    sol = Solution()
    R = sol.given("R_s^c", np.array([[0.0, 0, 1], [0, -1, 0], [1, 0, 0]]))
    r = sol.given("r_cs^c", np.array([-0.3, 0.0, 0.2]), unit="m")
    h_s = sol.given("h_s", np.array([20.0, 0, 0, 0, 6, 0]), unit="N, N·m")
    W = sol.value("W", wrench_transform(R, r), unit="1 (R blocks), m (S(r) R block)")
    h_c = W @ h_s
    f_c, mu_c = sol.value("f_c", h_c[:3], unit="N"), sol.value("mu_c", h_c[3:], unit="N·m")
    manual_W = np.array([[0, 0, 1, 0, 0, 0], [0, -1, 0, 0, 0, 0], [1, 0, 0, 0, 0, 0],
                         [0, 0.2, 0, 0, 0, 1], [0.3, 0, 0.2, 0, -1, 0], [0, 0.3, 0, 1, 0, 0]])
    sol.check_close("6×6 map of (5.32) equals the manual's", W, manual_W, atol=1e-12, reference="closed form")
    sol.check_close("f_c^c = [0, 0, 20] N", f_c, [0, 0, 20], atol=1e-12, reference="closed form")
    sol.check_close("μ_c^c = 0: no resulting moment in the contact frame", mu_c, [0, 0, 0], atol=1e-12,
                    reference="closed form")
    F = pin.SE3(R, r).act(pin.Force(h_s[:3], h_s[3:]))
    sol.check_close("Pinocchio: SE3(R_s^c, r_cs^c).act(force) gives the same wrench",
                    np.concatenate([F.linear, F.angular]), h_c, atol=1e-12, reference="other library")
    return sol


@problem("5.7", "Pixel coordinates of a point seen by a camera on a SCARA end effector", kind="numeric")
def problem_5_7() -> Solution:
    """Camera frame = SCARA end-effector frame (Frame 4 of Fig. S2.3, a_1 = a_2 = 0.5 m) at
    q = [0, π/4, 0.1, 0]; find the image coordinates of P, p^b = [0.8, 0.5, 0.9] m [recalled from the
    textbook statement], with (5.35), (5.40) and Ω of (5.41).

    T_c^b comes from the URDF model (Pinocchio) and is checked against the closed form (S2.3) and the
    manual's rounded matrix. The manual rounds p^c before projecting (withheld values): our values
    are unrounded.
    """
    sol = Solution()
    robot = load("scara")
    q = sol.given("q", np.array([0.0, np.pi / 4, 0.1, 0.0]), unit="rad (q3 in m)")
    T = sol.value("T_bc", direct_kinematics(robot, q), unit="1 (R), m (o)")
    a1 = a2 = sol.given("a1 = a2", 0.5, unit="m")
    c1, s1, c12, s12 = np.cos(q[0]), np.sin(q[0]), np.cos(q[0] + q[1]), np.sin(q[0] + q[1])
    c124, s124 = np.cos(q[0] + q[1] + q[3]), np.sin(q[0] + q[1] + q[3])
    T_S23 = np.array([[c124, -s124, 0, a1 * c1 + a2 * c12], [s124, c124, 0, a1 * s1 + a2 * s12],
                      [0, 0, 1, q[2]], [0, 0, 0, 1]])
    sol.check_close("T_c^b from the URDF model = closed form (S2.3)", T, T_S23, atol=1e-12, reference="closed form")
    manual_T = np.array([[0.707, -0.707, 0, 0.854], [0.707, 0.707, 0, 0.354], [0, 0, 1, 0.1], [0, 0, 0, 1]])
    sol.check_close("T_c^b = manual's matrix (3 decimals)", T, manual_T, atol=1e-3, reference="manual number")
    camera = PinholeCamera(*sol.given("f α_x, f α_y, X_0, Y_0", np.array([633.6, 964.0, 250.0, 250.0]), unit="pixel"))
    p_b = sol.given("p^b", np.array([0.8, 0.5, 0.9]), unit="m")
    proj = project_from_robot(camera, robot, q, p_b)
    sol.value("p_c", proj.p_c, unit="m")
    sol.value("x_I", proj.x_I, unit="1")
    sol.value("y_I", proj.y_I, unit="1")
    lam, X, Y = sol.value("lambda", proj.lam, unit="m"), sol.value("X_I", proj.X_I, unit="pixel"), sol.value("Y_I", proj.Y_I, unit="pixel")
    # Independent route: the manual's rounded transform, by hand.
    R, o = manual_T[:3, :3], manual_T[:3, 3]
    p_c = R.T @ (p_b - o)
    X_m, Y_m = 633.6 * p_c[0] / p_c[2] + 250, 964 * p_c[1] / p_c[2] + 250
    sol.check_close("λ = depth of P in the camera frame = 0.9 − d_3", lam, 0.9 - q[2], atol=1e-12,
                    reference="closed form")
    sol.check_close("(X_I, Y_I) within 1 pixel of the projection through the manual's rounded T_c^b",
                    [X, Y], [X_m, Y_m], atol=1.0, reference="closed form")
    return sol
