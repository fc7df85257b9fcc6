"""No crash, no silent wrong answer: invalid models, singular dynamics, limits, tolerances, threads.

Each test reproduces a defect of the earlier code (noted per test) and checks the answer against an
independent reference: a hand computation, the DH product (2.52), or the definition of the error raised.
"""

import sys
import threading

import numpy as np
import pinocchio as pin
import pytest

from rigid_body import kinematics as kin
from rigid_body import rotations as rot
from rigid_body.book_robots import book_robot_spec, planar_2r, planar_3r
from rigid_body.dh import DHLink, dh_chain, dh_transform, urdf_from_dh
from rigid_body.dynamics import forward_dynamics, inertia_matrix
from rigid_body.robots import _check_model_inertias, load, robot_from_dh, robot_from_urdf_string
from rigid_body.task_space import frame_state
from rigid_body.validation import as_matrix


# --------------------------------------------------------------------------------------------
# 3. A massless link keeps its inertia (was: <inertial> written only when mass > 0, so B₁₁ lost 0.35)
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("alpha, inertia", [(0.0, np.diag([0.1, 0.2, 0.35])),
                                            (-np.pi / 2, np.diag([0.1, 0.35, 0.2]))])  # Puma 560 link 1
def test_massless_link_keeps_its_moment_of_inertia(alpha, inertia):
    # Joint axis z0 in frame 1 is Rx(α)^T z0 = [0, −sin α, cos α]: I_zz for α = 0, I_yy for α = −π/2.
    bare = robot_from_dh([DHLink(a=0.4, alpha=alpha, com=(-0.2, 0.0, 0.0), inertia=inertia)])
    np.testing.assert_allclose(inertia_matrix(bare, [0.7]), [[0.35]], atol=1e-12)
    # with the book's rotor on joint 1 (carried by the base): + k_r² I_m = 10² · 0.01 = 1
    geared = robot_from_dh([DHLink(a=0.4, alpha=alpha, com=(-0.2, 0.0, 0.0), inertia=inertia,
                                   motor_inertia=0.01, motor_mass=2.0, gear_ratio=10.0)])
    np.testing.assert_allclose(inertia_matrix(geared, [0.7]), [[0.35 + 1.0]], atol=1e-12)


def test_link_without_mass_or_inertia_writes_no_inertial():
    xml = urdf_from_dh([DHLink(a=1.0), DHLink(a=1.0, mass=1.0, inertia=np.eye(3) * 0.1)])
    assert xml.count("<inertial>") == 1


# --------------------------------------------------------------------------------------------
# 4. Invalid inertial data is refused (was: mass −1 → B ≈ −1e62; mass="nan" → the link silently massless)
# --------------------------------------------------------------------------------------------

XML = book_robot_spec("planar_2r").urdf()


@pytest.mark.parametrize("old, new, field", [
    ('<mass value="50.0"/>', '<mass value="-1"/>', "mass"),
    ('<mass value="50.0"/>', '<mass value="nan"/>', "mass"),
    ('<mass value="50.0"/>', '<mass value="heavy"/>', "mass"),
    ('ixx="0.0"', 'ixx="nan"', "ixx"),
    ('iyy="10.0"', 'iyy="-10.0"', "inertia"),
    ('ixy="0.0"', 'ixy="100.0"', "inertia"),  # not positive semi-definite
])
def test_urdf_with_invalid_inertial_is_refused_naming_link_and_field(old, new, field, tmp_path):
    bad = XML.replace(old, new, 1)
    assert bad != XML
    with pytest.raises(ValueError, match=rf"'frame_1'.*`{field}`"):
        robot_from_urdf_string(bad)
    path = tmp_path / "bad.urdf"
    path.write_text(bad)
    with pytest.raises(ValueError, match="frame_1"):
        load(path)


def test_model_inertias_are_checked_after_parsing():
    model = load("planar_2r").model.copy()
    total = sum(float(body.mass) for body in model.inertias)
    _check_model_inertias(model, total)  # the book's arm passes
    with pytest.raises(ValueError, match="dropped"):  # one declared inertial missing from the model
        _check_model_inertias(model, total + 50.0)
    model.inertias[1] = pin.Inertia(-1.0, np.zeros(3), np.eye(3))
    with pytest.raises(ValueError, match="`mass`"):
        _check_model_inertias(model, total)


