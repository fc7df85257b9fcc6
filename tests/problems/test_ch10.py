"""Extra assertions on the chapter-10 problems beyond their own checks (the closed loops run in
test_all_problems.py)."""

import numpy as np
import pytest

import problems.ch10 as ch10
from problems.registry import all_problems, solve


def test_all_chapter_10_problems_registered():
    assert {p.id for p in all_problems() if p.id.startswith("10.")} == {f"10.{i}" for i in range(1, 14)}


def test_pose_estimation_values_have_the_required_keys():
    s4, s5 = solve("10.4"), solve("10.5")
    assert s4.passed and s5.passed
    np.testing.assert_allclose(s4.values["x_hat_final"], [-0.1, 0.1, 0.6, -np.pi / 3], atol=3e-3)
    assert np.shape(s5.values["s"]) == (4,) and np.shape(s5.values["x_hat_final"]) == (4,)
    # s = [x_m, y_m, L, α] of the measured points, computed independently here
    p = ch10.S_POINTS_MEASURED.reshape(2, 2)
    d = p[1] - p[0]
    np.testing.assert_allclose(s5.values["s"], [*p.mean(0), np.hypot(*d), np.arctan2(d[1], d[0])], atol=1e-12)


@pytest.mark.parametrize("pid, name", [("10.3", "nearest_rotation"), ("10.7", "register_point_clouds"),
                                       ("10.13", "hybrid_error_jacobians"), ("10.2", "pose_from_homography")])
def test_derivation_checks_can_fail(pid, name, monkeypatch):
    """Perturbing the library function the check relies on must make the problem fail."""
    original = getattr(ch10, name)

    def perturbed(*args, **kwargs):
        out = original(*args, **kwargs)
        if isinstance(out, tuple):
            return (out[0] * 1.001,) + tuple(out[1:])
        if hasattr(out, "R"):
            return type(out)(R=out.R * 1.001, o=out.o, Q=out.Q)
        return out * 1.001

    monkeypatch.setattr(ch10, name, perturbed)
    assert not solve(pid).passed


def test_estimator_check_fails_with_a_wrong_interaction_matrix(monkeypatch):
    """A wrong sign in Γ makes the pose estimate diverge or miss: 10.4 must fail."""
    import controllers.visual_servoing as vs

    original = vs.gamma_matrix
    monkeypatch.setattr(vs, "gamma_matrix", lambda o, ops=None: -original(o, ops))
    try:
        assert not solve("10.4").passed
    except ValueError as exc:                # the estimate may run behind the camera: also a failure
        assert "behind the camera" in str(exc)


def test_eye_in_hand_animation_tracks_the_camera_and_the_rays():
    """The animation of a SCARA loop (0.4 s of 10.11): 25 frames per second, the pyramid carried by the camera
    pose (T = the camera frame's from an independent FK of the SCARA's DH geometry), each ray's unit segment
    mapped from the optical centre onto its target point."""
    from controllers.scenes import scara_eye_in_hand, scara_ibvs, scara_target_points
    from controllers.simulation import simulate
    from viewer import eye_in_hand_animation

    setup = scara_ibvs(ch10.TC_MANUAL, "segment", K_s=1.0)
    setup["t_span"] = (0.0, 0.4)
    res = simulate(**setup)
    points = scara_target_points()
    spec = eye_in_hand_animation(scara_eye_in_hand(), res, points, depth=0.6)
    t, q = spec["motion"]
    assert spec["fps"] == 25.0 and np.allclose(np.diff(t), 0.04) and t[-1] == res.t[-1]
    for k, qk in enumerate(q):                      # SCARA of a1 = a2 = 1, z down: camera above the target
        th = qk[0] + qk[1]
        o = [np.cos(qk[0]) + np.cos(th), np.sin(qk[0]) + np.sin(th), qk[2]]
        T = spec["tracks"]["camera"][k]
        np.testing.assert_allclose(T[:3, 3], o, atol=1e-12)
        np.testing.assert_allclose(T[:3, 2], [0, 0, 1], atol=1e-12)      # the optical axis along z₀ (down)
        for i, p in enumerate(points):
            R = spec["tracks"][f"ray_{i + 1}"][k]
            np.testing.assert_allclose(R @ [0, 0, 1, 1], np.r_[p, 1], atol=1e-12)
            np.testing.assert_allclose(R @ [0, 0, 0, 1], np.r_[o, 1], atol=1e-12)
    import viewer

    scene = viewer.animate(scara_eye_in_hand(), **spec)
    assert scene.duration == pytest.approx(0.4)


def test_fast_backend_compiles_the_pd_gravity_chains_only():
    """10.8/10.10 (PD + gravity laws with a symbolic form) take the compiled loop with a compiler; the
    resolved-velocity chains of 10.9/10.11 have none and stay on the Python loop."""
    from controllers.compiled import fast_backend
    from controllers.scenes import scara_pbvs
    from rigid_body.codegen import compiler

    pd = scara_pbvs(ch10.TC_MANUAL, K_P=np.full(4, 100.0), K_D=np.full(4, 10.0))["controller"]
    velocity = scara_pbvs(ch10.TC_MANUAL, K=np.ones(4))["controller"]
    assert pd.compilable and not velocity.compilable
    assert fast_backend(velocity) == "python"
    if compiler() is not None:
        assert fast_backend(pd) == "casadi"
