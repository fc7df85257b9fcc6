import numpy as np
import pytest

from rigid_body.robots import available, example_robot_data_dir, load, with_payload


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
    with pytest.raises(ValueError, match="planar_3r"):
        load("planar_3r", lengths=(1, 1, 1))
    with pytest.raises(ValueError, match="'panda' takes only `payload`"):
        load("panda", a=(1.0, 1.0))
    with pytest.raises(FileNotFoundError):
        load(str(tmp_path / "missing.urdf"))
    assert "scara" in available() and "ur5" in available()


def test_frame_none_is_the_end_effector_and_ids_are_checked():
    from rigid_body.kinematics import direct_kinematics

    arm = load("planar_2r")
    assert arm.frame(None) == arm.frame() == arm.ee_frame == arm.frame("ee")
    q = np.array([0.3, -0.4])
    nframes = arm.model.nframes
    with pytest.raises(ValueError, match=rf"`frame` id 16 out of range \[0, {nframes}\)"):
        direct_kinematics(arm, q, frame=16)
    with pytest.raises(ValueError, match="`frame` id -1 out of range"):
        direct_kinematics(arm, q, frame=-1)
    with pytest.raises(ValueError, match=r"no frame 'frame_7'.*nearest: \['frame_"):
        direct_kinematics(arm, q, frame="frame_7")
    # a numpy integer id is an id (Pinocchio's bindings reject np.int64): same pose as the plain int and the name
    fid = arm.frame("frame_1")
    T = direct_kinematics(arm, q, frame=np.int64(fid))
    np.testing.assert_allclose(T, direct_kinematics(arm, q, frame=fid))
    np.testing.assert_allclose(T[:2, 3], [np.cos(0.3), np.sin(0.3)], atol=1e-12)  # a1 = 1 m along θ1


def test_payload_on_panda_adds_the_weight_through_the_jacobian_transpose(rng):
    """g(q) with a 2 kg payload minus without = −J_Pᵀ m g₀ (the weight m g₀ applied at the end effector)."""
    from rigid_body.dynamics import gravity_torques
    from rigid_body.kinematics import geometric_jacobian

    m = 2.0
    panda, loaded = load("panda"), load("panda", payload=m)
    assert loaded.nq == 7 and loaded.ee_frame == panda.ee_frame
    g0 = np.array([0.0, 0.0, -9.81])
    for _ in range(5):
        q = panda.random_configuration(rng)
        J_P = geometric_jacobian(panda, q)[:3]
        np.testing.assert_allclose(gravity_torques(loaded, q) - gravity_torques(panda, q), -J_P.T @ (m * g0),
                                   atol=1e-10)
    # the book's arm: the same point mass at the tip of the two-link arm, from the closed form m g a (c1 + c12)
    arm, arm_loaded = load("planar_2r"), load("planar_2r", payload=m)
    q = np.array([0.4, 0.7])
    dg = gravity_torques(arm_loaded, q) - gravity_torques(arm, q)
    np.testing.assert_allclose(dg, m * 9.81 * np.array([np.cos(0.4) + np.cos(1.1), np.cos(1.1)]), atol=1e-10)
    with pytest.raises(ValueError, match="`mass`"):
        with_payload(load("panda"), -1.0)


@pytest.mark.parametrize("name", ["planar_2r", "scara", "anthropomorphic_wrist", "panda", "ur5"])
def test_robots_have_collision_and_visual_geometry(name):
    robot = load(name)
    assert robot.collision_model.ngeoms > 0 and robot.visual_model.ngeoms > 0
    # every shape hangs on a joint of the (reduced) model
    assert all(0 <= g.parentJoint < robot.model.njoints for g in robot.collision_model.geometryObjects)
    assert with_payload(robot, 1.0).collision_model is robot.collision_model


def test_book_shapes_follow_the_dh_frames():
    """The a2 cylinder of the two-link arm is centred half-way along link 2: at the (book) midpoint of
    the segment from joint 2 to the tip, a1 [c1, s1] + a2/2 [c12, s12]."""
    import pinocchio as pin

    arm = load("planar_2r")
    q = np.array([0.5, -0.9])
    data = pin.GeometryData(arm.collision_model)
    pin.forwardKinematics(arm.model, arm.data, q)
    pin.updateGeometryPlacements(arm.model, arm.data, arm.collision_model, data)
    centres = [data.oMg[k].translation for k, g in enumerate(arm.collision_model.geometryObjects)]
    mid = np.array([np.cos(0.5) + 0.5 * np.cos(-0.4), np.sin(0.5) + 0.5 * np.sin(-0.4), 0.0])
    assert min(np.linalg.norm(c - mid) for c in centres) < 1e-12


def test_panda_collision_distance_between_far_links_changes_with_q():
    """Hand vs link 0 (base): apart at the neutral pose, closer when the arm folds back over its base."""
    import pinocchio as pin

    from rigid_body.kinematics import direct_kinematics

    panda = load("panda")
    geom = panda.collision_model
    names = [g.name for g in geom.geometryObjects]
    hand, base = names.index("panda_hand_0"), names.index("panda_link0_0")
    geom = geom.copy()
    geom.addCollisionPair(pin.CollisionPair(hand, base))
    data = pin.GeometryData(geom)

    def distance(q):
        pin.computeDistances(panda.model, panda.data, geom, data, q)
        return data.distanceResults[0].min_distance

    d_neutral = distance(np.zeros(7))
    q_folded = np.array([0.0, 1.6, 0.0, -2.9, 0.0, 1.2, 0.0])
    d_folded = distance(q_folded)
    assert d_neutral > 0.3 and 0 <= d_folded < d_neutral
    # the meshes are ~0.1 m around their frames: the distance follows the hand frame's distance from the base
    for q, d in ((np.zeros(7), d_neutral), (q_folded, d_folded)):
        p_hand = direct_kinematics(panda, q)[:3, 3]
        assert np.linalg.norm(p_hand) - 0.3 < d < np.linalg.norm(p_hand)


def test_a_frame_name_typo_suggests_the_frames_containing_it():
    panda = load("panda")
    with pytest.raises(ValueError, match=r"no frame 'hand'; nearest: \['panda_hand', "):
        panda.frame("hand")
    with pytest.raises(ValueError, match=r"no frame 'zzz'; its frames: \['universe', "):
        panda.frame("zzz")


def test_a_missing_named_configuration_lists_the_names():
    with pytest.raises(KeyError, match=r"no configuration named 'home'.*\['neutral', 'ready'\]"):
        load("panda").configurations["home"]
    assert "ready" in load("panda", payload=1.0).configurations  # kept by with_payload


@pytest.mark.parametrize("name", ["ur5", "planar_2r", "puma560"])
def test_a_negative_payload_names_the_argument(name):
    with pytest.raises(ValueError, match="`payload`"):
        load(name, payload=-1.0)
