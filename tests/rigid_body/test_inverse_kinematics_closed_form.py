"""Closed-form IK of the book's arms (Sect. 2.12): every returned solution reproduces the pose by
Pinocchio's direct kinematics on the URDF model, and the configuration the pose came from is among them."""

from __future__ import annotations

import numpy as np
import pytest

from rigid_body import kinematics as kin
from rigid_body.robots import load


def wrap(a):
    return np.arctan2(np.sin(a), np.cos(a))


def contains(qs, q, revolute, atol=1e-8):
    d = np.asarray(qs) - q
    d[:, revolute] = wrap(d[:, revolute])
    return bool(np.any(np.max(np.abs(d), axis=1) < atol))


def fk(robot, q):
    return kin.direct_kinematics(robot, q)


def random_q(robot, rng):
    return rng.uniform(robot.lower, robot.upper) if np.all(np.isfinite(robot.upper)) else rng.uniform(-np.pi, np.pi, robot.nq)


@pytest.mark.parametrize("params", [{}, {"a": (0.7, 0.4)}])
def test_planar_2r_both_elbows_reproduce_the_point(params):
    rng = np.random.default_rng(0)
    robot = load("planar_2r", **params)
    for _ in range(30):
        q = rng.uniform(-np.pi, np.pi, 2)
        p = fk(robot, q)[:2, 3]
        qs = kin.inverse_kinematics_planar_2r(p, **params)
        assert qs.shape == (2, 2)
        assert qs[kin.ELBOW_UP, 1] <= 0 <= qs[kin.ELBOW_DOWN, 1]
        for qk in qs:
            np.testing.assert_allclose(fk(robot, qk)[:2, 3], p, atol=1e-10)
        assert contains(qs, q, [0, 1])


def test_planar_3r_both_elbows_reproduce_the_pose():
    rng = np.random.default_rng(1)
    arm = dict(a=(0.5, 0.3, 0.3), lower=(None,) * 3, upper=(None,) * 3)  # no joint limits: both elbows
    robot = load("planar_3r", **arm)
    for _ in range(30):
        q = rng.uniform(-np.pi, np.pi, 3)
        T = fk(robot, q)
        x = [T[0, 3], T[1, 3], np.arctan2(T[1, 0], T[0, 0])]
        qs = kin.inverse_kinematics_planar_3r(x, **arm)
        for qk in qs:
            np.testing.assert_allclose(fk(robot, qk), T, atol=1e-10)
        assert contains(qs, q, [0, 1, 2])


def test_scara_ik_problem_2_20_and_companion_example():
    rng = np.random.default_rng(2)
    robot = load("scara")
    for _ in range(30):
        q = random_q(robot, rng)
        T = fk(robot, q)
        x = [*T[:3, 3], np.arctan2(T[1, 0], T[0, 0])]
        qs = kin.inverse_kinematics_scara(x)
        for qk in qs:
            np.testing.assert_allclose(fk(robot, qk), T, atol=1e-10)
        assert contains(qs, q, [0, 1, 3])
    # the companion file inv_ksu: x = [1, 1, 0.5, π/4] (elbow-up, a1 = a2 = 0.5) gives q = [π/2, −π/2, 0.5, π/4]
    # (here with a = (1, 1): p = (1, 1) is then reachable as in the companion's unit-length call)
    q_up = kin.inverse_kinematics_scara([1.0, 1.0, 0.5, np.pi / 4], a=(1.0, 1.0))[kin.ELBOW_UP]
    np.testing.assert_allclose(q_up, [np.pi / 2, -np.pi / 2, 0.5, np.pi / 4], atol=1e-12)


def test_cylindrical_ik_problem_2_19():
    rng = np.random.default_rng(3)
    robot = load("cylindrical")
    for _ in range(30):
        q = random_q(robot, rng)
        p = fk(robot, q)[:3, 3]
        qs = kin.inverse_kinematics_cylindrical(p)
        assert qs.shape == (1, 3)
        np.testing.assert_allclose(fk(robot, qs[0])[:3, 3], p, atol=1e-10)
        assert contains(qs, q, [0])


