"""The viewer under hostile input (issue 26, item 10): huge spans, results of another robot, robots by name."""

import time

import numpy as np
import pytest

from controllers.plants import ArmPlant, UnicyclePlant
from controllers.simulation import simulate
from rigid_body.robots import load
from viewer import Scene, TeachPendant, animate, motion_of, show
from viewer.mobile import planar_body


@pytest.fixture(scope="module")
def arm():
    return load("planar_2r")


def test_a_huge_span_is_refused_at_once(arm):
    """A 1e7 s span used to build 3e8 frames (a hang)."""
    started = time.perf_counter()
    with pytest.raises(ValueError, match=r"1e\+07 s of motion.*3e\+08 frames.*MAX_FRAMES = 36000.*`speed` \(≥ 8\.33e\+03\)"):
        animate(arm, (np.array([0.0, 1e7]), np.zeros((2, 2))))
    assert time.perf_counter() - started < 5.0
    scene = animate(arm, (np.array([0.0, 1e7]), np.zeros((2, 2))), speed=1e4)    # the remedy works
    assert scene.duration == pytest.approx(1e7 / 1e4, rel=1e-3)


@pytest.mark.parametrize("fps, speed", [(1e6, 1.0), (30.0, 1e-6)])
def test_frame_count_is_bounded_by_fps_and_speed_too(arm, fps, speed):
    with pytest.raises(ValueError, match="MAX_FRAMES"):
        animate(arm, (np.array([0.0, 10.0]), np.zeros((2, 2))), fps=fps, speed=speed)


def test_a_unicycle_result_is_not_animated_as_an_arm(arm):
    """animate(planar_2r, <UnicyclePlant result>) used to play x, y as joint angles."""
    res = simulate(UnicyclePlant(), lambda t, m: np.array([0.5, 0.2]), (0.0, 1.0), [0.0, 0.0, 0.0], h=0.01)
    with pytest.raises(ValueError, match=r"no configuration of 'planar_2r'.*states \['p', 'theta', 'x', 'y'\]"):
        motion_of(res, arm)
    t, q = motion_of(res, planar_body())                    # its own robot: the joints x, y, θ by name
    np.testing.assert_array_equal(q, res.x[:, :3])


def test_an_unnamed_state_is_taken_for_joint_angles_only_when_it_fits(arm):
    res = simulate(lambda t, x, u: -x, lambda t, x: np.zeros(3), (0.0, 0.1), np.ones(3), h=0.01)
    with pytest.raises(ValueError, match="no `q`"):
        motion_of(res, arm)                                # 3 states: neither [q] nor [q, q̇] of a 2R arm
    res = simulate(lambda t, x, u: -x, lambda t, x: np.zeros(4), (0.0, 0.1), np.ones(4), h=0.01)
    t, q = motion_of(res, arm)                             # [q, q̇]: the documented reading
    np.testing.assert_array_equal(q, res.x[:, :2])


def test_an_arm_result_of_another_size_is_refused(arm):
    plant = ArmPlant(load("planar_3r"))
    res = simulate(plant, lambda t, m: np.zeros(3), (0.0, 0.05), plant.initial_state(np.zeros(3)), h=0.01)
    with pytest.raises(ValueError, match=r"must have shape \(6, 2\) for robot 'planar_2r', got \(6, 3\)"):
        motion_of(res, arm)


def test_robots_by_name():
    scene = show("planar_2r", [0.3, -0.6])
    assert "robot" in scene.robots and scene.robots["robot"].robot.name == "planar_2r"
    with pytest.raises(ValueError, match="unknown robot 'pandaa'"):
        show("pandaa")
    with pytest.raises(ValueError, match="`robot` must be a Robot or a name"):
        show(42)
    scene = Scene()
    scene.add_robot("planar_3r", name="arm")
    assert scene.robots["arm"].robot.nq == 3
    with pytest.raises(ValueError, match="`robot` must be a Robot"):
        TeachPendant(None, server=False)
