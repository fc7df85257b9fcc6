"""The book's Lagrange model (7.32), (7.45), (7.39) and Newton–Euler (7.107)–(7.114) vs Pinocchio.

Independent references: neither module uses Pinocchio, so each comparison can fail.
"""

import numpy as np
import pytest

from rigid_body import dynamics as dyn
from rigid_body import lagrange as lg
from rigid_body import newton_euler as ne
from rigid_body.book_robots import BOOK_ROBOTS
from rigid_body.dh import DHLink
from rigid_body.kinematics import geometric_jacobian
from rigid_body.robots import load, robot_from_dh


def random_arm(rng, n=6, prismatic=(2,), tensors=True):
    """A 6-DOF DH arm with motors (scalar and axisymmetric-tensor rotors) and random inertial data."""
    links = []
    for i in range(n):
        A = rng.normal(size=(3, 3))
        links.append(DHLink(
            a=rng.uniform(0, 0.5), alpha=rng.choice([0.0, np.pi / 2, -np.pi / 2]), d=rng.uniform(0, 0.3),
            theta=rng.uniform(-1, 1), joint="prismatic" if i in prismatic else "revolute",
            mass=rng.uniform(1, 5), com=tuple(rng.uniform(-0.2, 0.2, 3)), inertia=A @ A.T * 0.05 + 0.01 * np.eye(3),
            motor_inertia=np.diag([0.002, 0.002, 0.01]) if (tensors and i % 2) else 0.01,
            motor_mass=rng.uniform(0.5, 2), gear_ratio=rng.uniform(20, 100)))
    return links


@pytest.mark.parametrize("name", sorted(BOOK_ROBOTS))
def test_lagrange_and_newton_euler_match_pinocchio_on_book_robots(name):
    rng = np.random.default_rng(0)
    model, robot = lg.serial_model(BOOK_ROBOTS[name]()), load(name)
    for _ in range(5):
        q = robot.random_configuration(rng)
        qd, qdd = rng.normal(size=(2, robot.nv))
        scale = max(1.0, np.abs(dyn.inertia_matrix(robot, q)).max())
        np.testing.assert_allclose(lg.inertia_matrix(model, q), dyn.inertia_matrix(robot, q), atol=1e-12 * scale)
        np.testing.assert_allclose(lg.coriolis_matrix(model, q, qd), dyn.coriolis_matrix(robot, q, qd),
                                   atol=1e-12 * scale)
        np.testing.assert_allclose(lg.gravity_torques(model, q), dyn.gravity_torques(robot, q), atol=1e-10 * scale)
        tau = dyn.inverse_dynamics(robot, q, qd, qdd)
        np.testing.assert_allclose(ne.inverse_dynamics(model, q, qd, qdd), tau, atol=1e-10 * scale)
        np.testing.assert_allclose(lg.inverse_dynamics(model, q, qd, qdd), tau, atol=1e-10 * scale)


def test_six_dof_arm_with_motors_matches_pinocchio_crba_and_rnea():
    rng = np.random.default_rng(1)
    links = random_arm(rng)
    model = lg.serial_model(links, gravity=(0.0, 0.0, -9.81), payload=1.5)
    robot = robot_from_dh(links, payload=1.5)
    assert robot.has_mimic
    for _ in range(5):
        q = rng.uniform(-2, 2, 6)
        qd, qdd = rng.normal(size=(2, 6))
        np.testing.assert_allclose(lg.inertia_matrix(model, q), dyn.inertia_matrix(robot, q), atol=1e-11)
        np.testing.assert_allclose(lg.gravity_torques(model, q), dyn.gravity_torques(robot, q), atol=1e-10)
        # Pinocchio 4.1's computeCoriolisMatrix is wrong with mimic joints on spatial arms; the
        # foundation's coriolis_matrix works around it (Christoffel symbols by polarisation of RNEA).
        np.testing.assert_allclose(dyn.coriolis_matrix(robot, q, qd), lg.coriolis_matrix(model, q, qd), atol=1e-10)
        np.testing.assert_allclose(lg.christoffel_symbols(model, q), dyn.christoffel_symbols(robot, q), atol=1e-10)
        tau = dyn.inverse_dynamics(robot, q, qd, qdd)
        np.testing.assert_allclose(lg.inverse_dynamics(model, q, qd, qdd), tau, atol=1e-10)
        np.testing.assert_allclose(ne.inverse_dynamics(model, q, qd, qdd), tau, atol=1e-10)
        # Tip force and moment exerted by the end effector enter as J^T h_e (7.42).
        h = rng.normal(size=6)
        np.testing.assert_allclose(ne.inverse_dynamics(model, q, qd, qdd, h[:3], h[3:]),
                                   tau + geometric_jacobian(robot, q).T @ h, atol=1e-10)


