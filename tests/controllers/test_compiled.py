"""The compiled backend reproduces the Python loop; symbolic forward dynamics against Pinocchio's ABA."""

import numpy as np
import pinocchio as pin
import pytest

import controllers.compiled as compiled
import rigid_body.codegen as codegen
from controllers.environment import CompliantPlane, SteppedPlane
from controllers.force import ForceWithInnerLoop, HybridForceMotionControl
from controllers.independent_joint import JointDrive, design_position_velocity
from controllers.joint_space import (AdaptivePayloadControl, ComputedTorqueFeedforward, InverseDynamicsControl,
                                     PDGravityCompensation, RobustControl, as_reference)
from controllers.operational_space import OperationalInverseDynamics, OperationalPDGravity
from controllers.plants import ArmInContact, ArmPlant, JointIntegrator, VoltageControlledArm
from controllers.simulation import SimulationDiverged, simulate
from planners.paths import PathLaw, Segment
from planners.timing import quintic, trapezoidal_law
from rigid_body.kinematics import ELBOW_UP, inverse_kinematics_planar_2r
from rigid_body.robots import load
from rigid_body.symbolic import forward_dynamics_function, inverse_dynamics_function

Q_D = np.array([np.pi / 4, -np.pi / 2])
SEGMENT = Segment([0.9, 0.7, 0.0], [0.6, 1.1, 0.0])          # near the tip at Q_D − 0.1, length 0.5 m


@pytest.fixture(scope="module")
def arm():
    return load("planar_2r")


@pytest.mark.parametrize("make", [
    lambda arm: PDGravityCompensation(arm, 3750, 750, Q_D),
    lambda arm: InverseDynamicsControl(arm, 100, 16, quintic(Q_D - 0.3, Q_D, 0.4, dt=1e-3), 100.0),
    lambda arm: OperationalPDGravity(arm, 2000, 500, [0.7, 0.9], rows=(0, 1)),
    lambda arm: OperationalInverseDynamics(arm, 100, 16, PathLaw(SEGMENT, trapezoidal_law(0.0, 0.5, 0.4, 2.0)),
                                           rows=(0, 1), viscous_friction=100.0),
    lambda arm: OperationalInverseDynamics(arm, 400, 40, [0.8, 0.9], rows=(0, 1), viscous_friction=50.0, inertia=2.0),
    lambda arm: OperationalInverseDynamics(arm, 100, 20, PathLaw(SEGMENT, trapezoidal_law(0.0, 0.5, 0.4, 2.0)),
                                           rows=(1,), null_space_damping=5.0, posture=Q_D, posture_stiffness=10.0),
    lambda arm: RobustControl(arm, [8.0, 2.0], 100, 16, quintic(Q_D - 0.3, Q_D, 0.4, dt=1e-3), rho=5.0,
                              epsilon=0.05, viscous_friction=100.0),
    lambda arm: AdaptivePayloadControl(arm, 200, 5, 50.0, quintic(Q_D - 0.3, Q_D, 0.4, dt=1e-3), 100.0, mass0=1.0),
], ids=["pd_gravity", "inverse_dynamics", "operational_pd", "operational_inverse_dynamics", "impedance",
        "operational_redundant", "robust", "adaptive"])
def test_casadi_backend_reproduces_python_loop(arm, make):
    plant = ArmPlant(arm, viscous_friction=100.0, tau_max=[3000.0, 3000.0])
    x0 = np.r_[Q_D - 0.1, 0.2, -0.1]
    a = simulate(plant, make(arm), (0.0, 0.5), x0, h=5e-4, Ts=1e-3)
    b = simulate(plant, make(arm), (0.0, 0.5), x0, h=5e-4, Ts=1e-3, backend="casadi")
    np.testing.assert_array_equal(a.t, b.t)
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.u, a.u, rtol=1e-12, atol=1e-9)
    assert set(a.signals) == set(b.signals)
    for name in a.signals:
        np.testing.assert_allclose(b[name], a[name], rtol=0, atol=1e-9)


