"""Robots: a Pinocchio model + data + named frames + geometry + the URDF it came from, and ``load()``.

``load("planar_2r")`` loads one of the book's robots from ``urdf/`` (rebuilt from its DH table in
:mod:`rigid_body.book_robots` when a parameter is changed: ``load("planar_2r", a=(1.0, 0.8))``),
``load("panda")`` one of the robots shipped by the ``example-robot-data`` wheel, ``load("path/to/robot.urdf")``
any URDF file. ``load(..., payload=m)`` adds a point mass at the end effector of any of them
(:func:`with_payload`). :func:`robot_from_dh` builds a Robot from any DH table.
"""

from __future__ import annotations

import difflib
import math
import os
import re
import sys
import threading
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import pinocchio as pin

from rigid_body.book_robots import BOOK_ROBOTS, DH_ROBOTS, URDF_DIR, book_robot_spec
from rigid_body.dh import GRAVITY, DHLink, as_links, urdf_from_dh
from rigid_body.validation import as_positive

__all__ = [
    "Robot", "JointFriction", "load", "available", "with_payload", "robot_from_dh", "robot_from_urdf_string",
    "example_robot_data_dir", "joint_kind", "joint_units", "revolute_joints", "model_frame_id", "URDF_DIR", "EXAMPLE_ROBOTS",
]

# example-robot-data: name → (urdf file relative to robots/, end-effector frame); the Panda's
# gripper fingers are locked at 0 so that ``load("panda")`` is the 7-DOF arm.
EXAMPLE_ROBOTS: dict[str, tuple[str, str]] = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_hand"),
    "ur3": ("ur_description/urdf/ur3_robot.urdf", "tool0"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", "tool0"),
    "kinova": ("kinova_description/robots/kinova.urdf", "j2s6s200_end_effector"),
    "z1": ("z1_description/urdf/z1.urdf", "link06"),
    "double_pendulum": ("double_pendulum_description/urdf/double_pendulum_simple.urdf", "link2"),
}
LOCKED_JOINTS: dict[str, tuple[str, ...]] = {"panda": ("panda_finger_joint1", "panda_finger_joint2")}
#: Named configurations of the real robots, inside their joint limits and away from singularities [rad]:
#: the Panda's ``ready`` is Franka's own start pose; the UR arms' ``home`` has the elbow bent and the tool down.
_UR_HOME = (0.0, -np.pi / 2, np.pi / 2, -np.pi / 2, -np.pi / 2, 0.0)
EXAMPLE_CONFIGURATIONS: dict[str, dict[str, tuple[float, ...]]] = {
    "panda": {"ready": (0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4)},
    "ur3": {"home": _UR_HOME},
    "ur5": {"home": _UR_HOME},
    "ur10": {"home": _UR_HOME},
}

Geometry = tuple[pin.GeometryModel, pin.GeometryModel]  # (collision, visual)
_AXES = {"X": np.array([1.0, 0.0, 0.0]), "Y": np.array([0.0, 1.0, 0.0]), "Z": np.array([0.0, 0.0, 1.0])}


def model_frame_id(model: pin.Model, frame: str | int | np.integer) -> int:
    """The id of ``frame`` in ``model``, checked: an integer id in [0, nframes) or an existing frame name.

    Pinocchio's bindings do not check ids (an id out of range reads garbage), so every frame argument
    goes through here. ValueError names ``frame`` and the valid range, or the nearest frame names.
    """
    if isinstance(frame, (int, np.integer)) and not isinstance(frame, bool):
        if not 0 <= frame < model.nframes:
            raise ValueError(f"`frame` id {frame} out of range [0, {model.nframes}) of model {model.name!r}")
        return int(frame)
    if not isinstance(frame, str):
        raise ValueError(f"`frame` must be a frame name or an integer id, got {frame!r}")
    if not model.existFrame(frame):
        names = [f.name for f in model.frames]
        containing = sorted((n for n in names if frame.lower() in n.lower()), key=len)  # "hand" → "panda_hand"
        near = list(dict.fromkeys(containing + difflib.get_close_matches(frame, names, n=5)))[:5]
        hint = f"nearest: {near}" if near else f"its frames: {names}"
        raise ValueError(f"`frame`: model {model.name!r} has no frame {frame!r}; {hint}")
    return model.getFrameId(frame)


