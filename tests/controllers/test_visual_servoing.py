"""Visual-servoing blocks: Γ and J_Ad against finite differences, the estimator, the laws' degraded modes
and their input checks."""

import numpy as np
import pytest

from controllers.plants import ArmMeasurement
from controllers.simulation import Augmented
from controllers.visual_servoing import (SCARA_DOFS, CameraImage, EyeInHandCamera, IBVSResolvedVelocity,
                                         PBVSResolvedVelocity, PoseEstimator, TargetFeatures, gamma_matrix,
                                         hybrid_error_jacobians, planar_pose, planar_pose_vector,
                                         relative_pose_vector)
from controllers.scenes import SCARA_DESIRED_POSE as X_DO, SCARA_Q0 as Q0, SCARA_TARGET_POINTS as P_O, \
    SCARA_TARGET_POSE as X_O, scara_eye_in_hand, scara_target_points

TARGET = TargetFeatures(P_O, kind="segment")


def _x_co(robot, q):
    return relative_pose_vector(EyeInHandCamera(robot, scara_target_points()).pose(q), planar_pose(X_O))


def test_planar_pose_round_trip(rng):
    for _ in range(5):
        x = np.r_[rng.normal(size=3), rng.uniform(-np.pi, np.pi)]
        np.testing.assert_allclose(planar_pose_vector(planar_pose(x)), x, atol=1e-12)


def test_pbvs_jacobian_is_the_derivative_of_the_relative_pose(rng):
    """J_Ad = Γ(o) [R_cᵀ J_P; ω_z] = ∂x_{c,o}/∂q (central differences on the SCARA)."""
    robot = scara_eye_in_hand()
    law = PBVSResolvedVelocity(robot, X_DO, np.ones(4))
    for _ in range(5):
        q = Q0 + 0.2 * rng.normal(size=4)
        J = law.pbvs_jacobian(q, _x_co(robot, q))
        fd = np.column_stack([(_x_co(robot, q + 1e-6 * e) - _x_co(robot, q - 1e-6 * e)) / 2e-6 for e in np.eye(4)])
        np.testing.assert_allclose(J, fd, atol=1e-7)


def test_gamma_maps_the_camera_twist_to_the_relative_pose_rate(rng):
    o = rng.normal(size=3)
    v, wz = rng.normal(size=3), rng.normal()
    # a fixed object seen from a camera moving with (v, ω_z e_z): ȯ = −v − ω_z e_z × o, φ̇ = −ω_z
    expected = np.r_[-v - np.cross([0, 0, wz], o), -wz]
    np.testing.assert_allclose(gamma_matrix(o) @ np.r_[v, wz], expected, atol=1e-12)


def test_estimator_converges_and_holds_when_the_segment_is_lost():
    s = TARGET.features(TARGET.view_from_pose(planar_pose(X_DO)).xy)
    est = PoseEstimator(TARGET, [0, 0, 0.5, 0], 160.0, 1e-3)
    for _ in range(200):
        est.update(s)
    np.testing.assert_allclose(est.x_hat, X_DO, atol=1e-8)
    lost = CameraImage(xy=np.full((2, 2), np.nan), visible=np.array([False, True]), z=np.ones(2))
    out = est(0.0, Augmented(ArmMeasurement(Q0, np.zeros(4)), image=lost))
    np.testing.assert_allclose(out, est.x_hat)
    assert np.all(np.isnan(est.log()["e_s"]))


