"""What every control law takes: per-joint values, friction, gains, references, task rows, redundancy.

One home for the argument handling shared by the laws of :mod:`controllers.joint_space`,
:mod:`controllers.operational_space`, :mod:`controllers.force`, the plants and the simulation loop, so a law
never imports another law's helpers. Each function validates once, at construction, and names the argument.

* :func:`per_joint`, :func:`nonnegative`, :func:`as_friction` — a scalar or an (n,) vector per joint.
* :func:`as_gain`, :func:`diagonal_or_matrix`, :func:`gain_times` — positive definite gain matrices
  (scalar K I, diagonal or full) and their product with an error, per joint when diagonal.
* :func:`as_reference`, :func:`array_law` — a set point, a trajectory or a law ``t -> (x, ẋ, ẍ)`` as one
  sampled reference (vectorised over instants when the law allows it); :func:`as_pose_reference` for a pose
  task ``t -> (T_d, v_d, a_d)``; :func:`task_reference` restricts a 3-D point or law to a task's rows.
* :func:`position_rows`, :func:`check_redundancy` — the components of a position task and the rule
  "at most one task component per joint".
"""

from __future__ import annotations

from typing import Any, Callable, Sequence

import numpy as np

from rigid_body.rotations import as_homogeneous
from rigid_body.validation import as_matrix, as_positive, as_vector

Reference = Callable[[float], tuple[np.ndarray, np.ndarray, np.ndarray]]
PoseReference = Callable[[float], tuple[np.ndarray, np.ndarray, np.ndarray]]


# --------------------------------------------------------------------------------------------
# Per-joint values
# --------------------------------------------------------------------------------------------

def per_joint(value: Any, n: int, name: str) -> np.ndarray:
    """A per-joint quantity given as a scalar (the same for every joint) or (n,): a finite (n,) vector."""
    if np.ndim(value) == 0:
        value = np.full(n, as_vector(value, 1, name)[0])
    return as_vector(value, n, name).copy()


def nonnegative(value: Any, n: int, name: str) -> np.ndarray:
    """A non-negative per-joint quantity (scalar or (n,)) as a finite (n,) vector."""
    v = per_joint(value, n, name)
    if np.any(v < 0):
        raise ValueError(f"`{name}` must be non-negative, got {v}")
    return v


def as_friction(viscous_friction: Any, n: int) -> np.ndarray:
    """Viscous friction F_v (scalar or (n,)) as a finite non-negative (n,) vector [N·m·s/rad]."""
    return nonnegative(viscous_friction, n, "viscous_friction")


# --------------------------------------------------------------------------------------------
# Gains
# --------------------------------------------------------------------------------------------

def as_gain(K: Any, n: int, name: str) -> np.ndarray:
    """A gain matrix (n, n) from a scalar (K I), a vector (diag K) or a matrix; must be positive definite."""
    K_arr = np.asarray(K)
    if K_arr.dtype.kind not in "biuf":
        raise ValueError(f"`{name}` must be a number, a vector or a matrix of numbers, got {K!r:.60}")
    K_arr = K_arr.astype(float)
    if K_arr.ndim == 0:
        M = as_vector(K_arr, 1, name)[0] * np.eye(n)
    elif K_arr.ndim == 1:
        M = np.diag(as_vector(K_arr, n, name))
    else:
        M = as_matrix(K_arr, (n, n), name)
    if not np.all(np.isfinite(M)) or np.min(np.linalg.eigvalsh(0.5 * (M + M.T))) <= 0:
        raise ValueError(f"`{name}` must be a finite positive definite gain, got {K!r}")
    return M


def diagonal_or_matrix(K: np.ndarray) -> np.ndarray:
    """A gain matrix as its diagonal (n,) when it is diagonal (per-joint gains, K e = k * e), else as is."""
    return np.diag(K).copy() if np.count_nonzero(K - np.diag(np.diag(K))) == 0 else K


def gain_times(K: np.ndarray, e: np.ndarray) -> np.ndarray:
    """K e for a gain from :func:`diagonal_or_matrix`: per-joint product or matrix product."""
    return K * e if K.ndim == 1 else K @ e


# --------------------------------------------------------------------------------------------
# References
# --------------------------------------------------------------------------------------------

