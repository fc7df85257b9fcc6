"""Optimal point-to-point joint trajectories with CasADi and IPOPT (beyond the book's Chapter 4).

Transcription: multiple shooting of the joint-space chain of integrators. On N intervals the
highest derivative u is constant — the acceleration (``order=2``: C¹ motion with acceleration
jumps, like the book's trapezoid (4.8)) or the jerk (``order=3``: C² motion, continuous torques) —
so between the nodes the motion is *exactly* the polynomial

    q(t_k + τ) = q_k + q̇_k τ + u_k τ²/2            (order 2)
    q(t_k + τ) = q_k + q̇_k τ + q̈_k τ²/2 + u_k τ³/6   (order 3)

and the shooting constraints (node k+1 = that polynomial at τ = h_k) carry no integration error.
The result is a :class:`~planners.timing.PiecewisePolynomial`, a timing law like the book's.
Interval k lasts h_k = σ_k T with fixed fractions σ_k: uniform for a given duration; for minimum
time the mesh of the warm start, the fastest synchronised trapezoid within the same limits
(:func:`trapezoidal_under_limits`), whose phase changes are nodes — so that trapezoid is a
feasible point of the transcription and the optimum can only be faster.

Limits: joint positions, velocities, accelerations and torques, the torques from the CasADi
Newton–Euler :func:`rigid_body.symbolic.inverse_dynamics_function` generated from the
``pin.Model``. They are imposed at the start, middle and end of every interval. After the solve
every limit is checked on a fine grid (``options.subsamples`` points per interval) with the
*numeric* Pinocchio RNEA; where a limit is exceeded between the constraint points, that bound is
tightened by the excess and the problem re-solved (back-off), so a result reported as a success
satisfies every limit on the fine grid.

Objectives: minimum time T (plus a small control regularisation), minimum effort ∫ τ^T W τ dt
with W = diag(1/τ_max²), minimum jerk ∫ j^T j dt, the last two for a given duration.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 4.2 (timing laws, (4.8)), Sect. 7.5 (Newton–Euler); Betts, *Practical Methods for Optimal
Control*, SIAM 2010 (direct transcription).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np
import pinocchio as pin

from planners.timing import PiecewisePolynomial, Trajectory, quintic_law, sample, trapezoidal_law
from rigid_body.robots import Robot
from rigid_body.symbolic import inverse_dynamics_function, model_digest
from rigid_body.validation import as_positive, as_vector

__all__ = [
    "JointLimits", "OptimizationOptions", "OptimalTrajectory", "minimum_time_trajectory",
    "minimum_effort_trajectory", "minimum_jerk_trajectory", "limit_ratios", "trapezoidal_under_limits",
]

LIMIT_KINDS = ("q", "qd", "qdd", "tau")
HESSIANS = ("limited-memory", "exact")


@dataclass(frozen=True)
class JointLimits:
    """Box limits per joint: q ∈ [q_min, q_max] [rad | m], |q̇| ≤ qd_max, |q̈| ≤ qdd_max, |τ| ≤ tau_max.

    A joint without position limits has q_min = −inf and q_max = +inf (both, or neither: a one-sided
    infinite limit is refused); qd_max and tau_max may be +inf (no limit; minimum effort needs finite
    torque limits); qdd_max must be finite (it bounds every motion, and minimum time needs it).
    """

    q_min: np.ndarray
    q_max: np.ndarray
    qd_max: np.ndarray
    qdd_max: np.ndarray
    tau_max: np.ndarray

    def __post_init__(self) -> None:
        n = np.size(self.q_min)
        for name in ("q_min", "q_max", "qd_max", "qdd_max", "tau_max"):
            try:
                v = np.asarray(getattr(self, name), dtype=float)
            except (TypeError, ValueError):
                raise ValueError(f"`{name}` must be numeric, got {getattr(self, name)!r}") from None
            v = np.full(n, float(v)) if v.ndim == 0 else v
            if v.shape != (n,) or np.any(np.isnan(v)):
                raise ValueError(f"`{name}` must have shape ({n},) and no NaN, got {v}")
            object.__setattr__(self, name, v)
        if np.any(self.q_min == np.inf) or np.any(self.q_max == -np.inf):
            raise ValueError(f"`q_min` must not be +inf nor `q_max` -inf, got {self.q_min}, {self.q_max}")
        one_sided = np.isfinite(self.q_min) != np.isfinite(self.q_max)
        if np.any(one_sided):
            j = int(np.flatnonzero(one_sided)[0])
            raise ValueError(f"joint {j} has one infinite position limit (`q_min` = {self.q_min[j]}, `q_max` = "
                             f"{self.q_max[j]}): give both finite, or both infinite for an unbounded joint")
        if np.any(self.q_min >= self.q_max):
            raise ValueError("`q_min` must be below `q_max` for every joint")
        for name in ("qd_max", "qdd_max", "tau_max"):
            if np.any(getattr(self, name) <= 0):
                raise ValueError(f"`{name}` must be positive, got {getattr(self, name)}")
        if not np.all(np.isfinite(self.qdd_max)):
            raise ValueError(f"`qdd_max` must be finite (it bounds every motion), got {self.qdd_max}")

    def position_box(self, scale: Any = 1.0) -> tuple[np.ndarray, np.ndarray]:
        """(mid, half) of the position box, the half-width multiplied by ``scale``; an unbounded joint
        has mid 0 and half +inf, so |q − mid|/half is its position ratio (0 when unbounded)."""
        bounded = np.isfinite(self.q_min)
        lo, hi = np.where(bounded, self.q_min, 0.0), np.where(bounded, self.q_max, 0.0)
        mid = 0.5 * (hi + lo)
        half = np.where(bounded, 0.5 * (hi - lo) * scale, np.inf)
        return mid, half

    @property
    def n(self) -> int:
        return self.q_min.size

    @staticmethod
    def from_robot(robot: Robot, qdd_max: Any, *, qd_max: Any = None, tau_max: Any = None) -> "JointLimits":
        """Position, velocity and effort limits of the URDF (overridable); accelerations given."""
        model = robot.model
        return JointLimits(model.lowerPositionLimit.copy(), model.upperPositionLimit.copy(),
                           model.velocityLimit.copy() if qd_max is None else qd_max, qdd_max,
                           model.effortLimit.copy() if tau_max is None else tau_max)


@dataclass(frozen=True)
class OptimizationOptions:
    """Transcription and solver settings.

    nodes : number of shooting intervals N (raised to the number of phases of the warm start).
    order : 2, piecewise-constant accelerations (C¹ motion, like the book's trapezoid), or 3,
        piecewise-constant jerk (C², continuous torques). Minimum jerk always uses 3.
    subsamples : points per interval of the verification grid.
    max_backoff : re-solves allowed when a limit is exceeded between the constraint points.
    regularization : weight ε of ∫ ‖u/u_ref‖² dt / T added to T in minimum time (u the control,
        u_ref its limit); the duration then exceeds the minimum by at most ~ε n T.
    tol, max_iter : IPOPT settings; verbose prints IPOPT's log.
    hessian : ``"limited-memory"`` (IPOPT's L-BFGS approximation of the Lagrangian's Hessian, the
        default) or ``"exact"``. The exact Hessian of the Newton–Euler torque constraints is the costliest
        expression of the NLP (1.4 million SX nodes for the UR5 with 20 intervals against 0.5 million for
        the constraint Jacobian): L-BFGS halves a repeated UR5 minimum-time solve (27 → 22 iterations, no
        Hessian evaluations, measured in ``benchmarks/bench_trajectories.py``) and the first one, with the
        same optimum within the solver tolerance.
    """

    nodes: int = 30
    order: int = 2
    subsamples: int = 20
    max_backoff: int = 4
    regularization: float = 1e-4
    tol: float = 1e-8
    max_iter: int = 2000
    verbose: bool = False
    hessian: str = "limited-memory"

    def __post_init__(self) -> None:
        for name, least in (("nodes", 2), ("subsamples", 2), ("max_backoff", 0), ("max_iter", 1)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < least:
                raise ValueError(f"`{name}` must be an integer >= {least}, got {v!r}")
        as_positive(self.regularization, "regularization", allow_zero=True)
        as_positive(self.tol, "tol")
        if self.order not in (2, 3):
            raise ValueError(f"`order` must be 2 or 3, got {self.order}")
        if self.hessian not in HESSIANS:
            raise ValueError(f"`hessian` must be one of {HESSIANS}, got {self.hessian!r}")
        if self.subsamples < 2:
            raise ValueError(f"`subsamples` must be at least 2, got {self.subsamples}")


@dataclass(frozen=True)
class OptimalTrajectory:
    """Result of a trajectory optimisation.

    trajectory : the optimum sampled on the verification grid (its ``law`` is the exact piecewise
        cubic); tau : (M, n) joint torques on that grid from Pinocchio's RNEA.
    t_f : duration [s]; objective : "time", "effort" or "jerk"; cost : its optimal value.
    success : IPOPT converged and every limit holds on the grid; message : why not, otherwise.
    ratios : for each limit kind, max over grid and joints of |value|/limit (1 = active).
    iterations : IPOPT iterations over all back-off rounds; solve_time : wall time [s].
    """

    trajectory: Trajectory
    tau: np.ndarray
    t_f: float
    objective: str
    cost: float
    success: bool
    message: str
    ratios: dict[str, float] = field(default_factory=dict)
    iterations: int = 0
    solve_time: float = 0.0

    def __repr__(self) -> str:
        """One line: objective, duration, cost, success, the active limits (not the samples)."""
        active = ", ".join(f"{k} {v:.3g}" for k, v in self.ratios.items())
        return (f"OptimalTrajectory(minimum {self.objective}: t_f={self.t_f:.4g} s, cost={self.cost:.4g}, "
                f"success={self.success}, limit ratios: {active or '-'}, {len(self.trajectory)} samples, "
                f"{self.iterations} IPOPT iterations in {self.solve_time:.2g} s)")


def limit_ratios(robot: Robot, trajectory: Trajectory, limits: JointLimits) -> tuple[dict[str, float], np.ndarray]:
    """max |value|/limit per kind on the trajectory's samples (positions relative to their box),
    and the torques (M, n) from Pinocchio's RNEA."""
    per_joint, tau = _per_joint_ratios(robot, trajectory, limits)
    return {k: float(np.max(v)) for k, v in per_joint.items()}, tau


def _torques(robot: Robot, trajectory: Trajectory) -> np.ndarray:
    """(M, n) joint torques of Pinocchio's RNEA on the trajectory's samples."""
    model, data = robot.model, robot.data
    return np.array([pin.rnea(model, data, q, qd, qdd)
                     for q, qd, qdd in zip(trajectory.q, trajectory.qd, trajectory.qdd)])


def _per_joint_ratios(robot: Robot, trajectory: Trajectory, limits: JointLimits,
                      kinematic_first: bool = False) -> tuple[dict[str, np.ndarray], np.ndarray | None]:
    """max over the samples of |value|/limit per kind and joint, and the torques. With
    ``kinematic_first``, the torques (the costly part) are skipped, ratio +inf and torques None, when a
    position, velocity or acceleration limit is already exceeded."""
    mid, half = limits.position_box()
    out = {"q": np.max(np.abs(trajectory.q - mid) / half, axis=0),
           "qd": np.max(np.abs(trajectory.qd) / limits.qd_max, axis=0),
           "qdd": np.max(np.abs(trajectory.qdd) / limits.qdd_max, axis=0)}
    if kinematic_first and any(np.any(v > 1.0) for v in out.values()):
        return {**out, "tau": np.full(limits.n, np.inf)}, None
    tau = _torques(robot, trajectory)
    out["tau"] = np.max(np.abs(tau) / limits.tau_max, axis=0)
    return out, tau


class _Transcription:
    """The NLP of one problem.

    Variables w = [T, X, U]: the duration T (fixed unless minimum time), the node states
    X = [q; q̇] (order 2) or [q; q̇; q̈] (order 3) and the constant control U of each interval
    (q̈ for order 2, the jerk for order 3). Interval k lasts h_k = σ_k T, the fractions σ_k given
    (the mesh of the warm start).
    """

    def __init__(self, robot: Robot, q_i: np.ndarray, q_f: np.ndarray, limits: JointLimits, objective: str,
                 t_f: float | None, mesh: np.ndarray, options: OptimizationOptions):
        n, N, r = robot.nv, mesh.size - 1, (3 if objective == "jerk" else options.order)
        self.n, self.N, self.order, self.objective = n, N, r, objective
        t_scale = float(mesh[-1] - mesh[0])
        self.sigma = np.diff(mesh) / t_scale
        u_ref = limits.qdd_max if r == 2 else limits.qdd_max / (t_scale / N)
        # What changes from one problem to the next is a parameter: the mesh fractions σ, the control
        # scale u_ref, 1/t_scale, 1/τ_max; the NLP and IPOPT's setup are cached per robot and options.
        self.parameters = np.concatenate([self.sigma, u_ref, [1.0 / max(t_scale, 1e-9)], 1.0 / limits.tau_max])
        self.solver, self.cost_function, self.n_shooting = _transcription(robot, N, r, objective, options)
        self.q_i, self.q_f, self.limits, self.t_f = q_i, q_f, limits, t_f

    def bounds(self, scale: dict[str, np.ndarray], T_guess: float) -> dict[str, np.ndarray]:
        """Variable and constraint bounds with the limits multiplied by the back-off ``scale``."""
        n, N, r, L = self.n, self.N, self.order, self.limits
        mid, half = L.position_box(scale["q"])
        q_lo, q_hi = mid - half, mid + half
        v, a, u = L.qd_max * scale["qd"], L.qdd_max * scale["qdd"], L.tau_max * scale["tau"]
        lo_node = np.concatenate([q_lo, -v] + ([-a] if r == 3 else []))
        hi_node = -np.concatenate([-q_hi, -v] + ([-a] if r == 3 else []))
        lbX = np.tile(lo_node[:, None], (1, N + 1))
        ubX = np.tile(hi_node[:, None], (1, N + 1))
        lbX[:, 0] = ubX[:, 0] = np.concatenate([self.q_i, np.zeros((r - 1) * n)])  # rest to rest
        lbX[:, -1] = ubX[:, -1] = np.concatenate([self.q_f, np.zeros((r - 1) * n)])
        if self.t_f is None:
            lbh, ubh = [1e-3 * T_guess], [1e3 * T_guess]
        else:
            lbh = ubh = [self.t_f]
        big = np.inf
        lbU, ubU = (np.tile(-a, N), np.tile(a, N)) if r == 2 else (np.full(n * N, -big), np.full(n * N, big))
        return {"lbx": np.concatenate([lbh, lbX.ravel(order="F"), lbU]),
                "ubx": np.concatenate([ubh, ubX.ravel(order="F"), ubU]),
                "lbg": np.concatenate([np.zeros(self.n_shooting), np.tile(q_lo, N), np.tile(-v, N), np.tile(-u, 3 * N)]),
                "ubg": np.concatenate([np.zeros(self.n_shooting), np.tile(q_hi, N), np.tile(v, N), np.tile(u, 3 * N)])}

    def guess(self, law: Any, breaks: np.ndarray) -> np.ndarray:
        """Initial guess: a law at the mesh ``breaks`` (N+1 instants); controls from its midpoints."""
        n, r = self.n, self.order
        q, qd, qdd = (np.reshape(x, (self.N + 1, n)) for x in law(breaks))
        X = np.vstack([q.T, qd.T] + ([qdd.T] if r == 3 else []))
        h = np.diff(breaks)
        if r == 2:
            U = np.reshape(law(0.5 * (breaks[:-1] + breaks[1:]))[2], (self.N, n)).T
        else:
            U = np.diff(qdd.T, axis=1) / h
        return np.concatenate([[breaks[-1] - breaks[0]], X.ravel(order="F"), U.ravel(order="F")])

    def unpack(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        n, N, r = self.n, self.N, self.order
        h = w[0] * self.sigma
        X = w[1:1 + r * n * (N + 1)].reshape((r * n, N + 1), order="F")
        U = w[1 + r * n * (N + 1):].reshape((n, N), order="F")
        return h, X, U

    def coefficients(self, X: np.ndarray, U: np.ndarray) -> np.ndarray:
        """(N, 4, n) ascending coefficients of each interval's exact polynomial."""
        n = self.n
        q, qd = X[:n, :-1].T, X[n:2 * n, :-1].T
        if self.order == 2:
            return np.stack([q, qd, U.T / 2, np.zeros_like(q)], axis=1)
        return np.stack([q, qd, X[2 * n:, :-1].T / 2, U.T / 6], axis=1)


_TRANSCRIPTIONS: dict[tuple, tuple] = {}


def _transcription(robot: Robot, N: int, r: int, objective: str,
                   options: OptimizationOptions) -> tuple[ca.Function, ca.Function, int]:
    """(IPOPT solver, cost function, number of shooting constraints) of the NLP of :class:`_Transcription`,
    built once per (model content, N, order, objective, options) and reused — a model changed in place gets
    its own (:func:`rigid_body.symbolic.model_digest`): the parameters p are
    [σ (N), u_ref (n), 1/t_scale, 1/τ_max (n)]."""
    key = (model_digest(robot.model), N, r, objective, options.regularization, options.tol,
           options.max_iter, options.verbose, options.hessian)
    cached = _TRANSCRIPTIONS.get(key)
    if cached is not None:
        return cached
    n = robot.nv
    T = ca.SX.sym("T")
    sigma, u_ref = ca.SX.sym("sigma", N), ca.SX.sym("u_ref", n)
    inv_t_scale, inv_tau_max = ca.SX.sym("inv_t_scale"), ca.SX.sym("inv_tau_max", n)
    H = T * sigma
    X = ca.SX.sym("X", r * n, N + 1)
    U = ca.SX.sym("U", n, N)
    h = ca.transpose(H)  # (1, N), broadcast over the joints

    def taylor(tau: Any) -> list:
        """[q, q̇, q̈] at τ into every interval, from its start state and control (exact)."""
        d = [X[k * n:(k + 1) * n, :-1] for k in range(r)] + [U]  # q, q̇, (q̈,) u
        tau = ca.repmat(tau, n, 1)
        out = []
        for i in range(3):
            acc = 0
            for k in range(i, r + 1):
                acc = acc + d[k] * tau ** (k - i) / float(np.prod(np.arange(1, k - i + 1)))
            out.append(acc)
        return out

    end = taylor(h)
    mid = taylor(h / 2)
    start = [X[:n, :-1], X[n:2 * n, :-1], X[2 * n:3 * n, :-1] if r == 3 else U]
    shooting = ca.vertcat(*[ca.vec(X[k * n:(k + 1) * n, 1:] - end[k]) for k in range(r)])
    inverse_dynamics = inverse_dynamics_function(robot).map(3 * N)
    tau = inverse_dynamics(ca.horzcat(start[0], mid[0], end[0]), ca.horzcat(start[1], mid[1], end[1]),
                           ca.horzcat(start[2], mid[2], end[2]))  # (n, 3N): starts, mids, ends
    if objective == "time":
        # T + ε ∫ ‖u/u_ref‖² dt: a small control regularisation makes the optimum unique where
        # some joints are not time-critical (it costs at most ε·n·T in duration).
        cost = T + options.regularization * ca.sum2(h * ca.sum1((U / ca.repmat(u_ref, 1, N)) ** 2)) * inv_t_scale
    elif objective == "effort":
        sq = ca.sum1((tau * ca.repmat(inv_tau_max, 1, 3 * N)) ** 2)  # normalised, (1, 3N)
        cost = ca.sum2(h / 6 * (sq[:, :N] + 4 * sq[:, N:2 * N] + sq[:, 2 * N:]))  # Simpson
    else:  # jerk
        cost = ca.sum2(h * ca.sum1(U**2))
    w = ca.vertcat(T, ca.vec(X), ca.vec(U))
    p = ca.vertcat(sigma, u_ref, inv_t_scale, inv_tau_max)
    g = ca.vertcat(shooting, ca.vec(mid[0]), ca.vec(mid[1]), ca.vec(tau))
    cost_function = ca.Function("cost", [w, p], [cost])
    opts = {"ipopt.tol": options.tol, "ipopt.max_iter": options.max_iter,
            "ipopt.print_level": 5 if options.verbose else 0, "print_time": options.verbose,
            "ipopt.sb": "yes", "ipopt.hessian_approximation": options.hessian}
    solver = ca.nlpsol("trajectory_optimization", "ipopt", {"x": w, "f": cost, "g": g, "p": p}, opts)
    _TRANSCRIPTIONS[key] = (solver, cost_function, shooting.size1())
    return solver, cost_function, shooting.size1()


def _solution(h: np.ndarray, coeffs: np.ndarray, subsamples: int, name: str) -> Trajectory:
    """The exact piecewise polynomial, sampled on each closed interval (both sides of the
    acceleration jumps of order 2 appear, at equal instants)."""
    keep = h > 1e-12 * np.sum(h)  # collapsed intervals carry no motion
    h, coeffs = h[keep], coeffs[keep]
    breaks = np.concatenate([[0.0], np.cumsum(h)])
    law = PiecewisePolynomial(breaks, coeffs)
    tau = np.linspace(0.0, 1.0, subsamples)[None, :] * h[:, None]  # (K, s)
    t = (breaks[:-1, None] + tau).ravel()
    powers = tau[..., None] ** np.arange(4)  # (K, s, 4)
    q = np.einsum("ksj,kjn->ksn", powers, coeffs)
    qd = np.einsum("ksj,kjn->ksn", powers[..., :3], coeffs[:, 1:] * np.array([1, 2, 3])[None, :, None])
    qdd = np.einsum("ksj,kjn->ksn", powers[..., :2], coeffs[:, 2:] * np.array([2, 6])[None, :, None])
    n = coeffs.shape[2]
    return Trajectory(t, q.reshape(-1, n), qd.reshape(-1, n), qdd.reshape(-1, n), law, name)


def _mesh(breaks: np.ndarray, N: int) -> np.ndarray:
    """N+1 instants containing every instant of ``breaks`` (the phases of the warm start),
    the N intervals shared among the phases in proportion to their lengths."""
    phases = np.diff(breaks)
    counts = np.maximum(1, np.floor(phases / phases.sum() * N)).astype(int)
    while counts.sum() < N:
        counts[np.argmax(phases / counts)] += 1
    while counts.sum() > N:
        k = np.argmax(np.where(counts > 1, counts, 0))
        counts[k] -= 1
    return np.concatenate([np.linspace(a, b, c + 1)[:-1] for a, b, c in zip(breaks[:-1], breaks[1:], counts)]
                          + [[breaks[-1]]])


def _optimize(robot: Robot, q_i: Any, q_f: Any, limits: JointLimits, objective: str, t_f: float | None,
              options: OptimizationOptions | None) -> OptimalTrajectory:
    options = OptimizationOptions() if options is None else options
    n = robot.nv
    if robot.nq != robot.nv:
        raise ValueError("trajectory optimisation needs nq == nv (no continuous or free-flyer joints)")
    q_i = as_vector(q_i, n, "q_i")
    q_f = as_vector(q_f, n, "q_f")
    if limits.n != n:
        raise ValueError(f"`limits` are for {limits.n} joints, the robot has {n}")
    for name, q in (("q_i", q_i), ("q_f", q_f)):
        if np.any(q < limits.q_min) or np.any(q > limits.q_max):
            raise ValueError(f"`{name}` is outside the joint limits")
        g = pin.computeGeneralizedGravity(robot.model, robot.data, q)
        if np.any(np.abs(g) > limits.tau_max):
            raise ValueError(f"the gravity torques at `{name}` exceed `tau_max`: the arm cannot hold it")
    start = time.perf_counter()
    if t_f is None:  # warm start: the fastest synchronised trapezoid, its phases on the mesh
        first, _ = trapezoidal_under_limits(robot, q_i, q_f, limits)
        law = first.law
        nodes = max(options.nodes, law.breaks.size - 1)
        breaks = _mesh(law.breaks, nodes)
    else:
        nodes = options.nodes
        law = quintic_law(q_i, q_f, float(t_f))
        breaks = np.linspace(0.0, float(t_f), nodes + 1)
    nlp = _Transcription(robot, q_i, q_f, limits, objective, t_f, breaks, options)
    w0 = nlp.guess(law, breaks)
    scale = {k: np.ones(n) for k in LIMIT_KINDS}
    iterations, message, ok = 0, "", False
    for _ in range(options.max_backoff + 1):
        sol = nlp.solver(x0=w0, p=nlp.parameters, **nlp.bounds(scale, float(breaks[-1])))
        stats = nlp.solver.stats()
        iterations += int(stats.get("iter_count", 0))
        ok = bool(stats.get("success", False))
        w = np.asarray(sol["x"]).ravel()
        h, X, U = nlp.unpack(w)
        traj = _solution(h, nlp.coefficients(X, U), options.subsamples, f"minimum {objective}")
        per_joint, tau = _per_joint_ratios(robot, traj, limits)
        if not ok:
            message = f"IPOPT: {stats.get('return_status', 'failed')}"
            break
        if all(np.all(per_joint[k] <= 1.0 + 1e-6) for k in LIMIT_KINDS):
            message = "all limits hold on the verification grid"
            break
        message = "limits exceeded between constraint points after the last back-off"
        for k in LIMIT_KINDS:  # tighten each exceeded bound by its excess
            over = per_joint[k] > 1.0 + 1e-6
            scale[k] = np.where(over, scale[k] / per_joint[k] * (1.0 - 1e-4), scale[k])
        w0 = w
    ratios = {k: float(np.max(v)) for k, v in per_joint.items()}
    success = ok and all(v <= 1.0 + 1e-6 for v in ratios.values())
    return OptimalTrajectory(traj, tau, float(np.sum(h)), objective, float(nlp.cost_function(w, nlp.parameters)), success,
                             message, ratios, iterations, time.perf_counter() - start)


def minimum_time_trajectory(robot: Robot, q_i: Any, q_f: Any, limits: JointLimits,
                            options: OptimizationOptions | None = None) -> OptimalTrajectory:
    """The fastest rest-to-rest motion q_i → q_f within the joint limits (position, velocity,
    acceleration, torque). Warm-started from :func:`trapezoidal_under_limits`.

    The first call for a robot, number of intervals and options builds the CasADi transcription (≈ 1 s
    for the UR5 at 20 intervals, several seconds for the 7-DOF Panda); later calls reuse it (≈ 0.3 s for
    the UR5, ``benchmarks/bench_trajectories.py``). Along a path fixed in advance,
    :func:`planners.time_optimal.time_optimal_path` (TOPP-RA) takes milliseconds."""
    return _optimize(robot, q_i, q_f, limits, "time", None, options)


def minimum_effort_trajectory(robot: Robot, q_i: Any, q_f: Any, t_f: float, limits: JointLimits,
                              options: OptimizationOptions | None = None) -> OptimalTrajectory:
    """Rest-to-rest motion of duration t_f minimising ∫ Σ (τ_j/τ_max,j)² dt within the limits."""
    t_f = as_positive(t_f, "t_f")
    if not np.all(np.isfinite(limits.tau_max)):
        raise ValueError(f"minimum effort weighs the torques by 1/tau_max²: `tau_max` must be finite, got {limits.tau_max}")
    return _optimize(robot, q_i, q_f, limits, "effort", t_f, options)


def minimum_jerk_trajectory(robot: Robot, q_i: Any, q_f: Any, t_f: float, limits: JointLimits,
                            options: OptimizationOptions | None = None) -> OptimalTrajectory:
    """Rest-to-rest motion of duration t_f minimising ∫ ‖j‖² dt (j = d³q/dt³) within the limits.

    Without active limits this is the quintic of (4.3) (the minimum-jerk polynomial).
    """
    return _optimize(robot, q_i, q_f, limits, "jerk", as_positive(t_f, "t_f"), options)


def trapezoidal_under_limits(robot: Robot, q_i: Any, q_f: Any, limits: JointLimits, *,
                             samples: int = 601, tol: float = 1e-4) -> tuple[Trajectory, np.ndarray]:
    """The shortest synchronised trapezoidal profile (4.8) that satisfies all the limits.

    For a duration T every joint uses the cruise speed min(qd_max, 2|Δq|/T) (the least peak
    acceleration a trapezoid of duration T can have under the velocity limit); T is found by
    bisection on the feasibility of velocities, accelerations and the RNEA torques on ``samples``
    points. Returns the trajectory and its torques (samples, n).
    """
    q_i = as_vector(q_i, robot.nv, "q_i")
    q_f = as_vector(q_f, robot.nv, "q_f")
    dq = np.abs(q_f - q_i)
    if not np.any(dq > 0):
        raise ValueError("`q_f` equals `q_i`: nothing to plan")

    def build(T: float) -> Trajectory | None:
        vc = np.minimum(limits.qd_max, 2 * dq / T)
        if np.any((dq > 0) & (vc <= dq / T * (1 + 1e-12))):
            return None
        return sample(trapezoidal_law(q_i, q_f, T, np.where(dq > 0, vc, 1.0)), samples=samples,
                      name="trapezoidal under limits")

    def feasible(T: float) -> bool:
        tr = build(T)
        if tr is None:
            return False
        return all(np.all(r <= 1.0) for r in _per_joint_ratios(robot, tr, limits, kinematic_first=True)[0].values())

    hi = float(np.max(dq / limits.qd_max)) * 2.0 + 1e-3
    while not feasible(hi):
        hi *= 2.0
        if hi > 1e4:
            raise ValueError("no trapezoidal profile within the limits (torque limits too low?)")
    lo = float(np.max(dq / limits.qd_max))
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if feasible(mid) else (mid, hi)
    tr = build(hi)
    return tr, limit_ratios(robot, tr, limits)[1]
