"""Chapter 6 — Control Architecture: Problems 6.1–6.4 made executable.

The manual answers these qualitatively (6.1–6.3) and with a PASCAL listing (6.4); here the task and
action levels of Fig. 6.1 are run: the pick-and-place decomposition and its C–D–E–F path (6.1, 6.2)
on the three-link planar arm, the peg-in-hole flow chart (6.3) as a state machine on the simulated
planar arm with a wrist force sensor against a compliant surface, and the pallet-filling program
(6.4) on the simulated SCARA. All coordinates of the scenes (A, B, the obstacle, the hole, home,
conveyor, pallet, lift, object size, speeds) are chosen here: the book leaves them as placeholders.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Ch. 6
and Sect. 4.4; solution manual, Problems 6.1–6.4 (Figs. S6.1, S6.2).
"""

from __future__ import annotations

import numpy as np

from controllers.environment import SurfaceWithHole
from controllers.force import PEG_STATES, PegInHoleTask, run_peg_in_hole
from controllers.tasks import (ActionExecutor, ExecutionOptions, Step, TaskError, Workcell, fill_pallet_program,
                               moveto)
from planners.configuration_space import distance_to_box
from planners.tasks import decompose_pick_and_place, pick_and_place_path
from problems.common import subplots, label_axes
from problems.registry import Solution, problem
from rigid_body.kinematics import inverse_kinematics_planar_3r, inverse_kinematics_scara
from rigid_body.robots import load
from planners.timing import sample

# Scene of 6.1/6.2 (three-link planar arm of Fig. 2.20 in the vertical plane, base at the origin):
TABLE = -0.2                                    # work surface y = −0.2 m (below the arm's base)
A, B = (0.45, TABLE), (0.75, TABLE)             # pick and place locations on the table
OBSTACLE = (0.55, 0.65, -0.05)                  # box x ∈ [0.55, 0.65] standing on the table, top at y = −0.05 m
CLEARANCE = 0.05                                # safety distance [m]
PHI_DOWN = -np.pi / 2                           # end effector pointing down (constant orientation, 6.2)
DURATIONS = (1.0, 1.5, 1.0)                     # CD, DE, EF [s]
OVERLAP = 0.4                                   # via points: anticipation of DE and EF [s]

# Scene of 6.4 (SCARA of Table S2.3, z0 down: "above" is −z0):
HOME = (0.5, -0.3, 0.3, 0.0)
CONVEYOR = (0.7, -0.3, 0.8, 0.0)
PALLET = (0.3, 0.35, 0.8, 0.0)
LIFT, LENGTH, WIDTH, FAST, SLOW = 0.1, 0.08, 0.08, 1.0, 0.2
OBJECT_MASS = 0.5


def _given_scene(sol: Solution) -> tuple:
    """Declare the scene of 6.1–6.2 (A, B, the obstacle box, the clearance) as the problem's data."""
    return (sol.given("A", np.array(A), unit="m"), sol.given("B", np.array(B), unit="m"),
            sol.given("obstacle [x_min, x_max, y_top]", np.array(OBSTACLE), unit="m"),
            sol.given("clearance", CLEARANCE, unit="m"))