def test_estimator_input_checks():
    with pytest.raises(ValueError, match="4 features"):
        PoseEstimator(TargetFeatures(np.zeros((3, 3)) + [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "points"), X_DO, 1.0, 1e-3)
    with pytest.raises(ValueError, match="x0"):
        PoseEstimator(TARGET, [0, 0, 0.5], 1.0, 1e-3)
    with pytest.raises(ValueError, match="T"):
        PoseEstimator(TARGET, X_DO, 1.0, 0.0)
    est = PoseEstimator(TARGET, [0, 0, -0.5, 0], 1.0, 1e-3)
    with pytest.raises(ValueError, match="behind the camera"):
        est.update(np.zeros(4))


def test_ibvs_degrades_without_crashing_when_points_are_lost():
    robot = scara_eye_in_hand()
    s_d = TARGET.features(TARGET.view_from_pose(planar_pose(X_DO)).xy)
    points = TargetFeatures(P_O, "points")
    law = IBVSResolvedVelocity(robot, points, points.features(points.view_from_pose(planar_pose(X_DO)).xy), 1.0,
                               depth=0.6)
    camera = EyeInHandCamera(robot, scara_target_points(), lost={0: (0.0, 1.0)})
    meas = ArmMeasurement(Q0, None)
    u = law(0.5, Augmented(meas, image=camera(0.5, meas)))
    assert u.shape == (4,) and np.all(np.isfinite(u))
    assert np.all(np.isnan(law.log()["e_s"][:2])) and np.all(np.isfinite(law.log()["e_s"][2:]))
    seg = IBVSResolvedVelocity(robot, TARGET, s_d, 1.0, depth=0.6)
    np.testing.assert_array_equal(seg(0.5, Augmented(meas, image=camera(0.5, meas))), np.zeros(4))


def test_camera_and_laws_check_their_inputs():
    robot = scara_eye_in_hand()
    with pytest.raises(ValueError, match="rng"):
        EyeInHandCamera(robot, scara_target_points(), noise=0.01)
    with pytest.raises(ValueError, match="points_b"):
        EyeInHandCamera(robot, np.zeros(3))
    with pytest.raises(ValueError, match="kind"):
        TargetFeatures(P_O, kind="circle")
    with pytest.raises(ValueError, match="s_d"):
        IBVSResolvedVelocity(robot, TARGET, np.zeros(3), 1.0)
    with pytest.raises(ValueError, match="depth"):
        IBVSResolvedVelocity(robot, TARGET, np.zeros(4), 1.0, depth=-1.0)
    with pytest.raises(ValueError, match="no frame"):
        EyeInHandCamera(robot, scara_target_points(), frame="camera_link")


def test_hybrid_jacobians_need_positive_depth():
    J_p, J_o = hybrid_error_jacobians(0.1, -0.2, 0.5)
    assert J_p.shape == J_o.shape == (3, 3)
    with pytest.raises(ValueError, match="z_c"):
        hybrid_error_jacobians(0.1, 0.1, 0.0)


def test_scara_dofs_are_the_book_twist():
    assert SCARA_DOFS == (0, 1, 2, 5)


def test_depth_from_segment_length_matches_the_true_depth_for_a_parallel_segment():
    from controllers.visual_servoing import depth_from_segment

    robot = scara_eye_in_hand()
    camera = EyeInHandCamera(robot, scara_target_points())
    image = camera(0.0, ArmMeasurement(Q0, None))
    np.testing.assert_allclose(depth_from_segment(0.1)(image), image.z, atol=1e-12)
    with pytest.raises(ValueError, match="length"):
        depth_from_segment(0.0)


def test_camera_jacobian_is_the_world_jacobian_rotated_into_the_camera(rng):
    import pinocchio as pin

    from controllers.visual_servoing import camera_jacobian
    robot = scara_eye_in_hand()
    q = Q0 + 0.3 * rng.normal(size=4)
    J = pin.computeFrameJacobian(robot.model, robot.data, q, robot.ee_frame, pin.LOCAL_WORLD_ALIGNED)
    R = robot.data.oMf[robot.ee_frame].rotation
    np.testing.assert_allclose(camera_jacobian(robot, q, robot.ee_frame), np.vstack([R.T @ J[:3], R.T @ J[3:]]),
                               atol=1e-12)


@pytest.mark.parametrize("kind", ["segment", "points"])
def test_estimator_prediction_is_the_derivative_of_the_features(rng, kind):
    """ŝ(x̂) is the view of the target at x̂ and L_s(x̂) = −∂ŝ/∂x̂ Γ: central differences of the features
    along the estimator's pose (ẋ = Γ v, so ∂s/∂x Γ = L_s) against its closed-form 4×4 L_s."""
    target = TargetFeatures(P_O, kind=kind)
    est = PoseEstimator(target, X_DO, 160.0, 1e-3)
    for _ in range(3):
        x = X_DO + rng.uniform(-0.05, 0.05, 4)
        s_hat, L = est.predicted(x)
        np.testing.assert_allclose(s_hat, target.features(target.view_from_pose(planar_pose(x)).xy), atol=1e-14)
        h = 1e-6
        ds = np.column_stack([(est.predicted(x + h * e)[0] - est.predicted(x - h * e)[0]) / (2 * h) for e in np.eye(4)])
        np.testing.assert_allclose(ds @ gamma_matrix(x[:3]), L, atol=1e-7)


def test_hybrid_and_6dof_pbvs_name_bad_arguments():
    from controllers.visual_servoing import HybridVisualServo, PBVSPoseResolvedVelocity

    robot = scara_eye_in_hand()
    square = np.array([[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]])
    with pytest.raises(ValueError, match="xy_d"):
        HybridVisualServo(robot, square[:3], [0, 0, 1], 0.5, 1.0, 1.0)
    with pytest.raises(ValueError, match="z_d"):
        HybridVisualServo(robot, square, [0, 0, 1], -0.5, 1.0, 1.0)
    with pytest.raises(ValueError, match="n_d"):
        HybridVisualServo(robot, square, [0, 1], 0.5, 1.0, 1.0)
    with pytest.raises(ValueError, match="zeta"):
        PBVSPoseResolvedVelocity(robot, np.full((4, 2), np.nan), np.eye(4), 1.0, 1.0)
    with pytest.raises(ValueError, match="T_do"):
        PBVSPoseResolvedVelocity(robot, square, np.eye(3), 1.0, 1.0)
    with pytest.raises(ValueError, match="K_o"):
        PBVSPoseResolvedVelocity(robot, square, np.eye(4), 1.0, 0.0)


def test_compiled_pbvs_loop_reproduces_the_python_loop():
    """10.8's chain (camera → estimator at 1 ms → PD + gravity held over 40 ms) as one compiled run: the
    estimate, the held torque and the held log of the law as its state."""
    from controllers.scenes import scara_pbvs as pbvs_setup
    from problems.ch10 import TC_COMPANION
    from controllers.simulation import simulate

    runs = []
    for backend in ("python", "casadi"):
        setup = pbvs_setup(TC_COMPANION, K_P=[500, 500, 10, 10], K_D=[500, 500, 10, 10])
        runs.append(simulate(**{**setup, "t_span": (0.0, 1.0)}, backend=backend))
    a, b = runs
    assert np.abs(a.x[-1] - a.x[0]).max() > 0.05 and len(np.unique(a.u[:, 0])) == 26   # moves; u held 40 ms
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.u, a.u, rtol=1e-12, atol=1e-9)
    assert set(a.signals) == set(b.signals)
    for name in a.signals:
        np.testing.assert_allclose(b[name], a[name], rtol=0, atol=1e-9)


