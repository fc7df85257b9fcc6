"""Compiled backend of the one simulation loop: ``simulate(..., backend="casadi")``.

The same loop as :func:`controllers.simulation.simulate` — the one RK4 of step ``h``
(:func:`rigid_body.integration.rk4_step_law`) on the plant, the controller every ``Ts`` with zero-order
hold — as CasADi expressions: one *sample* (the controller's law, then ``Ts/h`` RK4 steps with the output
held) is a ``casadi.Function`` ``(x_k, r_k, p) → (x_{k+1}, u_k, signals)`` and the whole run is that function
accumulated over the samples (``Function.mapaccum``), generated as C and compiled with the system C compiler.

The blocks are written once (:mod:`controllers.laws`): a controller's body ``law(ops, …)`` and a plant's
``dynamics(ops, x, u)`` are evaluated here on symbols with :class:`Symbolic`, the twin of
:class:`controllers.laws.Numeric` (the Python loop's primitives). What the loop needs from its blocks, beside
the contract of :mod:`controllers.simulation`:

* the plant: ``dynamics(ops, x, u)`` (or ``symbolic() -> casadi.Function (x, u) → ẋ``), a ``state_layout``
  with ``q`` and ``qd`` (where the law reads them in x), ``integrate_law`` when the state is on a manifold
  (nq ≠ nv) and ``symbolic_measurement(name)`` for what else the law reads (the sensed ``wrench``);
* the controller: a :class:`~controllers.laws.ControlLaw` (or ``symbolic() -> SymbolicLaw``): the law
  ``(q, q̇, r, p[, measurements][, state, dt]) → (u[, next_state], signals…)``. The reference ``r`` is open loop
  (a function of time only), sampled at the controller instants before the run (at once when it can:
  ``at_times``) and fed to it, as are the camera's noise and occlusion of a visual servo; the parameters ``p``
  are the gains (the numeric controller's values); the law's own state starts at its value after ``reset()``.

The run is keyed by a digest of the blocks' structure (:func:`loop_key`: no code generated), built once per
process (:func:`compiled_loop`) and cached on disk (``$RMPC_CACHE``, :mod:`rigid_body.codegen`) with the names
of its signals, safely under concurrency; a compiler or cache fault sends ``simulate`` to the Python loop with one warning
(:class:`CompiledLoopUnavailable`). A block without a symbolic form is refused through one path,
:func:`no_symbolic_form`.

Because the run is one CasADi function of ``(x_0, R, p)``, its derivatives with respect to the
initial state and the gains come by automatic differentiation (:meth:`CompiledLoop.rollout`):
gain tuning by gradient-based optimisation over the whole closed-loop response
(``examples/gain_tuning.py``).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 8.4
(the closed loops); Andersson et al., *CasADi*, Math. Prog. Comp. 11 (2019) (map/mapaccum, codegen).
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import pickle
import threading
import time
import types
import warnings
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import casadi as ca
import numpy as np
import pinocchio as pin

from rigid_body import codegen
from rigid_body.codegen import COMPILE_FLAGS, CompiledLoopUnavailable, key_lock  # noqa: F401 (the loop's fault)
from rigid_body.integration import rk4_step_law
from rigid_body.task_space import FrameState

BACKENDS = ("python", "casadi")


# --------------------------------------------------------------------------------------------
# The symbolic primitives of a law (the twin of controllers.laws.Numeric)
# --------------------------------------------------------------------------------------------

class Symbolic:
    """The symbolic primitives of a law: the names of :class:`Numeric` in CasADi SX expressions
    (:mod:`rigid_body.symbolic`), for the compiled loop (:mod:`controllers.compiled`); called once, when the
    loop is built. Branches of the numeric law (a singular task, a point not seen) become masked expressions
    (``if_else``)."""

    symbolic = True

    @staticmethod
    def gravity(model: pin.Model, data: Any, q: Any) -> Any:
        from rigid_body.symbolic import gravity_expression

        return gravity_expression(model, q)

    @staticmethod
    def rnea(model: pin.Model, data: Any, q: Any, qd: Any, qdd: Any) -> Any:
        from rigid_body.symbolic import inverse_dynamics_expression

        return inverse_dynamics_expression(model, q, qd, qdd)

    @staticmethod
    def inertia(model: pin.Model, data: Any, q: Any) -> Any:
        from rigid_body.symbolic import inertia_expression

        return inertia_expression(model, q)

    @staticmethod
    def reference_torque(model: pin.Model, data: Any, q: Any, qd: Any, qd_r: Any, qdd_r: Any) -> Any:
        from rigid_body.symbolic import reference_torque_expression

        return reference_torque_expression(model, q, qd, qd_r, qdd_r)

    @staticmethod
    def frame_state(model: pin.Model, data: Any, fid: int, q: Any, qd: Any) -> FrameState:
        """(T (4×4), J, J̇q̇ = ∂(J q̇)/∂q q̇, the classical acceleration at q̈ = 0, or None)."""
        from rigid_body.symbolic import frame_state_expression

        return FrameState(*frame_state_expression(model, fid, q, qd))

    @staticmethod
    def pose_error(model: pin.Model, data: Any, space: Any, fid: int, q: Any, T_d: Any, qd: Any) -> tuple:
        from rigid_body.symbolic import frame_state_expression, orientation_error_expression

        ca = _casadi()
        T, J, Jdot_qd = frame_state_expression(model, fid, q, qd)
        e = ca.vertcat(T_d[:3, 3] - T[:3, 3], orientation_error_expression(T_d[:3, :3], T[:3, :3], space.orientation))
        rows = list(space.selected)
        return e[rows], J[rows, :], None if Jdot_qd is None else Jdot_qd[rows], T

    @staticmethod
    def forward_dynamics(robot: Any, q: Any, qd: Any, tau: Any) -> Any:
        from rigid_body.symbolic import forward_dynamics_expression

        return forward_dynamics_expression(robot, q, qd, tau)

    @staticmethod
    def friction(friction: Any, qd: Any, smoothing: float) -> Any:
        from rigid_body.symbolic import friction_expression

        return friction_expression(friction, qd, smoothing)

    @staticmethod
    def integrate(model: pin.Model, q: Any, v: Any) -> Any:
        from rigid_body.symbolic import integrate_expression

        return integrate_expression(model, q, v)

    @staticmethod
    def frame_jacobian(model: pin.Model, data: Any, fid: int, q: Any) -> tuple[Any, Any]:
        from rigid_body.symbolic import frame_state_expression

        T, J, _ = frame_state_expression(model, fid, q)
        return T, J

    @staticmethod
    def translation(T: Any) -> Any:
        return T[:3, 3]

    @staticmethod
    def contact_wrench(environment: Any, T_e: Any, v_e: Any) -> Any:
        """The environment's one body ``wrench_law(ops, p_e, v_e)`` on symbols (a position-only environment)."""
        law = getattr(environment, "wrench_law", None)
        if law is None:
            raise no_symbolic_form(environment, "an environment needs wrench_law(ops, p_e, v_e)")
        return law(Symbolic, T_e[:3, 3], v_e)

    @staticmethod
    def frame_pose(model: pin.Model, data: Any, fid: int, q: Any) -> tuple[Any, Any]:
        from rigid_body.symbolic import pose_function

        R, p, _ = pose_function(model, fid)(q)
        return R, p

    @staticmethod
    def camera_jacobian(model: pin.Model, data: Any, fid: int, q: Any) -> Any:
        from rigid_body.symbolic import pose_function

        R, _, J = pose_function(model, fid)(q)
        return _casadi().vertcat(R.T @ J[:3, :], R.T @ J[3:, :])

    @staticmethod
    def to_camera(R: Any, o: Any, points: np.ndarray) -> tuple[Any, Any, Any]:
        ca = _casadi()
        p = R.T @ (ca.DM(points.T) - ca.repmat(o, 1, points.shape[0]))            # (5.35)
        return p[0, :].T, p[1, :].T, p[2, :].T

    @staticmethod
    def perspective(X: Any, Y: Any, Z: Any) -> tuple[Any, Any, Any]:
        ca = _casadi()
        in_front = Z > 0
        Z_seen = ca.if_else(in_front, Z, np.nan)
        return X / Z_seen, Y / Z_seen, in_front

    @staticmethod
    def solve_task(J: Any, b: Any) -> Any:
        """J⁻¹ b or Jᵀ (J Jᵀ)⁻¹ b (LU); a singular J gives non-finite values (the compiled loop stops there)."""
        ca = _casadi()
        return ca.solve(J, b) if J.shape[0] == J.shape[1] else J.T @ ca.solve(J @ J.T, b)

    @staticmethod
    def times(K: Any, e: Any) -> Any:
        ca = _casadi()
        if isinstance(K, np.ndarray) and K.ndim == 1:
            return ca.DM(K) * e
        return K @ e

    @staticmethod
    def sqrt(x: Any) -> Any:
        return _casadi().sqrt(x)

    @staticmethod
    def fmax(a: Any, b: Any) -> Any:
        return _casadi().fmax(a, b)

    @staticmethod
    def sin(x: Any) -> Any:
        return _casadi().sin(x)

    @staticmethod
    def cos(x: Any) -> Any:
        return _casadi().cos(x)

    @staticmethod
    def atan2(y: Any, x: Any) -> Any:
        return _casadi().atan2(y, x)

    @staticmethod
    def norm(z: Any) -> Any:
        ca = _casadi()
        return ca.sqrt(ca.dot(z, z))

    @staticmethod
    def tanh(x: Any) -> Any:
        return _casadi().tanh(x)

    @staticmethod
    def sign(x: Any) -> Any:
        return _casadi().sign(x)

    @staticmethod
    def maximum(a: Any, b: Any) -> Any:
        return _casadi().fmax(a, b)

    @staticmethod
    def minimum(a: Any, b: Any) -> Any:
        return _casadi().fmin(a, b)

    @staticmethod
    def clip(x: Any, lower: Any, upper: Any) -> Any:
        ca = _casadi()
        return ca.fmin(ca.fmax(x, lower), upper)

    @staticmethod
    def vector(*entries: Any) -> Any:
        return _casadi().vertcat(*entries)

    @staticmethod
    def matrix(rows: Sequence[Sequence[Any]]) -> Any:
        ca = _casadi()
        return ca.vertcat(*[ca.horzcat(*row) for row in rows])

    @staticmethod
    def solve(A: Any, b: Any, why: Callable[[], str]) -> Any:
        return _casadi().solve(A, b)

    @staticmethod
    def unless(bad: Any, value: Callable[[], Any], why: Callable[[], str]) -> Any:
        return _casadi().if_else(bad, np.nan, value())

    @staticmethod
    def where(mask: Any, a: Any, b: Any) -> Any:
        """Row i of ``a`` where mask_i, else of ``b`` (a scalar ``b`` or ``a`` fills its rows)."""
        ca = _casadi()
        n = mask.shape[0]
        a, b = (ca.SX(v) if isinstance(v, (np.ndarray, ca.DM)) else v for v in (a, b))
        cols = max(v.shape[1] if isinstance(v, ca.SX) else 1 for v in (a, b))
        a, b = (v if isinstance(v, ca.SX) else ca.repmat(ca.SX(v), n, cols) for v in (a, b))
        return ca.vertcat(*[ca.if_else(mask[i], a[i, :], b[i, :]) for i in range(n)])

    @staticmethod
    def hypot(a: Any, b: Any) -> Any:
        return _casadi().hypot(a, b)

    @staticmethod
    def entries(v: Any) -> list:
        return [v[i] for i in range(v.shape[0])]

    @staticmethod
    def logic_and(a: Any, b: Any) -> Any:
        return _casadi().logic_and(a, b)

    @staticmethod
    def logic_not(a: Any) -> Any:
        return _casadi().logic_not(a)

    @staticmethod
    def repeat(mask: Any, k: int) -> Any:
        ca = _casadi()
        return ca.vertcat(*[mask[i] for i in range(mask.shape[0]) for _ in range(k)])

    @staticmethod
    def interleave(x: Any, y: Any) -> Any:
        ca = _casadi()
        return ca.vec(ca.horzcat(x, y).T)

    @staticmethod
    def columns(M: Any, cols: Any) -> Any:
        return M[:, [int(c) for c in cols]]

    @staticmethod
    def cond(condition: Any, then: Callable[[], Any], otherwise: Callable[[], Any]) -> Any:
        ca = _casadi()
        if isinstance(condition, (bool, np.bool_)):
            return then() if condition else otherwise()
        a, b = then(), otherwise()
        if isinstance(a, tuple):
            return tuple(ca.if_else(condition, x, y) for x, y in zip(a, b))
        return ca.if_else(condition, a, b)

    @staticmethod
    def dot(a: Any, b: Any) -> Any:
        return _casadi().dot(a, b)

    @staticmethod
    def vertcat(*parts: Any) -> Any:
        return _casadi().vertcat(*parts)

    @staticmethod
    def horzcat(*blocks: Any) -> Any:
        return _casadi().horzcat(*blocks)

    @staticmethod
    def zeros(n: int) -> Any:
        return _casadi().DM.zeros(n)

    @staticmethod
    def diag(M: Any) -> Any:
        return _casadi().diag(M)

    @staticmethod
    def copy(x: Any) -> Any:
        return x

    @staticmethod
    def index(rows: Any) -> list[int]:
        if isinstance(rows, slice):
            return list(range(*rows.indices(6)))
        return [int(i) for i in rows]

    @staticmethod
    def if_else(condition: Any, a: Any, b: Any) -> Any:
        if isinstance(condition, (bool, np.bool_)):
            return a if condition else b
        return _casadi().if_else(condition, a, b)


