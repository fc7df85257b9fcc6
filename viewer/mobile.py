"""A mobile robot for the viewer: a rigid body moving in the plane, q = (x, y, θ) (the book's posture, Ch. 11).

A wheeled robot has no URDF arm. :func:`planar_body` generates a small model whose configuration *is*
the posture — a prismatic joint along x, one along y, a revolute joint about z — carrying a box (the
chassis) and a heading arrow along the body's x axis. It is an ordinary ``Robot``, so ``show``,
``animate``, ``export_html`` and ``Solution.animation`` draw it along a ``SimulationResult`` of a
unicycle plant (its state starts with x, y, θ), a planner's path ``(t, Q)`` or any pose trajectory of
a rigid body in the plane. θ is a revolute coordinate, not wrapped: unwrap sampled angles first
(``np.unwrap``) so that playback does not spin through 2π between two samples.

>>> robot = planar_body(0.4, 0.25)
>>> robot.model.nq
3
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rigid_body.robots import Robot, robot_from_urdf_string
from rigid_body.validation import as_positive

BODY_COLOR = "0.90 0.45 0.10 1"    # the skeleton's orange (the browser test looks for it)
ARROW_COLOR = "0.15 0.15 0.15 1"
THETA_LIMIT = 1e3                  # [rad]: θ is not wrapped (many turns allowed)


def _link(name: str, visuals: str = "") -> str:
    # a tiny inertia: the model is only drawn, but rmpc's URDF loader wants physical bodies
    return (f'<link name="{name}"><inertial><mass value="1e-3"/><inertia ixx="1e-6" iyy="1e-6" izz="1e-6" '
            f'ixy="0" ixz="0" iyz="0"/></inertial>{visuals}</link>')


def _visual(name: str, xyz: tuple[float, ...], box: tuple[float, ...], rgba: str) -> str:
    return (f'<visual name="{name}"><origin xyz="{xyz[0]:g} {xyz[1]:g} {xyz[2]:g}"/>'
            f'<geometry><box size="{box[0]:g} {box[1]:g} {box[2]:g}"/></geometry>'
            f'<material name="{name}"><color rgba="{rgba}"/></material></visual>')


def planar_body(length: float = 0.4, width: float = 0.25, height: float = 0.08, name: str = "unicycle",
                bounds: Any = (-5.0, 5.0, -5.0, 5.0), offset: float = 0.0) -> Robot:
    """A rigid body in the plane, q = (x, y, θ): a ``length`` × ``width`` × ``height`` box [m] whose
    centre is ``offset`` [m] ahead of the point (x, y) (the unicycle's wheel axle midpoint), with a dark
    arrow from (x, y) along the heading θ.

    ``bounds`` = (x_min, x_max, y_min, y_max) are the prismatic joints' limits (where the viewer's
    default camera looks). No gravity: the viewer shows the plane horizontal, seen from above.
    """
    L, W, H = (as_positive(v, k) for v, k in ((length, "length"), (width, "width"), (height, "height")))
    b = np.asarray(bounds, dtype=float)
    if b.shape != (4,) or not np.all(np.isfinite(b)) or b[0] >= b[1] or b[2] >= b[3]:
        raise ValueError(f"`bounds` must be finite (x_min, x_max, y_min, y_max) with min < max, got {bounds!r}")
    d = float(offset)
    if not abs(d) < L / 2:  # (x, y) inside the chassis; also rejects NaN
        raise ValueError(f"`offset` must lie within ±length/2 = ±{L / 2:g} m, got {offset!r}")
    shaft, head = 0.55 * L + d, 0.2 * L   # the arrow: from (x, y) to 0.15 L beyond the front face
    visuals = (_visual("chassis", (d, 0.0, H / 2), (L, W, H), BODY_COLOR)
               + _visual("arrow_shaft", (shaft / 2, 0.0, H + 0.01), (shaft, 0.12 * W, 0.02), ARROW_COLOR)
               + _visual("arrow_head", (shaft + head / 2, 0.0, H + 0.01), (head, 0.4 * W, 0.02), ARROW_COLOR))
    joint = ('<joint name="{n}" type="{kind}"><parent link="{p}"/><child link="{c}"/><axis xyz="{axis}"/>'
             '<limit lower="{lo:g}" upper="{hi:g}" effort="1" velocity="1"/></joint>')
    xml = (f'<robot name="{name}">' + _link("world") + _link("carriage_x") + _link("carriage_y")
           + _link("body", visuals) + _link("ee")
           + joint.format(n="x", kind="prismatic", p="world", c="carriage_x", axis="1 0 0", lo=b[0], hi=b[1])
           + joint.format(n="y", kind="prismatic", p="carriage_x", c="carriage_y", axis="0 1 0", lo=b[2], hi=b[3])
           + joint.format(n="theta", kind="revolute", p="carriage_y", c="body", axis="0 0 1",
                          lo=-THETA_LIMIT, hi=THETA_LIMIT)
           + '<joint name="ee_joint" type="fixed"><parent link="body"/><child link="ee"/></joint></robot>')
    return robot_from_urdf_string(xml, gravity=np.zeros(3), name=name, ee="ee")


def plane_camera(points: Any, margin: float = 0.3) -> tuple[np.ndarray, np.ndarray]:
    """A viewpoint ``(position, target)`` above the plane z = 0 framing the planar ``points`` (N, 2)
    (a path, obstacles' corners) with ``margin`` [m] around them; for ``animate(..., camera=...)``."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    if p.size == 0 or not np.all(np.isfinite(p)):
        raise ValueError("`points` must be a non-empty finite (N, 2) array")
    lo, hi = p.min(axis=0) - margin, p.max(axis=0) + margin
    centre = np.r_[(lo + hi) / 2, 0.0]
    extent = float(max(hi - lo))
    return centre + np.array([0.0, -0.05, 0.75]) * extent, centre  # meshcat: a 75° field of view