def joint_kind(model: pin.Model, i: int) -> tuple[str, np.ndarray | None]:
    """Kind of joint ``i`` — ``"revolute"``, ``"prismatic"``, ``"revolute_unbounded"``, ``"mimic"``
    or ``"universe"`` — and its unit axis in the joint frame (None for the last two).

    Raises ValueError for the joint types the book's arms do not have (free-flyer, spherical, ...).
    """
    if i == 0:
        return "universe", None
    jmodel = model.joints[i]
    name = jmodel.shortname().replace("JointModel", "")
    if name == "Mimic":
        return "mimic", None
    if name in ("RX", "RY", "RZ"):
        return "revolute", _AXES[name[1]].copy()
    if name in ("PX", "PY", "PZ"):
        return "prismatic", _AXES[name[1]].copy()
    if name in ("RUBX", "RUBY", "RUBZ"):
        return "revolute_unbounded", _AXES[name[3]].copy()
    if name == "RevoluteUnaligned":
        return "revolute", np.asarray(jmodel.extract().axis, dtype=float).copy()
    if name == "PrismaticUnaligned":
        return "prismatic", np.asarray(jmodel.extract().axis, dtype=float).copy()
    raise ValueError(f"joint {model.names[i]!r} of type {name} is not supported (revolute and prismatic joints only)")


@dataclass(frozen=True)
class JointFriction:
    """Joint friction at the link side, per joint (nv,): τ_f = F_v q̇ + F_s+ for q̇ > 0, F_v q̇ − F_s− for q̇ < 0.

    The book's F_v q̇ + F_s sgn(q̇) of (7.42) when F_s+ = F_s− = F_s. ``viscous`` F_v [N·m·s/rad];
    ``coulomb_positive``/``coulomb_negative`` the magnitudes F_s+/F_s− [N·m] (measured data such as the
    Puma 560's differ with the direction). Evaluated by :func:`rigid_body.dynamics.friction_torques`.
    """

    viscous: np.ndarray
    coulomb_positive: np.ndarray
    coulomb_negative: np.ndarray

    @classmethod
    def from_model(cls, model: pin.Model) -> "JointFriction":
        """From Pinocchio's ``model.damping`` (F_v) and ``model.friction`` (F_s), read from URDF ``<dynamics>``."""
        Fs = np.array(model.friction, dtype=float)
        return cls(np.array(model.damping, dtype=float), Fs, Fs.copy())

    @classmethod
    def from_links(cls, links: Sequence[DHLink]) -> "JointFriction":
        """From a DH table's ``viscous_friction`` and ``coulomb_friction`` fields."""
        pairs = np.array([link.coulomb_pair for link in links], dtype=float).reshape(-1, 2)
        return cls(np.array([link.viscous_friction for link in links], dtype=float), pairs[:, 0], pairs[:, 1])

    @property
    def is_zero(self) -> bool:
        return not (np.any(self.viscous) or np.any(self.coulomb_positive) or np.any(self.coulomb_negative))


class Configurations(dict):
    """``robot.configurations``: a dict of named joint configurations whose missing key lists the names."""

    def __missing__(self, key: str) -> np.ndarray:
        raise KeyError(f"no configuration named {key!r}; this robot has {sorted(self)}")


