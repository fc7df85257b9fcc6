"""The ``rmpc`` command line: ``rmpc list [--chapter N]``, ``rmpc solve ID [--json] [--figures DIR]``, ``rmpc report [-j N]``.

Exit codes: 0 every check passed, 1 a check failed (or a problem raised), 2 bad input (unknown id or
chapter, an output directory that cannot be written, bad arguments) — reported in one line on stderr,
checked before any problem is solved. A reader closing the pipe (``rmpc list | head -1``) ends the
command quietly.
This module parses the arguments; the JSON and the HTML report are built by :mod:`problems.report`.
"""

from __future__ import annotations

import argparse
import difflib
import json
import os
import re
import sys
import tempfile
import time
from pathlib import Path

from problems.format import solution_text
from problems.registry import all_problems, get
from problems.report import save_figures, show_compiler_progress, solution_dict, to_json, write_report

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


def chapter_number(text: str) -> int:
    """A chapter as the user may write it: ``2``, ``02``, ``ch02``, ``ch2`` → 2."""
    match = re.fullmatch(r"(?:ch(?:apter)?)?0*(\d{1,2})", text.strip().lower())
    if match is None:
        raise argparse.ArgumentTypeError(f"{text!r} is not a chapter (write 8, 08 or ch08)")
    return int(match.group(1))


def selected(chapters: list[int] | None) -> list:
    """The problems of ``chapters`` (all when None); BadInput naming the chapters that have none."""
    problems = all_problems()
    if not chapters:
        return problems
    known = sorted({p.chapter for p in problems})
    unknown = sorted(set(chapters) - set(known))
    if unknown:
        raise BadInput(f"no problem in chapter {', '.join(map(str, unknown))} "
                       f"(chapters: {', '.join(map(str, known))})")
    return [p for p in problems if p.chapter in chapters]


def cmd_list(args: argparse.Namespace) -> int:
    for p in selected(args.chapter):
        print(f"{p.id:>6}  {p.kind:<12} {p.title}")
    return 0


def cmd_solve(args: argparse.Namespace) -> int:
    try:
        prob = get(args.id)
    except KeyError as exc:
        raise BadInput(exc.args[0]) from None
    fig_dir = writable_directory(args.figures, "--figures") if args.figures else None
    started = time.perf_counter()
    try:
        sol = prob.solve()
    except Exception as exc:  # a crashing problem is a failure, told in one line
        print(f"rmpc: problem {prob.id} raised {type(exc).__name__}: {exc}", file=sys.stderr)
        return 1
    seconds = round(time.perf_counter() - started, 3)
    try:
        figures = [str(fig_dir / f) for f in save_figures(sol, fig_dir)] if fig_dir is not None else None
    except OSError as exc:
        raise BadInput(f"--figures {args.figures}: cannot write the figures ({exc.strerror or exc})") from None
    if args.json:  # full precision
        print(json.dumps(solution_dict(sol, figures) | {"passed": sol.passed, "seconds": seconds}))
    else:  # for reading: 4 significant digits, matrices as tables, units
        print(solution_text(sol, seconds, figures))
    return 0 if sol.passed else 1


def cmd_report(args: argparse.Namespace) -> int:
    problems = selected(args.chapter)
    out = writable_directory(args.out, "--out")
    show_compiler_progress()
    try:
        summary = write_report(problems, out, jobs=args.jobs)
    except OSError as exc:
        raise BadInput(f"--out {args.out}: cannot write the report ({exc.strerror or exc})") from None
    print(f"report written to {out / 'index.html'} (figures in {out / 'figures'}, full-precision values in "
          f"{out / 'summary.json'})")
    if args.open:  # the default browser, where one exists (a headless machine has none: say so, go on)
        import webbrowser

        if not webbrowser.open((out / "index.html").resolve().as_uri()):
            print("no browser to open the report in", file=sys.stderr)
    failed = [d["id"] for d in summary if not d["passed"]]
    if failed:
        print(f"failed: {', '.join(failed)}")
    print(f"{len(summary) - len(failed)} passed, {len(failed)} failed")
    return 0 if not failed else 1


EPILOG = "exit codes: 0 every check passed, 1 a check failed, 2 bad input (one line on stderr)"


class Parser(argparse.ArgumentParser):
    """argparse without abbreviations (``--jsn`` is not ``--json``), whose errors are one line with
    the closest option or command when there is one."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("allow_abbrev", False)
        kwargs.setdefault("epilog", EPILOG)
        super().__init__(*args, **kwargs)

    def error(self, message: str):
        words = re.findall(r"(?:unrecognized arguments|invalid choice): '?([^\s',]+)", message)
        choices = [o for a in self._actions for o in a.option_strings]
        for action in self._actions:
            if isinstance(action, argparse._SubParsersAction):  # the commands and their options
                choices += list(action.choices)
                choices += [o for p in action.choices.values() for a in p._actions for o in a.option_strings]
        near = difflib.get_close_matches(words[0], choices, n=1, cutoff=0.6) if words else []
        hint = f" (did you mean {near[0]}?)" if near else ""
        self.exit(2, f"{self.prog}: {message}{hint}\n")


def main(argv: list[str] | None = None) -> int:
    parser = Parser(prog="rmpc", description="Solve, check and plot the end-of-chapter problems of "
                    "Robotics: Modelling, Planning and Control: rmpc list, rmpc solve ID, rmpc report.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser, metavar="COMMAND")
    about = "list the problems: id, kind (derivation, numeric, simulation, programming, qualitative), title"
    p_list = sub.add_parser("list", help=about, description=about,
                            epilog="exit codes: 0 listed, 2 bad input (one line on stderr)")
    p_list.add_argument("--chapter", type=chapter_number, action="append",
                        help="only this chapter: 8, 08 or ch08 (repeatable)")
    p_list.set_defaults(func=cmd_list)
    about = "solve one problem; print its statement, values (4 significant digits, units) and checks"
    p_solve = sub.add_parser("solve", help=about, description=about)
    p_solve.add_argument("id", help="the problem's number in the book, e.g. 3.21 (see rmpc list)")
    p_solve.add_argument("--json", action="store_true",
                         help="print one JSON object (full precision): id, title, kind, statement, values, "
                              "units, checks, figures, passed, seconds")
    p_solve.add_argument("--figures", metavar="DIR", help="write the figures as PNG into DIR")
    p_solve.set_defaults(func=cmd_solve)
    about = ("solve every problem (or a chapter's); write DIR/index.html (values, checks, figures), "
             "DIR/figures/ (PNG) and DIR/summary.json (full precision)")
    p_report = sub.add_parser("report", help=about, description=about)
    p_report.add_argument("--out", default="report", metavar="DIR",
                          help="the report's directory (created; default: report)")
    p_report.add_argument("--chapter", type=chapter_number, action="append",
                          help="only this chapter: 8, 08 or ch08 (repeatable)")
    p_report.add_argument("-j", "--jobs", type=positive_int, default=os.cpu_count() or 1, metavar="N",
                          help="solve the problems in N processes (default: the number of cores)")
    p_report.add_argument("--open", action="store_true", help="open the report in the default browser")
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


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("rmpc")
    except PackageNotFoundError:  # running from a source tree that is not installed
        return "(not installed)"


if __name__ == "__main__":
    sys.exit(main())
