"""The viewer's scene, geometry and animation records, checked against closed forms and scipy."""

from __future__ import annotations

import base64
import re

import numpy as np
import pinocchio as pin
import pytest
import umsgpack
from scipy.spatial.transform import Rotation

from controllers.simulation import SimulationResult
from planners.timing import quintic
from problems.registry import Solution
from rigid_body.camera import PinholeCamera, project
from rigid_body.manipulability import velocity_ellipsoid
from rigid_body.robots import load, robot_from_urdf_string
from viewer import (Scene, TeachPendant, animate, arrow_transform, export_html, geometry_of, motion_of,
                    report_animations, show, skeleton_of, up_rotation)
from viewer.scene import _decompose

A1 = A2 = 1.0  # link lengths of the book's two-link arm (planar_2r)


def _tip_2r(q):
    """Closed-form tip position of the two-link planar arm, Eq. (2.63)."""
    return np.array([A1 * np.cos(q[0]) + A2 * np.cos(q[0] + q[1]), A1 * np.sin(q[0]) + A2 * np.sin(q[0] + q[1]), 0.0])


def _commands(scene: Scene) -> list[dict]:
    return [umsgpack.unpackb(c) for c in scene._recorder.commands()]


def _transform(scene: Scene, path: str) -> np.ndarray:
    """The last transform recorded for ``path`` (meshcat stores it column-major)."""
    matrices = [c["matrix"] for c in _commands(scene) if c["type"] == "set_transform" and c["path"] == path]
    assert matrices, f"no transform recorded for {path}"
    return np.array(matrices[-1]).reshape(4, 4).T


def test_the_skeleton_of_planar_2r_ends_at_the_closed_form_tip(rng):
    robot = load("planar_2r")
    geom = skeleton_of(robot)
    assert geom.ngeoms > 0 and all(g.name.startswith(("link_", "joint_")) for g in geom.geometryObjects)
    gdata = geom.createData()
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, 2)
        pin.forwardKinematics(robot.model, robot.data, q)
        pin.updateGeometryPlacements(robot.model, robot.data, geom, gdata)
        # the far end of every cylinder: centre + half length along its z axis
        ends = [gdata.oMg[k].translation + g.geometry.halfLength * gdata.oMg[k].rotation[:, 2]
                for k, g in enumerate(geom.geometryObjects) if g.name.startswith("link_")]
        distances = [np.linalg.norm(e - _tip_2r(q)) for e in ends]
        assert min(distances) < 1e-12


def test_a_urdf_without_geometry_is_drawn_as_its_skeleton():
    xml = re.sub(r"<(visual|collision)>.*?</\1>", "", load("planar_3r").urdf_xml, flags=re.S)
    robot = robot_from_urdf_string(xml)
    geom = geometry_of(robot)
    assert geom.ngeoms == skeleton_of(robot).ngeoms > 0


def test_panda_geometry_sits_where_yourdfpy_puts_the_urdf_links(rng):
    """The meshes are matched to the reduced 7-DOF model (fingers locked): their world poses agree
    with an independent URDF parser (yourdfpy) at random configurations."""
    import yourdfpy

    robot = load("panda")
    collision, visual = geometry_of(robot, "collision"), geometry_of(robot, "visual")
    assert visual.ngeoms >= 9 and all(g.meshPath.endswith(".dae") for g in visual.geometryObjects)
    assert sum(g.meshPath.endswith(".stl") for g in collision.geometryObjects) >= 9
    urdf = yourdfpy.URDF.load(str(robot.urdf_path), load_meshes=False, build_scene_graph=True)
    gdata = collision.createData()
    for _ in range(3):
        q = robot.random_configuration(rng)
        urdf.update_cfg({f"panda_joint{k + 1}": q[k] for k in range(7)})
        pin.forwardKinematics(robot.model, robot.data, q)
        pin.updateGeometryPlacements(robot.model, robot.data, collision, gdata)
        for k, g in enumerate(collision.geometryObjects):
            link, index = g.name.rsplit("_", 1)
            origin = urdf.link_map[link].collisions[int(index)].origin  # None: at the link frame
            expected = urdf.get_transform(link) @ (np.eye(4) if origin is None else origin)
            assert np.allclose(gdata.oMg[k].homogeneous, expected, atol=1e-9), g.name
    with pytest.raises(ValueError, match="kind"):
        geometry_of(robot, "pretty")


def test_geometry_of_prefers_the_robots_own_geometry_model(monkeypatch):
    robot = load("planar_3r")
    own = skeleton_of(robot, radius=0.05)
    monkeypatch.setattr(type(robot), "visual_model", property(lambda self: own), raising=False)
    assert geometry_of(robot, "visual") is own


