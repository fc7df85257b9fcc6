"""Flat-output and chained-form planners: boundary conditions, flatness, the (11.50) system, bad input."""

import numpy as np
import pytest

from planners import wheeled as pw


def test_cartesian_path_meets_boundary_postures_forward_and_backward():
    for k in (1.0, -2.0):
        q_i, q_f = np.array([0.5, -0.2, 0.3]), np.array([-1.0, 2.0, -1.2])
        path = pw.cartesian_polynomial_path(q_i, q_f, k, k)
        p, _, _ = path(np.array([0.0, 1.0]))
        th, v, _ = path.geometric_inputs(np.array([0.0, 1.0]))
        np.testing.assert_allclose(p, [q_i[:2], q_f[:2]], atol=1e-14)
        np.testing.assert_allclose(np.angle(np.exp(1j * (th - [q_i[2], q_f[2]]))), 0, atol=1e-12)
        np.testing.assert_allclose(v, [k, k], atol=1e-12)


def test_flat_inputs_equal_finite_differences_of_heading_and_arc_length():
    ref = pw.FigureEight(a=1.5, T=12.0)
    t, dt = 2.3, 1e-5
    a, b, c = ref(t - dt), ref(t), ref(t + dt)
    assert b.omega == pytest.approx((c.theta - a.theta) / (2 * dt), abs=1e-7)
    assert b.v == pytest.approx(np.linalg.norm(c.p - a.p) / (2 * dt), rel=1e-8)


def test_time_scaled_path_holds_the_final_posture():
    path = pw.cartesian_polynomial_path([0, 0, 0], [2, 1, np.pi / 2])
    ref = pw.TimeScaledPath(path, 10.0)
    end = ref(12.0)
    np.testing.assert_allclose(end.p, [2, 1])
    assert end.v == 0 and end.omega == 0 and end.theta == pytest.approx(np.pi / 2)
    assert ref(5.0).v == pytest.approx(path.geometric_inputs(0.5)[1] / 10.0)


def test_parameterised_inputs_reach_the_goal_for_any_n(rng):
    for n in (3, 4, 5):
        for unit in (False, True):
            z_i, z_f = rng.normal(size=n), rng.normal(size=n)
            path = pw.parameterised_inputs(z_i, z_f, unit_interval=unit)
            np.testing.assert_allclose(path.z(path.s_f), z_f, atol=1e-9)
            np.testing.assert_allclose(path.z(0.0), z_i, atol=1e-14)


def test_interpolation_scheme_matches_parameterised_inputs(rng):
    z_i, z_f = rng.normal(size=3), rng.normal(size=3)
    s = np.linspace(0, 1, 50)
    np.testing.assert_allclose(pw.parameterised_inputs(z_i, z_f, True).z(s), pw.chained_form_interpolation(z_i, z_f).z(s),
                               atol=1e-12)


def test_bad_inputs_name_the_argument():
    with pytest.raises(ValueError, match="Δ = 0"):
        pw.parameterised_inputs([0, 1, 2], [0, 3, 4])
    with pytest.raises(ValueError, match="n ≥ 3"):
        pw.chained_form_system([0, 1], [1, 2])
    with pytest.raises(ValueError, match="`k_i`"):
        pw.cartesian_polynomial_path([0, 0, 0], [1, 1, 0], 1.0, -1.0)
    with pytest.raises(ValueError, match="`q_f`"):
        pw.cartesian_polynomial_path([0, 0, 0], [1, 1])
    with pytest.raises(ValueError, match="`v_max`"):
        pw.uniform_time_scaling(pw.cartesian_polynomial_path([0, 0, 0], [1, 1, 0]), 0.0, 1.0)
    with pytest.raises(ValueError, match="stops"):
        pw.unicycle_flat_inputs(np.zeros(2), np.ones(2))


def test_dubins_closed_forms_and_end_postures(rng):
    assert pw.dubins_path([0, 0, 0], [3, 0, 0], 2.0).length == pytest.approx(3.0)
    assert pw.dubins_path([0, 0, 0], [0, -4, np.pi], 2.0).length == pytest.approx(2 * np.pi)  # right U-turn, ρ = 2
    assert pw.dubins_path([0, 0, 0], [0, -4, np.pi], 2.0).word[0] == "R"
    for _ in range(50):
        q_i, q_f = rng.uniform(-3, 3, 3), rng.uniform(-3, 3, 3)
        for p in pw.dubins_paths(q_i, q_f, 0.7):
            e = p.end() - q_f
            assert np.max(np.abs(np.r_[e[:2], np.sin(e[2]), 1 - np.cos(e[2])])) < 1e-7
            assert p.sample(0.05).shape[1] == 3


def test_single_arc_is_its_own_dubins_path():
    arc = pw.DubinsPath(np.zeros(3), 1.0, "LSL", np.array([1.2, 0.0, 0.0]))
    assert pw.dubins_path(np.zeros(3), arc.end(), 1.0).length == pytest.approx(1.2)


def test_steering_feasible_path_respects_the_bound_or_says_why():
    path = pw.steering_feasible_path([0, 0, 0], [-7, -2.5, 0], 2.5, 0.6, forward=False)
    assert pw.max_steering_angle(path, 2.5) <= 0.6 and not path.forward
    with pytest.raises(ValueError, match="phi_max"):
        pw.steering_feasible_path([0, 0, 0], [-1, -2.5, 0], 2.5, 0.3, forward=False)


def test_time_scaled_path_with_quintic_law_starts_and_stops_at_rest():
    from planners.timing import quintic_law

    ref = pw.TimeScaledPath(pw.cartesian_polynomial_path([0, 0, 0], [2, 1, 0.5]), law=quintic_law(0.0, 1.0, 5.0))
    assert ref(0.0).v == pytest.approx(0, abs=1e-12) and ref(5.0).v == pytest.approx(0, abs=1e-12)
    np.testing.assert_allclose(ref(5.0).p, [2, 1], atol=1e-12)
    with pytest.raises(ValueError, match="either"):
        pw.TimeScaledPath(pw.cartesian_polynomial_path([0, 0, 0], [2, 1, 0.5]))


def test_reeds_shepp_reaches_the_goal_and_is_never_longer_than_dubins(rng):
    for _ in range(100):
        q_i, q_f = rng.uniform(-3, 3, 3), rng.uniform(-3, 3, 3)
        paths = pw.reeds_shepp_paths(q_i, q_f, 0.8)
        for p in paths:
            e = p.end() - q_f
            assert np.max(np.abs(np.r_[e[:2], np.sin(e[2]), 1 - np.cos(e[2])])) < 1e-7
        assert paths[0].length <= pw.dubins_path(q_i, q_f, 0.8).length + 1e-9
    assert pw.reeds_shepp_path([0, 0, 0], [-2, 0, 0], 1.0).length == pytest.approx(2.0)
