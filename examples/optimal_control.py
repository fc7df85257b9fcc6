"""Beyond the book: optimal control and model predictive control on the book's two-link arm and on real robots.

* :func:`two_link_tracking` — Chapter 4's minimum-time motion of the two-link arm (its motors included, as the book
  models them), run faster than its torque limits allow: inverse dynamics control (8.57) commands torques the motors
  cannot give, saturates and leaves the path; model predictive control plans within the limits and tracks better.
  With ``payload`` the arm carries a mass the controllers' model does not know.
* :func:`reach` — the Panda or the UR5 reaching an end-effector pose with its real (URDF) torque limits: one optimal
  control solve (checked independently: KKT, limits) and the same problem closed in the loop by MPC at 100 Hz in
  real-time iteration (one SQP step per sample, warm-started from the previous plan).

Not problems of the book: run them from ``notebooks/optimal_control.ipynb`` or ``python -m examples.optimal_control``;
each returns a :class:`problems.registry.Solution` (values, checks, figures) like a book problem.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 4.2, 7.3, 8.5.2;
Rawlings, Mayne & Diehl, *Model Predictive Control*, 2017.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin

from controllers.joint_space import InverseDynamicsControl
from controllers.mpc import MPCOptions, ModelPredictiveControl
from controllers.plants import ArmPlant
from controllers.simulation import SimulationResult, simulate
from planners.optimal_control import OptimalControlProblem, StageCost, solve_optimal_control
from planners.optimization import JointLimits, OptimizationOptions, minimum_time_trajectory
from planners.timing import time_scaled
from problems.common import label_axes, subplots
from problems.registry import Solution
from rigid_body.robots import load, with_payload

H = 1e-3            # plant step and computed-torque sampling period [s]
DT = 0.01           # MPC sampling period = its interval [s]
Q_I, Q_F = np.array([0.0, np.pi / 4]), np.array([np.pi / 2, np.pi / 2])          # Chapter 4's motion (tra_4)
LIMITS = dict(qdd_max=[20.0, 20.0], qd_max=[3.0, 3.0], tau_max=[3000.0, 1500.0])  # the notebook's of Chapter 4


def two_link_problem(arm: Any, horizon: int = 20) -> OptimalControlProblem:
    """The tracking problem of the two-link arm: N intervals of 10 ms, heavy joint-error weights, a small torque
    weight about the reference's computed torque, the torque box of Chapter 4's limits (hard)."""
    return OptimalControlProblem(arm, horizon, DT, running=StageCost(q=1e4, qd=10.0, tau=1e-7),
                                 terminal=StageCost(q=1e5, qd=1e2), tau_max=LIMITS["tau_max"],
                                 q_min=-np.inf, q_max=np.inf, qd_max=np.inf)


def tracking_error(result: SimulationResult, law: Any) -> np.ndarray:
    """|q_d(t) − q(t)| (N, n) along a run."""
    return np.abs(law(result.t)[0] - result.q)


def two_link_tracking(speed: float = 1.2, payload: float = 0.0, horizon: int = 20) -> Solution:
    """Minimum-time motion of Chapter 4 run ``speed`` times faster: computed torque vs MPC on the saturating arm.

    The motion q_i = [0, π/4] → q_f = [π/2, π/2] is the fastest within |q̇| ≤ 3 rad/s, |q̈| ≤ 20 rad/s² and
    |τ| ≤ (3000, 1500) N·m (:func:`planners.optimization.minimum_time_trajectory`, its torque limit active); run
    ``speed`` times faster its torques grow by speed² and exceed the motors'. The plant saturates at those limits;
    ``payload`` kg at the tip is unknown to both controllers. Inverse dynamics control (8.57) with ω_n = 20 rad/s
    at 1 kHz against MPC (``horizon`` intervals of 10 ms, 100 Hz) on the same model.
    """
    sol = Solution(id="ocp-2r", title="Two-link arm: computed torque vs MPC beyond the torque limits",
                   kind="simulation")
    arm = load("planar_2r")
    limits = JointLimits.from_robot(arm, **LIMITS)
    tau_max = limits.tau_max
    planned = minimum_time_trajectory(arm, Q_I, Q_F, limits, OptimizationOptions(nodes=30))
    sol.value("t_f_minimum", planned.t_f, "s")
    law = time_scaled(planned.trajectory.law, speed)
    sol.value("t_f_reference", law.t_f, "s")
    plant_robot = with_payload(arm, payload) if payload else arm
    plant = ArmPlant(plant_robot, tau_max=tau_max)
    span, x0 = (0.0, law.t_f + 0.5), np.r_[Q_I, 0.0, 0.0]
    runs = {
        "computed torque (8.57)": simulate(plant, InverseDynamicsControl(arm, 400.0, 40.0, law), span, x0, h=H, Ts=H),
        "MPC": simulate(plant, ModelPredictiveControl(two_link_problem(arm, horizon), reference=law), span, x0, h=H,
                        Ts=H),
    }
    ratio_needed = np.max(np.abs(planned.tau) / tau_max) * speed**2
    sol.value("reference_torque_ratio", float(ratio_needed))
    metrics = {}
    for name, r in runs.items():
        e = tracking_error(r, law)
        over = float(np.mean(np.any(np.abs(r.u) > tau_max * (1 + 1e-9), axis=1)))
        metrics[name] = (float(e.max()), float(np.sqrt(np.mean(np.sum(e**2, axis=1)))), float(e[-1].max()), over)
        sol.value(f"max_error {name}", metrics[name][0], "rad")
        sol.value(f"rms_error {name}", metrics[name][1], "rad")
        sol.value(f"final_error {name}", metrics[name][2], "rad")
        sol.value(f"commanded_over_limit {name}", over)
    ct, mpc = metrics["computed torque (8.57)"], metrics["MPC"]
    sol.check_bound("the sped-up reference needs more torque than the motors give", ratio_needed, 1.0, ">")
    sol.check_bound("computed torque commands beyond the limits (it saturates)", ct[3], 0.0, ">")
    sol.check_bound("MPC commands stay within the limits", mpc[3], 0.0, "<=")
    sol.check("MPC tracks better: smaller largest and RMS errors", mpc[0] < ct[0] and mpc[1] < ct[1],
              f"max |q~|: MPC {mpc[0]:.3g} vs CT {ct[0]:.3g} rad; RMS: {mpc[1]:.3g} vs {ct[1]:.3g} rad")
    r_mpc = runs["MPC"]
    samples = r_mpc["failed"][::round(DT / H)]
    sol.value("mpc_failed_solves", int(samples.sum()))
    sol.value("mpc_median_solve_time", float(np.nanmedian(r_mpc["solve_time"][::round(DT / H)])), "s")
    fig, axes = subplots(3, 2, sharex=True, figsize=(10, 8))
    for j in range(2):
        axes[0, j].plot(r_mpc.t, law(r_mpc.t)[0][:, j], "k--", label="reference")
        for name, r in runs.items():
            axes[0, j].plot(r.t, r.q[:, j], label=name)
            axes[1, j].plot(r.t, tracking_error(r, law)[:, j], label=name)
            axes[2, j].plot(r.t, r.u[:, j] / tau_max[j], label=name)
        axes[2, j].axhline(1.0, color="k", ls=":")
        axes[2, j].axhline(-1.0, color="k", ls=":")
        axes[2, j].set_ylim(-3, 3)
        axes[0, j].set_title(f"joint {j + 1}")
        label_axes(axes[0, j], None, f"q{j + 1} [rad]", legend=j == 0)
        label_axes(axes[1, j], None, f"|q~{j + 1}| [rad]", legend=False)
        label_axes(axes[2, j], "t [s]", f"commanded τ{j + 1} / τ_max", legend=False)
    what = f", unknown {payload:g} kg payload" if payload else ""
    sol.figure(fig, f"Two-link arm, minimum-time motion ×{speed:g}{what}: computed torque vs MPC")
    return sol


def reach_target(robot: Any, q0: np.ndarray, offset: Any = (0.2, 0.1, -0.2), turn: float = 0.5) -> np.ndarray:
    """A pose T_d near the end effector's at q0: translated by ``offset`` [m] and turned by ``turn`` rad about z."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, q0)
    M = data.oMf[robot.ee_frame]
    T = np.eye(4)
    T[:3, :3] = M.rotation @ pin.exp3(np.array([0.0, 0.0, turn]))
    T[:3, 3] = M.translation + np.asarray(offset, dtype=float)
    return T


