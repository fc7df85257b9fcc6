"""Optimal control of a robot arm by multiple shooting (beyond the book: Chapter 4's planning and Chapter 8's
control in one problem).

The problem (horizon N intervals of length dt, state x = [q; q̇], torque τ held constant on each interval)::

    min  Σ_k ∫_{t_k}^{t_k+dt} ℓ(x(t), τ_k) dt + ℓ_N(x_N)
    s.t. x_{k+1} = Φ(x_k, τ_k)        (one RK4 step of q̈ = B(q)⁻¹ (τ − C(q, q̇) q̇ − g(q)), Eq. (7.42))
         x_0 = the measured state,    |τ_k| ≤ τ_max (hard),
         q_min ≤ q_k ≤ q_max, |q̇_k| ≤ q̇_max  (hard, or soft: violations cost slack_weight · Σ |excess|, an L1 penalty)

with ℓ = ½ Σ w_q (q − q_ref)² + ½ Σ w_q̇ (q̇ − q̇_ref)² + ½ Σ w_τ (τ − τ_ref)² + ½ w_p ‖p(q) − p_d‖² + ½ w_o ‖ϑ r‖², ϑ r the
rotation vector of R_dᵀ R(q) (the angle–axis error of Sect. 3.7.3 as a vector of length ϑ). The integral is taken by
the same RK4 stages that integrate the state (cost at the four stage states, weights 1, 2, 2, 1 over 6), and Φ is
the project's symbolic dynamics (:func:`rigid_body.symbolic.forward_dynamics_expression`, rotors included).

Solver: a Gauss–Newton SQP. Each iteration linearises every interval at once — Φ, its Jacobians A_k = ∂Φ/∂x,
B_k = ∂Φ/∂τ and the cost residuals with their Jacobians, one CasADi function generated as C (for the host's
instruction set), compiled once per model content and cached. The Jacobians follow the RK4 stages by the chain rule,
with the dynamics' partials ∂q̈/∂[q, q̇] = −B⁻¹ ∂RNEA/∂[q, q̇], ∂q̈/∂τ = B⁻¹ (one Cholesky factor of B; a third of the
operations of differentiating the whole step automatically). The quadratic program of the step goes to HPIPM (a
Riccati-recursion interior point method that works stage by stage: its cost grows like N, not N³), called directly
through its C interface on arrays filled in place, soft limits as its native L1 slacks, warm-started from the
previous QP's solution (:mod:`planners.stage_qp`: CasADi's libhpipm is checked before first use — found, its
interface, a test QP in a separate process compared with proxsuite's solution — and when it fails the QPs go to
a sparse solver (PIQP through CasADi) with one warning naming why). A state limit enters the QP only near the iterate (within ``SCREEN_FRACTION`` of its range);
a step that crosses one left out is solved again with it, so the step is always the full QP's. Soft limits that the
iterate satisfies are tried as hard bounds first (half the interior point iterations): that step is the soft QP's
when no multiplier exceeds the slack price, else the soft QP is solved. Then an Armijo line search on the L1 merit
function, whose values at the point taken are those of the result. Measured on the Panda reach (N = 50): a dense or
general sparse QP per iteration (proxsuite's sparse backend, OSQP, qrqp) took 10–20 times HPIPM's time, CasADi's
FATROP with an expanded NLP minutes, IPOPT's exact Hessian of the RK4 dynamics is the costliest expression of all;
per MPC sample (one real-time iteration) the linearisation and HPIPM take about 1.5 ms each
(``benchmarks/bench_mpc.py``; ``result.timings`` splits each solve). Warm start from a previous result (shifted for
MPC), a trajectory, or the state held at rest with gravity torques.

Success is decided independently of the iterations, as the IK does: at the returned solution Pinocchio (not the
CasADi model) integrates every interval, differentiates the dynamics and the costs, and the KKT conditions —
stationarity of the Lagrangian with the solver's multipliers, primal feasibility (defects, every hard limit),
complementarity — must hold within ``tol``. Real-time loops that cannot afford that pass (``verify=False``) get
success from the solver's own quantities instead, computed with the step: convergence, finite values, every hard
limit, and the defects of the solver's model within ``tol`` (the KKT residual is then NaN).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 4.2, 7.2–7.5,
8.5 (Eq. (7.42)); Bock & Plitt, IFAC 1984 (multiple shooting); Frison & Diehl, IFAC 2020 (HPIPM);
Diehl et al., SIAM J. Control Optim. 43 (2005) (real-time iteration).
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np
import pinocchio as pin

from planners.optimization import OptimalTrajectory
from planners.stage_qp import check_qp_solver, stage_qp
from planners.timing import PiecewisePolynomial, Trajectory
from rigid_body.codegen import compile_function
from rigid_body.integration import RK4_WEIGHTS, rk4_sensitivities, rk4_stages
from rigid_body.robots import Robot
from rigid_body.rotations import as_homogeneous_batch
from rigid_body.symbolic import (forward_dynamics_derivatives_expression, forward_dynamics_expression, frame_placement,
                                 model_digest, rotation_log_expression)
from rigid_body.validation import as_positive, as_vector

__all__ = [
    "StageCost", "OptimalControlProblem", "OptimalControlOptions", "OptimalControlResult", "OptimalControlSolver",
    "solve_optimal_control",
]

STATE_LIMITS = ("hard", "soft")
SCREEN_FRACTION = 0.1
"""A state limit enters the step QP when the iterate is within this fraction of its range from it (or beyond); the
others are checked on the QP's step and added when it crosses them (the QP is then solved again), so the step is
the full QP's."""
MU0_FLOOR = 1e2
"""HPIPM's initial barrier parameter on a cold start: the largest slack cost of the limits in the QP, at least this
(a warm start begins from the previous QP's solution instead)."""


# --------------------------------------------------------------------------------------------
# The problem
# --------------------------------------------------------------------------------------------

def _weights(value: Any, n: int, name: str) -> np.ndarray:
    """A non-negative finite weight, scalar or (n,), as (n,)."""
    v = np.full(n, float(value)) if np.ndim(value) == 0 and _is_number(value) else value
    v = as_vector(v, n, name)
    if np.any(v < 0):
        raise ValueError(f"`{name}` must be non-negative, got {v}")
    return v.copy()


def _is_number(value: Any) -> bool:
    try:
        float(value)
    except (TypeError, ValueError):
        return False
    return True


@dataclass(frozen=True)
class StageCost:
    """Weights of ℓ = ½ Σ w_q (q − q_ref)² + ½ Σ w_q̇ (q̇ − q̇_ref)² + ½ Σ w_τ (τ − τ_ref)² + ½ w_p ‖p − p_d‖² + ½ w_o ‖ϑ r‖².

    q [1/rad²], qd [s²/rad²], tau [1/(N·m)²]: scalars or one per joint; position [1/m²] and orientation [1/rad²]
    scalars for the end-effector pose error (0: no pose term). The torque weight is ignored in a terminal cost.
    All finite and non-negative.
    """

    q: Any = 0.0
    qd: Any = 0.0
    tau: Any = 0.0
    position: float = 0.0
    orientation: float = 0.0

    def resolved(self, n: int, name: str) -> "StageCost":
        """The weights as (n,) arrays and floats, validated (``name`` prefixes the arguments in errors)."""
        return StageCost(_weights(self.q, n, f"{name}.q"), _weights(self.qd, n, f"{name}.qd"),
                         _weights(self.tau, n, f"{name}.tau"),
                         as_positive(self.position, f"{name}.position", allow_zero=True),
                         as_positive(self.orientation, f"{name}.orientation", allow_zero=True))


