"""Plants beyond the torque-driven arm: the voltage-controlled arm of Fig. 8.3.

:class:`~controllers.simulation.ArmPlant` is the torque-controlled arm of Fig. 8.4. When the
actuators are voltage-controlled DC motors with negligible armature inductance (Sect. 8.2), each
motor delivers the joint torque

    τ = K_r k_t R_a⁻¹ (G_v v_c − k_v K_r q̇),

so the arm obeys B(q) q̈ + C q̇ + F_v q̇ + g = K_r k_t R_a⁻¹ G_v v_c − K_r k_t R_a⁻¹ k_v K_r q̇:
the electrical damping K_r k_t R_a⁻¹ k_v K_r adds to the mechanical friction F_v, Eq. (8.6)/(8.7).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 8.2, Eqs. (5.1)–(5.4), (8.3)–(8.7), Fig. 8.3.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from controllers.independent_joint import JointDrive
from controllers.simulation import ArmPlant, per_joint


def _positive(x: Any, n: int, name: str) -> np.ndarray:
    v = per_joint(x, n, name)
    if np.any(v <= 0):
        raise ValueError(f"`{name}` must be positive, got {v}")
    return v


class VoltageControlledArm:
    """Arm driven through DC servomotors by the voltages ``v_c`` (Fig. 8.3); x = [q, q̇], u = v_c.

    Parameters
    ----------
    robot : the arm (its B(q) includes the rotors, Sect. 7.3).
    gear_ratio : k_r (n,), motor-side angle θ_m = k_r q.
    drives : one :class:`controllers.independent_joint.JointDrive` per joint (R_a, k_t, k_v are used;
        the rotor inertia is already in the robot's B(q)).
    amplifier_gain : G_v (n,), default 1.
    viscous_friction : F_v (n,) joint-side mechanical friction [N·m·s/rad] (k_r² F_m).
    tau_max : optional joint-torque limits (n,).
    """

    def __init__(self, robot: Any, gear_ratio: Any, drives: Sequence[JointDrive], amplifier_gain: Any = 1.0,
                 viscous_friction: Any = 0.0, tau_max: Any = None):
        n = robot.nv
        self.n = n
        if len(drives) != n:
            raise ValueError(f"`drives` must have one JointDrive per joint ({n}), got {len(drives)}")
        k_r = _positive(gear_ratio, n, "gear_ratio")
        R_a = np.array([d.Ra for d in drives])
        k_t = np.array([d.kt for d in drives])
        k_v = np.array([d.kv for d in drives])
        G_v = _positive(amplifier_gain, n, "amplifier_gain")
        self.voltage_gain = k_r * k_t * G_v / R_a  # G_r = K_r k_t R_a⁻¹ G_v: v_c → τ
        self.electrical_damping = k_r * k_t * k_v * k_r / R_a  # K_r k_t R_a⁻¹ k_v K_r, Eq. (8.7)
        self.arm = ArmPlant(robot, viscous_friction=viscous_friction, tau_max=tau_max)

    def torque(self, x: np.ndarray, v_c: np.ndarray) -> np.ndarray:
        """The joint torques the motors deliver at state ``x`` under the voltages ``v_c``."""
        return self.voltage_gain * v_c - self.electrical_damping * x[self.n:]

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return self.arm.derivative(t, x, self.torque(x, u))
