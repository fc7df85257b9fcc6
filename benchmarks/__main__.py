"""``python -m benchmarks``: every benchmark's measurements in one table.

Columns: measurement, rmpc, reference (raw Pinocchio, a floor, or a peer library), ratio, target, met.
Each ``bench_*.py`` stays runnable alone (``python benchmarks/bench_ik.py``); here their ``rows()`` are
collected in one run. Peers (roboticstoolbox-python, OMPL: ``pip install rmpc[bench]``) are skipped when absent.

Options: ``--only NAME`` (repeatable; ``wrappers`` or ``bench_wrappers``) runs some scripts only; ``--quick``
runs fewer repetitions/queries where a script offers it (a smoke run, noisier); ``--out PATH`` writes the
table also as JSON (``PATH.json`` or ``PATH`` ending in ``.json``) and Markdown (``.md``) — a directory gets
``benchmarks.json`` and ``benchmarks.md`` — with the machine's load, for the README to quote.
A script that raises is reported on stderr and in the JSON; the others still run (exit status 1).
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import json
import os
import platform
import sys
import time
import traceback
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))       # the scripts import benchtools directly

from benchtools import json_rows, markdown, print_rows  # noqa: E402

# In the order of the table: the wrappers and the book's algorithms, IK, trajectories, the loops, chapters 9-12, MuJoCo.
SCRIPTS = ("wrappers", "dynamics", "closed_form_ik", "ik", "trajectories", "control", "loop", "compiled", "tasks",
           "force", "vision", "wheeled", "planning", "mujoco", "mpc")


def script_name(text: str) -> str:
    """``bench_wrappers``, ``bench_wrappers.py`` or ``wrappers`` → ``wrappers`` (argparse error otherwise)."""
    name = Path(text).stem.removeprefix("bench_")
    if name not in SCRIPTS:
        raise argparse.ArgumentTypeError(f"no benchmark {text!r} (one of: {', '.join(SCRIPTS)})")
    return name


def run_script(name: str, quick: bool) -> list[dict]:
    """The rows of ``bench_<name>.py``, with ``quick`` passed where its ``rows()`` takes it."""
    rows = importlib.import_module(f"bench_{name}").rows
    params = inspect.signature(rows).parameters
    kwargs = {}
    if quick and "quick" in params:
        kwargs["quick"] = True
    return rows(**kwargs)


def machine() -> dict:
    """Where and when: the load matters on a shared machine (compare ratios, not absolute times)."""
    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    return {"date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "cpus": os.cpu_count(), "load_average": load,
            "python": platform.python_version(), "platform": platform.platform()}


def write_outputs(out: Path, rows: list[dict], info: dict) -> list[Path]:
    """The table as JSON and/or Markdown at ``out`` (see the module docstring); the paths written."""
    if out.suffix in (".json", ".md"):
        paths = [out]
    else:
        out.mkdir(parents=True, exist_ok=True)
        paths = [out / "benchmarks.json", out / "benchmarks.md"]
    for path in paths:
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".json":
            path.write_text(json.dumps({"machine": info, "rows": json_rows(rows)}, indent=1, ensure_ascii=False))
        else:
            load = info["load_average"]
            load_s = f", load average {load[0]:.2f}" if load else ""
            scripts = ", ".join(info["scripts"]) + (" (--quick)" if info["quick"] else "")
            path.write_text(f"Measured {info['date']} on {info['cpus']} CPUs{load_s}, Python {info['python']}; "
                            f"{scripts}.\n\n" + markdown(rows))
    return paths


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.split("\n")[0])
    parser.add_argument("--only", action="append", type=script_name, metavar="NAME",
                        help=f"run only this script (repeatable): {', '.join(SCRIPTS)}")
    parser.add_argument("--quick", action="store_true", help="fewer repetitions and queries (a smoke run)")
    parser.add_argument("--out", type=Path, help="also write the table as JSON/Markdown (file or directory)")
    args = parser.parse_args(argv)
    names = [n for n in SCRIPTS if args.only is None or n in args.only]
    info = machine() | {"scripts": names, "quick": args.quick, "errors": {}, "seconds": {}}
    rows: list[dict] = []
    for name in names:
        print(f"running bench_{name} ...", file=sys.stderr, flush=True)
        t0 = time.perf_counter()
        try:
            rows += run_script(name, args.quick)
        except Exception:  # one broken script does not hide the others' rows
            info["errors"][name] = traceback.format_exc()
            print(f"bench_{name} failed:\n{info['errors'][name]}", file=sys.stderr)
        info["seconds"][name] = round(time.perf_counter() - t0, 1)
    info["load_average_end"] = machine()["load_average"]
    print()
    print_rows(rows)
    if args.out is not None:
        for path in write_outputs(args.out, rows, info):
            print(f"wrote {path}", file=sys.stderr)
    return 1 if info["errors"] else 0


if __name__ == "__main__":
    sys.exit(main())
