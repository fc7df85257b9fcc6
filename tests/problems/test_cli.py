"""The `rmpc` command line contract of ARCHITECTURE.md."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from problems import cli
from problems.registry import Solution, all_problems, problem


@problem("99.1", "A test problem with a failing check", kind="numeric")
def _failing_problem() -> Solution:
    """A problem registered by the tests only: one check passes, one fails."""
    sol = Solution()
    sol.value("M", np.eye(2))
    sol.value("z", 1 + 2j)
    sol.check_close("identity", np.eye(2), np.eye(2))
    sol.check_close("wrong", 1.0, 2.0, atol=1e-3)
    return sol


def test_to_json_converts_arrays_and_complex():
    assert cli.to_json({"A": np.eye(2), "p": [1 + 2j], "n": np.int64(3)}) == {
        "A": [[1.0, 0.0], [0.0, 1.0]], "p": [[1.0, 2.0]], "n": 3}


def test_solve_json_and_exit_code(capsys):
    assert cli.main(["solve", "99.1", "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert set(data) == {"id", "title", "kind", "values", "checks", "figures"}
    assert data["values"]["z"] == [1.0, 2.0]
    assert [c["passed"] for c in data["checks"]] == [True, False]


def test_unknown_id_exits_2_and_names_nearest(capsys):
    assert cli.main(["solve", "99.2"]) == 2
    assert "99.1" in capsys.readouterr().err


def test_check_close_fails_on_shape_and_nan():
    sol = Solution()
    assert not sol.check_close("shape", np.zeros(2), np.zeros(3))
    assert not sol.check_close("nan", np.nan, 0.0, atol=1.0)
    assert not sol.passed


def test_console_script_lists_every_problem_and_rejects_unknown_ids():
    rmpc = Path(sys.executable).parent / "rmpc"
    out = subprocess.run([str(rmpc), "list"], capture_output=True, text=True, check=True)
    listed = [line.split()[0] for line in out.stdout.splitlines()]
    assert listed == [p.id for p in all_problems() if p.chapter != 99]
    bad = subprocess.run([str(rmpc), "solve", "2.99"], capture_output=True, text=True)
    assert bad.returncode == 2 and "unknown problem id '2.99'" in bad.stderr


def test_report_writes_html_and_summary_line(tmp_path, capsys):
    code = cli.main(["report", "--out", str(tmp_path), "--chapter", "99"])
    out = capsys.readouterr().out.strip().splitlines()
    assert out[-1] == "0 passed, 1 failed" and code == 1
    html = (tmp_path / "index.html").read_text()
    assert "99.1" in html and "wrong" in html
    assert '<a class="fail" href="#p99.1"' in html
