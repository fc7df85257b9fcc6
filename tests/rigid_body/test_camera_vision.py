"""Camera features and interaction matrices (finite differences), image moments, and geometric vision
(homography, pose, registration, calibration, triangulation) on synthetic data with known truth."""

import numpy as np
import pinocchio as pin
import pytest
from scipy.spatial.transform import Rotation

from rigid_body.camera import (FieldOfView, LineFeatures, PinholeCamera, line_features, line_interaction_matrix,
                               point_interaction_matrix, points_interaction_matrix, region_moments,
                               segment_features, segment_interaction_matrix, view_points, view_target)
from rigid_body.vision import (decompose_projection_matrix, homography_dlt, pose_from_homography,
                               projection_matrix_dlt, register_point_clouds, triangulate)


def _moved(p_c: np.ndarray, twist: np.ndarray, eps: float) -> np.ndarray:
    """The fixed points ``p_c`` (n, 3) seen from the camera after it moved by exp(eps·twist) (camera frame)."""
    M = pin.exp6(pin.Motion(eps * twist))
    return (p_c - M.translation) @ M.rotation


def _fd_interaction(features, p_c: np.ndarray, h: float = 1e-6) -> np.ndarray:
    return np.column_stack([(features(_moved(p_c, e, h)) - features(_moved(p_c, e, -h))) / (2 * h) for e in np.eye(6)])


def _random_points(rng, n):
    return np.column_stack([rng.uniform(-0.3, 0.3, (n, 2)), rng.uniform(0.5, 1.5, n)])


def test_point_matrices_match_finite_differences(rng):
    for _ in range(10):
        p = _random_points(rng, 3)
        L = points_interaction_matrix(p[:, :2] / p[:, 2:], p[:, 2])
        fd = _fd_interaction(lambda q: (q[:, :2] / q[:, 2:]).reshape(-1), p)
        np.testing.assert_allclose(L, fd, atol=1e-7)


def test_segment_matrix_matches_finite_differences(rng):
    for _ in range(10):
        p = _random_points(rng, 2)
        xy = p[:, :2] / p[:, 2:]
        L = segment_interaction_matrix(xy[0], xy[1], p[0, 2], p[1, 2])
        fd = _fd_interaction(lambda q: segment_features(q[0, :2] / q[0, 2], q[1, :2] / q[1, 2]).as_array(), p)
        np.testing.assert_allclose(L, fd, atol=1e-7)


def test_line_matrix_matches_finite_differences(rng):
    for _ in range(10):
        p = _random_points(rng, 2)
        xy = p[:, :2] / p[:, 2:]
        line = line_features(xy[0], xy[1])
        L = line_interaction_matrix(line, p[0], p[1])
        fd = _fd_interaction(lambda q: line_features(q[0, :2] / q[0, 2], q[1, :2] / q[1, 2]).as_array(), p)
        np.testing.assert_allclose(L, fd, atol=1e-6)
        # both image points lie on the line
        for x, y in xy:
            assert abs(x * np.cos(line.theta) + y * np.sin(line.theta) - line.rho) < 1e-12


def test_feature_inputs_are_checked():
    with pytest.raises(ValueError, match="z"):
        point_interaction_matrix(0.1, 0.2, 0.0)
    with pytest.raises(ValueError, match="coincide"):
        segment_features([0.1, 0.1], [0.1, 0.1])
    with pytest.raises(ValueError, match="optical centre"):
        line_interaction_matrix(LineFeatures(0.0, 0.0), [0, 0, 1.0], [0, 0, 2.0])
    with pytest.raises(ValueError, match="xy"):
        points_interaction_matrix(np.zeros((2, 3)), [1, 1])


def test_view_reports_points_behind_and_outside():
    cam = PinholeCamera(500, 500, 320, 240)
    fov = cam.field_of_view(640, 480)
    np.testing.assert_allclose([fov.x_min, fov.x_max, fov.y_min, fov.y_max], [-0.64, 0.64, -0.48, 0.48])
    view = view_points([[0, 0, 1.0], [0.0, 0.0, -1.0], [2.0, 0.0, 1.0]], fov)
    assert view.in_front.tolist() == [True, False, True]
    assert view.in_view.tolist() == [True, False, False]
    assert np.all(np.isnan(view.xy[1])) and not view.all_visible
    with pytest.raises(ValueError, match=r"behind the camera \[1\], outside the field of view \[2\]"):
        view.require_visible()
    np.testing.assert_allclose(cam.to_normalised(cam.to_pixels([[0.1, -0.2]])), [[0.1, -0.2]])
    T = np.eye(4)
    T[:3, 3] = [0.0, 0.0, 2.0]                          # camera at z = 2 looking along +z
    assert view_target(T, [[0.0, 0.0, 1.0]]).in_front.tolist() == [False]
    with pytest.raises(ValueError, match="x_min"):
        FieldOfView(1.0, -1.0, -1.0, 1.0)


def test_region_moments_orientation_and_errors():
    g = np.linspace(-3, 3, 401)
    X, Y = np.meshgrid(g, g)
    a = -0.7
    u, v = np.cos(a) * X + np.sin(a) * Y, -np.sin(a) * X + np.cos(a) * Y
    m = region_moments((u / 2.5) ** 2 + (v / 0.8) ** 2 <= 1, g, g)
    assert abs(m.orientation - a) < 2e-3
    lam, lam_p = m.principal_moments
    assert lam > lam_p > 0
    with pytest.raises(ValueError, match="empty"):
        region_moments(np.zeros((401, 401), bool), g, g)
    with pytest.raises(ValueError, match="mask"):
        region_moments(np.ones((3, 4), bool), g, g)


