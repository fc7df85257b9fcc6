"""The book's controllers on MuJoCo physics: :class:`MujocoPlant`, a plant of the simulation loop stepped by MuJoCo.

Every closed loop of rmpc runs against Pinocchio's forward dynamics integrated by the loop's RK4
(:class:`controllers.plants.ArmPlant`, :class:`controllers.plants.ArmInContact`). ``MujocoPlant(robot, scene)``
runs the same controllers, unchanged, on MuJoCo: it follows the plant contract of
:mod:`controllers.simulation` (``initial_state``, ``measure`` → :class:`~controllers.plants.ArmMeasurement`,
``derivative``) and advances its own state over the loop's step h (``stepper(h)``: MuJoCo's ``mj_step``, its
timestep dividing h, the controller's torque held as ``qfrc_applied``).

The MuJoCo model is written as MJCF from the :class:`~rigid_body.robots.Robot` object itself, not from its URDF
file, so what was changed on the robot carries over (a payload of :func:`~rigid_body.robots.with_payload`, the
Panda's locked fingers, a book robot rebuilt with other link lengths):

* one MuJoCo body per Pinocchio joint, placed by ``model.jointPlacements``, with the joint's inertia
  (``model.inertias``: the links welded to it merged, as Pinocchio merges them); hinge/slide joints on the joint's
  axis (continuous joints, ``cos``/``sin`` in Pinocchio's q, are one hinge angle here), ``range`` from the
  position limits, ``damping`` F_v and ``frictionloss`` F_s from the robot's friction (``robot.friction``, the
  URDF's ``<dynamics>``: MuJoCo applies them, ``pin.aba`` does not — give ``ArmPlant(robot,
  friction=robot.friction)`` the same), ``armature`` from ``model.armature``; the robot's joints first in
  ``qpos``/``qvel``, in the robot's order;
* the robot's collision shapes (``robot.collision_model``): boxes, spheres, cylinders, capsules and ellipsoids as
  they are; meshes (STL, Collada, OBJ: whatever Pinocchio loaded) as their convex hull — MuJoCo collides the convex
  hull of a mesh anyway; self-collision pairs between adjacent bodies and those the robot's SRDF disables
  (``<disable_collisions>``, example-robot-data's for the Panda and the UR arms) are excluded, as
  :class:`planners.collision.CollisionChecker` excludes them;
* the book's rotors (Sect. 7.3: mimic joints spinning at k_r q̇): MuJoCo can couple two joints only softly
  (an equality constraint), so the plant refuses them unless ``rotors="armature"``: then each rotor's mass and
  inertia ride on the link that carries it and its spin inertia reflected through the gear, k_r² I_m, becomes the
  driven joint's armature. The book's B(q) also has the couplings k_r I_m z_{i−1}ᵀ ω_{i−1} (7.32) that this drops:
  the difference is measured at construction (``plant.inertia_difference``, the largest ‖B_MuJoCo − B‖/‖B‖ over
  random configurations, 1e-15 for a robot without rotors) and named in the refusal. A body without a positive mass
  and three positive principal moments (a thin rod, a point mass), which MuJoCo refuses, gets them raised to
  ``INERTIA_FLOOR`` (1e-10) times the robot's scale (``plant.inertia_floor`` names such bodies).

Scenes (``scene``: one object or a sequence) become MuJoCo geoms fixed to the world:

* :class:`~controllers.environment.CompliantPlane` → a plane (MuJoCo planes are half-spaces);
  :class:`~controllers.environment.SteppedPlane` → two boxes (the surface and its recess, the riser included);
  :class:`~controllers.environment.SurfaceWithHole` → three boxes around the hole. Their stiffness K [N/m] and
  damping D [N·s/m] hold *per contact point*: each contact of such a surface is a MuJoCo soft contact in the
  direct (−stiffness, −damping) format with a constant impedance d = ``CONTACT_IMPEDANCE`` (0.001), calibrated so
  that its normal force is f = K δ + D δ̇ + m_v δ̈ with δ the penetration — the compliant plane's law plus a small
  virtual mass m_v = d/((1 − d) Â), Â MuJoCo's diagonal approximation of the inverse inertia at the contact
  (``body_invweight0``; from MuJoCo's soft-contact identity R f = a_ref − a with R = (1 − d)/d · Â, Computation
  chapter of its documentation). So the force at rest is the compliant plane's; in motion it differs by m_v δ̈, and
  a force sensor read at a sample sees the torque held over the interval ending there. A flat face resting on the
  surface makes several contact points (up to 4 for a box face): their stiffnesses add. Coulomb friction μ is
  MuJoCo's elliptic friction cone: below μN it acts as a damper of coefficient D (MuJoCo's default contact damping
  when D = 0), where the compliant plane regularises as μN tanh(‖v_t‖/v_s); while sliding, the soft cone turns part
  of the tangential push into normal force. A bilateral plane (a spring that pulls) cannot be represented:
  MuJoCo's contacts only push.
* :class:`planners.collision.Box` → a box with MuJoCo's default (stiff) contact, e.g. the Chapter 12 scenes.

The sensed wrench (``force_sensor``, default: when the scene has objects) is the sum of the MuJoCo contact forces
between the geoms of the body that carries the end-effector frame (``frame``) and the scene, as h_e = [f; μ] exerted
by the end effector on the environment in the base frame, μ about the frame's origin (Sect. 9.1): what
:class:`~controllers.plants.ArmInContact` reports. With ``probe=ρ`` only a sphere of radius ρ at the frame's
origin touches the compliant surfaces (the point contact of Sect. 9.2; the surfaces are moved by ρ so that the
penetration is the compliant plane's δ): the robot's own shapes then touch only the boxes.

MuJoCo is optional: ``pip install 'rmpc[mujoco]'``. Importing this module works without it; building a plant
raises an ImportError with that command.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 7.2–7.3
(B(q), the rotors), 8.5 (the loop), 9.1–9.2 (h_e, compliant environment); MuJoCo documentation, Computation
(soft constraints, impedance, R = (1 − d)/d · Â) and Modeling (solref/solimp) chapters.
"""

from __future__ import annotations

import math
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np
import pinocchio as pin

from controllers.environment import CompliantPlane, SteppedPlane, SurfaceWithHole
from controllers.laws import Numeric
from controllers.plants import ArmMeasurement, arm_units, joint_torques, saturated
from controllers.simulation import SimulationDiverged
from rigid_body.robots import EXAMPLE_ROBOTS, JointFriction, Robot
from rigid_body.validation import as_positive, as_vector