def _casadi() -> Any:
    import casadi

    return casadi


# --------------------------------------------------------------------------------------------
# The symbolic law of a controller
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class SymbolicLaw:
    """A controller's law as a CasADi function ``(q, qd, r, p) → (u, *signals)``.

    ``reference(t) -> r`` samples the (open-loop) reference; ``parameters`` are the numeric values of
    ``p`` (the gains of the numeric controller) and ``parameter_shapes`` their names and shapes, in
    the order they are stacked (column-major, CasADi's ``vec``).
    """

    function: ca.Function
    reference: Callable[[float], np.ndarray]
    parameters: np.ndarray
    parameter_shapes: tuple[tuple[str, tuple[int, int]], ...]
    signals: tuple[str, ...]
    measurements: tuple[str, ...] = ()
    state: np.ndarray | None = None
    scalars: tuple[str, ...] = ()

    @staticmethod
    def build(nq: int, nv: int, nr: int, gains: Mapping[str, np.ndarray],
              law: Callable[..., tuple],
              reference: Callable[[float], np.ndarray], measurements: Mapping[str, int] | None = None,
              state: Any = None, scalars: tuple[str, ...] = ()) -> "SymbolicLaw":
        """The law from ``law(q, qd, r, K, **extra) -> (u, {signal: expression})``, ``K[name]`` the symbolic
        gain of the numeric gain ``gains[name]`` (same shape).

        ``measurements`` ``{name: size}``: what else the law reads of the measurement (``extra[name]``).
        ``state``: the initial value of the law's own state; then ``extra`` has ``state`` and ``dt`` (the
        time since the previous sample, 0 at the first) and the law returns ``(u, signals, next_state)``.
        The function's inputs are ``q, qd, r, p, *measurements[, state, dt]``, its outputs
        ``u[, next_state], *signals``. ``scalars`` names the signals the numeric law logs as floats
        (a result's (N,) rather than (N, 1))."""
        q, qd, r = ca.SX.sym("q", nq), ca.SX.sym("qd", nv), ca.SX.sym("r", nr)
        symbols, values, shapes = {}, [], []
        for name, value in gains.items():
            value = np.atleast_2d(np.asarray(value, dtype=float))
            symbols[name] = ca.SX.sym(name, *value.shape)
            values.append(value.ravel(order="F"))
            shapes.append((name, value.shape))
        p = ca.vertcat(*[ca.vec(s) for s in symbols.values()])
        extra = {name: ca.SX.sym(name, size) for name, size in (measurements or {}).items()}
        inputs, names = [q, qd, r, p, *extra.values()], ["q", "qd", "r", "p", *extra]
        if state is None:
            u, signals = law(q, qd, r, symbols, **extra)
            outputs, out_names = [u], ["u"]
        else:
            state = np.atleast_1d(np.asarray(state, dtype=float)).copy()
            c, dt = ca.SX.sym("state", state.size), ca.SX.sym("dt")
            u, signals, c_next = law(q, qd, r, symbols, **extra, state=c, dt=dt)
            inputs, names = inputs + [c, dt], names + ["state", "dt"]
            outputs, out_names = [u, c_next], ["u", "next_state"]
        function = ca.Function("law", inputs, [*outputs, *signals.values()], names, [*out_names, *signals])
        return SymbolicLaw(function, reference, np.concatenate(values), tuple(shapes), tuple(signals),
                           tuple(extra), state, tuple(scalars))

    @staticmethod
    def of(law: Any) -> "SymbolicLaw":
        """The symbolic form of a :class:`controllers.laws.ControlLaw`: its one body ``law.law`` evaluated on
        CasADi symbols with the :class:`controllers.compiled.Symbolic` primitives. The reference r stacks the
        parts of ``law.reference(t)`` (shapes ``law.reference_shapes``, matrices column by column), the
        parameters are ``law.gains``, the state the parts of ``law.initial_state()`` after ``reset()``."""
        shapes = tuple(tuple(shape) for shape in law.reference_shapes)
        sizes = [int(np.prod(shape)) for shape in shapes]
        state = law._state
        state_sizes = None if state is None else [int(np.size(part)) for part in state]

        def parts(v: Any, shapes_: Any, sizes_: list[int]) -> tuple:
            out, k = [], 0
            for shape, size in zip(shapes_, sizes_):
                part = v[k:k + size]
                out.append(ca.reshape(part, *shape) if len(shape) == 2 else part[0] if shape == () else part)
                k += size
            return tuple(out)

        def body(q: Any, qd: Any, r: Any, K: dict, **extra: Any) -> tuple:
            ref = parts(r, shapes, sizes)
            if state is None:
                return law.law(Symbolic, K, q, qd, ref, **extra)
            c, dt = extra.pop("state"), extra.pop("dt")
            u, signals, c_next = law.law(Symbolic, K, q, qd, ref, **extra,
                                         state=parts(c, [np.shape(p) for p in state], state_sizes), dt=dt)
            return u, signals, ca.vertcat(*[ca.vec(ca.SX(v)) for v in c_next])

        initial = None if state is None else np.concatenate([np.ravel(part) for part in state])
        return SymbolicLaw.build(law.nq, law.nv, sum(sizes), law.gains, body, stacked_reference(law.reference, shapes),
                                 measurements=dict(law.measurements) or None, state=initial, scalars=law.scalars)

    def unpack(self, p: Any) -> dict[str, Any]:
        """The gains of a parameter vector ``p`` (numeric or symbolic) by name, in their shapes."""
        out, k = {}, 0
        for name, (rows, cols) in self.parameter_shapes:
            out[name] = ca.reshape(p[k:k + rows * cols], rows, cols)
            k += rows * cols
        return out