@dataclass
class Robot:
    """A Pinocchio model with its data, end-effector frame, geometry and source URDF.

    Attributes
    ----------
    name : the robot's name.
    model : the ``pin.Model``.
    data : a ``pin.Data`` for ``model`` (scratch space of the algorithms), one per thread: the thread
        that builds the Robot gets the one given, every other thread its own ``model.createData()`` on
        first use. So the functions taking a Robot may be called from several threads at once; objects
        that keep ``robot.data`` (controllers, plants) belong to the thread that made them.
    ee_frame : id of the end-effector frame (``ee`` for the book's robots).
    urdf_path : the URDF file, or None for a model built in memory.
    urdf_xml : the URDF text the model was built from.
    configurations : named joint configurations, all within the joint limits: ``"neutral"`` (Pinocchio's
        neutral moved onto the limits; often singular — the Panda's stands stretched upright with q₄ on its limit,
        a dead start for the local IK ``solve_clik``: start from ``"ready"``) for every robot, the Panda's ``"ready"``, the UR
        arms' ``"home"``, the Puma 560's ``"qz"``, ``"qr"``, ``"qs"``, ``"qn"``, and for each book robot
        at least one non-singular posture, the manual's where it gives one (``planar_2r``:
        ``"p8_10_target"``, ``"p8_15_start"``; ``scara``: ``"p5_7_camera"``; ``planar_pr``: ``"fig_s7_2"``),
        otherwise an illustrative one (``"bent"``, ``"mid_stroke"``, ``"extended"``, ...).
    friction : the joint friction (:class:`JointFriction`); by default Pinocchio's ``model.damping`` and
        ``model.friction`` (URDF ``<dynamics>``); a DH table's friction fields for :func:`robot_from_dh`.
    geometry_loader : builds ``(collision, visual)`` geometry models on first use (meshes take ~0.5 s).
    collision_model, visual_model : ``pin.GeometryModel`` of the URDF's ``<collision>`` / ``<visual>``
        shapes, empty when the URDF has none.
    """

    name: str
    model: pin.Model
    data: pin.Data
    ee_frame: int
    urdf_path: Path | None = None
    urdf_xml: str = ""
    configurations: dict[str, np.ndarray] = field(default_factory=Configurations)
    geometry_loader: Callable[[], Geometry] | None = field(default=None, repr=False)
    friction: JointFriction | None = field(default=None, repr=False)

    @property
    def nq(self) -> int:
        return self.model.nq

    @property
    def nv(self) -> int:
        return self.model.nv

    has_mimic: bool = field(init=False)
    _geometry: Geometry | None = field(init=False, default=None, repr=False)

    _local: threading.local = field(init=False, repr=False, compare=False)
    #: Objects built once per robot by other layers and kept as long as it lives (e.g. the default IK
    #: solver of each frame, ``planners.inverse_kinematics.solve_ik``).
    derived: dict = field(init=False, default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        # True when the model has mimic joints (the book's rotors): ABA is then unavailable.
        self.has_mimic = len(getattr(self.model, "mimicking_joints", ())) > 0
        if not isinstance(self.configurations, Configurations):
            self.configurations = Configurations(self.configurations)
        if self.friction is None:
            self.friction = JointFriction.from_model(self.model)

    def __repr__(self) -> str:
        """One line: name, sizes, end effector, named configurations, motors and mass (not the URDF)."""
        mass = sum(inertia.mass for inertia in self.model.inertias)
        extra = ", rotors" if self.has_mimic else ""
        return (f"Robot({self.name!r}, nq={self.nq}, nv={self.nv}, ee={self.model.frames[self.ee_frame].name!r}, "
                f"configurations={sorted(self.configurations)}, mass={mass:.4g} kg{extra})")

    def __getstate__(self) -> dict:  # copy.deepcopy: the calling thread's data, not the thread-local store
        state = {k: v for k, v in self.__dict__.items() if k != "_local"}
        state["data"] = self.data
        return state

    def __setstate__(self, state: dict) -> None:
        state = dict(state)
        data = state.pop("data")
        self.__dict__.update(state)
        self.data = data

    def frame_id(self, name: str) -> int:
        """Id of the frame ``name``; ValueError with the nearest frame names when it does not exist."""
        return model_frame_id(self.model, name)

    def frame(self, frame: str | int | np.integer | None = None) -> int:
        """Id of ``frame`` (a name or an id, checked); None means the end effector."""
        return self.ee_frame if frame is None else model_frame_id(self.model, frame)

    def _geometry_models(self) -> Geometry:
        if self._geometry is None:
            empty = (pin.GeometryModel(), pin.GeometryModel())
            self._geometry = self.geometry_loader() if self.geometry_loader is not None else empty
        return self._geometry

    @property
    def collision_model(self) -> pin.GeometryModel:
        return self._geometry_models()[0]

    @property
    def visual_model(self) -> pin.GeometryModel:
        return self._geometry_models()[1]

    @property
    def lower(self) -> np.ndarray:
        return np.array(self.model.lowerPositionLimit)

    @property
    def upper(self) -> np.ndarray:
        return np.array(self.model.upperPositionLimit)

    def random_configuration(self, rng: np.random.Generator) -> np.ndarray:
        """A configuration drawn uniformly within the joint limits (limits clipped to ±π)."""
        lo = np.maximum(self.lower, -np.pi)
        hi = np.minimum(self.upper, np.pi)
        return rng.uniform(lo, hi)


def _thread_data(self: Robot) -> pin.Data:
    try:
        return self._local.data
    except AttributeError:  # first use in this thread
        data = self._local.data = self.model.createData()
        return data


def _set_data(self: Robot, data: pin.Data) -> None:
    if "_local" not in self.__dict__:
        self._local = threading.local()
    self._local.data = data


# ``data`` is a dataclass field (so Robot(..., data=...) sets it) read through a per-thread property.
Robot.data = property(_thread_data, _set_data, doc="The calling thread's ``pin.Data`` for ``model``.")


_INERTIA_TOL = 1e-9  # symmetry / positive semi-definiteness of an inertia tensor [kg·m²]
_INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


def _urdf_number(text: str | None, link: str, field: str) -> float:
    try:
        value = float(text if text is not None else "0")
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise ValueError(f"URDF link {link!r}: `{field}` must be a finite number, got {text!r}")
    return value


def _check_inertia(mass: float, inertia: np.ndarray, where: str) -> None:
    if mass < 0:
        raise ValueError(f"{where}: `mass` must be non-negative, got {mass:g}")
    asym = np.abs(inertia - inertia.T).max()
    lowest = np.linalg.eigvalsh(0.5 * (inertia + inertia.T)).min()
    if asym > _INERTIA_TOL or lowest < -_INERTIA_TOL:
        raise ValueError(f"{where}: `inertia` must be symmetric positive semi-definite, got {inertia.tolist()}")


def _check_urdf_text(xml: str, source: str) -> None:
    """ValueError naming ``source`` unless ``xml`` is well-formed XML whose root is ``<robot>`` with a ``<link>``
    (Pinocchio's parser would raise a bare error, or print to the C++ stderr, without the file's name)."""
    if not isinstance(xml, str) or not xml.strip():
        raise ValueError(f"{source}: empty, not a URDF (no <robot> element)")
    try:
        root = ET.fromstring(xml)
    except ET.ParseError as err:
        raise ValueError(f"{source}: malformed URDF XML ({err})") from None
    if root.tag != "robot":
        raise ValueError(f"{source}: not a URDF: the root element is <{root.tag}>, not <robot>")
    if root.find("link") is None:
        raise ValueError(f"{source}: a URDF robot needs at least one <link>")


def _declared_inertials(xml: str) -> float:
    """Check every ``<inertial>`` of the URDF text (finite numbers, mass ≥ 0, inertia PSD) and return the total mass.

    Pinocchio's URDF parser (urdfdom) drops an ``<inertial>`` it cannot read (``mass="nan"``, a
    malformed number) with only a line on the C++ stderr, leaving the link massless: checked here first.
    """
    total = 0.0
    for link in ET.fromstring(xml).iter("link"):
        name = link.get("name", "?")
        inertial = link.find("inertial")
        if inertial is None:
            continue
        mass_el, inertia_el, origin_el = inertial.find("mass"), inertial.find("inertia"), inertial.find("origin")
        mass = _urdf_number(None if mass_el is None else mass_el.get("value"), name, "mass")
        if origin_el is not None:
            for key in ("xyz", "rpy"):
                for v in (origin_el.get(key) or "0 0 0").split():
                    _urdf_number(v, name, f"origin {key}")
        v = {k: _urdf_number(None if inertia_el is None else inertia_el.get(k), name, k) for k in _INERTIA_KEYS}
        inertia = np.array([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]],
                            [v["ixz"], v["iyz"], v["izz"]]])
        _check_inertia(mass, inertia, f"URDF link {name!r}")
        total += mass
    return total