def test_decompose_matches_scipy_quaternion_and_recovers_scale(rng):
    for _ in range(10):
        R = Rotation.random(random_state=rng.integers(1 << 31))
        s = rng.uniform(0.1, 3.0, 3)
        T = np.eye(4)
        T[:3, :3] = R.as_matrix() @ np.diag(s)
        T[:3, 3] = rng.normal(size=3)
        p, quat, scale = _decompose(T)
        ref = R.as_quat()  # scipy: [x, y, z, w], the order three.js reads
        assert np.allclose(quat, ref) or np.allclose(quat, -ref)
        assert np.allclose(scale, s) and np.allclose(p, T[:3, 3])


def test_animation_keyframes_follow_the_closed_form_kinematics():
    robot = load("planar_2r")
    traj = quintic([0.0, 0.0], [np.pi / 2, -np.pi / 3], 1.0, dt=0.01)
    scene = animate(robot, traj, speed=0.5, fps=20)
    assert scene.duration == pytest.approx(2.0)  # 1 s of motion played at half speed
    animation = [c for c in _commands(scene) if c["type"] == "set_animation"]
    assert len(animation) == 1 and _commands(scene)[-1]["type"] == "set_animation"  # last: binds to objects
    clips = {a["path"]: a["clip"] for a in animation[0]["animations"]}
    # the triad of the end-effector frame follows the tip of the arm
    track = {t["name"]: t for t in clips["/meshcat/robot/frames/ee"]["tracks"]}[".position"]
    assert len(track["keys"]) == 41  # 2 s at 20 fps, both ends
    for key in track["keys"][::8]:
        t = key["time"] / 20.0 * 0.5  # frame → motion time
        q = traj.law(t)[0]
        assert np.allclose(key["value"], _tip_2r(q), atol=1e-9)


def test_motion_of_reads_trajectories_simulation_results_and_pairs():
    robot = load("planar_2r")
    t = np.linspace(0.0, 1.0, 11)
    q = np.column_stack([t, -t])
    res = SimulationResult(t=t, x=np.column_stack([q, np.ones_like(q)]), u=np.zeros((11, 2)))
    for motion in (res, (t, q), quintic([0.0, 0.0], [1.0, -1.0], 1.0, samples=11)):
        tt, qq = motion_of(motion, robot)
        assert qq.shape == (11, 2) and np.allclose(qq[-1], [1.0, -1.0])
    with pytest.raises(ValueError, match="motion"):
        motion_of((t, q[:, :1]), robot)
    with pytest.raises(ValueError, match="motion"):
        motion_of(object(), robot)
    with pytest.raises(ValueError, match="`t`"):
        show(robot).animate(t[::-1], q)


def test_arrow_transform_maps_the_unit_arrow_onto_the_vector(rng):
    for _ in range(5):
        o, v = rng.normal(size=3), rng.normal(size=3)
        T = arrow_transform(o, v)
        assert np.allclose(T @ [0.0, 0.0, 0.0, 1.0], [*o, 1.0])
        assert np.allclose(T @ [0.0, 1.0, 0.0, 1.0], [*(o + v), 1.0])  # the tip of the unit arrow
        assert np.linalg.det(T[:3, :3]) > 0


def test_ellipsoid_overlay_is_the_velocity_ellipsoid(rng):
    robot = load("anthropomorphic")
    q = np.array([0.3, 0.5, -1.0])
    J = pin.computeFrameJacobian(robot.model, robot.data, q, robot.ee_frame, pin.LOCAL_WORLD_ALIGNED)[:3]
    scene = Scene()
    scene.ellipsoid("manipulability", [0.1, 0.2, 0.3], velocity_ellipsoid(J))
    T = _transform(scene, "/meshcat/overlays/manipulability")
    u = rng.normal(size=(20, 3))
    x = (T[:3, :3] @ (u / np.linalg.norm(u, axis=1, keepdims=True)).T).T  # points of the unit sphere, mapped
    assert np.allclose(np.einsum("ij,jk,ik->i", x, np.linalg.inv(J @ J.T), x), 1.0)  # v^T (J J^T)^-1 v = 1
    assert np.allclose(T[:3, 3], [0.1, 0.2, 0.3])


def test_frustum_corners_project_to_the_image_corners():
    camera, size = PinholeCamera(800.0, 820.0, 320.0, 240.0), (640.0, 480.0)
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("xyz", [0.3, -0.2, 1.0]).as_matrix()
    T[:3, 3] = [0.5, -0.1, 1.2]
    scene = Scene()
    scene.frustum("camera", T, camera, size, depth=0.4)
    command = [c for c in _commands(scene) if c["path"] == "/meshcat/overlays/camera" and c["type"] == "set_object"][0]
    data = command["object"]["geometries"][0]["data"]["attributes"]["position"]["array"].data
    points = np.frombuffer(data, dtype=np.float32).reshape(-1, 3)
    far = points[np.abs(points[:, 2] - 0.4) < 1e-6]
    world = (T[:3, :3] @ far.T).T + T[:3, 3]
    pixels = [(project(camera, p, T).X_I, project(camera, p, T).Y_I) for p in world]
    assert len(pixels) == 12  # each corner ends an edge ray and two rim segments
    for corner in ((0.0, 0.0), (640.0, 0.0), (640.0, 480.0), (0.0, 480.0)):  # float32 vertices
        assert min(np.hypot(X - corner[0], Y - corner[1]) for X, Y in pixels) < 1e-3


