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
import gc
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

from problems.format import format_value_html, statement_html

__all__ = ["to_json", "solution_dict", "save_figures", "figure_png", "solution_html", "write_report",
           "show_compiler_progress"]

FIGURE_DPI = 90  # the report's PNG files
PNG_COMPRESS_LEVEL = 3  # zlib level: ~1/3 less encoding time than the default 6, files ~4 % larger
INLINE_DPI = 72  # a notebook's inline figures (notebooks are committed with their outputs: keep them small)


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
    """``8_10_1_joint_positions.png``: problem id, figure number, its title in lower-case words."""
    label = figure_title(fig, k)
    label = "" if label == f"figure {k + 1}" else label
    words = "".join(ch.lower() if ch.isascii() and ch.isalnum() else " " for ch in label).split()
    slug = "_".join(words)[:48].rstrip("_")
    return f"{sol.id.replace('.', '_')}_{k + 1}{'_' + slug if slug else ''}.png"


def save_figures(sol: Any, directory: Path) -> list[str]:
    """Write each figure of a solution as PNG into ``directory``; return the file names."""
    directory.mkdir(parents=True, exist_ok=True)
    names = []
    for k, fig in enumerate(sol.figures):
        name = _figure_name(sol, k, fig)
        fig.savefig(directory / name, dpi=FIGURE_DPI, pil_kwargs={"compress_level": PNG_COMPRESS_LEVEL})
        names.append(name)
    return names


