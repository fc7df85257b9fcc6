"""Every registered problem solves and every one of its checks passes and can fail; the registry's contract."""

import matplotlib.pyplot as plt
import numpy as np
import pytest

from problems.format import is_quantity
from problems.registry import KINDS, REFERENCES, all_problems
from tests.problems.figure_lint import lint_figure

PROBLEMS = [p for p in all_problems() if p.chapter != 99]  # 99.x: test_cli.py's own
#: Chapters whose every check must name the kind of its reference and whose problems declare their data.
CLASSIFIED_CHAPTERS = range(2, 13)
#: Chapters whose every numeric value carries a unit ("1" when dimensionless).
UNIT_CHAPTERS = range(2, 13)

#: The problems that declare no datum (``sol.given``): derivations proved symbolically or checked on random
#: samples (angles, rotations, postures, motors, point clouds...), whose statement gives no numbers. Every
#: other problem declares the data it takes from the manual or the companion files.
NO_DATA = frozenset({
    "2.1", "2.2", "2.3", "2.4", "2.5", "2.6", "2.7", "2.8", "2.9", "2.10",   # rotations at random angles
    "2.12", "2.16", "2.19",                                                # random postures, infinitesimal angles
    "3.1", "3.2", "3.6", "3.10", "3.11", "3.12", "3.13", "3.16", "3.17", "3.18", "3.19", "3.20",
    "4.4",                                                                 # spline systems of random size
    "5.4",                                                                 # random hydraulic parameters
    "7.1", "7.3", "7.5", "7.8", "7.9", "7.10",                             # random inertial parameters
    "8.1", "8.2", "8.3", "8.8",                                            # random drives
    "9.1", "9.5", "9.6", "9.8", "9.9",                                     # random matrices, symbols
    "10.2", "10.3", "10.6", "10.7", "10.12",                               # random scenes, poses, point clouds
    "11.1", "11.3", "11.10", "11.11", "11.12",                             # random lengths, symbols, boundary values
    "12.1",                                                                # the model alone
})


def _same_side(a, b) -> bool:
    """The two sides of a check are one object (or share memory): the check compares a value with itself."""
    if a is None or b is None:
        return False
    if a is b:
        return True
    return isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.size > 0 and np.shares_memory(a, b)


def _is_echo(check, values: dict) -> bool:
    """Both sides equal (exactly) the recorded value whose name the check bears: a value echoed back
    under its own name (a check named "x" comparing the recorded x with itself or a copy)."""
    if check.actual is None or check.expected is None or check.name not in values:
        return False
    v = values[check.name]
    try:
        return bool(np.array_equal(np.asarray(v), np.asarray(check.actual))
                    and np.array_equal(np.asarray(v), np.asarray(check.expected)))
    except (TypeError, ValueError):
        return False


def _given_data(data: dict):
    """(name, value) of every datum of ``sol.given``; a dict datum (a motor's parameters) gives one entry
    per field, named ``datum.field``."""
    for name, v in data.items():
        if isinstance(v, dict):
            yield from _given_data({f"{name}.{k}": w for k, w in v.items()})
        else:
            yield name, v


#: References under which a check may expect a datum of the problem with an equality: the actual side is
#: a simulation of the closed loop, which reaches the set point only if it works, or the designed system
#: evaluated on a separate path (its poles or gains by python-control), which meets the requirement only
#: if the design is right.
MAY_EXPECT_A_DATUM = ("simulation vs prediction", "specification met")