@pytest.mark.parametrize("kind, depth", [("segment", 0.6), ("points", None)])
def test_compiled_ibvs_loop_reproduces_the_python_loop(kind, depth):
    """10.10's chain (camera → IBVS PD + gravity held over 4 ms), segment or point features, a constant or
    the measured depth."""
    from controllers.scenes import scara_ibvs as ibvs_setup
    from problems.ch10 import TC_MANUAL
    from controllers.simulation import simulate

    runs = []
    for backend in ("python", "casadi"):
        setup = ibvs_setup(TC_MANUAL, kind, K_Ps=[5.0, 5.0, 5.0, 5.0], K_Ds=[0.5, 0.5, 0.5, 0.5], depth=depth)
        runs.append(simulate(**{**setup, "t_span": (0.0, 0.5)}, backend=backend))
    a, b = runs
    assert np.abs(a.x[-1] - a.x[0]).max() > 1e-3
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.u, a.u, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(b["e_s"], a["e_s"], rtol=0, atol=1e-9)


def _chain_runs(case: str, t_end: float = 0.6):
    """The Python and compiled runs of a 10.8/10.10-like chain with the camera or features of ``case``."""
    from controllers.plants import ArmPlant
    from controllers.simulation import simulate
    from controllers.visual_servoing import (EyeInHandCamera, IBVSPDGravity, PBVSPDGravity, depth_from_segment,
                                             visual_servo)
    from problems import ch10
    from rigid_body.camera import FieldOfView

    runs = []
    for backend in ("python", "casadi"):
        robot = scara_eye_in_hand()
        points = scara_target_points()
        plant = ArmPlant(robot, viscous_friction=ch10.F_V)
        x0 = plant.initial_state(ch10.Q0)
        camera_options = {}
        if case == "fov":
            camera_options["fov"] = FieldOfView(-0.3, 0.185, -0.3, 0.3)         # point 1 enters the view later
        if case in ("occlusion_noise", "estimator_lost"):
            camera_options.update(lost={1: (0.1, 0.25)}, noise=2e-4, rng=np.random.default_rng(7))
        camera = EyeInHandCamera(robot, points, **camera_options)
        if case.startswith("estimator"):
            kind = "points" if case == "estimator_points" else "segment"
            estimator = PoseEstimator(TargetFeatures(ch10.P_O, kind), ch10.X_DO, ch10.K_S_ESTIMATOR, ch10.T_ESTIMATOR)
            law = PBVSPDGravity(robot, ch10.X_DO, [500, 500, 10, 10], [500, 500, 10, 10])
            controller, Ts = visual_servo(camera, law, ch10.TC_COMPANION, estimator), ch10.T_ESTIMATOR
        else:
            kind = "points" if case == "fov" else "segment"
            target = TargetFeatures(ch10.P_O, kind)
            s_d = target.features(target.view_from_pose(ch10.planar_pose(ch10.X_DO)).xy)
            depth = depth_from_segment(float(np.linalg.norm(ch10.P_O[1] - ch10.P_O[0]))) \
                if case == "estimated_depth" else None
            law = IBVSPDGravity(robot, target, s_d, [5.0] * target.size, [0.5] * target.size, depth=depth)
            controller, Ts = visual_servo(camera, law, ch10.TC_MANUAL), ch10.TC_MANUAL
        runs.append(simulate(plant, controller, (0.0, t_end), x0, h=ch10.H_ARM, Ts=Ts, backend=backend))
    return runs


