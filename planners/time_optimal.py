"""Time-optimal timing of a fixed joint-space path (TOPP-RA) under velocity, acceleration and torque limits.

The path q(s), s ∈ [0, 1], is the cubic spline through the waypoints (a chapter-4 path, a planner's
output). Along it q̇ = q'(s) ṡ, q̈ = q'(s) s̈ + q''(s) ṡ² and the torque τ = B q̈ + C q̇ + g is affine in
(s̈, ṡ²), so every limit is a linear constraint on (s̈, ṡ²) at each grid point: TOPP-RA (Pham & Pham
2018, the ``toppra`` package) finds the fastest ṡ(s) by reachability analysis. rmpc's dynamics
(:func:`rigid_body.dynamics.inverse_dynamics`) give the torque constraint.

Output: **constant path acceleration** between grid points (ṡ² linear in s, the exact solution of
TOPP-RA's discretisation), not the package's spline of ṡ, which exceeded the torque limits by up to
11 % between grid points (measured). The limits are then re-checked on a fine time grid; when one
is exceeded, the limits given to TOPP-RA are tightened by the excess and the problem re-solved.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sect. 4.1
(trajectory timing) and 7.1; Pham, Pham, "A new approach to time-optimal path parameterization
based on reachability analysis", IEEE T-RO 34 (2018).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from planners.optimization import JointLimits
from rigid_body.dynamics import inverse_dynamics
from rigid_body.robots import Robot


@dataclass(frozen=True)
class TimeOptimalPath:
    """t (M,), q, qd, qdd (M, n) on the fine check grid; t_f [s]; ``ratios`` the largest |value|/limit
    of velocity, acceleration and torque on that grid; ``solve_time`` [s]; ``backoffs`` re-solves."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray
    t_f: float
    ratios: dict
    solve_time: float
    backoffs: int


def time_optimal_path(robot: Robot, waypoints: np.ndarray, limits: JointLimits, gridpoints: int = 200,
                      subsamples: int = 10, max_backoff: int = 4) -> TimeOptimalPath:
    """The time-optimal rest-to-rest timing of the spline through ``waypoints`` (K, n) within ``limits``."""
    import toppra
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    start = time.perf_counter()
    n = robot.nv
    W = np.asarray(waypoints, dtype=float)
    if W.ndim != 2 or W.shape[1] != n or W.shape[0] < 2 or not np.all(np.isfinite(W)):
        raise ValueError(f"`waypoints` must be a finite (K >= 2, {n}) array, got shape {W.shape}")
    if limits.n != n:
        raise ValueError(f"`limits` are for {limits.n} joints, the robot has {n}")
    path = toppra.SplineInterpolator(np.linspace(0.0, 1.0, W.shape[0]), W)
    s = np.linspace(0.0, 1.0, gridpoints + 1)
    scale = {"qd": 1.0, "qdd": 1.0, "tau": 1.0}

    def inv_dyn(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
        return inverse_dynamics(robot, q, qd, qdd)

    for backoff in range(max_backoff + 1):
        v, a, u = limits.qd_max * scale["qd"], limits.qdd_max * scale["qdd"], limits.tau_max * scale["tau"]
        constraints = [constraint.JointVelocityConstraint(np.c_[-v, v]),
                       constraint.JointAccelerationConstraint(np.c_[-a, a]),
                       constraint.JointTorqueConstraint(inv_dyn, np.c_[-u, u], np.zeros(n))]
        instance = algo.TOPPRA(constraints, path, gridpoints=s, parametrizer="ParametrizeConstAccel")
        _, sd, _ = instance.compute_parameterization(0.0, 0.0)
        if sd is None:
            raise ValueError("no timing of the path satisfies the limits (TOPP-RA found it infeasible)")
        sd = np.maximum(np.asarray(sd, dtype=float), 0.0)
        ds = np.diff(s)
        sdd = (sd[1:] ** 2 - sd[:-1] ** 2) / (2 * ds)               # constant on each interval
        dt = 2 * ds / np.maximum(sd[1:] + sd[:-1], 1e-12)
        tau_in = np.linspace(0.0, 1.0, subsamples, endpoint=False)[None, :] * dt[:, None]
        S = s[:-1, None] + sd[:-1, None] * tau_in + 0.5 * sdd[:, None] * tau_in**2
        SD = sd[:-1, None] + sdd[:, None] * tau_in
        t = np.concatenate([[0.0], np.cumsum(dt)])
        T = np.append((t[:-1, None] + tau_in).ravel(), t[-1])
        S, SD = np.append(S.ravel(), 1.0), np.append(SD.ravel(), 0.0)
        SDD = np.append(np.repeat(sdd, subsamples), sdd[-1])
        q, dq, ddq = path(S), path(S, 1), path(S, 2)
        qd = dq * SD[:, None]
        qdd = dq * SDD[:, None] + ddq * (SD**2)[:, None]
        tau = np.array([inverse_dynamics(robot, *z) for z in zip(q, qd, qdd)])
        ratios = {"qd": float(np.max(np.abs(qd) / limits.qd_max)), "qdd": float(np.max(np.abs(qdd) / limits.qdd_max)),
                  "tau": float(np.max(np.abs(tau) / limits.tau_max))}
        if all(r <= 1.0 + 1e-6 for r in ratios.values()):
            break
        for k, r in ratios.items():
            if r > 1.0 + 1e-6:
                scale[k] *= (1.0 - 1e-4) / r
    return TimeOptimalPath(T, q, qd, qdd, tau, float(t[-1]), ratios, time.perf_counter() - start, backoff)