def _echoes_given(check, data: dict) -> str | None:
    """The given datum (``sol.given``) that a check expects back, or None. The rule:

    * a check *echoes an input* when it is an equality (``relation == "=="``: ``check_close`` and hand-
      written comparisons) whose ``expected`` is a datum of the problem or a field of a datum given as a
      dict (a motor's parameters): the same object, or for arrays of several numbers, equal numbers of the
      same shape (a copy, a list typed again); e.g. a check that the trajectory ends at q_f, with q_f of the
      data on the expected side;
    * whatever the reference kind says, a ``"property"`` or ``"closed form"`` included: a property written
      as an equality with a datum states the input back unless something independent produced the actual;
    * except under :data:`MAY_EXPECT_A_DATUM`: a closed-loop simulation reaching a given set point
      (``"simulation vs prediction"``), or a designed system evaluated on a separate path meeting the
      requirement it was designed for (``"specification met"``: ζ of the poles computed by python-control),
      is evidence: it can fail to get there;
    * bounds (``relation`` ``"<="``, ``">="``, …: a torque limit, a settling-time requirement of the data)
      and error measures (``"error"``, expected 0) never echo: the actual side can cross the bound.
    A scalar matches by identity only, and an expected side of zeros never: equal numbers are too common to
    tell an echo from a coincidence (a path of 1 m and t_f = 1 s; 0.9 − 0.1 = 0.8 and p = [0.8, …]), and a
    null residual is no datum. So a single entry of a given array is not matched either."""
    if check.expected is None or check.relation != "==" or check.reference in MAY_EXPECT_A_DATUM:
        return None
    given = list(_given_data(data))
    for name, v in given:
        if check.expected is v:
            return name
    try:
        e = np.asarray(check.expected)
    except (TypeError, ValueError):
        return None
    if e.dtype.kind not in "biufc" or e.size < 2 or not np.any(e):
        return None
    for name, v in given:
        try:
            g = np.asarray(v)
        except (TypeError, ValueError):
            continue
        if g.dtype.kind in "biufc" and e.shape == g.shape and np.array_equal(e, g):
            return name
    return None


def dishonest_checks(sol) -> list[str]:
    """The checks of a solution that cannot fail by construction (detectable cases)."""
    bad = []
    for c in sol.checks:
        if c.reference is not None and c.reference not in REFERENCES:
            bad.append(f"{c.name}: unknown reference {c.reference!r}")
        if _same_side(c.actual, c.expected):
            bad.append(f"{c.name}: actual and expected are the same object")
        elif _is_echo(c, sol.values):
            bad.append(f"{c.name}: both sides equal the recorded value it is named after")
        if (given := _echoes_given(c, getattr(sol, "data", {}))) is not None:
            bad.append(f"{c.name}: expects the given datum {given!r} (an input echoed back)")
    return bad


def test_the_honesty_lint_catches_a_value_compared_with_itself():
    from problems.registry import Solution

    sol = Solution()
    x = np.array([0.3, 0.7])
    sol.value("x", x)
    sol.check_close("x == x", x, x)
    sol.check_close("view", x, x[:])
    sol.value("x echoed", x)
    sol.check_close("x echoed", x.copy(), x.copy())
    sol.check_close("independent", np.array([0.3, 0.7]), np.array([0.1 + 0.2, 0.7]), atol=1e-12)
    assert len(dishonest_checks(sol)) == 3


