"""A contact too stiff for the integration step is refused before the first step (issue 26, item 1), and the
environments check what they are given (items 4 and 7)."""

import math

import numpy as np
import pinocchio as pin
import pytest

from controllers.environment import CompliantPlane, SteppedPlane, SurfaceWithHole
from controllers.joint_space import PDGravityCompensation
from controllers.plants import ArmInContact
from controllers.simulation import rk4_stable, rk4_step_bound, rk4_stiffness_bound, simulate
from rigid_body.robots import load


# --------------------------------------------------------------------------------------------
# RK4's stability on a spring-mass-damper mode, against the closed form and against RK4 itself
# --------------------------------------------------------------------------------------------

def test_undamped_bound_is_the_closed_form():
    # |R(iy)|² = 1 − y⁶/72 + y⁸/576 ≤ 1 ⇔ y² ≤ 8: h √(k/m) ≤ 2√2
    for m, h in ((1.0, 1e-3), (3.7, 2e-4), (0.01, 1e-2)):
        assert rk4_stiffness_bound(m, 0.0, h) == pytest.approx(8.0 * m / h**2, rel=1e-9)
        assert rk4_step_bound(m, 0.0, 1e6) == pytest.approx(2 * math.sqrt(2) * math.sqrt(m / 1e6), rel=1e-9)


def test_damping_alone_is_bounded_by_the_real_axis_limit():
    # on the real axis RK4 is stable for −2.7853 ≤ hλ ≤ 0 (R(z) = 1: the real root of z³ + 4z² + 12z + 24)
    z = np.roots([1, 4, 12, 24])
    limit = -min(r.real for r in z if abs(r.imag) < 1e-9)
    assert limit == pytest.approx(2.7853, abs=1e-4)
    assert rk4_stable(1.0, 0.99 * limit / 1e-3, 0.0, 1e-3)
    assert not rk4_stable(1.0, 1.01 * limit / 1e-3, 0.0, 1e-3)
    assert rk4_stiffness_bound(1.0, 1.01 * limit / 1e-3, 1e-3) == 0.0


@pytest.mark.parametrize("damping", [0.0, 30.0, 1500.0])
def test_bound_separates_bounded_and_growing_rk4_runs(damping):
    """The bound found by rk4_stiffness_bound against RK4 itself (the loop's own stepper) on m ẍ + c ẋ + k x = 0."""
    m, h = 2.0, 1e-3
    k_max = rk4_stiffness_bound(m, damping, h)

    def peak(k):
        res = simulate(lambda t, x, u: np.array([x[1], -(k * x[0] + damping * x[1]) / m]),
                       lambda t, x: np.zeros(1), (0.0, 2.0), [1e-3, 0.0], h=h, bound=1e300)
        return np.abs(res.x[:, 0]).max()

    assert peak(0.98 * k_max) <= 1e-3 * (1 + 1e-9)
    assert peak(1.02 * k_max) > 1e-2


# --------------------------------------------------------------------------------------------
# Both backends refuse the step before the first one
# --------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def panda_at_wall():
    panda = load("panda")
    q0 = panda.configurations["ready"]
    pin.framesForwardKinematics(panda.model, panda.data, q0)
    p = panda.data.oMf[panda.ee_frame].translation.copy()
    ctrl = PDGravityCompensation(panda, [600, 600, 600, 600, 250, 150, 50], [50, 50, 50, 50, 10, 10, 3], q0)
    return panda, q0, p, ctrl


@pytest.mark.parametrize("backend", ["python", "casadi"])
def test_stiff_wall_is_refused_on_both_backends(panda_at_wall, backend):
    """The issue's case: the Panda against a plane of 1e12 N/m at h = 1 ms used to end 0 N away from the wall."""
    panda, q0, p, ctrl = panda_at_wall
    plant = ArmInContact(panda, CompliantPlane(p, [0, 0, 1], 1e12))
    with pytest.raises(ValueError, match=r"`stiffness` k = 1e\+12 N/m.*h = 0\.001 s.*k ≤ 3\.1\d*e\+07 N/m.*h ≤ 5\.6\d*e-06 s"):
        simulate(plant, ctrl, (0.0, 0.01), plant.initial_state(q0), h=1e-3, Ts=1e-3, backend=backend)


