"""Scenes: a robot, its surroundings and a start, as the book's figures and the demos beyond it set them up.

The problems (``problems/``), the examples, the benchmarks and the notebooks build their runs on these, so a
scene is written once and a user can start from it (``rmpc.scenes``):

Force control (Ch. 9)
    :func:`compliant_plane_9_16` — the compliant plane of Fig. 9.16 (through o_r = [1, 0] m at π/4, k = 5·10³ N/m)
    for the two-link arm; :func:`panda_wall` — the Panda's tool 1 cm from a vertical wall that steps back by 1 cm
    (a :class:`PandaWall`: robot, start posture, wall, constraint frame, slide).
Visual servoing (Ch. 10)
    :func:`scara_eye_in_hand` — the eye-in-hand SCARA of Example 10.3 with its target (:data:`SCARA_TARGET_POSE`,
    :data:`SCARA_TARGET_POINTS`, :data:`SCARA_DESIRED_POSE`, :data:`SCARA_Q0`); :func:`scara_pbvs` and
    :func:`scara_ibvs` — the loops of Problems 10.8–10.11 as keyword arguments of ``simulate``;
    :func:`panda_camera_target` — a 0.2 m square 0.5 m below the Panda's hand camera (a :class:`CameraTarget`).
Motion planning (Ch. 12)
    :func:`scene_12_7` (two-link arm among discs and a square), :func:`scene_12_8` (a triangular unicycle),
    :func:`grid_12_13` (the occupancy grid of 12.13); :func:`panda_shelf` and :func:`anthropomorphic_pillar` —
    URDF arms among boxes with a planning query (a :class:`Scenario`).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Fig. 9.16,
Example 10.3, Sect. 12.5; the authors' companion files i9_3, i10_8, s12_7, s12_8, s12_13.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Callable

import numpy as np

from controllers.environment import CompliantPlane, SteppedPlane
from controllers.plants import ArmPlant, KinematicArm
from controllers.visual_servoing import (EyeInHandCamera, IBVSPDGravity, IBVSResolvedVelocity, PBVSPDGravity,
                                         PBVSResolvedVelocity, PoseEstimator, TargetFeatures, planar_pose,
                                         visual_servo)
from planners.collision import Box, CollisionChecker, UrdfCSpace, example_robot_srdf
from planners.configuration_space import Disc, PlanarArm, PlanarBody, PlanarCSpace, Polygon, Scene, box
from planners.inverse_kinematics import solve_clik
from planners.timing import quintic_law
from rigid_body.book_robots import book_robot_spec
from rigid_body.dh import G, DHLink
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import Robot, load, robot_from_dh
from rigid_body.rotations import homogeneous_transform, rot_y
from rigid_body.task_space import TaskSpace

__all__ = ["PLANE_POINT", "PLANE_FRAME", "PLANE_STIFFNESS", "compliant_plane_9_16",
           "PandaWall", "panda_wall", "WALL_STIFFNESS", "WALL_DAMPING", "WALL_FRICTION", "SLIP_VELOCITY",
           "SLIDE", "STEP_AT", "STEP_DEPTH", "PANDA_TOOL",
           "scara_eye_in_hand", "SCARA_TARGET_POSE", "SCARA_TARGET_POINTS", "SCARA_DESIRED_POSE", "SCARA_Q0",
           "scara_target_points", "scara_pbvs", "scara_ibvs", "CameraTarget", "panda_camera_target",
           "scene_12_7", "scene_12_8", "grid_12_13", "Scenario", "panda_shelf", "anthropomorphic_pillar"]


# --------------------------------------------------------------------------------------------
# Chapter 9: contact
# --------------------------------------------------------------------------------------------

PLANE_POINT = np.array([1.0, 0.0])                                 # o_r, a point of the undeformed plane [m]
PLANE_FRAME = np.array([[1.0, -1.0], [1.0, 1.0]]) / np.sqrt(2.0)   # R_c: x_c along the plane, y_c its outward normal
PLANE_STIFFNESS = 5e3                                               # k_y along the normal [N/m] (companion i9_3)


def compliant_plane_9_16(stiffness: float = PLANE_STIFFNESS) -> CompliantPlane:
    """The compliant plane of Fig. 9.16 (companion i9_3) for the two-link arm of Sect. 7.3.2: through
    o_r = [1, 0] m at π/4 to x₀, outward normal y_c (:data:`PLANE_FRAME`'s second column), stiffness k_y
    [N/m] along it and none along x_c; unilateral (it only pushes)."""
    return CompliantPlane(np.r_[PLANE_POINT, 0.0], np.r_[PLANE_FRAME[:, 1], 0.0], stiffness)


PANDA_TOOL = "panda_hand_tcp"
WALL_STIFFNESS, WALL_DAMPING, WALL_FRICTION = 2e4, 200.0, 0.3   # [N/m], [N·s/m], Coulomb μ
SLIP_VELOCITY = 0.01        # friction regularisation [m/s]: below it friction is a damper μN/v_s, which must
                            # stay non-stiff for RK4 at 1 ms on the tool's few-kg task-space inertia
SLIDE, STEP_AT, STEP_DEPTH = 0.2, 0.1, 0.01   # sliding length, edge along the slide, recess depth [m]


@dataclass
class PandaWall:
    """The Panda at a wall (:func:`panda_wall`): ``panda``, its start posture ``q0`` (the tool ``PANDA_TOOL`` at
    ``p0`` [m] with orientation ``R0``), the wall (a :class:`controllers.environment.SteppedPlane`) with outward
    normal ``n`` and slide direction ``t1``, the constraint frame ``R_c`` (x_c along the slide, z_c = n) and the
    slide ``s(t)`` along t1 (a quintic of :data:`SLIDE` m over 1–3 s: t → (s, ṡ, s̈))."""

    panda: Robot
    q0: np.ndarray
    R0: np.ndarray
    p0: np.ndarray
    n: np.ndarray
    t1: np.ndarray
    wall: SteppedPlane
    R_c: np.ndarray
    slide: Callable[[float], tuple]
    tool: str = PANDA_TOOL

    def __repr__(self) -> str:
        return (f"PandaWall(tool {self.tool!r} at {np.round(self.p0, 3).tolist()} m, wall x = {self.wall.point[0]:g} m, "
                f"k = {WALL_STIFFNESS:g} N/m, μ = {WALL_FRICTION:g}, step {STEP_DEPTH * 100:g} cm at {STEP_AT:g} m)")


def panda_wall() -> PandaWall:
    """The Panda's tool (``panda_hand_tcp``) pointing along +x₀ at p₀ = [0.59, −0.1, 0.45] m, 1 cm from a wall at
    x₀ = 0.6 m (outward normal n = −x₀; k = 2·10⁴ N/m, d = 200 N·s/m, Coulomb μ = 0.3) that steps back by 1 cm
    0.1 m further along +y₀. The start posture is found by CLIK from Franka's ``ready``."""
    panda = load("panda")
    R0, p0 = rot_y(np.pi / 2), np.array([0.59, -0.1, 0.45])
    ik = solve_clik(panda, homogeneous_transform(R0, p0), panda.configurations["ready"],
                    TaskSpace(PANDA_TOOL, "axis_angle"))
    if not ik.success:
        raise RuntimeError(f"no Panda posture at the start pose: {ik.message}")
    n, t1 = np.array([-1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    wall = SteppedPlane([0.6, p0[1], p0[2]], n, t1, STEP_AT, STEP_DEPTH, WALL_STIFFNESS, WALL_DAMPING,
                        friction=WALL_FRICTION, slip_velocity=SLIP_VELOCITY)
    R_c = np.column_stack([t1, np.cross(n, t1), n])       # x_c along the slide, z_c the wall's outward normal
    return PandaWall(panda, ik.q, R0, p0, n, t1, wall, R_c, quintic_law(0.0, SLIDE, 3.0, t_i=1.0))


# --------------------------------------------------------------------------------------------
# Chapter 10: cameras on arms
# --------------------------------------------------------------------------------------------

SCARA_TARGET_POSE = np.array([1.0, 1.0, 1.0, np.pi / 4])      # x_o = [x, y, z, φ] of the object (companion i10_8)
SCARA_DESIRED_POSE = np.array([-0.1, 0.1, 0.6, -np.pi / 3])   # x_{d,o}: the object seen from the desired camera pose
SCARA_TARGET_POINTS = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0]])   # feature points P₁, P₂ in the object frame [m]
SCARA_Q0 = np.array([np.pi / 2, -np.pi / 2, 0.5, np.pi / 4])  # start: the camera at x_c(0) = [1, 1, 0.5, π/4]
SCARA_FRICTION = np.array([100.0, 100.0, 0.0, 0.0])           # K_r diag(0.01, 0.01, 0, 0) K_r [N·m·s/rad]
SCARA_ESTIMATOR_GAIN, SCARA_ESTIMATOR_PERIOD = 160.0, 1e-3     # K_s = 160 I₄, Euler at 1 ms (10.8, 10.9)
SCARA_DURATION, SCARA_STEP = 8.0, 1e-3                         # t_d [s], the arm's integration step [s]


