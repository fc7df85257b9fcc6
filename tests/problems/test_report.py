"""A solution renders itself (Jupyter), the report module, the shared figure helpers, no backend at import."""

import base64
import subprocess
import sys

import numpy as np
import pytest

from problems.common import label_axes, subplots
from problems.registry import Solution
from problems.report import solution_dict, solution_html


def _solution() -> Solution:
    sol = Solution(id="0.1", title="A <small> test", kind="numeric")
    sol.value("K_P", np.array([1.0, 2.5]))
    sol.check_close("passes", 1.0, 1.0)
    sol.check("fails", False, "on purpose")
    fig, ax = subplots(figsize=(3, 2))
    ax.plot([0, 1], [0, 1], label="a")
    ax.plot([0, 1], [1, 0], label="b")
    label_axes(ax, "t [s]", "q [rad]")
    sol.figure(fig, "a figure")
    return sol


def test_repr_html_has_title_values_checks_and_inline_png():
    sol = _solution()
    text = sol._repr_html_()
    assert "0.1 — A &lt;small&gt; test" in text                      # title, escaped
    assert "<th>K_P</th>" in text and "[1, 2.5]" in text              # values table, 4 significant digits
    assert "✔ <b>passes</b>" in text and "✘ <b>fails</b>" in text     # checks with pass/fail
    assert 'class="fail"' in text                                     # one check failed → section fails
    src = text.split('src="data:image/png;base64,')[1].split('"')[0]
    assert base64.b64decode(src)[:8] == b"\x89PNG\r\n\x1a\n"           # a real PNG, inline


def test_report_section_links_figure_files():
    sol = _solution()
    d = solution_dict(sol, ["0_1_1.png"]) | {"passed": False, "seconds": 0.5}
    text = solution_html(d, ["figures/0_1_1.png"])
    assert '<img src="figures/0_1_1.png"' in text and "[numeric, 0.5 s]" in text


def test_attached_figure_is_laid_out_and_left_without_a_layout_engine():
    """``Solution.figure`` applies the tight layout once: the 2×2 axes' labels and titles no longer overlap,
    and no layout engine stays on the figure (with one, each ``savefig`` draws the figure twice)."""
    def crowded():
        fig, axes = subplots(2, 2, figsize=(4, 3))
        for ax in axes.flat:
            ax.plot([0, 1], [0, 1000])
            label_axes(ax, "t [s]", "q [rad]", title="joint position")
        return fig

    def overlaps(fig) -> bool:
        renderer = fig.canvas.get_renderer()
        boxes = [ax.get_tightbbox(renderer) for ax in fig.axes]
        return any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])

    assert overlaps(crowded())                       # the default subplot parameters crowd them
    fig = Solution(id="0.1", title="t", kind="numeric").figure(crowded(), "crowded")
    assert not overlaps(fig)
    assert fig.get_layout_engine() is None


def test_label_axes_adds_a_legend_only_for_several_lines():
    fig, (a, b) = subplots(1, 2)
    a.plot([0, 1], label="one")
    b.plot([0, 1], label="one")
    b.plot([1, 0], label="two")
    label_axes(a, "t [s]", "y [m]")
    label_axes(b, "t [s]", "y [m]")
    assert a.get_legend() is None and b.get_legend() is not None
    assert a.get_xlabel() == "t [s]" and b.get_ylabel() == "y [m]"


