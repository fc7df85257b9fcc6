"""A 3-D scene on Pinocchio's ``MeshcatVisualizer``: robots, overlays, animations, offline HTML.

A :class:`Scene` keeps every meshcat command it is given in a scene tree (as ``meshcat-server``
does), so it can be written as **one self-contained HTML file** — meshcat's JavaScript packed in,
no server, no network — and shown inline in a notebook. With ``server=True`` the same commands are
also sent to a live ``meshcat-server`` bound to 127.0.0.1 (open ``scene.url``).

Overlays are named nodes under ``overlays/``: frames, polylines, point sets, boxes, planes, arrows,
ellipsoids and camera frusta. A robot's frames (the book's DH frames ``frame_0 … frame_n``, ``ee``)
are drawn as triads that follow the robot. :meth:`Scene.animate` records a meshcat animation (a
three.js clip per node: position, quaternion, scale keyed by frame) that the page plays and scrubs.
"""

from __future__ import annotations

import base64
import html as html_lib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Mapping, Sequence

import coal
import meshcat
import meshcat.geometry as mg
import msgpack
import numpy as np
import pinocchio as pin
import umsgpack
from meshcat.animation import Animation, AnimationFrameVisualizer
from meshcat.servers.tree import SceneTree, find_node, walk
from pinocchio.visualize import MeshcatVisualizer

from rigid_body.manipulability import Ellipsoid
from rigid_body.robots import Robot
from rigid_body.rotations import rotation_to_quaternion
from rigid_body.validation import as_matrix, as_positive, as_vector
from viewer.geometry import geometry_of


MESHCAT_JS = Path(meshcat.__file__).resolve().parent / "viewer" / "dist" / "main.min.js"
OVERLAYS = "overlays"


def _ext(value: Any) -> msgpack.ExtType:
    if isinstance(value, umsgpack.Ext):  # meshcat's typed arrays (Float32Array …)
        return msgpack.ExtType(value.type, value.data)
    raise TypeError(f"cannot pack {type(value).__name__} for meshcat")


def _packb(data: Any) -> bytes:
    """A meshcat command as msgpack bytes: the same bytes as meshcat's ``umsgpack.packb``, by the
    compiled packer (an animation's keyframes are ~10⁵ floats: ~15× faster)."""
    return msgpack.packb(data, default=_ext, use_bin_type=True)


# --------------------------------------------------------------------------------------------------
# The recording "window": what meshcat.Visualizer sends commands to.

class _Recorder:
    """Keeps the scene tree of the commands sent (like meshcat-server) and mirrors them to ``live``."""

    def __init__(self, live: Any | None = None):
        self.tree = SceneTree()
        self.animation: bytes | None = None
        self.live = live

    def send(self, command: Any) -> None:
        data = command.lower()
        packed = _packb(data)
        kind = data["type"]
        path = [p for p in data["path"].split("/") if p]
        if kind == "set_animation":
            self.animation = packed
        elif kind == "delete":
            if path:
                find_node(self.tree, path[:-1]).pop(path[-1], None)
            else:
                self.tree, self.animation = SceneTree(), None
        else:
            node = find_node(self.tree, path)
            if kind == "set_object":
                node.object, node.properties = packed, []
            elif kind == "set_transform":
                node.transform = packed
            elif kind == "set_property":
                node.properties.append(packed)
        if self.live is not None:
            self.live.send(command)

    def commands(self) -> list[bytes]:
        """The scene as msgpack commands: objects, properties, transforms, then the animation
        (last, so that its tracks bind to the objects and not to placeholders)."""
        out = []
        for node in walk(self.tree):
            out += [c for c in (node.object, *node.properties, node.transform) if c is not None]
        if self.animation is not None:
            out.append(self.animation)
        return out


class _Frame(AnimationFrameVisualizer):
    """One animation frame: like meshcat's, but a transform's scale is keyed too (arrows grow)."""

    __slots__ = ()

    def set_transform(self, matrix: np.ndarray) -> None:
        position, quaternion, scale = _decompose(matrix)
        clip = self.get_clip()
        clip.set_property(self.current_frame, "position", "vector3", position)
        clip.set_property(self.current_frame, "quaternion", "quaternion", quaternion)
        clip.set_property(self.current_frame, "scale", "vector3", scale)

    def __getitem__(self, path: str) -> "_Frame":
        return _Frame(self.animation, self.path.append(path), self.current_frame)


