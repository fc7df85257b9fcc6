"""Every plant of rmpc's closed loops, following the contract of :mod:`controllers.simulation`.

* :class:`ArmPlant` — the torque-driven arm of Fig. 8.4: x = [q (nq), v (nv)], ẋ = [v, v̇] (2 nv),
  B(q) v̇ + C v + F_v v + F_s sgn(v) + g = τ − Jᵀ h_e (Eq. 7.42; nq ≠ nv moves q by ``pin.integrate``).
* :class:`VoltageControlledArm` — the arm driven through DC servomotors by voltages (Fig. 8.3).
* :class:`ArmInContact` — an arm whose end effector touches an environment of
  :mod:`controllers.environment`; its measurement carries the sensed wrench h_e.
* :class:`JointDrivePlant` — one joint's electric drive M(s) of independent joint control (Sect. 8.3).
* :class:`ServomotorPlant` — the servomotor of Fig. 5.2 (armature current, rotor, amplifier, PI).
* :class:`JointIntegrator` — the kinematic plant q̇ = u of closed-loop inverse kinematics (Sect. 3.7), and
  :class:`KinematicArm`, the same plant measured as encoders (``meas.q``): the arm of the resolved-velocity
  visual servoing of Figs. 10.15 and 10.17 (``visual_servo`` also accepts a JointIntegrator's bare q).
* Wheeled mobile robots (Chapter 11), kinematic: :class:`UnicyclePlant` (11.13) — with optional
  wheel-speed saturation (Problem 11.9) and wheel encoders (odometry, Sect. 11.7) —,
  :class:`BicyclePlant` (11.19)/(11.20), :class:`ChainedFormPlant` (11.25), :class:`DriftlessPlant`
  (q̇ = G(q) u, 11.10) and :class:`MobileManipulatorPlant` (a unicycle base carrying an arm, one
  Pinocchio model with a planar root joint). Their measurements are :class:`Posture`,
  :class:`OdometerPosture`, :class:`BicycleState` and :class:`MobileManipulatorState`.

Arm plants return an :class:`ArmMeasurement` from ``measure`` and build their state with
``initial_state(q0, qd0)``.

Voltage-controlled arm: when the actuators are DC motors with negligible armature inductance
(Sect. 8.2), each delivers τ = K_r k_t R_a⁻¹ (G_v v_c − k_v K_r q̇), so the arm obeys
B(q) q̈ + C q̇ + F_v q̇ + g = K_r k_t R_a⁻¹ G_v v_c − K_r k_t R_a⁻¹ k_v K_r q̇: the electrical damping
K_r k_t R_a⁻¹ k_v K_r adds to the mechanical friction F_v, Eq. (8.6)/(8.7).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 3.7, 5.1, 7.2, 8.2, 8.3, 9.1, 11.2–11.7; Eqs. (5.1)–(5.4), (7.42), (8.3)–(8.7), (11.10)–(11.25),
Figs. 5.2, 8.3, 8.4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial
from typing import Any, Callable, Sequence

import numpy as np
import pinocchio as pin

from controllers.environment import NO_CONTACT
from controllers.independent_joint import JointDrive
from controllers.laws import Numeric, as_friction, per_joint
from rigid_body.actuators import DCServomotor, PIRegulator
from rigid_body.robots import JointFriction, Robot, joint_units
from rigid_body.validation import as_positive, as_vector
from rigid_body.wheeled import (chained_form_velocity, mobile_manipulator_input_matrix, saturate_wheel_speeds,
                                unicycle_velocity)


@dataclass(frozen=True, slots=True)
class ArmMeasurement:
    """What an arm's sensors give the controller: joint positions ``q`` (nq,), velocities ``qd`` (nv,)
    and, with a force sensor, the wrench ``wrench`` (6,) exerted by the end effector on the environment
    (base frame, [f; μ], Sect. 9.1)."""

    q: np.ndarray
    qd: np.ndarray
    wrench: np.ndarray | None = None


_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED   # the book's geometric Jacobian (3.30)
ARM_UNITS = {"q": "rad", "qd": "rad/s", "u": "N·m", "e": "rad", "q_d": "rad"}


def arm_units(robot: Robot) -> dict[str, str]:
    """The units of an arm's signals from its joint types: rad, rad/s, N·m (revolute), m, m/s, N
    (prismatic), both when the arm mixes them."""
    kinds = set(joint_units(robot))
    if kinds == {"rad"}:
        return dict(ARM_UNITS)
    q = "m" if kinds == {"m"} else "rad | m"
    u = "N" if kinds == {"m"} else "N·m | N"
    qd = "m/s" if kinds == {"m"} else "rad/s | m/s"
    return {"q": q, "qd": qd, "u": u, "e": q, "q_d": q}


def joint_torques(u: Any, n: int) -> np.ndarray:
    """``u`` as the (n,) float array of an arm's commanded joint torques (an array of that shape as it is); a
    ValueError naming the shape otherwise."""
    if type(u) is not np.ndarray or u.shape != (n,):
        if np.shape(u) != (n,):
            raise ValueError(f"the arm needs {n} joint torques, got an input of shape {np.shape(u)}")
        u = np.asarray(u, dtype=float)
    return u


def saturated(ops: Any, u: Any, tau_max: Any, tau_min: Any = None) -> Any:
    """The torque the actuators apply: the command ``u`` saturated at [−tau_max, tau_max] (``tau_min`` the lower
    limit −tau_max when given precomputed), ``u`` itself without limits — the one body of the saturation of
    :class:`ArmPlant` (both loops) and :class:`controllers.mujoco.MujocoPlant`."""
    if tau_max is None:
        return u
    return ops.clip(u, -tau_max if tau_min is None else tau_min, tau_max)


class ArmPlant:
    """A rigid arm driven by joint torques: x = [q, v], ẋ = [v, B⁻¹(τ − C v − g − τ_f − τ_ext)].

    ``τ_ext = Jᵀ h_e`` is the joint torque of the external wrench (Eq. 7.42). With nq ≠ nv (continuous
    joints, a floating base) x has nq + nv entries, ẋ has 2 nv, ``integrate`` uses ``pin.integrate`` and
    ``dexp_inverse`` its Jacobian ``pin.dIntegrate`` (RK4 stays fourth order on SE(3)).

    Parameters
    ----------
    robot : the :class:`~rigid_body.robots.Robot` (motors included when its URDF has them).
    viscous_friction : F_v, scalar or (nv,) [N·m·s/rad].
    tau_max : optional actuator limits (nv,) — the commanded torque is saturated.
    external_force : optional ``(t, q, v) -> τ_ext`` (joint torques of external forces), subtracted
        (``q``, ``v`` may be the loop's scratch arrays: copy them to keep them).
    coulomb_friction : F_s, scalar or (nv,) [N·m]: τ_f = F_v v + F_s sgn(v)
        (:func:`rigid_body.dynamics.friction_torques`).
    friction : a :class:`~rigid_body.robots.JointFriction` instead of the two arguments above, e.g.
        ``robot.friction`` (the robot's published friction: DH table or URDF ``<dynamics>``).
        By default the plant is frictionless apart from ``viscous_friction``/``coulomb_friction``.
    friction_smoothing : ε [rad/s]: sgn(v) becomes tanh(v/ε) (0: the exact sign; a fixed RK4 step then
        chatters around v = 0 once friction holds the arm).
    """

    units = ARM_UNITS
    integrate: Callable[[np.ndarray, np.ndarray, float], np.ndarray] | None = None  # x + h·dx when nq = nv
    dexp_inverse: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None = None

    def __init__(self, robot: Robot, viscous_friction: Any = 0.0, tau_max: Any = None,
                 external_force: Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None = None,
                 coulomb_friction: Any = 0.0, friction: JointFriction | None = None,
                 friction_smoothing: float = 0.0):
        self.robot = robot
        self.n = robot.nv
        self.nq = robot.nq
        self.units = arm_units(robot)
        self.state_size = robot.nq + robot.nv
        self.tangent_size = 2 * robot.nv
        self.input_size = robot.nv
        self._x_shape = (self.state_size,)
        self.state_layout = {"q": slice(0, self.nq), "qd": slice(self.nq, self.state_size)}
        self.Fv = as_friction(viscous_friction, self.n)
        Fs = per_joint(coulomb_friction, self.n, "coulomb_friction")
        if np.any(Fs < 0):
            raise ValueError(f"`coulomb_friction` must be non-negative, got {Fs}")
        if friction is not None:
            if np.any(self.Fv) or np.any(Fs):
                raise ValueError("give `friction` or `viscous_friction`/`coulomb_friction`, not both")
            if not all(np.shape(v) == (self.n,) for v in (friction.viscous, friction.coulomb_positive,
                                                         friction.coulomb_negative)):
                raise ValueError(f"`friction` must hold ({self.n},) vectors for this robot")
            self.Fv = np.asarray(friction.viscous, dtype=float)
        self.friction = JointFriction(self.Fv, Fs, Fs) if friction is None else friction
        self.friction_smoothing = as_positive(friction_smoothing, "friction_smoothing", allow_zero=True)
        # Viscous only (the book's problems): the cheap F_v v; else friction_torques.
        self._coulomb = bool(np.any(self.friction.coulomb_positive) or np.any(self.friction.coulomb_negative))
        self.tau_max = None if tau_max is None else as_vector(tau_max, self.n, "tau_max")
        if self.tau_max is not None and np.any(self.tau_max <= 0):
            raise ValueError(f"`tau_max` must be positive torque limits, got {self.tau_max}")
        self.external_force = external_force
        if self.nq != self.n:
            self.integrate = self._integrate_configuration
            self.dexp_inverse = self._dexp_inverse
        from rigid_body.dynamics import forward_dynamics, friction_torques

        self._forward_dynamics = forward_dynamics  # called with check=False: inputs validated here
        self._friction_torques = friction_torques
        # The hot path of derivative(): no friction product when F_v = 0, no clipping without limits, and
        # without rotors (mimic joints) ABA on this thread's data (the plant belongs to the thread that made it).
        self._viscous = bool(np.any(self.Fv))
        self._u_shape = (self.n,)
        if self.tau_max is not None:
            self._tau_min = -self.tau_max
        self._model, self._data = (None, None) if robot.has_mimic else (robot.model, robot.data)
        self._simple = self.tau_max is None and not self._coulomb and external_force is None  # τ = u − F_v q̇
        self._frictionless = self._simple and not self._viscous and self._data is not None      # τ = u, ABA

    def initial_state(self, q0: Any, qd0: Any = None) -> np.ndarray:
        """x0 = [q0, q̇0] (q̇0 = 0 by default).

        The plant has no joint stops: q0 and the motion may leave ``robot.lower``/``robot.upper`` (the
        Panda's all-zero q breaks its q4 ≤ −0.07 rad: start from ``robot.configurations``).
        """
        q0 = as_vector(q0, self.nq, "q0")
        qd0 = np.zeros(self.n) if qd0 is None else as_vector(qd0, self.n, "qd0")
        return np.concatenate([q0, qd0])

    def _integrate_configuration(self, x: np.ndarray, dx: np.ndarray, h: float) -> np.ndarray:
        return self.integrate_law(Numeric, x, dx, h)

    def integrate_law(self, ops: Any, x: Any, dx: Any, h: Any) -> Any:
        """x ⊕ h dx: q moved on its manifold by ``integrate`` (q ⊕ h v), v by h v̇ — the one body of both loops'
        RK4 stages when nq ≠ nv."""
        nq, n = self.nq, self.n
        return ops.vertcat(ops.integrate(self.robot.model, x[:nq], h * dx[:n]), x[nq:] + h * dx[n:])

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
        return self._saturated(Numeric, self._checked_input(u))

    def _checked_input(self, u: Any) -> np.ndarray:
        return u if type(u) is np.ndarray and u.shape == self._u_shape else joint_torques(u, self.n)

    def _saturated(self, ops: Any, u: Any) -> Any:
        return u if self.tau_max is None else saturated(ops, u, self.tau_max, self._tau_min)

    def torque_law(self, ops: Any, qd: Any, u: Any) -> Any:
        """τ − τ_f: the commanded torques saturated at ±tau_max, minus friction (F_v q̇, and F_s sgn(q̇) with the
        exact sign unless smoothed) — the one body of both loops (the external force is the Python loop's)."""
        tau = self._saturated(ops, u)
        if self._coulomb:
            return tau - ops.friction(self.friction, qd, self.friction_smoothing)
        return tau - self.Fv * qd if self._viscous else tau

    def dynamics(self, ops: Any, x: Any, u: Any) -> Any:
        """ẋ = [v, B⁻¹(q)(τ − τ_f − C v − g)] (Eq. 7.42), the one body of the plant: the compiled loop evaluates
        it on symbols; the Python loop's :meth:`derivative` and :meth:`acceleration` take the same steps with
        the numeric primitives (ABA bound to this plant's data on the hot path)."""
        q, qd = x[:self.nq], x[self.nq:]
        return ops.vertcat(qd, ops.forward_dynamics(self.robot, q, qd, self.torque_law(ops, qd, u)))

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        n, nq = self.n, self.nq
        if type(x) is not np.ndarray or x.shape != self._x_shape:     # the cheap test first (hot path)
            _check_state(x, self.state_size, nq)
        q, qd = x[:nq], x[nq:]
        xd = np.empty(2 * n)
        xd[:n] = qd
        xd[n:] = qdd = self.acceleration(t, q, qd, u)
        if not math.isfinite(sum(qdd.tolist())):  # the checked forward dynamics names a singular B(q)
            xd[n:] = self._forward_dynamics(self.robot, q, qd, self.applied_torque(t, q, qd, u))
        return xd

    def acceleration(self, t: float, q: np.ndarray, qd: np.ndarray, u: np.ndarray) -> np.ndarray:
        """q̈ = B(q)⁻¹ (τ − C q̇ − g), τ the :meth:`applied_torque` (Eq. 7.42): the second half of ẋ,
        which the loop integrates directly when nq = nv (the Nyström form of RK4)."""
        if self._simple and type(u) is np.ndarray and u.shape == self._u_shape:
            if self._frictionless:  # the benchmark's plain arm: ABA on u as it is
                return pin.aba(self._model, self._data, q, qd, u)
            tau = self.torque_law(Numeric, qd, u)
        else:
            tau = self.applied_torque(t, q, qd, u)
        if self._data is None:  # rotors (mimic joints): the Cholesky solve
            return self._forward_dynamics(self.robot, q, qd, tau, check=False)
        return pin.aba(self._model, self._data, q, qd, tau)

    @property
    def time_invariant_acceleration(self) -> Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None:
        """q̈ = ABA(q, q̇, u) as one library call (q, q̇, u) → q̈ when τ = u (no friction, saturation or external
        force, no rotor joints): the loop's Nyström stages call it without a Python frame in between
        (:func:`~controllers.simulation.rk4_stepper`). None otherwise, or when a subclass redefines
        :meth:`acceleration`."""
        if not self._frictionless or type(self).acceleration is not ArmPlant.acceleration:
            return None
        return partial(pin.aba, self._model, self._data)

    def applied_torque(self, t: float, q: np.ndarray, qd: np.ndarray, u: Any) -> np.ndarray:
        """τ − τ_f − τ_ext: the commanded torques ``u`` (n,) saturated at ±tau_max, minus friction and the
        external forces' joint torques at (t, q, q̇)."""
        tau = self.torque_law(Numeric, qd, self._checked_input(u))  # names a wrong input shape
        if self.external_force is not None:
            tau = tau - self.external_force(t, q, qd)
        return tau

    def measure(self, t: float, x: np.ndarray) -> ArmMeasurement:
        if type(x) is not np.ndarray or x.shape != self._x_shape:     # the cheap test first (hot path)
            _check_state(x, self.state_size, self.nq)
        return ArmMeasurement(x[:self.nq], x[self.nq:])

    def symbolic(self) -> Any:
        """ẋ = f(x, u) of :meth:`dynamics` as a ``casadi.Function`` for ``simulate(..., backend="casadi")``; the
        compiled stage moves q by :meth:`integrate_law` when nq ≠ nv. An external-force function has no symbolic
        form (the generic refusal of :func:`controllers.compiled.no_symbolic_form`)."""
        from controllers.compiled import no_symbolic_form, plant_of

        if self.external_force is not None:
            raise no_symbolic_form(self, "an external_force function")
        return plant_of(self)

    def symbolic_integrate(self) -> Any:
        """x ⊕ h dx of :meth:`integrate_law` as a ``casadi.Function`` (x, dx, h) → x', None when nq = nv."""
        from controllers.compiled import integrate_of

        return None if self.nq == self.n else integrate_of(self)


def _check_state(x: Any, size: int, nq: int) -> None:
    """ValueError naming ``x`` unless it is an arm state [q (nq), q̇ (size − nq)] of ``size`` entries."""
    if np.shape(x) != (size,):
        raise ValueError(f"`x` (the state [q; q̇], {nq} + {size - nq} entries) must have shape ({size},), "
                         f"got {np.shape(x)}")


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
        self.input_size = n
        self.integrate, self.measure, self.initial_state = a.integrate, a.measure, a.initial_state
        self.units = {**ARM_UNITS, "u": "V"}

    def torque(self, x: np.ndarray, v_c: np.ndarray) -> np.ndarray:
        """The joint torques the motors deliver at state ``x`` under the voltages ``v_c`` (n,) (checked: numpy
        would broadcast one voltage to every motor)."""
        _check_state(x, self.state_size, self.arm.nq)
        if np.shape(v_c) != (self.n,):
            raise ValueError(f"`u` (the motor voltages v_c) must have shape ({self.n},), one per joint, "
                             f"got {np.shape(v_c)}")
        return self.motor_torque(x[self.arm.nq:], v_c)

    def motor_torque(self, qd: Any, v_c: Any) -> Any:
        """τ = K_r k_t R_a⁻¹ (G_v v_c − k_v K_r q̇) (Eqs. 8.6–8.7), for either loop."""
        return self.voltage_gain * v_c - self.electrical_damping * qd

    def dynamics(self, ops: Any, x: Any, u: Any) -> Any:
        """ẋ of the arm (:meth:`ArmPlant.dynamics`) under the motor torques."""
        return self.arm.dynamics(ops, x, self.motor_torque(x[self.arm.nq:], u))

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return self.arm.derivative(t, x, self.torque(x, u))

    def acceleration(self, t: float, q: np.ndarray, qd: np.ndarray, u: np.ndarray) -> np.ndarray:
        """q̈ under the voltages ``u`` (the loop's Nyström form of RK4, see :class:`ArmPlant`)."""
        return self.arm.acceleration(t, q, qd, self.motor_torque(qd, u))

    def symbolic(self) -> Any:
        """ẋ = f(x, v_c) of :meth:`dynamics` as a ``casadi.Function`` for ``simulate(..., backend="casadi")``."""
        from controllers.compiled import plant_of

        return plant_of(self)

    def symbolic_integrate(self) -> Any:
        return self.arm.symbolic_integrate()


def _positive(x: Any, n: int, name: str) -> np.ndarray:
    v = per_joint(x, n, name)
    if np.any(v <= 0):
        raise ValueError(f"`{name}` must be positive, got {v}")
    return v


class ArmInContact:
    """An arm whose end effector (frame ``frame``) touches ``environment``, with a wrist force sensor.

    The environment gives h_e = ``environment.wrench(T_e, v_e)``, the wrench (6,) exerted BY the end
    effector ON the environment in the base frame (Sect. 9.1), from the end-effector pose T_e and twist
    v_e = J q̇; the arm feels −h_e, i.e. the joint torque Jᵀ h_e is subtracted (Eq. 7.42):
    B(q) q̈ + C q̇ + F_v q̇ + g = τ − Jᵀ h_e. It is computed once per derivative evaluation and once per
    measurement; ``measure`` reports it as ``meas.wrench``, and the loop's first RK4 stage at the sample
    (same t and x) reuses it.

    Hot path: one Pinocchio pass gives the frame's position and Jacobian; an environment with
    ``wrench_at(p_e, v_e)`` (plain arrays, :class:`controllers.environment.ContactEnvironment`) is
    asked directly; no contact (:data:`controllers.environment.NO_CONTACT`) skips Jᵀ h_e.
    """

    runtime_attributes = ("_measured",)      # the last measurement (a Python-loop cache): not part of the loop's key

    def __init__(self, robot: Robot, environment: Any, viscous_friction: Any = 0.0,
                 frame: str | int | None = None):
        if not callable(getattr(environment, "wrench", None)):
            raise ValueError("`environment` must have a method wrench(T_e, v_e) -> h_e (6,)")
        self.robot, self.environment, self.frame = robot, environment, frame
        self._fid = robot.frame(frame)
        self.arm = ArmPlant(robot, viscous_friction=viscous_friction)
        a = self.arm
        self.n, self.nq = a.n, a.nq
        self.state_size, self.tangent_size, self.state_layout = a.state_size, a.tangent_size, a.state_layout
        self._x_shape = (self.state_size,)
        self.input_size = a.input_size
        self.integrate, self.initial_state = a.integrate, a.initial_state
        self.units = {**ARM_UNITS, "wrench": "N, N·m"}
        self._Fv = a.Fv
        self._viscous = a._viscous
        from rigid_body.dynamics import forward_dynamics

        self._forward_dynamics = forward_dynamics   # called with check=False: x, u come from the loop
        wrench_at = getattr(environment, "wrench_at", None)
        self._wrench_at = wrench_at if callable(wrench_at) else None
        # Bound once (the plant belongs to the thread that made it, as ArmPlant): this thread's data, and
        # ABA when the arm has no rotors (mimic joints), else the Cholesky solve of forward_dynamics.
        self._model, self._data = robot.model, robot.data
        self._aba = not robot.has_mimic
        self._measured: tuple = (None, None, None, None)   # (t, x as a list, h_e, J) of the last measurement

    def contact_masses(self, q: Any) -> list[tuple[np.ndarray, float, float, float]]:
        """(d, k, c, m) for each spring of the environment (its ``contact_modes``): direction d (base frame),
        stiffness k, damping c and the arm's effective mass along d at the contact point at q,
        m = 1/(dᵀ J_P B⁻¹ J_Pᵀ d) (the mass a force along d accelerates, Sect. 7.8; inf when the arm
        cannot move along d there)."""
        from rigid_body.dynamics import inertia_matrix

        modes = getattr(self.environment, "contact_modes", None)
        if modes is None:
            return []
        q = as_vector(q, self.nq, "q")
        J = pin.computeFrameJacobian(self._model, self._data, q, self._fid, _LWA)[:3]
        B = inertia_matrix(self.robot, q)
        out = []
        for d, k, c in modes():
            w = J.T @ np.asarray(d, dtype=float)
            mobility = float(w @ np.linalg.solve(B, w))
            out.append((np.asarray(d, dtype=float), float(k), float(c), 1.0 / mobility if mobility > 0 else math.inf))
        return out

    def check_step(self, h: float, x0: Any) -> None:
        """ValueError when RK4 of step ``h`` is unstable on a spring of the contact from the state ``x0``:
        k and c of the environment on the arm's effective mass m at the contact (:meth:`contact_masses`,
        :func:`controllers.simulation.rk4_stable`; without damping h √(k/m) ≤ 2√2). Such a run would stay
        bounded and be non-physical (the arm kicked off the wall), so :func:`~controllers.simulation.simulate`
        calls this before the first step. The mass is the one at x0 (it changes with the posture)."""
        from controllers.simulation import rk4_stable, rk4_step_bound, rk4_stiffness_bound

        x0 = as_vector(x0, self.state_size, "x0")
        for d, k, c, m in self.contact_masses(x0[:self.nq]):
            if math.isfinite(m) and not rk4_stable(m, c, k, h):
                k_max, h_max = rk4_stiffness_bound(m, c, h), rk4_step_bound(m, c, k)
                why = f" (h √(k/m) = {h * math.sqrt(k / m):.3g} > 2√2)" if c == 0 else ""
                raise ValueError(
                    f"`stiffness` k = {k:.4g} N/m (damping {c:.4g} N·s/m) of the {type(self.environment).__name__} "
                    f"along {np.round(d, 3).tolist()} is too stiff for the step h = {h:.4g} s: on the arm's "
                    f"effective mass m = {m:.4g} kg at the contact the RK4 step is unstable{why}. Bound: "
                    f"k ≤ {k_max:.4g} N/m at this h, or h ≤ {h_max:.4g} s for this k")

    def wrench(self, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(h_e (6,), J (6, nv)) at (q, q̇)."""
        return self.contact_wrench(Numeric, q, qd)

    def contact_wrench(self, ops: Any, q: Any, qd: Any) -> tuple[Any, Any]:
        """(h_e, J): the environment's wrench at the frame's pose T_e and twist v_e = J q̇, one kinematics pass —
        the one body of the contact for both loops."""
        T_e, J = ops.frame_jacobian(self._model, self._data, self._fid, q)
        return ops.contact_wrench(self.environment, T_e, J @ qd), J

    def torque_law(self, ops: Any, qd: Any, u: Any, h_e: Any, J: Any) -> Any:
        """u − F_v q̇ − Jᵀ h_e (Eq. 7.42); no contact (:data:`~controllers.environment.NO_CONTACT`) skips Jᵀ h_e."""
        tau = u - self._Fv * qd if self._viscous else u
        return tau if h_e is NO_CONTACT else tau - J.T @ h_e

    def dynamics(self, ops: Any, x: Any, u: Any) -> Any:
        """ẋ = [v, B⁻¹(q)(u − F_v v − Jᵀ h_e − C v − g)] (Eq. 7.42): the one body of the plant (the Python
        loop's :meth:`acceleration` reuses the measurement's h_e at the sample)."""
        q, qd = x[:self.nq], x[self.nq:]
        h_e, J = self.contact_wrench(ops, q, qd)
        return ops.vertcat(qd, ops.forward_dynamics(self.robot, q, qd, self.torque_law(ops, qd, u, h_e, J)))

    def contact_torques(self, t: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """Jᵀ h_e: the joint torques the contact takes from the arm."""
        h_e, J = self.wrench(q, qd)
        return J.T @ h_e

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        n, nq = self.n, self.nq
        if type(x) is not np.ndarray or x.shape != self._x_shape:     # the cheap test first (hot path)
            _check_state(x, self.state_size, nq)
        u = joint_torques(u, n)
        q, qd = x[:nq], x[nq:]
        xd = np.empty(2 * n)
        xd[:n] = qd
        xd[n:] = qdd = self.acceleration(t, q, qd, u)
        if not math.isfinite(sum(qdd.tolist())):  # the forward dynamics names a singular B(q)
            xd[n:] = self._forward_dynamics(self.robot, q, qd, self._torque(q, qd, u), check=False)
        return xd

    def acceleration(self, t: float, q: np.ndarray, qd: np.ndarray, u: np.ndarray) -> np.ndarray:
        """q̈ = B(q)⁻¹ (u − F_v q̇ − Jᵀ h_e − C q̇ − g) (Eq. 7.42): the second half of ẋ, which the loop
        integrates directly when nq = nv (the Nyström form of RK4)."""
        if self._aba:
            return pin.aba(self._model, self._data, q, qd, self._torque(q, qd, u, t))
        return self._forward_dynamics(self.robot, q, qd, self._torque(q, qd, u, t), check=False)

    def _torque(self, q: np.ndarray, qd: np.ndarray, u: np.ndarray, t: float | None = None) -> np.ndarray:
        """u − F_v q̇ − Jᵀ h_e; (h_e, J) of the last measurement when (t, q, q̇) is the same (the loop's
        first RK4 stage follows the measurement at the sample)."""
        t_m, x_m, h_e, J = self._measured
        if t != t_m or t is None or q.tolist() + qd.tolist() != x_m:
            h_e, J = self.contact_wrench(Numeric, q, qd)
        return self.torque_law(Numeric, qd, u, h_e, J)                           # Eq. (7.42)

    def measure(self, t: float, x: np.ndarray) -> ArmMeasurement:
        nq = self.nq
        if type(x) is not np.ndarray or x.shape != self._x_shape:     # the cheap test first (hot path)
            _check_state(x, self.state_size, nq)
        q, qd = x[:nq], x[nq:]
        h_e, J = self.wrench(q, qd)
        kept = h_e if h_e is NO_CONTACT else np.array(h_e, dtype=float)   # the controller may keep or alter its own
        self._measured = (t, x.tolist(), kept, J)
        return ArmMeasurement(q, qd, h_e)

    def symbolic(self) -> Any:
        """ẋ = f(x, u) of :meth:`dynamics` as a ``casadi.Function`` for ``simulate(..., backend="casadi")``
        (the environment's wrench from its ``wrench_law``)."""
        from controllers.compiled import plant_of

        return plant_of(self)

    def symbolic_integrate(self) -> Any:
        return self.arm.symbolic_integrate()

    def symbolic_measurement(self, name: str) -> Any:
        """The measurement entry ``name`` (``"wrench"``: h_e (6,)) as a ``casadi.Function`` x → value."""
        import casadi as ca

        from controllers.compiled import Symbolic

        if name != "wrench":
            raise ValueError(f"`name`: ArmInContact measures q, qd and wrench, got {name!r}")
        x = ca.SX.sym("x", self.state_size)
        h_e, _ = self.contact_wrench(Symbolic, x[:self.nq], x[self.nq:])
        return ca.Function("wrench", [x], [h_e], ["x"], ["wrench"])


class JointDrivePlant:
    """The drive M(s) as a plant: x = [ϑ_m, ϑ̇_m], u = [v] or [v, d]; ``T_m ϑ̈ = k_m(v − (R_a/k_t) d) − ϑ̇``.

    Its measurement is an :class:`ArmMeasurement` of the motor side: ``q = [ϑ_m]``, ``qd = [ϑ̇_m]``.
    """

    state_size = 2
    input_size = (1, 2)
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
    input_size = (1, 2)
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
        return self._amplifier(x, v_c)[0]

    def _amplifier(self, x: Any, v_c: Any) -> tuple[Any, Any, Any]:
        """(v_a, the amplifier's input G_v C_i(e), the current error e): with T_v = 0 the output follows the input."""
        m = self.motor
        e = v_c - m.ki * x[0]
        regulated = m.Gv * (self._KP * e + self._KI * x[4])                    # cf. (S5.5)
        return (x[3] if m.Tv > 0 else regulated), regulated, e

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return self.dynamics(Numeric, x, u)

    def dynamics(self, ops: Any, x: Any, u: Any) -> Any:
        """ẋ of (5.1)–(5.4) with the amplifier lag and the PI integral, u = [v'_c] or [v'_c, c_r]: the one body of
        both loops."""
        m = self.motor
        v_c, c_r = u[0], (u[1] if u.shape[0] > 1 else 0.0)
        i_a, omega = x[0], x[1]
        v_a, regulated, e = self._amplifier(x, v_c)
        dva = (regulated - x[3]) / m.Tv if m.Tv > 0 else 0.0
        return ops.vector((v_a - m.Ra * i_a - m.kv * omega) / m.La,           # (5.1)–(5.2)
                          (m.kt * i_a - m.Fm * omega - c_r) / m.Im,           # (5.3)–(5.4)
                          omega, dva, e)

    symbolic_input_size = 2

    def symbolic(self) -> Any:
        """ẋ = f(x, u) of :meth:`dynamics` (u = [v'_c, c_r]) as a ``casadi.Function`` for
        ``simulate(..., backend="casadi")``."""
        from controllers.compiled import plant_of

        return plant_of(self)


class JointIntegrator:
    """The plant q̇ = u of a kinematic IK loop (x = q); RK4 with u held is Euler's step (3.48).

    Its ``bound`` (500 rad, about 80 turns) stops an unstable loop early — e.g. CLIK with K·Ts > 2,
    where the error grows by |1 − K Ts| every step — instead of returning a meaningless q ~ 1e5 rad.
    ``n`` (optional) fixes the number of joints: the loop then checks ``x0`` and the controller's output.
    """

    bound = 500.0
    state_layout = {"q": slice(None)}
    units = {"q": "rad", "u": "rad/s"}

    def __init__(self, n: int | None = None):
        if n is not None:
            if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
                raise ValueError(f"`n` must be a positive number of joints, got {n!r}")
            self.state_size = self.tangent_size = self.input_size = int(n)

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return u


class KinematicArm(JointIntegrator):
    """The manipulator modelled as an integrator, q̇ = u (the resolved-velocity schemes of Figs. 10.15 and
    10.17): like :class:`JointIntegrator`, but the controller reads the joint encoders as an
    :class:`ArmMeasurement` (``meas.q``); the velocity is the controller's own command, so ``qd`` is None."""

    def measure(self, t: float, x: np.ndarray) -> ArmMeasurement:
        return ArmMeasurement(x, None)


# --------------------------------------------------------------------------------------------
# Wheeled mobile robots (Chapter 11): kinematic plants
# --------------------------------------------------------------------------------------------

# the posture, the inputs, and the polar coordinates the regulators of Sect. 11.6.2 log (ρ, γ, δ)
POSTURE_UNITS = {"x": "m", "y": "m", "theta": "rad", "p": "m", "u": "m/s, rad/s", "rho": "m", "gamma": "rad",
                 "delta": "rad"}


@dataclass(frozen=True, slots=True)
class Posture:
    """What a unicycle's sensors give: x, y [m], θ [rad]; ``p`` = (x, y)."""

    x: float
    y: float
    theta: float

    @property
    def p(self) -> np.ndarray:
        return np.array([self.x, self.y])


@dataclass(frozen=True, slots=True)
class OdometerPosture(Posture):
    """A posture with the wheel encoders' readings: ``distance`` s = ∫v dt [m] and ``rotation``
    ψ = ∫ω dt [rad] (not wrapped). Over a sampling interval their increments are the book's
    v_k T_s = Δs and ω_k T_s = Δθ of odometric localisation (Sect. 11.7)."""

    distance: float
    rotation: float


@dataclass(frozen=True, slots=True)
class BicycleState(Posture):
    """Measured bicycle state: the rear contact point's posture (x, y, θ) and the steering angle φ [rad]."""

    phi: float


class UnicyclePlant:
    """The unicycle (11.13), x = (x, y, θ), u = (v, ω); θ stays wrapped into (−π, π].

    ``wheel_limits = (r, d, ω_RL)`` makes it a differential drive whose wheel speeds saturate at ±ω_RL: the
    applied (v, ω) are scaled into the admissible rhombus of Problem 11.9 keeping the curvature.
    ``odometer=True`` adds the wheel encoders: x = (x, y, θ, s, ψ) with ṡ = v, ψ̇ = ω (applied), and the
    measurement is an :class:`OdometerPosture`.
    """

    def __init__(self, wheel_limits: tuple[float, float, float] | None = None, odometer: bool = False):
        if wheel_limits is not None:
            r, d, w = wheel_limits
            wheel_limits = (as_positive(r, "r"), as_positive(d, "d"), as_positive(w, "omega_RL"))
        self.wheel_limits = wheel_limits
        self.odometer = bool(odometer)
        self.state_size = 5 if self.odometer else 3
        self.input_size = 2                                  # (v, ω), checked by the loop at the first sample
        self.state_layout = {"x": 0, "y": 1, "theta": 2, "p": slice(0, 2)}
        self.units = dict(POSTURE_UNITS)
        if self.odometer:
            self.state_layout |= {"distance": 3, "rotation": 4}
            self.units |= {"distance": "m", "rotation": "rad"}

    def applied(self, u: np.ndarray) -> np.ndarray:
        """The (v, ω) actually applied (saturated when the plant has wheel limits)."""
        if self.wheel_limits is None:
            return u
        return np.array(saturate_wheel_speeds(u[0], u[1], *self.wheel_limits))

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        u = self.applied(u) if self.wheel_limits else u
        qd = unicycle_velocity(x, u)
        return np.concatenate([qd, u[:2]]) if self.odometer else qd

    def integrate(self, x: np.ndarray, dx: np.ndarray, h: float) -> np.ndarray:
        """x ⊕ h dx on R² × SO(2) (× R² for the encoders): θ wrapped into (−π, π]."""
        y = x + h * dx
        y[2] = math.pi - (math.pi - float(y[2])) % (2.0 * math.pi)     # rotations.wrap_angle on one float
        return y

    def measure(self, t: float, x: np.ndarray) -> Posture:
        if self.odometer:
            return OdometerPosture(float(x[0]), float(x[1]), float(x[2]), float(x[3]), float(x[4]))
        return Posture(float(x[0]), float(x[1]), float(x[2]))


class BicyclePlant:
    """The bicycle, rear-wheel (11.19) or front-wheel (11.20) drive: x = (x, y, θ, φ), u = (v, ω = φ̇)."""

    state_size = 4
    input_size = 2                                           # (v, ω = φ̇)
    state_layout = {"x": 0, "y": 1, "theta": 2, "phi": 3, "p": slice(0, 2)}
    units = {**POSTURE_UNITS, "phi": "rad"}

    def __init__(self, ell: float, drive: str = "rear"):
        self.ell = as_positive(ell, "ell")
        if drive not in ("rear", "front"):
            raise ValueError(f"`drive` must be 'rear' or 'front', got {drive!r}")
        self.drive = drive

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        th, phi, v = x[2], x[3], u[0]
        if self.drive == "rear":
            return np.array([v * np.cos(th), v * np.sin(th), v * np.tan(phi) / self.ell, u[1]])
        c = np.cos(phi)
        return np.array([v * np.cos(th) * c, v * np.sin(th) * c, v * np.sin(phi) / self.ell, u[1]])

    def measure(self, t: float, x: np.ndarray) -> BicycleState:
        return BicycleState(float(x[0]), float(x[1]), float(x[2]), float(x[3]))


class ChainedFormPlant:
    """The (2, n) chained form (11.25), x = z, u = (v1, v2); the measurement is z itself."""

    state_layout = {"z": slice(None)}
    input_size = 2                                           # (v1, v2)

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return chained_form_velocity(x, u)


class DriftlessPlant:
    """q̇ = G(q) u for any kinematic model (11.10): ``input_matrix(q) -> G`` (n, m)."""

    state_layout = {"q": slice(None)}

    def __init__(self, input_matrix: Callable[[np.ndarray], np.ndarray]):
        self.input_matrix = input_matrix

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return self.input_matrix(x) @ u


@dataclass(frozen=True, slots=True)
class MobileManipulatorState:
    """What a mobile manipulator's sensors give: the configuration ``q`` (nq,) of the whole model
    (base x, y, cos θ, sin θ, then the arm's joints) and the base ``posture`` (x, y, θ)."""

    q: np.ndarray
    posture: Posture


class MobileManipulatorPlant:
    """A unicycle base carrying an arm, kinematic: x = q (nq = nv + 1), ẋ = v = Γ u (nv), u = (v, ω, q̇_arm).

    ``robot`` is one Pinocchio model with a planar root joint (:func:`rigid_body.wheeled.mobile_manipulator`).
    Γ = [G 0; 0 I] (:func:`rigid_body.wheeled.mobile_manipulator_input_matrix`) maps the unicycle's (v, ω)
    to the base's body velocity (v, 0, ω) — never sideways, the no-slip constraint (11.12) — and the arm's
    inputs to its joint velocities. The configuration moves by ``pin.integrate`` (cos θ, sin θ stay a unit
    pair). ``input_limits`` (m,) saturates |u|.
    """

    units = {"q": "m, rad", "u": "m/s, rad/s"}

    def __init__(self, robot: Robot, input_limits: Any = None):
        self.robot, self.model = robot, robot.model
        self.state_size, self.tangent_size = robot.nq, robot.nv
        self.input_matrix = mobile_manipulator_input_matrix(robot)
        self.n_inputs = self.input_size = self.input_matrix.shape[1]
        self.state_layout = {"q": slice(None), "p": slice(0, 2)}
        self.input_limits = None if input_limits is None else as_vector(input_limits, self.n_inputs, "input_limits")

    def initial_state(self, base: Any, q_arm: Any) -> np.ndarray:
        """x0 from the base posture (x, y, θ) and the arm's joint angles."""
        x, y, th = as_vector(base, 3, "base")
        return np.concatenate([[x, y, np.cos(th), np.sin(th)],
                               as_vector(q_arm, self.robot.nq - 4, "q_arm")])

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        if self.input_limits is not None:
            u = np.clip(u, -self.input_limits, self.input_limits)
        return self.input_matrix @ u

    def integrate(self, x: np.ndarray, dx: np.ndarray, h: float) -> np.ndarray:
        return pin.integrate(self.model, x, h * dx)

    def measure(self, t: float, x: np.ndarray) -> MobileManipulatorState:
        return MobileManipulatorState(x, Posture(float(x[0]), float(x[1]), float(np.arctan2(x[3], x[2]))))
