"""A rigid wall (Pinocchio's constrained dynamics) as the limit of the compliant wall (beyond the book)."""


from examples.rigid_contact import rigid_versus_compliant


def test_compliant_contact_tends_to_the_rigid_one():
    sol = rigid_versus_compliant(stiffnesses=(1e3, 1e5), duration=0.6)
    failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
    assert not failed, failed
    dev = sol.values["mean_force_deviation_from_rigid"]
    assert dev[1] < 0.1 * dev[0]
    assert sol.values["constraint_violation_max"] < 1e-9