class ConstantInput:
    """The open-loop input u(t) = ``value`` (a step applied at t_0, e.g. V'_c of Problem 5.2), as a controller
    of either backend: its law ``u = value`` (:meth:`law`) reads nothing of the measurement (``plant``'s
    ``state_layout`` gives only the sizes of q and q̇ the symbolic law is called with); ``value`` is the
    compiled loop's parameter."""

    measurements: tuple = ()
    scalars: tuple = ()
    reference_shapes: tuple = ()
    _state = None

    def __init__(self, value: Any, plant: Any):
        self.value = np.atleast_1d(np.asarray(value, dtype=float)).copy()
        if self.value.ndim != 1 or not np.all(np.isfinite(self.value)):
            raise ValueError(f"`value` must be a finite vector, got {value!r}")
        self.value.setflags(write=False)
        layout = getattr(plant, "state_layout", {})
        if "q" not in layout or "qd" not in layout:
            raise ValueError("`plant` needs a state_layout with 'q' and 'qd'")
        self.nq, self.nv = _length(layout["q"]), _length(layout["qd"])
        self.gains = {"u": self.value[:, None]}

    def reference(self, t: float) -> tuple:
        """No reference: the law reads nothing."""
        return ()

    def law(self, ops: Any, K: dict, q: Any, qd: Any, ref: tuple) -> tuple[Any, dict]:
        """u = value, for both executors (numeric: the value itself, read-only)."""
        return K["u"], {}

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        return self.law(None, {"u": self.value}, None, None, ())[0]

    def symbolic(self) -> SymbolicLaw:
        return SymbolicLaw.of(self)


