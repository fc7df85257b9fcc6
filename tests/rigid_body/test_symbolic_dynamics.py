"""Symbolic (CasADi) Newton–Euler against the book's two-link closed form and Pinocchio's RNEA/CRBA."""

import numpy as np
import pinocchio as pin
import pytest

from rigid_body.robots import load
from rigid_body.symbolic import inverse_dynamics_function


def _two_link_closed_form(q, qd, qdd):
    """Sect. 7.3.2 arm with motors, companion param.m: π = [80, 97.51, 25, −2.5, 0.01], k_r = 100, a = 1."""
    a1 = a2 = 1.0
    p1, p2, p3, p4, p5, kr2, g = 80.0, 97.51, 25.0, -2.5, 0.01, 100.0, 9.81
    c1, c2, s2, c12 = np.cos(q[0]), np.cos(q[1]), np.sin(q[1]), np.cos(q[0] + q[1])
    B = np.array([[a1 * p1 + p2 + (a2 + 2 * a1 * c2) * p3 + p4, (a2 + a1 * c2) * p3 + p4 + kr2 * p5],
                  [(a2 + a1 * c2) * p3 + p4 + kr2 * p5, a2 * p3 + p4 + kr2**2 * p5]])
    h = -a1 * p3 * s2
    c = np.array([2 * h * qd[0] * qd[1] + h * qd[1] ** 2, -h * qd[0] ** 2])
    g2 = g * c12 * p3
    return B @ qdd + c + np.array([g2 + g * c1 * p1, g2])


def test_planar_2r_with_rotors_matches_book_closed_form(rng):
    robot = load("planar_2r")
    assert robot.has_mimic
    tau = inverse_dynamics_function(robot)
    for _ in range(20):
        q, qd, qdd = rng.uniform(-3, 3, size=(3, 2))
        np.testing.assert_allclose(tau(q, qd, qdd).full().ravel(), _two_link_closed_form(q, qd, qdd),
                                   rtol=1e-10, atol=1e-9)


@pytest.mark.parametrize("name", ["anthropomorphic_wrist", "ur5", "planar_2r"])
def test_symbolic_rnea_matches_pinocchio(name, rng):
    robot = load(name)
    tau = inverse_dynamics_function(robot)
    for _ in range(10):
        q = robot.random_configuration(rng)
        qd, qdd = rng.normal(size=(2, robot.nv))
        ref = pin.rnea(robot.model, robot.data, q, qd, qdd)
        np.testing.assert_allclose(tau(q, qd, qdd).full().ravel(), ref, atol=1e-9 * (1 + np.abs(ref).max()))
        # B(q) q̈ from CRBA (a different algorithm)
        B = pin.crba(robot.model, robot.data, q)
        B = np.triu(B) + np.triu(B, 1).T
        diff = (tau(q, qd, qdd) - tau(q, qd, np.zeros(robot.nv))).full().ravel()
        np.testing.assert_allclose(diff, B @ qdd, atol=1e-9 * (1 + np.abs(B).max()))


def test_symbolic_dynamics_built_once_per_model_content(monkeypatch):
    """The recursions are cached by the model's content: an equal model reuses them, a changed one
    (here its armature) gets its own — never the stale expression. The Newton–Euler recursion is
    counted: an empty cache, then one build for two equal models and a second for the changed one."""
    import rigid_body.symbolic as symbolic

    monkeypatch.setattr(symbolic, "_BUILT", {})
    builds = []
    recursion = symbolic._newton_euler

    def counted(*args, **kwargs):
        builds.append(1)
        return recursion(*args, **kwargs)

    monkeypatch.setattr(symbolic, "_newton_euler", counted)
    model = load("planar_2r").model.copy()
    q, v, a = np.array([0.3, -0.4]), np.array([0.5, 0.2]), np.array([1.0, -2.0])
    before = inverse_dynamics_function(model)(q, v, a).full().ravel()
    assert len(builds) == 1
    np.testing.assert_allclose(inverse_dynamics_function(load("planar_2r"))(q, v, a).full().ravel(), before, atol=0)
    assert len(builds) == 1, "an equal model (a fresh load) built the recursion again"
    model.armature[:] = [0.5, 0.25]
    after = inverse_dynamics_function(model)(q, v, a).full().ravel()
    assert len(builds) == 2, "a changed model (its armature) reused the stale recursion"
    np.testing.assert_allclose(after - before, [0.5 * 1.0, 0.25 * -2.0], atol=1e-12)
    data = model.createData()
    np.testing.assert_allclose(after, pin.rnea(model, data, q, v, a), atol=1e-9)


