"""Wheeled-robot models: A(q) G(q) = 0, brackets (finite differences vs sympy), chained form, bad input."""

import numpy as np
import pytest
import sympy as sp

from rigid_body import wheeled as w


def test_input_matrices_annihilate_the_constraints(rng):
    for _ in range(10):
        q4 = rng.normal(size=4)
        for drive in ("rear", "front"):
            np.testing.assert_allclose(w.bicycle_constraints(q4, 1.3) @ w.bicycle_input_matrix(q4, 1.3, drive), 0,
                                       atol=1e-14)
        q3 = rng.normal(size=3)
        np.testing.assert_allclose(w.unicycle_constraint(q3) @ w.unicycle_input_matrix(q3), 0, atol=1e-15)
        lengths = rng.uniform(0.3, 2.0, 4)
        q = rng.normal(size=8)
        G = w.trailer_input_matrix(q, 0.8, lengths)
        np.testing.assert_allclose(w.trailer_constraints(q, 0.8, lengths) @ G, 0, atol=1e-14)
        assert np.linalg.matrix_rank(G) == 2


def test_differential_drive_maps_are_inverse_and_rhombus_vertices(rng):
    wr, wl = rng.normal(size=(2, 50))
    v, om = w.differential_drive_velocities(wr, wl, 0.1, 0.5)
    back = w.differential_drive_wheel_speeds(v, om, 0.1, 0.5)
    np.testing.assert_allclose(back, [wr, wl], atol=1e-12)
    assert w.differential_drive_limits(0.1, 0.5, 10.0) == pytest.approx((1.0, 4.0))
    vs, ws = w.saturate_wheel_speeds(2.0, 2.0, 0.1, 0.5, 10.0)
    assert vs / ws == pytest.approx(1.0) and max(map(abs, w.differential_drive_wheel_speeds(vs, ws, 0.1, 0.5))) == \
        pytest.approx(10.0)


def test_lie_bracket_finite_differences_match_sympy():
    x, y, th, phi = sp.symbols("x y theta phi")
    q = [x, y, th, phi]
    g1 = sp.Matrix([sp.cos(th), sp.sin(th), sp.tan(phi), 0])
    g2 = sp.Matrix([0, 0, 0, 1])
    b = w.lie_bracket_symbolic(g1, g2, q)
    f = sp.lambdify([q], [g1, g2, b])
    q0 = np.array([0.1, 0.2, 0.3, 0.4])
    fd = w.lie_bracket(lambda z: np.ravel(f(z)[0]).astype(float), lambda z: np.ravel(f(z)[1]).astype(float), q0)
    np.testing.assert_allclose(fd, np.ravel(f(q0)[2]).astype(float), atol=1e-9)


def test_accessibility_rank_of_bicycle_is_four_at_depth_three():
    fields = [lambda q: w.bicycle_input_matrix(q, 1.0)[:, 0], lambda q: w.bicycle_input_matrix(q, 1.0)[:, 1]]
    q0 = np.array([0.0, 0.0, 0.3, 0.2])
    assert w.accessibility_rank(fields, q0, depth=2) == 3
    assert w.accessibility_rank(fields, q0, depth=3) == 4
    sym = w.accessibility_fields_symbolic([sp.Matrix([sp.cos(sp.Symbol("t")), sp.sin(sp.Symbol("t")), 0]),
                                           sp.Matrix([0, 0, 1])], sp.symbols("x y t"), depth=2)
    assert sp.Matrix.hstack(*sym).rank(simplify=True) == 3


def test_unicycle_chained_form_round_trip_and_input_transformation(rng):
    q = rng.normal(size=3)
    z = w.unicycle_to_chained(q)
    np.testing.assert_allclose(w.chained_to_unicycle(z), q, atol=1e-14)
    u = rng.normal(size=2)
    v = w.unicycle_inputs_to_chained(z, u)
    np.testing.assert_allclose(w.chained_inputs_to_unicycle(z, v), u, atol=1e-14)
    # ż from the unicycle's motion (finite differences of the map) equals the chained form's velocity.
    eps = 1e-6
    qd = w.unicycle_velocity(q, u)
    zd = (w.unicycle_to_chained(q + eps * qd) - w.unicycle_to_chained(q - eps * qd)) / (2 * eps)
    np.testing.assert_allclose(zd, w.chained_form_velocity(z, v), atol=1e-8)


def test_bad_inputs_name_the_argument():
    with pytest.raises(ValueError, match="`q`"):
        w.unicycle_input_matrix([0.0, 1.0])
    with pytest.raises(ValueError, match="`ell`"):
        w.bicycle_input_matrix(np.zeros(4), -1.0)
    with pytest.raises(ValueError, match="`drive`"):
        w.bicycle_input_matrix(np.zeros(4), 1.0, drive="all")
    with pytest.raises(ValueError, match="infinity"):
        w.bicycle_icr(np.zeros(4), 1.0)
    with pytest.raises(ValueError, match="`lengths`"):
        w.trailer_input_matrix(np.zeros(6), 1.0, [1.0, -1.0])
    with pytest.raises(ValueError, match="`q`"):
        w.trailer_constraints(np.zeros(5), 1.0, [1.0, 1.0])
    with pytest.raises(ValueError, match="`N`"):
        w.trailer_configuration_size(-1)
    with pytest.raises(ValueError, match="`r`"):
        w.differential_drive_velocities(1.0, 1.0, 0.0, 0.5)
    with pytest.raises(ValueError, match="`depth`"):
        w.accessibility_rank([lambda q: q], np.zeros(2), depth=0)


def test_trailer_input_function_is_the_checked_matrix():
    """The hot-loop form (ℓ, ℓ_i checked once) spans the admissible velocities: A(q) G(q) = 0 with
    G(q) of rank 2 (a zero G would satisfy the constraints too)."""
    from rigid_body.wheeled import trailer_constraints, trailer_input_function

    ell, lengths = 0.4, [0.5, 0.3, 0.6]
    G = trailer_input_function(ell, lengths)
    rng = np.random.default_rng(5)
    for _ in range(10):
        q = rng.uniform(-1.0, 1.0, 7)
        np.testing.assert_allclose(trailer_constraints(q, ell, lengths) @ G(q), 0.0, atol=1e-14)
        assert np.linalg.matrix_rank(G(q)) == 2
    with pytest.raises(ValueError, match="lengths"):
        trailer_input_function(ell, [0.5, -0.3])
