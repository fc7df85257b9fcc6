"""Joint friction τ_f = F_v q̇ + F_s sgn(q̇) (7.42): closed forms, the smooth limit, the Toolbox's motor-side
convention, and the two homes of the data (DH table fields, URDF <dynamics>) ending in ``robot.friction``."""

import numpy as np
import pytest

from rigid_body.dh import DHLink, joint_friction_from_motor, urdf_from_dh
from rigid_body.dynamics import friction_torques, inverse_dynamics
from rigid_body.robots import JointFriction, robot_from_dh, robot_from_urdf_string

LINKS = [DHLink(a=0.5, mass=1.0, viscous_friction=0.2, coulomb_friction=1.5),
         DHLink(a=0.4, mass=1.0, viscous_friction=0.1, coulomb_friction=(0.8, 1.2))]


def test_sign_magnitude_and_direction_dependence():
    robot = robot_from_dh(LINKS)
    for qd in ([2.0, 3.0], [-2.0, -3.0], [0.5, -0.25]):
        qd = np.array(qd)
        expected = [0.2 * qd[0] + 1.5 * np.sign(qd[0]), 0.1 * qd[1] + (0.8 if qd[1] > 0 else -1.2)]
        np.testing.assert_allclose(friction_torques(robot, qd), expected, rtol=1e-15)
    np.testing.assert_array_equal(friction_torques(robot, [0.0, 0.0]), [0.0, 0.0])  # at rest: no Coulomb term
    # friction opposes motion: it dissipates power
    assert friction_torques(robot, [0.3, -0.7]) @ [0.3, -0.7] > 0


def test_smooth_option_tends_to_the_sign():
    robot = robot_from_dh(LINKS)
    qd = np.array([0.05, -0.05])
    exact = friction_torques(robot, qd)
    for eps in (1e-2, 1e-3, 1e-4):
        smooth = friction_torques(robot, qd, smoothing=eps)
        # |tanh(x) − sgn(x)| = 1 − tanh|x| ≤ 2 e^{−2|x|}
        bound = 2 * np.exp(-2 * 0.05 / eps) * np.array([1.5, 1.2])
        assert np.all(np.abs(smooth - exact) <= bound + 1e-15)
    np.testing.assert_allclose(friction_torques(robot, [1e-9, -1e-9], smoothing=1e-3),
                               [0.2e-9 + 1.5e-6, -0.1e-9 - 1.2e-6], rtol=1e-6)  # linear through 0: tanh(x) ≈ x


def test_motor_side_friction_reflects_like_the_toolbox():
    """Robotics Toolbox ``DHLink(B=3, G=2, Tc=[2, −1]).friction(qd)`` = −|G|(B|G| q̇ + Tc) = −[16, 28, 40, 52]
    for q̇ = [1, 2, 3, 4] (its test suite): τ_f here is minus the Toolbox's value."""
    link = DHLink(**joint_friction_from_motor(2.0, viscous=3.0, coulomb=(2.0, -1.0)))
    robot = robot_from_dh([link] * 4)
    np.testing.assert_allclose(friction_torques(robot, [1.0, 2.0, 3.0, 4.0]), [16, 28, 40, 52], rtol=1e-15)
    np.testing.assert_allclose(friction_torques(robot, -np.ones(4)), -(12 + 2) * np.ones(4), rtol=1e-15)


def test_urdf_dynamics_tag_is_read_into_robot_friction():
    """URDF ``<dynamics damping friction>`` → Pinocchio's model.damping/friction → robot.friction."""
    xml = urdf_from_dh([DHLink(a=1.0, mass=1.0, viscous_friction=0.4, coulomb_friction=2.0)])
    assert 'damping="0.4"' in xml and 'friction="2.0"' in xml
    robot = robot_from_urdf_string(xml)
    np.testing.assert_array_equal(robot.model.damping, [0.4])
    np.testing.assert_allclose(friction_torques(robot, [-1.0]), [-2.4])
    # a DH table without friction writes no <dynamics>: the book's URDF files are unchanged
    assert "dynamics" not in urdf_from_dh([DHLink(a=1.0, mass=1.0)])


def test_inverse_dynamics_stays_rigid_body_and_friction_argument_overrides():
    robot = robot_from_dh(LINKS)
    frictionless = robot_from_dh([DHLink(a=0.5, mass=1.0), DHLink(a=0.4, mass=1.0)])
    q, qd, qdd = [0.3, -0.2], [1.0, -2.0], [0.5, 0.1]
    np.testing.assert_allclose(inverse_dynamics(robot, q, qd, qdd), inverse_dynamics(frictionless, q, qd, qdd))
    other = JointFriction(np.zeros(2), np.array([1.0, 0.0]), np.array([0.0, 3.0]))
    np.testing.assert_allclose(friction_torques(robot, qd, friction=other), [1.0, -3.0])


def test_bad_friction_input_is_named():
    with pytest.raises(ValueError, match="friction"):
        DHLink(a=1.0, coulomb_friction=-1.0)
    with pytest.raises(ValueError, match="friction"):
        DHLink(a=1.0, coulomb_friction=(1.0, 2.0, 3.0))
    robot = robot_from_dh(LINKS)
    with pytest.raises(ValueError, match="qd"):
        friction_torques(robot, [1.0])
    with pytest.raises(ValueError, match="smoothing"):
        friction_torques(robot, [1.0, 1.0], smoothing=-1.0)
