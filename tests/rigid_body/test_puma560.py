"""The Puma 560 as a named robot: the Robotics Toolbox's published torques (its test suite, MATLAB-derived,
4 decimals), the book's Lagrange reference, both motor models, and the eight closed-form IK solutions."""

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

from rigid_body import dynamics as dyn
from rigid_body import lagrange as lg
from rigid_body.book_robots import puma560
from rigid_body.dh import DHLink
from rigid_body.kinematics import direct_kinematics, distinct_solutions, inverse_kinematics_6r_spherical_wrist
from rigid_body.robots import load, robot_from_dh

# Robotics Toolbox for Python, tests/test_DHRobot.py (Puma560 at qn).
TOOLBOX_GRAVLOAD_QN = [0.0, 31.6399, 6.0351, 0.0, 0.0283, 0.0]
TOOLBOX_INERTIA_QN = [
    [3.6594, -0.4044, 0.1006, -0.0025, 0.0000, -0.0000],
    [-0.4044, 4.4137, 0.3509, 0.0000, 0.0024, 0.0000],
    [0.1006, 0.3509, 0.9378, 0.0000, 0.0015, 0.0000],
    [-0.0025, 0.0000, 0.0000, 0.1925, 0.0000, 0.0000],
    [0.0000, 0.0024, 0.0015, 0.0000, 0.1713, 0.0000],
    [-0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.1941]]
TOOLBOX_CORIOLIS_QN = [  # coriolis(qn, [1, 2, 3, 1, 2, 3])
    [-0.1735, -2.0494, -0.1178, -0.0002, -0.0045, 0.0001],
    [0.6274, 1.1572, 1.9287, -0.0015, -0.0003, -0.0000],
    [-0.3608, -0.7734, -0.0018, -0.0009, -0.0064, -0.0000],
    [0.0011, 0.0005, -0.0001, 0.0002, 0.0002, -0.0001],
    [-0.0002, 0.0028, 0.0046, -0.0002, -0.0000, -0.0000],
    [0.0001, 0.0000, 0.0000, 0.0000, 0.0000, 0]]
TOOLBOX_ITORQUE_QN = [3.1500, 9.4805, 3.6189, 0.1901, 0.3519, 0.5823]  # itorque(qn, [1, 2, 3, 1, 2, 3])


@pytest.fixture(scope="module")
def puma():
    return load("puma560")


def test_named_configurations_and_armature_model(puma):
    assert set(puma.configurations) >= {"qz", "qr", "qs", "qn", "neutral"}
    # the Toolbox's documented qn = [0, π/4, π, 0, π/4, 0] (q3 = π is outside this joint's limits): ours is
    # the same posture — equal angles modulo 2π, the same end-effector pose, and inside the limits
    qn, toolbox_qn = puma.configurations["qn"], np.array([0, np.pi / 4, np.pi, 0, np.pi / 4, 0])
    np.testing.assert_allclose(np.angle(np.exp(1j * (qn - toolbox_qn))), 0.0, atol=1e-12)
    np.testing.assert_allclose(direct_kinematics(puma, qn), direct_kinematics(puma, toolbox_qn), atol=1e-12)
    assert np.all(qn >= puma.lower) and np.all(qn <= puma.upper)
    assert not puma.has_mimic          # armature: ABA is available (forward dynamics below uses it)
    assert load("puma560", motors="rotors").has_mimic


def test_gravity_torques_at_qn_are_the_toolboxs(puma):
    np.testing.assert_allclose(dyn.gravity_torques(puma, puma.configurations["qn"]), TOOLBOX_GRAVLOAD_QN, atol=6e-5)


def test_inertia_coriolis_and_inertial_torque_at_qn_are_the_toolboxs(puma):
    qn = puma.configurations["qn"]
    B = dyn.inertia_matrix(puma, qn)
    np.testing.assert_allclose(B, TOOLBOX_INERTIA_QN, atol=6e-5)
    np.testing.assert_allclose(B @ [1, 2, 3, 1, 2, 3], TOOLBOX_ITORQUE_QN, atol=6e-5)
    np.testing.assert_allclose(dyn.coriolis_matrix(puma, qn, [1, 2, 3, 1, 2, 3]), TOOLBOX_CORIOLIS_QN, atol=6e-5)