@problem("6.1", "Task decomposition of a pick-and-place around an obstacle (Fig. 6.1)", kind="qualitative")
def problem_6_1() -> Solution:
    """Describe the sequence of actions to pick an object at A and place it at B, avoiding an
    obstacle, with reference to the hierarchical architecture of Fig. 6.1.

    Task level: :func:`decompose_pick_and_place` gives the actions of the manual (approach A, pick,
    move avoiding the obstacle, approach B, place) and the intermediate points C, D, E, F of Fig.
    S6.1. The feasibility check of the modelling module is made concrete: every point of the path
    has a closed-form inverse kinematics solution of the planar arm with the end effector pointing down.
    """
    sol = Solution()
    plan = decompose_pick_and_place(*_given_scene(sol))
    names = [a.name for a in plan.actions]
    sol.value("actions", names)
    sol.value("points", plan.points, unit="m")
    path = pick_and_place_path(plan, DURATIONS)
    traj = sample(path, samples=301)
    d = float(distance_to_box(traj.q[:, :2], OBSTACLE).min())
    sol.check("the path C–D–E–F keeps the safety distance from the obstacle", d >= CLEARANCE - 1e-12,
              f"min distance {d:.4f} m (clearance {CLEARANCE} m)")
    failures = 0
    for p in traj.q:
        try:
            inverse_kinematics_planar_3r(np.array([p[0], p[1], PHI_DOWN]))
        except ValueError:
            failures += 1
    sol.check("path feasible: closed-form IK of the planar arm exists along C–D–E–F (φ = −π/2)", failures == 0,
              f"{failures} of {len(traj.q)} samples unreachable")
    # The motion executed on the simulated arm (inverse-dynamics control, 1 ms): the end effector grasps
    # at A, releases at B and passes over the obstacle with the stated clearance.
    robot = load("planar_3r")
    q0 = inverse_kinematics_planar_3r(np.array([*A, PHI_DOWN]))[0]
    executor = ActionExecutor(robot, inverse_kinematics_planar_3r, None, q0, ExecutionOptions(Ts=1e-3, h=1e-3))
    executor.follow(path, position_rows=(0, 1), orientation=(PHI_DOWN,), jacobian_rows=(0, 1, 5))
    rec = executor.record()
    reach = [float(np.min(np.linalg.norm(rec.p[:, :2] - np.asarray(P), axis=1))) for P in (A, B)]
    sol.check_error("executed: the end effector reaches A (grasp) and B (release) within 1 mm", max(reach), 1e-3,
                    "simulation vs prediction",
                    detail=f"closest approach to A {reach[0] * 1e3:.3f} mm, to B {reach[1] * 1e3:.3f} mm")
    over = (rec.p[:, 0] >= OBSTACLE[0]) & (rec.p[:, 0] <= OBSTACLE[1])
    d_run = float(distance_to_box(rec.p[:, :2], OBSTACLE).min())
    lowest = float(rec.p[over, 1].min()) if over.any() else float("nan")
    # the smaller of the two clearances (NaN, failing, when the path never passes over the box)
    cleared = float(np.minimum(d_run, lowest - OBSTACLE[2]))
    sol.check_bound("executed: clears the obstacle by the clearance, 1 mm tolerance (min distance, lowest point "
                    "above the box)", cleared, CLEARANCE - 1e-3, ">=", "simulation vs prediction",
                    f"min distance {d_run:.4f} m, lowest y over the box {lowest:.4f} m "
                    f"(top {OBSTACLE[2]} m + clearance {CLEARANCE} m)")
    unreachable = False
    try:
        decompose_pick_and_place(A, (0.6, TABLE), OBSTACLE, CLEARANCE)
    except ValueError:
        unreachable = True
    sol.check("an impossible task (B inside the obstacle's span) is rejected at the task level", unreachable,
              "ValueError raised")
    return sol


