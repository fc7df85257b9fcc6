"""Beyond the book: wheeled mobile robots (Chapter 11) and a mobile manipulator.

* :func:`tracking_comparison` — the three unicycle trackers of Sect. 11.6.1 on one figure-eight;
* :func:`parallel_parking` — a car-like robot (bicycle (11.19)) parks in reverse along a cubic path;
* :func:`wheel_saturation` — posture regulation of a differential drive whose wheels saturate (Problem 11.9);
* :func:`car_shortest_paths` — Dubins and Reeds–Shepp shortest paths against random feasible paths;
* :func:`mobile_manipulator_hold` — a unicycle base carrying the book's anthropomorphic arm with spherical
  wrist (one Pinocchio model, planar root joint) drives 1 m while the arm holds its end effector still.

Not problems of the book: run them from the chapter notebook or ``python -m examples.mobile_robots``; each
returns a :class:`problems.registry.Solution` (values, checks, figures) like a book problem.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 11.2–11.7,
3.5 (damped least squares (3.59)); Chapter 12 (Problem 12.1 uses the mobile manipulator's dimension).
"""

from __future__ import annotations

import numpy as np

from rmpc import (ApproximateLinearizationTracking, BicyclePlant, direct_kinematics, dubins_path, FigureEight,
                  InputOutputTracking, load, NonlinearTracking, PostureRegulator, reeds_shepp_path, simulate,
                  UnicyclePlant)
from controllers.plants import MobileManipulatorPlant
from controllers.wheeled import BicycleTracking, MobileManipulatorHold
from planners.timing import quintic_law
from planners.wheeled import (DubinsPath, ReedsSheppPath, TimeScaledPath, dubins_paths, max_steering_angle,
                              reeds_shepp_paths, steering_feasible_path)
from problems.ch11 import H, K_POSTURE, Q0_COMPANION, SEED, draw_unicycle, plane_axes, time_axes
from problems.common import label_axes, subplots
from problems.registry import Solution
from rigid_body.wheeled import differential_drive_wheel_speeds, mobile_manipulator

__all__ = ["tracking_comparison", "parallel_parking", "wheel_saturation", "car_shortest_paths",
           "mobile_manipulator_hold"]


def _settling_time(t: np.ndarray, err: np.ndarray, tol: float) -> float:
    """First time after which ``err`` stays below ``tol`` (inf if it never does)."""
    above = np.nonzero(err >= tol)[0]
    if above.size == 0:
        return float(t[0])
    return float(t[above[-1] + 1]) if above[-1] + 1 < len(t) else float("inf")


def tracking_comparison(t_end: float = 30.0) -> Solution:
    """The three unicycle trackers of Sect. 11.6.1 on one figure-eight with the same initial error.

    Reference: Gerono figure-eight, a = 2 m, period 30 s (|v_d| ≤ 0.59 m/s). Start 0.3 m off in x and y and
    0.4 rad off in heading. Gains: approximate linearisation a = 1, ζ = 0.7; nonlinear ζ = 0.7, b = 4;
    input–output linearisation of B at b = 0.1 m, k = 1 (the error of B is the one it controls). Table:
    settling time (error of the controlled point < 1 cm for good), peak |v|, |ω| and the final error.
    """
    sol = Solution(id="figure-eight", title="Three unicycle trackers on a figure-eight", kind="simulation")
    ref = FigureEight(a=2.0, T=30.0)
    r0 = ref(0.0)
    q0 = np.r_[r0.p + [0.3, -0.3], r0.theta + 0.4]
    laws = {"approximate linearisation": ApproximateLinearizationTracking(ref, a=1.0, zeta=0.7),
            "nonlinear": NonlinearTracking(ref, zeta=0.7, b=4.0),
            "input-output linearisation (b = 0.1 m)": InputOutputTracking(ref, b=0.1, k1=1.0)}
    table, runs = {}, {}
    for name, law in laws.items():
        res = simulate(UnicyclePlant(), law, (0.0, t_end), q0, h=H, Ts=H)
        runs[name] = res
        err = res["point_error"]
        row = {"settling_time": _settling_time(res.t, err, 1e-2), "peak_abs_v": float(np.max(np.abs(res.u[:, 0]))),
               "peak_abs_omega": float(np.max(np.abs(res.u[:, 1]))), "final_error": float(err[-1])}
        table[name] = row
        sol.check(f"{name}: the controlled point converges (error < 1e-3 m at {t_end:g} s, settles within 15 s)",
                  row["final_error"] < 1e-3 and row["settling_time"] < 15.0,
                  f"final {row['final_error']:.1e} m, settling {row['settling_time']:.2f} s")
    sol.value("table", table)
    io = runs["input-output linearisation (b = 0.1 m)"]
    pred = io["point_error"][0] * np.exp(-io.t)
    sol.check("input–output law: the error of B decays as e^{−k t} (k = 1)",
              np.max(np.abs(io["point_error"] - pred)) < 1e-2 * io["point_error"][0],
              f"max deviation {np.max(np.abs(io['point_error'] - pred)):.1e} m")
    sol.check("input–output law: the robot itself stays within b of the reference once B has converged",
              io["position_error"][-1] <= 0.1 + 1e-3, f"‖p_d − p‖ = {io['position_error'][-1]:.3f} m")
    fig, (a1, a2) = subplots(1, 2, figsize=(11, 4.2))
    tt = np.linspace(0, 30, 601)
    pr = np.array([ref(t).p for t in tt])
    a1.plot(pr[:, 0], pr[:, 1], "k:", label="reference")
    for k, (name, res) in enumerate(runs.items()):
        a1.plot(res.x[:, 0], res.x[:, 1], color=f"C{k}", label=name)
        a2.semilogy(res.t, np.maximum(res["point_error"], 1e-12), color=f"C{k}", label=name)
    plane_axes(a1, "Figure-eight tracking", fontsize="x-small")
    label_axes(a2, "t [s]", "error of the controlled point [m]", title="Tracking error", fontsize="x-small")
    sol.figure(fig, "The three unicycle trackers of Sect. 11.6.1 on a figure-eight")
    return sol


