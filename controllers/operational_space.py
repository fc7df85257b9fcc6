"""Centralised operational-space motion control (Sect. 8.6): position or full pose of a frame.

The task is either
* the **position** of a frame's origin, restricted to the components ``rows`` (e.g. (0, 1): x and y
  of a planar arm); then J_A = J_P[rows] (Eq. 3.30) and J̇_A q̇ is the classical acceleration of the
  origin at q̈ = 0; or
* the **pose** (``orientation="quaternion"`` or ``"axis_angle"``): the error is
  x̃ = [p_d − p_e; e_O] with the unit-quaternion (3.91) or angle–axis (3.85) orientation error, and
  the Jacobian is the geometric one (the one these errors go with, Sect. 3.7.3), with the desired
  velocity and acceleration [ṗ_d; ω_d], [p̈_d; ω̇_d]. Euler-angle errors (analytical Jacobian (3.66))
  are not offered: they are singular where the Panda's hand points down (ZYZ) and, with the gains
  that work for the quaternion error, the 1 ms PD loop on the Panda with RPY angles oscillated
  without settling (measured).

The laws, with errors x̃ = x_d − x_e and the task Jacobian J (rows of :class:`rigid_body.task_space.TaskSpace`):

* :class:`OperationalPDGravity` — u = g(q) + Jᵀ K_P x̃ − Jᵀ K_D J q̇ − K_N q̇ (Eq. 8.110, Fig. 8.29).
* :class:`OperationalInverseDynamics` — u = B(q) y + n(q, q̇),
  y = J†(ẍ_d + K_D (ẋ_d − J q̇) + K_P x̃ − J̇ q̇) + (I − J† J) y_0 (Eqs. 8.57, 8.114, Fig. 8.30),
  J† = J⁻¹ for a square task, the right pseudo-inverse (3.52) for a redundant one. With a desired
  inertia M_d it is **impedance control** (Sect. 9.3, Eq. 9.28), with the sensed wrench too the
  linear impedance of Eqs. (9.30)–(9.31). (PD + gravity, in contact, is compliance control,
  Sect. 9.2: its rest is :func:`controllers.force.compliance_equilibrium`.)

Redundancy (fewer task components than joints, e.g. a 6-D pose on the 7-DOF Panda): the task does not
fix the self-motion. The PD law adds the joint damping −K_N q̇ (``joint_damping``): it only adds
dissipation, so the Lyapunov argument of (8.110) holds and the self-motion comes to rest. Inverse
dynamics adds, in the null space of J, y_0 = K_q (q_0 − q) − K_N q̇ (``posture``, ``posture_stiffness``,
``null_space_damping``), cf. (3.54): the task dynamics x̃̈ + K_D x̃̇ + K_P x̃ = 0 are untouched and the
arm does not drift along the self-motion.

References are as in :mod:`controllers.joint_space` for a position task (a constant point, a
trajectory with ``evaluate``, or a callable ``t -> (x_d, ẋ_d, ẍ_d)``) in the task components; for a
pose task a constant (4, 4) pose or a callable ``t -> (T_d (4, 4), v_d (6,), a_d (6,))`` (see
:func:`as_pose_reference`).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 3.7.3, 8.6, 9.2–9.3, Eqs. (3.85), (3.91), (8.110)–(8.114), (9.28)–(9.31), Figs. 8.29–8.30.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from scipy.optimize import fsolve

from controllers.laws import (ControlLaw, Numeric, as_friction, as_gain, as_pose_reference, as_reference,
                              check_redundancy, nonnegative, position_rows, task_reference)
from rigid_body.dynamics import gravity_torques, inertia_matrix
from rigid_body.robots import Robot
from rigid_body.task_space import TaskSpace, singular_task, solve_task
from rigid_body.validation import as_vector

CONTROL_ORIENTATIONS = ("none", "axis_angle", "quaternion")


class _Task:
    """The controlled task of one frame: error x̃, Jacobian J and J̇q̇ from one kinematics pass
    (:func:`rigid_body.task_space.pose_error`), and the reference in the task components."""

    def __init__(self, robot: Robot, rows: Sequence[int] | None, frame: str | int | None, orientation: str,
                 reference: Any = None):
        if orientation not in CONTROL_ORIENTATIONS:
            raise ValueError(f"`orientation` must be one of {CONTROL_ORIENTATIONS}, got {orientation!r}")
        self.robot = robot
        self.pose = orientation != "none"
        self._fid = fid = robot.frame(frame)  # resolved once (unknown frame → ValueError now)
        self._model, self._data = robot.model, robot.data
        if self.pose:
            self.space = TaskSpace(fid, orientation, None if rows is None else tuple(int(r) for r in rows))
            self.rows = np.array(self.space.selected)
        else:
            self.rows = position_rows((0, 1, 2) if rows is None else rows)
            self.space = TaskSpace(fid, "none", tuple(self.rows.tolist()))
        self.m = self.rows.size
        self._T_d = np.eye(4)
        if reference is None:
            self.reference = None
        elif self.pose:
            law, r = as_pose_reference(reference), self.rows

            def restricted(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
                T, v, a = law(t)
                return T, np.asarray(v, dtype=float)[r], np.asarray(a, dtype=float)[r]

            self.reference = restricted
        else:
            self.reference = as_reference(task_reference(reference, self.rows), self.m)
        m = self.m
        self.reference_shapes = ((4, 4) if self.pose else (m,), (m,), (m,))

    def target(self, x_d: np.ndarray) -> np.ndarray:
        """The desired pose: T_d itself, or a pose whose origin has the ``rows`` components x_d."""
        if self.pose:
            return x_d
        self._T_d[self.rows, 3] = x_d
        return self._T_d

    def error(self, q: np.ndarray, x_d: np.ndarray, qd: np.ndarray | None = None, ops: Any = Numeric) -> tuple:
        """(x̃, J, J̇q̇ or None, T_e) at q (and q̇), for either executor (``ops``)."""
        if not self.pose:                     # position task: x̃ = x_d − p_e[rows] from one kinematics pass
            st = ops.frame_state(self._model, self._data, self._fid, q, qd)
            r = ops.index(self.rows)
            return x_d - st.T[r, 3], st.J[r, :], None if qd is None else st.Jdot_qd[r], st.T
        return ops.pose_error(self._model, self._data, self.space, self._fid, q, x_d, qd)

    def logged(self, ops: Any, x_d: Any, T_e: Any, e: Any) -> dict[str, Any]:
        if self.pose:
            return {"p_d": ops.copy(x_d[:3, 3]), "p_e": ops.copy(T_e[:3, 3]), "e": e}
        return {"x_d": x_d, "x_e": T_e[ops.index(self.rows), 3], "e": e}


class OperationalPDGravity(ControlLaw):
    """u = g(q) + Jᵀ(q) K_P x̃ − Jᵀ(q) K_D J(q) q̇ − K_N q̇ (Eq. 8.110, Fig. 8.29), x̃ = x_d − x_e.

    For a constant x_d and J of full rank the equilibrium x̃ = 0 is asymptotically stable
    (Lyapunov function ½ q̇ᵀ B q̇ + ½ x̃ᵀ K_P x̃ for a position task, with the orientation potential
    of the quaternion/angle–axis error for a pose task and a scalar orientation gain).

    Parameters
    ----------
    robot : the controller's model (g(q) and the kinematics).
    K_P, K_D : (m, m) gains (scalar, (m,) or matrix), positive definite (m = number of task components).
    reference : position task: the desired position x_d, (m,) in the ``rows`` components or (3,) (or a
        trajectory, see :func:`task_reference`); pose task: a (4, 4) pose or a pose trajectory
        (:func:`as_pose_reference`; only T_d is used).
    rows : controlled components: of the position (0..2, default all three) for a position task, of
        [position; orientation] (0..5, default all six) for a pose task.
    frame : the controlled frame (default the end effector).
    orientation : ``"none"`` (position task, default), ``"quaternion"`` (3.91) or ``"axis_angle"`` (3.85).
    joint_damping : K_N ≥ 0 [N·m·s/rad] (scalar or (n,)), the extra term −K_N q̇ that brings the self-motion
        of a redundant arm to rest (pure dissipation: the equilibrium and its stability are those of (8.110)).
    """

    def __init__(self, robot: Robot, K_P: Any, K_D: Any, reference: Any, rows: Sequence[int] | None = None,
                 frame: str | int | None = None, orientation: str = "none", joint_damping: Any = 0.0):
        self.robot, self.n, self.nq, self.nv = robot, robot.nv, robot.nq, robot.nv
        self.task = _Task(robot, rows, frame, orientation, reference)
        m = self.task.m
        check_redundancy(m, self.n)
        self.K_P, self.K_D = as_gain(K_P, m, "K_P"), as_gain(K_D, m, "K_D")
        self.set_gains(K_P=self.K_P, K_D=self.K_D)
        self.K_N = nonnegative(joint_damping, self.n, "joint_damping")
        self.reference, self.reference_shapes = self.task.reference, self.task.reference_shapes
        self._model, self._data = robot.model, robot.data

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple) -> tuple[Any, dict]:
        """Eq. (8.110), once for both executors."""
        x_d = ref[0]
        e, J, _, T_e = self.task.error(q, x_d, None, ops)
        u = ops.gravity(self._model, self._data, q) + J.T @ (ops.times(K["K_P"], e) - ops.times(K["K_D"], J @ qd)) \
            - self.K_N * qd                                                                       # Eq. (8.110)
        return u, self.task.logged(ops, x_d, T_e, e)


class OperationalInverseDynamics(ControlLaw):
    """u = B(q) y + n(q, q̇), y = J†(ẍ_d + K_D x̃̇ + K_P x̃ − J̇ q̇) + (I − J† J) y_0 (Eqs. 8.57, 8.114, Fig. 8.30).

    With a perfect model the task error obeys x̃̈ + K_D x̃̇ + K_P x̃ = 0 (x̃̇ = ẋ_d − J q̇; for a pose task
    the orientation part is ω_d − ω_e). J must have full row rank along the motion; for a redundant
    task (fewer components than joints) J† is the right pseudo-inverse (3.52) and
    y_0 = K_q (q_0 − q) − K_N q̇ keeps the self-motion at rest near the posture q_0.

    Parameters
    ----------
    robot : the controller's model (e.g. without the payload the real arm carries).
    K_P, K_D : (m, m) gains, positive definite.
    reference : trajectory in the task components (position task, see
        :func:`controllers.laws.as_reference`) or a pose reference (:func:`as_pose_reference`).
    rows, frame, orientation : the task, as in :class:`OperationalPDGravity` (``"quaternion"`` or
        ``"axis_angle"`` for a pose task: geometric Jacobian).
    viscous_friction : F_v of the model.
    null_space_damping : K_N [1/s] (scalar or (n,)); posture : q_0 (required when K_q ≠ 0);
        posture_stiffness : K_q [1/s²] (scalar or (n,)). Used only for a redundant task.
    inertia : M_d, the desired inertia of an **impedance** (Sect. 9.3): y = J†(ẍ_d + M_d⁻¹(K_D x̃̇ + K_P x̃)
        − J̇ q̇), so that (free motion) M_d x̃̈ + K_D x̃̇ + K_P x̃ = 0 — and in contact
        M_d x̃̈ + K_D x̃̇ + K_P x̃ = M_d B_A⁻¹(q) h_A, a configuration-dependent impedance (Eq. 9.28).
    force_feedback : with the sensed wrench h_e (``meas.wrench``, its ``rows`` components),
        u = B y + n + Jᵀ h_e, y = J† M_d⁻¹(M_d ẍ_d + K_D x̃̇ + K_P x̃ − M_d J̇ q̇ − h_e) (Eqs. 9.30–9.31): the
        linear impedance M_d x̃̈ + K_D x̃̇ + K_P x̃ = h_e. The impedance of one axis against a spring of
        stiffness k has ω_n, ζ of :func:`controllers.force.impedance_parameters`.

    With the quaternion error e_O ≈ (ϑ/2) r for small angles, an orientation stiffness 2 K_P gives
    the orientation the bandwidth of a position stiffness K_P.
    """

    def __init__(self, robot: Robot, K_P: Any, K_D: Any, reference: Any, rows: Sequence[int] | None = None,
                 frame: str | int | None = None, viscous_friction: Any = 0.0, orientation: str = "none",
                 null_space_damping: Any = 0.0, posture: Any = None, posture_stiffness: Any = 0.0,
                 inertia: Any = None, force_feedback: bool = False):
        self.robot, self.n, self.nq, self.nv = robot, robot.nv, robot.nq, robot.nv
        self.task = _Task(robot, rows, frame, orientation, reference)
        m = self.task.m
        check_redundancy(m, self.n)
        self.K_P, self.K_D = as_gain(K_P, m, "K_P"), as_gain(K_D, m, "K_D")
        self.set_gains(K_P=self.K_P, K_D=self.K_D)
        self.Fv = as_friction(viscous_friction, self.n)
        self.K_N = nonnegative(null_space_damping, self.n, "null_space_damping")
        self.K_q = nonnegative(posture_stiffness, self.n, "posture_stiffness")
        if posture is None and np.any(self.K_q > 0):
            raise ValueError("`posture` (q_0) is required with a nonzero `posture_stiffness`")
        self.q_0 = np.zeros(robot.nq) if posture is None else as_vector(posture, robot.nq, "posture").copy()
        self.redundant = m < self.n
        self.reference, self.reference_shapes = self.task.reference, self.task.reference_shapes
        self.force_feedback = bool(force_feedback)
        if inertia is None and self.force_feedback:
            raise ValueError("`force_feedback` needs the impedance's desired `inertia` M_d")
        self.M_d_inv = None if inertia is None else np.linalg.inv(as_gain(inertia, m, "inertia"))
        self.measurements = (("wrench", 6),) if self.force_feedback else ()
        self._model, self._data = robot.model, robot.data

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple, wrench: Any = None) -> tuple[Any, dict]:
        """Eqs. (8.57), (8.114) (with the impedance M_d of Eqs. 9.28, 9.30–9.31 and the null-space term of a
        redundant task), once for both executors."""
        x_d, xd_d, xdd_d = ref
        task = self.task
        e, J, Jdot_qd, T_e = task.error(q, x_d, qd, ops)
        ed = xd_d - J @ qd
        if self.M_d_inv is None:
            a = xdd_d + ops.times(K["K_D"], ed) + ops.times(K["K_P"], e) - Jdot_qd
        else:  # impedance, Eq. (9.31) (without h_e: the law of Eq. 9.28)
            w = ops.times(K["K_D"], ed) + ops.times(K["K_P"], e)
            if self.force_feedback:
                h = wrench[ops.index(task.rows)]
                w = w - h
            a = xdd_d + self.M_d_inv @ w - Jdot_qd
        y = ops.solve_task(J, a)                                                        # Eq. (8.114)
        if self.redundant:
            y0 = self.K_q * (self.q_0 - q) - self.K_N * qd
            y = y + (y0 - ops.solve_task(J, J @ y0))                                    # (I − J† J) y_0, cf. (3.54)
        u = ops.rnea(self._model, self._data, q, qd, y) + self.Fv * qd                  # B y + n
        signals = task.logged(ops, x_d, T_e, e)
        if self.force_feedback:
            u = u + J.T @ h                                                             # + Jᵀ h_e, Eq. (9.30)
            signals["h_e"] = wrench
        return u, signals


def operational_inverse_dynamics_steady_state(plant_robot: Robot, model_robot: Robot, K_P: Any, x_d: Any,
                                              q0: Any, rows: Sequence[int] = (0, 1, 2),
                                              frame: str | int | None = None) -> np.ndarray:
    """The rest posture q of operational-space inverse dynamics with a wrong model at a set point x_d.

    At rest the controller applies B̂(q) J_A⁻¹(q) K_P x̃ + ĝ(q) and the arm needs g(q), so q solves
    B̂(q) J_A⁻¹(q) K_P (x_d − x_e(q)) = g(q) − ĝ(q) (Newton iterations from ``q0``, e.g. the posture
    reached at the end of the motion).
    """
    task = _Task(model_robot, rows, frame, "none")
    n = model_robot.nv
    if task.m != n:
        raise ValueError(f"`rows` must select {n} components, got {task.m}")
    K_P = as_gain(K_P, n, "K_P")
    x_d = as_vector(x_d, n, "x_d")
    start = as_vector(q0, n, "q0")

    def residual(q: np.ndarray) -> np.ndarray:
        e, J, _, _ = task.error(q, x_d)
        y = solve_task(J, K_P @ e)
        if y is None:
            raise singular_task(f"at q = {q}")
        return inertia_matrix(model_robot, q) @ y - gravity_torques(plant_robot, q) + gravity_torques(model_robot, q)

    q, _, _, msg = fsolve(residual, start, full_output=True, xtol=1e-13)
    if np.max(np.abs(residual(q))) > 1e-8:  # judged by the residual (fsolve's ier is pessimistic at a root)
        raise ValueError(f"no steady state of the operational-space loop found near {start}: {msg}")
    return q
