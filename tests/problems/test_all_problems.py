"""Every registered problem solves and every one of its checks passes and can fail; the registry's contract."""

import matplotlib.pyplot as plt
import numpy as np
import pytest

from problems.registry import KINDS, REFERENCES, all_problems
from tests.problems.figure_lint import lint_figure

PROBLEMS = [p for p in all_problems() if p.chapter != 99]  # 99.x: test_cli.py's own
#: Chapters whose every check must name the kind of its reference (9–12 not yet classified).
CLASSIFIED_CHAPTERS = range(2, 9)


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


def _echoes_given(check, data: dict) -> str | None:
    """The name of the given datum (``sol.given``) that a check's ``expected`` is (same object or an
    equal array): the input echoed back. A ``"property"`` (a specification met, an interpolation
    condition) names the data it is about, so it is exempt."""
    if check.expected is None or check.reference == "property":
        return None
    for name, v in data.items():
        if check.expected is v:
            return name
        try:
            e, g = np.asarray(check.expected), np.asarray(v)
            if e.ndim >= 1 and e.size > 1 and e.dtype.kind in "biufc" and e.shape == g.shape and np.array_equal(e, g):
                return name
        except (TypeError, ValueError):
            continue
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
    sol.check_close("interpolation condition", q + 0.0, q, reference="property")
    sol.check_close("independent", np.sqrt(4.0), np.float64(1.0) + 1.0, reference="closed form")
    assert sol.data == {"q": q, "t_f": 2.0} and sol.units["t_f"] == "s"
    assert [b.split(": expects")[0] for b in dishonest_checks(sol)] == ["echo: q", "echo: equal copy of q", "echo: t_f"]


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