def parallel_parking(ell: float = 2.5, phi_max: float = 0.6, T: float = 15.0) -> Solution:
    """Parallel parking of a car-like robot (rear-drive bicycle (11.19), wheelbase ℓ = 2.5 m, |φ| ≤ 0.6 rad).

    Plan: the cubic Cartesian path (11.52) run backwards from (0, 0, 0) to (−7, −2.5, 0) (a bay 2.5 m to the
    side), its k chosen to minimise the peak steering angle (tan φ = ℓ κ), along a quintic timing law s(t) so
    the car starts and stops at rest, T = 15 s. Track: nonlinear unicycle law (ζ = 0.7, b = 2) on the rear
    axle, its ω turned into a steering angle clipped to ±φ_max, steering rate φ̇ = 5(φ_d − φ). The car starts
    0.2 m and 0.05 rad off.
    """
    sol = Solution(id="parallel-parking", title="Parallel parking of a car-like robot", kind="simulation")
    q_i, q_f = np.zeros(3), np.array([-7.0, -2.5, 0.0])
    path = steering_feasible_path(q_i, q_f, ell, phi_max, forward=False)
    sol.value("k", path.k_i)
    sol.value("planned_max_phi", max_steering_angle(path, ell))
    sol.check("planned path respects the steering bound", max_steering_angle(path, ell) <= phi_max,
              f"max |φ| = {max_steering_angle(path, ell):.3f} ≤ {phi_max} rad")
    ref = TimeScaledPath(path, law=quintic_law(0.0, 1.0, T))
    ctrl = BicycleTracking(NonlinearTracking(ref, zeta=0.7, b=2.0, at_rest="stop"), ell, phi_max, k_phi=5.0)
    x0 = np.array([0.1, 0.2, 0.05, 0.0])
    res = simulate(BicyclePlant(ell), ctrl, (0.0, T + 3.0), x0, h=H, Ts=H)
    final = res.x[-1, :3] - q_f
    sol.value("final_posture_error", final)
    sol.value("closed_loop_max_phi", float(np.max(np.abs(res.x[:, 3]))))
    sol.check("parked: final position error < 2 cm and heading error < 0.02 rad",
              np.hypot(*final[:2]) < 0.02 and abs(final[2]) < 0.02, f"error {np.round(final, 4)}")
    sol.check("closed loop keeps |φ| ≤ φ_max", np.max(np.abs(res.x[:, 3])) <= phi_max + 1e-9,
              f"max |φ| = {np.max(np.abs(res.x[:, 3])):.3f} rad")
    sol.check("the manoeuvre is made in reverse (v ≤ 0 after the first second)", np.max(res.u[res.t > 1.0, 0]) <= 1e-6,
              f"max v = {np.max(res.u[res.t > 1.0, 0]):.2e} m/s")
    fig, (a1, a2) = subplots(1, 2, figsize=(11, 4.0))
    pp, _, _ = path(np.linspace(0, 1, 300))
    a1.plot(pp[:, 0], pp[:, 1], "k:", label="planned rear-axle path")
    a1.plot(res.x[:, 0], res.x[:, 1], label="car (closed loop)")
    for k in range(0, len(res.t), 300):
        draw_unicycle(a1, *res.x[k, :3], size=0.4)
    plane_axes(a1, "Parallel parking (reverse)")
    a2.axhline(-phi_max, color="k", ls=":", lw=1)
    a2.axhline(phi_max, color="k", ls=":", lw=1)
    time_axes(a2, res.t, [(res.u[:, 0], "v [m/s]"), (res.x[:, 3], "φ [rad] (dotted: ±φ_max)")], "v [m/s], φ [rad]",
              "Driving velocity and steering angle")
    sol.figure(fig, f"Parallel parking of a car-like robot, ℓ = {ell:g} m, |φ| ≤ {phi_max:g} rad")
    return sol