@lru_cache(maxsize=1)
def scara_eye_in_hand() -> Robot:
    """The eye-in-hand SCARA of Example 10.3: the SCARA of Table S2.3 with a₁ = a₂ = 1 m, links 1–2 of the two-link
    arm (Sect. 7.3.2, with motors), the last link m₃ = 2 kg, I₄ = 1 kg·m² (its motors negligible), z₀ down
    (gravity +g z₀); the camera frame is the end-effector frame ``ee`` (its z the optical axis, along z₀)."""
    two_link = book_robot_spec("planar_2r").links
    links = two_link + (DHLink(joint="prismatic", lower=0.0, upper=1.0),
                        DHLink(mass=2.0, inertia=np.diag([1.0, 1.0, 1.0])))
    return robot_from_dh(links, gravity=(0.0, 0.0, G), name="scara_eye_in_hand")


def scara_target_points() -> np.ndarray:
    """P₁, P₂ of the target in the base frame [m] (:data:`SCARA_TARGET_POINTS` placed at :data:`SCARA_TARGET_POSE`)."""
    T_bo = planar_pose(SCARA_TARGET_POSE)
    return SCARA_TARGET_POINTS @ T_bo[:3, :3].T + T_bo[:3, 3]


def scara_pbvs(Tc: float, K_P: Any = None, K_D: Any = None, K: Any = None) -> dict:
    """The keyword arguments of ``simulate`` for PBVS on the eye-in-hand SCARA (Problems 10.8, 10.9): camera →
    pose estimator at 1 ms (10.40)–(10.41) → PD + gravity law (gains ``K_P``, ``K_D``, Fig. 10.14) on the arm's
    dynamics, or the resolved-velocity law (gain ``K``, Fig. 10.15) on the kinematic arm, held over ``Tc`` [s]."""
    robot = scara_eye_in_hand()
    camera = EyeInHandCamera(robot, scara_target_points())
    estimator = PoseEstimator(TargetFeatures(SCARA_TARGET_POINTS, "segment"), SCARA_DESIRED_POSE,
                              SCARA_ESTIMATOR_GAIN, SCARA_ESTIMATOR_PERIOD)
    if K is None:
        plant, law = ArmPlant(robot, viscous_friction=SCARA_FRICTION), PBVSPDGravity(robot, SCARA_DESIRED_POSE, K_P, K_D)
        x0 = plant.initial_state(SCARA_Q0)
    else:
        plant, law, x0 = KinematicArm(), PBVSResolvedVelocity(robot, SCARA_DESIRED_POSE, K), SCARA_Q0
    return dict(plant=plant, controller=visual_servo(camera, law, Tc, estimator), t_span=(0.0, SCARA_DURATION),
                x0=x0, h=SCARA_STEP, Ts=SCARA_ESTIMATOR_PERIOD)


