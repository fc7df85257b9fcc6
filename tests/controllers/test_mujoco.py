"""MujocoPlant: the book's controllers on MuJoCo physics, cross-validated against Pinocchio.

The references are independent of MuJoCo: Pinocchio's CRBA/RNEA and ABA (``inertia_matrix``,
``nonlinear_effects``, ``ArmPlant``), the compliant-plane law of :class:`ArmInContact` and its closed-form rest
k_P K/(k_P + K) δ, the Panda's fingertip geometry from its URDF, coal's exact mesh distances and collisions.

MuJoCo is an optional dependency (``pip install 'rmpc[mujoco]'``), installed by the ``test`` extra: without it
these tests skip and say how to install it — except under CI (``CI=true``), where its absence is a failure.
"""

from __future__ import annotations

import os
import sys

import numpy as np
import pinocchio as pin
import pytest

from controllers.mujoco import INSTALL, MujocoPlant, import_mujoco, mujoco_available

if not mujoco_available():
    if os.environ.get("CI", "").lower() == "true":
        raise ImportError(f"MuJoCo is missing under CI, where the test extra installs it: {INSTALL}")
    pytest.skip(f"MuJoCo is not installed: {INSTALL}", allow_module_level=True)

from controllers.environment import CompliantPlane, SteppedPlane, SurfaceWithHole  # noqa: E402
from controllers.force import HybridForceMotionControl  # noqa: E402
from controllers.joint_space import InverseDynamicsControl, PDGravityCompensation  # noqa: E402
from controllers.operational_space import OperationalInverseDynamics  # noqa: E402
from controllers.plants import ArmInContact, ArmPlant  # noqa: E402
from controllers.simulation import SimulationDiverged, simulate  # noqa: E402
from planners.collision import Box, CollisionChecker  # noqa: E402
from planners.timing import quintic_law  # noqa: E402
from rigid_body.dynamics import inertia_matrix, nonlinear_effects  # noqa: E402
from rigid_body.robots import JointFriction, load, with_payload  # noqa: E402
from rigid_body.rotations import homogeneous_transform, rot_y  # noqa: E402
from rigid_body.task_space import selection_matrices  # noqa: E402

TOOL = "panda_hand_tcp"
#: a Panda posture with the tool along +x₀ at (0.55, −0.1, 0.45) m, every joint ≥ 0.23 rad inside its limits
#: (found by solve_ik; MuJoCo enforces the limits, ArmPlant has no stops)
Q_TOOL_X = np.array([-1.2895, -0.6757, 1.0066, -2.5074, 2.6674, 2.3316, 1.72])
P_TOOL = np.array([0.55, -0.1, 0.45])
PD_KP = np.r_[100.0, 100, 100, 100, 50, 30, 10]
PD_KD = np.r_[20.0, 20, 20, 20, 5, 3, 1]


@pytest.fixture(scope="module")
def panda():
    return load("panda")


@pytest.fixture(scope="module")
def panda_plant(panda):
    return MujocoPlant(panda)


def random_configurations(robot, rng, count):
    """Configurations within the limits (clipped to ±3 rad); continuous joints as unit (cos, sin) pairs."""
    lo, hi = np.maximum(robot.lower, -3.0), np.minimum(robot.upper, 3.0)
    return [pin.randomConfiguration(robot.model, lo, hi) for _ in range(count)]


# --------------------------------------------------------------------------------------------
# The model: B(q) and the bias forces against Pinocchio's CRBA and RNEA
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["panda", "ur5", "kinova", "z1"])
def test_inertia_and_bias_forces_match_pinocchio(name, rng):
    """MuJoCo's qM and qfrc_bias of the MJCF written from the Robot = Pinocchio's CRBA and C q̇ + g (1e-8 relative)
    at random configurations and velocities (Kinova: continuous joints, one hinge angle in MuJoCo)."""
    robot = load(name)
    plant = MujocoPlant(robot, friction=None)
    for q in random_configurations(robot, rng, 25):
        qd = rng.uniform(-2.0, 2.0, robot.nv)
        B = inertia_matrix(robot, q)
        assert np.linalg.norm(plant.inertia_matrix(q) - B) <= 1e-8 * np.linalg.norm(B)
        h = nonlinear_effects(robot, q, qd)
        assert np.linalg.norm(plant.bias_forces(q, qd) - h) <= 1e-8 * np.linalg.norm(h)
    assert plant.inertia_difference < 1e-12 and plant.inertia_floor == []