@problem("6.2", "Motion primitives with path points versus via points", kind="qualitative")
def problem_6_2() -> Solution:
    """Give the operational-space primitives for 6.1 with path points and with via points.

    Path points: CD and EF timed by quintics (null velocity and acceleration at C and F — "at least
    fourth order"), DE by a cubic or a trapezoidal velocity profile; the arm stops at D and E. Via
    points: the same laws with DE and EF anticipated (overlapping), so the path rounds D and E keeping
    a safety distance from the obstacle. The constant end-effector orientation along −y uses the
    redundant DOF of the planar arm (checked by IK along the path). Both motions are then executed
    on the simulated planar arm (joint reference from closed-form IK and differential kinematics,
    inverse-dynamics control at 1 ms). Fig. S6.1 (the scene's coordinates are chosen here).
    """
    sol = Solution()
    plan = decompose_pick_and_place(*_given_scene(sol))
    durations = sol.given("durations CD, DE, EF", np.array(DURATIONS), unit="s")
    sol.given("overlap", OVERLAP, unit="s")
    t_D, t_E = durations[0], durations[0] + durations[1]
    results = {}
    for label, kwargs in (("path points (cubic DE)", dict(middle="cubic")),
                          ("path points (trapezoidal DE)", dict(middle="trapezoidal")),
                          ("via points", dict(via_points=True, overlap=OVERLAP))):
        law = pick_and_place_path(plan, DURATIONS, **kwargs)
        results[label] = (law, sample(law, samples=1201))
    for label in ("path points (cubic DE)", "path points (trapezoidal DE)"):
        law, traj = results[label]
        p0, v0, a0 = law(law.t_i)
        pf, vf, af = law(law.t_f)
        sol.check(f"{label}: null velocity and acceleration at C and F",
                  max(np.abs(v0).max(), np.abs(a0).max(), np.abs(vf).max(), np.abs(af).max()) < 1e-12,
                  f"|v|, |a| at C and F ≤ {max(np.abs(v0).max(), np.abs(a0).max(), np.abs(vf).max(), np.abs(af).max()):.1e}")
        vD, vE = law(t_D)[1], law(t_E)[1]
        sol.check(f"{label}: null velocity at D and E (the arm stops)", max(np.abs(vD).max(), np.abs(vE).max()) < 1e-12,
                  f"|v(t_D)| = {np.abs(vD).max():.1e}, |v(t_E)| = {np.abs(vE).max():.1e}")
        sol.check_close(f"{label}: passes through D and E", [law(t_D)[0][:2], law(t_E)[0][:2]],
                        [plan.points["D"], plan.points["E"]], atol=1e-12, reference="property")
    law, traj = results["via points"]
    p0, v0, a0 = law(law.t_i)
    pf, vf, af = law(law.t_f)
    sol.check("via points: null initial and final velocity and acceleration",
              max(np.abs(v0).max(), np.abs(a0).max(), np.abs(vf).max(), np.abs(af).max()) < 1e-12, "at C and F")
    dmin = float(distance_to_box(traj.q[:, :2], OBSTACLE).min())
    sol.value("via_min_distance", dmin, unit="m")
    sol.check("via points: the path keeps a safety distance (≥ half the clearance) from the obstacle",
              dmin >= 0.5 * CLEARANCE, f"min distance {dmin:.4f} m")
    dD = float(np.min(np.linalg.norm(traj.q[:, :2] - plan.points["D"], axis=1)))
    sol.check("via points: the path rounds D instead of stopping there", dD > 1e-3 and
              np.linalg.norm(law(t_D - OVERLAP / 2)[1]) > 0.05, f"closest approach to D {dD:.4f} m")
    T_path = results["path points (cubic DE)"][0].t_f - results["path points (cubic DE)"][0].t_i
    T_via = law.t_f - law.t_i
    sol.value("duration_path_points", T_path, unit="s")
    sol.value("duration_via_points", T_via, unit="s")
    ik_ok = True
    for _, (_, tr) in results.items():
        for p in tr.q[::10]:
            try:
                inverse_kinematics_planar_3r(np.array([p[0], p[1], PHI_DOWN]))
            except ValueError:
                ik_ok = False
    sol.check("redundancy: the orientation along −y is kept constant along every path (IK exists)", ik_ok,
              "planar 3R, φ = −π/2 at every 10th sample")
    # Primitive level: both motions executed on the simulated arm (inverse-dynamics control, 1 ms).
    robot = load("planar_3r")
    q0 = inverse_kinematics_planar_3r(np.array([*A, PHI_DOWN]))[0]          # elbow up: within the joint limits
    executed = {}
    for label in ("path points (cubic DE)", "via points"):
        law = results[label][0]
        executor = ActionExecutor(robot, inverse_kinematics_planar_3r, None, q0, ExecutionOptions(Ts=1e-3, h=1e-3))
        executor.follow(law, position_rows=(0, 1), orientation=(PHI_DOWN,), jacobian_rows=(0, 1, 5))
        rec = executor.record()
        executed[label] = rec
        err = float(np.max(np.abs(rec.p[:, :2] - law(rec.t)[0][:, :2])))
        d_run = float(distance_to_box(rec.p[:, :2], OBSTACLE).min())
        within = bool(np.all(rec.q >= robot.lower) and np.all(rec.q <= robot.upper))
        sol.check(f"{label} executed on the simulated planar arm: tracking error < 1 mm, clear of the obstacle, "
                  f"within the joint limits", err < 1e-3 and d_run >= 0.5 * CLEARANCE and within,
                  f"max |p − p_d| = {err * 1e3:.3f} mm, min distance {d_run:.4f} m, joint limits respected: {within}")
    fig, (ax, ax2) = subplots(1, 2, figsize=(11, 4.2))
    x0, x1, top = OBSTACLE
    ax.fill([x0, x1, x1, x0], [TABLE, TABLE, top, top], color="0.7", label="obstacle")
    ax.axhline(TABLE, color="k", lw=0.8)
    for label, style in (("path points (cubic DE)", "b-"), ("via points", "r--")):
        rec = executed[label]
        ax.plot(rec.p[:, 0], rec.p[:, 1], style, label=f"{label} (executed)")
    for k, p in plan.points.items():
        ax.plot(*p, "ko")
        ax.annotate(k, p, textcoords="offset points", xytext=(5, 5))
    ax.set_aspect("equal")
    label_axes(ax, "x [m]", "y [m]", legend="lower center", grid=False)
    for label, style in (("path points (cubic DE)", "b-"), ("path points (trapezoidal DE)", "g-."),
                         ("via points", "r--")):
        tr = results[label][1]
        ax2.plot(tr.t, np.linalg.norm(tr.qd, axis=1), style, label=label)
    label_axes(ax2, "t [s]", "|ṗ| [m/s]", legend=True)
    sol.figure(fig, "Fig. S6.1 — pick-and-place around an obstacle: path points vs via points")
    return sol


