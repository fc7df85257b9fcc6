"""Benchmark: evaluating the timing laws of Chapter 4, and minimum-time solves (planar_2r, UR5).

Per-call wall times (best of several repetitions, time.perf_counter), each also given as a ratio to a
raw Pinocchio call measured in the same run: ``pin.rnea`` on the robot concerned (one inverse
dynamics evaluation). Run: ``python benchmarks/bench_trajectories.py``.
"""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin

from planners import paths, timing
from planners.time_optimal import time_optimal_path
from planners.optimization import JointLimits, OptimizationOptions, minimum_time_trajectory, trapezoidal_under_limits
from rigid_body.robots import load

from benchtools import per_call

SAMPLES = 1000


def rnea_time(robot) -> float:
    rng = np.random.default_rng(0)
    q, v, a = robot.random_configuration(rng), rng.normal(size=robot.nv), rng.normal(size=robot.nv)
    return per_call(lambda: pin.rnea(robot.model, robot.data, q, v, a), 20000)


def main() -> None:
    arm, ur5 = load("planar_2r"), load("ur5")
    t_rnea_arm, t_rnea_ur5 = rnea_time(arm), rnea_time(ur5)
    print(f"reference: pin.rnea planar_2r {t_rnea_arm * 1e6:.2f} µs, UR5 {t_rnea_ur5 * 1e6:.2f} µs per call\n")

    q_i, q_f = np.array([0.0, np.pi / 4]), np.array([np.pi / 2, np.pi / 2])
    t6_i, t6_f = np.zeros(6), np.linspace(0.5, 1.5, 6)
    via_t, via_q = np.array([0.0, 2.0, 4.0]), np.array([0.0, 2.0, 3.0])
    seg = paths.Segment([0, 0.5, 0], [1, -0.5, 0])
    circle = paths.circle_through([0, 0.5, 1], [-1, 0, 0], [0, 0, 1], length=np.pi / 2)
    laws = {
        "cubic (2 joints)": timing.cubic_law(q_i, q_f, 1.0),
        "quintic (2 joints)": timing.quintic_law(q_i, q_f, 1.0),
        "quintic (6 joints)": timing.quintic_law(t6_i, t6_f, 1.0),
        "raised cosine (2 joints)": timing.raised_cosine_law(q_i, q_f, 1.0),
        "trapezoidal tra_4 (2 joints)": timing.trapezoidal_law(q_i, q_f, 1.0, [3 * np.pi / 4, np.pi / 3]),
        "two quintics via point (4.3)": timing.polynomial_sequence_law(via_t, via_q),
        "cubic spline, virtual points (4.5)": timing.cubic_spline_law(via_t, via_q, t_virtual=(1, 3)),
        "parabolic blends (4.6)": timing.linear_parabolic_blends_law(via_t, via_q, 0.2),
        "segment + trapezoid (4.7)": paths.PathLaw(seg, timing.trapezoidal_law(0.0, seg.length, 2.0, 1.0)),
        "circle + trapezoid (4.8)": paths.PathLaw(circle, timing.trapezoidal_law(0.0, np.pi / 2, 2.0, 1.0)),
    }
    print(f"{'law':38s} {SAMPLES}-sample eval   ratio to rnea(2R)   one-instant evaluate   ratio")
    for name, law in laws.items():
        t = np.linspace(law.t_i, law.t_f, SAMPLES)
        t_vec = per_call(lambda: law(t), 200)
        t_one = per_call(lambda: law(0.37 * law.t_f), 5000)
        print(f"{name:38s} {t_vec * 1e6:10.1f} µs {t_vec / t_rnea_arm:14.1f} x {t_one * 1e6:16.2f} µs {t_one / t_rnea_arm:9.1f} x")
    big = np.cumsum(np.random.default_rng(1).uniform(0.5, 1.0, 10000))
    t_spline = per_call(lambda: timing.cubic_spline_law(big, np.sin(big)), 3)
    print(f"\ncubic spline through 10 000 points (banded O(N) solve): {t_spline * 1e3:.2f} ms "
          f"({t_spline / t_rnea_arm:.0f} x rnea(2R))")

    print("\nminimum-time solves (build + IPOPT + fine-grid verification, one run each)")
    limits = JointLimits.from_robot(arm, qdd_max=[20.0, 20.0], qd_max=[3.0, 3.0], tau_max=[3000.0, 1500.0])
    start = time.perf_counter()
    res = minimum_time_trajectory(arm, q_i, q_f, limits, OptimizationOptions(nodes=30))
    wall = time.perf_counter() - start
    trap, _ = trapezoidal_under_limits(arm, q_i, q_f, limits)
    print(f"planar_2r, 30 intervals: {wall:.2f} s ({wall / t_rnea_arm:.3g} x rnea), T* = {res.t_f:.4f} s vs "
          f"trapezoid {trap.duration:.4f} s, {res.iterations} iterations, success {res.success}")
    limits5 = JointLimits.from_robot(ur5, qdd_max=np.full(6, 8.0), tau_max=[60, 60, 40, 10, 10, 10])
    q5_i = np.array([0.0, -1.2, 1.0, -1.2, -1.5, 0.0])
    q5_f = np.array([1.5, -0.6, 1.8, -2.0, -1.0, 1.0])
    start = time.perf_counter()
    res5 = minimum_time_trajectory(ur5, q5_i, q5_f, limits5, OptimizationOptions(nodes=20))
    wall5 = time.perf_counter() - start
    trap5, _ = trapezoidal_under_limits(ur5, q5_i, q5_f, limits5)
    print(f"UR5, 20 intervals:       {wall5:.2f} s ({wall5 / t_rnea_ur5:.3g} x rnea), T* = {res5.t_f:.4f} s vs "
          f"trapezoid {trap5.duration:.4f} s, {res5.iterations} iterations, success {res5.success}")


