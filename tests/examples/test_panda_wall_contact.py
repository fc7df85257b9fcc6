"""The Panda on a stepped wall with friction: impedance and hybrid force/motion control (beyond the book)."""


from examples.panda_wall_contact import panda_wall_contact


def test_panda_on_a_stepped_wall_with_friction():
    sol = panda_wall_contact()
    failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
    assert not failed, failed
    v = sol.values
    assert v["hybrid_force_error_sliding"] < 0.5
    assert 2.6 < v["hybrid_contact_regained_at"] < 2.9 and 1.9 < v["hybrid_contact_lost_at"] < 2.1
    assert abs(v["impedance_force_after_step"] - 10.48) < 0.1
    assert abs(v["hybrid_friction_force_sliding"] - 6.0) < 0.1
    assert len(sol.figures) == 2
