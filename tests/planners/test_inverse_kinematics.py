"""Inverse kinematics: CLIK laws, null-space tasks, CasADi SQP IK and proxsuite QP IK (Panda, UR5, book arms).

FK(IK(T)) is always checked with Pinocchio's direct kinematics, independent of the solvers' own models.
"""

import numpy as np
import pytest

from controllers.plants import JointIntegrator
from controllers.simulation import simulate
from planners.inverse_kinematics import (CLIK, CasadiIK, CasadiIKOptions, QPIKOptions, QPVelocityIK,
                                         constant_pose, cosine_pose_reference, gradient_velocity,
                                         joint_limit_distance, joint_limit_distance_gradient, solve_clik)
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import load
from rigid_body.task_space import TaskSpace, damped_least_squares_inverse, pose_residual, weighted_pseudo_inverse


@pytest.fixture(scope="module")
def panda():
    return load("panda")


@pytest.fixture(scope="module")
def panda_ik(panda):
    return CasadiIK(panda)


def _within_limits(robot, q):
    return np.all(q >= robot.lower - 1e-12) and np.all(q <= robot.upper + 1e-12)


def test_casadi_ik_reaches_random_reachable_poses(panda, panda_ik):
    rng = np.random.default_rng(7)
    for _ in range(6):
        T = direct_kinematics(panda, panda.random_configuration(rng))
        res = panda_ik.solve(T, rng=rng)
        assert res.success, res.message
        assert res.residual < 1e-6
        assert _within_limits(panda, res.q)
        assert pose_residual(T, direct_kinematics(panda, res.q)) < 1e-6


def test_casadi_ik_unreachable_pose_reports_failure(panda, panda_ik):
    T = np.eye(4)
    T[:3, 3] = [2.0, 0.0, 0.5]  # ~2 m away: outside the Panda's workspace
    res = panda_ik.solve(T, rng=np.random.default_rng(0))
    assert not res.success
    assert res.residual > 0.5 and "unreachable" in res.message
    assert _within_limits(panda, res.q)


def test_casadi_ik_posture_cost_and_ur5():
    robot = load("ur5")
    rng = np.random.default_rng(3)
    ik = CasadiIK(robot, options=CasadiIKOptions(posture_weight=1e-10, restarts=5))
    q_ref = robot.random_configuration(rng)
    res = ik.solve(direct_kinematics(robot, q_ref), q0=q_ref + 0.05, rng=rng, q_posture=q_ref)
    assert res.success and pose_residual(direct_kinematics(robot, q_ref), direct_kinematics(robot, res.q)) < 1e-6


def test_qp_velocity_ik_converges_within_limits(panda):
    rng = np.random.default_rng(11)
    qp = QPVelocityIK(panda)
    q_goal = panda.random_configuration(rng)
    q0 = np.clip(q_goal + rng.normal(scale=0.3, size=7), panda.lower, panda.upper)
    T = direct_kinematics(panda, q_goal)
    res = qp.solve(T, q0)
    assert res.success, res.message
    assert _within_limits(panda, res.q)
    assert pose_residual(T, direct_kinematics(panda, res.q)) < 1e-6


def test_qp_step_respects_velocity_and_position_limits(panda):
    qp = QPVelocityIK(panda, QPIKOptions(dt=0.05, gain=100.0, velocity_limit=0.5))
    q = panda.lower + 1e-3  # at the lower limits
    T = direct_kinematics(panda, np.zeros(7))
    T[:3, 3] += [0.3, -0.3, -0.3]
    qd, _ = qp.step(q, T)
    assert np.all(np.abs(qd) <= 0.5 + 1e-6)
    assert np.all(q + 0.05 * qd >= panda.lower - 1e-6)


def test_solve_clik_converges_and_never_claims_false_success():
    robot = load("ur5")
    rng = np.random.default_rng(5)
    q_goal = robot.random_configuration(rng)
    T = direct_kinematics(robot, q_goal)
    res = solve_clik(robot, T, q_goal + 0.1)
    assert res.success and res.residual < 1e-6
    short = solve_clik(robot, T, q_goal + 0.5, max_iterations=2)
    assert short.success == (short.residual < 1e-6)
    far = np.eye(4)
    far[:3, 3] = [3.0, 0.0, 0.0]
    bad = solve_clik(robot, far, q_goal, max_iterations=50)
    assert not bad.success and bad.residual > 1.0


