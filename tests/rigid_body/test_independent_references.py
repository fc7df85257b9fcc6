"""Library functions against references computed another way (finite differences, closed forms,
another algorithm): the checks a self-consistent bug would pass otherwise."""

import control
import numpy as np
import pinocchio as pin
import pytest

from controllers.independent_joint import acceleration_filter
from planners.inverse_kinematics import TwoStageCLIK
from planners.timing import trapezoidal_law
from rigid_body.camera import PinholeCamera, project, project_from_robot
from rigid_body.dynamics import gravity_torques, inertia_matrix
from rigid_body.kinematics import geometric_jacobian
from rigid_body.robots import load
from rigid_body.rotations import quaternion_rate, rotation_to_quaternion

RNG = np.random.default_rng(2024)


def _random_rotation(rng):
    axis = rng.normal(size=3)
    return pin.exp3(rng.uniform(-np.pi, np.pi) * axis / np.linalg.norm(axis))


@pytest.mark.parametrize("seed", range(5))
def test_quaternion_rate_is_the_derivative_of_the_quaternion(seed):
    """Q̇ (3.94)–(3.95) against central differences of Q(t) along R(t) = exp(S(ω) t) R0 (ω in the base frame)."""
    rng = np.random.default_rng(seed)
    R0, w, h = _random_rotation(rng), rng.normal(size=3), 1e-6
    Q0 = rotation_to_quaternion(R0)

    def Q(t):
        q = rotation_to_quaternion(pin.exp3(w * t) @ R0)
        return q if q @ Q0 > 0 else -q          # the same sign as Q0 (continuity)

    fd = (Q(h) - Q(-h)) / (2 * h)
    assert np.allclose(quaternion_rate(Q0, w), fd, atol=1e-8)


def test_camera_image_axes_follow_the_camera_frame():
    """X_I grows with x_c and Y_I with y_c (no mirrored axis); the optical axis images at (X0, Y0)."""
    cam = PinholeCamera(600.0, 800.0, 320.0, 240.0)
    centre = project(cam, [0.0, 0.0, 2.0])
    right, down = project(cam, [0.1, 0.0, 2.0]), project(cam, [0.0, 0.1, 2.0])
    assert (centre.X_I, centre.Y_I) == (320.0, 240.0)
    assert right.X_I == pytest.approx(320.0 + 600.0 * 0.05) and right.Y_I == pytest.approx(240.0)
    assert down.Y_I == pytest.approx(240.0 + 800.0 * 0.05) and down.X_I == pytest.approx(320.0)


def test_project_from_robot_uses_the_end_effector_pose():
    """SCARA at q = (0, 0, d3, 0): T_c^b = [I, (a1 + a2, 0, d3)] (S2.3, a1 = a2 = 0.5, z down); a point
    below the camera images through that pose."""
    scara = load("scara")
    cam = PinholeCamera(500.0, 500.0, 250.0, 250.0)
    p_b = np.array([1.1, -0.05, 0.9])
    proj = project_from_robot(cam, scara, np.array([0.0, 0.0, 0.1, 0.0]), p_b)
    p_c = p_b - np.array([1.0, 0.0, 0.1])
    assert np.allclose(proj.p_c, p_c, atol=1e-12)
    assert proj.X_I == pytest.approx(250 + 500 * p_c[0] / p_c[2]) and proj.Y_I == pytest.approx(250 + 500 * p_c[1] / p_c[2])


def test_acceleration_filter_reconstructs_a_ramp_with_the_right_gain():
    """Velocity ramp ω(t) = t (unit acceleration): Â(t) = 1 − e^{−k_f t}; and Â/Ω = k_f jω/(jω + k_f)."""
    k_f = 40.0
    F = acceleration_filter(k_f)
    t = np.linspace(0, 0.5, 501)
    a_hat = control.forced_response(F, t, t).outputs
    assert np.allclose(a_hat, 1 - np.exp(-k_f * t), atol=1e-6)
    w = np.array([1.0, 40.0, 1000.0])
    assert np.allclose(F(1j * w), k_f * 1j * w / (1j * w + k_f), rtol=1e-12)


