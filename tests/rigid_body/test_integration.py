"""The one RK4 (rigid_body/integration.py): its order against closed forms, the stage states it reports, and its
forward sensitivities against finite differences."""

import casadi as ca
import numpy as np

from rigid_body.integration import rk4_sensitivities, rk4_stages, rk4_step_law


def pendulum(x, u):
    """ẋ for θ̈ = −sin θ + u (a nonlinear test system)."""
    return np.array([x[1], -np.sin(x[0]) + u[0]])


def test_fourth_order_on_linear_decay():
    """x' = −x: one step is the Taylor series of e^{−h} to h⁴ (error h⁵/120), the global error falls 16× per halving."""
    h = 0.1
    x1 = rk4_step_law(lambda t, x, u: -x, 0.0, np.array([1.0]), None, h)
    assert abs(x1[0] - (1 - h + h**2 / 2 - h**3 / 6 + h**4 / 24)) < 1e-15
    errors = []
    for n in (10, 20, 40):
        x = np.array([1.0])
        for k in range(n):
            x = rk4_step_law(lambda t, x, u: -x, k / n, x, None, 1.0 / n)
        errors.append(abs(x[0] - np.exp(-1.0)))
    assert 14 < errors[0] / errors[1] < 18 and 14 < errors[1] / errors[2] < 18


def test_stages_are_the_states_the_step_visits():
    x, u, h = np.array([0.3, -0.2]), np.array([0.1]), 0.05
    x_next, stages = rk4_stages(pendulum, x, u, h)
    k1 = pendulum(x, u)
    k2 = pendulum(x + h / 2 * k1, u)
    k3 = pendulum(x + h / 2 * k2, u)
    k4 = pendulum(x + h * k3, u)
    for got, expected in zip(stages, (x, x + h / 2 * k1, x + h / 2 * k2, x + h * k3)):
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-15)
    np.testing.assert_allclose(x_next, x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(x_next, rk4_step_law(lambda t, s, v: pendulum(s, v), 0.0, x, u, h))


def test_sensitivities_match_finite_differences_numeric_and_symbolic():
    x, u, h = np.array([0.7, 0.4]), np.array([0.3]), 0.1
    E_x, E_u = np.eye(2, 3), np.eye(1, 3, 2)

    def slope(s, v):
        return pendulum(s, v), np.array([[0.0, 1.0], [-np.cos(s[0]), 0.0]]), np.array([[0.0], [1.0]])

    x_next, J, states, jacobians = rk4_sensitivities(slope, x, u, h, E_x, E_u)
    np.testing.assert_array_equal(x_next, rk4_stages(pendulum, x, u, h)[0])
    z, eps = np.r_[x, u], 1e-6
    fd = np.column_stack([(rk4_stages(pendulum, (z + e)[:2], (z + e)[2:], h)[0]
                           - rk4_stages(pendulum, (z - e)[:2], (z - e)[2:], h)[0]) / (2 * eps)
                          for e in eps * np.eye(3)])
    np.testing.assert_allclose(J, fd, rtol=0, atol=1e-9)
    for i, (s, ds) in enumerate(zip(states, jacobians)):                # each stage state's Jacobian too
        fd_s = np.column_stack([(rk4_stages(pendulum, (z + e)[:2], (z + e)[2:], h)[1][i]
                                 - rk4_stages(pendulum, (z - e)[:2], (z - e)[2:], h)[1][i]) / (2 * eps)
                                for e in eps * np.eye(3)])
        np.testing.assert_allclose(ds, fd_s, rtol=0, atol=1e-9)
    # the same arithmetic on CasADi symbols, against CasADi's own automatic differentiation
    xs, us, hs = ca.SX.sym("x", 2), ca.SX.sym("u", 1), ca.SX.sym("h")
    f = lambda s, v: ca.vertcat(s[1], -ca.sin(s[0]) + v[0])
    sym_slope = lambda s, v: (f(s, v), ca.vertcat(ca.horzcat(0, 1), ca.horzcat(-ca.cos(s[0]), 0)), ca.SX([[0], [1]]))
    xn, Jn, _, _ = rk4_sensitivities(sym_slope, xs, us, hs, ca.SX(E_x), ca.SX(E_u))
    ad = ca.jacobian(rk4_stages(f, xs, us, hs)[0], ca.vertcat(xs, us))
    g = ca.Function("g", [xs, us, hs], [xn, Jn, ad])
    got_x, got_J, ad_J = (np.asarray(v) for v in g(x, u, h))
    np.testing.assert_allclose(got_x.ravel(), x_next, rtol=0, atol=1e-15)
    np.testing.assert_allclose(got_J, ad_J, rtol=0, atol=1e-14)
    np.testing.assert_allclose(got_J, J, rtol=0, atol=1e-14)
