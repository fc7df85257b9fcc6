"""Optimal control by multiple shooting (planners/optimal_control.py) against independent references: the discrete
Riccati solution of a linear–quadratic case, the first-order optimality of a nonlinear case by finite differences of
a Pinocchio simulation, and a second solver (IPOPT on single shooting) for an unconstrained reach."""

import numpy as np
import pinocchio as pin
import pytest
import casadi as ca

from planners.optimal_control import (OptimalControlOptions, OptimalControlProblem, OptimalControlResult,
                                      OptimalControlSolver, StageCost, solve_optimal_control)
from rigid_body.robots import load
from rigid_body.symbolic import forward_dynamics_function, frame_placement_function


def rk4(f, x, u, h):
    """The test's own RK4 step (numpy), with the four stage states."""
    k1 = f(x, u)
    k2 = f(x + h / 2 * k1, u)
    k3 = f(x + h / 2 * k2, u)
    k4 = f(x + h * k3, u)
    return x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4), [x, x + h / 2 * k1, x + h / 2 * k2, x + h * k3]


def arm_dynamics(robot):
    """ẋ = [q̇; B⁻¹(τ − n)] with Pinocchio's CRBA and RNEA (rotors included)."""
    model, data, n = robot.model, robot.model.createData(), robot.nv

    def f(x, u):
        q, v = x[:n], x[n:]
        B = pin.crba(model, data, q)
        B = np.triu(B) + np.triu(B, 1).T
        return np.concatenate([v, np.linalg.solve(B, u - pin.rnea(model, data, q, v, np.zeros(n)))])
    return f


# --------------------------------------------------------------------------------------------
# Linear–quadratic case: the prismatic arm (constant B and g) against the discrete Riccati recursion
# --------------------------------------------------------------------------------------------

def test_linear_quadratic_case_equals_the_discrete_riccati_solution():
    arm = load("cartesian_skew")                    # two prismatic joints with rotors: B, g constant, no C
    n, N, dt = arm.nv, 15, 0.05
    model, data = arm.model, arm.model.createData()
    B = pin.crba(model, data, np.zeros(n))
    B = np.triu(B) + np.triu(B, 1).T
    g = pin.rnea(model, data, np.zeros(n), np.zeros(n), np.zeros(n))
    w_q, w_v, w_t = np.array([40.0, 25.0]), np.array([1.0, 2.0]), np.array([1e-3, 2e-3])
    wN_q, wN_v = np.array([400.0, 300.0]), np.array([10.0, 10.0])
    q_ref, tau_ref = np.array([0.3, -0.2]), g
    problem = OptimalControlProblem(arm, N, dt, StageCost(q=w_q, qd=w_v, tau=w_t), StageCost(q=wN_q, qd=wN_v),
                                    tau_max=1e6, q_min=-np.inf, q_max=np.inf, qd_max=np.inf, state_limits="hard")
    x0 = np.array([0.1, 0.05, 0.0, 0.2])
    res = solve_optimal_control(problem, x0, q_ref=q_ref, tau_ref=tau_ref)
    assert res.success, res.message

    # ẋ = F x + G τ + c; the RK4 step and its stage states are affine maps of z = [x; τ; 1]
    F = np.block([[np.zeros((n, n)), np.eye(n)], [np.zeros((n, 2 * n))]])
    G = np.vstack([np.zeros((n, n)), np.linalg.inv(B)])
    c = np.concatenate([np.zeros(n), -np.linalg.solve(B, g)])
    nx, nz = 2 * n, 3 * n + 1
    X_of_z = np.hstack([np.eye(nx), np.zeros((nx, n + 1))])
    rate = lambda S: F @ S + np.hstack([np.zeros((nx, nx)), G, c[:, None]])       # ẋ as a map of z
    nxt, stages = rk4(lambda S, _: rate(S), X_of_z, None, dt)
    A_d, B_d, c_d = nxt[:, :nx], nxt[:, nx:nx + n], nxt[:, -1]
    # cost ½ zᵀ M z of one interval: RK4 quadrature of the state terms at the stages, the torque term once
    W = np.diag(np.concatenate([w_q, w_v]))
    x_ref = np.concatenate([q_ref, np.zeros(n)])
    M = np.zeros((nz, nz))
    for weight, S in zip((1, 2, 2, 1), stages):
        E = S - np.hstack([np.zeros((nx, nx + n)), x_ref[:, None]])
        M += weight / 6 * dt * E.T @ W @ E
    T = np.hstack([np.zeros((n, nx)), np.eye(n), -tau_ref[:, None]])
    M += dt * T.T @ np.diag(w_t) @ T
    # Riccati on the augmented state y = [x; 1]: y⁺ = Ā y + B̄ τ
    A_bar = np.block([[A_d, c_d[:, None]], [np.zeros((1, nx)), np.ones((1, 1))]])
    B_bar = np.vstack([B_d, np.zeros((1, n))])
    iy, iu = np.r_[0:nx, nz - 1], np.r_[nx:nx + n]
    Q, R, S = M[np.ix_(iy, iy)], M[np.ix_(iu, iu)], M[np.ix_(iy, iu)]
    E_N = np.hstack([np.eye(nx), -x_ref[:, None]])
    P = E_N.T @ np.diag(np.concatenate([wN_q, wN_v])) @ E_N
    gains = []
    for _ in range(N):
        K = -np.linalg.solve(R + B_bar.T @ P @ B_bar, S.T + B_bar.T @ P @ A_bar)
        P = Q + A_bar.T @ P @ A_bar + (S + A_bar.T @ P @ B_bar) @ K
        gains.append(K)
    y, U, X = np.append(x0, 1.0), [], [x0]
    for K in reversed(gains):
        U.append(K @ y)
        y = A_bar @ y + B_bar @ U[-1]
        X.append(y[:nx])
    cost = 0.5 * np.append(x0, 1.0) @ P @ np.append(x0, 1.0)
    np.testing.assert_allclose(res.u, np.array(U), atol=1e-8 * np.max(np.abs(U)))
    np.testing.assert_allclose(res.x, np.array(X), atol=1e-8)
    assert res.cost == pytest.approx(cost, rel=1e-8)