def _check_model_inertias(model: pin.Model, declared_mass: float) -> None:
    """Every body inertia of ``model`` physical (finite, mass ≥ 0, inertia symmetric PSD), and no declared mass lost."""
    total = 0.0
    for i in range(model.njoints):  # 0: the links fixed to the base (universe)
        body = model.inertias[i]
        mass, lever, inertia = float(body.mass), np.asarray(body.lever), np.asarray(body.inertia)
        if not (math.isfinite(mass) and np.isfinite(lever).all() and np.isfinite(inertia).all()):
            raise ValueError(f"model {model.name!r}: body of joint {model.names[i]!r} has a non-finite inertia")
        _check_inertia(mass, inertia, f"model {model.name!r}, body of joint {model.names[i]!r}")
        total += mass
    if abs(total - declared_mass) > 1e-9 * max(1.0, declared_mass):
        raise ValueError(f"model {model.name!r}: the URDF declares {declared_mass:g} kg of links but the "
                         f"model has {total:g} kg (an <inertial> was dropped by the URDF parser)")


def _build(xml: str, gravity: Any | None, name: str, ee: str | None, path: Path | None,
           lock: tuple[str, ...] = (), package_dirs: Sequence[str] = ()) -> Robot:
    """The Robot of URDF text ``xml``: rotors kept as mimic joints, joints ``lock`` fixed at 0 (model and geometry).
    ValueError naming the file (``path``, or the robot's name for text) when the text is not a URDF."""
    source = str(path) if path is not None else f"the URDF text of {name!r}"
    _check_urdf_text(xml, source)
    try:
        declared_mass = _declared_inertials(xml)
        model = pin.buildModelFromXML(xml, mimic=not lock)
    except (ValueError, RuntimeError) as err:
        raise ValueError(f"{source}: {err}") from None
    model.name = name
    _check_model_inertias(model, declared_mass)
    lock_ids = [model.getJointId(j) for j in lock if model.existJointName(j)]
    full_model = model
    if lock_ids:
        model = pin.buildReducedModel(full_model, lock_ids, pin.neutral(full_model))
    model.name = name
    if gravity is not None:
        g = np.asarray(gravity, dtype=float)
        if g.shape != (3,) or not np.all(np.isfinite(g)):
            raise ValueError(f"`gravity` must be a finite (3,) vector, got {gravity!r}")
        model.gravity = pin.Motion(g, np.zeros(3))
    if ee is None:
        ee = "ee" if model.existFrame("ee") else model.frames[len(model.frames) - 1].name
    if not model.existFrame(ee):
        raise ValueError(f"robot {name!r}: end-effector frame {ee!r} not found")

    def geometry() -> Geometry:
        dirs = [str(d) for d in package_dirs]
        col, vis = (pin.buildGeomFromUrdfString(full_model, xml, kind, package_dirs=dirs)
                    for kind in (pin.GeometryType.COLLISION, pin.GeometryType.VISUAL))
        if lock_ids:  # the locked joints' bodies are merged into their parents: so are their shapes
            _, (col, vis) = pin.buildReducedModel(full_model, [col, vis], lock_ids, pin.neutral(full_model))
        return col, vis

    robot = Robot(name=name, model=model, data=model.createData(), ee_frame=model.getFrameId(ee),
                  urdf_path=path, urdf_xml=xml, geometry_loader=geometry)
    # Pinocchio's neutral (all zeros for revolute joints) moved onto the joint limits where it lies
    # outside them (the Panda's q4 ≤ −0.07 rad, a prismatic joint's minimum stroke): a valid start.
    robot.configurations["neutral"] = np.clip(pin.neutral(model), model.lowerPositionLimit, model.upperPositionLimit)
    return robot