def test_effective_mass_is_the_inverse_mobility(panda_at_wall):
    """m = 1/(nᵀ J_P B⁻¹ J_Pᵀ n): against the operational-space inertia Λ = (J_P B⁻¹ J_Pᵀ)⁻¹ (its n-n
    reciprocal) from a finite-difference Jacobian."""
    panda, q0, p, _ = panda_at_wall
    n = np.array([0.0, 0.6, 0.8])
    plant = ArmInContact(panda, CompliantPlane(p, n, 1e5))
    (d, k, c, m), = plant.contact_masses(q0)
    eps = 1e-7
    J = np.zeros((3, panda.nv))
    for i in range(panda.nv):
        dq = np.zeros(panda.nv)
        dq[i] = eps
        pin.framesForwardKinematics(panda.model, panda.data, q0 + dq)
        plus = panda.data.oMf[panda.ee_frame].translation.copy()
        pin.framesForwardKinematics(panda.model, panda.data, q0 - dq)
        J[:, i] = (plus - panda.data.oMf[panda.ee_frame].translation) / (2 * eps)
    B = pin.crba(panda.model, panda.data, q0)
    Lambda_inv = J @ np.linalg.inv(B) @ J.T
    assert m == pytest.approx(1.0 / (n @ Lambda_inv @ n), rel=1e-6)
    assert (k, c) == (1e5, 0.0)


@pytest.mark.parametrize("make", [
    lambda p: CompliantPlane(p, [0, 0, 1], 1e9, damping=10.0),
    lambda p: CompliantPlane(p, [0, 0, 1], 1e9, bilateral=True),
    lambda p: CompliantPlane(p, [0, 0, 1], 1e3, damping=1e5),                 # the damping alone is too much
    lambda p: CompliantPlane(p, [1, 0, 0], 1e9, friction=0.3),
    lambda p: SteppedPlane(p, [0, 0, 1], [1, 0, 0], 0.1, 0.01, 1e9),
])
def test_neighbouring_stiff_environments_are_refused(panda_at_wall, make):
    panda, q0, p, ctrl = panda_at_wall
    plant = ArmInContact(panda, make(p))
    with pytest.raises(ValueError, match="too stiff for the step h"):
        simulate(plant, ctrl, (0.0, 0.01), plant.initial_state(q0), h=1e-3, Ts=1e-3)


def test_stiff_hole_is_refused_for_the_peg():
    arm = load("planar_3r")
    env = SurfaceWithHole(x_hole=0.5, clearance=0.004, depth=0.05, stiffness=1e10)
    plant = ArmInContact(arm, env)
    with pytest.raises(ValueError, match="SurfaceWithHole along"):
        plant.check_step(1e-3, plant.initial_state([0.3, -0.6, -1.2]))
    plant.check_step(1e-6, plant.initial_state([0.3, -0.6, -1.2]))     # a step short enough passes


def test_stable_stiffness_runs(panda_at_wall):
    panda, q0, p, ctrl = panda_at_wall
    plant = ArmInContact(panda, CompliantPlane(p, [0, 0, 1], 1e6))
    res = simulate(plant, ctrl, (0.0, 0.01), plant.initial_state(q0), h=1e-3, Ts=1e-3)
    assert np.all(np.isfinite(res.x))


# --------------------------------------------------------------------------------------------
# Environments check their data and the pose they are given
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, name", [
    (dict(clearance=-0.01), "clearance"), (dict(clearance=0.0), "clearance"), (dict(depth=-0.05), "depth"),
    (dict(stiffness=-2e4), "stiffness"), (dict(stiffness=0.0), "stiffness"), (dict(damping=-1.0), "damping"),
    (dict(x_hole=np.nan), "x_hole"), (dict(depth=np.inf), "depth"), (dict(clearance="0.01"), "clearance"),
])
def test_surface_with_hole_checks_its_data(kwargs, name):
    args = dict(x_hole=0.5, clearance=0.004, depth=0.05) | kwargs
    with pytest.raises(ValueError, match=f"`{name}`"):
        SurfaceWithHole(**args)


