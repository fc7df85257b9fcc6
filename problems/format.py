"""How a value is shown to a reader: the one formatter of the CLI text, the HTML report and a notebook.

Numbers get 4 significant digits; rounding noise becomes 0 (an entry of an array below 1e-12 times
the array's largest magnitude, a lone scalar below 1e-15 — ``cos(π/2)`` = 6.12e-17 reads 0);
vectors are one line ``[a, b, c]``; matrices are aligned multi-line tables in text and ``<table>`` in
HTML; dictionaries are one ``key: value`` per line (a nested table in HTML); a unit follows the value.
Full precision stays in ``rmpc solve --json`` and ``summary.json`` (:func:`problems.report.to_json`).

>>> print(format_value(np.array([[1.0, 6.123e-17], [0.5, -2.0 / 3.0]]), "m"))
[[ 1       0      ]
 [ 0.5    -0.6667 ]] m
>>> format_value([np.cos(np.pi / 2), 243.889132], "kg·m²")
'[0, 243.9] kg·m²'
"""

from __future__ import annotations

import html
import re
import textwrap
from typing import Any

import numpy as np

__all__ = ["DIGITS", "format_number", "format_value", "format_value_html", "is_quantity", "solution_text", "statement_html",
           "statement_text"]

DIGITS = 4          # significant digits shown
ARRAY_ZERO = 1e-12  # entries below this fraction of an array's largest magnitude are shown as 0
SCALAR_ZERO = 1e-15  # a scalar below this magnitude is shown as 0


def format_number(x: Any, scale: float | None = None) -> str:
    """One number with :data:`DIGITS` significant digits; 0 when |x| < 1e-12·``scale`` (``scale``
    None: a lone scalar, 0 below 1e-15); complex as ``a + bj``; bool, int and str unchanged."""
    if isinstance(x, (bool, np.bool_, str)) or x is None:
        return str(x)
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, (complex, np.complexfloating)):
        if x.imag == 0:
            return format_number(x.real, scale)
        s = max(abs(x.real), abs(x.imag)) if scale is None else scale
        re, im = format_number(x.real, s), format_number(abs(x.imag), s)
        return f"{im}j" if re == "0" and x.real == 0 else f"{re} {'-' if x.imag < 0 else '+'} {im}j"
    x = float(x)
    if not np.isfinite(x):
        return str(x)
    threshold = SCALAR_ZERO if scale is None else ARRAY_ZERO * scale
    if abs(x) < threshold:
        return "0"
    return f"{x:.{DIGITS}g}"


def _as_array(value: Any) -> np.ndarray | None:
    """A numeric array when ``value`` is one (nested lists of numbers included), else None."""
    if hasattr(value, "homogeneous") and not isinstance(value, np.ndarray):  # pin.SE3
        value = np.asarray(value.homogeneous)
    if isinstance(value, (list, tuple, np.ndarray)):
        try:
            a = np.asarray(value)
        except ValueError:  # ragged
            return None
        if a.dtype.kind in "biufc" and a.ndim >= 1:
            return a
    return None


def is_quantity(value: Any) -> bool:
    """Whether ``value`` is a number or holds numbers (an array, a list of numbers, a pose, a dictionary with a
    numeric entry): a quantity, which carries a unit ("1" when dimensionless). Text, truth values and lists of
    them are not.

    >>> [is_quantity(v) for v in (2.0, np.eye(2), [1, 2], {"a": 1.0, "b": "x"}, True, "text", ["a", "b"], None)]
    [True, True, True, True, False, False, False, False]
    """
    if isinstance(value, (bool, np.bool_, str)) or value is None:
        return False
    if isinstance(value, (int, float, complex, np.number)):
        return True
    if isinstance(value, dict):
        return any(is_quantity(v) for v in value.values())
    a = _as_array(value)
    if a is not None:
        return a.dtype.kind in "iufc"
    if isinstance(value, (list, tuple)):
        return any(is_quantity(v) for v in value)
    return False


def _entries(a: np.ndarray) -> list[str]:
    finite = np.abs(a[np.isfinite(a)]) if a.dtype.kind in "fc" else np.abs(a)
    scale = float(finite.max()) if finite.size else 0.0
    return [format_number(x, scale) for x in a.ravel()]


def _matrix_lines(a: np.ndarray) -> list[str]:
    cells = np.array(_entries(a), dtype=object).reshape(a.shape)
    width = max(len(c) for c in cells.ravel())
    rows = [" ".join(f"{c:<{width}}" if c.startswith("-") else f" {c:<{width - 1}}" for c in row) for row in cells]
    return [("[[" if i == 0 else " [") + r + " ]" + ("]" if i == len(rows) - 1 else "") for i, r in enumerate(rows)]


