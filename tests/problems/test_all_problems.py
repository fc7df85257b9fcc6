"""Every registered problem solves and every one of its checks passes; the registry's own contract."""

import matplotlib.pyplot as plt
import pytest

from problems.registry import KINDS, all_problems

PROBLEMS = [p for p in all_problems() if p.chapter != 99]  # 99.x: test_cli.py's own


@pytest.mark.parametrize("prob", PROBLEMS, ids=[p.id for p in PROBLEMS])
def test_problem_checks_pass(prob):
    sol = prob.solve()
    try:
        assert sol.checks, f"problem {prob.id} has no checks"
        failed = [f"{c.name}: {c.detail}" for c in sol.checks if not c.passed]
        assert not failed, f"problem {prob.id} failed checks: {failed}"
    finally:
        for fig in sol.figures:
            plt.close(fig)


@pytest.mark.parametrize("prob", PROBLEMS, ids=[p.id for p in PROBLEMS])
def test_problem_is_documented(prob):
    doc = prob.function.__doc__ or ""
    assert len(doc.strip()) > 20, f"problem {prob.id} needs a docstring paraphrasing the problem"
    assert prob.kind in KINDS and prob.title