@problem("6.3", "Peg-in-hole with a wrist force sensor: flow chart as a state machine", kind="qualitative")
def problem_6_3() -> Solution:
    """A planar arm with a wrist force sensor inserts a peg into a hole whose position is known with
    an error along x only (axes aligned, no jamming). The flow chart of Fig. S6.2 — fast approach to
    (x_H, Δy), slow descent until y < −Δy or |f_y| > ε, force/position search sliding along ±x (motion
    inverted when |x − x_H| > Δx) until the force drops, insertion with position along y and force
    along x — runs as :class:`PegInHoleController` on the simulated three-link planar arm against a
    compliant surface with a hole (stiffness 2·10⁴ N/m, clearance 4 mm). Each phase is chapter 9's hybrid
    force/motion law (9.77)–(9.81) with its selection matrices: pure motion while approaching and
    descending, the 10 N push along y while searching, zero force along x while inserting.

    The manual's moment control about z during insertion (keeping the peg aligned) is replaced by
    holding the peg's orientation: the point-contact model of the hole produces no moment.

    Two scenes: the hole 12 mm to the left of its estimate (the search starts to the right, inverts,
    finds it) and the hole within the clearance of its estimate (no search needed).
    """
    sol = Solution()
    robot = load("planar_3r")
    task = PegInHoleTask(x_H=sol.given("x_H", 0.6, unit="m"))
    sol.given("Δy, Δx, f_push", np.array([task.dy, task.dx, task.f_push]), unit="m, m, N")
    q0 = inverse_kinematics_planar_3r(np.array([0.55, 0.15, task.phi]))[0]       # elbow up, within the limits
    fig, axes = subplots(3, 2, figsize=(11, 7), sharex="col")
    for col, (label, offset, duration) in enumerate((("hole 12 mm left of x_H", -0.012, 7.0),
                                                    ("hole within the clearance of x_H", 0.002, 4.0))):
        env = SurfaceWithHole(x_hole=task.x_H + offset, clearance=0.004, depth=0.05)
        res, ctrl = run_peg_in_hole(robot, env, task, q0, duration)
        states = [s for _, s in ctrl.transitions]
        q = res.q
        sol.check(f"{label}: the motion respects the joint limits of the arm (Problem 2.17)",
                  bool(np.all(q >= robot.lower) and np.all(q <= robot.upper)),
                  f"q ranges {np.round(q.min(axis=0), 3).tolist()} … {np.round(q.max(axis=0), 3).tolist()}")
        key = "search" if offset < -0.004 else "direct"
        sol.value(f"transitions_{key}", [(round(t, 3), s) for t, s in ctrl.transitions], unit="s (instant of each state)")
        x_e, f, state = res["x_e"], res["f"], res["state"]
        if key == "search":
            sol.check("search scene: approach → descend → search → insert → done", states == list(PEG_STATES),
                      " → ".join(states))
            sol.check("search scene: the sliding motion is inverted once at |x − x_H| > Δx", ctrl.inversions == 1,
                      f"{ctrl.inversions} inversion(s); max |x − x_H| while searching = "
                      f"{np.max(np.abs(x_e[state == PEG_STATES.index('search'), 0] - task.x_H)):.4f} m (Δx = {task.dx} m)")
            in_search = state == PEG_STATES.index("search")
            mean_push = float(np.mean(np.abs(f[in_search][50:, 1])))
            sol.check("search: the sensed force holds the desired push while sliding", abs(mean_push - task.f_push) < 1.0,
                      f"mean |f_y| while sliding = {mean_push:.2f} N (desired {task.f_push} N)")
        else:
            sol.check("direct scene: approach → descend → insert → done (no search)",
                      states == ["approach", "descend", "insert", "done"], " → ".join(states))
        sol.check(f"{label}: peg inserted to the depth, inside the hole",
                  abs(x_e[-1, 1] + task.insert_depth) < 1e-3 and abs(x_e[-1, 0] - env.x_hole) <= env.clearance + 5e-4,
                  f"final tip ({x_e[-1, 0]:.4f}, {x_e[-1, 1]:.4f}) m; hole at x = {env.x_hole:.4f} ± {env.clearance} m")
        axes[0, col].plot(res.t, x_e[:, 0] * 1e3, label="x")
        axes[0, col].axhline(env.x_hole * 1e3, color="k", ls=":", label="hole centre")
        axes[0, col].set_title(label, fontsize="small")
        label_axes(axes[0, col], None, "x [mm]", legend=True, grid=False, fontsize="x-small")
        axes[1, col].plot(res.t, x_e[:, 1] * 1e3)
        label_axes(axes[1, col], None, "y [mm]", legend=False, grid=False)
        axes[2, col].plot(res.t, f[:, 1], label="f_y")
        axes[2, col].plot(res.t, f[:, 0], label="f_x")
        label_axes(axes[2, col], "t [s]", "force [N]", legend=True, grid=False, fontsize="x-small")
        for t_s, s in ctrl.transitions[1:]:
            for ax in axes[:, col]:
                ax.axvline(t_s, color="0.6", lw=0.7)
            axes[1, col].annotate(s, (t_s, axes[1, col].get_ylim()[1]), fontsize="x-small", rotation=90, va="top")
    sol.figure(fig, "Fig. S6.2 as a state machine — peg-in-hole with a wrist force sensor")
    return sol


