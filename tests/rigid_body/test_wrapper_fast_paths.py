"""The fast paths of the dynamics/kinematics wrappers: still validated, results never views of robot.data."""

import re
import threading

import numpy as np
import pytest

from rigid_body import dynamics as dyn
from rigid_body import kinematics as kin
from rigid_body.robots import load
from rigid_body.validation import as_vector

ROBOT = load("panda")
RNG = np.random.default_rng(7)
Q1, Q2 = ROBOT.random_configuration(RNG), ROBOT.random_configuration(RNG)
V = RNG.normal(size=(3, ROBOT.nv))

CALLS = {
    "inertia_matrix": lambda q: dyn.inertia_matrix(ROBOT, q),
    "gravity_torques": lambda q: dyn.gravity_torques(ROBOT, q),
    "nonlinear_effects": lambda q: dyn.nonlinear_effects(ROBOT, q, V[0]),
    "inverse_dynamics": lambda q: dyn.inverse_dynamics(ROBOT, q, V[0], V[1]),
    "forward_dynamics": lambda q: dyn.forward_dynamics(ROBOT, q, V[0], V[2]),
    "coriolis_matrix": lambda q: dyn.coriolis_matrix(ROBOT, q, V[0]),
    "direct_kinematics": lambda q: kin.direct_kinematics(ROBOT, q),
    "geometric_jacobian": lambda q: kin.geometric_jacobian(ROBOT, q),
    "frame_poses": lambda q: kin.frame_poses(ROBOT, q, [ROBOT.ee_frame, 0])[0],
}


@pytest.mark.parametrize("name", CALLS)
def test_result_is_not_a_view_of_robot_data(name):
    """A result survives the next call at another posture, and shares no memory with any data buffer."""
    first = CALLS[name](Q1)
    kept = first.copy()
    CALLS[name](Q2)
    np.testing.assert_array_equal(first, kept)
    data = ROBOT.data
    buffers = [data.M, data.g, data.nle, data.tau, data.ddq, data.J, data.C] + [m.homogeneous for m in data.oMf]
    assert not any(np.shares_memory(first, b) for b in buffers)


def test_crba_fills_both_triangles():
    """Pinocchio 4's crba returns the symmetric B(q) (inertia_matrix makes no symmetrisation of its own),
    with and without the book's mimic rotors; B agrees with RNEA column by column (B e_j = τ(q, 0, e_j) − g)."""
    for robot in (ROBOT, load("planar_2r"), load("puma560")):
        q = robot.random_configuration(RNG)
        B = dyn.inertia_matrix(robot, q)
        np.testing.assert_array_equal(B, B.T)
        g = dyn.gravity_torques(robot, q)
        columns = [dyn.inverse_dynamics(robot, q, np.zeros(robot.nv), e) - g for e in np.eye(robot.nv)]
        np.testing.assert_allclose(B, np.array(columns).T, atol=1e-12)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
@pytest.mark.parametrize("where", range(3))
def test_non_finite_entries_are_rejected_by_name(bad, where):
    args = [Q1.copy(), V[0].copy(), V[1].copy()]
    args[where][3] = bad
    with pytest.raises(ValueError, match=f"`{('q', 'qd', 'qdd')[where]}` must be finite"):
        dyn.inverse_dynamics(ROBOT, *args)


def test_wrong_shapes_types_and_frames_are_rejected_by_name():
    with pytest.raises(ValueError, match=r"`q` must have shape \(7,\), got \(6,\)"):
        dyn.inertia_matrix(ROBOT, Q1[:6])
    with pytest.raises(ValueError, match=r"`q` must have shape \(7,\), got \(7, 1\)"):
        dyn.gravity_torques(ROBOT, Q1[:, None])
    with pytest.raises(ValueError, match="`tau` must have shape"):
        dyn.forward_dynamics(ROBOT, Q1, V[0], V[1][:3])
    with pytest.raises(ValueError, match="`q` must be a numeric vector"):
        kin.geometric_jacobian(ROBOT, ["a"] * 7)
    with pytest.raises(ValueError, match="out of range"):
        kin.direct_kinematics(ROBOT, Q1, frame=ROBOT.model.nframes)
    with pytest.raises(ValueError, match="no frame"):
        kin.geometric_jacobian(ROBOT, Q1, frame="no_such_frame")


def test_other_inputs_still_convert():
    """Lists, integers, float32 and strided views take the full path and give the same result."""
    q32 = Q1.astype(np.float32)
    np.testing.assert_allclose(dyn.gravity_torques(ROBOT, list(q32)), dyn.gravity_torques(ROBOT, q32.astype(float)))
    np.testing.assert_array_equal(dyn.gravity_torques(ROBOT, np.zeros(7, dtype=int)), dyn.gravity_torques(ROBOT, np.zeros(7)))
    strided = np.repeat(Q1, 2)[::2]
    np.testing.assert_array_equal(kin.direct_kinematics(ROBOT, strided), kin.direct_kinematics(ROBOT, Q1))


