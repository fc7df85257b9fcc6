"""Operational-space controllers against the two-link arm's closed-form kinematics and dynamics, and full
pose tasks on the Panda judged from the 4×4 poses (not from the controllers' own errors)."""

import numpy as np
import pytest

from tests import two_link_closed_form as arm2
from controllers.operational_space import (OperationalInverseDynamics, OperationalPDGravity,
                                           operational_inverse_dynamics_steady_state, task_reference)
from controllers.plants import ArmMeasurement, ArmPlant
from controllers.simulation import simulate
from planners.paths import PathLaw, Segment
from planners.timing import trapezoidal_law
from rigid_body.dynamics import forward_dynamics
from rigid_body.kinematics import direct_kinematics, geometric_jacobian
from rigid_body.robots import load
from rigid_body.rotations import axis_angle_to_rotation, rotation_to_axis_angle

M_L = 10.0


@pytest.fixture(scope="module")
def arm_loaded():
    return load("planar_2r", payload=M_L)


def test_pd_gravity_law_is_eq_8_110(arm_loaded, rng):
    p_d = np.array([0.5, 0.5])
    ctrl = OperationalPDGravity(arm_loaded, 16250.0, 3250.0, p_d, rows=(0, 1))
    for _ in range(5):
        q, qd = rng.uniform(-np.pi, np.pi, 2), rng.uniform(-1, 1, 2)
        J = arm2.jacobian(q)
        expected = arm2.gravity(q, M_L) + J.T @ (16250.0 * (p_d - arm2.tip(q)) - 3250.0 * J @ qd)
        np.testing.assert_allclose(ctrl(0.0, ArmMeasurement(q, qd)), expected, atol=1e-7)


def test_inverse_dynamics_imposes_the_task_acceleration(arm_loaded, rng):
    """With the exact model the tip acceleration J q̈ + J̇ q̇ is ẍ_d + K_D x̃̇ + K_P x̃ (Eq. 8.114)."""
    law = PathLaw(Segment([0.7, 0.2, 0.0], [0.1, -0.6, 0.0]), trapezoidal_law(0.0, 1.0, 1.0, 1.5))
    ctrl = OperationalInverseDynamics(arm_loaded, 100.0, 16.0, law, rows=(0, 1), viscous_friction=100.0)
    for t in (0.1, 0.5, 0.9):
        q = np.array([1.2, -2.2]) + rng.uniform(-0.2, 0.2, 2)
        qd = rng.uniform(-1, 1, 2)
        u = ctrl(t, ArmMeasurement(q, qd))
        qdd = arm2.forward_dynamics(q, qd, u - 100.0 * qd, M_L)
        acc = arm2.jacobian(q) @ qdd + arm2.jacobian_derivative_times_qd(q, qd)
        x_d, xd_d, xdd_d = (v[:2] for v in law(t))
        expected = xdd_d + 16.0 * (xd_d - arm2.jacobian(q) @ qd) + 100.0 * (x_d - arm2.tip(q))
        np.testing.assert_allclose(acc, expected, atol=1e-8)


def test_pd_gravity_reaches_a_tip_position(arm_loaded):
    p_d = np.array([0.6, -0.2])
    res = simulate(ArmPlant(arm_loaded, viscous_friction=100.0),
                   OperationalPDGravity(arm_loaded, 16250.0, 3250.0, p_d, rows=(0, 1)),
                   (0.0, 2.5), np.r_[0.73453, -2.54990, 0, 0], h=1e-3, Ts=1e-3)
    np.testing.assert_allclose(arm2.tip(res.q[-1]), p_d, atol=1e-5)


def test_steady_state_fixed_point_residual(arm_loaded):
    arm = load("planar_2r")
    p_f = np.array([0.1, -0.6])
    q = operational_inverse_dynamics_steady_state(arm_loaded, arm, 100.0, p_f, [-0.15, -2.5], rows=(0, 1))
    y = np.linalg.solve(arm2.jacobian(q), 100.0 * (p_f - arm2.tip(q)))
    np.testing.assert_allclose(arm2.inertia(q) @ y, arm2.gravity(q, M_L) - arm2.gravity(q), atol=1e-7)