__all__ = ["MujocoPlant", "MujocoContact", "INSTALL", "import_mujoco", "mujoco_available"]

#: the command that installs the optional dependency (the ``[mujoco]`` extra and its pinned range)
INSTALL = "pip install 'rmpc[mujoco]'  (or: pip install 'mujoco>=3.3,<5')"
INTEGRATORS = ("RK4", "Euler", "implicit", "implicitfast")
#: the constant impedance d of the compliant surfaces' contacts: small, so that the virtual mass d/((1 − d) Â)
#: of MuJoCo's soft contact stays a thousandth of the body's effective mass 1/Â
CONTACT_IMPEDANCE = 0.001
_HALF_SPACE = 2.0     # [m] half extent of the boxes standing for a stepped plane or a surface with a hole
_ROBOT_GROUP, _SCENE_GROUP, _PROBE_GROUP = 0, 1, 2     # MuJoCo geom groups (visualisation)


def import_mujoco() -> Any:
    """The ``mujoco`` module, or an ImportError that says how to install it."""
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - the message is tested with the module hidden
        raise ImportError(f"MuJoCo is not installed; MujocoPlant needs it: {INSTALL}") from exc
    return mujoco


def mujoco_available() -> bool:
    """True when ``import mujoco`` works."""
    try:
        import_mujoco()
    except ImportError:
        return False
    return True


@dataclass(frozen=True)
class MujocoContact:
    """One MuJoCo contact: the two geoms' names, the contact point (3,) [m] in the base frame, the penetration
    depth [m] (> 0 inside) and the force (3,) [N] the first geom exerts on the second, in the base frame."""

    geom1: str
    geom2: str
    position: np.ndarray
    penetration: float
    force: np.ndarray


# --------------------------------------------------------------------------------------------
# The robot as MJCF
# --------------------------------------------------------------------------------------------

def _numbers(values: Any) -> str:
    return " ".join(repr(float(v)) for v in np.ravel(values))


def _pose(element: ET.Element, placement: pin.SE3) -> None:
    """pos and quat (MuJoCo's scalar-first order) of a child relative to its parent."""
    element.set("pos", _numbers(placement.translation))
    q = pin.Quaternion(placement.rotation)
    element.set("quat", _numbers([q.w, q.x, q.y, q.z]))


def _inertial(body: ET.Element, inertia: pin.Inertia, floor: tuple[float, float]) -> bool:
    """The body's <inertial> in principal axes. MuJoCo refuses a moving body without a positive mass, three positive
    principal moments and the triangle inequality A + B ≥ C (a thin rod, a point mass, some published data): a mass
    or moment below ``floor`` = (mass, moment) is raised to it, and the smallest moment as far as the inequality
    needs. Returns whether anything was raised."""
    mass = float(inertia.mass)
    moments, axes = np.linalg.eigh(np.asarray(inertia.inertia, dtype=float))   # ascending
    before = moments.copy()
    mass = max(mass, floor[0])
    moments = np.maximum(moments, floor[1])
    moments[0] = max(moments[0], moments[2] - moments[1])
    raised = mass > inertia.mass or bool(np.any(moments > before))
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    q = pin.Quaternion(axes)
    ET.SubElement(body, "inertial", pos=_numbers(inertia.lever), quat=_numbers([q.w, q.x, q.y, q.z]),
                  mass=repr(mass), diaginertia=_numbers(moments))
    return bool(raised)


#: relative floor of a body's mass and principal moments (MuJoCo needs them positive; see _inertial)
INERTIA_FLOOR = 1e-10


_AXIS_JOINTS = {"RX": ("hinge", (1, 0, 0)), "RY": ("hinge", (0, 1, 0)), "RZ": ("hinge", (0, 0, 1)),
                "PX": ("slide", (1, 0, 0)), "PY": ("slide", (0, 1, 0)), "PZ": ("slide", (0, 0, 1)),
                "RUBX": ("hinge", (1, 0, 0)), "RUBY": ("hinge", (0, 1, 0)), "RUBZ": ("hinge", (0, 0, 1))}


def _joint_type(model: pin.Model, j: int) -> tuple[str, np.ndarray, bool]:
    """(MuJoCo type, axis, continuous) of Pinocchio joint j; ValueError naming it when MuJoCo has no such joint."""
    jmodel = model.joints[j]
    short = jmodel.shortname().removeprefix("JointModel")
    if short in _AXIS_JOINTS:
        kind, axis = _AXIS_JOINTS[short]
        return kind, np.array(axis, dtype=float), short.startswith("RUB")
    if short in ("RevoluteUnaligned", "PrismaticUnaligned", "RevoluteUnboundedUnaligned"):
        axis = np.asarray(jmodel.extract().axis, dtype=float)
        return ("slide" if short.startswith("Prismatic") else "hinge"), axis, short.startswith("RevoluteUnbounded")
    raise ValueError(f"MujocoPlant: joint {model.names[j]!r} is a {short} joint; MuJoCo's model is built here from "
                     f"revolute, prismatic and continuous joints only (not free-flyer, planar, spherical or composite)")


def _mimic_parts(model: pin.Model) -> dict[int, tuple[int, float, np.ndarray]]:
    """Mimic joint id → (mimicked joint id, multiplier k_r, unit motion subspace φ (6,)) of each rotor."""
    out = {}
    for mimicking, mimicked in zip(model.mimicking_joints, model.mimicked_joints):
        jmodel = model.joints[mimicking]
        data = jmodel.createData()
        jmodel.calc(data, pin.neutral(model))
        k_r = float(jmodel.extract().scaling)
        out[int(mimicking)] = (int(mimicked), k_r, np.asarray(data.S).reshape(6) / k_r)
    return out


def _body_names(model: pin.Model) -> dict[int, str]:
    """Pinocchio joint id → the name of the link it moves (its first BODY frame), or the joint's name."""
    names = {0: "world"}
    for frame in model.frames:
        j = frame.parentJoint
        if frame.type == pin.FrameType.BODY and j not in names:
            names[j] = frame.name
    return {j: names.get(j, f"{model.names[j]}_body") for j in range(model.njoints)}