def test_as_vector_fast_path_and_overflow():
    x = np.array([1.0, 2.0])
    assert as_vector(x, 2, "x") is x
    huge = np.full(3, 1e308)  # its sum overflows: the full checks accept it (finite entries)
    assert as_vector(huge, 3, "x") is huge
    long = np.ones(100)
    long[50] = np.nan
    with pytest.raises(ValueError, match="`x` must be finite"):
        as_vector(long, 100, "x")


# The fast path (rigid_body/dynamics.py's docstring): one tolist+sum per vector, Pinocchio's own size checks.
# Every entry of every argument, every wrapper, robots with and without mimic rotors and with a prismatic joint.
ARGUMENTS = {  # wrapper: (its callable on a robot, the names of its vector arguments)
    "inertia_matrix": (dyn.inertia_matrix, ("q",)),
    "gravity_torques": (dyn.gravity_torques, ("q",)),
    "nonlinear_effects": (dyn.nonlinear_effects, ("q", "qd")),
    "inverse_dynamics": (dyn.inverse_dynamics, ("q", "qd", "qdd")),
    "forward_dynamics": (dyn.forward_dynamics, ("q", "qd", "tau")),
    "direct_kinematics": (kin.direct_kinematics, ("q",)),
    "geometric_jacobian": (kin.geometric_jacobian, ("q",)),
}
FAST_ROBOTS = {name: load(name) for name in ("panda", "planar_2r", "scara")}  # 7R; 2R with rotors; RRPR


def _arguments(robot, names):
    rng = np.random.default_rng(3)
    return [robot.random_configuration(rng) if n == "q" else rng.normal(size=robot.nv) for n in names]


@pytest.mark.parametrize("robot_name", FAST_ROBOTS)
@pytest.mark.parametrize("name", ARGUMENTS)
def test_every_non_finite_entry_of_every_argument_is_named(name, robot_name):
    robot, (f, names) = FAST_ROBOTS[robot_name], ARGUMENTS[name]
    good = _arguments(robot, names)
    for k, arg in enumerate(names):
        for i in range(len(good[k])):
            for bad in (np.nan, np.inf, -np.inf):
                args = [a.copy() for a in good]
                args[k][i] = bad
                with pytest.raises(ValueError, match=f"`{arg}` must be finite"):
                    f(robot, *args)


@pytest.mark.parametrize("name", ARGUMENTS)
def test_a_column_or_a_wrong_size_is_refused_by_name_though_pinocchio_takes_a_column(name):
    """Pinocchio accepts an (n, 1) column for an (n,) vector; the wrappers keep to shape (n,)."""
    robot, (f, names) = ROBOT, ARGUMENTS[name]
    good = _arguments(robot, names)
    for k, arg in enumerate(names):
        for wrong in (good[k][:, None], good[k][:-1], np.r_[good[k], 0.0]):
            args = list(good)
            args[k] = wrong
            with pytest.raises(ValueError, match=re.escape(f"`{arg}` must have shape ({len(good[k])},), got {wrong.shape}")):
                f(robot, *args)


def test_mimic_forward_dynamics_refuses_a_short_tau_that_would_broadcast():
    """With rotors, q̈ is the Cholesky solve of B q̈ = τ − h: a (1,) τ would broadcast against h."""
    arm = load("planar_2r")
    for check in (True, False):
        with pytest.raises(ValueError, match=r"`tau` must have shape \(2,\), got \(1,\)"):
            dyn.forward_dynamics(arm, np.zeros(2), np.zeros(2), np.ones(1), check=check)


def test_a_sum_that_overflows_is_not_mistaken_for_a_non_finite_entry():
    """Finite entries whose sum overflows to inf take the full checks, which accept them: no ValueError,
    and B(q) is the finite, symmetric positive definite matrix its docstring promises."""
    q = np.full(ROBOT.nq, 1e308)
    assert not np.isfinite(sum(q.tolist()))  # the fast path's check does overflow here
    B = dyn.inertia_matrix(ROBOT, q)
    assert B.shape == (ROBOT.nv, ROBOT.nv) and np.all(np.isfinite(B))
    np.testing.assert_allclose(B, B.T, atol=1e-12)
    assert np.linalg.eigvalsh(B).min() > 0.0
    np.testing.assert_array_equal(kin.direct_kinematics(ROBOT, q),
                                  kin.direct_kinematics(ROBOT, [float(v) for v in q]))


def test_the_first_call_in_a_new_thread_gets_its_own_data():
    """The fast path reads the thread's data directly; a thread's first call creates it (the full path)."""
    expected = {name: f(ROBOT, *_arguments(ROBOT, names)) for name, (f, names) in ARGUMENTS.items()}
    results, seen = {}, []

    def work():
        for name, (f, names) in ARGUMENTS.items():
            results[name] = f(ROBOT, *_arguments(ROBOT, names))
        seen.append(ROBOT.data)

    thread = threading.Thread(target=work)
    thread.start()
    thread.join()
    assert seen[0] is not ROBOT.data
    for name in ARGUMENTS:
        np.testing.assert_array_equal(results[name], expected[name])