def wheel_saturation(t_end: float = 20.0) -> Solution:
    """Posture regulation (11.81)–(11.82) of a differential drive whose wheels saturate at ω_RL (Problem 11.9).

    r = 0.1 m, d = 0.5 m, ω_RL = 10 rad/s (|v| ≤ 1 m/s, |ω| ≤ 4 rad/s); the commands are scaled into the
    admissible rhombus keeping the curvature. From the companion start the regulator asks for more than the
    wheels give; the loop still converges, later than without the bound.
    """
    sol = Solution(id="wheel-saturation", title="Posture regulation with saturated wheel speeds", kind="simulation")
    limits = (0.1, 0.5, 10.0)
    plant = UnicyclePlant(wheel_limits=limits)
    reg = PostureRegulator(*K_POSTURE)
    res = simulate(plant, reg, (0.0, t_end), Q0_COMPANION, h=H, Ts=H, log=lambda t, x, u: {"applied": plant.applied(u)})
    free = simulate(UnicyclePlant(), reg, (0.0, t_end), Q0_COMPANION, h=H, Ts=H)
    wR, wL = differential_drive_wheel_speeds(res.u[:, 0], res.u[:, 1], *limits[:2])
    aR, aL = differential_drive_wheel_speeds(res["applied"][:, 0], res["applied"][:, 1], *limits[:2])
    peak_cmd, peak_applied = float(np.max(np.abs([wR, wL]))), float(np.max(np.abs([aR, aL])))
    sol.value("peak_commanded_wheel_speed", peak_cmd)
    sol.value("peak_applied_wheel_speed", peak_applied)
    sol.check("saturation is active: commanded wheel speeds exceed ω_RL", peak_cmd > limits[2], f"{peak_cmd:.2f} rad/s")
    sol.check("applied wheel speeds within ±ω_RL", peak_applied <= limits[2] + 1e-9, f"{peak_applied:.3f} rad/s")
    dist = np.hypot(res.x[:, 0], res.x[:, 1])
    dist_free = np.hypot(free.x[:, 0], free.x[:, 1])
    ts, ts_free = _settling_time(res.t, dist, 1e-2), _settling_time(free.t, dist_free, 1e-2)
    sol.value("time_to_1cm", ts)
    sol.value("time_to_1cm_unsaturated", ts_free)
    sol.check("the saturated loop still converges (‖p‖ < 1 cm), later than the unsaturated one",
              dist[-1] < 1e-2 and ts > ts_free, f"{ts:.2f} s vs {ts_free:.2f} s")
    fig, (a1, a2) = subplots(1, 2, figsize=(11, 4.0))
    a1.plot(free.x[:, 0], free.x[:, 1], label="no wheel bound")
    a1.plot(res.x[:, 0], res.x[:, 1], "--", label="|ω_R|, |ω_L| ≤ 10 rad/s")
    plane_axes(a1, "Posture regulation")
    time_axes(a2, res.t, [(aR, "ω_R applied"), (aL, "ω_L applied")], "wheel speed [rad/s]", "Saturated wheel speeds")
    sol.figure(fig, "Posture regulation of a differential drive with saturated wheel speeds")
    return sol


