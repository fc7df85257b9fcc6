"""Chapter 8, centralised control: registration and the companion design data."""

import numpy as np

from problems.ch08_centralised import motor_side_inertias
from problems.registry import all_problems


def test_problems_8_10_to_8_16_are_registered_as_simulations():
    kinds = {p.id: p.kind for p in all_problems()}
    for i in range(10, 17):
        assert kinds.get(f"8.{i}") == "simulation"


def test_motor_side_inertias_of_the_companion_design():
    """I1 = (10 + 50·0.25 + 0.01 + 5·1)/100² + 0.01, I2 = (10 + 50·0.25 + 10·1)/100² + 0.01."""
    np.testing.assert_allclose(motor_side_inertias(10.0), [0.012751, 0.01325], atol=1e-12)