def test_symbolic_forward_dynamics_matches_aba_with_armature():
    ur5 = load("ur5")
    model = ur5.model.copy()
    model.armature[:] = np.linspace(0.1, 0.6, 6)
    data = model.createData()
    rng = np.random.default_rng(3)
    fd, rnea = forward_dynamics_function(model), inverse_dynamics_function(model)
    for _ in range(5):
        q, v, tau = rng.uniform(-2, 2, 6), rng.uniform(-1, 1, 6), rng.uniform(-20, 20, 6)
        np.testing.assert_allclose(fd(q, v, tau).full().ravel(), pin.aba(model, data, q, v, tau), atol=1e-9)
        a = rng.uniform(-1, 1, 6)
        np.testing.assert_allclose(rnea(q, v, a).full().ravel(), pin.rnea(model, data, q, v, a), atol=1e-9)


def test_backend_errors_name_the_argument(arm):
    plant = ArmPlant(arm)
    x0 = np.zeros(4)
    with pytest.raises(ValueError, match="backend"):
        simulate(plant, PDGravityCompensation(arm, 10, 5, Q_D), (0, 0.01), x0, h=1e-3, backend="numba")
    with pytest.raises(ValueError, match="controller"):                   # a plain function: no symbolic form
        simulate(plant, lambda t, meas: np.zeros(2), (0, 0.01), x0, h=1e-3, backend="casadi")
    with pytest.raises(ValueError, match="plant"):
        simulate(JointIntegrator(), PDGravityCompensation(arm, 10, 5, Q_D), (0, 0.01), np.zeros(2), h=1e-3,
                 backend="casadi")


def test_diverging_compiled_loop_says_when(arm):
    plant = ArmPlant(arm)
    with pytest.raises(SimulationDiverged) as err:   # explicit RK4 at 10 ms with K_D = 1e6: unstable
        simulate(plant, PDGravityCompensation(arm, 1e6, 1e6, Q_D), (0.0, 2.0), np.r_[Q_D - 0.1, 0, 0],
                 h=1e-2, backend="casadi")
    assert 0.0 < err.value.t < 2.0


def test_references_sampled_at_once_match_one_by_one():
    """The compiled loop samples a trajectory or a path law at all instants in one call (``at_times``)."""
    times = np.linspace(0.0, 0.6, 601)                                     # beyond the end too: held
    law = PathLaw(SEGMENT, trapezoidal_law(0.0, 0.5, 0.4, 2.0))
    for reference, n in ((quintic(Q_D - 0.3, Q_D, 0.4, dt=1e-3), 2), (law, 3)):
        ref = as_reference(reference, n)
        stacked = compiled.stacked_reference(ref)
        one_by_one = np.column_stack([stacked(t) for t in times])
        np.testing.assert_allclose(stacked.at_times(times), one_by_one, rtol=0, atol=1e-12)
    ctrl = OperationalInverseDynamics(load("planar_2r"), 100, 16, law, rows=(0, 1))
    assert hasattr(ctrl.reference, "at_times")                            # the (x, y) rows of the 3-D law
    np.testing.assert_allclose(ctrl.reference.at_times(times)[1], law(times)[1][:, :2], rtol=0, atol=0)


def test_fast_backend_falls_back_to_python_without_a_compiler(monkeypatch):
    monkeypatch.setattr(codegen, "compiler", lambda: None)
    with pytest.warns(UserWarning, match="Python backend"):
        assert compiled.fast_backend() == "python"
    monkeypatch.setattr(codegen, "compiler", lambda: "cc")
    assert compiled.fast_backend() == "casadi"


