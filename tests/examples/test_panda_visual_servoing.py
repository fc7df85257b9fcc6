"""The Panda IBVS demo beyond the book: convergence, field of view, joint limits, noise, occlusion, retreat."""

from examples.panda_visual_servoing import panda_ibvs


def test_panda_ibvs_converges_and_shows_the_retreat():
    sol = panda_ibvs()
    failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
    assert not failed, failed
    assert sol.values["image_error_final"] < 1e-3
    assert sol.values["retreat_depth_max"] > 0.7
    assert len(sol.figures) == 1
    assert len(sol.animations) == 1


def test_hybrid_homography_recovers_the_rotation_and_the_depth_ratio(rng):
    """R_d^c and ρ_z = z_c/z_d from the homography of the four points against the true camera poses."""
    import numpy as np

    from controllers.visual_servoing import HybridVisualServo
    from examples.panda_visual_servoing import scene
    from rigid_body.camera import view_target
    from rigid_body.rotations import rot_x, rot_z

    sc = scene()
    xy_d = view_target(sc.T_d, sc.points_b).xy
    law = HybridVisualServo(sc.robot, xy_d, [0, 0, 1], 0.5, 1.0, 1.0, frame="panda_hand")
    for _ in range(5):
        T = sc.T_d.copy()
        T[:3, :3] = sc.T_d[:3, :3] @ rot_z(rng.uniform(-3, 3)) @ rot_x(rng.uniform(-0.3, 0.3))
        T[:3, 3] += rng.uniform(-0.1, 0.1, 3)
        R, rho, s_c = law.rotation_and_depth_ratio(view_target(T, sc.points_b).xy)
        np.testing.assert_allclose(R, T[:3, :3].T @ sc.T_d[:3, :3], atol=1e-9)        # R_d^c = R_cᵀ R_d
        centre = sc.points_b.mean(axis=0)                     # the square's centre: the default reference
        p_c, p_d = T[:3, :3].T @ (centre - T[:3, 3]), sc.T_d[:3, :3].T @ (centre - sc.T_d[:3, 3])
        np.testing.assert_allclose(rho, p_c[2] / p_d[2], rtol=1e-9)
        np.testing.assert_allclose(s_c, p_c[:2] / p_c[2], atol=1e-9)


def test_hybrid_servo_turns_by_pi_without_retreat_where_ibvs_retreats():
    """From a start rotated by π about the optical axis IBVS backs away (> 0.2 m); the 2½-D law turns the
    camera with θ_k = θ_0 (1 − K_o T_c)^k (Euler-exact for the held ω = K_o θ r), keeps the depth of the
    reference point (ln ρ_z stays 0) and reaches the desired pose with the points in view."""
    import numpy as np

    from examples.panda_visual_servoing import (DEPTH, FRAME, TC, camera_depth, run_hybrid, run_ibvs, scene,
                                                start_configuration, views)
    from rigid_body.kinematics import direct_kinematics

    sc = scene()
    q_pi = start_configuration(sc, np.pi, np.zeros(3))
    assert camera_depth(sc, run_ibvs(sc, q_pi, 1.2, depth=DEPTH)).max() - DEPTH > 0.2
    res = run_hybrid(sc, q_pi, 8.0)
    z = camera_depth(sc, res)
    assert np.max(np.abs(z - DEPTH)) < 1e-3
    theta = res["theta"]
    k = np.arange(len(theta))
    np.testing.assert_allclose(theta[:200], theta[0] * (1 - TC) ** k[:200], rtol=2e-2)
    assert all(v.all_visible for v in views(sc, res))
    T = direct_kinematics(sc.robot, res.q[-1], FRAME)
    assert np.linalg.norm(T[:3, 3] - sc.T_d[:3, 3]) < 1e-3
    assert np.linalg.norm(T[:3, :3] - sc.T_d[:3, :3]) < 5e-3


def test_pbvs_6dof_estimates_the_pose_and_moves_the_camera_on_a_straight_line():
    """PBVS in the general form on the Panda: the homography pose estimate = the true T_o^c; from the 60°,
    0.2 m start the camera's origin stays on the chord to the desired one (FK, within 1 mm), its distance
    and θ decay as (1 − K T_c)^k (the held twist, Euler-exact), and the desired pose is reached."""
    import numpy as np

    from examples.panda_visual_servoing import FRAME, TC, run_pbvs, scene, start_configuration, views
    from controllers.visual_servoing import PBVSPoseResolvedVelocity
    from rigid_body.camera import view_target
    from rigid_body.kinematics import direct_kinematics

    sc = scene()
    centre = sc.points_b.mean(axis=0)
    zeta = ((sc.points_b - centre) @ sc.T_d[:3, :3])[:, :2]
    law = PBVSPoseResolvedVelocity(sc.robot, zeta, np.eye(4), 1.0, 1.0, frame=FRAME)
    q0 = start_configuration(sc, np.pi / 3, 0.2 * np.array([0.4, -0.3, -0.85]) / np.linalg.norm([0.4, -0.3, -0.85]))
    T0 = direct_kinematics(sc.robot, q0, FRAME)
    T_o = np.eye(4)
    T_o[:3, :3], T_o[:3, 3] = sc.T_d[:3, :3], centre                  # the object frame in the base frame
    np.testing.assert_allclose(law.estimate(view_target(T0, sc.points_b).xy), np.linalg.solve(T0, T_o), atol=1e-9)

    res = run_pbvs(sc, q0, 8.0)
    P = np.array([direct_kinematics(sc.robot, q, FRAME)[:3, 3] for q in res.q])
    d = P - sc.T_d[:3, 3]
    u = d[0] / np.linalg.norm(d[0])
    assert np.max(np.linalg.norm(d - np.outer(d @ u, u), axis=1)) < 1e-3
    k = np.arange(len(res.t))[:200]
    np.testing.assert_allclose(np.linalg.norm(d, axis=1)[:200], np.linalg.norm(d[0]) * (1 - TC) ** k, rtol=2e-2)
    np.testing.assert_allclose(res["theta"][:200], res["theta"][0] * (1 - TC) ** k, rtol=2e-2)
    assert all(v.all_visible for v in views(sc, res))
    assert np.linalg.norm(d[-1]) < 1e-4
