"""Every plant of rmpc's closed loops, following the contract of :mod:`controllers.simulation`.

* :class:`ArmPlant` — the torque-driven arm of Fig. 8.4: x = [q (nq), v (nv)], ẋ = [v, v̇] (2 nv),
  B(q) v̇ + C v + F_v v + g = τ − Jᵀ h_e (Eq. 7.42; nq ≠ nv moves q by ``pin.integrate``).
* :class:`VoltageControlledArm` — the arm driven through DC servomotors by voltages (Fig. 8.3).
* :class:`ArmInContact` — an arm whose end effector touches an environment of
  :mod:`controllers.environment`; its measurement carries the sensed wrench h_e.
* :class:`JointDrivePlant` — one joint's electric drive M(s) of independent joint control (Sect. 8.3).
* :class:`ServomotorPlant` — the servomotor of Fig. 5.2 (armature current, rotor, amplifier, PI).
* :class:`JointIntegrator` — the kinematic plant q̇ = u of closed-loop inverse kinematics (Sect. 3.7).

Arm plants return an :class:`ArmMeasurement` from ``measure`` and build their state with
``initial_state(q0, qd0)``.

Voltage-controlled arm: when the actuators are DC motors with negligible armature inductance
(Sect. 8.2), each delivers τ = K_r k_t R_a⁻¹ (G_v v_c − k_v K_r q̇), so the arm obeys
B(q) q̈ + C q̇ + F_v q̇ + g = K_r k_t R_a⁻¹ G_v v_c − K_r k_t R_a⁻¹ k_v K_r q̇: the electrical damping
K_r k_t R_a⁻¹ k_v K_r adds to the mechanical friction F_v, Eq. (8.6)/(8.7).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 3.7, 5.1, 7.2, 8.2, 8.3, 9.1; Eqs. (5.1)–(5.4), (7.42), (8.3)–(8.7), Figs. 5.2, 8.3, 8.4.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np
import pinocchio as pin

from controllers.independent_joint import JointDrive
from controllers.simulation import as_friction, per_joint
from rigid_body.actuators import DCServomotor, PIRegulator
from rigid_body.robots import Robot
from rigid_body.validation import as_positive, as_vector


@dataclass(frozen=True, slots=True)
class ArmMeasurement:
    """What an arm's sensors give the controller: joint positions ``q`` (nq,), velocities ``qd`` (nv,)
    and, with a force sensor, the wrench ``wrench`` (6,) exerted by the end effector on the environment
    (base frame, [f; μ], Sect. 9.1)."""

    q: np.ndarray
    qd: np.ndarray
    wrench: np.ndarray | None = None


ARM_UNITS = {"q": "rad", "qd": "rad/s", "u": "N·m", "e": "rad", "q_d": "rad"}


def frame_jacobian_and_pose(robot: Robot, q: np.ndarray, fid: int) -> tuple[np.ndarray, pin.SE3]:
    """(geometric Jacobian (6, nv) in the book's convention, pose pin.SE3) of frame ``fid`` in one
    Pinocchio pass (hot loops: q and fid are trusted)."""
    J = pin.computeFrameJacobian(robot.model, robot.data, q, fid, pin.LOCAL_WORLD_ALIGNED)
    return J, robot.data.oMf[fid].copy()


class ArmPlant:
    """A rigid arm driven by joint torques: x = [q, v], ẋ = [v, B⁻¹(τ − C v − g − F_v v − τ_ext)].

    ``τ_ext = Jᵀ h_e`` is the joint torque of the external wrench (Eq. 7.42). With nq ≠ nv (continuous
    joints, a floating base) x has nq + nv entries, ẋ has 2 nv, ``integrate`` uses ``pin.integrate`` and
    ``dexp_inverse`` its Jacobian ``pin.dIntegrate`` (RK4 stays fourth order on SE(3)).

    Parameters
    ----------
    robot : the :class:`~rigid_body.robots.Robot` (motors included when its URDF has them).
    viscous_friction : F_v, scalar or (nv,) [N·m·s/rad].
    tau_max : optional actuator limits (nv,) — the commanded torque is saturated.
    external_force : optional ``(t, q, v) -> τ_ext`` (joint torques of external forces), subtracted.
    """

    units = ARM_UNITS
    integrate: Callable[[np.ndarray, np.ndarray, float], np.ndarray] | None = None  # x + h·dx when nq = nv
    dexp_inverse: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None = None

    def __init__(self, robot: Robot, viscous_friction: Any = 0.0, tau_max: Any = None,
                 external_force: Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None = None):
        self.robot = robot
        self.n = robot.nv
        self.nq = robot.nq
        self.state_size = robot.nq + robot.nv
        self.tangent_size = 2 * robot.nv
        self.state_layout = {"q": slice(0, self.nq), "qd": slice(self.nq, self.state_size)}
        self.Fv = as_friction(viscous_friction, self.n)
        self.tau_max = None if tau_max is None else as_vector(tau_max, self.n, "tau_max")
        if self.tau_max is not None and np.any(self.tau_max <= 0):
            raise ValueError(f"`tau_max` must be positive torque limits, got {self.tau_max}")
        self.external_force = external_force
        if self.nq != self.n:
            self.integrate = self._integrate_configuration
            self.dexp_inverse = self._dexp_inverse
        from rigid_body.dynamics import forward_dynamics

        self._forward_dynamics = forward_dynamics  # called with check=False: inputs validated here

    def initial_state(self, q0: Any, qd0: Any = None) -> np.ndarray:
        """x0 = [q0, q̇0] (q̇0 = 0 by default)."""
        q0 = as_vector(q0, self.nq, "q0")
        qd0 = np.zeros(self.n) if qd0 is None else as_vector(qd0, self.n, "qd0")
        return np.concatenate([q0, qd0])

    def _integrate_configuration(self, x: np.ndarray, dx: np.ndarray, h: float) -> np.ndarray:
        nq, n = self.nq, self.n
        out = np.empty(nq + n)
        out[:nq] = pin.integrate(self.robot.model, x[:nq], h * dx[:n])
        out[nq:] = x[nq:] + h * dx[n:]
        return out

    def _dexp_inverse(self, x: np.ndarray, xi: np.ndarray, dx: np.ndarray) -> np.ndarray:
        """The RK4 stage derivative dx, taken at integrate(x, xi, 1), as a tangent vector at x: the
        velocity part is solved through the Jacobian of ``pin.integrate`` with respect to its step."""
        n = self.n
        J = pin.dIntegrate(self.robot.model, x[:self.nq], xi[:n], pin.ArgumentPosition.ARG1)
        out = dx.copy()
        out[:n] = np.linalg.solve(J, dx[:n])
        return out

    def torque(self, u: np.ndarray) -> np.ndarray:
        """The torque actually applied: ``u`` saturated at ±tau_max."""
        if np.shape(u) != (self.n,):
            raise ValueError(f"the arm needs {self.n} joint torques, got an input of shape {np.shape(u)}")
        return u if self.tau_max is None else np.clip(u, -self.tau_max, self.tau_max)

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        n, nq = self.n, self.nq
        q, qd = x[:nq], x[nq:]
        tau = self.torque(u) - self.Fv * qd
        if self.external_force is not None:
            tau = tau - self.external_force(t, q, qd)
        xd = np.empty(2 * n)
        xd[:n] = qd
        xd[n:] = self._forward_dynamics(self.robot, q, qd, tau, check=False)
        return xd

    def measure(self, t: float, x: np.ndarray) -> ArmMeasurement:
        return ArmMeasurement(x[:self.nq], x[self.nq:])

    def symbolic(self) -> Any:
        """ẋ = f(x, u) as a ``casadi.Function`` for ``simulate(..., backend="casadi")`` (nq = nv, no
        external force): B(q) q̈ = sat(u) − F_v q̇ − C q̇ − g by the symbolic Newton–Euler."""
        import casadi as ca

        from rigid_body.symbolic import forward_dynamics_expression

        if self.nq != self.n or self.external_force is not None:
            raise ValueError("`plant`: backend='casadi' takes an ArmPlant with nq = nv and no external_force")
        n = self.n
        x, u = ca.SX.sym("x", 2 * n), ca.SX.sym("u", n)
        tau = u if self.tau_max is None else ca.fmin(ca.fmax(u, -self.tau_max), self.tau_max)
        q, qd = x[:n], x[n:]
        qdd = forward_dynamics_expression(self.robot, q, qd, tau - ca.DM(self.Fv) * qd)
        return ca.Function("plant", [x, u], [ca.vertcat(qd, qdd)], ["x", "u"], ["xdot"])


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

    def __init__(self, robot: Robot, gear_ratio: Any, drives: Sequence[JointDrive], amplifier_gain: Any = 1.0,
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
        a = self.arm
        self.state_size, self.tangent_size, self.state_layout = a.state_size, a.tangent_size, a.state_layout
        self.integrate, self.measure, self.initial_state = a.integrate, a.measure, a.initial_state
        self.units = {**ARM_UNITS, "u": "V"}

    def torque(self, x: np.ndarray, v_c: np.ndarray) -> np.ndarray:
        """The joint torques the motors deliver at state ``x`` under the voltages ``v_c``."""
        return self.voltage_gain * v_c - self.electrical_damping * x[self.arm.nq:]

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return self.arm.derivative(t, x, self.torque(x, u))


def _positive(x: Any, n: int, name: str) -> np.ndarray:
    v = per_joint(x, n, name)
    if np.any(v <= 0):
        raise ValueError(f"`{name}` must be positive, got {v}")
    return v


class ArmInContact:
    """An arm whose end effector (frame ``frame``) touches ``environment``, with a wrist force sensor.

    The environment gives h_e = ``environment.wrench(T_e, v_e)``, the wrench (6,) exerted BY the end
    effector ON the environment in the base frame (Sect. 9.1), from the end-effector pose T_e and twist
    v_e = J q̇; the arm feels −h_e, i.e. the joint torque Jᵀ h_e is subtracted (Eq. 7.42). It is computed
    once per derivative evaluation and once per measurement; ``measure`` reports it as ``meas.wrench``.
    """

    def __init__(self, robot: Robot, environment: Any, viscous_friction: Any = 0.0,
                 frame: str | int | None = None):
        if not callable(getattr(environment, "wrench", None)):
            raise ValueError("`environment` must have a method wrench(T_e, v_e) -> h_e (6,)")
        self.robot, self.environment, self.frame = robot, environment, frame
        self._fid = robot.frame(frame)
        self.arm = ArmPlant(robot, viscous_friction=viscous_friction, external_force=self.contact_torques)
        a = self.arm
        self.state_size, self.tangent_size, self.state_layout = a.state_size, a.tangent_size, a.state_layout
        self.integrate, self.initial_state = a.integrate, a.initial_state
        self.units = {**ARM_UNITS, "wrench": "N, N·m"}

    def wrench(self, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(h_e (6,), J (6, nv)) at (q, q̇)."""
        J, T = frame_jacobian_and_pose(self.robot, q, self._fid)
        return self.environment.wrench(T, J @ qd), J

    def contact_torques(self, t: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """Jᵀ h_e: the joint torques the contact takes from the arm."""
        h_e, J = self.wrench(q, qd)
        return J.T @ h_e

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return self.arm.derivative(t, x, u)

    def measure(self, t: float, x: np.ndarray) -> ArmMeasurement:
        nq = self.arm.nq
        q, qd = x[:nq], x[nq:]
        return ArmMeasurement(q, qd, self.wrench(q, qd)[0])


class JointDrivePlant:
    """The drive M(s) as a plant: x = [ϑ_m, ϑ̇_m], u = [v] or [v, d]; ``T_m ϑ̈ = k_m(v − (R_a/k_t) d) − ϑ̇``.

    Its measurement is an :class:`ArmMeasurement` of the motor side: ``q = [ϑ_m]``, ``qd = [ϑ̇_m]``.
    """

    state_size = 2
    state_layout = {"q": slice(0, 1), "qd": slice(1, 2)}
    units = {"q": "rad", "qd": "rad/s", "u": "V", "e": "rad"}

    def __init__(self, drive: JointDrive):
        self.k_m, self.T_m, self.g = drive.k_m, drive.T_m, drive.disturbance_gain

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        d = u[1] if len(u) > 1 else 0.0
        return np.array([x[1], (self.k_m * (u[0] - self.g * d) - x[1]) / self.T_m])

    def measure(self, t: float, x: np.ndarray) -> ArmMeasurement:
        return ArmMeasurement(x[:1], x[1:])


class ServomotorPlant:
    """The servomotor of Fig. 5.2 (a :class:`rigid_body.actuators.DCServomotor`) as a plant.

    State ``x = [i_a, ω_m, ϑ_m, v_a, z]``: armature current, rotor velocity and angle, amplifier output
    (a first-order lag of T_v; when T_v = 0 it follows its input and its state stays 0), and the
    integral of the current error (used by a PI regulator). Input ``u = [v'_c, c_r]`` (or just v'_c).
    ``res.q``/``res.qd`` are ϑ_m/ω_m, ``res["i_a"]`` the current.
    """

    state_size = 5
    state_layout = {"i_a": 0, "omega": 1, "theta": 2, "v_a": 3, "q": slice(2, 3), "qd": slice(1, 2)}
    units = {"i_a": "A", "omega": "rad/s", "theta": "rad", "v_a": "V", "q": "rad", "qd": "rad/s"}

    def __init__(self, motor: DCServomotor, regulator: PIRegulator | float = 1.0):
        if motor.La <= 0:
            raise ValueError("`motor.La` must be > 0 to simulate the armature current dynamics")
        self.motor = motor
        if isinstance(regulator, PIRegulator):
            self._KP, self._KI = regulator.K * regulator.T, regulator.K
        else:
            self._KP, self._KI = as_positive(regulator, "regulator"), 0.0

    x0 = np.zeros(5)          # the motor at rest (read-only; simulate() copies it)
    x0.setflags(write=False)

    def regulator_output(self, x: np.ndarray, v_c: float) -> float:
        """v_c of the regulator: C_i applied to the current error, cf. (S5.5)."""
        e = v_c - self.motor.ki * x[0]
        return self._KP * e + self._KI * x[4]

    def armature_voltage(self, x: np.ndarray, v_c: float) -> float:
        """v_a: the amplifier output."""
        m = self.motor
        return x[3] if m.Tv > 0 else m.Gv * self.regulator_output(x, v_c)

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        m = self.motor
        v_c = float(u[0])
        c_r = float(u[1]) if len(u) > 1 else 0.0
        i_a, omega = x[0], x[1]
        e = v_c - m.ki * i_a
        v_a = self.armature_voltage(x, v_c)
        di = (v_a - m.Ra * i_a - m.kv * omega) / m.La               # (5.1)–(5.2)
        domega = (m.kt * i_a - m.Fm * omega - c_r) / m.Im         # (5.3)–(5.4)
        dva = (m.Gv * (self._KP * e + self._KI * x[4]) - x[3]) / m.Tv if m.Tv > 0 else 0.0
        return np.array([di, domega, omega, dva, e])


class JointIntegrator:
    """The plant q̇ = u of a kinematic IK loop (x = q); RK4 with u held is Euler's step (3.48)."""

    state_layout = {"q": slice(None)}
    units = {"q": "rad", "u": "rad/s"}

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return u