@pytest.mark.parametrize("name", ["planar_2r", "ur5"])
def test_gravity_and_reference_torque_expressions_against_pinocchio(name, rng):
    """g(q) and B q̈_r + C(q, q̇) q̇_r + g (8.98) from the symbolic Newton–Euler against Pinocchio's
    computeGeneralizedGravity and CRBA, computeCoriolisMatrix (Christoffel C, (7.45))."""
    import casadi as ca

    from rigid_body.symbolic import gravity_expression, reference_torque_expression

    robot = load(name)
    model, data, n = robot.model, robot.data, robot.nv
    q, qd, qd_r, qdd_r = (rng.uniform(-1.0, 1.0, n) for _ in range(4))
    g = np.array(ca.evalf(gravity_expression(robot, q))).ravel()
    np.testing.assert_allclose(g, pin.computeGeneralizedGravity(model, data, q), rtol=1e-10, atol=1e-10)
    tau = np.array(ca.evalf(reference_torque_expression(robot, q, qd, qd_r, qdd_r))).ravel()
    B, C = pin.crba(model, data, q), pin.computeCoriolisMatrix(model, data, q, qd)
    np.testing.assert_allclose(tau, B @ qdd_r + C @ qd_r + g, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_forward_dynamics_derivatives_match_pinocchio_aba_derivatives(name, rng):
    """q̈ and ∂q̈/∂[q, q̇, τ] by −B⁻¹ ∂RNEA (symbolic) against Pinocchio's analytical ABA derivatives."""
    import casadi as ca

    from rigid_body.symbolic import forward_dynamics_derivatives_expression

    robot = load(name)
    n = robot.nv
    q_, v_, t_ = ca.SX.sym("q", n), ca.SX.sym("v", n), ca.SX.sym("t", n)
    f = ca.Function("fdd", [q_, v_, t_], list(forward_dynamics_derivatives_expression(robot, q_, v_, t_)))
    data = robot.model.createData()
    for _ in range(5):
        q = robot.random_configuration(rng)
        v, tau = rng.normal(size=n), rng.normal(size=n) * 5.0
        qdd, J = (np.array(o) for o in f(q, v, tau))
        pin.computeABADerivatives(robot.model, data, q, v, tau)
        Minv = np.triu(data.Minv) + np.triu(data.Minv, 1).T
        np.testing.assert_allclose(qdd.ravel(), data.ddq, rtol=1e-9, atol=1e-9)
        reference = np.hstack([data.ddq_dq, data.ddq_dv, Minv])
        np.testing.assert_allclose(J, reference, rtol=1e-8, atol=1e-8 * np.max(np.abs(reference)))


def test_forward_dynamics_derivatives_with_rotors_match_finite_differences(rng):
    """The book's two-link arm with its rotors (ABA refuses mimic joints): central differences of Pinocchio's
    forward dynamics by CRBA and RNEA."""
    import casadi as ca

    from rigid_body.dynamics import forward_dynamics
    from rigid_body.symbolic import forward_dynamics_derivatives_expression

    robot = load("planar_2r")
    n = robot.nv
    q_, v_, t_ = ca.SX.sym("q", n), ca.SX.sym("v", n), ca.SX.sym("t", n)
    f = ca.Function("fdd", [q_, v_, t_], list(forward_dynamics_derivatives_expression(robot, q_, v_, t_)))
    for _ in range(5):
        z = np.concatenate([rng.uniform(-2, 2, n), rng.normal(size=n), rng.normal(size=n) * 500.0])
        qdd, J = (np.array(o) for o in f(z[:n], z[n:2 * n], z[2 * n:]))
        fd = lambda w: forward_dynamics(robot, w[:n], w[n:2 * n], w[2 * n:])
        np.testing.assert_allclose(qdd.ravel(), fd(z), rtol=1e-10, atol=1e-10)
        steps = np.concatenate([np.full(2 * n, 1e-6), np.full(n, 1e-3)])
        central = np.column_stack([(fd(z + h * e) - fd(z - h * e)) / (2 * h) for h, e in zip(steps, np.eye(3 * n))])
        np.testing.assert_allclose(J, central, rtol=1e-6, atol=1e-6 * np.max(np.abs(central)))
