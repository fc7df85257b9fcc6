"""Denavit–Hartenberg tables: homogeneous transforms (2.52) and DH table → URDF → Pinocchio.

A serial arm is a list of :class:`DHLink` (or dicts with the same keys). The URDF written by
:func:`urdf_from_dh` has one link ``frame_i`` per DH frame i (``frame_0`` is the base frame), so
that the Pinocchio frame ``frame_i`` is the product of the book's A matrices ``A_1^0 ... A_i^{i-1}``.

URDF layout of joint i:

* revolute: joint ``joint_i`` at DH frame i−1, origin ``Rz(theta_i)``, axis z; then a fixed joint
  ``Tz(d_i) Tx(a_i) Rx(alpha_i)`` to ``frame_i``;
* prismatic: joint ``joint_i`` at DH frame i−1, origin ``Tz(d_i) Rz(theta_i)``, axis z; then a fixed
  joint ``Tx(a_i) Rx(alpha_i)`` to ``frame_i``.

Modified (proximal, Craig) DH, ``convention="modified"``: row i holds (a_{i−1}, α_{i−1}, d_i, θ_i) and
frame i sits on joint axis i: A_i^{i−1} = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i) Tz(d_i)
(:func:`modified_dh_transform`); ``com`` and ``inertia`` are then in that frame. Joint ``joint_i`` has
origin A_i^{i−1}(0) and axis z, its child is frame i itself.

Motors follow the book (Sect. 7.3): rotor i is carried by link i−1, sits on joint axis i at the
origin of frame i−1 and spins at ``k_ri q̇_i``. In URDF it is a link ``rotor_i`` on a revolute joint
``rotor_i_joint`` that ``<mimic>``s ``joint_i`` with multiplier ``k_ri`` (load with ``mimic=True``).
With ``motors="armature"`` (the Robotics Toolbox's model) the rotor is a fixed part of link i−1
carrying its mass and transverse moments only; its spin moment enters as the armature k_ri² I_mi that
:func:`rigid_body.robots.robot_from_dh` puts in ``model.armature`` (URDF has no armature tag).

Friction at joint i (link side, the book's F_v q̇ + F_s sgn(q̇) of (7.42)) is written as the joint's
``<dynamics damping="F_v" friction="F_s">``, which Pinocchio reads into ``model.damping``/``model.friction``.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Eq. (2.52), Sect. 2.8.2; Sect. 7.3 (motor model); Eq. (7.42) (friction). J. J. Craig, *Introduction to
Robotics*, 3rd ed., Sect. 3.4 (modified DH).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

from rigid_body.rotations import as_homogeneous
from rigid_body.validation import as_matrix, as_scalar, as_vector

JOINT_TYPES = ("revolute", "prismatic")
CONVENTIONS = ("standard", "modified")
MOTOR_MODELS = ("rotors", "armature")
G = 9.81  # m/s², the book's gravitational acceleration (one constant for every model and problem)
GRAVITY = (0.0, 0.0, -G)  # g₀ in the base frame of a robot whose z₀ points up


def dh_transform(a: float, alpha: float, d: float, theta: float) -> np.ndarray:
    """A_i^{i-1} = Rz(theta) Tz(d) Tx(a) Rx(alpha), Eq. (2.52); returns a (4, 4) array.

    ValueError naming the argument when one is not a finite number.
    """
    try:
        finite = math.isfinite(a + alpha + d + theta)  # one test on the fast path (NaN and ±inf propagate)
    except TypeError:
        finite = False
    if not finite:
        for key, value in (("a", a), ("alpha", alpha), ("d", d), ("theta", theta)):
            as_scalar(value, key)
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([
        [ct, -st * ca, st * sa, a * ct],
        [st, ct * ca, -ct * sa, a * st],
        [0.0, sa, ca, d],
        [0.0, 0.0, 0.0, 1.0],
    ])


def modified_dh_transform(a: float, alpha: float, d: float, theta: float) -> np.ndarray:
    """Craig's A_i^{i−1} = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i) Tz(d_i) (modified DH); ``a``, ``alpha`` are row i's
    a_{i−1}, α_{i−1}. Returns a (4, 4) array."""
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([
        [ct, -st, 0.0, a],
        [st * ca, ct * ca, -sa, -sa * d],
        [st * sa, ct * sa, ca, ca * d],
        [0.0, 0.0, 0.0, 1.0],
    ])


def _check_convention(convention: str) -> None:
    if convention not in CONVENTIONS:
        raise ValueError(f"`convention` must be one of {CONVENTIONS}, got {convention!r}")


@dataclass(frozen=True)
class DHLink:
    """One row of a DH table with the link's inertial and motor data (SI units).

    ``theta`` (revolute) and ``d`` (prismatic) are the offsets added to the joint variable.
    ``com`` is the centre of mass in DH frame i, ``inertia`` the 3×3 inertia about the com in
    DH frame i; ``inertia=None`` (the default) makes the link a point mass at ``com``.
    ``joint`` is ``"revolute"`` or ``"prismatic"``. ``motor_inertia`` is the rotor's moment about its spin axis (or a 3×3 tensor in the
    rotor frame, z = spin axis), ``motor_mass`` its mass, ``gear_ratio`` the book's k_r.
    ``viscous_friction`` F_v [N·m·s/rad] and ``coulomb_friction`` F_s [N·m] act at the joint (link side,
    (7.42)); F_s is a magnitude, or a pair (F_s+, F_s−) of magnitudes for q̇ > 0 and q̇ < 0. Friction
    measured at the motor reflects through the gear: :func:`joint_friction_from_motor`.
    In the modified convention ``a``, ``alpha`` are a_{i−1}, α_{i−1} and ``com``, ``inertia`` are in
    Craig's frame i (on joint axis i).
    """

    a: float = 0.0
    alpha: float = 0.0
    d: float = 0.0
    theta: float = 0.0
    joint: str = "revolute"
    mass: float = 0.0
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: Any = None
    motor_inertia: Any = 0.0
    motor_mass: float = 0.0
    gear_ratio: float = 1.0
    lower: float | None = None
    upper: float | None = None
    effort: float | None = None
    velocity: float | None = None
    name: str | None = None
    viscous_friction: float = 0.0
    coulomb_friction: Any = 0.0

    def __post_init__(self) -> None:
        try:
            self._check()
        except ValueError as exc:  # name the link and the field
            text = str(exc).removeprefix("DH link ")
            raise ValueError(f"DH link{f' {self.name!r}' if isinstance(self.name, str) else ''}: {text}") from None

    def _check(self) -> None:
        if self.joint not in JOINT_TYPES:
            raise ValueError(f"DH link `joint` must be one of {JOINT_TYPES}, got {self.joint!r}")
        put = object.__setattr__  # frozen: store the checked, converted values
        for key in ("a", "alpha", "d", "theta", "mass", "motor_mass", "gear_ratio"):
            put(self, key, as_scalar(getattr(self, key), key))
        if self.mass < 0 or self.motor_mass < 0:
            raise ValueError(f"DH link masses must be non-negative, got `mass` = {self.mass}, "
                             f"`motor_mass` = {self.motor_mass}")
        put(self, "com", tuple(as_vector(self.com, 3, "com").tolist()))
        if self.inertia is not None:
            put(self, "inertia", _inertia_tensor(self.inertia, "inertia"))
        Im = np.asarray(as_scalar(self.motor_inertia, "motor_inertia") if np.ndim(self.motor_inertia) == 0
                        else _inertia_tensor(self.motor_inertia, "motor_inertia"))
        if Im.shape == () and Im < 0:
            raise ValueError(f"DH link `motor_inertia` must be non-negative, got {float(Im)}")
        put(self, "motor_inertia", float(Im) if Im.shape == () else Im)
        for key in ("lower", "upper"):
            if getattr(self, key) is not None:
                put(self, key, as_scalar(getattr(self, key), key))
        if self.lower is not None and self.upper is not None and self.lower > self.upper:
            raise ValueError(f"DH link joint limits must have `lower` <= `upper`, got {self.lower} > {self.upper}")
        for key in ("effort", "velocity"):
            value = getattr(self, key)
            if value is not None:
                value = as_scalar(value, key)
                if value <= 0:
                    raise ValueError(f"DH link `{key}` limit must be positive, got {value}")
                put(self, key, value)
        if self.name is not None and not isinstance(self.name, str):
            raise ValueError(f"DH link `name` must be a string, got {self.name!r}")
        Fs = np.asarray(self.coulomb_friction, dtype=float)
        if (Fs.shape not in ((), (2,)) or not np.all(np.isfinite(Fs)) or np.any(Fs < 0)
                or not np.isfinite(self.viscous_friction) or self.viscous_friction < 0):
            raise ValueError("DH link friction must be finite and non-negative (`viscous_friction` a number, "
                             f"`coulomb_friction` a number or a pair), got {self.viscous_friction!r}, "
                             f"{self.coulomb_friction!r}")

    @property
    def coulomb_pair(self) -> tuple[float, float]:
        """(F_s+, F_s−): the Coulomb friction magnitudes for q̇ > 0 and q̇ < 0."""
        Fs = np.asarray(self.coulomb_friction, dtype=float)
        return (float(Fs), float(Fs)) if Fs.shape == () else (float(Fs[0]), float(Fs[1]))

    @property
    def has_motor(self) -> bool:
        return bool(np.any(np.asarray(self.motor_inertia) != 0) or self.motor_mass != 0)

    @property
    def rotor_inertia(self) -> np.ndarray:
        """The rotor's (3, 3) inertia tensor in its frame (z = spin axis), Sect. 7.3.

        A scalar ``motor_inertia`` I_m is the moment about the spin axis, the transverse moments being 0
        as in the book: diag(0, 0, I_m); a (3, 3) value is returned as given.
        """
        Im = np.asarray(self.motor_inertia, dtype=float)
        return np.diag([0.0, 0.0, float(Im)]) if Im.shape == () else Im.copy()

    def transform(self, q: float, convention: str = "standard") -> np.ndarray:
        """A_i^{i-1}(q_i) of this link: Eq. (2.52), or Craig's product with ``convention="modified"``."""
        if convention != "standard":
            _check_convention(convention)
        A = dh_transform if convention == "standard" else modified_dh_transform
        if self.joint == "revolute":
            return A(self.a, self.alpha, self.d, self.theta + q)
        return A(self.a, self.alpha, self.d + q, self.theta)


