"""What `print(x)` shows for the main objects: one line each, not the URDF nor every array."""

import numpy as np

from controllers.simulation import SimulationResult
from planners.optimization import OptimalTrajectory
from planners.timing import quintic
from rigid_body.robots import load


def test_robot_repr_is_one_line_without_the_urdf():
    text = repr(load("panda"))
    assert text.startswith("Robot('panda', nq=7, nv=7, ee='panda_hand'") and "\n" not in text
    assert "ready" in text and "<robot" not in text and len(text) < 200
    assert "rotors" in repr(load("planar_2r"))


def test_result_reprs_summarise_instead_of_dumping_arrays():
    t = np.linspace(0.0, 2.0, 2001)
    res = SimulationResult(t=t, x=np.zeros((t.size, 4)), u=np.zeros((t.size, 2)), signals={"e": np.zeros((t.size, 2))})
    assert repr(res) == "SimulationResult(2001 samples on [0, 2] s, x: (4,), u: (2,), signals=['e'])"
    traj = quintic([0.0, 0.0], [1.0, 2.0], 2.0, dt=0.01)
    assert repr(traj) == "<Trajectory quintic: 201 samples x 2 joints on [0, 2] s>"
    opt = OptimalTrajectory(traj, np.zeros((201, 2)), 2.0, "time", 2.0, True, "", {"tau": 1.0}, 12, 0.5)
    text = repr(opt)
    assert text.startswith("OptimalTrajectory(minimum time: t_f=2 s") and "tau 1" in text and "\n" not in text


def test_solution_repr_is_one_line():
    from problems.registry import Solution

    sol = Solution(id="0.1", title="t", kind="numeric")
    sol.value("M", np.eye(30))
    sol.check("ok", True)
    assert repr(sol) == "Solution('0.1', 't', 1 values, 1/1 checks passed, 0 figures)"
