"""Visual servoing under hostile input (issue 26): singular postures (item 2), features behind the camera and
degenerate geometry (item 6), NaN gains (item 4), the IBVS twist components of a robot (item 14)."""

import math
import warnings

import numpy as np
import pytest

from controllers.plants import ArmMeasurement
from controllers.simulation import Augmented
from controllers.visual_servoing import (SCARA_DOFS, CameraImage, EyeInHandCamera, HybridVisualServo, IBVSPDGravity,
                                         IBVSResolvedVelocity, PBVSPDGravity, PBVSPoseResolvedVelocity,
                                         PBVSResolvedVelocity, PoseEstimator, TargetFeatures, camera_dofs,
                                         camera_jacobian, depth_from_segment, hybrid_error_jacobians, planar_pose)
from controllers.scenes import SCARA_DESIRED_POSE as X_DO, SCARA_Q0 as Q0, SCARA_TARGET_POINTS as P_O, \
    scara_eye_in_hand, scara_target_points
from rigid_body.robots import load
from rigid_body.task_space import RATE_CONDITION, resolved_rates

SEGMENT = TargetFeatures(P_O, "segment")
S_D = SEGMENT.features(SEGMENT.view_from_pose(planar_pose(X_DO)).xy)


@pytest.fixture(scope="module")
def scara():
    return scara_eye_in_hand()


@pytest.fixture(scope="module")
def panda():
    return load("panda")


def _estimate(q, x_hat=(0.0, 0.0, 0.5, 0.0)):
    return Augmented(ArmMeasurement(np.asarray(q, dtype=float), None), estimate=np.array(x_hat))


# --------------------------------------------------------------------------------------------
# Item 2: resolved-velocity PBVS at singular postures
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("theta2", [0.0, np.pi, -np.pi, 1e-8, 1e-4, np.pi - 1e-5])
def test_pbvs_resolved_velocity_refuses_singular_postures(scara, theta2):
    """The issue's stretched SCARA (θ₂ = 0) commanded 3e16 rad/s; folded (θ₂ = π) and near-singular postures too."""
    law = PBVSResolvedVelocity(scara, X_DO, [1.0, 1.0, 1.0, 1.0])
    q = [0.3, theta2, 0.5, 0.2]
    with pytest.raises(ValueError, match=r"singular \(J_Ad at q = \[0\.3, .*cond = .* > max_condition = 1000.*damping"):
        law(0.0, _estimate(q))


def test_pbvs_rates_stay_physical_where_they_are_given(scara):
    """At cond(J_Ad) just below the bound the rates are at most cond × the error's size; with damping λ they
    are bounded by |K x̃|/(2λ) at the singular posture itself (3.59)."""
    law = PBVSResolvedVelocity(scara, X_DO, 1.0)
    meas = _estimate([0.3, 0.02, 0.5, 0.2])
    J = law.pbvs_jacobian(meas.q, meas.estimate)
    assert np.linalg.cond(J) < RATE_CONDITION
    qd = law(0.0, meas)
    np.testing.assert_allclose(J @ qd, law.log()["x_tilde"], atol=1e-12)            # J_Ad q̇ = K x̃ (K = I)
    damped = PBVSResolvedVelocity(scara, X_DO, 1.0, damping=0.05)
    at_singular = damped(0.0, _estimate([0.3, 0.0, 0.5, 0.2]))
    assert np.linalg.norm(at_singular) <= np.linalg.norm(damped.log()["x_tilde"]) / (2 * 0.05) + 1e-12


def test_resolved_rates_match_the_pseudo_inverse_and_refuse_by_condition(rng):
    for shape, rank in (((4, 4), None), ((3, 7), None), ((8, 7), 6)):
        U, _ = np.linalg.qr(rng.standard_normal((shape[0], shape[0])))
        V, _ = np.linalg.qr(rng.standard_normal((shape[1], shape[1])))
        r = rank or min(shape)
        sigma = np.zeros(min(shape))
        sigma[:r] = np.geomspace(1.0, 1e-2, r)
        J = U[:, :len(sigma)] @ np.diag(sigma) @ V[:, :len(sigma)].T
        b = rng.standard_normal(shape[0])
        np.testing.assert_allclose(resolved_rates(J, b, "here", rank=rank), np.linalg.pinv(J, rcond=1e-9) @ b,
                                   atol=1e-10)
        sigma[r - 1] = 1e-4                                                               # cond 1e4 > 1e3
        J = U[:, :len(sigma)] @ np.diag(sigma) @ V[:, :len(sigma)].T
        with pytest.raises(ValueError, match="singular here: cond = 1e\\+04"):
            resolved_rates(J, b, "here", rank=rank)
        resolved_rates(J, b, "here", max_condition=1e5, rank=rank)


