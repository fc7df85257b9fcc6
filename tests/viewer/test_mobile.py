"""Mobile robots and planar scenes in the viewer (Ch. 11–12): the generated q = (x, y, θ) body against
closed forms and scipy's rotations, the planar obstacles as solids, and the reports' exports of 11.16
and 12.8 read back from the HTML file (offline, the body moving along the simulated/planned motion)."""

from __future__ import annotations

import base64
import re

import numpy as np
import pinocchio as pin
import pytest
import umsgpack
from scipy.spatial.transform import Rotation

from planners.configuration_space import Disc, Polygon
from problems.registry import solve
from viewer import Scene, animate, geometry_of, planar_body, plane_camera, report_animations

from tests.viewer.test_scene import _commands, _transform


def test_the_chassis_is_placed_at_the_posture(rng):
    """Chassis centre = (x + d cos θ, y + d sin θ, H/2), orientation Rot_z(θ) (scipy), for offset d."""
    L, W, H, d = 0.6, 0.4, 0.1, 0.2
    robot = planar_body(L, W, H, offset=d)
    geom = geometry_of(robot)
    chassis = [k for k, g in enumerate(geom.geometryObjects) if g.geometry.halfSide[0] == pytest.approx(L / 2)]
    assert len(chassis) == 1 and np.allclose(2 * geom.geometryObjects[chassis[0]].geometry.halfSide, [L, W, H])
    gdata = geom.createData()
    for _ in range(5):
        x, y, th = rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-10, 10)
        pin.forwardKinematics(robot.model, robot.data, np.array([x, y, th]))
        pin.updateGeometryPlacements(robot.model, robot.data, geom, gdata)
        M = gdata.oMg[chassis[0]]
        assert np.allclose(M.translation, [x + d * np.cos(th), y + d * np.sin(th), H / 2], atol=1e-12)
        assert np.allclose(M.rotation, Rotation.from_euler("z", th).as_matrix(), atol=1e-12)


def test_planar_body_rejects_bad_data_naming_the_argument():
    with pytest.raises(ValueError, match="bounds"):
        planar_body(bounds=(1.0, -1.0, 0.0, 1.0))
    with pytest.raises(ValueError, match="offset"):
        planar_body(0.4, offset=0.3)
    with pytest.raises(ValueError, match="width"):
        planar_body(0.4, -0.1)
    with pytest.raises(ValueError, match="points"):
        plane_camera(np.full((3, 2), np.nan))


def test_the_prism_is_a_closed_outward_solid_of_volume_area_times_height():
    """Divergence theorem on the triangles: V = Σ (a · (b × c)) / 6 = area × height for a closed mesh
    oriented outward; every face's normal points away from the prism's centre."""
    V = np.array([[0.0, 0.0], [2.0, 0.0], [2.5, 1.0], [1.0, 2.0], [-0.5, 1.0]])  # convex, counter-clockwise
    area = 0.5 * np.sum(V[:, 0] * np.roll(V[:, 1], -1) - np.roll(V[:, 0], -1) * V[:, 1])
    scene = Scene()
    scene.prism("p", V, 0.3)
    obj = [c for c in _commands(scene) if c["type"] == "set_object" and c["path"].endswith("overlays/p")][-1]
    geometry = obj["object"]["geometries"][0]["data"]
    # meshcat's typed arrays: msgpack extensions 0x17 (Float32Array) and 0x16 (Uint32Array)
    P = np.frombuffer(geometry["attributes"]["position"]["array"].data, np.float32).astype(float).reshape(-1, 3)
    F = np.frombuffer(geometry["index"]["array"].data, np.uint32).reshape(-1, 3)
    a, b, c = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    assert np.sum(np.einsum("ij,ij->i", a, np.cross(b, c))) / 6 == pytest.approx(area * 0.3, rel=1e-6)
    normals, centres = np.cross(b - a, c - a), (a + b + c) / 3 - P.mean(axis=0)
    assert np.all(np.einsum("ij,ij->i", normals, centres) > 0)


def test_planar_shapes_draws_discs_as_cylinders_and_polygons_as_prisms():
    scene = Scene()
    scene.planar_shapes("obstacles", [Disc([1.0, -2.0], 0.3), Polygon([[0, 0], [1, 0], [1, 1], [0, 1]])], 0.2)
    T = _transform(scene, "/meshcat/overlays/obstacles/0")
    assert np.allclose(T[:3, 3], [1.0, -2.0, 0.0]) and np.allclose(T[:3, 1], [0.0, 0.0, 1.0])  # three.js: y = axis
    kinds = {c["path"]: c["object"]["geometries"][0]["type"] for c in _commands(scene) if c["type"] == "set_object"}
    assert kinds["/meshcat/overlays/obstacles/0"] == "CylinderGeometry"
    assert kinds["/meshcat/overlays/obstacles/1"] == "BufferGeometry"
    with pytest.raises(ValueError, match=r"shapes\[0\]"):
        scene.planar_shapes("bad", [np.zeros(2)])


