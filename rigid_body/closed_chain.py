"""The four-link closed-chain planar arm of Problem 2.11 (Sect. 2.8.3): cut joint, branches, loop constraints.

Cutting joint 4 opens the loop into a tree with two branches from base frame 0 (Table S2.1):
branch ' = links 1', 2', 3' and branch '' = link 1''; link 4 is the constant A_4^{3'} = Tz(d4).
The loop closes when (2.60), with θ_{3'1''} = π, holds:

* z_{3'} = z_{1''} and x_{3'}^T x_{1''} = −1  →  θ2' + θ3' = π − θ1' + θ1''           (S2.1)
* [x_{3'}^T; y_{3'}^T] (p_{3'} − p_{1''}) = 0  →  c3' = (−a1'' + a1' cos(θ1'' − θ1'))/a2'   (S2.2)

so the actuated joints q = [θ1', θ1''] fix θ2', θ3' (two branches s3' = ±√(1 − c3'²)).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 2.8.3, Eqs. (2.52), (2.60); solution manual, Problem 2.11, Table S2.1, (S2.1)–(S2.2).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rigid_body.dh import DHLink, dh_chain
from rigid_body.rotations import as_homogeneous
from rigid_body.trees import DHBranch
from rigid_body.validation import as_vector


@dataclass(frozen=True)
class FourLinkClosedChain:
    """Lengths of Table S2.1: a1', a2' (branch '), a1'' (branch ''), d4 (link 4) [m]."""

    a1p: float
    a2p: float
    a1pp: float
    d4: float

    def __post_init__(self) -> None:
        for key in ("a1p", "a2p", "a1pp", "d4"):
            value = getattr(self, key)
            if not np.isfinite(value):
                raise ValueError(f"closed chain `{key}` must be finite, got {value!r}")
        if min(self.a1p, self.a2p, self.a1pp) <= 0:
            raise ValueError("closed chain link lengths a1', a2', a1'' must be positive")

    @property
    def branch_1(self) -> tuple[DHLink, ...]:
        """Links 1', 2', 3' of Table S2.1: (a1', 0, 0, θ1'), (a2', 0, 0, θ2'), (0, π/2, 0, θ3')."""
        return (DHLink(a=self.a1p), DHLink(a=self.a2p), DHLink(alpha=np.pi / 2))

    @property
    def branch_2(self) -> tuple[DHLink, ...]:
        """Link 1'' of Table S2.1: (a1'', −π/2, 0, θ1'')."""
        return (DHLink(a=self.a1pp, alpha=-np.pi / 2),)

    @property
    def A_4_3p(self) -> np.ndarray:
        """The constant A_4^{3'} = Tz(d4) of link 4."""
        T = np.eye(4)
        T[2, 3] = self.d4
        return T

    def branches(self) -> list[DHBranch]:
        """The tree obtained by cutting joint 4 (for :func:`rigid_body.trees.robot_from_dh_tree`).

        Branch ' (prefix ``b1_``, its ``ee`` = frame 4), branch '' (prefix ``b2_``) from the same base frame.
        """
        return [DHBranch("b1_", self.branch_1, tool=self.A_4_3p),
                DHBranch("b2_", self.branch_2, parent="b1_frame_0")]


def closed_chain_joints(chain: FourLinkClosedChain, q: Any, sign: int = 1) -> np.ndarray:
    """All joints [θ1', θ2', θ3', θ1''] closing the loop at the actuated q = [θ1', θ1''], Eqs. (S2.1)–(S2.2).

    ``sign`` picks s3' = sign·√(1 − c3'²). ValueError when |c3'| > 1 (possible only if a1' + a1'' > a2').
    """
    th1p, th1pp = as_vector(q, 2, "q")
    if sign not in (1, -1):
        raise ValueError(f"`sign` must be +1 or -1, got {sign!r}")
    c3 = (-chain.a1pp + chain.a1p * np.cos(th1pp - th1p)) / chain.a2p  # (S2.2)
    if abs(c3) > 1.0 + 1e-12:
        raise ValueError(f"the loop cannot close at q = {[th1p, th1pp]}: c3' = {c3:.6g} (a1' + a1'' > a2')")
    c3 = float(np.clip(c3, -1.0, 1.0))
    th3p = np.arctan2(sign * np.sqrt(1.0 - c3**2), c3)
    th2p = np.pi - th1p + th1pp - th3p  # (S2.1)
    return np.array([th1p, th2p, th3p, th1pp])


def loop_constraint_residual(T_3p: Any, T_1pp: Any) -> np.ndarray:
    """Residual (6,) of the loop constraints (2.60) from the poses of frames 3' and 1'' in frame 0.

    [z_{3'} − z_{1''} (3); x_{3'}^T x_{1''} + 1; x_{3'}^T (p_{3'} − p_{1''}); y_{3'}^T (p_{3'} − p_{1''})]:
    zero when the cut joint closes (its axis z_{3'} passes through the origin of frame 1'').
    """
    T_3p = as_homogeneous(T_3p, "T_3p")
    T_1pp = as_homogeneous(T_1pp, "T_1pp")
    x3, y3, z3, p3 = T_3p[:3, 0], T_3p[:3, 1], T_3p[:3, 2], T_3p[:3, 3]
    x1, z1, p1 = T_1pp[:3, 0], T_1pp[:3, 2], T_1pp[:3, 3]
    return np.concatenate([z3 - z1, [x3 @ x1 + 1.0, x3 @ (p3 - p1), y3 @ (p3 - p1)]])


def closed_chain_direct_kinematics(chain: FourLinkClosedChain, q: Any, sign: int = 1) -> np.ndarray:
    """T_4^0(q) = A_{3'}^0(q) A_4^{3'} with θ2', θ3' from (S2.1)–(S2.2), q = [θ1', θ1'']."""
    joints = closed_chain_joints(chain, q, sign)
    return dh_chain(chain.branch_1, joints[:3])[-1] @ chain.A_4_3p
