"""See it move: ``show``, ``animate``, ``export_html`` for any robot, and the report's animations.

A *motion* is anything with times ``t`` and configurations: a ``planners.timing.Trajectory``
(``.t``, ``.q``), a ``controllers.simulation.SimulationResult`` (``res.q`` when it has it, the states named
after the robot's joints, or the first nq columns of an unnamed state ``x = [q, q̇]``: :func:`motion_of`),
or a pair ``(t, q)``.
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
from viewer.scene import Scene, as_robot


def motion_of(motion: Any, robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """``(t, q)`` of a Trajectory, a SimulationResult or a ``(t, q)`` pair, q as (N, nq).

    A SimulationResult gives its joint positions ``q`` (a logged signal or a named part of its plant's state),
    or else the states named after the robot's joints (a unicycle's x, y, θ for
    :func:`viewer.mobile.planar_body`), or else — its plant naming no state — the first nq columns of a state
    of nq or nq + nv entries (an arm's [q, q̇]); anything else (a unicycle's result for an arm) is a ValueError
    naming what the result holds."""
    if isinstance(motion, tuple) and len(motion) == 2:
        t, q = motion
    elif hasattr(motion, "signals") and hasattr(motion, "layout") and hasattr(motion, "x"):
        t, q = motion.t, _result_positions(motion, robot)
    else:
        t, q = getattr(motion, "t", None), getattr(motion, "q", None)
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


def _result_positions(res: Any, robot: Robot) -> np.ndarray:
    """The configurations (N, nq) of ``robot`` in a SimulationResult: its ``q``, or its states named after the
    robot's (one-coordinate) joints; ValueError otherwise."""
    if "q" in res.signals or "q" in res.layout:
        return res["q"]
    model = robot.model
    joints = [model.names[j] for j in range(1, model.njoints)]
    if all(model.joints[j].nq == 1 for j in range(1, model.njoints)) and joints and all(n in res.layout for n in joints):
        return np.column_stack([np.asarray(res.x[:, res.layout[n]], dtype=float).reshape(len(res.t)) for n in joints])
    width = np.shape(res.x)[1] if np.ndim(res.x) == 2 else -1
    if not res.layout and width in (robot.nq, robot.nq + robot.nv):      # an unnamed arm state [q] or [q, q̇]
        return np.asarray(res.x)[:, :robot.nq]
    raise ValueError(f"`motion`: this SimulationResult holds no configuration of {robot.name!r}: no `q` among its "
                     f"signals {sorted(res.signals)} or states {sorted(res.layout)}, and not the robot's joints "
                     f"{joints}; animate its own robot, or pass (res.t, q)")


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


def show(robot: Robot | str, q: Any | None = None, *, server: bool = False, scene: Scene | None = None,
         overlays: Callable[[Scene], None] | None = None, camera: tuple[Any, Any] | None = None,
         **options: Any) -> Scene:
    """Draw ``robot`` at ``q`` (neutral by default); the Scene shows itself inline in a notebook.

    ``server=True`` also opens a live meshcat server on 127.0.0.1 (``scene.url``). ``overlays(scene)``
    draws the problem's extras (targets, obstacles, paths). ``camera`` = (position, target) in the
    viewer's frame replaces :func:`default_camera` (e.g. ``viewer.mobile.plane_camera`` for a mobile
    robot's workspace). ``options`` go to :meth:`Scene.add_robot`.
    """
    robot = as_robot(robot)
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


def animate(robot: Robot | str, motion: Any, speed: float = 1.0, *, server: bool = False, scene: Scene | None = None,
            overlays: Callable[[Scene], None] | None = None, tracks: dict[str, Any] | None = None,
            fps: float = 30.0, camera: tuple[Any, Any] | None = None, **options: Any) -> Scene:
    """Animate ``robot`` along ``motion`` (a SimulationResult, a Trajectory or ``(t, q)``).

    ``speed`` scales playback (2 = twice as fast); ``tracks`` moves overlays with the motion (see
    :meth:`Scene.animate`). Save it with ``scene.save(path)`` or :func:`export_html`.
    """
    robot = as_robot(robot)
    t, q = motion_of(motion, robot)
    scene = show(robot, q[0], server=server, scene=scene, overlays=overlays, camera=camera, **options)
    scene.animate(t, q, name=options.get("name", "robot"), speed=speed, fps=fps, tracks=tracks)
    return scene