def joint_friction_from_motor(gear_ratio: float, viscous: float = 0.0, coulomb: Any = 0.0) -> dict[str, Any]:
    """Friction measured at the motor, as the joint-side ``DHLink`` fields: F_v = k_r² F_m, F_s = |k_r| τ_c.

    The motor turns k_r times faster than the joint and its torque is multiplied by k_r through the gear
    (Sect. 8.2: F_v = K_r F_m K_r), so a motor-side viscous coefficient F_m and Coulomb torque τ_c (a
    magnitude or a pair for q̇ > 0, q̇ < 0) give ``dict(viscous_friction=…, coulomb_friction=…)``.
    """
    k = abs(float(gear_ratio))
    c = np.abs(np.asarray(coulomb, dtype=float)) * k
    return dict(viscous_friction=k * k * float(viscous),
                coulomb_friction=float(c) if c.shape == () else (float(c[0]), float(c[1])))


INERTIA_TOL = 1e-9  # symmetry and positive semi-definiteness of an inertia tensor [kg·m²]


def _inertia_tensor(value: Any, name: str) -> np.ndarray:
    """A (3, 3) inertia tensor, checked: finite, symmetric and positive semi-definite (ValueError naming ``name``)."""
    inertia = as_matrix(value, (3, 3), name).copy()
    asym = np.abs(inertia - inertia.T).max()
    if asym > INERTIA_TOL:
        raise ValueError(f"DH link `{name}` must be symmetric, max |I - I^T| = {asym:.3g}")
    lowest = np.linalg.eigvalsh(inertia).min()
    if lowest < -INERTIA_TOL:
        raise ValueError(f"DH link `{name}` must be positive semi-definite, smallest eigenvalue {lowest:.3g}")
    inertia.setflags(write=False)
    return inertia