# --------------------------------------------------------------------------------------------
# A nonlinear case: the two-link arm with its rotors, torque limits active
# --------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def arm_problem():
    arm = load("planar_2r")
    problem = OptimalControlProblem(arm, horizon=20, dt=0.02, running=StageCost(q=1e3, qd=1.0, tau=1e-6),
                                    terminal=StageCost(q=1e4, qd=1e2), tau_max=[3000.0, 1500.0])
    return problem, OptimalControlSolver(problem)


def single_shooting_cost(problem, f, x0, U, q_ref):
    """The problem's cost of the torques U from x0, by the test's RK4 and quadrature (terminal included)."""
    n, dt, run, ter = problem.n, problem.dt, problem.running, problem.terminal
    x, total = x0, 0.0
    ell = lambda s, w: 0.5 * (np.sum(w.q * (s[:n] - q_ref) ** 2) + np.sum(w.qd * s[n:] ** 2))
    for u in U.reshape(-1, n):
        x_next, stages = rk4(f, x, u, dt)
        total += dt * sum(c * ell(s, run) for c, s in zip((1 / 6, 1 / 3, 1 / 3, 1 / 6), stages))
        total += dt * 0.5 * np.sum(run.tau * u**2)
        x = x_next
    return total + ell(x, ter)


def test_nonlinear_case_satisfies_first_order_optimality_by_finite_differences(arm_problem):
    problem, solver = arm_problem
    q_ref = np.array([0.3, -0.2])
    x0 = np.zeros(4)
    res = solver.solve(x0, q_ref=q_ref)
    assert res.success and res.kkt < 1e-6 and res.verified, res
    assert res.ratios["tau"] == pytest.approx(1.0, abs=1e-9)          # the torque box is active
    f = arm_dynamics(problem.robot)
    U = res.u.ravel()
    J0 = single_shooting_cost(problem, f, x0, U, q_ref)
    assert J0 == pytest.approx(res.cost, rel=1e-9)
    tau_max = np.tile(problem.tau_max, problem.horizon)
    grad = np.empty(U.size)
    for i in range(U.size):
        h = 1e-4 * tau_max[i]
        Up, Um = U.copy(), U.copy()
        Up[i] += h
        Um[i] -= h
        grad[i] = (single_shooting_cost(problem, f, x0, Up, q_ref) - single_shooting_cost(problem, f, x0, Um, q_ref)) / (2 * h)
    grad *= tau_max                                                     # per unit of τ_max
    scale = np.max(np.abs(grad))
    upper, lower = U >= tau_max * (1 - 1e-5), U <= -tau_max * (1 - 1e-5)
    free = ~(upper | lower)
    assert upper.any() or lower.any()
    assert np.max(np.abs(grad[free])) < 1e-5 * scale                   # stationary where free
    assert np.all(grad[upper] <= 1e-5 * scale) and np.all(grad[lower] >= -1e-5 * scale)   # pushing outward at a bound


