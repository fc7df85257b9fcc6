"""Chapter 6: the task and action levels of the hierarchical control architecture, made executable.

The task level decomposes a job into actions (6.1) and the action level plans their paths (6.2):
that is planning, in :mod:`planners.tasks`. Here the primitive level runs them on the arm (the
simulation loop of :mod:`controllers.simulation`):

* :class:`ActionExecutor` — the primitives MOVETO(location, velocity), GRASP, RELEASE and
  NEW_OBJECT of the PASCAL program of 6.4, executed on a simulated arm: MOVETO solves the closed-form
  inverse kinematics, plans a joint-space quintic and tracks it with inverse-dynamics control;
  GRASP/RELEASE act on a :class:`Workcell` (the modelling module's knowledge of where the objects
  are). :func:`fill_pallet_program` is the program FILL_PALLET of 6.4. A primitive asked to do the
  impossible (unreachable location, grasp with nothing there, release with nothing held) stops the
  program with a :class:`TaskError` naming the step.
The peg-in-hole flow chart of 6.3 is a force controller: :class:`controllers.force.PegInHoleController`
(the arm in contact is :class:`controllers.plants.ArmInContact`, the surface
:class:`controllers.environment.SurfaceWithHole`).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Ch. 6
(Sects. 6.1–6.6, Fig. 6.1), Sect. 4.4 (via points), Sects. 8.5.2, 9.x (force/position control);
solution manual, Problems 6.1–6.4.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from controllers.joint_space import InverseDynamicsControl
from controllers.plants import ArmPlant
from controllers.simulation import sample_times, simulate
from planners.timing import quintic_law
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import Robot, revolute_joints, with_payload
from rigid_body.rotations import wrap_angle
from rigid_body.task_space import joint_reference
from rigid_body.validation import as_vector


class TaskError(RuntimeError):
    """A primitive could not be executed; ``step`` is its index in the program and ``text`` the step."""

    def __init__(self, step: int, text: str, reason: str):
        super().__init__(f"step {step} {text}: {reason}")
        self.step, self.text, self.reason = step, text, reason


# --------------------------------------------------------------------------------------------
# 6.4: programs of primitives and their execution on the simulated arm
# --------------------------------------------------------------------------------------------

PRIMITIVES = ("MOVETO", "GRASP", "RELEASE", "NEW_OBJECT")


@dataclass(frozen=True)
class Step:
    """One primitive of a robot program: MOVETO(location, velocity), GRASP, RELEASE, NEW_OBJECT."""

    primitive: str
    location: tuple[float, ...] | None = None
    velocity: float | None = None

    def __post_init__(self) -> None:
        if self.primitive not in PRIMITIVES:
            raise ValueError(f"`primitive` must be one of {PRIMITIVES}, got {self.primitive!r}")
        if (self.primitive == "MOVETO") != (self.location is not None and self.velocity is not None):
            raise ValueError("MOVETO (and only MOVETO) needs a location and a velocity")

    def __str__(self) -> str:
        if self.primitive != "MOVETO":
            return self.primitive
        loc = ", ".join(f"{v:.4g}" for v in self.location)
        return f"MOVETO([{loc}], {self.velocity:g})"


def moveto(location: Any, velocity: float) -> Step:
    """A MOVETO step (location = [x, y, z, φ] for the SCARA, velocity [m/s])."""
    velocity = float(velocity)
    if not (np.isfinite(velocity) and velocity > 0):
        raise ValueError(f"`velocity` must be positive, got {velocity}")
    return Step("MOVETO", tuple(float(v) for v in as_vector(location, None, "location")), velocity)


def fill_pallet_program(home: Any, object_location: Any, pallet: Any, lift: float, length: float, width: float,
                        fast: float, slow: float, rows: int = 4, columns: int = 4,
                        up: Any = (0.0, 0.0, 1.0)) -> list[Step]:
    """The program FILL_PALLET of 6.4 (the manual's PASCAL listing, its garbled block structure repaired).

    Locations are [x, y, z, φ] (position and rotation about the vertical). ``up`` is the unit vector
    "above" in the base frame — (0, 0, −1) for the SCARA of Table S2.3, whose z₀ points down. For
    each of ``rows × columns`` objects: NEW_OBJECT; MOVETO(object + lift, fast); MOVETO(object, slow);
    GRASP; MOVETO(object + lift, slow); MOVETO(pallet + [i·length, j·width] + lift, fast);
    MOVETO(down by lift, slow); RELEASE; MOVETO(up by lift, slow). It starts and ends at home.
    """
    home, obj, pal = (as_vector(v, 4, n) for v, n in ((home, "home"), (object_location, "object_location"),
                                                      (pallet, "pallet")))
    up = np.append(as_vector(up, 3, "up"), 0.0)
    raise_ = float(lift) * up
    steps = [moveto(home, fast)]
    for i in range(rows):
        for j in range(columns):
            above_object = obj + raise_
            slot = pal + np.array([i * length, j * width, 0.0, 0.0])
            steps += [Step("NEW_OBJECT"), moveto(above_object, fast), moveto(obj, slow), Step("GRASP"),
                      moveto(above_object, slow), moveto(slot + raise_, fast), moveto(slot, slow),
                      Step("RELEASE"), moveto(slot + raise_, slow)]
    steps.append(moveto(home, fast))
    return steps


@dataclass
class WorkObject:
    """An object of the work cell: its name, position (3,) in the base frame, mass [kg]."""

    name: str
    position: np.ndarray
    mass: float = 0.0


class Workcell:
    """What the modelling module knows of the environment: the objects, the conveyor's feed point.

    NEW_OBJECT makes the conveyor deliver an object at ``feed`` (the robot commands the feed, so an
    object is there afterwards); GRASP takes the object within ``grasp_tolerance`` of the gripper.
    """

    def __init__(self, feed: Any, object_mass: float = 0.0, grasp_tolerance: float = 2e-3):
        self.feed = as_vector(feed, 3, "feed").copy()
        self.object_mass = float(object_mass)
        self.grasp_tolerance = float(grasp_tolerance)
        self.objects: list[WorkObject] = []
        self.held: WorkObject | None = None

    def new_object(self) -> WorkObject:
        if self.object_at(self.feed) is not None:
            raise ValueError("the conveyor's feed point is still occupied")
        obj = WorkObject(f"object {len(self.objects) + 1}", self.feed.copy(), self.object_mass)
        self.objects.append(obj)
        return obj

    def object_at(self, p: np.ndarray) -> WorkObject | None:
        free = [o for o in self.objects if o is not self.held]
        if not free:
            return None
        d = [np.linalg.norm(o.position - p) for o in free]
        k = int(np.argmin(d))
        return free[k] if d[k] <= self.grasp_tolerance else None


@dataclass(frozen=True)
class ExecutionOptions:
    """Options of the primitive level: sampling ``Ts`` and integration step ``h`` [s], inverse-dynamics
    gains ``K_P`` [1/s²], ``K_D`` [1/s], shortest motion ``min_duration`` [s], and the tolerance on the
    reached position ``position_tolerance`` [m]."""

    Ts: float = 2e-3
    h: float = 2e-3
    K_P: float = 400.0
    K_D: float = 40.0
    min_duration: float = 0.25
    position_tolerance: float = 1e-3


@dataclass(frozen=True)
class ExecutionRecord:
    """What a program did: executed ``steps`` as (index, text, t_start, t_end), the time histories
    ``t`` (N,), ``q`` (N, n), end-effector positions ``p`` (N, 3), the step index running at each
    sample ``step_of_sample`` (N,), and the objects at the end (name → position)."""

    steps: list[tuple[int, str, float, float]]
    t: np.ndarray
    q: np.ndarray
    p: np.ndarray
    step_of_sample: np.ndarray
    objects: dict[str, np.ndarray]


class ActionExecutor:
    """Runs programs of MOVETO / GRASP / RELEASE / NEW_OBJECT on a simulated arm.

    Parameters
    ----------
    robot : the arm (its dynamics is the plant; the same model is used by the controller).
    inverse_kinematics : ``location -> (k, n)`` closed-form solutions (e.g.
        :func:`rigid_body.kinematics.inverse_kinematics_scara`); raises ValueError when unreachable.
    workcell : the :class:`Workcell`.
    q0 : initial configuration (n,).
    options : :class:`ExecutionOptions`.
    viscous_friction : F_v of the arm (plant and model).
    """

    def __init__(self, robot: Robot, inverse_kinematics: Callable[[np.ndarray], np.ndarray],
                 workcell: Workcell | None, q0: Any, options: ExecutionOptions = ExecutionOptions(),
                 viscous_friction: Any = 0.0):
        workcell = Workcell(np.zeros(3)) if workcell is None else workcell
        self.robot, self.ik, self.workcell, self.options = robot, inverse_kinematics, workcell, options
        self.Fv = viscous_friction
        self._loaded = with_payload(robot, workcell.object_mass) if workcell.object_mass > 0 else robot
        self._revolute = revolute_joints(robot)
        self.x = np.concatenate([as_vector(q0, robot.nq, "q0"), np.zeros(robot.nv)])
        self.t = 0.0
        self._segments: list[tuple[int, Any]] = []
        self._steps: list[tuple[int, str, float, float]] = []

    # -- the primitives --------------------------------------------------------------------
    def _model(self) -> Robot:
        return self._loaded if self.workcell.held is not None else self.robot

    def ee_position(self, q: np.ndarray | None = None) -> np.ndarray:
        return direct_kinematics(self.robot, self.x[:self.robot.nq] if q is None else q)[:3, 3]

    def _closest_solution(self, location: np.ndarray) -> np.ndarray:
        q = self.x[:self.robot.nq]
        lo, hi = self.robot.lower, self.robot.upper
        best, best_d = None, np.inf
        revolute = self._revolute
        for sol in np.atleast_2d(self.ik(location)):
            cand = sol.copy()
            # the 2π-equivalent of each revolute joint closest to the current value
            cand[revolute] = q[revolute] + wrap_angle(sol[revolute] - q[revolute])
            for k in np.nonzero(revolute)[0]:
                for shift in (0.0, -2 * np.pi, 2 * np.pi):
                    if lo[k] - 1e-9 <= cand[k] + shift <= hi[k] + 1e-9:
                        cand[k] += shift
                        break
            if np.any(cand < lo - 1e-9) or np.any(cand > hi + 1e-9):
                continue
            d = float(np.linalg.norm(cand - q))
            if d < best_d:
                best, best_d = cand, d
        if best is None:
            raise ValueError("no inverse-kinematics solution within the joint limits")
        return best

    def moveto(self, location: Any, velocity: float, step: int = -1) -> None:
        """Plan (IK + joint quintic of duration distance/velocity) and execute on the simulated arm."""
        opts = self.options
        location = as_vector(location, None, "location")
        q_f = self._closest_solution(location)
        q_i = self.x[:self.robot.nq].copy()
        distance = float(np.linalg.norm(self.ee_position(q_f) - self.ee_position(q_i)))
        T = max(distance / velocity, opts.min_duration)
        T = opts.Ts * np.ceil(T / opts.Ts - 1e-9)
        law = quintic_law(q_i, q_f, self.t + T, t_i=self.t)
        model = self._model()
        controller = InverseDynamicsControl(model, opts.K_P, opts.K_D, law, viscous_friction=self.Fv)
        plant = ArmPlant(model, viscous_friction=self.Fv)
        res = simulate(plant, controller, (self.t, self.t + T), self.x, h=opts.h, Ts=opts.Ts)
        self._segments.append((step, res))
        self.x, self.t = res.x[-1].copy(), float(res.t[-1])
        reached = self.ee_position()
        target = self.ee_position(q_f)
        err = float(np.linalg.norm(reached - target))
        if err > opts.position_tolerance:
            raise ValueError(f"location not reached: end-effector error {err:.3g} m > {opts.position_tolerance:g} m")
        if self.workcell.held is not None:
            self.workcell.held.position = reached.copy()

    def follow(self, law: Any, position_rows: Sequence[int], orientation: Sequence[float],
               jacobian_rows: Sequence[int], step: int = -1) -> None:
        """Track an operational-space motion ``law(t) -> (p, ṗ, p̈)`` (p (3,), absolute times from now on)
        with constant end-effector orientation: joint reference by :func:`joint_reference`, then
        inverse-dynamics control on the simulated arm until ``law.t_f``."""
        opts = self.options
        if law.t_i < self.t - 1e-12:
            raise ValueError(f"the motion starts at t = {law.t_i} s, before the executor's time {self.t} s")
        t_f = self.t + opts.Ts * np.ceil((law.t_f - self.t) / opts.Ts - 1e-9)
        samples = sample_times(self.t, t_f, opts.Ts)
        reference = joint_reference(self.robot, self.ik, law, position_rows, orientation, jacobian_rows,
                                    self.x[:self.robot.nq], times=samples)   # open loop: computed before the loop
        model = self._model()
        controller = InverseDynamicsControl(model, opts.K_P, opts.K_D, reference, viscous_friction=self.Fv)
        res = simulate(ArmPlant(model, viscous_friction=self.Fv), controller, (self.t, t_f), self.x, h=opts.h, Ts=opts.Ts)
        self._segments.append((step, res))
        self.x, self.t = res.x[-1].copy(), float(res.t[-1])

    def grasp(self) -> None:
        if self.workcell.held is not None:
            raise ValueError(f"the gripper already holds {self.workcell.held.name}")
        obj = self.workcell.object_at(self.ee_position())
        if obj is None:
            raise ValueError(f"nothing to grasp within {self.workcell.grasp_tolerance:g} m of the gripper at "
                             f"{np.round(self.ee_position(), 4).tolist()}")
        self.workcell.held = obj

    def release(self) -> None:
        if self.workcell.held is None:
            raise ValueError("nothing to release: the gripper is empty")
        self.workcell.held.position = self.ee_position().copy()
        self.workcell.held = None

    # -- programs ----------------------------------------------------------------------------
    def run(self, program: Sequence[Step]) -> ExecutionRecord:
        """Execute the steps in order; the first impossible one raises :class:`TaskError` naming it."""
        for k, step in enumerate(program):
            t0 = self.t
            try:
                if step.primitive == "MOVETO":
                    self.moveto(step.location, step.velocity, k)
                elif step.primitive == "GRASP":
                    self.grasp()
                elif step.primitive == "RELEASE":
                    self.release()
                else:
                    self.workcell.new_object()
            except ValueError as err:
                raise TaskError(k, str(step), str(err)) from None
            self._steps.append((k, str(step), t0, self.t))
        return self.record()

    def record(self) -> ExecutionRecord:
        """The history so far (samples of every executed MOVETO, joined)."""
        n = self.robot.nq
        if self._segments:
            t = np.concatenate([r.t for _, r in self._segments])
            q = np.concatenate([r.x[:, :n] for _, r in self._segments])
            idx = np.concatenate([np.full(len(r.t), k) for k, r in self._segments])
        else:
            t, q, idx = np.array([self.t]), self.x[None, :n], np.array([-1])
        p = np.array([direct_kinematics(self.robot, qk)[:3, 3] for qk in q])
        return ExecutionRecord(list(self._steps), t, q, p, idx,
                               {o.name: o.position.copy() for o in self.workcell.objects})


