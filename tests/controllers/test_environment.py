"""Environments (wrench from the end-effector motion) and the arm in contact with them."""

import numpy as np
import pinocchio as pin
import pytest

from tests import two_link_closed_form as arm2
from controllers.environment import CompliantPlane, SurfaceWithHole
from controllers.plants import ArmInContact
from controllers.simulation import LoggedController, simulate
from rigid_body.kinematics import inverse_kinematics_planar_3r
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


def test_wrench_at_on_plain_arrays_is_the_wrench_of_the_pose(rng):
    """The hot-loop entry wrench_at(p_e, v_e) gives what wrench(T_e, v_e) gives for any pose with that
    origin; without contact it is the shared read-only NO_CONTACT."""
    from controllers.environment import NO_CONTACT, SteppedPlane

    plane = SteppedPlane([0.6, 0.0, 0.4], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 0.1, 0.01, 2e4, 200.0, friction=0.3,
                         slip_velocity=0.01)
    for _ in range(20):
        p = np.array([0.6, 0.0, 0.4]) + rng.uniform(-0.02, 0.02, 3) + [0.0, rng.uniform(0.0, 0.2), 0.0]
        v = rng.standard_normal(6) * 0.05
        T = pin.SE3(pin.SE3.Random().rotation, p)
        np.testing.assert_array_equal(plane.wrench_at(p, v), plane.wrench(T, v))
        np.testing.assert_array_equal(plane.wrench(T.homogeneous, v), plane.wrench(T, v))
        # independent reference: the spring–damper along n and Coulomb friction written out here
        d = p[0] - 0.6 - (0.01 if p[1] > 0.1 else 0.0)                  # penetration beyond x = 0.6 m
        N = 2e4 * d - 200.0 * (-v[0])
        expected = np.zeros(6)
        if d > 0 and N > 0:
            vt = np.array([0.0, v[1], v[2]])
            expected[:3] = [N, 0.0, 0.0] + 0.3 * N * np.tanh(np.linalg.norm(vt) / 0.01) * vt / np.linalg.norm(vt)
        np.testing.assert_allclose(plane.wrench_at(p, v), expected, rtol=1e-12, atol=1e-9)
    away = plane.wrench_at(np.array([0.5, 0.0, 0.4]), np.zeros(6))
    assert away is NO_CONTACT and not away.flags.writeable


def test_surface_with_hole_damping_only_pushes():
    """The damped reaction k·δ − c·v along each face's normal, hand-computed; pulling is clipped to none."""
    from controllers.environment import NO_CONTACT

    env = SurfaceWithHole(x_hole=0.0, clearance=0.01, depth=0.05, stiffness=1e4, damping=50.0)
    top = env.wrench_at(np.array([0.1, -0.001, 0.0]), np.array([0.0, -0.1, 0, 0, 0, 0]))   # moving in at 0.1 m/s
    np.testing.assert_allclose(top, [0, -(10.0 + 5.0), 0, 0, 0, 0], atol=1e-12)
    wall = env.wrench_at(np.array([-0.012, -0.02, 0.0]), np.array([-0.2, 0, 0, 0, 0, 0]))  # into the left wall
    np.testing.assert_allclose(wall, [-(20.0 + 10.0), 0, 0, 0, 0, 0], atol=1e-12)
    assert env.wrench_at(np.array([0.1, -0.001, 0.0]), np.array([0, 0.3, 0, 0, 0, 0])) is NO_CONTACT  # leaving fast
    assert env.wrench_at(np.array([0.012, -0.02, 0.0]), np.array([-0.5, 0, 0, 0, 0, 0])) is NO_CONTACT
    assert env.wrench_at(np.array([0.0, 0.01, 0.0]), np.zeros(6)) is NO_CONTACT                  # above
    np.testing.assert_allclose(env.force(np.array([0.1, -0.001]), np.array([0.0, -0.1])), [0, 15.0])


def test_arm_in_contact_acceleration_matches_equation_7_42_and_its_measurement_memo():
    """q̈ of the hot path against B⁻¹(u − Jᵀh_e − C q̇ − g) assembled from CRBA/RNEA/the frame Jacobian,
    also right after a measurement at another state (the kept wrench must not leak)."""
    robot = load("planar_3r")
    env = SurfaceWithHole(x_hole=0.6, clearance=0.004, depth=0.05)
    plant = ArmInContact(robot, env)
    model, data, fid = robot.model, robot.model.createData(), robot.frame(None)

    def reference(q, qd, u):
        J = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)
        p = pin.updateFramePlacement(model, data, fid).translation
        h = env.wrench(pin.SE3(np.eye(3), p), J @ qd)
        B = pin.crba(model, data, q)
        return np.linalg.solve(B, u - J.T @ h - pin.rnea(model, data, q, qd, np.zeros(3)))

    rng = np.random.default_rng(3)
    pushed = []
    for tip in ([0.55, -0.002], [0.55, 0.05], [0.606, -0.02]):   # on the top face, free, against the hole wall
        q = inverse_kinematics_planar_3r(np.array([*tip, -np.pi / 2]))[0]
        qd, u = rng.normal(size=3), rng.normal(size=3)
        qd[:] = np.linalg.solve(pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)[[0, 1, 5]],
                                [0.0, -0.05, 0.0])                 # the tip moving down at 5 cm/s
        x = np.concatenate([q, qd])
        plant.measure(0.5, x + 0.1)                               # a measurement at another state, same t
        expect = reference(q, qd, u)
        np.testing.assert_allclose(plant.acceleration(0.5, q, qd, u), expect, rtol=1e-9, atol=1e-9)
        pushed.append(np.any(plant.measure(0.5, x).wrench))       # now the kept wrench is this state's
        np.testing.assert_allclose(plant.acceleration(0.5, q, qd, u), expect, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(plant.derivative(0.5, x, u)[3:], expect, rtol=1e-9, atol=1e-9)
    assert pushed == [True, False, True]