def figure_png(fig: Any, dpi: int = FIGURE_DPI) -> bytes:
    """The figure as PNG bytes (no file, no pyplot: works for a bare ``matplotlib.figure.Figure``)."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=dpi, pil_kwargs={"compress_level": PNG_COMPRESS_LEVEL})
    return buffer.getvalue()


def figure_title(fig: Any, k: int) -> str:
    """The figure's title (its ``suptitle``, else its first axes' title), or ``figure k+1``."""
    if getattr(fig, "_suptitle", None) is not None and fig._suptitle.get_text():
        return fig._suptitle.get_text()
    for ax in getattr(fig, "axes", ()):
        if ax.get_title():
            return ax.get_title()
    return f"figure {k + 1}"


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
    """A check as JSON: the required ``name, passed, detail`` and ``actual, expected, reference, relation``."""
    return {"name": c.name, "passed": c.passed, "detail": c.detail, "actual": _side(getattr(c, "actual", None)),
            "expected": _side(getattr(c, "expected", None)), "reference": getattr(c, "reference", None),
            "relation": getattr(c, "relation", "==")}


def solution_dict(sol: Any, figures: list[str] | None = None) -> dict:
    """The JSON object of ``rmpc solve --json``: id, title, kind, values (full precision), units (one entry per value
    and per datum: "1" when dimensionless, null for text), given (the problem's data, ``sol.given``), checks, figures (the written files' paths, or the figures' titles when none
    were written)."""
    return {
        "id": sol.id,
        "title": sol.title,
        "kind": sol.kind,
        "statement": getattr(sol, "statement", ""),
        "values": to_json(sol.values),
        "units": {**dict(getattr(sol, "units", {})), **{name: getattr(sol, "units", {}).get(name) for name in sol.values}},
        "given": to_json(getattr(sol, "data", {})),
        "checks": [_check_dict(c) for c in sol.checks],
        "figures": figures if figures is not None else [figure_title(f, k) for k, f in enumerate(sol.figures)],
    }


def _html_value(d: dict, name: str) -> str:
    """A value of a :func:`solution_dict` as HTML, 4 significant digits, with its unit."""
    return format_value_html(d["values"][name], d.get("units", {}).get(name, ""))


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
    parts = [f'<section id="p{d["id"]}" class="{status}"><h3>{d["id"]} — {html.escape(d["title"])} '
             f'<small>[{d["kind"]}{timing}]</small></h3>']
    if d.get("statement"):
        parts.append(f'<p class="statement">{statement_html(d["statement"])}</p>')
    if d["values"]:
        parts.append("<table>")
        for name in d["values"]:
            parts.append(f"<tr><th>{html.escape(name)}</th><td>{_html_value(d, name)}</td></tr>")
        parts.append("</table>")
    if d.get("given"):
        units = d.get("units", {})
        names = ", ".join(html.escape(n + (f" [{units[n]}]" if units.get(n) else "")) for n in d["given"])
        parts.append(f'<p class="given" style="font-size:small;color:#555">Data of the problem (given): {names}</p>')
    parts.append("<ul>")
    for c in d["checks"]:
        mark, cls = ("✔", "pass") if c["passed"] else ("✘", "fail")
        reference = c.get("reference") or "unclassified"
        if c.get("relation") in ("<=", "<", ">=", ">"):
            reference += f", bound {c['relation']}"
        tag = (f'<span class="ref" style="font-size:small;border:1px solid #999;border-radius:3px;'
               f'padding:0 3px;color:#555">{html.escape(reference)}</span>')
        parts.append(f'<li class="{cls}" style="color:{"#070" if c["passed"] else "#b00"}">{mark} '
                     f'<b>{html.escape(c["name"])}</b> {tag} <pre style="display:inline;white-space:pre-wrap">'
                     f'{html.escape(c["detail"])}</pre></li>')
    parts.append("</ul>")
    captions = d.get("figure_titles") or [f"figure {k + 1}" for k in range(len(d["figures"]))]
    for k, src in enumerate(figure_sources):
        caption = html.escape(figure_caption(d["id"], k, captions[k] if k < len(captions) else ""))
        parts.append(f'<figure><a href="{html.escape(src)}" target="_blank"><img src="{html.escape(src)}" '
                     f'alt="{caption}" title="click to enlarge"></a><figcaption>{caption}</figcaption></figure>')
    parts.extend(extras)  # HTML snippets, e.g. the 3-D animations
    parts.append("</section>")
    return "\n".join(parts)


def figure_caption(pid: str, k: int, title: str) -> str:
    """The caption of figure ``k`` of problem ``pid``: "Fig. 8.10.1: title"; a title that names the manual's figure
    ("Fig. S12.3 — PRM …") keeps that name once: "Fig. 12.7.1 (the manual's Fig. S12.3): PRM …"; the problem's own
    number, which the caption's number already gives ("Problem 7.7 — …", "… (Problem 11.8)"), is dropped.

    >>> figure_caption("12.7", 0, "Fig. S12.3 — PRM for a 2R planar manipulator")
    "Fig. 12.7.1 (the manual's Fig. S12.3): PRM for a 2R planar manipulator"
    >>> figure_caption("8.10", 1, "joint errors")
    'Fig. 8.10.2: joint errors'
    >>> figure_caption("7.7", 0, "Problem 7.7 — Fig. S7.3: trajectory 1")
    "Fig. 7.7.1 (the manual's Fig. S7.3): trajectory 1"
    >>> figure_caption("3.21", 1, "Problem 3.21 — Fig. S3.5 (constrained, k0 = 35)")
    "Fig. 3.21.2 (the manual's Fig. S3.5): constrained, k0 = 35"
    >>> figure_caption("11.8", 0, "Tricycle with 3 trailers (Problem 11.8)")
    'Fig. 11.8.1: Tricycle with 3 trailers'
    >>> figure_caption("11.16", 0, "Fig. S11.2 (here) — the two regulators")
    "Fig. 11.16.1 (the manual's Fig. S11.2): the two regulators"
    """
    import re

    number = f"Fig. {pid}.{k + 1}"
    own = re.escape(pid)
    title = re.sub(rf"^\s*Problem\s+{own}\b\s*[—:–/-]?\s*", "", title)          # "Problem 7.7 — …"
    title = re.sub(rf"\s*\(Problem\s+{own}\)\s*$", "", title)                   # "… (Problem 11.8)"
    match = re.match(r"\s*(?:Fig\.|Figure)\s*(S?\d+\.\d+[a-z]?)\s*(?:\(here\)\s*)?[—:–-]?\s*(.*)", title, re.S)
    if match:
        rest = match.group(2).strip()
        if re.fullmatch(r"\([^()]*\)", rest):                                       # "(constrained, …)"
            rest = rest[1:-1]
        return f"{number} (the manual's Fig. {match.group(1)})" + (f": {rest}" if rest else "")
    return f"{number}: {title}".rstrip(": ")


def inline_html(sol: Any) -> str:
    """A solution with its figures inline as base64 PNG (what a notebook shows)."""
    sources = [f"data:image/png;base64,{base64.b64encode(figure_png(fig, INLINE_DPI)).decode('ascii')}"
               for fig in sol.figures]
    d = solution_dict(sol)
    d["figure_titles"] = d["figures"]
    return solution_html(d, sources)


def _html_index(summary: list[dict]) -> str:
    """One link per problem, grouped by chapter, red when it failed."""
    chapters: dict[str, list[str]] = {}
    for d in summary:
        cls = "pass" if d["passed"] else "fail"
        chapters.setdefault(d["id"].split(".")[0], []).append(
            f'<a class="{cls}" href="#p{d["id"]}" title="{html.escape(d["title"])}">{d["id"]}</a>')
    return "<nav>" + "".join(f'<div><a href="#ch{ch}">Ch. {ch}</a>: {" ".join(links)}</div>'
                             for ch, links in chapters.items()) + "</nav>"


CHAPTERS = {2: "Kinematics", 3: "Differential kinematics and statics", 4: "Trajectory planning",
            5: "Actuators and sensors", 6: "Control architecture", 7: "Dynamics", 8: "Motion control",
            9: "Force control", 10: "Visual servoing", 11: "Mobile robots", 12: "Motion planning"}


def _html_page(rows: list[str], n_pass: int, n_fail: int, summary: list[dict]) -> str:
    animation_script, animation_style = _animation_assets() if any('class="animation"' in r for r in rows) else ("", "")
    style = ("body{font-family:sans-serif;max-width:1100px;margin:auto} section{border-top:1px solid #ccc}"
             " .fail h3{color:#b00} li.fail{color:#b00} pre{display:inline;white-space:pre-wrap}"
             " figure{display:inline-block;margin:4px;vertical-align:top;max-width:100%} figure img{max-width:100%}"
             " figcaption{font-size:small;color:#444} th{text-align:left;padding-right:1em;vertical-align:top}"
             " table.matrix td{text-align:right;padding:0 .6em;font-family:monospace;border-left:1px solid #ddd}"
             " table.dict th{font-weight:normal;font-style:italic} .unit{color:#555}"
             " p.statement{color:#333;font-style:italic} h2 a{font-size:small;margin-left:1em}"
             " nav a{margin-right:.4em} a.fail{color:#b00;font-weight:bold}"
             " p.statement code{font-style:normal}"
             f" {animation_style}")
    body, chapter = [], None
    for d, row in zip(summary, rows):
        ch = int(d["id"].split(".")[0])
        if ch != chapter:
            chapter = ch
            body.append(f'<h2 id="ch{ch}">Chapter {ch} — {CHAPTERS.get(ch, "")} <a href="#top">back to top</a></h2>')
        body.append(row)
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>rmpc report</title><link rel='icon' href='data:,'>"
            f"<style>{style}</style></head><body><h1 id='top'>rmpc — solved problems</h1>"
            f"<p>{n_pass} passed, {n_fail} failed. Values are shown to 4 significant digits; full precision "
            f"in <a href='summary.json'>summary.json</a> (one object per problem, as <code>rmpc solve ID --json</code>). "
            f"Click a figure to enlarge it; a 3-D animation plays when it is scrolled into view or clicked.</p>"
            f"{_html_index(summary)}{''.join(body)}{animation_script}</body></html>")


def _animation_assets() -> tuple[str, str]:
    """The page's script and style that make the animations live when seen (viewer/, imported on use; without it,
    the report has no animations)."""
    try:
        from viewer.animation import LIVE_ANIMATIONS_SCRIPT, LIVE_ANIMATIONS_STYLE
    except ImportError:  # pragma: no cover
        return "", ""
    return LIVE_ANIMATIONS_SCRIPT, LIVE_ANIMATIONS_STYLE


def _progress(k: int, n: int, pid: str, started: float) -> None:
    width = 30
    done = int(width * k / n)
    bar = "#" * done + "-" * (width - done)
    sys.stderr.write(f"\r[{bar}] {k}/{n} {pid:<6} {time.time() - started:6.1f}s")
    sys.stderr.flush()


_SOLVING = [""]   # the problem this process is solving (the compiler's progress lines name it)


def show_compiler_progress() -> None:
    """Print the compiled backend's build messages (INFO of the logger ``rmpc.compiler``) on stderr, each with the
    problem being solved: the first report on a machine compiles its closed loops (20–25 s in all) while the
    progress bar waits for them."""
    import logging

    class _Problem(logging.Filter):
        def filter(self, record: logging.LogRecord) -> bool:
            record.problem = _SOLVING[0] or "-"
            return True

    class _Stderr(logging.StreamHandler):
        def emit(self, record: logging.LogRecord) -> None:
            self.stream = sys.stderr           # the stderr of now (a test or a notebook may have replaced it)
            super().emit(record)

    logger = logging.getLogger("rmpc.compiler")
    if any(getattr(h, "rmpc_report", False) for h in logger.handlers):
        return
    handler = _Stderr()
    handler.rmpc_report = True
    handler.addFilter(_Problem())
    handler.setFormatter(logging.Formatter("\r%(problem)6s %(message)s"))
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)


def _solve_for_report(prob: Any, out: Path) -> tuple[dict, list[str]]:
    """Solve one problem for the report: its :func:`solution_dict` (with ``passed``, ``seconds``), figures
    written under ``out/figures``, and its animations' HTML."""
    _SOLVING[0] = prob.id
    fig_dir = out / "figures"
    t0 = time.time()
    try:
        sol = prob.solve()
        figures = save_figures(sol, fig_dir)
        data = solution_dict(sol, figures)
        data["figure_titles"] = [figure_title(f, k) for k, f in enumerate(sol.figures)]
        animations = _animations(sol, out)
        passed = sol.passed
    except Exception:  # a crashing problem is reported as failed, the report goes on
        data = {"id": prob.id, "title": prob.title, "kind": prob.kind, "statement": prob.statement, "values": {},
                "checks": [{"name": "solve", "passed": False, "detail": traceback.format_exc()}],
                "figures": []}
        passed, animations = False, []
    data["seconds"] = round(time.time() - t0, 3)
    data["passed"] = passed
    return data, animations