@pytest.mark.parametrize("case", ["fov", "occlusion_noise", "estimated_depth", "estimator_points", "estimator_lost"])
def test_compiled_visual_servo_covers_the_camera_and_the_features(case):
    """The camera's field of view and occlusion (masked expressions), its noise (pre-sampled from the same
    generator, fed as an input), the depth estimated from the segment, the estimator on point features and an
    estimator holding its estimate while the segment is hidden: the compiled chain against the Python one."""
    a, b = _chain_runs(case)
    signal = "e_s" if "e_s" in a.signals else "x_hat"
    if case in ("fov", "occlusion_noise", "estimator_lost"):
        assert np.isnan(a["e_s"]).any()                          # some feature is not seen along the run
    assert np.abs(a.x[-1] - a.x[0]).max() > 1e-3
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.u, a.u, rtol=1e-12, atol=1e-8)
    assert set(a.signals) == set(b.signals)
    for name in a.signals:
        np.testing.assert_allclose(b[name], a[name], rtol=0, atol=1e-9)
    assert signal in a.signals


def test_a_joint_integrator_runs_the_eye_in_hand_loop_as_the_kinematic_arm_does():
    """The plant of closed-loop IK (JointIntegrator, whose measurement is the bare q) closes the IBVS loop of
    eye_in_hand_ibvs exactly as its KinematicArm (encoders ``meas.q``) does — once an AttributeError."""
    from controllers.plants import JointIntegrator
    from controllers.scenes import panda_camera_target
    from controllers.simulation import simulate
    from controllers.visual_servoing import eye_in_hand_ibvs
    from rigid_body.camera import PinholeCamera

    table = panda_camera_target()
    ibvs = eye_in_hand_ibvs(table.robot, table.points_b, table.T_d, frame="panda_hand",
                            camera=PinholeCamera(600.0, 600.0, 320.0, 240.0), image_size=(640, 480), K_s=1.0, Tc=0.02)
    q_off = table.start(np.pi / 3, [0.08, -0.06, -0.17])
    on_arm = ibvs.run(q_off, 1.0)
    on_integrator = simulate(JointIntegrator(), ibvs.controller, (0.0, 1.0), q_off, h=0.02, Ts=0.02)
    np.testing.assert_array_equal(on_integrator.q, on_arm.q)
    assert ibvs.image_error(on_integrator)[-1] < 0.5 * ibvs.image_error(on_integrator)[0]