def as_robot(robot: Any) -> Robot:
    """``robot`` itself, or the robot ``load`` gives for a name or URDF path (``show("panda")``); ValueError for
    anything else."""
    if isinstance(robot, Robot):
        return robot
    if isinstance(robot, (str, Path)):
        from rigid_body.robots import load

        return load(robot)
    raise ValueError(f"`robot` must be a Robot or a name/URDF path for rigid_body.robots.load (e.g. 'panda'), "
                     f"got {type(robot).__name__}")


def _decompose(T: np.ndarray) -> tuple[list[float], list[float], list[float]]:
    """T = [R diag(s) | p] → p, quaternion [x, y, z, w] (three.js order) of R, s."""
    T = np.asarray(T, dtype=float)
    s = np.linalg.norm(T[:3, :3], axis=0)
    R = T[:3, :3] / np.where(s > 0, s, 1.0)
    eta_eps = rotation_to_quaternion(R)  # the book's {η, ε}, scalar first
    return list(T[:3, 3]), [*eta_eps[1:], eta_eps[0]], list(np.maximum(s, 1e-9))


# --------------------------------------------------------------------------------------------------
# Colours and small geometric helpers.

def _color(color: Any) -> tuple[int, float]:
    """``"#e67319"``, 0xE67319 or an RGB(A) tuple of floats in [0, 1] → (0xRRGGBB, opacity)."""
    if isinstance(color, str):
        text = color.lstrip("#")
        if len(text) != 6:
            raise ValueError(f"`color` must look like '#rrggbb', got {color!r}")
        return int(text, 16), 1.0
    if isinstance(color, (int, np.integer)):
        return int(color), 1.0
    c = np.asarray(color, dtype=float)
    if c.shape not in ((3,), (4,)) or np.any(c < 0) or np.any(c > 1):
        raise ValueError(f"`color` must be '#rrggbb', an int or RGB(A) floats in [0, 1], got {color!r}")
    rgb = np.round(c[:3] * 255).astype(int)
    return int(rgb[0]) << 16 | int(rgb[1]) << 8 | int(rgb[2]), float(c[3]) if c.size == 4 else 1.0


def _material(color: Any, opacity: float | None = None) -> mg.MeshPhongMaterial:
    rgb, alpha = _color(color)
    alpha = alpha if opacity is None else opacity
    return mg.MeshPhongMaterial(color=rgb, opacity=alpha, transparent=alpha < 1.0)


def _points(points: Any, name: str) -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim == 1 and p.size == 3:
        p = p.reshape(1, 3)
    if p.ndim != 2 or p.shape[1] not in (2, 3) or not np.all(np.isfinite(p)):
        raise ValueError(f"`{name}` must be a finite (N, 3) (or planar (N, 2)) array, got shape {p.shape}")
    if p.shape[1] == 2:
        p = np.column_stack([p, np.zeros(len(p))])
    return p


def _frame_from_z(z: np.ndarray) -> np.ndarray:
    """A rotation whose third column is the unit vector ``z``."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def arrow_transform(origin: Any, vector: Any) -> np.ndarray:
    """The transform placing the unit arrow of :meth:`Scene.arrow` at ``origin`` along ``vector``.

    The arrow is drawn along its local y axis (three.js cylinders) and scaled by ``|vector|``; a zero
    vector gives a vanishing arrow.
    """
    o = as_vector(origin, 3, "origin")
    v = as_vector(vector, 3, "vector")
    length = float(np.linalg.norm(v))
    T = np.eye(4)
    T[:3, 3] = o
    if length > 1e-12:
        R = _frame_from_z(v / length)
        T[:3, :3] = R[:, [1, 2, 0]] @ np.diag([1.0, length, 1.0])  # local y along the vector
    else:
        T[:3, :3] = np.diag([1.0, 1e-9, 1.0])
    return T


def _as_pose(T: Any, name: str = "T") -> np.ndarray:
    if isinstance(T, pin.SE3):
        return T.homogeneous
    return as_matrix(T, (4, 4), name)


# --------------------------------------------------------------------------------------------------

@dataclass
class RobotView:
    """A robot drawn in a scene: Pinocchio's MeshcatVisualizer plus the frames drawn as triads."""

    robot: Robot
    viz: MeshcatVisualizer
    node: str
    frames: list[int] = field(default_factory=list)

    def display(self, q: np.ndarray, viewer: Any) -> None:
        """Place the geometry (and the frame triads) at configuration q through ``viewer``."""
        self.viz.viewer = viewer
        self.viz.display(q)
        if self.frames:
            pin.updateFramePlacements(self.viz.model, self.viz.data)
            for f in self.frames:
                name = self.viz.model.frames[f].name
                viewer[f"{self.node}/frames/{name}"].set_transform(self.viz.data.oMf[f].homogeneous)


