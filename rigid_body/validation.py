"""Input checks shared by the whole package: one place for the error messages.

Every check raises ``ValueError`` naming the argument (shape, non-numeric, NaN/inf, range); the fast
path (a well-formed float array) costs a type test and one finiteness test (:func:`as_vector`: the sum of
the entries). The Pinocchio wrappers of :mod:`rigid_body.dynamics` and :mod:`rigid_body.kinematics` inline
that test and fall back on :func:`as_vector` for the messages (their docstring).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

MAX_TOL = 1e-3  # the largest tolerance a geometric check accepts (rotations, Euler singularities)


def _as_float_array(x: Any, name: str, what: str) -> np.ndarray:
    """``x`` as a float array; ValueError naming ``name`` for anything that is not numbers — text too, which
    numpy would parse ("2" → 2.0): a number given as a string is a mistake to report, not to guess."""
    if type(x) is np.ndarray and x.dtype == np.float64:
        return x
    try:
        a = np.asarray(x)
        if a.dtype.kind in "USO" and (a.dtype.kind != "O" or _has_text(a)):
            raise TypeError
        return a.astype(float) if a.dtype != np.float64 else a
    except (TypeError, ValueError):
        raise ValueError(f"`{name}` must be {what}, got {type(x).__name__} {x!r:.60}") from None


def _has_text(a: np.ndarray) -> bool:
    """Whether an object array holds text (str or bytes) anywhere."""
    return any(isinstance(v, (str, bytes)) for v in a.ravel().tolist())


_FLOAT64, _NDARRAY, _isfinite = np.dtype(np.float64), np.ndarray, math.isfinite


def as_array(x: Any, name: str) -> np.ndarray:
    """``x`` as a float array of any shape (not checked for finiteness); ValueError naming ``name`` when it is
    not numbers (text too: "2" is not 2.0)."""
    return _as_float_array(x, name, "numbers")


def as_vector(x: Any, n: int | None, name: str) -> np.ndarray:
    """``x`` as a finite float vector of shape (n,); ValueError naming ``name`` otherwise.

    A float64 vector of the right size whose sum (x·x beyond 16 entries) is finite is returned as it is
    at once (~0.2 µs: the sum is NaN or inf when an entry is; should it overflow, the full checks below
    take over); anything else goes through the full checks and their messages.
    """
    if type(x) is _NDARRAY and x.dtype is _FLOAT64 and x.ndim == 1 and (n is None or x.shape[0] == n) \
            and _isfinite(sum(x.tolist()) if x.shape[0] <= 16 else x.dot(x)):
        return x
    v = _as_float_array(x, name, "a numeric vector")
    if v.ndim == 0 and n in (None, 1):
        v = v.reshape(1)
    if v.ndim != 1 or (n is not None and v.shape[0] != n):
        expected = f"({n},)" if n is not None else "a 1-D vector"
        raise ValueError(f"`{name}` must have shape {expected}, got {v.shape}")
    if not np.isfinite(v).all():
        raise ValueError(f"`{name}` must be finite, got {v}")
    return v


def as_matrix(x: Any, shape: tuple[int, int], name: str) -> np.ndarray:
    """``x`` as a finite float array of the given shape; ValueError naming ``name`` otherwise."""
    m = _as_float_array(x, name, "a numeric array")
    if m.shape != shape:
        raise ValueError(f"`{name}` must have shape {shape}, got {m.shape}")
    if not np.isfinite(m).all():
        raise ValueError(f"`{name}` must be finite")
    return m


def as_scalar(value: Any, name: str) -> float:
    """``value`` as a finite float; ValueError naming ``name`` (non-numeric, NaN, inf, more than one value)."""
    if isinstance(value, (float, int, np.floating, np.integer)) and not isinstance(value, bool):
        v = float(value)
    else:
        v = float(as_vector(_as_float_array(value, name, "a number"), 1, name)[0])  # 0-d or (1,); else a shape error
    if not math.isfinite(v):
        raise ValueError(f"`{name}` must be finite, got {v}")
    return v


def as_positive(value: Any, name: str, allow_zero: bool = False) -> float:
    """``value`` as a finite positive (or, with ``allow_zero``, non-negative) float; ValueError naming ``name``."""
    if isinstance(value, (str, bytes)):
        raise ValueError(f"`{name}` must be a number, got {type(value).__name__} {value!r:.60}")
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


def as_count(value: Any, name: str, minimum: int = 1) -> int:
    """``value`` as an integer ≥ ``minimum`` (a number of samples, points, ...); ValueError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        if not (isinstance(value, (float, np.floating)) and float(value).is_integer()):
            raise ValueError(f"`{name}` must be an integer >= {minimum}, got {value!r}")
    if value < minimum:
        raise ValueError(f"`{name}` must be an integer >= {minimum}, got {value!r}")
    return int(value)


def as_tolerance(tol: Any, name: str = "tol", upper: float = MAX_TOL) -> float:
    """``tol`` as a tolerance in (0, ``upper``]: a larger one would accept wrong answers, a non-positive one
    would miss exact cases (ValueError naming ``name``)."""
    t = as_scalar(tol, name)
    if not 0.0 < t <= upper:
        raise ValueError(f"`{name}` must be in (0, {upper:g}], got {t:g}")
    return t


def as_points(x: Any, dim: int, name: str) -> np.ndarray:
    """``x`` as a finite (n, dim) float array (a single point (dim,) becomes (1, dim))."""
    a = np.asarray(x, dtype=float)
    if a.ndim == 1 and a.shape[0] == dim:
        a = a.reshape(1, dim)
    if a.ndim != 2 or a.shape[1] != dim or a.shape[0] == 0:
        raise ValueError(f"`{name}` must have shape (n, {dim}), got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"`{name}` must be finite")
    return a


def as_generator(rng: Any, name: str = "rng") -> np.random.Generator:
    """``rng`` as a ``numpy.random.Generator``: a Generator is used as it is (its state advances), an integer
    seeds a new one (as ``numpy.random.default_rng`` does); anything else (None, a float, a legacy
    RandomState) raises ValueError naming ``name`` — a seeded run must repeat exactly."""
    if isinstance(rng, np.random.Generator):
        return rng
    if isinstance(rng, (int, np.integer)) and not isinstance(rng, bool):
        if rng < 0:
            raise ValueError(f"`{name}` as a seed must be a non-negative integer, got {rng}")
        return np.random.default_rng(int(rng))
    raise ValueError(f"`{name}` must be an integer seed or a numpy.random.Generator, got {type(rng).__name__} "
                     f"{rng!r:.40}")
