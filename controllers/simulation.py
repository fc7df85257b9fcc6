"""The one simulation loop of rmpc: continuous plant (fixed-step RK4), discrete controller (ZOH).

What Simulink did in the manual. A *plant* has a state ``x`` and a derivative ``f(t, x, u)``;
a *controller* is called every ``Ts`` seconds with the plant's measurement and its output ``u`` is
held constant until the next sample (zero-order hold). The plant is integrated with classical
fourth-order Runge–Kutta at step ``h`` (the manual's "max step"); ``Ts`` must be a multiple of ``h``.
Nothing else in rmpc integrates ODEs by hand. The plants live in :mod:`controllers.plants`.

The plant contract (duck-typed; only ``derivative`` is required)
----------------------------------------------------------------
``derivative(t, x, u) -> ẋ``
    The state derivative, an array of the plant's tangent size. A plain function ``f(t, x, u)``
    may stand for the whole plant.
``integrate(x, dx, h) -> x'``
    The state reached from ``x`` moving along the tangent vector ``dx`` for ``h``; every RK4 stage
    uses it, so a state on a manifold works. Absent or ``None``: ``x + h·dx``. The arm plants keep
    ``x = [q (nq), v (nv)]`` and ``ẋ = [v, v̇]`` (size 2 nv); when nq ≠ nv (continuous joints, a
    planar or free-flyer base) the ``q`` part moves by ``pin.integrate(model, q, h·v)``.
``dexp_inverse(x, xi, dx) -> dx'``
    With ``integrate``, on a non-commutative manifold (a free-flyer base): the tangent vector at ``x``
    whose flow ``integrate(x, ·)`` moves like ``dx`` (given at ``integrate(x, xi, 1)``). RK4 then
    corrects its stages (Runge–Kutta–Munthe-Kaas) and stays fourth order; without it, stages are
    composed as they are (exact on vector spaces and commutative groups, second order otherwise).
    ``ArmPlant`` provides it through ``pin.dIntegrate`` when nq ≠ nv.
``acceleration(t, q, v, u) -> v̇``
    For a mechanical plant with x = [q, v] (equal sizes, no ``integrate``) and ẋ = [v, v̇]: the loop
    then takes the same RK4 steps in Nyström form (:func:`rk4_stepper`; equal to the classical form in
    exact arithmetic) without building ẋ; ``q`` and ``v`` are the loop's scratch arrays, read during
    the call and never kept. ``derivative`` stays the reference: the loop calls it at the
    first sample (the shape check) and repeats a step that became non-finite through it, so a plant
    that can tell why (``ArmPlant``: a singular B(q)) raises its own error. ``ArmPlant`` provides it.
``time_invariant_acceleration``
    Optional, with ``acceleration``: a callable ``(q, v, u) -> v̇`` (or ``None``) for a plant whose
    acceleration does not depend on t and needs no check beyond the loop's (``u`` a finite float vector
    of the first sample's size); the Nyström stages call it instead, without a Python frame in between.
    ``ArmPlant`` without friction, saturation or external force gives ``pin.aba`` on its model and data.
``tangent_size``
    The size of ``ẋ`` when it differs from ``len(x)`` (default ``len(x)``). ``simulate`` checks the
    shape of the first derivative once and names the plant's derivative when it is wrong.
``state_size``
    The length ``x0`` must have (checked once, the error names ``x0``).
``input_size``
    The length of ``u`` (an int, or a tuple of the accepted lengths): the controller's first output
    is checked against it once, so a scalar voltage for a two-joint arm is an error rather than
    broadcast to both joints.
``measure(t, x) -> measurement``
    What the controller receives (default ``x`` itself). Arm plants return an
    :class:`~controllers.plants.ArmMeasurement` (frozen: ``q``, ``qd``, ``wrench`` or ``None``), so a
    controller reads ``meas.q``, ``meas.qd``, ``meas.wrench`` and never slices a flat vector; other
    plants define their own small frozen dataclass (image features, mobile-robot postures...).
    A measurement with ``q``/``qd`` attributes is logged automatically as ``res.q``/``res.qd``.
``state_layout``
    ``{name: slice or index}`` of named parts of ``x`` (e.g. ``{"q": slice(0, 2), "qd": slice(2, 4)}``):
    ``res[name]``, ``res.q`` and ``res.qd`` read the logged states through it.
``units``
    ``{signal name: unit}`` used as axis labels by :meth:`SimulationResult.plot`.
``bound``
    The plant's own divergence bound on ``max |x_i|`` (default ``1e12``; the kinematic
    :class:`~controllers.plants.JointIntegrator` uses a few hundred rad); ``simulate(..., bound=)``
    overrides it. The loop's only per-step check is one dot product, x·x <= bound² (the exact
    ``max |x_i| <= bound`` is evaluated when it fails).
``initial_state(q0, qd0=None) -> x0``
    On arm plants: the state at rest (or moving with ``qd0``).
``check_step(h, x0)``
    The plant's own test of the integration step, called by :func:`simulate` before the first step
    (for either backend): ValueError when RK4 of step ``h`` cannot be stable on the plant from ``x0``
    (:class:`~controllers.plants.ArmInContact`: a contact too stiff for h at the arm's effective mass,
    :func:`rk4_stable`), instead of a run that stays bounded and is non-physical.
``stepper(h) -> step``
    A plant that advances its own state (a physics engine: :class:`controllers.mujoco.MujocoPlant`) gives the
    function ``step(t, x, u) -> x(t + h)`` that replaces the loop's RK4 step; the loop asks for it once per run
    with its step ``h`` (the plant checks that its own step divides h) and holds ``u`` over it as for RK4.
    ``derivative`` is still required (the first sample's shape check; stage-by-stage comparisons). A plant that
    detects a divergence itself raises :class:`SimulationDiverged`.

The controller contract
-----------------------
A controller is a callable ``(t, measurement) -> u``; ``reset()`` is called before the run and
``log() -> dict`` after every call (its entries become signals of the result); an optional
``diagnose(plant, Ts, measurement) -> str`` (measurement at the start) says why the loop may diverge
and is appended to the :class:`SimulationDiverged` message (e.g. a violated sampled-stability bound). Controllers derive from
:class:`LoggedController`, which provides both: the law calls ``self.record(e=..., q_d=...)``.

Multi-rate loops: ``ZeroOrderHold(block, Ts)`` runs ``block`` every ``Ts`` (a multiple of the loop's
period) and holds its output in between — a vision loop at 40 ms inside a motion loop at 1 ms.
``Chain(first, second, name=...)`` feeds ``first``'s output to ``second`` as the extra measurement
attribute ``name`` (``meas.name``; every other attribute is the plant's measurement): an estimator
at 1 ms feeding a controller at 40 ms is ``Chain(estimator, ZeroOrderHold(controller, 0.04),
name="estimate")``: the controller reads ``meas.estimate`` and ``meas.q`` (an :class:`Augmented`
measurement). The chain's output is the second block's; the logs of both blocks are merged. A block
with periods inside declares them through ``periods()``; ``simulate`` checks each is a multiple of ``Ts``.

>>> import numpy as np
>>> class Decay:                       # ẋ = −x + u
...     def derivative(self, t, x, u): return -x + u
>>> res = simulate(Decay(), lambda t, x: np.zeros(1), (0.0, 1.0), [1.0], h=1e-3, Ts=1e-2)
>>> round(float(res.x[-1, 0]), 6) == round(float(np.exp(-1.0)), 6)
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Mapping, Protocol

import numpy as np

from rigid_body.integration import RK4_WEIGHTS, rk4_step_law
from rigid_body.validation import as_positive, as_vector

DEFAULT_BOUND = 1e12
_FLOAT64 = np.dtype(np.float64)


class Plant(Protocol):
    """A continuous-time system: ``derivative(t, x, u) -> ẋ``; the optional hooks are in the module docstring."""

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray: ...


class Controller(Protocol):
    """A discrete controller: ``__call__(t, measurement) -> u``; optionally ``reset()`` and ``log()``."""

    def __call__(self, t: float, measurement: Any) -> np.ndarray: ...


class SimulationDiverged(RuntimeError):
    """The plant's state became non-finite (or left its bound): ``t`` is when it happened."""

    def __init__(self, message: str, t: float):
        super().__init__(message)
        self.t = t