def scara_ibvs(Tc: float, kind: str, K_Ps: Any = None, K_Ds: Any = None, K_s: Any = None,
               depth: Any = SCARA_DESIRED_POSE[2]) -> dict:
    """The keyword arguments of ``simulate`` for IBVS on the eye-in-hand SCARA (Problems 10.10, 10.11): PD + gravity
    (gains ``K_Ps``, ``K_Ds``, Fig. 10.16) or resolved velocity (gain ``K_s``, Fig. 10.17) with ``kind`` = "segment"
    or "points" features, L̂_s = L_s(s, ẑ): ẑ = z_d = 0.6 m (the manual's), or another ``depth`` of the IBVS laws
    (None: the true depth, or an estimator)."""
    robot = scara_eye_in_hand()
    camera = EyeInHandCamera(robot, scara_target_points())
    target = TargetFeatures(SCARA_TARGET_POINTS, kind)
    s_d = target.features(target.view_from_pose(planar_pose(SCARA_DESIRED_POSE)).xy)
    if K_s is None:
        plant = ArmPlant(robot, viscous_friction=SCARA_FRICTION)
        law, x0 = IBVSPDGravity(robot, target, s_d, K_Ps, K_Ds, depth=depth), plant.initial_state(SCARA_Q0)
    else:
        plant, law, x0 = KinematicArm(), IBVSResolvedVelocity(robot, target, s_d, K_s, depth=depth), SCARA_Q0
    h = Tc if K_s is not None else SCARA_STEP          # q̇ = u held over T_c: one RK4 step is exact
    return dict(plant=plant, controller=visual_servo(camera, law, Tc), t_span=(0.0, SCARA_DURATION), x0=x0, h=h, Ts=Tc)


