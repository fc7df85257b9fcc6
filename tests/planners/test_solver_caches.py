"""Solvers built once are keyed by the model's content, not by the robot object: a model changed in place
gets a solver of its own, and a robot given to ``solve_ik`` is not kept alive by a module-level cache."""

import gc
import weakref

import numpy as np
import pytest

from planners.inverse_kinematics import solve_ik
from planners.optimization import JointLimits, OptimizationOptions, minimum_time_trajectory
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import load


def test_a_model_changed_in_place_gets_its_own_transcription():
    """Link 2 made 3× heavier in place: the minimum time (torque-limited) is that of a fresh robot with the
    same heavier link, not the time of the transcription built before the change."""
    def heavier(robot):
        inertia = robot.model.inertias[2]
        robot.model.inertias[2] = type(inertia)(3.0 * inertia.mass, inertia.lever, 3.0 * inertia.inertia)
        return robot

    options = OptimizationOptions(nodes=12, tol=1e-7)
    args = ([0.0, 0.0], [1.0, -0.5])
    arm = load("planar_2r", motors=False)
    limits = JointLimits.from_robot(arm, qdd_max=[50.0, 50.0], qd_max=[5.0, 5.0], tau_max=[3000.0, 1500.0])
    light = minimum_time_trajectory(arm, *args, limits, options)
    changed = minimum_time_trajectory(heavier(arm), *args, limits, options)
    fresh = minimum_time_trajectory(heavier(load("planar_2r", motors=False)), *args, limits, options)
    assert light.success and changed.success and fresh.success
    assert changed.t_f == pytest.approx(fresh.t_f, rel=1e-6)
    assert changed.t_f > light.t_f * 1.05            # the heavier link is slower under the same torque limits


def test_solve_ik_keeps_no_robot_alive():
    robot = load("planar_3r")
    q = robot.configurations[next(iter(robot.configurations))] if robot.configurations else np.full(3, 0.3)
    result = solve_ik(robot, direct_kinematics(robot, q), rng=np.random.default_rng(0))
    assert result.success
    ref = weakref.ref(robot)
    del robot, result
    gc.collect()
    assert ref() is None
