"""The figure lint of the problems: what a reader of a figure would miss.

Used by ``test_all_problems.py`` on every solved problem (after its layout, as the report saves it):

* axis labels carry units — ``[m]``, ``(rad)``, ``/ s`` or the word ``dimensionless`` (``[-]`` marks a pure
  number); several line styles carry a legend;
* every label, title and legend lies inside the canvas (a clipped label is unreadable);
* no text shows TeX that is not rendered: ``_{…}`` or ``^{…}`` outside ``$…$`` (mathtext renders it inside);
* marked points (a start, a goal: a few points drawn with a marker) lie inside the axes' limits;
* a categorical map (an image of a few integer labels, a component map or an occupancy grid) has a colour key:
  a colour bar of that image, or legend entries that are colour patches;
* a legend inside the axes does not cover the text annotations of the axes (cell values, labels);
* a norm or an error measure (a y label with ‖…‖, "norm" or "error") whose positive curve spans more than two
  decades is drawn on a log axis (on a linear one its exponential rate is invisible);
* legend text stays legible in the report: at least :data:`LEGIBLE_PX` pixels high where the report shows the
  figure (saved at ``problems.report.FIGURE_DPI``, shown at its own width up to :data:`REPORT_WIDTH_PX`).
"""

from __future__ import annotations

import re

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.image import AxesImage
from matplotlib.patches import Patch

UNIT = re.compile(r"\[[^\]]*\]|\([^)]*\)|/\s*\S+|dimensionless")
RAW_TEX = re.compile(r"[_^]\{")
#: A categorical map has at most this many distinct integer values (more is a quantity, e.g. a cost-to-go).
CATEGORIES = 12
#: A positive norm or error curve spanning more decades than this wants a log axis.
DECADES = 2.0
#: The smallest legend text [px] as the report shows a figure, and the widest a figure is shown there [px].
LEGIBLE_PX, REPORT_WIDTH_PX = 8.0, 1080.0
DECAYING = re.compile(r"‖|\|\||\bnorm\b|\berror\b", re.IGNORECASE)


def _styles(ax) -> set:
    """The distinct (colour, line style) of the drawn lines of ``ax`` with more than one point (vertical
    event markers, ``axvline``, excluded: they are annotated in place)."""
    styles = set()
    for line in ax.get_lines():
        x = np.asarray(line.get_xdata(), dtype=float)
        if len(x) > 1 and np.ptp(x) > 0 and line.get_linestyle() not in ("None", "", " "):
            styles.add((str(line.get_color()), line.get_linestyle()))
    return styles


def _renderer(fig):
    """A renderer of ``fig`` with its texts placed (a bare figure gets an Agg canvas)."""
    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    fig.draw_without_rendering()
    return canvas.get_renderer()


def _texts(fig):
    """(what, Text) of every visible non-empty text of the figure: titles, axis labels, legends, annotations."""
    out = []
    if getattr(fig, "_suptitle", None) is not None:
        out.append(("suptitle", fig._suptitle))
    for legend in fig.legends:
        out += [("figure legend", t) for t in legend.get_texts()]
    for k, ax in enumerate(fig.axes):
        where = f"axes {k}"
        out += [(f"{where} title", t) for t in (ax.title, ax._left_title, ax._right_title)]
        out += [(f"{where} x label", ax.xaxis.label), (f"{where} y label", ax.yaxis.label)]
        if hasattr(ax, "zaxis"):
            out.append((f"{where} z label", ax.zaxis.label))
        if ax.get_legend() is not None:
            out += [(f"{where} legend", t) for t in ax.get_legend().get_texts()]
        if not hasattr(ax, "zaxis"):     # a 3-D annotation's window extent ignores its projection
            out += [(f"{where} annotation", t) for t in ax.texts]
    return [(w, t) for w, t in out if t.get_visible() and t.get_text().strip()]


def _raw_tex(text: str) -> bool:
    """``_{`` or ``^{`` outside the ``$…$`` spans that mathtext renders."""
    outside = re.sub(r"(?<!\\)\$.*?(?<!\\)\$", "", text)
    return bool(RAW_TEX.search(outside))


def _categorical(image: AxesImage) -> bool:
    a = np.ma.masked_invalid(np.ma.asarray(image.get_array(), dtype=float)).compressed()
    if a.size == 0 or np.ma.asarray(image.get_array()).ndim != 2:      # RGB(A) pictures are no maps
        return False
    values = np.unique(a)
    return 2 <= values.size <= CATEGORIES and np.all(values == np.round(values))