def test_spherical_arm_ik_two_solutions():
    rng = np.random.default_rng(4)
    robot = load("spherical")
    for _ in range(30):
        q = random_q(robot, rng)
        q[:2] = rng.uniform(-np.pi, np.pi, 2)
        p = fk(robot, q)[:3, 3]
        qs = kin.inverse_kinematics_spherical(p)
        for qk in qs:
            np.testing.assert_allclose(fk(robot, qk)[:3, 3], p, atol=1e-10)
        assert contains(qs, q, [0, 1])


@pytest.mark.parametrize("params", [{}, {"a2": 0.5, "a3": 0.5}, {"a2": 0.3, "a3": 0.6}])
def test_anthropomorphic_ik_four_solutions(params):
    rng = np.random.default_rng(5)
    robot = load("anthropomorphic", **params)
    for _ in range(30):
        q = rng.uniform(-np.pi, np.pi, 3)
        p = fk(robot, q)[:3, 3]
        qs = kin.inverse_kinematics_anthropomorphic(p, **params)
        assert qs.shape == (4, 3)
        assert len(kin.distinct_solutions(qs)) == 4
        for qk in qs:
            np.testing.assert_allclose(fk(robot, qk)[:3, 3], p, atol=1e-10)
        assert contains(qs, q, [0, 1, 2])


def test_anthropomorphic_ik_singular_cases_problem_2_18():
    rng = np.random.default_rng(6)
    robot = load("anthropomorphic")
    a2, a3 = 0.5, 0.4
    # s3 = 0 (outstretched and retracted), off the z0 axis: two distinct configurations
    for th3 in (0.0, np.pi):
        q = np.array([rng.uniform(-3, 3), rng.uniform(-1.4, 1.4), th3])
        p = fk(robot, q)[:3, 3]
        qs = kin.distinct_solutions(kin.inverse_kinematics_anthropomorphic(p))
        assert len(qs) == 2
        for qk in qs:
            np.testing.assert_allclose(fk(robot, qk)[:3, 3], p, atol=1e-10)
    # on the z0 axis: θ1 arbitrary
    for p, th3 in (([0, 0, a2 + a3], 0.0), ([0, 0, a2 - a3], np.pi), ([0, 0, -(a2 + a3)], 0.0)):
        for th1 in rng.uniform(-np.pi, np.pi, 5):
            qs = kin.inverse_kinematics_anthropomorphic(p, theta1=th1)
            assert np.allclose(wrap(qs[:2, 0] - th1), 0)
            for qk in qs:
                np.testing.assert_allclose(fk(robot, qk)[:3, 3], p, atol=1e-10)
    # a2 = a3 and p = 0: θ1 and θ2 arbitrary
    equal = load("anthropomorphic", a2=0.5, a3=0.5)
    for th1, th2 in rng.uniform(-np.pi, np.pi, (5, 2)):
        qs = kin.inverse_kinematics_anthropomorphic([0, 0, 0], theta1=th1, theta2=th2, a2=0.5, a3=0.5)
        for qk in qs:
            np.testing.assert_allclose(fk(equal, qk)[:3, 3], 0.0, atol=1e-10)


def test_spherical_wrist_ik_both_solutions():
    rng = np.random.default_rng(7)
    robot = load("spherical_wrist")
    for _ in range(30):
        q = rng.uniform(-np.pi, np.pi, 3)
        T = fk(robot, q)
        qs = kin.inverse_kinematics_spherical_wrist(T[:3, :3])
        assert qs.shape == (2, 3)
        for qk in qs:
            np.testing.assert_allclose(fk(robot, qk), T, atol=1e-10)
        assert contains(qs, q, [0, 1, 2])


def test_anthropomorphic_wrist_ik_eight_solutions():
    rng = np.random.default_rng(8)
    for params in ({}, {"a2": 0.4, "d4": 0.6, "d6": 0.15}):
        robot = load("anthropomorphic_wrist", **params)
        for _ in range(15):
            q = rng.uniform(-np.pi, np.pi, 6)
            T = fk(robot, q)
            qs = kin.inverse_kinematics_anthropomorphic_wrist(T, **params)
            assert qs.shape == (8, 6)
            assert len(kin.distinct_solutions(qs)) == 8
            for qk in qs:
                np.testing.assert_allclose(fk(robot, qk), T, atol=1e-10)
            assert contains(qs, q, list(range(6)))


