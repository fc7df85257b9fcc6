"""The committed URDF files: regenerated from their tables, <mimic> kept, and yourdfpy agrees with Pinocchio."""


import numpy as np
import pytest
import yourdfpy

from rigid_body.kinematics import frame_poses
from rigid_body.robots import URDF_DIR, load
from rigid_body.book_robots import BOOK_ROBOTS, write_all


@pytest.mark.parametrize("name", sorted(BOOK_ROBOTS))
def test_committed_urdf_equals_regenerated(name, tmp_path):
    write_all(tmp_path)
    assert (tmp_path / f"{name}.urdf").read_text() == (URDF_DIR / f"{name}.urdf").read_text(), (
        f"urdf/{name}.urdf is stale: run `python -m rigid_body.book_robots`")


def test_motor_rotors_are_written_as_mimic_joints():
    text = (URDF_DIR / "planar_2r.urdf").read_text()
    assert text.count("<mimic ") == 2
    assert 'joint="joint_2" multiplier="100.0"' in text
    robot = load("planar_2r")
    assert robot.has_mimic and robot.nq == 2


def _yourdfpy_pose(urdf: yourdfpy.URDF, q_by_name: dict, frame: str) -> np.ndarray:
    cfg = [q_by_name.get(j, 0.0) for j in urdf.actuated_joint_names]
    urdf.update_cfg(cfg)
    return urdf.get_transform(frame_to=frame, frame_from=urdf.base_link)


def _joint_values(robot, q) -> dict:
    values = {}
    for j in range(1, robot.model.njoints):
        joint = robot.model.joints[j]
        if joint.nq == 1:
            values[robot.model.names[j]] = float(q[joint.idx_q])
    return values


@pytest.mark.parametrize("name", sorted(BOOK_ROBOTS) + ["panda", "ur5"])
def test_yourdfpy_forward_kinematics_agrees_with_pinocchio(name, rng):
    robot = load(name)
    urdf = yourdfpy.URDF.load(str(robot.urdf_path), build_scene_graph=True, load_meshes=False,
                              build_collision_scene_graph=False, load_collision_meshes=False)
    ee = robot.model.frames[robot.ee_frame].name
    for _ in range(5):
        q = robot.random_configuration(rng)
        T_pin = frame_poses(robot, q, [ee])[0]
        T_yd = _yourdfpy_pose(urdf, _joint_values(robot, q), ee)
        np.testing.assert_allclose(T_pin, T_yd, atol=1e-10, err_msg=f"{name} at q={q}")
