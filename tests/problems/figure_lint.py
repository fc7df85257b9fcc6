"""The figure lint of the problems: axis labels carry units, several lines carry a legend.

Used by ``test_all_problems.py`` on every solved problem. A unit is written ``[m]``, ``(rad)``,
``/ s`` or the word ``dimensionless`` (``[-]`` also marks a pure number).
"""

from __future__ import annotations

import re

import numpy as np

UNIT = re.compile(r"\[[^\]]*\]|\([^)]*\)|/\s*\S+|dimensionless")


def _styles(ax) -> set:
    """The distinct (colour, line style) of the drawn lines of ``ax`` with more than one point (vertical
    event markers, ``axvline``, excluded: they are annotated in place)."""
    styles = set()
    for line in ax.get_lines():
        x = np.asarray(line.get_xdata(), dtype=float)
        if len(x) > 1 and np.ptp(x) > 0 and line.get_linestyle() not in ("None", "", " "):
            styles.add((str(line.get_color()), line.get_linestyle()))
    return styles


def lint_figure(fig) -> list[str]:
    """What a reader misses on ``fig``: an axis label without a unit, a legend for several line styles."""
    problems = []
    title = fig._suptitle.get_text() if getattr(fig, "_suptitle", None) is not None else "figure"
    for k, ax in enumerate(fig.axes):
        if not ax.axison or not (ax.get_lines() or ax.collections or ax.images or ax.patches):
            continue
        if ax.get_label() == "<colorbar>":
            continue
        where = f"{title!r} axes {k}"
        names = [("x", ax.get_xlabel()), ("y", ax.get_ylabel())]
        if hasattr(ax, "get_zlabel"):
            names.append(("z", ax.get_zlabel()))
        for axis, label in names:
            if not label:
                shared = getattr(ax, f"get_shared_{axis}_axes", None)
                if axis == "x" and shared is not None and len(shared().get_siblings(ax)) > 1:
                    continue  # a shared x axis is labelled once, under the bottom panel
                problems.append(f"{where}: no {axis} label")
            elif not UNIT.search(label):
                problems.append(f"{where}: {axis} label {label!r} has no unit")
        if len(_styles(ax)) > 1 and ax.get_legend() is None and fig.legends == []:
            problems.append(f"{where}: {len(_styles(ax))} line styles and no legend")
    return problems