# Puma 560, standard DH (Corke's table: a2 = 0.4318 between joints 2 and 3, a3 = 0.0203, shoulder offset d3).
PUMA_560 = [dict(alpha=np.pi / 2), dict(a=0.4318), dict(a=0.0203, d=0.15005, alpha=-np.pi / 2),
            dict(d=0.4318, alpha=np.pi / 2), dict(alpha=-np.pi / 2), dict()]


def random_6r_spherical_wrist(rng):
    """A random arm of the Puma class: offsets d1, d2, d3, lengths a2, a3, d4, d6, twist signs, joint offsets θ_i."""
    s1, s3, s4 = rng.choice([-1.0, 1.0], 3)
    th = rng.uniform(-1.0, 1.0, 6)
    return [dict(d=rng.uniform(0.1, 0.4), alpha=s1 * np.pi / 2, theta=th[0]),
            dict(a=rng.uniform(0.3, 0.6), d=rng.uniform(-0.2, 0.2), theta=th[1]),
            dict(a=rng.uniform(-0.1, 0.1), d=rng.uniform(-0.2, 0.2), alpha=s3 * np.pi / 2, theta=th[2]),
            dict(d=rng.uniform(0.3, 0.6), alpha=s4 * np.pi / 2, theta=th[3]),
            dict(alpha=-s4 * np.pi / 2, theta=th[4]), dict(d=rng.uniform(0.05, 0.2), theta=th[5])]


@pytest.mark.parametrize("arm", ["puma560", "random"])
def test_6r_spherical_wrist_ik_eight_solutions_by_pinocchio(arm):
    """Pinocchio's direct kinematics on the URDF built from the table is the reference (the solver checks the DH
    product itself): 8 distinct solutions reproduce the pose and the generating q is among them."""
    from rigid_body.robots import robot_from_dh

    rng = np.random.default_rng(11)
    for _ in range(3 if arm == "random" else 1):
        links = PUMA_560 if arm == "puma560" else random_6r_spherical_wrist(rng)
        robot = robot_from_dh(links)
        for _ in range(10):
            q = rng.uniform(-np.pi, np.pi, 6)
            T = fk(robot, q)
            qs = kin.inverse_kinematics_6r_spherical_wrist(T, links)
            assert qs.shape == (8, 6) and len(kin.distinct_solutions(qs, atol=1e-6)) == 8
            for qk in qs:
                np.testing.assert_allclose(fk(robot, qk), T, atol=1e-9)
            assert contains(qs, q, list(range(6)))


def test_anthropomorphic_wrist_is_the_6r_solver_on_the_book_table():
    from rigid_body.book_robots import anthropomorphic_wrist

    T = fk(load("anthropomorphic_wrist"), np.array([0.3, -0.5, 0.9, 0.2, 0.7, -1.1]))
    np.testing.assert_array_equal(kin.inverse_kinematics_anthropomorphic_wrist(T),
                                  kin.inverse_kinematics_6r_spherical_wrist(T, anthropomorphic_wrist().links))


def test_closed_forms_take_a_users_dh_table():
    links = [dict(a=0.8), dict(a=0.3)]
    from rigid_body.robots import robot_from_dh

    robot = robot_from_dh(links)
    q = np.array([0.4, -1.2])
    qs = kin.inverse_kinematics_planar_2r(fk(robot, q)[:2, 3], links=links)
    assert contains(qs, q, [0, 1])
    with pytest.raises(ValueError, match="`links` is not a two-link planar arm: link 2 has alpha"):
        kin.inverse_kinematics_planar_2r([0.5, 0.5], links=[dict(a=0.8), dict(a=0.3, alpha=0.2)])
    with pytest.raises(ValueError, match="either `links` or"):
        kin.inverse_kinematics_planar_2r([0.5, 0.5], links=links, a=(1.0, 1.0))
    with pytest.raises(ValueError, match="`links` is not a 6R arm with spherical wrist: it needs .*α5 = −α4"):
        kin.inverse_kinematics_6r_spherical_wrist(np.eye(4), PUMA_560[:4] + [dict(alpha=np.pi / 2), dict()])


