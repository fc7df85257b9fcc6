"""Chapter 4 — Trajectory planning: Problems 4.1–4.8.

Each problem builds its data (the manual's, confirmed by the authors' companion files s4_1 … s4_8),
calls ``planners.timing`` / ``planners.paths`` and checks the result against the manual: its
equations written out independently here, the numbers it prints, and the properties its figures
S4.1–S4.7 show (boundary conditions, continuity, peak values), with finite differences as a
second reference for every velocity and acceleration.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Chapter 4,
Eqs. (4.1)–(4.44), and its solution manual (Problems 4.1–4.8, (S4.1)–(S4.4), Figs. S4.1–S4.7).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.interpolate import BPoly, CubicSpline

from planners import paths, timing
from problems.common import label_axes, subplots
from problems.registry import Solution, problem

TS = 0.01  # sample time of the companion files' plots [s]


def _figure(tr: timing.Trajectory, title: str, columns: list[int] | None = None,
            labels: list[str] | None = None, unit: str = "rad", symbol: str = "q",
            points: tuple[Any, Any] | None = None):
    """Position, velocity, acceleration of the chosen columns of a trajectory, one axis each, in
    ``unit``, ``unit``/s, ``unit``/s²; ``points`` = (t_k, q_k) marks the path or via points."""
    fig, axes = subplots(3, 1, sharex=True, figsize=(6.4, 6.4))
    columns = list(range(tr.n)) if columns is None else columns
    names = (f"{symbol} [{unit}]", f"{symbol}̇ [{unit}/s]", f"{symbol}̈ [{unit}/s²]")
    for ax, y, name in zip(axes, (tr.q, tr.qd, tr.qdd), names):
        for j, col in enumerate(columns):
            ax.plot(tr.t, y[:, col], color=f"C{j}", label=None if labels is None else labels[j])
        if points is not None and ax is axes[0]:
            ax.plot(*points, "ko", ms=5, label="given points")
        label_axes(ax, "t [s]" if ax is axes[-1] else None, name,
                   legend=labels is not None or (points is not None and ax is axes[0]))
    axes[0].set_xlim(tr.t[0], tr.t[-1])
    fig.suptitle(title)
    return fig  # laid out by Solution.figure


def _derivative_errors(law, t: np.ndarray, h: float = 1e-6) -> tuple[float, float]:
    """max |q̇ − central difference of q| and the same for q̈ (skip points on a break)."""
    q1, v1, _ = law(t + h)
    q0, v0, _ = law(t - h)
    _, v, a = law(t)
    return float(np.max(np.abs((q1 - q0) / (2 * h) - v))), float(np.max(np.abs((v1 - v0) / (2 * h) - a)))


def _jumps(law, instants, order: int, eps: float = 1e-12) -> float:
    """Largest jump of the given derivative order across the instants."""
    return max(float(np.max(np.abs(np.asarray(law(t + eps)[order]) - np.asarray(law(t - eps)[order]))))
               for t in instants)


# --------------------------------------------------------------------------------------------
# 4.1–4.3: point-to-point laws and a sequence of quintics
# --------------------------------------------------------------------------------------------

@problem("4.1", "Quintic joint trajectory from q(0) = 1 to q(2) = 4", kind="numeric")
def problem_4_1() -> Solution:
    """Fifth-order polynomial q(t) = Σ a_j t^j from q(0) = 1 to q(2) = 4 with null boundary
    velocities and accelerations (Eq. (4.3); data of the companion file s4_1).

    The coefficients come from ``planners.timing.quintic_law`` and are substituted into the six
    equations the manual writes out. Peak velocity 15Δq/(8t_f) at t_f/2 and peak acceleration
    10Δq/(√3 t_f²) at t_f/2 (1 ∓ 1/√3) are the closed forms of the rest-to-rest quintic.
    """
    sol = Solution()
    q_i, q_f = sol.given("q_i", 1.0, unit="rad"), sol.given("q_f", 4.0, unit="rad")
    t_f = sol.given("t_f", 2.0, unit="s")
    law = timing.quintic_law(q_i, q_f, t_f)
    a = sol.value("coefficients", law.coefficients[0].tolist(), unit="a_j in rad/s^j")
    a0, a1, a2, a3, a4, a5 = a
    manual = [a0 - q_i, a1 - 0.0, 2 * a2 - 0.0,
              a5 * t_f**5 + a4 * t_f**4 + a3 * t_f**3 + a2 * t_f**2 + a1 * t_f + a0 - q_f,
              5 * a5 * t_f**4 + 4 * a4 * t_f**3 + 3 * a3 * t_f**2 + 2 * a2 * t_f + a1 - 0.0,
              20 * a5 * t_f**3 + 12 * a4 * t_f**2 + 6 * a3 * t_f + 2 * a2 - 0.0]
    sol.check_close("manual's six equations hold", manual, np.zeros(6), atol=1e-12, reference="closed form")
    dq = q_f - q_i
    tr = timing.sample(law, dt=TS, name="quintic")
    sol.check_close("peak velocity 15Δq/(8 t_f) = 2.8125 at t = 1", [tr.qd.max(), law(1.0)[1]],
                    [15 * dq / (8 * t_f)] * 2, atol=1e-12, reference="closed form")
    t_peak = t_f / 2 * (1 - 1 / np.sqrt(3))
    sol.check_close("peak acceleration 10Δq/(√3 t_f²) = 4.3301 at t = 0.4226",
                    [law(t_peak)[2], -law(t_f - t_peak)[2]], [10 * dq / (np.sqrt(3) * t_f**2)] * 2, atol=1e-12,
                        reference="closed form")
    sol.check("|q̈| never exceeds its peak on the 0.01 s grid", np.max(np.abs(tr.qdd)) <= law(t_peak)[2] + 1e-12)
    sol.check_close("q(1) = 2.5 (symmetry)", law(1.0)[0], 2.5, atol=1e-12, reference="closed form")
    ev, ea = _derivative_errors(law, np.linspace(0.01, 1.99, 50))
    sol.check("q̇, q̈ agree with finite differences of q", ev < 1e-7 and ea < 1e-6, f"{ev:.2g}, {ea:.2g}")
    sol.figure(_figure(tr, "Fig. S4.1 — fifth-order polynomial timing law"))
    return sol


@problem("4.2", "Timing law with velocity profile k(1 − cos(a t))", kind="numeric")
def problem_4_2() -> Solution:
    """Timing law from q(0) = 0 to q(2) = 3 with velocity q̇ = k(1 − cos(a t)) (companion s4_2).

    q̇_i = 0 holds for every a; q̇_f = k(1 − cos(a t_f)) = 0 gives a = 2π/t_f; integrating,
    q = k1 + k(t − t_f/(2π) sin(2πt/t_f)), and the boundary positions give k1 = q_i,
    k = (q_f − q_i)/t_f. The manual prints k = 1.5, k1 = 0.
    """
    sol = Solution()
    q_i, q_f = sol.given("q_i", 0.0, unit="rad"), sol.given("q_f", 3.0, unit="rad")
    t_f = sol.given("t_f", 2.0, unit="s")
    law = timing.raised_cosine_law(q_i, q_f, t_f)
    k, k1 = sol.value("k", float(law.k), unit="rad/s"), sol.value("k1", float(law.k1), unit="rad")
    sol.check_close("k = 1.5, k1 = 0 (manual)", [k, k1], [1.5, 0.0], atol=1e-12, reference="manual number")
    sol.check_close("a = 2π/t_f = π", law.a, np.pi, atol=1e-12, reference="closed form")
    t = np.linspace(0, t_f, 401)
    q, qd, qdd = law(t)
    sol.check_close("velocity profile is k(1 − cos(a t))", qd, k * (1 - np.cos(law.a * t)), atol=1e-12,
                    reference="closed form")
    sol.check_close("q(0) = 0, q(2) = 3, q̇(0) = q̇(2) = 0", [q[0], q[-1], qd[0], qd[-1]], [0, 3, 0, 0], atol=1e-12,
                    reference="closed form")
    sol.check_close("peaks: q̇ = 2k = 3 at t = 1, q̈ = k a = 4.7124 at t = 0.5",
                    [qd.max(), law(1.0)[1], qdd.max(), law(0.5)[2]], [2 * k, 2 * k, k * np.pi, k * np.pi], atol=1e-12,
                        reference="closed form")
    ev, ea = _derivative_errors(law, np.linspace(0.01, 1.99, 50))
    sol.check("q̇, q̈ agree with finite differences of q", ev < 1e-7 and ea < 1e-6, f"{ev:.2g}, {ea:.2g}")
    sol.figure(_figure(timing.sample(law, dt=TS), "Fig. S4.2 — raised cosine timing law"))
    return sol


@problem("4.3", "Two quintic polynomials through an intermediate point", kind="programming")
def problem_4_3() -> Solution:
    """q(0) = 0, q(2) = 2, q(4) = 3: two fifth-order polynomials with null boundary velocities and
    accelerations and continuous velocity and acceleration at t = 2 (companion s4_3).

    The intermediate velocity is the mean of the two mean velocities, q̇_m = (q̇_a + q̇_b)/2, and the
    intermediate acceleration the mean of (q̇_m − q̇_i)/(t_m − t_i) and (q̇_f − q̇_m)/(t_f − t_m)
    (the manual's rule; ``via_point_accelerations``). Companion-code slip: s4_3 uses (q̇_f − q_m)
    for the second difference, which would give q̈_m = −0.3125; the manual's formula gives 0.
    """
    sol = Solution()
    t = sol.given("t_k", np.array([0.0, 2.0, 4.0]), unit="s")
    q = sol.given("q_k", np.array([0.0, 2.0, 3.0]), unit="rad")
    qd = timing.via_point_velocities(t, q)
    qdd = timing.via_point_accelerations(t, qd)
    qd_a, qd_b = (q[1] - q[0]) / (t[1] - t[0]), (q[2] - q[1]) / (t[2] - t[1])
    qd_m = (qd_a + qd_b) / 2
    qdd_m = ((qd_m - 0) / (t[1] - t[0]) + (0 - qd_m) / (t[2] - t[1])) / 2
    sol.value("qd_m", float(qd[1]), unit="rad/s")
    sol.value("qdd_m", float(qdd[1]), unit="rad/s²")
    sol.check_close("q̇_m = (q̇_a + q̇_b)/2 = 0.75, q̈_m = 0 (manual's rule; not −0.3125 of the s4_3 slip)",
                    [qd[1], qdd[1]], [qd_m, qdd_m], atol=1e-12, reference="closed form")
    law = timing.polynomial_sequence_law(t, q, qd, qdd, degree=5)
    sol.value("coefficients_1", law.coefficients[0].tolist(), unit="a_j in rad/s^j")
    sol.value("coefficients_2", law.coefficients[1].tolist(), unit="a_j in rad/s^j")
    sol.check_close("segment coefficients [0, 0, 0, 1.75, −1.21875, 0.234375], [2, 0.75, 0, 0.125, −0.1875, 0.046875]",
                    law.coefficients, [[0, 0, 0, 1.75, -1.21875, 0.234375], [2, 0.75, 0, 0.125, -0.1875, 0.046875]],
                    atol=1e-12, reference="independent derivation")
    grid = np.linspace(t[0], t[-1], 201)
    hermite = BPoly.from_derivatives(t, np.column_stack([q, qd, qdd]), orders=5)   # quintic Hermite (scipy)
    sol.check_close("q(t) = SciPy's quintic Hermite interpolant of (q_k, q̇_k, q̈_k) on 201 instants", law(grid)[0],
                    hermite(grid), atol=1e-12, reference="other library")
    sol.check("velocity and acceleration continuous at t = 2", max(_jumps(law, [2.0], 1), _jumps(law, [2.0], 2)) < 1e-7)
    sol.check_close("null velocity and acceleration at t = 0 and 4",
                    [law(0.0)[1], law(0.0)[2], law(4.0)[1], law(4.0)[2]], np.zeros(4), atol=1e-12,
                        reference="closed form")
    sol.figure(_figure(timing.sample(law, dt=TS), "Fig. S4.3 — two fifth-order interpolating polynomials", points=(t, q)))
    return sol


# --------------------------------------------------------------------------------------------
# 4.4–4.5: cubic spline with two virtual points
# --------------------------------------------------------------------------------------------

def manual_spline_system(dt: np.ndarray, q: np.ndarray, qd_i: float, qd_f: float, qdd_i: float,
                         qdd_f: float) -> tuple[np.ndarray, np.ndarray]:
    """A and b of (4.28) exactly as the manual's solution of Problem 4.4 writes them (1-based).

    ``dt`` = (Δt_1, ..., Δt_{N+1}); ``q`` = the N given positions q_1, q_3, ..., q_N, q_{N+2}.
    Independent of ``planners.timing.spline_system``, which assembles (S4.2) with (S4.3), (S4.4).
    """
    N = len(dt) - 1
    D = {k + 1: dt[k] for k in range(N + 1)}
    Q = {1: q[0], N + 2: q[-1]}
    for j, k in enumerate(range(3, N + 1)):
        Q[k] = q[j + 1]
    A = np.zeros((N, N))
    A[0, 0] = D[1] / 2 + D[2] / 3 + D[1] ** 2 / (6 * D[2])
    for k in range(2, N):
        A[k - 1, k - 1] = (D[k] + D[k + 1]) / 3
    A[N - 1, N - 1] = D[N] / 3 + D[N + 1] / 2 + D[N + 1] ** 2 / (6 * D[N])
    A[1, 0] = D[2] / 6 - D[1] ** 2 / (6 * D[2])
    for k in range(3, N + 1):
        A[k - 1, k - 2] = D[k] / 6
    for k in range(1, N - 1):
        A[k - 1, k] = D[k + 1] / 6
    A[N - 2, N - 1] = D[N] / 6 - D[N + 1] ** 2 / (6 * D[N])
    qi, qf, vi, vf, ai, af = Q[1], Q[N + 2], qd_i, qd_f, qdd_i, qdd_f
    b = np.zeros(N)
    b[0] = (Q[3] - qi) / D[2] - (1 / D[2] + 1 / D[1]) * (vi * D[1] + ai * D[1] ** 2 / 3) - ai * D[1] / 6
    start = (qi + vi * D[1] + ai * D[1] ** 2 / 3) / D[2]
    if N == 3:
        b[1] = start - (1 / D[3] + 1 / D[2]) * Q[3] + (qf - vf * D[4] + af * D[4] ** 2 / 3) / D[3]
    else:
        b[1] = start - (1 / D[3] + 1 / D[2]) * Q[3] + Q[4] / D[3]
        for k in range(3, N - 1):
            b[k - 1] = Q[k] / D[k] - (1 / D[k + 1] + 1 / D[k]) * Q[k + 1] + Q[k + 2] / D[k + 1]
        b[N - 2] = (Q[N - 1] / D[N - 1] - (1 / D[N] + 1 / D[N - 1]) * Q[N]
                    + (qf - vf * D[N + 1] + af * D[N + 1] ** 2 / 3) / D[N])
    b[N - 1] = ((Q[N] - qf) / D[N] - (1 / D[N + 1] + 1 / D[N]) * (-vf * D[N + 1] + af * D[N + 1] ** 2 / 3)
                - af * D[N + 1] / 6)
    return A, b


def _spline_checks(sol: Solution, label: str, t, q, vi, vf, ai, af, t_virtual) -> timing.PiecewisePolynomial:
    system = timing.spline_system(t, q, vi, vf, ai, af, t_virtual=t_virtual)
    A_ref, b_ref = manual_spline_system(np.diff(system.knots), np.asarray(q, float), vi, vf, ai, af)
    sol.check_close(f"{label}: A and b equal the manual's formulas", np.concatenate([system.A.ravel(), system.b]),
                    np.concatenate([A_ref.ravel(), b_ref]), atol=1e-12, reference="closed form")
    sol.check(f"{label}: A is tridiagonal", np.allclose(np.triu(system.A, 2), 0) and np.allclose(np.tril(system.A, -2), 0))
    law = timing.cubic_spline_law(t, q, vi, vf, ai, af, t_virtual=t_virtual)
    # SciPy's clamped cubic spline through the given points and the two virtual points (their positions
    # from the law): equal everywhere only if the law interpolates the points and is C2 with these q̇.
    values = np.asarray(q, float)
    values = np.r_[values[0], law(float(system.knots[1]))[0], values[1:-1], law(float(system.knots[-2]))[0], values[-1]]
    scipy_spline = CubicSpline(system.knots, values, bc_type=((1, vi), (1, vf)))
    grid = np.linspace(system.knots[0], system.knots[-1], 201)
    sol.check_close(f"{label}: q(t) = SciPy's clamped cubic spline through the points (201 instants)", law(grid)[0],
                    scipy_spline(grid), atol=1e-10, reference="other library")
    inner = system.knots[1:-1]
    jumps = [_jumps(law, inner, k) for k in range(3)]
    sol.check(f"{label}: C2 at every knot (virtual points included)", max(jumps) < 1e-7, f"jumps {jumps}")
    (_, v0, a0), (_, v1, a1) = law(float(t[0])), law(float(t[-1]))
    sol.check_close(f"{label}: boundary velocities and accelerations", [v0, a0, v1, a1], [vi, ai, vf, af], atol=1e-10,
                    reference="property")
    return law


@problem("4.4", "Tridiagonal band structure of A in (4.28) (cubic spline with virtual points)", kind="derivation")
def problem_4_4() -> Solution:
    """Show that with two virtual points the N unknown accelerations of the cubic spline solve a
    tridiagonal system A x = b (4.28) and give its entries (manual: (S4.1)–(S4.4)).

    The manual's a_ij and b_i (including the special b_2 for N = 3) are written out in
    ``manual_spline_system`` and compared with the library's assembly for N = 3, 4, 5, 7, 12 with
    random intervals, positions, virtual-point instants and non-zero boundary velocities and
    accelerations; the spline built from the solution must interpolate, be C² and meet the four
    boundary conditions. The manual's "I" is Π (the text file's rendering), and the left-hand side
    of (S4.1) is the velocity Π̇_k.
    """
    sol = Solution()
    rng = np.random.default_rng(44)
    for N in (3, 4, 5, 7, 12):
        t = np.cumsum(np.concatenate([[0.0], rng.uniform(0.5, 2.0, N - 1)]))
        q = rng.normal(size=N)
        vi, vf, ai, af = rng.normal(size=4)
        tv = (t[0] + rng.uniform(0.2, 0.8) * (t[1] - t[0]), t[-2] + rng.uniform(0.2, 0.8) * (t[-1] - t[-2]))
        _spline_checks(sol, f"N = {N}", t, q, vi, vf, ai, af, tv)
    return sol


@problem("4.5", "Cubic spline with virtual points at t = 1 and t = 3", kind="numeric")
def problem_4_5() -> Solution:
    """Cubic spline through q(0) = 0, q(2) = 2, q(4) = 3 with null boundary velocities and
    accelerations, virtual points at t = 1 and t = 3 (manual; companion s4_5), so Δt_k = 1, N = 3.

    A and b of (4.28) are computed (the manual withholds them) and compared with the formulas of
    Problem 4.4.
    """
    sol = Solution()
    t, q = sol.given("t_k", [0.0, 2.0, 4.0], unit="s"), sol.given("q_k", [0.0, 2.0, 3.0], unit="rad")
    sol.given("virtual points t", np.array([1.0, 3.0]), unit="s")
    system = timing.spline_system(t, q, t_virtual=(1.0, 3.0))
    sol.value("A", system.A.tolist(), unit="s")
    sol.value("b", system.b.tolist(), unit="rad/s")
    law = _spline_checks(sol, "data of 4.5", t, q, 0.0, 0.0, 0.0, 0.0, (1.0, 3.0))
    sol.value("accelerations", law(np.array([1.0, 2.0, 3.0]))[2].tolist(), unit="rad/s²")
    sol.value("virtual_points", law(np.array([1.0, 3.0]))[0].tolist(), unit="rad")
    sol.value("knot_velocities", law(np.array([1.0, 2.0, 3.0]))[1].tolist(), unit="rad/s")
    sol.figure(_figure(timing.sample(law, dt=TS), "Fig. S4.4 — cubic spline timing law", points=(t, q)))
    return sol


# --------------------------------------------------------------------------------------------
# 4.6: linear segments with parabolic blends
# --------------------------------------------------------------------------------------------

@problem("4.6", "Linear segments with parabolic blends", kind="numeric")
def problem_4_6() -> Solution:
    """Through q(0) = 0, q(2) = 2, q(4) = 3 with null initial and final velocities: linear segments
    joined by parabolic blends of duration Δt'_k = 0.2 (manual; companion s4_6, ``lin_par``).

    As the companion code, the blends are centred on the knots, so the trajectory runs on
    [−0.1, 4.1] and passes near, not through, q(0), q(2), q(4). The coefficients a_k0, a_k1, b_k0,
    b_k1, b_k2 (withheld by the manual) are computed; the checks show the continuity the manual
    claims at both ends of every blend.
    """
    sol = Solution()
    t = sol.given("t_k", np.array([0.0, 2.0, 4.0]), unit="s")
    q = sol.given("q_k", np.array([0.0, 2.0, 3.0]), unit="rad")
    blend = sol.given("Δt'", 0.2, unit="s")
    c = timing.blend_coefficients(t, q, blend)
    for k in range(2):
        sol.value(f"a{k + 1}0", float(c.a[k, 0]), unit="rad")
        sol.value(f"a{k + 1}1", float(c.a[k, 1]), unit="rad/s")
    for k in range(3):
        for j in range(3):
            sol.value(f"b{k + 1}{j}", float(c.b[k, j]), unit=("rad", "rad/s", "rad/s²")[j])
    # the manual's formulas, written out
    v = np.array([0.0, (q[1] - q[0]) / 2, (q[2] - q[1]) / 2, 0.0])  # q̇_{k−1,k}, k = 1..4
    b_ref = [[q[k] + (v[k + 1] - v[k]) * blend / 8, (v[k + 1] + v[k]) / 2, (v[k + 1] - v[k]) / (2 * blend)]
             for k in range(3)]
    sol.check_close("a_k0 = q_k, a_k1 = q̇_{k,k+1}", c.a, [[q[0], v[1]], [q[1], v[2]]], atol=1e-12,
                    reference="closed form")
    sol.check_close("b_k0, b_k1, b_k2 as the manual's formulas", c.b, b_ref, atol=1e-12, reference="closed form")
    law = timing.linear_parabolic_blends_law(t, q, blend)
    edges = [-0.1, 0.1, 1.9, 2.1, 3.9, 4.1]
    sol.check_close("trajectory on [−0.1, 4.1] (blends centred on the knots)", [law.t_i, law.t_f], [-0.1, 4.1], atol=1e-12,
                    reference="closed form")
    sol.check("position and velocity continuous at every t_k ± Δt'/2",
              max(_jumps(law, edges[1:-1], 0), _jumps(law, edges[1:-1], 1)) < 1e-7)
    sol.check_close("constant velocity 1 on [0.1, 1.9] and 0.5 on [2.1, 3.9]",
                    [law(np.linspace(0.1, 1.9, 9))[1], law(np.linspace(2.1, 3.9, 9))[1]], [np.ones(9), 0.5 * np.ones(9)],
                    atol=1e-12, reference="closed form")
    sol.check_close("blend accelerations 2 b_k2 = (q̇_{k,k+1} − q̇_{k−1,k})/Δt'_k = 5, −2.5, −2.5",
                    law(np.array([0.0, 2.0, 4.0]))[2], [(v[k + 1] - v[k]) / blend for k in range(3)], atol=1e-12,
                        reference="closed form")
    sol.check("the tabulated 'accelerations 2.5, −1.25, −1.25' are the coefficients b_k2 = q̈/2",
              np.allclose(c.b[:, 2], [2.5, -1.25, -1.25]) and np.allclose(law(np.array([0.0, 2.0, 4.0]))[2], 2 * c.b[:, 2]))
    sol.check_close("q(−0.1) = 0, q(4.1) = 3, null end velocities",
                    [law(-0.1)[0], law(4.1)[0], law(-0.1)[1], law(4.1)[1]], [0, 3, 0, 0], atol=1e-12,
                        reference="closed form")
    tr = timing.sample(law, times=np.append(np.arange(-0.1, 4.1 - 1e-9, TS), 4.1))  # lin_par's grid, closed at t_f
    sol.figure(_figure(tr, "Fig. S4.5 — linear polynomials with parabolic blends", points=(t, q)))
    return sol


# --------------------------------------------------------------------------------------------
# 4.7–4.8: operational-space paths with a trapezoidal timing law
# --------------------------------------------------------------------------------------------

def _trapezoid_checks(sol: Solution, law, s_f: float, t_f: float, sd_c: float) -> None:
    """(4.8) for the path coordinate: feasibility, t_c and s̈_c from the closed forms."""
    t_c = (0.0 - s_f + sd_c * t_f) / sd_c
    sdd_c = sd_c**2 / (0.0 - s_f + sd_c * t_f)
    sol.value("t_c", float(law.breaks[1]), unit="s")
    sol.value("sdd_c", float(law(0.5 * t_c)[2]), unit="m/s²")
    sol.check_close("t_c = (s_i − s_f + ṡ_c t_f)/ṡ_c and s̈_c = ṡ_c²/(s_i − s_f + ṡ_c t_f), Eq. (4.8)",
                    [law.breaks[1], law(0.5 * t_c)[2], law(t_f / 2)[1]], [t_c, sdd_c, sd_c], atol=1e-12,
                        reference="closed form")


@problem("4.7", "Straight-line path with a trapezoidal velocity profile", kind="programming")
def problem_4_7() -> Solution:
    """Timing law p(t) along the segment from p_i = [0, 0.5, 0] to p_f = [1, −0.5, 0] in t_f = 2 s,
    the arc length s following a trapezoidal velocity profile (4.8) with ṡ_c = 1; p(t) and its
    derivatives by (4.34) and ṗ = ṡ t̂, p̈ = s̈ t̂. The end points and t_f are those of the companion
    file s4_7 (the manual does not print them).
    """
    sol = Solution()
    p_i = sol.given("p_i", np.array([0.0, 0.5, 0.0]), unit="m")
    p_f = sol.given("p_f", np.array([1.0, -0.5, 0.0]), unit="m")
    t_f, sd_c = sol.given("t_f", 2.0, unit="s"), sol.given("ṡ_c", 1.0, unit="m/s")
    seg = paths.Segment(p_i, p_f)
    s_f = sol.value("s_f", seg.length, unit="m")
    sol.check_close("s_f = ‖p_f − p_i‖ = √2", s_f, np.sqrt(2), atol=1e-12, reference="closed form")
    s_law = timing.trapezoidal_law(0.0, s_f, t_f, sd_c)
    _trapezoid_checks(sol, s_law, s_f, t_f, sd_c)
    law = paths.PathLaw(seg, s_law)
    t = np.linspace(0, t_f, 801)
    p, pd, pdd = law(t)
    s, sd, sdd = s_law(t)
    sol.check_close("p(0) = p_i, p(t_f) = p_f, ṗ = 0 at both ends", [p[0], p[-1], pd[0], pd[-1]],
                    [p_i, p_f, np.zeros(3), np.zeros(3)], atol=1e-12, reference="closed form")
    sol.check_close("‖ṗ‖ = ṡ, direction constant (ṗ = ṡ t̂, p̈ = s̈ t̂)", np.concatenate([pd, pdd]),
                    np.concatenate([np.outer(sd, seg.tangent), np.outer(sdd, seg.tangent)]), atol=1e-12,
                        reference="closed form")
    sol.check_close("z constant", p[:, 2], np.zeros(t.size), atol=1e-12, reference="closed form")
    cruise = (t > s_law.breaks[1] + 1e-9) & (t < t_f - s_law.breaks[1] - 1e-9)
    sol.check_close("|ẋ| = |ẏ| = ṡ_c/√2 = 0.7071 while cruising", np.abs(pd[cruise, :2]),
                    np.full((cruise.sum(), 2), sd_c / np.sqrt(2)), atol=1e-12, reference="closed form")
    h = 1e-6
    away = np.min(np.abs(t[:, None] - s_law.breaks[None, :]), axis=1) > 1e-4  # not on a phase change
    fd_v = (law(t[away] + h)[0] - law(t[away] - h)[0]) / (2 * h)
    fd_a = (law(t[away] + h)[1] - law(t[away] - h)[1]) / (2 * h)
    err_v, err_a = np.max(np.abs(fd_v - pd[away])), np.max(np.abs(fd_a - pdd[away]))
    sol.check("ṗ and p̈ agree with finite differences", err_v < 1e-6 and err_a < 1e-5, f"{err_v:.2g}, {err_a:.2g}")
    tr = timing.sample(law, dt=TS, name="segment")
    sol.figure(_figure(tr, "Fig. S4.6 — straight path, trapezoidal velocity profile", columns=[0, 1], labels=["x", "y"],
                       unit="m", symbol="p"))
    return sol


@problem("4.8", "Half-circle path with a trapezoidal velocity profile", kind="programming")
def problem_4_8() -> Solution:
    """Timing law p(t) along half a circle from p_i = [0, 0.5, 1] to p_f = [0, −0.5, 1], centre
    c = [0, 0, 1], radius ρ = 0.5, clockwise about x, in t_f = 2 s, with a trapezoidal profile (4.8)
    for the arc length s, ṡ_c = 1 (manual; centre and radius from the companion file s4_8).

    The manual's circle frame x' = y, y' = −z, z' = −x is what ``circle_through`` builds from the
    axis −x through c and the point p_i; then p(s) = [0, 0.5 cos 2s, 1 − 0.5 sin 2s] by (4.39),
    s_f = ρπ = π/2, and ṗ, p̈ by (4.44) with ṡ, s̈.
    """
    sol = Solution()
    p_i, c = sol.given("p_i", np.array([0.0, 0.5, 1.0]), unit="m"), sol.given("c", np.array([0.0, 0.0, 1.0]), unit="m")
    rho, t_f, sd_c = sol.given("ρ", 0.5, unit="m"), sol.given("t_f", 2.0, unit="s"), sol.given("ṡ_c", 1.0, unit="m/s")
    s_f = rho * np.pi
    circle = paths.circle_through(p_i, [-1.0, 0.0, 0.0], c, length=s_f)
    sol.value("R", circle.R.tolist(), unit="1")
    sol.check_close("circle frame R = [x' y' z'] with x' = y, y' = −z, z' = −x", circle.R,
                    [[0, 0, -1], [1, 0, 0], [0, -1, 0]], atol=1e-12, reference="closed form")
    sol.check_close("centre and radius", np.concatenate([circle.center, [circle.radius]]), [0, 0, 1, 0.5], atol=1e-12,
                    reference="closed form")
    s = np.linspace(0, s_f, 50)
    sol.check_close("p(s) = [0, 0.5 cos 2s, 1 − 0.5 sin 2s] (manual)", circle(s)[0],
                    np.column_stack([0 * s, 0.5 * np.cos(2 * s), 1 - 0.5 * np.sin(2 * s)]), atol=1e-12,
                        reference="closed form")
    s_law = timing.trapezoidal_law(0.0, s_f, t_f, sd_c)
    _trapezoid_checks(sol, s_law, s_f, t_f, sd_c)
    sol.check_close("t_c = 2 − π/2", s_law.breaks[1], 2 - np.pi / 2, atol=1e-12, reference="closed form")
    law = paths.PathLaw(circle, s_law)
    t = np.linspace(0, t_f, 801)
    p, pd, pdd = law(t)
    _, sd, sdd = s_law(t)
    sol.check_close("‖p − c‖ = 0.5 and x = 0 for all t", np.column_stack([np.linalg.norm(p - c, axis=1), p[:, 0]]),
                    np.column_stack([np.full(t.size, 0.5), np.zeros(t.size)]), atol=1e-12, reference="closed form")
    sol.check_close("p(0) = p_i, p(1) = [0, 0, 0.5], p(2) = p_f", [law(0.0)[0], law(1.0)[0], law(2.0)[0]],
                    [p_i, [0, 0, 0.5], [0, -0.5, 1]], atol=1e-12, reference="closed form")
    sol.check_close("‖ṗ‖ = ṡ, ṗ = 0 at both ends", np.concatenate([np.linalg.norm(pd, axis=1), pd[0], pd[-1]]),
                    np.concatenate([sd, np.zeros(6)]), atol=1e-12, reference="closed form")
    sol.check("clockwise about x: (p − c) × ṗ points along −x while moving",
              np.all(np.cross(p - c, pd)[sd > 1e-9, 0] < 0) and np.allclose(np.cross(p - c, pd)[:, 1:], 0, atol=1e-12))
    cruise = (t > s_law.breaks[1] + 1e-9) & (t < t_f - s_law.breaks[1] - 1e-9)
    sol.check_close("centripetal acceleration ṡ_c²/ρ = 2 while cruising", np.linalg.norm(pdd[cruise], axis=1),
                    np.full(cruise.sum(), sd_c**2 / rho), atol=1e-12, reference="closed form")
    manual_pdd = np.column_stack([0 * t, -sdd * np.sin(2 * law.timing(t)[0]) - 2 * sd**2 * np.cos(2 * law.timing(t)[0]),
                                  -sdd * np.cos(2 * law.timing(t)[0]) + 2 * sd**2 * np.sin(2 * law.timing(t)[0])])
    sol.check_close("p̈ = [0, −s̈ sin 2s − 2ṡ² cos 2s, −s̈ cos 2s + 2ṡ² sin 2s]", pdd, manual_pdd, atol=1e-12,
                    reference="closed form")
    h = 1e-6
    fd_v = (law(t + h)[0] - law(t - h)[0]) / (2 * h)
    sol.check("ṗ agrees with finite differences of p", np.max(np.abs(fd_v - pd)) < 1e-6)
    tr = timing.sample(law, dt=TS, name="circle")
    sol.figure(_figure(tr, "Fig. S4.7 — circular path, trapezoidal velocity profile", columns=[1, 2], labels=["y", "z"],
                       unit="m", symbol="p"))
    return sol
