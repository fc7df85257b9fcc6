"""Loading robots from bad files or with parameters they do not take (issue 26, item 12)."""

import pytest

from rigid_body.robots import load, robot_from_urdf_string


@pytest.mark.parametrize("text, message", [
    ("", "empty, not a URDF"),
    ("   \n", "empty, not a URDF"),
    ("<robot name='x'><link name='a'></robot>", r"malformed URDF XML \(mismatched tag: line 1, column 33\)"),
    ("<?xml version='1.0'?>", "malformed URDF XML"),
    ("<robot name='x'></robot>", "needs at least one <link>"),
    ("<sdf version='1.6'><model/></sdf>", "the root element is <sdf>, not <robot>"),
    ("<robot name='x'><link name='a'><inertial><mass value='nan'/></inertial></link></robot>", "mass"),
])
def test_a_bad_urdf_file_is_named(tmp_path, text, message):
    path = tmp_path / "arm.urdf"
    path.write_text(text)
    with pytest.raises(ValueError, match=message) as err:
        load(str(path))
    assert str(err.value).startswith(str(path))


def test_bad_urdf_text_names_the_robot():
    with pytest.raises(ValueError, match="the URDF text of 'mine': malformed"):
        robot_from_urdf_string("<robot name='mine'><link>", name="mine")


@pytest.mark.parametrize("name", ["panda", "ur5"])
@pytest.mark.parametrize("params", [dict(a=(1.0, 1.0)), dict(motors="rotors"), dict(gravity=(0, 0, -9.81))])
def test_example_robots_refuse_book_parameters(name, params):
    with pytest.raises(ValueError, match=f"{sorted(params)}.*'{name}' takes only `payload`"):
        load(name, **params)


def test_book_robots_name_their_parameters():
    with pytest.raises(ValueError, match=r"book robot 'puma560': unknown parameters \['a'\]; it takes \['motors'"):
        load("puma560", a=(1.0,))
    with pytest.raises(ValueError, match="book robot 'planar_2r'"):
        load("planar_2r", lengths=(1.0, 1.0))
    assert load("planar_2r", payload=1.0).nq == 2
