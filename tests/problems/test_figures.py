"""The result figures of the catalogues (Fig. S2.x … S8.x) have a problem figure, and the figure lint
(``figure_lint.py``, applied to every problem in ``test_all_problems.py``) sees what a reader misses."""

import re
from pathlib import Path

import pytest

from problems.common import label_axes, subplots
from tests.problems.figure_lint import lint_figure

ROOT = Path(__file__).resolve().parents[2]
SPEC = Path("/work/shared/spec")
# Result figures that are block diagrams: their transfer functions are checked (8.7), not drawn.
BLOCK_DIAGRAMS = {"S8.5", "S8.6", "S8.7"}


def _result_figures() -> set[str]:
    """The result figures named by the catalogues; the catalogues live outside the repository, so a
    machine without them skips (visibly) rather than checking nothing."""
    if not SPEC.is_dir():
        pytest.skip(f"catalogue folder {SPEC} is absent: the result figures cannot be listed")
    found = set()
    for name in ("ch02-04.md", "ch05-08.md"):
        path = SPEC / name
        assert path.is_file(), f"catalogue {path} is missing from {SPEC}"
        for line in path.read_text(encoding="utf-8").splitlines():
            if "Results" in line:
                for a, b in re.findall(r"S([2-8]\.\d+)(?:[–-]S[2-8]\.(\d+))?", line):
                    found.add(f"S{a}")
                    if b:  # a range "S8.5–S8.7"
                        chapter, first = a.split(".")
                        found.update(f"S{chapter}.{k}" for k in range(int(first), int(b) + 1))
    return found


def test_every_result_figure_of_the_catalogues_has_a_problem_figure():
    source = "\n".join(p.read_text(encoding="utf-8") for p in sorted((ROOT / "problems").glob("ch0[2-8]*.py")))
    drawn = set(re.findall(r"S[2-8]\.\d+", source))
    wanted = _result_figures()
    assert wanted, f"no result figure found in the catalogues of {SPEC}: the parser no longer matches them"
    missing = sorted(wanted - drawn - BLOCK_DIAGRAMS)
    assert not missing, f"result figures of the catalogues without a problem figure: {missing}"


def test_the_lint_sees_missing_units_and_legends():
    fig, (a, b) = subplots(1, 2)
    a.plot([0, 1], [0, 1])
    a.plot([0, 1], [1, 0], "--")
    label_axes(a, "t [s]", "position", legend=False)
    b.plot([0, 1], [0, 1], label="x")
    b.plot([0, 1], [1, 0], label="y")
    label_axes(b, "t [s]", "x (m)")
    found = lint_figure(fig)
    assert len(found) == 2 and "no unit" in found[0] and "no legend" in found[1]
