"""The book's robots as data: DH tables (Siciliano et al. 2009), inertial and motor data, gravity.

Every ``urdf/<name>.urdf`` file is generated from these tables by ``python -m rigid_body.book_robots``
(a test regenerates them and compares); ``urdf/`` holds those generated files only. All parameters are
in SI units: m, rad, kg, kg·m². A table's ``payload`` is not written into the file:
``load(name, payload=m)`` adds it to the model (:func:`rigid_body.robots.with_payload`). Each table names
joint configurations inside its limits and away from its singularities (``robot.configurations``): the
manual's postures where it gives one (``planar_2r`` ``p8_10_target``, ``scara`` ``p5_7_camera``, ...),
else an illustrative one (``bent``, ``mid_stroke``, ``extended``), a start for IK and simulation.

Provenance:

* ``planar_2r``: the two-link arm of Sect. 7.3.2 / Example 7.2 / Sect. 8.7, data confirmed by the
  authors' companion file ``param.m`` (a = 1 m, ℓ = 0.5 m, m_ℓ = 50 kg, I_ℓ = 10 kg·m², k_r = 100,
  m_m = 5 kg, I_m = 0.01 kg·m²); vertical plane, gravity along −y₀, g = 9.81 m/s².
* ``scara``: Table S2.3 (all axes pointing down, so the URDF root is DH frame 0 with z₀ down and
  gravity is +g along z₀); a₁ = a₂ = 0.5 m (from the manual's 5.7 matrix). Last link m = 2 kg,
  I = 1 kg·m²; the first two links' inertial data are illustrative (not in the book).
* ``cylindrical``: Table S2.2; ``spherical``, ``anthropomorphic``, ``spherical_wrist``,
  ``anthropomorphic_wrist``: the DH tables of Sect. 2.9 (recalled from the textbook, not printed in
  the solution manual); the lengths are test values; inertial data illustrative.
* ``planar_3r``: Fig. 2.20 arm; a = (0.5, 0.3, 0.2) and the joint limits of Problem 2.17.
* ``cartesian_skew``: the two-link Cartesian arm of Problem 7.1 (joint 2 axis at π/4 to joint 1).
* ``planar_pr``: the prismatic–revolute arm of Problems 7.5/7.8 (z₁ = y₀, gravity along −x₀).
* The Franka Emika Panda as a standard DH table (:func:`panda_links`), a reference for the dynamics,
  and as its published modified DH table (:func:`panda_modified_links`): see the Panda section.
* ``puma560`` (not one of the book's robots, ``load("puma560")``): the Unimation Puma 560 of the
  Robotics Toolbox (Corke & Armstrong-Hélouvry 1994), see :func:`puma560`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable

import numpy as np

import pinocchio as pin

from rigid_body.dh import G, DHLink, dh_transform, joint_friction_from_motor, urdf_from_dh

# The generated URDF files: ``urdf/`` beside the packages in a source tree (and an editable install),
# ``rigid_body/urdf/`` (package data) in an installed wheel.
_SOURCE_URDF_DIR = Path(__file__).resolve().parent.parent / "urdf"
URDF_DIR = _SOURCE_URDF_DIR if _SOURCE_URDF_DIR.is_dir() else Path(__file__).resolve().parent / "urdf"


def rod_inertia(mass: float, length: float, axis: int = 0) -> np.ndarray:
    """Inertia about the com of a slender rod along ``axis`` (illustrative link data)."""
    moment = mass * length**2 / 12.0
    diag = np.full(3, moment)
    diag[axis] = 1e-3 * mass
    return np.diag(diag)


@dataclass(frozen=True)
class BookRobot:
    """A book robot's DH table, gravity (in the URDF root frame = DH frame 0) and payload; its motor model
    (``"rotors"``, the book's, or ``"armature"``) and named joint configurations."""

    name: str
    links: tuple[DHLink, ...]
    gravity: tuple[float, float, float]
    payload: float = 0.0
    motors: str = "rotors"
    configurations: dict[str, tuple[float, ...]] = field(default_factory=dict)

    def urdf(self) -> str:
        """The arm's URDF text (the payload is added to the model by ``load``, not written into the file)."""
        return urdf_from_dh(self.links, name=self.name, motors=self.motors)


def planar_2r(a: Any = (1.0, 1.0), l: Any = (0.5, 0.5), m_l: Any = (50.0, 50.0), I_l: Any = (10.0, 10.0),
              k_r: Any = (100.0, 100.0), m_m: Any = (5.0, 5.0), I_m: Any = (0.01, 0.01),
              payload: float = 0.0, motors: bool = True) -> BookRobot:
    """Two-link planar arm of Sect. 7.3.2 with motors (7.82); link i's com at ℓ_i from joint i."""
    links = []
    for i in range(2):
        links.append(DHLink(
            a=a[i], mass=m_l[i], com=(l[i] - a[i], 0.0, 0.0), inertia=np.diag([0.0, I_l[i], I_l[i]]),
            motor_inertia=I_m[i] if motors else 0.0, motor_mass=m_m[i] if motors else 0.0,
            gear_ratio=k_r[i]))
    configurations = {
        "p8_10_target": (np.pi / 4, -np.pi / 2),  # Problem 8.10, case c = 0: the desired posture q_d
        "p8_15_start": (2.06944, -2.56808),  # Problem 8.15, case c = 0: q(0) = inv_k2u([0.4, 0.4]) (elbow up)
    }
    return BookRobot("planar_2r", tuple(links), (0.0, -G, 0.0), payload, configurations=configurations)


def planar_3r(a: Any = (0.5, 0.3, 0.2), lower: Any = (-np.pi / 3, -2 * np.pi / 3, -np.pi / 2),
              upper: Any = (np.pi / 3, 2 * np.pi / 3, np.pi / 2), mass: float = 1.0,
              payload: float = 0.0) -> BookRobot:
    """Three-link planar arm of Fig. 2.20 with the joint limits of Problem 2.17."""
    links = tuple(DHLink(a=a[i], mass=mass, com=(-a[i] / 2, 0.0, 0.0), inertia=rod_inertia(mass, a[i]),
                         lower=lower[i], upper=upper[i]) for i in range(3))
    # Problem 3.21's q_i = [0.51469, −1.55168, 1.82239] (for a₃ = 0.3 m) breaks 2.17's limit |θ3| ≤ π/2; its
    # first two angles with θ3 = π/3 instead: non-singular (θ2 ≠ 0), inside the limits.
    configurations = {"p3_21_within_limits": (0.51469, -1.55168, np.pi / 3)}
    return BookRobot("planar_3r", links, (0.0, -G, 0.0), payload, configurations=configurations)


def scara(a: Any = (0.5, 0.5), d3_range: Any = (0.0, 1.0), payload: float = 0.0) -> BookRobot:
    """SCARA of Table S2.3, joint axes pointing down (DH frame 0 has z₀ down: gravity +g z₀)."""
    links = (
        DHLink(a=a[0], mass=10.0, com=(-a[0] / 2, 0, 0), inertia=rod_inertia(10.0, a[0])),
        DHLink(a=a[1], mass=10.0, com=(-a[1] / 2, 0, 0), inertia=rod_inertia(10.0, a[1])),
        DHLink(joint="prismatic", lower=d3_range[0], upper=d3_range[1]),
        DHLink(mass=2.0, inertia=np.diag([1.0, 1.0, 1.0])),
    )
    # Problem 5.7: the camera on the end effector at q = [0, π/4, 0.1, 0] (θ2 ≠ 0, π: non-singular)
    configurations = {"p5_7_camera": (0.0, np.pi / 4, 0.1, 0.0)}
    return BookRobot("scara", links, (0.0, 0.0, G), payload, configurations=configurations)


def cylindrical(d2_range: Any = (0.0, 1.0), d3_range: Any = (0.1, 1.0), payload: float = 0.0) -> BookRobot:
    """Cylindrical arm (R-P-P) of Table S2.2."""
    links = (
        DHLink(mass=5.0, inertia=np.diag([0.1, 0.1, 0.1])),
        DHLink(alpha=-np.pi / 2, joint="prismatic", mass=3.0, inertia=np.diag([0.05] * 3),
               lower=d2_range[0], upper=d2_range[1]),
        DHLink(joint="prismatic", mass=2.0, com=(0, 0, -0.25), inertia=rod_inertia(2.0, 0.5, axis=2),
               lower=d3_range[0], upper=d3_range[1]),
    )
    # Both strokes at mid-range (d3 > 0: off the singularity of Problem 3.6); illustrative, the manual gives none.
    configurations = {"mid_stroke": (0.0, float(np.mean(d2_range)), float(np.mean(d3_range)))}
    return BookRobot("cylindrical", links, (0.0, 0.0, -G), payload, configurations=configurations)


def spherical(d2: float = 0.2, d3_range: Any = (0.1, 1.0), payload: float = 0.0) -> BookRobot:
    """Spherical (Stanford-type) arm R-R-P: (0,−π/2,0,θ1), (0,π/2,d2,θ2), (0,0,d3,0)."""
    links = (
        DHLink(alpha=-np.pi / 2, mass=5.0, inertia=np.diag([0.1] * 3)),
        DHLink(alpha=np.pi / 2, d=d2, mass=3.0, inertia=np.diag([0.05] * 3)),
        DHLink(joint="prismatic", mass=2.0, com=(0, 0, -0.25), inertia=rod_inertia(2.0, 0.5, axis=2),
               lower=d3_range[0], upper=d3_range[1]),
    )
    # θ2 = π/4, d3 at mid-range: away from θ2 = 0, π and d3 = 0 (Problem 3.5); illustrative.
    configurations = {"bent": (0.0, np.pi / 4, float(np.mean(d3_range)))}
    return BookRobot("spherical", links, (0.0, 0.0, -G), payload, configurations=configurations)


def anthropomorphic(a2: float = 0.5, a3: float = 0.4, payload: float = 0.0) -> BookRobot:
    """Anthropomorphic arm: (0,π/2,0,θ1), (a2,0,0,θ2), (a3,0,0,θ3), Eq. (2.66)."""
    links = (
        DHLink(alpha=np.pi / 2, mass=5.0, inertia=np.diag([0.1] * 3)),
        DHLink(a=a2, mass=4.0, com=(-a2 / 2, 0, 0), inertia=rod_inertia(4.0, a2)),
        DHLink(a=a3, mass=3.0, com=(-a3 / 2, 0, 0), inertia=rod_inertia(3.0, a3)),
    )
    # Shoulder up, forearm bent down: away from the elbow (θ3 = 0, π) and shoulder (wrist point on z₀)
    # singularities of Sect. 3.3.2; illustrative (the manual gives no posture).
    configurations = {"bent": (0.0, np.pi / 4, -np.pi / 2)}
    return BookRobot("anthropomorphic", links, (0.0, 0.0, -G), payload, configurations=configurations)


def _wrist_links(d6: float, first: int = 4) -> tuple[DHLink, ...]:
    return (
        DHLink(alpha=-np.pi / 2, mass=0.5, inertia=np.diag([0.005] * 3), name=f"joint_{first}"),
        DHLink(alpha=np.pi / 2, mass=0.5, inertia=np.diag([0.005] * 3), name=f"joint_{first + 1}"),
        DHLink(d=d6, mass=0.2, com=(0, 0, -d6 / 2), inertia=np.diag([0.002] * 3), name=f"joint_{first + 2}"),
    )


def spherical_wrist(d6: float = 0.1, payload: float = 0.0) -> BookRobot:
    """Spherical wrist: (0,−π/2,0,θ4), (0,π/2,0,θ5), (0,0,d6,θ6); joints named joint_4..joint_6."""
    # Away from the wrist singularity θ5 = 0, π (Sect. 3.3.2: z₃ ∥ z₅): an illustrative posture.
    configurations = {"bent": (0.0, np.pi / 2, 0.0)}
    return BookRobot("spherical_wrist", _wrist_links(d6), (0.0, 0.0, -G), payload, configurations=configurations)


def anthropomorphic_wrist(a2: float = 0.5, d4: float = 0.5, d6: float = 0.1, payload: float = 0.0) -> BookRobot:
    """Anthropomorphic arm with spherical wrist (Sect. 2.9.7): 6R."""
    links = (
        DHLink(alpha=np.pi / 2, mass=5.0, inertia=np.diag([0.1] * 3)),
        DHLink(a=a2, mass=4.0, com=(-a2 / 2, 0, 0), inertia=rod_inertia(4.0, a2)),
        DHLink(alpha=np.pi / 2, mass=2.0, inertia=np.diag([0.02] * 3)),
        DHLink(alpha=-np.pi / 2, d=d4, mass=2.0, com=(0, d4 / 2, 0) , inertia=rod_inertia(2.0, d4, axis=1)),
        DHLink(alpha=np.pi / 2, mass=0.5, inertia=np.diag([0.005] * 3)),
        DHLink(d=d6, mass=0.2, com=(0, 0, -d6 / 2), inertia=np.diag([0.002] * 3)),
    )
    # Away from the shoulder (wrist centre on z₀), elbow (θ3 = 0, π for this table) and wrist (θ5 = 0, π)
    # singularities of Sect. 3.3.2: an illustrative posture (the manual gives none).
    configurations = {"bent": (0.0, np.pi / 4, np.pi / 2 + np.pi / 4, 0.0, np.pi / 2, 0.0)}
    return BookRobot("anthropomorphic_wrist", links, (0.0, 0.0, -G), payload, configurations=configurations)


def cartesian_skew(m_l: Any = (10.0, 5.0), m_m: Any = (2.0, 2.0), I_m: Any = (0.01, 0.01),
                   k_r: Any = (50.0, 50.0), payload: float = 0.0) -> BookRobot:
    """Two-link Cartesian arm of Problem 7.1: z₀ = [0 0 1], z₁ = [1/√2 0 1/√2], gravity −g z₀.

    DH: (0, π/4, d1, π/2), (0, 0, d2, 0). Masses are illustrative (the problem is symbolic).
    Rotor i sits on axis i, driven through a screw of k_r (rad/m).
    """
    links = (
        DHLink(alpha=np.pi / 4, theta=np.pi / 2, joint="prismatic", mass=m_l[0], inertia=np.diag([0.1] * 3),
               motor_inertia=I_m[0], motor_mass=m_m[0], gear_ratio=k_r[0], lower=-1.0, upper=1.0),
        DHLink(joint="prismatic", mass=m_l[1], inertia=np.diag([0.05] * 3), motor_inertia=I_m[1],
               motor_mass=m_m[1], gear_ratio=k_r[1], lower=-1.0, upper=1.0),
    )
    # Both joints half way out; illustrative: the Jacobian is constant (never singular, σ = √(1 ± 1/√2)).
    configurations = {"extended": (0.5, 0.5)}
    return BookRobot("cartesian_skew", links, (0.0, 0.0, -G), payload, configurations=configurations)


def planar_pr(a2: float = 0.5, l2: float = 0.25, m_l: Any = (10.0, 5.0), I_l2: float = 0.1,
              payload: float = 0.0) -> BookRobot:
    """Prismatic–revolute arm of Problems 7.5/7.8: q = [d1, θ2], z₁ = y₀, gravity along −x₀.

    DH: (0, π/2, d1, π), (a2, 0, 0, θ2); link 2's com at ℓ2 from the joint: p_ℓ2 = [−ℓ2 c2, 0, d1 + ℓ2 s2].
    """
    links = (
        DHLink(alpha=np.pi / 2, theta=np.pi, joint="prismatic", mass=m_l[0], inertia=np.diag([0.1] * 3),
               lower=-1.0, upper=1.0),
        DHLink(a=a2, mass=m_l[1], com=(l2 - a2, 0, 0), inertia=np.diag([0.0, I_l2, I_l2])),
    )
    configurations = {"fig_s7_2": (0.4, 0.6)}  # the posture drawn in Fig. S7.2 (Problem 7.5): d1 = 0.4 m, ϑ2 = 0.6
    return BookRobot("planar_pr", links, (-G, 0.0, 0.0), payload, configurations=configurations)


# --------------------------------------------------------------------------------------------
# The Unimation Puma 560
# --------------------------------------------------------------------------------------------
# Standard DH table, link masses, centres of mass and inertias (about the com, in DH frame i), motor
# inertias J_m, gear ratios G and motor-side friction (viscous B, Coulomb Tc for q̇ > 0 and q̇ < 0) as in
# the Robotics Toolbox's Puma560 model, from P. Corke and B. Armstrong-Hélouvry, "A search for consensus
# among model parameters reported for the PUMA 560 robot", IEEE ICRA 1994. Link 1 has m = 0 but
# I_yy = 0.35 kg·m² (its inertia about the joint-1 axis, y1 = z0): kept. The Toolbox's recent versions put
# the shoulder d1 = 0.672 m above the mounting surface; here d1 = 0 (frame 0 at the shoulder), which
# changes no torque. Joint limits after Wang & Chen 1991 (as the Toolbox).
_DEG = np.pi / 180
PUMA560_DH = (  # a [m], α [rad], d [m]
    (0.0, np.pi / 2, 0.0), (0.4318, 0.0, 0.0), (0.0203, -np.pi / 2, 0.15005),
    (0.0, np.pi / 2, 0.4318), (0.0, -np.pi / 2, 0.0), (0.0, 0.0, 0.0))
PUMA560_MASS = (0.0, 17.4, 4.8, 0.82, 0.34, 0.09)
PUMA560_COM = ((0, 0, 0), (-0.3638, 0.006, 0.2275), (-0.0203, -0.0141, 0.070), (0, 0.019, 0), (0, 0, 0),
               (0, 0, 0.032))
PUMA560_INERTIA = ((0, 0.35, 0), (0.13, 0.524, 0.539), (0.066, 0.086, 0.0125), (1.8e-3, 1.3e-3, 1.8e-3),
                   (0.3e-3, 0.4e-3, 0.3e-3), (0.15e-3, 0.15e-3, 0.04e-3))  # I_xx, I_yy, I_zz
PUMA560_MOTOR_INERTIA = (200e-6, 200e-6, 200e-6, 33e-6, 33e-6, 33e-6)
PUMA560_GEAR_RATIO = (-62.6111, 107.815, -53.7063, 76.0364, 71.923, 76.686)
PUMA560_MOTOR_VISCOUS = (1.48e-3, 0.817e-3, 1.38e-3, 71.2e-6, 82.6e-6, 36.7e-6)
PUMA560_MOTOR_COULOMB = ((0.395, 0.435), (0.126, 0.071), (0.132, 0.105), (11.2e-3, 16.9e-3),
                         (9.26e-3, 14.5e-3), (3.96e-3, 10.5e-3))  # magnitudes for q̇ > 0, q̇ < 0
PUMA560_LIMITS = ((-160, 160), (-45, 225), (-225, 45), (-110, 170), (-100, 100), (-266, 266))  # deg


def puma560(motors: str = "armature", friction: bool = True, payload: float = 0.0) -> BookRobot:
    """The Puma 560 (Robotics Toolbox data, Corke & Armstrong-Hélouvry 1994), 6R with a spherical wrist.

    ``motors="armature"`` (default, the Toolbox's model: B = B_links + diag(J_m G²)) or ``"rotors"`` (the
    book's, Sect. 7.3). ``friction``: the published motor-side friction reflected to the joints
    (F_v = G² B, F_s = |G| Tc). Configurations: ``qz`` (zero angles), ``qr`` (ready, arm up), ``qs``
    (stretched along x), ``qn`` (nominal, non-singular).
    """
    links = []
    for i in range(6):
        a, alpha, d = PUMA560_DH[i]
        G_i = PUMA560_GEAR_RATIO[i]
        links.append(DHLink(
            a=a, alpha=alpha, d=d, mass=PUMA560_MASS[i], com=PUMA560_COM[i], inertia=np.diag(PUMA560_INERTIA[i]),
            motor_inertia=PUMA560_MOTOR_INERTIA[i], gear_ratio=G_i,
            lower=PUMA560_LIMITS[i][0] * _DEG, upper=PUMA560_LIMITS[i][1] * _DEG,
            **(joint_friction_from_motor(G_i, PUMA560_MOTOR_VISCOUS[i], PUMA560_MOTOR_COULOMB[i])
               if friction else {})))
    configurations = {"qz": (0.0,) * 6, "qr": (0.0, np.pi / 2, -np.pi / 2, 0.0, 0.0, 0.0),
                      "qs": (0.0, 0.0, -np.pi / 2, 0.0, 0.0, 0.0),
                      # the Toolbox's qn has q3 = +π, outside the joint's [−225°, 45°]: the same pose at −π
                      "qn": (0.0, np.pi / 4, -np.pi, 0.0, np.pi / 4, 0.0)}
    return BookRobot("puma560", tuple(links), (0.0, 0.0, -G), payload, motors, configurations)


# Robots built from a DH table that are not the book's (no committed URDF file).
DH_ROBOTS: dict[str, Callable[..., BookRobot]] = {"puma560": puma560}

BOOK_ROBOTS: dict[str, Callable[..., BookRobot]] = {
    "planar_2r": planar_2r,
    "planar_3r": planar_3r,
    "scara": scara,
    "cylindrical": cylindrical,
    "spherical": spherical,
    "anthropomorphic": anthropomorphic,
    "spherical_wrist": spherical_wrist,
    "anthropomorphic_wrist": anthropomorphic_wrist,
    "cartesian_skew": cartesian_skew,
    "planar_pr": planar_pr,
}


def book_robot_spec(name: str, **params: Any) -> BookRobot:
    """The table of the book robot (or named DH robot) ``name`` with its parameters changed by ``params``."""
    tables = {**BOOK_ROBOTS, **DH_ROBOTS}
    if name not in tables:
        raise ValueError(f"unknown book robot {name!r}; available: {', '.join(sorted(tables))}")
    import inspect

    signature = inspect.signature(tables[name]).parameters
    accepted = [k for k, p in signature.items() if p.kind is not p.VAR_KEYWORD]
    unknown = sorted(set(params) - set(accepted))
    if unknown and len(accepted) == len(signature):
        raise ValueError(f"book robot {name!r}: unknown parameters {unknown}; it takes {accepted}")
    try:
        return tables[name](**params)
    except TypeError as exc:
        raise ValueError(f"book robot {name!r}: {exc}") from None


def write_all(directory: Path = _SOURCE_URDF_DIR) -> list[Path]:
    """Regenerate every ``urdf/<name>.urdf`` from its table."""
    paths = []
    for name in BOOK_ROBOTS:
        path = directory / f"{name}.urdf"
        path.write_text(book_robot_spec(name).urdf())
        paths.append(path)
    return paths


# --------------------------------------------------------------------------------------------
# The Franka Emika Panda
# --------------------------------------------------------------------------------------------
# The Franka Emika Panda as a standard DH table (the book's convention), for the dynamics references.
#
# Franka publishes the Panda's kinematics in Craig's modified DH convention, with rows
# (a_{i−1}, α_{i−1}, d_i) and θ_i = q_i. The joint frames of example-robot-data's ``panda.urdf`` are
# those Craig frames. Craig's product Π Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i) Tz(d_i) regroups into the
# book's A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i) (2.52), with (a_i, α_i) taken from Craig's next row:
# the book's frame i is Craig's frame i times Tx(a_i) Rx(α_i). The base frames coincide.
#
# Inertial data come from the example-robot-data URDF as Pinocchio parses it: one lumped body per
# joint, in Craig's frame i. The hand and the locked fingers are merged into link 7. They are moved
# into the book's frame i here. The flange and hand, Tz(0.107) Rz(−π/4), form the tool.
#
# References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 2.8.2;
# Franka Control Interface documentation (robot kinematics, modified DH parameters).

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


def panda_modified_links(model: pin.Model) -> tuple[DHLink, ...]:
    """The Panda's published modified (Craig) DH table, joints 1..7, with the inertial data of ``model`` =
    ``load("panda").model`` as they are, in Craig's frame i (the URDF's ``panda_link{i}``). Load it with
    ``robot_from_dh(links, convention="modified", tool=panda_tool())``."""
    links = []
    for i, (a, alpha, d) in enumerate(PANDA_MODIFIED_DH):
        inertia = model.inertias[model.getJointId(f"panda_joint{i + 1}")]
        links.append(DHLink(
            a=a, alpha=alpha, d=d, mass=float(inertia.mass), com=tuple(np.asarray(inertia.lever)),
            inertia=np.asarray(inertia.inertia).copy(), lower=float(model.lowerPositionLimit[i]),
            upper=float(model.upperPositionLimit[i]), name=f"joint_{i + 1}"))
    return tuple(links)


def panda_links(model: pin.Model) -> tuple[DHLink, ...]:
    """The Panda's standard DH table, with the inertial data of ``model`` = ``load("panda").model``
    (example-robot-data's URDF, fingers locked): :func:`panda_modified_links` regrouped as above."""
    modified = panda_modified_links(model)
    links = []
    for i, link in enumerate(modified):
        a, alpha = (modified[i + 1].a, modified[i + 1].alpha) if i + 1 < len(modified) else (0.0, 0.0)
        T_fix = dh_transform(a, alpha, 0.0, 0.0)  # Craig frame i -> book frame i: Tx(a_i) Rx(α_i)
        R, p = T_fix[:3, :3], T_fix[:3, 3]
        links.append(replace(link, a=a, alpha=alpha, com=tuple(R.T @ (np.asarray(link.com) - p)),
                             inertia=R.T @ np.asarray(link.inertia) @ R))
    return tuple(links)


if __name__ == "__main__":
    for p in write_all():
        print(p)