def car_shortest_paths(cases: int = 300) -> Solution:
    """Shortest paths of a car with turning radius ρ: Dubins (forward only) and Reeds–Shepp (both ways).

    Closed forms: straight ahead (length d), the U-turn to (0, 2ρ, π) (πρ), straight back (d for Reeds–Shepp).
    Every candidate's end posture, by exact integration of its arcs (11.85), is the goal. Optimality: random
    paths of curvature ≤ 1/ρ (1–5 random arcs and straights; forward only for Dubins, either way for
    Reeds–Shepp) are never shorter than the closed-form shortest path between their end postures, and many
    are themselves optimal (equal); Reeds–Shepp is never longer than Dubins.
    """
    sol = Solution(id="car-shortest-paths", title="Dubins and Reeds–Shepp shortest paths", kind="numeric")
    rho = 1.0
    sol.check_close("straight ahead: length = distance", dubins_path([0, 0, 0], [4, 0, 0], rho).length, 4.0, atol=1e-12)
    sol.check_close("U-turn to (0, 2ρ, π): length = πρ", dubins_path([0, 0, 0], [0, 2, np.pi], rho).length, np.pi,
                    atol=1e-12)
    sol.check_close("Reeds–Shepp straight back: length = distance",
                    reeds_shepp_path([0, 0, 0], [-3, 0, 0], rho).length, 3.0, atol=1e-12)
    rng = np.random.default_rng(SEED)
    worst_end, worst_gap, equal = 0.0, -np.inf, 0
    for _ in range(cases):
        q_i = rng.uniform(-3, 3, 3)
        n_seg = int(rng.integers(2, 6))
        word = "".join(rng.choice(list("LSR"), n_seg))
        seg = rng.uniform(0.05, 2.0, n_seg)
        random_path = DubinsPath(q_i, rho, word, seg)  # any sequence of primitives: a feasible path
        q_f = random_path.end()
        for p in dubins_paths(q_i, q_f, rho):
            e = p.end() - q_f
            worst_end = max(worst_end, float(np.max(np.abs(np.r_[e[:2], np.angle(np.exp(1j * e[2]))]))))
        gap = dubins_path(q_i, q_f, rho).length - random_path.length
        worst_gap = max(worst_gap, gap)
        equal += abs(gap) < 1e-9
    sol.value("max_end_error", worst_end)
    sol.value("max_dubins_minus_random_length", worst_gap)
    sol.value("random_paths_that_are_optimal", f"{equal}/{cases}")
    # Tangent lengths p = √p² lose half the digits when two circles (nearly) touch: 1e-7, not 1e-15.
    sol.check_error("every word ends at the goal (exact arcs)", worst_end, 1e-7)
    sol.check(f"Dubins length ≤ length of {cases} random feasible paths with the same end postures",
              worst_gap <= 1e-9, f"max (Dubins − random) = {worst_gap:.2e} m; equal in {equal} cases")
    sol.check("the bound is tight: some random paths are themselves optimal", equal > 0, f"{equal}/{cases}")

    rs_end, rs_gap, rs_equal, rs_vs_dubins = 0.0, -np.inf, 0, -np.inf
    for _ in range(cases):
        q_i = rng.uniform(-3, 3, 3)
        n_seg = int(rng.integers(1, 6))
        random_path = ReedsSheppPath(q_i, rho, "".join(rng.choice(list("LSR"), n_seg)),
                                     rng.uniform(0.05, 2.0, n_seg) * rng.choice([-1.0, 1.0], n_seg))
        q_f = random_path.end()
        for p in reeds_shepp_paths(q_i, q_f, rho):
            e = p.end() - q_f
            rs_end = max(rs_end, float(np.max(np.abs(np.r_[e[:2], np.angle(np.exp(1j * e[2]))]))))
        best = reeds_shepp_path(q_i, q_f, rho).length
        rs_gap = max(rs_gap, best - random_path.length)
        rs_equal += abs(best - random_path.length) < 1e-9
        rs_vs_dubins = max(rs_vs_dubins, best - dubins_path(q_i, q_f, rho).length)
    sol.value("reeds_shepp_max_end_error", rs_end)
    sol.value("reeds_shepp_random_paths_that_are_optimal", f"{rs_equal}/{cases}")
    sol.check_error("Reeds–Shepp: every candidate ends at the goal (exact arcs)", rs_end, 1e-7)
    sol.check(f"Reeds–Shepp length ≤ length of {cases} random forward/backward paths (and some equal)",
              rs_gap <= 1e-9 and rs_equal > 0, f"max (RS − random) = {rs_gap:.2e} m; equal in {rs_equal} cases")
    sol.check("Reeds–Shepp ≤ Dubins (forward paths are a subset)", rs_vs_dubins <= 1e-9, f"max (RS − Dubins) = {rs_vs_dubins:.2e} m")
    fig, ax = subplots(figsize=(6, 5))
    q_i, q_f = np.array([0.0, 0.0, 0.0]), np.array([1.0, 1.5, np.pi])
    for p in dubins_paths(q_i, q_f, rho):
        xy = p.sample(0.02)
        ax.plot(xy[:, 0], xy[:, 1], lw=2.5 if p is dubins_paths(q_i, q_f, rho)[0] else 1,
                label=f"{p.word}: {p.length:.2f} m")
    draw_unicycle(ax, *q_i, size=0.2)
    draw_unicycle(ax, *q_f, size=0.2)
    rs = reeds_shepp_path(q_i, q_f, rho)
    xy = rs.sample(0.02)
    ax.plot(xy[:, 0], xy[:, 1], "k--", lw=2, label=f"Reeds–Shepp {rs.word}: {rs.length:.2f} m")
    plane_axes(ax)
    sol.figure(fig, "Dubins words and the Reeds–Shepp path, (0, 0, 0) → (1, 1.5, π), ρ = 1 m")
    return sol