def stacked_reference(reference: Callable[[float], tuple[np.ndarray, ...]],
                      shapes: tuple[tuple[int, ...], ...] | None = None) -> Callable[[float], np.ndarray]:
    """``t -> concatenate(reference(t))``: a (x_d, ẋ_d, ẍ_d) reference as one vector r (a matrix part, of a
    2-D shape in ``shapes``, column by column as CasADi's ``reshape`` reads it).

    When ``reference`` samples many instants at once (``reference.at_times(times) -> (x_d, ẋ_d, ẍ_d)``,
    each (N, n), as :func:`controllers.laws.as_reference` of a trajectory), so does the result
    (``at_times(times) -> R (nr, N)``).
    """
    matrix = [len(shape) == 2 for shape in shapes] if shapes is not None else None

    def stacked(t: float) -> np.ndarray:
        parts = reference(t)
        if not parts:
            return np.zeros(0)
        if matrix is None or not any(matrix):
            return np.concatenate([np.ravel(v) for v in parts])
        return np.concatenate([np.ravel(v, order="F" if m else "C") for v, m in zip(parts, matrix)])

    if shapes == ():
        stacked.at_times = lambda times: np.zeros((0, len(times)))
        return stacked
    at_times = getattr(reference, "at_times", None)
    if at_times is not None:
        def stacked_at(times: np.ndarray) -> np.ndarray:
            N = len(times)
            parts = at_times(times)
            flags = matrix if matrix is not None else [False] * len(parts)
            return np.hstack([np.reshape(np.swapaxes(v, 1, 2) if m else v, (N, -1))
                              for v, m in zip(parts, flags)]).T

        stacked.at_times = stacked_at
    return stacked


# --------------------------------------------------------------------------------------------
# The plant
# --------------------------------------------------------------------------------------------

class NoSymbolicForm(ValueError):
    """A block of the loop has no symbolic form: ``backend="casadi"`` refuses it (:func:`no_symbolic_form`)."""


def no_symbolic_form(block: Any, why: str = "") -> NoSymbolicForm:
    """The one refusal of the compiled loop: ``block`` (a controller, a plant, an environment or a function
    inside them) has no symbolic form — a Python function, a block that gives no ``symbolic()`` — so the loop
    runs on the Python backend only. The error names the block and why."""
    name = getattr(block, "__qualname__", None) or type(block).__name__
    return NoSymbolicForm(f"{name} has no symbolic form for backend='casadi'{f' ({why})' if why else ''}: "
                          "use backend='python' (the same loop)")


def plant_of(plant: Any) -> ca.Function:
    """``ẋ = f(x, u)`` as a ``casadi.Function`` from the plant's one body ``plant.dynamics(ops, x, u)`` evaluated
    on symbols (:class:`controllers.compiled.Symbolic`); x has ``state_size`` entries, u ``symbolic_input_size``
    (default ``input_size``)."""
    nu = getattr(plant, "symbolic_input_size", None) or plant.input_size
    x, u = ca.SX.sym("x", plant.state_size), ca.SX.sym("u", int(nu))
    return ca.Function("plant", [x, u], [plant.dynamics(Symbolic, x, u)], ["x", "u"], ["xdot"])


