"""The loop's and the plants' messages for a state or an input of the wrong length (issue 26, item 12)."""

import numpy as np
import pytest

from controllers.independent_joint import JointDrive
from controllers.plants import (ArmInContact, ArmPlant, BicyclePlant, ChainedFormPlant, UnicyclePlant,
                                VoltageControlledArm)
from controllers.environment import CompliantPlane
from controllers.simulation import simulate
from rigid_body.robots import load


@pytest.fixture(scope="module")
def arm():
    return load("planar_2r")


@pytest.mark.parametrize("make", [lambda a: ArmPlant(a), lambda a: ArmInContact(a, CompliantPlane([0, 0, 0], [0, 1, 0], 1e3)),
                                  lambda a: VoltageControlledArm(a, [50, 50], [JointDrive(1e-4, 1.0, 0.1, 0.1)] * 2)])
@pytest.mark.parametrize("size", [3, 5])
def test_a_state_of_the_wrong_length_is_named_x(arm, make, size):
    """It used to say `qd` (the slice that came out short)."""
    plant = make(arm)
    with pytest.raises(ValueError, match=rf"`x` \(the state \[q; q̇\], 2 \+ 2 entries\) must have shape \(4,\), got \({size},\)"):
        plant.derivative(0.0, np.zeros(size), np.zeros(2))
    with pytest.raises(ValueError, match="`x`"):
        plant.measure(0.0, np.zeros(size))
    with pytest.raises(ValueError, match="`x0` must have 4 entries"):
        simulate(plant, lambda t, m: np.zeros(2), (0.0, 0.01), np.zeros(size), h=1e-3)


@pytest.mark.parametrize("v_c", [np.zeros(1), np.zeros(3), 1.0])
def test_a_voltage_vector_of_the_wrong_length_is_not_broadcast(arm, v_c):
    plant = VoltageControlledArm(arm, [50, 50], [JointDrive(1e-4, 1.0, 0.1, 0.1)] * 2)
    with pytest.raises(ValueError, match=r"`u` \(the motor voltages v_c\) must have shape \(2,\)"):
        plant.derivative(0.0, np.zeros(4), v_c)
    with pytest.raises(ValueError, match="VoltageControlledArm takes an input u of size 2"):
        simulate(plant, lambda t, m: np.atleast_1d(v_c), (0.0, 0.01), np.zeros(4), h=1e-3)


@pytest.mark.parametrize("plant, x0", [(UnicyclePlant(), np.zeros(3)), (BicyclePlant(1.0), np.zeros(4)),
                                       (ChainedFormPlant(), np.zeros(3))])
@pytest.mark.parametrize("u", [np.zeros(1), np.zeros(3)])
def test_wheeled_plants_name_an_input_of_the_wrong_length(plant, x0, u):
    """A bicycle driven by one input used to raise a bare IndexError."""
    with pytest.raises(ValueError, match=f"{type(plant).__name__} takes an input u of size 2"):
        simulate(plant, lambda t, m: u, (0.0, 0.01), x0, h=1e-3)
