"""Input checks shared by the whole package: one place for the error messages."""

from __future__ import annotations

from typing import Any

import numpy as np


def as_vector(x: Any, n: int | None, name: str) -> np.ndarray:
    """``x`` as a finite float vector of shape (n,); ValueError naming ``name`` otherwise."""
    try:
        v = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"`{name}` must be a numeric vector, got {type(x).__name__}") from None
    if v.ndim == 0 and n in (None, 1):
        v = v.reshape(1)
    if v.ndim != 1 or (n is not None and v.shape[0] != n):
        expected = f"({n},)" if n is not None else "a 1-D vector"
        raise ValueError(f"`{name}` must have shape {expected}, got {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"`{name}` must be finite, got {v}")
    return v


def as_matrix(x: Any, shape: tuple[int, int], name: str) -> np.ndarray:
    """``x`` as a finite float array of the given shape; ValueError naming ``name`` otherwise."""
    m = np.asarray(x, dtype=float)
    if m.shape != shape:
        raise ValueError(f"`{name}` must have shape {shape}, got {m.shape}")
    if not np.all(np.isfinite(m)):
        raise ValueError(f"`{name}` must be finite")
    return m


def as_positive(value: Any, name: str, allow_zero: bool = False) -> float:
    """``value`` as a finite positive (or, with ``allow_zero``, non-negative) float; ValueError naming ``name``."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"`{name}` must be a number, got {type(value).__name__}") from None
    if not (np.isfinite(v) and (v > 0 or (allow_zero and v == 0))):
        kind = "non-negative" if allow_zero else "positive"
        raise ValueError(f"`{name}` must be a finite {kind} number, got {v}")
    return v


def as_square_matrix(x: Any, n: int, name: str) -> np.ndarray:
    """A finite (n, n) matrix from a scalar (x I), a vector (diag x) or an (n, n) array; ValueError naming ``name``."""
    m = np.asarray(x, dtype=float)
    if m.ndim == 0:
        return float(as_vector(m, 1, name)[0]) * np.eye(n)
    if m.ndim == 1:
        return np.diag(as_vector(m, n, name))
    return as_matrix(m, (n, n), name)
