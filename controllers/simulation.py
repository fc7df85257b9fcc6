"""The one simulation loop of rmpc: continuous plant (fixed-step RK4), discrete controller (ZOH).

What Simulink did in the manual. A *plant* has a state ``x`` and a derivative ``f(t, x, u)``;
a *controller* is called every ``Ts`` seconds with the plant's measurement and its output ``u`` is
held constant until the next sample (zero-order hold). The plant is integrated with classical
fourth-order Runge–Kutta at step ``h`` (the manual's "max step"); ``Ts`` must be a multiple of ``h``.

Nothing else in rmpc integrates ODEs by hand.

>>> import numpy as np
>>> class Decay:                       # ẋ = −x + u
...     def derivative(self, t, x, u): return -x + u
>>> res = simulate(Decay(), lambda t, x: np.zeros(1), (0.0, 1.0), [1.0], h=1e-3, Ts=1e-2)
>>> round(float(res.x[-1, 0]), 6) == round(float(np.exp(-1.0)), 6)
True
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Protocol

import numpy as np

from rigid_body.validation import as_vector


class Plant(Protocol):
    """A continuous-time system: ``derivative(t, x, u) -> ẋ``; optionally ``measure(t, x)``."""

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray: ...


class Controller(Protocol):
    """A discrete controller: ``__call__(t, measurement) -> u``; optionally ``reset()`` and ``log()``."""

    def __call__(self, t: float, measurement: Any) -> np.ndarray: ...


class SimulationDiverged(RuntimeError):
    """The plant's state became non-finite (or left its bound): ``t`` is when it happened."""

    def __init__(self, message: str, t: float):
        super().__init__(message)
        self.t = t


@dataclass(frozen=True)
class SimulationResult:
    """Samples at the controller instants: ``t`` (N,), state ``x`` (N, nx), input ``u`` (N, nu),
    and named signals (N, ...) logged by the controller's ``log()`` and the ``log`` callback.

    ``result["e"]`` is the signal ``e``.
    """

    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    signals: dict[str, np.ndarray] = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        if name in ("t", "x", "u"):
            return getattr(self, name)
        if name not in self.signals:
            raise KeyError(f"no signal {name!r}; logged: {sorted(self.signals)}")
        return self.signals[name]

    def __len__(self) -> int:
        return len(self.t)


def rk4_step(f: Callable[[float, np.ndarray], np.ndarray], t: float, x: np.ndarray, h: float) -> np.ndarray:
    """One classical Runge–Kutta step of ẋ = f(t, x)."""
    k1 = f(t, x)
    k2 = f(t + 0.5 * h, x + 0.5 * h * k1)
    k3 = f(t + 0.5 * h, x + 0.5 * h * k2)
    k4 = f(t + h, x + h * k3)
    return x + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def simulate(plant: Plant | Callable[[float, np.ndarray, np.ndarray], np.ndarray],
             controller: Controller | Callable[[float, Any], np.ndarray],
             t_span: tuple[float, float], x0: Any, h: float, Ts: float | None = None,
             log: Callable[[float, np.ndarray, np.ndarray], Mapping[str, Any]] | None = None,
             bound: float = 1e12) -> SimulationResult:
    """Simulate a sampled-data loop: RK4 plant of step ``h``, controller every ``Ts`` with ZOH.

    Parameters
    ----------
    plant : object with ``derivative(t, x, u)`` (and optionally ``measure(t, x)``, default ``x``),
        or a plain function ``f(t, x, u)``.
    controller : object or function ``(t, measurement) -> u``; ``reset()`` is called first if present,
        and ``log() -> dict`` after each call if present (its entries become signals).
    t_span : (t0, tf) [s].
    x0 : initial state (nx,).
    h : integration step [s]; ``Ts`` : controller period [s], a multiple of ``h`` (default ``h``).
    log : optional ``(t, x, u) -> dict`` of extra signals, evaluated at each controller sample.
    bound : the run stops when any |x_i| exceeds this (a diverging loop).

    Raises
    ------
    SimulationDiverged : when the state becomes non-finite or exceeds ``bound``, naming the time.
    """
    t0, tf = (float(v) for v in t_span)
    if not (np.isfinite(t0) and np.isfinite(tf) and tf > t0):
        raise ValueError(f"`t_span` must be finite with t_f > t_0, got {t_span}")
    if not (np.isfinite(h) and h > 0):
        raise ValueError(f"`h` must be a positive step, got {h}")
    Ts = h if Ts is None else float(Ts)
    if not (np.isfinite(Ts) and Ts > 0):
        raise ValueError(f"`Ts` must be a positive sampling period, got {Ts}")
    ratio = Ts / h
    n_sub = int(round(ratio))
    if n_sub < 1 or abs(ratio - n_sub) > 1e-9 * max(1.0, ratio):
        raise ValueError(f"`Ts` must be a positive multiple of `h`, got Ts={Ts}, h={h}")
    x = as_vector(x0, None, "x0").copy()
    derivative = plant.derivative if hasattr(plant, "derivative") else plant
    measure = getattr(plant, "measure", None)
    if hasattr(controller, "reset"):
        controller.reset()
    controller_log = getattr(controller, "log", None)
    n_samples = int(np.floor((tf - t0) / Ts + 1e-9)) + 1

    ts = np.empty(n_samples)
    xs = np.empty((n_samples, x.size))
    us: list[np.ndarray] = []
    signals: dict[str, list] = {}
    for k in range(n_samples):
        t = t0 + k * Ts
        u = np.atleast_1d(np.asarray(controller(t, measure(t, x) if measure else x), dtype=float))
        ts[k], xs[k] = t, x
        us.append(u)
        extra: dict[str, Any] = {}
        if controller_log is not None:
            extra.update(controller_log())
        if log is not None:
            extra.update(log(t, x, u))
        for name, value in extra.items():
            signals.setdefault(name, []).append(np.asarray(value, dtype=float))
        if not np.all(np.isfinite(u)):
            raise SimulationDiverged(f"controller output became non-finite at t = {t:.6g} s: u = {u}", t)
        if k == n_samples - 1:
            break

        def f(tau: float, xi: np.ndarray, u: np.ndarray = u) -> np.ndarray:
            return derivative(tau, xi, u)

        for j in range(n_sub):
            ti = t + j * h
            x = rk4_step(f, ti, x, h)
            if not np.all(np.isfinite(x)):
                raise SimulationDiverged(
                    f"plant state became non-finite at t = {ti + h:.6g} s (step h = {h:g} s); "
                    "the loop is unstable or the step is too large", ti + h)
            if np.max(np.abs(x)) > bound:
                raise SimulationDiverged(
                    f"plant state exceeded {bound:g} at t = {ti + h:.6g} s: the loop diverges", ti + h)
    return SimulationResult(t=ts, x=xs, u=np.array(us),
                            signals={k: np.array(v) for k, v in signals.items()})