def test_overlays_reject_bad_input_naming_the_argument():
    scene = Scene()
    with pytest.raises(ValueError, match="`size`"):
        scene.box("b", np.eye(4), [1.0, -1.0, 1.0])
    with pytest.raises(ValueError, match="`normal`"):
        scene.plane("p", [0, 0, 0], [0, 0, 0])
    with pytest.raises(ValueError, match="`paths`"):
        scene.polyline("l", [[0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match="`color`"):
        scene.points("s", np.zeros((3, 3)), color="red")
    with pytest.raises(ValueError, match="`name`"):
        scene.frame("/abs", np.eye(4))
    with pytest.raises(ValueError, match="robot"):
        scene.display([0.0, 0.0])
    show(load("planar_2r"), scene=scene)
    with pytest.raises(ValueError, match="`q`"):
        scene.display([0.0, 0.0, 0.0])


def test_polyline_draws_every_segment_of_a_tree():
    scene = Scene()
    branches = [np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0]], float), np.array([[0, 0], [0, 1]], float)]
    scene.polyline("tree", branches)
    command = [c for c in _commands(scene) if c["path"] == "/meshcat/overlays/tree" and c["type"] == "set_object"][0]
    data = command["object"]["geometries"][0]["data"]["attributes"]["position"]["array"].data
    assert np.frombuffer(data, dtype=np.float32).size == 3 * 2 * 3  # 3 segments of 2 points


def test_teach_pendant_moves_one_joint_within_its_limits():
    robot = load("planar_2r")
    pendant = TeachPendant(robot, server=False)
    q = pendant.set(0, np.pi / 2)
    T = _transform(pendant.scene, "/meshcat/robot/frames/ee")
    assert np.allclose(T[:3, 3], _tip_2r(q))
    assert pendant.set(1, 100.0)[1] == pytest.approx(min(robot.upper[1], np.pi))
    with pytest.raises(ValueError, match="`joint`"):
        pendant.set(2, 0.0)


def test_export_is_one_offline_html_file_and_the_report_hook_writes_one_per_animation(tmp_path):
    robot = load("planar_2r")
    traj = quintic([0.0, 0.0], [1.0, -1.0], 1.0, dt=0.01)
    path = export_html(robot, traj, tmp_path / "a.html")
    page = path.read_text()
    assert not re.search(r'<(script|link|img)[^>]+(src|href)="(?!data:)', page)  # nothing loaded from elsewhere
    assert "new MeshCat.Viewer" in page and path.stat().st_size < 2_000_000
    sol = Solution(id="8.10")
    sol.animation(robot, traj, "PD + gravity", speed=2.0)
    snippets = report_animations(sol, tmp_path)
    assert len(snippets) == 1 and 'src="animations/8.10_1.html"' in snippets[0]
    assert (tmp_path / "animations" / "8.10_1.html").is_file()
    # the commands decode back to meshcat's msgpack
    first = re.search(r'var commands = \[\n"([^"]+)"', page).group(1)
    assert umsgpack.unpackb(base64.b64decode(first))["type"] in ("set_object", "set_property", "set_transform")


def test_live_server_binds_to_localhost_and_receives_the_scene():
    scene = Scene(server=True)
    try:
        assert scene.url.startswith("http://127.0.0.1:")
        scene.add_robot(load("planar_2r"), [0.3, 0.2])
        served = scene._recorder.live.get_scene()  # the server's own static export of what it received
        assert served.count("data:application/octet-binary;base64,") == len(scene._recorder.commands())  # all mirrored
    finally:
        scene.close()
    assert scene.url is None


@pytest.mark.parametrize("g", [(0, 0, -9.81), (0, 0, 9.81), (0, -9.81, 0), (1.0, 2.0, -3.0), (-1e-3, 0, 5.0)])
def test_up_rotation_turns_minus_gravity_to_the_viewers_vertical(g):
    R = up_rotation(g)
    assert np.allclose(R @ R.T, np.eye(3)) and np.linalg.det(R) == pytest.approx(1.0)
    assert np.allclose(R @ (-np.asarray(g) / np.linalg.norm(g)), [0.0, 0.0, 1.0])
    assert np.allclose(up_rotation((0, 0, 0)), np.eye(3))


