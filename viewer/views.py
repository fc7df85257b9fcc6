"""Animations of the chapters' tasks: what to draw beside the robot, as keyword arguments of ``animate``.

Each function returns a dictionary ``{"motion": (t, q), "overlays": …, "tracks": …, "fps": …}`` so that
``viewer.animate(robot, **spec)`` or ``viewer.export_html(robot, path=…, **spec)`` shows it and a problem attaches
it with ``sol.animation(robot, title=…, **spec)``:

* :func:`contact_animation` — a contact run (Ch. 9): the surface patches and the contact force as an arrow;
* :func:`eye_in_hand_animation` — an eye-in-hand run (Ch. 10): the camera's viewing pyramid carried by the
  camera frame, the target points and the rays from the optical centre to them;
* :func:`box_overlays` — obstacles (``planners.collision.Box``) and paths for a planned motion (Ch. 12);
  :func:`frame_path` the positions of a frame along configurations (the end effector's path).
"""

from __future__ import annotations

from typing import Any, Callable, Sequence

import numpy as np
import pinocchio as pin

from rigid_body.camera import PinholeCamera
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import Robot
from viewer.scene import arrow_transform

__all__ = ["contact_animation", "eye_in_hand_animation", "box_overlays", "frame_path", "ANIMATION_FPS"]

ANIMATION_FPS = 25.0        # the frame rate of these animations: the runs are decimated to it


def _decimated(res: Any, every: int | None) -> np.ndarray:
    """Sample indices of a run at :data:`ANIMATION_FPS` (or one in ``every``), the last one kept."""
    if every is None:
        every = max(1, int(round(1.0 / (ANIMATION_FPS * (res.t[1] - res.t[0]))))) if len(res.t) > 1 else 1
    return np.unique(np.r_[np.arange(0, len(res.t), every), len(res.t) - 1])


def contact_animation(robot: Robot, res: Any, normal: Any, patches: Sequence[tuple[Any, tuple[float, float]]],
                      force_scale: float, frame: str | int | None = None, every: int | None = 40) -> dict:
    """A contact run ``res`` (a SimulationResult logging the sensed wrench ``h_e``): the arm, the undeformed
    surface (square ``patches`` (centre (3,), size (2,) [m]) with outward ``normal``) and the force on the
    environment, −h_e, as an arrow from ``frame`` (default: the end effector) of ``force_scale`` [m/N].
    The run is decimated to one sample in ``every`` (40 × 1 ms: 25 frames per second; None: to 25 fps, the last
    sample kept)."""
    idx = _decimated(res, None) if every is None else np.arange(0, len(res.t), every)
    t, q = res.t[idx], res.q[idx]
    h = np.asarray(res["h_e"], dtype=float)[idx]
    force = np.zeros((idx.size, 3))
    force[:, :min(3, h.shape[1])] = -h[:, :3]
    tip = np.array([direct_kinematics(robot, qk, frame)[:3, 3] for qk in q])
    arrows = np.array([arrow_transform(p, force_scale * f) for p, f in zip(tip, force)])
    surfaces = [(np.asarray(c, dtype=float), tuple(size)) for c, size in patches]

    def overlays(scene: Any) -> None:
        for k, (center, size) in enumerate(surfaces):
            scene.plane(f"surface{k}", center, normal, size)
        scene.arrow("force", tip[0], force_scale * force[0], color="#d62728")

    return {"motion": (t, q), "overlays": overlays, "tracks": {"force": arrows}, "fps": ANIMATION_FPS}


def _ray_pose(origin: np.ndarray, point: np.ndarray) -> np.ndarray:
    """The pose (with a scale) taking the unit segment [0, e_z] to the segment from ``origin`` to ``point``."""
    d = point - origin
    length = float(np.linalg.norm(d))
    z = d / length
    x = np.cross([0.0, 1.0, 0.0] if abs(z[1]) < 0.9 else [1.0, 0.0, 0.0], z)
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, np.cross(z, x), length * z])
    T[:3, 3] = origin
    return T


def eye_in_hand_animation(robot: Robot, res: Any, points_b: Any, frame: str | int | None = None,
                          half_width: tuple[float, float] = (0.3, 0.3), depth: float = 0.3,
                          speed: float = 1.0) -> dict:
    """An eye-in-hand run ``res``: the arm (decimated to :data:`ANIMATION_FPS`), the camera's viewing pyramid
    (normalised half-widths ``half_width``, out to ``depth`` [m]) carried by the camera frame ``frame`` (default:
    the end effector), the target points ``points_b`` (n, 3, base frame) and the rays from the optical centre to
    each point. ``speed`` scales the playback."""
    keep = _decimated(res, None)
    t, q = res.t[keep], res.q[keep]
    poses = np.array([direct_kinematics(robot, qk, frame) for qk in q])
    pts = np.asarray(points_b, dtype=float)
    tracks = {"camera": poses}
    for i, p in enumerate(pts):
        tracks[f"ray_{i + 1}"] = np.array([_ray_pose(T[:3, 3], p) for T in poses])
    hx, hy = half_width
    pinhole = PinholeCamera(1.0, 1.0, hx, hy)          # normalised coordinates: the image spans ±half-widths

    def overlays(scene: Any) -> None:
        scene.frustum("camera", poses[0], pinhole, (2 * hx, 2 * hy), depth=depth, color="#1f77b4")
        scene.points("target", pts, size=0.03)
        for i in range(len(pts)):
            scene.polyline(f"ray_{i + 1}", np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]]), color="#ff7f0e")

    return {"motion": (t, q), "overlays": overlays, "tracks": tracks, "fps": ANIMATION_FPS, "speed": speed}


def box_overlays(boxes: Any, polylines: tuple = ()) -> Callable[[Any], None]:
    """An ``overlays`` function drawing the boxes (grey, ``planners.collision.Box``: centre and size) and
    polylines (e.g. the end-effector path of :func:`frame_path`, 5 mm tubes)."""
    def draw(scene: Any) -> None:
        for k, b in enumerate(boxes):
            scene.box(f"obstacles/{b.name}_{k}", pin.SE3(np.eye(3), np.asarray(b.center, dtype=float)).homogeneous,
                      b.size, color="#8c8c8c", opacity=0.6)
        for k, p in enumerate(polylines):
            scene.polyline(f"paths/{k}", p, radius=0.005)
    return draw


def frame_path(robot: Robot, Q: Any, frame: str | int | None = None) -> np.ndarray:
    """Positions (N, 3) [m] of ``frame`` (default: the end effector) at the configurations Q (N, nq)."""
    fid = robot.ee_frame if frame is None else robot.frame(frame)
    data = robot.model.createData()
    out = []
    for q in np.atleast_2d(np.asarray(Q, dtype=float)):
        pin.framesForwardKinematics(robot.model, data, q)
        out.append(data.oMf[fid].translation.copy())
    return np.array(out)