def integrate_of(plant: Any) -> ca.Function:
    """``x ⊕ h dx`` as a ``casadi.Function`` (x, dx, h) → x' from the plant's one body ``plant.integrate_law``."""
    x, dx, h = ca.SX.sym("x", plant.state_size), ca.SX.sym("dx", plant.tangent_size), ca.SX.sym("h")
    return ca.Function("integrate", [x, dx, h], [plant.integrate_law(Symbolic, x, dx, h)], ["x", "dx", "h"], ["x_next"])


def plant_function(plant: Any) -> tuple[ca.Function, int, int, ca.Function | None]:
    """``(f, nq, nv, integrate)``: the plant's ẋ = f(x, u) from its ``symbolic()``, the sizes of q and q̇ in x
    (from its ``state_layout``) and its x ⊕ h dx (``symbolic_integrate()``, None on a vector space)."""
    if not hasattr(plant, "symbolic"):
        raise no_symbolic_form(plant, "a plant needs dynamics(ops, x, u) or symbolic() and a state_layout")
    f = plant.symbolic()
    layout = getattr(plant, "state_layout", {})
    if "q" not in layout or "qd" not in layout:
        raise no_symbolic_form(plant, "a compiled plant needs a state_layout with 'q' and 'qd'")
    integrate = plant.symbolic_integrate() if hasattr(plant, "symbolic_integrate") else None
    return f, _length(layout["q"]), _length(layout["qd"]), integrate


def plant_measurement(plant: Any, name: str) -> ca.Function:
    """The plant's ``symbolic_measurement(name)``: x → the measurement entry ``name`` (e.g. the sensed wrench
    of :class:`~controllers.plants.ArmInContact`)."""
    if not hasattr(plant, "symbolic_measurement"):
        raise ValueError(f"`plant` {type(plant).__name__} has no symbolic measurement {name!r} for backend='casadi'")
    return plant.symbolic_measurement(name)


def _length(index: Any) -> int:
    return len(range(*index.indices(10**9))) if isinstance(index, slice) else 1


# --------------------------------------------------------------------------------------------
# Compilation: rigid_body.codegen (the compiler and its cache); the loop's choice of backend
# --------------------------------------------------------------------------------------------

def fast_backend(controller: Any = None) -> str:
    """The backend for a loop that needs speed: ``"casadi"`` when a C compiler can build the compiled loop,
    else ``"python"`` (the same loop, slower; a one-line warning says so) — never the interpreted CasADi.
    Given the ``controller``, ``"python"`` also when it has no symbolic form (its ``compilable``, by
    default whether it has ``symbolic()``). A compiler or cache that fails later sends the run to the Python
    loop too (:class:`CompiledLoopUnavailable`)."""
    if controller is not None and not getattr(controller, "compilable", hasattr(controller, "symbolic")):
        return "python"
    if codegen.compiler() is not None:
        return "casadi"
    warnings.warn("no C compiler found: the loop runs on the Python backend (same results, slower)", stacklevel=2)
    return "python"



# --------------------------------------------------------------------------------------------
# The key of a loop: a digest of its blocks' structure, without generating code
# --------------------------------------------------------------------------------------------

_NOT_STRUCTURE = frozenset({"gains", "_K", "_state", "_t_last", "_log"})
"""Attributes of every law that are not part of its symbolic structure, because the executor feeds them at run
time or only the Python loop keeps them: its gains (fed as p; also ``_K``, their fast copies), its state (fed as
the initial law state), the Python loop's last sample time and signals. References are fed too (as R: every
attribute whose name ends in ``reference``). A class names its own such attributes in ``runtime_attributes``
(e.g. a log the Python loop appends to); Pinocchio's work data, thread-local stores and random generators are
keyed by their type (the generator's draws are fed as inputs)."""
_BY_TYPE = (pin.Data, np.random.Generator, threading.local)
_SOURCES: dict[str, bytes] = {}
_BOOST_INSTANCE = next(c for c in pin.SE3.__mro__ if c.__module__ == "Boost.Python" and c.__name__ == "instance")
"""The base of every Boost.Python object (Pinocchio's SE3, Motion, Inertia …): its value is not in ``__dict__``."""


def _module_of(obj: Any) -> str:
    """The name of the module defining ``obj`` ('' when it has none as a string, e.g. a pybind11 class)."""
    name = getattr(obj, "__module__", "")
    return name if isinstance(name, str) else ""


def _source_digest(module: str) -> bytes:
    """The digest of a module's source file (cached): a loop built from changed code gets a new key."""
    if module not in _SOURCES:
        import sys

        path = getattr(sys.modules.get(module), "__file__", None)
        _SOURCES[module] = hashlib.sha256(Path(path).read_bytes()).digest() if path else module.encode()
    return _SOURCES[module]