def test_inertia_at_qz_and_qn_equals_the_book_lagrange_model_plus_armature(puma):
    """Lagrange (7.32) of the links alone (no Pinocchio) + diag(J_m G²) = CRBA of the armature model."""
    spec = puma560()
    bare = lg.serial_model([dataclasses.replace(l, motor_inertia=0.0) for l in spec.links], gravity=spec.gravity)
    armature = np.array([l.gear_ratio ** 2 * l.motor_inertia for l in spec.links])
    for name in ("qz", "qn", "qr", "qs"):
        q = puma.configurations[name]
        np.testing.assert_allclose(dyn.inertia_matrix(puma, q), lg.inertia_matrix(bare, q) + np.diag(armature),
                                   atol=1e-12, err_msg=name)
        np.testing.assert_allclose(dyn.gravity_torques(puma, q), lg.gravity_torques(bare, q), atol=1e-12)


def test_rotor_model_on_request_is_the_book_lagrange_model(rng):
    """load("puma560", motors="rotors"): the book's rotors (7.32) with every coupling term."""
    spec = puma560(motors="rotors")
    robot, model = load("puma560", motors="rotors"), lg.serial_model(spec)
    for _ in range(3):
        q, qd = rng.uniform(-np.pi, np.pi, size=6), rng.normal(size=6)
        np.testing.assert_allclose(dyn.inertia_matrix(robot, q), lg.inertia_matrix(model, q), atol=1e-12)
        np.testing.assert_allclose(dyn.nonlinear_effects(robot, q, qd),
                                   lg.coriolis_matrix(model, q, qd) @ qd + lg.gravity_torques(model, q), atol=1e-10)


def test_rne_with_published_friction_gives_the_toolboxs_torques(puma):
    """Toolbox ``rne`` includes friction: τ = RNEA(q, q̇, q̈) + τ_f(q̇), τ_f from its motor-side B and Tc."""
    qn, z, o = puma.configurations["qn"], np.zeros(6), np.ones(6)
    cases = [  # (q̇, q̈, gravity on?, Toolbox rne)
        (z, o, True, [3.35311, 36.0025, 7.42596, 0.190043, 0.203441, 0.194133]),
        (o, o, True, [32.4952, 60.867, 17.7436, 1.45452, 1.29911, 0.713781]),
        (o, z, True, [29.1421, 56.5044, 16.3528, 1.26448, 1.12392, 0.519648]),
        (o, o, False, [32.4952, 29.2271, 11.7085, 1.45452, 1.27086, 0.713781]),
    ]
    no_gravity = load("puma560")
    no_gravity.model.gravity = pin.Motion.Zero()
    for qd, qdd, gravity, expected in cases:
        robot = puma if gravity else no_gravity
        tau = dyn.inverse_dynamics(robot, qn, qd, qdd) + dyn.friction_torques(robot, qd)
        np.testing.assert_allclose(tau, expected, atol=6e-5)


def test_forward_dynamics_with_friction_is_the_toolboxs_accel(puma):
    """Toolbox ``accel(qn, q̇, τ)`` (friction included) by ABA on the armature model."""
    qn = puma.configurations["qn"]
    qd, tau = np.array([0.1, 0.2, 0.8, 0.2, 0.5, 1.0]), np.array([1.0, 3.2, 1.8, 0.1, 0.7, 4.6])
    qdd = dyn.forward_dynamics(puma, qn, qd, tau - dyn.friction_torques(puma, qd))
    np.testing.assert_allclose(qdd, [-7.4102, -9.8432, -10.9694, -4.4314, -0.9881, 21.0228], atol=6e-5)


def test_eight_closed_form_ik_solutions_reach_the_pose(puma, rng):
    spec = puma560()
    free = [dataclasses.replace(link, lower=None, upper=None) for link in spec.links]  # the geometry alone
    for q_true in (puma.configurations["qn"], puma.random_configuration(rng)):
        T = direct_kinematics(puma, q_true)
        within = inverse_kinematics_6r_spherical_wrist(T, spec.links)  # rows outside the Puma's limits dropped
        assert np.all(within >= puma.lower - 1e-9) and np.all(within <= puma.upper + 1e-9)
        qs = inverse_kinematics_6r_spherical_wrist(T, free)
        assert qs.shape == (8, 6) and len(distinct_solutions(qs, atol=1e-6)) == 8
        for q in qs:  # checked with Pinocchio's forward kinematics, not the DH product the solver uses
            np.testing.assert_allclose(direct_kinematics(puma, q), T, atol=1e-10)
        assert np.min(np.linalg.norm(np.angle(np.exp(1j * (qs - q_true))), axis=1)) < 1e-8


def test_bad_motor_model_is_named():
    with pytest.raises(ValueError, match="motors"):
        robot_from_dh([DHLink(a=1.0, motor_inertia=0.1)], motors="gears")