def _previous_seconds(out: Path) -> dict[str, float]:
    """Each problem's solve time in the report already in ``out`` (its ``summary.json``), if any."""
    try:
        return {d["id"]: float(d["seconds"]) for d in json.loads((out / "summary.json").read_text())}
    except (OSError, ValueError, KeyError, TypeError):
        return {}


FIRST_RUN_ORDER = ("simulation", "programming", "qualitative", "numeric", "derivation")
"""Without a previous time, the kinds in the order of their usual cost (a simulation takes ≈ 0.6 s, a
derivation ≈ 0.1 s), later chapters first within a kind (a chapter-12 derivation ≈ 0.3 s, a chapter-2 one
≈ 0.02 s), so that short problems end the run."""


def _longest_first(ids: list[str], kinds: list[str], previous: dict[str, float]) -> list[int]:
    """The indices of ``ids`` by decreasing ``previous`` time; those without one first, by their kind and
    chapter (:data:`FIRST_RUN_ORDER`); ties keep their order.

    >>> _longest_first(["2.1", "2.2", "2.3", "2.4"], ["numeric"] * 4, {"2.1": 0.1, "2.2": 1.5, "2.4": 0.3})
    [2, 1, 3, 0]
    >>> _longest_first(["2.1", "3.21", "4.3", "12.2"], ["derivation", "simulation", "numeric", "derivation"], {})
    [1, 2, 3, 0]
    """
    rank = {kind: r for r, kind in enumerate(FIRST_RUN_ORDER)}
    return sorted(range(len(ids)), key=lambda k: (-previous.get(ids[k], float("inf")),
                                                  rank.get(kinds[k], len(rank)), -int(ids[k].split(".")[0])))