def per_joint(value: Any, n: int, name: str) -> np.ndarray:
    """A per-joint quantity given as a scalar (the same for every joint) or (n,): a finite (n,) vector."""
    if np.ndim(value) == 0:
        value = np.full(n, as_vector(value, 1, name)[0])
    return as_vector(value, n, name).copy()


def as_friction(viscous_friction: Any, n: int) -> np.ndarray:
    """Viscous friction F_v (scalar or (n,)) as a finite non-negative (n,) vector [N·m·s/rad]."""
    Fv = per_joint(viscous_friction, n, "viscous_friction")
    if np.any(Fv < 0):
        raise ValueError(f"`viscous_friction` must be non-negative, got {Fv}")
    return Fv


class ArmPlant:
    """A rigid arm driven by joint torques: x = [q, q̇], ẋ = [q̇, B⁻¹(τ − C q̇ − g − F_v q̇ − J^T h_e)].

    Parameters
    ----------
    robot : the :class:`~rigid_body.robots.Robot` (motors included when its URDF has them).
    viscous_friction : F_v, scalar or (nv,) [N·m·s/rad].
    tau_max : optional actuator limits (nv,) — the commanded torque is saturated.
    external_force : optional ``(t, q, qd) -> tau_ext`` (joint torques of external forces), subtracted.
    """

    def __init__(self, robot: Any, viscous_friction: Any = 0.0, tau_max: Any = None,
                 external_force: Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None = None):
        self.robot = robot
        self.n = robot.nv
        self.Fv = as_friction(viscous_friction, self.n)
        self.tau_max = None if tau_max is None else as_vector(tau_max, self.n, "tau_max")
        if self.tau_max is not None and np.any(self.tau_max <= 0):
            raise ValueError(f"`tau_max` must be positive torque limits, got {self.tau_max}")
        self.external_force = external_force
        from rigid_body.dynamics import forward_dynamics

        self._forward_dynamics = forward_dynamics  # called with check=False: inputs validated here

    def torque(self, u: np.ndarray) -> np.ndarray:
        """The torque actually applied: ``u`` saturated at ±tau_max."""
        if np.shape(u) != (self.n,):
            raise ValueError(f"the arm needs {self.n} joint torques, got an input of shape {np.shape(u)}")
        return u if self.tau_max is None else np.clip(u, -self.tau_max, self.tau_max)

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        n = self.n
        q, qd = x[:n], x[n:]
        tau = self.torque(u) - self.Fv * qd
        if self.external_force is not None:
            tau = tau - self.external_force(t, q, qd)
        xd = np.empty(2 * n)
        xd[:n] = qd
        xd[n:] = self._forward_dynamics(self.robot, q, qd, tau, check=False)
        return xd