def test_task_reference_restricts_three_dimensional_references():
    f = task_reference(lambda t: (np.array([1.0, 2.0, 3.0]), np.zeros(3), np.ones(3)), (0, 1))
    np.testing.assert_allclose(np.array(f(0.0)), [[1, 2], [0, 0], [1, 1]])
    np.testing.assert_allclose(task_reference([1.0, 2.0, 3.0], (1, 2)), [2.0, 3.0])


def test_bad_task_definitions_raise(arm_loaded):
    with pytest.raises(ValueError, match="rows"):
        OperationalInverseDynamics(arm_loaded, 100.0, 16.0, [0.5, 0.5, 0.0])  # 3 rows, 2 joints
    with pytest.raises(ValueError, match="rows"):
        OperationalPDGravity(arm_loaded, 1.0, 1.0, [0.5, 0.5], rows=(0, 4))
    ctrl = OperationalInverseDynamics(arm_loaded, 100.0, 16.0, [0.5, 0.5], rows=(0, 1))
    with pytest.raises(ValueError, match="singular"):
        ctrl(0.0, ArmMeasurement(np.array([0.3, 0.0]), np.zeros(2)))  # stretched arm: J singular


def test_nearly_singular_jacobian_raises_instead_of_huge_torques(arm_loaded):
    ctrl = OperationalInverseDynamics(arm_loaded, 100.0, 16.0, [0.5, 0.5], rows=(0, 1))
    with pytest.raises(ValueError, match="J_A is singular at t = 0 s"):
        ctrl(0.0, ArmMeasurement(np.array([0.3, 1e-14]), np.zeros(2)))  # numerically stretched: cond(J) ~ 1e14
    assert np.all(np.isfinite(ctrl(0.0, ArmMeasurement(np.array([0.3, 1e-3]), np.zeros(2)))))  # near the singularity, not at it
    arm = load("planar_2r")
    with pytest.raises(ValueError, match="J_A is singular at q"):
        operational_inverse_dynamics_steady_state(arm_loaded, arm, 100.0, [2.0, 0.0], [0.0, 0.0], rows=(0, 1))


# --------------------------------------------------------------------------------------------
# Full pose tasks on the 7-DOF Panda (redundant: 6 task components, 7 joints)
# --------------------------------------------------------------------------------------------

Q0_PANDA = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8])
AXIS = np.array([1.0, -1.0, 0.5]) / 1.5           # unit rotation axis of the orientation changes
DP = np.array([0.06, -0.05, 0.06])                 # ‖DP‖ = 0.098 m


@pytest.fixture(scope="module")
def panda():
    return load("panda")


def _pose_errors(robot, q, T_d):
    """(‖p_d − p_e‖, angle of R_dᵀ R_e) from the 4×4 poses: independent of the controllers' errors."""
    T = direct_kinematics(robot, q)
    return np.linalg.norm(T_d[:3, 3] - T[:3, 3]), rotation_to_axis_angle(T_d[:3, :3].T @ T[:3, :3])[0]


def _moved(T, s):
    """T moved by s·DP and rotated by s·20° about AXIS (in the base frame)."""
    T = T.copy()
    T[:3, :3] = axis_angle_to_rotation(s * np.deg2rad(20.0), AXIS) @ T[:3, :3]
    T[:3, 3] += s * DP
    return T


def _pose_path(T_0, t_f=1.0):
    """t -> (T_d, v_d, a_d): quintic timing s(t) of the translation DP and the 20° rotation about AXIS."""
    twist = np.r_[DP, np.deg2rad(20.0) * AXIS]

    def reference(t):
        tau = min(max(t / t_f, 0.0), 1.0)
        s = 10 * tau**3 - 15 * tau**4 + 6 * tau**5
        sd = (30 * tau**2 - 60 * tau**3 + 30 * tau**4) / t_f
        sdd = (60 * tau - 180 * tau**2 + 120 * tau**3) / t_f**2
        return _moved(T_0, s), sd * twist, sdd * twist

    return reference


