"""What the chapter modules share: error measures for checks, random test data, figure helpers.

* checks — :func:`max_abs_error`, :func:`max_error` (the largest over pairs), :func:`max_relative_error`;
* random data for the checks at many points — :func:`unit`, :func:`random_rotation`,
  :func:`random_quaternion` (always from a seeded ``np.random.Generator``);
* figures — :func:`subplots` makes a bare :class:`matplotlib.figure.Figure` (no pyplot, so no
  backend is chosen and nothing stays open: a chapter module can be imported in a notebook without
  touching its backend), :func:`label_axes` the axes epilogue (labels with units, grid, a legend
  when more than one line is labelled); ``Solution.figure(fig, title)`` the figure epilogue.
"""

from __future__ import annotations

from typing import Any, Iterable

import numpy as np
import pinocchio as pin
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from problems.report import FIGURE_DPI

__all__ = ["max_abs_error", "max_error", "max_relative_error", "unit", "random_rotation", "random_quaternion", "subplots",
           "label_axes", "frames_figure"]


# -- checks ------------------------------------------------------------------------------------

def max_abs_error(a: Any, b: Any) -> float:
    """max |a − b| over the elements of two real arrays of the same shape.

    >>> max_abs_error([1.0, 2.0], [1.0, 2.5])
    0.5
    """
    return float(np.max(np.abs(np.asarray(a, dtype=float) - np.asarray(b, dtype=float))))


def max_error(pairs: Iterable[tuple[Any, Any]]) -> float:
    """max over the pairs (a, b) of :func:`max_abs_error` (a, b).

    >>> max_error([([1.0, 2.0], [1.0, 2.5]), (np.eye(2), np.eye(2))])
    0.5
    """
    return max(max_abs_error(a, b) for a, b in pairs)


def max_relative_error(a: Any, b: Any) -> float:
    """max |a − b| / |b| elementwise (``b`` the reference; complex allowed).

    >>> max_relative_error([1.1, 2.0], [1.0, 2.0])
    0.10000000000000009
    """
    a, b = np.asarray(a), np.asarray(b)
    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-300)))


# -- random data -------------------------------------------------------------------------------

def unit(v: Any) -> np.ndarray:
    """v / ‖v‖."""
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """R = exp(S(ϑ r)): a random unit axis r and angle ϑ ∈ [−π, π) (Eq. (2.25) via ``pin.exp3``)."""
    return pin.exp3(rng.uniform(-np.pi, np.pi) * unit(rng.normal(size=3)))


def random_quaternion(rng: np.random.Generator, positive_scalar: bool = False) -> np.ndarray:
    """A random unit quaternion {η, ε} (scalar first); ``positive_scalar`` picks the sign with η ≥ 0."""
    Q = unit(rng.normal(size=4))
    return -Q if positive_scalar and Q[0] < 0 else Q


# -- figures -----------------------------------------------------------------------------------

def subplots(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float] | None = None,
             **kwargs: Any) -> tuple[Figure, Any]:
    """``(fig, axes)`` like ``plt.subplots`` but on a bare :class:`~matplotlib.figure.Figure`.

    >>> fig, axes = subplots(1, 2, figsize=(6, 3))
    >>> type(fig).__name__, axes.shape
    ('Figure', (2,))
    """
    fig = _figure(figsize)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def _figure(figsize: tuple[float, float] | None) -> Figure:
    """A bare figure at the report's resolution with its own Agg canvas: ``tight_layout`` and the report's
    ``savefig`` then share one renderer (its text metrics are measured once, not once per pass)."""
    fig = Figure(figsize=figsize, dpi=FIGURE_DPI)
    FigureCanvasAgg(fig)
    return fig


def label_axes(ax: Any, xlabel: str | None = None, ylabel: str | None = None, *, title: str | None = None,
               legend: bool | str | None = None, grid: bool = True, **legend_kwargs: Any) -> Any:
    """The axes epilogue: labels (give units: "t [s]"), a light grid, and a small legend.

    ``legend=None`` draws one when two or more artists carry a label, ``True`` always, ``False``
    never, a string is its ``loc``. Returns ``ax``.
    """
    if xlabel is not None:
        ax.set_xlabel(xlabel)
    if ylabel is not None:
        ax.set_ylabel(ylabel)
    if title is not None:
        ax.set_title(title)
    if grid:
        ax.grid(True, alpha=0.3)
    if legend is None:
        legend = len(ax.get_legend_handles_labels()[1]) > 1
    if legend:
        legend_kwargs.setdefault("fontsize", "small")
        if isinstance(legend, str):
            legend_kwargs["loc"] = legend
        ax.legend(**legend_kwargs)
    return ax


def frames_figure(robot: Any, q: Any, title: str, length: float | None = None, z_down: bool = False) -> Figure:
    """The DH frames of ``robot`` at ``q`` (the manual's frame drawings, e.g. Figs. S2.2, S2.3, S7.1):
    a 3-D view with the links as a polyline through the frame origins and x (red), y (green), z (blue)
    axes drawn at each origin ``frame_0 … frame_n``. ``z_down`` draws z₀ pointing down (the SCARA's
    convention, Fig. S2.3)."""
    from rigid_body.kinematics import frame_poses

    names = [f.name for f in robot.model.frames if f.name.startswith("frame_") and f.name[6:].isdigit()]
    poses = frame_poses(robot, np.asarray(q, dtype=float), names)
    origins = np.array([T[:3, 3] for T in poses])
    span = float(np.ptp(origins, axis=0).max()) or 1.0
    length = 0.2 * span if length is None else length
    fig = _figure((7, 5.5))
    ax = fig.add_subplot(projection="3d")
    ax.plot(*origins.T, "k-", lw=2, label="links (frame origins)")
    for k, (name, color) in enumerate((("x", "r"), ("y", "g"), ("z", "b"))):
        d = np.array([T[:3, k] for T in poses]) * length
        ax.quiver(*origins.T, *d.T, color=color, label=f"{name} axes")
    for name, o in zip(names, origins):
        ax.text(*o, name.replace("frame_", " "), fontsize="small")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_box_aspect(np.maximum(np.ptp(origins, axis=0) + 2 * length, 1e-3))
    if z_down:
        ax.invert_zaxis()
    ax.legend(fontsize="small", loc="upper left")
    fig.suptitle(title)
    return fig