def as_reference(reference: Any, n: int, name: str = "reference") -> Reference:
    """``reference`` as a function ``t -> (x_d, ẋ_d, ẍ_d)`` of (n,) arrays.

    Accepts a constant (n,) vector (a set point: zero velocity and acceleration), an object with
    ``evaluate(t)`` (a :class:`planners.timing.Trajectory`) or a callable ``t -> (x, ẋ, ẍ)``.
    """
    if hasattr(reference, "evaluate"):
        law = reference.evaluate
    elif callable(reference):
        law = reference
    else:
        x_d = as_vector(reference, n, name).copy()
        zero = np.zeros(n)
        return lambda t: (x_d, zero, zero)

    def sampled(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        x, xd, xdd = law(t)
        return _as_reference_vector(x, n), _as_reference_vector(xd, n), _as_reference_vector(xdd, n)

    try:
        first = sampled(0.0)
    except (ValueError, TypeError) as err:
        raise ValueError(f"`{name}` must give (n,) = ({n},) position, velocity and acceleration: {err}") from None
    if not all(np.all(np.isfinite(v)) for v in first):
        raise ValueError(f"`{name}` must be finite, got {first} at t = 0")
    vectorised = array_law(reference)
    if vectorised is not None:                                  # the compiled loop samples it at once
        sampled.at_times = lambda times: tuple(np.reshape(v, (len(times), n)) for v in vectorised(times))
    return sampled


def array_law(reference: Any) -> Callable[[np.ndarray], tuple[np.ndarray, ...]] | None:
    """The law of ``reference`` that takes an array of instants, or None: a trajectory's timing law
    (:class:`planners.timing.Trajectory`), or ``reference`` itself when it is a timing law (``t_i``, ``t_f``
    and ``law(t)`` on arrays, :class:`planners.timing.TimingLaw`, e.g. a :class:`planners.paths.PathLaw`)."""
    if hasattr(reference, "evaluate") and hasattr(reference, "law"):
        return reference.law
    if callable(reference) and hasattr(reference, "t_i") and hasattr(reference, "t_f"):
        return reference
    return None


def _as_reference_vector(x: Any, n: int) -> np.ndarray:
    """One sample of a reference as a float (n,) array (at once when it already is one)."""
    if type(x) is np.ndarray and x.dtype == np.float64 and x.shape == (n,):
        return x
    return np.reshape(np.asarray(x, dtype=float), n)


def as_pose_reference(reference: Any, name: str = "reference") -> PoseReference:
    """``reference`` as ``t -> (T_d (4, 4), v_d = [ṗ_d; ω_d] (6,), a_d = [p̈_d; ω̇_d] (6,))``.

    Accepts a constant homogeneous transform (regulation: zero velocity and acceleration), an object
    with ``evaluate(t)`` or a callable with that signature (checked at t = 0).
    """
    if not (hasattr(reference, "evaluate") or callable(reference)):
        T_d = as_homogeneous(reference, name).copy()
        zero = np.zeros(6)
        return lambda t: (T_d, zero, zero)
    law = reference.evaluate if hasattr(reference, "evaluate") else reference
    try:
        T, v, a = law(0.0)
        as_homogeneous(T, f"{name} pose")
        as_vector(v, 6, f"{name} velocity")
        as_vector(a, 6, f"{name} acceleration")
    except (TypeError, ValueError) as err:
        raise ValueError(f"`{name}` must give (T_d (4, 4), v_d (6,), a_d (6,)) at t = 0: {err}") from None
    return law


# --------------------------------------------------------------------------------------------
# Task rows and redundancy
# --------------------------------------------------------------------------------------------

def position_rows(rows: Sequence[int]) -> np.ndarray:
    """The components ``rows`` of a position task: distinct indices in 0..2 (x, y, z), as an int array."""
    r = np.asarray(rows, dtype=int).ravel()
    if r.size == 0 or len(set(r.tolist())) != r.size or np.any((r < 0) | (r > 2)):
        raise ValueError(f"`rows` must be distinct position components in 0..2, got {rows!r}")
    return r


def task_reference(reference: Any, rows: Sequence[int]) -> Any:
    """``reference`` in the task components: a point or law given in full (x, y, z) is restricted to ``rows``.

    Lets a 3-D path law (e.g. :class:`planners.paths.PathLaw`) drive a planar task (rows (0, 1)).
    """
    r = position_rows(rows)
    if r.size == 3:
        return reference
    if hasattr(reference, "evaluate") or callable(reference):
        law = reference.evaluate if hasattr(reference, "evaluate") else reference
        if np.size(law(0.0)[0]) != 3:
            return reference
        vectorised = array_law(reference)
        if vectorised is not None:
            return _RowsOfLaw(vectorised, r)

        def restricted(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            x, xd, xdd = law(t)
            return (np.reshape(x, 3)[r], np.reshape(xd, 3)[r], np.reshape(xdd, 3)[r])

        return restricted
    v = np.asarray(reference, dtype=float).ravel()
    return v[r] if v.size == 3 else reference


class _RowsOfLaw:
    """The ``rows`` components of a timing law ``law(t) -> (x, ẋ, ẍ)`` (3,), itself a timing law (t scalar or array)."""

    def __init__(self, law: Callable[[Any], tuple], rows: np.ndarray):
        self.law, self.rows, self.t_i, self.t_f = law, rows, law.t_i, law.t_f

    def __call__(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r = self.rows
        return tuple(np.asarray(v, dtype=float)[..., r] for v in self.law(t))


def rate_options(max_condition: Any, damping: Any) -> tuple[float, float | None]:
    """(max_condition, damping) of a resolved-velocity law (:func:`rigid_body.task_space.resolved_rates`):
    a condition bound ≥ 1 and a damping λ > 0 or None (exact inverse, refused near a singularity)."""
    bound = as_positive(max_condition, "max_condition")
    if bound < 1:
        raise ValueError(f"`max_condition` must be >= 1 (a condition number), got {bound:g}")
    return bound, None if damping is None else as_positive(damping, "damping")


def check_redundancy(m: int, n: int) -> None:
    """A task of m components on n joints must have m ≤ n (one component per joint at most)."""
    if m > n:
        raise ValueError(f"`rows` must select at most {n} components (one per joint), got {m}")