def test_clik_null_space_keeps_panda_away_from_joint_limits(panda):
    """Position CLIK (3.72) on the 7-DOF Panda with q̇_0 = k0 ∂w/∂q, w the distance from the limits (3.57)."""
    q0 = np.array([0.3, 0.2, -0.2, -2.8, 0.1, 3.2, 0.8])
    T0 = direct_kinematics(panda, q0)
    ref = cosine_pose_reference(T0[:3, 3], T0[:3, 3] + [0.1, 0.1, 0.05], 2.0, R_0=T0[:3, :3])
    task = TaskSpace(orientation="none")
    out = {}
    for k0 in (0.0, 200.0):
        sec = gradient_velocity(None, k0, gradient=lambda q: joint_limit_distance_gradient(panda, q)) if k0 else None
        res = simulate(JointIntegrator(), CLIK(panda, ref, task, K=50.0, secondary=sec), (0.0, 4.0), q0, h=1e-2)
        out[k0] = res
        assert np.linalg.norm(res["e"][-1]) < 1e-6
        assert np.linalg.norm(res["e"], axis=1).max() < 1e-3
    w0, w1 = joint_limit_distance(panda, out[0.0].x[-1]), joint_limit_distance(panda, out[200.0].x[-1])
    assert w1 > 0.5 * w0 > w0  # w < 0: the null-space task more than halves the distance measure
    # the numerical gradient agrees with the analytic one
    g = gradient_velocity(lambda q: joint_limit_distance(panda, q), 1.0, scheme="central")(q0)
    np.testing.assert_allclose(g, joint_limit_distance_gradient(panda, q0), atol=1e-8)


def test_clik_regulates_ur5_with_quaternion_and_dls():
    robot = load("ur5")
    rng = np.random.default_rng(9)
    q_goal = robot.random_configuration(rng)
    T = direct_kinematics(robot, q_goal)
    for orientation, law in (("quaternion", "dls"), ("axis_angle", "inverse"), ("euler_zyz", "pseudo_inverse")):
        clik = CLIK(robot, constant_pose(T), TaskSpace(orientation=orientation), K=20.0, law=law, damping=1e-4)
        res = simulate(JointIntegrator(), clik, (0.0, 2.0), q_goal + 0.05, h=1e-2)
        assert pose_residual(T, direct_kinematics(robot, res.x[-1])) < 1e-6, orientation


def test_generalised_inverses(rng):
    J = rng.normal(size=(3, 6))
    np.testing.assert_allclose(weighted_pseudo_inverse(J), np.linalg.pinv(J), atol=1e-10)
    W = np.diag(rng.uniform(1, 3, 6))
    Jw = weighted_pseudo_inverse(J, W)
    np.testing.assert_allclose(J @ Jw, np.eye(3), atol=1e-10)
    np.testing.assert_allclose(damped_least_squares_inverse(J, 0.5), J.T @ np.linalg.inv(J @ J.T + 0.25 * np.eye(3)))
    with pytest.raises(ValueError, match="singular"):
        weighted_pseudo_inverse(np.ones((2, 3)))


def test_bad_inputs_raise(panda):
    with pytest.raises(ValueError, match="orientation"):
        TaskSpace(orientation="euler_xyz")
    with pytest.raises(ValueError, match="rows"):
        TaskSpace(orientation="none", rows=(0, 4))
    with pytest.raises(ValueError, match="law"):
        CLIK(panda, constant_pose(np.eye(4)), law="newton")
    with pytest.raises(ValueError, match="law .inverse. needs a square task Jacobian"):
        CLIK(panda, constant_pose(np.eye(4)), law="inverse")(0.0, np.zeros(7))
    with pytest.raises(ValueError, match="T_d"):
        CasadiIK(panda, options=CasadiIKOptions(restarts=0)).solve(np.eye(3))
    not_a_pose = np.eye(4)
    not_a_pose[:3, :3] *= 2.0  # scaled "rotation": no configuration can reach it
    with pytest.raises(ValueError, match="T_d.*orthonormal"):
        solve_clik(panda, not_a_pose, np.zeros(7))
    with pytest.raises(ValueError, match="T_d.*orthonormal"):
        QPVelocityIK(panda).solve(not_a_pose, np.zeros(7))
    with pytest.raises(ValueError, match="QPIKOptions"):
        QPIKOptions(dt=float("nan"))
    with pytest.raises(ValueError, match="finite 2-D Jacobian"):
        damped_least_squares_inverse(np.full((2, 3), np.nan), 0.1)
    with pytest.raises(ValueError, match="R_0.*orthonormal"):
        cosine_pose_reference([0, 0, 0], [1, 0, 0], 1.0, R_0=2 * np.eye(3))
    with pytest.raises(ValueError, match="axis"):
        cosine_pose_reference([0, 0, 0], [1, 0, 0], 1.0, axis=[0, 0, 0])
    with pytest.raises(ValueError, match="phi_f"):
        cosine_pose_reference([0, 0, 0], [1, 0, 0], 1.0, phi_f=np.nan)


