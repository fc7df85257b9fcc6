"""Tree-structured manipulators built from DH chains: the humanoid of Sect. 2.9.8 and the branches of closed chains.

A tree is a list of :class:`DHBranch`: each branch is a serial DH chain (written by
:func:`rigid_body.dh.urdf_from_dh`, so inertias, rotors and the ``frame_i`` layout are the same as
for a serial arm), its names prefixed, mounted by a constant transform on a link of an earlier
branch. Pinocchio then gives every branch's frames in the common base frame, which the tests
compare with the matrix products of the book (e.g. (2.78)–(2.79)).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 2.8.3 (closed chains, tree structure), 2.9.8 (humanoid manipulator); Problem 2.14.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
import pinocchio as pin

from rigid_body.dh import GRAVITY, DHLink, as_links, dh_chain, urdf_from_dh
from rigid_body.robots import Robot, robot_from_urdf_string
from rigid_body.rotations import as_homogeneous
from rigid_body.validation import as_vector


@dataclass(frozen=True)
class DHBranch:
    """One serial DH chain of a tree.

    ``prefix`` is prepended to its link and joint names (``left_frame_3``, ``left_joint_2``, ``left_ee``);
    ``parent`` is the (prefixed) link it hangs from, None for the root branch; ``mount`` is the constant
    transform from ``parent`` to the branch's ``frame_0``; ``tool`` from its last DH frame to its ``ee``.
    """

    prefix: str
    links: tuple[DHLink, ...]
    parent: str | None = None
    mount: Any = field(default_factory=lambda: np.eye(4))
    tool: Any = None


def urdf_tree_from_dh(branches: Sequence[DHBranch], name: str = "dh_tree") -> str:
    """URDF text of a tree of DH chains (joint order = branch order, then DH order)."""
    from lxml import etree

    if not branches or branches[0].parent is not None:
        raise ValueError("`branches` must start with the root branch (parent=None)")
    root = etree.Element("robot", name=name)
    known: set[str] = set()
    for b, branch in enumerate(branches):
        if b > 0 and branch.parent not in known:
            raise ValueError(f"branch {branch.prefix!r}: parent link {branch.parent!r} is not in an earlier branch")
        xml = urdf_from_dh(as_links(branch.links), name=branch.prefix, tool=branch.tool)
        chain = etree.fromstring(xml.encode())
        for element in chain:
            if element.tag in ("link", "joint"):
                element.set("name", branch.prefix + element.get("name"))
                for tag in ("parent", "child"):
                    ref = element.find(tag)
                    if ref is not None:
                        ref.set("link", branch.prefix + ref.get("link"))
                mimic = element.find("mimic")
                if mimic is not None:
                    mimic.set("joint", branch.prefix + mimic.get("joint"))
                if element.tag == "link":
                    known.add(element.get("name"))
                root.append(element)
        if branch.parent is not None:
            T = as_homogeneous(branch.mount, "mount")
            joint = etree.SubElement(root, "joint", name=f"{branch.prefix}mount", type="fixed")
            etree.SubElement(joint, "parent", link=branch.parent)
            etree.SubElement(joint, "child", link=f"{branch.prefix}frame_0")
            rpy = pin.rpy.matrixToRpy(T[:3, :3])
            etree.SubElement(joint, "origin", xyz=" ".join(repr(float(v)) for v in T[:3, 3]),
                             rpy=" ".join(repr(float(v)) for v in rpy))
    return etree.tostring(root, pretty_print=True, xml_declaration=True, encoding="utf-8").decode()


def robot_from_dh_tree(branches: Sequence[DHBranch], name: str = "dh_tree", ee: str | None = None,
                       gravity: Any = GRAVITY) -> Robot:
    """A :class:`Robot` of a tree of DH chains (``ee`` defaults to the last branch's ``ee``)."""
    xml = urdf_tree_from_dh(branches, name)
    return robot_from_urdf_string(xml, gravity=gravity, name=name, ee=ee or f"{branches[-1].prefix}ee")


# --------------------------------------------------------------------------------------------
# The humanoid manipulator (Sect. 2.9.8, Problem 2.14)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Humanoid:
    """Geometry of the humanoid manipulator of Fig. 2.28 (torso 3 DOF + two 7-DOF arms).

    The torso is the anthropomorphic arm (2.66) with lengths ``a2``, ``a3``. The shoulder frames l, r
    sit at distances ``d_l``, ``d_r`` from the torso frame t, at angle ``beta`` (Problem 2.14).
    Inferred data (not in the solution manual): the arms use the DLR table
    (2.72) with the link matrix (2.77) taken as α_i = −π/2 (i = 1..6), offsets d3, d5, d7;
    T_t^3 = ``T_t3`` (default identity: frame t coincides with frame 3); the numbers are test values.
    """

    a2: float = 0.3
    a3: float = 0.3
    beta: float = np.pi / 6
    d_l: float = 0.3
    d_r: float = 0.3
    d3: float = 0.4
    d5: float = 0.4
    d7: float = 0.1
    T_t3: Any = field(default_factory=lambda: np.eye(4))

    def __post_init__(self) -> None:
        for key in ("a2", "a3", "beta", "d_l", "d_r", "d3", "d5", "d7"):
            if not np.isfinite(getattr(self, key)):
                raise ValueError(f"humanoid `{key}` must be finite")
        as_homogeneous(self.T_t3, "T_t3")

    @property
    def torso_links(self) -> tuple[DHLink, ...]:
        """Anthropomorphic arm (0, π/2, 0, θ1), (a2, 0, 0, θ2), (a3, 0, 0, θ3), Eq. (2.66)."""
        return (DHLink(alpha=np.pi / 2), DHLink(a=self.a2), DHLink(a=self.a3))

    @property
    def arm_links(self) -> tuple[DHLink, ...]:
        """7-DOF arm: (0, −π/2, d_i, θ_i), i = 1..6 with d = (0, 0, d3, 0, d5, 0), then (0, 0, d7, θ7)."""
        d = (0.0, 0.0, self.d3, 0.0, self.d5, 0.0)
        return tuple(DHLink(alpha=-np.pi / 2, d=di) for di in d) + (DHLink(d=self.d7),)

    def shoulders(self) -> tuple[np.ndarray, np.ndarray]:
        """(T_l^t, T_r^t) of Problem 2.14: o_tl = [d_l cβ, 0, d_l sβ], R_l^t = [[0, −sβ, cβ], [1, 0, 0], [0, cβ, sβ]], ..."""
        c, s = np.cos(self.beta), np.sin(self.beta)
        T_l, T_r = np.eye(4), np.eye(4)
        T_l[:3, :3] = [[0.0, -s, c], [1.0, 0.0, 0.0], [0.0, c, s]]
        T_l[:3, 3] = [self.d_l * c, 0.0, self.d_l * s]
        T_r[:3, :3] = [[0.0, s, c], [1.0, 0.0, 0.0], [0.0, c, -s]]
        T_r[:3, 3] = [self.d_r * c, 0.0, -self.d_r * s]
        return T_l, T_r

    def branches(self) -> list[DHBranch]:
        T_l, T_r = self.shoulders()
        return [
            DHBranch("torso_", self.torso_links, tool=np.asarray(self.T_t3, dtype=float)),
            DHBranch("left_", self.arm_links, parent="torso_ee", mount=T_l),
            DHBranch("right_", self.arm_links, parent="torso_ee", mount=T_r),
        ]

    def robot(self) -> Robot:
        """Pinocchio model of the tree; q = [torso (3), left arm (7), right arm (7)]; frames ``left_ee``, ``right_ee``."""
        return robot_from_dh_tree(self.branches(), name="humanoid", ee="left_ee")

    def hand_poses(self, q: Any) -> tuple[np.ndarray, np.ndarray]:
        """(T_lh^0, T_rh^0) = T_3^0 T_t^3 T_l^t T_lh^l and T_3^0 T_t^3 T_r^t T_rh^r, Eqs. (2.78)–(2.79)."""
        q = as_vector(q, 17, "q")
        T_l, T_r = self.shoulders()
        T_t0 = dh_chain(self.torso_links, q[:3])[-1] @ np.asarray(self.T_t3, dtype=float)
        return (T_t0 @ T_l @ dh_chain(self.arm_links, q[3:10])[-1],
                T_t0 @ T_r @ dh_chain(self.arm_links, q[10:17])[-1])
