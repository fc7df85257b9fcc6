"""The Franka Emika Panda as a standard DH table (the book's convention), for the dynamics references.

Franka publishes the Panda's kinematics in Craig's modified DH convention, with rows
(a_{i−1}, α_{i−1}, d_i) and θ_i = q_i. The joint frames of example-robot-data's ``panda.urdf`` are
those Craig frames. Craig's product Π Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i) Tz(d_i) regroups into the
book's A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i) (2.52), with (a_i, α_i) taken from Craig's next row:
the book's frame i is Craig's frame i times Tx(a_i) Rx(α_i). The base frames coincide.

Inertial data come from the example-robot-data URDF as Pinocchio parses it: one lumped body per
joint, in Craig's frame i. The hand and the locked fingers are merged into link 7. They are moved
into the book's frame i here. The flange and hand, Tz(0.107) Rz(−π/4), form the tool.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 2.8.2;
Franka Control Interface documentation (robot kinematics, modified DH parameters).
"""

from __future__ import annotations

import numpy as np

from rigid_body.dh import DHLink, dh_transform

# Craig rows (a_{i-1} [m], α_{i-1} [rad], d_i [m]) of joints 1..7, then the flange (d = 0.107 m).
PANDA_MODIFIED_DH = (
    (0.0, 0.0, 0.333),
    (0.0, -np.pi / 2, 0.0),
    (0.0, np.pi / 2, 0.316),
    (0.0825, np.pi / 2, 0.0),
    (-0.0825, -np.pi / 2, 0.384),
    (0.0, np.pi / 2, 0.0),
    (0.088, np.pi / 2, 0.0),
)
FLANGE = 0.107
HAND_ROTATION = -np.pi / 4


def panda_tool() -> np.ndarray:
    """Frame 7 → ``panda_hand``: Tz(0.107) Rz(−π/4)."""
    return dh_transform(0.0, 0.0, FLANGE, HAND_ROTATION)


def panda_links() -> tuple[DHLink, ...]:
    """The Panda's standard DH table, with the inertial data of example-robot-data's URDF."""
    from rigid_body.robots import load

    model = load("panda").model
    rows = list(PANDA_MODIFIED_DH) + [(0.0, 0.0, FLANGE)]
    links = []
    for i in range(7):
        a, alpha = rows[i + 1][0], rows[i + 1][1]
        T_fix = dh_transform(a, alpha, 0.0, 0.0)  # Craig frame i -> book frame i: Tx(a_i) Rx(α_i)
        R, p = T_fix[:3, :3], T_fix[:3, 3]
        inertia = model.inertias[model.getJointId(f"panda_joint{i + 1}")]
        lower = model.lowerPositionLimit[i]
        upper = model.upperPositionLimit[i]
        links.append(DHLink(
            a=a, alpha=alpha, d=rows[i][2], mass=float(inertia.mass),
            com=tuple(R.T @ (np.asarray(inertia.lever) - p)), inertia=R.T @ np.asarray(inertia.inertia) @ R,
            lower=float(lower), upper=float(upper), name=f"joint_{i + 1}"))
    return tuple(links)
