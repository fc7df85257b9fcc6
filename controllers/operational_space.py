"""Centralised operational-space motion control (Sect. 8.6) of the end-effector position.

The task is the position of a frame's origin, restricted to the components ``rows`` (e.g. (0, 1):
x and y of a planar arm). For a position task the analytical Jacobian J_A is the position part of
the geometric Jacobian, J_P (Eq. 3.30), and J̇_A q̇ is the classical acceleration of the origin at
q̈ = 0. Orientation tasks (which need the analytical Jacobian of an Euler representation) are not
covered here.

* :class:`OperationalPDGravity` — u = g(q) + J_Aᵀ K_P x̃ − J_Aᵀ K_D J_A q̇ (Eq. 8.110, Fig. 8.29).
* :class:`OperationalInverseDynamics` — u = B(q) y + n(q, q̇),
  y = J_A⁻¹ (ẍ_d + K_D x̃̇ + K_P x̃ − J̇_A q̇) (Eqs. 8.57, 8.114, Fig. 8.30).

Errors are x̃ = x_d − x_e. References are as in :mod:`controllers.joint_space` (a constant point, a
trajectory with ``evaluate``, or a callable ``t -> (x_d, ẋ_d, ẍ_d)``) in the task components.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 8.6, Eqs. (8.110)–(8.114), Figs. 8.29–8.30.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from scipy.optimize import fsolve

from controllers.joint_space import as_gain, as_reference
from controllers.simulation import as_friction
from rigid_body.dynamics import gravity_torques, inertia_matrix, inverse_dynamics
from rigid_body.kinematics import direct_kinematics, geometric_jacobian, jacobian_derivative_times_qd
from rigid_body.robots import Robot
from rigid_body.validation import as_vector


def _rows(rows: Sequence[int]) -> np.ndarray:
    r = np.asarray(rows, dtype=int).ravel()
    if r.size == 0 or len(set(r.tolist())) != r.size or np.any((r < 0) | (r > 2)):
        raise ValueError(f"`rows` must be distinct position components in 0..2, got {rows!r}")
    return r


def task_reference(reference: Any, rows: Sequence[int]) -> Any:
    """``reference`` in the task components: a point or law given in full (x, y, z) is restricted to ``rows``.

    Lets a 3-D path law (e.g. :class:`planners.paths.PathLaw`) drive a planar task (rows (0, 1)).
    """
    r = _rows(rows)
    if r.size == 3:
        return reference
    if hasattr(reference, "evaluate") or callable(reference):
        law = reference.evaluate if hasattr(reference, "evaluate") else reference
        if np.size(law(0.0)[0]) != 3:
            return reference

        def restricted(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            x, xd, xdd = law(t)
            return (np.reshape(x, 3)[r], np.reshape(xd, 3)[r], np.reshape(xdd, 3)[r])

        return restricted
    v = np.asarray(reference, dtype=float).ravel()
    return v[r] if v.size == 3 else reference


class _PositionTask:
    """x_e(q) = p_e[rows], J_A = J_P[rows], J̇_A q̇ = ṗ̇_e[rows] at q̈ = 0, for one frame."""

    def __init__(self, robot: Robot, rows: Sequence[int], frame: str | int | None):
        self.robot, self.rows = robot, _rows(rows)
        self.frame = robot.ee_frame if frame is None else robot.frame(frame)
        self.m = self.rows.size

    def position(self, q: np.ndarray) -> np.ndarray:
        return direct_kinematics(self.robot, q, self.frame)[:3, 3][self.rows]

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        return geometric_jacobian(self.robot, q, self.frame)[self.rows]

    def jacobian_derivative_times_qd(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        return jacobian_derivative_times_qd(self.robot, q, qd, self.frame)[self.rows]


SINGULAR_CONDITION = 1e10  # cond(J_A) above which the task is treated as singular


def _solve_task(J: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """J_A⁻¹ b for a square J_A; None at (or numerically at) a kinematic singularity, cond(J_A) > 1e10."""
    s = np.linalg.svd(J, compute_uv=False)
    return np.linalg.solve(J, b) if s[-1] > s[0] / SINGULAR_CONDITION else None


def _singular(where: str) -> ValueError:
    return ValueError(f"J_A is singular {where} (condition number > {SINGULAR_CONDITION:g}): "
                      "the task cannot be inverted")


class OperationalPDGravity:
    """u = g(q) + J_Aᵀ(q) K_P x̃ − J_Aᵀ(q) K_D J_A(q) q̇ (Eq. 8.110, Fig. 8.29), x̃ = x_d − x_e.

    For a constant x_d and J_A of full rank the equilibrium x_e = x_d is asymptotically stable
    (Lyapunov function ½ q̇ᵀ B q̇ + ½ x̃ᵀ K_P x̃).

    Parameters
    ----------
    robot : the controller's model (g(q) and the kinematics).
    K_P, K_D : (m, m) gains (scalar, (m,) or matrix), positive definite.
    reference : the desired position x_d, (m,) in the ``rows`` components or (3,) (or a trajectory,
        see :func:`task_reference`).
    rows : controlled position components of the frame origin (default x, y, z).
    frame : the controlled frame (default the end effector).
    """

    def __init__(self, robot: Robot, K_P: Any, K_D: Any, reference: Any, rows: Sequence[int] = (0, 1, 2),
                 frame: str | int | None = None):
        self.robot, self.n = robot, robot.nv
        self.task = _PositionTask(robot, rows, frame)
        m = self.task.m
        self.K_P, self.K_D = as_gain(K_P, m, "K_P"), as_gain(K_D, m, "K_D")
        self.reference = as_reference(task_reference(reference, rows), m)
        self._log: dict[str, np.ndarray] = {}

    def reset(self) -> None:
        self._log = {}

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        q, qd = meas.q, meas.qd
        x_d, _, _ = self.reference(t)
        x_e = self.task.position(q)
        J = self.task.jacobian(q)
        e = x_d - x_e
        u = gravity_torques(self.robot, q) + J.T @ (self.K_P @ e - self.K_D @ (J @ qd))  # Eq. (8.110)
        self._log = {"x_d": x_d, "x_e": x_e, "e": e}
        return u

    def log(self) -> dict[str, np.ndarray]:
        return self._log


class OperationalInverseDynamics:
    """u = B(q) y + n(q, q̇), y = J_A⁻¹(q)(ẍ_d + K_D x̃̇ + K_P x̃ − J̇_A q̇) (Eqs. 8.57, 8.114, Fig. 8.30).

    With a perfect model the task error obeys x̃̈ + K_D x̃̇ + K_P x̃ = 0. J_A must be square
    (a nonredundant task: as many components as joints) and nonsingular along the motion.

    Parameters
    ----------
    robot : the controller's model (e.g. without the payload the real arm carries).
    K_P, K_D : (m, m) gains, positive definite.
    reference : trajectory in the task components (see :func:`controllers.joint_space.as_reference`).
    rows, frame : the task, as in :class:`OperationalPDGravity`; ``len(rows)`` must equal n.
    viscous_friction : F_v of the model.
    """

    def __init__(self, robot: Robot, K_P: Any, K_D: Any, reference: Any, rows: Sequence[int] = (0, 1, 2),
                 frame: str | int | None = None, viscous_friction: Any = 0.0):
        self.robot, self.n = robot, robot.nv
        self.task = _PositionTask(robot, rows, frame)
        m = self.task.m
        if m != self.n:
            raise ValueError(f"`rows` must select {self.n} components (J_A square, nonredundant task), got {m}")
        self.K_P, self.K_D = as_gain(K_P, m, "K_P"), as_gain(K_D, m, "K_D")
        self.Fv = as_friction(viscous_friction, self.n)
        self.reference = as_reference(task_reference(reference, rows), m)
        self._log: dict[str, np.ndarray] = {}

    def reset(self) -> None:
        self._log = {}

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        q, qd = meas.q, meas.qd
        x_d, xd_d, xdd_d = self.reference(t)
        x_e = self.task.position(q)
        J = self.task.jacobian(q)
        e, ed = x_d - x_e, xd_d - J @ qd
        a = xdd_d + self.K_D @ ed + self.K_P @ e - self.task.jacobian_derivative_times_qd(q, qd)
        y = _solve_task(J, a)  # Eq. (8.114)
        if y is None:
            raise _singular(f"at t = {t:.6g} s, q = {q}")
        u = inverse_dynamics(self.robot, q, qd, y) + self.Fv * qd
        self._log = {"x_d": x_d, "x_e": x_e, "e": e}
        return u

    def log(self) -> dict[str, np.ndarray]:
        return self._log


def operational_inverse_dynamics_steady_state(plant_robot: Robot, model_robot: Robot, K_P: Any, x_d: Any,
                                              q0: Any, rows: Sequence[int] = (0, 1, 2),
                                              frame: str | int | None = None) -> np.ndarray:
    """The rest posture q of operational-space inverse dynamics with a wrong model at a set point x_d.

    At rest the controller applies B̂(q) J_A⁻¹(q) K_P x̃ + ĝ(q) and the arm needs g(q), so q solves
    B̂(q) J_A⁻¹(q) K_P (x_d − x_e(q)) = g(q) − ĝ(q) (Newton iterations from ``q0``, e.g. the posture
    reached at the end of the motion).
    """
    task = _PositionTask(model_robot, rows, frame)
    n = model_robot.nv
    if task.m != n:
        raise ValueError(f"`rows` must select {n} components, got {task.m}")
    K_P = as_gain(K_P, n, "K_P")
    x_d = as_vector(x_d, n, "x_d")
    start = as_vector(q0, n, "q0")

    def residual(q: np.ndarray) -> np.ndarray:
        y = _solve_task(task.jacobian(q), K_P @ (x_d - task.position(q)))
        if y is None:
            raise _singular(f"at q = {q}")
        return inertia_matrix(model_robot, q) @ y - gravity_torques(plant_robot, q) + gravity_torques(model_robot, q)

    q, _, _, msg = fsolve(residual, start, full_output=True, xtol=1e-13)
    if np.max(np.abs(residual(q))) > 1e-8:  # judged by the residual (fsolve's ier is pessimistic at a root)
        raise ValueError(f"no steady state of the operational-space loop found near {start}: {msg}")
    return q
