"""The ``rmpc`` command line: ``rmpc list``, ``rmpc solve ID [--json] [--figures DIR]``, ``rmpc report``.

Exit codes: 0 every check passed, 1 a check failed, 2 bad input (unknown id, bad arguments).
This module parses the arguments; the JSON and the HTML report are built by :mod:`problems.report`.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from problems.registry import all_problems, get
from problems.report import save_figures, solution_dict, to_json, write_report

__all__ = ["main", "to_json"]


def cmd_list(args: argparse.Namespace) -> int:
    for p in all_problems():
        print(f"{p.id:>6}  {p.kind:<12} {p.title}")
    return 0


def cmd_solve(args: argparse.Namespace) -> int:
    try:
        prob = get(args.id)
    except KeyError as exc:
        print(f"rmpc: {exc.args[0]}", file=sys.stderr)
        return 2
    sol = prob.solve()
    figures = save_figures(sol, Path(args.figures)) if args.figures else None
    if args.json:
        print(json.dumps(solution_dict(sol, figures)))
    else:
        print(f"Problem {sol.id} — {sol.title} [{sol.kind}]")
        for name, value in sol.values.items():
            text = json.dumps(to_json(value))
            print(f"  {name} = {text if len(text) < 200 else text[:197] + '...'}")
        for c in sol.checks:
            print(f"  [{'PASS' if c.passed else 'FAIL'}] {c.name}: {c.detail}")
        for f in figures or []:
            print(f"  figure: {Path(args.figures) / f}")
    return 0 if sol.passed else 1


def cmd_report(args: argparse.Namespace) -> int:
    problems = all_problems()
    if args.chapter:
        problems = [p for p in problems if p.chapter in args.chapter]
    out = Path(args.out)
    summary = write_report(problems, out)
    print(f"report written to {out / 'index.html'}")
    failed = [d["id"] for d in summary if not d["passed"]]
    if failed:
        print(f"failed: {', '.join(failed)}")
    print(f"{len(summary) - len(failed)} passed, {len(failed)} failed")
    return 0 if not failed else 1


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="rmpc", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="list every problem").set_defaults(func=cmd_list)
    p_solve = sub.add_parser("solve", help="solve one problem")
    p_solve.add_argument("id")
    p_solve.add_argument("--json", action="store_true", help="print one JSON object")
    p_solve.add_argument("--figures", metavar="DIR", help="write the figures as PNG into DIR")
    p_solve.set_defaults(func=cmd_solve)
    p_report = sub.add_parser("report", help="solve every problem, write DIR/index.html")
    p_report.add_argument("--out", default="report", metavar="DIR")
    p_report.add_argument("--chapter", type=int, action="append", help="only this chapter (repeatable)")
    p_report.set_defaults(func=cmd_report)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0) and 2
    import matplotlib

    matplotlib.use("Agg")  # the CLI draws into files only (chapter modules never pick a backend)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