def as_links(links: Iterable[DHLink | Mapping[str, Any]]) -> list[DHLink]:
    """Accept DHLink objects or dicts with DHLink's keys (unknown keys → TypeError)."""
    names = {f.name for f in fields(DHLink)}
    out = []
    for k, link in enumerate(links):
        if isinstance(link, DHLink):
            out.append(link)
            continue
        unknown = set(link) - names
        if unknown:
            raise TypeError(f"DH link {k + 1}: unrecognized key(s) {sorted(unknown)}; allowed {sorted(names)}")
        try:
            out.append(DHLink(**link))
        except ValueError as exc:
            raise ValueError(f"DH link {k + 1}{str(exc).removeprefix('DH link')}") from None
    if not out:
        raise ValueError("a DH table needs at least one link")
    return out


def dh_chain(links: Sequence[DHLink | Mapping[str, Any]], q: Any, convention: str = "standard") -> list[np.ndarray]:
    """[T_0^0, T_1^0, ..., T_n^0]: the DH frames in the base frame at q (products of (2.52), or of Craig's
    A matrices with ``convention="modified"``)."""
    _check_convention(convention)
    links = as_links(links)
    q = as_vector(np.ravel(q) if np.ndim(q) > 1 else q, len(links), "q")
    T = [np.eye(4)]
    for link, qi in zip(links, q):
        T.append(T[-1] @ link.transform(qi, convention))
    return T