def test_the_echo_lint_catches_an_input_expected_back():
    from problems.registry import Solution

    sol = Solution()
    q = sol.given("q", np.array([0.0, 2.0, 3.0]), unit="rad")
    t_f = sol.given("t_f", 2.0, unit="s")
    sol.check_close("echo: q", np.array([0.0, 2.0, 3.0]), q, reference="closed form")
    sol.check_close("echo: equal copy of q", q + 0.0, [0.0, 2.0, 3.0], reference="manual number")
    sol.check_close("echo: t_f", np.sqrt(4.0), t_f, reference="closed form")
    sol.check_close("echo: a property stated as an equality with q", q + 0.0, q, reference="property")
    sol.check("echo: by hand", True, actual=np.float64(2.0), expected=t_f, reference="manual number")
    drive = sol.given("drive", dict(I=0.01, kt=0.5, kr=[1.0, 2.0]))
    sol.check_close("echo: a field of a given dict", np.float64(0.5), drive["kt"], reference="manual number")
    sol.check_close("echo: a field of a given dict, typed again", np.float64(2.0) * np.array([0.5, 1.0]), [1, 2],
                    reference="manual number")
    # not echoes: an independent value, a bound of the data, an error measure, a simulation reaching the datum
    sol.check_close("independent", np.sqrt(5.0), np.float64(1.0) + 1.2, atol=0.1, reference="closed form")
    sol.check_bound("peak ≤ t_f", 1.5, t_f)
    sol.check_error("error", 1e-12, 1e-9, reference="closed form")
    sol.check_close("simulated end point = q", q + 1e-9, q, atol=1e-6, reference="simulation vs prediction")
    sol.check_close("zero is not a datum", np.float64(0.0), 0.0, reference="closed form")
    sol.check_close("an entry of q equal by coincidence", np.float64(0.9) - 0.1 + 2.2, 3.0, reference="closed form")
    sol.check_close("a scalar equal to t_f by coincidence (a 2 m path)", np.float64(2.0), np.hypot(1.2, 1.6),
                    reference="closed form")
    sol.check_close("requirement met by the designed system", np.float64(2.0) + 1e-12, t_f, atol=1e-9,
                    reference="specification met")
    assert sol.data == {"q": q, "t_f": 2.0, "drive": drive} and sol.units["t_f"] == "s"
    assert [b.split(": expects")[0] for b in dishonest_checks(sol)] == [
        "echo: q", "echo: equal copy of q", "echo: t_f", "echo: a property stated as an equality with q",
        "echo: by hand", "echo: a field of a given dict", "echo: a field of a given dict, typed again"]
    assert all(c.passed for c in sol.checks)


def test_a_bound_records_its_relation_and_can_fail():
    from problems.registry import Solution

    sol = Solution()
    assert sol.check_bound("below", 1.0, 2.0) and not sol.check_bound("above", 3.0, 2.0)
    assert not sol.check_bound("NaN", float("nan"), 2.0) and sol.check_bound("≥", 3.0, 2.0, ">=")
    assert [c.relation for c in sol.checks] == ["<=", "<=", "<=", ">="]
    with pytest.raises(ValueError, match="relation"):
        sol.check("x", True, relation="≈")


@pytest.mark.parametrize("prob", PROBLEMS, ids=[p.id for p in PROBLEMS])
def test_problem_checks_pass(prob):
    sol = prob.solve()
    try:
        assert sol.checks, f"problem {prob.id} has no checks"
        failed = [f"{c.name}: {c.detail}" for c in sol.checks if not c.passed]
        assert not failed, f"problem {prob.id} failed checks: {failed}"
        bad = dishonest_checks(sol)
        assert not bad, f"problem {prob.id} has checks that cannot fail: {bad}"
        if prob.chapter in CLASSIFIED_CHAPTERS:
            unnamed = [c.name for c in sol.checks if c.reference is None]
            assert not unnamed, f"problem {prob.id}: checks without a reference kind (REFERENCES): {unnamed}"
            assert bool(sol.data) != (prob.id in NO_DATA), (
                f"problem {prob.id}: " + ("listed in NO_DATA but declares data" if sol.data else
                                          "declares no data: sol.given(name, value, unit) for each datum"))
        if prob.chapter in UNIT_CHAPTERS:
            bare = [name for name, v in sol.values.items() if is_quantity(v) and not sol.units.get(name)]
            assert not bare, f"problem {prob.id}: values without a unit (sol.value(name, v, unit=...), '1' if none): {bare}"
        unreadable = [m for fig in sol.figures for m in lint_figure(fig)]
        assert not unreadable, f"problem {prob.id}: figures a reader cannot use: {unreadable}"
    finally:
        for fig in sol.figures:
            plt.close(fig)


def test_every_problem_is_documented():
    """Not a behaviour test: one lint over all problems (docstring paraphrasing the problem, kind, title)."""
    missing = [p.id for p in PROBLEMS if len((p.function.__doc__ or "").strip()) <= 20 or p.kind not in KINDS
               or not p.title]
    assert not missing, f"problems without a docstring, kind or title: {missing}"
