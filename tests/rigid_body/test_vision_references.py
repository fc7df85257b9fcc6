"""Camera and vision functions of Chapter 10 against references computed here: the principal point's default,
the field of view's margins, the homography depth ratio (10.94)–(10.95) against true depths, registration of
coplanar point clouds (a rank-2 K, Problem 10.7)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rigid_body.camera import FieldOfView, PinholeCamera
from rigid_body.vision import depth_ratio, homography_between_views, register_point_clouds


def test_a_camera_without_principal_point_images_the_optical_axis_at_pixel_zero():
    camera = PinholeCamera(800.0, 600.0)
    np.testing.assert_allclose(camera.to_pixels([[0.0, 0.0], [0.01, -0.02]]), [[0.0, 0.0], [8.0, -12.0]])
    np.testing.assert_allclose(camera.intrinsic_matrix, np.diag([800.0, 600.0, 1.0]))


def test_the_field_of_view_is_closed_and_shrinks_by_its_margin_on_every_edge():
    fov = FieldOfView(-0.4, 0.5, -0.3, 0.2)
    corners = np.array([[-0.4, -0.3], [0.5, 0.2], [-0.4, 0.2], [0.5, -0.3]])
    assert fov.contains(corners).all()                                   # the edges belong to the window
    inside_edges = np.array([[-0.35, 0.0], [0.45, 0.0], [0.0, -0.25], [0.0, 0.15]])   # 0.05 inside each edge
    assert fov.contains(inside_edges, margin=0.05 - 1e-12).all()
    assert not fov.contains(inside_edges, margin=0.05 + 1e-9).any()     # each point just outside one shrunk edge
    assert not fov.contains(np.array([[0.51, 0.0], [0.0, 0.21], [-0.41, 0.0], [0.0, -0.31]])).any()


def test_depth_ratio_from_the_homography_equals_the_true_depths():
    """(10.94)–(10.95): z_c/z_d = det(H) (n^{dT} s̃_d)/(n^{cT} s̃_c) for points of the plane n^{dT} p^d = d_d."""
    rng = np.random.default_rng(10)
    for _ in range(20):
        R_dc = Rotation.from_rotvec(0.4 * rng.normal(size=3)).as_matrix()
        o_cd = rng.uniform(-0.3, 0.3, 3)
        n_d = rng.normal(size=3) + [0.0, 0.0, 3.0]
        n_d /= np.linalg.norm(n_d)
        d_d = rng.uniform(0.6, 1.5)
        H = homography_between_views(R_dc, o_cd, n_d, d_d)
        u = np.cross(n_d, rng.normal(size=3))
        p_d = d_d * n_d + 0.3 * u / np.linalg.norm(u)                    # a point of the plane, in d
        p_c = R_dc @ p_d + o_cd
        ratio = depth_ratio(H, R_dc @ n_d, p_c[:2] / p_c[2], n_d, p_d[:2] / p_d[2])
        assert ratio == pytest.approx(p_c[2] / p_d[2], rel=1e-10)


def test_coplanar_point_clouds_are_registered():
    """Points on a plane give K = Σ p̄ p̄'ᵀ of rank 2, enough for the rotation (Problem 10.7); collinear ones not."""
    rng = np.random.default_rng(7)
    R = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix()
    o = np.array([0.2, -0.1, 0.5])
    planar = np.column_stack([rng.uniform(-1, 1, (8, 2)), np.zeros(8)])
    R_hat, o_hat = register_point_clouds(planar @ R.T + o, planar)
    np.testing.assert_allclose(R_hat, R, atol=1e-12)
    np.testing.assert_allclose(o_hat, o, atol=1e-12)
    line = np.outer(np.linspace(-1, 1, 5), [1.0, 2.0, -1.0])
    with pytest.raises(ValueError, match="collinear"):
        register_point_clouds(line @ R.T + o, line)


def test_degenerate_data_are_refused():
    """A homography needs 4 points, no 3 aligned: with 5 on one line A (12×9) has rank 7, not 8 — refused
    rather than a wrong H; collinear clouds at any scale (1 km here) are refused by the registration."""
    from rigid_body.vision import homography_dlt

    zeta = np.r_[np.c_[np.linspace(-1, 1, 5), np.zeros(5)], [[0.3, 0.7]]]
    with pytest.raises(ValueError, match="degenerate"):
        homography_dlt(zeta, 0.4 * zeta + [0.1, 0.2])
    line = 1e3 * np.outer(np.linspace(-1, 1, 6), [1.0, 2.0, -1.0]) + 1e-9 * np.random.default_rng(2).normal(size=(6, 3))
    with pytest.raises(ValueError, match="collinear"):
        register_point_clouds(line + [5.0, 0.0, 0.0], line)
