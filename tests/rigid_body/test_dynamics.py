"""planar_2r dynamics against the closed forms of Sect. 7.3.2 (7.82) with the motors' terms."""

import numpy as np
import pytest

from rigid_body.dynamics import (coriolis_matrix, forward_dynamics, gravity_torques, inertia_matrix,
                                 inverse_dynamics, nonlinear_effects, reference_torque)
from rigid_body.robots import load

from tests.two_link_closed_form import A1 as a1, I_M1 as Im1, I_M2 as Im2, K_R1 as kr1, K_R2 as kr2, M_M2 as mm2
from tests.two_link_closed_form import coriolis as C_closed, gravity as g_closed, inertia as B_closed


@pytest.mark.parametrize("mL", [0.0, 10.0])
def test_two_link_B_C_g_equal_closed_forms(mL, rng):
    robot = load("planar_2r", payload=mL) if mL else load("planar_2r")
    for _ in range(20):
        q, qd = rng.uniform(-np.pi, np.pi, 2), rng.normal(size=2)
        np.testing.assert_allclose(inertia_matrix(robot, q), B_closed(q, mL), atol=1e-9)
        np.testing.assert_allclose(coriolis_matrix(robot, q, qd), C_closed(q, qd, mL), atol=1e-9)
        np.testing.assert_allclose(gravity_torques(robot, q), g_closed(q, mL), atol=1e-9)


def test_brief_numbers_at_q_03_05():
    robot = load("planar_2r")
    q = np.array([0.3, 0.5])
    np.testing.assert_allclose(inertia_matrix(robot, q), [[243.8891, 45.4396], [45.4396, 122.5]], atol=1e-4)
    np.testing.assert_allclose(gravity_torques(robot, q), [920.615, 170.867], atol=1e-3)


def test_motor_coupling_term_kr2_Im2_is_in_b12():
    """Without rotors b12 loses exactly k_r2 I_m2 (the gyroscopic coupling of (7.32))."""
    q = np.array([0.1, 0.7])
    with_motors = inertia_matrix(load("planar_2r"), q)
    without = inertia_matrix(load("planar_2r", motors=False), q)
    assert with_motors[0, 1] - without[0, 1] == pytest.approx(kr2 * Im2, abs=1e-9)
    assert with_motors[1, 1] - without[1, 1] == pytest.approx(kr2**2 * Im2, abs=1e-9)
    assert with_motors[0, 0] - without[0, 0] == pytest.approx(kr1**2 * Im1 + Im2 + mm2 * a1**2, abs=1e-9)


def test_rnea_equals_lagrange_form_and_forward_inverts_inverse(rng):
    robot = load("planar_2r")
    for _ in range(20):
        q, qd, qdd = rng.uniform(-np.pi, np.pi, 2), rng.normal(size=2), rng.normal(size=2)
        tau = inverse_dynamics(robot, q, qd, qdd)
        np.testing.assert_allclose(tau, B_closed(q) @ qdd + C_closed(q, qd) @ qd + g_closed(q), atol=1e-8)
        np.testing.assert_allclose(nonlinear_effects(robot, q, qd), C_closed(q, qd) @ qd + g_closed(q), atol=1e-8)
        np.testing.assert_allclose(forward_dynamics(robot, q, qd, tau), qdd, atol=1e-9)


@pytest.mark.parametrize("name", ["panda", "ur5", "planar_3r"])
def test_forward_dynamics_without_mimic_uses_aba_and_inverts_rnea(name, rng):
    robot = load(name)
    assert not robot.has_mimic
    q, qd, qdd = robot.random_configuration(rng), rng.normal(size=robot.nv), rng.normal(size=robot.nv)
    tau = inverse_dynamics(robot, q, qd, qdd)
    np.testing.assert_allclose(forward_dynamics(robot, q, qd, tau), qdd, atol=1e-8)


def test_bad_inputs_raise_value_error_naming_the_argument():
    robot = load("planar_2r")
    with pytest.raises(ValueError, match="`qd` must have shape"):
        inverse_dynamics(robot, np.zeros(2), np.zeros(3), np.zeros(2))
    with pytest.raises(ValueError, match="`tau` must be finite"):
        forward_dynamics(robot, np.zeros(2), np.zeros(2), [np.inf, 0.0])


@pytest.mark.parametrize("mL", [0.0, 10.0])
def test_reference_torque_is_B_qdd_r_plus_C_qd_r_plus_g(mL, rng):
    """B q̈_r + C(q, q̇) q̇_r + g by polarised RNEA against (7.82) and against the book's Lagrange model."""
    robot = load("planar_2r", payload=mL) if mL else load("planar_2r")
    for _ in range(5):
        q, qd, qd_r, qdd_r = rng.uniform(-2, 2, (4, 2))
        expected = B_closed(q, mL) @ qdd_r + C_closed(q, qd, mL) @ qd_r + g_closed(q, mL)
        np.testing.assert_allclose(reference_torque(robot, q, qd, qd_r, qdd_r), expected, atol=1e-9)
    from rigid_body import lagrange as lg
    from rigid_body.book_robots import anthropomorphic_wrist
    spatial, model = load("anthropomorphic_wrist"), lg.serial_model(anthropomorphic_wrist())
    q = spatial.random_configuration(rng)
    qd, qd_r, qdd_r = rng.normal(size=(3, spatial.nv))
    expected = (lg.inertia_matrix(model, q) @ qdd_r + lg.coriolis_matrix(model, q, qd) @ qd_r
                + lg.gravity_torques(model, q))
    np.testing.assert_allclose(reference_torque(spatial, q, qd, qd_r, qdd_r), expected, atol=1e-9)
    with pytest.raises(ValueError, match="`qd_r`"):
        reference_torque(robot, q[:2], qd[:2], [0.0], qdd_r[:2])