def test_warm_start_from_the_solution_converges_at_once(arm_problem):
    problem, solver = arm_problem
    first = solver.solve(np.zeros(4), q_ref=[0.3, -0.2])
    again = solver.solve(np.zeros(4), q_ref=[0.3, -0.2], warm_start=first)
    assert again.success and again.iterations <= 2
    assert again.cost == pytest.approx(first.cost, rel=1e-9)


def test_soft_and_hard_state_limits(arm_problem):
    problem, _ = arm_problem
    kw = dict(horizon=20, dt=0.02, running=StageCost(q=1e3, qd=1.0, tau=1e-6), terminal=StageCost(q=1e4, qd=1e2),
              tau_max=[3000.0, 1500.0], qd_max=[1.0, 1.0])
    hard = solve_optimal_control(OptimalControlProblem(problem.robot, state_limits="hard", **kw), np.zeros(4),
                                 q_ref=[0.3, -0.2])
    assert hard.success, hard.message
    assert hard.ratios["qd"] == pytest.approx(1.0, abs=1e-8)           # the speed limit binds
    soft = solve_optimal_control(OptimalControlProblem(problem.robot, state_limits="soft", slack_weight=1e5, **kw),
                                 np.zeros(4), q_ref=[0.3, -0.2])
    assert soft.success, soft.message                                   # exact penalty: the hard optimum
    assert soft.cost == pytest.approx(hard.cost, rel=1e-6) and soft.slack < 1e-8
    cheap = solve_optimal_control(OptimalControlProblem(problem.robot, state_limits="soft", slack_weight=1e-3, **kw),
                                  np.zeros(4), q_ref=[0.3, -0.2])
    assert cheap.success and cheap.ratios["qd"] > 1.01 and cheap.slack > 0    # a cheap violation is bought


# --------------------------------------------------------------------------------------------
# Unconstrained reach against a second solver
# --------------------------------------------------------------------------------------------

