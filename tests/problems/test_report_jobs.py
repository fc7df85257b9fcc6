"""`rmpc report -j N`: the same report from N processes, in the same order."""

import gc
import json
import re

from problems import cli, report
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


def test_a_second_report_takes_the_longest_problems_first(tmp_path):
    """The processes take the problems by decreasing time of the report already in ``out``; the report keeps
    the given order."""
    ids = ["2.1", "2.2", "2.3"]
    (tmp_path / "summary.json").write_text(json.dumps([{"id": "2.1", "seconds": 0.01},
                                                       {"id": "2.3", "seconds": 2.0}]))
    previous = report._previous_seconds(tmp_path)
    assert previous == {"2.1": 0.01, "2.3": 2.0}
    assert report._longest_first(ids, ["numeric"] * 3, previous) == [1, 2, 0]   # 2.2 has no time: it may be long
    summary = write_report([get(pid) for pid in ids], tmp_path, jobs=2)
    assert [d["id"] for d in summary] == ids
    assert gc.get_freeze_count() == 0          # frozen only for the fork: the caller's objects stay collectable
    assert report._previous_seconds(tmp_path).keys() == set(ids)
    (tmp_path / "summary.json").write_text("not json")
    assert report._previous_seconds(tmp_path) == {}


def test_jobs_must_be_a_positive_count(capsys):
    assert cli.main(["report", "-j", "0", "--chapter", "2"]) == 2
    assert "-j" in capsys.readouterr().err