def _geometry_element(parent: ET.Element, assets: ET.Element, obj: Any, placement: pin.SE3, name: str) -> ET.Element:
    """A <geom> for a Pinocchio geometry object (coal shape); meshes become their convex hull's vertices."""
    import coal

    shape = obj.geometry
    geom = ET.SubElement(parent, "geom", name=name)
    _pose(geom, placement)
    if isinstance(shape, coal.Box):
        geom.set("type", "box"), geom.set("size", _numbers(shape.halfSide))
    elif isinstance(shape, coal.Sphere):
        geom.set("type", "sphere"), geom.set("size", _numbers([shape.radius]))
    elif isinstance(shape, coal.Cylinder):
        geom.set("type", "cylinder"), geom.set("size", _numbers([shape.radius, shape.halfLength]))
    elif isinstance(shape, coal.Capsule):
        geom.set("type", "capsule"), geom.set("size", _numbers([shape.radius, shape.halfLength]))
    elif isinstance(shape, coal.Ellipsoid):
        geom.set("type", "ellipsoid"), geom.set("size", _numbers(shape.radii))
    elif isinstance(shape, (coal.BVHModelBase, coal.ConvexBase)):
        vertices = _hull_vertices(shape, name)
        ET.SubElement(assets, "mesh", name=f"{name}_hull", vertex=_numbers(vertices))
        geom.set("type", "mesh"), geom.set("mesh", f"{name}_hull")
    else:
        raise ValueError(f"MujocoPlant: the collision shape {name!r} is a {type(shape).__name__}, which MuJoCo "
                         f"cannot represent (boxes, spheres, cylinders, capsules, ellipsoids and meshes only)")
    return geom


def _hull_vertices(shape: Any, name: str) -> np.ndarray:
    """The vertices of a mesh's convex hull (as Pinocchio loaded it, scale applied)."""
    from scipy.spatial import ConvexHull, QhullError

    points = np.asarray(shape.vertices() if callable(getattr(shape, "vertices", None)) else shape.points,
                        dtype=float).reshape(-1, 3)
    try:
        return points[ConvexHull(points).vertices]
    except (QhullError, ValueError) as exc:
        raise ValueError(f"MujocoPlant: the collision mesh {name!r} ({len(points)} vertices) has no 3-D convex hull "
                         f"for MuJoCo: {exc}".splitlines()[0]) from None


def _srdf_pairs(path: Path | None) -> list[tuple[str, str]]:
    if path is None:
        return []
    root = ET.parse(str(path)).getroot()
    return [(e.get("link1", ""), e.get("link2", "")) for e in root.iter("disable_collisions")]


def _default_srdf(robot: Robot) -> Path | None:
    """example-robot-data's SRDF of an example robot (``<description>/srdf/<name>.srdf``: the Panda's, the UR5's),
    a payload copy ``panda+2kg`` included; None for any other robot."""
    from rigid_body.robots import example_robot_data_dir

    base = robot.name.split("+")[0]
    if base not in EXAMPLE_ROBOTS:
        return None
    path = example_robot_data_dir() / EXAMPLE_ROBOTS[base][0].split("/")[0] / "srdf" / f"{base}.srdf"
    return path if path.is_file() else None


# --------------------------------------------------------------------------------------------
# Scenes
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _SceneGeom:
    """A scene geom: its MJCF attributes and, for a compliant surface, (K, D, μ) of its contacts."""

    attributes: dict[str, str]
    compliance: tuple[float, float, float] | None
    source: int


def _frame_of_normal(normal: np.ndarray, along: np.ndarray | None = None) -> np.ndarray:
    """A rotation whose z axis is ``normal`` (and x axis ``along`` when given)."""
    z = normal / np.linalg.norm(normal)
    if along is None:
        along = np.eye(3)[int(np.argmin(np.abs(z)))]
    x = along - (along @ z) * z
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def _box_attributes(center: np.ndarray, half: np.ndarray, R: np.ndarray | None = None) -> dict[str, str]:
    R = np.eye(3) if R is None else R
    q = pin.Quaternion(R)
    return {"type": "box", "pos": _numbers(center), "quat": _numbers([q.w, q.x, q.y, q.z]), "size": _numbers(half)}


def _scene_geoms(scene: Sequence[Any], shift: float) -> list[_SceneGeom]:
    """The MuJoCo geoms of the scene's objects (``shift``: the probe radius the compliant surfaces move by)."""
    from planners.collision import Box

    out: list[_SceneGeom] = []
    for k, obj in enumerate(scene):
        if isinstance(obj, Box):
            out.append(_SceneGeom(_box_attributes(obj.center, obj.size / 2), None, k))
        elif isinstance(obj, SteppedPlane):
            out.extend(_stepped_plane(obj, k, shift))
        elif isinstance(obj, CompliantPlane):
            if type(obj) is not CompliantPlane:
                raise ValueError(f"`scene[{k}]`: MujocoPlant cannot represent a {type(obj).__name__} (a subclass of "
                                 f"CompliantPlane with its own surface)")
            if obj.bilateral:
                raise ValueError(f"`scene[{k}]`: a bilateral CompliantPlane (a spring that also pulls) cannot be a "
                                 f"MuJoCo contact, which only pushes: use bilateral=False")
            n = obj.normal
            q = pin.Quaternion(_frame_of_normal(n))
            attributes = {"type": "plane", "pos": _numbers(obj.point - shift * n),
                          "quat": _numbers([q.w, q.x, q.y, q.z]), "size": "0 0 1"}
            out.append(_SceneGeom(attributes, (obj.stiffness, obj.damping, obj.friction), k))
        elif isinstance(obj, SurfaceWithHole):
            out.extend(_surface_with_hole(obj, k, shift))
        else:
            raise ValueError(f"`scene[{k}]`: MujocoPlant cannot represent a {type(obj).__name__}; a scene holds "
                             f"CompliantPlane, SteppedPlane, SurfaceWithHole (controllers.environment) and Box "
                             f"(planners.collision) objects")
    return out


def _stepped_plane(obj: SteppedPlane, k: int, shift: float) -> list[_SceneGeom]:
    """The surface up to the edge and the recess beyond it, as two boxes 2·_HALF_SPACE wide and deep."""
    n, d = obj.normal, obj.direction
    R = _frame_of_normal(n, d)                              # x along the slide direction, z the outward normal
    H = _HALF_SPACE
    surface_point = obj.point - shift * n
    edge = surface_point + obj.step_at * d
    geoms = []
    for offset, sign in ((0.0, -1.0), (obj.depth, 1.0)):     # up to the edge; beyond it, recessed by depth
        centre = edge + sign * H * d - (offset + H) * n
        geoms.append(_SceneGeom(_box_attributes(centre, np.array([H, H, H]), R),
                                (obj.stiffness, obj.damping, obj.friction), k))
    return geoms


