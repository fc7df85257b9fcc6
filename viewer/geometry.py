"""What the viewer draws of a robot: its URDF geometry, or a skeleton of its links.

``geometry_of(robot)`` returns the ``pin.GeometryModel`` shown by the viewer. It prefers the robot's
own ``robot.visual_model`` / ``robot.collision_model`` when ``rigid_body.robots`` provides them, else
it reads the URDF's ``<visual>`` / ``<collision>`` elements (meshes of example-robot-data are found
through its ``package://`` root). A URDF without geometry (the book's robots, generated from their DH
tables) is drawn as a *skeleton*: a sphere at each joint and a cylinder from each joint to the next
one and to each frame its link carries (the book's ``frame_i`` and ``ee``).
"""

from __future__ import annotations

from pathlib import Path

import coal
import numpy as np
import pinocchio as pin

from rigid_body.robots import Robot, example_robot_data_dir, joint_kind

SKELETON_COLOR = np.array([0.90, 0.45, 0.10, 1.0])  # orange: the colour the browser test looks for
JOINT_COLOR = np.array([0.20, 0.30, 0.55, 1.0])
KINDS = ("collision", "visual")


def _package_dirs(robot: Robot) -> list[str]:
    """Where ``package://`` URIs of the robot's URDF resolve: example-robot-data's share/ and the URDF's folder."""
    dirs = []
    if robot.urdf_path is not None:
        dirs.append(str(Path(robot.urdf_path).resolve().parent))
    try:
        dirs.append(str(example_robot_data_dir().parents[1]))  # .../share, holding example-robot-data/
    except FileNotFoundError:
        pass
    return dirs


def _from_urdf(robot: Robot, kind: str) -> pin.GeometryModel:
    geom_type = pin.GeometryType.VISUAL if kind == "visual" else pin.GeometryType.COLLISION
    if "<" + kind not in robot.urdf_xml:
        return pin.GeometryModel()
    # Built against robot.model, so that a reduced model (the Panda with locked fingers) is matched by
    # link name: the locked links hang on their parent joint as fixed frames.
    return pin.buildGeomFromUrdfString(robot.model, robot.urdf_xml, geom_type, package_dirs=_package_dirs(robot))


def _segment(name: str, joint: int, a: np.ndarray, b: np.ndarray, radius: float) -> pin.GeometryObject | None:
    """A cylinder from point ``a`` to point ``b`` (both in the frame of ``joint``), None when a == b."""
    d = b - a
    length = float(np.linalg.norm(d))
    if length < 1e-9:
        return None
    z = d / length
    # A rotation whose z axis is along the segment (coal's cylinders are along z).
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    R = np.column_stack([x, np.cross(z, x), z])
    obj = pin.GeometryObject(name, joint, pin.SE3(R, 0.5 * (a + b)), coal.Cylinder(radius, length))
    obj.meshColor = SKELETON_COLOR
    return obj


def _reach(points: list[tuple[int, np.ndarray]]) -> float:
    """The longest offset among (joint, point) pairs [m] (0 without any)."""
    return max((float(np.linalg.norm(p)) for _, p in points), default=0.0)


def skeleton_of(robot: Robot, radius: float | None = None) -> pin.GeometryModel:
    """Spheres at the joints and cylinders along the links: a drawing of any kinematic chain.

    Each cylinder is rigidly attached to one joint: from the joint's origin to the origin of every
    child joint and of every frame (DH frame, end effector) carried by the same joint. A prismatic joint also
    carries a quill along its axis over its stroke, so that whatever its extension the link it moves stays
    attached to the one before (the SCARA's third link, which carries the camera of Example 10.3).
    """
    model = robot.model
    mimic = set(getattr(model, "mimicking_joints", ()))
    points: list[tuple[int, np.ndarray]] = []  # (joint, point in the joint frame)
    for j in range(1, model.njoints):
        if j not in mimic:
            points.append((model.parents[j], np.array(model.jointPlacements[j].translation)))
    for f in model.frames:
        if f.type == pin.FrameType.BODY:
            points.append((f.parentJoint, np.array(f.placement.translation)))
    if radius is None:
        radius = float(np.clip(0.04 * _reach(points), 0.005, 0.03))
    geom = pin.GeometryModel()
    for k, (joint, p) in enumerate(points):
        seg = _segment(f"link_{model.names[joint]}_{k}", joint, np.zeros(3), p, radius)
        if seg is not None:
            geom.addGeometryObject(seg)
    for quill in quills(robot, 0.8 * radius, _reach(points)):
        geom.addGeometryObject(quill)
    for j in range(1, model.njoints):
        if j not in mimic:
            ball = pin.GeometryObject(f"joint_{model.names[j]}", j, pin.SE3.Identity(), coal.Sphere(1.6 * radius))
            ball.meshColor = JOINT_COLOR
            geom.addGeometryObject(ball)
    return geom


def quills(robot: Robot, radius: float, reach: float = 0.1) -> list[pin.GeometryObject]:
    """A cylinder on each prismatic joint's axis over its stroke [lower, upper] (``reach`` when unbounded), attached
    to the joint: whatever its extension, the link it moves stays joined to the link before (the SCARA's third
    link, which carries the camera of Example 10.3)."""
    model = robot.model
    mimic = set(getattr(model, "mimicking_joints", ()))
    out = []
    for j in range(1, model.njoints):
        try:
            kind, axis = joint_kind(model, j)
        except ValueError:
            continue
        if kind == "prismatic" and j not in mimic:
            lo, hi = (float(v[model.joints[j].idx_q]) for v in (model.lowerPositionLimit, model.upperPositionLimit))
            lo, hi = (lo, hi) if np.isfinite(lo) and np.isfinite(hi) and hi > lo else (0.0, max(reach, 0.1))
            seg = _segment(f"quill_{model.names[j]}", j, -hi * axis, -lo * axis, radius)
            if seg is not None:
                out.append(seg)
    return out


def geometry_of(robot: Robot, kind: str = "collision") -> pin.GeometryModel:
    """The geometry the viewer draws for ``robot``.

    ``kind`` is ``"collision"`` (simple meshes: small exports, the default) or ``"visual"`` (the
    detailed meshes). The robot's own ``visual_model``/``collision_model`` win when it has them; a
    robot with no geometry of either kind is drawn as its :func:`skeleton_of`. Drawn from primitive shapes only
    (a DH table's), a prismatic joint also gets its :func:`quills`.
    """
    if kind not in KINDS:
        raise ValueError(f"`kind` must be one of {KINDS}, got {kind!r}")
    other = KINDS[1 - KINDS.index(kind)]
    for k in (kind, other):
        geom = getattr(robot, f"{k}_model", None)
        if geom is None:
            geom = _from_urdf(robot, k)
        if geom.ngeoms > 0:
            if all(obj.meshPath in ("", "BOX", "CYLINDER", "SPHERE") for obj in geom.geometryObjects):
                # primitive shapes only (a DH table's cylinders and the gripper's box): no quill on the prismatic joints
                radii = [obj.geometry.radius for obj in geom.geometryObjects if isinstance(obj.geometry, coal.Cylinder)]
                carried = {obj.parentJoint for obj in geom.geometryObjects}     # a quill joins two drawn links
                extra = [quill for quill in quills(robot, 0.8 * max(radii, default=0.01))
                         if robot.model.parents[quill.parentJoint] in carried]
                if extra:
                    geom = geom.copy()
                    for quill in extra:
                        quill.meshColor = geom.geometryObjects[0].meshColor     # the links' colour
                        geom.addGeometryObject(quill)
            return geom
    return skeleton_of(robot)