def format_value(value: Any, unit: str = "") -> str:
    """``value`` as text (see the module docstring), followed by ``unit``."""
    tail = f" {unit}" if unit else ""
    if isinstance(value, dict):
        lines = [f"{k}: {format_value(v)}" for k, v in value.items()]
        return "\n".join(lines) + tail
    a = _as_array(value)
    if a is not None:
        if a.ndim == 1:
            return "[" + ", ".join(_entries(a)) + "]" + tail
        if a.ndim == 2 and a.size:
            return "\n".join(_matrix_lines(a)) + tail
        return "[" + ", ".join(format_value(v) for v in a) + "]" + tail
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(format_value(v) for v in value) + "]" + tail
    return format_number(value) + tail


def format_value_html(value: Any, unit: str = "") -> str:
    """``value`` as HTML: a matrix a ``<table class="matrix">``, a dictionary a nested table, the rest
    the text of :func:`format_value` in ``<code>``; then the unit."""
    tail = f" <span class='unit'>{html.escape(unit)}</span>" if unit else ""
    if isinstance(value, dict):
        rows = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{format_value_html(v)}</td></tr>" for k, v in value.items())
        return f"<table class='dict'>{rows}</table>{tail}"
    a = _as_array(value)
    if a is not None and a.ndim == 2 and a.size:
        cells = np.array(_entries(a), dtype=object).reshape(a.shape)
        rows = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>" for row in cells)
        return f"<table class='matrix'>{rows}</table>{tail}"
    return f"<code>{html.escape(format_value(value))}</code>{tail}"


_ROLE = re.compile(r":[a-z]+(?::[a-z]+)?:`~?([^`<]*?)(?:\s*<[^>]*>)?`")       # :func:`~a.b` → b, :ref:`text <x>` → text
_LITERAL = re.compile(r"``(.+?)``")
_EMPHASIS = re.compile(r"(?<![\w*])\*(?!\s)([^*]+?)(?<!\s)\*(?![\w*])")


def _role_text(match: re.Match) -> str:
    text = match.group(1)
    return text.rsplit(".", 1)[-1] if match.group(0).split("`", 1)[1].startswith("~") else text


def statement_text(text: str) -> str:
    """A problem's statement (its docstring's first paragraph) as plain text: the reStructuredText markup removed
    (``literal`` → literal, :func:`a.b` → a.b, :class:`~a.B` → B, *emphasis* → emphasis).

    >>> statement_text("Compared with ``urdf/scara.urdf`` by :func:`~rigid_body.kinematics.direct_kinematics`; *all* q.")
    'Compared with urdf/scara.urdf by direct_kinematics; all q.'
    """
    text = _ROLE.sub(_role_text, text)
    text = _LITERAL.sub(r"\1", text)
    return _EMPHASIS.sub(r"\1", text)


def statement_html(text: str) -> str:
    """A problem's statement as HTML: literals and roles in ``<code>``, emphasis in ``<em>``, the rest escaped.

    >>> statement_html("companion ``i8_13``, K_P = 100 I & *no* payload")
    'companion <code>i8_13</code>, K_P = 100 I &amp; <em>no</em> payload'
    """
    out, last = [], 0
    pattern = re.compile(f"{_ROLE.pattern}|{_LITERAL.pattern}|{_EMPHASIS.pattern}")
    for m in pattern.finditer(text):
        out.append(html.escape(text[last:m.start()]))
        if m.group(0).startswith("*"):
            out.append(f"<em>{html.escape(m.group(3))}</em>")
        elif m.group(0).startswith("``"):
            out.append(f"<code>{html.escape(m.group(2))}</code>")
        else:
            out.append(f"<code>{html.escape(_role_text(m))}</code>")
        last = m.end()
    out.append(html.escape(text[last:]))
    return "".join(out)


MAX_LINES = 12  # a value longer than this is cut in the text view (all of it in --json)


def solution_text(sol: Any, seconds: float | None = None, figures: list[str] | None = None) -> str:
    """A solved problem as text (``rmpc solve ID``, ``print(sol)``): title, statement, values with units, checks,
    verdict."""
    timing = f", {seconds:.2f} s" if seconds is not None else ""
    out = [f"Problem {sol.id} — {sol.title} [{sol.kind}{timing}]"]
    if getattr(sol, "statement", ""):  # what is asked and the data, so the output reads without the book
        out += textwrap.wrap(statement_text(sol.statement), 100, initial_indent="  ", subsequent_indent="  ")
    for name, value in sol.values.items():
        lines = format_value(value, sol.units.get(name, "")).splitlines() or [""]
        if len(lines) > MAX_LINES:
            lines = lines[:MAX_LINES] + [f"... ({len(lines) - MAX_LINES} more lines; all of it with --json)"]
        pad = " " * (len(name) + 5)
        out.append(f"  {name} = " + f"\n{pad}".join(lines))
    out += [f"  [{'PASS' if c.passed else 'FAIL'}] {c.name}: {c.detail}" for c in sol.checks]
    out += [f"  figure: {f}" for f in figures or []]
    out.append(f"{'PASS' if sol.passed else 'FAIL'}: {sum(c.passed for c in sol.checks)} of {len(sol.checks)} checks")
    return "\n".join(out)