def test_null_space_manipulability_task_increases_w():
    """Planar position task on the three-link arm: q̇_0 = k0 ∂w/∂q with w of (3.56) raises w without moving p."""
    from planners.inverse_kinematics import manipulability_objective

    robot = load("planar_3r", a=(0.5, 0.3, 0.3))
    q0 = np.array([0.2, 0.3, 2.5])
    T = direct_kinematics(robot, q0)
    task = TaskSpace(orientation="none", rows=(0, 1))
    w = manipulability_objective(robot, rows=(0, 1))
    clik = CLIK(robot, constant_pose(T), task, K=50.0, secondary=gradient_velocity(w, 5.0, scheme="central"))
    res = simulate(JointIntegrator(), clik, (0.0, 3.0), q0, h=1e-2)
    assert w(res.x[-1]) > 1.5 * w(q0)
    assert np.linalg.norm(direct_kinematics(robot, res.x[-1])[:2, 3] - T[:2, 3]) < 1e-6


def _outside_start(panda):
    """A Panda configuration with q[3] = 0.3 above its upper limit (−0.0698) and its pose."""
    q = 0.5 * (panda.lower + panda.upper)
    q[3] = 0.3
    return q, direct_kinematics(panda, q)


@pytest.mark.parametrize("solver", ["clik", "qp", "casadi"])
def test_no_solver_reports_success_outside_the_joint_limits(panda, solver):
    """The old solve_clik returned success=True at iteration 0 with q[3] = 0.3 (outside the limits)."""
    q, T = _outside_start(panda)
    run = {"clik": lambda: solve_clik(panda, T, q),
           "qp": lambda: QPVelocityIK(panda, QPIKOptions(max_iterations=50)).solve(T, q),
           "casadi": lambda: CasadiIK(panda, options=CasadiIKOptions(restarts=2)).solve(T, q)}[solver]
    res = run()
    assert _within_limits(panda, res.q)
    assert "clipped" in res.message
    if res.success:   # another configuration within the limits may reach the pose: check it independently
        assert pose_residual(T, direct_kinematics(panda, res.q)) < 1e-6
    else:
        assert res.iterations >= 0


def test_solve_clik_iterations_count_and_stall_message(panda):
    q_goal = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.5])
    T = direct_kinematics(panda, q_goal)
    res = solve_clik(panda, T, q_goal)
    assert res.success and res.iterations == 0
    res = solve_clik(panda, T, q_goal + 0.05)
    assert res.success and 0 < res.iterations < 50
    assert solve_clik(panda, T, q_goal + 0.05, max_iterations=0).iterations == 0
    # a start pinned at joint limits, the target pulling further out: the message blames the limit
    q_lim = panda.upper.copy()
    q_lim[[0, 2, 4, 6]] = 0.0
    q_lim[5] = 1.0
    T_far = direct_kinematics(panda, q_lim)
    T_far[:3, 3] += [0.0, 0.0, 0.5]
    bad = solve_clik(panda, T_far, q_lim, max_iterations=20)
    assert not bad.success
    assert "joint limits" in bad.message or "singular" in bad.message or "local minimum" in bad.message


@pytest.mark.parametrize("kwargs, name", [
    ({"tol": float("nan")}, "tol"), ({"tol": 0.0}, "tol"), ({"max_iterations": -1}, "max_iterations"),
    ({"max_iterations": 2.5}, "max_iterations"), ({"damping": -1.0}, "damping"),
    ({"damping": float("nan")}, "damping"), ({"step": 0.0}, "step"), ({"step": float("inf")}, "step")])
