"""The ``rmpc`` command line: ``rmpc list``, ``rmpc solve ID [--json] [--figures DIR]``, ``rmpc report [-j N]``.

Exit codes: 0 every check passed, 1 a check failed (or a problem raised), 2 bad input (unknown id or
chapter, an output directory that cannot be written, bad arguments) — reported in one line on stderr,
checked before any problem is solved. A reader closing the pipe (``rmpc list | head -1``) ends the
command quietly.
This module parses the arguments; the JSON and the HTML report are built by :mod:`problems.report`.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

from problems.registry import all_problems, get
from problems.report import save_figures, solution_dict, to_json, write_report

__all__ = ["main", "to_json"]


class BadInput(Exception):
    """A command-line input that makes the command impossible: exit 2 with its message on one line."""


def writable_directory(path: str, option: str) -> Path:
    """``path`` as a directory that exists (created if needed) and accepts a file; BadInput naming
    ``option`` otherwise (a regular file in the way, no permission, read-only file system)."""
    directory = Path(path)
    if directory.exists() and not directory.is_dir():
        raise BadInput(f"{option} {path}: is not a directory")
    try:
        directory.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=directory):
            pass
    except OSError as exc:
        raise BadInput(f"{option} {path}: cannot write there ({exc.strerror or exc})") from None
    return directory


def positive_int(text: str) -> int:
    """An argument N ≥ 1 (``-j N``)."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a whole number of processes >= 1, got {text!r}")
    return value


def cmd_list(args: argparse.Namespace) -> int:
    for p in all_problems():
        print(f"{p.id:>6}  {p.kind:<12} {p.title}")
    return 0


def cmd_solve(args: argparse.Namespace) -> int:
    try:
        prob = get(args.id)
    except KeyError as exc:
        raise BadInput(exc.args[0]) from None
    fig_dir = writable_directory(args.figures, "--figures") if args.figures else None
    try:
        sol = prob.solve()
    except Exception as exc:  # a crashing problem is a failure, told in one line
        print(f"rmpc: problem {prob.id} raised {type(exc).__name__}: {exc}", file=sys.stderr)
        return 1
    try:
        figures = save_figures(sol, fig_dir) if fig_dir is not None else None
    except OSError as exc:
        raise BadInput(f"--figures {args.figures}: cannot write the figures ({exc.strerror or exc})") from None
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
        chapters = sorted({p.chapter for p in problems})
        unknown = sorted(set(args.chapter) - set(chapters))
        if unknown:
            raise BadInput(f"no problem in chapter {', '.join(map(str, unknown))} "
                           f"(chapters: {', '.join(map(str, chapters))})")
        problems = [p for p in problems if p.chapter in args.chapter]
    out = writable_directory(args.out, "--out")
    try:
        summary = write_report(problems, out, jobs=args.jobs)
    except OSError as exc:
        raise BadInput(f"--out {args.out}: cannot write the report ({exc.strerror or exc})") from None
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
    p_report.add_argument("-j", "--jobs", type=positive_int, default=os.cpu_count() or 1, metavar="N",
                          help="solve the problems in N processes (default: the number of cores)")
    p_report.set_defaults(func=cmd_report)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0) and 2
    if args.command != "list":  # `rmpc list` reads problems/index.py only: no plotting library
        import matplotlib

        matplotlib.use("Agg")  # the CLI draws into files only (chapter modules never pick a backend)
    try:
        code = args.func(args)
        sys.stdout.flush()
    except BadInput as exc:
        print(f"rmpc: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader stopped reading (`rmpc list | head -1`): end quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so that the final flush at exit does not raise again
        return 141  # 128 + SIGPIPE, the shell's convention
    return code


if __name__ == "__main__":
    sys.exit(main())
