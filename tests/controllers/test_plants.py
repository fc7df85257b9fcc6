"""Plants of controllers/plants.py: manifold states (nq ≠ nv) against closed forms, measurements, named states."""

import numpy as np
import pinocchio as pin
import pytest

from controllers.plants import ArmMeasurement, ArmPlant, JointDrivePlant, JointIntegrator
from controllers.independent_joint import JointDrive
from controllers.simulation import simulate
from rigid_body.robots import Robot

M, L, G = 2.0, 0.7, 9.81


def _pendulum(joint: pin.JointModel, gravity: bool = True) -> Robot:
    """A point mass M at distance L from a z axis, in the x–y plane, gravity along −y."""
    model = pin.Model()
    jid = model.addJoint(0, joint, pin.SE3.Identity(), "pivot")
    model.appendBodyToJoint(jid, pin.Inertia(M, np.array([L, 0.0, 0.0]), np.zeros((3, 3))), pin.SE3.Identity())
    fid = model.addFrame(pin.Frame("ee", jid, 0, pin.SE3(np.eye(3), np.array([L, 0.0, 0.0])), pin.FrameType.OP_FRAME))
    model.gravity = pin.Motion(np.array([0.0, -G, 0.0] if gravity else [0.0, 0.0, 0.0]), np.zeros(3))
    return Robot(name="pendulum", model=model, data=model.createData(), ee_frame=fid)


def test_continuous_joint_pendulum_conserves_energy_and_stays_on_the_circle():
    """A continuous joint (q = [cos θ, sin θ], nq = 2, nv = 1): E = ½ M L² θ̇² + M g L sin θ is constant,
    and θ(t) is the same as with a revolute joint (nq = nv = 1)."""
    plant = ArmPlant(_pendulum(pin.JointModelRUBZ()))
    assert (plant.state_size, plant.tangent_size) == (3, 2)
    x0 = plant.initial_state([1.0, 0.0], [0.5])                         # horizontal, θ̇ = 0.5 rad/s
    res = simulate(plant, lambda t, m: np.zeros(1), (0.0, 3.0), x0, h=1e-3, Ts=1e-2)
    c, s, w = res.q[:, 0], res.q[:, 1], res.qd[:, 0]
    np.testing.assert_allclose(c**2 + s**2, 1.0, atol=1e-12)            # pin.integrate keeps q on the circle
    theta = np.unwrap(np.arctan2(s, c))
    energy = 0.5 * M * L**2 * w**2 + M * G * L * np.sin(theta)
    assert np.ptp(energy) < 1e-8 * abs(energy[0] - M * G * L)
    assert np.ptp(theta) > 1.0                                         # it really swings
    revolute = ArmPlant(_pendulum(pin.JointModelRZ()))
    ref = simulate(revolute, lambda t, m: np.zeros(1), (0.0, 3.0), revolute.initial_state([0.0], [0.5]),
                   h=1e-3, Ts=1e-2)
    np.testing.assert_allclose(theta, ref.q[:, 0], atol=1e-9)


def test_free_flyer_spinning_about_a_principal_axis_follows_the_closed_form():
    """Zero gravity, no torque: the body spins at ω about its principal axis z and its centre moves at
    constant world velocity v: p(t) = v t, R(t) = exp(ω t ẑ) (nq = 7, nv = 6). With the stage corrections
    (dexp_inverse) RK4 stays fourth order on SE(3): the position error drops 16-fold when h halves."""
    model = pin.Model()
    jid = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base")
    model.appendBodyToJoint(jid, pin.Inertia(3.0, np.zeros(3), np.diag([0.1, 0.2, 0.3])), pin.SE3.Identity())
    model.gravity = pin.Motion.Zero()
    fid = model.addFrame(pin.Frame("ee", jid, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME))
    plant = ArmPlant(Robot(name="body", model=model, data=model.createData(), ee_frame=fid))
    assert (plant.state_size, plant.tangent_size) == (13, 12)
    omega, v, T = 2.0, np.array([0.3, -0.1, 0.2]), 1.5
    x0 = plant.initial_state([0, 0, 0, 0, 0, 0, 1], np.r_[v, 0.0, 0.0, omega])  # body-frame twist at t = 0
    Rz = np.array([[np.cos(omega * T), -np.sin(omega * T), 0], [np.sin(omega * T), np.cos(omega * T), 0], [0, 0, 1]])
    errors = []
    for h in (4e-3, 2e-3):
        res = simulate(plant, lambda t, m: np.zeros(6), (0.0, T), x0, h=h, Ts=0.1)
        R_end = pin.Quaternion(res.q[-1, 6], *res.q[-1, 3:6]).toRotationMatrix()
        np.testing.assert_allclose(R_end, Rz, atol=1e-9)
        np.testing.assert_allclose(np.linalg.norm(res.q[:, 3:], axis=1), 1.0, atol=1e-12)
        np.testing.assert_allclose(res.qd[-1], [*(Rz.T @ v), 0.0, 0.0, omega], atol=1e-6)
        errors.append(np.max(np.abs(res.q[:, :3] - np.outer(res.t, v))))
    assert errors[1] < 1e-11 and 12.0 < errors[0] / errors[1] < 20.0


def test_arm_measurement_and_drive_plant_named_states():
    plant = ArmPlant(_pendulum(pin.JointModelRZ()))
    m = plant.measure(0.0, np.array([0.2, -0.3]))
    assert isinstance(m, ArmMeasurement) and m.wrench is None
    np.testing.assert_array_equal(m.q, [0.2])
    np.testing.assert_array_equal(m.qd, [-0.3])
    with pytest.raises(AttributeError):
        m.q = np.zeros(1)                                               # frozen
    with pytest.raises(ValueError, match="`q0`"):
        plant.initial_state([0.1, 0.2])
    drive = JointDrive(I=0.01, Ra=1.0, kt=0.5, kv=0.5)
    res = simulate(JointDrivePlant(drive), lambda t, m: np.array([1.0]), (0.0, 1.0), [0.0, 0.0], h=1e-3)
    T_m, k_m = drive.T_m, drive.k_m                                     # step response of k_m/(s(1 + s T_m))
    np.testing.assert_allclose(res.qd[:, 0], k_m * (1 - np.exp(-res.t / T_m)), atol=1e-9)
    np.testing.assert_allclose(res.q[:, 0], k_m * (res.t - T_m * (1 - np.exp(-res.t / T_m))), atol=1e-9)
    res = simulate(JointIntegrator(), lambda t, q: np.array([1.0, -2.0]), (0.0, 1.0), [0.0, 0.0], h=0.1)
    np.testing.assert_allclose(res.q[-1], [1.0, -2.0], atol=1e-12)