@pytest.mark.parametrize("force_feedback", [False, True], ids=["pd_gravity", "impedance_force_feedback"])
def test_casadi_backend_reproduces_python_loop_in_contact(arm, force_feedback):
    """ArmInContact's symbolic plant and sensed wrench: the tip pushed into a compliant plane, contact made
    and lost along the run (unilateral plane), against the Python loop."""
    plane = CompliantPlane([1.2, 0.0, 0.0], [-1.0, -1.0, 0.0], 5e3, damping=20.0)
    plant = ArmInContact(arm, plane, viscous_friction=100.0)
    q0 = np.array([0.2, -1.6])                              # tip outside the plane
    target = [0.95, 0.55]                                   # beyond the plane: pushes in, then rests in contact
    if force_feedback:
        make = lambda: OperationalInverseDynamics(arm, 2000, 300, target, rows=(0, 1), viscous_friction=100.0,
                                                  inertia=5.0, force_feedback=True)
    else:
        make = lambda: OperationalPDGravity(arm, 3000, 600, target, rows=(0, 1))
    a = simulate(plant, make(), (0.0, 0.6), plant.initial_state(q0), h=1e-3, Ts=1e-3)
    b = simulate(plant, make(), (0.0, 0.6), plant.initial_state(q0), h=1e-3, Ts=1e-3, backend="casadi")
    wrench = np.array([plant.wrench(x[:2], x[2:])[0] for x in a.x])
    assert np.any(wrench[:, 0] != 0) and np.any(wrench[:, 0] == 0)          # free motion and contact
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.u, a.u, rtol=1e-12, atol=1e-9)
    for name in a.signals:
        np.testing.assert_allclose(b[name], a[name], rtol=0, atol=1e-9)


@pytest.mark.parametrize("environment", ["friction", "stepped", "bilateral"])
def test_casadi_backend_reproduces_python_loop_against_more_environments(arm, environment):
    """The plane's one body (wrench_law) with Coulomb friction on the surface, a stepped plane (the recess as a
    masked branch) and a bilateral spring, against the Python loop."""
    if environment == "friction":
        env = CompliantPlane([1.2, 0.0, 0.0], [-1.0, -1.0, 0.0], 5e3, damping=20.0, friction=0.3, slip_velocity=1e-2)
    elif environment == "stepped":
        env = SteppedPlane([1.2, 0.0, 0.0], [-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], 0.05, 0.02, 5e3, damping=20.0)
    else:
        env = CompliantPlane([1.2, 0.0, 0.0], [-1.0, -1.0, 0.0], 5e3, damping=20.0, bilateral=True)
    plant = ArmInContact(arm, env, viscous_friction=100.0)
    make = lambda: OperationalPDGravity(arm, 3000, 600, PathLaw(Segment([0.9, 0.55, 0.0], [0.6, 0.95, 0.0]),
                                                                trapezoidal_law(0.0, 0.5, 0.5, 2.0)), rows=(0, 1))
    x0 = plant.initial_state(np.array([0.2, -1.6]))
    a = simulate(plant, make(), (0.0, 0.6), x0, h=1e-3, Ts=1e-3)
    b = simulate(plant, make(), (0.0, 0.6), x0, h=1e-3, Ts=1e-3, backend="casadi")
    wrench = np.array([plant.wrench(x[:2], x[2:])[0] for x in a.x])
    assert np.any(wrench[:, :2] != 0)
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.u, a.u, rtol=1e-12, atol=1e-8)


def test_compiled_loop_refuses_blocks_without_a_symbolic_form(arm):
    """The one generic refusal: a Python function inside a block (an external force, an environment without
    a wrench law) names the block and points to the Python loop."""
    from controllers.environment import SurfaceWithHole

    law = PDGravityCompensation(arm, 3750, 750, Q_D)
    x0 = np.r_[Q_D - 0.1, 0.0, 0.0]
    with pytest.raises(compiled.NoSymbolicForm, match="ArmPlant.*external_force.*backend='python'"):
        simulate(ArmPlant(arm, external_force=lambda t, q, v: np.zeros(2)), law, (0, 0.01), x0, h=1e-3,
                 backend="casadi")
    with pytest.raises(compiled.NoSymbolicForm, match="SurfaceWithHole.*wrench_law"):
        simulate(ArmInContact(arm, SurfaceWithHole(0.6, 0.01, 0.05)), law, (0, 0.01), x0, h=1e-3, backend="casadi")