# --------------------------------------------------------------------------------------------
# The mobile manipulator (a unicycle base carrying the book's 6R arm with spherical wrist)
# --------------------------------------------------------------------------------------------

MOUNT = np.array([0.0, 0.0, 0.3])                                  # arm base above the axle midpoint [m]
Q_ARM0 = np.array([np.pi / 2, -1.1, -2.8, 0.0, 0.5, 0.0])          # end effector 0.6 m to the left [rad]


def lateral_velocities(t: np.ndarray, base: np.ndarray) -> np.ndarray:
    """The sideways velocity that the no-slip constraint (11.12) forbids, by finite differences of a sampled
    base pose history (N, 3): (−sin θ̄ Δx + cos θ̄ Δy)/Δt per interval (N − 1,), θ̄ the interval's mean heading
    (under a held (v, ω) the base runs an arc whose chord has exactly that direction, so this vanishes to
    round-off for a rolling base and not for one that slides)."""
    dt = np.diff(t)
    th = 0.5 * (base[1:, 2] + base[:-1, 2])
    return (-np.sin(th) * np.diff(base[:, 0]) + np.cos(th) * np.diff(base[:, 1])) / dt


def mobile_manipulator_hold(distance: float = 1.0, curvature: float = 0.3, T: float = 5.0, Ts: float = 0.01,
                            K: float = 10.0) -> Solution:
    """A unicycle base carrying the anthropomorphic arm with spherical wrist drives ``distance`` along an arc
    of ``curvature`` [1/m] (quintic timing law over T) while the arm holds its end effector where it started.

    One Pinocchio model (:func:`rigid_body.wheeled.mobile_manipulator`: planar root joint, nq = 10, nv = 9),
    a kinematic plant whose base moves only along its heading (:class:`controllers.plants.MobileManipulatorPlant`)
    and the task-space law :class:`controllers.wheeled.MobileManipulatorHold` (K = 10 s⁻¹, period Ts). Checked:
    nv = 3 + the arm's nv (the configuration space's dimension, Problem 12.1) and nq = nv + 1 (cos θ, sin θ);
    the base's lateral velocity (finite differences of its pose history) vanishes at every sample; the path
    length is ``distance``; the end effector — recomputed by composing the base pose, the mount and the
    arm's own direct kinematics (not the combined model) — stays within 1e-3 m of its start.
    """
    sol = Solution(id="mobile-manipulator", title="Mobile manipulator: drive 1 m, hold the end effector",
                   kind="simulation")
    arm = load("anthropomorphic_wrist")
    robot = mobile_manipulator(arm, mount=MOUNT)
    sol.value("nq", robot.nq)
    sol.value("nv", robot.nv)
    sol.value("configuration_space_dimension", robot.nv)
    sol.check("dim C = nv = 3 (x, y, θ) + the arm's joints, nq = nv + 1 (cos θ, sin θ)",
              robot.nv == 3 + arm.nv and robot.nq == robot.nv + 1, f"nq = {robot.nq}, nv = {robot.nv}, arm {arm.nv}")

    base0 = np.array([-0.5, -0.1, 0.0])
    law = quintic_law(0.0, distance, T)

    def base_velocity(t: float) -> np.ndarray:
        v = float(law(min(t + Ts / 2, T))[1])                     # the held value: mid-interval speed
        return np.array([v, curvature * v])

    plant = MobileManipulatorPlant(robot)
    x0 = plant.initial_state(base0, Q_ARM0)
    p_d = direct_kinematics(robot, x0)[:3, 3]                     # the whole model's end effector at the start
    ctrl = MobileManipulatorHold(robot, p_d, base_velocity, K=K)
    res = simulate(plant, ctrl, (0.0, T + 1.0), x0, h=Ts, Ts=Ts)

    base = res["base"]
    lateral = lateral_velocities(res.t, base)
    steps = np.diff(base[:, :2], axis=0)
    length = float(np.sum(np.hypot(steps[:, 0], steps[:, 1])))
    # End effector from the arm's own model: T_base(x, y, θ) · mount · T_arm(q_arm) (independent of the appended model).
    def ee_from_parts(x: np.ndarray, pose: np.ndarray) -> np.ndarray:
        c, s = np.cos(pose[2]), np.sin(pose[2])
        R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        return np.r_[pose[:2], 0.0] + R @ (MOUNT + direct_kinematics(arm, x[4:])[:3, 3])

    ee = np.array([ee_from_parts(x, b) for x, b in zip(res.x, base)])
    hold = np.linalg.norm(ee - ee[0], axis=1)
    sol.value("path_length", length)
    sol.value("final_heading", float(base[-1, 2]))
    sol.value("max_lateral_velocity", float(np.max(np.abs(lateral))))
    sol.value("max_end_effector_error", float(np.max(hold)))
    sol.value("max_logged_error", float(np.max(np.linalg.norm(res["e"], axis=1))))
    sol.value("peak_speed", float(np.max(np.abs(res.u[:, 0]))))
    sol.check_error("no sideways slip: |−sin θ̄ Δx + cos θ̄ Δy|/Δt over every sampling interval", np.max(np.abs(lateral)),
                    1e-9)
    sol.check_close("the base drives the planned distance (path length of the sampled poses)", length, distance,
                    atol=2e-3)
    sol.check("the base turns as planned: θ(T) = θ0 + κ·distance", abs(base[-1, 2] - curvature * distance) < 2e-3,
              f"θ(T) = {base[-1, 2]:.4f} rad")
    sol.check_error("end effector held: ‖p_e(t) − p_e(0)‖ (base pose ∘ mount ∘ arm kinematics)", np.max(hold), 1e-3)
    sol.check_close("the appended model's end effector = the composition of the parts", ee[0], p_d, atol=1e-12)

    fig, (a1, a2) = subplots(1, 2, figsize=(11, 4.0))
    a1.plot(base[:, 0], base[:, 1], label="base (axle midpoint)")
    a1.plot(ee[:, 0], ee[:, 1], "o", ms=3, label="end effector")
    for k in range(0, len(res.t), 100):
        draw_unicycle(a1, *base[k], size=0.1)
    plane_axes(a1, "Base path and end effector (top view)")
    a2.semilogy(res.t[1:], np.maximum(hold[1:], 1e-12), label="‖p_e − p_e(0)‖ [m]")
    a2.semilogy(res.t[1:], np.maximum(np.abs(lateral), 1e-18), "--", label="|lateral velocity| [m/s]")
    label_axes(a2, "t [s]", "end-effector error [m], lateral velocity [m/s]", title="Hold and no-slip")
    sol.figure(fig, f"Mobile manipulator (nq = {robot.nq}, nv = {robot.nv}): the base drives {distance:g} m, "
                    "the arm holds its end effector")
    return sol


if __name__ == "__main__":
    for demo in (tracking_comparison, parallel_parking, wheel_saturation, car_shortest_paths, mobile_manipulator_hold):
        result = demo()
        for c in result.checks:
            print(f"[{'PASS' if c.passed else 'FAIL'}] {c.name}: {c.detail}")
