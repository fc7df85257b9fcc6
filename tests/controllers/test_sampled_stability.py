"""PD + gravity on a real arm: a diverging loop says which joint violates which sampled-stability bound."""

import numpy as np
import pytest

from controllers.joint_space import PDGravityCompensation, sampled_stability
from controllers.plants import ArmPlant
from controllers.simulation import SimulationDiverged, simulate
from rigid_body.robots import load


@pytest.fixture(scope="module")
def panda():
    return load("panda")


def test_the_bounds_are_the_exact_poles_of_a_sampled_double_integrator():
    """Jury's conditions against the eigenvalues of the ZOH-discretised closed loop, on a grid."""
    arm = load("planar_2r")
    q = np.zeros(2)
    from rigid_body.dynamics import inertia_matrix

    b = 1.0 / np.diag(np.linalg.inv(inertia_matrix(arm, q)))[0]
    Ts = 1e-3
    for kd in np.linspace(1e4, 1e6, 9):
        for kp in np.linspace(1e5, 2e9, 9):
            A = np.array([[1.0, Ts], [0.0, 1.0]])
            B = np.array([[Ts ** 2 / (2 * b)], [Ts / b]])
            stable = np.max(np.abs(np.linalg.eigvals(A - B @ np.array([[kp, kd]])))) < 1
            joint1 = [p for p in sampled_stability(arm, [kp, 1.0], [kd, 1.0], Ts, q) if p.startswith("joint 1")]
            assert stable == (not joint1), (kp, kd)


def test_panda_pd_gravity_divergence_names_joint_7_and_the_damping_bound(panda):
    q0 = panda.configurations["ready"]
    plant = ArmPlant(panda)
    pd = PDGravityCompensation(panda, K_P=100.0, K_D=20.0, reference=q0)
    with pytest.raises(SimulationDiverged) as err:
        simulate(plant, pd, (0.0, 0.5), plant.initial_state(q0 + 0.05), h=1e-3, Ts=1e-3)
    message = str(err.value)
    assert "joint 7: K_D,7·Ts/b_7" in message and "≥ 2" in message and "lower K_D,7 below" in message
    assert "joint 1" not in message  # the heavy shoulder is fine with these gains


def test_a_period_given_to_the_controller_checks_the_gains_up_front(panda):
    q0 = panda.configurations["ready"]
    with pytest.raises(ValueError, match="joint 7"):
        PDGravityCompensation(panda, K_P=100.0, K_D=20.0, reference=q0, Ts=1e-3)


def test_the_docstring_gains_for_the_panda_are_stable_and_regulate(panda):
    q_d = panda.configurations["ready"]
    pd = PDGravityCompensation(panda, K_P=[600, 600, 600, 600, 250, 150, 50], K_D=[50, 50, 50, 50, 10, 10, 3],
                               reference=q_d, Ts=1e-3)
    plant = ArmPlant(panda)
    res = simulate(plant, pd, (0.0, 1.0), plant.initial_state(q_d + 0.05), h=1e-3, Ts=1e-3)
    assert np.abs(res.q[-1] - q_d).max() < 0.01


def test_the_docstring_gains_for_the_ur5_pass_the_check():
    ur5 = load("ur5")
    assert sampled_stability(ur5, [600, 600, 400, 100, 100, 50], [60, 60, 40, 10, 10, 8], 1e-3,
                             ur5.configurations["home"]) == []


# ---- inverse dynamics control: the sampled unit double integrator per joint ------------------

def test_sampled_error_poles_match_the_closed_form_characteristic_polynomial():
    """Eigenvalues of A − b k against the roots of z² − (2 − d − p/2) z + 1 − d + p/2 (d = K_D Ts, p = K_P Ts²)."""
    from controllers.joint_space import sampled_error_poles

    Ts = 2e-3
    for kp, kd in [(100.0, 16.0), (1e5, 900.0), (4e6, 100.0), (1e4, 1500.0)]:
        d, p = kd * Ts, kp * Ts**2
        expected = np.sort_complex(np.roots([1.0, -(2 - d - p / 2), 1 - d + p / 2]).astype(complex))
        got = np.sort_complex(sampled_error_poles(kp, kd, Ts)[0].astype(complex))
        np.testing.assert_allclose(got, expected, atol=1e-12)


def test_inverse_dynamics_divergence_names_the_joint_and_the_gain_to_lower():
    from controllers.joint_space import InverseDynamicsControl

    arm = load("planar_2r")
    q_d = np.array([0.3, 0.5])
    plant = ArmPlant(arm)
    ctrl = InverseDynamicsControl(arm, [100.0, 100.0], [16.0, 2500.0], q_d)  # K_D,2 Ts = 2.5 ≥ 2
    with pytest.raises(SimulationDiverged) as err:
        simulate(plant, ctrl, (0.0, 0.5), plant.initial_state(q_d + 0.05), h=1e-3, Ts=1e-3)
    message = str(err.value)
    assert "joint 2: sampled error poles" in message and "lower K_D,2 below 2000" in message
    assert "joint 1" not in message


def test_inverse_dynamics_with_stable_gains_diagnoses_nothing():
    from controllers.joint_space import InverseDynamicsControl
    from controllers.plants import ArmMeasurement

    arm = load("planar_2r")
    ctrl = InverseDynamicsControl(arm, 100.0, 16.0, np.zeros(2))
    assert ctrl.diagnose(None, 1e-3, ArmMeasurement(np.zeros(2), np.zeros(2))) == ""
