"""Beyond the book: the joint-space controllers of Ch. 8 on a UR5 carrying an unknown payload.

PD control with gravity compensation, inverse dynamics control (8.57) and adaptive control on the
payload mass — the schemes of Problems 8.10, 8.12 and 8.14 — on the UR5 of example-robot-data, with the torques saturated at the URDF effort
limits. Not a problem of the book: run it from a notebook or ``python -m examples.ur5_joint_space``;
it returns a :class:`problems.registry.Solution` (values, checks, figures) like a book problem.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 8.5.1, 8.5.2, 8.5.4 (centralized joint-space control); Sect. 4.2.1 (quintic, Eq. (4.3)).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rmpc import (ArmPlant, inertia_matrix, InverseDynamicsControl, load, PDGravityCompensation, quintic,
                  simulate, SimulationResult, with_payload)
from controllers.joint_space import AdaptivePayloadControl
from problems.common import label_axes, subplots
from problems.registry import Solution

T_C = 1e-3  # controller sampling period and plant step [s]


def ur5_joint_space_control(payload: float = 5.0, t_f: float = 1.5, omega_n: float = 20.0) -> Solution:
    """PD + gravity, inverse dynamics and adaptive-on-payload control of a UR5 (example-robot-data).

    The UR5 carries ``payload`` kg at ``tool0`` (its rated payload is 5 kg) that the controllers' model
    does not know; the joints track a quintic (4.3) from q_i = [0, −π/2, π/2, 0, π/2, 0] over t_f, and
    the plant saturates the torques at the URDF effort limits (150 N·m shoulder/elbow, 28 N·m wrist).
    Gains are scaled by the diagonal inertia at q_i so that every joint has ω_n, ζ = 1 (PD + gravity:
    K_P = ω_n² diag B, K_D = 2ω_n diag B; inverse dynamics: K_P = ω_n² I, K_D = 2ω_n I; adaptive:
    Λ = 10 I, K_D = 20 diag B, k_π⁻¹ = 20). A faster motion (t_f/3) shows the saturation at work.
    Not a problem of the book: a companion to 8.10, 8.12 and 8.14.
    """
    sol = Solution(id="ur5", title="UR5: joint-space control with an unknown payload", kind="simulation")
    ur5 = load("ur5")
    real = with_payload(ur5, payload)
    tau_max = sol.value("tau_max", np.array(ur5.model.effortLimit))
    q_i = np.array([0.0, -np.pi / 2, np.pi / 2, 0.0, np.pi / 2, 0.0])
    q_f = q_i + np.array([np.pi / 2, np.pi / 4, -np.pi / 3, np.pi / 4, -np.pi / 4, np.pi / 2])
    B_d = np.diag(inertia_matrix(real, q_i))
    plant = ArmPlant(real, tau_max=tau_max)
    x0 = np.r_[q_i, np.zeros(6)]

    def run(ctrl: Any, duration: float) -> SimulationResult:
        return simulate(plant, ctrl, (0.0, duration + 1.0), x0, h=T_C, Ts=T_C,
                        log=lambda t, x, u: {"tau": plant.torque(u)})

    tra = quintic(q_i, q_f, t_f, dt=T_C)
    runs = {
        "PD + gravity": run(PDGravityCompensation(ur5, omega_n**2 * B_d, 2 * omega_n * B_d, tra), t_f),
        "inverse dynamics (no payload model)": run(InverseDynamicsControl(ur5, omega_n**2, 2 * omega_n, tra), t_f),
        "inverse dynamics (payload known)": run(InverseDynamicsControl(real, omega_n**2, 2 * omega_n, tra), t_f),
        "adaptive on the payload": run(AdaptivePayloadControl(ur5, 20 * B_d, 10.0, 20.0, tra), t_f),
    }
    for name, r in runs.items():
        sol.value(f"max_error {name}", float(np.abs(r["e"]).max()))
        sol.value(f"final_error {name}", float(np.abs(r["e"][-1]).max()))
        sol.value(f"peak_torque_ratio {name}", np.abs(r["tau"]).max(axis=0) / tau_max)
        sol.check(f"{name}: applied torques within the effort limits", np.all(np.abs(r["tau"]) <= tau_max + 1e-12),
                  f"peak |τ|/τ_max = {np.max(np.abs(r['tau']) / tau_max):.2f}")
    adaptive = runs["adaptive on the payload"]
    sol.value("m_hat_final", float(adaptive["m_hat"][-1]))
    sol.check("adaptive: payload estimate converges", abs(adaptive["m_hat"][-1] - payload) < 0.02 * payload,
              f"m̂_L = {adaptive['m_hat'][-1]:.4f} kg vs {payload} kg")
    e = {name: np.abs(r["e"][-1]).max() for name, r in runs.items()}
    sol.check("unknown payload: inverse dynamics keeps a steady-state error, adaptation removes it",
              e["inverse dynamics (no payload model)"] > 1e-3 and e["adaptive on the payload"] < 1e-5
              and e["inverse dynamics (payload known)"] < 1e-6,
              f"final |q~|: {e['inverse dynamics (no payload model)']:.2e} (no payload model), "
              f"{e['adaptive on the payload']:.2e} (adaptive), {e['inverse dynamics (payload known)']:.2e} (known)")
    fast = run(InverseDynamicsControl(real, omega_n**2, 2 * omega_n, quintic(q_i, q_f, t_f / 3, dt=T_C)), t_f / 3)
    saturated = float(np.mean(np.any(np.abs(fast.u) > tau_max, axis=1)))
    sol.value("fast_saturated_fraction", saturated)
    sol.value("fast_final_error", float(np.abs(fast["e"][-1]).max()))
    sol.check("fast motion: saturation active, target still reached", saturated > 0 and np.abs(fast["e"][-1]).max() < 1e-4,
              f"{100 * saturated:.1f} % of the samples saturate; final |q~| = {np.abs(fast['e'][-1]).max():.2e}")
    fig, axes = subplots(2, 2, sharex=True, figsize=(10, 6))
    for ax, (name, r) in zip(axes.flat, runs.items()):
        ax.plot(r.t, r["e"])
        ax.set_title(name, fontsize="medium")
        ax.set_ylabel("q~ [rad]")
        ax.grid(True, alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("t [s]")
    axes[0, 0].legend([f"joint {j + 1}" for j in range(6)], fontsize="x-small", ncol=2)
    sol.figure(fig, f"UR5, unknown {payload:g} kg payload, quintic in {t_f:g} s, torques saturated at the URDF limits")
    fig2, ax = subplots(figsize=(6.4, 3.2))
    ax.plot(fast.t, fast["tau"] / tau_max)
    label_axes(ax, "t [s]", "τ / τ_max", legend=False)
    sol.figure(fig2, f"UR5, inverse dynamics along the quintic in {t_f / 3:g} s: saturated torques")
    return sol


if __name__ == "__main__":
    result = ur5_joint_space_control()
    for c in result.checks:
        print(f"[{'PASS' if c.passed else 'FAIL'}] {c.name}: {c.detail}")