def robot_from_urdf_string(xml: str, gravity: Any | None = GRAVITY, name: str | None = None,
                           ee: str | None = None) -> Robot:
    """Build a Robot from URDF text, keeping ``<mimic>`` joints (the book's rotors)."""
    if name is None:
        match = re.search(r'<robot[^>]*name="([^"]+)"', xml)
        name = match.group(1) if match else "robot"
    return _build(xml, gravity, name, ee, None)


def robot_from_dh(links: Sequence[DHLink | Mapping[str, Any]], gravity: Any = GRAVITY,
                  name: str = "dh_robot", payload: float = 0.0, tool: np.ndarray | None = None,
                  convention: str = "standard", base: np.ndarray | None = None, motors: str = "rotors") -> Robot:
    """A Robot from a DH table (through its URDF, :func:`rigid_body.dh.urdf_from_dh`).

    ``gravity`` [m/s²] is given in the world frame (= DH frame 0 without ``base``) and defaults to
    (0, 0, −9.81): along −z₀. A planar arm whose DH axes z_i are all parallel to z₀ then moves in a
    horizontal plane and has zero gravity torques; the book draws its planar arms in a vertical plane
    with gravity along −y₀ (``load("planar_2r")`` uses it): pass ``gravity=[0, -9.81, 0]``.
    Each link is a :class:`~rigid_body.dh.DHLink` (or a dict of its fields): ``mass`` at ``com``
    with ``inertia`` about it (``None``: a point mass), in DH frame i.

    ``payload`` is a point mass [kg] at the origin of the last DH frame (:func:`with_payload`); ``tool``
    the constant transform from the last DH frame to the end-effector frame ``ee``; ``base`` the constant
    transform from the world (root link ``base``, where ``gravity`` is given) to DH frame 0.
    ``convention``: ``"standard"`` (the book's DH, (2.52)) or ``"modified"`` (Craig's).

    ``motors`` chooses the motor model of links with motor data (Sect. 7.3):

    * ``"rotors"`` (the book's): rotor i is a body carried by link i−1 spinning at k_ri q̇_i (mimic joints);
      B(q) holds every coupling term of (7.32). CRBA/RNEA work, ABA does not (forward dynamics by Cholesky).
    * ``"armature"`` (the Robotics Toolbox's J_m G², Pinocchio's ``model.armature``): B(q) = B_links(q) +
      diag(k_ri² I_mi), the rotor's mass and transverse moments riding on link i−1; the gyroscopic couplings
      k_ri I_mi z_{i−1}ᵀ ω_{i−1} of the book's model are dropped (small beside k_r² I_m for large k_r).
      No mimic joints: forward dynamics uses ABA.

    >>> arm = robot_from_dh([dict(a=1.0), dict(a=1.0)])
    >>> arm.model.nq
    2
    """
    links = as_links(links)
    xml = urdf_from_dh(links, name=name, tool=tool, convention=convention, base=base, motors=motors)
    robot = _build(xml, gravity, name, "ee", None)
    robot.friction = JointFriction.from_links(links)
    if motors == "armature":
        _set_armature(robot, links)
    return _with_dh_payload(robot, payload)