def test_unconstrained_reach_equals_a_second_solver():
    arm = load("planar_3r")
    n, N, dt = arm.nv, 10, 0.05
    q0 = np.array([0.2, 0.4, -0.3])
    data = arm.model.createData()
    pin.framesForwardKinematics(arm.model, data, np.array([0.7, -0.2, 0.4]))
    T_d = data.oMf[arm.ee_frame].homogeneous.copy()
    running, terminal = StageCost(qd=1.0, tau=1e-3, position=10.0, orientation=1.0), \
        StageCost(qd=1.0, position=1e3, orientation=1e2)
    problem = OptimalControlProblem(arm, N, dt, running, terminal, tau_max=1e6, q_min=-np.inf, q_max=np.inf,
                                    qd_max=np.inf)
    x0 = np.concatenate([q0, np.zeros(n)])
    res = solve_optimal_control(problem, x0, T_d=T_d)
    assert res.success, res.message
    running, terminal = problem.running, problem.terminal              # the weights as arrays
    f = arm_dynamics(arm)
    fid = arm.ee_frame

    def ell(s, w):
        pin.framesForwardKinematics(arm.model, data, s[:n])
        M = data.oMf[fid]
        e_p = M.translation - T_d[:3, 3]
        e_o = pin.log3(T_d[:3, :3].T @ M.rotation)
        return 0.5 * (np.sum(w.qd * s[n:] ** 2) + w.position * e_p @ e_p + w.orientation * e_o @ e_o)

    def cost(U):
        x, total = x0, 0.0
        for u in U.reshape(-1, n):
            x_next, stages = rk4(f, x, u, dt)
            total += dt * (sum(c * ell(s, running) for c, s in zip((1 / 6, 1 / 3, 1 / 3, 1 / 6), stages))
                           + 0.5 * running.tau[0] * u @ u)
            x = x_next
        return total + ell(x, terminal)

    # IPOPT (exact Hessian) on single shooting: the torques are the only unknowns, the states a CasADi RK4 rollout
    fd = forward_dynamics_function(arm)
    fk = frame_placement_function(arm)
    U = ca.SX.sym("U", n, N)

    def ell_sx(s, w):
        R, p = fk(s[:n])
        E = ca.mtimes(T_d[:3, :3].T, R)
        cos = ca.fmin(ca.fmax((ca.trace(E) - 1) / 2, -1), 1)
        w_vec = ca.vertcat(E[2, 1] - E[1, 2], E[0, 2] - E[2, 0], E[1, 0] - E[0, 1]) / 2
        angle = ca.acos(cos)
        e_o = w_vec * ca.if_else(angle > 1e-6, angle / ca.sin(angle), 1 + angle**2 / 6)
        return 0.5 * (ca.sumsqr(ca.sqrt(w.qd) * s[n:]) + w.position * ca.sumsqr(p - T_d[:3, 3])
                      + w.orientation * ca.sumsqr(e_o))

    x, total = ca.DM(x0), 0
    for k in range(N):
        u = U[:, k]
        x_next, stages = rk4(lambda s, v: ca.vertcat(s[n:], fd(s[:n], s[n:], v)), x, u, dt)
        total += dt * (sum(c * ell_sx(s_, running) for c, s_ in zip((1 / 6, 1 / 3, 1 / 3, 1 / 6), stages))
                       + 0.5 * running.tau[0] * ca.sumsqr(u))
        x = x_next
    total += ell_sx(x, terminal)
    ipopt = ca.nlpsol("second", "ipopt", {"x": ca.vec(U), "f": total},
                      {"ipopt": {"print_level": 0, "tol": 1e-10}, "print_time": False})
    g0 = pin.computeGeneralizedGravity(arm.model, data, q0)
    second = ipopt(x0=np.tile(g0, N))
    assert ipopt.stats()["success"], ipopt.stats()["return_status"]
    u_second = np.asarray(second["x"]).ravel()
    assert cost(res.u.ravel()) == pytest.approx(res.cost, rel=1e-9)
    assert cost(u_second) == pytest.approx(res.cost, rel=1e-8)
    np.testing.assert_allclose(res.u.ravel(), u_second, atol=1e-5 * np.max(np.abs(u_second)))


# --------------------------------------------------------------------------------------------
# Bad input
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("change, name", [
    (dict(horizon=0), "horizon"), (dict(horizon=2.5), "horizon"), (dict(dt=-0.1), "dt"), (dict(dt=np.nan), "dt"),
    (dict(tau_max=[1.0, -1.0]), "tau_max"), (dict(tau_max=[1.0, np.inf]), "tau_max"),
    (dict(q_min=[0.0, 0.0], q_max=[1.0, -1.0]), "q_min"), (dict(qd_max=0.0), "qd_max"),
    (dict(running=StageCost(q=np.nan)), "running.q"), (dict(terminal=StageCost(position=-1.0)), "terminal.position"),
    (dict(running=StageCost(tau=[1.0, 2.0, 3.0])), "running.tau"), (dict(state_limits="firm"), "state_limits"),
    (dict(slack_weight=0.0), "slack_weight"), (dict(slack_weight=np.inf), "slack_weight"),
    (dict(q_min=[-np.inf, -1.0], q_max=[0.1, 1.0]), "q_min` and `q_max` of joint\\(s\\) \\[1\\]"),
    (dict(q_min=[-1.0, -1.0], q_max=[0.1, np.inf]), "q_min` and `q_max` of joint\\(s\\) \\[2\\]"),
    (dict(q_min=[np.nan, -1.0]), "q_min"), (dict(running=StageCost(qd=[1.0, np.inf])), "running.qd"),
    (dict(terminal=StageCost(orientation=np.nan)), "terminal.orientation"), (dict(tau_max=np.nan), "tau_max"),
])
def test_bad_problems_are_refused_naming_the_argument(change, name):
    arm = load("planar_2r")
    kw = dict(robot=arm, horizon=5, dt=0.1)
    kw.update(change)
    with pytest.raises(ValueError, match=name):
        OptimalControlProblem(**kw)