def _has_key(fig, ax, image: AxesImage) -> bool:
    """A colour bar of ``image``, or colour patches among the legend entries of ``ax`` or of the figure."""
    if getattr(image, "colorbar", None) is not None:
        return True
    handles = list(ax.get_legend().legend_handles) if ax.get_legend() is not None else []
    for legend in fig.legends:
        handles += list(legend.legend_handles)
    return any(isinstance(h, Patch) for h in handles)


def _marked_points_outside(ax) -> list[str]:
    """Labels (or indices) of the marked points (a line of at most 5 points with a marker) outside the limits."""
    if hasattr(ax, "zaxis"):
        return []
    (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
    out = []
    for k, line in enumerate(ax.get_lines()):
        x, y = (np.asarray(v, dtype=float) for v in line.get_data())
        if line.get_marker() in (None, "", " ", "None") or not 0 < x.size <= 5:
            continue
        ok = (x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)
        if not np.all(ok | ~np.isfinite(x) | ~np.isfinite(y)):
            out.append(line.get_label() if not line.get_label().startswith("_") else f"line {k}")
    return out


def _legend_covers_texts(ax, renderer) -> int:
    """How many text annotations of ``ax`` the legend's box overlaps."""
    legend = ax.get_legend()
    if legend is None or not ax.texts:
        return 0
    box = legend.get_window_extent(renderer)
    return sum(t.get_visible() and box.overlaps(t.get_window_extent(renderer)) for t in ax.texts)


def _decades_on_linear_axis(ax) -> float:
    """The most decades a positive drawn curve of ``ax`` spans on a linear y axis labelled as a norm or an error
    (0 on a log axis or for other quantities)."""
    if ax.get_yscale() != "linear" or hasattr(ax, "zaxis") or not DECAYING.search(ax.get_ylabel()):
        return 0.0
    worst = 0.0
    for line in ax.get_lines():
        y = np.asarray(line.get_ydata(), dtype=float)
        y = y[np.isfinite(y)]
        if y.size > 5 and np.all(y > 0):
            worst = max(worst, float(np.log10(y.max() / y.min())))
    return worst


def lint_figure(fig) -> list[str]:
    """What a reader misses on ``fig`` (see the module docstring), one message each."""
    problems = []
    title = fig._suptitle.get_text() if getattr(fig, "_suptitle", None) is not None else "figure"
    renderer = _renderer(fig)
    canvas = fig.bbox
    for what, text in _texts(fig):
        box = text.get_window_extent(renderer)
        if box.x0 < canvas.x0 - 1 or box.y0 < canvas.y0 - 1 or box.x1 > canvas.x1 + 1 or box.y1 > canvas.y1 + 1:
            problems.append(f"{title!r} {what} {text.get_text()!r} is cut by the canvas's edge")
        if _raw_tex(text.get_text()):
            problems.append(f"{title!r} {what} {text.get_text()!r} shows TeX that is not rendered (wrap it in $…$)")
    from problems.report import FIGURE_DPI

    scale = FIGURE_DPI / 72.0 * min(1.0, REPORT_WIDTH_PX / (fig.get_figwidth() * FIGURE_DPI))   # px per point shown
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    small = [t.get_text() for legend in legends for t in legend.get_texts() if t.get_fontsize() * scale < LEGIBLE_PX]
    if small:
        problems.append(f"{title!r}: legend text {small[:3]} below {LEGIBLE_PX:g} px in the report (font "
                        f"{min(t.get_fontsize() for lg in legends for t in lg.get_texts()):g} pt)")
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
        outside = _marked_points_outside(ax)
        if outside:
            problems.append(f"{where}: marked points outside the axes' limits: {outside}")
        for image in ax.images:
            if _categorical(image) and not _has_key(fig, ax, image):
                problems.append(f"{where}: a categorical map without a colour key (a colour bar or legend patches)")
        covered = _legend_covers_texts(ax, renderer)
        if covered:
            problems.append(f"{where}: the legend covers {covered} text annotations")
        decades = _decades_on_linear_axis(ax)
        if decades > DECADES:
            problems.append(f"{where}: a positive {ax.get_ylabel()!r} spans {decades:.1f} decades on a linear axis "
                            "(a log axis shows its rate)")
    return problems