def reach_problem(robot: Any, horizon: int = 50, dt: float = DT) -> OptimalControlProblem:
    """Reach a pose within the URDF torque limits: position and orientation costs (heavier at the end), a small
    regularisation of the joint motion and the torques (the same costs as the Crocoddyl comparison of
    ``benchmarks/bench_mpc.py``); joint position and speed limits soft (the URDF's)."""
    n = robot.nv
    return OptimalControlProblem(robot, horizon, dt,
                                 running=StageCost(q=1e-2, qd=1e-1, tau=1e-4, position=1e2, orientation=1e1),
                                 terminal=StageCost(q=0.0, qd=np.full(n, 1e1), position=1e4, orientation=1e3))


def reach(name: str = "panda", duration: float = 1.0) -> Solution:
    """The ``name`` robot (``"panda"`` or ``"ur5"``) reaching a pose 0.3 m away, turned by 0.5 rad, in 0.5 s.

    First one optimal control solve over the 0.5 s horizon (N = 50, dt = 10 ms) with its independent check; then
    MPC with the same problem at 100 Hz for ``duration`` s on the plant saturating at the URDF effort limits, one SQP
    step per sample (real-time iteration, Diehl et al. 2005). The time per sample is the whole computation's (wall
    time; the processor time beside it is what it takes on an idle core)."""
    sol = Solution(id=f"ocp-{name}", title=f"{name}: reaching a pose with its torque limits", kind="simulation")
    robot = load(name)
    q0 = robot.configurations["ready" if name == "panda" else "home"]
    n = robot.nv
    x0 = np.r_[q0, np.zeros(n)]
    T_d = reach_target(robot, q0)
    problem = reach_problem(robot)
    ocp = solve_optimal_control(problem, x0, q_ref=q0, T_d=T_d)
    sol.value("ocp_cost", ocp.cost)
    sol.value("ocp_iterations", ocp.iterations)
    sol.value("ocp_solve_time", ocp.solve_time, "s")
    sol.value("ocp_torque_ratio", ocp.ratios["tau"])
    sol.check("optimal control: converged, KKT and limits checked by Pinocchio", ocp.success,
              f"{ocp.message}; KKT {ocp.kkt:.2g}, defect {ocp.defect:.2g}")
    sol.check_bound("optimal control: torques within the URDF limits", ocp.ratios["tau"], 1.0 + 1e-9)
    data = robot.model.createData()

    def pose_error(q: np.ndarray) -> tuple[float, float]:
        pin.framesForwardKinematics(robot.model, data, q)
        M = data.oMf[robot.ee_frame]
        return (float(np.linalg.norm(M.translation - T_d[:3, 3])),
                float(np.linalg.norm(pin.log3(T_d[:3, :3].T @ M.rotation))))

    sol.value("ocp_final_position_error", pose_error(ocp.x[-1, :n])[0], "m")
    plant = ArmPlant(robot, tau_max=problem.tau_max)
    mpc = ModelPredictiveControl(problem, reference=q0, target=T_d, options=MPCOptions(real_time_iteration=True))
    run = simulate(plant, mpc, (0.0, duration), x0, h=H, Ts=DT)
    errors = np.array([pose_error(q) for q in run.q])
    sol.value("mpc_final_position_error", float(errors[-1, 0]), "m")
    sol.value("mpc_final_orientation_error", float(errors[-1, 1]), "rad")
    solve = run["solve_time"]
    sol.value("mpc_median_solve_time", float(np.median(solve)), "s")
    sol.value("mpc_worst_solve_time", float(np.max(solve)), "s")
    sol.value("mpc_median_cpu_time", float(np.median(run["cpu_time"])), "s")
    sol.value("mpc_missed_deadlines", float(np.mean(run["deadline_met"] == 0)))
    sol.check_bound("MPC: torques within the URDF limits", float(np.max(np.abs(run.u) / problem.tau_max)), 1.0 + 1e-9)
    sol.check_bound("MPC: the pose is reached (position error [m])", errors[-1, 0], 5e-3, "<=",
                    detail=f"{errors[-1, 0] * 1e3:.3g} mm, orientation {errors[-1, 1]:.2g} rad")
    sol.check_bound("MPC: no failed solve", float(run["failed"].sum()), 0.0, "<=")
    fig, axes = subplots(1, 3, figsize=(12, 3.4))
    axes[0].plot(run.t, errors[:, 0] * 1e3, label="MPC")
    axes[0].plot(ocp.trajectory.t, [pose_error(q)[0] * 1e3 for q in ocp.x[:, :n]], "--", label="open-loop plan")
    label_axes(axes[0], "t [s]", "‖p − p_d‖ [mm]")
    axes[1].plot(run.t, run.u / problem.tau_max)
    label_axes(axes[1], "t [s]", "τ / τ_max (MPC)", legend=False)
    axes[2].plot(run.t, solve * 1e3, label="solve time")
    axes[2].axhline(DT * 1e3, color="k", ls=":", label="deadline T_s")
    label_axes(axes[2], "t [s]", "time per sample [ms]")
    sol.figure(fig, f"{name}: optimal reach and MPC at 100 Hz within the URDF torque limits")
    return sol


if __name__ == "__main__":
    for result in (two_link_tracking(), two_link_tracking(payload=10.0), reach("panda"), reach("ur5")):
        print(result.title)
        for c in result.checks:
            print(f"  [{'PASS' if c.passed else 'FAIL'}] {c.name}: {c.detail}")