@dataclass(frozen=True)
class CameraTarget:
    """A camera on ``frame`` of ``robot`` above a planar target (:func:`panda_camera_target`): the target's points
    ``points_b`` (n, 3, base frame), the desired camera pose ``T_d`` (4×4) that sees them from ``depth`` [m], and the
    joints ``q_d`` that place the camera there."""

    robot: Robot
    frame: str
    points_b: np.ndarray
    q_d: np.ndarray
    T_d: np.ndarray
    depth: float

    def start(self, angle: float, offset_c: Any) -> np.ndarray:
        """Joints placing the camera at T_d · (rotation ``angle`` [rad] about z_c, translation ``offset_c`` [m] in the
        camera frame): CLIK from q_d with the last joint seeded by ±angle; ValueError when unreachable within limits."""
        T = np.eye(4)
        T[:3, :3] = homogeneous_transform(_rot_z(angle), np.zeros(3))[:3, :3]
        T[:3, 3] = offset_c
        last = self.robot.nq - 1
        for sign in (1.0, -1.0):                            # the last joint turns the hand about z_c
            guess = self.q_d.copy()
            guess[last] += sign * angle
            if self.robot.lower[last] <= guess[last] <= self.robot.upper[last]:
                ik = solve_clik(self.robot, self.T_d @ T, guess, TaskSpace(self.frame))
                if ik.success:
                    return ik.q
        raise ValueError(f"start pose (angle {angle}, offset {offset_c}) unreachable within the joint limits")


def _rot_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def panda_camera_target(side: float = 0.2, depth: float = 0.5,
                        q_d: Any = (0.0, -0.3, 0.0, -2.2, 0.0, 1.9, np.pi / 4)) -> CameraTarget:
    """A camera on the Panda's hand (``panda_hand``: z the approach axis, the optical axis) at the joints ``q_d``
    (default: the hand over the table, pointing down), and four points at the corners of a square of ``side`` [m]
    facing it at ``depth`` [m] along the optical axis: what the camera must see again (IBVS, PBVS, 2½-D)."""
    robot = load("panda")
    q_d = np.asarray(q_d, dtype=float)
    T_d = direct_kinematics(robot, q_d, "panda_hand")
    centre = T_d[:3, 3] + depth * T_d[:3, 2]
    h = side / 2
    corners = np.array([[-h, -h, 0.0], [h, -h, 0.0], [h, h, 0.0], [-h, h, 0.0]])
    return CameraTarget(robot, "panda_hand", centre + corners @ T_d[:3, :3].T, q_d.copy(), T_d, float(depth))


# --------------------------------------------------------------------------------------------
# Chapter 12: planning scenes
# --------------------------------------------------------------------------------------------

def scene_12_7() -> tuple[PlanarCSpace, np.ndarray, np.ndarray]:
    """Companion s12_7: 2R arm (links 1 m × 0.1 m + joint discs), four discs and a square; q_s, q_g [rad]."""
    obstacles = [Disc([-0.8, 1.2], 0.2), Disc([-1.2, -0.9], 0.3), Disc([1.3, 1.5], 0.2), Disc([-1.2, 0.9], 0.3),
                 Polygon([[0, 0.5], [0.5, 0.5], [0.5, 1], [0, 1]])]
    space = PlanarCSpace(PlanarArm((1.0, 1.0), 0.1), Scene(obstacles, (-2.2, 2.2, -2.2, 2.2)),
                         [-np.pi, -np.pi], [np.pi, np.pi], resolution=0.01)
    return space, np.array([-np.pi / 4, 3 * np.pi / 4]), np.array([5 * np.pi / 8, -np.pi / 2])


def scene_12_8() -> tuple[PlanarCSpace, np.ndarray, np.ndarray]:
    """Companion s12_8: triangular unicycle (+ a 0.03 m disc), four discs and three squares; q_s, q_g = [x, y, θ]."""
    obstacles = [Disc([-2, -0.9], 0.3), Disc([0.8, 1.5], 0.2), Disc([0, -1], 0.3), Disc([-2, 0.9], 0.3),
                 box(0, 0, 0.5, 1), box(0, -3, 0.5, -2.5), box(2, -1, 2.5, -0.5)]
    body = PlanarBody((Polygon([[-0.1, -0.2], [-0.1, 0.2], [0.5, 0.0]]), Disc([0.0, 0.0], 0.03)))
    space = PlanarCSpace(body, Scene(obstacles, (-5, 5, -5, 5)), [-5, -5, -np.pi], [5, 5, np.pi], resolution=0.01)
    return space, np.array([-3.0, 0.0, 0.0]), np.array([3.0, -3.5, 0.0])


