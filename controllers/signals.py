"""The names and units of the signals the book's loops log, component by component, for plots and tables.

A controller logs arrays (``h_e`` (6,), ``e_s`` (8,) …); a reader needs f_x … μ_z in N and N·m, or x₁, y₁ … of
the image points. :func:`components` gives, for a signal name and its width, one ``(label, unit)`` per column —
:meth:`controllers.simulation.SimulationResult.plot` uses it for its legend and axis label. A signal not
described here keeps ``name1, name2 …`` and its plant's unit.

>>> components("h_e", 6)[3]
('μ_x', 'N·m')
>>> [label for label, _ in components("e_s", 4)]
['x_m', 'y_m', 'L', 'α']
>>> components("e_s", 8)[:2]
[('x₁', '1'), ('y₁', '1')]
"""

from __future__ import annotations

__all__ = ["components", "point_features", "SEGMENT_FEATURES", "WRENCH", "SUBSCRIPTS"]

SUBSCRIPTS = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")

#: a wrench [f; μ] (Sect. 3.8.1): force components in N, moment components in N·m
WRENCH = (("f_x", "N"), ("f_y", "N"), ("f_z", "N"), ("μ_x", "N·m"), ("μ_y", "N·m"), ("μ_z", "N·m"))
_POSITION = (("x", "m"), ("y", "m"), ("z", "m"))
SEGMENT_FEATURES = (("x_m", "1"), ("y_m", "1"), ("L", "1"), ("α", "rad"))       # (10.28): normalised image units
_POSE_4 = (("x", "m"), ("y", "m"), ("z", "m"), ("φ", "rad"))             # the 4-DOF pose of Example 10.3


def point_features(width: int) -> list[tuple[str, str]]:
    """x₁, y₁, x₂, y₂ … of image points in normalised coordinates (10.26)."""
    return [(f"{axis}{str(k + 1).translate(SUBSCRIPTS)}", "1") for k in range(width // 2) for axis in "xy"]


def components(name: str, width: int) -> list[tuple[str, str]] | None:
    """One (label, unit) per column of the signal ``name`` of ``width`` columns, or None when not described.

    Wrenches ``h_e``, ``wrench`` (f_x … μ_z; the first two or three for a planar task), forces ``f_e``, ``f_d``
    (f_x, f_y, f_z), tip positions ``p_e``, ``p_d`` (x, y, z), image errors and features ``e_s``, ``s``, ``s_hat``
    (x_m, y_m, L, α of a segment when 4 wide — a law on two points declares its own ``signal_components`` —, else
    x₁, y₁ … of points), pose estimates ``x_hat`` (x, y, z, φ)."""
    if name in ("h_e", "wrench") and width in (2, 3, 6):
        return list(WRENCH[:width])
    if name in ("f_e", "f_d") and width in (1, 2, 3):
        return [(f"f_{axis}", "N") for axis in "xyz"[:width]]
    if name in ("p_e", "p_d") and width in (2, 3):
        return list(_POSITION[:width])
    if name in ("e_s", "s", "s_hat", "s_d"):
        if width == 4:
            return list(SEGMENT_FEATURES)
        if width % 2 == 0:
            return point_features(width)
    if name == "x_hat" and width == 4:
        return list(_POSE_4)
    return None