def test_casadi_backend_reproduces_python_loop_with_exact_coulomb_friction(arm):
    """Coulomb friction with the exact sign (the default, F_s sgn(q̇)) and direction-dependent values, and its
    smoothed form, run compiled: the arm is stopped by friction (q̇ = 0 along the way) in both loops alike."""
    from rigid_body.robots import JointFriction

    for plant in (ArmPlant(arm, friction=JointFriction(np.array([5.0, 2.0]), np.array([40.0, 20.0]),
                                                       np.array([30.0, 25.0]))),
                  ArmPlant(arm, viscous_friction=5.0, coulomb_friction=30.0, friction_smoothing=0.05)):
        x0 = plant.initial_state(Q_D - 0.1, [0.5, -0.4])
        make = lambda: PDGravityCompensation(arm, 400, 40, Q_D)
        a = simulate(plant, make(), (0.0, 0.5), x0, h=1e-3, Ts=1e-3)
        b = simulate(plant, make(), (0.0, 0.5), x0, h=1e-3, Ts=1e-3, backend="casadi")
        np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
        np.testing.assert_allclose(b.u, a.u, rtol=1e-12, atol=1e-8)


def test_casadi_backend_reproduces_python_loop_on_a_continuous_joint():
    """nq ≠ nv: a continuous joint (q = [cos θ, sin θ]) — the compiled RK4 stages move q by the plant's
    integrate (the symbolic pin.integrate), as the Python loop does."""
    from tests.controllers.test_plants import _pendulum

    plant = ArmPlant(_pendulum(pin.JointModelRUBZ()), viscous_friction=0.1)
    x0 = plant.initial_state([1.0, 0.0], [0.5])
    a = simulate(plant, lambda t, m: np.array([0.3]), (0.0, 1.0), x0, h=1e-3, Ts=1e-2)
    b = simulate(plant, compiled.ConstantInput([0.3], plant), (0.0, 1.0), x0, h=1e-3, Ts=1e-2, backend="casadi")
    assert np.ptp(np.arctan2(a.q[:, 1], a.q[:, 0])) > 0.5                  # it swings
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(b.q, axis=1), 1.0, atol=1e-12)


R_C = np.array([[1.0, -1.0], [1.0, 1.0]]) / np.sqrt(2.0)        # constraint frame: x_c along the plane, y_c normal


@pytest.mark.parametrize("make", [
    lambda arm: ForceWithInnerLoop(arm, 400.0, 40.0, 1.0, 1e-4, [1.0, 0.0] + R_C @ [0.15, -0.02], -40.0 * R_C[:, 1],
                                   K_I=1e-3, rows=(0, 1), viscous_friction=100.0),
    lambda arm: ForceWithInnerLoop(arm, 400.0, 40.0, 1.0, 1e-4, [1.0, 0.0], -40.0 * R_C[:, 1], inner="velocity",
                                   rows=(0, 1), viscous_friction=100.0),
    lambda arm: HybridForceMotionControl(arm, R_C[:, 1:], R_C[:, :1], [-50.0], lambda t: ([0.1 * np.cos(t)], [-0.1 * np.sin(t)]),
                                         100.0, 50.0, 30.0, 400.0, compliance=np.eye(2) / 5e3, rows=(0, 1),
                                         viscous_friction=100.0),
], ids=["force_PI_inner_position", "force_P_inner_velocity", "hybrid"])
def test_casadi_backend_reproduces_python_force_loops(arm, make):
    """Laws with a state (the integral actions, forward Euler per sample) and the sensed wrench."""
    plant = ArmInContact(arm, CompliantPlane([1.0, 0.0, 0.0], np.r_[R_C[:, 1], 0.0], 5e3), viscous_friction=100.0)
    x0 = plant.initial_state(inverse_kinematics_planar_2r(np.array([1.0, 0.0]) + R_C @ [0.15, 0.0])[ELBOW_UP])
    a = simulate(plant, make(arm), (0.0, 1.0), x0, h=1e-3, Ts=1e-3)
    b = simulate(plant, make(arm), (0.0, 1.0), x0, h=1e-3, Ts=1e-3, backend="casadi")
    assert np.abs(a.u).max() > 1.0 and np.abs(a["h_e" if "h_e" in a.signals else "f_e"]).max() > 1.0
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.u, a.u, rtol=1e-12, atol=1e-8)
    for name in a.signals:
        np.testing.assert_allclose(b[name], a[name], rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("feedforward", [True, False])
def test_casadi_backend_reproduces_python_voltage_controlled_servos(arm, feedforward):
    """The PV servos with computed-torque feedforward (PI integrals as the law's state) on the
    voltage-controlled arm (Fig. 8.3)."""
    drives = [JointDrive(I=i, Ra=10.0, kt=2.0, kv=2.0, Fm=0.01) for i in (0.02, 0.005)]
    designs = [design_position_velocity(d, 0.8, 10.0) for d in drives]
    plant = VoltageControlledArm(arm, 100.0, drives, viscous_friction=100.0)
    make = lambda: ComputedTorqueFeedforward(arm, quintic(Q_D - 0.3, Q_D, 0.4, dt=1e-3), 100.0, drives, designs,
                                             feedforward=feedforward)
    x0 = plant.initial_state(Q_D - 0.3)
    a = simulate(plant, make(), (0.0, 0.6), x0, h=5e-4, Ts=1e-3)
    b = simulate(plant, make(), (0.0, 0.6), x0, h=5e-4, Ts=1e-3, backend="casadi")
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.u, a.u, rtol=1e-12, atol=1e-9)
    for name in a.signals:
        np.testing.assert_allclose(b[name], a[name], rtol=0, atol=1e-9)