def structure_digest(*blocks: Any) -> str:
    """A digest of what determines the symbolic form of ``blocks`` (a plant, a controller): their classes and the
    source of their modules, every attribute that is not a parameter, a state, a reference or work data, the
    names and shapes of the gains, robot models by content (:func:`rigid_body.symbolic.model_digest`). Two
    blocks with the same digest build the same loop, so it is the cache key — computed without generating
    code (≈ 0.3 ms for an arm and its law)."""
    from rigid_body.robots import Robot
    from rigid_body.symbolic import model_digest

    h = hashlib.sha256()
    seen: dict[int, int] = {}
    models: dict[int, bytes] = {}
    modules: set[str] = set()

    def feed(tag: str, payload: bytes) -> None:
        h.update(tag.encode())
        h.update(len(payload).to_bytes(8, "little"))
        h.update(payload)

    def walk(v: Any, depth: int = 0) -> None:
        if v is None or isinstance(v, (bool, int, float, complex, str, bytes)):
            feed("s", repr(v).encode())
            return
        if isinstance(v, np.generic):
            feed("s", repr(v.item()).encode())
            return
        if isinstance(v, np.ndarray):
            feed("a", f"{v.dtype}{v.shape}".encode() + (np.ascontiguousarray(v).tobytes() if v.dtype != object
                                                         else repr(v.tolist()).encode()))
            return
        if isinstance(v, _BY_TYPE):
            feed("o", type(v).__qualname__.encode())
            return
        if depth > 12:
            feed("i", f"{os.getpid()}:{id(v)}".encode())    # too deep to read: this object only
            return
        if isinstance(v, pin.Model):
            if id(v) not in models:
                models[id(v)] = model_digest(v)
            feed("m", models[id(v)])
            return
        if isinstance(v, Robot):
            walk(v.model, depth + 1)
            return
        if isinstance(v, (slice, range)):
            feed("s", repr(v).encode())
            return
        if isinstance(v, (list, tuple, set, frozenset)):
            feed("l", f"{type(v).__name__}{len(v)}".encode())
            for item in (sorted(v, key=repr) if isinstance(v, (set, frozenset)) else v):
                walk(item, depth + 1)
            return
        if isinstance(v, dict):
            feed("d", str(len(v)).encode())
            for k in sorted(v, key=repr):
                walk(k, depth + 1)
                walk(v[k], depth + 1)
            return
        if isinstance(v, types.ModuleType):
            feed("u", v.__name__.encode())
            return
        if isinstance(v, type):
            feed("t", f"{_module_of(v)}.{v.__qualname__}".encode())
            modules.add(_module_of(v))
            return
        if isinstance(v, types.FunctionType):
            feed("f", f"{_module_of(v)}.{v.__qualname__}".encode() + v.__code__.co_code + repr(v.__code__.co_consts).encode())
            modules.add(_module_of(v))
            for cell in v.__closure__ or ():
                try:
                    walk(cell.cell_contents, depth + 1)
                except ValueError:                          # an empty cell
                    feed("e", b"")
            walk(v.__defaults__, depth + 1)
            return
        if isinstance(v, types.MethodType):
            feed("b", v.__func__.__qualname__.encode())
            walk(v.__self__, depth + 1)
            return
        if isinstance(v, functools.partial):
            feed("p", b"")
            walk(v.func, depth + 1)
            walk(v.args, depth + 1)
            walk(v.keywords, depth + 1)
            return
        if isinstance(v, types.BuiltinFunctionType) or type(v).__module__ == "Boost.Python":
            feed("n", repr(v).encode())
            return
        if id(v) in seen:
            feed("r", str(seen[id(v)]).encode())
            return
        seen[id(v)] = len(seen)
        cls = type(v)
        feed("c", f"{_module_of(cls)}.{cls.__qualname__}".encode())
        modules.add(_module_of(cls))
        attributes = dict(getattr(v, "__dict__", {}))
        for slot in getattr(cls, "__slots__", ()):
            if hasattr(v, slot):
                attributes[slot] = getattr(v, slot)
        if not attributes or _BOOST_INSTANCE in cls.__mro__:
            # No Python state (an extension object such as a pin.SE3, whose value lives in C++): by value when
            # it pickles (its full state), else opaque — this object only. Never by its class alone.
            try:
                feed("v", pickle.dumps(v, protocol=4))
            except Exception:                               # noqa: BLE001 (any refusal to pickle)
                feed("i", f"{os.getpid()}:{id(v)}".encode())
        skipped = _NOT_STRUCTURE.union(getattr(cls, "runtime_attributes", ()))
        gains = attributes.get("gains")
        gain_values = [] if not isinstance(gains, dict) else list(gains.values())
        if gain_values:
            feed("g", repr([(k, np.shape(g)) for k, g in gains.items()]).encode())
        for name in sorted(attributes):
            value = attributes[name]
            if name in skipped or name.endswith("reference") or any(value is g for g in gain_values):
                continue
            feed("k", name.encode())
            walk(value, depth + 1)

    for block in blocks:
        walk(block)
    for module in sorted(modules | {__name__, "controllers.laws", "controllers.simulation", "rigid_body.symbolic"}):
        feed("M", module.encode() + _source_digest(module))
    return h.hexdigest()


# --------------------------------------------------------------------------------------------
# The loop
# --------------------------------------------------------------------------------------------

MAPACCUM_BASE = 2
"""The nesting base of the run's ``mapaccum`` (a tower of loops of this many samples): 2 builds a run of
N samples several times faster than CasADi's default 10, for the same operations."""

LOOPS_KEPT = 32
"""How many built loops a process keeps (least recently used dropped): ``simulate(..., backend="casadi")``
called again with blocks of the same structure reuses one."""
_LOOPS: OrderedDict[str, "CompiledLoop"] = OrderedDict()
_LOOPS_GUARD = threading.Lock()


def law_inputs(controller: Any, n_state: int = 0) -> tuple[np.ndarray, np.ndarray | None, Callable[[float], Any]]:
    """(p, c_0, reference) of a controller for a compiled run — what a loop built for another controller of
    the same structure needs from this one: its gains (the parameters p, stacked as :meth:`SymbolicLaw.build`
    does), its own state after ``reset()`` (None for a static law) and its stacked reference (the rows R). A
    controller may give them itself (``compiled_inputs(n_state)``; ``n_state`` the size of the law's state)."""
    custom = getattr(controller, "compiled_inputs", None)
    if custom is not None:
        return custom(n_state)
    gains = getattr(controller, "gains", {})
    p = (np.concatenate([np.atleast_2d(np.asarray(v, dtype=float)).ravel(order="F") for v in gains.values()])
         if gains else np.zeros(0))
    state = getattr(controller, "_state", None)
    c0 = None if state is None else np.concatenate([np.ravel(np.asarray(s, dtype=float)) for s in state])
    shapes = tuple(tuple(s) for s in getattr(controller, "reference_shapes", ()))
    return p, c0, stacked_reference(controller.reference, shapes)


def loop_key(plant: Any, controller: Any, h: float, n_sub: int, n_samples: int) -> str:
    """The cache key of the loop of ``plant`` and ``controller``: :func:`structure_digest` of both and the run's
    grid (no code generated)."""
    grid = repr((float(h), int(n_sub), int(n_samples), MAPACCUM_BASE, ca.__version__, COMPILE_FLAGS)).encode()
    return hashlib.sha256(structure_digest(plant, controller).encode() + grid).hexdigest()