@pytest.mark.parametrize("kwargs, name", [(dict(max_condition=0.5), "max_condition"), (dict(damping=-1.0), "damping"),
                                          (dict(damping=np.nan), "damping"), (dict(max_condition="1e3"), "max_condition")])
def test_rate_options_are_checked(scara, kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        PBVSResolvedVelocity(scara, X_DO, 1.0, **kwargs)
    with pytest.raises(ValueError, match=f"`{name}`"):
        IBVSResolvedVelocity(scara, SEGMENT, S_D, 1.0, **kwargs)


def test_ibvs_resolved_velocity_refuses_a_singular_image_jacobian(scara):
    law = IBVSResolvedVelocity(scara, SEGMENT, S_D, 1.0, depth=0.6)
    camera = EyeInHandCamera(scara, scara_target_points())
    q = np.array([0.3, 0.0, 0.5, 0.2])                                                  # stretched
    meas = ArmMeasurement(q, None)
    with pytest.raises(ValueError, match=r"J_L = L_s J_c at q = \[0\.3, 0\.0, 0\.5, 0\.2\]"):
        law(0.0, Augmented(meas, image=camera(0.0, meas)))


# --------------------------------------------------------------------------------------------
# Item 6: features behind the camera, zero depth, coincident points, zero-length segments
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("z", [[-1.0, 0.6], [0.6, 0.0], [np.nan, 0.6], [0.6, np.inf]])
def test_interaction_matrix_refuses_points_not_in_front(z):
    xy = SEGMENT.view_from_pose(planar_pose(X_DO)).xy
    for target in (SEGMENT, TargetFeatures(P_O, "points")):
        with pytest.raises(ValueError, match="`z`"):
            target.interaction_matrix(xy, z)


def test_interaction_matrix_refuses_coincident_segment_ends_and_bad_points():
    with pytest.raises(ValueError, match="coincide"):
        SEGMENT.interaction_matrix([[0.1, 0.1], [0.1, 0.1]], [0.6, 0.6])
    with pytest.raises(ValueError, match="`xy`"):
        SEGMENT.interaction_matrix([[0.1, np.nan], [0.2, 0.1]], [0.6, 0.6])
    with pytest.raises(ValueError, match="`xy`"):
        SEGMENT.features(np.zeros((3, 2)))


def test_coincident_target_points_are_refused():
    with pytest.raises(ValueError, match="`points_o` 0 and 1 coincide"):
        TargetFeatures([[0.1, 0.0, 0.0], [0.1, 0.0, 0.0]], "segment")
    with pytest.raises(ValueError, match="`points_o` 1 and 2 coincide"):
        TargetFeatures([[0, 0, 0], [0.1, 0, 0], [0.1, 0, 0]], "points")


def test_pose_estimator_with_a_segment_seen_end_on():
    """Two points on one viewing ray of the estimate: the image segment has zero length (was ZeroDivisionError)."""
    target = TargetFeatures([[0.0, 0.0, 0.0], [0.0, 0.0, 0.1]], "segment")
    est = PoseEstimator(target, [0.0, 0.0, 0.5, 0.0], 160.0, 1e-3)
    with pytest.raises(ValueError, match="end-on"):
        est.update([0.0, 0.0, 0.1, 0.0])
    with pytest.raises(ValueError, match="`s`"):
        PoseEstimator(SEGMENT, X_DO, 160.0, 1e-3).update([0.0, np.nan, 0.1, 0.0])


def test_depth_from_a_zero_length_segment():
    image = CameraImage(xy=np.array([[0.1, 0.2], [0.1, 0.2]]), visible=np.ones(2, bool), z=np.full(2, 0.5))
    with pytest.raises(ValueError, match="coincide"):
        depth_from_segment(0.1)(image)


def test_depth_estimate_that_is_not_positive_is_named(scara):
    law = IBVSResolvedVelocity(scara, SEGMENT, S_D, 1.0, depth=lambda image: np.array([0.6, -0.1]))
    camera = EyeInHandCamera(scara, scara_target_points())
    meas = ArmMeasurement(Q0, None)
    with pytest.raises(ValueError, match="`depth` estimated non-positive"):
        law(0.0, Augmented(meas, image=camera(0.0, meas)))


@pytest.mark.parametrize("K_s", [np.nan, np.inf, -1.0, 0.0, np.full((4, 4), np.nan), "160"])
def test_pose_estimator_gain_is_checked(K_s):
    with pytest.raises(ValueError, match="`K_s`"):
        PoseEstimator(SEGMENT, X_DO, K_s, 1e-3)


def test_other_camera_inputs_are_checked(scara):
    with pytest.raises(ValueError, match="`points_b`"):
        EyeInHandCamera(scara, [[0.0, np.nan, 0.0], [0.1, 0.0, 0.0]])
    with pytest.raises(ValueError, match="`x`"):
        hybrid_error_jacobians(np.nan, 0.0, 0.5)
    square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    with pytest.raises(ValueError, match="`zeta`"):
        PBVSPoseResolvedVelocity(scara, [[0, 0], [1, 0], [2, 0], [3, 0]], np.eye(4), 1.0, 1.0)
    with pytest.raises(ValueError, match="`T_do`"):
        PBVSPoseResolvedVelocity(scara, square, np.zeros((4, 4)), 1.0, 1.0)
    with pytest.raises(ValueError, match="`n_d`"):
        HybridVisualServo(scara, square, [0, 0, 0], 0.5, 1.0, 1.0)
    with pytest.raises(ValueError, match="`xy_d`"):
        HybridVisualServo(scara, [[0, 0], [0, 0], [1, 1], [0, 1]], [0, 0, 1], 0.5, 1.0, 1.0)


# --------------------------------------------------------------------------------------------
# Item 14: the IBVS twist components come from the robot; a law that cannot reduce the error is refused
# --------------------------------------------------------------------------------------------

def test_camera_dofs_are_derived_from_the_robot(scara, panda):
    assert camera_dofs(scara) == SCARA_DOFS
    assert camera_dofs(panda, "panda_hand") == tuple(range(6))
    planar = load("planar_2r")
    assert camera_dofs(planar) == (0, 1, 5)          # a planar arm in x–y moves its frame along x, y, about z


def test_default_dofs_follow_the_robot(scara, panda):
    assert IBVSResolvedVelocity(scara, SEGMENT, S_D, 1.0).dofs == list(SCARA_DOFS)
    target = TargetFeatures([[-0.1, -0.1, 0], [0.1, -0.1, 0], [0.1, 0.1, 0], [-0.1, 0.1, 0]], "points")
    s_d = target.features(target.view_from_pose(np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.5], [0, 0, 0, 1.0]])).xy)
    law = IBVSPDGravity(panda, target, s_d, 1.0, 1.0, frame="panda_hand")
    assert law.dofs == list(range(6))