@dataclass(frozen=True)
class OptimalControlProblem:
    """An optimal control problem on ``robot`` (module docstring).

    Parameters
    ----------
    robot : the model (nq = nv), rotors included when its URDF has them.
    horizon : number of intervals N >= 1; dt : their length [s].
    running, terminal : :class:`StageCost` weights of ℓ and ℓ_N.
    tau_max : (n,) or scalar torque limits [N·m], hard; default the URDF's effort limits.
    q_min, q_max : position limits [rad | m] (default the URDF's; ±inf: none); qd_max : speed limits (default the
        URDF's; inf: none).
    state_limits : ``"hard"`` (constraints) or ``"soft"`` (L1 penalty ``slack_weight`` Σ |excess| on every node
        but the first, which is given).
    slack_weight : the L1 weight [cost per rad | rad/s]; above the constraints' multipliers the soft optimum is the
        hard one whenever that is feasible (exact penalty).
    frame : the end-effector frame of the pose terms (default the robot's).
    """

    robot: Robot
    horizon: int
    dt: float
    running: StageCost = field(default_factory=StageCost)
    terminal: StageCost = field(default_factory=StageCost)
    tau_max: Any = None
    q_min: Any = None
    q_max: Any = None
    qd_max: Any = None
    state_limits: str = "soft"
    slack_weight: float = 1e3
    frame: str | int | None = None

    def __post_init__(self) -> None:
        robot = self.robot
        if not isinstance(robot, Robot):
            raise ValueError(f"`robot` must be a Robot, got {type(robot).__name__}")
        if robot.nq != robot.nv:
            raise ValueError("`robot` must have nq == nv (no continuous or free-flyer joints) for optimal control")
        n = robot.nv
        h = self.horizon
        if isinstance(h, (bool, np.bool_)) or not isinstance(h, (int, np.integer)) or h < 1:
            raise ValueError(f"`horizon` must be an integer >= 1, got {h!r}")
        object.__setattr__(self, "horizon", int(h))
        object.__setattr__(self, "dt", as_positive(self.dt, "dt"))
        for name in ("running", "terminal"):
            cost = getattr(self, name)
            if not isinstance(cost, StageCost):
                raise ValueError(f"`{name}` must be a StageCost, got {type(cost).__name__}")
            object.__setattr__(self, name, cost.resolved(n, name))
        model = robot.model
        tau = model.effortLimit if self.tau_max is None else self.tau_max
        tau = np.full(n, float(tau)) if np.ndim(tau) == 0 and _is_number(tau) else tau
        tau = as_vector(tau, n, "tau_max").copy()
        if np.any(tau <= 0):
            raise ValueError(f"`tau_max` must be positive and finite, got {tau}")
        object.__setattr__(self, "tau_max", tau)
        for name, default in (("q_min", model.lowerPositionLimit), ("q_max", model.upperPositionLimit),
                              ("qd_max", model.velocityLimit)):
            v = getattr(self, name)
            v = np.array(default, dtype=float) if v is None else np.asarray(v, dtype=float)
            v = np.full(n, float(v)) if v.ndim == 0 else v
            if v.shape != (n,) or np.any(np.isnan(v)):
                raise ValueError(f"`{name}` must be a scalar or have shape ({n},) without NaN, got {v}")
            object.__setattr__(self, name, v.copy())
        if np.any(self.q_min >= self.q_max) or np.any(self.q_min == np.inf) or np.any(self.q_max == -np.inf):
            raise ValueError(f"`q_min` must be below `q_max` for every joint, got {self.q_min} and {self.q_max}")
        one_sided = np.flatnonzero(np.isfinite(self.q_min) != np.isfinite(self.q_max))
        if one_sided.size:
            raise ValueError(f"`q_min` and `q_max` of joint(s) {(one_sided + 1).tolist()} have one finite side: give "
                             "both limits finite, or both infinite (no position limit)")
        if np.any(self.qd_max <= 0):
            raise ValueError(f"`qd_max` must be positive, got {self.qd_max}")
        if self.state_limits not in STATE_LIMITS:
            raise ValueError(f"`state_limits` must be one of {STATE_LIMITS}, got {self.state_limits!r}")
        object.__setattr__(self, "slack_weight", as_positive(self.slack_weight, "slack_weight"))
        object.__setattr__(self, "frame", robot.frame(self.frame))

    @property
    def n(self) -> int:
        return self.robot.nv

    @property
    def pose_terms(self) -> tuple[bool, bool]:
        """(position, orientation): whether a pose term appears in either cost."""
        return (self.running.position > 0 or self.terminal.position > 0,
                self.running.orientation > 0 or self.terminal.orientation > 0)

    def limited(self) -> tuple[np.ndarray, np.ndarray]:
        """Indices of the joints with finite position limits (both sides: one-sided limits are refused) and with
        finite speed limits."""
        return np.flatnonzero(np.isfinite(self.q_min)), np.flatnonzero(np.isfinite(self.qd_max))


@dataclass(frozen=True)
class OptimalControlOptions:
    """Settings of :class:`OptimalControlSolver`.

    max_iter : SQP iterations (1: one real-time iteration); time_limit : wall time [s] after which the SQP stops
        (checked between iterations).
    tol : the KKT tolerance of success (stationarity relative to the cost gradient, defects [rad | rad/s],
        complementarity); step_tol : the SQP stops when no step component exceeds it (torques relative to τ_max).
    limit_tol : hard limits may be exceeded by this fraction of their size and still hold.
    qp_tol, qp_max_iter : HPIPM's residual tolerances and iteration cap.
    qp_solver : the step QP's solver (:mod:`planners.stage_qp`): ``"auto"`` (HPIPM through its C interface when
        CasADi's libhpipm passes the checks, else the sparse fallback with one warning), ``"hpipm"`` (an error naming
        what is missing when it cannot be used), ``"piqp"`` or ``"proxsuite"`` (the fallback: one sparse QP per step
        by PIQP through CasADi, or proxsuite; slower).
    verify : False skips the independent Pinocchio check (KKT and defects; success is then the solver's own
        convergence and defects with every hard limit checked; real-time loops that cannot afford the check).
    """

    max_iter: int = 50
    tol: float = 1e-6
    step_tol: float = 1e-8
    limit_tol: float = 1e-9
    time_limit: float = math.inf
    qp_tol: float = 1e-10
    qp_max_iter: int = 100
    verify: bool = True
    qp_solver: str = "auto"

    def __post_init__(self) -> None:
        for name in ("max_iter", "qp_max_iter"):
            v = getattr(self, name)
            if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)) or v < 1:
                raise ValueError(f"`{name}` must be an integer >= 1, got {v!r}")
        for name in ("tol", "step_tol", "qp_tol"):
            as_positive(getattr(self, name), name)
        as_positive(self.limit_tol, "limit_tol", allow_zero=True)
        check_qp_solver(self.qp_solver)
        if not (isinstance(self.time_limit, (int, float)) and self.time_limit > 0):
            raise ValueError(f"`time_limit` must be a positive number of seconds (inf: none), got {self.time_limit!r}")