def grid_12_13() -> np.ndarray:
    """The occupancy grid of Problem 12.13 (companion s12_13), 7 × 7, True = obstacle; start (0, 0), goal (6, 6)."""
    return np.array([[0, 0, 1, 1, 1, 0, 0],
                     [1, 0, 1, 0, 0, 0, 0],
                     [0, 0, 1, 0, 0, 0, 0],
                     [0, 0, 0, 0, 1, 0, 0],
                     [0, 0, 0, 0, 1, 0, 0],
                     [0, 0, 1, 0, 1, 0, 0],
                     [0, 0, 1, 0, 1, 0, 0]], dtype=bool)


PLANNING_RESOLUTION = 0.05   # step of the planners' explicit sampled edge check [rad, Euclidean]


@dataclass
class Scenario:
    """A robot among boxes with a planning query (``q_start`` → ``q_goal``) and the limits of its timing law:
    the ``space`` (:class:`planners.collision.UrdfCSpace`) the planners search and certify edges in."""

    name: str
    robot: Robot
    boxes: tuple[Box, ...]
    space: UrdfCSpace
    q_start: np.ndarray
    q_goal: np.ndarray
    qd_max: np.ndarray      # joint speed limits of the timing law [rad/s]
    qdd_max: np.ndarray     # joint acceleration limits [rad/s²]

    def __repr__(self) -> str:
        return f"Scenario({self.name!r}, {self.robot.name!r}, boxes {[b.name for b in self.boxes]})"


def panda_shelf(resolution: float = PLANNING_RESOLUTION) -> Scenario:
    """The Panda (base at the origin) with a table top (z = 0.18–0.22 m), a shelf board (z ≈ 0.6 m) and a
    back panel in front of it; start: the hand inside the shelf (0.55, 0.25, 0.40) m pointing into it,
    goal: the hand above the board (0.40, −0.20, 0.80) m pointing down (found once by CLIK, stored).
    Self-collision pairs: all, minus the SRDF's ``disable_collisions`` and adjacent links. Timing limits: half
    the URDF's joint speeds, 5 rad/s²."""
    robot = load("panda")
    boxes = (Box([0.6, 0.0, 0.20], [0.5, 1.2, 0.04], "table"),
             Box([0.6, 0.0, 0.60], [0.5, 1.2, 0.03], "shelf"),
             Box([0.87, 0.0, 0.45], [0.04, 1.2, 0.5], "back"))
    checker = CollisionChecker(robot, boxes, srdf=example_robot_srdf("panda"))
    return Scenario("Panda: from inside the shelf to above it", robot, boxes,
                    UrdfCSpace(checker, resolution),
                    np.array([1.67, 1.465, -1.622, -1.833, 2.89, 2.973, 2.487]),
                    np.array([-0.065, -0.081, -0.36, -1.159, -0.032, 1.083, 0.346]),
                    0.5 * np.array(robot.model.velocityLimit), np.full(7, 5.0))


def anthropomorphic_pillar(resolution: float = PLANNING_RESOLUTION) -> Scenario:
    """The book's anthropomorphic arm (a₂ = 0.5 m, a₃ = 0.4 m; cylinders of its DH → URDF) on a table
    (top at z = −0.43 m) with a pillar (top at z = 0.5 m) in front: from one side of the pillar to the
    other, the arm must lift over it. Self-collision: non-adjacent links (no SRDF)."""
    robot = load("anthropomorphic")
    boxes = (Box([0.5, 0.0, -0.45], [0.8, 1.4, 0.04], "table"),
             Box([0.55, 0.0, 0.03], [0.15, 0.15, 0.94], "pillar"))
    checker = CollisionChecker(robot, boxes)
    return Scenario("anthropomorphic arm: over the pillar", robot, boxes,
                    UrdfCSpace(checker, resolution),
                    np.array([0.6, -0.3, 0.9]), np.array([-0.6, -0.3, 0.9]),
                    np.full(3, 1.5), np.full(3, 4.0))
