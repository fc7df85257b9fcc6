"""Solutions as JSON and HTML: the ``rmpc report`` page, ``rmpc solve --json`` and a notebook's view.

:func:`to_json` turns values into JSON (arrays → nested lists, complex → [re, im]);
:func:`solution_dict` is the JSON object of one solved problem (ARCHITECTURE.md's required keys);
:func:`solution_html` renders one problem (title, values, checks with pass/fail, figures) — used by
:func:`write_report` for ``index.html`` and by ``Solution._repr_html_`` in Jupyter (figures inline
as base64 PNG). Nothing here imports the registry: it works on plain dictionaries and duck-typed
solutions (``id``, ``title``, ``kind``, ``values``, ``checks``, ``figures``).
"""

from __future__ import annotations

import base64
import html
import io
import json
import os
import sys
import time
import traceback
from pathlib import Path
from typing import Any, Iterable

import numpy as np

__all__ = ["to_json", "solution_dict", "save_figures", "figure_png", "solution_html", "write_report"]

FIGURE_DPI = 90


def to_json(value: Any) -> Any:
    """Convert values to JSON: arrays → nested lists, complex → [re, im], SE3 → 4×4.

    >>> to_json({"A": np.eye(2), "z": 1 + 2j, "n": np.int64(3), "x": float("nan")})
    {'A': [[1.0, 0.0], [0.0, 1.0]], 'z': [1.0, 2.0], 'n': 3, 'x': 'nan'}
    """
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


def _figure_name(sol: Any, k: int, fig: Any) -> str:
    label = ""
    if getattr(fig, "_suptitle", None) is not None:
        label = fig._suptitle.get_text()
    slug = "".join(ch if ch.isalnum() else "_" for ch in label).strip("_")[:40]
    return f"{sol.id.replace('.', '_')}_{k + 1}{'_' + slug if slug else ''}.png"


def save_figures(sol: Any, directory: Path) -> list[str]:
    """Write each figure of a solution as PNG into ``directory``; return the file names."""
    directory.mkdir(parents=True, exist_ok=True)
    names = []
    for k, fig in enumerate(sol.figures):
        name = _figure_name(sol, k, fig)
        fig.savefig(directory / name, dpi=FIGURE_DPI)
        names.append(name)
    return names