class Scene:
    """A meshcat scene recorded for offline HTML, optionally mirrored to a live server.

    >>> from rigid_body.robots import load
    >>> scene = Scene()
    >>> _ = scene.add_robot(load("planar_2r"))
    >>> scene.html().startswith("<!DOCTYPE html>")
    True
    """

    def __init__(self, server: bool = False, zmq_url: str | None = None, grid: bool = True):
        live = None
        if server or zmq_url is not None:
            from meshcat.visualizer import ViewerWindow

            # meshcat-server binds its web and zmq ports to 127.0.0.1 by default.
            live = ViewerWindow(zmq_url=zmq_url, start_server=zmq_url is None, server_args=[])
        self._recorder = _Recorder(live)
        self.vis = meshcat.Visualizer(window=self._recorder)
        self.robots: dict[str, RobotView] = {}
        self.duration = 0.0
        if not grid:
            self.vis["/Grid"].set_property("visible", False)

    @property
    def url(self) -> str | None:
        """Address of the live viewer (None without a server)."""
        live = self._recorder.live
        return None if live is None else live.web_url

    def close(self) -> None:
        """Stop the live meshcat server this scene started (the recorded scene stays usable)."""
        live, self._recorder.live = self._recorder.live, None
        proc = getattr(live, "server_proc", None)
        if proc is not None:
            proc.kill()
            proc.wait()

    # -- robots ------------------------------------------------------------------------------------
    def add_robot(self, robot: Robot, q: Any | None = None, name: str = "robot", kind: str = "collision",
                  frames: Iterable[str | int] | None = None, color: Any | None = None,
                  frame_length: float = 0.08) -> RobotView:
        """Draw ``robot`` at ``q`` (neutral by default) under the node ``name``.

        ``frames`` are drawn as triads that follow the robot; by default the book's DH frames
        ``frame_i`` and the end effector. ``color`` overrides the URDF colours.
        """
        robot = as_robot(robot)
        geom = _as_triangle_meshes(geometry_of(robot, kind))
        viz = MeshcatVisualizer(robot.model, None, geom)  # drawn once, as the visual group
        viz.initViewer(viewer=self.vis)
        rgba = None if color is None else _rgba(color)
        viz.loadViewerModel(rootNodeName=name, collision_color=rgba, visual_color=rgba)
        if frames is None:
            frames = [f.name for f in robot.model.frames
                      if f.name.startswith("frame_") and f.type == pin.FrameType.BODY] + [robot.ee_frame]
        view = RobotView(robot, viz, name, [robot.frame(f) for f in frames])
        for f in view.frames:
            self.vis[f"{name}/frames/{robot.model.frames[f].name}"].set_object(mg.triad(frame_length))
        self.robots[name] = view
        self.display(robot.configurations["neutral"] if q is None else q, name)
        return view

    def display(self, q: Any, name: str = "robot") -> None:
        """Put the robot ``name`` at configuration ``q``."""
        view = self._view(name)
        view.display(as_vector(q, view.robot.nq, "q"), self.vis)

    def _view(self, name: str) -> RobotView:
        if name not in self.robots:
            raise ValueError(f"no robot named {name!r} in the scene; robots: {sorted(self.robots)}")
        return self.robots[name]

    # -- overlays ----------------------------------------------------------------------------------
    def _node(self, name: str) -> Any:
        if not name or name.startswith("/"):
            raise ValueError(f"`name` must be a relative node name like 'target', got {name!r}")
        return self.vis[f"{OVERLAYS}/{name}"]

    def set_transform(self, name: str, T: Any) -> None:
        """Move the overlay ``name`` to the pose ``T`` (4×4 or ``pin.SE3``)."""
        self._node(name).set_transform(_as_pose(T))

    def frame(self, name: str, T: Any, length: float = 0.1) -> None:
        """A triad (x red, y green, z blue) at the pose ``T``: a target, a DH frame, a tool frame."""
        node = self._node(name)
        node.set_object(mg.triad(as_positive(length, "length")))
        node.set_transform(_as_pose(T))

    def polyline(self, name: str, paths: Any, color: Any = "#ffd400", radius: float | None = None) -> None:
        """Line strips through the points of ``paths``: one (N, 3) array (a path) or a list of them
        (the branches of a tree). Planar (N, 2) points lie in z = 0.

        WebGL draws lines one pixel wide; with ``radius`` [m] each segment is a tube (a cylinder),
        better seen for a few segments (a path), heavier for thousands (a tree).
        """
        single = isinstance(paths, np.ndarray) or (len(paths) > 0 and np.ndim(paths[0]) == 1)
        pieces = [paths] if single else list(paths)
        segments = []
        for k, piece in enumerate(pieces):
            p = _points(piece, f"paths[{k}]")
            if len(p) >= 2:
                segments.append(np.repeat(p, 2, axis=0)[1:-1])
        if not segments:
            raise ValueError("`paths` must hold at least one path of two points or more")
        ends = np.vstack(segments)
        if radius is None:
            rgb, _ = _color(color)
            geometry = mg.PointsGeometry(ends.T.astype(np.float32))
            self._node(name).set_object(mg.LineSegments(geometry, mg.LineBasicMaterial(color=rgb)))
            return
        r = as_positive(radius, "radius")
        node, material = self._node(name), _material(color)
        for k, (a, b) in enumerate(zip(ends[::2], ends[1::2])):
            length = float(np.linalg.norm(b - a))
            if length > 1e-12:
                node[f"segment_{k}"].set_object(mg.Cylinder(length, r), material)
                node[f"segment_{k}"].set_transform(arrow_transform(0.5 * (a + b), (b - a) / length))

    def points(self, name: str, points: Any, color: Any = "#d62728", size: float = 0.02) -> None:
        """A point set (via points, samples of a PRM, features): squares of side ``size`` metres."""
        p = _points(points, "points")
        rgb, _ = _color(color)
        material = mg.PointsMaterial(size=as_positive(size, "size"), color=rgb)
        self._node(name).set_object(mg.Points(mg.PointsGeometry(p.T.astype(np.float32)), material))

    def box(self, name: str, T: Any, size: Any, color: Any = "#7f7f7f", opacity: float = 1.0) -> None:
        """A box of edge lengths ``size`` centred at the pose ``T``: an obstacle, a table."""
        s = as_vector(size, 3, "size")
        if np.any(s <= 0):
            raise ValueError(f"`size` must be three positive lengths, got {s}")
        node = self._node(name)
        node.set_object(mg.Box(s), _material(color, opacity))
        node.set_transform(_as_pose(T))

    def sphere(self, name: str, center: Any, radius: float, color: Any = "#7f7f7f", opacity: float = 1.0) -> None:
        """A sphere: a point obstacle, a via point."""
        node = self._node(name)
        node.set_object(mg.Sphere(as_positive(radius, "radius")), _material(color, opacity))
        T = np.eye(4)
        T[:3, 3] = as_vector(center, 3, "center")
        node.set_transform(T)

    def cylinder(self, name: str, center: Any, radius: float, height: float, axis: Any = (0.0, 0.0, 1.0),
                 color: Any = "#7f7f7f", opacity: float = 1.0) -> None:
        """A cylinder centred at ``center`` along ``axis``: a disc obstacle of a planar arm, a pillar."""
        a = as_vector(axis, 3, "axis")
        if np.linalg.norm(a) < 1e-12:
            raise ValueError("`axis` must be a non-zero vector")
        node = self._node(name)
        node.set_object(mg.Cylinder(as_positive(height, "height"), as_positive(radius, "radius")),
                        _material(color, opacity))
        node.set_transform(arrow_transform(center, a / np.linalg.norm(a)))  # three.js cylinders lie along y

    def planar_shapes(self, name: str, shapes: Iterable[Any], height: float = 0.1, color: Any = "#7f7f7f",
                      opacity: float = 1.0) -> None:
        """Obstacles of a planar scene (``planners.configuration_space``) raised into solids of ``height``
        [m] centred on z = 0: a disc (``.center``, ``.radius``) as an upright cylinder, a convex polygon
        (``.vertices`` (k, 2), counter-clockwise) as a prism. Named ``name/0``, ``name/1`` …"""
        h = as_positive(height, "height")
        for k, shape in enumerate(shapes):
            if hasattr(shape, "radius") and hasattr(shape, "center"):
                self.cylinder(f"{name}/{k}", [*as_vector(shape.center, 2, f"shapes[{k}].center"), 0.0],
                              shape.radius, h, color=color, opacity=opacity)
            elif hasattr(shape, "vertices"):
                self.prism(f"{name}/{k}", shape.vertices, h, color=color, opacity=opacity)
            else:
                raise ValueError(f"`shapes[{k}]` must be a disc (center, radius) or a polygon (vertices), "
                                 f"got {type(shape).__name__}")

    def prism(self, name: str, vertices: Any, height: float, color: Any = "#7f7f7f", opacity: float = 1.0) -> None:
        """A right prism over the convex polygon ``vertices`` (k, 2) (counter-clockwise, in z = 0), from
        z = −height/2 to +height/2: a polygonal obstacle of a planar scene."""
        V = _points(vertices, "vertices")[:, :2]
        k = len(V)
        if k < 3:
            raise ValueError(f"`vertices` must have at least 3 points, got {k}")
        h = as_positive(height, "height") / 2
        points = np.vstack([np.c_[V, np.full(k, -h)], np.c_[V, np.full(k, h)]])
        faces = [[0, j + 1, j] for j in range(1, k - 1)] + [[k, k + j, k + j + 1] for j in range(1, k - 1)]
        for j in range(k):  # the sides, outward for counter-clockwise vertices
            a, b = j, (j + 1) % k
            faces += [[a, b, k + b], [a, k + b, k + a]]
        node = self._node(name)
        node.set_object(mg.TriangularMeshGeometry(points, np.array(faces)), _material(color, opacity))

    def plane(self, name: str, point: Any, normal: Any, size: Any = (1.0, 1.0), color: Any = "#2ca02c",
              opacity: float = 0.5) -> None:
        """A square patch of the plane through ``point`` with ``normal``: a contact surface (ch. 9)."""
        n = as_vector(normal, 3, "normal")
        if np.linalg.norm(n) < 1e-12:
            raise ValueError("`normal` must be a non-zero vector")
        T = np.eye(4)
        T[:3, :3] = _frame_from_z(n / np.linalg.norm(n))
        T[:3, 3] = as_vector(point, 3, "point")
        w, h = as_vector(size, 2, "size")
        self.box(name, T, (w, h, 0.002), color, opacity)

    def arrow(self, name: str, origin: Any, vector: Any, color: Any = "#9467bd", radius: float = 0.01) -> None:
        """An arrow from ``origin`` to ``origin + vector`` (a force scaled to metres, a velocity).

        Animate it with ``tracks={name: [arrow_transform(o_k, v_k) ...]}`` in :meth:`animate`.
        """
        r = as_positive(radius, "radius")
        node = self._node(name)
        material = _material(color)
        shaft = np.eye(4)
        shaft[1, 3] = 0.4
        head = np.eye(4)
        head[1, 3] = 0.9
        node["shaft"].set_object(mg.Cylinder(0.8, r), material)
        node["shaft"].set_transform(shaft)
        node["head"].set_object(mg.Cylinder(0.2, radiusTop=0.0, radiusBottom=2.5 * r), material)
        node["head"].set_transform(head)
        node.set_transform(arrow_transform(origin, vector))

    def ellipsoid(self, name: str, center: Any, ellipsoid: Ellipsoid, scale: float = 1.0,
                  color: Any = "#17becf", opacity: float = 0.4) -> None:
        """A manipulability ellipsoid (``rigid_body.manipulability``) centred at ``center``.

        Planar ellipses (2 axes) are drawn in the plane z = 0 with a thin third axis.
        """
        axes = np.asarray(ellipsoid.axes, dtype=float)
        semi = np.asarray(ellipsoid.semi_axes, dtype=float) * as_positive(scale, "scale")
        if axes.shape == (2, 2):
            axes = np.block([[axes, np.zeros((2, 1))], [np.zeros((1, 2)), np.ones((1, 1))]])
            semi = np.append(semi, 0.01 * max(semi))
        if axes.shape != (3, 3) or semi.shape != (3,):
            raise ValueError(f"`ellipsoid` must have 2 or 3 axes, got axes of shape {axes.shape}")
        R = axes[:, :3] * (np.sign(np.linalg.det(axes)) or 1.0)
        T = np.eye(4)
        T[:3, :3] = R @ np.diag(np.maximum(semi, 1e-6))
        T[:3, 3] = as_vector(center, 3, "center")
        node = self._node(name)
        node.set_object(mg.Sphere(1.0), _material(color, opacity))
        node.set_transform(T)

    def frustum(self, name: str, T: Any, camera: Any, image_size: Sequence[float], depth: float = 0.2,
                color: Any = "#000000") -> None:
        """A camera's viewing pyramid at pose ``T`` (z along the optical axis), out to ``depth`` metres.

        ``camera`` is a ``rigid_body.camera.PinholeCamera``; ``image_size`` = (width, height) in pixels.
        """
        w, h = as_vector(image_size, 2, "image_size")
        d = as_positive(depth, "depth")
        corners = []
        for X, Y in ((0, 0), (w, 0), (w, h), (0, h)):
            corners.append(d * np.array([(X - camera.X0) / camera.f_alpha_x, (Y - camera.Y0) / camera.f_alpha_y, 1.0]))
        lines = []
        for k in range(4):
            lines += [np.zeros(3), corners[k], corners[k], corners[(k + 1) % 4]]
        rgb, _ = _color(color)
        node = self._node(name)
        node.set_object(mg.LineSegments(mg.PointsGeometry(np.array(lines).T.astype(np.float32)),
                                        mg.LineBasicMaterial(color=rgb)))
        node.set_transform(_as_pose(T))

    def set_world(self, R: Any, offset: Any = (0.0, 0.0, 0.0)) -> None:
        """Orient the whole scene (robots and overlays, given in the robot's base frame) by the rotation
        ``R`` in the viewer, whose z axis is up (see ``viewer.animation.up_rotation``), then shift it by
        ``offset`` (the viewer's frame): meshcat's camera always looks at the viewer's origin."""
        T = np.eye(4)
        T[:3, :3] = as_matrix(R, (3, 3), "R")
        T[:3, 3] = as_vector(offset, 3, "offset")
        self.vis.set_transform(T)

    def camera(self, position: Any, target: Any = (0.0, 0.0, 0.0)) -> None:
        """Put the viewpoint at ``position`` looking at ``target`` (the viewer's frame, z up).

        The mouse orbits around ``target``. (meshcat's camera lives in a frame rotated by +90° about
        x, where world (x, y, z) reads (x, z, −y).)
        """
        p = as_vector(position, 3, "position")
        c = as_vector(target, 3, "target")
        T = np.eye(4)
        T[:3, 3] = c
        self.vis["/Cameras/default"].set_transform(T)
        d = p - c
        self.vis["/Cameras/default/rotated/<object>"].set_property("position", [d[0], d[2], -d[1]])

    def delete(self, name: str) -> None:
        """Remove the overlay ``name``."""
        self._node(name).delete()

    # -- animation ---------------------------------------------------------------------------------
    MAX_FRAMES = 36000          # 20 minutes at 30 fps: beyond, the page would hold millions of transforms

    def animate(self, t: Any, q: Any, name: str = "robot", speed: float = 1.0, fps: float = 30.0,
                tracks: Mapping[str, Any] | None = None, repetitions: int = 1000) -> int:
        """Record the motion ``q(t)`` of robot ``name`` as the page's animation; return the frame count.

        ``t`` (N,) non-decreasing times (at a repeated instant the last sample wins), ``q`` (N, nq)
        samples; the animation shows one frame every ``speed / fps`` seconds of motion (``speed`` 2
        plays twice as fast), the configuration between samples from ``pin.interpolate``. ``tracks`` maps overlay names to (N, 4, 4) poses at the same
        times (a moving target, a force arrow), held between samples.
        """
        view = self._view(name)
        t = as_vector(t, None, "t")
        model = view.robot.model
        Q = np.asarray(q, dtype=float)
        if Q.shape != (t.size, model.nq) or not np.all(np.isfinite(Q)):
            raise ValueError(f"`q` must be a finite ({t.size}, {model.nq}) array, got shape {Q.shape}")
        if t.size < 1 or np.any(np.diff(t) < 0) or t[-1] <= t[0] and t.size > 1:
            raise ValueError("`t` must be a non-empty non-decreasing vector of times")
        speed = as_positive(speed, "speed")
        fps = as_positive(fps, "fps")
        poses = {}
        for key, value in (tracks or {}).items():
            poses[key] = np.asarray(value, dtype=float)
            if poses[key].shape != (t.size, 4, 4):
                raise ValueError(f"`tracks[{key!r}]` must have shape ({t.size}, 4, 4), got {poses[key].shape}")
        span = float(t[-1] - t[0])
        frames = span / speed * fps
        if not frames < self.MAX_FRAMES:
            raise ValueError(f"animating {span:.4g} s of motion at `speed` {speed:g} and `fps` {fps:g} takes "
                             f"{frames:.3g} frames, more than Scene.MAX_FRAMES = {self.MAX_FRAMES}: raise `speed` "
                             f"(≥ {span * fps / self.MAX_FRAMES:.3g}), lower `fps`, or animate a shorter span")
        n_frames = int(np.floor(frames + 1e-9)) + 1
        animation = Animation(default_framerate=fps)
        for k in range(n_frames):
            tk = t[0] + k * speed / fps
            i = int(np.clip(np.searchsorted(t, tk, side="right") - 1, 0, t.size - 1))
            qk = Q[i]
            if i + 1 < t.size:
                qk = pin.interpolate(model, Q[i], Q[i + 1], (tk - t[i]) / (t[i + 1] - t[i]))
            frame = _Frame(animation, self.vis.path, k)
            view.display(qk, frame)
            for key, value in poses.items():
                frame[f"{OVERLAYS}/{key}"].set_transform(value[i])
        view.viz.viewer = self.vis
        self.vis.set_animation(animation, play=True, repetitions=repetitions)
        self.duration = (n_frames - 1) / fps
        return n_frames

    # -- output ------------------------------------------------------------------------------------
    def html(self, title: str = "rmpc viewer") -> str:
        """The scene as one self-contained HTML page (meshcat's JavaScript inlined; no network)."""
        commands = ",\n".join(f'"{base64.b64encode(c).decode("ascii")}"' for c in self._recorder.commands())
        return _PAGE.format(title=html_lib.escape(title), js=MESHCAT_JS.read_text(), commands=commands)

    def save(self, path: str | Path, title: str = "rmpc viewer") -> Path:
        """Write :meth:`html` to ``path`` (parents created) and return the path."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(self.html(title), encoding="utf-8")
        return path

    def _repr_html_(self) -> str:
        """Inline in Jupyter: the static page in an iframe (works without a server)."""
        srcdoc = html_lib.escape(self.html(), quote=True)
        return f'<iframe srcdoc="{srcdoc}" style="width:100%;height:420px;border:none"></iframe>'


def _as_triangle_meshes(geom: pin.GeometryModel) -> pin.GeometryModel:
    """A copy whose meshes read from files are sent as their triangles (Pinocchio's loaded BVH, the
    scale already applied) rather than as the file: the browser then computes the normals, where some
    URDF STL files (the UR5's) carry zero normals and render black. Triangles are also smaller."""
    out = pin.GeometryModel()
    for obj in geom.geometryObjects:
        obj = obj.copy()
        if isinstance(obj.geometry, coal.BVHModelBase) and obj.meshPath:
            obj.meshPath = ""
            obj.meshScale = np.ones(3)
        out.addGeometryObject(obj)
    return out


def _rgba(color: Any) -> list[float]:
    rgb, alpha = _color(color)
    return [(rgb >> 16 & 255) / 255, (rgb >> 8 & 255) / 255, (rgb & 255) / 255, alpha]


# The commands are decoded synchronously, in order (meshcat's own static export goes through
# fetch(data:...) promises whose order is not guaranteed).
_PAGE = """<!DOCTYPE html>
<html>
<head><meta charset="utf-8"><title>{title}</title><link rel="icon" href="data:,">
<style>body {{ margin: 0; }} #meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}</style>
</head>
<body>
<div id="meshcat-pane"></div>
<script>
{js}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
var commands = [
{commands}
];
for (const c of commands) {{
  viewer.handle_command_bytearray(Uint8Array.from(atob(c), ch => ch.charCodeAt(0)));
}}
window.rmpcSceneReady = true;
</script>
</body>
</html>
"""