def _set_armature(robot: Robot, links: Sequence[DHLink]) -> None:
    """model.armature[joint i] = k_ri² I_mi (the rotor's spin moment reflected through the gear)."""
    armature = np.zeros(robot.nv)
    for i, link in enumerate(links, start=1):
        if link.has_motor:
            jid = robot.model.getJointId(link.name or f"joint_{i}")
            armature[robot.model.joints[jid].idx_v] = link.gear_ratio ** 2 * link.rotor_inertia[2, 2]
    robot.model.armature = armature


def _with_dh_payload(robot: Robot, payload: float) -> Robot:
    """A DH robot with its payload at the origin of the last DH frame (the book's tip load)."""
    if payload == 0:
        return robot
    last = max(int(f.name[6:]) for f in robot.model.frames if re.fullmatch(r"frame_\d+", f.name))
    return with_payload(robot, payload, f"frame_{last}")


def with_payload(robot: Robot, mass: float, frame: str | int | None = None) -> Robot:
    """A copy of ``robot`` carrying a point mass ``mass`` [kg] at the origin of ``frame`` (default the end effector).

    The mass is added to the inertia of the body that carries the frame, so B(q), C(q, q̇) and g(q)
    of the copy are those of the arm with the payload (Sect. 7.2.2, a concentrated load). Works on
    any Robot (the book's, example-robot-data's, a URDF file's); the geometry is shared.
    """
    if not (np.ndim(mass) == 0 and np.isfinite(mass) and mass >= 0):
        raise ValueError(f"`mass` must be a non-negative payload [kg], got {mass!r}")
    fid = robot.frame(frame)
    model = robot.model.copy()
    f = model.frames[fid]
    model.inertias[f.parentJoint] = model.inertias[f.parentJoint] + pin.Inertia(
        float(mass), f.placement.translation.copy(), np.zeros((3, 3)))
    loaded = Robot(name=f"{robot.name}+{mass:g}kg", model=model, data=model.createData(),
                   ee_frame=robot.ee_frame, urdf_path=None, urdf_xml=robot.urdf_xml,
                   configurations=dict(robot.configurations), geometry_loader=robot._geometry_models,
                   friction=robot.friction)
    return loaded


