"""The ``rmpc`` command line: ``rmpc list``, ``rmpc solve ID [--json] [--figures DIR]``, ``rmpc report``.

Exit codes: 0 every check passed, 1 a check failed, 2 bad input (unknown id, bad arguments).
"""

from __future__ import annotations

import argparse
import html
import json
import os
import sys
import time
import traceback
from pathlib import Path
from typing import Any

import numpy as np

from problems.registry import Solution, all_problems, get


def to_json(value: Any) -> Any:
    """Convert values to JSON: arrays → nested lists, complex → [re, im], SE3 → 4×4."""
    if isinstance(value, dict):
        return {str(k): to_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json(v) for v in value]
    if hasattr(value, "homogeneous") and not isinstance(value, np.ndarray):  # pin.SE3
        return to_json(np.asarray(value.homogeneous))
    if isinstance(value, np.ndarray):
        return [to_json(v) for v in value] if value.ndim else to_json(value.item())
    if isinstance(value, (complex, np.complexfloating)):
        return [float(value.real), float(value.imag)]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if np.isfinite(v) else str(v)
    if value is None or isinstance(value, str):
        return value
    return str(value)


def _figure_name(sol: Solution, k: int, fig: Any) -> str:
    label = ""
    if getattr(fig, "_suptitle", None) is not None:
        label = fig._suptitle.get_text()
    slug = "".join(ch if ch.isalnum() else "_" for ch in label).strip("_")[:40]
    return f"{sol.id.replace('.', '_')}_{k + 1}{'_' + slug if slug else ''}.png"


def save_figures(sol: Solution, directory: Path) -> list[str]:
    """Write each figure of a solution as PNG into ``directory``; return the file names."""
    import matplotlib.pyplot as plt

    directory.mkdir(parents=True, exist_ok=True)
    names = []
    for k, fig in enumerate(sol.figures):
        name = _figure_name(sol, k, fig)
        fig.savefig(directory / name, dpi=90)
        plt.close(fig)
        names.append(name)
    return names


def solution_dict(sol: Solution, figures: list[str] | None = None) -> dict:
    return {
        "id": sol.id,
        "title": sol.title,
        "kind": sol.kind,
        "values": to_json(sol.values),
        "checks": [{"name": c.name, "passed": c.passed, "detail": c.detail} for c in sol.checks],
        "figures": figures if figures is not None else [f"figure {k + 1}" for k in range(len(sol.figures))],
    }


def _close_figures(sol: Solution) -> None:
    import matplotlib.pyplot as plt

    for fig in sol.figures:
        plt.close(fig)


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
    if figures is None:
        _close_figures(sol)
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


def _progress(k: int, n: int, pid: str, started: float) -> None:
    width = 30
    done = int(width * k / n)
    bar = "#" * done + "-" * (width - done)
    sys.stderr.write(f"\r[{bar}] {k}/{n} {pid:<6} {time.time() - started:6.1f}s")
    sys.stderr.flush()


def _html_value(value: Any) -> str:
    text = json.dumps(to_json(value))
    if len(text) > 600:
        text = text[:597] + "..."
    return html.escape(text)


