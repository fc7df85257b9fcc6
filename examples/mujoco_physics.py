"""Beyond the book: the book's controllers on MuJoCo physics, beside the Pinocchio runs.

The same controller objects run on :class:`controllers.mujoco.MujocoPlant` (MuJoCo steps the robot and its scene,
contacts included) and on the Pinocchio plants (:class:`~controllers.plants.ArmInContact`,
:class:`~controllers.plants.ArmPlant`: ABA integrated by the loop's RK4), and the differences are measured:

* :func:`force_control_on_mujoco` — Chapter 9 on MuJoCo: the impedance control of Problem 9.3 and the hybrid
  force/motion control of Problem 9.10, the two-link arm (its rotors as MuJoCo armature) touching the compliant plane
  of Fig. 9.16, a MuJoCo plane, with a probe at the tip (the point contact of Sect. 9.2).
* :func:`panda_wall_on_mujoco` — the Panda's impedance control pushing its fingertips (the URDF's collision boxes,
  no probe) into a MuJoCo wall: 8 contact points, and the compliant-plane prediction at that equivalent stiffness;
  and the hybrid force/motion control of :mod:`examples.panda_wall_contact` sliding along the stepped wall with
  Coulomb friction, where MuJoCo's friction cone and the compliant plane's regularised friction differ.
* :func:`planned_motion_on_mujoco` — the Panda's RRT-Connect motion out of the shelf (:mod:`examples.planning`),
  executed by computed torque on MuJoCo among the boxes: MuJoCo reports no contact and its clearance equals coal's;
  the straight line between the same postures, unplanned, hits the shelf board, and MuJoCo reports where and how hard.

Needs MuJoCo (``pip install 'rmpc[mujoco]'``). Run it from a notebook (``notebooks/mujoco_physics.ipynb``) or
``python -m examples.mujoco_physics``; each function returns a :class:`problems.registry.Solution`.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 7.3, 8.5, 9.2–9.7,
12.5; Problems 9.3, 9.10.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from controllers.environment import CompliantPlane
from controllers.force import HybridForceMotionControl
from controllers.joint_space import InverseDynamicsControl
from controllers.mujoco import MujocoPlant
from controllers.operational_space import OperationalInverseDynamics
from controllers.plants import ArmInContact, ArmPlant
from controllers.simulation import SimulationResult, simulate
from planners.paths import PathLaw, Segment
from planners.timing import quintic_law, trapezoidal_law
from controllers.scenes import PLANE_FRAME as R_C, PLANE_POINT as O_R, PLANE_STIFFNESS as K_Y, compliant_plane_9_16
from problems.ch09 import F_V, K_D_IMP, K_D_LAMBDA, K_I_NU, K_P_IMP, K_P_LAMBDA, K_P_NU, LAMBDA_D, M_D, T_C, T_D
from problems.common import label_axes, subplots
from problems.registry import Solution
from rigid_body.kinematics import ELBOW_UP, inverse_kinematics_planar_2r
from rigid_body.robots import JointFriction, Robot, load
from rigid_body.rotations import homogeneous_transform, rot_y
from rigid_body.task_space import selection_matrices

PROBE = 0.01           # radius of the tip's probe sphere [m] (the plane is moved by it: the penetration is δ)


def _both(plant_mj: MujocoPlant, plant_pin: Any, controller: Any, q0: Any, t_f: float, **kwargs: Any
          ) -> tuple[SimulationResult, SimulationResult]:
    """The same controller on MuJoCo and on the Pinocchio plant, RK4 at 1 ms on both."""
    mj = simulate(plant_mj, controller, (0.0, t_f), plant_mj.initial_state(q0), h=T_C, **kwargs)
    ref = simulate(plant_pin, controller, (0.0, t_f), plant_pin.initial_state(q0), h=T_C)
    return mj, ref


# --------------------------------------------------------------------------------------------
# Chapter 9 on MuJoCo
# --------------------------------------------------------------------------------------------

def _two_link_on_the_plane() -> tuple[Robot, CompliantPlane, MujocoPlant, ArmInContact]:
    """The two-link arm with its motors (viscous friction F_v) against the plane of Fig. 9.16, on both simulators."""
    arm = load("planar_2r")
    plane = compliant_plane_9_16()                     # Fig. 9.16 (controllers.scenes)
    friction = JointFriction(np.full(2, F_V), np.zeros(2), np.zeros(2))
    mj = MujocoPlant(arm, plane, rotors="armature", probe=PROBE, friction=friction)
    return arm, plane, mj, ArmInContact(arm, plane, viscous_friction=F_V)


def force_control_on_mujoco() -> Solution:
    """Problems 9.3 and 9.10 on MuJoCo beside Pinocchio: impedance control (9.30)–(9.31) with M_d = 100, K_D = 1600,
    K_P = 5000 along the segment of tra_5 0.1 m inside the plane, and hybrid force/motion control (9.77)–(9.84) with
    λ_d = −50 N and the stiffness estimate k̂ = 4000 N/m; the two-link arm's rotors become MuJoCo armature (B(q)
    then lacks the couplings k_r I_m: a difference measured and shown), the plane a MuJoCo plane touched by a probe.
    """
    sol = Solution(id="mujoco-ch9", title="Chapter 9 on MuJoCo: impedance (9.3) and hybrid force/motion (9.10)",
                   kind="simulation")
    arm, plane, mj_plant, pin_plant = _two_link_on_the_plane()
    sol.value("B_relative_difference", mj_plant.inertia_difference)
    sol.check("MuJoCo's B(q) with the rotors as armature: within 1 % of the book's (the k_r I_m couplings dropped)",
              mj_plant.inertia_difference < 0.01, f"max ‖ΔB‖/‖B‖ = {mj_plant.inertia_difference:.2%}")
    p_i = np.array([1.0 + 0.2 * np.cos(np.pi / 4), 0.0, 0.0])
    path = PathLaw(Segment(p_i, p_i + np.array([0.2, 0.2, 0.0])), trapezoidal_law(0.0, 0.2 * np.sqrt(2), 1.0, 0.5))
    q_i = inverse_kinematics_planar_2r(p_i[:2])[ELBOW_UP]
    impedance = OperationalInverseDynamics(arm, K_P_IMP, K_D_IMP, path, rows=(0, 1), viscous_friction=F_V, inertia=M_D,
                                           force_feedback=True)
    imp_mj, imp_pin = _both(mj_plant, pin_plant, impedance, q_i, T_D)

    def nu_reference(t: float) -> tuple[np.ndarray, np.ndarray]:
        _, pd, pdd = path(t)
        return (R_C.T @ pd[:2])[:1], (R_C.T @ pdd[:2])[:1]

    S_f, S_v = selection_matrices(("x",), R_C, axes=("x", "y"))
    C_hat = np.eye(2) / 4e3
    hybrid = HybridForceMotionControl(arm, S_f, S_v, [LAMBDA_D], nu_reference, K_P_NU, K_I_NU, K_D_LAMBDA, K_P_LAMBDA,
                                      compliance=C_hat, stiffness=np.linalg.inv(C_hat),
                                      compliance_prime=R_C @ np.diag([0.0, 1.0 / 4e3]) @ R_C.T, rows=(0, 1),
                                      viscous_friction=F_V)
    hyb_mj, hyb_pin = _both(mj_plant, pin_plant, hybrid, inverse_kinematics_planar_2r(O_R)[ELBOW_UP], T_D)

    f_y = {name: r["h_e"][:, :2] @ R_C[:, 1] for name, r in (("MuJoCo", imp_mj), ("Pinocchio", imp_pin))}
    f_rest = K_Y * K_P_IMP / (K_P_IMP + K_Y) * (-0.1)          # k_y k_P/(k_P + k_y)(y_d − y_r), −250 N
    sol.value("impedance_force_final_mujoco", float(f_y["MuJoCo"][-1]))
    sol.check_close("9.3 on MuJoCo: f_y^c(t_d) = k_y k_P/(k_P + k_y)(y_d − y_r) [N]", f_y["MuJoCo"][-1], f_rest,
                    rtol=1e-3, reference="closed form")
    gap = float(np.abs(f_y["MuJoCo"] - f_y["Pinocchio"]).max())
    sol.value("impedance_force_max_difference", gap)
    sol.check("9.3: MuJoCo's force within 1 % of Pinocchio's (of the initial 500 N) all along", gap < 5.0,
              f"max |Δf| = {gap:.3f} N: MuJoCo's virtual contact mass d/((1−d)Â) and the rotors' couplings")
    lam = {name: r["lam"][:, 0] for name, r in (("MuJoCo", hyb_mj), ("Pinocchio", hyb_pin))}
    sol.value("hybrid_force_final_mujoco", float(lam["MuJoCo"][-1]))
    sol.check_close("9.10 on MuJoCo: λ(t_d) = λ_d [N]", lam["MuJoCo"][-1], LAMBDA_D, atol=0.5,
                    reference="simulation vs prediction")
    sol.value("hybrid_force_max_difference", float(np.abs(lam["MuJoCo"] - lam["Pinocchio"]).max()))
    sol.value("joint_path_max_difference", float(max(np.abs(imp_mj.q - imp_pin.q).max(),
                                                     np.abs(hyb_mj.q - hyb_pin.q).max())))

    fig, axes = subplots(1, 2, figsize=(11, 4))
    for name, style in (("MuJoCo", "C0-"), ("Pinocchio", "C1--")):
        axes[0].plot(imp_mj.t, f_y[name], style, label=name)
        axes[1].plot(hyb_mj.t, lam[name], style, label=name)
    axes[0].axhline(f_rest, color="k", ls=":", lw=1, label="k_y k_P/(k_P + k_y)(y_d − y_r)")
    axes[1].axhline(LAMBDA_D, color="k", ls=":", lw=1, label="λ_d")
    label_axes(axes[0], "t [s]", "f along y_c [N]", title="9.3 impedance control")
    label_axes(axes[1], "t [s]", "λ [N]", title="9.10 hybrid force/motion control")
    sol.figure(fig, "Chapter 9 on MuJoCo (probe on the plane) and on Pinocchio (compliant plane)")
    return sol


# --------------------------------------------------------------------------------------------
# The Panda on a MuJoCo wall
# --------------------------------------------------------------------------------------------

TOOL = "panda_hand_tcp"
#: the tool along +x₀ at (0.55, −0.1, 0.45) m, every joint ≥ 0.23 rad inside its limits (MuJoCo enforces them)
Q_TOOL_X = np.array([-1.2895, -0.6757, 1.0066, -2.5074, 2.6674, 2.3316, 1.72])


def _fingertip_reach(panda: Robot) -> float:
    """How far the fingertips' collision boxes reach beyond the tool frame along its z axis [m] (the URDF's boxes)."""
    tcp = panda.model.frames[panda.frame_id(TOOL)].placement.inverse()
    corners = []
    for obj in panda.collision_model.geometryObjects:
        if type(obj.geometry).__name__ == "Box":
            half = np.asarray(obj.geometry.halfSide)
            for signs in np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).T.reshape(-1, 3):
                corners.append((tcp * obj.placement).act(signs * half)[2])
    return float(max(corners))


def panda_wall_on_mujoco() -> Solution:
    """The Panda's tool (pointing along +x₀) driven 2 cm behind a wall (K = 5000 N/m per contact point, D = 100 N·s/m)
    by impedance control (9.30)–(9.31), K_P = 1000 N/m: on MuJoCo the fingertip boxes of the URDF touch it (two faces,
    8 contact points); the compliant-plane prediction at the equivalent stiffness 8K, moved to where the fingertips
    reach, is the rest k_P K_eq/(k_P + K_eq)(δ + reach), which ArmInContact on that plane reproduces. Then the hybrid
    force/motion control of ``examples.panda_wall_contact`` on its stepped wall with friction μ = 0.3, a probe at the
    tool.
    """
    import examples.panda_wall_contact as wall_example
    from controllers.scenes import WALL_FRICTION, panda_wall

    sol = Solution(id="mujoco-panda-wall", title="The Panda on a MuJoCo wall: fingertip contacts, friction cone",
                   kind="simulation")
    panda = load("panda")
    n, K, D, K_P, depth = np.array([-1.0, 0.0, 0.0]), 5000.0, 100.0, 1000.0, 0.02
    wall = CompliantPlane([0.6, 0.0, 0.45], n, K, D)
    R0, p0 = rot_y(np.pi / 2), np.array([0.55, -0.1, 0.45])
    approach = quintic_law(0.0, 0.05 + depth, 1.0)

    def reference(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        a, ad, add = approach(t)
        v, acc = np.zeros(6), np.zeros(6)
        v[:3], acc[:3] = -ad * n, -add * n
        return homogeneous_transform(R0, p0 - a * n), v, acc

    impedance = OperationalInverseDynamics(panda, np.r_[K_P, K_P, K_P, 100.0, 100.0, 100.0],
                                           np.r_[400.0, 400.0, 400.0, 15.0, 15.0, 15.0], reference, frame=TOOL,
                                           orientation="quaternion", inertia=np.r_[5.0, 5.0, 5.0, 0.5, 0.5, 0.5],
                                           force_feedback=True, null_space_damping=10.0, posture=Q_TOOL_X,
                                           posture_stiffness=10.0)
    mj_plant = MujocoPlant(panda, wall, frame=TOOL)
    imp_mj = simulate(mj_plant, impedance, (0.0, 2.5), mj_plant.initial_state(Q_TOOL_X), h=T_C,
                      log=mj_plant.contact_signals)
    touching = mj_plant.contacts(imp_mj.x[-1])
    reach = _fingertip_reach(panda)
    K_eq = len(touching) * K
    f_pred = K_P * K_eq / (K_P + K_eq) * (depth + reach)
    equivalent = ArmInContact(panda, CompliantPlane(wall.point + reach * n, n, K_eq, len(touching) * D), frame=TOOL)
    imp_pin = simulate(equivalent, impedance, (0.0, 2.5), equivalent.initial_state(Q_TOOL_X), h=T_C)
    f_imp = {"MuJoCo": -(imp_mj["h_e"][:, :3] @ n), "Pinocchio": -(imp_pin["h_e"][:, :3] @ n)}
    sol.value("contact_points", len(touching))
    sol.value("fingertip_reach", reach)
    sol.value("impedance_force_final", {k: float(v[-1]) for k, v in f_imp.items()})
    sol.check("MuJoCo reports the two fingertip faces on the wall, 4 corners each",
              len(touching) == 8 and {c.geom2 for c in touching} == {"panda_leftfinger_3", "panda_rightfinger_3"},
              ", ".join(sorted({c.geom2 for c in touching})) + f": {len(touching)} points")
    sol.check("impedance on MuJoCo rests at the compliant-plane prediction k_P K_eq/(k_P + K_eq)(δ + reach), K_eq = 8K "
              "(within 2 %)", abs(f_imp["MuJoCo"][-1] / f_pred - 1) < 0.02,
              f"{f_imp['MuJoCo'][-1]:.4f} N vs {f_pred:.4f} N (K_eq = {K_eq:g} N/m, reach {reach * 1e3:.2f} mm)")

    scene = panda_wall()
    stepped = scene.wall
    S_f, S_v = selection_matrices(("x", "y", "rx", "ry", "rz"), scene.R_c)
    slide = scene.slide

    def nu_reference(t: float) -> tuple[np.ndarray, np.ndarray]:
        _, sd, sdd = slide(t)
        return np.array([sd, 0.0, 0.0, 0.0, 0.0]), np.array([sdd, 0.0, 0.0, 0.0, 0.0])

    hybrid = HybridForceMotionControl(panda, S_f, S_v, [-wall_example.F_PUSH], nu_reference, 16.0, 100.0, 32.0, 400.0,
                                      compliance=np.eye(6) / stepped.stiffness, frame=TOOL, null_space_damping=10.0)
    # the CLIK start posture has joint 5 on its limit: MuJoCo's limits are left out, as ArmInContact has none
    hyb_mj, hyb_pin = _both(MujocoPlant(panda, stepped, frame=TOOL, probe=0.005, joint_limits=False),
                            ArmInContact(panda, stepped, frame=TOOL), hybrid, scene.q0, wall_example.T_PANDA)
    n_s, t = scene.n, hyb_mj.t
    f_hyb = {"MuJoCo": -(hyb_mj["h_e"][:, :3] @ n_s), "Pinocchio": -(hyb_pin["h_e"][:, :3] @ n_s)}
    cruise = (t > 1.3) & (t < 1.9)
    tangential = {k: r["h_e"][cruise, :3] - np.outer(r["h_e"][cruise, :3] @ n_s, n_s)
                  for k, r in (("MuJoCo", hyb_mj), ("Pinocchio", hyb_pin))}
    friction = {k: float(np.linalg.norm(h_t, axis=1).mean()) for k, h_t in tangential.items()}
    normal = {k: float(v[cruise].mean()) for k, v in f_hyb.items()}
    sol.value("hybrid_sliding_normal_force", normal)
    sol.value("hybrid_sliding_friction_force", friction)
    sol.check("sliding: friction = μ f_n on both (MuJoCo's cone edge, the regularised Coulomb law)",
              all(abs(friction[k] / (WALL_FRICTION * normal[k]) - 1) < 0.02 for k in friction),
              ", ".join(f"{k}: {friction[k]:.3f} N / {normal[k]:.3f} N" for k in friction))
    sol.check("sliding: MuJoCo's normal force exceeds the 20 N held on the compliant plane by < 10 % (its soft "
              "friction cone turns part of the tangential push into normal force)",
              0 < normal["MuJoCo"] - normal["Pinocchio"] < 2.0,
              f"{normal['MuJoCo']:.3f} N vs {normal['Pinocchio']:.3f} N")
    lost = {k: t[(v == 0.0) & (t > 1.0)] for k, v in f_hyb.items()}
    sol.value("hybrid_contact_lost_regained", {k: (float(v[0]), float(v[-1])) for k, v in lost.items()})
    sol.check("contact lost at the edge (±20 ms) and regained within 60 ms of each other (MuJoCo presses harder "
              "while sliding, so the tool springs back further at the edge)",
              abs(lost["MuJoCo"][0] - lost["Pinocchio"][0]) < 0.02
              and abs(lost["MuJoCo"][-1] - lost["Pinocchio"][-1]) < 0.06,
              ", ".join(f"{k}: {v[0]:.3f}–{v[-1]:.3f} s" for k, v in lost.items()))

    fig, axes = subplots(1, 2, figsize=(11, 4))
    for name, style in (("MuJoCo", "C0-"), ("Pinocchio", "C1--")):
        axes[0].plot(imp_mj.t, f_imp[name], style, label=name + (" (8 fingertip points)" if name == "MuJoCo"
                                                                  else " (plane at K_eq = 8K)"))
        axes[1].plot(t, f_hyb[name], style, label=name)
    axes[0].axhline(f_pred, color="k", ls=":", lw=1, label="k_P K_eq/(k_P + K_eq)(δ + reach)")
    axes[1].axhline(wall_example.F_PUSH, color="k", ls=":", lw=1, label="20 N")
    label_axes(axes[0], "t [s]", "force on the wall [N]", title="impedance, fingertips on the wall")
    label_axes(axes[1], "t [s]", "force on the wall [N]", title="hybrid, stepped wall with friction")
    sol.figure(fig, "The Panda on a MuJoCo wall beside the compliant-plane runs")
    return sol


# --------------------------------------------------------------------------------------------
# A planned motion among boxes
# --------------------------------------------------------------------------------------------

def planned_motion_on_mujoco(seed: int = 1) -> Solution:
    """The Panda's RRT-Connect motion out of the shelf (certified, shortcut, time-optimal, re-checked) tracked by
    computed torque (8.57), K_P = 400, K_D = 40, on MuJoCo among the boxes and on ArmPlant; then the straight line
    between the same postures (a quintic in 3 s), which the planner would not accept, on MuJoCo."""
    from controllers.scenes import panda_shelf
    from examples.planning import plan_and_time

    sol = Solution(id="mujoco-plan", title="A planned Panda motion executed on MuJoCo among the boxes",
                   kind="simulation")
    scenario = panda_shelf()
    panda, boxes = scenario.robot, scenario.boxes
    law = plan_and_time(scenario, "rrt_connect", seed).motion     # time-optimal along the certified path
    ctrl = InverseDynamicsControl(panda, 400.0, 40.0, law, viscous_friction=panda.friction.viscous)
    mj_plant = MujocoPlant(panda, boxes)
    run, ref = _both(mj_plant, ArmPlant(panda, friction=panda.friction), ctrl, scenario.q_start, law.t_f + 0.5,
                     log=mj_plant.contact_signals)
    every = 50
    clearance_mj = np.array([mj_plant.clearance(x) for x in run.x[::every]])
    clearance_coal = np.array([scenario.space.checker.box_clearance(q) for q in run.q[::every]])
    sol.value("contacts_along_the_plan", float(run["scene_contacts"].max() + run["self_contacts"].max()))
    sol.value("min_clearance_mujoco", float(clearance_mj.min()))
    sol.check("MuJoCo reports no contact along the planned motion (robot–box or self)",
              run["scene_contacts"].max() == 0 and run["self_contacts"].max() == 0,
              f"max penetration {run['penetration'].max():.1e} m")
    excess = clearance_coal - clearance_mj
    sol.check("MuJoCo's clearance to the boxes ≤ coal's (to 1 µm) and within 0.5 mm of it (MuJoCo collides the "
              "convex hull of each collision mesh, coal the mesh itself)",
              bool(np.all(excess >= -1e-6) and excess.max() < 5e-4),
              f"coal − MuJoCo ∈ [{excess.min():.1e}, {excess.max():.1e}] m; "
              f"min clearance {clearance_mj.min() * 1e3:.2f} mm")
    gap = float(np.abs(run.q - ref.q).max())
    sol.value("joint_path_max_difference", gap)
    sol.check("the same joint path on MuJoCo and ArmPlant (1e-6 rad)", gap < 1e-6, f"max |Δq| = {gap:.1e} rad")

    straight = quintic_law(0.0, 1.0, 3.0)
    dq = scenario.q_goal - scenario.q_start

    def line(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        s, sd, sdd = straight(t)
        return scenario.q_start + s * dq, sd * dq, sdd * dq

    unplanned = InverseDynamicsControl(panda, 400.0, 40.0, line, viscous_friction=panda.friction.viscous)
    blocked = simulate(mj_plant, unplanned, (0.0, 3.5), mj_plant.initial_state(scenario.q_start), h=T_C,
                       log=mj_plant.contact_signals)
    hit = int(np.argmax(blocked["scene_contacts"] > 0))
    touching = mj_plant.contacts(blocked.x[hit + 50])
    sol.value("straight_line_first_contact", float(blocked.t[hit]))
    sol.check("the unplanned straight line hits a box and MuJoCo reports it",
              blocked["scene_contacts"].max() > 0 and bool(touching),
              f"first contact at {blocked.t[hit]:.3f} s: "
              + ", ".join(sorted({f'{c.geom1}–{c.geom2}' for c in touching}))
              + f"; contact force {max(np.linalg.norm(c.force) for c in touching):.0f} N")

    fig, axes = subplots(2, 1, figsize=(8, 6), sharex=True)
    axes[0].plot(run.t[::every], clearance_mj * 1e3, "C0-", label="MuJoCo (mj_geomDistance)")
    axes[0].plot(run.t[::every], clearance_coal * 1e3, "C1--", label="coal (planner's checker)")
    label_axes(axes[0], None, "clearance to the boxes [mm]", title="planned motion")
    axes[1].plot(blocked.t, blocked["scene_contacts"], "C3-", label="MuJoCo contacts (straight line)")
    axes[1].plot(run.t, run["scene_contacts"], "C0-", label="MuJoCo contacts (planned)")
    label_axes(axes[1], "t [s]", "robot–box contacts [–]")
    sol.figure(fig, "The planned motion and the straight line on MuJoCo among the shelf's boxes")
    return sol


def mujoco_demo() -> list[Solution]:
    """The three demonstrations."""
    return [force_control_on_mujoco(), panda_wall_on_mujoco(), planned_motion_on_mujoco()]


if __name__ == "__main__":  # pragma: no cover
    for result in mujoco_demo():
        print(result.title)
        for c in result.checks:
            print(f"  [{'PASS' if c.passed else 'FAIL'}] {c.name}: {c.detail}")
