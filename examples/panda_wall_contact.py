"""Beyond the book: impedance and hybrid force/motion control of the Panda on a wall.

The Panda's tool approaches a vertical wall, pushes on it with 20 N, slides 0.2 m along it against
Coulomb friction with its orientation held, and passes an edge where the wall steps back by 1 cm:
contact is lost and regained. The same scene is run with impedance control with force feedback
(Eqs. 9.30–9.31, on the full pose with the quaternion error) and with hybrid force/motion control
(Eqs. 9.77–9.81: force along the wall's normal, PI velocity on the five other twist components) —
the laws of Problems 9.3 and 9.10 on a 7-DOF arm. Run it from a notebook or
``python -m examples.panda_wall_contact``; it returns a :class:`problems.registry.Solution`.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 9.3, 9.5–9.7.
"""

from __future__ import annotations


import numpy as np
import pinocchio as pin
from scipy.signal import lsim

from rmpc import (ArmInContact, direct_kinematics, HybridForceMotionControl, OperationalInverseDynamics,
                  Robot, selection_matrices, simulate, SimulationResult)
from controllers.scenes import PANDA_TOOL, SLIDE, STEP_AT, STEP_DEPTH, WALL_FRICTION, WALL_STIFFNESS, PandaWall, \
    panda_wall
from planners.timing import quintic_law
from problems.common import label_axes, subplots
from problems.registry import Solution
from rigid_body.rotations import homogeneous_transform
from viewer import contact_animation

T_C = 1e-3                  # controller sampling period and plant step [s]
F_PUSH = 20.0               # the force held on the wall [N]
T_PANDA = 3.5               # simulated time [s]: approach 0–1 s, slide 1–3 s (quintic), hold


def panda_hybrid(scene: PandaWall) -> SimulationResult:
    """Hybrid force/motion control: λ along n (λ_d = −20 N), PI velocity on the other 5 twist components
    (slide along +y₀, no rotation). Gains: k_Pλ = 400, k_Dλ = 32 (ω = 20 rad/s, ζ = 0.8 with the stiffness
    known), k_Pν = 16, k_Iν = 100; in free space the force loop approaches at ĉ k_Pλ |λ_d| / k_Dλ."""
    S_f, S_v = selection_matrices(("x", "y", "rx", "ry", "rz"), scene.R_c)
    slide = scene.slide

    def nu_reference(t: float) -> tuple[np.ndarray, np.ndarray]:
        _, sd, sdd = slide(t)
        return np.array([sd, 0.0, 0.0, 0.0, 0.0]), np.array([sdd, 0.0, 0.0, 0.0, 0.0])

    panda = scene.panda
    ctrl = HybridForceMotionControl(panda, S_f, S_v, [-F_PUSH], nu_reference, 16.0, 100.0, 32.0, 400.0,
                                    compliance=np.eye(6) / WALL_STIFFNESS, frame=PANDA_TOOL, null_space_damping=10.0)
    plant = ArmInContact(panda, scene.wall, frame=PANDA_TOOL)
    return simulate(plant, ctrl, (0.0, T_PANDA), plant.initial_state(scene.q0), h=T_C, Ts=T_C)


PANDA_IMPEDANCE = dict(M_d=np.r_[5.0, 5.0, 5.0, 0.5, 0.5, 0.5], K_P=np.r_[1000.0, 1000.0, 1000.0, 100.0, 100.0, 100.0],
                       K_D=np.r_[400.0, 400.0, 400.0, 15.0, 15.0, 15.0])