@pytest.mark.parametrize("case", ["no_current_loop", "no_amplifier_lag", "pi_current_loop"])
def test_casadi_backend_reproduces_python_servomotor_loops(case):
    from controllers.plants import ServomotorPlant
    from rigid_body.actuators import DCServomotor, design_pi_current_loop

    data = dict(Ra=0.2, La=2e-3, kt=0.2, kv=0.2, Im=0.0014, Fm=0.01, Gv=1.0, Tv=1e-4)
    if case == "no_amplifier_lag":
        data["Tv"] = 0.0
    motor = DCServomotor(**data, ki=1.0 if case == "pi_current_loop" else 0.0)
    plant = ServomotorPlant(motor, design_pi_current_loop(motor, 0.7, 2e-3)[0] if case == "pi_current_loop" else 1.0)
    u = np.array([1.0, 0.02])                                   # a step V'_c with a load torque C_r
    a = simulate(plant, lambda t, x: u, (0.0, 0.02), plant.x0, h=1e-6, Ts=1e-5)
    b = simulate(plant, compiled.ConstantInput(u, plant), (0.0, 0.02), plant.x0, h=1e-6, Ts=1e-5, backend="casadi")
    np.testing.assert_allclose(b.t, a.t, rtol=1e-14, atol=0)          # k·(10 h) against k·Ts: last-bit rounding
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(b.u, a.u)
    assert np.max(np.abs(a["i_a"])) > 0.1 and not b.signals


def test_constant_input_checks_its_arguments():
    from controllers.plants import ServomotorPlant, UnicyclePlant
    from rigid_body.actuators import DCServomotor

    plant = ServomotorPlant(DCServomotor(Ra=0.2, La=2e-3, kt=0.2, kv=0.2, Im=0.0014, Fm=0.01), 1.0)
    with pytest.raises(ValueError, match="value"):
        compiled.ConstantInput([1.0, np.nan], plant)
    with pytest.raises(ValueError, match="plant"):
        compiled.ConstantInput([1.0, 0.0], UnicyclePlant())


def test_cached_run_is_the_rollout(arm, tmp_path, monkeypatch):
    """A loop found in the cache (a fresh process: nothing loaded) runs the code of its own rollout."""
    monkeypatch.setattr(codegen, "CACHE", tmp_path)
    plant, x0 = ArmPlant(arm, viscous_friction=100.0), np.r_[Q_D - 0.1, 0.2, -0.1]
    first = compiled.CompiledLoop(plant, PDGravityCompensation(arm, 400, 40, Q_D), 1e-3, 2, 50)
    codegen._loaded.clear()
    loop = compiled.CompiledLoop(plant, PDGravityCompensation(arm, 500, 30, Q_D), 1e-3, 2, 50)
    assert len(list(tmp_path.glob("rollout_*.so"))) == 1 and loop._rollout is None   # found, not rebuilt
    other = compiled.CompiledLoop(plant, PDGravityCompensation(arm, 500, 30, Q_D), 1e-3, 2, 60)
    assert len(list(tmp_path.glob("rollout_*.so"))) == 2                              # N is in the key
    R, p = loop.references(0.0), loop.law.parameters
    for got, expected in zip(loop.run(x0, R, p), loop.rollout(x0, R, p)):
        np.testing.assert_allclose(np.asarray(got), np.asarray(expected), rtol=1e-12, atol=1e-12)
    assert first.run(x0, R, first.law.parameters)[0].shape == (4, 50) and other.n_samples == 60