def test_bad_solve_arguments_are_refused(arm_problem):
    problem, solver = arm_problem
    with pytest.raises(ValueError, match="x0"):
        solver.solve([0.0, 0.0, np.nan, 0.0])
    with pytest.raises(ValueError, match="q_ref"):
        solver.solve(np.zeros(4), q_ref=np.zeros((3, 2)))
    with pytest.raises(ValueError, match="warm_start"):
        solver.solve(np.zeros(4), warm_start=(np.zeros((3, 4)), np.zeros((2, 2))))
    hard = OptimalControlProblem(problem.robot, 5, 0.1, qd_max=1.0, state_limits="hard")
    with pytest.raises(ValueError, match="x0"):                         # an infeasible start under hard limits
        solve_optimal_control(hard, [0.0, 0.0, 2.0, 0.0])
    posed = OptimalControlProblem(problem.robot, 5, 0.1, terminal=StageCost(position=1.0))
    with pytest.raises(ValueError, match="T_d"):
        solve_optimal_control(posed, np.zeros(4))
    with pytest.raises(ValueError, match="T_d"):
        solve_optimal_control(posed, np.zeros(4), T_d=2 * np.eye(4))
    with pytest.raises(ValueError, match="max_iter"):
        OptimalControlOptions(max_iter=0)


def test_result_is_an_optimal_trajectory(arm_problem):
    problem, solver = arm_problem
    res = solver.solve(np.zeros(4), q_ref=[0.3, -0.2])
    assert isinstance(res, OptimalControlResult)
    assert len(res.trajectory) == problem.horizon + 1 == len(res.tau)
    np.testing.assert_allclose(res.trajectory.t[-1], problem.horizon * problem.dt)
    q, qd, _ = res.trajectory.evaluate(res.trajectory.t[3])
    np.testing.assert_allclose(q, res.x[3, :2], atol=1e-12)
    assert "SQP iterations" in repr(res)
    x, u = res.shifted()
    np.testing.assert_array_equal(x[0], res.x[1])
    np.testing.assert_array_equal(u[-1], res.u[-1])


# --------------------------------------------------------------------------------------------
# The pieces of one SQP step: the linearisation and the step QP, against independent computations
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["planar_2r", "ur5"])
def test_chain_rule_linearisation_equals_automatic_differentiation(name):
    """The interval's Jacobian by the chain rule through the RK4 stages (−B⁻¹ ∂RNEA) against CasADi's automatic
    differentiation of the whole RK4 step and cost residual (built here from forward_dynamics_expression)."""
    from planners.optimal_control import RK4_WEIGHTS, _linearised_interval, _parameter_size, _state_residual, _unpack
    from rigid_body.symbolic import forward_dynamics_expression

    robot = load(name)
    n, frame = robot.nv, robot.ee_frame
    x, u, p = ca.SX.sym("x", 2 * n), ca.SX.sym("u", n), ca.SX.sym("p", _parameter_size(n))
    P = _unpack(p, n)
    chain = ca.Function("chain", [x, u, p], list(_linearised_interval(robot, frame, x, u, p, True, True)))
    x_next, stages = rk4(lambda s, v: ca.vertcat(s[n:], forward_dynamics_expression(robot, s[:n], s[n:], v)), x, u,
                         P["dt"])
    r = ca.vertcat(*[ca.sqrt(c * P["dt"]) * _state_residual(robot, frame, s, P, True, True)
                     for c, s in zip(RK4_WEIGHTS, stages)], ca.sqrt(P["dt"]) * P["sw_tau"] * (u - P["tau_ref"]))
    ad = ca.Function("ad", [x, u, p], [x_next, r, ca.jacobian(ca.vertcat(x_next, r), ca.vertcat(x, u))])
    rng = np.random.default_rng(3)
    for _ in range(3):
        xv, uv = rng.normal(size=2 * n), rng.normal(size=n) * 20.0
        pv = rng.uniform(0.1, 1.0, size=_parameter_size(n))
        pv[0] = 0.02
        R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        pv[1 + 3 * n + 3:1 + 3 * n + 12] = (R * np.sign(np.linalg.det(R))).ravel(order="F")
        ours, theirs = chain(xv, uv, pv), ad(xv, uv, pv)
        for a, b in zip(ours[:3], theirs):
            a, b = np.array(a), np.array(b)
            np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-10 * max(1.0, np.max(np.abs(b))))