def test_trapezoid_position_during_the_motion():
    """q(t) of (4.8) in the three phases: ½ q̈_c t², then q̇_c-linear, then symmetric."""
    q_i, q_f, t_f, qd_c = 0.2, 1.4, 2.0, 0.9
    law = trapezoidal_law([q_i], [q_f], t_f, [qd_c])
    t_c = (q_i - q_f + qd_c * t_f) / qd_c
    qdd_c = qd_c / t_c
    for t in (0.3 * t_c, t_c, 0.5 * t_f, t_f - 0.5 * t_c):
        if t <= t_c:
            expected = q_i + 0.5 * qdd_c * t**2
        elif t <= t_f - t_c:
            expected = q_i + qdd_c * t_c * (t - t_c / 2)
        else:
            expected = q_f - 0.5 * qdd_c * (t_f - t) ** 2
        assert float(np.ravel(law(t)[0])[0]) == pytest.approx(expected, abs=1e-12)
    assert float(np.ravel(law(0.5 * t_c)[1])[0]) == pytest.approx(qdd_c * 0.5 * t_c, abs=1e-12)
    assert float(np.ravel(law(0.5 * t_f)[1])[0]) == pytest.approx(qd_c, abs=1e-12)


def test_two_stage_clik_reproduces_the_reference_twist_on_the_path():
    """With zero error the two-stage law must return q̇ with J q̇ = [ṗ_d; ω_d]: a dropped feedforward
    (ω_d × R_d o_W, or ω_d in stage 2) breaks this at once."""
    robot = load("anthropomorphic_wrist")
    rng = np.random.default_rng(7)
    for _ in range(5):
        q = rng.uniform(-1.0, 1.0, robot.nq)
        pin.framesForwardKinematics(robot.model, robot.data, q)
        T = robot.data.oMf[robot.ee_frame].homogeneous.copy()
        v_d = rng.normal(size=6)
        clik = TwoStageCLIK(robot, lambda t: (T, v_d), "frame_4", 3, 500.0, 500.0)
        qd = clik(0.0, q)
        assert np.allclose(geometric_jacobian(robot, q) @ qd, v_d, atol=1e-9)


def _link_com_poses(robot, q):
    """World position of every link's centre of mass and the rotation of its joint frame (plain FK)."""
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q)
    return [(data.oMi[i].act(model.inertias[i].lever).copy(), data.oMi[i].rotation.copy())
            for i in range(1, model.njoints)]


def test_ur5_dynamics_against_the_kinetic_and_potential_energy():
    """B(q) = ∂²T/∂q̇² and g(q) = ∂U/∂q from finite differences of the link COM poses (no CRBA, no RNEA)."""
    robot = load("ur5")
    model = robot.model
    g0 = model.gravity.linear.copy()
    h = 1e-6
    q = np.random.default_rng(5).uniform(-np.pi, np.pi, robot.nq)

    def kinetic(qd):
        plus, minus = _link_com_poses(robot, q + h * qd), _link_com_poses(robot, q - h * qd)
        T = 0.0
        for i, ((p1, R1), (p0, R0)) in enumerate(zip(plus, minus), start=1):
            v = (p1 - p0) / (2 * h)
            w = pin.log3(R1 @ R0.T) / (2 * h)
            R = 0.5 * (R1 + R0)
            inertia = model.inertias[i]
            T += 0.5 * inertia.mass * v @ v + 0.5 * w @ (R @ inertia.inertia @ R.T) @ w
        return T

    n = robot.nv
    E = np.eye(n)
    B = np.array([[kinetic(E[i] + E[j]) - kinetic(E[i]) - kinetic(E[j]) for j in range(n)] for i in range(n)])
    B = 0.5 * (B + B.T)
    assert np.allclose(inertia_matrix(robot, q), B, atol=1e-5 * np.abs(B).max())

    def potential(x):
        return -sum(model.inertias[i].mass * g0 @ p for i, (p, _) in enumerate(_link_com_poses(robot, x), start=1))

    g = np.array([(potential(q + h * E[k]) - potential(q - h * E[k])) / (2 * h) for k in range(n)])
    assert np.allclose(gravity_torques(robot, q), g, atol=1e-5 * np.abs(g).max())
