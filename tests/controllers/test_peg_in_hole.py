"""The peg-in-hole controller (controllers/force.py, Problem 6.3): its state machine and its hybrid
force/position law, with the task-space wrench recovered through a finite-difference Jacobian."""

import numpy as np
import pytest

from controllers.force import PegInHoleController, PegInHoleTask
from controllers.plants import ArmMeasurement
from rigid_body.dynamics import gravity_torques
from rigid_body.kinematics import direct_kinematics, inverse_kinematics_planar_3r
from rigid_body.robots import load


def _x(robot, q):
    T = direct_kinematics(robot, q)
    return np.array([T[0, 3], T[1, 3], np.arctan2(T[1, 0], T[0, 0])])


def _fd_jacobian(robot, q, h=1e-7):
    return np.column_stack([(_x(robot, q + h * e) - _x(robot, q - h * e)) / (2 * h) for e in np.eye(len(q))])


@pytest.fixture(scope="module")
def arm():
    return load("planar_3r")


def _wrench(robot, q, tau):
    """w with τ = g(q) + Jᵀ w, J by central differences of (x, y, φ)."""
    return np.linalg.solve(_fd_jacobian(robot, q).T, tau - gravity_torques(robot, q))


def test_state_machine_and_hybrid_law(arm):
    task = PegInHoleTask(x_H=0.6)
    ctrl = PegInHoleController(arm, task)
    q = inverse_kinematics_planar_3r(np.array([task.x_H, task.dy, task.phi]))[0]
    qd = np.zeros(arm.nv)
    no_force = np.zeros(6)
    ctrl(0.0, ArmMeasurement(q, qd, no_force))                      # plans the approach from here
    assert ctrl.state == "approach"
    ctrl(task.T_approach + 0.01, ArmMeasurement(q, qd, no_force))    # reached (x_H, Δy): descend
    assert ctrl.state == "descend"
    contact = np.array([0.0, -2 * task.eps, 0, 0, 0, 0])            # |f_y| > ε: the peg touches the surface
    t = task.T_approach + 0.011                                     # 1 ms sampling
    ctrl(t, ArmMeasurement(q, qd, contact))
    assert ctrl.state == "search"
    tau = ctrl(t + 0.001, ArmMeasurement(q, qd, contact))
    w = _wrench(arm, q, tau)
    # search (the hybrid law of controllers/force.py, tested on its own there): the tip is pushed down
    # the y axis (force-controlled) and driven along +x (the reference slides at v_search)
    assert w[1] < 0 and w[0] > 0
    ctrl(t + 0.002, ArmMeasurement(q, qd, no_force))                # force drops: the peg is over the hole
    assert ctrl.state == "insert"
    tau = ctrl(t + 0.003, ArmMeasurement(q, qd, no_force))
    w = _wrench(arm, q, tau)
    assert w[1] < 0                                                   # y position-controlled downwards
    assert abs(w[0]) < abs(w[1])                                      # x force-controlled (no push along x)
