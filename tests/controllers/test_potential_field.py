"""Potential-field control of a planar 3R arm while a disc obstacle crosses its workspace (Sect. 12.6.4)."""

import numpy as np
import pytest
from shapely.geometry import LineString, Point

from controllers.plants import ArmPlant
from controllers.potential_field import PotentialFieldControl
from controllers.simulation import simulate
from rigid_body.robots import load

GOAL = np.array([0.2, 0.7])
A = np.array([0.5, 0.3, 0.2])                     # planar_3r link lengths (Fig. 2.20)
RADIUS = 0.06


def center(t):
    return np.array([0.75 - 0.15 * t, 0.35])     # the obstacle drifts left across the arm's sweep


def _controller(robot, k_r=0.01):
    return PotentialFieldControl(robot, GOAL, center, RADIUS, k_a=10.0, k_r=k_r, eta0=0.2, K_D=[2.0, 0.6, 0.1])


def _clearance_by_hand(q, c):
    """Distance of the arm's links (closed-form planar kinematics) from the disc, by shapely."""
    phi = np.cumsum(q)
    pts = np.vstack([[0.0, 0.0], np.cumsum(A[:, None] * np.column_stack([np.cos(phi), np.sin(phi)]), axis=0)])
    return LineString(pts).distance(Point(c)) - RADIUS, pts[-1]


@pytest.fixture(scope="module")
def run():
    robot = load("planar_3r")
    plant = ArmPlant(robot)
    return simulate(plant, _controller(robot), (0.0, 8.0), plant.initial_state(np.zeros(3)), h=1e-3, Ts=2e-3)


def test_the_goal_is_reached_with_positive_clearance(run):
    clear, tips = zip(*(_clearance_by_hand(q, center(t)) for t, q in zip(run.t[::5], run.q[::5])))
    clear = np.array(clear)
    assert clear.min() > 0.02                                      # never closer than 2 cm
    assert np.linalg.norm(tips[-1] - GOAL) < 5e-3                  # at the goal within 5 mm
    assert np.abs(run.qd[-1]).max() < 0.05                         # and at rest
    # the controller's own clearance agrees with shapely's on the closed-form arm
    np.testing.assert_allclose(run["eta"][::5], clear, atol=1e-9)
    assert np.abs(run["tau_r"]).max() > 1.0                        # the repulsion did act


def test_without_repulsion_the_arm_hits_the_moving_obstacle():
    robot = load("planar_3r")
    plant = ArmPlant(robot)
    with pytest.raises(ValueError, match="touches the obstacle at t ="):
        simulate(plant, _controller(robot, k_r=1e-12), (0.0, 8.0), plant.initial_state(np.zeros(3)),
                 h=1e-3, Ts=2e-3)


def test_bad_arguments_are_named():
    robot = load("planar_3r")
    with pytest.raises(ValueError, match="radius"):
        PotentialFieldControl(robot, GOAL, center, 0.0, 1.0, 1.0, 0.2, 1.0)
    with pytest.raises(ValueError, match="center"):
        PotentialFieldControl(robot, GOAL, [0.5, 0.5], RADIUS, 1.0, 1.0, 0.2, 1.0)
    with pytest.raises(ValueError, match="K_D"):
        PotentialFieldControl(robot, GOAL, center, RADIUS, 1.0, 1.0, 0.2, [1.0, -1.0, 1.0])
