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
B_k = ∂Φ/∂τ and the cost residuals with their Jacobians, one CasADi function generated as C, compiled once per
model content and cached — and solves the quadratic program of the step with HPIPM (a Riccati-recursion interior
point method that works stage by stage: its cost grows like N, not N³), then an Armijo line search on the L1 merit
function. Measured on the Panda reach (N = 50): a dense or general sparse QP per iteration (proxsuite's sparse
backend, OSQP, qrqp) took 10–20 times HPIPM's time, CasADi's FATROP with an expanded NLP minutes, IPOPT's
exact Hessian of the RK4 dynamics is the costliest expression of all (``benchmarks/bench_mpc.py``). Warm start from a
previous result (shifted for MPC), a trajectory, or the state held at rest with gravity torques.

Success is decided independently of the iterations, as the IK does: at the returned solution Pinocchio (not the
CasADi model) integrates every interval, differentiates the dynamics and the costs, and the KKT conditions —
stationarity of the Lagrangian with the solver's multipliers, primal feasibility (defects, every hard limit),
complementarity — must hold within ``tol``.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 4.2, 7.2–7.5,
8.5 (Eq. (7.42)); Bock & Plitt, IFAC 1984 (multiple shooting); Frison & Diehl, IFAC 2020 (HPIPM);
Diehl et al., SIAM J. Control Optim. 43 (2005) (real-time iteration).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np
import pinocchio as pin

from planners.optimization import OptimalTrajectory
from planners.timing import PiecewisePolynomial, Trajectory
from rigid_body.robots import Robot
from rigid_body.symbolic import forward_dynamics_expression, frame_placement, model_digest, rotation_log_expression
from rigid_body.validation import as_positive, as_vector

__all__ = [
    "StageCost", "OptimalControlProblem", "OptimalControlOptions", "OptimalControlResult", "OptimalControlSolver",
    "solve_optimal_control", "rk4_step",
]

STATE_LIMITS = ("hard", "soft")
QP_BOUND = 1e4
"""Bounds of the step QP beyond this are absent: [rad | rad/s] for the states, τ_max for the torques."""
RK4_WEIGHTS = (1.0 / 6.0, 2.0 / 6.0, 2.0 / 6.0, 1.0 / 6.0)


