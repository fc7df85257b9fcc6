"""Tuning PD + gravity gains by gradient descent through the compiled closed loop (Problem 8.10's arm).

The loop of Problem 8.10 — the two-link arm with motors, F_v = 100 N·m·s/rad, PD + gravity
compensation (8.51), RK4 at 1 ms, controller at 1 ms — is one CasADi function of the gains
(:class:`controllers.compiled.CompiledLoop`), so the cost

    J(k_P, k_D) = Σ_k (‖q̃_k‖² + ρ ‖u_k − g(q_d)‖²) T_s      (K_P = k_P I, K_D = k_D I)

(integrated squared error plus a penalty on the control effort beyond gravity compensation, without
which J falls forever as the gains grow) and its exact gradient come from automatic differentiation
of the whole rollout. The example minimises J with L-BFGS-B over (log k_P, log k_D) from the manual's
case-F gains K_P = 3750, K_D = 750.

Run: ``python -m examples.gain_tuning``.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np
from scipy.optimize import minimize

from controllers.compiled import CompiledLoop
from controllers.joint_space import PDGravityCompensation
from controllers.plants import ArmPlant
from problems.ch08_centralised import F_V    # 8.10's joint-side viscous friction, from the motor data
from rigid_body.codegen import compile_function
from rigid_body.dynamics import gravity_torques
from rigid_body.robots import load

Q_D = np.array([np.pi / 4, -np.pi / 2])       # 8.10's first posture
T_C = 1e-3                                    # controller period and RK4 step [s]


@dataclass(frozen=True)
class TunedGains:
    """Result: the gains before and after, their costs and the cost's gradient at the optimum."""

    k_P0: float
    k_D0: float
    k_P: float
    k_D: float
    cost0: float
    cost: float
    gradient: np.ndarray
    iterations: int


def cost_function(t_end: float = 1.0, rho: float = 1e-6, compile: bool = True) -> tuple[ca.Function, np.ndarray]:
    """``(J, x0)``: J(log k) → (cost, gradient) of the 8.10 loop from q(0) = q_d − 0.1, and x0."""
    arm = load("planar_2r")
    plant = ArmPlant(arm, viscous_friction=F_V)
    controller = PDGravityCompensation(arm, 3750.0, 750.0, Q_D)
    loop = CompiledLoop(plant, controller, T_C, 1, int(round(t_end / T_C)) + 1, compile=False)
    x0 = plant.initial_state(Q_D - 0.1)
    log_k = ca.MX.sym("log_k", 2)
    k = ca.exp(log_k)
    n = arm.nv
    p = ca.vertcat(ca.vec(k[0] * ca.DM.eye(n)), ca.vec(k[1] * ca.DM.eye(n)))
    X, U, *_ = loop.rollout(x0, loop.references(0.0), p)
    e = ca.DM(Q_D) - X[:n, :]
    effort = U - ca.DM(gravity_torques(arm, Q_D))
    J = T_C * (ca.sumsqr(e) + rho * ca.sumsqr(effort))
    function = ca.Function("gain_cost", [log_k], [J, ca.gradient(J, log_k)], ["log_k"], ["J", "grad"])
    return (compile_function(function) if compile else function), x0


def tune(t_end: float = 1.0, rho: float = 1e-6, k0: tuple[float, float] = (3750.0, 750.0)) -> TunedGains:
    """Minimise J over (k_P, k_D) by L-BFGS-B with the exact gradient of the compiled rollout."""
    J, _ = cost_function(t_end, rho)

    def fun(z: np.ndarray) -> tuple[float, np.ndarray]:
        value, grad = J(z)
        return float(value), np.asarray(grad).ravel()

    z0 = np.log(np.asarray(k0, dtype=float))
    res = minimize(fun, z0, jac=True, method="L-BFGS-B", bounds=[(np.log(10.0), np.log(1e5))] * 2,
                   options={"gtol": 1e-10, "ftol": 1e-14})
    k_P, k_D = np.exp(res.x)
    return TunedGains(float(k0[0]), float(k0[1]), float(k_P), float(k_D), fun(z0)[0], float(res.fun),
                      fun(res.x)[1], int(res.nit))


if __name__ == "__main__":
    tuned = tune()
    print(f"K_P: {tuned.k_P0:g} -> {tuned.k_P:.1f},  K_D: {tuned.k_D0:g} -> {tuned.k_D:.1f}  "
          f"({tuned.iterations} iterations)")
    print(f"cost: {tuned.cost0:.6g} -> {tuned.cost:.6g}; gradient at the optimum {tuned.gradient}")
