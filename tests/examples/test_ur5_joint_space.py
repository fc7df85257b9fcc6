"""The UR5 demo beyond the book: joint-space control with an unknown payload."""

from examples.ur5_joint_space import ur5_joint_space_control


def test_ur5_joint_space_control_with_unknown_payload():
    sol = ur5_joint_space_control()
    failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
    assert not failed, failed
    assert abs(sol.values["m_hat_final"] - 5.0) < 0.1
    assert sol.values["fast_saturated_fraction"] > 0
    assert len(sol.figures) == 2