@pytest.mark.parametrize("orientation", ["quaternion", "axis_angle"])
def test_pose_regulation_on_panda(panda, orientation):
    """Both laws bring the hand to a pose 0.1 m / 20° away; the self-motion comes to rest (no drift)."""
    T_0 = direct_kinematics(panda, Q0_PANDA)
    T_d = _moved(T_0, 1.0)
    controllers = {
        "PD + gravity": OperationalPDGravity(panda, np.r_[[2000.0] * 3, [400.0] * 3], np.r_[[100.0] * 3, [10.0] * 3],
                                             T_d, orientation=orientation, joint_damping=2.0),
        "inverse dynamics": OperationalInverseDynamics(panda, np.r_[[400.0] * 3, [800.0] * 3], 40.0, T_d,
                                                       orientation=orientation, null_space_damping=10.0,
                                                       posture=Q0_PANDA, posture_stiffness=25.0),
    }
    for name, ctrl in controllers.items():
        res = simulate(ArmPlant(panda), ctrl, (0.0, 3.0), np.r_[Q0_PANDA, np.zeros(7)], h=1e-3, Ts=1e-3)
        dp, dtheta = _pose_errors(panda, res.x[-1, :7], T_d)
        assert dp < 1e-3 and dtheta < 1e-3, (name, dp, dtheta)
        k2 = np.searchsorted(res.t, 2.0)
        assert np.abs(res.x[-1, :7] - res.x[k2, :7]).max() < 1e-3, name        # no drift of the self-motion
        assert np.abs(res.x[-1, 7:]).max() < 1e-3, name


def test_pose_tracking_on_panda(panda):
    """A 1 s path translating by 0.1 m and turning by 20°: inverse dynamics tracks it (exact model,
    error ≈ 0 all along), PD + gravity reaches its end; both end within 1e-3 m and 1e-3 rad."""
    T_0 = direct_kinematics(panda, Q0_PANDA)
    path = _pose_path(T_0)
    T_f = path(1.0)[0]
    id_law = OperationalInverseDynamics(panda, np.r_[[400.0] * 3, [800.0] * 3], 40.0, path, orientation="quaternion",
                                        null_space_damping=10.0, posture=Q0_PANDA, posture_stiffness=25.0)
    res = simulate(ArmPlant(panda), id_law, (0.0, 1.5), np.r_[Q0_PANDA, np.zeros(7)], h=1e-3, Ts=1e-3)
    worst = max(max(_pose_errors(panda, q, path(t)[0])) for t, q in zip(res.t[::50], res.x[::50, :7]))
    assert worst < 1e-4
    assert max(_pose_errors(panda, res.x[-1, :7], T_f)) < 1e-3
    pd_law = OperationalPDGravity(panda, np.r_[[2000.0] * 3, [400.0] * 3], np.r_[[100.0] * 3, [10.0] * 3], path,
                                  orientation="quaternion", joint_damping=2.0)
    res = simulate(ArmPlant(panda), pd_law, (0.0, 3.0), np.r_[Q0_PANDA, np.zeros(7)], h=1e-3, Ts=1e-3)
    assert max(_pose_errors(panda, res.x[-1, :7], T_f)) < 1e-3


def test_pose_inverse_dynamics_imposes_the_task_acceleration(panda, rng):
    """Exact model: J q̈ + J̇ q̇ = a_d + K_D (v_d − J q̇) + K_P x̃, with J̇q̇ by central differences of J(q(t))
    and x̃ = [p_d − p_e; r sin(ϑ/2)] from the poses; the posture term stays in the null space."""
    path = _pose_path(direct_kinematics(panda, Q0_PANDA))
    ctrl = OperationalInverseDynamics(panda, 100.0, 20.0, path, orientation="quaternion",
                                      null_space_damping=5.0, posture=Q0_PANDA, posture_stiffness=9.0)
    for t in (0.2, 0.6):
        q, qd = Q0_PANDA + rng.uniform(-0.1, 0.1, 7), rng.uniform(-0.5, 0.5, 7)
        qdd = forward_dynamics(panda, q, qd, ctrl(t, ArmMeasurement(q, qd)))
        h = 1e-6
        J = geometric_jacobian(panda, q)
        Jdot_qd = (geometric_jacobian(panda, q + h * qd) - geometric_jacobian(panda, q - h * qd)) @ qd / (2 * h)
        T_d, v_d, a_d = path(t)
        T_e = direct_kinematics(panda, q)
        theta, r = rotation_to_axis_angle(T_d[:3, :3] @ T_e[:3, :3].T)
        e = np.r_[T_d[:3, 3] - T_e[:3, 3], np.sin(theta / 2) * r]
        np.testing.assert_allclose(J @ qdd + Jdot_qd, a_d + 20.0 * (v_d - J @ qd) + 100.0 * e, atol=1e-6)


