"""Task space: the one-pass frame state against separate kinematics passes and finite differences,
the pose errors against their closed forms (Rodrigues), the inverses and the joint rates against
the two-link arm's closed-form kinematics."""

import numpy as np
import pytest

from tests import two_link_closed_form as arm2
from rigid_body.kinematics import direct_kinematics, geometric_jacobian, jacobian_derivative_times_qd
from rigid_body.robots import load
from rigid_body.rotations import axis_angle_to_rotation, rotation_to_rpy
from rigid_body.task_space import (FrameState, TaskSpace, damped_least_squares_inverse, frame_state, joint_rates,
                                   joint_reference,
                                   orientation_error, pose_error, pose_residual, weighted_pseudo_inverse)


@pytest.fixture(scope="module")
def panda():
    return load("panda")


def test_frame_state_equals_three_separate_passes(panda, rng):
    ur5 = load("ur5")
    for robot, frame in ((panda, None), (panda, "panda_link4"), (ur5, None)):
        for _ in range(5):
            q = robot.random_configuration(rng)
            qd = rng.uniform(-1.5, 1.5, robot.nv)
            s = frame_state(robot, q, qd, frame)
            np.testing.assert_allclose(s.T, direct_kinematics(robot, q, frame), atol=1e-12)
            np.testing.assert_allclose(s.J, geometric_jacobian(robot, q, frame), atol=1e-12)
            np.testing.assert_allclose(s.Jdot_qd, jacobian_derivative_times_qd(robot, q, qd, frame), atol=1e-12)
            assert frame_state(robot, q, frame=frame).Jdot_qd is None


def test_jdot_qd_is_the_derivative_of_J_along_the_motion(panda, rng):
    """J̇q̇ = d/dt [J(q + t q̇)] q̇ at t = 0 (central differences of the Jacobian alone)."""
    h = 1e-6
    for _ in range(5):
        q, qd = panda.random_configuration(rng), rng.uniform(-1.0, 1.0, 7)
        fd = (geometric_jacobian(panda, q + h * qd) - geometric_jacobian(panda, q - h * qd)) @ qd / (2 * h)
        np.testing.assert_allclose(frame_state(panda, q, qd).Jdot_qd, fd, atol=1e-7)


def test_orientation_errors_match_their_closed_forms(panda, rng):
    """R_d = R(ϑ, r) R_e: angle–axis e_O = r sin ϑ (3.85), quaternion e_O = r sin(ϑ/2) (3.91)."""
    q = panda.random_configuration(rng)
    T_e = direct_kinematics(panda, q)
    for _ in range(5):
        r = rng.normal(size=3)
        r /= np.linalg.norm(r)
        theta, dp = rng.uniform(0.1, 2.5), rng.normal(scale=0.1, size=3)
        T_d = T_e.copy()
        T_d[:3, :3] = axis_angle_to_rotation(theta, r) @ T_e[:3, :3]
        T_d[:3, 3] += dp
        for kind, expected in (("axis_angle", np.sin(theta)), ("quaternion", np.sin(theta / 2))):
            err = pose_error(panda, q, T_d, task=TaskSpace(orientation=kind))
            np.testing.assert_allclose(err.e, np.r_[dp, expected * r], atol=1e-12)
            np.testing.assert_allclose(err.J, geometric_jacobian(panda, q), atol=1e-12)
        assert pose_residual(T_d, T_e) == pytest.approx(max(np.linalg.norm(dp), theta), abs=1e-9)
    R_d, R_e = T_d[:3, :3], T_e[:3, :3]
    np.testing.assert_allclose(orientation_error(R_d, R_e, "rpy"),
                               np.angle(np.exp(1j * (rotation_to_rpy(R_d).angles - rotation_to_rpy(R_e).angles))))


def test_pose_error_with_velocity_gives_the_task_rows_of_jdot_qd(panda, rng):
    q, qd = panda.random_configuration(rng), rng.uniform(-1, 1, 7)
    rows = (0, 2, 3, 5)
    err = pose_error(panda, q, direct_kinematics(panda, q), task=TaskSpace(orientation="quaternion", rows=rows), qd=qd)
    np.testing.assert_allclose(err.Jdot_qd, jacobian_derivative_times_qd(panda, q, qd)[list(rows)], atol=1e-12)
    with pytest.raises(ValueError, match="Euler"):
        pose_error(panda, q, direct_kinematics(panda, q), task=TaskSpace(orientation="rpy"), qd=qd)


def test_generalised_inverses(rng):
    J = rng.normal(size=(3, 6))
    np.testing.assert_allclose(weighted_pseudo_inverse(J), np.linalg.pinv(J), atol=1e-10)   # (3.52): SVD route
    W = np.diag(rng.uniform(1, 3, 6))
    Jw = weighted_pseudo_inverse(J, W)
    np.testing.assert_allclose(J @ Jw, np.eye(3), atol=1e-10)
    # (3.50) minimises ½ q̇ᵀ W q̇ among the solutions of J q̇ = v: any null-space step costs more
    v, N = rng.normal(size=3), np.eye(6) - np.linalg.pinv(J) @ J
    qd = Jw @ v
    for _ in range(5):
        other = qd + N @ rng.normal(size=6)
        assert other @ W @ other >= qd @ W @ qd - 1e-12
    # (3.59): the DLS inverse is the regularised least-squares solution (Jᵀ J + k² I)⁻¹ Jᵀ
    np.testing.assert_allclose(damped_least_squares_inverse(J, 0.5), np.linalg.solve(J.T @ J + 0.25 * np.eye(6), J.T),
                               atol=1e-12)
    with pytest.raises(ValueError, match="singular"):
        weighted_pseudo_inverse(np.ones((2, 3)))
    with pytest.raises(ValueError, match="`k`"):
        damped_least_squares_inverse(J, -1.0)


