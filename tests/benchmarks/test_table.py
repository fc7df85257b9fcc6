"""``python -m benchmarks``: every script collected, the table's target logic, its JSON and Markdown."""

import ast
import json
import sys
import types
from pathlib import Path

import pytest

import benchmarks.__main__ as bench_main
from benchmarks import benchtools

BENCH_DIR = Path(bench_main.__file__).parent


def test_every_bench_script_is_collected_and_has_rows():
    """A new bench_*.py cannot be left out of the table; each defines rows() and stays runnable alone."""
    scripts = {p.stem.removeprefix("bench_") for p in BENCH_DIR.glob("bench_*.py")}
    assert scripts == set(bench_main.SCRIPTS)
    for name in scripts:
        tree = ast.parse((BENCH_DIR / f"bench_{name}.py").read_text())
        functions = {node.name for node in tree.body if isinstance(node, ast.FunctionDef)}
        assert "rows" in functions, name
        assert any(isinstance(node, ast.If) and "__main__" in ast.unparse(node.test) for node in tree.body), name


@pytest.mark.parametrize("row, expected", [
    (dict(rmpc=1.4, reference=1.0, target=("ratio<=", 1.5)), True),
    (dict(rmpc=1.6, reference=1.0, target=("ratio<=", 1.5)), False),
    (dict(rmpc=25.0, reference=None, target=(">=", 20.0)), True),
    (dict(rmpc=19.9, reference=None, target=(">=", 20.0)), False),
    (dict(rmpc=0.0, reference=None, target=("<=", 0.0)), True),
    (dict(rmpc=1.0, reference=None, target=None), None),
    (dict(rmpc=1.0, reference=None, target=("ratio<=", 1.0)), None),   # a ratio target without a reference
])
def test_met(row, expected):
    assert benchtools.met(row) is expected


def test_script_names():
    assert bench_main.script_name("bench_wrappers.py") == "wrappers"
    assert bench_main.script_name("wrappers") == "wrappers"
    with pytest.raises(Exception, match="no benchmark 'nope'"):
        bench_main.script_name("nope")


def test_main_collects_rows_passes_quick_and_writes_json_and_markdown(tmp_path, monkeypatch, capsys):
    """Two fake scripts — one taking ``quick``, one raising — give one table; the error is reported, not fatal."""
    calls = []

    def rows(quick=False):
        calls.append(quick)
        return [dict(measurement="fake | call [µs]", rmpc=1.2, reference=1.0, ref_name="raw", target=("ratio<=", 1.5)),
                dict(measurement="fake loop [simulated s / wall s]", rmpc=10.0, reference=None, target=(">=", 20.0))]

    def broken():
        raise RuntimeError("no peer here")

    monkeypatch.setitem(sys.modules, "bench_fake", types.SimpleNamespace(rows=rows))
    monkeypatch.setitem(sys.modules, "bench_broken", types.SimpleNamespace(rows=broken))
    monkeypatch.setattr(bench_main, "SCRIPTS", ("fake", "broken"))
    assert bench_main.main(["--quick", "--out", str(tmp_path)]) == 1
    assert calls == [True]
    out = capsys.readouterr()
    assert "fake | call [µs]" in out.out and "no peer here" in out.err
    data = json.loads((tmp_path / "benchmarks.json").read_text())
    assert [r["met"] for r in data["rows"]] == [True, False]
    assert data["rows"][0]["ratio"] == pytest.approx(1.2)
    assert "no peer here" in data["machine"]["errors"]["broken"]
    md = (tmp_path / "benchmarks.md").read_text().splitlines()
    assert md[2].startswith("| measurement |")
    assert md[4] == "| fake / call [µs] | 1.2 | 1 | 1.20 | ratio≤ 1.5 | yes | raw |"
    assert md[5].endswith("| ≥ 20 | **no** |  |")
    assert bench_main.main(["--only", "fake", "--out", str(tmp_path / "t.md")]) == 0
    assert calls == [True, False]
    assert (tmp_path / "t.md").read_text().count("\n| fake") == 2


def test_json_rows_write_numpy_scalars_as_plain_numbers():
    import numpy as np

    rows = [dict(measurement="x [ms]", rmpc=np.float64(2.0), reference=np.float64(1.0), ref_name="",
                 target=("ratio<=", 2.0), met_by_hand=np.bool_(True))]
    data = json.loads(json.dumps(benchtools.json_rows(rows)))
    assert data[0]["rmpc"] == 2.0 and data[0]["met_by_hand"] is True and data[0]["met"] is True
