"""Chapter 6: the task and action levels of the hierarchical control architecture, made executable.

The task level decomposes a job into actions (6.1); the action level turns each action into motion
primitives, choosing the frames, the path/via points and the timing laws (6.2); the primitive
level plans and runs the motion on the arm (here: the simulation loop of
:mod:`controllers.simulation`). Three pieces:

* :func:`decompose_pick_and_place` and :func:`pick_and_place_path` — the action sequence of a
  pick-and-place around an obstacle and its operational-space path through the intermediate
  points C, D, E, F (Fig. S6.1), as path points (stop at D, E) or via points (overlapping
  segments), timed with the laws of :mod:`planners.timing` on a :class:`planners.paths.SegmentSequence`.
* :class:`ActionExecutor` — the primitives MOVETO(location, velocity), GRASP, RELEASE and
  NEW_OBJECT of the PASCAL program of 6.4, executed on a simulated arm: MOVETO solves the closed-form
  inverse kinematics, plans a joint-space quintic and tracks it with inverse-dynamics control;
  GRASP/RELEASE act on a :class:`Workcell` (the modelling module's knowledge of where the objects
  are). :func:`fill_pallet_program` is the program FILL_PALLET of 6.4. A primitive asked to do the
  impossible (unreachable location, grasp with nothing there, release with nothing held) stops the
  program with a :class:`TaskError` naming the step.
* :class:`PegInHoleController` — the flow chart of 6.3 (Fig. S6.2) as a state machine running as
  the controller of a planar arm with a wrist force sensor against a compliant surface with a hole
  (:class:`SurfaceWithHole`, :class:`ForceSensingArm`).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Ch. 6
(Sects. 6.1–6.6, Fig. 6.1), Sect. 4.4 (via points), Sects. 8.5.2, 9.x (force/position control);
solution manual, Problems 6.1–6.4.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np
import pinocchio as pin

from controllers.joint_space import InverseDynamicsControl
from controllers.simulation import ArmPlant, simulate
from planners.paths import SegmentSequence
from planners.timing import cubic_law, quintic_law, trapezoidal_law
from rigid_body.dynamics import gravity_torques
from rigid_body.kinematics import direct_kinematics, geometric_jacobian, jacobian_derivative_times_qd
from rigid_body.robots import Robot, revolute_joints, with_payload
from rigid_body.rotations import wrap_angle
from rigid_body.validation import as_vector


class TaskError(RuntimeError):
    """A primitive could not be executed; ``step`` is its index in the program and ``text`` the step."""

    def __init__(self, step: int, text: str, reason: str):
        super().__init__(f"step {step} {text}: {reason}")
        self.step, self.text, self.reason = step, text, reason


# --------------------------------------------------------------------------------------------
# 6.1–6.2: task decomposition and the path of a pick-and-place around an obstacle
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Action:
    """One action of the task level: its name, the points it uses and how it moves."""

    name: str
    points: tuple[str, ...]
    motion: str


@dataclass(frozen=True)
class PickAndPlacePlan:
    """Intermediate points of Fig. S6.1 and the actions that use them.

    C = grasp location (A), D = above A at a safe height, E = above B at the same height,
    F = release location (B); ``actions`` is the task-level sequence of 6.1.
    """

    points: dict[str, np.ndarray]
    actions: tuple[Action, ...]
    safe_height: float


def decompose_pick_and_place(A: Any, B: Any, obstacle: Any, clearance: float) -> PickAndPlacePlan:
    """Task decomposition of 6.1 for a planar pick-and-place from A to B over a box obstacle.

    ``A``, ``B`` are (x, y) on the work surface (y vertical up); ``obstacle`` = (x_min, x_max, top)
    of a box standing on the surface between them (``top`` its upper face); ``clearance`` is the
    safety distance. The safe height of D and E is top + clearance.
    """
    A, B = as_vector(A, 2, "A"), as_vector(B, 2, "B")
    x_min, x_max, top = as_vector(obstacle, 3, "obstacle")
    if not (x_min < x_max and clearance > 0):
        raise ValueError(f"`obstacle` must be (x_min < x_max, top) and `clearance` > 0, got {obstacle}, {clearance}")
    if not (A[0] < x_min and B[0] > x_max or B[0] < x_min and A[0] > x_max):
        raise ValueError("the obstacle must stand between A and B along x (else no avoidance is needed)")
    y_safe = top + clearance
    if min(A[1], B[1]) >= y_safe:
        raise ValueError("A and B are already above the obstacle")
    points = {"C": A, "D": np.array([A[0], y_safe]), "E": np.array([B[0], y_safe]), "F": B}
    actions = (
        Action("approach A", ("C",), "slow, vertical end-effector orientation"),
        Action("pick object", ("C",), "grasp at rest (null velocity and acceleration)"),
        Action("move object avoiding obstacle", ("C", "D", "E"), "lift to D, transfer to E above the obstacle"),
        Action("approach B", ("E", "F"), "slow descent, vertical orientation"),
        Action("place object", ("F",), "release at rest (null velocity and acceleration)"),
    )
    return PickAndPlacePlan(points, actions, y_safe)


def pick_and_place_path(plan: PickAndPlacePlan, durations: Sequence[float], via_points: bool = False,
                        overlap: float = 0.0, middle: str = "cubic", t_i: float = 0.0) -> SegmentSequence:
    """The operational-space motion C → D → E → F of 6.2 as a :class:`SegmentSequence` (z = 0).

    Path points: segments CD and EF are timed by quintics (null velocity *and* acceleration at C and
    F: "at least fourth order"), DE by a cubic (``middle="cubic"``) or a trapezoidal velocity profile
    (``"trapezoidal"``), back to back, so the arm stops at D and E. Via points: the same laws, but DE
    and EF start ``overlap`` seconds before the previous segment ends, so the path rounds D and E.
    """
    T1, T2, T3 = (float(v) for v in as_vector(durations, 3, "durations"))
    if min(T1, T2, T3) <= 0:
        raise ValueError(f"`durations` must be positive, got {durations}")
    if via_points and not 0 < overlap < min(T1, T2, T3):
        raise ValueError(f"`overlap` must be in (0, {min(T1, T2, T3)}) for via points, got {overlap}")
    shift = overlap if via_points else 0.0
    pts = np.array([np.append(plan.points[k], 0.0) for k in "CDEF"])
    L = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    t1 = t_i + T1
    t2 = t1 - shift + T2
    laws = [quintic_law(0.0, L[0], t1, t_i=t_i)]
    if middle == "cubic":
        laws.append(cubic_law(0.0, L[1], t2, t_i=t1 - shift))
    elif middle == "trapezoidal":
        laws.append(trapezoidal_law(0.0, L[1], t2, 1.5 * L[1] / T2, t_i=t1 - shift))
    else:
        raise ValueError(f"`middle` must be 'cubic' or 'trapezoidal', got {middle!r}")
    laws.append(quintic_law(0.0, L[2], t2 - shift + T3, t_i=t2 - shift))
    return SegmentSequence(pts, laws)


def distance_to_box(p: np.ndarray, obstacle: Any) -> np.ndarray:
    """Euclidean distance of planar points p (N, 2) to the box [x_min, x_max] × (−∞, top]."""
    x_min, x_max, top = as_vector(obstacle, 3, "obstacle")
    p = np.atleast_2d(p)
    dx = np.maximum(np.maximum(x_min - p[:, 0], p[:, 0] - x_max), 0.0)
    dy = np.maximum(p[:, 1] - top, 0.0)
    return np.hypot(dx, dy)


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
        reference = joint_reference(self.robot, self.ik, law, position_rows, orientation, jacobian_rows,
                                    self.x[:self.robot.nq])
        model = self._model()
        controller = InverseDynamicsControl(model, opts.K_P, opts.K_D, reference, viscous_friction=self.Fv)
        t_f = self.t + opts.Ts * np.ceil((law.t_f - self.t) / opts.Ts - 1e-9)
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


def joint_reference(robot: Robot, inverse_kinematics: Callable[[np.ndarray], np.ndarray], law: Any,
                    position_rows: Sequence[int], orientation: Sequence[float], jacobian_rows: Sequence[int],
                    q_near: Any) -> Callable[[float], tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Joint reference (q_d, q̇_d, q̈_d)(t) of an operational motion with constant orientation.

    q_d: closed-form IK of ``[p[position_rows], *orientation]``, the solution nearest to the previous
    one (starting from ``q_near``); q̇_d = J⁻¹ ẋ_d and q̈_d = J⁻¹ (ẍ_d − J̇ q̇_d) (Eqs. (3.50), (3.99)
    inverted), with J the ``jacobian_rows`` of the geometric Jacobian — square for a non-redundant task
    (e.g. x, y, ω_z of a planar three-link arm).
    """
    rows = list(position_rows)
    jrows = list(jacobian_rows)
    phi = np.asarray(orientation, dtype=float)
    n_o = phi.size
    if len(jrows) != robot.nv or len(rows) + n_o != len(jrows):
        raise ValueError(f"the task must be square: {len(rows)} positions + {n_o} orientations vs "
                         f"{len(jrows)} Jacobian rows for {robot.nv} joints")
    last = [as_vector(q_near, robot.nq, "q_near").copy()]
    revolute = revolute_joints(robot)

    def nearest(q: np.ndarray) -> np.ndarray:
        """The 2π-equivalent of q (revolute joints only) closest to the previous reference."""
        d = q - last[0]
        d[..., revolute] = wrap_angle(d[..., revolute])
        return last[0] + d

    def reference(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        p, pd, pdd = (np.asarray(v, dtype=float) for v in law(t))
        sols = nearest(np.atleast_2d(inverse_kinematics(np.concatenate([p[rows], phi]))))
        q = sols[np.argmin(np.linalg.norm(sols - last[0], axis=1))]
        last[0] = q
        J = geometric_jacobian(robot, q)[jrows]
        qd = np.linalg.solve(J, np.concatenate([pd[rows], np.zeros(n_o)]))
        Jd_qd = jacobian_derivative_times_qd(robot, q, qd)[jrows]
        qdd = np.linalg.solve(J, np.concatenate([pdd[rows], np.zeros(n_o)]) - Jd_qd)
        return q, qd, qdd

    return reference


# --------------------------------------------------------------------------------------------
# 6.3: peg-in-hole with a wrist force sensor
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class SurfaceWithHole:
    """A compliant horizontal surface y ≤ 0 with a hole (penalty contact, frictionless).

    The hole is centred at ``x_hole`` with half-width ``clearance`` (hole radius minus peg radius:
    the peg tip is a point), ``depth`` deep. The material reacts with stiffness ``stiffness`` [N/m]
    and damping ``damping`` [N·s/m] along the normal of the nearest face (top surface, hole walls,
    hole bottom); it only pushes.
    """

    x_hole: float
    clearance: float
    depth: float
    stiffness: float = 2e4
    damping: float = 50.0

    def force(self, p: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Force (f_x, f_y) exerted by the environment on the peg tip at position p, velocity v."""
        x, y = p
        if y >= 0.0:
            return np.zeros(2)
        offset = x - self.x_hole
        into_wall = abs(offset) - self.clearance
        if into_wall <= 0.0:                                        # inside the hole opening
            pen = -self.depth - y
            if pen <= 0.0:
                return np.zeros(2)
            return np.array([0.0, max(self.stiffness * pen - self.damping * v[1], 0.0)])
        if -y <= into_wall:                                         # on the top surface
            return np.array([0.0, max(self.stiffness * (-y) - self.damping * v[1], 0.0)])
        sign = np.sign(offset)                                      # against a hole wall
        return np.array([-sign * max(self.stiffness * into_wall + self.damping * v[0] * sign, 0.0), 0.0])


class ForceSensingArm:
    """A planar arm in contact with an environment, with a wrist force sensor.

    The plant is :class:`~controllers.simulation.ArmPlant` with the contact force on the tip frame
    ``frame``; ``measure(t, x)`` returns ``[q, q̇, f_x, f_y]`` where f is the force exerted by the end
    effector on the environment (the sensor's reading, Sect. 9.1 convention: h_e).
    """

    def __init__(self, robot: Robot, environment: SurfaceWithHole, viscous_friction: Any = 0.0,
                 frame: str | int | None = None):
        self.robot, self.env, self.frame = robot, environment, frame
        self._fid = robot.ee_frame if frame is None else robot.frame(frame)
        self.arm = ArmPlant(robot, viscous_friction=viscous_friction, external_force=self._joint_torques)

    def contact_force(self, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(force of the environment on the tip (2,), J_P rows x, y (2, n))."""
        J, T = _jacobian_and_pose(self.robot, q, self._fid)
        J = J[:2]
        return self.env.force(T.translation[:2], J @ qd), J

    def _joint_torques(self, t: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        f, J = self.contact_force(q, qd)
        return -J.T @ f                       # J^T h_e with h_e = −f (force of the tip on the environment)

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return self.arm.derivative(t, x, u)

    def measure(self, t: float, x: np.ndarray) -> np.ndarray:
        n = self.robot.nv
        f, _ = self.contact_force(x[:n], x[n:])
        return np.concatenate([x, -f])


def _jacobian_and_pose(robot: Robot, q: np.ndarray, fid: int) -> tuple[np.ndarray, Any]:
    """(geometric Jacobian (6, n), pose pin.SE3) of frame ``fid`` in one Pinocchio pass (hot loops: q is
    trusted, no validation)."""
    J = pin.computeFrameJacobian(robot.model, robot.data, q, fid, pin.LOCAL_WORLD_ALIGNED)
    return J, robot.data.oMf[fid].copy()


PEG_STATES = ("approach", "descend", "search", "insert", "done")


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


class PegInHoleController:
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
        self.state = "approach"
        self.transitions: list[tuple[float, str]] = [(0.0, "approach")]
        self.inversions = 0
        self._law: Any = None
        self._t0 = 0.0
        self._y0 = 0.0
        self._x_ref = 0.0
        self._direction = 1.0
        self._last_t = 0.0
        self._log: dict[str, Any] = {}

    def _switch(self, t: float, state: str) -> None:
        self.state, self._t0 = state, t
        self.transitions.append((t, state))

    def __call__(self, t: float, meas: np.ndarray) -> np.ndarray:
        n, task = self.n, self.task
        q, qd, f = meas[:n], meas[n:2 * n], meas[2 * n:2 * n + 2]
        J, T = _jacobian_and_pose(self.robot, q, self._fid)
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
        self._log = {"x_e": x, "x_d": x_d, "f": f, "state": PEG_STATES.index(self.state)}
        return gravity_torques(self.robot, q) + J.T @ wrench

    def log(self) -> dict[str, Any]:
        return self._log


def run_peg_in_hole(robot: Robot, environment: SurfaceWithHole, task: PegInHoleTask, q0: Any,
                    duration: float, Ts: float = 1e-3, h: float = 1e-3,
                    viscous_friction: Any = 0.0) -> tuple[Any, PegInHoleController]:
    """Simulate the peg-in-hole state machine on ``robot`` against ``environment`` from ``q0``.

    Returns the :class:`~controllers.simulation.SimulationResult` (signals ``x_e``, ``x_d``, ``f``,
    ``state``) and the controller (its ``transitions`` and ``inversions``).
    """
    plant = ForceSensingArm(robot, environment, viscous_friction)
    controller = PegInHoleController(robot, task)
    x0 = np.concatenate([as_vector(q0, robot.nq, "q0"), np.zeros(robot.nv)])
    res = simulate(plant, controller, (0.0, duration), x0, h=h, Ts=Ts)
    return res, controller