def test_scara_dofs_on_the_panda_are_refused(panda):
    """The issue: the SCARA's default (0, 1, 2, 5) on the Panda stalled at ‖e_s‖ = 0.0074."""
    with pytest.raises(ValueError, match=r"`dofs` \(0, 1, 2, 5\) leaves out ω_x, ω_y.*'panda'.*dofs=\(0, 1, 2, 3, 4, 5\)"):
        IBVSResolvedVelocity(panda, SEGMENT, S_D, 1.0, frame="panda_hand", dofs=SCARA_DOFS)
    with pytest.raises(ValueError, match="4-DOF case"):
        PBVSResolvedVelocity(panda, X_DO, 1.0, frame="panda_hand")
    with pytest.raises(ValueError, match="4-DOF case"):
        PBVSPDGravity(panda, X_DO, 1.0, 1.0, frame="panda_hand")


def test_dofs_the_camera_does_not_move_along_change_nothing(scara):
    """ω_x, ω_y rows of the SCARA camera's J_c vanish: adding them to `dofs` gives the same law."""
    camera = EyeInHandCamera(scara, scara_target_points())
    meas = ArmMeasurement(np.array([0.5, -1.2, 0.45, 0.6]), None)
    meas = Augmented(meas, image=camera(0.0, meas))
    u = IBVSResolvedVelocity(scara, SEGMENT, S_D, 1.0, depth=0.6)(0.0, meas)
    for dofs in ((0, 1, 2, 3, 4, 5), (0, 1, 2, 4, 5)):
        np.testing.assert_allclose(IBVSResolvedVelocity(scara, SEGMENT, S_D, 1.0, depth=0.6, dofs=dofs)(0.0, meas), u,
                                   rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("dofs", [(0,), (0, 1), (2, 5), (0, 1, 2)])
def test_dofs_leaving_out_a_camera_motion_are_refused(scara, dofs):
    with pytest.raises(ValueError, match="leaves out"):
        IBVSResolvedVelocity(scara, SEGMENT, S_D, 1.0, dofs=dofs)


@pytest.mark.parametrize("s_d, kind", [
    (np.r_[S_D[:2], S_D[:2]], "points"),            # two coincident desired points: rank 2 < 4
    ([0.1, 0.1, 0.0, 0.3], "segment"),             # a zero-length desired segment
])
def test_degenerate_desired_features_are_refused(scara, s_d, kind):
    with pytest.raises(ValueError, match="`s_d`"):
        IBVSResolvedVelocity(scara, TargetFeatures(P_O, kind), s_d, 1.0, depth=0.6)
    with pytest.raises(ValueError, match="`s_d`"):
        IBVSPDGravity(scara, TargetFeatures(P_O, kind), s_d, 1.0, 1.0, depth=0.6)


def test_a_planar_arm_needs_only_its_own_motions():
    """A 2R arm moves its frame along x, y (rank 2): segment features (4) are refused only below rank 2."""
    arm = load("planar_2r")
    target = TargetFeatures([[0.0, 0.0, 0.5], [0.1, 0.0, 0.5]], "segment")
    s_d = target.features(target.view_from_pose(np.eye(4)).xy)
    assert IBVSResolvedVelocity(arm, target, s_d, 1.0).dofs == [0, 1, 5]


@pytest.mark.parametrize("dofs", [(1.5, 2), (0, 0, 1), (6,), (), "xyz"])
def test_malformed_dofs_are_named(scara, dofs):
    with pytest.raises(ValueError, match="`dofs`"):
        IBVSResolvedVelocity(scara, SEGMENT, S_D, 1.0, dofs=dofs)


def test_a_stalled_servo_is_reported(panda):
    """e_s in the left null space of J_L (8 point features, 6 camera motions: a 2-D subspace the law cannot
    reduce): the law commands nothing while the error stays; it warns once and keeps (t, ‖e_s‖)."""
    side, depth = 0.2, 0.5
    target = TargetFeatures(np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]) * side / 2, "points")
    q = panda.configurations["ready"]
    from rigid_body.kinematics import direct_kinematics

    T_c = direct_kinematics(panda, q, "panda_hand")
    T_co = np.eye(4)
    T_co[2, 3] = depth
    points_b = (T_c @ T_co @ np.c_[target.points_o, np.ones(4)].T).T[:, :3]
    s_d = target.features(target.view_from_pose(T_co).xy)
    law = IBVSResolvedVelocity(panda, target, s_d, 1.0, depth=depth, frame="panda_hand")
    xy = s_d.reshape(-1, 2)
    n = np.zeros(8)
    for _ in range(20):                          # a fixed point: e = s_d − s in the left null space of J_L(s)
        L = target.interaction_matrix(xy - n.reshape(-1, 2), np.full(4, depth))
        J = L @ camera_jacobian(panda, q, law.frame)
        _, _, Vt = np.linalg.svd(J.T)
        n = Vt[-1] * 2e-3 if Vt[-1] @ n >= 0 else -Vt[-1] * 2e-3
    image = CameraImage(xy=xy - n.reshape(-1, 2), visible=np.ones(4, bool), z=np.full(4, depth))
    meas = Augmented(ArmMeasurement(q, None), image=image)
    with pytest.warns(RuntimeWarning, match="stalls at t = 1.5 s with ‖e_s‖ = 0.002"):
        qd = law(1.5, meas)
    assert np.linalg.norm(qd) < 1e-5 and law.stall == (1.5, pytest.approx(2e-3))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        law(1.6, meas)                            # once per run
    law.reset()
    assert law.stall is None
    moving = CameraImage(xy=xy + 2e-3, visible=np.ones(4, bool), z=np.full(4, depth))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.linalg.norm(law(0.0, Augmented(ArmMeasurement(q, None), image=moving))) > 1e-4
    assert law.stall is None
    assert math.isfinite(points_b.sum())


