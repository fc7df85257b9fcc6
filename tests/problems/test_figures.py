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


def _defects():
    """One figure per defect the lint must catch (each as a problem figure had it), and its fixed twin."""
    import numpy as np
    from matplotlib.figure import Figure

    def clipped(fixed):             # 12.8: a 3-D panel beside a 2-D one, the 2-D x label below the canvas
        fig = Figure(figsize=(6, 3))
        ax = fig.add_axes([0.1, 0.0 if not fixed else 0.2, 0.8, 0.7])
        ax.plot([0, 1], [0, 1])
        label_axes(ax, "x [m]", "y [m]")
        return fig

    def raw_tex(fixed):             # 10.4/10.5/10.10/10.11: "x̂_{c,o}" shown as typed
        fig, ax = subplots(figsize=(5, 3))
        ax.plot([0, 1], [0, 1])
        label_axes(ax, "t [s]", r"$\hat{x}_{c,o}$ [m]" if fixed else "x̂_{c,o} [m]")
        return fig

    def marked_outside(fixed):      # 12.12: the goal beyond the plotted range
        fig, ax = subplots(figsize=(5, 3))
        ax.plot([0, 10], [0, 1], label="path")
        ax.plot(12, 0.5, "g*", label="goal")
        ax.set_xlim(-0.5, 12.5 if fixed else 11)
        label_axes(ax, "x [m]", "y [m]")
        return fig

    def categorical(fixed):         # 12.4: a component map without a key
        fig, ax = subplots(figsize=(5, 3))
        labels = np.repeat(np.arange(4), 25).reshape(10, 10)
        image = ax.imshow(labels, cmap="Pastel1")
        if fixed:
            fig.colorbar(image, ax=ax, label="component [-]")
        label_axes(ax, "q₁ [rad]", "q₂ [rad]")
        return fig

    def legend_on_text(fixed):      # 12.13: the legend over the cells' values
        fig, ax = subplots(figsize=(5, 4))
        ax.plot([0, 6], [0, 6], label="path")
        ax.plot([0, 6], [6, 0], "--", label="other")
        for i in range(7):
            for j in range(7):
                ax.text(i, j, f"{i + j:.1f}", ha="center", va="center", fontsize=7)
        label_axes(ax, "column [cells]", "row [cells]", legend="lower left")
        if fixed:
            ax.get_legend().remove()
            fig.legend(*ax.get_legend_handles_labels(), loc="upper right")
        return fig

    def linear_decay(fixed):        # 10.4: ‖e_s‖ decaying by 0.84 a step drawn on a linear axis
        fig, ax = subplots(figsize=(5, 3))
        k = np.arange(41)
        (ax.semilogy if fixed else ax.plot)(k * 1e-3, 0.37 * 0.84 ** k)
        label_axes(ax, "t [s]", "‖e_s‖ [-]")
        return fig

    return {"cut by the canvas": clipped, "not rendered": raw_tex, "outside the axes' limits": marked_outside,
            "without a colour key": categorical, "covers": legend_on_text, "decades on a linear axis": linear_decay}


@pytest.mark.parametrize("message", list(_defects()))
def test_the_lint_catches_each_defect_of_the_chapter_9_12_figures_and_passes_its_fix(message):
    from problems.registry import Solution

    # laid out as a problem's figure (the clipped one is placed by hand: no tight layout)
    make = lambda fixed: Solution().figure(_defects()[message](fixed), tight=message != "cut by the canvas")  # noqa
    found = lint_figure(make(False))
    assert any(message in m for m in found), found
    assert lint_figure(make(True)) == []


def test_the_lint_sees_legend_text_too_small_for_the_report():
    """A 14-inch figure is shown at 1080 px of its 1260: a 6-pt legend reads 6.4 px, below the 8 px the lint asks;
    at 8 pt it reads 8.6 px."""
    for size, expected in ((6, 1), (8, 0)):
        fig, ax = subplots(figsize=(14, 3))
        ax.plot([0, 1], [0, 1], label="x")
        ax.plot([0, 1], [1, 0], label="y")
        label_axes(ax, "t [s]", "x [m]", legend=False)
        ax.legend(fontsize=size)
        found = [m for m in lint_figure(fig) if "legend text" in m]
        assert len(found) == expected, found