# --------------------------------------------------------------------------------------------
# URDF
# --------------------------------------------------------------------------------------------

def _inertial(mass: float, com: Any, inertia: Any, origin_rot: np.ndarray | None = None):
    import yourdfpy

    origin = np.eye(4)
    origin[:3, 3] = np.asarray(com, dtype=float)
    if inertia is None:
        inertia = np.zeros((3, 3))
    return yourdfpy.Inertial(mass=float(mass), origin=origin, inertia=np.asarray(inertia, dtype=float))


def _shapes(*shapes: tuple[str, tuple[float, ...], np.ndarray]) -> dict:
    """``visuals`` and ``collisions`` of a yourdfpy Link: the same simple shapes for drawing and collision checking.

    Each shape is ``("cylinder", (radius, length), origin)`` (axis z of ``origin``) or ``("box", size, origin)``.
    """
    import yourdfpy

    visuals, collisions = [], []
    grey = yourdfpy.Material(name="rmpc_grey", color=yourdfpy.Color(rgba=np.array([0.6, 0.6, 0.65, 1.0])))
    for kind, size, origin in shapes:
        geometry = (yourdfpy.Geometry(cylinder=yourdfpy.Cylinder(radius=size[0], length=size[1])) if kind == "cylinder"
                    else yourdfpy.Geometry(box=yourdfpy.Box(size=np.asarray(size, dtype=float))))
        visuals.append(yourdfpy.Visual(origin=origin, geometry=geometry, material=grey))
        collisions.append(yourdfpy.Collision(name=None, origin=origin, geometry=geometry))
    return dict(visuals=visuals, collisions=collisions)


def _link_shapes(link: DHLink, radius: float, next_a: float | None = None) -> list[tuple[str, tuple[float, ...], np.ndarray]]:
    """Body i drawn in its joint frame: a cylinder on the joint axis z_{i−1}, then the link as cylinders along
    the DH offset d_i (along z) and the length a_i (along x, at height d_i), up to the origin of frame i.
    Modified DH (``next_a`` = a_i of row i+1): the joint frame is frame i; d_i is drawn below its origin and
    a_i along x from it."""
    shapes = [("cylinder", (1.3 * radius, 4.0 * radius), np.eye(4))]
    d = link.d if link.joint == "revolute" else 0.0
    a = link.a if next_a is None else next_a
    if abs(d) > 1e-9:
        shapes.append(("cylinder", (radius, abs(d)), dh_transform(0.0, 0.0, d / 2 if next_a is None else -d / 2, 0.0)))
    if next_a is not None:
        d = 0.0
    if abs(a) > 1e-9:
        along_x = dh_transform(0.0, 0.0, d, 0.0) @ dh_transform(a / 2, 0.0, 0.0, 0.0)
        along_x[:3, :3] = [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]  # Ry(π/2): the cylinder's z along x
        shapes.append(("cylinder", (radius, abs(a)), along_x))
    return shapes