# --------------------------------------------------------------------------------------------
# Controllers: logging, zero-order hold, chains
# --------------------------------------------------------------------------------------------

class LoggedController:
    """Base of the controllers: ``record(**signals)`` in the law, ``log()`` and ``reset()`` inherited.

    A subclass with its own state overrides ``reset`` and calls ``super().reset()``.
    """

    _log: dict[str, Any] = {}

    def record(self, **signals: Any) -> None:
        """Keep ``signals`` as this sample's log (the loop reads them with :meth:`log`)."""
        self._log = signals

    def log(self) -> dict[str, Any]:
        return self._log

    def reset(self) -> None:
        self._log = {}


def _hold_rule(t: float, next_t: float | None, Ts: float) -> tuple[bool, float | None]:
    """A zero-order hold's rule at time t: (whether it evaluates its block now, its next instant). It does at
    its first call and whenever t reaches the next instant (within 1e-9 Ts), which then moves on by Ts."""
    if next_t is None or t >= next_t - 1e-9 * Ts:
        return True, (t if next_t is None else next_t) + Ts
    return False, next_t


class ZeroOrderHold:
    """Runs ``block`` every ``Ts`` seconds (from the first call) and holds its output in between.

    ``Ts`` must be a multiple of the loop's controller period (:func:`simulate` checks it). The block's
    log is the one of its last sample (held too).
    """

    runtime_attributes = ("_next", "_output")   # the Python loop's hold: not part of the compiled loop's key

    def __init__(self, block: Callable[[float, Any], Any], Ts: float):
        self.block, self.Ts = block, as_positive(Ts, "Ts")
        self.reset()

    def reset(self) -> None:
        self._next: float | None = None
        self._output: Any = None
        if hasattr(self.block, "reset"):
            self.block.reset()

    def periods(self) -> tuple[float, ...]:
        """The sampling periods of this block and of the blocks inside it."""
        return (self.Ts,) + tuple(getattr(self.block, "periods", tuple)())

    def __call__(self, t: float, measurement: Any) -> Any:
        due, self._next = _hold_rule(t, self._next, self.Ts)
        if due:
            self._output = self.block(t, measurement)
        return self._output

    @staticmethod
    def instants(times: np.ndarray, Ts: float) -> np.ndarray:
        """Where a hold of period ``Ts`` called at ``times`` (from the run's first sample) evaluates its block
        (bool (N,)): the same rule as a call, for a loop that samples the block itself (the compiled one)."""
        out, next_t = np.zeros(len(times), dtype=bool), None
        for k, t in enumerate(np.asarray(times, dtype=float).tolist()):
            out[k], next_t = _hold_rule(t, next_t, Ts)
        return out

    def log(self) -> dict[str, Any]:
        return self.block.log() if hasattr(self.block, "log") else {}


