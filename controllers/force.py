"""Force control: tasks where the end effector touches the environment (Ch. 9; Problem 6.3).

* :class:`PegInHoleController` — the hybrid force/position law of the peg-in-hole task of 6.3 (flow
  chart of Fig. S6.2 as a state machine): τ = g(q) + Jᵀ (K_P S (x_d − x) + K_D (ẋ_d − ẋ) + f_d), with S
  selecting the position-controlled directions and f_d the commanded force along the others.
* :class:`PegInHoleTask` — the data of 6.3; :func:`run_peg_in_hole` runs it on an
  :class:`~controllers.plants.ArmInContact` against a :class:`~controllers.environment.SurfaceWithHole`.

The controllers read the sensed wrench ``meas.wrench`` (h_e, exerted by the end effector on the
environment, Sect. 9.1) of the :class:`~controllers.plants.ArmMeasurement`.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 6.3,
8.5.2, 9.1–9.7; solution manual, Problem 6.3.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from controllers.environment import SurfaceWithHole
from controllers.plants import ArmInContact, ArmMeasurement, frame_jacobian_and_pose
from controllers.simulation import LoggedController, SimulationResult, simulate
from planners.timing import quintic_law
from rigid_body.dynamics import gravity_torques
from rigid_body.robots import Robot
from rigid_body.rotations import wrap_angle
from rigid_body.validation import as_vector


PEG_STATES = ("approach", "descend", "search", "insert", "done")


class PegInHoleController(LoggedController):
    """The flow chart of Fig. S6.2 as a state machine driving a planar arm (x, y, φ task).

    States: ``approach`` (fast pure motion to (x_H, Δy)), ``descend`` (slow motion along −y until
    y < −Δy, or a contact force |f_y| > ε), ``search`` (force/position: x position-controlled, sliding
    at ``v_search`` and inverting when |x − x_H| > Δx; y force-controlled to −f_push; until |f_y| < ε),
    ``insert`` (force/position: y position-controlled down to −insert_depth, x force-controlled to 0,
    the peg orientation held), ``done``.

    The control law is a task-space PD with gravity compensation and a force command,
    ``τ = g(q) + J^T (K_P S (x_d − x) + K_D (ẋ_d − ẋ) + f_d)`` with J the (x, y, ω_z) rows of the
    geometric Jacobian and S selecting the position-controlled directions.
    """

    def __init__(self, robot: Robot, task: PegInHoleTask, K_P: Any = (3000.0, 3000.0, 300.0),
                 K_D: Any = (120.0, 120.0, 10.0), frame: str | int | None = None):
        self.robot, self.task, self.frame = robot, task, frame
        self._fid = robot.ee_frame if frame is None else robot.frame(frame)
        self.K_P, self.K_D = as_vector(K_P, 3, "K_P"), as_vector(K_D, 3, "K_D")
        self.n = robot.nv
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.state = "approach"
        self.transitions: list[tuple[float, str]] = [(0.0, "approach")]
        self.inversions = 0
        self._law: Any = None
        self._t0 = 0.0
        self._y0 = 0.0
        self._x_ref = 0.0
        self._direction = 1.0
        self._last_t = 0.0

    def _switch(self, t: float, state: str) -> None:
        self.state, self._t0 = state, t
        self.transitions.append((t, state))

    def __call__(self, t: float, meas: ArmMeasurement) -> np.ndarray:
        task = self.task
        q, qd, f = meas.q, meas.qd, meas.wrench[:2]       # f: force of the peg on the environment (h_e)
        J, T = frame_jacobian_and_pose(self.robot, q, self._fid)
        J = J[[0, 1, 5]]
        R, p = T.rotation, T.translation
        x = np.array([p[0], p[1], np.arctan2(R[1, 0], R[0, 0])])
        xd = J @ qd
        x_d, xd_d = x.copy(), np.zeros(3)
        select = np.ones(3)
        force = np.zeros(3)
        if self._law is None:                       # plan the fast approach from where the arm is
            self._law = quintic_law(x, np.array([task.x_H, task.dy, task.phi]), t + task.T_approach, t_i=t)
        if self.state == "approach":
            x_d, xd_d, _ = self._law(t)
            if t >= self._law.t_f and np.linalg.norm(x[:2] - x_d[:2]) < 1e-3:
                self._switch(t, "descend")
                self._y0 = x[1]
        if self.state == "descend":
            x_d = np.array([task.x_H, self._y0 - task.v_slow * (t - self._t0), task.phi])
            xd_d = np.array([0.0, -task.v_slow, 0.0])
            if abs(f[1]) > task.eps:
                self._switch(t, "search")
                self._x_ref = x[0]
            elif x[1] < -task.dy:
                self._switch(t, "insert")
                self._y0 = x[1]
        if self.state == "search":
            if abs(f[1]) < task.eps:
                self._switch(t, "insert")
                self._y0 = x[1]
            else:
                dt = t - self._last_t
                if abs(self._x_ref - task.x_H) > task.dx and np.sign(self._x_ref - task.x_H) == self._direction:
                    self._direction = -self._direction
                    self.inversions += 1
                self._x_ref += self._direction * task.v_search * dt
                x_d = np.array([self._x_ref, x[1], task.phi])
                xd_d = np.array([self._direction * task.v_search, 0.0, 0.0])
                select = np.array([1.0, 0.0, 1.0])
                force = np.array([0.0, -task.f_push, 0.0])
        if self.state == "insert":
            y_d = max(self._y0 - task.v_slow * (t - self._t0), -task.insert_depth)
            x_d = np.array([x[0], y_d, task.phi])
            xd_d = np.array([0.0, -task.v_slow if y_d > -task.insert_depth else 0.0, 0.0])
            select = np.array([0.0, 1.0, 1.0])
            if x[1] < -task.insert_depth + 1e-3:
                self._switch(t, "done")
                self._y0 = -task.insert_depth
        if self.state == "done":
            x_d = np.array([x[0], -task.insert_depth, task.phi])
            select = np.array([0.0, 1.0, 1.0])
        self._last_t = t
        e = x_d - x
        e[2] = wrap_angle(e[2])
        wrench = self.K_P * select * e + self.K_D * (xd_d - xd) + force
        self.record(x_e=x, x_d=x_d, f=f, state=PEG_STATES.index(self.state))
        return gravity_torques(self.robot, q) + J.T @ wrench


@dataclass(frozen=True)
class PegInHoleTask:
    """Data of 6.3: estimated hole abscissa ``x_H``, approach height ``dy`` (Δy), search limit ``dx``
    (Δx), force threshold ``eps`` (ε) [N], pushing force ``f_push`` [N] during the search, insertion
    depth ``insert_depth`` [m], speeds ``v_slow`` (descent, insertion) and ``v_search`` [m/s], duration
    of the fast approach ``T_approach`` [s], peg orientation ``phi`` (vertical, pointing down)."""

    x_H: float
    dy: float = 0.02
    dx: float = 0.03
    eps: float = 3.0
    f_push: float = 10.0
    insert_depth: float = 0.03
    v_slow: float = 0.02
    v_search: float = 0.02
    T_approach: float = 1.0
    phi: float = -np.pi / 2


def run_peg_in_hole(robot: Robot, environment: SurfaceWithHole, task: PegInHoleTask, q0: Any,
                    duration: float, Ts: float = 1e-3, h: float = 1e-3,
                    viscous_friction: Any = 0.0) -> tuple[SimulationResult, PegInHoleController]:
    """Simulate the peg-in-hole state machine on ``robot`` against ``environment`` from ``q0``.

    Returns the :class:`~controllers.simulation.SimulationResult` (signals ``x_e``, ``x_d``, ``f``,
    ``state``) and the controller (its ``transitions`` and ``inversions``).
    """
    plant = ArmInContact(robot, environment, viscous_friction)
    controller = PegInHoleController(robot, task)
    res = simulate(plant, controller, (0.0, duration), plant.initial_state(q0), h=h, Ts=Ts)
    return res, controller