@problem("6.4", "Pallet-filling program: 16 objects from a conveyor onto a pallet", kind="programming")
def problem_6_4() -> Solution:
    """Write a program that picks 16 equal objects from a conveyor (the robot commands the feed, so an
    object is always there) and loads them onto a 4 × 4 pallet.

    The manual's PASCAL FILL_PALLET (its garbled block structure repaired — erratum) is
    :func:`fill_pallet_program`; it runs on the simulated SCARA (Table S2.3, a₁ = a₂ = 0.5 m) through
    :class:`ActionExecutor`: MOVETO = closed-form IK + joint quintic tracked by inverse-dynamics
    control (1 ms-class sampling, 2 ms here), GRASP/RELEASE on the work-cell model (objects of 0.5 kg
    added to the arm's dynamics while held). Scene data chosen here (placeholders in the manual).
    """
    sol = Solution()
    robot = load("scara")
    for name, datum in (("home", HOME), ("conveyor", CONVEYOR), ("pallet", PALLET)):
        sol.given(name, np.array(datum), unit="m, m, m, rad")
    sol.given("lift, length, width", np.array([LIFT, LENGTH, WIDTH]), unit="m")
    sol.given("fast, slow", np.array([FAST, SLOW]), unit="m/s")
    program = fill_pallet_program(HOME, CONVEYOR, PALLET, LIFT, LENGTH, WIDTH, FAST, SLOW, up=(0.0, 0.0, -1.0))
    prims = [s.primitive for s in program]
    sol.value("program_length", len(program), unit="1")
    sol.check("16 NEW_OBJECT, 16 GRASP, 16 RELEASE", prims.count("NEW_OBJECT") == prims.count("GRASP")
              == prims.count("RELEASE") == 16, f"{prims.count('GRASP')} grasps, {prims.count('RELEASE')} releases")
    home_step = moveto(HOME, FAST)
    sol.check("starts and ends with MOVETO(home, fast)", program[0] == home_step and program[-1] == home_step,
              f"{program[0]} … {program[-1]}")
    conveyor = np.array(CONVEYOR)
    grasp_ok = all(program[k - 1].primitive == "MOVETO" and program[k - 1].velocity == SLOW
                   and np.allclose(program[k - 1].location, conveyor) for k, p in enumerate(prims) if p == "GRASP")
    sol.check("every GRASP is preceded by a slow MOVETO to the object", grasp_ok, "")
    pattern = ["NEW_OBJECT", "MOVETO", "MOVETO", "GRASP", "MOVETO", "MOVETO", "MOVETO", "RELEASE", "MOVETO"]
    sol.check("per object: new object, fast above, slow down, grasp, slow up, fast above slot, slow down, release, "
              "slow up", prims[1:-1] == pattern * 16, "the manual's action sequence")

    q0 = inverse_kinematics_scara(np.array(HOME))[0]
    cell = Workcell(CONVEYOR[:3], object_mass=OBJECT_MASS)
    executor = ActionExecutor(robot, inverse_kinematics_scara, cell, q0)
    record = executor.run(program)
    sol.value("executed_steps", len(record.steps), unit="1")
    sol.value("simulated_time", float(record.t[-1]), unit="s")
    sol.check("no primitive skipped: every step executed in order", [k for k, *_ in record.steps] == list(range(len(program))),
              f"{len(record.steps)} of {len(program)} steps")
    slots = np.array([np.array(PALLET[:3]) + [i * LENGTH, j * WIDTH, 0.0] for i in range(4) for j in range(4)])
    placed = np.array([record.objects[f"object {k + 1}"] for k in range(16)])
    err = float(np.max(np.linalg.norm(placed - slots, axis=1)))
    sol.value("max_placement_error", err, unit="m")
    sol.check("every object on its pallet slot pallet + (i·length, j·width) (order i, j)", err < 1e-3,
              f"max placement error {err * 1e3:.3f} mm")
    gaps = np.linalg.norm(placed[:, None] - placed[None], axis=2) + np.eye(16)
    sol.check("all 16 slots distinct (no two objects stacked)", gaps.min() > 0.5 * min(LENGTH, WIDTH),
              f"min distance between objects {gaps.min():.3f} m")
    sol.check_close("end effector back home at the end", record.p[-1], HOME[:3], atol=1e-3,
                    reference="simulation vs prediction")
    sol.check("the gripper is empty at the end", cell.held is None, "")
    sol.animation(robot, record, "FILL_PALLET on the SCARA", speed=4.0,
                  overlays=lambda s: s.points("slots", slots, size=0.03))

    # Impossible requests stop the program naming the step.
    messages = []
    for bad in ([moveto(HOME, FAST), moveto((1.2, 0.0, 0.5, 0.0), FAST)],               # out of reach
                [moveto(HOME, FAST), moveto(CONVEYOR, SLOW), Step("GRASP")]):            # no NEW_OBJECT before
        try:
            ActionExecutor(robot, inverse_kinematics_scara, Workcell(CONVEYOR[:3]), q0).run(bad)
            messages.append("")
        except TaskError as e:
            messages.append(str(e))
    sol.value("error_unreachable", messages[0])
    sol.value("error_empty_grasp", messages[1])
    sol.check("unreachable location → TaskError naming the step", messages[0].startswith("step 1 MOVETO([1.2")
              and "unreachable" in messages[0], messages[0])
    sol.check("grasp with nothing there → TaskError naming the step", messages[1].startswith("step 2 GRASP")
              and "nothing to grasp" in messages[1], messages[1])

    fig, (ax, ax2) = subplots(1, 2, figsize=(11, 4.5))
    ax.plot(record.p[:, 0], record.p[:, 1], lw=0.6, label="end-effector path (top view)")
    ax.plot(slots[:, 0], slots[:, 1], "s", mfc="none", ms=12, color="0.5", label="pallet slots")
    ax.plot(placed[:, 0], placed[:, 1], "r.", label="objects placed")
    ax.plot(*CONVEYOR[:2], "g^", ms=10, label="conveyor")
    ax.plot(*HOME[:2], "k*", ms=10, label="home")
    ax.set_aspect("equal")
    label_axes(ax, "x₀ [m]", "y₀ [m]", legend=True, grid=False, fontsize="x-small")
    ax2.plot(record.t, record.p[:, 2])
    ax2.invert_yaxis()
    label_axes(ax2, "t [s]", "z₀ [m] (down)", legend=False)
    sol.figure(fig, "6.4 — FILL_PALLET on the simulated SCARA")
    return sol