def test_payload_and_locked_joints_carry_over(panda, rng):
    """The model is the Robot's, not its URDF file's: a 3 kg payload changes B(q) on both sides alike; the Panda's
    fingers are locked (7 dofs, their mass on the hand)."""
    loaded = with_payload(panda, 3.0)
    plant = MujocoPlant(loaded)
    assert plant.model.nv == 7 and plant.model.njnt == 7
    for q in random_configurations(panda, rng, 10):
        B = inertia_matrix(loaded, q)
        assert np.linalg.norm(plant.inertia_matrix(q) - B) <= 1e-8 * np.linalg.norm(B)
        assert np.linalg.norm(plant.inertia_matrix(q) - inertia_matrix(panda, q)) > 1e-3 * np.linalg.norm(B)


def test_changed_book_parameters_carry_over(rng):
    """A book robot rebuilt with other link lengths and a payload: MuJoCo's B(q) follows (point-mass/thin-rod bodies
    get the minimum principal moments MuJoCo needs, a difference of ≤ 1e-9 relative, reported)."""
    arm = load("scara", a=(0.6, 0.3), payload=1.5)
    plant = MujocoPlant(arm)
    for q in random_configurations(arm, rng, 10):
        B = inertia_matrix(arm, q)
        assert np.linalg.norm(plant.inertia_matrix(q) - B) <= 1e-8 * np.linalg.norm(B)
    assert plant.inertia_difference < 1e-8


def test_joint_data_carry_over(panda, panda_plant):
    """Limits, damping and the robot's joints first in qpos/qvel, in the robot's order."""
    mujoco = import_mujoco()
    m = panda_plant.model
    for j in range(1, panda.model.njoints):
        jid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, panda.model.names[j])
        assert m.jnt_qposadr[jid] == m.jnt_dofadr[jid] == j - 1
        assert np.allclose(m.jnt_range[jid], [panda.lower[j - 1], panda.upper[j - 1]])
    assert np.allclose(m.dof_damping, panda.friction.viscous) and np.all(m.dof_damping == 0.003)
    assert np.all(MujocoPlant(panda, friction=None).model.dof_damping == 0.0)
    assert not np.any(MujocoPlant(panda, joint_limits=False).model.jnt_limited)