WORKER_GC_THRESHOLD = 20_000
"""A report worker's young-generation threshold (Python's default: 700 allocations): the figures and the
symbolic derivations allocate millions of short-lived objects; collecting them 30× less often halves the
time the collector takes (0.9 → 0.55 s over the report)."""


def _worker_collector() -> None:
    """A report worker's collector: young collections every :data:`WORKER_GC_THRESHOLD` allocations."""
    gc.set_threshold(WORKER_GC_THRESHOLD, *gc.get_threshold()[1:])


def _solved(problems: list, out: Path, jobs: int,
            previous: dict[str, float] | None = None) -> Iterable[tuple[dict, list[str]]]:
    """:func:`_solve_for_report` of each problem, in order: here, or in ``jobs`` processes (forked after
    the parent imported the problems' chapters, so that each worker starts with them). The processes take
    the problems longest first by their ``previous`` times (as a build tool orders its jobs by the last
    build's times; a problem without one counts as long, by its kind), so that no long problem starts last
    and leaves the other processes idle; the results come back in the given order."""
    jobs = max(1, min(int(jobs), len(problems)))
    if jobs == 1:
        yield from (_solve_for_report(prob, out) for prob in problems)
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    for prob in problems:  # import the chapter modules once, before the workers are forked
        getattr(prob, "function", None)
    try:  # and the viewer, which exports the animations: one import instead of one per worker
        import viewer  # noqa: F401
    except ImportError:
        pass
    order = _longest_first([prob.id for prob in problems], [prob.kind for prob in problems], previous or {})
    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("fork" if "fork" in methods else None)
    # The objects of the imported modules (some 200 000) go to the collector's permanent generation for the
    # fork (Python's advice for fork without exec): the workers' collections no longer traverse them — about
    # 5 % of the report's CPU — and leave their pages shared. The first submit forks the workers.
    gc.freeze()
    try:
        with ProcessPoolExecutor(jobs, mp_context=context, initializer=_worker_collector) as pool:
            futures = {k: pool.submit(_solve_for_report, problems[k], out) for k in order}
            gc.unfreeze()
            for k in range(len(problems)):
                yield futures[k].result()
    finally:
        gc.unfreeze()