def test_resolved_rates_arguments_are_named():
    """Review LOW: damping = 0 at a singular J gave a bare LinAlgError; a `rank` above min(m, n) said "near
    singular"; `max_condition` was unchecked. Each is now a ValueError naming the argument."""
    J_singular = np.array([[1.0, 2.0], [2.0, 4.0]])
    b = np.array([1.0, 0.0])
    for damping in (0.0, -0.1, np.nan, np.inf, "0.1", True):
        with pytest.raises(ValueError, match="`damping` must be a finite number > 0"):
            resolved_rates(J_singular, b, "here", damping=damping)
    qd = resolved_rates(J_singular, b, "here", damping=0.1)          # damped: defined at the singularity
    np.testing.assert_allclose(qd, J_singular.T @ np.linalg.solve(J_singular @ J_singular.T + 0.01 * np.eye(2), b))
    J = np.array([[1.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    for rank in (3, 0, 1.0, True):
        with pytest.raises(ValueError, match=r"`rank` must be an integer in \[1, min\(m, n\) = 2\]"):
            resolved_rates(J, b, "here", rank=rank)
    for bound in (0.5, np.nan, "1e3", None):
        with pytest.raises(ValueError, match="`max_condition` must be a number >= 1"):
            resolved_rates(J, b, "here", max_condition=bound)
    np.testing.assert_allclose(resolved_rates(J, [1.0, 1.0], "here", rank=1), [0.0, 0.5, 0.0])   # σ = 2 kept