def test_position_task_on_the_redundant_panda(panda):
    """A position-only task (3 rows) on 7 joints: the null-space terms keep the arm still at the end."""
    p_d = direct_kinematics(panda, Q0_PANDA)[:3, 3] + DP
    ctrl = OperationalInverseDynamics(panda, 400.0, 40.0, p_d, null_space_damping=10.0, posture=Q0_PANDA,
                                      posture_stiffness=25.0)
    res = simulate(ArmPlant(panda), ctrl, (0.0, 2.0), np.r_[Q0_PANDA, np.zeros(7)], h=1e-3, Ts=1e-3)
    assert np.linalg.norm(direct_kinematics(panda, res.x[-1, :7])[:3, 3] - p_d) < 1e-6
    assert np.abs(res.x[-1, 7:]).max() < 1e-4


def test_bad_pose_tasks_raise(panda):
    T = direct_kinematics(panda, Q0_PANDA)
    with pytest.raises(ValueError, match="orientation"):
        OperationalPDGravity(panda, 1.0, 1.0, T, orientation="euler_xyz")
    with pytest.raises(ValueError, match="orientation"):
        OperationalInverseDynamics(panda, 1.0, 1.0, T, orientation="rpy")
    with pytest.raises(ValueError, match="reference"):
        OperationalPDGravity(panda, 1.0, 1.0, np.eye(3), orientation="quaternion")
    with pytest.raises(ValueError, match="reference"):
        OperationalInverseDynamics(panda, 1.0, 1.0, lambda t: (T, np.zeros(3), np.zeros(6)), orientation="quaternion")
    with pytest.raises(ValueError, match="posture"):
        OperationalInverseDynamics(panda, 1.0, 1.0, T, orientation="quaternion", posture_stiffness=1.0)
    with pytest.raises(ValueError, match="joint_damping"):
        OperationalPDGravity(panda, 1.0, 1.0, T, orientation="quaternion", joint_damping=-1.0)
    with pytest.raises(ValueError, match="null_space_damping"):
        OperationalInverseDynamics(panda, 1.0, 1.0, T, orientation="quaternion", null_space_damping=-1.0)
    with pytest.raises(ValueError, match="no frame"):
        OperationalPDGravity(panda, 1.0, 1.0, T, orientation="quaternion", frame="nope")


def test_without_null_space_terms_the_panda_drifts(panda):
    """The reason for y_0: with the task alone the self-motion keeps going (measured ≈ 0.19 rad in 2–3 s)."""
    T_d = _moved(direct_kinematics(panda, Q0_PANDA), 1.0)
    ctrl = OperationalInverseDynamics(panda, np.r_[[400.0] * 3, [800.0] * 3], 40.0, T_d, orientation="quaternion")
    res = simulate(ArmPlant(panda), ctrl, (0.0, 3.0), np.r_[Q0_PANDA, np.zeros(7)], h=1e-3, Ts=1e-3)
    k2 = np.searchsorted(res.t, 2.0)
    assert max(_pose_errors(panda, res.x[-1, :7], T_d)) < 1e-5                  # the task is still met …
    assert np.abs(res.x[-1, :7] - res.x[k2, :7]).max() > 0.05                     # … but the arm wanders


def test_solve_task_3x3_adjugate_matches_lapack_and_refuses_singular():
    """The 3 × 3 fast path (adjugate over the determinant) agrees with LAPACK's LU solve on random
    well-conditioned tasks, and a numerically singular J still gives None (cond > 1e10)."""
    from rigid_body.task_space import _solve3, solve_task

    rng = np.random.default_rng(3)
    for _ in range(50):
        J, b = rng.normal(size=(3, 3)), rng.normal(size=3)
        y = _solve3(J, b)
        assert y is not None
        np.testing.assert_allclose(y, np.linalg.solve(J, b), rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(J @ solve_task(J, b), b, atol=1e-12)
    J = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0 + 1e-13], [0.0, 1.0, 1.0]])      # rows 1, 2 almost parallel
    assert _solve3(J, np.ones(3)) is None and solve_task(J, np.ones(3)) is None
    assert solve_task(np.zeros((3, 3)), np.ones(3)) is None
