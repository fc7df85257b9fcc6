"""Compiled backend of the one simulation loop: ``simulate(..., backend="casadi")``.

The same loop as :func:`controllers.simulation.simulate` — classical RK4 of step ``h`` on the plant,
the controller every ``Ts`` with zero-order hold — written once as CasADi expressions: one *sample*
(the controller's law, then ``Ts/h`` RK4 steps with the output held) is a ``casadi.Function``
``(x_k, r_k, p) → (x_{k+1}, u_k)`` and the whole run is that function accumulated over the samples
(``Function.mapaccum``). The run is generated as C and compiled with the system C compiler (``cc``,
cached by the hash of the sample's code, the number of samples and this module's source, so that a
cached run is loaded without building the accumulated function); without a compiler it is interpreted
by CasADi's virtual machine (a one-line note says so).

What the loop needs from its two blocks, beside the contract of :mod:`controllers.simulation`:

* the plant: ``symbolic() -> casadi.Function (x, u) → ẋ`` (time-invariant, x + h·ẋ integration)
  and a ``state_layout`` with ``q`` and ``qd`` (where the law reads them in x): an
  :class:`~controllers.plants.ArmPlant` with nq = nv and no external force (forward dynamics
  :func:`rigid_body.symbolic.forward_dynamics_expression`), a :class:`~controllers.plants.ServomotorPlant`;
* the controller: ``symbolic() -> SymbolicLaw``: the law ``(q, q̇, r, p) → (u, signals…)`` in CasADi
  expressions. The reference ``r`` is open loop (a function of time only), so it is sampled in Python
  at the controller instants and fed to the run; the parameters ``p`` are the gains, their values
  taken from the numeric controller (its single source). A law may read more of the measurement
  (``measurements``, e.g. the sensed ``wrench``: the plant's ``symbolic_measurement(name)``, a
  ``casadi.Function`` x → value) and keep a state of its own (``state``: its value after ``reset()``;
  the law also receives ``dt``, the time since the previous sample, 0 at the first, and returns the
  next state: an integral action, an adaptive estimate). Chains and ``ZeroOrderHold`` blocks stay on
  the Python backend.

Because the run is one CasADi function of ``(x_0, R, p)``, its derivatives with respect to the
initial state and the gains come by automatic differentiation (:meth:`CompiledLoop.rollout`):
gain tuning by gradient-based optimisation over the whole closed-loop response
(``examples/gain_tuning.py``).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 8.4
(the closed loops); Andersson et al., *CasADi*, Math. Prog. Comp. 11 (2019) (map/mapaccum, codegen).
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping

import casadi as ca
import numpy as np


BACKENDS = ("python", "casadi")


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
        CasADi symbols with the :class:`controllers.laws.Symbolic` primitives. The reference r stacks the
        parts of ``law.reference(t)`` (shapes ``law.reference_shapes``, matrices column by column), the
        parameters are ``law.gains``, the state the parts of ``law.initial_state()`` after ``reset()``."""
        from controllers.laws import Symbolic

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
    of either backend: ``(t, measurement) -> u`` and its :class:`SymbolicLaw`, which reads nothing of the
    measurement (``plant``'s ``state_layout`` gives only the sizes of q and q̇ the law is called with)."""

    def __init__(self, value: Any, plant: Any):
        self.value = np.atleast_1d(np.asarray(value, dtype=float)).copy()
        if self.value.ndim != 1 or not np.all(np.isfinite(self.value)):
            raise ValueError(f"`value` must be a finite vector, got {value!r}")
        self.value.setflags(write=False)
        layout = getattr(plant, "state_layout", {})
        if "q" not in layout or "qd" not in layout:
            raise ValueError("`plant` needs a state_layout with 'q' and 'qd'")
        self._sizes = (_length(layout["q"]), _length(layout["qd"]))

    def __call__(self, t: float, measurement: Any) -> np.ndarray:
        return self.value

    def symbolic(self) -> SymbolicLaw:
        def no_reference(t: float) -> np.ndarray:
            return np.zeros(0)

        no_reference.at_times = lambda times: np.zeros((0, len(times)))
        return SymbolicLaw.build(*self._sizes, 0, {"u": self.value[:, None]}, lambda q, qd, r, K: (K["u"], {}),
                                 no_reference)


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
        if matrix is None or not any(matrix):
            return np.concatenate([np.ravel(v) for v in parts])
        return np.concatenate([np.ravel(v, order="F" if m else "C") for v, m in zip(parts, matrix)])

    at_times = getattr(reference, "at_times", None)
    if at_times is not None and not (matrix and any(matrix)):
        stacked.at_times = lambda times: np.hstack([np.reshape(v, (len(times), -1)) for v in at_times(times)]).T
    return stacked


# --------------------------------------------------------------------------------------------
# The plant
# --------------------------------------------------------------------------------------------

def plant_function(plant: Any) -> tuple[ca.Function, int, int]:
    """``(f, nq, nv)``: the plant's ẋ = f(x, u) from its ``symbolic()``, and the sizes of q and q̇ in x
    (from its ``state_layout``). :class:`~controllers.plants.ArmPlant` provides both."""
    if not hasattr(plant, "symbolic"):
        raise ValueError(f"`plant` {type(plant).__name__} has no symbolic() form for backend='casadi' "
                         "(an ArmPlant, or a plant with symbolic() and a state_layout)")
    f = plant.symbolic()
    layout = getattr(plant, "state_layout", {})
    if "q" not in layout or "qd" not in layout:
        raise ValueError("`plant` with a symbolic form needs a state_layout with 'q' and 'qd'")
    return f, _length(layout["q"]), _length(layout["qd"])


def plant_measurement(plant: Any, name: str) -> ca.Function:
    """The plant's ``symbolic_measurement(name)``: x → the measurement entry ``name`` (e.g. the sensed wrench
    of :class:`~controllers.plants.ArmInContact`)."""
    if not hasattr(plant, "symbolic_measurement"):
        raise ValueError(f"`plant` {type(plant).__name__} has no symbolic measurement {name!r} for backend='casadi'")
    return plant.symbolic_measurement(name)


def _length(index: Any) -> int:
    return len(range(*index.indices(10**9))) if isinstance(index, slice) else 1


# --------------------------------------------------------------------------------------------
# Compilation
# --------------------------------------------------------------------------------------------

CACHE = Path(os.environ.get("RMPC_CACHE", Path(tempfile.gettempdir()) / "rmpc-casadi"))
_SOURCE_HASH = hashlib.sha256(Path(__file__).read_bytes()).hexdigest().encode()   # in the loops' cache keys
_loaded: dict[str, ca.Function] = {}


def compiler() -> str | None:
    """The system C compiler (``$CC``, ``cc``, ``gcc`` or ``clang``), None when there is none."""
    for name in (os.environ.get("CC"), "cc", "gcc", "clang"):
        if name and shutil.which(name):
            return name
    return None


def fast_backend(controller: Any = None) -> str:
    """The backend for a loop that needs speed: ``"casadi"`` when a C compiler can build the compiled loop,
    else ``"python"`` (the same loop, slower; a one-line warning says so) — never the interpreted CasADi.
    Given the ``controller``, ``"python"`` also when it has no symbolic form (its ``compilable``, by
    default whether it has ``symbolic()``)."""
    if controller is not None and not getattr(controller, "compilable", hasattr(controller, "symbolic")):
        return "python"
    if compiler() is not None:
        return "casadi"
    warnings.warn("no C compiler found: the loop runs on the Python backend (same results, slower)", stacklevel=2)
    return "python"


def c_code(function: ca.Function) -> bytes:
    """The C source CasADi generates for ``function``."""
    name = function.name()
    with tempfile.TemporaryDirectory() as tmp:
        generator = ca.CodeGenerator(f"{name}.c", {"with_header": False})
        generator.add(function)
        generator.generate(tmp + os.sep)
        return (Path(tmp) / f"{name}.c").read_bytes()


COMPILE_FLAGS = ("-O1",)
"""The C compiler's optimisation: CasADi's generated code is straight-line arithmetic, which ``-O1`` compiles
about 40 % faster than ``-O2`` and runs as fast (Puma 560 PD + g rollout: 8.1 ms with either)."""


def compile_function(function: ca.Function | Callable[[], ca.Function], flags: tuple[str, ...] = COMPILE_FLAGS,
                     name: str | None = None, key: bytes | None = None) -> ca.Function:
    """``function`` generated as C, compiled into a shared library (cached by the code's hash) and loaded.

    Without a C compiler the function is returned as it is (interpreted), with a warning. With ``key``
    (bytes that determine the code) and ``name``, ``function`` may be a callable building it: the cache
    is looked up by the hash of ``key`` and the function built and generated only when it misses.
    """
    cc = compiler()
    if cc is None:
        warnings.warn("no C compiler found: the CasADi loop runs interpreted (slower)", stacklevel=2)
        return function if key is None else function()
    code = None
    if key is None:
        name, code = function.name(), c_code(function)
        key = code
    key = hashlib.sha256(key + " ".join((cc, *flags)).encode()).hexdigest()[:16]
    if key in _loaded:
        return _loaded[key]
    CACHE.mkdir(parents=True, exist_ok=True)
    library = CACHE / f"{name}_{key}.so"
    if not library.exists():
        code = code if code is not None else c_code(function())
        c_file = CACHE / f"{name}_{key}.c"
        c_file.write_bytes(code)
        partial = CACHE / f"{name}_{key}.{os.getpid()}.so"
        subprocess.run([cc, *flags, "-fPIC", "-shared", str(c_file), "-o", str(partial), "-lm"],
                       check=True, capture_output=True)
        partial.replace(library)                                # atomic: parallel runs share it
    _loaded[key] = ca.external(name, str(library))
    return _loaded[key]


# --------------------------------------------------------------------------------------------
# The loop
# --------------------------------------------------------------------------------------------

MAPACCUM_BASE = 2
"""The nesting base of the run's ``mapaccum`` (a tower of loops of this many samples): 2 builds a run of
N samples several times faster than CasADi's default 10 (the build is timed with every ``simulate``),
for the same operations."""


class CompiledLoop:
    """The closed loop of ``plant`` and ``controller`` over ``n_samples`` controller samples.

    ``rollout`` is the CasADi function ``(x0, R, p) → (X (nx, N), U (nu, N), signals…)`` (R: the
    references at the N samples, p: the gains), differentiable; ``run`` is the same compiled (or
    interpreted). With a law that has a state, x0 and X also hold it (below the plant's state) and R
    has the row dt (see :meth:`references`).
    ``compile_time`` is the time spent building and compiling [s].
    """

    def __init__(self, plant: Any, controller: Any, h: float, n_sub: int, n_samples: int,
                 compile: bool = True):
        if not hasattr(controller, "symbolic"):
            raise ValueError(f"`controller` {type(controller).__name__} has no symbolic() law: "
                             "use backend='python'")
        start = time.perf_counter()
        if hasattr(controller, "reset"):
            controller.reset()                                  # the law's initial state is the reset one
        self.law = controller.symbolic()
        f, nq, nv = plant_function(plant)
        self.nq, self.nv, self.n_samples = nq, nv, n_samples
        nx, nr, n_p = f.size1_in(0), self.law.function.size1_in(2), self.law.function.size1_in(3)
        nc = 0 if self.law.state is None else self.law.state.size
        self.nx, self.nc = nx, nc
        xc, r, p = ca.SX.sym("x", nx + nc), ca.SX.sym("r", nr + (1 if nc else 0)), ca.SX.sym("p", n_p)
        x = xc[:nx]
        layout = plant.state_layout                              # q, q̇ where the plant keeps them in x
        args = [x[layout["q"]], x[layout["qd"]], r[:nr], p,
                *(plant_measurement(plant, name)(x) for name in self.law.measurements)]
        if nc:
            args += [xc[nx:], r[nr]]                             # the law's state, dt (the last row of R)
        out = self.law.function(*args)
        out = list(out) if isinstance(out, (list, tuple)) else [out]
        u, c_next, logged = out[0], (out[1] if nc else None), out[1 + (1 if nc else 0):]
        if u.shape[0] != f.size1_in(1):
            raise ValueError(f"the symbolic law of {type(controller).__name__} gives {u.shape[0]} inputs, "
                             f"the plant takes {f.size1_in(1)}")
        x_next = x
        for _ in range(n_sub):                                  # RK4 with u held (ZOH), as rk4_step
            k1 = f(x_next, u)
            k2 = f(x_next + 0.5 * h * k1, u)
            k3 = f(x_next + 0.5 * h * k2, u)
            k4 = f(x_next + h * k3, u)
            x_next = x_next + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        self._sample = ca.Function("sample", [xc, r, p], [ca.vertcat(x_next, c_next) if nc else x_next, u, *logged])
        self._rollout: ca.Function | None = None
        if compile:                       # the run's code is fixed by the sample's, N and this module's source
            key = b"|".join((c_code(self._sample), str((n_samples, MAPACCUM_BASE, ca.__version__)).encode(),
                             _SOURCE_HASH))
            self.run = compile_function(lambda: self.rollout, name="rollout", key=key)
        else:
            self.run = self.rollout
        self.compile_time = time.perf_counter() - start
        self.Ts = n_sub * h
        self._references: tuple[float, np.ndarray] | None = None

    @property
    def rollout(self) -> ca.Function:
        """``(x0, R, p) → (X, U, signals…)``: the sample accumulated over the run (built on first use)."""
        if self._rollout is None:
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

    def references(self, t0: float) -> np.ndarray:
        """R (nr, N): the reference sampled at the controller instants from ``t0`` (kept for the next run:
        references are functions of time only)."""
        if self._references is None or self._references[0] != t0:
            times = t0 + self.Ts * np.arange(self.n_samples)
            at_times = getattr(self.law.reference, "at_times", None)
            R = at_times(times) if at_times is not None else np.column_stack([self.law.reference(float(t))
                                                                             for t in times])
            if self.nc:                                        # dt = t_k − t_{k−1} as the Python loop's, 0 at k = 0
                R = np.vstack([R, np.diff(times, prepend=times[0])])
            self._references = (t0, np.ascontiguousarray(R, dtype=float))
        return self._references[1]

    def arrays(self, t0: float, x0: Any, bound: float = 1e12) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                                      dict[str, np.ndarray], float | None]:
        """One run from ``x0`` at ``t0``: (t (N,), x (N, nx), u (N, nu), signals, t_diverged).

        ``t_diverged`` is None, or the first sample whose state is non-finite or beyond ``bound``
        (divergence is checked on the samples, every ``Ts``).
        """
        ts = t0 + self.Ts * np.arange(self.n_samples)
        x0 = np.asarray(x0, dtype=float)
        if self.nc:
            x0 = np.concatenate([x0, self.law.state])
        X, U, *logged = (np.asarray(v) for v in self.run(x0, self.references(t0), self.law.parameters))
        X = X[:self.nx]
        bad = ~(np.all(np.isfinite(X), axis=0) & (np.max(np.abs(X), axis=0, initial=0.0) <= bound))
        bad |= ~np.all(np.isfinite(U), axis=0)
        t_bad = float(ts[int(np.argmax(bad))]) if np.any(bad) else None
        signals = {name: v.T[:, 0].copy() if name in self.law.scalars else v.T
                   for name, v in zip(self.law.signals, logged)}
        return ts, X.T.copy(), U.T.copy(), signals, t_bad


def simulate_compiled(plant: Any, controller: Any, t0: float, n_samples: int, x0: np.ndarray, h: float,
                      n_sub: int, bound: float, backend: str) -> tuple:
    """The body of ``simulate(..., backend="casadi")`` over ``n_samples`` controller samples (arguments
    validated by ``simulate``), returning :meth:`CompiledLoop.arrays`."""
    if backend not in BACKENDS:
        raise ValueError(f"`backend` must be one of {BACKENDS}, got {backend!r}")
    return CompiledLoop(plant, controller, h, n_sub, n_samples).arrays(t0, x0, bound)