def test_inertia_derivatives_match_finite_differences_and_skew_symmetry():
    rng = np.random.default_rng(2)
    model = lg.serial_model(random_arm(rng), payload=0.7)
    q, qd = rng.uniform(-2, 2, 6), rng.normal(size=6)
    D = lg.inertia_matrix_derivatives(model, q)
    eps = 1e-6
    for k in range(6):
        dq = np.zeros(6)
        dq[k] = eps
        fd = (lg.inertia_matrix(model, q + dq) - lg.inertia_matrix(model, q - dq)) / (2 * eps)
        np.testing.assert_allclose(D[k], fd, atol=1e-7)
    N = lg.inertia_matrix_rate(model, q, qd) - 2 * lg.coriolis_matrix(model, q, qd)
    np.testing.assert_allclose(N, -N.T, atol=1e-12)  # (7.48)
    # Problem 7.2: the alternative C gives the same C q̇ but N is not skew; q̇ᵀ N q̇ = 0 (7.49).
    Ca = lg.alternative_coriolis_matrix(model, q, qd)
    np.testing.assert_allclose(Ca @ qd, lg.coriolis_matrix(model, q, qd) @ qd, atol=1e-12)
    Na = lg.inertia_matrix_rate(model, q, qd) - 2 * Ca
    assert np.abs(Na + Na.T).max() > 1e-3
    assert abs(qd @ Na @ qd) < 1e-10


def test_newton_euler_recursion_of_problem_7_8():
    """PR arm: intermediate quantities of the manual's solution of 7.8 (frames of Fig. S7.2)."""
    rng = np.random.default_rng(3)
    from rigid_body.book_robots import planar_pr
    spec = planar_pr()
    model = lg.serial_model(spec)
    m2, a2 = spec.links[1].mass, spec.links[1].a
    lC2 = spec.links[1].com[0]
    g = 9.81
    d1, th2 = rng.uniform(-1, 1, 2)
    qd, qdd = rng.normal(size=(2, 2))
    res = ne.newton_euler(model, [d1, th2], qd, qdd)
    c2, s2 = np.cos(th2), np.sin(th2)
    np.testing.assert_allclose(res.p_ddot[0], [-g, qdd[0], 0.0], atol=1e-12)
    np.testing.assert_allclose(res.omega[1], [0, 0, qd[1]], atol=1e-12)
    np.testing.assert_allclose(res.p_ddot[1], [s2 * qdd[0] - a2 * qd[1] ** 2 - g * c2,
                                               c2 * qdd[0] + a2 * qdd[1] + g * s2, 0.0], atol=1e-12)
    l2 = lC2 + a2
    np.testing.assert_allclose(res.f[1], [m2 * s2 * qdd[0] - m2 * l2 * qd[1] ** 2 - m2 * g * c2,
                                          m2 * c2 * qdd[0] + m2 * l2 * qdd[1] + m2 * g * s2, 0.0], atol=1e-12)


def test_bad_input():
    model = lg.serial_model(BOOK_ROBOTS["planar_2r"]())
    with pytest.raises(ValueError, match="`q`"):
        lg.inertia_matrix(model, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="axisymmetric"):
        lg.serial_model([DHLink(a=1.0, mass=1.0, motor_inertia=np.diag([0.1, 0.2, 0.3]))])
    with pytest.raises(ValueError, match="payload"):
        lg.serial_model([DHLink(a=1.0, mass=1.0)], payload=-1.0)


def test_panda_standard_dh_table_reproduces_example_robot_data():
    """The Panda converted from Craig's modified DH: kinematics and dynamics equal load("panda")."""
    from rigid_body.kinematics import direct_kinematics
    from rigid_body.book_robots import panda_links, panda_tool

    rng = np.random.default_rng(4)
    links = panda_links(load("panda").model)
    panda, from_dh, model = load("panda"), robot_from_dh(links, tool=panda_tool()), lg.serial_model(links)
    for _ in range(3):
        q = panda.random_configuration(rng)
        qd, qdd = rng.normal(size=(2, 7))
        np.testing.assert_allclose(direct_kinematics(from_dh, q), direct_kinematics(panda, q), atol=1e-12)
        np.testing.assert_allclose(lg.inertia_matrix(model, q), dyn.inertia_matrix(panda, q), atol=1e-12)
        np.testing.assert_allclose(lg.coriolis_matrix(model, q, qd), dyn.coriolis_matrix(panda, q, qd), atol=1e-12)
        tau = dyn.inverse_dynamics(panda, q, qd, qdd)
        np.testing.assert_allclose(ne.inverse_dynamics(model, q, qd, qdd), tau, atol=1e-10)
        np.testing.assert_allclose(dyn.inverse_dynamics(from_dh, q, qd, qdd), tau, atol=1e-10)