def joint_units(robot: Robot) -> list[str]:
    """The unit of each joint variable (nv,): ``"rad"`` for a revolute joint, ``"m"`` for a prismatic one
    (other joint types, e.g. a planar base, count as ``"rad"`` only where they are revolute)."""
    units = ["rad"] * robot.nv
    for i in range(1, robot.model.njoints):
        try:
            kind, _ = joint_kind(robot.model, i)
        except ValueError:
            continue
        if kind == "prismatic":
            units[robot.model.joints[i].idx_v] = "m"
    return units


def revolute_joints(robot: Robot) -> np.ndarray:
    """Boolean mask (nq,) of the configuration entries that are revolute angles (defined modulo 2π)."""
    mask = np.zeros(robot.nq, dtype=bool)
    for i in range(1, robot.model.njoints):
        kind, _ = joint_kind(robot.model, i)
        if kind == "revolute":
            mask[robot.model.joints[i].idx_q] = True
    return mask


def example_robot_data_dir() -> Path:
    """Where the ``example-robot-data`` wheel installs its robots (no Python loader is shipped)."""
    candidates = [Path(p) / "cmeel.prefix" / "share" / "example-robot-data" / "robots" for p in sys.path if p]
    candidates.append(Path(sys.prefix) / "share" / "example-robot-data" / "robots")
    for c in candidates:
        if c.is_dir():
            return c
    raise FileNotFoundError("example-robot-data is not installed: `pip install example-robot-data`")


