"""The `rmpc` command line contract of ARCHITECTURE.md."""

import json
import os
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
    assert set(data) >= {"id", "title", "kind", "values", "checks", "figures", "passed", "seconds", "units"}
    assert data["passed"] is False and data["seconds"] >= 0
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


# --------------------------------------------------------------------------------------------
# Bad input: exit 2, one line on stderr, no traceback, before any work (subprocess, as a user runs it)
# --------------------------------------------------------------------------------------------

ROOT = Path(__file__).resolve().parents[2]


def _run(*args, **kwargs):
    return subprocess.run([sys.executable, "-m", "problems.cli", *args], capture_output=True, text=True,
                          cwd=ROOT, **kwargs)


def _one_line_error(proc, *words):
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    for w in words:
        assert w in lines[0], lines[0]


def test_unwritable_output_directories_exit_2_before_any_work(tmp_path, capsys):
    regular = tmp_path / "file.txt"
    regular.write_text("x")
    proc = _run("solve", "2.1", "--figures", str(regular / "figs"))   # the old CLI failed after solving
    _one_line_error(proc, "--figures", "cannot write")
    assert proc.stdout == ""            # refused before solving: nothing printed
    cases = [(str(regular), "not a directory"), (str(regular / "sub"), "cannot write")]
    if os.geteuid() != 0:              # root writes anywhere: the permission case needs a user
        locked = tmp_path / "locked"
        locked.mkdir()
        locked.chmod(0o500)
        cases.append((str(locked / "r"), "cannot write"))
    for out, words in cases:
        assert cli.main(["report", "--out", out, "--chapter", "99"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--out" in err[0] and words in err[0], err


def test_unknown_chapter_exits_2():
    """The old `rmpc report --chapter 99` exited 0 with "0 passed, 0 failed"."""
    _one_line_error(_run("report", "--out", "/tmp/unused-rmpc-report", "--chapter", "99"), "chapter 99")
    assert not Path("/tmp/unused-rmpc-report/index.html").exists()


def test_closed_pipe_ends_quietly():
    """`rmpc list | head -1`: the old CLI printed a BrokenPipeError traceback."""
    proc = subprocess.Popen([sys.executable, "-m", "problems.cli", "list"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, cwd=ROOT)
    proc.stdout.readline()
    proc.stdout.close()                 # the reader goes away after one line
    err = proc.stderr.read().decode()
    proc.wait(timeout=60)
    proc.stderr.close()
    assert "Traceback" not in err and "BrokenPipeError" not in err, err


def test_a_crashing_problem_fails_in_one_line(monkeypatch, capsys):
    class Crashing:
        id, title, kind = "99.9", "crashes", "numeric"

        def solve(self):
            raise RuntimeError("boom")

    monkeypatch.setattr(cli, "get", lambda pid: Crashing())
    assert cli.main(["solve", "99.9"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["rmpc: problem 99.9 raised RuntimeError: boom"]


def test_chapter_is_accepted_as_2_02_or_ch02_and_list_filters_by_chapter(capsys):
    for spelling in ("2", "02", "ch02", "ch2"):
        assert cli.main(["list", "--chapter", spelling]) == 0
        ids = [line.split()[0] for line in capsys.readouterr().out.splitlines()]
        assert ids and all(i.startswith("2.") for i in ids), spelling
    assert cli.main(["list", "--chapter", "x2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "not a chapter" in err[0]


def test_misspelt_option_or_command_exits_2_with_the_closest_one(capsys):
    assert cli.main(["solve", "99.1", "--jsn"]) == 2       # no abbreviation, a suggestion
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "did you mean --json?" in err[0], err
    assert cli.main(["lsit"]) == 2
    assert "did you mean list?" in capsys.readouterr().err


def test_help_has_no_rst_and_documents_every_argument_and_the_exit_codes(capsys):
    for argv in (["--help"], ["solve", "--help"], ["report", "--help"], ["list", "--help"]):
        assert cli.main(argv) == 0
        text = capsys.readouterr().out
        assert "``" not in text and "exit codes: 0" in text, argv
    cli.main(["solve", "--help"])
    assert "problem's number" in capsys.readouterr().out
    cli.main(["report", "--help"])
    assert "the report's directory" in capsys.readouterr().out
    assert cli.main(["--version"]) == 0
    assert capsys.readouterr().out.startswith("rmpc ")


def test_solve_json_figures_are_paths_with_figures_else_titles(tmp_path, capsys):
    assert cli.main(["solve", "4.1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["figures"] and not any(f.endswith(".png") or f.startswith("figure ") for f in data["figures"])
    assert cli.main(["solve", "4.1", "--json", "--figures", str(tmp_path)]) == 0
    paths = json.loads(capsys.readouterr().out)["figures"]
    assert paths and all(Path(p).is_file() and Path(p).parent == tmp_path for p in paths)


def test_solve_text_rounds_to_four_digits_and_lays_matrices_out(capsys):
    assert cli.main(["solve", "99.1"]) == 1
    out = capsys.readouterr().out
    assert "  M = [[ 1  0 ]\n       [ 0  1 ]]" in out and "z = 1 + 2j" in out
    assert out.rstrip().endswith("FAIL: 1 of 2 checks")


def test_print_of_a_solution_is_the_solve_text(capsys):
    """``print(rmpc.solve(id))`` in a terminal shows what ``rmpc solve id`` prints (without the timing)."""
    from problems.registry import get

    sol = get("99.1").solve()
    assert cli.main(["solve", "99.1"]) == 1
    cli_lines = capsys.readouterr().out.rstrip().splitlines()
    text = str(sol).splitlines()
    assert text[0] == "Problem 99.1 — A test problem with a failing check [numeric]"
    assert text[1:] == cli_lines[1:] and "[FAIL] wrong" in str(sol)
    assert text[1] == "  A problem registered by the tests only: one check passes, one fails."  # the statement
    assert repr(sol).count("\n") == 0  # the one-line summary stays the repr
