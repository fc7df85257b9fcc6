"""Regressors and minimum parameters (Problems 7.4, 7.5) against Pinocchio RNEA with mimic rotors."""

import dataclasses

import numpy as np
import pytest

from rigid_body.robots import robot_from_dh
from rigid_body.dynamics import inverse_dynamics
from rigid_body import lagrange as lg
from rigid_body.regressor import (identify, minimum_parameters, payload_link_parameters, pr_minimum_parameters,
                                  pr_regressor, stack_regressor, two_link_parameters, two_link_reference_regressor,
                                  two_link_regressor, two_link_textbook_parameters, two_link_textbook_regressor)
from rigid_body.robots import load
from rigid_body.book_robots import planar_2r, planar_pr


@pytest.mark.parametrize("convention", ["manual", "companion"])
@pytest.mark.parametrize("payload", [0.0, 10.0])
def test_two_link_regressor_matches_rnea(convention, payload):
    rng = np.random.default_rng(0)
    robot = load("planar_2r", payload=payload)
    pi = minimum_parameters(planar_2r().links, payload=payload, convention=convention)
    for _ in range(20):
        q, qd, qdd = rng.uniform(-3, 3, size=(3, 2))
        tau = two_link_regressor(q, qd, qdd, convention=convention) @ pi
        np.testing.assert_allclose(tau, inverse_dynamics(robot, q, qd, qdd), atol=1e-9)


def test_minimum_parameters_book_values():
    # Problem 7.4 / companion param.m: π' = [80, 97.5 (manual) | 97.51 (companion), 25, -2.5, 0.01].
    np.testing.assert_allclose(minimum_parameters(planar_2r().links), [80, 97.5, 25, -2.5, 0.01], atol=1e-12)
    np.testing.assert_allclose(minimum_parameters(planar_2r().links, convention="companion"),
                               [80, 97.51, 25, -2.5, 0.01], atol=1e-12)
    # Payload m_L = 10 kg (load_m.m): Δπ'1 = a1 m_L, Δπ'3 = a2 m_L.
    np.testing.assert_allclose(minimum_parameters(planar_2r().links, payload=10.0, convention="companion"),
                               [90, 97.51, 35, -2.5, 0.01], atol=1e-12)


@pytest.mark.parametrize("payload", [0.0, 4.0])
def test_pr_regressor_matches_rnea(payload):
    rng = np.random.default_rng(1)
    spec = planar_pr()
    links = [dataclasses.replace(spec.links[0], motor_inertia=0.02, motor_mass=1.0, gear_ratio=30.0),
             dataclasses.replace(spec.links[1], motor_inertia=0.01, motor_mass=2.0, gear_ratio=50.0)]
    robot = robot_from_dh(links, gravity=spec.gravity, payload=payload)
    pi = pr_minimum_parameters(links, payload=payload)
    for _ in range(10):
        q, qd, qdd = rng.normal(size=(3, 2))
        np.testing.assert_allclose(pr_regressor(q, qd, qdd) @ pi, inverse_dynamics(robot, q, qd, qdd), atol=1e-9)


def test_identify_recovers_parameters_and_rejects_poor_excitation():
    rng = np.random.default_rng(2)
    pi = minimum_parameters(planar_2r().links)
    q, qd, qdd = rng.uniform(-2, 2, size=(3, 60, 2))
    Y = stack_regressor(two_link_regressor, q, qd, qdd)
    result = identify(Y, Y @ pi)
    np.testing.assert_allclose(result.estimate, pi, atol=1e-8)
    assert result.rank == 5 and result.condition_number > 1
    with pytest.raises(ValueError, match="rank"):
        identify(Y[:, :4] @ np.ones((4, 5)), Y @ pi)  # rank-1 columns


def test_bad_input_names_the_argument():
    with pytest.raises(ValueError, match="`q`"):
        two_link_regressor([0.0], [0.0, 0.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="convention"):
        minimum_parameters(planar_2r().links, convention="book")
    with pytest.raises(ValueError, match="planar"):
        minimum_parameters(planar_pr().links)


@pytest.mark.parametrize("payload", [0.0, 10.0])
def test_reference_regressor_is_B_qdd_r_plus_C_qd_r_plus_g(payload):
    rng = np.random.default_rng(5)
    model = lg.serial_model(planar_2r(payload=payload))
    pi = minimum_parameters(planar_2r().links, payload=payload)
    for _ in range(10):
        q, qd, qd_r, qdd_r = rng.uniform(-3, 3, size=(4, 2))
        expected = (lg.inertia_matrix(model, q) @ qdd_r + lg.coriolis_matrix(model, q, qd) @ qd_r
                    + lg.gravity_torques(model, q))
        np.testing.assert_allclose(two_link_reference_regressor(q, qd, qd_r, qdd_r) @ pi, expected, atol=1e-9)


def test_textbook_eight_parameter_regressor_matches_rnea():
    rng = np.random.default_rng(6)
    robot = load("planar_2r")
    pi8 = two_link_textbook_parameters(two_link_parameters(planar_2r().links, convention="companion"))
    for _ in range(10):
        q, qd, qdd = rng.uniform(-3, 3, size=(3, 2))
        np.testing.assert_allclose(two_link_textbook_regressor(q, qd, qdd) @ pi8, inverse_dynamics(robot, q, qd, qdd),
                                   atol=1e-9)


def test_regressor_geometry_is_validated():
    with pytest.raises(ValueError, match="`a`"):
        two_link_regressor([0.0, 0.0], [0.0, 0.0], [0.0, 0.0], a=(np.nan, 1.0))
    with pytest.raises(ValueError, match="`a`"):
        two_link_regressor([0.0, 0.0], [0.0, 0.0], [0.0, 0.0], a=(1.0,))
    with pytest.raises(ValueError, match="`k_r`"):
        two_link_textbook_regressor([0.0, 0.0], [0.0, 0.0], [0.0, 0.0], k_r=(100.0,))
    with pytest.raises(ValueError, match="`g`"):
        pr_regressor([0.0, 0.0], [0.0, 0.0], [0.0, 0.0], g=np.inf)
    with pytest.raises(ValueError, match="`mass`"):
        payload_link_parameters(np.nan, 0.5, 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="non-negative"):
        payload_link_parameters(5.0, 0.5, 1.0, 1.0, -1.0)
