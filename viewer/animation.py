"""See it move: ``show``, ``animate``, ``export_html`` for any robot, and the report's animations.

A *motion* is anything with times ``t`` and configurations: a ``planners.timing.Trajectory``
(``.t``, ``.q``), a ``controllers.simulation.SimulationResult`` (``res.q`` when it has it, else the
first nq columns of its state ``x = [q, q̇]``), or a pair ``(t, q)``.
"""

from __future__ import annotations

import html as html_lib
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pinocchio as pin

from rigid_body.robots import Robot
from rigid_body.rotations import axis_angle_to_rotation
from rigid_body.validation import as_vector
from viewer.scene import Scene


def motion_of(motion: Any, robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """``(t, q)`` of a Trajectory, a SimulationResult or a ``(t, q)`` pair, q as (N, nq)."""
    if isinstance(motion, tuple) and len(motion) == 2:
        t, q = motion
    else:
        t = getattr(motion, "t", None)
        try:
            q = motion.q  # a Trajectory; a SimulationResult whose plant names its states
        except (AttributeError, KeyError):
            q = None
        if q is None and getattr(motion, "x", None) is not None:
            x = np.asarray(motion.x, dtype=float)
            if x.ndim != 2 or x.shape[1] < robot.nq:
                raise ValueError(f"`motion` state x has shape {x.shape}: fewer than nq = {robot.nq} columns")
            q = x[:, :robot.nq]  # arm plants: x = [q, q̇]
        if t is None or q is None:
            raise ValueError(f"`motion` must be a Trajectory, a SimulationResult or a (t, q) pair, "
                             f"got {type(motion).__name__}")
    t = np.asarray(t, dtype=float).reshape(-1)
    q = np.asarray(q, dtype=float)
    if q.ndim == 1 and robot.nq == 1:
        q = q.reshape(-1, 1)
    if q.shape != (t.size, robot.nq):
        raise ValueError(f"`motion` q must have shape ({t.size}, {robot.nq}) for robot {robot.name!r}, got {q.shape}")
    return t, q


def up_rotation(gravity: Any) -> np.ndarray:
    """The rotation R_up taking the robot's base frame to the viewer's (z up) so that −g points up:
    the book's SCARA (g along +z) stands on its base, planar arms with g along −y stand in a vertical
    plane. Identity without gravity."""
    g = np.asarray(gravity, dtype=float)
    norm = float(np.linalg.norm(g))
    if norm < 1e-12:
        return np.eye(3)
    up, z = -g / norm, np.array([0.0, 0.0, 1.0])
    axis = np.cross(up, z)
    if np.linalg.norm(axis) < 1e-12:  # already vertical: identity, or upside down: half a turn about x
        return np.eye(3) if up[2] > 0 else axis_angle_to_rotation(np.pi, [1.0, 0.0, 0.0])
    return axis_angle_to_rotation(float(np.arccos(np.clip(up @ z, -1.0, 1.0))), axis / np.linalg.norm(axis))


def default_camera(robot: Robot, R_up: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A viewpoint ``(position, target)`` in the viewer's frame that frames the robot (shown rotated
    by ``R_up``): square to the plane of a planar arm (all its frames stay in one plane), from the
    front-right and above otherwise, aimed at the centre of the frames' origins over a few random
    configurations, from a distance proportional to their spread."""
    model, data = robot.model, robot.model.createData()
    R_up = np.eye(3) if R_up is None else R_up
    rng = np.random.default_rng(0)
    origins = []
    for _ in range(4):
        pin.framesForwardKinematics(model, data, robot.random_configuration(rng))
        origins += [R_up @ m.translation for m in data.oMf]
    origins = np.array(origins)
    centre = origins.mean(axis=0)
    _, sigma, Vt = np.linalg.svd(origins - centre, full_matrices=False)
    if sigma[-1] < 1e-9 * max(sigma[0], 1.0):  # a planar arm: centred on its base, square to its plane
        n = Vt[-1]
        base = n * (n @ centre)
        reach = max(float(np.max(np.linalg.norm(origins - base, axis=1))), 0.3)
        if abs(n[2]) > 0.9:  # a horizontal plane: from above, with y up on the screen
            return base + np.array([0.0, -0.01, 2.0]) * reach, base
        n = -n if n[1] > 0 else n  # a vertical plane: from the −y side, z up
        return base + 2.0 * reach * n, base
    spread = max(float(np.max(np.linalg.norm(origins - centre, axis=1))), 0.3)
    return centre + np.array([1.4, 1.0, 0.65]) * spread, centre


def show(robot: Robot, q: Any | None = None, *, server: bool = False, scene: Scene | None = None,
         overlays: Callable[[Scene], None] | None = None, camera: tuple[Any, Any] | None = None,
         **options: Any) -> Scene:
    """Draw ``robot`` at ``q`` (neutral by default); the Scene shows itself inline in a notebook.

    ``server=True`` also opens a live meshcat server on 127.0.0.1 (``scene.url``). ``overlays(scene)``
    draws the problem's extras (targets, obstacles, paths). ``camera`` = (position, target) in the
    viewer's frame replaces :func:`default_camera` (e.g. ``viewer.mobile.plane_camera`` for a mobile
    robot's workspace). ``options`` go to :meth:`Scene.add_robot`.
    """
    new = scene is None
    scene = Scene(server=server) if new else scene
    if new:
        R_up = up_rotation(robot.model.gravity.linear)
        if camera is None:
            scene.set_world(R_up)
            scene.camera(*default_camera(robot, R_up))
        else:  # the camera looks at the viewer's origin: the scene is shifted to bring `target` there
            position, target = (as_vector(v, 3, k) for v, k in zip(camera, ("camera position", "camera target")))
            scene.set_world(R_up, -target)
            scene.vis["/Axes"].set_property("visible", False)  # meshcat's triad at the viewer's origin, now not ours
            scene.camera(position - target)
    scene.add_robot(robot, q, **options)
    if overlays is not None:
        overlays(scene)
    return scene


def animate(robot: Robot, motion: Any, speed: float = 1.0, *, server: bool = False, scene: Scene | None = None,
            overlays: Callable[[Scene], None] | None = None, tracks: dict[str, Any] | None = None,
            fps: float = 30.0, camera: tuple[Any, Any] | None = None, **options: Any) -> Scene:
    """Animate ``robot`` along ``motion`` (a SimulationResult, a Trajectory or ``(t, q)``).

    ``speed`` scales playback (2 = twice as fast); ``tracks`` moves overlays with the motion (see
    :meth:`Scene.animate`). Save it with ``scene.save(path)`` or :func:`export_html`.
    """
    t, q = motion_of(motion, robot)
    scene = show(robot, q[0], server=server, scene=scene, overlays=overlays, camera=camera, **options)
    scene.animate(t, q, name=options.get("name", "robot"), speed=speed, fps=fps, tracks=tracks)
    return scene


def export_html(robot: Robot, motion: Any, path: str | Path, speed: float = 1.0, title: str = "",
                **options: Any) -> Path:
    """Write a self-contained HTML animation of ``robot`` along ``motion`` (no server, no network)."""
    scene = animate(robot, motion, speed, **options)
    return scene.save(path, title or f"{robot.name}: animation")


def report_animations(solution: Any, directory: str | Path, prefix: str = "animations") -> list[str]:
    """Export the animations a problem attached with ``Solution.animation(...)`` for the report.

    Writes ``directory/prefix/<id>_<k>.html`` and returns one HTML snippet per animation: a
    caption and an ``<iframe>`` whose ``src`` is relative to ``directory`` (the report's folder).
    """
    snippets = []
    for k, spec in enumerate(getattr(solution, "animations", ()), start=1):
        spec = dict(spec)
        robot, motion, caption = spec.pop("robot"), spec.pop("motion"), spec.pop("title", "")
        name = f"{solution.id or 'problem'}_{k}.html".replace("/", "_")
        started = time.perf_counter()
        export_html(robot, motion, Path(directory) / prefix / name, title=f"Problem {solution.id}: {caption}", **spec)
        elapsed = time.perf_counter() - started
        snippets.append(
            f'<figure class="animation"><iframe src="{prefix}/{name}" loading="lazy" '
            f'style="width:100%;height:420px;border:1px solid #ccc"></iframe>'
            f"<figcaption>{html_lib.escape(caption or robot.name)} — 3-D animation "
            f"(drag to orbit; controls at the top right; exported in {elapsed:.1f} s)</figcaption></figure>")
    return snippets