@pytest.mark.parametrize("soft", [True, False])
@pytest.mark.parametrize("solver", ["hpipm", "piqp", "proxsuite"])
def test_step_qp_equals_a_dense_qp(soft, solver):
    """HPIPM called directly, and the sparse fallback (PIQP through CasADi, proxsuite's sparse solver), on a random
    stage-wise QP (torque box, state limits soft or hard, one limit left out) against proxsuite's dense solver on the
    same QP written out whole: steps, slacks and multipliers."""
    import proxsuite

    from planners.stage_qp import stage_qp

    rng = np.random.default_rng(7)
    N, nx, nu, limited = 6, 4, 2, np.array([0, 3])
    nb = limited.size
    qp = stage_qp(N, nx, nu, limited, soft, OptimalControlOptions(qp_tol=1e-12), solver)
    assert qp.name == {"hpipm": "HPIPM"}.get(solver, solver)
    A, B, b = rng.normal(size=(N, nx, nx)) * 0.5, rng.normal(size=(N, nx, nu)), rng.normal(size=(N, nx))
    M = rng.normal(size=(N + 1, nx + nu, nx + nu))
    H = M @ np.transpose(M, (0, 2, 1)) + 0.1 * np.eye(nx + nu)                  # over [x; u]
    g = rng.normal(size=(N + 1, nx + nu)) * 3.0
    lbu, ubu, w = np.array([-0.5, -0.4]), np.array([0.7, 0.6]), 2.0
    lbx, ubx = np.array([-0.3, -0.2]), np.array([0.2, 0.25])
    if not soft:                                                              # hard: wide enough to be feasible
        lbx, ubx = np.array([-1.5, -1.2]), np.array([1.2, 1.0])
    for k in range(N):
        qp.A[k], qp.B[k], qp.b[k] = A[k].T, B[k].T, b[k]
        qp.R[k], qp.S[k], qp.r[k] = H[k][nx:, nx:], H[k][:nx, nx:], g[k][nx:]
        qp.lbu[k], qp.ubu[k] = lbu, ubu
    for k in range(1, N + 1):
        qp.Q[k], qp.q[k], qp.lbx[k, :nb], qp.ubx[k, :nb] = H[k][:nx, :nx], g[k][:nx], lbx, ubx
        if soft:
            qp.zl[k, :nb] = qp.zu[k, :nb] = w
    assert qp.solve()[0] == 0
    binding = np.argwhere(qp.x[1:, limited] >= ubx - 1e-9)                  # upper limits that bind (or are paid)
    assert binding.size
    k_out, j_out = binding[0][0] + 1, binding[0][1]
    qp.ubx_mask[k_out, j_out] = 0.0                                          # left out: no bound there
    assert qp.solve()[0] == 0
    assert qp.x[k_out, limited[j_out]] > ubx[j_out] + 1e-6                   # and the step crosses it
    # the dense QP: z = [u_0, (x_k, u_k) k = 1..N−1, x_N, s_l (k, j), s_u (k, j)]
    nv = nu + (N - 1) * (nx + nu) + nx
    ns = N * nb if soft else 0
    n_all = nv + 2 * ns
    ix = lambda k: nu + (k - 1) * (nx + nu) + np.arange(nx)
    iu = lambda k: np.arange(nu) if k == 0 else nu + (k - 1) * (nx + nu) + nx + np.arange(nu)
    Hd, gd = np.zeros((n_all, n_all)), np.zeros(n_all)
    for k in range(N + 1):
        none = np.zeros(0, int)
        idx = np.concatenate([ix(k) if k else none, iu(k) if k < N else none])
        sel = np.concatenate([np.arange(nx) if k else none, nx + np.arange(nu) if k < N else none])
        Hd[np.ix_(idx, idx)] += H[k][np.ix_(sel, sel)]
        gd[idx] += g[k][sel]
    gd[nv:] = w
    Ae = np.zeros((N * nx, n_all))
    for k in range(N):
        rows = slice(k * nx, (k + 1) * nx)
        if k:
            Ae[rows, ix(k)] = A[k]
        Ae[rows, iu(k)] = B[k]
        Ae[rows, ix(k + 1)] -= np.eye(nx)
    be = -b.ravel()
    C, lo, hi = [], [], []
    for k in range(N):
        C.append(np.eye(n_all)[iu(k)]), lo.append(lbu), hi.append(ubu)
    big = 1e20
    for k in range(1, N + 1):
        for j in range(nb):
            row = np.zeros(n_all)
            row[ix(k)[limited[j]]] = 1.0
            upper = big if (k == k_out and j == j_out) else ubx[j]
            if soft:
                m = (k - 1) * nb + j
                low, up = row.copy(), row.copy()
                low[nv + m], up[nv + ns + m] = 1.0, -1.0
                C += [low[None], up[None]]
                lo += [[lbx[j]], [-big]]
                hi += [[big], [upper]]
            else:
                C.append(row[None]), lo.append([lbx[j]]), hi.append([upper])
    if soft:
        C.append(np.eye(n_all)[nv:]), lo.append(np.zeros(2 * ns)), hi.append(np.full(2 * ns, big))
    C, lo, hi = np.vstack(C), np.concatenate(lo), np.concatenate(hi)
    dense = proxsuite.proxqp.dense.QP(n_all, Ae.shape[0], C.shape[0])
    dense.settings.eps_abs = 1e-12
    dense.init(Hd + 1e-14 * np.eye(n_all), gd, Ae, be, C, lo, hi)
    dense.solve()
    z = dense.results.x
    np.testing.assert_allclose(np.array([z[iu(k)] for k in range(N)]), qp.u[:N], atol=1e-8)
    np.testing.assert_allclose(np.array([z[ix(k)] for k in range(1, N + 1)]), qp.x[1:], atol=1e-8)
    np.testing.assert_allclose(dense.results.y.reshape(N, nx), qp.pi[:N], atol=1e-7)   # Φ − x_{k+1} = 0: + π
    y_box = dense.results.z[:N * nu].reshape(N, nu)                                     # upper − lower
    np.testing.assert_allclose(y_box, qp.lam_ub[:N, :nu] - qp.lam_lb[:N, :nu], atol=1e-7)
    if soft:
        np.testing.assert_allclose(z[nv:nv + ns].reshape(N, nb), qp.sl[1:, :nb], atol=1e-8)
        np.testing.assert_allclose(z[nv + ns:].reshape(N, nb), qp.su[1:, :nb], atol=1e-8)
        assert qp.sl[1:, :nb].max() + qp.su[1:, :nb].max() > 1e-3          # some limit is violated at a cost