def urdf_from_dh(links: Sequence[DHLink | Mapping[str, Any]], name: str = "dh_robot",
                 tool: np.ndarray | None = None, convention: str = "standard", base: np.ndarray | None = None,
                 motors: str = "rotors") -> str:
    """URDF text of a serial DH arm, with link inertias, rotors on ``<mimic>`` joints and simple shapes.

    Every body gets the same ``<visual>`` and ``<collision>`` shapes (drawing and collision checking):
    a cylinder on its joint axis, cylinders along d_i and a_i, and a box for the gripper at ``ee``; their
    radius scales with the arm's size. They carry no mass: the dynamics is the table's.

    A payload is not part of the arm's file: :func:`rigid_body.robots.with_payload` adds it to a model.

    Parameters
    ----------
    links : DH table, one entry per joint (see :class:`DHLink`).
    name : the robot's name.
    tool : optional (4, 4) constant rigid transform from the last DH frame to the end-effector frame ``ee``;
        identity by default (``ee`` coincides with ``frame_n``). ValueError if it is not [[R, o], [0, 1]], R ∈ SO(3).
    convention : ``"standard"`` (the book's, (2.52)) or ``"modified"`` (Craig's) DH.
    base : optional (4, 4) constant transform from the root link ``base`` (world) to DH frame 0; without it
        ``frame_0`` is the root.
    motors : ``"rotors"`` (the book's mimic rotors) or ``"armature"`` (rotor fixed to link i−1 with its mass
        and transverse moments; the spin moment k_r² I_m goes to ``model.armature``, set by ``robot_from_dh``).

    A link's ``<inertial>`` is written when its mass or its inertia is non-zero (a massless link may
    still have a moment of inertia, e.g. link 1 of the Puma 560).
    """
    import yourdfpy
    from lxml import etree

    _check_convention(convention)
    if motors not in MOTOR_MODELS:
        raise ValueError(f"`motors` must be one of {MOTOR_MODELS}, got {motors!r}")
    links = as_links(links)
    modified = convention == "modified"
    eye = np.eye(4)
    radius = 0.02 * max(sum(abs(link.a) + abs(link.d) for link in links), 0.5)
    robot = yourdfpy.Robot(name=name)
    robot.links.append(yourdfpy.Link(name="frame_0"))
    if base is not None:
        base = np.asarray(base, dtype=float)
        if base.shape != (4, 4) or not np.all(np.isfinite(base)):
            raise ValueError(f"`base` must be a finite (4, 4) transform, got shape {base.shape}")
        robot.links.append(yourdfpy.Link(name="base"))
        robot.joints.append(yourdfpy.Joint(name="base_fixed", type="fixed", parent="base", child="frame_0",
                                           origin=base))
    mimics: dict[str, tuple[str, float]] = {}
    for i, link in enumerate(links, start=1):
        parent = f"frame_{i - 1}"
        body = f"link_{i}"
        lower = link.lower if link.lower is not None else (-np.pi if link.joint == "revolute" else -1.0)
        upper = link.upper if link.upper is not None else (np.pi if link.joint == "revolute" else 1.0)
        limit = yourdfpy.Limit(effort=link.effort if link.effort is not None else 1e4,
                               velocity=link.velocity if link.velocity is not None else 1e2,
                               lower=lower, upper=upper)
        if modified:  # joint i's frame is Craig's frame i: the fixed joint to frame_i is the identity
            origin, fixed = modified_dh_transform(link.a, link.alpha, link.d, link.theta), eye.copy()
            next_a = links[i].a if i < len(links) else 0.0
        elif link.joint == "revolute":
            origin = dh_transform(0.0, 0.0, 0.0, link.theta)
            fixed = dh_transform(link.a, link.alpha, link.d, 0.0)
            next_a = None
        else:
            origin = dh_transform(0.0, 0.0, link.d, link.theta)
            fixed = dh_transform(link.a, link.alpha, 0.0, 0.0)
            next_a = None
        robot.links.append(yourdfpy.Link(name=body, **_shapes(*_link_shapes(link, radius, next_a))))
        Fs = link.coulomb_pair
        dynamics = (yourdfpy.Dynamics(damping=float(link.viscous_friction), friction=(Fs[0] + Fs[1]) / 2)
                    if link.viscous_friction or any(Fs) else None)
        robot.joints.append(yourdfpy.Joint(
            name=link.name or f"joint_{i}", type=link.joint, parent=parent, child=body,
            origin=origin, axis=np.array([0.0, 0.0, 1.0]), limit=limit, dynamics=dynamics))
        has_inertia = link.inertia is not None and np.any(np.asarray(link.inertia) != 0)
        inertial = _inertial(link.mass, link.com, link.inertia) if link.mass > 0 or has_inertia else None
        robot.links.append(yourdfpy.Link(name=f"frame_{i}", inertial=inertial))
        robot.joints.append(yourdfpy.Joint(name=f"frame_{i}_fixed", type="fixed", parent=body,
                                           child=f"frame_{i}", origin=fixed))
        rotor_origin = origin if modified else eye.copy()  # on joint axis i, carried by link i−1
        if link.has_motor and motors == "armature":
            # The rotor's mass and transverse moments ride on link i−1; its spin moment is armature.
            rigid = link.rotor_inertia
            rigid[2, 2] = 0.0
            if link.motor_mass > 0 or np.any(rigid != 0):
                robot.links.append(yourdfpy.Link(
                    name=f"rotor_{i}", inertial=_inertial(link.motor_mass, np.zeros(3), rigid)))
                robot.joints.append(yourdfpy.Joint(name=f"rotor_{i}_fixed", type="fixed", parent=parent,
                                                   child=f"rotor_{i}", origin=rotor_origin))
        elif link.has_motor:
            # Rotor i sits on axis i at the origin of frame i-1, carried by link i-1 (Sect. 7.3).
            rotor = f"rotor_{i}"
            robot.links.append(yourdfpy.Link(
                name=rotor, inertial=_inertial(max(link.motor_mass, 1e-12), np.zeros(3),
                                               link.rotor_inertia)))
            rotor_joint = f"rotor_{i}_joint"
            robot.joints.append(yourdfpy.Joint(
                name=rotor_joint, type="revolute", parent=parent, child=rotor, origin=rotor_origin,
                axis=np.array([0.0, 0.0, 1.0]),
                limit=yourdfpy.Limit(effort=1e4, velocity=1e5, lower=-1e6, upper=1e6),
                mimic=yourdfpy.Mimic(joint=link.name or f"joint_{i}", multiplier=float(link.gear_ratio),
                                     offset=0.0)))
            mimics[rotor_joint] = (link.name or f"joint_{i}", float(link.gear_ratio))
    n = len(links)
    tool = eye.copy() if tool is None else as_homogeneous(tool, "tool")  # a rigid transform: R ∈ SO(3)
    gripper = dh_transform(0.0, 0.0, radius, 0.0)
    robot.links.append(yourdfpy.Link(name="ee", **_shapes(("box", (2 * radius, 5 * radius, 2 * radius), gripper))))
    robot.joints.append(yourdfpy.Joint(name="ee_fixed", type="fixed", parent=f"frame_{n}", child="ee",
                                       origin=tool))
    urdf = yourdfpy.URDF(robot=robot, build_scene_graph=False, load_meshes=False)
    root = urdf.write_xml().getroot()
    # yourdfpy 0.0.60 drops <mimic> when writing: add it back.
    for joint in root.findall("joint"):
        if joint.get("name") in mimics:
            target, multiplier = mimics[joint.get("name")]
            etree.SubElement(joint, "mimic", attrib={"joint": target, "multiplier": repr(multiplier),
                                                     "offset": "0.0"})
    return etree.tostring(root, pretty_print=True, xml_declaration=True, encoding="utf-8").decode()