def test_solve_clik_options_are_checked(panda, kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        solve_clik(panda, np.eye(4), np.zeros(7), **kwargs)


@pytest.mark.parametrize("kwargs, name", [
    ({"tol": float("nan")}, "tol"), ({"orientation_weight": float("nan")}, "orientation_weight"),
    ({"posture_weight": -1.0}, "posture_weight"), ({"position_weights": (1.0, np.nan, 1.0)}, "position_weights"),
    ({"position_weights": (1.0, 1.0)}, "position_weights"), ({"restarts": -1}, "restarts"),
    ({"max_iter": 0}, "max_iter")])
def test_casadi_ik_options_are_checked(kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        CasadiIKOptions(**kwargs)


def test_qp_ik_velocity_limit_is_checked(panda):
    with pytest.raises(ValueError, match="velocity_limit"):
        QPIKOptions(velocity_limit=float("nan"))
    with pytest.raises(ValueError, match="velocity_limit"):
        QPVelocityIK(panda, QPIKOptions(velocity_limit=[1.0, 2.0]))
    with pytest.raises(ValueError, match="max_iterations"):
        QPIKOptions(max_iterations=-1)


def test_clik_and_reference_arguments_are_named(panda):
    with pytest.raises(ValueError, match="`damping`"):
        CLIK(panda, constant_pose(np.eye(4)), law="dls", damping=float("nan"))
    with pytest.raises(ValueError, match="`t_f`"):
        cosine_pose_reference([0, 0, 0], [1, 0, 0], "one")
    from planners.inverse_kinematics import numerical_gradient
    with pytest.raises(ValueError, match="`step`"):
        numerical_gradient(lambda q: 0.0, np.zeros(2), step=0.0)


def _independent_residual(robot, q, T_d):
    """max(‖p_d − p_e‖, angle of R_eᵀ R_d) from FK and the trace formula (not the solver's own residual)."""
    T_e = direct_kinematics(robot, q)
    cos_angle = np.clip((np.trace(T_e[:3, :3].T @ T_d[:3, :3]) - 1.0) / 2.0, -1.0, 1.0)
    return max(float(np.linalg.norm(T_d[:3, 3] - T_e[:3, 3])), float(np.arccos(cos_angle)))


def test_solve_clik_success_flag_agrees_with_an_independent_residual():
    """``success`` and ``residual`` against FK of the returned q: a flag set from a stale or wrong
    residual (e.g. the initial guess's) is caught."""
    robot = load("ur5")
    rng = np.random.default_rng(11)
    for start_offset, iterations in ((0.1, 500), (0.6, 3), (0.3, 500)):
        q_goal = robot.random_configuration(rng)
        T = direct_kinematics(robot, q_goal)
        res = solve_clik(robot, T, q_goal + start_offset, max_iterations=iterations)
        independent = _independent_residual(robot, res.q, T)
        assert independent == pytest.approx(res.residual, abs=1e-7)
        assert res.success == (independent < 1e-6)


def _panda_target(panda, seed=5):
    rng = np.random.default_rng(seed)
    q_src = np.clip(panda.random_configuration(rng), panda.lower + 0.1, panda.upper - 0.1)
    return q_src, direct_kinematics(panda, q_src), rng


def test_casadi_ik_gauss_newton_converges_quadratically(panda):
    """From 0.03 rad off a solution the Gauss–Newton SQP lands within tolerance in a few iterations
    (quadratic convergence: 3 measured; a mis-scaled Hessian or a wrong residual takes many more)."""
    q_src, T, _ = _panda_target(panda)
    ik = CasadiIK(panda, options=CasadiIKOptions(restarts=0))
    res = ik.solve(T, q_src + 0.03 * np.array([1, -1, 1, -1, 1, -1, 1.0]))
    assert res.success and 1 <= res.iterations <= 4, res
    assert pose_residual(T, direct_kinematics(panda, res.q)) < 1e-6


def test_casadi_ik_starts_mid_range_and_stops_at_once_on_a_solution(panda):
    """Default start: the middle of the limits (clipped to ±π); started on a solution, no iteration."""
    mid = 0.5 * (np.maximum(panda.lower, -np.pi) + np.minimum(panda.upper, np.pi))
    res = CasadiIK(panda, options=CasadiIKOptions(restarts=0)).solve(direct_kinematics(panda, mid))
    assert res.success and res.iterations == 0
    np.testing.assert_array_equal(res.q, mid)


def test_casadi_ik_counts_attempts_and_iterations_of_a_failure(panda):
    """An unreachable pose: 1 + restarts attempts, each at most max_iter SQP iterations, all counted."""
    far = np.eye(4)
    far[:3, 3] = [2.0, 0.0, 0.5]
    res = CasadiIK(panda, options=CasadiIKOptions(restarts=1, max_iter=3)).solve(far)
    assert not res.success and "after 2 attempts" in res.message
    assert 4 <= res.iterations <= 6          # two attempts of ≤ 3 iterations; the first alone is ≤ 3
    assert res.residual == pytest.approx(pose_residual(far, direct_kinematics(panda, res.q)), rel=1e-9)


def test_casadi_ik_posture_cost_pulls_toward_the_posture(panda):
    """min pose error + w ‖q − q_posture‖²: the optimum q* is no farther from q_posture than the start
    q_src, which has zero pose error (else q_src would have a lower cost); the pose error stays ~√w."""
    q_src, T, rng = _panda_target(panda)
    q_post = np.clip(q_src + 0.4 * rng.standard_normal(7), panda.lower, panda.upper)
    res = CasadiIK(panda, options=CasadiIKOptions(restarts=0, posture_weight=1e-6)).solve(T, q_src, q_posture=q_post)
    assert np.linalg.norm(res.q - q_post) < np.linalg.norm(q_src - q_post) - 0.05, res
    assert pose_residual(T, direct_kinematics(panda, res.q)) < 1e-4


@pytest.mark.parametrize("law", ["dls", "pseudo_inverse"])
def test_clik_law_uses_its_own_inverse(panda, law):
    """Position-only CLIK (3.70) at a random q: "dls" is J^T (J J^T + k² I)^{-1} K e (3.59), the damping
    k = 0.3 changing the answer; "pseudo_inverse" ignores the damping (J^T (J J^T)^{-1} K e, (3.52)).
    Both recomputed here from Pinocchio's Jacobian, with numpy's solve."""
    import pinocchio as pin

    rng = np.random.default_rng(21)
    q = panda.random_configuration(rng)
    T = direct_kinematics(panda, panda.random_configuration(rng))
    K, k = 2.0, 0.3
    clik = CLIK(panda, constant_pose(T), TaskSpace(orientation="none"), K=K, law=law, damping=k)
    qd = clik(0.0, q)
    J = pin.computeFrameJacobian(panda.model, panda.model.createData(), q, panda.ee_frame,
                                 pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)[:3]
    e = T[:3, 3] - direct_kinematics(panda, q)[:3, 3]
    damping = k if law == "dls" else 0.0
    np.testing.assert_allclose(qd, J.T @ np.linalg.solve(J @ J.T + damping**2 * np.eye(3), K * e), rtol=1e-9, atol=1e-12)


def test_cosine_pose_reference_rotates_about_z_by_default():
    """The manual's references turn about the base z axis: R(t_f) = Rot_z(φ_f) R_0, written out."""
    phi = 0.7
    T, v = cosine_pose_reference([0, 0, 0], [0.1, 0, 0], 2.0, phi_f=phi)(2.0)
    c, s = np.cos(phi), np.sin(phi)
    np.testing.assert_allclose(T[:3, :3], [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-12)
    _, v_mid = cosine_pose_reference([0, 0, 0], [0.1, 0, 0], 2.0, phi_f=phi)(1.0)
    np.testing.assert_allclose(v_mid[3:], [0, 0, 0.5 * np.pi / 2.0 * phi], atol=1e-12)   # ω = ṡ φ_f z


def test_failure_reason_names_the_joint_at_a_limit_and_a_rank_deficient_jacobian(panda):
    """The diagnosis of a stalled solver: q[1] on its lower limit is named; a task Jacobian with one
    zero singular value (rank 5 of 6) is singular, a full-rank one is not."""
    from planners.inverse_kinematics import _failure_reason

    q = 0.5 * (panda.lower + panda.upper)
    q_low = q.copy()
    q_low[1] = panda.lower[1]
    J = np.diag([3.0, 2.0, 1.5, 1.0, 0.5, 0.0])
    msg = _failure_reason(panda, q, q_low, J)
    assert "q[1] at its joint limit" in msg and "singular" in msg and msg.startswith("stalled")
    msg = _failure_reason(panda, q, q, np.diag([3.0, 2.0, 1.5, 1.0, 0.5, 0.4]))
    assert msg.startswith("never improved") and "joint limits" not in msg and "singular" not in msg


def test_qp_ik_with_no_iteration_allowed_still_checks_its_start(panda):
    """max_iterations=0: the start itself is judged (a solution → success with 0 iterations)."""
    q_goal = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.5])
    res = QPVelocityIK(panda, QPIKOptions(max_iterations=0)).solve(direct_kinematics(panda, q_goal), q_goal)
    assert res.success and res.iterations == 0


def test_two_stage_clik_takes_any_arm_size_that_leaves_a_wrist():
    from planners.inverse_kinematics import TwoStageCLIK

    wrist = load("anthropomorphic_wrist")
    ref = constant_pose(np.eye(4))
    frame = wrist.model.frames[wrist.ee_frame].name
    assert TwoStageCLIK(wrist, ref, frame, n_arm=1).n_arm == 1
    with pytest.raises(ValueError, match="n_arm"):
        TwoStageCLIK(wrist, ref, frame, n_arm=0)
    with pytest.raises(ValueError, match="n_arm"):
        TwoStageCLIK(wrist, ref, frame, n_arm=wrist.nv)


def test_failure_reason_thresholds_are_tight_and_relative(panda):
    """At a limit means within 1e-6 of it (either side): 0.5 rad inside is not; singular is relative to
    the largest singular value: a uniformly small, well-conditioned Jacobian is not singular."""
    from planners.inverse_kinematics import _failure_reason

    q = 0.5 * (panda.lower + panda.upper)
    near, upper = q.copy(), q.copy()
    near[0] = panda.lower[0] + 0.5
    upper[2] = panda.upper[2]
    J = np.diag([3.0, 2.0, 1.5, 1.0, 0.5, 0.4])
    assert "joint limits" not in _failure_reason(panda, q, near, J)
    assert "q[2] at its joint limit" in _failure_reason(panda, q, upper, J)
    assert "singular" not in _failure_reason(panda, q, q, 1e-3 * np.diag([1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5]))


@pytest.mark.parametrize("side", [-1.0, 1.0])
def test_qp_ik_step_stops_on_a_joint_limit(panda, side):
    """A target beyond a limit of q_4: one QP step brings q_4 exactly onto that limit, (q_m − q)/Δt or
    (q_M − q)/Δt being the velocity bound, and not past it."""
    qp = QPVelocityIK(panda)
    limit = panda.upper[3] if side > 0 else panda.lower[3]
    q = np.array([0.3, -0.4, 0.2, limit - side * 0.01, 0.1, 1.8, 0.5])
    q_far = q.copy()
    q_far[3] = limit + side * 0.3
    qd, _ = qp.step(q, direct_kinematics(panda, q_far))
    assert q[3] + qp.options.dt * qd[3] == pytest.approx(limit, abs=1e-6)


def test_qp_ik_failure_returns_its_best_configuration(panda):
    """Not converged in 3 steps: the result is the best configuration met, better than the start."""
    q_goal = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.5])
    T = direct_kinematics(panda, q_goal)
    q0 = q_goal + 0.3
    res = QPVelocityIK(panda, QPIKOptions(max_iterations=3, gain=5.0)).solve(T, q0)
    assert not res.success
    assert res.residual < pose_residual(T, direct_kinematics(panda, q0))
    assert res.residual == pytest.approx(pose_residual(T, direct_kinematics(panda, res.q)), rel=1e-9)


def test_qp_ik_velocity_limits_must_be_positive(panda):
    with pytest.raises(ValueError, match="velocity_limit"):
        QPIKOptions(velocity_limit=np.zeros(7))


def test_a_dead_start_says_so_and_names_a_better_one():
    """The Panda's neutral (stretched upright, q₄ on its limit) is a dead start for the local CLIK: the failure says
    which joint sits on its limit (one joint: "its limit") and names another configuration to start from; from
    ``ready`` the same pose converges."""
    from planners.inverse_kinematics import solve_clik
    from rigid_body.kinematics import direct_kinematics
    from rigid_body.robots import load

    panda = load("panda")
    T = direct_kinematics(panda, panda.configurations["neutral"])
    T[:3, 3] += [0.05, 0.0, -0.1]
    dead = solve_clik(panda, T, panda.configurations["neutral"])
    assert not dead.success and "q[3] at its joint limit" in dead.message
    assert "robot.configurations['ready']" in dead.message
    assert solve_clik(panda, T, panda.configurations["ready"]).success