def test_limits_screened_into_the_qp_give_the_full_qp_steps(arm_problem, monkeypatch):
    """Limits far from the iterate are left out of the step QP and added when a step crosses them: the same solution
    as with every limit in every QP (soft and hard speed limits that bind)."""
    import planners.optimal_control as oc

    problem, _ = arm_problem
    kw = dict(horizon=20, dt=0.02, running=StageCost(q=1e3, qd=1.0, tau=1e-6), terminal=StageCost(q=1e4, qd=1e2),
              tau_max=[3000.0, 1500.0], qd_max=[1.0, 1.0], q_min=[-0.1, -0.25], q_max=[0.5, 0.1])
    for limits in ("hard", "soft"):
        results = []
        for fraction in (0.0, np.inf):
            monkeypatch.setattr(oc, "SCREEN_FRACTION", fraction)
            solver = OptimalControlSolver(OptimalControlProblem(problem.robot, state_limits=limits, **kw))
            results.append(solver.solve(np.zeros(4), q_ref=[0.3, -0.2]))
            assert results[-1].success, results[-1].message
        screened, full = results
        assert screened.ratios["qd"] == pytest.approx(1.0, abs=1e-6)         # a limit binds
        np.testing.assert_allclose(screened.u, full.u, atol=1e-6 * np.max(problem.tau_max))
        np.testing.assert_allclose(screened.x, full.x, atol=1e-8)
        assert screened.cost == pytest.approx(full.cost, rel=1e-9)
