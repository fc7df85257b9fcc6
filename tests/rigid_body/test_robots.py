import numpy as np
import pytest

from rigid_body.robots import available, example_robot_data_dir, load


def test_unknown_robot_lists_available_names():
    with pytest.raises(ValueError, match="unknown robot 'pnada'.*Did you mean panda.*planar_2r"):
        load("pnada")


def test_example_robot_data_found_without_network():
    assert (example_robot_data_dir() / "panda_description").is_dir()
    panda = load("panda")
    assert panda.nq == 7 and panda.model.frames[panda.ee_frame].name == "panda_hand"
    assert load("ur5").nq == 6


def test_load_from_path_and_parameters(tmp_path):
    robot = load("planar_2r")
    copy = tmp_path / "arm.urdf"
    copy.write_text(robot.urdf_xml)
    assert load(str(copy)).nq == 2
    longer = load("planar_3r", a=(1.0, 1.0, 1.0))
    from rigid_body.kinematics import direct_kinematics

    np.testing.assert_allclose(direct_kinematics(longer, np.zeros(3))[0, 3], 3.0)
    with pytest.raises(TypeError, match="planar_3r"):
        load("planar_3r", lengths=(1, 1, 1))
    with pytest.raises(TypeError, match="only accepted for the book"):
        load("panda", a=(1.0, 1.0))
    with pytest.raises(FileNotFoundError):
        load(str(tmp_path / "missing.urdf"))
    assert "scara" in available() and "ur5" in available()