def _load_example_robot(name: str) -> Robot:
    rel, ee = EXAMPLE_ROBOTS[name]
    root = example_robot_data_dir()
    path = root / rel
    if not path.is_file():
        raise FileNotFoundError(f"example-robot-data has no {rel} (looked in {root})")
    # Meshes are package://example-robot-data/robots/...: the package directory is the ``share`` above it.
    robot = _build(path.read_text(), GRAVITY, name, ee, path, LOCKED_JOINTS.get(name, ()),
                   package_dirs=(root.parent.parent,))
    robot.configurations.update({k: np.array(v) for k, v in EXAMPLE_CONFIGURATIONS.get(name, {}).items()})
    return robot


def available() -> list[str]:
    """Names accepted by :func:`load`: the book's robots, named DH robots (the Puma 560) and the
    example-robot-data robots."""
    return sorted(BOOK_ROBOTS) + sorted(DH_ROBOTS) + sorted(EXAMPLE_ROBOTS)


def _with_table_configurations(robot: Robot, configurations: dict[str, tuple[float, ...]]) -> Robot:
    """Add a table's named configurations to ``robot``, leaving out any that changed parameters (a shorter
    stroke, ``load("scara", d3_range=(0.2, 1.0))``) put outside the joint limits."""
    for key, value in configurations.items():
        q = np.array(value, dtype=float)
        if np.all(q >= robot.model.lowerPositionLimit) and np.all(q <= robot.model.upperPositionLimit):
            robot.configurations[key] = q
    return robot


def load(name_or_path: str | os.PathLike, payload: float = 0.0, **params: Any) -> Robot:
    """Load a robot by name (book or example-robot-data) or from a URDF path.

    ``payload`` [kg] is a point mass at the end effector (for the book's robots: the origin of the last
    DH frame), added by :func:`with_payload`. Other keyword parameters change the book robot's data
    (link lengths ``a``, ...) and rebuild it from its DH table; without them the committed URDF file
    in ``urdf/`` is used. ``load("puma560")`` builds the Puma 560 from its DH table with the Toolbox's
    armature motor model; ``load("puma560", motors="rotors")`` with the book's rotors.

    >>> load("planar_2r").model.nq
    2
    """
    payload = as_positive(payload, "payload", allow_zero=True)  # [kg]
    key = str(name_or_path)
    if key in DH_ROBOTS:
        spec = book_robot_spec(key, payload=payload, **params)
        robot = robot_from_dh(spec.links, gravity=spec.gravity, name=key, motors=spec.motors)
        return _with_dh_payload(_with_table_configurations(robot, spec.configurations), spec.payload)
    if key in BOOK_ROBOTS:
        spec = book_robot_spec(key, payload=payload, **params)
        path = URDF_DIR / f"{key}.urdf"
        if not params and path.is_file():
            robot = _build(path.read_text(), spec.gravity, key, "ee", path)
        else:
            robot = _build(spec.urdf(), spec.gravity, key, "ee", None)
        return _with_dh_payload(_with_table_configurations(robot, spec.configurations), spec.payload)
    if params:
        raise ValueError(f"parameters {sorted(params)} change a book robot's table (load(name, a=..., ...) for "
                         f"{', '.join(sorted(BOOK_ROBOTS) + sorted(DH_ROBOTS))}); {key!r} takes only `payload`")
    if key in EXAMPLE_ROBOTS:
        robot = _load_example_robot(key)
    else:
        path = Path(key)
        if path.suffix == ".urdf" or os.sep in key:
            if not path.is_file():
                raise FileNotFoundError(f"no URDF file at {path}")
            robot = _build(path.read_text(), GRAVITY, path.stem, None, path, package_dirs=(path.parent,))
        else:
            names = available()
            near = difflib.get_close_matches(key, names, n=3)
            hint = f" Did you mean {', '.join(near)}?" if near else ""
            raise ValueError(f"unknown robot {key!r}.{hint} Available: {', '.join(names)}, "
                             "or a path to a .urdf file")
    return with_payload(robot, payload) if payload else robot
