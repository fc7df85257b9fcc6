"""The one Runge–Kutta step of rmpc: classical RK4 with the input held, for any scalar type.

:func:`rk4_step_law` is written once and run by the Python loop (:func:`controllers.simulation.rk4_stepper`'s
manifold stepper, on arrays), by the compiled loop (:class:`controllers.compiled.CompiledLoop`, on CasADi symbols)
and by optimal control's multiple shooting (:mod:`planners.optimal_control`: the transcription on CasADi symbols and
its independent check on arrays, through :func:`rk4_stages` and :func:`rk4_sensitivities`); the Python loop's matrix
and Nyström forms are fast paths of the same steps, rows of the same tableau (:data:`RK4_WEIGHTS`). Nothing else in
rmpc integrates ODEs by hand. It lives in ``rigid_body`` so that both ``controllers`` and ``planners`` can use it.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009 (the manual's fixed-step
simulations); Munthe-Kaas, BIT 38 (1998) (RK4 on a Lie group).
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

__all__ = ["RK4_WEIGHTS", "rk4_step_law", "rk4_stages", "rk4_sensitivities"]

RK4_WEIGHTS = np.array([1.0, 2.0, 2.0, 1.0]) / 6.0
"""The weights b_i of classical Runge–Kutta: x' = x + h Σ b_i k_i."""


def rk4_step_law(derivative: Callable[[Any, Any, Any], Any], t: Any, x: Any, u: Any, h: Any,
                 integrate: Callable[[Any, Any, Any], Any] | None = None,
                 dexp_inverse: Callable[[Any, Any, Any], Any] | None = None,
                 weighted_sum: Callable[[Any, Any, Any, Any], Any] | None = None) -> Any:
    """One classical Runge–Kutta step x' = x ⊕ (h/6)(k_1 + 2k_2 + 2k_3 + k_4) of ẋ = f(t, x, u), u held: the one
    RK4 of rmpc, written once for any scalar type (the Python loop's manifold stepper runs it on arrays, the
    compiled loop and the optimal-control transcription on CasADi symbols; :func:`controllers.simulation.rk4_stepper`'s
    matrix and Nyström forms are the Python loop's fast paths of the same steps, rows of the same tableau).

    ``integrate(x, k, c)`` is x ⊕ c k (default x + c k); ``dexp_inverse`` brings the stage derivatives back to
    the tangent space at x (Runge–Kutta–Munthe-Kaas); ``weighted_sum(k_1, …, k_4)`` is k_1 + 2k_2 + 2k_3 + k_4
    (default that expression)."""
    hh = 0.5 * h
    step = integrate if integrate is not None else (lambda x0, k, c: x0 + c * k)
    k1 = derivative(t, x, u)
    k2 = derivative(t + hh, step(x, k1, hh), u)
    if dexp_inverse is not None:
        k2 = dexp_inverse(x, hh * k1, k2)
    k3 = derivative(t + hh, step(x, k2, hh), u)
    if dexp_inverse is not None:
        k3 = dexp_inverse(x, hh * k2, k3)
    k4 = derivative(t + h, step(x, k3, h), u)
    if dexp_inverse is not None:
        k4 = dexp_inverse(x, h * k3, k4)
    total = weighted_sum(k1, k2, k3, k4) if weighted_sum is not None else k1 + 2.0 * k2 + 2.0 * k3 + k4
    return step(x, total, h / 6.0)


def rk4_stages(f: Callable[[Any, Any], Any], x: Any, u: Any, h: Any) -> tuple[Any, list]:
    """:func:`rk4_step_law` of the time-invariant ẋ = f(x, u): (x_next, [s_1 … s_4]) the result and the four stage
    states (where the stage costs of a multiple-shooting interval are evaluated, weights :data:`RK4_WEIGHTS`). The
    same arithmetic on numpy arrays and on CasADi expressions."""
    states: list = []

    def derivative(t: Any, s: Any, v: Any) -> Any:
        states.append(s)
        return f(s, v)

    return rk4_step_law(derivative, 0.0, x, u, h), states


def rk4_sensitivities(slope: Callable[[Any, Any], tuple[Any, Any, Any]], x: Any, u: Any, h: Any, E_x: Any,
                      E_u: Any) -> tuple[Any, Any, list, list]:
    """:func:`rk4_step_law` with its forward sensitivities (the chain rule through the stages), on the pair
    (s, ∂s/∂z): ``slope(s, u)`` gives (f, ∂f/∂s, ∂f/∂u) at a stage state, so the stage slope's Jacobian is
    ∂k/∂z = ∂f/∂s ∂s/∂z + ∂f/∂u E_u; E_x = ∂x/∂z = [I 0] and E_u = ∂u/∂z = [0 I] with z = [x; u]. Returns (x_next,
    ∂x_next/∂z, [s_1 … s_4], [∂s_1/∂z … ∂s_4/∂z]). The same arithmetic on numpy arrays (with Pinocchio's
    derivatives) and on CasADi expressions (with the symbolic ones)."""
    states: list = []
    state_jacobians: list = []

    def derivative(t: Any, pair: tuple[Any, Any], v: Any) -> tuple[Any, Any]:
        s, ds = pair
        states.append(s)
        state_jacobians.append(ds)
        k, k_s, k_u = slope(s, v)
        return k, k_s @ ds + k_u @ E_u

    def integrate(pair: tuple[Any, Any], k: tuple[Any, Any], c: Any) -> tuple[Any, Any]:
        return pair[0] + c * k[0], pair[1] + c * k[1]

    def weighted_sum(k1: tuple, k2: tuple, k3: tuple, k4: tuple) -> tuple[Any, Any]:
        return tuple(a + 2.0 * b + 2.0 * c + d for a, b, c, d in zip(k1, k2, k3, k4))

    x_next, dx_next = rk4_step_law(derivative, 0.0, (x, E_x), u, h, integrate, None, weighted_sum)
    return x_next, dx_next, states, state_jacobians