@pytest.mark.parametrize("T, name", [
    (np.array([0.0, 0.0, 0.1]), "T_e"),                                   # a position, not a pose
    (pin.SE3(np.eye(3), np.array([np.nan, 0.0, 0.0])), "T_e"),
    (np.full((4, 4), np.nan), "T_e"),
    (np.eye(4) * 2, "T_e"),                                               # not a rigid transform
])
def test_wrench_checks_the_pose(T, name):
    for env in (CompliantPlane([0, 0, 0], [0, 0, 1], 1e4), SurfaceWithHole(0.0, 0.01, 0.05)):
        with pytest.raises(ValueError, match=f"`{name}`"):
            env.wrench(T, np.zeros(6))
    with pytest.raises(ValueError, match="`T_e`"):
        CompliantPlane([0, 0, 0], [0, 0, 1], 1e4).in_contact(T)


@pytest.mark.parametrize("v", [np.full(6, np.nan), np.zeros(3), [0, 0, np.inf, 0, 0, 0]])
def test_wrench_checks_the_twist(v):
    with pytest.raises(ValueError, match="`v_e`"):
        CompliantPlane([0, 0, 0], [0, 0, 1], 1e4).wrench(np.eye(4), v)


# --------------------------------------------------------------------------------------------
# Item 11: singular compliances and equilibria say what is singular and what to pass
# --------------------------------------------------------------------------------------------

def _hybrid(C, **kwargs):
    from controllers.force import HybridForceMotionControl

    R = np.array([[math.cos(math.pi / 4), -math.sin(math.pi / 4)], [math.sin(math.pi / 4), math.cos(math.pi / 4)]])
    return HybridForceMotionControl(load("planar_2r"), R[:, 1:2], R[:, 0:1], 10.0, 0.0, 20.0, 100.0, 20.0, 100.0,
                                    compliance=C, rows=(0, 1), **kwargs), R


@pytest.mark.parametrize("C", [
    lambda R: R @ np.diag([0.0, 1 / 5e3]) @ R.T,          # the book's: rigid along the motion direction
    lambda R: np.zeros((2, 2)),                           # Ĉ = 0
    lambda R: np.diag([1e-4, 0.0]),
])
def test_rank_deficient_compliance_asks_for_the_stiffness(C):
    R = np.array([[math.cos(math.pi / 4), -math.sin(math.pi / 4)], [math.sin(math.pi / 4), math.cos(math.pi / 4)]])
    with pytest.raises(ValueError, match=r"`compliance` Ĉ is singular \(rank \d < 2.*pass `stiffness=`"):
        _hybrid(C(R))


def test_book_compliance_with_stiffness_is_accepted_and_matches_the_weighted_inverse():
    R = np.array([[math.cos(math.pi / 4), -math.sin(math.pi / 4)], [math.sin(math.pi / 4), math.cos(math.pi / 4)]])
    law, _ = _hybrid(R @ np.diag([0.0, 1 / 5e3]) @ R.T, stiffness=R @ np.diag([1e4, 5e3]) @ R.T)
    # S_f† with the weight Ĉ picks the force along y_c: λ = y_cᵀ h_e (a unit S_f)
    h = np.array([3.0, -1.0])
    assert law.S_f_dagger @ h == pytest.approx(R[:, 1] @ h)