@dataclass(frozen=True)
class OptimalControlResult(OptimalTrajectory):
    """The solution of an optimal control problem, an :class:`~planners.optimization.OptimalTrajectory` with:

    trajectory : the N+1 nodes t_k = k dt (q, q̇, and q̈ = the forward dynamics at (q_k, q̇_k, τ_k); the law between
        nodes the cubic Hermite interpolant of q, q̇); tau : (N+1, n) τ_k held on [t_k, t_{k+1}) (the last row
        repeats τ_{N−1}); cost : the optimal value; ratios : max |τ|/τ_max, position ratio in the box, max |q̇|/q̇_max.
    status : ``"converged"``, ``"iteration limit"``, ``"time limit"`` or ``"qp failure"`` (the SQP's own account;
        ``success`` adds the independent check). x : (N+1, 2n) node states; u : (N, n) torques; kkt : the largest KKT residual found by the independent check
        (NaN when not verified); defect : max |x_{k+1} − Φ(x_k, τ_k)| by Pinocchio; slack : the total soft-limit
        excess; iterations : SQP iterations; solve_time : wall time of the SQP (the check apart: check_time);
        timings : where solve_time went [s]: ``"linearisation"`` (the compiled intervals' values and Jacobians),
        ``"qp assembly"`` (the step QP's stage arrays), ``"qp"`` (HPIPM), ``"line search"``.
    verified : whether Pinocchio's independent check ran (``OptimalControlOptions.verify``): with it ``success``
        includes the KKT residual by Pinocchio; without, ``success`` is the solver's own account (converged, finite,
        hard limits, its model's defects) and ``kkt`` is NaN.
    """

    status: str = ""
    x: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    u: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    dt: float = 0.0
    kkt: float = math.nan
    defect: float = math.nan
    slack: float = 0.0
    check_time: float = 0.0
    multipliers: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    timings: dict[str, float] = field(default_factory=dict, repr=False)
    verified: bool = False

    def __repr__(self) -> str:
        ratios = ", ".join(f"{k} {v:.3g}" for k, v in self.ratios.items())
        return (f"OptimalControlResult(N={len(self.u)}, dt={self.dt:g} s, cost={self.cost:.6g}, success={self.success}, "
                f"KKT {self.kkt:.2g}{'' if self.verified else ' (not verified)'}, defect {self.defect:.2g}, limit ratios: {ratios}, {self.iterations} SQP "
                f"iterations in {self.solve_time * 1e3:.3g} ms, message={self.message!r})")

    def shifted(self, steps: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """(x, u) moved ``steps`` intervals ahead, the last values repeated: the warm start of the next sample."""
        x = np.concatenate([self.x[steps:], np.repeat(self.x[-1:], steps, axis=0)])
        u = np.concatenate([self.u[steps:], np.repeat(self.u[-1:], steps, axis=0)])
        return x, u


# --------------------------------------------------------------------------------------------
# The transcription: one interval's linearisation, generated as C
# --------------------------------------------------------------------------------------------

@functools.lru_cache(maxsize=None)
def _layout(n: int) -> dict[str, slice]:
    """Where each per-node parameter sits in a parameter column (the one layout: the compiled functions, the
    references written by :meth:`OptimalControlSolver.parameters` and the independent check read it): dt, q_ref,
    q̇_ref, τ_ref, p_d (3), vec R_d (9, by columns), √w_q, √w_q̇, √w_τ, √w_p, √w_o."""
    out, k = {}, 0
    for name, size in (("dt", 1), ("q_ref", n), ("qd_ref", n), ("tau_ref", n), ("p_d", 3), ("R_d", 9), ("sw_q", n),
                       ("sw_qd", n), ("sw_tau", n), ("sw_p", 1), ("sw_o", 1)):
        out[name] = slice(k, k + size)
        k += size
    return out


def _parameter_size(n: int) -> int:
    """The length of a parameter column (:func:`_layout`)."""
    return _layout(n)["sw_o"].stop


def _unpack(p: Any, n: int) -> dict[str, Any]:
    """The parameters of the column ``p`` (CasADi) by name, R_d as 3 × 3."""
    out = {name: p[where] for name, where in _layout(n).items()}
    out["R_d"] = ca.reshape(out["R_d"], 3, 3)
    return out


def _state_residual(robot: Robot, frame: int, x: Any, P: dict, position: bool, orientation: bool) -> Any:
    """The residual whose ½‖·‖² is ℓ's state and pose part at the state x (SX)."""
    n = robot.nv
    q, qd = x[:n], x[n:]
    parts = [P["sw_q"] * (q - P["q_ref"]), P["sw_qd"] * (qd - P["qd_ref"])]
    if position or orientation:
        R, p = frame_placement(robot.model, frame, q)
        if position:
            parts.append(P["sw_p"] * (p - P["p_d"]))
        if orientation:
            parts.append(P["sw_o"] * rotation_log_expression(ca.mtimes(P["R_d"].T, R)))
    return ca.vertcat(*parts)


def _linearised_interval(robot: Robot, frame: int, x: Any, u: Any, p: Any, position: bool,
                         orientation: bool) -> tuple[Any, Any, Any, Any]:
    """One interval's (Φ(x, u), r, ∂[Φ; r]/∂[x; u], q̈(x, u)) as SX, the Jacobian by the chain rule through the RK4
    stages (forward sensitivities): with z = [x; u], each stage state s_i has ∂s_i/∂z, the stage slope k_i = f(s_i, u)
    has ∂k_i/∂z = ∂f/∂s ∂s_i/∂z + ∂f/∂u ∂u/∂z, the dynamics' partials from
    :func:`rigid_body.symbolic.forward_dynamics_derivatives_expression` (−B⁻¹ times the Newton–Euler partials: about
    a third of the operations of differentiating the whole step automatically)."""
    n = robot.nv
    nx, nz = 2 * n, 3 * n
    P = _unpack(p, n)
    h = P["dt"]
    E_x = ca.SX(ca.DM(ca.Sparsity.diag(nx, nz), 1.0))                # ∂x/∂z = [I 0]
    E_u = ca.SX(ca.DM(ca.Sparsity.triplet(n, nz, list(range(n)), list(range(nx, nz))), 1.0))   # ∂u/∂z = [0 I]
    s_sym, p_sym = ca.SX.sym("s", nx), ca.SX.sym("p", p.shape[0])
    r_sym = _state_residual(robot, frame, s_sym, _unpack(p_sym, n), position, orientation)
    state_residual = ca.Function("state_residual", [s_sym, p_sym], [r_sym, ca.jacobian(r_sym, s_sym)])
    zero, eye = ca.SX(n, n), ca.SX.eye(n)
    accelerations: list = []

    def slope(s: Any, v: Any) -> tuple[Any, Any, Any]:
        qdd, J = forward_dynamics_derivatives_expression(robot, s[:n], s[n:], v)
        accelerations.append(qdd)
        return ca.vertcat(s[n:], qdd), ca.vertcat(ca.horzcat(zero, eye), J[:, :nx]), ca.vertcat(zero, J[:, nx:])

    x_next, dx_next, states, state_jacobians = rk4_sensitivities(slope, x, u, h, E_x, E_u)
    w = RK4_WEIGHTS
    residuals, residual_jacobians = [], []
    for wi, s, ds in zip(w, states, state_jacobians):
        scale = ca.sqrt(wi * h)
        r_s, dr_s = state_residual(s, p)
        residuals.append(scale * r_s)
        residual_jacobians.append(scale * ca.mtimes(dr_s, ds))
    torque = ca.sqrt(h) * P["sw_tau"]
    residuals.append(torque * (u - P["tau_ref"]))
    residual_jacobians.append(ca.mtimes(ca.diag(torque), E_u))
    return x_next, ca.vertcat(*residuals), ca.vertcat(dx_next, *residual_jacobians), accelerations[0]


_FUNCTIONS: dict[tuple, tuple] = {}


def _functions(robot: Robot, frame: int, position: bool, orientation: bool) -> tuple:
    """(stage, stage_value, terminal, terminal_value): the compiled interval and terminal functions, built once per
    (model content, frame, pose terms).

    stage (x, u, p) → (Φ(x, u), r, ∂[Φ; r]/∂[x; u], q̈(x, u)); stage_value (x, u, p) → (Φ, r, q̈); terminal (x, p) →
    (r_N, ∂r_N/∂x) and terminal_value (x, p) → r_N, with ½‖r‖² the interval's cost (RK4 quadrature) and ½‖r_N‖² the
    terminal one.
    """
    key = (model_digest(robot.model), frame, position, orientation)
    cached = _FUNCTIONS.get(key)
    if cached is not None:
        return cached
    n = robot.nv
    x, u, p = ca.SX.sym("x", 2 * n), ca.SX.sym("u", n), ca.SX.sym("p", _parameter_size(n))
    P = _unpack(p, n)

    slopes: list = []

    def f(xs: Any, us: Any) -> Any:
        slopes.append(ca.vertcat(xs[n:], forward_dynamics_expression(robot, xs[:n], xs[n:], us)))
        return slopes[-1]

    x_next, stages = rk4_stages(f, x, u, P["dt"])
    r = ca.vertcat(*[ca.sqrt(c * P["dt"]) * _state_residual(robot, frame, s, P, position, orientation)
                     for c, s in zip(RK4_WEIGHTS, stages)],
                   ca.sqrt(P["dt"]) * P["sw_tau"] * (u - P["tau_ref"]))
    tag = f"{'p' if position else ''}{'o' if orientation else ''}"
    x_next_, r_, J_, qdd_ = _linearised_interval(robot, frame, x, u, p, position, orientation)
    stage = ca.Function(f"ocp_stage{tag}", [x, u, p], [x_next_, r_, ca.densify(J_), qdd_])
    stage_value = ca.Function(f"ocp_value{tag}", [x, u, p], [x_next, r, slopes[0][n:]])
    r_N = _state_residual(robot, frame, x, P, position, orientation)
    terminal = ca.Function(f"ocp_terminal{tag}", [x, p], [r_N, ca.densify(ca.jacobian(r_N, x))])
    terminal_value = ca.Function(f"ocp_terminal_value{tag}", [x, p], [r_N])
    stage = compile_function(stage, native=True)    # the linearisation, the hot spot: the host's instruction set
    built = (stage, *(compile_function(g) for g in (stage_value, terminal, terminal_value)))
    _FUNCTIONS[key] = built
    return built


class _Call:
    """A CasADi function called on numpy arrays without DM conversions (CasADi's function buffer): each argument's
    C-order data is the input's column-major nonzeros (a dense (r, c) input is given as its (c, r) transpose);
    returns the outputs as dense (rows, cols) arrays (copies), or with ``transposed`` as their (cols, rows)
    transposes, views of the output buffers without a copy (valid until the next call; dense outputs only): a
    function mapped over N intervals then gives one row per interval."""

    def __init__(self, function: ca.Function, transposed: bool = False):
        self.function, self.transposed = function, transposed
        self._buffer, self._run = function.buffer()
        self._outputs = []
        for i in range(function.n_out()):
            sp = function.sparsity_out(i)
            nz = np.zeros(sp.nnz())
            self._buffer.set_res(i, memoryview(nz))
            rows, cols = (np.array(v, dtype=int) for v in sp.get_triplet())
            self._outputs.append((nz, rows, cols, (sp.size1(), sp.size2()), sp.is_dense()))
        self._inputs: list[np.ndarray] = [np.zeros(0)] * function.n_in()
        self._sizes = [function.sparsity_in(i).nnz() for i in range(function.n_in())]

    def __call__(self, *args: Any) -> list[np.ndarray]:
        for i, a in enumerate(args):
            a = np.ascontiguousarray(a, dtype=float).reshape(-1)
            if a.size != self._sizes[i]:
                raise ValueError(f"{self.function.name()}: input {i} has {a.size} values, expected {self._sizes[i]}")
            self._inputs[i] = a                      # kept alive for the call
            self._buffer.set_arg(i, memoryview(a))
        self._run()
        if self.transposed:
            return [nz.reshape(shape[1], shape[0]) for nz, _, _, shape, _ in self._outputs]
        out = []
        for nz, rows, cols, shape, dense in self._outputs:
            if dense:
                out.append(nz.reshape(shape[1], shape[0]).T.copy())
            else:
                full = np.zeros(shape)
                full[rows, cols] = nz
                out.append(full)
        return out


# --------------------------------------------------------------------------------------------
# The solver
# --------------------------------------------------------------------------------------------

class OptimalControlSolver:
    """The Gauss–Newton SQP of an :class:`OptimalControlProblem` (module docstring), built once and solved from many
    initial states and references (model predictive control).

    >>> from rigid_body.robots import load
    >>> arm = load("planar_2r")
    >>> problem = OptimalControlProblem(arm, horizon=20, dt=0.02, running=StageCost(q=1e3, qd=1.0, tau=1e-6),
    ...                                 terminal=StageCost(q=1e4, qd=1e2), tau_max=[3000.0, 1500.0])
    >>> res = OptimalControlSolver(problem).solve([0.0, 0.0, 0.0, 0.0], q_ref=[0.3, -0.2])
    >>> res.success, res.ratios["tau"] <= 1.0
    (True, True)
    """

    def __init__(self, problem: OptimalControlProblem, options: OptimalControlOptions | None = None):
        if not isinstance(problem, OptimalControlProblem):
            raise ValueError(f"`problem` must be an OptimalControlProblem, got {type(problem).__name__}")
        self.problem, self.options = problem, options or OptimalControlOptions()
        pr = problem
        n, N = pr.n, pr.horizon
        self.n, self.N, self.nx = n, N, 2 * n
        position, orientation = pr.pose_terms
        self._pose = (position, orientation)
        stage, stage_value, terminal, terminal_value = _functions(pr.robot, pr.frame, position, orientation)
        self._stage = _Call(stage.map(N), transposed=True)            # rows: intervals; Jacobians as [Φ; r]ᵀ
        self._stage_value = _Call(stage_value.map(N), transposed=True)
        self._stage_value_one = _Call(stage_value)
        self._terminal, self._terminal_value = _Call(terminal), _Call(terminal_value)
        q_lim, v_lim = pr.limited()
        self._limited = np.concatenate([q_lim, n + v_lim]).astype(int)        # the limited entries of x
        self._lower = np.concatenate([pr.q_min, -pr.qd_max])[self._limited]
        self._upper = np.concatenate([pr.q_max, pr.qd_max])[self._limited]
        span = self._upper - self._lower
        self._margin = np.where(np.isfinite(span), SCREEN_FRACTION * span, np.inf)
        self._qp = stage_qp(N, self.nx, n, self._limited, pr.state_limits == "soft", self.options,
                            self.options.qp_solver)
        self.qp_solver = self._qp.name      # "HPIPM", "piqp" or "proxsuite"
        self._hard_qp = None                # soft limits: the same QP with them hard, tried first (fewer iterations)
        if self._qp.ns:
            self._hard_qp = stage_qp(N, self.nx, n, self._limited, False, self.options, inputs_of=self._qp)
        self.qp_solves, self._qp_time = 0, 0.0
        self._gravity_data = pr.robot.model.createData()
        self._weights = tuple(np.concatenate([np.sqrt(c.q), np.sqrt(c.qd), np.sqrt(c.tau),
                                              [math.sqrt(c.position), math.sqrt(c.orientation)]])
                              for c in (pr.running, pr.terminal))

    # ---- references -----------------------------------------------------------------------------------------
    def parameters(self, x0: np.ndarray, q_ref: Any = None, qd_ref: Any = None, tau_ref: Any = None,
                   T_d: Any = None) -> tuple[np.ndarray, np.ndarray]:
        """The per-node parameters (running (N, np), one row per interval; terminal (np,)) for the references: q_ref, qd_ref
        ((n,) or (N+1, n); default the start's q and rest), tau_ref ((n,) or (N, n); default 0), T_d ((4, 4) or
        (N+1, 4, 4); required when a pose weight is set)."""
        pr, n, N = self.problem, self.n, self.N
        q_ref = _per_node(x0[:n] if q_ref is None else q_ref, N + 1, n, "q_ref")
        qd_ref = _per_node(np.zeros(n) if qd_ref is None else qd_ref, N + 1, n, "qd_ref")
        tau_ref = _per_node(np.zeros(n) if tau_ref is None else tau_ref, N, n, "tau_ref")
        if T_d is None:
            if any(self._pose):
                raise ValueError("`T_d` is required: the problem has an end-effector pose cost")
            T = np.tile(np.eye(4), (N + 1, 1, 1))
        else:
            T = np.asarray(T_d, dtype=float)
            T = np.tile(T, (N + 1, 1, 1)) if T.shape == (4, 4) else T
            if T.shape != (N + 1, 4, 4):
                raise ValueError(f"`T_d` must be a (4, 4) pose or (N+1, 4, 4) poses, got shape {np.shape(T_d)}")
            as_homogeneous_batch(T, "T_d")

        rotations = np.transpose(T[:, :3, :3], (0, 2, 1)).reshape(N + 1, 9)   # each R_d by columns
        running, terminal = self._weights
        at = _layout(n)
        weights = slice(at["sw_q"].start, at["sw_o"].stop)
        P = np.empty((N + 1, _parameter_size(n)))                            # rows 0..N−1 running, N terminal
        P[:, at["dt"]] = pr.dt
        P[:, at["q_ref"]], P[:, at["qd_ref"]] = q_ref, qd_ref
        P[:N, at["tau_ref"]], P[N, at["tau_ref"]] = tau_ref, 0.0
        P[:, at["p_d"]], P[:, at["R_d"]] = T[:, :3, 3], rotations
        P[:N, weights], P[N, weights] = running, terminal
        return P[:N], P[N].copy()

    # ---- the SQP --------------------------------------------------------------------------------------------
    def solve(self, x0: Any, q_ref: Any = None, qd_ref: Any = None, tau_ref: Any = None, T_d: Any = None,
              warm_start: Any = None, max_iter: int | None = None, time_limit: float | None = None) -> OptimalControlResult:
        """Solve from the state ``x0`` = [q; q̇] (2n,) for the references (:meth:`parameters`).

        ``warm_start`` : a previous :class:`OptimalControlResult` (its x, u), an (x (N+1, 2n), u (N, n)) pair
        (e.g. ``result.shifted()``), or a :class:`~planners.timing.Trajectory` with N+1 samples and torques
        (``(trajectory, tau)``); default: x0 held with the gravity torques at q0. ``max_iter``, ``time_limit``
        override the options for this call.
        """
        start = time.perf_counter()
        pr, n, N, nx, o = self.problem, self.n, self.N, self.nx, self.options
        x0 = as_vector(x0, nx, "x0").copy()
        if pr.state_limits == "hard":
            self._check_start(x0)
        max_iter = o.max_iter if max_iter is None else max_iter
        time_limit = o.time_limit if time_limit is None else time_limit
        P, P_N = self.parameters(x0, q_ref, qd_ref, tau_ref, T_d)
        X, U = self._initial_guess(x0, warm_start)
        X[0] = x0
        tau_max = pr.tau_max
        U = np.clip(U, -tau_max, tau_max)
        if pr.state_limits == "hard":
            X[1:, :n] = np.clip(X[1:, :n], pr.q_min, pr.q_max)
            X[1:, n:] = np.clip(X[1:, n:], -pr.qd_max, pr.qd_max)
        rho = 1.0
        iterations, converged, message, mult, qp_notes, status = 0, False, "", {}, set(), "iteration limit"
        values = None
        clock = time.perf_counter
        self._qp_time, lin_time, step_time, search_time = 0.0, 0.0, 0.0, 0.0
        for it in range(max_iter):
            t0 = clock()
            Xn, R, JT, qdd = self._stage(X[:-1], U, P)      # (N, 2n), (N, nr), (N·3n, 2n + nr), (N, n)
            r_N, J_N = self._terminal(X[-1], P_N)
            values = (Xn, R, r_N.ravel(), qdd)
            t1 = clock()
            step, mult, ok, qp_message = self._step(X, U, Xn, R, JT.reshape(N, nx + n, -1), r_N.ravel(), J_N)
            t2 = clock()
            lin_time, step_time = lin_time + t1 - t0, step_time + t2 - t1
            iterations += 1
            if not ok:
                message = f"the QP of SQP iteration {it + 1} failed ({qp_message})"
                status = "qp failure"
                break
            if qp_message:
                qp_notes.add(qp_message)
            dX, dU, S, slope = step
            size = max(float(np.max(np.abs(dX), initial=0.0)), float(np.max(np.abs(dU) / tau_max, initial=0.0)))
            defect = float(np.max(np.abs(Xn - X[1:])))
            rho = max(rho, 1.5 * float(np.max(np.abs(mult["gap"]), initial=0.0)))
            alpha, values = self._line_search(X, U, dX, dU, S, slope, P, P_N, values, rho)
            search_time += clock() - t2
            X[1:] += alpha * dX
            U += alpha * dU
            if size <= o.step_tol and defect <= o.tol:
                converged, status = True, "converged"
                message = f"converged in {iterations} SQP iterations"
                break
            if alpha < 1e-6 and size <= math.sqrt(o.step_tol) and defect <= o.tol:
                converged, status = True, "converged"   # the merit no longer decreases: at the QP's accuracy (checked below)
                message = f"stationary to the QP's accuracy after {iterations} SQP iterations"
                break
            if time.perf_counter() - start > time_limit:
                message = f"stopped by the time limit ({time_limit:g} s) after {iterations} SQP iterations"
                status = "time limit"
                break
        else:
            message = f"not converged in {max_iter} SQP iterations"
        if qp_notes:
            message += f" (step QPs stopped early: {', '.join(sorted(qp_notes))})"
        solve_time = time.perf_counter() - start
        timings = {"linearisation": lin_time, "qp assembly": step_time - self._qp_time, "qp": self._qp_time,
                   "line search": search_time}
        return self._result(X, U, P, P_N, values, mult, converged, message, iterations, solve_time, status, timings)

    def predict(self, x: Any, tau: Any) -> np.ndarray:
        """Φ(x, τ): the state one interval dt after x under the held torque τ, by the problem's model (the same RK4
        step as the transcription)."""
        column = np.zeros(_parameter_size(self.n))
        column[_layout(self.n)["dt"]] = self.problem.dt
        x_next = self._stage_value_one(as_vector(x, self.nx, "x"), as_vector(tau, self.n, "tau"), column)[0]
        return np.asarray(x_next).ravel()

    def violated(self, x0: Any) -> np.ndarray:
        """The joints (0-based) whose position or speed in the state ``x0`` is beyond the problem's limits."""
        pr, n = self.problem, self.n
        x0 = np.asarray(x0, dtype=float)
        q, qd = x0[:n], x0[n:]
        return np.flatnonzero((q < pr.q_min) | (q > pr.q_max) | (np.abs(qd) > pr.qd_max))

    def _check_start(self, x0: np.ndarray) -> None:
        bad = self.violated(x0)
        if bad.size:
            raise ValueError(f"`x0` violates the hard state limits at joint(s) {(bad + 1).tolist()}: with "
                             "state_limits='hard' the start must be feasible (use state_limits='soft')")

    def _initial_guess(self, x0: np.ndarray, warm_start: Any) -> tuple[np.ndarray, np.ndarray]:
        n, N, nx = self.n, self.N, self.nx
        if warm_start is None:
            g = pin.computeGeneralizedGravity(self.problem.robot.model, self._gravity_data, x0[:n])
            return np.tile(x0, (N + 1, 1)), np.tile(g, (N, 1))
        if isinstance(warm_start, OptimalControlResult):
            x, u = warm_start.x, warm_start.u
        elif isinstance(warm_start, tuple) and len(warm_start) == 2 and isinstance(warm_start[0], Trajectory):
            tr, tau = warm_start
            x, u = np.hstack([tr.q, tr.qd]), np.asarray(tau, dtype=float)[:N]
        elif isinstance(warm_start, tuple) and len(warm_start) == 2:
            x, u = warm_start
        else:
            raise ValueError("`warm_start` must be an OptimalControlResult, an (x, u) pair or a (Trajectory, tau) pair")
        x, u = np.array(x, dtype=float), np.array(u, dtype=float)
        if x.shape != (N + 1, nx) or u.shape != (N, n) or not (np.all(np.isfinite(x)) and np.all(np.isfinite(u))):
            raise ValueError(f"`warm_start` must give finite x of shape ({N + 1}, {nx}) and u of shape ({N}, {n}), "
                             f"got {x.shape} and {u.shape}")
        return x, u

    def _step(self, X: np.ndarray, U: np.ndarray, Xn: np.ndarray, R: np.ndarray, JT: np.ndarray, r_N: np.ndarray,
              J_N: np.ndarray) -> tuple:
        """Solve the QP of the step at (X, U), given Φ(x_k, τ_k) (N, 2n), the residuals R (N, nr) and the transposed
        Jacobians JT_k = ∂[Φ; r]/∂[x_k; τ_k]ᵀ (N, 3n, 2n + nr): ((δX (N, 2n), δU (N, n), S (N, n_limited), the
        cost's directional derivative along the step), multipliers, ok, message).

        The Gauss–Newton Hessian JᵀJ and gradient Jᵀr of each interval, the dynamics' linearisation and the limits go
        straight into HPIPM's stage arrays. Each variable is scaled by 1/√(its Hessian diagonal) (Jacobi scaling: the
        scaled Hessian has a unit diagonal) and each dynamics row by the scale of the state it defines, so that HPIPM's
        absolute tolerances mean the same on a 12 N·m wrist and on a 10⁶ N·m bound. S: the total slack (lower +
        upper) of each limited quantity, soft limits only."""
        pr, n, N, nx, qp = self.problem, self.n, self.N, self.nx, self._qp
        JT_r = JT[:, :, nx:]                                                  # (N, nz, nr): ∂r/∂z transposed
        H = JT_r @ np.transpose(JT_r, (0, 2, 1))                              # Gauss–Newton: JᵀJ, (N, nz, nz)
        g = (JT_r @ R[:, :, None])[:, :, 0]                                   # Jᵀr, (N, nz)
        H_N, g_N = J_N.T @ J_N, J_N.T @ r_N
        diag = np.vstack([np.diagonal(H, axis1=1, axis2=2), np.concatenate([np.diag(H_N), np.zeros(n)])])
        top = max(float(np.max(diag)), 1e-12)
        D = 1.0 / np.sqrt(np.maximum(diag, 1e-8 * top))                      # (N+1, nz): x_k, τ_k scales
        D_x, D_u = D[1:, :nx], D[:N, nx:]                                     # x_1..x_N, τ_0..τ_{N−1}
        inv = 1.0 / D_x                                                       # row scales of the dynamics
        Hs = H * D[:N, :, None] * D[:N, None, :]
        qp.R[:N] = Hs[:, nx:, nx:]
        qp.S[1:N] = Hs[1:, :nx, nx:]
        qp.Q[1:N] = Hs[1:, :nx, :nx]
        qp.Q[N] = H_N * D_x[-1][:, None] * D_x[-1][None, :]
        qp.r[:N] = g[:, nx:] * D_u
        qp.q[1:N] = g[1:, :nx] * D_x[:-1]
        qp.q[N] = g_N * D_x[-1]
        qp.A[1:N] = JT[1:, :nx, :nx] * D_x[:-1, :, None] * inv[1:, None, :]  # A_kᵀ, B_kᵀ scaled (HPIPM's order)
        qp.B[:N] = JT[:, nx:, :nx] * D_u[:, :, None] * inv[:, None, :]
        qp.b[:N] = (Xn - X[1:]) * inv                                         # the defects
        qp.lbu[:N] = (-pr.tau_max - U) / D_u
        qp.ubu[:N] = (pr.tau_max - U) / D_u
        limited, nb = self._limited, qp.nb
        D_l = D_x[:, limited]
        if nb:                              # the limits near the iterate (or beyond) enter the QP; the others are
            y = X[1:, limited]              # checked on the step and added if it crosses them (then solved again)
            qp.lbx[1:, :nb] = (self._lower - y) / D_l
            qp.ubx[1:, :nb] = (self._upper - y) / D_l
            if qp.ns:
                qp.zl[1:, :nb] = qp.zu[1:, :nb] = pr.slack_weight * D_l
            lower_on, upper_on = y - self._lower < self._margin, self._upper - y < self._margin
        # soft limits that the iterate satisfies: first the QP with them hard; its step is the soft QP's when it
        # solves and no limit's multiplier exceeds the slack's price (then the slacks are 0 and w − λ ≥ 0 theirs)
        hard_first = self._hard_qp is not None and bool(np.all(y >= self._lower) and np.all(y <= self._upper))
        solves = 0
        while True:
            if nb:
                qp.lbx_mask[1:, :nb], qp.ubx_mask[1:, :nb] = lower_on, upper_on
                slack_costs = qp.zl[1:, :nb][lower_on | upper_on] if qp.ns else np.zeros(0)
            else:
                slack_costs = np.zeros(0)
            t0 = time.perf_counter()
            solved = None
            if hard_first:
                self._hard_qp.set_mu0(MU0_FLOOR)
                status, iterations, residual = self._hard_qp.solve()
                solves += 1
                hard = self._hard_qp
                priced = np.maximum(_bound_rows(hard.lam_lb, n, nb), _bound_rows(hard.lam_ub, n, nb))
                if status == 0 and np.all(priced <= qp.zl[1:, :nb]):
                    solved = hard
                else:
                    hard_first = False          # the soft QP from here on (this step)
            if solved is None:
                qp.set_mu0(max(MU0_FLOOR, float(np.max(slack_costs, initial=0.0))))
                status, iterations, residual = qp.solve()
                solves += 1
                solved = qp
            self._qp_time += time.perf_counter() - t0
            dX, dU = solved.x[1:] * D_x, solved.u[:N] * D_u
            if status == 3 or not (np.all(np.isfinite(dX)) and np.all(np.isfinite(dU))):
                return None, {}, False, (f"non-finite or failed step, {solved.name} status {status} after "
                                         f"{iterations} iterations")
            if not nb:
                break
            y_new = y + dX[:, limited]
            lower_out, upper_out = ~lower_on & (y_new < self._lower), ~upper_on & (y_new > self._upper)
            if not (lower_out.any() or upper_out.any()):
                break                       # every limit left out holds at the step: it solves the full QP
            lower_on, upper_on = lower_on | lower_out, upper_on | upper_out
        self.qp_solves += solves
        lower, upper = _bound_rows(solved.lam_lb, n, nb) / D_l, _bound_rows(solved.lam_ub, n, nb) / D_l
        mult = {"gap": solved.pi[:N] * inv, "tau": (solved.lam_ub[:N, :n] - solved.lam_lb[:N, :n]) / D_u,
                "x": np.zeros((N, nx))}
        mult["x"][:, limited] = upper - lower
        slope = float(np.sum(g[:, :nx][1:] * dX[:-1]) + np.sum(g[:, nx:] * dU) + g_N @ dX[-1])
        S = np.zeros((N, 0))
        if qp.ns and solved is qp:
            S = (qp.sl[1:, :nb] + qp.su[1:, :nb]) * D_l
            mult.update(lower=lower, upper=upper, slack_lower=qp.lam_ls[1:, :nb] / D_l,
                        slack_upper=qp.lam_us[1:, :nb] / D_l)
        elif qp.ns:                         # the hard QP's step: no slack, the slacks' multipliers w − λ
            S = np.zeros((N, nb))
            w = pr.slack_weight
            mult.update(lower=lower, upper=upper, slack_lower=w - lower, slack_upper=w - upper)
        note = "" if status == 0 else f"{solved.name} status {status} (residual {residual:.1g})"
        return (dX, dU, S, slope), mult, True, note


    def _values(self, X: np.ndarray, U: np.ndarray, P: np.ndarray, P_N: np.ndarray) -> tuple:
        """(Φ(x_k, τ_k) (N, 2n), the running residuals (N, nr), the terminal residual, q̈_k (N, n)) at (X, U)
        (views of the function's buffers: valid until its next call)."""
        Xn, R, qdd = self._stage_value(X[:-1], U, P)
        return Xn, R, self._terminal_value(X[-1], P_N)[0].ravel(), qdd

    def _merit(self, X: np.ndarray, values: tuple, rho: float) -> tuple[float, float]:
        """(cost, L1 merit = cost + soft-limit penalty + ρ Σ |defects|) at X with its ``values``."""
        Xn, R, r_N, _ = values
        cost = 0.5 * float(np.sum(R * R) + r_N @ r_N)
        penalty = self.problem.slack_weight * self._excess(X) if self.problem.state_limits == "soft" else 0.0
        return cost, cost + penalty + rho * float(np.sum(np.abs(Xn - X[1:])))

    def _excess(self, X: np.ndarray) -> float:
        """Σ over nodes 1..N and limited joints of the amount by which q and |q̇| leave their limits."""
        pr, n = self.problem, self.n
        q, v = X[1:, :n], X[1:, n:]
        over = np.maximum(q - pr.q_max, 0.0) + np.maximum(pr.q_min - q, 0.0)
        fast = np.maximum(np.abs(v) - pr.qd_max, 0.0)
        return float(np.sum(over[np.isfinite(over)]) + np.sum(fast[np.isfinite(fast)]))

    def _line_search(self, X: np.ndarray, U: np.ndarray, dX: np.ndarray, dU: np.ndarray, S: np.ndarray,
                     slope: float, P: np.ndarray, P_N: np.ndarray, values: tuple, rho: float) -> tuple[float, tuple]:
        """Armijo backtracking on the L1 merit along the step; its directional derivative from the linearisation
        (``slope``: the cost's, from the QP's gradient): (the step length, the values at the point taken, copied)."""
        pr = self.problem
        cost0, merit0 = self._merit(X, values, rho)
        penalty0 = merit0 - cost0 - rho * float(np.sum(np.abs(values[0] - X[1:])))
        defects = float(np.sum(np.abs(values[0] - X[1:])))
        slope += (pr.slack_weight * float(np.sum(S)) - penalty0) if pr.state_limits == "soft" else 0.0
        slope -= rho * defects
        alpha = 1.0
        for _ in range(30):
            X_trial = np.vstack([X[:1], X[1:] + alpha * dX])
            values = self._values(X_trial, U + alpha * dU, P, P_N)
            trial = self._merit(X_trial, values, rho)[1]
            if trial <= merit0 + 1e-4 * alpha * min(slope, 0.0) or trial <= merit0 - 1e-12 * abs(merit0) \
                    and slope >= 0:
                break
            alpha *= 0.5
        return alpha, tuple(v.copy() for v in values)

    # ---- the result and its independent check ----------------------------------------------------------------
    def _result(self, X: np.ndarray, U: np.ndarray, P: np.ndarray, P_N: np.ndarray, values: tuple | None,
                mult: dict, converged: bool, message: str, iterations: int, solve_time: float,
                status: str, timings: dict | None = None) -> OptimalControlResult:
        """The result at (X, U); ``values`` are the solver's own at that point (:meth:`_values`). With ``verify``
        Pinocchio recomputes the accelerations and defects and checks the KKT conditions; without, the defects and
        accelerations are the solver's (computed with the step, nothing is evaluated again)."""
        pr, n, N, o = self.problem, self.n, self.N, self.options
        if values is None:
            values = self._values(X, U, P, P_N)
        cost, _ = self._merit(X, values, 0.0)
        penalty = self._excess(X)
        if pr.state_limits == "soft":
            cost += pr.slack_weight * penalty
        check_start = time.perf_counter()
        if o.verify:
            check = _KKTCheck(pr, P, P_N)
            qdd = check.accelerations(X, U)
            defect = check.defects(X, U)
            kkt = check.residual(X, U, mult) if (converged and mult) else math.nan
        else:                               # the solver's own defect (the real-time loops skip Pinocchio's)
            qdd = values[3]
            defect = float(np.max(np.abs(values[0] - X[1:])))
            defect = defect if np.isfinite(defect) else math.inf
            kkt = math.nan
        check_time = time.perf_counter() - check_start
        bounded = np.isfinite(pr.q_min)
        mid = 0.5 * (pr.q_max[bounded] + pr.q_min[bounded])
        half = 0.5 * (pr.q_max[bounded] - pr.q_min[bounded])
        ratios = {"tau": float(np.max(np.abs(U) / pr.tau_max)),
                  "q": float(np.max(np.abs(X[:, :n][:, bounded] - mid) / half, initial=0.0)),
                  "qd": float(np.max(np.abs(X[:, n:]) / pr.qd_max, initial=0.0))}
        slack_ok = 1.0 + o.limit_tol
        hard = ratios["tau"] <= slack_ok and (pr.state_limits == "soft" or (ratios["q"] <= slack_ok
                                                                            and ratios["qd"] <= slack_ok))
        finite = bool(np.all(np.isfinite(X)) and np.all(np.isfinite(U)))
        success = finite and converged and hard and defect <= o.tol and (not o.verify or kkt <= o.tol)
        if converged and not success:
            why = []
            if not hard:
                why.append(f"a hard limit is exceeded (ratios {ratios})")
            if defect > o.tol:
                why.append(f"the dynamics defect {defect:.2g} exceeds tol {o.tol:g}")
            if o.verify and not kkt <= o.tol:
                why.append(f"the independent KKT residual {kkt:.2g} exceeds tol {o.tol:g}")
            message += "; but " + " and ".join(why)
        t = pr.dt * np.arange(N + 1)
        q, qd = X[:, :n], X[:, n:]
        qdd = np.vstack([qdd, qdd[-1:]])
        trajectory = Trajectory(t, q.copy(), qd.copy(), qdd, _hermite(t, q, qd), "optimal control")
        tau = np.vstack([U, U[-1:]])
        return OptimalControlResult(trajectory, tau, float(t[-1]), "optimal control", cost, success, message, ratios,
                                    iterations, solve_time, status=status, x=X.copy(), u=U.copy(), dt=pr.dt, kkt=kkt,
                                    defect=defect,
                                    slack=penalty, check_time=check_time, multipliers=mult, timings=timings or {},
                                    verified=bool(o.verify) and not math.isnan(kkt))


def _bound_rows(lam: np.ndarray, n: int, nb: int) -> np.ndarray:
    """The state bounds' entries (N, nb) of HPIPM's per-stage bound multipliers (stages 1 … N: after the n torque
    bounds, except at the last stage, which has none)."""
    return np.vstack([lam[1:-1, n:n + nb], lam[-1:, :nb]])


def _per_node(value: Any, rows: int, n: int, name: str) -> np.ndarray:
    """A reference given once (n,) or per node (rows, n), as (rows, n), finite."""
    v = np.asarray(value, dtype=float) if _is_array_like(value) else value
    if np.ndim(v) == 1:
        return np.tile(as_vector(v, n, name), (rows, 1))
    v = np.asarray(v, dtype=float)
    if v.shape != (rows, n) or not np.all(np.isfinite(v)):
        raise ValueError(f"`{name}` must be finite of shape ({n},) or ({rows}, {n}), got {v.shape}")
    return v


def _is_array_like(value: Any) -> bool:
    try:
        np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


def _hermite(t: np.ndarray, q: np.ndarray, qd: np.ndarray) -> PiecewisePolynomial:
    """The C¹ cubic through (q_k, q̇_k) at the nodes t_k."""
    h = np.diff(t)[:, None]
    dq = q[1:] - q[:-1]
    c2 = (3 * dq - (2 * qd[:-1] + qd[1:]) * h) / h**2
    c3 = (-2 * dq + (qd[:-1] + qd[1:]) * h) / h**3
    return PiecewisePolynomial(t, np.stack([q[:-1], qd[:-1], c2, c3], axis=1))


# --------------------------------------------------------------------------------------------
# The independent check: Pinocchio dynamics, derivatives and costs
# --------------------------------------------------------------------------------------------

class _KKTCheck:
    """The KKT conditions of the solution evaluated with Pinocchio: integration by :func:`rk4_stages` of
    :func:`rigid_body.dynamics.forward_dynamics`, its derivatives from RNEA's (Pinocchio's analytical ones, central
    differences on models with rotors, which Pinocchio's derivatives refuse), the pose costs from Pinocchio's
    kinematics, ``log3`` and ``Jlog3``."""

    def __init__(self, problem: OptimalControlProblem, P: np.ndarray, P_N: np.ndarray):
        self.pr, self.P, self.P_N = problem, P, P_N
        self._at = _layout(problem.n)
        robot = problem.robot
        self.model, self.data = robot.model, robot.model.createData()
        self.n = robot.nv
        self.mimic = robot.has_mimic

    def _fd(self, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        from rigid_body.dynamics import forward_dynamics

        n = self.n
        return np.concatenate([x[n:], forward_dynamics(self.pr.robot, x[:n], x[n:], u, check=False)])

    def defects(self, X: np.ndarray, U: np.ndarray) -> float:
        """max |x_{k+1} − Φ(x_k, τ_k)| over the intervals, Φ by Pinocchio."""
        worst = 0.0
        for k in range(len(U)):
            x_next, _ = rk4_stages(self._fd, X[k], U[k], self.pr.dt)
            worst = max(worst, float(np.max(np.abs(x_next - X[k + 1]))))
        return worst if np.isfinite(worst) else math.inf

    def accelerations(self, X: np.ndarray, U: np.ndarray) -> np.ndarray:
        """q̈_k (N, n) at the nodes under τ_k (Pinocchio)."""
        return np.array([self._fd(X[k], U[k])[self.n:] for k in range(len(U))])

    def _fd_jacobian(self, x: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """f(x, u) = [q̇; q̈] and ∂f/∂[x; u] (2n, 3n): q̈ = B⁻¹(τ − h), ∂q̈ = B⁻¹ (dτ − ∂τ_RNEA/∂q dq − ∂τ_RNEA/∂q̇ dq̇)."""
        n, model, data = self.n, self.model, self.data
        q, v = x[:n], x[n:]
        f = self._fd(x, u)
        a = f[n:]
        Bq = pin.crba(model, data, q)
        Bq = np.triu(Bq) + np.triu(Bq, 1).T
        if self.mimic:
            eps = 1e-6
            Rq = np.column_stack([(pin.rnea(model, data, q + eps * e, v, a) - pin.rnea(model, data, q - eps * e, v, a))
                                  / (2 * eps) for e in np.eye(n)])
            Rv = np.column_stack([(pin.rnea(model, data, q, v + eps * e, a) - pin.rnea(model, data, q, v - eps * e, a))
                                  / (2 * eps) for e in np.eye(n)])
        else:
            Rq, Rv, _ = (np.array(m) for m in pin.computeRNEADerivatives(model, data, q, v, a))
        Binv = np.linalg.inv(Bq)
        Jf = np.zeros((2 * n, 3 * n))
        Jf[:n, n:2 * n] = np.eye(n)
        Jf[n:, :n], Jf[n:, n:2 * n], Jf[n:, 2 * n:] = -Binv @ Rq, -Binv @ Rv, Binv
        return f, Jf

    def _interval(self, x: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, list, list]:
        """Φ(x, u), ∂Φ/∂[x; u], the RK4 stage states and their Jacobians ∂s_i/∂[x; u] (:func:`rk4_sensitivities`
        with Pinocchio's dynamics and derivatives)."""
        n, nx = self.n, 2 * self.n
        E = np.eye(nx + n)

        def slope(s: np.ndarray, v: np.ndarray) -> tuple:
            f, Jf = self._fd_jacobian(s, v)
            return f, Jf[:, :nx], Jf[:, nx:]

        return rk4_sensitivities(slope, x, u, self.pr.dt, E[:nx], E[nx:])

    def _state_gradient(self, x: np.ndarray, p: np.ndarray) -> np.ndarray:
        """∂/∂x of ½‖r(x)‖², r the state and pose residual with the parameter column p."""
        n = self.n
        q, v = x[:n], x[n:]
        at = _layout(n)
        q_ref, qd_ref = p[at["q_ref"]], p[at["qd_ref"]]
        p_d, R_d = p[at["p_d"]], p[at["R_d"]].reshape(3, 3, order="F")
        w_q, w_qd = p[at["sw_q"]] ** 2, p[at["sw_qd"]] ** 2
        w_p, w_o = p[at["sw_p"]][0] ** 2, p[at["sw_o"]][0] ** 2
        grad = np.concatenate([w_q * (q - q_ref), w_qd * (v - qd_ref)])
        if w_p > 0 or w_o > 0:
            fid = self.pr.frame
            pin.computeJointJacobians(self.model, self.data, q)
            pin.updateFramePlacements(self.model, self.data)
            M = self.data.oMf[fid]
            if w_p > 0:
                J = pin.getFrameJacobian(self.model, self.data, fid, pin.LOCAL_WORLD_ALIGNED)[:3]
                grad[:n] += w_p * J.T @ (M.translation - p_d)
            if w_o > 0:
                E = R_d.T @ M.rotation
                J = pin.Jlog3(E) @ pin.getFrameJacobian(self.model, self.data, fid, pin.LOCAL)[3:]
                grad[:n] += w_o * J.T @ pin.log3(E)
        return grad

    def residual(self, X: np.ndarray, U: np.ndarray, mult: dict) -> float:
        """The largest of: stationarity of the Lagrangian (relative to 1 + the cost gradient's size), the defects,
        the hard limits' violation and complementarity (relative to the multipliers' size)."""
        pr, n, N, h = self.pr, self.n, len(U), self.pr.dt
        nx = 2 * n
        lam = mult["gap"]                       # multipliers of Φ(x_k, τ_k) − x_{k+1} = 0, (N, nx)
        grad_x = np.zeros((N + 1, nx))
        grad_u = np.zeros((N, n))
        stat_x = np.zeros((N + 1, nx))
        stat_u = np.zeros((N, n))
        for k in range(N):
            p = self.P[k]
            _, dPhi, states, jacs = self._interval(X[k], U[k])
            g = np.zeros(3 * n)
            for c, s, ds in zip(RK4_WEIGHTS, states, jacs):
                g += c * h * ds.T @ self._state_gradient(s, p)
            w_tau = p[self._at["sw_tau"]] ** 2
            g[nx:] += h * w_tau * (U[k] - p[self._at["tau_ref"]])
            grad_x[k] += g[:nx]
            grad_u[k] = g[nx:]
            stat_x[k] += g[:nx] + dPhi[:, :nx].T @ lam[k]
            stat_u[k] = g[nx:] + dPhi[:, nx:].T @ lam[k] + mult["tau"][k]
            stat_x[k + 1] -= lam[k]
        gN = self._state_gradient(X[N], self.P_N)
        grad_x[N] += gN
        stat_x[N] += gN
        stat_x[1:] += mult["x"]                 # the limits' multipliers (upper − lower) on the limited entries
        scale = 1.0 + max(float(np.max(np.abs(grad_x))), float(np.max(np.abs(grad_u))))
        stationarity = max(float(np.max(np.abs(stat_x[1:]))), float(np.max(np.abs(stat_u)))) / scale
        comp_soft = 0.0
        if pr.state_limits == "soft" and "lower" in mult:
            # lo − s_l ≤ y ≤ hi + s_u, s_l, s_u ≥ 0, cost w (s_l + s_u): the least slacks at X, the slacks'
            # stationarity w − λ − μ = 0, complementarity and the multipliers' signs (all ≥ 0)
            q_lim, v_lim = pr.limited()
            limited = np.concatenate([q_lim, n + v_lim])
            lo = np.concatenate([pr.q_min, -pr.qd_max])[limited]
            hi = np.concatenate([pr.q_max, pr.qd_max])[limited]
            y = X[1:][:, limited]
            s_l, s_u = np.maximum(lo - y, 0.0), np.maximum(y - hi, 0.0)
            w = pr.slack_weight
            lam_l, lam_u, mu_l, mu_u = mult["lower"], mult["upper"], mult["slack_lower"], mult["slack_upper"]
            stat_s = max(float(np.max(np.abs(w - lam_l - mu_l), initial=0.0)),
                         float(np.max(np.abs(w - lam_u - mu_u), initial=0.0)))
            stationarity = max(stationarity, stat_s / (1.0 + w))
            parts = [lam_l * (y - lo + s_l), lam_u * (hi + s_u - y), mu_l * s_l, mu_u * s_u,
                     np.minimum(lam_l, 0.0), np.minimum(lam_u, 0.0), np.minimum(mu_l, 0.0), np.minimum(mu_u, 0.0)]
            comp_soft = max(float(np.max(np.abs(v), initial=0.0)) for v in parts) / (1.0 + w)
        # complementarity: a multiplier pushes only on an active bound (> 0 at the upper one)
        lam_scale = 1.0 + max(float(np.max(np.abs(lam))), float(np.max(np.abs(mult["tau"]))))
        comp = float(np.max(np.abs(np.where(mult["tau"] > 0, mult["tau"] * (pr.tau_max - U),
                                             -mult["tau"] * (U + pr.tau_max)))))
        if pr.state_limits == "hard":
            hi = np.concatenate([pr.q_max, pr.qd_max])
            lo = np.concatenate([pr.q_min, -pr.qd_max])
            mx = mult["x"]
            with np.errstate(invalid="ignore"):                 # 0 · inf where a limit is absent
                gap = np.where(mx > 0, mx * (hi - X[1:]), -mx * (X[1:] - lo))
            gap = np.where(np.isfinite(gap), gap, np.where(mx == 0, 0.0, np.inf))
            comp = max(comp, float(np.max(np.abs(gap))))
        return max(stationarity, comp / lam_scale, comp_soft)


def solve_optimal_control(problem: OptimalControlProblem, x0: Any, options: OptimalControlOptions | None = None,
                          **references: Any) -> OptimalControlResult:
    """Build the solver of ``problem`` and solve it once from ``x0`` (``references``: q_ref, qd_ref, tau_ref, T_d,
    warm_start; see :meth:`OptimalControlSolver.solve`). Build an :class:`OptimalControlSolver` to solve many times."""
    return OptimalControlSolver(problem, options).solve(x0, **references)