def figure_png(fig: Any) -> bytes:
    """The figure as PNG bytes (no file, no pyplot: works for a bare ``matplotlib.figure.Figure``)."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=FIGURE_DPI)
    return buffer.getvalue()


CHECK_VALUE_SIZE = 64  # larger sides are written as their shape


def _side(value: Any) -> Any:
    """One side of a check for JSON: small values as they are, large arrays as ``"array (shape)"``."""
    if value is None:
        return None
    size = np.size(value) if isinstance(value, (np.ndarray, list, tuple)) else 1
    if size > CHECK_VALUE_SIZE:
        return f"array {np.shape(value)}"
    return to_json(value)


def _check_dict(c: Any) -> dict:
    """A check as JSON: the required ``name, passed, detail`` and ``actual, expected, reference``."""
    return {"name": c.name, "passed": c.passed, "detail": c.detail, "actual": _side(getattr(c, "actual", None)),
            "expected": _side(getattr(c, "expected", None)), "reference": getattr(c, "reference", None)}


def solution_dict(sol: Any, figures: list[str] | None = None) -> dict:
    """The JSON object of ``rmpc solve --json``: id, title, kind, values, checks, figures."""
    return {
        "id": sol.id,
        "title": sol.title,
        "kind": sol.kind,
        "values": to_json(sol.values),
        "checks": [_check_dict(c) for c in sol.checks],
        "figures": figures if figures is not None else [f"figure {k + 1}" for k in range(len(sol.figures))],
    }


def _html_value(value: Any) -> str:
    text = json.dumps(to_json(value))
    if len(text) > 600:
        text = text[:597] + "..."
    return html.escape(text)


def _animations(sol: Any, out: Path) -> list[str]:
    """The problem's 3-D animations (``Solution.animation``) exported under ``out/animations/``, as
    ``<iframe>`` snippets; none when the optional viewer (meshcat) is not installed."""
    if not getattr(sol, "animations", None):
        return []
    try:
        from viewer import report_animations
    except ImportError:
        return []
    return report_animations(sol, out)


def solution_html(d: dict, figure_sources: Iterable[str] = (), extras: Iterable[str] = ()) -> str:
    """One problem as an HTML ``<section>``: title, values table, checks (✔/✘ with detail), figures.

    ``d`` is a :func:`solution_dict` (plus ``passed``/``seconds`` in a report); ``figure_sources``
    are the ``src`` of the images (file names or ``data:`` URLs); ``extras`` more HTML (animations).
    """
    passed = d.get("passed", bool(d["checks"]) and all(c["passed"] for c in d["checks"]))
    status = "pass" if passed else "fail"
    timing = f", {d['seconds']} s" if "seconds" in d else ""
    parts = [f'<section id="p{d["id"]}" class="{status}"><h2>{d["id"]} — {html.escape(d["title"])} '
             f'<small>[{d["kind"]}{timing}]</small></h2>']
    if d["values"]:
        parts.append("<table>")
        for name, value in d["values"].items():
            parts.append(f"<tr><th>{html.escape(name)}</th><td><code>{_html_value(value)}</code></td></tr>")
        parts.append("</table>")
    parts.append("<ul>")
    for c in d["checks"]:
        mark, cls = ("✔", "pass") if c["passed"] else ("✘", "fail")
        reference = c.get("reference") or "unclassified"
        tag = (f'<span class="ref" style="font-size:small;border:1px solid #999;border-radius:3px;'
               f'padding:0 3px;color:#555">{html.escape(reference)}</span>')
        parts.append(f'<li class="{cls}" style="color:{"#070" if c["passed"] else "#b00"}">{mark} '
                     f'<b>{html.escape(c["name"])}</b> {tag} <pre style="display:inline;white-space:pre-wrap">'
                     f'{html.escape(c["detail"])}</pre></li>')
    parts.append("</ul>")
    for src in figure_sources:
        parts.append(f'<img src="{html.escape(src)}" alt="figure" style="max-width:520px;margin:4px">')
    parts.extend(extras)  # HTML snippets, e.g. the 3-D animations
    parts.append("</section>")
    return "\n".join(parts)


def inline_html(sol: Any) -> str:
    """A solution with its figures inline as base64 PNG (what a notebook shows)."""
    sources = [f"data:image/png;base64,{base64.b64encode(figure_png(fig)).decode('ascii')}" for fig in sol.figures]
    return solution_html(solution_dict(sol), sources)


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


def _progress(k: int, n: int, pid: str, started: float) -> None:
    width = 30
    done = int(width * k / n)
    bar = "#" * done + "-" * (width - done)
    sys.stderr.write(f"\r[{bar}] {k}/{n} {pid:<6} {time.time() - started:6.1f}s")
    sys.stderr.flush()


def write_report(problems: list, out: Path) -> list[dict]:
    """Solve ``problems`` (registry ``Problem`` objects) and write ``out/index.html``, ``out/summary.json``
    and ``out/figures/``; return the summary (one :func:`solution_dict` per problem, with ``passed`` and
    ``seconds``). A crashing problem is reported as failed with its traceback; the report goes on."""
    out = Path(out)
    fig_dir = out / "figures"
    out.mkdir(parents=True, exist_ok=True)
    progress = sys.stderr.isatty() or bool(os.environ.get("RMPC_PROGRESS"))
    started = time.time()
    rows, summary = [], []
    for k, prob in enumerate(problems):
        if progress:
            _progress(k, len(problems), prob.id, started)
        t0 = time.time()
        try:
            sol = prob.solve()
            figures = save_figures(sol, fig_dir)
            data = solution_dict(sol, figures)
            animations = _animations(sol, out)
            passed = sol.passed
        except Exception:  # a crashing problem is reported as failed, the report goes on
            data = {"id": prob.id, "title": prob.title, "kind": prob.kind, "values": {},
                    "checks": [{"name": "solve", "passed": False, "detail": traceback.format_exc()}],
                    "figures": []}
            passed, animations = False, []
        data["seconds"] = round(time.time() - t0, 3)
        data["passed"] = passed
        summary.append(data)
        rows.append(solution_html(data, [f"figures/{f}" for f in data["figures"]], animations))
        if not sys.stderr.isatty():
            print(f"{prob.id:>6} {'PASS' if passed else 'FAIL'} {data['seconds']:7.2f}s  {prob.title}",
                  file=sys.stderr)
    if progress:
        _progress(len(problems), len(problems), "", started)
        sys.stderr.write("\n")
    n_pass = sum(d["passed"] for d in summary)
    (out / "summary.json").write_text(json.dumps(summary, indent=1))
    (out / "index.html").write_text(_html_page(rows, n_pass, len(summary) - n_pass, summary))
    return summary