@pytest.mark.parametrize("call, message", [
    (lambda: kin.inverse_kinematics_planar_2r([3.0, 0.0]), "unreachable"),
    (lambda: kin.inverse_kinematics_planar_3r([1.2, 0.0, 0.0]), "unreachable"),
    (lambda: kin.inverse_kinematics_scara([0.3, 0.2, 5.0, 0.0]), "unreachable.*d3"),
    (lambda: kin.inverse_kinematics_cylindrical([0.0, 0.0, 0.5]), "unreachable.*d3"),
    (lambda: kin.inverse_kinematics_spherical([0.05, 0.0, 0.5]), "unreachable"),
    (lambda: kin.inverse_kinematics_anthropomorphic([0.0, 0.0, 1.0]), "unreachable"),
    (lambda: kin.inverse_kinematics_anthropomorphic([0.0, 0.0, 0.05]), "unreachable"),
    (lambda: kin.inverse_kinematics_anthropomorphic_wrist(np.diag([1.0, 1.0, 1.0, 1.0]) + np.eye(4, k=3) * 2.0),
     "unreachable"),
    (lambda: kin.inverse_kinematics_spherical_wrist(np.ones((3, 3))), "`R`"),
    (lambda: kin.inverse_kinematics_6r_spherical_wrist(np.eye(4) + np.eye(4, k=3) * 2.0, PUMA_560), "unreachable"),
    (lambda: kin.inverse_kinematics_planar_2r([1.0, np.nan]), "`p` must be finite"),
])
def test_unreachable_or_bad_poses_raise(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_workspace_points_stay_within_reach():
    rng = np.random.default_rng(9)
    robot = load("planar_3r")
    pts = kin.workspace_points(robot, 500, rng)
    r = np.linalg.norm(pts[:, :2], axis=1)
    assert np.all(r <= 1.0 + 1e-12) and np.allclose(pts[:, 2], 0.0)
    with pytest.raises(ValueError, match="`n`"):
        kin.workspace_points(robot, 0, rng)
    with pytest.raises(ValueError, match="`rng`"):
        kin.workspace_points(robot, 10, 0)
    with pytest.raises(ValueError, match="`q_end`"):
        kin.joint_arc(robot, np.zeros(3), 0, np.nan)


# --------------------------------------------------------------------------------------------
# The vectorised planar three-link solver against the per-pose one
# --------------------------------------------------------------------------------------------

def test_planar_3r_batch_matches_the_per_pose_solver():
    """Same solutions (to 1e-12), same row order, same rows kept by the joint limits, pose by pose."""
    rng = np.random.default_rng(7)
    robot = load("planar_3r")
    Q0 = rng.uniform(robot.lower, robot.upper, size=(400, 3))
    X = np.array([[*fk(robot, q)[:2, 3], np.arctan2(fk(robot, q)[1, 0], fk(robot, q)[0, 0])] for q in Q0])
    Q, valid = kin.inverse_kinematics_planar_3r_batch(X)
    assert Q.shape == (400, 2, 3) and valid.shape == (400, 2)
    assert (~valid).any(), "some poses must have a branch outside the limits, or the filter is not exercised"
    for x, q, ok in zip(X, Q, valid):
        np.testing.assert_allclose(q[ok], kin.inverse_kinematics_planar_3r(x), rtol=0, atol=1e-12)


def test_planar_3r_batch_rejects_what_the_per_pose_solver_rejects():
    robot = load("planar_3r")
    T = fk(robot, np.array([0.2, 0.5, -0.3]))
    inside = [T[0, 3], T[1, 3], np.arctan2(T[1, 0], T[0, 0])]
    for pose, why in (([1.5, 0.0, 0.0], "pose 1 unreachable|point 1 unreachable"),   # beyond the reach
                      ([0.6, 0.0, 0.0], "pose 1 unreachable .* within its joint limits")):  # both branches out
        with pytest.raises(ValueError):
            kin.inverse_kinematics_planar_3r(np.array(pose))
        with pytest.raises(ValueError, match=why):
            kin.inverse_kinematics_planar_3r_batch(np.array([inside, pose]))
    with pytest.raises(ValueError, match="`X`"):
        kin.inverse_kinematics_planar_3r_batch(np.zeros((4, 2)))
    assert kin.batch_inverse_kinematics(kin.inverse_kinematics_planar_3r) is kin.inverse_kinematics_planar_3r_batch
    assert kin.batch_inverse_kinematics(kin.inverse_kinematics_scara) is None