def test_homography_pose_recovers_truth_and_rejects_degenerate(rng):
    zeta = rng.uniform(-0.2, 0.2, (8, 2))
    R = Rotation.from_euler("xyz", [0.2, -0.3, 1.0]).as_matrix()
    o = np.array([0.05, -0.02, 0.9])
    p = np.column_stack([zeta, np.zeros(8)]) @ R.T + o
    s = p[:, :2] / p[:, 2:]
    pose = pose_from_homography(homography_dlt(zeta, s))
    np.testing.assert_allclose(pose.R, R, atol=1e-9)
    np.testing.assert_allclose(pose.o, o, atol=1e-9)
    with pytest.raises(ValueError, match="degenerate"):
        line = np.column_stack([np.linspace(0, 1, 6), np.zeros(6)])
        homography_dlt(line, line)
    with pytest.raises(ValueError, match="at least 4"):
        homography_dlt(zeta[:3], s[:3])


def test_registration_with_noise_and_collinear_points(rng):
    R, o = Rotation.random(random_state=3).as_matrix(), np.array([0.3, -0.1, 0.5])
    pp = rng.uniform(-1, 1, (30, 3))
    p = pp @ R.T + o + 1e-3 * rng.standard_normal((30, 3))
    R_hat, o_hat = register_point_clouds(p, pp)
    assert np.linalg.norm(R_hat - R) < 2e-3 and np.linalg.norm(o_hat - o) < 2e-3
    line = np.outer(np.linspace(0, 1, 5), [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="collinear"):
        register_point_clouds(line, line)


def _camera_matrix(Omega, R, o):
    return Omega @ np.column_stack([R, o])


def test_calibration_from_known_points_with_noise(rng):
    """DLT of P from 3-D points and their pixels, then Ω and the extrinsics by RQ; noise of 0.2 pixel."""
    Omega = np.array([[800.0, 0.0, 320.0], [0.0, 780.0, 250.0], [0.0, 0.0, 1.0]])
    R = Rotation.from_euler("xyz", [0.1, -0.2, 0.3]).as_matrix()
    o = np.array([-0.1, 0.05, 2.0])
    pts = rng.uniform(-0.5, 0.5, (40, 3))
    h = (pts @ R.T + o) @ Omega.T
    pix = h[:, :2] / h[:, 2:]
    exact = decompose_projection_matrix(projection_matrix_dlt(pts, pix))
    np.testing.assert_allclose(exact.Omega, Omega, atol=1e-6)
    np.testing.assert_allclose(exact.R, R, atol=1e-9)
    np.testing.assert_allclose(exact.o, o, atol=1e-9)
    noisy = decompose_projection_matrix(projection_matrix_dlt(pts, pix + 0.2 * rng.standard_normal(pix.shape)))
    assert np.max(np.abs(noisy.Omega - Omega)) < 10.0          # pixels
    assert np.max(np.abs(noisy.R - R)) < 1e-2 and np.max(np.abs(noisy.o - o)) < 2e-2
    with pytest.raises(ValueError, match="coplanar"):
        flat = pts.copy()
        flat[:, 2] = 0.0
        hf = (flat @ R.T + o) @ Omega.T
        projection_matrix_dlt(flat, hf[:, :2] / hf[:, 2:])
    with pytest.raises(ValueError, match="at least 6"):
        projection_matrix_dlt(pts[:5], pix[:5])


def test_two_view_triangulation_with_noise(rng):
    pts = np.column_stack([rng.uniform(-0.3, 0.3, (20, 2)), rng.uniform(1.5, 2.5, 20)])
    P1 = _camera_matrix(np.eye(3), np.eye(3), np.zeros(3))
    R2 = Rotation.from_euler("y", -0.3).as_matrix()
    o2 = np.array([-0.5, 0.0, 0.1])
    P2 = _camera_matrix(np.eye(3), R2, o2)
    x1 = pts[:, :2] / pts[:, 2:]
    p2 = pts @ R2.T + o2
    x2 = p2[:, :2] / p2[:, 2:]
    np.testing.assert_allclose(triangulate(P1, P2, x1, x2), pts, atol=1e-9)
    noisy = triangulate(P1, P2, x1 + 1e-4 * rng.standard_normal(x1.shape), x2 + 1e-4 * rng.standard_normal(x2.shape))
    assert np.max(np.abs(noisy - pts)) < 1e-2         # depth error ≈ z²σ√2/baseline ≈ 1e-3 (1σ)
    with pytest.raises(ValueError, match="same number"):
        triangulate(P1, P2, x1, x2[:3])


def test_view_through_a_robot_frame():
    """MODEL-C at its start: the camera (end effector, z down) sees P₁ on its optical axis at depth 0.5 m."""
    from controllers.scenes import SCARA_Q0 as Q0, scara_eye_in_hand, scara_target_points
    from rigid_body.camera import view_target_from_robot

    view = view_target_from_robot(scara_eye_in_hand(), Q0, scara_target_points(), fov=FieldOfView(-0.5, 0.5, -0.5, 0.5))
    np.testing.assert_allclose(view.z, [0.5, 0.5], atol=1e-12)
    np.testing.assert_allclose(view.xy, [[0.0, 0.0], [0.2, 0.0]], atol=1e-12)
    assert view.all_visible
    behind = view_target_from_robot(scara_eye_in_hand(), Q0, [[1.0, 1.0, 0.0]])
    assert not behind.all_visible
