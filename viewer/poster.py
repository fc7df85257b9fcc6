"""A still picture of an animation: the robot's skeleton at the first sample and the path of its end effector, seen
from the animation's viewpoint, as a small inline SVG (no WebGL, no file, no network).

The report shows one in place of each 3-D animation until the reader scrolls to it or clicks it (a page keeps only
a few live WebGL views: :func:`viewer.animation.report_animations`).
"""

from __future__ import annotations

import html
from typing import Any

import numpy as np
import pinocchio as pin

from rigid_body.robots import Robot

__all__ = ["poster_svg"]

POSTER_SAMPLES = 120      # at most this many points of the end effector's path


def _basis(position: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Forward, right and up unit vectors of a camera at ``position`` looking at ``target`` (z up)."""
    forward = target - position
    forward = forward / max(float(np.linalg.norm(forward)), 1e-12)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    if np.linalg.norm(right) < 1e-6:                 # looking straight down: x to the right
        right = np.array([1.0, 0.0, 0.0])
    right = right / np.linalg.norm(right)
    return forward, right, np.cross(right, forward)


def _segments(robot: Robot, q: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """The skeleton at q (base frame): each joint's origin to its children's and to its body frames' origins."""
    model, data = robot.model, robot.model.createData()
    pin.framesForwardKinematics(model, data, q)
    mimic = set(getattr(model, "mimicking_joints", ()))
    out = []
    for j in range(1, model.njoints):
        if j not in mimic:
            out.append((data.oMi[model.parents[j]].translation.copy(), data.oMi[j].translation.copy()))
    for k, f in enumerate(model.frames):
        if f.type == pin.FrameType.BODY:
            out.append((data.oMi[f.parentJoint].translation.copy(), data.oMf[k].translation.copy()))
    return [(a, b) for a, b in out if np.linalg.norm(b - a) > 1e-9]


def poster_svg(robot: Robot, t: np.ndarray, q: np.ndarray, R_up: np.ndarray, camera: tuple[Any, Any],
               label: str = "", width: int = 640, height: int = 420) -> str:
    """An SVG (``width`` × ``height`` user units, scaled to its box) of ``robot`` at ``q[0]``: its skeleton (orange)
    and the path of its end effector over ``q`` (grey), seen from ``camera`` = (position, target) in the viewer's
    frame (the robot's base frame turned by ``R_up``), with a play mark and ``label``."""
    position, target = (np.asarray(v, dtype=float) for v in camera)
    forward, right, up = _basis(position, target)

    def project(points: np.ndarray) -> np.ndarray:
        v = np.atleast_2d(points) @ R_up.T - position
        depth = np.maximum(v @ forward, 1e-3)
        return np.column_stack([(v @ right) / depth, -(v @ up) / depth])

    segments = _segments(robot, q[0])
    every = max(1, len(q) // POSTER_SAMPLES)
    model, data = robot.model, robot.model.createData()
    path = []
    for qk in q[::every]:
        pin.framesForwardKinematics(model, data, qk)
        path.append(data.oMf[robot.ee_frame].translation.copy())
    path = np.array(path)
    ends = np.array([p for s in segments for p in s]).reshape(-1, 3)
    screen = project(np.vstack([ends, path]))
    lo, hi = screen.min(axis=0), screen.max(axis=0)
    span = np.maximum(hi - lo, 1e-9)
    scale = 0.8 * min(width / span[0], height / span[1])
    offset = np.array([width, height]) / 2 - scale * (lo + hi) / 2

    def xy(p: np.ndarray) -> np.ndarray:
        return project(p) * scale + offset

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {width} {height}" preserveAspectRatio="xMidYMid meet" '
             f'role="img" aria-label="{html.escape(label or robot.name)}">',
             f'<rect width="{width}" height="{height}" fill="#f3f5f8"/>']
    if len(path) > 1:
        pts = " ".join(f"{x:.1f},{y:.1f}" for x, y in xy(path))
        parts.append(f'<polyline points="{pts}" fill="none" stroke="#9aa3ad" stroke-width="2" stroke-dasharray="5 4"/>')
    for a, b in segments:
        (x1, y1), (x2, y2) = xy(np.vstack([a, b]))
        parts.append(f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" stroke="#e67319" '
                     'stroke-width="7" stroke-linecap="round"/>')
    x0, y0 = xy(path[:1])[0]
    parts.append(f'<circle cx="{x0:.1f}" cy="{y0:.1f}" r="6" fill="#1f77b4"/>')
    cx, cy = width / 2, height / 2
    parts.append(f'<circle cx="{cx}" cy="{cy}" r="34" fill="#000" fill-opacity="0.45"/>'
                 f'<path d="M{cx - 11},{cy - 18} L{cx + 19},{cy} L{cx - 11},{cy + 18} Z" fill="#fff"/>')
    parts.append(f'<text x="12" y="{height - 14}" font-family="sans-serif" font-size="15" fill="#333">'
                 f'{html.escape(label)}</text></svg>')
    return "".join(parts)
