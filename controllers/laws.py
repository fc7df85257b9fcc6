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

import math
import operator
from typing import Any, Callable, Sequence

import numpy as np
import pinocchio as pin

from scipy.linalg import get_lapack_funcs

from controllers.simulation import LoggedController
from rigid_body.camera import perspective, to_camera_frame
from rigid_body.dynamics import forward_dynamics, friction_kernel, reference_torque_kernel
from rigid_body.rotations import as_homogeneous
from rigid_body.task_space import frame_state_kernel, pose_error_kernel, singular_task, solve_task
from rigid_body.validation import as_array, as_matrix, as_positive, as_vector

Reference = Callable[[float], tuple[np.ndarray, np.ndarray, np.ndarray]]
_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_gesv = get_lapack_funcs("gesv", (np.zeros((1, 1)),))   # LU solve without numpy.linalg's wrapper cost
PoseReference = Callable[[float], tuple[np.ndarray, np.ndarray, np.ndarray]]
_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_gesv = get_lapack_funcs("gesv", (np.zeros((1, 1)),))   # LU solve without numpy.linalg's wrapper cost


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
    K_arr = as_array(K, name)
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

        def set_point(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            return x_d, zero, zero

        set_point.at_times = lambda times: (np.broadcast_to(x_d, (len(times), n)),) + (np.zeros((len(times), n)),) * 2
        return set_point

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


def joined_reference(*parts: tuple[Callable[[float], tuple], Sequence[int]]) -> Callable[[float], tuple]:
    """One reference ``t -> tuple`` from the entries ``indices`` of several: ``parts`` are (reference, indices),
    e.g. ``((motion, (0,)), (force, (0,)))`` for (x_d, f_d). Vectorised (``at_times``) when every part is."""
    def joined(t: float) -> tuple:
        out: list = []
        for reference, indices in parts:
            values = reference(t)
            out.extend(values[i] for i in indices)
        return tuple(out)

    if all(hasattr(reference, "at_times") for reference, _ in parts):
        def at_times(times: np.ndarray) -> tuple:
            out: list = []
            for reference, indices in parts:
                values = reference.at_times(times)
                out.extend(values[i] for i in indices)
            return tuple(out)

        joined.at_times = at_times
    return joined


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


# --------------------------------------------------------------------------------------------
# One law, two executors: the primitives a law is written against
# --------------------------------------------------------------------------------------------

class SingularTask(ValueError):
    """Raised by the numeric :meth:`Numeric.solve_task` at a kinematic singularity; the law's executor
    (:meth:`ControlLaw.__call__`) turns it into :func:`rigid_body.task_space.singular_task` naming t and q."""


class Numeric:
    """The numeric primitives of a law: numpy and Pinocchio on floats, called at every sample of the Python loop.

    A law's body (:meth:`ControlLaw.law`) is written once against a namespace ``ops`` of primitives; this
    class is that namespace for the Python loop and :class:`controllers.compiled.Symbolic` the same names in
    CasADi expressions for the compiled loop, as Pinocchio's ``cpin`` mirrors ``pin`` (one algorithm, two scalar
    types). The
    robot primitives take ``(model, data, ...)`` as Pinocchio does (the symbolic ones ignore ``data``); the
    hot-path kernels (ABA, the frame state in one pass, the task solve with its 3 × 3 cofactor inverse) are
    the numeric implementations of a named primitive, in one place each. The namespace is the class itself
    (never instantiated); its symbolic twin, :class:`controllers.compiled.Symbolic`, lives with the compiled
    loop.
    """

    symbolic = False

    # rigid-body primitives (model, data, ...)
    gravity = staticmethod(pin.computeGeneralizedGravity)        # g(q), (7.39)
    rnea = staticmethod(pin.rnea)                                 # B(q) q̈ + C(q, q̇) q̇ + g(q), Sect. 7.5
    frame_state = staticmethod(frame_state_kernel)               # (T, J, J̇q̇) of a frame in one pass

    @staticmethod
    def inertia(model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
        """B(q) (7.32), CRBA (Pinocchio 4 fills both triangles)."""
        return pin.crba(model, data, q)

    @staticmethod
    def reference_torque(model: pin.Model, data: pin.Data, q: np.ndarray, qd: np.ndarray, qd_r: np.ndarray,
                         qdd_r: np.ndarray) -> np.ndarray:
        """B(q) q̈_r + C(q, q̇) q̇_r + g(q) by polarised RNEA (:func:`rigid_body.dynamics.reference_torque`)."""
        return reference_torque_kernel(model, data, q, qd, qd_r, qdd_r)

    @staticmethod
    def pose_error(model: pin.Model, data: pin.Data, space: Any, fid: int, q: np.ndarray, T_d: np.ndarray,
                   qd: np.ndarray | None) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray]:
        """(e, J, J̇q̇, T_e) of a pose task (:func:`rigid_body.task_space.pose_error`): position error and the
        quaternion (3.91) or angle–axis (3.85) orientation error, with the geometric Jacobian, in ``space``'s rows."""
        err = pose_error_kernel(model, data, fid, q, T_d, space, qd)
        return err.e, err.J, err.Jdot_qd, err.T_e

    @staticmethod
    def forward_dynamics(robot: Any, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """q̈ = B(q)⁻¹ (τ − C q̇ − g) (7.42): ABA, or the Cholesky solve for an arm with rotors (mimic joints)."""
        return forward_dynamics(robot, q, qd, tau, check=False)

    @staticmethod
    def friction(friction: Any, qd: np.ndarray, smoothing: float) -> np.ndarray:
        """τ_f = F_v q̇ + F_s sgn(q̇) (direction-dependent F_s±; tanh(q̇/ε) for ``smoothing`` ε > 0)."""
        return friction_kernel(friction, qd, smoothing)

    @staticmethod
    def integrate(model: pin.Model, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """q ⊕ v on the configuration manifold (``pin.integrate``: continuous joints, a floating base)."""
        return pin.integrate(model, q, v)

    @staticmethod
    def frame_jacobian(model: pin.Model, data: pin.Data, fid: int, q: np.ndarray) -> tuple[Any, np.ndarray]:
        """(T_e, J) of a frame: its pose (a ``pin.SE3``) and geometric Jacobian [J_P; J_O] (3.30), one pass."""
        J = pin.computeFrameJacobian(model, data, q, fid, _LWA)        # after the forward kinematics of q
        return pin.updateFramePlacement(model, data, fid), J           # a fresh SE3 (quicker than oMf[fid])

    @staticmethod
    def translation(T: Any) -> np.ndarray:
        """The origin of a pose (``pin.SE3`` or (4, 4))."""
        return T.translation if hasattr(T, "translation") else T[:3, 3]

    @staticmethod
    def contact_wrench(environment: Any, T_e: Any, v_e: np.ndarray) -> np.ndarray:
        """h_e of an environment (:mod:`controllers.environment`) at the pose T_e and twist v_e: its
        ``wrench_at(p_e, v_e)`` on plain arrays when it has one (the hot path), else ``wrench(T_e, v_e)``."""
        wrench_at = getattr(environment, "wrench_at", None)
        if wrench_at is not None:
            return wrench_at(T_e.translation, v_e)
        return environment.wrench(T_e, v_e)

    @staticmethod
    def frame_pose(model: pin.Model, data: pin.Data, fid: int, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(R, o) of a frame in the base frame (2.50): views of a fresh (4, 4) (never of ``data.oMf``, which the
        next call changes); the forward kinematics and this frame only (not every frame's placement)."""
        pin.forwardKinematics(model, data, q)
        T = pin.updateFramePlacement(model, data, fid).homogeneous         # a fresh array
        return T[:3, :3], T[:3, 3]

    @staticmethod
    def camera_jacobian(model: pin.Model, data: pin.Data, fid: int, q: np.ndarray) -> np.ndarray:
        """J_c: [v_c^c; ω_c^c] = J_c q̇ = [R_cᵀ J_P; R_cᵀ J_O] q̇ (Pinocchio's LOCAL frame Jacobian)."""
        return pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL)

    @staticmethod
    def to_camera(R: np.ndarray, o: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(X, Y, Z) (n,) each: points (n, 3) of the base frame in the frame of a camera at (R, o), (5.35)."""
        p = to_camera_frame(R, o, points)
        return p[:, 0], p[:, 1], p[:, 2]

    perspective = staticmethod(perspective)                      # (x, y, in front) of (5.40), NaN behind

    @staticmethod
    def solve_task(J: np.ndarray, b: np.ndarray) -> np.ndarray:
        """J⁻¹ b, or J† b = Jᵀ (J Jᵀ)⁻¹ b (3.52) for a redundant task (:func:`rigid_body.task_space.solve_task`);
        :class:`SingularTask` when cond(J) > SINGULAR_CONDITION."""
        x = solve_task(J, b)
        if x is None:
            raise SingularTask("the task Jacobian is singular")
        return x

    # arithmetic
    times = staticmethod(gain_times)                             # K e: a gain from diagonal_or_matrix
    sqrt = staticmethod(math.sqrt)
    fmax = staticmethod(max)
    sin = staticmethod(math.sin)
    cos = staticmethod(math.cos)
    atan2 = staticmethod(math.atan2)
    hypot = staticmethod(math.hypot)

    @staticmethod
    def norm(z: np.ndarray) -> float:
        """‖z‖ (what np.linalg.norm computes, without its dispatch)."""
        return math.sqrt(z.dot(z))

    tanh = staticmethod(np.tanh)
    sign = staticmethod(np.sign)
    maximum = staticmethod(np.maximum)                           # elementwise (fmax: two scalars)
    minimum = staticmethod(np.minimum)

    @staticmethod
    def clip(x: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
        return np.minimum(np.maximum(x, lower), upper)

    @staticmethod
    def vector(*entries: Any) -> np.ndarray:
        """A vector of scalars."""
        return np.array(entries)

    @staticmethod
    def matrix(rows: Sequence[Sequence[Any]]) -> np.ndarray:
        """A matrix of scalars, row by row."""
        return np.array(rows)

    @staticmethod
    def solve(A: np.ndarray, b: np.ndarray, why: Callable[[], str]) -> np.ndarray:
        """A⁻¹ b (LU, LAPACK's gesv without numpy's wrapper); ValueError(``why()``) when A is singular."""
        _, _, x, info = _gesv(A, b)
        if info != 0:
            raise ValueError(why())
        return x

    @staticmethod
    def unless(bad: Any, value: Callable[[], Any], why: Callable[[], str]) -> Any:
        """``value()``, or ValueError(``why()``) where ``bad`` holds (symbolically: NaN there, so the compiled loop
        stops as diverged)."""
        if bad:
            raise ValueError(why())
        return value()

    @staticmethod
    def where(mask: np.ndarray, a: Any, b: Any) -> np.ndarray:
        """Row i of ``a`` where mask_i, else of ``b`` (a scalar ``b`` or ``a`` fills its rows); ``a`` itself when
        every row is taken."""
        if type(a) is np.ndarray and mask.all():
            return a
        if getattr(a, "ndim", 0) > 1 or getattr(b, "ndim", 0) > 1:
            mask = mask[:, None]
        return np.where(mask, a, b)

    @staticmethod
    def entries(v: np.ndarray) -> list:
        """The entries of a vector as scalars (Python floats: scalar arithmetic on them is the cheapest)."""
        return v.tolist() if type(v) is np.ndarray else list(v)
    logic_and = staticmethod(operator.and_)                      # a & b: bools or boolean arrays
    logic_not = staticmethod(np.logical_not)
    repeat = staticmethod(np.repeat)

    @staticmethod
    def interleave(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """[x_1, y_1, x_2, y_2, …]."""
        return np.column_stack((x, y)).reshape(-1)

    @staticmethod
    def columns(M: np.ndarray, cols: Any) -> np.ndarray:
        """The columns ``cols`` of M."""
        return M[:, cols]

    @staticmethod
    def cond(condition: Any, then: Callable[[], Any], otherwise: Callable[[], Any]) -> Any:
        """``then()`` where ``condition`` holds, else ``otherwise()``: numerically only the branch taken is
        evaluated (a guard against 0/0); symbolically both, masked (``if_else``)."""
        return then() if condition else otherwise()

    @staticmethod
    def dot(a: np.ndarray, b: np.ndarray) -> float:
        return float(a.dot(b))

    @staticmethod
    def vertcat(*parts: Any) -> np.ndarray:
        return np.concatenate(parts)

    @staticmethod
    def horzcat(*blocks: Any) -> np.ndarray:
        return np.hstack(blocks)

    @staticmethod
    def zeros(n: int) -> np.ndarray:
        return np.zeros(n)

    @staticmethod
    def diag(M: np.ndarray) -> np.ndarray:
        """The diagonal of a square matrix, as a vector."""
        return np.diag(M).copy()

    @staticmethod
    def copy(x: np.ndarray) -> np.ndarray:
        """A copy (logged signals must not be views of arrays the law or Pinocchio overwrite)."""
        return x.copy()

    @staticmethod
    def index(rows: np.ndarray) -> np.ndarray:
        """Row indices as the backend indexes with them (``M[r, :]``, ``v[r]``, ``T[r, 3]``): an int array."""
        return rows

    @staticmethod
    def if_else(condition: bool, a: Any, b: Any) -> Any:
        return a if condition else b


def _fast_gain(K: np.ndarray) -> Any:
    """The numeric law's form of a gain: a float for a scalar, a vector for a column (n, 1) or a diagonal
    matrix (:func:`diagonal_or_matrix`), else the matrix."""
    if K.ndim == 0:
        return float(K)
    if K.ndim == 2 and K.shape[1] == 1:
        return K[:, 0].copy()
    if K.ndim == 2 and K.shape[0] == K.shape[1]:
        return diagonal_or_matrix(K)
    return K


# --------------------------------------------------------------------------------------------
# The law: one body, run by the Python loop (Numeric) and the compiled loop (Symbolic)
# --------------------------------------------------------------------------------------------

class ControlLaw(LoggedController):
    """A controller whose law is written once, :meth:`law`, against a namespace of primitives ``ops``.

    ``__call__(t, meas)`` (the Python loop) evaluates ``law(Numeric, ...)`` at every sample; ``symbolic()``
    (``simulate(..., backend="casadi")``) evaluates the same ``law(Symbolic, ...)`` once on CasADi symbols
    (:meth:`controllers.compiled.SymbolicLaw.of`). A subclass gives:

    * ``law(ops, K, q, qd, ref, **measured[, state, dt]) -> (u, signals[, next_state])`` — ``K`` the gains by
      name (numeric: their fast form, a diagonal as a vector; symbolic: the loop's parameters), ``ref`` what
      ``reference(t)`` returns (a tuple of arrays, open loop), ``measured`` the extra measurement entries it
      reads (:attr:`measurements`), ``state``/``dt`` its own state (a tuple of parts, :meth:`initial_state`)
      and the time since the previous sample (0 at the first); ``signals`` the logged signals by name;
    * ``reference`` (``t -> tuple``) and :attr:`reference_shapes` (the shape of each part), and the gains
      through :meth:`set_gains` (their values are the compiled loop's parameters ``p``);
    * ``nq``, ``nv`` (the sizes of q and q̇ the law reads).
    """

    measurements: tuple[tuple[str, int], ...] = ()
    """The extra measurement entries the law reads, (name, size): e.g. ``(("wrench", 6),)``."""
    scalars: tuple[str, ...] = ()
    """The signals logged as floats ((N,) rather than (N, 1) in the result)."""
    reference_shapes: tuple[tuple[int, ...], ...] = ()
    gains: dict[str, np.ndarray] = {}
    _K: dict[str, Any] = {}
    _state: tuple | None = None
    _t_last: float | None = None

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple, **kwargs: Any) -> tuple:
        raise NotImplementedError

    def set_gains(self, **gains: Any) -> None:
        """The law's gains by name: ``gains`` keeps their values (the compiled loop's parameters, in the shapes
        given), the numeric law reads their fast form (a float, a vector for a column or a diagonal matrix)."""
        self.gains = {name: np.asarray(value, dtype=float) for name, value in gains.items()}
        self._K = {name: _fast_gain(v) for name, v in self.gains.items()}

    def initial_state(self) -> tuple | None:
        """The law's own state after ``reset()`` (a tuple of floats/vectors), None for a static law."""
        return None

    def reset(self) -> None:
        super().reset()
        self._state = self.initial_state()
        self._t_last = None

    def measured(self, meas: Any, name: str) -> Any:
        """The measurement entry ``name`` (e.g. the sensed wrench), ValueError naming the missing sensor."""
        value = getattr(meas, name, None)
        if value is None:
            if name == "wrench":
                raise ValueError(f"{type(self).__name__} needs a force sensor: the plant's measurement has no "
                                 "`wrench` (use controllers.plants.ArmInContact)")
            raise ValueError(f"{type(self).__name__} needs the measurement `{name}`: the plant's measurement has none")
        return value

    def __call__(self, t: float, meas: Any) -> np.ndarray:
        q, qd = as_vector(meas.q, self.nq, "q"), meas.qd
        try:
            if not self.measurements and self._state is None:        # the common case, without a keyword dict
                u, signals = self.law(Numeric, self._K, q, qd, self.reference(t))
                self._log = signals
                return u
            extra = {name: self.measured(meas, name) for name, _ in self.measurements} if self.measurements else {}
            if self._state is None:
                u, signals = self.law(Numeric, self._K, q, qd, self.reference(t), **extra)
            else:
                dt = 0.0 if self._t_last is None else t - self._t_last
                self._t_last = t
                u, signals, self._state = self.law(Numeric, self._K, q, qd, self.reference(t), **extra,
                                                   state=self._state, dt=dt)
        except SingularTask:
            raise singular_task(f"at t = {t:.6g} s, q = {q}") from None
        self._log = signals                                  # record(**signals), without copying the dict
        return u

    def symbolic(self) -> Any:
        """The law in CasADi expressions for ``simulate(..., backend="casadi")``, its parameters this
        controller's gains (a :class:`controllers.compiled.SymbolicLaw`)."""
        from controllers.compiled import SymbolicLaw

        return SymbolicLaw.of(self)