def rows(repeats: int = 3) -> list[dict]:
    """UR5 minimum time (20 intervals): the first solve (builds the NLP), the best of ``repeats`` repeated
    solves (cached NLP; best-of-N against the load of a shared machine, the CPU time beside it), and
    the optimum against the exact-Hessian solve (the default L-BFGS must not move it)."""
    ur5 = load("ur5")
    limits5 = JointLimits.from_robot(ur5, qdd_max=np.full(6, 8.0), tau_max=[60, 60, 40, 10, 10, 10])
    q5_i = np.array([0.0, -1.2, 1.0, -1.2, -1.5, 0.0])
    q5_f = np.array([1.5, -0.6, 1.8, -2.0, -1.0, 1.0])
    walls, cpus, results = [], [], []
    for _ in range(1 + repeats):
        start, cpu = time.perf_counter(), time.process_time()
        results.append(minimum_time_trajectory(ur5, q5_i, q5_f, limits5, OptimizationOptions(nodes=20)))
        walls.append(time.perf_counter() - start)
        cpus.append(time.process_time() - cpu)
    same = all(abs(r.t_f - results[0].t_f) <= 1e-9 * results[0].t_f for r in results[1:])
    best = int(np.argmin(walls[1:])) + 1
    exact = minimum_time_trajectory(ur5, q5_i, q5_f, limits5, OptimizationOptions(nodes=20, hessian="exact"))
    fixed = time_optimal_path(ur5, np.linspace(q5_i, q5_f, 5), limits5)
    t_f = results[best].t_f
    return [dict(measurement="UR5 fixed straight path, TOPP-RA t_f [s]", rmpc=fixed.t_f, reference=t_f,
                 ref_name="free-path minimum time t_f", target=("ratio>=", 1.0 - 1e-3)),
            dict(measurement=f"UR5 fixed path TOPP-RA solve [s] ({fixed.backoffs} back-offs, "
                             f"max limit ratio {max(fixed.ratios.values()):.4f})", rmpc=fixed.solve_time,
                 reference=None, target=None),
            dict(measurement=f"UR5 minimum time t_f [s], L-BFGS ({results[best].iterations} it.) vs exact Hessian",
                 rmpc=t_f, reference=exact.t_f, ref_name=f"exact Hessian ({exact.iterations} iterations)",
                 target=("ratio<=", 1.0 + 1e-6)),
            dict(measurement=f"UR5 minimum time, repeated solve [s] (best of {repeats}, CPU {cpus[best]:.3f} s, "
                             f"same t_f: {same})",
                 rmpc=walls[best], reference=walls[0], ref_name="first solve (NLP build)", target=("<=", 0.5))]


if __name__ == "__main__":
    main()