def _pose_reference(robot, q0, dq):
    """A pose trajectory t -> (T_d, v_d, a_d): the end-effector pose along q0 + s(t) dq (a quintic s), its
    twist and acceleration from the arm's kinematics (a reachable, smooth pose path)."""
    from rigid_body.task_space import frame_state

    def law(t):
        tau = min(max(t / 0.3, 0.0), 1.0)
        s, sd, sdd = 10 * tau**3 - 15 * tau**4 + 6 * tau**5, (30 * tau**2 - 60 * tau**3 + 30 * tau**4) / 0.3, \
            (60 * tau - 180 * tau**2 + 120 * tau**3) / 0.09
        q, qd, qdd = q0 + s * dq, sd * dq, sdd * dq
        st = frame_state(robot, q, qd)
        return st.T, st.J @ qd, st.J @ qdd + st.Jdot_qd

    return law


@pytest.mark.parametrize("orientation", ["quaternion", "axis_angle"])
@pytest.mark.parametrize("law", ["pd_gravity", "inverse_dynamics", "redundant"])
def test_casadi_backend_reproduces_python_pose_tasks(orientation, law):
    """Pose tasks (the quaternion (3.91) and angle–axis (3.85) errors) run compiled: the UR5 (a square task)
    and the Panda (redundant, null-space posture) against the Python loop."""
    robot = load("panda" if law == "redundant" else "ur5")
    q0 = robot.configurations["ready"] if law == "redundant" else np.array([0.3, -1.2, 1.4, -1.5, -1.4, 0.2])
    dq = np.linspace(0.1, 0.25, robot.nv)
    plant = ArmPlant(robot, viscous_friction=0.5)
    reference = _pose_reference(robot, q0, dq)
    if law == "pd_gravity":
        make = lambda: OperationalPDGravity(robot, [400, 400, 400, 40, 40, 40], [40, 40, 40, 4, 4, 4],
                                            reference(0.3)[0], orientation=orientation, joint_damping=1.0)
    elif law == "inverse_dynamics":
        make = lambda: OperationalInverseDynamics(robot, 100, 20, reference, orientation=orientation,
                                                  viscous_friction=0.5)
    else:
        make = lambda: OperationalInverseDynamics(robot, 100, 20, reference, orientation=orientation,
                                                  viscous_friction=0.5, null_space_damping=5.0, posture=q0,
                                                  posture_stiffness=10.0)
    x0 = plant.initial_state(q0 + 0.02, 0.05 * np.ones(robot.nv))
    a = simulate(plant, make(), (0.0, 0.4), x0, h=1e-3, Ts=1e-3)
    b = simulate(plant, make(), (0.0, 0.4), x0, h=1e-3, Ts=1e-3, backend="casadi")
    assert np.abs(a["e"]).max() > 1e-3                                     # the task error is exercised
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.u, a.u, rtol=1e-12, atol=1e-8)
    assert set(a.signals) == set(b.signals)
    for name in a.signals:
        np.testing.assert_allclose(b[name], a[name], rtol=0, atol=1e-9)


def test_numeric_frame_pose_returns_copies():
    """Numeric.frame_pose's (R, o) are the law's own: the next Pinocchio call on the same data leaves them."""
    from controllers.laws import Numeric

    arm = load("puma560")
    R, o = Numeric.frame_pose(arm.model, arm.data, arm.ee_frame, np.zeros(arm.nq))
    R0, o0 = R.copy(), o.copy()
    Numeric.frame_pose(arm.model, arm.data, arm.ee_frame, np.full(arm.nq, 0.3))
    np.testing.assert_array_equal(R, R0)
    np.testing.assert_array_equal(o, o0)
