"""`rmpc report -j N`: the same report from N processes, in the same order."""

import json
import re

from problems import cli
from problems.registry import get
from problems.report import write_report


def _without_times(text: str) -> str:
    return re.sub(r'"seconds": [0-9.e-]+|, [0-9.]+ s\]', "", text)


def test_parallel_report_equals_the_sequential_one(tmp_path):
    problems = [get(pid) for pid in ("2.4", "2.1", "2.3", "2.2")]  # not in the book's order: order is kept
    one = write_report(problems, tmp_path / "one", jobs=1)
    two = write_report(problems, tmp_path / "two", jobs=2)
    assert [d["id"] for d in two] == ["2.4", "2.1", "2.3", "2.2"]
    for d in one + two:
        d.pop("seconds")
    assert one == two
    for name in ("summary.json", "index.html"):
        texts = [_without_times((tmp_path / run / name).read_text()) for run in ("one", "two")]
        assert texts[0] == texts[1]
    assert sorted(p.name for p in (tmp_path / "one" / "figures").iterdir()) == \
        sorted(p.name for p in (tmp_path / "two" / "figures").iterdir())
    assert json.loads((tmp_path / "two" / "summary.json").read_text())[0]["id"] == "2.4"


def test_jobs_must_be_a_positive_count(capsys):
    assert cli.main(["report", "-j", "0", "--chapter", "2"]) == 2
    assert "-j" in capsys.readouterr().err