def export_html(robot: Robot | str, motion: Any, path: str | Path, speed: float = 1.0, title: str = "",
                **options: Any) -> Path:
    """Write a self-contained HTML animation of ``robot`` along ``motion`` (no server, no network)."""
    scene = animate(robot, motion, speed, **options)
    return scene.save(path, title or f"{robot.name}: animation")


def report_animations(solution: Any, directory: str | Path, prefix: str = "animations") -> list[str]:
    """Export the animations a problem attached with ``Solution.animation(...)`` for the report.

    Writes ``directory/prefix/<id>_<k>.html`` and returns one HTML snippet per animation: a ``<figure
    class="animation">`` whose ``data-src`` is the page (relative to ``directory``, the report's folder), holding a
    still poster (:func:`viewer.poster.poster_svg`) and a caption. No ``<iframe>``: the report's page makes the
    animation live when it is scrolled into view or clicked and removes it when scrolled away (a browser keeps
    only so many live WebGL contexts), see :data:`LIVE_ANIMATIONS_SCRIPT`.
    """
    from viewer.poster import poster_svg

    snippets = []
    for k, spec in enumerate(getattr(solution, "animations", ()), start=1):
        spec = dict(spec)
        robot, motion, caption = as_robot(spec.pop("robot")), spec.pop("motion"), spec.pop("title", "")
        name = f"{solution.id or 'problem'}_{k}.html".replace("/", "_")
        started = time.perf_counter()
        export_html(robot, motion, Path(directory) / prefix / name, title=f"Problem {solution.id}: {caption}", **spec)
        elapsed = time.perf_counter() - started
        t, q = motion_of(motion, robot)
        R_up = up_rotation(robot.model.gravity.linear)
        camera = spec.get("camera") or default_camera(robot, R_up)
        poster = poster_svg(robot, t, q, R_up, camera, label=caption or robot.name)
        snippets.append(
            f'<figure class="animation" data-src="{prefix}/{name}"><div class="stage">'
            f'<button type="button" class="poster" title="play the 3-D animation">{poster}</button></div>'
            f"<figcaption>{html_lib.escape(caption or robot.name)} — 3-D animation (plays when scrolled into view "
            f"or clicked; drag to orbit; controls at the top right; exported in {elapsed:.1f} s)</figcaption></figure>")
    return snippets


#: The report page's script for its animations (:func:`report_animations`): an animation is live (an ``<iframe>``
#: of its page) while its figure is within 300 px of the window or after a click, at most ``MAX_LIVE`` at once (the
#: oldest released first); a figure scrolled away gets its poster back and its iframe removed — the document and
#: its WebGL context go with it (``loseContext`` would leave a console warning). Chromium keeps 16 contexts.
MAX_LIVE_ANIMATIONS = 4
LIVE_ANIMATIONS_SCRIPT = """<script>
(function () {
  var MAX_LIVE = %d, live = [];
  function release(fig) {
    var frame = fig.querySelector("iframe");
    if (frame) { frame.src = "about:blank"; frame.remove(); }
    fig.classList.remove("live");
    var i = live.indexOf(fig);
    if (i >= 0) live.splice(i, 1);
  }
  function play(fig) {
    if (live.indexOf(fig) >= 0) return;
    while (live.length >= MAX_LIVE) release(live[0]);
    var frame = document.createElement("iframe");
    frame.src = fig.dataset.src;
    frame.title = "3-D animation";
    fig.querySelector(".stage").appendChild(frame);
    fig.classList.add("live");
    live.push(fig);
  }
  var figures = document.querySelectorAll("figure.animation[data-src]");
  var watch = new IntersectionObserver(function (entries) {
    entries.forEach(function (e) { if (e.isIntersecting) play(e.target); else release(e.target); });
  }, {rootMargin: "300px 0px"});
  figures.forEach(function (fig) {
    fig.querySelector(".poster").addEventListener("click", function () { play(fig); });
    watch.observe(fig);
  });
  window.rmpcLiveAnimations = function () { return live.length; };
})();
</script>""" % MAX_LIVE_ANIMATIONS
LIVE_ANIMATIONS_STYLE = (
    "figure.animation{display:block;margin:4px 0} figure.animation .stage{position:relative;width:100%;height:420px;"
    "border:1px solid #ccc} figure.animation .poster{all:unset;cursor:pointer;display:block;width:100%;height:100%}"
    " figure.animation .poster svg{width:100%;height:100%} figure.animation iframe{position:absolute;inset:0;"
    "width:100%;height:100%;border:0} figure.animation.live .poster{visibility:hidden}")
