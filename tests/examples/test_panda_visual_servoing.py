"""The Panda IBVS demo beyond the book: convergence, field of view, joint limits, noise, occlusion, retreat."""

from examples.panda_visual_servoing import panda_ibvs


def test_panda_ibvs_converges_and_shows_the_retreat():
    sol = panda_ibvs()
    failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
    assert not failed, failed
    assert sol.values["image_error_final"] < 1e-3
    assert sol.values["retreat_depth_max"] > 0.7
    assert len(sol.figures) == 1