def write_report(problems: list, out: Path, jobs: int = 1) -> list[dict]:
    """Solve ``problems`` (registry ``Problem`` objects) and write ``out/index.html``, ``out/summary.json``
    and ``out/figures/``; return the summary (one :func:`solution_dict` per problem, with ``passed`` and
    ``seconds``). A crashing problem is reported as failed with its traceback; the report goes on.
    ``jobs`` > 1 solves the problems in that many processes (longest first by the times of the report
    already in ``out``, if any); the report is the same, in the same order."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    previous = _previous_seconds(out)
    fig_dir = out / "figures"
    if fig_dir.is_dir():  # no stale figure of an earlier run (renamed or removed figures)
        for old in fig_dir.glob("*.png"):
            old.unlink()
    anim_dir = out / "animations"
    if anim_dir.is_dir():  # nor a stale animation page (a problem that no longer animates, or fewer animations)
        for old in anim_dir.glob("*.html"):
            old.unlink()
    progress = sys.stderr.isatty() or bool(os.environ.get("RMPC_PROGRESS"))
    started = time.time()
    rows, summary = [], []
    for k, (prob, (data, animations)) in enumerate(zip(problems, _solved(problems, out, jobs, previous))):
        if progress:
            _progress(k + 1, len(problems), prob.id, started)
        summary.append(data)
        rows.append(solution_html(data, [f"figures/{f}" for f in data["figures"]], animations))
        if not sys.stderr.isatty():
            print(f"{prob.id:>6} {'PASS' if data['passed'] else 'FAIL'} {data['seconds']:7.2f}s  {prob.title}",
                  file=sys.stderr)
    if progress:
        _progress(len(problems), len(problems), "", started)
        sys.stderr.write("\n")
    n_pass = sum(d["passed"] for d in summary)
    (out / "summary.json").write_text(json.dumps(summary, indent=1))
    (out / "index.html").write_text(_html_page(rows, n_pass, len(summary) - n_pass, summary))
    return summary