def test_zero_compliance_along_the_force_directions_is_named():
    with pytest.raises(ValueError, match=r"`compliance` gives a singular S_fᵀ W S_f"):
        _hybrid(np.zeros((2, 2)), stiffness=np.eye(2))
    R = np.array([[math.cos(math.pi / 4), -math.sin(math.pi / 4)], [math.sin(math.pi / 4), math.cos(math.pi / 4)]])
    with pytest.raises(ValueError, match=r"`stiffness` gives a singular S_vᵀ W S_v"):
        _hybrid(np.eye(2) / 5e3, stiffness=R @ np.diag([0.0, 1.0]) @ R.T)
    with pytest.raises(ValueError, match=r"`compliance_prime`"):
        _hybrid(np.eye(2) / 5e3, compliance_prime=np.zeros((2, 2)))
    with pytest.raises(ValueError, match=r"symmetric positive semi-definite"):
        _hybrid(-np.eye(2))


@pytest.mark.parametrize("K, C_F", [(np.eye(2), -np.eye(2)), (np.diag([1.0, 0.0]), -np.eye(2)),
                                    (np.array([[1.0, 1.0], [1.0, 1.0]]), -0.5 * np.eye(2))])
def test_singular_inner_loop_equilibrium_is_named(K, C_F):
    from controllers.force import inner_position_loop_equilibrium

    with pytest.raises(ValueError, match=r"I \+ C_F K is singular"):
        inner_position_loop_equilibrium([0.0, 0.0], [0.0, 0.0], K, C_F, [1.0, 1.0])


def test_inner_loop_equilibrium_solves_its_fixed_point():
    from controllers.force import inner_position_loop_equilibrium

    K, C_F = np.diag([2e3, 0.0]), np.diag([1e-3, 2e-3])
    x_d, x_r, f_d = np.array([0.1, 0.2]), np.array([0.12, 0.0]), np.array([5.0, 1.0])
    x_e = inner_position_loop_equilibrium(x_d, x_r, K, C_F, f_d)
    np.testing.assert_allclose(x_e, x_d + C_F @ (K @ (x_r - x_e) + f_d), atol=1e-14)   # Problem 9.4's rest


def test_singular_compliance_equilibrium_is_named():
    from controllers.force import compliance_equilibrium

    with pytest.raises(ValueError, match=r"I \+ K K_P⁻¹ is singular"):
        compliance_equilibrium(np.eye(2), -np.eye(2), [0.01, 0.0])


@pytest.mark.parametrize("kwargs, name", [(dict(dy=-0.02), "dy"), (dict(v_slow=0.0), "v_slow"),
                                          (dict(x_H=np.nan), "x_H"), (dict(eps="3"), "eps"), (dict(T_approach=np.inf), "T_approach")])
def test_peg_in_hole_task_checks_its_data(kwargs, name):
    from controllers.force import PegInHoleTask

    with pytest.raises(ValueError, match=f"`{name}`"):
        PegInHoleTask(**(dict(x_H=0.5) | kwargs))


def test_rk4_bounds_name_bad_arguments():
    """Review LOW: rk4_step_bound(m, 0, 0) divided by zero; no argument was checked."""
    assert rk4_step_bound(2.0, 0.0, 0.0) == math.inf                  # ẍ = 0: RK4 exact at any step
    assert rk4_step_bound(1.0, 2.0, 0.0) == pytest.approx(2.785 / 2.0, rel=1e-3)   # damping alone: h d/m ≤ 2.785
    for args, name in (((0.0, 1.0, 1.0), "mass"), ((1.0, -1.0, 1.0), "damping"), ((1.0, 1.0, np.nan), "stiffness"),
                       ((np.inf, 1.0, 1.0), "mass")):
        with pytest.raises(ValueError, match=f"`{name}`"):
            rk4_step_bound(*args)
        with pytest.raises(ValueError, match=f"`{name}`"):
            rk4_stable(*args, 1e-3)
    with pytest.raises(ValueError, match="`h`"):
        rk4_stable(1.0, 0.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="`h`"):
        rk4_stiffness_bound(1.0, 0.0, -1e-3)
    with pytest.raises(ValueError, match="`mass`"):
        rk4_stiffness_bound(-1.0, 0.0, 1e-3)