def _surface_with_hole(obj: SurfaceWithHole, k: int, shift: float) -> list[_SceneGeom]:
    """The surface y ≤ 0 of a planar task with its hole: left and right blocks, the hole's bottom."""
    H, c, x0 = _HALF_SPACE, obj.clearance + shift, obj.x_hole
    top = -shift                                             # the surfaces move back by the probe radius
    blocks = [(np.array([x0 - c - H, top - H, 0.0]), np.array([H, H, H])),
              (np.array([x0 + c + H, top - H, 0.0]), np.array([H, H, H])),
              (np.array([x0, top - obj.depth - H, 0.0]), np.array([c + 2 * H, H, H]))]
    return [_SceneGeom(_box_attributes(centre, half), (obj.stiffness, obj.damping, 0.0), k) for centre, half in blocks]


# --------------------------------------------------------------------------------------------
# The plant
# --------------------------------------------------------------------------------------------

class MujocoPlant:
    """A robot (and its scene) on MuJoCo physics, a plant of :func:`controllers.simulation.simulate`.

    State x = [q (n), q̇ (n)] = MuJoCo's [qpos, qvel] (a continuous joint's angle where Pinocchio has cos, sin);
    input u = the joint torques (n,), applied as ``qfrc_applied`` and held over the loop's step. The controllers
    receive the :class:`~controllers.plants.ArmMeasurement` an :class:`~controllers.plants.ArmPlant` gives
    (q in the robot's own convention), with the wrench when there is a force sensor.

    Parameters
    ----------
    robot : the :class:`~rigid_body.robots.Robot` (its current model: payloads, locked joints, parameters).
    scene : a scene object or a sequence of them (module docstring), or None.
    timestep : MuJoCo's step [s]; it must divide the loop's step h. None: the loop's h.
    integrator : MuJoCo's integrator, ``"RK4"`` (as the loop), ``"Euler"`` (semi-implicit), ``"implicit"``,
        ``"implicitfast"``.
    frame : the end-effector frame (name or id) of the force sensor and the probe (default the robot's).
    force_sensor : report the wrench h_e in the measurement (default: when there is a scene).
    friction : the joint friction given to MuJoCo (``damping`` F_v, ``frictionloss`` F_s): ``"robot"`` (default)
        ``robot.friction`` (the URDF's ``<dynamics>``, a DH table's friction), None (frictionless), or a
        :class:`~rigid_body.robots.JointFriction`. MuJoCo's dry friction is symmetric: F_s+ ≠ F_s− is refused.
    rotors : ``None`` (refuse a robot with rotors on mimic joints) or ``"armature"`` (module docstring).
    probe : radius [m] of a sphere at ``frame`` that alone touches the compliant surfaces, or None.
    srdf : an SRDF whose ``<disable_collisions>`` pairs are excluded; ``"auto"`` (default) example-robot-data's
        for its robots, None for none (adjacent bodies are always excluded).
    self_collision : collide the robot's non-excluded bodies with one another.
    joint_limits : MuJoCo's joint-limit constraints at the position limits (``ArmPlant`` has no joint stops).
    tau_max : optional actuator limits (n,): the commanded torque is saturated (:func:`controllers.plants.saturated`, the one body of ArmPlant's saturation).

    Attributes
    ----------
    model, data : the ``mujoco.MjModel`` and ``mujoco.MjData``. ``mjcf`` : the MJCF text they were built from.
    inertia_difference : max ‖B_MuJoCo(q) − B(q)‖_F/‖B(q)‖_F over random configurations: round-off, unless the
        robot has rotors (``rotors="armature"``) or bodies in ``inertia_floor``.
    inertia_floor : the bodies whose mass or principal moments were raised to MuJoCo's minimum.
    """

    def __init__(self, robot: Robot, scene: Any = None, timestep: float | None = None, integrator: str = "RK4", *,
                 frame: str | int | None = None, force_sensor: bool | None = None, friction: Any = "robot",
                 rotors: str | None = None, probe: float | None = None, srdf: Any = "auto",
                 self_collision: bool = True, joint_limits: bool = True, tau_max: Any = None):
        import_mujoco()        # the module is imported where used, never kept on the plant (its state is data)
        if not isinstance(robot, Robot):
            raise ValueError(f"`robot` must be a rigid_body.robots.Robot, got {type(robot).__name__}")
        self.robot = robot
        model = robot.model
        self.n = n = robot.nv
        self.nq = robot.nq
        self._fid = robot.frame(frame)
        self.frame = frame
        if integrator not in INTEGRATORS:
            raise ValueError(f"`integrator` must be one of {INTEGRATORS}, got {integrator!r}")
        self.integrator = integrator
        self.timestep = None if timestep is None else as_positive(timestep, "timestep")
        if rotors not in (None, "armature"):
            raise ValueError(f"`rotors` must be None (refuse rotors) or 'armature', got {rotors!r}")
        self.probe = None if probe is None else as_positive(probe, "probe")
        scene_list = [] if scene is None else list(scene) if isinstance(scene, (list, tuple)) else [scene]
        self.scene = tuple(scene_list)
        self.force_sensor = bool(scene_list) if force_sensor is None else bool(force_sensor)
        self.friction = self._friction(friction)
        self.tau_max = None if tau_max is None else as_vector(tau_max, n, "tau_max")
        if self.tau_max is not None and np.any(self.tau_max <= 0):
            raise ValueError(f"`tau_max` must be positive torque limits, got {self.tau_max}")
        self._rotors = _mimic_parts(model)
        #: (idx_q, idx_v, continuous) of the robot's joints (the rotors excluded)
        self._joint_indices = [(model.joints[j].idx_q, model.joints[j].idx_v, _joint_type(model, j)[2])
                               for j in range(1, model.njoints) if j not in self._rotors]
        self._continuous = [(iq, iv) for iq, iv, continuous in self._joint_indices if continuous]
        if self._rotors and rotors is None:
            difference = self._build(scene_list, srdf, self_collision, joint_limits)
            effect = (f"B(q) then differs from the book's by up to {100 * difference:.3g} % (Frobenius norm, random "
                      f"configurations): the couplings k_r I_m of (7.32) are dropped" if difference > 1e-12 else
                      "B(q) is then the book's: the couplings k_r I_m of (7.32) vanish on this robot")
            raise ValueError(
                f"robot {robot.name!r} has rotors on mimic joints (the book's motors, Sect. 7.3), which MuJoCo can "
                f"couple only softly: pass rotors='armature' (each rotor's spin inertia k_r² I_m as the driven "
                f"joint's armature, its mass on the carrying link; {effect}), or load the robot with "
                f"motors='armature'")
        self.inertia_difference = self._build(scene_list, srdf, self_collision, joint_limits)
        if self.inertia_floor and not self._rotors and self._floor_effect > 1e-8:   # (rotors: opted in, reported)
            warnings.warn(f"MujocoPlant: robot {robot.name!r}: the inertia of {', '.join(self.inertia_floor)} was "
                          f"raised to MuJoCo's minimum (positive principal moments, A + B ≥ C): B(q) differs by up to "
                          f"{100 * self.inertia_difference:.3g} % (plant.inertia_difference)", stacklevel=2)
        self.state_size = self.tangent_size = 2 * n
        self.input_size = n
        self.units = {**arm_units(robot), "wrench": "N, N·m"}
        self.state_layout = {"qd": slice(n, 2 * n)}
        if not self._continuous:
            self.state_layout["q"] = slice(0, n)

    # ---- construction -------------------------------------------------------------------------

    def _friction(self, friction: Any) -> JointFriction:
        n = self.n
        if isinstance(friction, str) and friction == "robot":
            friction = self.robot.friction
        if friction is None:
            return JointFriction(np.zeros(n), np.zeros(n), np.zeros(n))
        if not isinstance(friction, JointFriction):
            raise ValueError(f"`friction` must be 'robot', None or a JointFriction, got {type(friction).__name__}")
        parts = [np.asarray(v, dtype=float) for v in (friction.viscous, friction.coulomb_positive,
                                                        friction.coulomb_negative)]
        if any(p.shape != (n,) for p in parts) or any(np.any(p < 0) or not np.all(np.isfinite(p)) for p in parts):
            raise ValueError(f"`friction` must hold non-negative finite ({n},) vectors for robot {self.robot.name!r}")
        if not np.allclose(parts[1], parts[2], rtol=1e-12, atol=0.0):
            raise ValueError(f"`friction`: MuJoCo's dry friction (frictionloss) is symmetric, but robot "
                             f"{self.robot.name!r} has F_s+ = {parts[1]} ≠ F_s− = {parts[2]}: pass friction=None or a "
                             f"JointFriction with equal magnitudes")
        return JointFriction(*parts)

    def _build(self, scene: list, srdf: Any, self_collision: bool, joint_limits: bool) -> float:
        """Write the MJCF, compile it, calibrate the compliant contacts; returns the largest relative difference of
        MuJoCo's B(q) from the robot's over random configurations."""
        mujoco = import_mujoco()
        robot, model = self.robot, self.robot.model
        rotors = self._rotors
        root = ET.Element("mujoco", model=robot.name)
        ET.SubElement(root, "compiler", angle="radian", inertiafromgeom="false", autolimits="true",
                      boundmass="0", boundinertia="0", balanceinertia="false")
        option = ET.SubElement(root, "option", timestep=repr(self.timestep or 1e-3), integrator=self.integrator,
                               gravity=_numbers(model.gravity.linear), cone="elliptic")
        ET.SubElement(option, "flag", contact="enable")
        assets = ET.SubElement(root, "asset")
        world = ET.SubElement(root, "worldbody")
        names = _body_names(model)
        # the body each joint's inertia, shapes and frames go to: a rotor's are its carrying link's
        host = {0: 0}
        for j in range(1, model.njoints):
            host[j] = host[model.parents[j]] if j in rotors else j
        armature = np.array(model.armature, dtype=float).copy()
        extra_inertia: dict[int, pin.Inertia] = {}
        for j, (mimicked, k_r, phi) in rotors.items():       # a rotor rides on its carrying link …
            placed = model.jointPlacements[j].act(model.inertias[j])
            extra_inertia[host[j]] = extra_inertia.get(host[j], pin.Inertia.Zero()) + placed
            spin = float(phi @ (model.inertias[j].matrix() @ phi))   # … and spins k_r times as fast: k_r² I_m
            armature[model.joints[mimicked].idx_v] += k_r ** 2 * spin
        inertias = {j: model.inertias[j] + extra_inertia.get(j, pin.Inertia.Zero()) for j in range(1, model.njoints)
                    if j not in rotors}
        scale = max((float(np.trace(I.inertia)) + I.mass * float(I.lever @ I.lever) for I in inertias.values()),
                    default=1.0)
        floor = (INERTIA_FLOOR * max(sum(I.mass for I in inertias.values()), 1e-300),
                 INERTIA_FLOOR * max(scale, 1e-300))
        self.inertia_floor: list[str] = []
        self._floor_effect = 0.0            # the largest moment added to a body, relative to the robot's scale
        bodies: dict[int, ET.Element] = {0: world}
        for j in range(1, model.njoints):
            if j in rotors:
                continue
            kind, axis, continuous = _joint_type(model, j)
            body = ET.SubElement(bodies[host[model.parents[j]]], "body", name=names[j])
            _pose(body, model.jointPlacements[j])
            bodies[j] = body
            if _inertial(body, inertias[j], floor):
                self.inertia_floor.append(names[j])
                written = body.find("inertial")
                added = np.array(written.get("diaginertia").split(), dtype=float).sum() - np.trace(inertias[j].inertia)
                self._floor_effect = max(self._floor_effect, added / scale)
            joint = ET.SubElement(body, "joint", name=model.names[j], type=kind, axis=_numbers(axis))
            iq, iv = model.joints[j].idx_q, model.joints[j].idx_v
            lo, hi = model.lowerPositionLimit[iq], model.upperPositionLimit[iq]
            if joint_limits and not continuous and np.isfinite(lo) and np.isfinite(hi) and hi - lo < 1e10:
                joint.set("range", _numbers([lo, hi]))
            joint.set("damping", repr(float(self.friction.viscous[iv])))
            joint.set("frictionloss", repr(float(self.friction.coulomb_positive[iv])))
            joint.set("armature", repr(float(armature[iv])))

        def in_host(j: int, placement: pin.SE3) -> pin.SE3:
            """A placement given in joint j's frame, expressed in its host body's (a rotor's: its carrier's)."""
            return model.jointPlacements[j] * placement if j in rotors else placement

        # collision shapes, each in the body of its own link: the joint's body for the joint's link, a body welded
        # to it for a link fixed to that one (MuJoCo excludes contacts per body pair, the SRDF per link pair)
        link_bodies: dict[str, tuple[str, int]] = {}          # link → (MuJoCo body, host joint = weld group)
        contype = "1" if self_collision else "2"
        robot_geoms: list[tuple[str, int]] = []            # (name, host joint) of the moving robot geoms
        for obj in robot.collision_model.geometryObjects:
            j, frame = obj.parentJoint, model.frames[obj.parentFrame]
            h = host[j]
            link = frame.name if frame.type == pin.FrameType.BODY else names[h]
            if h != 0 and link == names[h]:
                parent, placement = bodies[h], in_host(j, obj.placement)
            else:
                if link not in link_bodies:
                    welded = ET.SubElement(bodies[h], "body", name=link)
                    _pose(welded, in_host(j, frame.placement))
                    link_bodies[link] = (link, h)
                parent = next(b for b in bodies[h].iter("body") if b.get("name") == link)
                placement = frame.placement.inverse() * obj.placement
            link_bodies.setdefault(link, (link, h))
            geom = _geometry_element(parent, assets, obj, placement, obj.name)
            geom.set("group", str(_ROBOT_GROUP))
            geom.set("contype", contype if h != 0 else "0")
            geom.set("conaffinity", "1")
            geom.set("rgba", "0.7 0.7 0.75 1")
            if h != 0:
                robot_geoms.append((obj.name, h))
        ee_frame = model.frames[self._fid]
        host_ee = host[ee_frame.parentJoint]
        if host_ee == 0:
            raise ValueError(f"`frame`: {ee_frame.name!r} is fixed to the world; the force sensor and the probe need "
                             f"a frame on a moving link")
        frame_placement = in_host(ee_frame.parentJoint, ee_frame.placement)
        _pose(ET.SubElement(bodies[host_ee], "site", name="end_effector"), frame_placement)
        if self.probe is not None:
            probe = ET.SubElement(bodies[host_ee], "geom", name="probe", type="sphere",
                                  size=_numbers([self.probe]), group=str(_PROBE_GROUP), contype="0",
                                  conaffinity="0", rgba="0.9 0.4 0.1 1")
            _pose(probe, frame_placement)
        # scene
        scene_geoms = _scene_geoms(scene, self.probe or 0.0)
        contact = ET.SubElement(root, "contact")
        compliant: list[tuple[str, str, int, tuple[float, float, float]]] = []   # (robot geom, scene geom, body, K D μ)
        for k, sg in enumerate(scene_geoms):
            name = f"scene{sg.source}_{k}"
            attrs = dict(sg.attributes, name=name, group=str(_SCENE_GROUP), rgba="0.55 0.6 0.7 0.5")
            if sg.compliance is not None:          # contacts through explicit pairs only (calibrated below)
                attrs.update(contype="0", conaffinity="0")
            else:
                attrs.update(contype="1", conaffinity="1")
            ET.SubElement(world, "geom", attrs)
            if sg.compliance is None:
                continue
            partners = [("probe", host_ee)] if self.probe is not None else robot_geoms
            if not partners:
                raise ValueError(f"`scene[{sg.source}]`: robot {robot.name!r} has no collision shapes on its moving "
                                 f"links to touch it: give probe=radius")
            for geom_name, body in partners:
                compliant.append((geom_name, name, body, sg.compliance))
                condim = "3" if sg.compliance[2] > 0 else "1"
                ET.SubElement(contact, "pair", geom1=geom_name, geom2=name, condim=condim,
                              friction=_numbers([max(sg.compliance[2], 1e-12)] * 2 + [0.0, 0.0, 0.0]))
        for a, b in sorted(self._excluded_pairs(link_bodies, host, srdf)):
            ET.SubElement(contact, "exclude", body1=a, body2=b)
        self.mjcf = ET.tostring(root, encoding="unicode")
        try:
            mj_model = mujoco.MjModel.from_xml_string(self.mjcf)
        except ValueError as exc:
            raise ValueError(f"MuJoCo cannot compile robot {robot.name!r}: {exc}") from None
        self._check_order(mj_model)
        self._calibrate(mj_model, compliant, names)
        self.model, self.data = mj_model, mujoco.MjData(mj_model)
        self._ee_body = int(mj_model.site_bodyid[0])
        weld = mj_model.body_weldid
        self._sensor_geoms = {g for g in range(mj_model.ngeom)
                              if weld[mj_model.geom_bodyid[g]] == weld[self._ee_body]}
        self._scene_geom_ids = {g for g in range(mj_model.ngeom) if mj_model.geom_group[g] == _SCENE_GROUP}
        return self._compare_inertia()

    def _excluded_pairs(self, link_bodies: dict[str, tuple[str, int]], host: dict[int, int],
                        srdf: Any) -> set[tuple[str, str]]:
        """Body pairs never collided: the robot's base (fixed to the world) and the links of the joints it carries
        (MuJoCo filters the other parent–child pairs itself, per weld group), and the SRDF's link pairs."""
        model = self.robot.model
        pairs: set[tuple[str, str]] = set()
        base = [b for b, h in link_bodies.values() if h == 0]
        for b, h in link_bodies.values():
            if h != 0 and host[model.parents[h]] == 0:
                pairs.update((a, b) for a in base)
        path = _default_srdf(self.robot) if isinstance(srdf, str) and srdf == "auto" else srdf
        if path is not None and not Path(path).is_file():
            raise ValueError(f"`srdf`: no SRDF file at {path}")
        for a, b in _srdf_pairs(None if path is None else Path(path)):
            if a in link_bodies and b in link_bodies and link_bodies[a][1] != link_bodies[b][1]:
                pairs.add((link_bodies[a][0], link_bodies[b][0]))
        return {tuple(sorted(p)) for p in pairs}

    def _check_order(self, mj_model: Any) -> None:
        """The robot's joints are MuJoCo's first dofs, in the robot's order (a property of the body tree written)."""
        mujoco, model = import_mujoco(), self.robot.model
        for j in range(1, model.njoints):
            if j in self._rotors:
                continue
            jid = mujoco.mj_name2id(mj_model, mujoco.mjtObj.mjOBJ_JOINT, model.names[j])
            if mj_model.jnt_dofadr[jid] != model.joints[j].idx_v:
                raise RuntimeError(f"MujocoPlant: joint {model.names[j]!r} is MuJoCo dof {mj_model.jnt_dofadr[jid]}, "
                                   f"not {model.joints[j].idx_v} as in the robot (joints out of order)")

    def _calibrate(self, mj_model: Any, compliant: list, names: dict[int, str]) -> None:
        """Each compliant pair's solref (direct format) and constant impedance d so that a contact point's normal
        force is K δ + D δ̇ (+ the virtual mass): stiffness_mj = K (1 − d) Â, damping_mj = D (1 − d) Â with Â
        the body's translational inverse weight (MuJoCo's diagonal approximation for a contact on it)."""
        mujoco, d = import_mujoco(), CONTACT_IMPEDANCE
        for i, (geom, _, _, (K, D, _)) in enumerate(compliant):
            body = mj_model.geom_bodyid[mujoco.mj_name2id(mj_model, mujoco.mjtObj.mjOBJ_GEOM, geom)]
            A_hat = float(mj_model.body_invweight0[body, 0])
            damping = D if D > 0 else 0.0
            mj_model.pair_solref[i] = (-K * (1 - d) * A_hat, -damping * (1 - d) * A_hat)
            mj_model.pair_solimp[i] = (d, d, 0.001, 0.5, 2.0)
            if D <= 0:    # friction rows: MuJoCo's default damping (a time constant of 0.02 s)
                mj_model.pair_solreffriction[i] = (0.02, 1.0)

    def _compare_inertia(self, samples: int = 20) -> float:
        """max ‖B_MuJoCo(q) − B(q)‖_F / ‖B(q)‖_F over random configurations (the rotors' armature model)."""
        from rigid_body.dynamics import inertia_matrix

        rng = np.random.default_rng(7)
        worst = 0.0
        for _ in range(samples):
            q = self.robot.random_configuration(rng)
            for iq, _ in self._continuous:
                angle = rng.uniform(-np.pi, np.pi)
                q[iq], q[iq + 1] = np.cos(angle), np.sin(angle)
            B = inertia_matrix(self.robot, q)
            worst = max(worst, float(np.linalg.norm(self.inertia_matrix(q) - B) / np.linalg.norm(B)))
        return worst

    # ---- state and contract ---------------------------------------------------------------------

    def _positions(self, q: np.ndarray) -> np.ndarray:
        """MuJoCo's qpos (n,) of the robot's q (nq,): a continuous joint's (cos, sin) → its angle."""
        if not self._continuous:
            return q
        out = np.empty(self.n)
        for iq, iv, continuous in self._joint_indices:
            out[iv] = math.atan2(q[iq + 1], q[iq]) if continuous else q[iq]
        return out

    def configuration(self, x: np.ndarray) -> np.ndarray:
        """The robot's q (nq,) at state x (the angle of a continuous joint → its cos, sin)."""
        if not self._continuous:
            return x[:self.n]
        q = np.empty(self.nq)
        for iq, iv, continuous in self._joint_indices:
            if continuous:
                q[iq], q[iq + 1] = math.cos(x[iv]), math.sin(x[iv])
            else:
                q[iq] = x[iv]
        return q

    def initial_state(self, q0: Any, qd0: Any = None) -> np.ndarray:
        """x0 = [q0 (as MuJoCo's qpos), q̇0] (q̇0 = 0 by default); q0 in the robot's convention (nq,)."""
        q0 = as_vector(q0, self.nq, "q0")
        qd0 = np.zeros(self.n) if qd0 is None else as_vector(qd0, self.n, "qd0")
        return np.concatenate([self._positions(q0), qd0])

    def _set(self, x: np.ndarray, u: np.ndarray | None = None) -> None:
        d, n = self.data, self.n
        d.qpos[:] = x[:n]
        d.qvel[:] = x[n:]
        if u is not None:
            d.qfrc_applied[:] = self.torque(u)

    def torque(self, u: Any) -> np.ndarray:
        """The torque actually applied: ``u`` saturated at ±tau_max."""
        return saturated(Numeric, joint_torques(u, self.n), self.tau_max)

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        """ẋ = [q̇, q̈] with q̈ MuJoCo's ``qacc`` from ``mj_forward`` at (x, u): contacts, joint limits, damping and
        friction loss included — the stage-by-stage counterpart of ``ArmPlant.derivative``."""
        self._set(x, u)
        import_mujoco().mj_forward(self.model, self.data)
        return np.concatenate([x[self.n:], self.data.qacc])

    def stepper(self, h: float) -> Callable[[float, np.ndarray, np.ndarray], np.ndarray]:
        """The loop's step (t, x, u) → x(t + h): MuJoCo's ``mj_step`` h/timestep times with u held (the
        self-stepping hook of :func:`controllers.simulation.simulate`). A step MuJoCo finds bad (a non-finite or
        huge acceleration, which it would silently reset) raises :class:`SimulationDiverged`."""
        h = as_positive(h, "h")
        timestep = self.timestep or h
        ratio = h / timestep
        k = int(round(ratio))
        if k < 1 or abs(ratio - k) > 1e-9 * max(1.0, ratio):
            raise ValueError(f"MujocoPlant: `timestep` = {timestep:g} s must divide the loop's step h = {h:g} s")
        self.model.opt.timestep = timestep
        mujoco, m, d, n = import_mujoco(), self.model, self.data, self.n
        mujoco.mj_resetData(m, d)           # a run starts afresh: no torque held, no solver warm start
        mj_step, qpos, qvel, qfrc, tau_max = mujoco.mj_step, d.qpos, d.qvel, d.qfrc_applied, self.tau_max
        counts = d.warning.number          # a view of MuJoCo's warning counters
        acc, pos, vel = (int(w) for w in (mujoco.mjtWarning.mjWARN_BADQACC, mujoco.mjtWarning.mjWARN_BADQPOS,
                                          mujoco.mjtWarning.mjWARN_BADQVEL))
        substeps = range(k)

        def step(t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
            qpos[:] = x[:n]
            qvel[:] = x[n:]
            qfrc[:] = saturated(Numeric, u, tau_max)
            before = counts.item(acc) + counts.item(pos) + counts.item(vel)
            for _ in substeps:
                mj_step(m, d)
            if counts.item(acc) + counts.item(pos) + counts.item(vel) != before:
                raise SimulationDiverged(f"MuJoCo found a non-finite or huge state or acceleration in the step "
                                         f"from t = {t:.6g} s and reset it: the loop diverges (step h = {h:g} s, "
                                         f"MuJoCo timestep {timestep:g} s)", t)
            out = np.empty(2 * n)
            out[:n] = qpos
            out[n:] = qvel
            return out
        return step

    def symbolic(self) -> Any:
        """No CasADi form: MuJoCo steps this plant (``simulate(..., backend="casadi")`` names the way out)."""
        raise ValueError("`plant`: MujocoPlant is stepped by MuJoCo (mj_step), which has no CasADi form for "
                         "backend='casadi': use backend='python'")

    def measure(self, t: float, x: np.ndarray) -> ArmMeasurement:
        q = self.configuration(x)
        if not self.force_sensor:
            return ArmMeasurement(q, x[self.n:])
        return ArmMeasurement(q, x[self.n:], self.wrench(x))

    # ---- contacts ---------------------------------------------------------------------------------

    def _forward(self, x: np.ndarray) -> None:
        """``mj_forward`` at state x under the torque last applied (held until this instant): MuJoCo's contact
        force is found with the accelerations (its soft contacts carry a small virtual mass), so a force sensor
        read at a sample sees the torque of the interval that ends there."""
        self._set(np.asarray(x, dtype=float))
        import_mujoco().mj_forward(self.model, self.data)

    def wrench(self, x: np.ndarray) -> np.ndarray:
        """h_e = [f; μ] (6,): the contact forces the end effector's body exerts on the scene at state x, in the
        base frame, μ about the end-effector frame's origin (Sect. 9.1)."""
        self._forward(x)
        mujoco, m, d = import_mujoco(), self.model, self.data
        h = np.zeros(6)
        if d.ncon == 0:
            return h
        p_e = d.site_xpos[0]
        sensor, scene = self._sensor_geoms, self._scene_geom_ids
        f6 = np.zeros(6)
        for i in range(d.ncon):
            g1, g2 = d.contact.geom[i]
            if g1 in sensor and g2 in scene:
                sign = 1.0         # the force geom1 (the end effector) exerts on geom2 (the scene)
            elif g2 in sensor and g1 in scene:
                sign = -1.0
            else:
                continue
            mujoco.mj_contactForce(m, d, i, f6)
            frame = d.contact.frame[i].reshape(3, 3)
            f = sign * (frame.T @ f6[:3])
            h[:3] += f
            h[3:] += np.cross(d.contact.pos[i] - p_e, f) + sign * (frame.T @ f6[3:])
        return h

    def contacts(self, x: np.ndarray) -> list[MujocoContact]:
        """Every MuJoCo contact at state x (robot–scene and robot–robot)."""
        self._forward(x)
        mujoco, m, d = import_mujoco(), self.model, self.data
        out, f6 = [], np.zeros(6)
        for i in range(d.ncon):
            g1, g2 = d.contact.geom[i]
            mujoco.mj_contactForce(m, d, i, f6)
            frame = d.contact.frame[i].reshape(3, 3)
            out.append(MujocoContact(mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g1) or f"geom{g1}",
                                     mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g2) or f"geom{g2}",
                                     d.contact.pos[i].copy(), float(-d.contact.dist[i]), frame.T @ f6[:3]))
        return out

    def contact_signals(self, t: float, x: np.ndarray, u: Any = None) -> dict[str, float]:
        """For ``simulate(..., log=plant.contact_signals)``: the number of robot–scene and self contacts and the
        deepest penetration [m] at each sample."""
        self._forward(x)
        d, scene = self.data, self._scene_geom_ids
        with_scene = self_contacts = 0
        deepest = 0.0
        for i in range(d.ncon):
            g1, g2 = d.contact.geom[i]
            if g1 in scene or g2 in scene:
                with_scene += 1
            else:
                self_contacts += 1
            deepest = max(deepest, float(-d.contact.dist[i]))
        return {"scene_contacts": float(with_scene), "self_contacts": float(self_contacts), "penetration": deepest}

    def clearance(self, x: np.ndarray, distmax: float = 1.0) -> float:
        """The smallest signed distance [m] between the robot's moving shapes and the scene's geoms at state x
        (MuJoCo's ``mj_geomDistance``, convex hulls for meshes; negative in penetration; ``distmax`` when all are
        farther)."""
        self._forward(x)
        mujoco, m, d = import_mujoco(), self.model, self.data
        robot = [g for g in range(m.ngeom) if m.geom_group[g] == _ROBOT_GROUP and m.body_weldid[m.geom_bodyid[g]] != 0]
        return min((mujoco.mj_geomDistance(m, d, g, s, distmax, None) for g in robot for s in self._scene_geom_ids),
                   default=distmax)

    # ---- dynamics, for the cross-validation ---------------------------------------------------------

    def inertia_matrix(self, q: Any) -> np.ndarray:
        """MuJoCo's joint-space inertia B(q) (``mj_fullM`` of ``qM``), armature included."""
        mujoco, m, d = import_mujoco(), self.model, self.data
        d.qpos[:] = self._positions(as_vector(q, self.nq, "q"))
        mujoco.mj_fwdPosition(m, d)
        M = np.zeros((m.nv, m.nv))
        try:
            mujoco.mj_fullM(m, d, M)            # MuJoCo 4: (model, data, destination)
        except TypeError:
            mujoco.mj_fullM(m, M, d.qM)         # MuJoCo 3: (model, destination, sparse qM)
        return M

    def bias_forces(self, q: Any, qd: Any) -> np.ndarray:
        """MuJoCo's bias forces C(q, q̇) q̇ + g(q) (``qfrc_bias``, by its recursive Newton–Euler)."""
        mujoco, m, d = import_mujoco(), self.model, self.data
        d.qpos[:] = self._positions(as_vector(q, self.nq, "q"))
        d.qvel[:] = as_vector(qd, self.n, "qd")
        mujoco.mj_fwdPosition(m, d)
        mujoco.mj_fwdVelocity(m, d)
        return d.qfrc_bias.copy()

    def __repr__(self) -> str:
        scene = ", ".join(type(o).__name__ for o in self.scene) or "none"
        return (f"MujocoPlant({self.robot.name!r}, n={self.n}, scene: {scene}, integrator={self.integrator}, "
                f"timestep={'the loop h' if self.timestep is None else f'{self.timestep:g} s'}, "
                f"force sensor: {'yes' if self.force_sensor else 'no'})")