def rk4_step(f: Any, x: Any, u: Any, h: Any) -> tuple[Any, list]:
    """One classical Runge–Kutta step of ẋ = f(x, u) with u held: (x_next, [s_1 … s_4]) the result and the four stage
    states. The same arithmetic on numpy arrays (the independent check) and on CasADi expressions (the transcription)."""
    s1 = x
    k1 = f(s1, u)
    s2 = x + 0.5 * h * k1
    k2 = f(s2, u)
    s3 = x + 0.5 * h * k2
    k3 = f(s3, u)
    s4 = x + h * k3
    k4 = f(s4, u)
    return x + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4), [s1, s2, s3, s4]


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
        """Indices of the joints with finite position limits and with finite speed limits."""
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

    def __post_init__(self) -> None:
        for name in ("max_iter", "qp_max_iter"):
            v = getattr(self, name)
            if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)) or v < 1:
                raise ValueError(f"`{name}` must be an integer >= 1, got {v!r}")
        for name in ("tol", "step_tol", "qp_tol"):
            as_positive(getattr(self, name), name)
        as_positive(self.limit_tol, "limit_tol", allow_zero=True)
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
        excess; iterations : SQP iterations; solve_time : wall time of the SQP (the check apart: check_time).
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

    def __repr__(self) -> str:
        ratios = ", ".join(f"{k} {v:.3g}" for k, v in self.ratios.items())
        return (f"OptimalControlResult(N={len(self.u)}, dt={self.dt:g} s, cost={self.cost:.6g}, success={self.success}, "
                f"KKT {self.kkt:.2g}, defect {self.defect:.2g}, limit ratios: {ratios}, {self.iterations} SQP "
                f"iterations in {self.solve_time * 1e3:.3g} ms, message={self.message!r})")

    def shifted(self, steps: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """(x, u) moved ``steps`` intervals ahead, the last values repeated: the warm start of the next sample."""
        x = np.concatenate([self.x[steps:], np.repeat(self.x[-1:], steps, axis=0)])
        u = np.concatenate([self.u[steps:], np.repeat(self.u[-1:], steps, axis=0)])
        return x, u


# --------------------------------------------------------------------------------------------
# The transcription: one interval's linearisation, generated as C
# --------------------------------------------------------------------------------------------

def _parameter_size(n: int) -> int:
    """Per-node parameters: dt, q_ref, q̇_ref, τ_ref, p_d (3), vec R_d (9), √w_q, √w_q̇, √w_τ, √w_p, √w_o."""
    return 1 + 3 * n + 12 + 3 * n + 2


def _unpack(p: Any, n: int) -> dict[str, Any]:
    k = 0
    out = {}
    for name, size in (("dt", 1), ("q_ref", n), ("qd_ref", n), ("tau_ref", n), ("p_d", 3), ("R_d", 9), ("sw_q", n),
                       ("sw_qd", n), ("sw_tau", n), ("sw_p", 1), ("sw_o", 1)):
        out[name] = p[k:k + size]
        k += size
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


_FUNCTIONS: dict[tuple, tuple] = {}


def _functions(robot: Robot, frame: int, position: bool, orientation: bool) -> tuple:
    """(stage, stage_value, terminal, terminal_value): the compiled interval and terminal functions, built once per
    (model content, frame, pose terms).

    stage (x, u, p) → (Φ(x, u), r, ∂[Φ; r]/∂[x; u]); stage_value (x, u, p) → (Φ, r); terminal (x, p) → (r_N, ∂r_N/∂x)
    and terminal_value (x, p) → r_N, with ½‖r‖² the interval's cost (RK4 quadrature) and ½‖r_N‖² the terminal one.
    """
    key = (model_digest(robot.model), frame, position, orientation)
    cached = _FUNCTIONS.get(key)
    if cached is not None:
        return cached
    from controllers.compiled import compile_function  # the C code cache (one home, in the compiled loop's module)

    n = robot.nv
    x, u, p = ca.SX.sym("x", 2 * n), ca.SX.sym("u", n), ca.SX.sym("p", _parameter_size(n))
    P = _unpack(p, n)

    def f(xs: Any, us: Any) -> Any:
        return ca.vertcat(xs[n:], forward_dynamics_expression(robot, xs[:n], xs[n:], us))

    x_next, stages = rk4_step(f, x, u, P["dt"])
    r = ca.vertcat(*[ca.sqrt(c * P["dt"]) * _state_residual(robot, frame, s, P, position, orientation)
                     for c, s in zip(RK4_WEIGHTS, stages)],
                   ca.sqrt(P["dt"]) * P["sw_tau"] * (u - P["tau_ref"]))
    z = ca.vertcat(x, u)
    out = ca.vertcat(x_next, r)
    tag = f"{'p' if position else ''}{'o' if orientation else ''}"
    stage = ca.Function(f"ocp_stage{tag}", [x, u, p], [x_next, r, ca.jacobian(out, z)])
    stage_value = ca.Function(f"ocp_value{tag}", [x, u, p], [x_next, r])
    r_N = _state_residual(robot, frame, x, P, position, orientation)
    terminal = ca.Function(f"ocp_terminal{tag}", [x, p], [r_N, ca.jacobian(r_N, x)])
    terminal_value = ca.Function(f"ocp_terminal_value{tag}", [x, p], [r_N])
    built = tuple(compile_function(g) for g in (stage, stage_value, terminal, terminal_value))
    _FUNCTIONS[key] = built
    return built


class _Call:
    """A CasADi function called on numpy arrays without DM conversions (CasADi's function buffer): each argument's
    C-order data is the input's column-major nonzeros (a dense (r, c) input is given as its (c, r) transpose);
    returns the outputs as dense (rows, cols) arrays (copies)."""

    def __init__(self, function: ca.Function):
        self.function = function
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
        out = []
        for nz, rows, cols, shape, dense in self._outputs:
            if dense:
                out.append(nz.reshape(shape[1], shape[0]).T.copy())
            else:
                full = np.zeros(shape)
                full[rows, cols] = nz
                out.append(full)
        return out

    def stats(self) -> dict:
        """The statistics of the last call (a solver's iterations and status)."""
        return self._buffer.stats()


# --------------------------------------------------------------------------------------------
# The structured QP of one SQP step (HPIPM through CasADi's conic interface)
# --------------------------------------------------------------------------------------------

class _StepQP:
    """The QP of one SQP step, stage-wise as HPIPM takes it (x_0 given, so stage 0 has no state)::

        min ½ δᵀ H δ + gᵀ δ   s.t.  δx_{k+1} = A_k δx_k + B_k δτ_k + d_k,  soft-limit rows,  bounds,

    δτ in units of τ_max. With soft limits each node k >= 1 also has the slacks s_k >= 0 (absolute values, cost
    slack_weight each) as states, set by the controls v_{k−1} of the interval before (s_{k+1} = v_k), so that the
    rows q_j − s ≤ q_max, q_j + s ≥ q_min, q̇_j − s ≤ q̇_max, q̇_j + s ≥ −q̇_max are stage-wise as HPIPM needs.
    Stage k's variables: state [δx_k; s_k] (k >= 1), control [δτ_k; v_k] (k < N). The sparsity patterns are fixed
    at construction; each step fills their nonzeros from stacked blocks."""

    def __init__(self, N: int, n: int, soft_q: np.ndarray, soft_v: np.ndarray, options: OptimalControlOptions):
        nx = 2 * n
        self.N, self.n, self.nx = N, n, nx
        ns = soft_q.size + soft_v.size
        self.ns, self.soft_q, self.soft_v = ns, soft_q, soft_v
        idx, k0 = [], 0
        for k in range(N + 1):
            stage = {}
            for name, size in (("x", nx if k > 0 else 0), ("s", ns if k > 0 else 0), ("u", n if k < N else 0),
                               ("v", ns if k < N else 0)):
                stage[name] = np.arange(k0, k0 + size)
                k0 += size
            idx.append(stage)
        self.idx, self.nz = idx, k0
        rows, cols, src = [], [], []
        self._a_layout(rows, cols, src)
        self.A_sp, self.A_src = self._pattern(rows, cols, src, self.n_rows, self.nz)
        rows, cols, src, k = [], [], [], 0
        for stage in idx:                                  # dense blocks over (δx_k, δτ_k): Gauss–Newton's JᵀJ
            block = np.concatenate([stage["x"], stage["u"]])
            for i in block:
                for j in block:
                    rows.append(i)
                    cols.append(j)
                    src.append(k)
                    k += 1
        self.H_sp, self.H_src = self._pattern(rows, cols, src, self.nz, self.nz)
        structure = {"N": N, "nx": [0] + [nx + ns] * N, "nu": [n + ns] * N + [0], "ng": [0] + [2 * ns] * N}
        tol = options.qp_tol
        self.solver = ca.conic("ocp_step", "hpipm", {"h": self.H_sp, "a": self.A_sp},
                               {**structure, "error_on_fail": False,
                                "hpipm": {"mode": "robust", "iter_max": options.qp_max_iter, "res_g_max": tol,
                                          "res_b_max": tol, "res_d_max": tol, "res_m_max": tol}})

    def solve(self, h: np.ndarray, a: np.ndarray, **vectors: np.ndarray) -> tuple[dict[str, np.ndarray], dict]:
        """HPIPM on the nonzeros ``h``, ``a`` of the fixed patterns and the vectors g, lba, uba, lbx, ubx: the outputs
        by name (flat arrays) and the solver's statistics. (Called through DMs: CasADi's function buffer gave
        wrong steps from the second call of this conic on.)"""
        sol = self.solver(h=ca.DM(self.H_sp, h), a=ca.DM(self.A_sp, a), **vectors)
        return {name: np.asarray(sol[name]).ravel() for name in ("x", "lam_a", "lam_x")}, self.solver.stats()

    def _a_layout(self, rows: list, cols: list, src: list) -> None:
        """Rows [gap_0, gap_1, lincon_1, …, gap_{N−1}, lincon_{N−1}, lincon_N]; the value vector of
        :meth:`a_values` is [A_1…A_{N−1} (row-major blocks), B_0…B_{N−1}, constants]."""
        N, nx, n, ns, idx = self.N, self.nx, self.n, self.ns, self.idx
        n_A, n_B, n_I = (N - 1) * nx * nx, N * nx * n, N * nx
        n_L = N * 2 * ns
        constants: list[float] = []
        row = 0
        self.gap_rows, self.lincon_rows = [], []
        self._lincon_count = 0

        def constant(r: int, c: int, value: float) -> None:
            rows.append(r)
            cols.append(c)
            src.append(n_A + n_B + n_I + n_L + len(constants))
            constants.append(value)

        def scaled(r: int, c: int, position: int) -> None:
            rows.append(r)
            cols.append(c)
            src.append(position)

        for k in range(N):
            self.gap_rows.append(np.arange(row, row + nx + ns))
            for i in range(nx):
                if k > 0:
                    for j in range(nx):
                        rows.append(row + i)
                        cols.append(idx[k]["x"][j])
                        src.append((k - 1) * nx * nx + i * nx + j)
                for j in range(n):
                    rows.append(row + i)
                    cols.append(idx[k]["u"][j])
                    src.append(n_A + k * nx * n + i * n + j)
                scaled(row + i, idx[k + 1]["x"][i], n_A + n_B + k * nx + i)       # −d_x of x_{k+1}
            for i in range(ns):                              # s_{k+1} = v_k
                constant(row + nx + i, idx[k]["v"][i], 1.0)
                constant(row + nx + i, idx[k + 1]["s"][i], -1.0)
            row += nx + ns
            if ns and k > 0:
                row = self._lincons(k, row, constant, scaled, n_A + n_B + n_I)
        if ns:
            row = self._lincons(N, row, constant, scaled, n_A + n_B + n_I)
        self.n_rows = row
        self._constants = np.array(constants)
        self.targets = np.array([j for j in self.soft_q] + [self.n + j for j in self.soft_v], dtype=int)

    def _lincons(self, k: int, row: int, constant: Any, scaled: Any, offset: int) -> int:
        """The soft-limit rows of node k: for each limited quantity y_j (q_j, then q̇_j), y_j − s ≤ max, y_j + s ≥ min
        (y_j's coefficient is its variable scale)."""
        first = row
        x, s = self.idx[k]["x"], self.idx[k]["s"]
        targets = [j for j in self.soft_q] + [self.n + j for j in self.soft_v]
        for m, j in enumerate(targets):
            for sign in (-1.0, 1.0):
                scaled(row, x[j], offset + self._lincon_count)
                self._lincon_count += 1
                constant(row, s[m], sign)
                row += 1
        self.lincon_rows.append(np.arange(first, row))
        return row

    @staticmethod
    def _pattern(rows: list, cols: list, src: list, n_rows: int, n_cols: int) -> tuple[ca.Sparsity, np.ndarray]:
        """The CasADi pattern of the entries (rows, cols) and, for each nonzero in its column-major order, the index
        of its value in the stacked value vector."""
        rows, cols, src = np.asarray(rows), np.asarray(cols), np.asarray(src)
        order = np.lexsort((rows, cols))
        rows, cols, src = rows[order], cols[order], src[order]
        colind = np.searchsorted(cols, np.arange(n_cols + 1))
        return ca.Sparsity(n_rows, n_cols, colind.tolist(), rows.tolist()), src

    def a_values(self, A: np.ndarray, B: np.ndarray, Dx: np.ndarray) -> np.ndarray:
        """A's nonzeros from the scaled A_k (N, nx, nx) (A_0 unused: δx_0 = 0), B_k (N, nx, n) and the scales Dx
        (N, nx) of the states x_1 … x_N (the −I of x_{k+1} becomes −diag(Dx_k); the soft rows' coefficients)."""
        lincon = np.repeat(Dx[:, self.targets], 2, axis=1).ravel() if self.ns else np.zeros(0)
        return np.concatenate([A[1:].ravel(), B.ravel(), -Dx.ravel(), lincon, self._constants])[self.A_src]


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
        self._stage, self._stage_value = _Call(stage.map(N)), _Call(stage_value.map(N))
        self._stage_value_one = _Call(stage_value)
        self._terminal, self._terminal_value = _Call(terminal), _Call(terminal_value)
        if pr.state_limits == "soft":
            soft_q, soft_v = pr.limited()
        else:
            soft_q, soft_v = np.zeros(0, dtype=int), np.zeros(0, dtype=int)
        self._qp = _StepQP(N, n, soft_q, soft_v, self.options)
        self._gravity_data = pr.robot.model.createData()

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
            if T.shape != (N + 1, 4, 4) or not np.all(np.isfinite(T)):
                raise ValueError(f"`T_d` must be a finite (4, 4) pose or (N+1, 4, 4) poses, got shape {np.shape(T_d)}")
            R = T[:, :3, :3]
            if np.max(np.abs(R @ np.transpose(R, (0, 2, 1)) - np.eye(3))) > 1e-6 or np.any(np.linalg.det(R) < 0):
                raise ValueError("`T_d` must hold rotation matrices in its upper-left 3×3 block")

        def column(cost: StageCost, k: int, tau: np.ndarray) -> np.ndarray:
            return np.concatenate([[pr.dt], q_ref[k], qd_ref[k], tau, T[k, :3, 3], T[k, :3, :3].ravel(order="F"),
                                   np.sqrt(cost.q), np.sqrt(cost.qd), np.sqrt(cost.tau),
                                   [math.sqrt(cost.position), math.sqrt(cost.orientation)]])

        P = np.vstack([column(pr.running, k, tau_ref[k]) for k in range(N)])
        P_N = column(pr.terminal, N, np.zeros(n))
        return P, P_N

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
        for it in range(max_iter):
            Xn, R, Jac = self._stage(X[:-1], U, P)
            r_N, J_N = self._terminal(X[-1], P_N)
            step, mult, ok, qp_message = self._step(X, U, Xn, R, Jac, r_N.ravel(), J_N)
            iterations += 1
            if not ok:
                message = f"the QP of SQP iteration {it + 1} failed ({qp_message})"
                status = "qp failure"
                break
            if qp_message:
                qp_notes.add(qp_message)
            dX, dU, S = step
            size = max(float(np.max(np.abs(dX), initial=0.0)), float(np.max(np.abs(dU) / tau_max, initial=0.0)))
            defect = float(np.max(np.abs(Xn.T - X[1:])))
            rho = max(rho, 1.5 * float(np.max(np.abs(mult["gap"]), initial=0.0)))
            alpha = self._line_search(X, U, dX, dU, S, P, P_N, R, Jac, r_N.ravel(), J_N, Xn, rho)
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
        return self._result(X, U, P, P_N, mult, converged, message, iterations, solve_time, status)

    def predict(self, x: Any, tau: Any) -> np.ndarray:
        """Φ(x, τ): the state one interval dt after x under the held torque τ, by the problem's model (the same RK4
        step as the transcription)."""
        column = np.zeros(_parameter_size(self.n))
        column[0] = self.problem.dt
        x_next, _ = self._stage_value_one(as_vector(x, self.nx, "x"), as_vector(tau, self.n, "tau"), column)
        return np.asarray(x_next).ravel()

    def _check_start(self, x0: np.ndarray) -> None:
        pr, n = self.problem, self.n
        q, qd = x0[:n], x0[n:]
        bad = np.flatnonzero((q < pr.q_min) | (q > pr.q_max) | (np.abs(qd) > pr.qd_max))
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

    def _step(self, X: np.ndarray, U: np.ndarray, Xn: np.ndarray, R: np.ndarray, Jac: np.ndarray, r_N: np.ndarray,
              J_N: np.ndarray) -> tuple:
        """Solve the QP of the step at (X, U): ((δX (N, 2n), δU (N, n), S (N, ns)), multipliers, ok, message).

        Each variable is scaled by 1/√(its Hessian diagonal) (Jacobi scaling: the scaled Hessian has a unit diagonal),
        so that HPIPM's absolute tolerances mean the same on a 12 N·m wrist and on a 10⁶ N·m bound."""
        pr, n, N, nx, qp = self.problem, self.n, self.N, self.nx, self._qp
        nz = nx + n
        J = Jac.reshape(nx + R.shape[0], N, nz).transpose(1, 0, 2)          # (N, nx + nr, nz)
        A, B, Jr = J[:, :nx, :nx], J[:, :nx, nx:], J[:, nx:, :]
        H = np.matmul(np.transpose(Jr, (0, 2, 1)), Jr)                        # Gauss–Newton: JᵀJ, (N, nz, nz)
        g = np.einsum("kri,kr->ki", Jr, R.T)
        H_N, g_N = J_N.T @ J_N, J_N.T @ r_N
        diag = np.vstack([np.diagonal(H, axis1=1, axis2=2), np.concatenate([np.diag(H_N), np.zeros(n)])])
        top = max(float(np.max(diag)), 1e-12)
        D = 1.0 / np.sqrt(np.maximum(diag, 1e-8 * top))                      # (N+1, nz): x_k, τ_k scales
        D_x, D_u = D[1:, :nx], D[:N, nx:]                                     # x_1..x_N, τ_0..τ_{N−1}
        Hs = H * D[:N, :, None] * D[:N, None, :]
        H_Ns = H_N * D_x[-1][:, None] * D_x[-1][None, :]
        h_values = np.concatenate([Hs[0, nx:, nx:].ravel(), Hs[1:].ravel(), H_Ns.ravel()])
        As, Bs = A * D[:N, None, :nx], B * D_u[:, None, :]
        ns = qp.ns
        g_full = np.zeros(qp.nz)
        g_full[qp.idx[0]["u"]] = g[0, nx:] * D_u[0]
        for k in range(1, N):
            g_full[qp.idx[k]["x"]] = g[k, :nx] * D_x[k - 1]
            g_full[qp.idx[k]["u"]] = g[k, nx:] * D_u[k]
        g_full[qp.idx[N]["x"]] = g_N * D_x[-1]
        lbx, ubx = np.full(qp.nz, -np.inf), np.full(qp.nz, np.inf)
        for k in range(N):
            lbx[qp.idx[k]["u"]] = (-pr.tau_max - U[k]) / D_u[k]
            ubx[qp.idx[k]["u"]] = (pr.tau_max - U[k]) / D_u[k]
        q_lo, q_hi, v_hi = pr.q_min, pr.q_max, pr.qd_max
        lba, uba = np.full(qp.n_rows, -np.inf), np.full(qp.n_rows, np.inf)
        d = Xn.T - X[1:]                                                      # defects (N, nx)
        for k in range(N):
            lba[qp.gap_rows[k][:nx]] = uba[qp.gap_rows[k][:nx]] = -d[k]
            lba[qp.gap_rows[k][nx:]] = uba[qp.gap_rows[k][nx:]] = 0.0
        for k in range(1, N + 1):
            xk = X[k]
            if pr.state_limits == "hard":
                lbx[qp.idx[k]["x"]] = (np.concatenate([q_lo, -v_hi]) - xk) / D_x[k - 1]
                ubx[qp.idx[k]["x"]] = (np.concatenate([q_hi, v_hi]) - xk) / D_x[k - 1]
            elif ns:
                s = qp.idx[k]["s"]
                lbx[s], ubx[s] = 0.0, np.inf
                g_full[s] = pr.slack_weight
                rows = qp.lincon_rows[k - 1]
                bounds = []
                for j in qp.soft_q:
                    bounds += [(-np.inf, q_hi[j] - xk[j]), (q_lo[j] - xk[j], np.inf)]
                for j in qp.soft_v:
                    bounds += [(-np.inf, v_hi[j] - xk[n + j]), (-v_hi[j] - xk[n + j], np.inf)]
                lba[rows], uba[rows] = np.array(bounds).T
        big = QP_BOUND                      # CasADi's HPIPM interface clips infinite bounds by wrong counts: none given
        sol, stats = qp.solve(h=h_values[qp.H_src], g=g_full, a=qp.a_values(As, Bs, D_x), lba=np.maximum(lba, -big),
                              uba=np.minimum(uba, big), lbx=np.maximum(lbx, -big), ubx=np.minimum(ubx, big))
        z = sol["x"]
        if not np.all(np.isfinite(z)):
            return None, {}, False, f"non-finite step, HPIPM status {stats.get('return_status')}"
        ok = bool(stats.get("success", False))
        dX = np.stack([z[qp.idx[k]["x"]] for k in range(1, N + 1)]) * D_x
        dU = np.stack([z[qp.idx[k]["u"]] for k in range(N)]) * D_u
        S = np.stack([z[qp.idx[k]["s"]] for k in range(1, N + 1)]) if ns else np.zeros((N, 0))
        lam_a, lam_x = sol["lam_a"], sol["lam_x"]
        mult = {"gap": np.stack([lam_a[qp.gap_rows[k][:nx]] for k in range(N)]),
                "tau": np.stack([lam_x[qp.idx[k]["u"]] for k in range(N)]) / D_u,
                "x": np.stack([lam_x[qp.idx[k]["x"]] for k in range(1, N + 1)]) / D_x,
                "slack": S,
                "slack_bound": np.stack([lam_x[qp.idx[k]["s"]] for k in range(1, N + 1)]) if ns else np.zeros((N, 0)),
                "soft": np.stack([lam_a[r] for r in qp.lincon_rows]) if ns else np.zeros((N, 0))}
        return (dX, dU, S), mult, True, "" if ok else f"HPIPM status {stats.get('return_status')}"

    def _merit(self, X: np.ndarray, U: np.ndarray, P: np.ndarray, P_N: np.ndarray, rho: float) -> tuple[float, float]:
        """(cost, L1 merit = cost + soft-limit penalty + ρ Σ |defects|) at (X, U)."""
        Xn, R = self._stage_value(X[:-1], U, P)
        r_N = self._terminal_value(X[-1], P_N)[0].ravel()
        cost = 0.5 * float(np.sum(R * R) + r_N @ r_N)
        penalty = self.problem.slack_weight * self._excess(X) if self.problem.state_limits == "soft" else 0.0
        return cost, cost + penalty + rho * float(np.sum(np.abs(Xn.T - X[1:])))

    def _excess(self, X: np.ndarray) -> float:
        """Σ over nodes 1..N and limited joints of the amount by which q and |q̇| leave their limits."""
        pr, n = self.problem, self.n
        q, v = X[1:, :n], X[1:, n:]
        over = np.maximum(q - pr.q_max, 0.0) + np.maximum(pr.q_min - q, 0.0)
        fast = np.maximum(np.abs(v) - pr.qd_max, 0.0)
        return float(np.sum(over[np.isfinite(over)]) + np.sum(fast[np.isfinite(fast)]))

    def _line_search(self, X, U, dX, dU, S, P, P_N, R, Jac, r_N, J_N, Xn, rho) -> float:
        """Armijo backtracking on the L1 merit along the step; its directional derivative from the linearisation."""
        pr, n, N, nx = self.problem, self.n, self.N, self.nx
        cost0 = 0.5 * float(np.sum(R * R) + r_N @ r_N)
        penalty0 = pr.slack_weight * self._excess(X) if pr.state_limits == "soft" else 0.0
        defects = float(np.sum(np.abs(Xn.T - X[1:])))
        merit0 = cost0 + penalty0 + rho * defects
        J = Jac.reshape(nx + R.shape[0], N, nx + n).transpose(1, 0, 2)[:, nx:, :]
        dz = np.concatenate([np.vstack([np.zeros(nx), dX[:-1]]), dU], axis=1)   # (N, nz): δx_k, δτ_k
        slope = float(np.einsum("kr,krz,kz->", R.T, J, dz) + r_N @ (J_N @ dX[-1]))
        slope += (pr.slack_weight * float(np.sum(S)) - penalty0) if pr.state_limits == "soft" else 0.0
        slope -= rho * defects
        alpha = 1.0
        for _ in range(30):
            trial = self._merit(np.vstack([X[:1], X[1:] + alpha * dX]), U + alpha * dU, P, P_N, rho)[1]
            if trial <= merit0 + 1e-4 * alpha * min(slope, 0.0) or trial <= merit0 - 1e-12 * abs(merit0) \
                    and slope >= 0:
                return alpha
            alpha *= 0.5
        return alpha

    # ---- the result and its independent check ----------------------------------------------------------------
    def _result(self, X: np.ndarray, U: np.ndarray, P: np.ndarray, P_N: np.ndarray, mult: dict, converged: bool,
                message: str, iterations: int, solve_time: float, status: str) -> OptimalControlResult:
        pr, n, N, o = self.problem, self.n, self.N, self.options
        robot = pr.robot
        cost, _ = self._merit(X, U, P, P_N, 0.0)
        penalty = self._excess(X)
        if pr.state_limits == "soft":
            cost += pr.slack_weight * penalty
        check_start = time.perf_counter()
        check = _KKTCheck(pr, P, P_N)
        qdd = check.accelerations(X, U)
        if o.verify:
            defect = check.defects(X, U)
        else:                               # the solver's own defect (the real-time loops skip Pinocchio's)
            Xn, _ = self._stage_value(X[:-1], U, P)
            defect = float(np.max(np.abs(Xn.T - X[1:])))
            defect = defect if np.isfinite(defect) else math.inf
        kkt = check.residual(X, U, mult) if (o.verify and converged and mult) else math.nan
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
                                    slack=penalty, check_time=check_time, multipliers=mult)


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
    """The KKT conditions of the solution evaluated with Pinocchio: integration by :func:`rk4_step` of
    :func:`rigid_body.dynamics.forward_dynamics`, its derivatives from RNEA's (Pinocchio's analytical ones, central
    differences on models with rotors, which Pinocchio's derivatives refuse), the pose costs from Pinocchio's
    kinematics, ``log3`` and ``Jlog3``."""

    def __init__(self, problem: OptimalControlProblem, P: np.ndarray, P_N: np.ndarray):
        self.pr, self.P, self.P_N = problem, P, P_N
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
            x_next, _ = rk4_step(self._fd, X[k], U[k], self.pr.dt)
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
        """Φ(x, u), ∂Φ/∂[x; u], the RK4 stage states and their Jacobians ∂s_i/∂[x; u] (chain rule of rk4_step)."""
        n, h = self.n, self.pr.dt
        nx, nz = 2 * n, 3 * n
        I = np.eye(nx, nz)
        du = np.zeros((n, nz))
        du[:, nx:] = np.eye(n)
        states, jacobians, ks, dks = [], [], [], []
        s, ds = x, I
        for c in (0.5, 0.5, 1.0, None):
            k, Jf = self._fd_jacobian(s, u)
            dk = Jf @ np.vstack([ds, du])
            states.append(s)
            jacobians.append(ds)
            ks.append(k)
            dks.append(dk)
            if c is not None:
                s, ds = x + c * h * k, I + c * h * dk
        x_next = x + h / 6.0 * (ks[0] + 2 * ks[1] + 2 * ks[2] + ks[3])
        dx_next = I + h / 6.0 * (dks[0] + 2 * dks[1] + 2 * dks[2] + dks[3])
        return x_next, dx_next, states, jacobians

    def _state_gradient(self, x: np.ndarray, p: np.ndarray) -> np.ndarray:
        """∂/∂x of ½‖r(x)‖², r the state and pose residual with the parameter column p."""
        n = self.n
        q, v = x[:n], x[n:]
        q_ref, qd_ref = p[1:1 + n], p[1 + n:1 + 2 * n]
        p_d, R_d = p[1 + 3 * n:4 + 3 * n], p[4 + 3 * n:13 + 3 * n].reshape(3, 3, order="F")
        w_q, w_qd = p[13 + 3 * n:13 + 4 * n] ** 2, p[13 + 4 * n:13 + 5 * n] ** 2
        w_p, w_o = p[13 + 6 * n] ** 2, p[14 + 6 * n] ** 2
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
            w_tau = p[13 + 5 * n:13 + 6 * n] ** 2
            g[nx:] += h * w_tau * (U[k] - p[1 + 2 * n:1 + 3 * n])
            grad_x[k] += g[:nx]
            grad_u[k] = g[nx:]
            stat_x[k] += g[:nx] + dPhi[:, :nx].T @ lam[k]
            stat_u[k] = g[nx:] + dPhi[:, nx:].T @ lam[k] + mult["tau"][k]
            stat_x[k + 1] -= lam[k]
        gN = self._state_gradient(X[N], self.P_N)
        grad_x[N] += gN
        stat_x[N] += gN
        stat_x[1:] += mult["x"]
        soft = pr.state_limits == "soft" and mult["soft"].size
        if soft:                                # lincons q_j ∓ s ≤/≥ limits: ∂/∂x of ν (q_j ∓ s) is ν e_j
            m = 0
            for offset, joints in ((0, np.flatnonzero(np.isfinite(pr.q_min))), (n, np.flatnonzero(np.isfinite(pr.qd_max)))):
                for j in joints:
                    stat_x[1:, offset + j] += mult["soft"][:, 2 * m] + mult["soft"][:, 2 * m + 1]
                    m += 1
        scale = 1.0 + max(float(np.max(np.abs(grad_x))), float(np.max(np.abs(grad_u))))
        stationarity = max(float(np.max(np.abs(stat_x[1:]))), float(np.max(np.abs(stat_u)))) / scale
        comp_soft = 0.0
        if soft:                                # slacks: w_s − ν_upper + ν_lower + μ_s = 0, s ≥ 0, rows complementary
            nu_, S, mu_s = mult["soft"], mult["slack"], mult["slack_bound"]
            stat_s = pr.slack_weight - nu_[:, 0::2] + nu_[:, 1::2] + mu_s
            stationarity = max(stationarity, float(np.max(np.abs(stat_s))) / (1.0 + pr.slack_weight))
            joints = [j for j in np.flatnonzero(np.isfinite(pr.q_min))] + \
                     [n + j for j in np.flatnonzero(np.isfinite(pr.qd_max))]
            hi = np.concatenate([pr.q_max, pr.qd_max])
            lo = np.concatenate([pr.q_min, -pr.qd_max])
            y = X[1:][:, joints]
            upper = np.where(nu_[:, 0::2] > 0, nu_[:, 0::2] * (hi[joints] - (y - S)), 0.0)
            lower = np.where(nu_[:, 1::2] < 0, -nu_[:, 1::2] * (y + S - lo[joints]), 0.0)
            at_zero = np.where(mu_s < 0, -mu_s * S, 0.0)
            comp_soft = max(float(np.max(np.abs(upper))), float(np.max(np.abs(lower))), float(np.max(np.abs(at_zero))))
            comp_soft /= 1.0 + pr.slack_weight
        # complementarity: a multiplier pushes only on an active bound (CasADi's sign: > 0 at the upper one)
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