class CompiledLoop:
    """The closed loop of ``plant`` and ``controller`` over ``n_samples`` controller samples.

    ``rollout`` is the CasADi function ``(x0, R, p) → (X (nx, N), U (nu, N), signals…)`` (R: the
    references at the N samples, p: the gains), differentiable; ``run`` is the same compiled (or
    interpreted, ``compile=False``). With a law that has a state, x0 and X also hold it (below the plant's
    state) and R has the row dt (see :meth:`references`).

    The compiled run is cached by :func:`loop_key` — a digest of the blocks' structure, not of generated code —
    in this process (:func:`compiled_loop`) and on disk (``$RMPC_CACHE``, with the names of its signals beside
    it): a loop found there is loaded without building any expression (``rollout``, ``law`` are then built on
    first use). ``compile_time`` is the time the constructor took [s]: ``build_time`` when it built the run
    (expressions, C code, the C compiler), ``lookup_time`` when it found it (the key, loading the library).
    """

    def __init__(self, plant: Any, controller: Any, h: float, n_sub: int, n_samples: int,
                 compile: bool = True, key: str | None = None):
        if not hasattr(controller, "symbolic"):
            raise no_symbolic_form(controller, "a controller needs a ControlLaw body or symbolic()")
        start = time.perf_counter()
        self.plant, self.controller = plant, controller
        self.h, self.n_sub, self.n_samples, self.Ts = h, n_sub, n_samples, n_sub * h
        self._law: SymbolicLaw | None = None
        self._sample: ca.Function | None = None
        self._rollout: ca.Function | None = None
        self._buffers = threading.local()
        self.key = key
        if compile:
            self.key = self.key or loop_key(plant, controller, h, n_sub, n_samples)
            self.run, meta = _compile(lambda: self.rollout, "rollout", self.key.encode(), self._metadata)
            meta = meta or self._metadata_of_build()
        else:
            self.run = self.rollout
            meta = self._metadata_of_build()
        self.nx, self.nc, self.signals, self.scalars = meta["nx"], meta["nc"], tuple(meta["signals"]), \
            tuple(meta["scalars"])
        self.compile_time = time.perf_counter() - start
        built = self._sample is not None                 # symbolic built here: generated and compiled (or interpreted)
        self.build_time = self.compile_time if built else 0.0
        self.lookup_time = 0.0 if built else self.compile_time

    # the symbolic loop, built when needed
    def _build(self) -> None:
        if self._sample is not None:
            return
        plant, controller, h, n_sub = self.plant, self.controller, self.h, self.n_sub
        if hasattr(controller, "reset"):
            controller.reset()                                  # the law's initial state is the reset one
        law = controller.symbolic()
        f, nq, nv, integrate = plant_function(plant)
        nx, nr, n_p = f.size1_in(0), law.function.size1_in(2), law.function.size1_in(3)
        nc = 0 if law.state is None else law.state.size
        xc, r, p = ca.SX.sym("x", nx + nc), ca.SX.sym("r", nr + (1 if nc else 0)), ca.SX.sym("p", n_p)
        x = xc[:nx]
        layout = plant.state_layout                              # q, q̇ where the plant keeps them in x
        args = [x[layout["q"]], x[layout["qd"]], r[:nr], p,
                *(plant_measurement(plant, name)(x) for name in law.measurements)]
        if nc:
            args += [xc[nx:], r[nr]]                             # the law's state, dt (the last row of R)
        out = law.function(*args)
        out = list(out) if isinstance(out, (list, tuple)) else [out]
        u, c_next, logged = out[0], (out[1] if nc else None), out[1 + (1 if nc else 0):]
        if u.shape[0] != f.size1_in(1):
            raise ValueError(f"the symbolic law of {type(controller).__name__} gives {u.shape[0]} inputs, "
                             f"the plant takes {f.size1_in(1)}")
        stage = None if integrate is None else (lambda x0, k, c: integrate(x0, k, c))
        x_next = x
        for _ in range(n_sub):                                  # the one RK4, u held (ZOH)
            x_next = rk4_step_law(lambda t, xi, ui: f(xi, ui), 0.0, x_next, u, h, stage)
        self._sample = ca.Function("sample", [xc, r, p], [ca.vertcat(x_next, c_next) if nc else x_next, u, *logged])
        self._law, self._nx, self._nc = law, nx, nc

    @property
    def law(self) -> SymbolicLaw:
        """The controller's :class:`SymbolicLaw` (built on first use when the run came from the cache)."""
        self._build()
        return self._law

    def _metadata_of_build(self) -> dict:
        self._build()
        law = self._law
        return {"nx": self._nx, "nc": self._nc, "signals": list(law.signals), "scalars": list(law.scalars)}

    def _metadata(self) -> bytes:
        return json.dumps(self._metadata_of_build()).encode()

    @property
    def rollout(self) -> ca.Function:
        """``(x0, R, p) → (X, U, signals…)``: the sample accumulated over the run (built on first use)."""
        if self._rollout is None:
            self._build()
            sample, n_samples = self._sample, self.n_samples
            X0, R, P = (ca.MX.sym(name, *sample.size_in(i)[:1], cols) for i, (name, cols)
                        in enumerate((("x0", 1), ("R", n_samples), ("p", 1))))
            if n_samples > 1:
                Xs, *rest = sample.mapaccum("loop", n_samples - 1, 1, {"base": MAPACCUM_BASE})(X0, R[:, :-1], P)
                X = ca.horzcat(X0, Xs)
                last = sample(X[:, -1], R[:, -1], P)[1:]
                outputs = [ca.horzcat(a, b) for a, b in zip(rest, last)]
            else:
                X, outputs = X0, sample(X0, R[:, 0], P)[1:]
            names = ["X", "U", *(f"signal_{i}" for i in range(len(outputs) - 1))]
            self._rollout = ca.Function("rollout", [X0, R, P], [X, *outputs], ["x0", "R", "p"], names)
        return self._rollout

    # one run
    def inputs(self, t0: float, controller: Any = None) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """(R (nr, N), p, c_0) of a run from ``t0`` for ``controller`` (default the one the loop was built for;
        any controller of the same structure), after its ``reset()``: the reference sampled at the controller
        instants (at once when it can: ``at_times``), with the row dt = t_k − t_{k−1} (0 at k = 0) as the
        Python loop's when the law has a state."""
        controller = self.controller if controller is None else controller
        if hasattr(controller, "reset"):
            controller.reset()
        p, c0, reference = law_inputs(controller, self.nc)
        times = t0 + self.Ts * np.arange(self.n_samples)
        at_times = getattr(reference, "at_times", None)
        R = at_times(times) if at_times is not None else np.column_stack([reference(float(t)) for t in times])
        R = np.reshape(R, (-1, self.n_samples))
        if self.nc:
            R = np.vstack([R, np.diff(times, prepend=times[0])])
        return np.ascontiguousarray(R, dtype=float), p, c0

    def references(self, t0: float) -> np.ndarray:
        """R (nr, N): the references of a run from ``t0`` (see :meth:`inputs`)."""
        return self.inputs(t0)[0]

    def arrays(self, t0: float, x0: Any, bound: float = 1e12, controller: Any = None
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, np.ndarray], float | None]:
        """One run from ``x0`` at ``t0`` (of ``controller``, default the loop's): (t (N,), x (N, nx), u (N, nu),
        signals, t_diverged).

        ``t_diverged`` is None, or the first sample whose state is non-finite or beyond ``bound``
        (divergence is checked on the samples, every ``Ts``).
        """
        R, p, c0 = self.inputs(t0, controller)
        ts = t0 + self.Ts * np.arange(self.n_samples)
        x0 = np.asarray(x0, dtype=float)
        if self.nc:
            x0 = np.concatenate([x0, c0])
        X, U, *logged = self._call(x0, R, p)                 # each (N, rows): the transposes of the run's outputs
        X = X[:, :self.nx] if self.nc else X
        t_bad = None
        if not (np.abs(X).max(initial=0.0) <= bound and np.isfinite(U.sum())):     # one pass; NaN fails it too
            bad = ~(np.all(np.isfinite(X), axis=1) & (np.max(np.abs(X), axis=1, initial=0.0) <= bound))
            bad |= ~np.all(np.isfinite(U), axis=1)
            t_bad = float(ts[int(np.argmax(bad))]) if np.any(bad) else None
        signals = {name: v[:, 0].copy() if name in self.scalars else v for name, v in zip(self.signals, logged)}
        return ts, np.ascontiguousarray(X), U, signals, t_bad

    def _call(self, x0: np.ndarray, R: np.ndarray, p: np.ndarray) -> list[np.ndarray]:
        """``run(x0, R, p)`` through a CasADi function buffer: the inputs are read and the outputs written in place
        as numpy arrays (column-major (rows, N) is row-major (N, rows): the outputs come transposed, as the result
        holds them), without converting to and from CasADi matrices."""
        run = self.run
        buffers = self._buffers.__dict__
        if "buffer" not in buffers:                          # one per thread: a buffer holds its arguments
            buffers["buffer"] = run.buffer()
        buf, evaluate = buffers["buffer"]
        inputs = [np.ascontiguousarray(x0, dtype=float), np.ascontiguousarray(R.T, dtype=float),
                  np.ascontiguousarray(p, dtype=float)]
        for i, value in enumerate(inputs):
            if value.size != run.nnz_in(i):
                raise ValueError(f"the compiled run's input {run.name_in(i)} has {run.nnz_in(i)} entries, got {value.size}")
            buf.set_arg(i, memoryview(value))
        outputs = [np.empty((run.size2_out(i), run.size1_out(i))) for i in range(run.n_out())]
        for i, value in enumerate(outputs):
            buf.set_res(i, memoryview(value))
        evaluate()
        return outputs


