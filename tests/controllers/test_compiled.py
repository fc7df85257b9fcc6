"""The compiled backend reproduces the Python loop; symbolic forward dynamics against Pinocchio's ABA."""

import numpy as np
import pinocchio as pin
import pytest

from controllers.joint_space import InverseDynamicsControl, PDGravityCompensation, RobustControl
from controllers.operational_space import OperationalPDGravity
from controllers.plants import ArmPlant, JointIntegrator
from controllers.simulation import SimulationDiverged, simulate
from planners.timing import quintic
from rigid_body.robots import load
from rigid_body.symbolic import forward_dynamics_function, inverse_dynamics_function

Q_D = np.array([np.pi / 4, -np.pi / 2])


@pytest.fixture(scope="module")
def arm():
    return load("planar_2r")


@pytest.mark.parametrize("make", [
    lambda arm: PDGravityCompensation(arm, 3750, 750, Q_D),
    lambda arm: InverseDynamicsControl(arm, 100, 16, quintic(Q_D - 0.3, Q_D, 0.4, dt=1e-3), 100.0),
    lambda arm: OperationalPDGravity(arm, 2000, 500, [0.7, 0.9], rows=(0, 1)),
], ids=["pd_gravity", "inverse_dynamics", "operational_pd"])
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
    robust = RobustControl(arm, [1.0, 1.0], 10, 5, Q_D, rho=1.0, epsilon=0.01)
    with pytest.raises(ValueError, match="controller"):
        simulate(plant, robust, (0, 0.01), x0, h=1e-3, backend="casadi")
    with pytest.raises(ValueError, match="plant"):
        simulate(JointIntegrator(), PDGravityCompensation(arm, 10, 5, Q_D), (0, 0.01), np.zeros(2), h=1e-3,
                 backend="casadi")


def test_diverging_compiled_loop_says_when(arm):
    plant = ArmPlant(arm)
    with pytest.raises(SimulationDiverged) as err:   # explicit RK4 at 10 ms with K_D = 1e6: unstable
        simulate(plant, PDGravityCompensation(arm, 1e6, 1e6, Q_D), (0.0, 2.0), np.r_[Q_D - 0.1, 0, 0],
                 h=1e-2, backend="casadi")
    assert 0.0 < err.value.t < 2.0