def test_the_scaras_base_frame_is_turned_upside_down_in_the_viewer():
    """The book's SCARA has g along +z (z0 down): the scene's root is rotated by R_x(π)."""
    scene = show(load("scara"))
    assert np.allclose(_transform(scene, "/meshcat"), np.diag([1.0, -1.0, -1.0, 1.0]))


def test_tubes_and_cylinders_span_their_segments():
    scene = Scene()
    scene.polyline("path", np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 2.0, 0.0]]), radius=0.01)
    for k, (a, b) in enumerate((([0, 0, 0], [1, 0, 0]), ([1, 0, 0], [1, 2, 0]))):
        T = _transform(scene, f"/meshcat/overlays/path/segment_{k}")
        height = [c for c in _commands(scene) if c["path"] == f"/meshcat/overlays/path/segment_{k}"
                  and c["type"] == "set_object"][0]["object"]["geometries"][0]["height"]
        # three.js cylinders run along local y from -h/2 to h/2
        assert np.allclose(T @ [0, -height / 2, 0, 1], [*a, 1]) and np.allclose(T @ [0, height / 2, 0, 1], [*b, 1])
    scene.cylinder("obstacle", [0.3, 0.0, 0.0], 0.1, 0.02)
    T = _transform(scene, "/meshcat/overlays/obstacle")
    assert np.allclose(T[:3, 1], [0.0, 0.0, 1.0]) and np.allclose(T[:3, 3], [0.3, 0.0, 0.0])


def test_repeated_instants_are_accepted_and_the_last_sample_wins():
    robot = load("planar_2r")
    t = np.array([0.0, 0.5, 0.5, 1.0])
    q = np.array([[0.0, 0.0], [0.1, 0.0], [1.0, 0.0], [1.0, 0.0]])
    scene = show(robot)
    assert scene.animate(t, q, fps=2) == 3
    clips = {a["path"]: a["clip"] for c in _commands(scene) if c["type"] == "set_animation" for a in c["animations"]}
    keys = {t["name"]: t for t in clips["/meshcat/robot/frames/ee"]["tracks"]}[".position"]["keys"]
    assert np.allclose(keys[1]["value"], _tip_2r([1.0, 0.0]))


def test_commands_packed_as_meshcat_packs_them():
    """viewer packs with the compiled msgpack: byte for byte what meshcat's umsgpack.packb gives, for
    typed arrays (Ext), floats, ints of every width, strings, bytes, booleans, None, nested maps."""
    import meshcat.geometry as mg

    from viewer.scene import _packb

    mesh = mg.Mesh(mg.Box([0.1, 0.2, 0.3]), mg.MeshPhongMaterial(color=0xFF0000))
    data = {"type": "set_object", "path": "/overlays/box", "object": mesh.lower(),
            "misc": [0, 1, -1, -33, 127, 128, 255, 256, 70000, -70000, 2**33, -2**40, 2**63, 0.1, -2.5e-300,
                     1e300, True, False, None, "é" * 40, b"\x00\x01" * 200, list(range(20)),
                     {str(k): k / 3 for k in range(20)}],
            "points": mg.PointsGeometry(np.arange(12.0).reshape(3, 4)).lower({})}
    assert _packb(data) == umsgpack.packb(data)
    with pytest.raises(TypeError, match="cannot pack"):
        _packb({"bad": object()})


def test_a_prismatic_link_stays_attached_whatever_its_extension():
    """The SCARA's third link (which carries the camera of Example 10.3) is a quill on the prismatic joint's axis over
    its stroke: at every extension the point where joint 3 is mounted on link 2 lies on it (no camera floating
    below the arm); a mobile body's x, y carriages get none."""
    import pinocchio as pin

    from controllers.scenes import scara_eye_in_hand
    from viewer import planar_body
    from viewer.geometry import geometry_of

    robot = scara_eye_in_hand()
    (quill,) = [o for o in geometry_of(robot).geometryObjects if o.name.startswith("quill")]
    j = quill.parentJoint
    model, data = robot.model, robot.model.createData()
    for d3 in (0.0, 0.3, 0.7, 1.0):
        q = np.array([0.4, -0.6, d3, 0.2])
        pin.forwardKinematics(model, data, q)
        mount = (data.oMi[model.parents[j]] * model.jointPlacements[j]).translation    # joint 3 on link 2
        pose = data.oMi[j] * quill.placement
        axis, half = pose.rotation[:, 2], quill.geometry.halfLength
        along = float(axis @ (mount - pose.translation))
        assert abs(along) <= half + 1e-9 and np.linalg.norm(mount - pose.translation - along * axis) < 1e-9
    assert not [o for o in geometry_of(planar_body()).geometryObjects if o.name.startswith("quill")]