def test_derivative_stage_by_stage(panda, panda_plant, rng):
    """ẋ through mj_forward = ArmPlant's (ABA with the URDF damping) at random states inside the limits without
    contact: the two simulators agree at every RK4 stage, not only at the end."""
    arm = ArmPlant(panda, friction=panda.friction)
    for q in random_configurations(panda, rng, 20):
        q = np.clip(q, panda.lower + 0.05, panda.upper - 0.05)
        x = np.r_[q, rng.uniform(-1.0, 1.0, 7)]
        if panda_plant.contact_signals(0.0, x)["self_contacts"]:
            continue
        u = rng.uniform(-20.0, 20.0, 7)
        expected = arm.derivative(0.0, x, u)
        assert np.allclose(panda_plant.derivative(0.0, x, u), expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


# --------------------------------------------------------------------------------------------
# The book's rotors
# --------------------------------------------------------------------------------------------

def test_rotors_are_refused_with_the_difference_or_modelled_as_armature():
    """The two-link arm's rotors (mimic joints): refused by default, the message naming the B(q) difference of
    the armature model; with rotors='armature' that difference is measured against Pinocchio's book B(q) and is
    exactly the coupling k_r2 I_m2 the armature model drops (b12 of Sect. 7.3.2)."""
    arm = load("planar_2r")
    with pytest.raises(ValueError, match=r"rotors on mimic joints.*rotors='armature'.*differs from the book's by up to "
                                         r"0\.\d+ %"):
        MujocoPlant(arm)
    plant = MujocoPlant(arm, rotors="armature")
    assert 1e-3 < plant.inertia_difference < 1e-2
    B_book = inertia_matrix(arm, np.array([0.3, -0.7]))
    B_mj = plant.inertia_matrix([0.3, -0.7])
    assert np.allclose(np.diag(B_mj), np.diag(B_book), rtol=1e-9)       # k_r² I_m on the diagonal: kept
    k_r2, I_m2 = 100.0, 0.01                                            # the URDF's rotor 2 (authors' param.m)
    assert B_book[0, 1] - B_mj[0, 1] == pytest.approx(k_r2 * I_m2, rel=1e-9)
    # rotors of a Cartesian arm: their coupling terms vanish, so the armature model is exact
    assert MujocoPlant(load("cartesian_skew"), rotors="armature").inertia_difference < 1e-12
    with pytest.raises(ValueError, match="vanish on this robot"):
        MujocoPlant(load("cartesian_skew"))


# --------------------------------------------------------------------------------------------
# Closed loops on both plants
# --------------------------------------------------------------------------------------------

def test_pd_gravity_panda_agrees_with_arm_plant_over_one_second(panda, panda_plant):
    """Cross-validation: PD + gravity compensation (8.51) of the Panda on MujocoPlant and on ArmPlant, the URDF's
    damping on both sides, RK4 at 1 ms: the joint paths agree to 1e-4 rad over 1 s (measured: ~1e-14). Leaving the
    damping out of ArmPlant alone breaks the agreement: the check can fail."""
    q0 = panda.configurations["ready"]
    q_d = q0 + np.array([0.3, -0.2, 0.2, 0.3, -0.3, 0.2, 0.4])
    ctrl = PDGravityCompensation(panda, PD_KP, PD_KD, q_d)
    mj = simulate(panda_plant, ctrl, (0.0, 1.0), panda_plant.initial_state(q0), h=1e-3)
    arm = ArmPlant(panda, friction=panda.friction)
    pin_run = simulate(arm, ctrl, (0.0, 1.0), arm.initial_state(q0), h=1e-3)
    assert np.abs(mj.q - pin_run.q).max() < 1e-4
    assert np.abs(mj.qd - pin_run.qd).max() < 1e-3
    assert np.abs(mj.q[-1] - q_d).max() < 0.01                         # and the loop did converge
    undamped = simulate(ArmPlant(panda), ctrl, (0.0, 1.0), arm.initial_state(q0), h=1e-3)
    assert np.abs(mj.q - undamped.q).max() > 1e-4


def test_computed_torque_tracks_a_quintic_on_the_ur5():
    """Inverse dynamics control (8.57) of the UR5 along a quintic: the same joint paths on both plants, errors tiny."""
    ur5 = load("ur5")
    q0 = ur5.configurations["home"]
    q1 = q0 + np.array([0.8, -0.4, 0.5, 0.3, -0.6, 1.0])
    s = quintic_law(0.0, 1.0, 1.0)

    def reference(t):
        a, ad, add = s(t)
        return q0 + a * (q1 - q0), ad * (q1 - q0), add * (q1 - q0)

    ctrl = InverseDynamicsControl(ur5, 400.0, 40.0, reference)
    plant = MujocoPlant(ur5)
    mj = simulate(plant, ctrl, (0.0, 1.2), plant.initial_state(q0), h=1e-3)
    arm = ArmPlant(ur5)
    ref = simulate(arm, ctrl, (0.0, 1.2), arm.initial_state(q0), h=1e-3)
    assert np.abs(mj.q - ref.q).max() < 1e-6
    assert np.abs(mj["e"]).max() < 1e-3                                # ZOH at 1 ms: tracking within 0.1 mrad


def test_operational_space_inverse_dynamics_on_the_panda(panda, panda_plant):
    """Operational-space inverse dynamics (8.114) of the Panda's tool towards a point: same run on both plants."""
    q0 = panda.configurations["ready"]
    pin.framesForwardKinematics(panda.model, panda.data, q0)
    p0 = panda.data.oMf[panda.frame_id(TOOL)].translation.copy()
    target = p0 + np.array([0.05, -0.1, -0.05])
    ctrl = OperationalInverseDynamics(panda, 400.0, 40.0, target, rows=(0, 1, 2), frame=TOOL, null_space_damping=5.0)
    mj = simulate(panda_plant, ctrl, (0.0, 1.0), panda_plant.initial_state(q0), h=1e-3)
    arm = ArmPlant(panda, friction=panda.friction)
    ref = simulate(arm, ctrl, (0.0, 1.0), arm.initial_state(q0), h=1e-3)
    assert np.abs(mj.q - ref.q).max() < 1e-6
    assert np.abs(mj["e"][-1]).max() < 1e-3


def _panda_impedance(panda, K_P, depth, stiffness):
    """Impedance control with force feedback (9.30)–(9.31): the tool (along +x₀) is driven 5 cm towards a wall at
    x₀ = 0.6 m and ``depth`` behind it in 1 s, orientation held."""
    R0, n = rot_y(np.pi / 2), np.array([-1.0, 0.0, 0.0])
    approach = quintic_law(0.0, 0.05 + depth, 1.0)

    def reference(t):
        a, ad, add = approach(t)
        v, acc = np.zeros(6), np.zeros(6)
        v[:3], acc[:3] = -ad * n, -add * n
        return homogeneous_transform(R0, P_TOOL - a * n), v, acc

    ctrl = OperationalInverseDynamics(panda, np.r_[K_P, K_P, K_P, 100.0, 100, 100], np.r_[400.0, 400, 400, 15, 15, 15],
                                      reference, frame=TOOL, orientation="quaternion",
                                      inertia=np.r_[5.0, 5, 5, 0.5, 0.5, 0.5], force_feedback=True,
                                      null_space_damping=10.0, posture=Q_TOOL_X, posture_stiffness=10.0)
    wall = CompliantPlane([0.6, 0.0, 0.45], n, stiffness, 100.0)
    return ctrl, wall, n


def test_impedance_with_a_probe_matches_the_compliant_plane(panda):
    """The point contact of Sect. 9.2 (probe=ρ): MuJoCo's wall and ArmInContact's compliant plane give the same
    steady force k_P K/(k_P + K) δ (within 0.01 %) and the same run up to MuJoCo's virtual contact mass
    (d/((1 − d) Â): a few tenths of a newton in the transient)."""
    K_P, depth, K = 1000.0, 0.02, 5000.0
    ctrl, wall, n = _panda_impedance(panda, K_P, depth, K)
    plant = MujocoPlant(panda, wall, frame=TOOL, probe=0.005)
    mj = simulate(plant, ctrl, (0.0, 2.5), plant.initial_state(Q_TOOL_X), h=1e-3)
    arm = ArmInContact(panda, wall, frame=TOOL)
    ref = simulate(arm, ctrl, (0.0, 2.5), arm.initial_state(Q_TOOL_X), h=1e-3)
    f_mj, f_pin = -(mj["h_e"][:, :3] @ n), -(ref["h_e"][:, :3] @ n)
    f_rest = K_P * K / (K_P + K) * depth
    assert f_mj[-1] == pytest.approx(f_rest, rel=1e-4) and f_pin[-1] == pytest.approx(f_rest, rel=1e-4)
    assert np.abs(f_mj - f_pin).max() < 0.05 * f_rest
    assert np.abs(mj.q - ref.q).max() < 1e-2


def test_impedance_against_a_mujoco_wall_vs_the_compliant_plane_prediction(panda):
    """Cross-validation of contact: the Panda's fingertips (URDF collision boxes, not a probe) pushed into a MuJoCo
    wall of K = 5000 N/m per contact point. The compliant-plane prediction at the equivalent stiffness — K_eq = K
    times the number of contact points MuJoCo makes (the two fingertip faces: 4 corners each), the plane where the
    fingertips' faces (from the URDF's boxes) are — is the rest k_P K_eq/(k_P + K_eq)(δ + offset), and ArmInContact
    on that plane rests at it too: the MuJoCo force agrees within 2 % (measured ~1e-5)."""
    K_P, depth, K = 1000.0, 0.02, 5000.0
    ctrl, wall, n = _panda_impedance(panda, K_P, depth, K)
    plant = MujocoPlant(panda, wall, frame=TOOL)
    mj = simulate(plant, ctrl, (0.0, 2.5), plant.initial_state(Q_TOOL_X), h=1e-3)
    f_mj = -(mj["h_e"][:, :3] @ n)
    touching = plant.contacts(mj.x[-1])
    assert {c.geom2 for c in touching} == {"panda_leftfinger_3", "panda_rightfinger_3"} and len(touching) == 8
    # how far the fingertip faces reach beyond the TCP along the tool axis, from the URDF's collision boxes
    tcp = panda.model.frames[panda.frame_id(TOOL)].placement
    reach = max((tcp.inverse() * obj.placement).act(np.array(corner))[2]
                for obj in panda.collision_model.geometryObjects if obj.name.endswith("finger_3")
                for corner in np.array(np.meshgrid(*[[-h, h] for h in obj.geometry.halfSide])).T.reshape(-1, 3))
    assert reach == pytest.approx(0.0584 + 0.04525 + 0.00925 - 0.1034, abs=1e-9)   # 9.5 mm
    K_eq = len(touching) * K
    f_pred = K_P * K_eq / (K_P + K_eq) * (depth + reach)
    assert f_mj[-1] == pytest.approx(f_pred, rel=0.02)
    # the compliant plane at the equivalent stiffness, where the fingertips touch: ArmInContact rests at the same force
    plane = CompliantPlane(wall.point + reach * n, n, K_eq, len(touching) * wall.damping)
    arm = ArmInContact(panda, plane, frame=TOOL)
    ref = simulate(arm, ctrl, (0.0, 2.5), arm.initial_state(Q_TOOL_X), h=1e-3)
    assert -(ref["h_e"][-1, :3] @ n) == pytest.approx(f_pred, rel=1e-3)
    assert f_mj[-1] == pytest.approx(-(ref["h_e"][-1, :3] @ n), rel=0.02)
    # without the fingertip offset, or at the stiffness of one contact point, the prediction misses by far more
    assert abs(K_P * K_eq / (K_P + K_eq) * depth / f_mj[-1] - 1) > 0.2
    assert abs(K_P * K / (K_P + K) * (depth + reach) / f_mj[-1] - 1) > 0.1


def test_each_compliant_contact_point_has_the_surface_stiffness(panda):
    """The calibration itself, read from MuJoCo's constraint rows at rest 3 mm inside the wall: a_ref/(r R) = K per
    contact point (MuJoCo's R f = a_ref − a), for bodies of different inverse weights Â (the fingers' bodies welded
    to the hand; the probe on the hand's body)."""
    from planners.inverse_kinematics import solve_clik
    from planners.inverse_kinematics import TaskSpace

    K = 5000.0
    wall = CompliantPlane([0.6, 0.0, 0.45], [-1.0, 0.0, 0.0], K, 100.0)
    for probe, reach in ((None, 0.0095), (0.005, 0.0)):
        plant = MujocoPlant(panda, wall, frame=TOOL, probe=probe)
        T = homogeneous_transform(rot_y(np.pi / 2), np.array([0.6 - reach + 0.003, -0.1, 0.45]))
        ik = solve_clik(panda, T, Q_TOOL_X, TaskSpace(TOOL, "axis_angle"))
        assert ik.success
        contacts = plant.contacts(plant.initial_state(ik.q))
        assert contacts and all(c.penetration == pytest.approx(0.003, abs=2e-4) for c in contacts)
        d = plant.data
        rows = [i for i in range(d.nefc) if d.efc_pos[i] < 0]
        assert len(rows) == len(contacts)
        for i in rows:
            assert d.efc_aref[i] / (-d.efc_pos[i] * d.efc_R[i]) == pytest.approx(K, rel=1e-9)
    A_hat = {b: plant.model.body_invweight0[b, 0] for b in plant.model.geom_bodyid}
    assert len(set(np.round(list(A_hat.values()), 6))) > 2               # the bodies do differ


def test_hybrid_force_motion_on_the_stepped_wall(panda):
    """Hybrid force/motion control (9.77)–(9.81) of the Panda sliding along a stepped wall (two MuJoCo boxes) with a
    probe: the force is held at 20 N, lost at the edge and regained as on ArmInContact's SteppedPlane; frictionless
    here (MuJoCo's friction cone and the regularised Coulomb law differ, see the example)."""
    import examples.panda_wall_contact as example
    from controllers.scenes import panda_wall

    scene = panda_wall()
    wall = scene.wall
    frictionless = SteppedPlane(wall.point, wall.normal, wall.direction, wall.step_at, wall.depth, wall.stiffness,
                                wall.damping)
    S_f, S_v = selection_matrices(("x", "y", "rx", "ry", "rz"), scene.R_c)
    slide = scene.slide

    def nu_reference(t):
        _, sd, sdd = slide(t)
        return np.array([sd, 0.0, 0.0, 0.0, 0.0]), np.array([sdd, 0.0, 0.0, 0.0, 0.0])

    ctrl = HybridForceMotionControl(panda, S_f, S_v, [-example.F_PUSH], nu_reference, 16.0, 100.0, 32.0, 400.0,
                                    compliance=np.eye(6) / wall.stiffness, frame=TOOL, null_space_damping=10.0)
    plant = MujocoPlant(panda, frictionless, frame=TOOL, probe=0.005, joint_limits=False)
    mj = simulate(plant, ctrl, (0.0, example.T_PANDA), plant.initial_state(scene.q0), h=1e-3)
    arm = ArmInContact(panda, frictionless, frame=TOOL)
    ref = simulate(arm, ctrl, (0.0, example.T_PANDA), arm.initial_state(scene.q0), h=1e-3)
    n, t = scene.n, mj.t
    f_mj, f_pin = -(mj["h_e"][:, :3] @ n), -(ref["h_e"][:, :3] @ n)
    cruise = (t > 1.3) & (t < 1.9)
    assert np.abs(f_mj[cruise] - example.F_PUSH).max() < 0.5
    lost_mj, lost_pin = t[(f_mj == 0) & (t > 1.0)], t[(f_pin == 0) & (t > 1.0)]
    assert abs(lost_mj[0] - lost_pin[0]) < 0.01 and abs(lost_mj[-1] - lost_pin[-1]) < 0.02
    assert f_mj[-1] == pytest.approx(example.F_PUSH, abs=0.1)


# --------------------------------------------------------------------------------------------
# Scenes, collisions, contacts
# --------------------------------------------------------------------------------------------

def test_self_collision_agrees_with_the_srdf_filtered_checker(panda, panda_plant, rng):
    """The Panda's self-contacts in MuJoCo (SRDF pairs and adjacent links excluded) = CollisionChecker's verdict
    (coal, exact meshes, the same SRDF) at random configurations: no spurious contact of overlapping link hulls."""
    from planners.collision import example_robot_srdf

    checker = CollisionChecker(panda, [], srdf=example_robot_srdf("panda"))
    colliding = 0
    for q in random_configurations(panda, rng, 200):
        mujoco_says = panda_plant.contact_signals(0.0, panda_plant.initial_state(q))["self_contacts"] > 0
        assert mujoco_says == checker.in_collision(q)
        colliding += mujoco_says
    assert 0 < colliding < 200                                         # the comparison saw both verdicts
    unfiltered = MujocoPlant(panda, srdf=None)                         # without the SRDF: more contacts
    counts = [unfiltered.contact_signals(0.0, unfiltered.initial_state(q))["self_contacts"] > 0
              for q in random_configurations(panda, np.random.default_rng(3), 200)]
    assert sum(counts) > colliding

def test_boxes_clearance_and_contacts(panda):
    """Chapter 12's boxes as MuJoCo geoms: MuJoCo's clearance = coal's (the hulls of the Panda's convex collision
    meshes), and a posture through the shelf board makes MuJoCo report contacts with it."""
    boxes = (Box([0.6, 0.0, 0.20], [0.5, 1.2, 0.04], "table"), Box([0.6, 0.0, 0.60], [0.5, 1.2, 0.03], "shelf"))
    plant = MujocoPlant(panda, boxes)
    checker = CollisionChecker(panda, boxes)
    q = panda.configurations["ready"]
    assert plant.clearance(plant.initial_state(q)) == pytest.approx(checker.box_clearance(q), abs=1e-6)
    x_table = plant.initial_state(q + np.array([0.0, 0.9, 0.0, 0.5, 0.0, 0.0, 0.0]))
    assert checker.box_clearance(x_table[:7]) < 0
    signals = plant.contact_signals(0.0, x_table)
    assert signals["scene_contacts"] > 0 and signals["penetration"] > 0
    assert any(c.geom1.startswith("scene") or c.geom2.startswith("scene") for c in plant.contacts(x_table))


def test_planar_scenes_become_boxes():
    """SurfaceWithHole (the peg-in-hole of 6.3) becomes three boxes: with a probe, the wrench MuJoCo measures at a
    tip 5 mm into the top surface, into a wall of the hole, and into its bottom is the environment's own
    (``wrench_at``: K δ along the face's normal, within 1 %: MuJoCo's virtual contact mass under gravity)."""
    from planners.inverse_kinematics import TaskSpace, solve_clik

    arm = load("planar_3r")
    hole = SurfaceWithHole(x_hole=0.7, clearance=0.004, depth=0.05)
    plant = MujocoPlant(arm, hole, probe=0.002)
    assert plant.model.ngeom - MujocoPlant(arm).model.ngeom == 3 + 1          # three blocks and the probe
    q = np.array([0.3, -0.9, -0.6])
    for tip in ([0.5, -0.005], [0.7 - 0.004 - 0.001, -0.02], [0.7, -0.055]):   # top, left wall, bottom
        T = np.eye(4)
        T[:2, 3] = tip
        ik = solve_clik(arm, T, q, TaskSpace(rows=(0, 1)))
        assert ik.success
        expected = hole.wrench_at(np.r_[tip, 0.0], np.zeros(6))
        assert np.abs(expected).max() > 10.0
        h = plant.wrench(plant.initial_state(ik.q))
        assert np.allclose(h, expected, rtol=0.01, atol=0.01 * np.abs(expected).max())


# --------------------------------------------------------------------------------------------
# Bad input
# --------------------------------------------------------------------------------------------

def test_bad_input_is_named(panda):
    with pytest.raises(ValueError, match=r"scene\[1\].*cannot represent a str"):
        MujocoPlant(panda, [Box([1, 0, 0], [0.1, 0.1, 0.1]), "wall"])
    with pytest.raises(ValueError, match="bilateral"):
        MujocoPlant(panda, CompliantPlane([0.6, 0, 0], [-1, 0, 0], 1e4, bilateral=True))
    with pytest.raises(ValueError, match="integrator"):
        MujocoPlant(panda, integrator="rk45")
    with pytest.raises(ValueError, match="rotors"):
        MujocoPlant(panda, rotors="constraint")
    with pytest.raises(ValueError, match="frictionloss.*symmetric"):
        MujocoPlant(panda, friction=JointFriction(np.zeros(7), np.ones(7), 2 * np.ones(7)))
    with pytest.raises(ValueError, match="fixed to the world"):
        MujocoPlant(panda, frame="panda_link0")
    with pytest.raises(ValueError, match="timestep.*must divide"):
        simulate(MujocoPlant(panda, timestep=3e-4), lambda t, m: np.zeros(7), (0.0, 0.01),
                 np.r_[panda.configurations["ready"], np.zeros(7)], h=1e-3)
    with pytest.raises(ValueError, match="stepped by MuJoCo.*backend='python'"):
        simulate(MujocoPlant(panda), PDGravityCompensation(panda, 100.0, 20.0, panda.configurations["ready"]),
                 (0.0, 0.01), np.r_[panda.configurations["ready"], np.zeros(7)], h=1e-3, backend="casadi")
    from rigid_body.wheeled import mobile_manipulator

    with pytest.raises(ValueError, match="Planar joint"):
        MujocoPlant(mobile_manipulator(load("planar_3r")))


def test_a_shape_mujoco_cannot_build_is_named():
    import coal

    arm = load("planar_3r")
    collision, visual = arm.collision_model.clone(), arm.visual_model
    collision.addGeometryObject(pin.GeometryObject("cone_tool", 3, arm.model.frames[arm.ee_frame].parentFrame,
                                                   pin.SE3.Identity(), coal.Cone(0.05, 0.1)))
    arm._geometry = (collision, visual)
    with pytest.raises(ValueError, match="'cone_tool' is a Cone"):
        MujocoPlant(arm)


def test_a_diverging_loop_stops_and_says_when(panda, panda_plant, tmp_path, monkeypatch):
    """MuJoCo resets a state it finds bad (silently, but for a warning): the plant raises SimulationDiverged."""
    monkeypatch.chdir(tmp_path)                 # MuJoCo writes its warning to MUJOCO_LOG.TXT in the working directory
    with pytest.raises(SimulationDiverged, match="MuJoCo found"):
        simulate(panda_plant, PDGravityCompensation(panda, 1e9, 1e7, panda.configurations["ready"]), (0.0, 0.2),
                 panda_plant.initial_state(panda.configurations["ready"] + 0.1), h=1e-3)


def test_missing_mujoco_names_the_install_command(monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)
    with pytest.raises(ImportError, match=r"pip install 'rmpc\[mujoco\]'"):
        MujocoPlant(load("planar_3r"))


def test_peg_in_hole_state_machine_on_mujoco():
    """Problem 6.3's peg-in-hole (hybrid force/motion phases, wrist force sensor) on MuJoCo: the hole's blocks as
    boxes, a 1 mm probe as the peg tip; the state machine passes through the same states as on ArmInContact, inverts
    its search once, and ends with the peg inside the hole, at nearly the same instants."""
    from controllers.force import PEG_STATES, PegInHoleController, PegInHoleTask, run_peg_in_hole
    from rigid_body.kinematics import inverse_kinematics_planar_3r

    robot = load("planar_3r")
    task = PegInHoleTask(x_H=0.6)
    hole = SurfaceWithHole(x_hole=task.x_H - 0.012, clearance=0.004, depth=0.05)
    q0 = inverse_kinematics_planar_3r(np.array([0.55, 0.15, task.phi]))[0]
    ref, ref_ctrl = run_peg_in_hole(robot, hole, task, q0, 7.0)
    plant = MujocoPlant(robot, hole, probe=0.001)
    ctrl = PegInHoleController(robot, task, stiffness=hole.stiffness)
    mj = simulate(plant, ctrl, (0.0, 7.0), plant.initial_state(q0), h=1e-3)
    assert [s for _, s in ctrl.transitions] == [s for _, s in ref_ctrl.transitions] == list(PEG_STATES)
    assert ctrl.inversions == ref_ctrl.inversions == 1
    assert np.allclose([t for t, _ in ctrl.transitions], [t for t, _ in ref_ctrl.transitions], atol=0.05)
    tip = mj["x_e"][-1]
    assert abs(tip[1] + task.insert_depth) < 1e-3 and abs(tip[0] - hole.x_hole) <= hole.clearance + 5e-4


def test_model_predictive_control_on_mujoco():
    """The MPC of controllers/mpc.py (multiple shooting on the symbolic model, SQP per sample, every 20 ms) regulating
    the UR5 within its effort limits: the same torques and joint paths on MujocoPlant as on ArmPlant."""
    from controllers.mpc import ModelPredictiveControl
    from planners.optimal_control import OptimalControlProblem, StageCost

    ur5 = load("ur5")
    q0 = ur5.configurations["home"]
    target = q0 + np.array([0.3, -0.2, 0.2, 0.1, -0.2, 0.3])
    tau_max = np.array(ur5.model.effortLimit)
    problem = OptimalControlProblem(ur5, horizon=10, dt=0.02, running=StageCost(q=1e3, qd=1.0, tau=1e-6),
                                    terminal=StageCost(q=1e4, qd=1e2), tau_max=tau_max)
    runs = []
    for plant in (MujocoPlant(ur5, tau_max=tau_max), ArmPlant(ur5, tau_max=tau_max)):
        runs.append(simulate(plant, ModelPredictiveControl(problem, reference=target), (0.0, 0.6),
                             plant.initial_state(q0), h=1e-3, Ts=0.02))
    mj, ref = runs
    assert mj["failed"].sum() == 0 and np.abs(mj.q[-1] - target).max() < 1e-3
    assert np.all(np.abs(mj.u) <= tau_max + 1e-9)
    assert np.abs(mj.q - ref.q).max() < 1e-8 and np.abs(mj.u - ref.u).max() < 1e-6 * tau_max.max()
