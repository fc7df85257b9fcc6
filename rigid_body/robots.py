"""Robots: a Pinocchio model + data + named frames + the URDF it came from, and ``load()``.

``load("planar_2r")`` loads one of the book's robots from ``urdf/`` (regenerated from its DH table
when a parameter is changed: ``load("planar_2r", payload=10.0)``), ``load("panda")`` one of the
robots shipped by the ``example-robot-data`` wheel, ``load("path/to/robot.urdf")`` any URDF file.
"""

from __future__ import annotations

import difflib
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

URDF_DIR = Path(__file__).resolve().parent.parent / "urdf"

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


@dataclass
class Robot:
    """A Pinocchio model with its data, end-effector frame and source URDF.

    Attributes
    ----------
    name : the robot's name.
    model, data : ``pin.Model`` and a ``pin.Data`` made for it (scratch space of the algorithms).
    ee_frame : id of the end-effector frame (``ee`` for the book's robots).
    urdf_path : the URDF file, or None for a model built in memory.
    urdf_xml : the URDF text the model was built from.
    configurations : named joint configurations (e.g. ``"neutral"``).
    """

    name: str
    model: pin.Model
    data: pin.Data
    ee_frame: int
    urdf_path: Path | None = None
    urdf_xml: str = ""
    configurations: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def nq(self) -> int:
        return self.model.nq

    @property
    def nv(self) -> int:
        return self.model.nv

    has_mimic: bool = field(init=False)

    def __post_init__(self) -> None:
        # True when the model has mimic joints (the book's rotors): ABA is then unavailable.
        self.has_mimic = len(getattr(self.model, "mimicking_joints", ())) > 0

    def frame_id(self, name: str) -> int:
        """Id of the frame ``name``; ValueError listing the frames when it does not exist."""
        if not self.model.existFrame(name):
            names = [f.name for f in self.model.frames]
            near = difflib.get_close_matches(name, names, n=5)
            raise ValueError(f"robot {self.name!r} has no frame {name!r}; nearest: {near}")
        return self.model.getFrameId(name)

    def frame(self, name_or_id: str | int) -> int:
        return name_or_id if isinstance(name_or_id, (int, np.integer)) else self.frame_id(name_or_id)

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


LOCKED_JOINTS: dict[str, tuple[str, ...]] = {"panda": ("panda_finger_joint1", "panda_finger_joint2")}


def _build(xml: str, gravity: Any | None, name: str, ee: str | None, path: Path | None,
           lock: tuple[str, ...] = ()) -> Robot:
    model = pin.buildModelFromXML(xml, mimic=not lock)
    if lock:
        ids = [model.getJointId(j) for j in lock if model.existJointName(j)]
        model = pin.buildReducedModel(model, ids, pin.neutral(model))
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
    robot = Robot(name=name, model=model, data=model.createData(), ee_frame=model.getFrameId(ee),
                  urdf_path=path, urdf_xml=xml)
    robot.configurations["neutral"] = pin.neutral(model)
    return robot


def robot_from_urdf_string(xml: str, gravity: Any | None = (0.0, 0.0, -9.81), name: str | None = None,
                           ee: str | None = None) -> Robot:
    """Build a Robot from URDF text, keeping ``<mimic>`` joints (the book's rotors)."""
    if name is None:
        import re

        match = re.search(r'<robot[^>]*name="([^"]+)"', xml)
        name = match.group(1) if match else "robot"
    return _build(xml, gravity, name, ee, None)


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
    xml = path.read_text()
    # Mesh paths (package://example-robot-data/robots/...) are not needed for kinematics/dynamics.
    return _build(xml, (0.0, 0.0, -9.81), name, ee, path, LOCKED_JOINTS.get(name, ()))


def available() -> list[str]:
    """Names accepted by :func:`load`: the book's robots and the example-robot-data robots."""
    from urdf.book_robots import BOOK_ROBOTS

    return sorted(BOOK_ROBOTS) + sorted(EXAMPLE_ROBOTS)


def load(name_or_path: str | os.PathLike, **params: Any) -> Robot:
    """Load a robot by name (book or example-robot-data) or from a URDF path.

    Keyword parameters change the book robot's data (``payload``, link lengths ``a``, ...) and
    regenerate it from its DH table; without them the committed URDF file in ``urdf/`` is used.

    >>> load("planar_2r").model.nq
    2
    """
    from urdf.book_robots import BOOK_ROBOTS, book_robot_spec

    key = str(name_or_path)
    if key in BOOK_ROBOTS:
        spec = book_robot_spec(key, **params)
        path = URDF_DIR / f"{key}.urdf"
        if not params and path.is_file():
            return _build(path.read_text(), spec.gravity, key, "ee", path)
        return _build(spec.urdf(), spec.gravity, key, "ee", None)
    if params:
        raise TypeError(f"parameters {sorted(params)} are only accepted for the book's robots")
    if key in EXAMPLE_ROBOTS:
        return _load_example_robot(key)
    path = Path(key)
    if path.suffix == ".urdf" or os.sep in key:
        if not path.is_file():
            raise FileNotFoundError(f"no URDF file at {path}")
        return _build(path.read_text(), (0.0, 0.0, -9.81), path.stem, None, path)
    names = available()
    near = difflib.get_close_matches(key, names, n=3)
    hint = f" Did you mean {', '.join(near)}?" if near else ""
    raise ValueError(f"unknown robot {key!r}.{hint} Available: {', '.join(names)}, or a path to a .urdf file")