def panda_impedance(scene: PandaWall, depth: float) -> SimulationResult:
    """Impedance control with force feedback (9.30)–(9.31) on the full pose (quaternion error): the
    reference approaches to ``depth`` behind the wall in 1 s, then slides along +y₀."""
    p0, n, t1, R0, slide = scene.p0, scene.n, scene.t1, scene.R0, scene.slide
    gap = float(n @ (p0 - scene.wall.point))
    approach = quintic_law(0.0, gap + depth, 1.0)

    def reference(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        a, ad, add = approach(t)
        s, sd, sdd = slide(t)
        v, acc = np.zeros(6), np.zeros(6)
        v[:3], acc[:3] = -ad * n + sd * t1, -add * n + sdd * t1
        return homogeneous_transform(R0, p0 - a * n + s * t1), v, acc

    panda = scene.panda
    g = PANDA_IMPEDANCE
    ctrl = OperationalInverseDynamics(panda, g["K_P"], g["K_D"], reference, frame=PANDA_TOOL, orientation="quaternion",
                                      inertia=g["M_d"], force_feedback=True, null_space_damping=10.0,
                                      posture=scene.q0, posture_stiffness=0.0)
    plant = ArmInContact(panda, scene.wall, frame=PANDA_TOOL)
    return simulate(plant, ctrl, (0.0, T_PANDA), plant.initial_state(scene.q0), h=T_C, Ts=T_C)


def _orientation_error(panda: Robot, qs: np.ndarray, R0: np.ndarray) -> np.ndarray:
    """Rotation angle [rad] of R_eᵀ R_0 along the run."""
    return np.array([np.linalg.norm(pin.log3(direct_kinematics(panda, q, PANDA_TOOL)[:3, :3].T @ R0)) for q in qs])


def panda_wall_contact() -> Solution:
    """The Panda's tool approaches a wall, pushes on it with 20 N, slides 0.2 m along it against Coulomb
    friction (μ = 0.3) with its orientation held, and passes an edge where the wall steps back by 1 cm:
    contact is lost and regained. Impedance control (9.30)–(9.31) and hybrid force/motion control
    (9.77)–(9.81) on the same scene (a unilateral compliant wall, k = 2·10⁴ N/m, d = 200 N·s/m).

    Not a problem of the book: an unregistered companion to 9.3 and 9.10 on a real 7-DOF arm.
    """
    sol = Solution(id="panda-wall", title="Panda: impedance and hybrid force/motion control on a wall",
                   kind="simulation")
    scene = panda_wall()
    panda, n, t1 = scene.panda, scene.n, scene.t1
    k = WALL_STIFFNESS
    hyb = panda_hybrid(scene)
    K_Pi = PANDA_IMPEDANCE["K_P"][0]
    k_series = K_Pi * k / (K_Pi + k)                         # active stiffness in series with the wall
    depth = F_PUSH / k_series                                # reference behind the wall for 20 N at rest
    imp = panda_impedance(scene, depth)
    runs = {"hybrid": hyb, "impedance": imp}
    t = hyb.t
    f_n = {name: -(r["h_e"][:, :3] @ n) for name, r in runs.items()}          # pushing force [N] ≥ 0
    slide_pos = {name: r["p_e"] @ t1 - scene.p0 @ t1
                 for name, r in runs.items()}
    ori = {name: _orientation_error(panda, r.q[::10], scene.R0) for name, r in runs.items()}

    # hybrid: the force is held, lost at the edge, regained at the predicted instant
    cruise = (t > 1.3) & (t < 1.9)
    fh = f_n["hybrid"]
    sol.value("hybrid_force_error_sliding", float(np.abs(fh[cruise] - F_PUSH).max()))
    sol.check("hybrid: 20 N held while sliding against friction (t ∈ [1.3, 1.9] s)", np.abs(fh[cruise] - F_PUSH).max() < 0.5,
              f"max |f_n − 20| = {np.abs(fh[cruise] - F_PUSH).max():.3f} N")
    lost = np.flatnonzero(fh == 0.0)
    lost = lost[t[lost] > 1.0]
    t_lost, t_back = float(t[lost[0]]), float(t[lost[-1] + 1])
    sol.value("hybrid_contact_lost_at", t_lost)
    sol.value("hybrid_contact_regained_at", t_back)
    t_edge = float(t[np.argmax(slide_pos["hybrid"] > STEP_AT)])
    v_approach = F_PUSH / k * 400.0 / 32.0                   # ĉ k_Pλ |λ_d| / k_Dλ
    gap = STEP_DEPTH - F_PUSH / k                            # from the deflected surface to the recess
    t_pred = t_edge + gap / v_approach + 1.0 / 32.0          # + the lag 1/k_Dλ of the approach velocity
    sol.check("hybrid: contact lost at the edge", abs(t_lost - t_edge) < 0.01, f"lost at {t_lost:.3f} s, edge at {t_edge:.3f} s")
    sol.check("hybrid: contact regained after gap/(ĉ k_Pλ|λ_d|/k_Dλ) + 1/k_Dλ", abs(t_back - t_pred) < 0.03,
              f"regained at {t_back:.3f} s, predicted {t_pred:.3f} s (approach speed {v_approach * 1e3:.1f} mm/s)")
    sol.check_close("hybrid: final force −20 N", fh[-1], F_PUSH, atol=0.1)
    sol.check_close("hybrid: slid 0.2 m", slide_pos["hybrid"][-1], SLIDE, atol=1e-3)
    sol.value("hybrid_max_orientation_error", float(ori["hybrid"].max()))
    sol.check("hybrid: orientation held", ori["hybrid"].max() < 5e-3, f"max angle {ori['hybrid'].max():.1e} rad")
    h_t = hyb["h_e"][cruise, :3] - np.outer(hyb["h_e"][cruise, :3] @ n, n)
    sol.value("hybrid_friction_force_sliding", float(np.linalg.norm(h_t, axis=1).mean()))   # ≈ μ f_n = 6 N

    # impedance: force set by the stiffnesses in series; lower after the step; friction lag along the slide
    fi = f_n["impedance"]
    before = (t > 1.3) & (t < 1.9)
    after_force = k_series * (depth - STEP_DEPTH)
    sol.value("impedance_force_before_step", float(fi[before].mean()))
    sol.value("impedance_force_after_step", float(fi[-1]))
    sol.check("impedance: f = k_P k/(k_P + k) d = 20 N on the wall while sliding",
              np.abs(fi[before] - F_PUSH).max() < 0.5, f"f_n ∈ [{fi[before].min():.2f}, {fi[before].max():.2f}] N")
    sol.check_close("impedance: after the step the same law gives k_P k/(k_P + k)(d − 1 cm) [N]", fi[-1], after_force, atol=0.1)
    sol.check("impedance: contact lost at the edge and regained", np.any(fi[(t > 2.0) & (t < 2.5)] == 0.0) and fi[-1] > 0,
              f"zero-force samples after the edge: {int(np.sum(fi[t > 1.0] == 0.0))}")
    # along the slide the tool lags behind the reference by the impedance's response to the friction force:
    # m_d x̃̈ + k_D x̃̇ + k_P x̃ = h_t, integrated separately (scipy lsim) from the measured h_t
    e_slide = imp["e"][:, :3] @ t1
    h_slide = imp["h_e"][:, :3] @ t1
    g = PANDA_IMPEDANCE
    _, e_pred, _ = lsim(([1.0], [g["M_d"][0], g["K_D"][0], K_Pi]), h_slide, t)
    dev = float(np.abs(e_slide - e_pred).max())
    sol.value("impedance_friction_lag_max", float(np.abs(e_slide).max()))
    sol.check("impedance: the lag along the slide is the impedance's response to friction, m_d x̃̈ + k_D x̃̇ + k_P x̃ = h_t",
              dev < 2e-4 and np.abs(e_slide).max() > 3e-3,
              f"max deviation {dev * 1e3:.3f} mm on a lag of up to {np.abs(e_slide).max() * 1e3:.2f} mm "
              f"(steady value μ f_n / k_P = {WALL_FRICTION * F_PUSH / K_Pi * 1e3:.1f} mm)")
    sol.value("impedance_max_orientation_error", float(ori["impedance"].max()))
    sol.check("impedance: orientation held", ori["impedance"].max() < 5e-3, f"max angle {ori['impedance'].max():.1e} rad")

    fig, axes = subplots(3, 1, sharex=True, figsize=(7, 7.5))
    for name, style in (("hybrid", "C0-"), ("impedance", "C1--")):
        axes[0].plot(t, f_n[name], style, label=name)
        axes[1].plot(t, slide_pos[name], style, label=name)
        axes[2].plot(t[::10], ori[name] * 1e3, style, label=name)
    axes[0].axhline(F_PUSH, color="k", ls=":", lw=1, label="20 N")
    axes[1].plot(t, [scene.slide(ti)[0] for ti in t], "k:", lw=1, label="reference")
    axes[1].axhline(STEP_AT, color="0.5", lw=0.8, label="edge of the step")
    label_axes(axes[0], None, "force on the wall [N]")
    label_axes(axes[1], None, "tool along the slide [m]")
    label_axes(axes[2], "t [s]", "orientation error [mrad]")
    sol.figure(fig, "Panda on a stepped wall with friction: impedance vs hybrid force/motion control")
    fig2, ax = subplots(figsize=(6.4, 3.4))
    for name, style in (("hybrid", "C0-"), ("impedance", "C1--")):
        ax.plot(runs[name]["p_e"][:, 1], runs[name]["p_e"][:, 0] * 1e3, style, label=name)
    y = scene.p0[1] + np.array([-0.02, STEP_AT, STEP_AT, 0.25])
    ax.plot(y, [600.0, 600.0, 610.0, 610.0], "k--", label="wall at rest")
    label_axes(ax, "y [m]", "x [mm]")
    sol.figure(fig2, "Tool path (top view) and the stepped wall")
    wall = scene.wall
    before = wall.point + (STEP_AT - 0.1) * t1                              # the wall up to the edge …
    after = wall.point - STEP_DEPTH * n + (STEP_AT + 0.1) * t1               # … and the recess beyond it
    sol.animation(panda, title="hybrid force/motion control on the stepped wall: force −h_e (0.15 m per 20 N)",
                  **contact_animation(panda, hyb, n, [(before, (0.3, 0.2)), (after, (0.3, 0.2))], 7.5e-3,
                                      frame=PANDA_TOOL))
    return sol


if __name__ == "__main__":
    result = panda_wall_contact()
    for c in result.checks:
        print(f"[{'PASS' if c.passed else 'FAIL'}] {c.name}: {c.detail}")
