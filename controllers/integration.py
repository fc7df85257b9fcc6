"""The one Runge–Kutta step of rmpc: classical RK4 with the input held, for any scalar type.

:func:`rk4_step_law` is written once and run by the Python loop (:func:`controllers.simulation.rk4_stepper`'s
manifold stepper, on arrays) and by the compiled loop (:class:`controllers.compiled.CompiledLoop`, on CasADi
symbols); the Python loop's matrix and Nyström forms are fast paths of the same steps, rows of the same
tableau (:data:`RK4_WEIGHTS`). Nothing else in rmpc integrates ODEs by hand.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009 (the manual's fixed-step
simulations); Munthe-Kaas, BIT 38 (1998) (RK4 on a Lie group).
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

RK4_WEIGHTS = np.array([1.0, 2.0, 2.0, 1.0]) / 6.0
"""The weights b_i of classical Runge–Kutta: x' = x + h Σ b_i k_i."""


def rk4_step_law(derivative: Callable[[Any, Any, Any], Any], t: Any, x: Any, u: Any, h: float,
                 integrate: Callable[[Any, Any, float], Any] | None = None,
                 dexp_inverse: Callable[[Any, Any, Any], Any] | None = None,
                 weighted_sum: Callable[[Any, Any, Any, Any], Any] | None = None) -> Any:
    """One classical Runge–Kutta step x' = x ⊕ (h/6)(k_1 + 2k_2 + 2k_3 + k_4) of ẋ = f(t, x, u), u held: the one
    RK4 of rmpc, written once for any scalar type (the Python loop's manifold stepper runs it on arrays, the
    compiled loop on CasADi symbols; :func:`rk4_stepper`'s matrix and Nyström forms are the Python loop's fast
    paths of the same steps, rows of the same tableau).

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