def test_chapter_modules_leave_the_backend_alone():
    """Importing every chapter module must not pick a matplotlib backend (that is a notebook's choice;
    python-control imports pyplot, which leaves the choice open until a figure is shown)."""
    code = ("import matplotlib; from problems.registry import load_all; load_all(); "
            "print(matplotlib.rcParams._get_backend_or_none())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={"PATH": "", "PYTHONPATH": ":".join(sys.path)}).stdout.split()
    assert out == ["None"]


def test_check_error_fails_above_the_tolerance_and_on_nan():
    sol = Solution()
    assert sol.check_error("small", 1e-13, 1e-12)
    assert not sol.check_error("large", 2e-12, 1e-12)
    assert not sol.check_error("nan", float("nan"), 1.0)
    assert [c.passed for c in sol.checks] == [True, False, False] and "2e-12" in sol.checks[1].detail


def test_report_page_has_chapters_statements_captions_and_a_fresh_figures_folder(tmp_path):
    import json

    from problems.registry import Problem
    from problems.report import write_report

    def one_figure() -> Solution:
        """Find the answer of the test problem; given a = 1 m.

        More detail that is not the statement."""
        sol = _solution()
        sol.value("a", 1.0, unit="m")
        return sol

    stale = tmp_path / "figures" / "stale_from_an_earlier_run.png"
    stale.parent.mkdir(parents=True)
    stale.write_bytes(b"")
    summary = write_report([Problem("0.1", "A test", "numeric", one_figure)], tmp_path)
    page = (tmp_path / "index.html").read_text()
    assert not stale.exists()                                            # figures folder cleared
    assert '<h2 id="ch0">Chapter 0' in page and 'href="#top"' in page     # chapter heading, back to top
    assert "Find the answer of the test problem; given a = 1 m." in page and "More detail" not in page
    assert "<figcaption>Fig. 0.1.1: a figure</figcaption>" in page        # captioned
    assert '<a href="figures/0_1_1_a_figure.png" target="_blank">' in page  # readable name, click to enlarge
    assert "summary.json" in page and "1 m" in page
    written = json.loads((tmp_path / "summary.json").read_text())[0]
    assert written["units"]["a"] == "m" and set(written["units"]) >= set(written["values"])   # an entry per value
    assert summary[0]["statement"].startswith("Find the answer")


def test_checks_record_both_sides_and_their_reference():
    from problems.report import solution_dict

    sol = Solution(id="0.1", title="t", kind="numeric")
    sol.check_close("x", [1.0, 2.0], [1.0, 2.0 + 1e-12], atol=1e-9, reference="closed form")
    sol.check("monotone", True)
    sol.check_error("fd", 1e-8, 1e-6, reference="finite differences")
    sol.check_close("big", np.zeros(100), np.zeros(100))
    rows = solution_dict(sol)["checks"]
    assert [r["reference"] for r in rows] == ["closed form", "property", "finite differences", None]
    assert rows[0]["actual"] == [1.0, 2.0] and rows[2]["actual"] == 1e-8 and rows[3]["actual"] == "array (100,)"
    assert {"name", "passed", "detail", "actual", "expected", "reference"} <= set(rows[0])
    with pytest.raises(ValueError, match="reference"):
        sol.check_close("y", 1.0, 1.0, reference="manual")
    assert "closed form</span>" in solution_html(solution_dict(sol))


def test_captions_name_the_manuals_figure_once_and_statements_show_no_markup():
    from problems.format import statement_text
    from problems.report import figure_caption, solution_html

    assert figure_caption("12.7", 0, "Fig. S12.3 — PRM for a 2R planar manipulator") == \
        "Fig. 12.7.1 (the manual's Fig. S12.3): PRM for a 2R planar manipulator"
    assert figure_caption("8.10", 1, "joint errors") == "Fig. 8.10.2: joint errors"
    d = {"id": "0.1", "title": "t", "kind": "numeric", "values": {}, "checks": [], "figures": [],
         "statement": "Compared with ``urdf/scara.urdf`` by :func:`~rigid_body.kinematics.direct_kinematics`."}
    page = solution_html(d)
    assert "<code>urdf/scara.urdf</code>" in page and "<code>direct_kinematics</code>" in page
    assert "``" not in page and ":func:" not in page
    assert statement_text(d["statement"]) == "Compared with urdf/scara.urdf by direct_kinematics."


def test_a_rerun_removes_stale_animation_pages(tmp_path):
    from problems.registry import Problem
    from problems.report import write_report

    stale = tmp_path / "animations" / "9.99_1.html"
    stale.parent.mkdir(parents=True)
    stale.write_text("<html></html>")
    write_report([Problem("0.1", "A test", "numeric", lambda: _solution())], tmp_path)
    assert not stale.exists()


def test_the_report_shows_the_compilers_progress(capsys):
    """The first report on a machine compiles its loops (20–25 s): each build is a line on stderr naming the problem."""
    import logging

    from problems import report

    logger = logging.getLogger("rmpc.compiler")
    before = [h for h in logger.handlers if not getattr(h, "rmpc_report", False)]   # an earlier report's: replaced
    for handler in set(logger.handlers) - set(before):
        logger.removeHandler(handler)
    try:
        report.show_compiler_progress()
        report._SOLVING[0] = "10.8"
        logger.info("compiling %s (C code)", "rollout")
    finally:
        report._SOLVING[0] = ""
        for handler in [h for h in logger.handlers if h not in before]:
            logger.removeHandler(handler)
    assert "10.8 compiling rollout (C code)" in capsys.readouterr().err