def _compile(build: Callable[[], ca.Function], name: str, key: bytes, metadata: Callable[[], bytes]
             ) -> tuple[ca.Function, dict | None]:
    """:func:`rigid_body.codegen.compiled_library` of a keyed build, and the metadata stored beside it."""
    return codegen.compiled_library(build, name=name, key=key, metadata=metadata)


def compiled_loop(plant: Any, controller: Any, h: float, n_sub: int, n_samples: int) -> CompiledLoop:
    """The :class:`CompiledLoop` of ``plant`` and ``controller`` on this grid: the one this process built for
    blocks of the same structure (:func:`loop_key`), else one loaded from the disk cache or built."""
    if not hasattr(controller, "symbolic"):
        raise no_symbolic_form(controller, "a controller needs a ControlLaw body or symbolic()")
    key = loop_key(plant, controller, h, n_sub, n_samples)
    with _LOOPS_GUARD:
        loop = _LOOPS.get(key)
        if loop is not None:
            _LOOPS.move_to_end(key)
            return loop
    with key_lock("loop" + key):
        with _LOOPS_GUARD:
            loop = _LOOPS.get(key)
        if loop is None:
            loop = CompiledLoop(plant, controller, h, n_sub, n_samples, key=key)
            with _LOOPS_GUARD:
                _LOOPS[key] = loop
                while len(_LOOPS) > LOOPS_KEPT:
                    _LOOPS.popitem(last=False)
    return loop


def simulate_compiled(plant: Any, controller: Any, t0: float, n_samples: int, x0: np.ndarray, h: float,
                      n_sub: int, bound: float, backend: str) -> tuple:
    """The body of ``simulate(..., backend="casadi")`` over ``n_samples`` controller samples (arguments
    validated by ``simulate``), returning :meth:`CompiledLoop.arrays`: the loop of blocks of this structure
    (:func:`compiled_loop`, built once per process, cached on disk), run with this controller's gains, state
    and reference. :class:`CompiledLoopUnavailable` when no compiler or cache can build it."""
    if backend not in BACKENDS:
        raise ValueError(f"`backend` must be one of {BACKENDS}, got {backend!r}")
    return compiled_loop(plant, controller, h, n_sub, n_samples).arrays(t0, x0, bound, controller)