@pytest.mark.parametrize("kwargs, field", [
    (dict(com=(np.nan, 0.0, 0.0)), "com"),
    (dict(com=(0.0, 0.0)), "com"),
    (dict(mass=1.0, inertia=np.full((3, 3), np.nan)), "inertia"),
    (dict(mass=1.0, inertia=-np.eye(3)), "inertia"),
    (dict(mass=1.0, inertia=[[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]), "inertia"),
    (dict(motor_inertia=-1.0), "motor_inertia"),
    (dict(motor_inertia=-np.eye(3)), "motor_inertia"),
    (dict(motor_inertia=np.nan), "motor_inertia"),
    (dict(lower=1.0, upper=0.0), "lower"),
    (dict(lower=np.nan), "lower"),
    (dict(mass=-1.0), "mass"),
    (dict(a="x"), "a"),
    (dict(effort=0.0), "effort"),
    (dict(name=3), "name"),
])
def test_dh_link_refuses_invalid_data_naming_the_field(kwargs, field):
    with pytest.raises(ValueError, match=f"`{field}`"):
        DHLink(**kwargs)
    with pytest.raises(ValueError, match=rf"DH link 2.*`{field}`"):  # in a table: the link's row too
        robot_from_dh([dict(a=1.0), {"a": 1.0, **kwargs}])


@pytest.mark.parametrize("tool", [2 * np.eye(4), np.diag([1.0, 1.0, -1.0, 1.0]), np.full((4, 4), np.nan),
                                  np.eye(3)])
def test_tool_must_be_a_rigid_transform(tool):
    with pytest.raises(ValueError, match="`tool"):
        robot_from_dh([DHLink(a=1.0)], tool=tool)


# --------------------------------------------------------------------------------------------
# 5. One Robot, several threads (was: shared robot.data, a thread read the other thread's pose)
# --------------------------------------------------------------------------------------------

def test_robot_used_from_two_threads_gives_each_its_own_pose():
    robot = load("planar_3r")
    links = book_robot_spec("planar_3r").links
    qs = [np.array([0.3, -0.4, 0.5]), np.array([-0.9, 1.2, -0.3])]
    expected = [dh_chain(links, q)[-1] for q in qs]  # independent of Pinocchio: the DH product (2.52)
    errors: list[str] = []

    def hammer(k: int) -> None:
        for _ in range(1500):
            T = kin.direct_kinematics(robot, qs[k])
            S = frame_state(robot, qs[k])
            if not (np.allclose(T, expected[k], atol=1e-12) and np.allclose(S.T, expected[k], atol=1e-12)):
                errors.append(f"thread {k} got another pose")
                return

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)  # switch threads between the Pinocchio calls of one function
    try:
        threads = [threading.Thread(target=hammer, args=(k,)) for k in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    finally:
        sys.setswitchinterval(interval)
    assert not errors, errors
    assert robot.data is robot.data  # one Data per thread, the same on every access


def test_each_thread_has_its_own_data():
    robot = load("planar_2r")
    seen = []
    t = threading.Thread(target=lambda: seen.append(robot.data))
    t.start()
    t.join()
    assert seen[0] is not robot.data and isinstance(seen[0], pin.Data)


# --------------------------------------------------------------------------------------------
# 6. Singular B(q): the same error with and without rotors (was: NaN from ABA, an error from Cholesky)
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("rotor", [False, True])
def test_forward_dynamics_refuses_a_singular_inertia_matrix(rotor):
    motor = dict(motor_mass=1.0, gear_ratio=0.0) if rotor else {}  # a rotor that does not turn: B₁₁ = 0
    robot = robot_from_dh([DHLink(a=1.0, **motor)])
    assert robot.has_mimic == rotor
    with pytest.raises(ValueError, match="B\\(q\\) is singular"):
        forward_dynamics(robot, [0.0], [0.0], [1.0])


def test_forward_dynamics_unchecked_nan_input_is_named():
    robot = robot_from_dh([DHLink(a=1.0, mass=1.0, inertia=np.eye(3))])
    with pytest.raises(ValueError, match="`q` must be finite"):
        forward_dynamics(robot, np.array([np.nan]), np.zeros(1), np.zeros(1), check=False)


# --------------------------------------------------------------------------------------------
# 7. Closed-form IK keeps to the joint limits (was: θ1 = ±2.62 for a ±60° joint)
# --------------------------------------------------------------------------------------------

def test_planar_3r_ik_outside_the_limits_is_unreachable():
    with pytest.raises(ValueError, match="joint limits"):
        kin.inverse_kinematics_planar_3r([-0.8, 0.0, np.pi])  # both rows have θ1 = ±2.62 > π/3


def test_planar_3r_ik_drops_the_row_outside_the_limits():
    x = [0.55, 0.15, -np.pi / 2]
    free = kin.inverse_kinematics_planar_3r(x, lower=(None,) * 3, upper=(None,) * 3)
    links = planar_3r().links
    lo, hi = np.array([l.lower for l in links]), np.array([l.upper for l in links])
    inside = [bool(np.all((q >= lo) & (q <= hi))) for q in free]
    assert inside.count(True) == 1  # one of the two is beyond a limit
    qs = kin.inverse_kinematics_planar_3r(x)
    np.testing.assert_allclose(qs, free[inside.index(True)][None], atol=1e-12)
    T = dh_chain(links, qs[0])[-1]
    np.testing.assert_allclose([T[0, 3], T[1, 3], np.arctan2(T[1, 0], T[0, 0])], x, atol=1e-12)


def test_ik_shifts_a_revolute_angle_by_2pi_into_its_range():
    # joint 1 limited to [0, 2π): the wrapped solution θ1 < 0 is returned as θ1 + 2π
    links = [DHLink(a=1.0, lower=0.0, upper=2 * np.pi - 1e-6), DHLink(a=1.0)]
    free = kin.inverse_kinematics_planar_2r([1.0, -1.0], links=[DHLink(a=1.0), DHLink(a=1.0)])
    qs = kin.inverse_kinematics_planar_2r([1.0, -1.0], links=links)
    assert np.all(qs[:, 0] >= 0.0)
    np.testing.assert_allclose(np.mod(qs[:, 0], 2 * np.pi), np.mod(free[:, 0], 2 * np.pi), atol=1e-12)
    for q in qs:
        np.testing.assert_allclose(dh_chain(links, q)[-1][:2, 3], [1.0, -1.0], atol=1e-12)


def test_anthropomorphic_ik_respects_a_shoulder_limit():
    links = [dict(alpha=np.pi / 2, lower=-0.2, upper=0.2), dict(a=0.5), dict(a=0.4)]
    p = [0.5, 0.05, 0.3]  # θ1 = atan2(0.05, 0.5) = 0.0997 (shoulder right) or 0.0997 − π (left)
    qs = kin.inverse_kinematics_anthropomorphic(p, links=links)
    assert len(qs) == 2 and np.all(np.abs(qs[:, 0]) <= 0.2)  # the shoulder-left rows are dropped
    for q in qs:
        np.testing.assert_allclose(dh_chain(links, q)[-1][:3, 3], p, atol=1e-12)
    with pytest.raises(ValueError, match="joint limits"):
        kin.inverse_kinematics_anthropomorphic([0.3, 0.3, 0.3], links=links)  # θ1 = π/4 or −3π/4


# --------------------------------------------------------------------------------------------
# 10. Tolerances are bounded (was: tol=10 gave Euler angles off by 0.48 and accepted 2·I as a rotation)
# --------------------------------------------------------------------------------------------

R0 = rot.rot_y(0.5) @ rot.rot_z(0.3)
TOL_CALLS = {
    "as_rotation": lambda tol: rot.as_rotation(R0, tol=tol),
    "as_homogeneous": lambda tol: rot.as_homogeneous(np.eye(4), tol=tol),
    "as_unit_quaternion": lambda tol: rot.as_unit_quaternion([1.0, 0.0, 0.0, 0.0], tol=tol),
    "rotation_to_euler_zyz": lambda tol: rot.rotation_to_euler_zyz(R0, tol=tol),
    "rotation_to_euler_zxz": lambda tol: rot.rotation_to_euler_zxz(R0, tol=tol),
    "rotation_to_rpy": lambda tol: rot.rotation_to_rpy(R0, tol=tol),
}


@pytest.mark.parametrize("name", sorted(TOL_CALLS))
@pytest.mark.parametrize("tol", [10.0, 2e-3, 0.0, -1e-9, np.nan, "x"])
def test_tolerance_out_of_range_is_refused(name, tol):
    with pytest.raises(ValueError, match="`tol`"):
        TOL_CALLS[name](tol)


@pytest.mark.parametrize("name", sorted(TOL_CALLS))
def test_tolerance_in_range_is_accepted(name):
    TOL_CALLS[name](1e-3)
    TOL_CALLS[name](1e-12)


def test_euler_angles_with_the_largest_tolerance_reproduce_r():
    phi = rot.rotation_to_euler_zyz(R0, tol=1e-3)
    assert not phi.singular
    np.testing.assert_allclose(rot.euler_zyz_to_rotation(phi.angles), R0, atol=1e-12)


# --------------------------------------------------------------------------------------------
# 15. Messages name the argument (was: NaN transforms, numpy's own messages, "unreachable" for a NaN)
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("k, name", enumerate(["a", "alpha", "d", "theta"]))
@pytest.mark.parametrize("value", [np.nan, np.inf, "x"])
def test_dh_transform_refuses_non_finite_parameters(k, name, value):
    args = [0.1, 0.2, 0.3, 0.4]
    args[k] = value
    with pytest.raises(ValueError, match=f"`{name}`"):
        dh_transform(*args)


def test_dh_chain_refuses_nan_q():
    with pytest.raises(ValueError, match="`q` must be finite"):
        dh_chain([DHLink(a=1.0)], [np.nan])


def test_messages_name_the_argument():
    with pytest.raises(ValueError, match="`M` must be a numeric array"):
        as_matrix("x", (3, 3), "M")
    with pytest.raises(ValueError, match="`theta1` must be finite"):
        kin.inverse_kinematics_anthropomorphic([0.0, 0.0, 0.3], theta1=np.nan)
    with pytest.raises(ValueError, match="`theta2` must be finite"):
        kin.inverse_kinematics_anthropomorphic([0.3, 0.0, 0.3], theta2=np.nan)
    robot = load("planar_2r")
    for n in (-1, 0, 1, 2.5, "3"):
        with pytest.raises(ValueError, match="`n`"):
            kin.joint_arc(robot, [0.0, 0.0], 0, 1.0, n=n)
    for joint in (-1, 2, 0.5):
        with pytest.raises(ValueError, match="`joint`"):
            kin.joint_arc(robot, [0.0, 0.0], joint, 1.0)
    with pytest.raises(ValueError, match="`n`"):
        kin.workspace_points(robot, 0, np.random.default_rng(0))
    with pytest.raises(ValueError, match="`n`"):
        kin.workspace_points(robot, 2.5, np.random.default_rng(0))


@pytest.mark.parametrize("tol", [10.0, 0.0, -1e-9, np.nan])
def test_rank_and_distinct_solution_tolerances_are_bounded(tol):
    from rigid_body.manipulability import is_singular, jacobian_rank

    J = np.array([[1.0, 0.0], [0.0, 1e-6]])
    with pytest.raises(ValueError, match="`tol`"):
        jacobian_rank(J, tol)  # tol = 10 called every Jacobian rank 0, a negative tol full rank
    with pytest.raises(ValueError, match="`tol`"):
        is_singular(J, tol)
    with pytest.raises(ValueError, match="`atol`"):
        kin.distinct_solutions(np.zeros((2, 2)), atol=tol)
    assert jacobian_rank(J, 1e-9) == 2 and jacobian_rank(J, 1e-5) == 1  # σ = (1, 1e-6)


def test_a_deep_copy_has_its_own_model_and_data():
    import copy

    robot = load("planar_2r")
    twin = copy.deepcopy(robot)
    assert twin.model is not robot.model and twin.data is not robot.data
    q = np.array([0.4, -0.2])
    np.testing.assert_allclose(kin.direct_kinematics(twin, q), dh_chain(planar_2r().links, q)[-1], atol=1e-12)
