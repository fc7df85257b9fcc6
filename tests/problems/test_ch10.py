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
    monkeypatch.setattr(vs, "gamma_matrix", lambda o: -original(o))
    try:
        assert not solve("10.4").passed
    except ValueError as exc:                # the estimate may run behind the camera: also a failure
        assert "behind the camera" in str(exc)
