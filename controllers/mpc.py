"""Model predictive control: the optimal control problem of :mod:`planners.optimal_control` solved again at every
sample from the measured state, its first torque applied (receding horizon).

At the sample t_k the controller measures x_k = [q; q̇], samples the reference at the horizon's nodes t_k + i·dt
(i = 0 … N: q_ref, q̇_ref and, with ``feedforward``, τ_ref = the inverse dynamics (7.82) of the reference, so the
effort cost weighs the departure from the computed torque of (8.57)), solves the problem warm-started from the
previous plan shifted by one interval, and applies τ_0 until the next sample (zero-order hold, like every controller
of :func:`controllers.simulation.simulate`). The torques of a plan lie within ±τ_max by construction (the hard box of
the problem), so a saturating plant applies what was planned.

Real-time options (:class:`MPCOptions`): a cap on the SQP iterations and on the wall time per sample, the
real-time iteration (one SQP step per sample, Diehl et al. 2005), and the computation delay: with ``delay`` the
torque computed at t_k is applied at t_{k+1} — the solve starts from the state predicted one sample ahead under the
torque already committed. A solve that fails (its QP fails, its plan is not finite, or the measured state is beyond a
hard state limit, where no plan can start) keeps the loop alive: the controller applies the previous plan's next
torque and logs the failure; it never outputs NaN.

Logged signals: ``q_d`` (the reference at t), ``e`` = q_d − q, ``tau_plan`` (the planned first torque), ``q_pred``
(the predicted positions over the horizon, (N+1, n) per sample), ``solve_time`` [s] (the wall time of the whole
sample: references, SQP, checks), ``cpu_time`` [s] (its processor time: what it takes on an idle core),
``linearisation_time`` and ``qp_time`` [s] (its two largest parts), ``iterations``, ``deadline_met`` (solve_time ≤ the
sampling period), ``failed``, ``converged``, ``plan_success`` (the plan's ``success``: its own checks, or with
``verify`` the independent one), ``cost`` and ``defect`` (max |x_{k+1} − Φ(x_k, τ_k)| of the plan).

What is checked at each sample: without ``verify`` (the real-time default) the plan is checked from the solver's own
quantities, all computed with the step (nothing is evaluated again): HPIPM's status (a NaN step is a failure),
finite states and torques, the torques within ±τ_max (the QP's hard box; the torque applied is clipped to it as
well), and the plan's dynamics defect by the solver's model (logged; a real-time iteration closes it over the next
samples). Pinocchio's independent check runs with ``MPCOptions(verify=True)``: every sample's defects by
Pinocchio's dynamics (about 1.5 ms per sample on the Panda, N = 50) and, when a sample's SQP has converged, the KKT
conditions (about 25 ms); :func:`~planners.optimal_control.solve_optimal_control` always runs it.

The law is an optimisation solved numerically at each sample; it has no symbolic form, so ``simulate(...,
backend="casadi")`` refuses it through the compiled loop's one generic path (a controller without ``symbolic()``)
and :func:`controllers.compiled.fast_backend` chooses the Python loop for it.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 8.5 (inverse
dynamics control), 4.2 (trajectories); Rawlings, Mayne & Diehl, *Model Predictive Control*, Nob Hill 2017;
Diehl, Bock & Schlöder, SIAM J. Control Optim. 43 (2005) (real-time iteration).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
import pinocchio as pin

from controllers.laws import as_reference
from controllers.plants import ArmMeasurement
from controllers.simulation import LoggedController
from planners.optimal_control import (OptimalControlOptions, OptimalControlProblem, OptimalControlResult,
                                      OptimalControlSolver)
from planners.stage_qp import check_qp_solver
from rigid_body.rotations import as_homogeneous, as_homogeneous_batch
from rigid_body.validation import as_positive

__all__ = ["MPCOptions", "ModelPredictiveControl"]


@dataclass(frozen=True)
class MPCOptions:
    """Real-time settings of :class:`ModelPredictiveControl`.

    max_iter : SQP iterations per sample (warm-started, a few suffice); real_time_iteration : one SQP step per
        sample whatever ``max_iter`` says.
    time_limit : wall-time cap per sample [s] (checked between SQP iterations; None: none).
    delay : model a one-sample computation delay (the torque computed at t_k is applied at t_{k+1}).
    feedforward : τ_ref of the effort cost is the inverse dynamics of the reference (else 0).
    verify : run the solver's independent KKT check at every sample (costly; off in real time).
    qp_solver : the step QPs' solver (``OptimalControlOptions.qp_solver``: "auto", "hpipm", "piqp", "proxsuite").
    """

    max_iter: int = 10
    real_time_iteration: bool = False
    time_limit: float | None = None
    delay: bool = False
    feedforward: bool = True
    verify: bool = False
    qp_solver: str = "auto"

    def __post_init__(self) -> None:
        v = self.max_iter
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)) or v < 1:
            raise ValueError(f"`max_iter` must be an integer >= 1, got {v!r}")
        if self.time_limit is not None:
            as_positive(self.time_limit, "time_limit")
        check_qp_solver(self.qp_solver)


class ModelPredictiveControl(LoggedController):
    """Receding-horizon optimal control of an arm, a controller for :func:`~controllers.simulation.simulate`.

    Parameters
    ----------
    problem : the :class:`~planners.optimal_control.OptimalControlProblem` (the controller's model, horizon N, step
        dt — the controller's sampling period —, costs and limits).
    reference : the joint reference: a set point (n,), a :class:`~planners.timing.Trajectory` or ``t -> (q, q̇, q̈)``;
        default: hold the first measured posture.
    target : the end-effector pose T_d (4, 4) or ``t -> T_d`` for the pose terms of the costs.
    options : :class:`MPCOptions`.

    The controller runs every dt: called at a faster loop rate it holds its torque in between (``periods()`` tells
    :func:`simulate` its period, which must be a multiple of the loop's).

    >>> import numpy as np
    >>> from rigid_body.robots import load
    >>> from controllers.plants import ArmPlant
    >>> from controllers.simulation import simulate
    >>> from planners.optimal_control import OptimalControlProblem, StageCost
    >>> arm = load("planar_2r")
    >>> problem = OptimalControlProblem(arm, horizon=10, dt=0.02, running=StageCost(q=1e3, qd=1.0, tau=1e-6),
    ...                                 terminal=StageCost(q=1e4, qd=1e2), tau_max=[3000.0, 1500.0])
    >>> mpc = ModelPredictiveControl(problem, reference=[0.3, -0.2])
    >>> res = simulate(ArmPlant(arm, tau_max=problem.tau_max), mpc, (0.0, 0.4), np.zeros(4), h=1e-3, Ts=0.02)
    >>> bool(np.abs(res.q[-1] - [0.3, -0.2]).max() < 1e-2), int(res["failed"].sum())
    (True, 0)
    """

    compilable = False                       # an optimisation per sample: no symbolic form (Python loop only)

    def __init__(self, problem: OptimalControlProblem, reference: Any = None, target: Any = None,
                 options: MPCOptions | None = None):
        if not isinstance(problem, OptimalControlProblem):
            raise ValueError(f"`problem` must be an OptimalControlProblem, got {type(problem).__name__}")
        self.problem = problem
        self.options = options or MPCOptions()
        if not isinstance(self.options, MPCOptions):
            raise ValueError(f"`options` must be MPCOptions, got {type(self.options).__name__}")
        self.robot, self.n, self.N, self.dt = problem.robot, problem.n, problem.horizon, problem.dt
        self.reference = None if reference is None else as_reference(reference, self.n)
        self._target_fixed: np.ndarray | None = None
        if target is None:
            if any(problem.pose_terms):
                raise ValueError("`target` is required: the problem has an end-effector pose cost")
            self._target: Callable[[float], np.ndarray] | None = None
        elif callable(target):
            self._target = target
            as_homogeneous(target(0.0), "target")
        else:
            T = as_homogeneous(target, "target").copy()
            self._target = lambda t: T
            self._target_fixed = T                                   # one pose: checked once, not per sample
        self._constant_reference = reference is None or not (callable(reference) or hasattr(reference, "evaluate"))
        o = self.options
        self.solver = OptimalControlSolver(problem, OptimalControlOptions(
            max_iter=1 if o.real_time_iteration else o.max_iter, verify=o.verify,
            time_limit=math.inf if o.time_limit is None else o.time_limit, qp_solver=o.qp_solver))
        self._data = self.robot.model.createData()
        self.reset()

    def periods(self) -> tuple[float, ...]:
        """The controller's sampling period dt (``simulate`` checks that its loop period divides it)."""
        return (self.dt,)

    def reset(self) -> None:
        super().reset()
        self._plan: OptimalControlResult | None = None
        self._plan_age = 0                   # samples since the plan was made
        self._next: float | None = None
        self._u: np.ndarray | None = None
        self._pending: np.ndarray | None = None   # with delay: the torque committed for the current sample
        self._hold: dict[str, Any] = {}
        self._q0: np.ndarray | None = None
        self._references: dict[str, np.ndarray] | None = None    # a set point's, computed once
        self.failures = 0
        self.samples = 0
        self.missed_deadlines = 0

    # ---- references along the horizon -------------------------------------------------------------------------
    def horizon_reference(self, t: float) -> dict[str, np.ndarray]:
        """q_ref, qd_ref (N+1, n), tau_ref (N, n) and T_d at the nodes t + i·dt of the horizon from ``t``."""
        n, N = self.n, self.N
        if self._references is not None:
            return self._references
        times = t + self.dt * np.arange(N + 1)
        if self.reference is None:
            q = np.tile(self._q0, (N + 1, 1))
            qd = qdd = np.zeros((N + 1, n))
        else:
            at_times = getattr(self.reference, "at_times", None)
            if at_times is not None:
                q, qd, qdd = at_times(times)
            else:
                q, qd, qdd = (np.array(v) for v in zip(*(self.reference(float(s)) for s in times)))
        out = {"q_ref": q, "qd_ref": qd}
        if self.options.feedforward:
            model, data = self.robot.model, self._data
            out["tau_ref"] = np.array([pin.rnea(model, data, q[i], qd[i], qdd[i]) for i in range(N)])
        if self._target_fixed is not None:
            out["T_d"] = self._target_fixed
        elif self._target is not None:
            out["T_d"] = as_homogeneous_batch(np.array([self._target(float(s)) for s in times]), "target")
        if self._constant_reference and (self._target is None or self._target_fixed is not None):
            self._references = out                                  # a set point and one pose: every sample's
        return out

    # ---- one sample -----------------------------------------------------------------------------------------
    def __call__(self, t: float, meas: ArmMeasurement) -> np.ndarray:
        if self._next is not None and t < self._next - 1e-9 * self.dt:
            self.record(**self._hold)
            return self._u                                          # held between the controller's samples
        start, start_cpu = time.perf_counter(), time.process_time()
        self._next = t + self.dt if self._next is None else self._next + self.dt
        q, qd = np.asarray(meas.q, dtype=float), np.asarray(meas.qd, dtype=float)
        if self._q0 is None:
            self._q0 = q.copy()
        x = np.concatenate([q, qd])
        t_plan = t
        if self.options.delay:                                      # plan from where the committed torque leads
            if self._pending is None:
                self._pending = self._fallback(x)
            x = self._predict(x, self._pending)
            t_plan = t + self.dt
        refs = self.horizon_reference(t_plan)
        warm = None
        if self._plan is not None:
            warm = self._plan.shifted(min(self._plan_age + 1, self.N))
        self.samples += 1
        try:
            if self.problem.state_limits == "hard" and self.solver.violated(x).size:
                raise ArithmeticError("the state is beyond a hard limit: no plan can start there")
            plan = self.solver.solve(x, warm_start=warm, **refs)
            failed = plan.status == "qp failure" or not (np.all(np.isfinite(plan.u)) and np.all(np.isfinite(plan.x)))
        except (ArithmeticError, RuntimeError):                        # a solver fault never stops the loop
            plan, failed = None, True
        if failed:
            self.failures += 1
            tau = self._fallback(x)
            self._plan_age += 1
        else:
            self._plan, self._plan_age = plan, 0
            tau = np.clip(plan.u[0], -self.problem.tau_max, self.problem.tau_max)
        solve_time = time.perf_counter() - start                    # the whole sample: references, SQP, checks
        cpu_time = time.process_time() - start_cpu
        deadline = bool(plan is not None and solve_time <= self.dt)
        self.missed_deadlines += not deadline
        if self.options.delay:
            u, self._pending = self._pending, tau
        else:
            u = tau
        self._u = u
        q_ref = refs["q_ref"][0] if not self.options.delay else self._reference_at(t)
        timings = plan.timings if plan is not None else {}
        shown = plan if plan is not None and not failed else self._plan
        self._hold = dict(q_d=q_ref, e=q_ref - q, tau_plan=tau,
                          q_pred=(shown.x[:, :self.n] if shown is not None else np.tile(q, (self.N + 1, 1))),
                          solve_time=float(solve_time), iterations=float(plan.iterations if plan is not None else 0),
                          deadline_met=float(deadline), failed=float(failed),
                          converged=float(plan is not None and plan.status == "converged"),
                          plan_success=float(plan is not None and not failed and plan.success),
                          cost=float(plan.cost if plan is not None and not failed else math.nan),
                          defect=float(plan.defect if plan is not None and not failed else math.nan),
                          cpu_time=float(cpu_time), linearisation_time=float(timings.get("linearisation", math.nan)),
                          qp_time=float(timings.get("qp", math.nan)))
        self.record(**self._hold)
        return u

    def _reference_at(self, t: float) -> np.ndarray:
        return self._q0 if self.reference is None else self.reference(t)[0]

    def _predict(self, x: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """The state one interval dt ahead under the held torque τ, by the controller's model."""
        return self.solver.predict(x, tau)

    def _fallback(self, x: np.ndarray) -> np.ndarray:
        """The torque when a solve fails: the previous plan's next torque (its plan shifted by the samples since),
        or the gravity torque at the measured posture when there is no plan yet."""
        if self._plan is not None:
            k = min(self._plan_age + 1, self.N - 1)
            return self._plan.u[k].copy()
        return np.clip(pin.computeGeneralizedGravity(self.robot.model, self._data, x[:self.n]),
                       -self.problem.tau_max, self.problem.tau_max)

    def diagnose(self, plant: Any, Ts: float, meas: Any) -> str:
        """Why the loop may have diverged (appended by :func:`simulate` to its error): names the MPC and its record."""
        return (f"ModelPredictiveControl (N = {self.N}, dt = {self.dt:g} s): {self.failures} failed solves and "
                f"{self.missed_deadlines} missed deadlines in {self.samples} samples; the prediction model "
                f"{self.robot.name!r} may differ too much from the plant")