def test_an_explicit_camera_shifts_the_scene_to_bring_its_target_to_the_viewers_origin():
    """meshcat's orbit controls look at the viewer's origin: the world moves by −target, the camera sits
    at position − target (in meshcat's camera frame (x, z, −y))."""
    robot = planar_body()
    t = np.linspace(0.0, 1.0, 11)
    position, target = np.array([1.0, 2.0, 5.0]), np.array([1.0, 2.5, 0.0])
    scene = animate(robot, (t, np.c_[t, 2 * t, t]), camera=(position, target))
    assert np.allclose(_transform(scene, "/meshcat")[:3, 3], -target)
    prop = [c for c in _commands(scene) if c["type"] == "set_property" and c["path"].endswith("rotated/<object>")]
    assert np.allclose(prop[-1]["value"], [0.0, 5.0, 0.5])


def _exported_animation(path) -> dict[str, dict]:
    """The page's own commands, decoded from the HTML file: the animation clips by node path."""
    page = path.read_text()
    assert not re.search(r'<(script|link|img|iframe)[^>]+(src|href)="(?!data:)', page)  # offline: nothing fetched
    commands = [umsgpack.unpackb(base64.b64decode(c)) for c in re.findall(r'^"([A-Za-z0-9+/=]+)",?$', page, re.M)]
    animation = [c for c in commands if c["type"] == "set_animation"]
    assert len(animation) == 1
    return {a["path"]: {t["name"]: t["keys"] for t in a["clip"]["tracks"]} for a in animation[0]["animations"]}


@pytest.mark.parametrize("problem_id, q_s, offset, goal, goal_tol", [
    ("11.16", [-1.0, -2.0, -np.pi / 2], 0.0, [0.0, 0.0], 1e-3),   # regulated to the origin (‖p(10 s)‖ < 1e-3)
    ("12.8", [-3.0, 0.0, 0.0], 0.2, [3.0, -3.5], 0.5),            # the RRT path ends within 0.5 of q_g
])
def test_the_reports_export_moves_the_robot_along_the_problems_motion(tmp_path, capsys, problem_id, q_s, offset,
                                                                       goal, goal_tol):
    """The export written for the report, read back from its HTML file: offline, the chassis' keyframes
    start at q_s (centre `offset` ahead along θ_s), end near the goal, ~25 frames per second."""
    sol = solve(problem_id)
    assert len(sol.animations) == 1
    snippets = report_animations(sol, tmp_path)
    path = tmp_path / "animations" / f"{problem_id}_1.html"
    assert len(snippets) == 1 and path.is_file()
    size = path.stat().st_size
    assert size < 2_000_000, f"export of {size} bytes"
    keys = _exported_animation(path)["/meshcat/robot/visuals/body_0"][".position"]
    p = np.array([k["value"] for k in keys])[:, :2]
    assert len(np.unique(np.round(p, 9), axis=0)) >= 2  # it moves
    x, y, th = q_s
    assert np.allclose(p[0], [x + offset * np.cos(th), y + offset * np.sin(th)], atol=1e-9)
    assert np.linalg.norm(p[-1] - goal) < goal_tol + offset
    duration = keys[-1]["time"] / 25.0
    assert 25 * duration <= len(keys) <= 25 * duration + 1
    with capsys.disabled():
        print(f"\n[viewer] {problem_id}: export {size} bytes, {len(keys)} keyframes over {duration:.2f} s")


def test_the_book_2r_arm_drawn_for_12_7_is_the_planners_planar_arm(rng):
    """12.7 plans for ``PlanarArm((1, 1))`` and animates ``load("planar_2r")``: the same chain (joint
    and tip positions of the planner's kinematics = the URDF model's frames, Pinocchio)."""
    from planners.configuration_space import PlanarArm
    from controllers.scenes import scene_12_7
    from rigid_body.robots import load

    space, _, _ = scene_12_7()
    assert isinstance(space.robot, PlanarArm) and space.robot.fixed_base and tuple(space.robot.base) == (0.0, 0.0)
    robot = load("planar_2r")
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, 2)
        pin.framesForwardKinematics(robot.model, robot.data, q)
        joints = space.robot.joint_positions(q)
        assert np.allclose(robot.data.oMf[robot.ee_frame].translation, [*joints[-1], 0.0], atol=1e-12)
        assert np.allclose(robot.data.oMi[2].translation, [*joints[1], 0.0], atol=1e-12)