class Augmented:
    """A measurement with extra named entries: ``meas.name`` is the entry, any other attribute the
    underlying measurement's (``base``)."""

    __slots__ = ("base", "_extra")

    def __init__(self, base: Any, **extra: Any):
        self.base, self._extra = base, extra

    def __getattr__(self, name: str) -> Any:
        extra = object.__getattribute__(self, "_extra")
        if name in extra:
            return extra[name]
        return getattr(object.__getattribute__(self, "base"), name)


class Chain:
    """``first`` then ``second``: ``second`` is called with the plant's measurement augmented by
    ``first``'s output under ``name`` (see :class:`Augmented`); the chain outputs ``second``'s output.
    The logs of both blocks are merged (``second``'s entries win on a name clash)."""

    def __init__(self, first: Callable[[float, Any], Any], second: Callable[[float, Any], Any], name: str):
        if not name.isidentifier():
            raise ValueError(f"`name` must be an identifier (an attribute of the measurement), got {name!r}")
        self.first, self.second, self.name = first, second, name

    def reset(self) -> None:
        for block in (self.first, self.second):
            if hasattr(block, "reset"):
                block.reset()

    def periods(self) -> tuple[float, ...]:
        return tuple(p for b in (self.first, self.second) for p in getattr(b, "periods", tuple)())

    def __call__(self, t: float, measurement: Any) -> Any:
        y = self.first(t, measurement)
        return self.second(t, Augmented(measurement, **{self.name: y}))

    def log(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for block in (self.first, self.second):
            if hasattr(block, "log"):
                out.update(block.log())
        return out


# --------------------------------------------------------------------------------------------
# The result
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class SimulationResult:
    """Samples at the controller instants: ``t`` (N,), state ``x`` (N, nx), input ``u`` (N, nu),
    and named signals (N, ...) logged by the controller's ``log()``, the ``log`` callback and the
    measurement (``q``, ``qd``).

    ``result["e"]`` is the signal ``e``; ``result[name]`` also reads the plant's ``state_layout``.
    ``result.q``, ``result.qd`` are the joint positions and velocities (N, n).
    """

    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    signals: dict[str, np.ndarray] = field(default_factory=dict)
    layout: Mapping[str, Any] = field(default_factory=dict)
    units: Mapping[str, str] = field(default_factory=dict)
    components: Mapping[str, Any] = field(default_factory=dict)   # {signal: [(label, unit) per column]}, declared

    def describe(self, name: str) -> list[tuple[str, str]]:
        """One (label, unit) per column of the signal ``name``: as its controller declares them
        (``signal_components``), else as :func:`controllers.signals.components` names the book's signals (f_x …
        μ_z of a wrench, x₁, y₁ … of image points), else ``name1, name2 …`` with the plant's unit."""
        from controllers.signals import components

        y = np.asarray(self[name])
        width = int(np.prod(y.shape[1:])) if y.ndim > 1 else 1
        described = self.components.get(name) or components(name, width)
        if described is not None and len(described) == width:
            return [tuple(c) for c in described]
        unit = self.units.get(name, "")
        return [(name if width == 1 else f"{name}{i + 1}", unit) for i in range(width)]

    def __getitem__(self, name: str) -> np.ndarray:
        if name in ("t", "x", "u"):
            return getattr(self, name)
        if name in self.signals:
            return self.signals[name]
        if name in self.layout:
            return self.x[:, self.layout[name]]
        raise KeyError(f"no signal {name!r}; logged: {sorted(self.signals)}, states: {sorted(self.layout)}")

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        """One line: samples, time span, state and input sizes, signal names (not the arrays)."""
        span = f"[{self.t[0]:.4g}, {self.t[-1]:.4g}] s" if len(self.t) else "[]"
        return (f"SimulationResult({len(self.t)} samples on {span}, x: {self.x.shape[1:]}, u: {self.u.shape[1:]}, "
                f"signals={sorted(self.signals)})")

    @property
    def q(self) -> np.ndarray:
        """Joint positions (N, nq) (from the measurement or the plant's state layout)."""
        return self["q"]

    @property
    def qd(self) -> np.ndarray:
        """Joint velocities (N, nv)."""
        return self["qd"]

    def plot(self, *names: str, ax: Any = None, labels: Iterable[str] | None = None, scale: float = 1.0,
             unit: str | None = None) -> Any:
        """Plot the signals ``names`` (default ``"q"``) against time on ``ax`` (a new figure if None).

        The y axis is labelled with the signals' names and units (``unit`` overrides, e.g. after a
        ``scale`` of 1e3 to mm); a legend names the components (:meth:`describe`: f_x … μ_z of a wrench, x₁,
        y₁ … of image points) when more than one line is drawn. Returns ``ax``.
        """
        import matplotlib.pyplot as plt

        names = names or ("q",)
        new_figure = ax is None
        if new_figure:
            _, ax = plt.subplots()
        lines: list[str] = []
        shown: list[str] = []
        for name in names:
            y = np.asarray(self[name], dtype=float).reshape(len(self.t), -1)
            for (label, column_unit), column in zip(self.describe(name), y.T):
                ax.plot(self.t, scale * column)
                lines.append(label)
                column_unit = "–" if column_unit == "1" else column_unit      # dimensionless
                if column_unit and column_unit not in shown:
                    shown.append(column_unit)
        if unit is not None:
            shown = [unit] if unit else []
        ax.set_xlabel("t [s]")
        ax.set_ylabel(", ".join(names) + (f" [{', '.join(shown)}]" if shown else ""))
        if len(lines) > 4:  # many curves: the legend beside the axes, clear of them
            ax.legend(list(labels) if labels is not None else lines, fontsize="small",
                      loc="upper left", bbox_to_anchor=(1.01, 1.0))
            if new_figure:  # room for it inside the figure (else a saved PNG cuts it off)
                ax.figure.subplots_adjust(right=0.82)
        elif len(lines) > 1:
            ax.legend(list(labels) if labels is not None else lines, fontsize="small", loc="best")
        return ax


# --------------------------------------------------------------------------------------------
# The loop
# --------------------------------------------------------------------------------------------



# --------------------------------------------------------------------------------------------
# The step RK4 can take on a spring-mass-damper mode (a stiff contact)
# --------------------------------------------------------------------------------------------

def _oscillator(mass: Any, damping: Any, stiffness: Any) -> tuple[float, float, float]:
    """m > 0, d ≥ 0, k ≥ 0 of m ẍ + d ẋ + k x = 0 as floats; ValueError naming the argument."""
    return (as_positive(mass, "mass"), as_positive(damping, "damping", allow_zero=True),
            as_positive(stiffness, "stiffness", allow_zero=True))


def rk4_stable(mass: float, damping: float, stiffness: float, h: float) -> bool:
    """Whether RK4 of step ``h`` is stable on m ẍ + d ẋ + k x = 0: both roots λ of m λ² + d λ + k
    have |R(hλ)| ≤ 1, R(z) = 1 + z + z²/2 + z³/6 + z⁴/24 (RK4's amplification; without damping
    h √(k/m) ≤ 2√2)."""
    mass, damping, stiffness = _oscillator(mass, damping, stiffness)
    h = as_positive(h, "h")
    roots = np.roots([mass, damping, stiffness]) if stiffness > 0 else np.array([0.0, -damping / mass])
    z = h * roots.astype(complex)
    return bool(np.all(np.abs(1 + z + z * z / 2 + z ** 3 / 6 + z ** 4 / 24) <= 1.0 + 1e-12))


def rk4_stiffness_bound(mass: float, damping: float, h: float) -> float:
    """The largest k for which RK4 of step ``h`` is stable on m ẍ + d ẋ + k x = 0 (:func:`rk4_stable`;
    8 m/h² without damping); 0 when the damping alone is too much for h (h d/m > 2.785)."""
    mass, damping, _ = _oscillator(mass, damping, 0.0)
    h = as_positive(h, "h")
    if not rk4_stable(mass, damping, 0.0, h):
        return 0.0
    lo, hi = 0.0, 8.0 * mass / (h * h)
    while rk4_stable(mass, damping, hi, h):
        lo, hi = hi, 2.0 * hi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if rk4_stable(mass, damping, mid, h) else (lo, mid)
    return lo


def rk4_step_bound(mass: float, damping: float, stiffness: float) -> float:
    """The largest h for which RK4 is stable on m ẍ + d ẋ + k x = 0 (:func:`rk4_stable`): 2√2 √(m/k)
    without damping; ∞ when d = k = 0 (ẍ = 0: RK4 is exact at every step)."""
    mass, damping, stiffness = _oscillator(mass, damping, stiffness)
    rate = float(np.max(np.abs(np.roots([mass, damping, stiffness]))))   # |λ|: stable for h |λ| ≤ 1, not 3.5
    if rate == 0.0:
        return math.inf
    lo, hi = 1.0 / rate, 3.5 / rate
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if rk4_stable(mass, damping, stiffness, mid) else (lo, mid)
    return lo


def rk4_stepper(derivative: Callable[[float, np.ndarray, np.ndarray], np.ndarray], h: float,
                integrate: Callable[[np.ndarray, np.ndarray, float], np.ndarray] | None = None,
                dexp_inverse: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None = None,
                acceleration: Callable[[float, np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None = None,
                time_invariant: bool = False) -> Callable[[float, np.ndarray, np.ndarray], np.ndarray]:
    """``step(t, x, u)``: one classical Runge–Kutta step of ẋ = f(t, x, u) with the input ``u`` held,
    built once for a run of step ``h``.

    The stages are k_1 = f(t, x), k_2 = f(t + h/2, x ⊕ (h/2) k_1), k_3 = f(t + h/2, x ⊕ (h/2) k_2),
    k_4 = f(t + h, x ⊕ h k_3) and x' = x ⊕ h Σ b_i k_i (:data:`RK4_WEIGHTS`), where ``integrate(x, dx, h)``
    is x ⊕ h dx on a manifold (default ``x + h·dx``) and ``dexp_inverse`` brings the stage derivatives
    back to the tangent space at x (Runge–Kutta–Munthe-Kaas; see the plant contract).

    On a vector space the rows of M = [x; k_1; k_2; k_3; k_4] (zeros until computed) give every stage
    state and the result as one product each, a row of the Butcher tableau (with 1 for x) times M.
    A mechanical plant x = [q, v], ẋ = [v, a(t, q, v, u)] given by its ``acceleration`` a (and no
    ``integrate``) takes the same steps in Nyström form: with A = [q; v; a_1; a_2; a_3; a_4],
    v_2 = v + (h/2) a_1, v_3 = v + (h/2) a_2, v_4 = v + h a_3 and
    q_2 = q + (h/2) v, q_3 = q + (h/2) v + (h²/4) a_1, q_4 = q + h v + (h²/2) a_2,
    q' = q + h v + (h²/6)(a_1 + a_2 + a_3), v' = v + (h/6)(a_1 + 2 a_2 + 2 a_3 + a_4):
    each stage's (q_i, v_i) is one product C_i A (the classical stages, without building ẋ), written into
    one (2, n) scratch array: ``acceleration`` reads its ``q``, ``v`` during the call and keeps no reference.
    With ``time_invariant`` it is called without the time, ``acceleration(q, v, u)``.
    """
    hh = 0.5 * h
    if integrate is None and acceleration is not None:
        return _nystrom_stepper(acceleration, h, time_invariant)
    if integrate is None:
        stage2, stage3, stage4, result = np.array([[1.0, hh, 0.0, 0.0, 0.0], [1.0, 0.0, hh, 0.0, 0.0],
                                                   [1.0, 0.0, 0.0, h, 0.0], [1.0, *(h * RK4_WEIGHTS)]])

        def step(t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
            M = np.zeros((5, len(x)))
            M[0] = x
            M[1] = derivative(t, x, u)
            M[2] = derivative(t + hh, stage2.dot(M), u)
            M[3] = derivative(t + hh, stage3.dot(M), u)
            M[4] = derivative(t + h, stage4.dot(M), u)
            return result.dot(M)
        return step

    weights = 6.0 * RK4_WEIGHTS

    def weighted_sum(k1: np.ndarray, k2: np.ndarray, k3: np.ndarray, k4: np.ndarray) -> np.ndarray:
        return weights.dot(np.array((k1, k2, k3, k4)))

    def manifold_step(t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return rk4_step_law(derivative, t, x, u, h, integrate, dexp_inverse, weighted_sum)
    return manifold_step


def _nystrom_stepper(acceleration: Callable[..., np.ndarray], h: float,
                     time_invariant: bool = False) -> Callable[[float, np.ndarray, np.ndarray], np.ndarray]:
    """:func:`rk4_stepper`'s Nyström form: A = [q; v; a_1; a_2; a_3; a_4] and the stage states are
    scratch arrays allocated once (for the first x's size); stage i reads only the rows already computed.
    With ``time_invariant`` the acceleration is called as ``acceleration(q, v, u)`` (the plant's
    ``time_invariant_acceleration``: a library call without a Python frame per stage)."""
    hh, h2 = 0.5 * h, h * h
    C2 = np.array([[1.0, hh, 0.0], [0.0, 1.0, hh]])
    C3 = np.array([[1.0, hh, h2 / 4, 0.0], [0.0, 1.0, 0.0, hh]])
    C4 = np.array([[1.0, h, 0.0, h2 / 2, 0.0], [0.0, 1.0, 0.0, 0.0, h]])
    CR = np.array([[1.0, h, h2 / 6, h2 / 6, h2 / 6, 0.0], [0.0, 1.0, *(h * RK4_WEIGHTS)]])
    size = -1
    A = A3 = A4 = A5 = q = v = S = Sq = Sv = x_rows = np.empty(0)

    def allocate(n: int) -> None:
        """The scratch arrays for states of size n (at the first step, and whenever the size changes)."""
        nonlocal size, A, A3, A4, A5, q, v, S, Sq, Sv, x_rows
        size = n
        A = np.empty((6, n >> 1))
        A3, A4, A5, q, v = A[:3], A[:4], A[:5], A[0], A[1]
        x_rows = A[:2].reshape(-1)   # a view: ``x_rows[...] = x`` fills [q; v] (4× faster than A[:2] = x.reshape)
        S = np.empty((2, n >> 1))
        Sq, Sv = S

    if time_invariant:
        def step(t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
            if len(x) != size:
                allocate(len(x))
            x_rows[...] = x
            A[2] = acceleration(q, v, u)
            C2.dot(A3, S)
            A[3] = acceleration(Sq, Sv, u)
            C3.dot(A4, S)
            A[4] = acceleration(Sq, Sv, u)
            C4.dot(A5, S)
            A[5] = acceleration(Sq, Sv, u)
            return CR.dot(A).ravel()
        return step

    def step(t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        if len(x) != size:
            allocate(len(x))
        x_rows[...] = x
        A[2] = acceleration(t, q, v, u)
        C2.dot(A3, S)
        A[3] = acceleration(t + hh, Sq, Sv, u)
        C3.dot(A4, S)
        A[4] = acceleration(t + hh, Sq, Sv, u)
        C4.dot(A5, S)
        A[5] = acceleration(t + h, Sq, Sv, u)
        return CR.dot(A).ravel()
    return step


def rk4_step(f: Callable[[float, np.ndarray], np.ndarray], t: float, x: np.ndarray, h: float,
             integrate: Callable[[np.ndarray, np.ndarray, float], np.ndarray] | None = None,
             dexp_inverse: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None = None) -> np.ndarray:
    """One classical Runge–Kutta step of ẋ = f(t, x) (:func:`rk4_stepper`, the loop's step, for one call)."""
    return rk4_stepper(lambda tau, xi, _: f(tau, xi), h, integrate, dexp_inverse)(t, x, None)


def sample_times(t0: float, tf: float, Ts: float) -> np.ndarray:
    """The controller's sample instants t_0 + k T_s, k = 0 … ⌊(t_f − t_0)/T_s⌋ (a ratio within 1e-9 of an
    integer counts as that integer): the times of every loop's samples."""
    return t0 + np.arange(int(np.floor((tf - t0) / Ts + 1e-9)) + 1) * Ts


def _periods_must_divide(controller: Any, Ts: float) -> None:
    for period in getattr(controller, "periods", tuple)():
        ratio = period / Ts
        if abs(ratio - round(ratio)) > 1e-9 * max(1.0, ratio) or round(ratio) < 1:
            raise ValueError(f"`Ts` = {Ts:g} s must divide the period {period:g} s of a ZeroOrderHold block")


def simulate(plant: Plant | Callable[[float, np.ndarray, np.ndarray], np.ndarray],
             controller: Controller | Callable[[float, Any], np.ndarray],
             t_span: tuple[float, float], x0: Any, h: float, Ts: float | None = None,
             log: Callable[[float, np.ndarray, np.ndarray], Mapping[str, Any]] | None = None,
             bound: float | None = None, backend: str = "python") -> SimulationResult:
    """Simulate a sampled-data loop: RK4 plant of step ``h``, controller every ``Ts`` with ZOH.

    Parameters
    ----------
    plant : object following the plant contract (module docstring), or a function ``f(t, x, u)``.
    controller : object or function ``(t, measurement) -> u``; ``reset()`` is called first if present,
        and ``log() -> dict`` after each call if present (its entries become signals).
    t_span : (t0, tf) [s].
    x0 : initial state (nx,) (``plant.initial_state(q0)`` for an arm).
    h : integration step [s]; ``Ts`` : controller period [s], a multiple of ``h`` (default ``h``).
    log : optional ``(t, x, u) -> dict`` of extra signals, evaluated at each controller sample.
    bound : the run stops when any |x_i| exceeds this (default: the plant's ``bound``, else 1e12).
    backend : ``"python"`` (this loop) or ``"casadi"`` (the same loop compiled, for plants and
        controllers with a symbolic form: :mod:`controllers.compiled`).

    Raises
    ------
    ValueError : bad arguments (naming them), an ``x0`` of the wrong size, a derivative of the wrong shape, a step
        ``h`` the plant says RK4 cannot take (its ``check_step``: e.g. a contact too stiff for h).
    SimulationDiverged : when the state becomes non-finite or exceeds ``bound``, naming the time.
    """
    try:
        t0, tf = (float(v) for v in t_span)
    except (TypeError, ValueError):
        raise ValueError(f"`t_span` must be (t_0, t_f) in seconds, got {t_span!r}") from None
    if not (np.isfinite(t0) and np.isfinite(tf) and tf > t0):
        raise ValueError(f"`t_span` must be finite with t_f > t_0, got {t_span}")
    h = as_positive(h, "h")
    Ts = h if Ts is None else as_positive(Ts, "Ts")
    ratio = Ts / h
    n_sub = int(round(ratio))
    if n_sub < 1 or abs(ratio - n_sub) > 1e-9 * max(1.0, ratio):
        raise ValueError(f"`Ts` must be a positive multiple of `h`, got Ts={Ts}, h={h}")
    _periods_must_divide(controller, Ts)
    bound_name = "bound" if bound is not None else f"{type(plant).__name__}.bound"
    bound = getattr(plant, "bound", DEFAULT_BOUND) if bound is None else bound
    try:
        bound = float(bound)
    except (TypeError, ValueError):
        raise ValueError(f"`{bound_name}` must be a positive number, got {bound!r}") from None
    if not (np.isfinite(bound) and bound > 0):
        raise ValueError(f"`{bound_name}` must be finite and positive, got {bound}")
    x = as_vector(x0, None, "x0").copy()
    nx = getattr(plant, "state_size", None)
    if nx is not None and x.size != nx:
        raise ValueError(f"`x0` must have {nx} entries for {type(plant).__name__} "
                         f"(see its initial_state), got {x.size}")
    check_step = getattr(plant, "check_step", None)
    if check_step is not None:
        check_step(h, x)
    if backend != "python":
        from controllers.compiled import CompiledLoopUnavailable, simulate_compiled  # the same loop, compiled

        try:
            ts, xs, us, signals, t_bad = simulate_compiled(plant, controller, t0, len(sample_times(t0, tf, Ts)), x,
                                                           h, n_sub, bound, backend)
        except CompiledLoopUnavailable as fault:   # no compiler, a failing one, an unusable cache: one line, go on
            import warnings

            warnings.warn(f"{fault}; the loop runs on the Python backend (same results, slower)", stacklevel=2)
        else:
            if t_bad is not None:
                raise SimulationDiverged(f"plant state became non-finite or exceeded {bound:g} by t = {t_bad:.6g} s "
                                         f"(backend={backend!r}, checked every Ts): the loop diverges", t_bad)
            for name, value in ({} if log is None else _logged(log, ts, xs, us)).items():
                signals[name] = value
            return SimulationResult(t=ts, x=xs, u=us, signals=signals,
                                    layout=dict(getattr(plant, "state_layout", {})),
                                    units=dict(getattr(plant, "units", {})), components=declared_components(controller))
    derivative = plant.derivative if hasattr(plant, "derivative") else plant
    integrate = getattr(plant, "integrate", None)
    n_dx = getattr(plant, "tangent_size", x.size)
    acceleration = getattr(plant, "acceleration", None) if n_dx == x.size and x.size % 2 == 0 else None
    timeless = getattr(plant, "time_invariant_acceleration", None) if acceleration is not None else None
    own_stepper = getattr(plant, "stepper", None)   # a self-stepping plant (module docstring)
    step = own_stepper(h) if own_stepper is not None else rk4_stepper(
        derivative, h, integrate, getattr(plant, "dexp_inverse", None), timeless or acceleration, timeless is not None)
    measure = getattr(plant, "measure", None)
    n_u = getattr(plant, "input_size", None)
    n_u = None if n_u is None else tuple(np.atleast_1d(n_u).tolist())
    if hasattr(controller, "reset"):
        controller.reset()
    controller_log = getattr(controller, "log", None)
    layout = getattr(plant, "state_layout", {})
    ts = sample_times(t0, tf, Ts)
    n_samples = len(ts)
    xs = np.empty((n_samples, x.size))
    us: list[np.ndarray] = []
    signals: dict[str, list] = {}
    log_q: list[str] = []
    # max |x_i| <= ‖x‖₂: the one dot product x·x <= bound² settles a step (NaN and inf fail it); else max |x_i|
    # (a bound beyond 1e150, whose square may overflow, sends every step to that exact test)
    exact_test = bound >= 1e150
    bound2 = bound * bound
    substeps = range(n_sub)
    for k in range(n_samples):
        t = t0 + k * Ts
        meas = measure(t, x) if measure else x
        u = controller(t, meas)
        if type(u) is not np.ndarray or u.ndim != 1 or u.dtype is not _FLOAT64:
            u = np.atleast_1d(np.asarray(u, dtype=float))
        if k == 0:
            log_q = [name for name in ("q", "qd") if hasattr(meas, name) and name not in layout]
            if n_u is not None and (u.ndim != 1 or u.size not in n_u):
                who = getattr(controller, "__qualname__", type(controller).__name__)
                sizes = " or ".join(map(str, n_u))
                raise ValueError(f"the controller `{who}` output shape {u.shape} at t = {t:g} s; "
                                 f"{type(plant).__name__} takes an input u of size {sizes}")
        xs[k] = x
        us.append(u)
        for name in log_q:
            _append(signals, name, getattr(meas, name))
        if controller_log is not None:
            for name, value in controller_log().items():
                if type(value) is np.ndarray or type(value) is float:  # stacked at the end (_append inline)
                    try:
                        signals[name].append(value)
                    except KeyError:
                        signals[name] = [value]
                else:
                    _append(signals, name, value)
        if log is not None:
            for name, value in log(t, x, u).items():
                _append(signals, name, value)
        if not (math.isfinite(sum(u.tolist())) or np.isfinite(u).all()):  # the sum may overflow: recheck
            why = _diagnosis(controller, plant, Ts, measure(t0, xs[0]) if measure else xs[0])
            raise SimulationDiverged(f"controller output became non-finite at t = {t:.6g} s: u = {u}{why}", t)
        if k == n_samples - 1:
            break
        if k == 0:
            shape = np.shape(derivative(t, x, u))
            if shape != (n_dx,):
                who = getattr(derivative, "__qualname__", "the plant's derivative")
                raise ValueError(f"`{who}` returned shape {shape}, expected ({n_dx},) for a state of size {x.size}")
        for j in substeps:
            ti = t + j * h
            x_next = step(ti, x, u)
            if exact_test or not x_next.dot(x_next) <= bound2:
                peak = np.max(np.abs(x_next))
                if peak <= bound:
                    x = x_next
                    continue
                why = _diagnosis(controller, plant, Ts, measure(t0, xs[0]) if measure else xs[0])
                if np.isfinite(peak):
                    raise SimulationDiverged(
                        f"plant state exceeded {bound:g} at t = {ti + h:.6g} s: the loop diverges{why}", ti + h)
                if acceleration is not None:  # the step again through ``derivative``, which may name the cause
                    rk4_stepper(derivative, h)(ti, x, u)
                raise SimulationDiverged(
                    f"plant state became non-finite at t = {ti + h:.6g} s (step h = {h:g} s); "
                    f"the loop is unstable or the step is too large{why}", ti + h)
            x = x_next
    return SimulationResult(t=ts, x=xs, u=_stacked(us),
                            signals={k: _stacked(v) for k, v in signals.items()},
                            layout=dict(layout),
                            units=dict(getattr(plant, "units", {})), components=declared_components(controller))


def declared_components(controller: Any) -> dict[str, list[tuple[str, str]]]:
    """The ``signal_components`` ({signal: [(label, unit) per column]}) the controller's blocks declare (a
    :class:`Chain`'s two blocks, a :class:`ZeroOrderHold`'s block; the later block wins a clash)."""
    out: dict[str, list[tuple[str, str]]] = {}
    stack, seen = [controller], set()
    while stack:
        block = stack.pop(0)
        if block is None or id(block) in seen:
            continue
        seen.add(id(block))
        out.update(getattr(block, "signal_components", None) or {})
        stack += [getattr(block, name, None) for name in ("block", "first", "second")]
    return out


def _stacked(samples: list) -> np.ndarray:
    """The logged samples as one float array (N, ...): ``np.array`` finds float64 at once; anything else
    is converted as ``np.array(samples, dtype=float)`` (twice as slow on float arrays)."""
    out = np.array(samples)
    return out if out.dtype is _FLOAT64 else np.array(samples, dtype=float)


def _append(signals: dict[str, list], name: str, value: Any) -> None:
    """Log one sample of a signal (float arrays are stacked at the end of the run, anything else is
    converted now, so that a list the controller changes later is logged as it was)."""
    if not isinstance(value, (float, np.ndarray)):
        value = np.asarray(value, dtype=float)
    try:
        signals[name].append(value)
    except KeyError:
        signals[name] = [value]


def _diagnosis(controller: Any, plant: Any, Ts: float, measurement: Any) -> str:
    """``controller.diagnose(plant, Ts, measurement)`` (a controller that can tell why its loop
    diverges, e.g. a violated sampled-stability bound) as text to append to the error; "" otherwise."""
    diagnose = getattr(controller, "diagnose", None)
    if diagnose is None:
        return ""
    try:
        text = diagnose(plant, Ts, measurement)
    except Exception as exc:  # the diagnosis must never hide the divergence itself
        return f" (the controller's diagnosis failed: {type(exc).__name__}: {exc})"
    return f". {text}" if text else ""


def _logged(log: Callable, ts: np.ndarray, xs: np.ndarray, us: np.ndarray) -> dict[str, np.ndarray]:
    """The ``log`` callback's signals along a finished run."""
    out: dict[str, list] = {}
    for t, x, u in zip(ts, xs, us):
        for name, value in log(t, x, u).items():
            out.setdefault(name, []).append(np.asarray(value, dtype=float))
    return {name: np.array(v) for name, v in out.items()}