def test_joint_rates_against_the_two_link_closed_form(rng):
    """J q̇ = ẋ and J q̈ + J̇ q̇ = ẍ with the closed-form Jacobian and J̇q̇ of the two-link arm."""
    robot = load("planar_2r")
    for _ in range(5):
        q = np.array([rng.uniform(-np.pi, np.pi), rng.uniform(0.3, 2.8)])
        xd, xdd = rng.normal(size=2), rng.normal(size=2)
        qd, qdd = joint_rates(robot, q, xd, xdd, rows=(0, 1))
        np.testing.assert_allclose(arm2.jacobian(q) @ qd, xd, atol=1e-12)
        np.testing.assert_allclose(arm2.jacobian(q) @ qdd + arm2.jacobian_derivative_times_qd(q, qd), xdd, atol=1e-10)
    with pytest.raises(ValueError, match="singular"):
        joint_rates(robot, [0.3, 0.0], [1.0, 0.0], [0.0, 0.0], rows=(0, 1))
    with pytest.raises(ValueError, match="singular"):  # σ_min/σ_max ≈ 1e-13: condition number above 1e12
        joint_rates(robot, [0.3, 2e-13], [1.0, 0.0], [0.0, 0.0], rows=(0, 1))
    with pytest.raises(ValueError, match="singular"):  # rows z, ω_x of a planar arm: J = 0
        joint_rates(robot, [0.3, 1.0], [1.0, 0.0], [0.0, 0.0], rows=(2, 3))
    with pytest.raises(ValueError, match="rows"):
        joint_rates(robot, [0.3, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0], rows=(0, 1, 2))


def test_bad_inputs_raise(panda):
    with pytest.raises(ValueError, match="`q`"):
        frame_state(panda, np.zeros(6))
    with pytest.raises(ValueError, match="`qd`"):
        frame_state(panda, np.zeros(7), [np.nan] * 7)
    with pytest.raises(ValueError, match="no frame"):
        frame_state(panda, np.zeros(7), frame="panda_link99")
    with pytest.raises(ValueError, match="orientation"):
        TaskSpace(orientation="euler_xyz")
    with pytest.raises(ValueError, match="rows"):
        TaskSpace(orientation="none", rows=(0, 4))
    assert isinstance(frame_state(panda, np.zeros(7)), FrameState)


# --------------------------------------------------------------------------------------------
# joint_reference computed at the sample instants before the loop
# --------------------------------------------------------------------------------------------

class CircleLaw:
    """p(t) on a circle of the planar arm's workspace (scalar t or an array of N times → (N, 3))."""
    t_i, t_f = 0.0, 1.0

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        w, c, r = 2.0, np.array([0.6, -0.2]), 0.12
        a = w * t
        p = np.stack([c[0] + r * np.cos(a), c[1] + r * np.sin(a), 0 * a], axis=-1)
        pd = np.stack([-r * w * np.sin(a), r * w * np.cos(a), 0 * a], axis=-1)
        pdd = np.stack([-r * w * w * np.cos(a), -r * w * w * np.sin(a), 0 * a], axis=-1)
        return p, pd, pdd


def test_joint_reference_at_sample_times_matches_the_per_sample_reference():
    from rigid_body.kinematics import inverse_kinematics_planar_3r
    robot = load("planar_3r")
    law = CircleLaw()
    q0 = inverse_kinematics_planar_3r(np.array([*law(0.0)[0][:2], -np.pi / 2]))[0]
    args = (robot, inverse_kinematics_planar_3r, law, (0, 1), (-np.pi / 2,), (0, 1, 5), q0)
    times = np.arange(501) * 2e-3
    per_sample, at_times = joint_reference(*args), joint_reference(*args, times=times)
    for t in times:
        for a, b in zip(per_sample(t), at_times(t)):
            np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12)
    a, b = per_sample(0.5011), at_times(0.5011)            # between samples: solved there
    np.testing.assert_allclose(b[0], a[0], atol=1e-12)
    with pytest.raises(ValueError, match="`times`"):
        joint_reference(*args, times=[0.0, 0.0])


def test_joint_rates_at_matches_joint_rates_and_names_a_singular_sample():
    from rigid_body.task_space import joint_rates_at
    robot = load("planar_3r")
    rng = np.random.default_rng(3)
    Q = rng.uniform(robot.lower, robot.upper, size=(20, 3))
    XD, XDD = rng.normal(size=(20, 3)), rng.normal(size=(20, 3))
    Qd, Qdd = joint_rates_at(robot, Q, XD, XDD, (0, 1, 5))
    for q, xd, xdd, qd, qdd in zip(Q, XD, XDD, Qd, Qdd):
        ref = joint_rates(robot, q, xd, xdd, (0, 1, 5))
        np.testing.assert_allclose(qd, ref[0], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(qdd, ref[1], rtol=1e-12, atol=1e-12)
    Q[7, 1] = 0.0                                           # stretched elbow: J singular
    with pytest.raises(ValueError, match="sample 7"):
        joint_rates_at(robot, Q, XD, XDD, (0, 1, 5))