def cmd_report(args: argparse.Namespace) -> int:
    import matplotlib

    matplotlib.use("Agg")
    out = Path(args.out)
    fig_dir = out / "figures"
    out.mkdir(parents=True, exist_ok=True)
    problems = all_problems()
    if args.chapter:
        problems = [p for p in problems if p.chapter in args.chapter]
    started = time.time()
    rows, summary = [], []
    n_pass = n_fail = 0
    for k, prob in enumerate(problems):
        if sys.stderr.isatty() or os.environ.get("RMPC_PROGRESS"):
            _progress(k, len(problems), prob.id, started)
        t0 = time.time()
        try:
            sol = prob.solve()
            figures = save_figures(sol, fig_dir)
            data = solution_dict(sol, figures)
            passed = sol.passed
        except Exception:  # a crashing problem is reported as failed, the report goes on
            data = {"id": prob.id, "title": prob.title, "kind": prob.kind, "values": {},
                    "checks": [{"name": "solve", "passed": False, "detail": traceback.format_exc()}],
                    "figures": []}
            passed = False
        data["seconds"] = round(time.time() - t0, 3)
        data["passed"] = passed
        n_pass += passed
        n_fail += not passed
        summary.append(data)
        rows.append(_html_problem(data))
        if not sys.stderr.isatty():
            print(f"{prob.id:>6} {'PASS' if passed else 'FAIL'} {data['seconds']:7.2f}s  {prob.title}",
                  file=sys.stderr)
    if sys.stderr.isatty() or os.environ.get("RMPC_PROGRESS"):
        _progress(len(problems), len(problems), "", started)
        sys.stderr.write("\n")
    (out / "summary.json").write_text(json.dumps(summary, indent=1))
    (out / "index.html").write_text(_html_page(rows, n_pass, n_fail, summary))
    print(f"report written to {out / 'index.html'}")
    failed = [d["id"] for d in summary if not d["passed"]]
    if failed:
        print(f"failed: {', '.join(failed)}")
    print(f"{n_pass} passed, {n_fail} failed")
    return 0 if n_fail == 0 else 1


def _html_problem(d: dict) -> str:
    status = "pass" if d["passed"] else "fail"
    parts = [f'<section id="p{d["id"]}" class="{status}"><h2>{d["id"]} — {html.escape(d["title"])} '
             f'<small>[{d["kind"]}, {d["seconds"]} s]</small></h2>']
    if d["values"]:
        parts.append("<table>")
        for name, value in d["values"].items():
            parts.append(f"<tr><th>{html.escape(name)}</th><td><code>{_html_value(value)}</code></td></tr>")
        parts.append("</table>")
    parts.append("<ul>")
    for c in d["checks"]:
        mark = "✔" if c["passed"] else "✘"
        parts.append(f'<li class="{"pass" if c["passed"] else "fail"}">{mark} <b>{html.escape(c["name"])}</b>'
                     f' <pre>{html.escape(c["detail"])}</pre></li>')
    parts.append("</ul>")
    for f in d["figures"]:
        parts.append(f'<img src="figures/{html.escape(f)}" alt="{html.escape(f)}">')
    parts.append("</section>")
    return "\n".join(parts)


def _html_index(summary: list[dict]) -> str:
    """One link per problem, grouped by chapter, red when it failed."""
    chapters: dict[str, list[str]] = {}
    for d in summary:
        cls = "pass" if d["passed"] else "fail"
        chapters.setdefault(d["id"].split(".")[0], []).append(
            f'<a class="{cls}" href="#p{d["id"]}" title="{html.escape(d["title"])}">{d["id"]}</a>')
    return "<nav>" + "".join(f"<div>Ch. {ch}: {' '.join(links)}</div>" for ch, links in chapters.items()) + "</nav>"


def _html_page(rows: list[str], n_pass: int, n_fail: int, summary: list[dict]) -> str:
    style = ("body{font-family:sans-serif;max-width:1100px;margin:auto} section{border-top:1px solid #ccc}"
             " .fail h2{color:#b00} li.fail{color:#b00} pre{display:inline;white-space:pre-wrap}"
             " img{max-width:520px;margin:4px} th{text-align:left;padding-right:1em;vertical-align:top}"
             " nav a{margin-right:.4em} a.fail{color:#b00;font-weight:bold}")
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>rmpc report</title>"
            f"<style>{style}</style></head><body><h1>rmpc — solved problems</h1>"
            f"<p>{n_pass} passed, {n_fail} failed</p>{_html_index(summary)}{''.join(rows)}</body></html>")


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
    if args.command != "report":
        import matplotlib

        matplotlib.use("Agg")
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
