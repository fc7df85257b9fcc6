"""Environments (wrench from the end-effector motion) and the arm in contact with them."""

import numpy as np
import pinocchio as pin
import pytest

from tests import two_link_closed_form as arm2
from controllers.environment import CompliantPlane, SurfaceWithHole
from controllers.plants import ArmInContact
from controllers.simulation import LoggedController, simulate
from rigid_body.robots import load


def _pose(p):
    return pin.SE3(np.eye(3), np.asarray(p, dtype=float))


def test_surface_with_hole_forces():
    env = SurfaceWithHole(x_hole=0.0, clearance=0.01, depth=0.05, stiffness=1e4, damping=0.0)
    assert np.allclose(env.force(np.array([0.1, 0.01]), np.zeros(2)), 0)             # above: free
    assert np.allclose(env.force(np.array([0.1, -0.001]), np.zeros(2)), [0, 10.0])    # top face pushes up
    assert np.allclose(env.force(np.array([0.005, -0.02]), np.zeros(2)), 0)           # inside the hole
    assert np.allclose(env.force(np.array([0.012, -0.02]), np.zeros(2)), [-20.0, 0])  # right wall pushes left
    assert np.allclose(env.force(np.array([-0.012, -0.02]), np.zeros(2)), [20.0, 0])
    assert np.allclose(env.force(np.array([0.0, -0.051]), np.zeros(2)), [0, 10.0])    # bottom


    h = env.wrench(_pose([0.012, -0.02, 0.3]), np.zeros(6))                         # h_e = − reaction
    np.testing.assert_allclose(h, [20.0, 0, 0, 0, 0, 0], atol=1e-12)


def test_compliant_plane_wrench():
    plane = CompliantPlane(point=[0, 0, 0.5], normal=[0, 0, 2.0], stiffness=1e4, damping=100.0)
    np.testing.assert_allclose(plane.wrench(_pose([1.0, 2.0, 0.6]), np.zeros(6)), 0.0)       # above: free
    h = plane.wrench(_pose([0.3, 0.0, 0.49]), np.array([0, 0, -0.2, 0, 0, 0]))  # 1 cm in, moving in at 0.2 m/s
    np.testing.assert_allclose(h, [0, 0, -(1e4 * 0.01 + 100.0 * 0.2), 0, 0, 0], atol=1e-9)
    T = np.eye(4)
    T[:3, 3] = [0.3, 0.0, 0.49]                                                  # a (4, 4) pose works too
    np.testing.assert_allclose(plane.wrench(T, np.array([0, 0, -0.2, 0, 0, 0])), h, atol=1e-12)
    assert plane.wrench(_pose([0, 0, 0.499]), np.array([0, 0, 1.0, 0, 0, 0]))[2] == 0.0   # leaving fast: no pull
    with pytest.raises(ValueError, match="`normal`"):
        CompliantPlane([0, 0, 0], [0, 0, 0], 1e4)
    with pytest.raises(ValueError, match="`stiffness`"):
        CompliantPlane([0, 0, 0], [0, 0, 1], -1.0)


class _PushDown(LoggedController):
    """τ = g(q) + Jᵀ (f_d + k_F (f_d − h_e)) − K_D q̇: the arm exerts f_d on the environment (closed-form
    g, J of the two-link arm; the sensed wrench is read from the measurement)."""

    def __init__(self, f_d, k_F=0.5, K_D=1500.0):
        self.f_d, self.k_F, self.K_D = np.asarray(f_d, dtype=float), k_F, K_D

    def __call__(self, t, meas):
        f = meas.wrench[:2]
        self.record(f=f)
        J = arm2.jacobian(meas.q)
        return arm2.gravity(meas.q) + J.T @ (self.f_d + self.k_F * (self.f_d - f)) - self.K_D * meas.qd


def test_arm_pressing_on_a_spring_plane_settles_at_stiffness_times_penetration():
    """The planar two-link arm pushes down with 50 N on a plane y = y_0 of stiffness 10⁴ N/m: at rest the
    sensed force is the commanded one and equals K × the penetration of the closed-form tip."""
    robot = load("planar_2r")
    q0 = np.array([0.2, 1.2])
    y0 = arm2.tip(q0)[1] - 0.01                         # the tip starts 1 cm above the plane
    K, F = 1e4, 50.0
    plant = ArmInContact(robot, CompliantPlane([0, y0, 0], [0, 1, 0], stiffness=K, damping=200.0),
                         viscous_friction=100.0)
    res = simulate(plant, _PushDown([0.0, -F]), (0.0, 4.0), plant.initial_state(q0), h=1e-3, Ts=1e-3)
    penetration = y0 - arm2.tip(res.q[-1])[1]
    assert penetration == pytest.approx(F / K, rel=1e-3)
    np.testing.assert_allclose(res["f"][-1], [0.0, -K * penetration], atol=1e-3 * F)
    assert np.all(res["f"][:50, 1] == 0.0) and np.min(res["f"][:, 1]) < -0.5 * F   # free, then in contact
    with pytest.raises(ValueError, match="`environment`"):
        ArmInContact(robot, object())


def test_compliant_plane_bilateral_friction_and_contact_flag():
    plane = CompliantPlane([0, 0, 0], [0, 0, 1], 1e4, bilateral=True)
    np.testing.assert_allclose(plane.wrench(_pose([0, 0, 0.01]), np.zeros(6))[:3], [0, 0, 100.0])  # it pulls too
    assert plane.in_contact(_pose([0, 0, 1.0]))
    rough = CompliantPlane([0, 0, 0], [0, 0, 1], 1e4, friction=0.5, slip_velocity=1e-3)
    assert not rough.in_contact(_pose([0, 0, 1e-6])) and rough.in_contact(_pose([0, 0, -1e-6]))
    # 1 cm in, sliding along x at 0.1 m/s ≫ v_s: the tool drags the surface with μ N along its motion
    h = rough.wrench(_pose([0, 0, -0.01]), np.array([0.1, 0, 0, 0, 0, 0]))
    np.testing.assert_allclose(h[:3], [0.5 * 100.0 * np.tanh(100.0), 0, -100.0], atol=1e-9)
    # slow sliding: the regularised law is viscous, μ N v / v_s
    h = rough.wrench(_pose([0, 0, -0.01]), np.array([0, 1e-6, 0, 0, 0, 0]))
    assert h[1] == pytest.approx(0.5 * 100.0 * 1e-6 / 1e-3, rel=1e-6)
    with pytest.raises(ValueError, match="`friction`"):
        CompliantPlane([0, 0, 0], [0, 0, 1], 1e4, friction=-0.1)


def test_stepped_plane_recedes_beyond_the_edge():
    from controllers.environment import SteppedPlane

    wall = SteppedPlane([0.6, 0, 0], [-1, 0, 0], [0, 1, 0], step_at=0.1, depth=0.01, stiffness=1e4)
    assert wall.wrench(_pose([0.601, 0.05, 0]), np.zeros(6))[0] == pytest.approx(10.0)   # before the edge
    assert not wall.in_contact(_pose([0.601, 0.15, 0]))                                   # beyond: free
    assert wall.wrench(_pose([0.612, 0.15, 0]), np.zeros(6))[0] == pytest.approx(20.0)
    with pytest.raises(ValueError, match="`direction`"):
        SteppedPlane([0, 0, 0], [1, 0, 0], [2, 0, 0], 0.1, 0.01, 1e4)
