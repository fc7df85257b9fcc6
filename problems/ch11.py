"""Chapter 11 — Mobile robots: Problems 11.1–11.18.

Models and their derivations (11.1–11.9) are checked numerically at random configurations (A(q) G(q) = 0,
Lie brackets by finite differences against sympy, the centre of rotation built as the intersection of the
wheel axes); the planners (11.10–11.13) against the manual's closed forms and against the chained form or the
unicycle integrated by :func:`controllers.simulation.simulate`; the controllers (11.14–11.18) in closed loop.

Data: test values chosen here where the manual leaves symbols (r = 0.1 m, d = 0.5 m, ω_RL = 10 rad/s;
ℓ = 1 m, b = 0.5 m; N = 3 trailers); the authors' companion files for 11.13 (q_i = 0, q_f = (2, 1, π/2),
k = 1), 11.16 (start (−1, −2, −π/2), k1 = 1, k2 = 3, 10 s) and 11.18 (start (−1, −2, −π/2), k = (1, 2.5, 3),
10 s, T_s = 0.01 s and 0.1 s). The unicycle is integrated by RK4 with the manual's maximum step 0.01 s.
The figure helpers :func:`draw_unicycle`, :func:`plane_axes`, :func:`time_axes`, :func:`motion_figure` serve
the demos beyond the book too (``examples/mobile_robots.py``, which this module never imports).

Errata of the manual corrected and named in the checks: 11.10 (d3 = … − z2i Δ²/2, not − z2i|Δ|), 11.12
(z3 misses the z2i Δ s term), 11.14 (the printed closed-loop matrix is garbled), 11.15 (|φ| < π/2, not ≤).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Chapter 11,
Eqs. (11.1)–(11.85); solution manual, Problems 11.1–11.18, Figs. S11.1–S11.6.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp
from scipy.linalg import expm

from controllers.plants import BicyclePlant, ChainedFormPlant, DriftlessPlant, UnicyclePlant
from controllers.simulation import Chain, SimulationDiverged, SimulationResult, ZeroOrderHold, simulate
from controllers.wheeled import (BicycleInputOutputTracking, CartesianRegulator, ChainedFormTracking, Odometry,
                                 PostureRegulator, odometry_step)
from planners.wheeled import (chained_form_interpolation, chained_form_system, cartesian_polynomial_path,
                              parameterised_inputs, parameterised_path, uniform_time_scaling)
from problems.common import label_axes, subplots
from problems.registry import Solution, problem
from rigid_body.wheeled import (accessibility_rank, bicycle_constraints, bicycle_icr,  # noqa: E402
                                bicycle_input_matrix, differential_drive_admissible, differential_drive_limits,
                                differential_drive_velocities, differential_drive_wheel_speeds,
                                front_wheel_point, front_wheel_point_matrix, lie_bracket, lie_bracket_symbolic,
                                null_space, trailer_angle_indices, trailer_axle_midpoints,
                                trailer_configuration_size, trailer_constraints, trailer_input_function,
                                trailer_input_matrix, unicycle_arc, unicycle_input_matrix)

H = 0.01          # the manual's maximum integration step for the unicycle [s]
SEED = 11         # random configurations of the derivation checks
Q0_COMPANION = np.array([-1.0, -2.0, -np.pi / 2])  # start of i11_16 and i11_18


def _rng() -> np.random.Generator:
    return np.random.default_rng(SEED)


def _column(G: Any, j: int):
    """The j-th input vector field q ↦ G(q)[:, j] of an input-matrix function."""
    return lambda q: G(q)[:, j]


def draw_unicycle(ax: Any, x: float, y: float, th: float, size: float = 0.12, color: str = "k") -> None:
    """A triangle pointing along θ at (x, y)."""
    c, s = np.cos(th), np.sin(th)
    pts = np.array([[1.0, 0.0], [-0.6, 0.5], [-0.6, -0.5], [1.0, 0.0]]) * size
    ax.plot(x + c * pts[:, 0] - s * pts[:, 1], y + s * pts[:, 0] + c * pts[:, 1], color=color, lw=1)


def plane_axes(ax: Any, title: str | None = None, **legend: Any) -> Any:
    """The epilogue of a motion in the plane: x, y [m] at equal scale (see :func:`problems.common.label_axes`)."""
    ax.set_aspect("equal", adjustable="datalim")
    return label_axes(ax, "x [m]", "y [m]", title=title, **legend)


def time_axes(ax: Any, t: np.ndarray, series: list[tuple[np.ndarray, str]], ylabel: str,
              title: str | None = None) -> Any:
    """Signals against time, the first solid and the others dashed, labelled (a legend for two or more)."""
    for k, (y, label) in enumerate(series):
        ax.plot(t, y, "-" if k == 0 else "--", label=label)
    return label_axes(ax, "t [s]", ylabel, title=title)


def _inputs_axes(ax: Any, t: np.ndarray, u: np.ndarray, title: str | None = None) -> Any:
    return time_axes(ax, t, [(u[:, 0], "v [m/s]"), (u[:, 1], "ω [rad/s]")], "v [m/s], ω [rad/s]", title)


# --------------------------------------------------------------------------------------------
# 11.1–11.9: models
# --------------------------------------------------------------------------------------------

@problem("11.1", "Generalised coordinates of a tricycle with N trailers", kind="derivation")
def problem_11_1() -> Solution:
    """Configuration of a tricycle pulling N trailers: q = [x, y, φ, θ0, θ1, …, θN] ∈ R² × SO(2)^{N+2}.

    Checked for N = 0…4: the coordinates are independent and sufficient — the Jacobian of the positions and
    headings of every body (front wheel, tricycle, trailers; by finite differences) has full rank N + 4 — and
    the N + 2 rolling constraints of 11.8 are independent, leaving 2 velocity directions (v and φ̇).
    """
    sol = Solution()
    rng = _rng()
    ranks, dims, constraint_ranks = [], [], []
    for N in range(5):
        n = trailer_configuration_size(N)          # the library's count, N + 4: the checks use the model's ranks
        lengths = rng.uniform(0.5, 1.5, N)
        q = rng.uniform(-1.0, 1.0, n)

        def bodies(q: np.ndarray) -> np.ndarray:  # every axle point, front-wheel heading θ0 + φ, every θ_i
            return np.r_[trailer_axle_midpoints(q, 1.0, lengths).ravel(), q[3] + q[2], q[3:]]

        eps = 1e-6
        J = np.column_stack([(bodies(q + eps * e) - bodies(q - eps * e)) / (2 * eps) for e in np.eye(n)])
        ranks.append(int(np.linalg.matrix_rank(J, tol=1e-8)))
        dims.append(n)
        constraint_ranks.append(int(np.linalg.matrix_rank(trailer_constraints(q, 1.0, lengths))))
    sol.value("N", list(range(5)), unit="1")
    sol.value("dimension", dims, unit="1")
    sol.value("angle_indices_N3", trailer_angle_indices(3), unit="1")
    sol.check_close("coordinates independent and sufficient: rank ∂(positions, headings)/∂q (finite differences) = "
                    "N + 4, the manual's dim C", ranks, [N + 4 for N in range(5)], atol=0, reference="manual number")
    sol.check_close("the N + 2 rolling constraints of 11.8 are independent: N + 4 − rank A(q) = 2 admissible directions "
                    "(v and φ̇)", np.subtract([N + 4 for N in range(5)], constraint_ranks), [2] * 5, atol=0,
                    reference="closed form")
    return sol


def _three_wheel_A(q: np.ndarray, ell: float, r: float) -> np.ndarray:
    """The 3×6 constraint matrix of Problem 11.2 (three wheels at 120°): the manual does not print it;
    from a public transcription of the book's statement."""
    c, s, a = np.cos(q[2]), np.sin(q[2]), np.sqrt(3) / 2
    return np.array([[a * c - s / 2, c / 2 + a * s, ell, r, 0, 0],
                     [s, -c, ell, 0, r, 0],
                     [-a * c - s / 2, c / 2 - a * s, ell, 0, 0, r]])


@problem("11.2", "Partial integrability of three Pfaffian constraints (q ∈ R⁶)", kind="derivation")
def problem_11_2() -> Solution:
    """Three wheels at 120° (q = [x, y, θ, φ1, φ2, φ3]): adding the constraints gives 3ℓθ̇ + r Σ φ̇_i = 0.

    Hence θ = −(r/3ℓ)(φ1 + φ2 + φ3) + c: one combination is integrable. Checked with sympy (the row sum has
    no x, y terms), by simulating random admissible motions (the invariant stays constant) and by the
    accessibility rank: 5 = n − 1, i.e. exactly one of the three constraints is holonomic.
    """
    sol = Solution()
    q3, ell_s, r_s = sp.symbols("q3 ell r", positive=True)
    c, s, a = sp.cos(q3), sp.sin(q3), sp.sqrt(3) / 2
    A_sym = sp.Matrix([[a * c - s / 2, c / 2 + a * s, ell_s, r_s, 0, 0],
                       [s, -c, ell_s, 0, r_s, 0],
                       [-a * c - s / 2, c / 2 - a * s, ell_s, 0, 0, r_s]])
    row_sum = sp.simplify(A_sym[0, :] + A_sym[1, :] + A_sym[2, :])
    sol.value("row_sum", str(list(row_sum)))
    sol.check("sympy: row sum = [0, 0, 3ℓ, r, r, r] (the manual's 3ℓ q̇3 + r(q̇4 + q̇5 + q̇6) = 0)",
              row_sum == sp.Matrix([[0, 0, 3 * ell_s, r_s, r_s, r_s]]), str(list(row_sum)), reference="closed form")

    ell, r = sol.given("ℓ (test value)", 0.3, unit="m"), sol.given("r (test value)", 0.05, unit="m")
    rng = _rng()

    def G(q: np.ndarray) -> np.ndarray:  # wheel rates from the body velocity: a smooth basis of N(A)
        out = np.zeros((6, 3))
        out[0, 0] = out[1, 1] = out[2, 2] = 1.0
        out[3:] = _three_wheel_A(q, ell, r)[:, :3] / -r
        return out

    q = rng.normal(size=6)
    freq = rng.uniform(0.5, 2.0, 3)
    res = simulate(DriftlessPlant(G), lambda t, q: np.sin(freq * t + np.arange(3)), (0.0, 5.0), q, h=1e-3, Ts=1e-3)
    invariant = res.x[:, 2] + r / (3 * ell) * res.x[:, 3:].sum(axis=1)
    sol.value("invariant_drift", float(np.ptp(invariant)), unit="rad")
    sol.value("orientation_change", float(np.ptp(res.x[:, 2])), unit="rad")
    sol.check_error("q3 + (r/3ℓ)(q4 + q5 + q6) constant along random admissible motions (5 s, peak-to-peak) [rad]",
                    np.ptp(invariant), 1e-9, reference="simulation vs prediction",
                    detail=f"while θ varies by {np.ptp(res.x[:, 2]):.2f} rad")
    sol.check_bound("… along motions that do turn the robot (peak-to-peak θ) [rad]", np.ptp(res.x[:, 2]), 0.1, ">=")
    fields = [_column(G, j) for j in range(3)]
    rank = accessibility_rank(fields, q, depth=3)
    sol.value("accessibility_rank", rank, unit="1")
    sol.check_close("partially integrable: dim Δ_A (brackets to depth 3) = n − 1 = 5: one holonomic constraint, "
                    "not three", [rank], [5], atol=0, reference="closed form")
    return sol


@problem("11.3", "A single Pfaffian constraint satisfying (11.9) gives an involutive distribution", kind="derivation")
def problem_11_3() -> Solution:
    """g_j = γ(−a_{j+1} e_1 + a_1 e_{j+1}) span N(aᵀ); under (11.9) (γa is a gradient) [g_i, g_j] ∈ span{g}.

    Checked with sympy for γa = ∇h, h = q1 q2 + sin q3, γ = 1 + q1²: the bracket equals the manual's
    expression ∂(γa3)/∂q1 g1 − ∂(γa2)/∂q1 g2 + ∂(γa1)/∂q1 (a3 g1 + a2 g2)/a1; rank[g1, g2, [g1, g2]] = 2 at
    random points (also with finite-difference brackets); the unicycle constraint gives rank 3 (not involutive).
    """
    sol = Solution()
    q = sp.symbols("q1:4")
    gamma = 1 + q[0] ** 2
    h = q[0] * q[1] + sp.sin(q[2])
    a = [sp.diff(h, qi) / gamma for qi in q]   # a = ∇h/γ, so γa is a gradient: (11.9) holds
    g1 = sp.Matrix([-gamma * a[1], gamma * a[0], 0])
    g2 = sp.Matrix([-gamma * a[2], 0, gamma * a[0]])
    br = lie_bracket_symbolic(g1, g2, q)
    ga = [gamma * ai for ai in a]

    def d(f: Any, i: int) -> Any:
        return sp.diff(f, q[i])

    printed = sp.Matrix([d(ga[1], 0) * ga[2] - d(ga[2], 0) * ga[1] + (d(ga[2], 1) - d(ga[1], 2)) * ga[0],
                         d(ga[0], 2) * ga[0] - d(ga[0], 0) * ga[2],
                         d(ga[0], 0) * ga[1] - d(ga[0], 1) * ga[0]])     # the manual's bracket vector
    combination = d(ga[2], 0) * g1 - d(ga[1], 0) * g2 + d(ga[0], 0) * (a[2] * g1 + a[1] * g2) / a[0]
    sol.value("bracket_g1_g2", str(list(br)))
    sol.check("sympy: the manual's vector = its linear combination of g1, g2 (uses (11.9))",
              sp.simplify(printed - combination) == sp.zeros(3, 1), reference="closed form")
    sol.check("erratum 11.3: the printed vector is [g2, g1] = −[g1, g2] in the book's convention "
              "[g1, g2] = (∂g2/∂q) g1 − (∂g1/∂q) g2; so [g1, g2] = −(combination), still in span{g1, g2}",
              sp.simplify(br + printed) == sp.zeros(3, 1) and sp.simplify(br - printed) != sp.zeros(3, 1),
              f"[g1, g2] = {list(br)}")
    aT = sp.Matrix([a])
    sol.check("sympy: aᵀ g1 = aᵀ g2 = 0 (the manual's g_j span N(aᵀ))",
              sp.simplify(aT * g1)[0] == 0 and sp.simplify(aT * g2)[0] == 0, reference="closed form")

    f_g = sp.lambdify([q], [g1, g2, br], "numpy")
    rng = _rng()
    ranks, fd_err = [], 0.0
    for _ in range(10):
        qn = rng.uniform(0.2, 1.5, 3)
        G1, G2, B = (np.asarray(v, dtype=float).ravel() for v in f_g(qn))
        ranks.append(int(np.linalg.matrix_rank(np.column_stack([G1, G2, B]), tol=1e-9)))
        fd = lie_bracket(lambda x: np.asarray(f_g(x)[0], dtype=float).ravel(),
                         lambda x: np.asarray(f_g(x)[1], dtype=float).ravel(), qn)
        fd_err = max(fd_err, float(np.max(np.abs(fd - B))))
    sol.check("rank[g1, g2, [g1, g2]] = 2 at 10 random q (involutive)", all(k == 2 for k in ranks), f"ranks {ranks}")
    sol.check_error("finite-difference bracket = sympy bracket", fd_err, 1e-7, reference="finite differences")
    th = sp.symbols("theta")
    u1, u2 = sp.Matrix([sp.cos(th), sp.sin(th), 0]), sp.Matrix([0, 0, 1])
    bu = lie_bracket_symbolic(u1, u2, [sp.Symbol("x"), sp.Symbol("y"), th])
    rank_u = sp.Matrix.hstack(u1, u2, bu).rank(simplify=True)
    sol.check("negative case (sympy): unicycle [g1, g2] = [sin θ, −cos θ, 0], rank 3 (not involutive)",
              rank_u == 3 and sp.simplify(bu - sp.Matrix([sp.sin(th), -sp.cos(th), 0])) == sp.zeros(3, 1), str(list(bu)),
              reference="closed form")
    return sol


@problem("11.4", "Pfaffian constraints with a constant matrix are holonomic", kind="derivation")
def problem_11_4() -> Solution:
    """Constant Aᵀ ⇒ constant g_j ⇒ [g_i, g_j] = 0 and dim Δ_A = m = n − k < n: not controllable, holonomic.

    Checked for random constant A (k = 2, n = 5): the accessibility rank (finite-difference brackets to depth
    3) stays m = 3; the linear rank condition (D.15) on the system's actual linearisation (the Jacobians of
    f(q, u) = G(q) u by central differences at a random (q, u)): rank[B AB … A⁴B] = m = 3 < 5. The unicycle,
    whose A depends on q, reaches dim Δ_A = 3 > m = 2, and its linearisation along a motion (u = (1, 0)) is
    controllable.
    """
    sol = Solution()
    rng = _rng()
    k, n = sol.given("k (constraints)", 2), sol.given("n (coordinates)", 5)
    A = rng.normal(size=(k, n))
    G = null_space(A)
    m = G.shape[1]
    fields = [lambda q, j=j: G[:, j] for j in range(m)]
    rank = accessibility_rank(fields, rng.normal(size=n), depth=3)
    sol.value("m", m, unit="1")
    sol.value("accessibility_rank", rank, unit="1")
    sol.check_error("A G = 0 (the library's null-space basis: its defining property)", np.abs(A @ G).max(), 1e-14,
                    reference="property")
    sol.check_close("dim Δ_A = m = n − k = 3 < 5 (the brackets vanish)", [rank, m], [n - k, n - k], atol=0,
                    reference="closed form")

    def controllability_rank(fields: list, q: np.ndarray, u: np.ndarray, eps: float = 1e-6) -> int:
        """rank [B AB … A^{n−1}B] of the linearisation of q̇ = Σ g_j(q) u_j at (q, u) (central differences)."""
        f = lambda q, u: sum(g(q) * uj for g, uj in zip(fields, u))        # noqa: E731
        dim = q.size
        A_lin = np.column_stack([(f(q + eps * e, u) - f(q - eps * e, u)) / (2 * eps) for e in np.eye(dim)])
        B_lin = np.column_stack([(f(q, u + eps * e) - f(q, u - eps * e)) / (2 * eps) for e in np.eye(len(fields))])
        blocks = [B_lin]
        for _ in range(dim - 1):
            blocks.append(A_lin @ blocks[-1])
        return int(np.linalg.matrix_rank(np.hstack(blocks), tol=1e-7))

    ctrb = controllability_rank(fields, rng.normal(size=n), rng.normal(size=m))
    sol.value("controllability_rank", ctrb, unit="1")
    sol.check_close("linear rank condition (D.15) on the linearisation at a random (q, u): rank[B AB … A⁴B] = m = 3 "
                    "< n = 5, not controllable", [ctrb], [m], atol=0, reference="closed form")
    unicycle = [_column(unicycle_input_matrix, 0), _column(unicycle_input_matrix, 1)]
    r_u = accessibility_rank(unicycle, rng.normal(size=3), depth=2)
    c_u = controllability_rank(unicycle, rng.normal(size=3), np.array([1.0, 0.0]))
    sol.check_close("contrast, the unicycle (A depends on q): dim Δ_A = 3 > m = 2, and its linearisation along the "
                    "motion u = (1, 0) is controllable (rank 3)", [r_u, c_u], [3, 3], atol=0, reference="closed form")
    return sol


def _four_piece(theta0: float, eps: float, h: float) -> SimulationResult:
    """The unicycle under (1, 0), (0, 1), (−1, 0), (0, −1), each for ε (Problem 11.5), from (0, 0, θ0)."""
    pieces = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])
    return simulate(UnicyclePlant(), lambda t, x: pieces[min(int(round(t / eps)), 3)], (0.0, 4 * eps),
                    [0.0, 0.0, theta0], h=h, Ts=eps)


@problem("11.5", "Net unicycle displacement of a four-piece input sequence and the Lie bracket", kind="derivation")
def problem_11_5() -> Solution:
    """Inputs (v, ω) = (1, 0), (0, 1), (−1, 0), (0, −1), each for ε, from q0 = (x0, y0, θ0):

    q(4ε) − q0 = [ε cos θ0 − ε cos(θ0 + ε), ε sin θ0 − ε sin(θ0 + ε), 0] = ε² t with t → [sin θ0, −cos θ0, 0]
    = [g1, g2](q0) as ε → 0. The unicycle is simulated (RK4) and compared with the closed form; the limit is
    compared with the bracket by finite differences and by sympy.
    """
    sol = Solution()
    theta0 = sol.given("θ0", 0.7, unit="rad")
    bracket = np.array([np.sin(theta0), -np.cos(theta0), 0.0])
    fd = lie_bracket(_column(unicycle_input_matrix, 0), _column(unicycle_input_matrix, 1), [0.3, -0.2, theta0])
    sol.check_close("finite-difference [g1, g2](q0) = [sin θ0, −cos θ0, 0]", fd, bracket, atol=1e-9,
                    reference="finite differences")
    err_closed, t_err = [], []
    epsilons = list(sol.given("ε", np.array([0.2, 0.1, 0.05, 0.025]), unit="s"))
    for eps in epsilons:
        res = _four_piece(theta0, eps, eps / 200)
        disp = res.x[-1] - res.x[0]
        closed = np.array([eps * np.cos(theta0) - eps * np.cos(theta0 + eps),
                           eps * np.sin(theta0) - eps * np.sin(theta0 + eps), 0.0])
        err_closed.append(float(np.max(np.abs(disp - closed))))
        t_err.append(float(np.linalg.norm(disp / eps**2 - bracket)))
    sol.value("epsilon", epsilons, unit="s")
    sol.value("t_minus_bracket", t_err, unit="m/s²")
    sol.check_error("simulated displacement = closed form (all ε)", max(err_closed), 1e-12,
                    reference="simulation vs prediction")
    orders = np.diff(np.log(t_err)) / np.diff(np.log(epsilons))
    sol.value("convergence_order", orders, unit="1")
    sol.check_close("‖t(ε) − [g1, g2](q0)‖ = O(ε): log–log slopes 1 (the expansion's next term is O(ε³))", orders,
                    np.ones_like(orders), atol=0.05, reference="closed form")
    return sol


@problem("11.6", "The differential-drive relations (11.14)", kind="derivation")
def problem_11_6() -> Solution:
    """v = r(ω_R + ω_L)/2 and ω = r(ω_R − ω_L)/d from the rolling wheel centres and ṗ_R = ṗ_L + S(ω)(p_R − p_L).

    Checked: sympy solves (S11.2) for ω uniquely; a simulated robot driven by (11.14) moves its wheel centres
    p_{R,L} = p ± (d/2)[sin θ, −cos θ] (finite differences) exactly as rolling wheels, ṗ_i = r ω_i [cos θ, sin θ].
    """
    sol = Solution()
    r_s, d_s, wR, wL, th, w = sp.symbols("r d omega_R omega_L theta omega", real=True)
    n = sp.Matrix([sp.cos(th), sp.sin(th)])
    S = sp.Matrix([[0, -w], [w, 0]])
    eqs = r_s * wR * n - (r_s * wL * n + S * sp.Matrix([d_s * sp.sin(th), -d_s * sp.cos(th)]))
    roots = sp.solve(list(eqs), w, dict=True)
    sol.check("sympy: (S11.2) has the unique solution ω = r(ω_R − ω_L)/d",
              len(roots) == 1 and sp.simplify(roots[0][w] - r_s * (wR - wL) / d_s) == 0, str(roots),
              reference="closed form")

    r, d = sol.given("r (test value)", 0.1, unit="m"), sol.given("d (test value)", 0.5, unit="m")
    rng = _rng()
    wheel = rng.uniform(-5, 5, (4, 2))
    h = 1e-3

    def drive(t: float, x: np.ndarray) -> np.ndarray:
        wr, wl = wheel[min(int(t), 3)]
        return np.array(differential_drive_velocities(wr, wl, r, d), dtype=float)

    res = simulate(UnicyclePlant(), drive, (0.0, 4.0 - h), rng.normal(size=3), h=h, Ts=h)
    x, y, th_ = res.x.T
    worst = 0.0
    for side, sign, col in (("R", 1.0, 0), ("L", -1.0, 1)):
        p = np.c_[x + sign * d / 2 * np.sin(th_), y - sign * d / 2 * np.cos(th_)]
        v_fd = (p[2:] - p[:-2]) / (2 * h)
        omega_i = wheel[np.minimum(res.t[1:-1].astype(int), 3), col]
        mid = (res.t[1:-1] % 1.0 > 2 * h) & (res.t[1:-1] % 1.0 < 1 - 2 * h)  # away from input switches
        rolling = r * omega_i[:, None] * np.c_[np.cos(th_[1:-1]), np.sin(th_[1:-1])]
        worst = max(worst, float(np.max(np.abs(v_fd - rolling)[mid])))
    sol.value("wheel_velocity_mismatch", worst, unit="m/s")
    sol.check_error("simulated wheel centres roll: ṗ_i = r ω_i [cos θ, sin θ] (finite differences)", worst, 1e-5,
                    reference="finite differences")
    return sol


@problem("11.7", "Bicycle: instantaneous centre of rotation and body angular velocity", kind="derivation")
def problem_11_7() -> Solution:
    """C = (x − ℓ sin θ / tan φ, y + ℓ cos θ / tan φ); ω_body = v tan φ / ℓ; v_P = R_P v tan φ / ℓ for any P.

    Checked at random states: C equals the intersection of the rear-axle line and the front-wheel axis (line
    intersection); every body point's velocity from the rigid motion (11.19) is ⟂ (P − C) with |v_P| = R_P |ω|.
    """
    sol = Solution()
    rng = _rng()
    ell = sol.given("ℓ (test value)", 1.0, unit="m")
    worst_C, worst_perp, worst_mag = 0.0, 0.0, 0.0
    for _ in range(20):
        x, y, th = rng.uniform(-2, 2, 3)
        phi = rng.uniform(0.1, 1.2) * rng.choice([-1, 1])
        v = rng.uniform(-2, 2)
        q = np.array([x, y, th, phi])
        C = bicycle_icr(q, ell)
        # Intersection of rear axle (through (x, y), direction ⟂ θ) and front axle (through front wheel, ⟂ θ + φ).
        front = np.array([x + ell * np.cos(th), y + ell * np.sin(th)])
        d_r, d_f = np.array([-np.sin(th), np.cos(th)]), np.array([-np.sin(th + phi), np.cos(th + phi)])
        lam = np.linalg.solve(np.column_stack([d_r, -d_f]), front - np.array([x, y]))
        worst_C = max(worst_C, float(np.max(np.abs(np.array([x, y]) + lam[0] * d_r - C))))
        qd = bicycle_input_matrix(q, ell) @ np.array([v, 0.0])
        omega = qd[2]
        P = np.array([x, y]) + rng.uniform(-1, 2, 2)
        vP = qd[:2] + omega * np.array([-(P[1] - y), P[0] - x])  # ṗ + ω × (P − p)
        R_P = np.linalg.norm(P - C)
        worst_perp = max(worst_perp, abs(float(vP @ (P - C))))
        worst_mag = max(worst_mag, abs(np.linalg.norm(vP) - R_P * abs(v * np.tan(phi) / ell)))
    q = np.r_[rng.uniform(-2, 2, 3), 0.4]
    sol.check_close("model (11.19): A(q) G(q) = 0 for the constraints (11.15)–(11.16)",
                    bicycle_constraints(q, ell) @ bicycle_input_matrix(q, ell), np.zeros((2, 2)), atol=1e-15,
                    reference="closed form")
    sol.check_error("C (11.7 formula) = intersection of the wheel axes", worst_C, 1e-12, reference="second algorithm")
    sol.check_error("v_P ⟂ (P − C)", worst_perp, 1e-12, reference="closed form")
    sol.check_error("|v_P| = R_P v tan φ / ℓ", worst_mag, 1e-12, reference="closed form")
    q = np.array([0.0, 0.0, 0.0, 0.5])
    sol.value("icr_example", bicycle_icr(q, ell), unit="m")
    sol.check_close("body frame: C = (0, ℓ/tan φ) at θ = 0", bicycle_icr(q, ell), [0.0, ell / np.tan(0.5)], atol=1e-15,
                    reference="closed form")
    return sol


@problem("11.8", "Kinematic model of a tricycle with N trailers", kind="derivation")
def problem_11_8() -> Solution:
    """N + 2 constraints (front wheel, rear axle, each trailer axle) and q̇ = g1(q) v + g2 ω with the manual's G.

    Checked for N = 3 at random q and random lengths: A(q) G(q) = 0 and rank G = 2; the constraint rows equal
    the ones obtained by differentiating the axle positions (finite differences); and a simulated train under
    random inputs has no lateral velocity at any axle.
    """
    sol = Solution()
    rng = _rng()
    N, ell = sol.given("N (test value)", 3), sol.given("ℓ (test value)", 1.0, unit="m")
    lengths = rng.uniform(0.5, 1.5, N)
    worst, worst_rows, ranks = 0.0, 0.0, set()
    for _ in range(20):
        q = rng.uniform(-1.0, 1.0, N + 4)
        A, G = trailer_constraints(q, ell, lengths), trailer_input_matrix(q, ell, lengths)
        worst = max(worst, float(np.max(np.abs(A @ G))))
        ranks.add(int(np.linalg.matrix_rank(G)))
        # Rows from the geometry: lateral velocity of each axle point, n_i^⊥ · ∂p_i/∂q, by finite differences.
        eps = 1e-6
        J = [(trailer_axle_midpoints(q + eps * e, ell, lengths) - trailer_axle_midpoints(q - eps * e, ell, lengths))
             / (2 * eps) for e in np.eye(N + 4)]
        J = np.stack(J, axis=-1)  # (N+2, 2, n)
        headings = np.r_[q[3] + q[2], q[3:]]
        rows = np.array([np.sin(hd) * J[i, 0] - np.cos(hd) * J[i, 1] for i, hd in enumerate(headings)])
        worst_rows = max(worst_rows, float(np.max(np.abs(rows - A))))
    sol.value("max_abs_AG", worst, unit="1")
    sol.check_error("A(q) G(q) = 0 at 20 random q (N = 3)", worst, 1e-14, reference="closed form")
    sol.check_close("rank G(q) = 2 (v and ω) at the 20 random q", sorted(ranks), [2], atol=0, reference="closed form")
    sol.check_error("constraint rows = lateral velocities of the axle points (finite differences)", worst_rows, 1e-8,
                    reference="finite differences")

    h = 1e-3
    res = simulate(DriftlessPlant(trailer_input_function(ell, lengths)), lambda t, q: np.array([1.0 + 0.5 * np.sin(t), 0.8 * np.cos(1.3 * t) - 0.5 * q[2]]),
                   (0.0, 6.0), np.r_[0.0, 0.0, 0.2, 0.0, 0.1, -0.1, 0.05], h=h, Ts=h)
    pts = np.array([trailer_axle_midpoints(q, ell, lengths) for q in res.x])
    v_fd = (pts[2:] - pts[:-2]) / (2 * h)
    headings = np.c_[res.x[1:-1, 3] + res.x[1:-1, 2], res.x[1:-1, 3:]]
    lateral = np.abs(np.sin(headings) * v_fd[..., 0] - np.cos(headings) * v_fd[..., 1])
    sol.value("max_lateral_velocity", float(lateral.max()), unit="m/s")
    sol.check_error("simulated train: no lateral slip at any wheel (6 s)", lateral.max(), 1e-6,
                    reference="simulation vs prediction")
    fig, ax = subplots(figsize=(6.4, 4.0))
    for i, label in enumerate(["front wheel", "tricycle"] + [f"trailer {k}" for k in range(1, N + 1)]):
        ax.plot(pts[:, i, 0], pts[:, i, 1], label=label)
    plane_axes(ax)
    sol.figure(fig, "Tricycle with 3 trailers (Problem 11.8)")
    return sol


@problem("11.9", "Admissible (v, ω) of a differential drive with wheel-speed bound ω_RL", kind="derivation")
def problem_11_9() -> Solution:
    """|2v ∓ dω|/(2r) ≤ ω_RL: a rhombus with vertices v = ±r ω_RL and ω = ±2r ω_RL/d.

    Example r = 0.1 m, d = 0.5 m, ω_RL = 10 rad/s ⇒ v_max = 1 m/s, ω_max = 4 rad/s. Checked: the inverse of
    (11.14) against a numerical solve; the rhombus predicate against the wheel-speed check on random samples.
    """
    sol = Solution()
    r, d, w_RL = sol.given("r", 0.1, unit="m"), sol.given("d", 0.5, unit="m"), sol.given("ω_RL", 10.0, unit="rad/s")
    v_max, w_max = differential_drive_limits(r, d, w_RL)
    sol.value("v_max", v_max, unit="m/s")
    sol.value("omega_max", w_max, unit="rad/s")
    sol.check_close("v_max = r ω_RL = 1 m/s, ω_max = 2r ω_RL/d = 4 rad/s", [v_max, w_max], [1.0, 4.0], atol=1e-15,
                    reference="closed form")
    rng = _rng()
    v, w = rng.uniform(-1.5, 1.5, 2000), rng.uniform(-6, 6, 2000)
    M = np.array([[r / 2, r / 2], [r / d, -r / d]])  # (11.14): [v, ω] = M [ω_R, ω_L]
    wheels = np.linalg.solve(M, np.vstack([v, w]))
    wR, wL = differential_drive_wheel_speeds(v, w, r, d)
    sol.check_close("ω_R = (2v + dω)/(2r), ω_L = (2v − dω)/(2r) (vs numerical inverse of (11.14))",
                    np.vstack([wR, wL]), wheels, atol=1e-12, reference="second algorithm")
    feasible = np.max(np.abs(wheels), axis=0) <= w_RL
    predicate = differential_drive_admissible(v, w, r, d, w_RL)
    sol.check("rhombus predicate = wheel-speed check (numerical inverse of (11.14)) on 2000 random (v, ω)",
              np.array_equal(feasible, predicate),
              f"{int(feasible.sum())} feasible samples, disagreements {int(np.sum(feasible != predicate))}",
              reference="second algorithm")
    fig, ax = subplots(figsize=(5.0, 4.0))
    ax.fill([v_max, 0, -v_max, 0], [0, w_max, 0, -w_max], alpha=0.3, label="admissible")
    ax.plot(v[~feasible], w[~feasible], "x", ms=2, color="C3", label="a wheel exceeds ω_RL")
    label_axes(ax, "v [m/s]", "ω [rad/s]", legend="upper right")
    sol.figure(fig, "Admissible velocities of a differential drive (Problem 11.9)")
    return sol


# --------------------------------------------------------------------------------------------
# 11.10–11.13: planning
# --------------------------------------------------------------------------------------------

def _integrate_chained(path: Any, z_i: np.ndarray) -> np.ndarray:
    """The chained form driven by the path's geometric inputs (s as time, evaluated at every RK4 stage) and
    integrated by simulate: z(s_f)."""
    plant = ChainedFormPlant()
    h = path.s_f / 1000

    def driven(s: float, z: np.ndarray, u: np.ndarray) -> np.ndarray:
        return plant.derivative(s, z, path.inputs(s))

    res = simulate(driven, lambda s, z: np.zeros(2), (0.0, path.s_f), z_i, h=h, Ts=path.s_f)
    return res.x[-1]


@problem("11.10", "Parameterised-input planning for the (2, 4) chained form", kind="derivation")
def problem_11_10() -> Solution:
    """ṽ1 = sgn Δ, ṽ2 = c0 + c1 s + c2 s², s ∈ [0, |Δ|]: z(s_f) = z_f gives D c = d (11.50).

    D = [[|Δ|, Δ²/2, |Δ|³/3], [sgnΔ Δ²/2, Δ³/6, sgnΔ Δ⁴/12], [|Δ|³/6, Δ⁴/24, |Δ|⁵/60]],
    d = [z2f − z2i, z3f − z3i − z2i Δ, z4f − z4i − z3i Δ − z2i Δ²/2].
    Erratum: the manual prints the last term of d3 as − z2i|Δ|; the correct − z2i Δ²/2 is shown by integrating
    the chained form (RK4) with the coefficients from either d.
    """
    sol = Solution()
    rng = _rng()
    worst_D, worst_d, miss, miss_manual = 0.0, 0.0, 0.0, 0.0
    for sign in (1.0, -1.0, 1.0, -1.0):
        z_i, z_f = rng.normal(size=4), rng.normal(size=4)
        z_f[0] = z_i[0] + sign * rng.uniform(0.5, 2.0)
        D, d = chained_form_system(z_i, z_f)
        De = z_f[0] - z_i[0]
        A, sg = abs(De), np.sign(De)
        D_book = np.array([[A, De**2 / 2, A**3 / 3], [sg * De**2 / 2, De**3 / 6, sg * De**4 / 12],
                           [A**3 / 6, De**4 / 24, A**5 / 60]])
        d_correct = np.array([z_f[1] - z_i[1], z_f[2] - z_i[2] - z_i[1] * De,
                              z_f[3] - z_i[3] - z_i[2] * De - z_i[1] * De**2 / 2])
        d_manual = d_correct + np.array([0.0, 0.0, z_i[1] * De**2 / 2 - z_i[1] * A])
        worst_D = max(worst_D, float(np.max(np.abs(D - D_book))))
        worst_d = max(worst_d, float(np.max(np.abs(d - d_correct))))
        path = parameterised_inputs(z_i, z_f)
        miss = max(miss, float(np.max(np.abs(_integrate_chained(path, z_i) - z_f))))
        wrong_path = parameterised_path(z_i, De, np.linalg.solve(D_book, d_manual))
        miss_manual = max(miss_manual, float(np.max(np.abs(_integrate_chained(wrong_path, z_i) - z_f))))
    sol.value("example_c", path.coefficients, unit="1")
    sol.value("miss_with_manual_d", miss_manual, unit="1")
    sol.check_error("D = the manual's matrix (both signs of Δ)", worst_D, 1e-12, reference="closed form")
    sol.check_error("d = corrected vector (… − z2i Δ²/2)", worst_d, 1e-12, reference="closed form")
    sol.check_error("chained form integrated (RK4) with c = D⁻¹d reaches z_f", miss, 1e-9,
                    reference="simulation vs prediction")
    sol.check("erratum 11.10: the manual's d3 (− z2i|Δ|) misses z_f", miss_manual > 1e-3,
              f"max |z(s_f) − z_f| = {miss_manual:.3g} with the printed d3")
    return sol


@problem("11.11", "Parameterised inputs with s_f = 1", kind="derivation")
def problem_11_11() -> Solution:
    """ṽ1 = Δ (instead of sgn Δ) makes z1 reach z1f at s = 1; for (2, 3): D = [[1, 1/2], [Δ/2, Δ/6]],
    d = [z2f − z2i, z3f − z3i − z2i Δ]. Checked against the manual's D, d and by integrating (2, 3) and (2, 4).
    """
    sol = Solution()
    rng = _rng()
    worst, miss, unit = 0.0, 0.0, True
    for n in (3, 4, 3, 4):
        z_i, z_f = rng.normal(size=n), rng.normal(size=n)
        D, d = chained_form_system(z_i, z_f, unit_interval=True)
        De = z_f[0] - z_i[0]
        if n == 3:
            worst = max(worst, float(np.max(np.abs(D - [[1, 0.5], [De / 2, De / 6]]))),
                        float(np.max(np.abs(d - [z_f[1] - z_i[1], z_f[2] - z_i[2] - z_i[1] * De]))))
        path = parameterised_inputs(z_i, z_f, unit_interval=True)
        unit = unit and path.s_f == 1.0 and abs(path.inputs(0.3)[0] - De) < 1e-14
        miss = max(miss, float(np.max(np.abs(_integrate_chained(path, z_i) - z_f))))
    sol.check("s_f = 1 and ṽ1 = Δ in all four cases (the manual's modification)", unit, reference="closed form")
    sol.check_error("(2, 3): D = [[1, 1/2], [Δ/2, Δ/6]], d = [z2f − z2i, z3f − z3i − z2i Δ]", worst, 1e-12,
                    reference="closed form")
    sol.check_error("(2, 3) and (2, 4) integrated (RK4) reach z_f at s = 1", miss, 1e-9,
                    reference="simulation vs prediction")
    return sol


@problem("11.12", "Parameterised inputs and interpolating polynomials give the same (2, 3) path", kind="derivation")
def problem_11_12() -> Solution:
    """Scheme A (ṽ1 = Δ, ṽ2 = c0 + c1 s) and scheme B (z1 linear, z3 the cubic meeting z3 and z3'/z1' = z2 at
    both ends) give identical z(s): z3 = z3i + Δ(z2i s + c0 s²/2 + c1 s³/6) is a cubic, and it is unique.

    Erratum: the manual's z3 = z3i + Δ(c0 s²/2 + c1 s³/6) omits the z2i Δ s term (it misses z3f when z2i ≠ 0).
    """
    sol = Solution()
    rng = _rng()
    s = np.linspace(0.0, 1.0, 201)
    worst, worst_formula, manual_miss = 0.0, 0.0, 0.0
    for _ in range(10):
        z_i, z_f = rng.normal(size=3), rng.normal(size=3)
        A, B = parameterised_inputs(z_i, z_f, unit_interval=True), chained_form_interpolation(z_i, z_f)
        worst = max(worst, float(np.max(np.abs(A.z(s) - B.z(s)))), float(np.max(np.abs(A.inputs(s) - B.inputs(s)))))
        c0, c1 = A.coefficients
        De = z_f[0] - z_i[0]
        z3 = z_i[2] + De * (z_i[1] * s + c0 * s**2 / 2 + c1 * s**3 / 6)
        worst_formula = max(worst_formula, float(np.max(np.abs(z3 - A.z(s)[:, 2]))))
        manual_miss = max(manual_miss, abs(z_i[2] + De * (c0 / 2 + c1 / 6) - z_f[2]))
    sol.check_error("schemes A and B: identical z(s) and geometric inputs (10 random boundary pairs)", worst, 1e-12,
                    reference="second algorithm")
    sol.check_error("z3 = z3i + Δ(z2i s + c0 s²/2 + c1 s³/6) (corrected)", worst_formula, 1e-12,
                    reference="closed form")
    sol.value("manual_z3_miss", manual_miss, unit="1")
    sol.check("erratum 11.12: the printed z3 (without z2i Δ s) misses z3f", manual_miss > 1e-3,
              f"max |z3(1) − z3f| = {manual_miss:.3g}")
    return sol


@problem("11.13", "Cartesian-polynomial parking manoeuvre of the unicycle and a feasible timing law", kind="programming")
def problem_11_13() -> Solution:
    """Cubic path (11.52) from q_i = (0, 0, 0) to q_f = (2, 1, π/2) with k_i = k_f = 1 (companion s11_13).

    α, β by (11.53); geometric inputs by flatness (11.45)–(11.47): with s = t, max|ω| = 10 rad/s; the uniform
    scaling s = t/T with T = 10 s (11.54)–(11.55) restores feasibility (the manual does not state the bounds:
    T = 10 s is the shortest for |ω| ≤ 1 rad/s, |v| ≤ 0.5 m/s). Fig. S11.1: path and geometric inputs. The
    unicycle driven open loop by the scaled inputs (RK4) reaches q_f.
    """
    sol = Solution()
    q_i = sol.given("q_i", np.zeros(3), unit="m, m, rad")
    q_f = sol.given("q_f", np.array([2.0, 1.0, np.pi / 2]), unit="m, m, rad")
    k = sol.given("k = k_i = k_f", 1.0, unit="m")
    path = cartesian_polynomial_path(q_i, q_f, k, k)
    sol.value("alpha_x", float(path.alpha[0]), unit="m")
    sol.value("beta_x", float(path.beta[0]), unit="m")
    sol.value("alpha_y", float(path.alpha[1]), unit="m")
    sol.value("beta_y", float(path.beta[1]), unit="m")
    s = np.linspace(0.0, 1.0, 100001)
    p, dp, _ = path(s)
    theta, v, w = path.geometric_inputs(s)
    sol.value("max_v", float(np.max(np.abs(v))), unit="m (per unit of s)")
    sol.value("max_omega", float(np.max(np.abs(w))), unit="rad (per unit of s)")
    sol.value("s_at_max_v", float(s[np.argmax(v)]), unit="1")
    # (11.52) with α, β of (11.53) evaluated here from the data, term by term
    alpha = k * np.array([np.cos(q_f[2]), np.sin(q_f[2])]) - 3 * q_f[:2]
    beta = k * np.array([np.cos(q_i[2]), np.sin(q_i[2])]) + 3 * q_i[:2]
    cubic = (np.outer(s**3, q_f[:2]) - np.outer((s - 1) ** 3, q_i[:2]) + np.outer(s**2 * (s - 1), alpha)
             + np.outer(s * (s - 1) ** 2, beta))
    sol.check_close("p(s) = s³p_f − (s − 1)³p_i + α s²(s − 1) + β s(s − 1)² with α = k_f[cos θ_f, sin θ_f] − 3p_f, "
                    "β = k_i[cos θ_i, sin θ_i] + 3p_i (11.53) (100001 s)", p, cubic, atol=1e-12, reference="closed form")
    sol.check_close("boundary headings Atan2(y', x') = 0, π/2 and speeds ṽ(0) = k_i, ṽ(1) = k_f",
                    [theta[0], theta[-1], v[0], v[-1]], [0.0, np.pi / 2, 1.0, 1.0], atol=1e-14, reference="closed form")
    sol.check_close("manual: max|ω̃| = 10 rad/s with s = t", float(np.max(np.abs(w))), 10.0, atol=1e-6,
                    reference="manual number")
    sol.check_close("derived value: max ṽ = 3.0275 m/s", float(np.max(v)), 3.0275, atol=1e-3,
                    reference="independent derivation")
    fd_theta = np.gradient(np.unwrap(theta), s)
    sol.check_close("ω̃ = dθ/ds (finite differences of the heading)", fd_theta[1:-1], w[1:-1], atol=1e-4,
                    reference="finite differences")
    # The manual scales by T = 10 s without stating the bounds: the scaling (11.54)–(11.55) is checked for an
    # ω-limited and a v-limited pair of bounds against its closed form on the dense samples above; the first
    # pair gives the manual's T = 10 s (|ω| ≤ 1 rad/s), used for the run below.
    bounds = sol.given("bounds (v_max, ω_max): ω-limited, v-limited", np.array([[0.5, 1.0], [0.2, 1.0]]),
                       unit="m/s, rad/s")
    T_lib = [uniform_time_scaling(path, v_max=vb, omega_max=wb) for vb, wb in bounds]
    T_cf = [max(np.max(np.abs(v)) / vb, np.max(np.abs(w)) / wb) for vb, wb in bounds]
    sol.value("T_for_bounds", np.array(T_lib), unit="s")
    sol.check_close("uniform scaling: the shortest T = max(max|ṽ|/v_max, max|ω̃|/ω_max) for both pairs of bounds [s]",
                    T_lib, T_cf, rtol=1e-6, reference="closed form")
    T = T_lib[0]
    sol.value("T", T, unit="s")
    sol.value("max_v_scaled", float(np.max(np.abs(v)) / T), unit="m/s")
    sol.value("max_omega_scaled", float(np.max(np.abs(w)) / T), unit="rad/s")

    def inputs(t: float, x: Any) -> np.ndarray:
        _, vs, ws = path.geometric_inputs(min((t + H / 2) / T, 1.0))  # midpoint of the hold interval
        return np.array([vs / T, ws / T])

    res = simulate(UnicyclePlant(), inputs, (0.0, T), q_i, h=H / 10, Ts=H)
    err = res.x[-1] - q_f
    sol.value("open_loop_final_error", err, unit="m, m, rad")
    sol.check_close("unicycle driven by the scaled inputs (RK4) reaches q_f", err, np.zeros(3), atol=1e-4,
                    reference="simulation vs prediction")

    fig, (ax1, ax2) = subplots(1, 2, figsize=(10, 4))
    ax1.plot(p[:, 0], p[:, 1], label="planned path")
    ax1.plot(res.x[:, 0], res.x[:, 1], "--", label="unicycle (open loop)")
    for sk in np.linspace(0, 1, 6):
        k = int(sk * (len(s) - 1))
        draw_unicycle(ax1, p[k, 0], p[k, 1], theta[k])
    plane_axes(ax1, "Cartesian path")
    ax2.plot(s, v, label="ṽ(s) [m]")
    ax2.plot(s, w, "--", label="ω̃(s) [rad]")
    label_axes(ax2, "s [-]", "geometric inputs ṽ [m], ω̃ [rad]", title="Geometric inputs")
    sol.figure(fig, "Fig. S11.1 — parking manoeuvre by Cartesian polynomials")
    return sol


# --------------------------------------------------------------------------------------------
# 11.14–11.18: control
# --------------------------------------------------------------------------------------------

@problem("11.14", "Linearisation-based tracking for the (2, 3) chained form", kind="derivation")
def problem_11_14() -> Solution:
    """ė1 = u1, ė2 = u2, ė3 = v1d e2 + z2d u1 − e2 u1; u1 = −k1 e1, u2 = −k2 e2 − (k3/v1d) e3.

    Closed loop [[−k1, 0, 0], [0, −k2, −k3/v1d], [−k1 z2d, v1d, 0]] (erratum: the manual's matrix is garbled),
    p(λ) = (λ + k1)(λ² + k2 λ + k3). Checked with sympy, and by simulating the chained form with v1d = 1,
    z2d = 0.5, k = (1, 2, 1) from a small error: e(t) follows the linear prediction exp(A_cl t) e(0) up to the
    nonlinear term, second order in e(0). The footnote (constant v1d, z2d: a unicycle reference with ω_d
    constant and v_d growing linearly) is checked by integrating the unicycle under the inputs (11.24).
    """
    sol = Solution()
    e1, e2, e3, u1, u2, v1d, z2d, k1, k2, k3, lam = sp.symbols("e1 e2 e3 u1 u2 v1d z2d k1 k2 k3 lambda")
    z2 = z2d - e2
    v1 = v1d - u1
    e3dot = z2d * v1d - z2 * v1
    sol.check("sympy: ė3 = v1d e2 + z2d u1 − e2 u1", sp.expand(e3dot - (v1d * e2 + z2d * u1 - e2 * u1)) == 0,
              reference="closed form")
    f = sp.Matrix([u1, u2, e3dot]).subs({u1: -k1 * e1, u2: -k2 * e2 - k3 / v1d * e3})
    A_cl = f.jacobian([e1, e2, e3]).subs({e1: 0, e2: 0, e3: 0})
    A_book = sp.Matrix([[-k1, 0, 0], [0, -k2, -k3 / v1d], [-k1 * z2d, v1d, 0]])
    sol.check("sympy: linearised closed-loop matrix = [[−k1,0,0],[0,−k2,−k3/v1d],[−k1 z2d, v1d, 0]] (erratum 11.14)",
              sp.simplify(A_cl - A_book) == sp.zeros(3, 3), str(A_cl.tolist()), reference="closed form")
    p = sp.factor(A_cl.charpoly(lam).as_expr())
    sol.value("characteristic_polynomial", str(p))
    sol.check("sympy: p(λ) = (λ + k1)(λ² + k2 λ + k3), independent of v1d, z2d",
              sp.expand(p - (lam + k1) * (lam**2 + k2 * lam + k3)) == 0, str(p), reference="closed form")

    k = tuple(sol.given("k1, k2, k3", np.array([1.0, 2.0, 1.0])))
    vd, zd2 = sol.given("v1d", 1.0), sol.given("z2d", 0.5)
    z3d0 = sol.given("z3d(0)", 0.2)

    def reference(t: float) -> tuple[np.ndarray, np.ndarray]:
        """The chained form's reference for constant v1d, v2d = 0: z1 = v1d t, z2 = z2d, ż3 = z2d v1d."""
        return np.array([vd * t, zd2, z3d0 + zd2 * vd * t]), np.array([vd, 0.0])

    h = 1e-3

    def deviation(e0: np.ndarray) -> tuple[SimulationResult, float]:
        """The tracking run from e(0) and its largest deviation from the linearised loop's exp(A_cl t) e(0)."""
        res = simulate(ChainedFormPlant(), ChainedFormTracking(reference, *k), (0.0, 8.0),
                       reference(0.0)[0] - e0, h=h, Ts=h)
        A_num = np.array([[-k[0], 0, 0], [0, -k[1], -k[2] / vd], [-k[0] * zd2, vd, 0]])
        Phi = expm(A_num * h)  # e(t_{k+1}) = Φ e(t_k) for the linearised loop
        predicted = np.empty_like(res["e"])
        predicted[0] = e0
        for j in range(1, len(predicted)):
            predicted[j] = Phi @ predicted[j - 1]
        return res, float(np.max(np.abs(res["e"] - predicted)))

    e0 = sol.given("e(0)", np.array([0.02, -0.03, 0.02]))
    res, dev = deviation(e0)
    _, dev_half = deviation(e0 / 2)
    sol.value("final_error", res["e"][-1], unit="1 (chained-form coordinates)")
    sol.value("max_deviation_from_linear_prediction", dev, unit="1")
    sol.check_error("simulated error follows the linearised loop exp(A_cl t) e(0): max deviation relative to |e(0)| "
                    "(it converges with it: |e(8 s)| = " + f"{np.linalg.norm(res['e'][-1]):.1e})",
                    dev / np.linalg.norm(e0), 0.02, reference="simulation vs prediction")
    sol.check_close("… the deviation is the nonlinear term e2 u1, second order in e(0): halving e(0) quarters it",
                    dev / dev_half, 4.0, rtol=0.1, reference="simulation vs prediction")
    # Footnote: through (11.23) the reference is a unicycle's, θ = z1, x = z2 cos θ + z3 sin θ, y = z2 sin θ − z3 cos θ;
    # (11.24) gives its inputs ω_d = v1d (constant) and v_d = v2d + z3d v1d (linear in t, as ż3d = z2d v1d): the
    # unicycle integrated under these inputs (RK4, evaluated at every stage) stays on the mapped reference
    def unicycle_of(z: np.ndarray) -> np.ndarray:
        c, s = np.cos(z[0]), np.sin(z[0])
        return np.array([z[1] * c + z[2] * s, z[1] * s - z[2] * c, z[0]])

    def inputs(t: float) -> np.ndarray:
        z, v = reference(t)
        return np.array([v[1] + z[2] * v[0], v[0]])                     # (11.24): v = v2 + z3 v1, ω = v1

    plant = UnicyclePlant()
    spiral = simulate(lambda t, q, u: plant.derivative(t, q, inputs(t)), lambda t, q: np.zeros(2), (0.0, 8.0),
                      unicycle_of(reference(0.0)[0]), h=h, Ts=8.0)
    mapped = np.array([unicycle_of(reference(t)[0]) for t in spiral.t])
    sol.value("footnote_v_d_slope", float(np.polyfit(spiral.t, [inputs(t)[0] for t in spiral.t], 1)[0]), unit="m/s²")
    sol.check_error("footnote: the unicycle driven by ω_d = v1d (constant) and v_d = v2d + z3d v1d (growing linearly, "
                    "slope z2d v1d²) follows the mapped chained-form reference (an involute of the circle of radius "
                    "z2d: an Archimedean spiral as t grows) [m, rad]", np.abs(spiral.x - mapped).max(), 1e-9,
                    reference="simulation vs prediction")
    return sol


@problem("11.15", "Input–output linearisation of the bicycle with a point on the front-wheel line", kind="derivation")
def problem_11_15() -> Solution:
    """y = [x + ℓ cos θ + b cos(θ+φ), y + ℓ sin θ + b sin(θ+φ)], ẏ = T(θ, φ)[v, ω]ᵀ, det T = b/cos φ.

    With [v, ω] = T⁻¹ u: ẏ = u and the zero dynamics of θ, φ as in the manual; u = ẏ_d + K(y_d − y) gives
    decoupled exponential convergence. Checked: T against finite differences of y along the bicycle's fields;
    det T; the manual's θ̇, φ̇ expressions against G T⁻¹ u; a circle tracked with ℓ = 1 m, b = 0.5 m whose error
    follows e_i(0) exp(−k_i t). Erratum: T is singular at |φ| = π/2, so the condition is |φ| < π/2 (not ≤).
    """
    sol = Solution()
    rng = _rng()
    ell, b = sol.given("ℓ (test value)", 1.0, unit="m"), sol.given("b (test value)", 0.5, unit="m")
    worst_T, worst_det, worst_zero = 0.0, 0.0, 0.0
    eps = 1e-6
    for _ in range(20):
        q = np.r_[rng.uniform(-2, 2, 3), rng.uniform(-1.3, 1.3)]
        G = bicycle_input_matrix(q, ell)
        T = front_wheel_point_matrix(q[2], q[3], ell, b)
        T_fd = np.column_stack([(front_wheel_point(q + eps * g, ell, b) - front_wheel_point(q - eps * g, ell, b)) / (2 * eps)
                                for g in G.T])
        worst_T = max(worst_T, float(np.max(np.abs(T - T_fd))))
        worst_det = max(worst_det, abs(np.linalg.det(T) - b / np.cos(q[3])) / abs(b / np.cos(q[3])))
        u = rng.normal(size=2)
        qd = G @ np.linalg.solve(T, u)
        th, ph = q[2], q[3]
        c2, s2 = np.cos(th + ph), np.sin(th + ph)
        theta_dot = np.sin(ph) * (c2 * u[0] + s2 * u[1]) / ell
        phi_dot = -(c2 * np.sin(ph) / ell + s2 / b) * u[0] - (s2 * np.sin(ph) / ell - c2 / b) * u[1]
        worst_zero = max(worst_zero, float(np.max(np.abs(qd[2:] - [theta_dot, phi_dot]))))
    sol.check_error("T(θ, φ) = ∂y/∂q G(q) (finite differences)", worst_T, 1e-8, reference="finite differences")
    sol.check_error("det T = b / cos φ (relative)", worst_det, 1e-12, reference="closed form")
    sol.check_error("zero dynamics θ̇, φ̇ = manual's expressions", worst_zero, 1e-12, reference="closed form")
    near = np.linalg.cond(front_wheel_point_matrix(0.3, np.pi / 2 - 1e-7, ell, b))
    sol.check("erratum 11.15: T degenerates as |φ| → π/2 (cond > 1e6 at π/2 − 1e-7), so |φ| < π/2 strictly",
              near > 1e6, f"cond T = {near:.2e}")

    R, Om = sol.given("circle radius", 2.0, unit="m"), sol.given("angular rate on the circle", 0.25, unit="rad/s")

    def reference(t: float) -> tuple[np.ndarray, np.ndarray]:
        return (R * np.array([np.cos(Om * t), np.sin(Om * t)]),
                R * Om * np.array([-np.sin(Om * t), np.cos(Om * t)]))

    k = tuple(sol.given("k1, k2", np.array([1.0, 2.0]), unit="1/s"))
    q0 = sol.given("q(0)", np.array([R - ell - b + 0.3, -0.2, np.pi / 2 - 0.3, 0.1]), unit="m, m, rad, rad")
    h = 1e-3
    res = simulate(BicyclePlant(ell), BicycleInputOutputTracking(ell, b, reference, *k), (0.0, 6.0), q0, h=h, Ts=h)
    e = res["e"]
    predicted = e[0] * np.exp(-np.outer(res.t, k))
    dev = float(np.max(np.abs(e - predicted)))
    sol.value("initial_error", e[0], unit="m")
    sol.value("final_error", e[-1], unit="m")
    sol.check_error("circle tracked: e_i(t) = e_i(0) exp(−k_i t) (decoupled, up to the 1 ms hold): max deviation "
                    "relative to |e(0)|", dev / np.max(np.abs(e[0])), 1e-3, reference="simulation vs prediction",
                    detail=f"|e(0)| = {np.max(np.abs(e[0])):.2f} m")
    sol.check("|φ| stays < π/2 along the run", np.max(np.abs(res.x[:, 3])) < np.pi / 2,
              f"max |φ| = {np.max(np.abs(res.x[:, 3])):.3f} rad")
    return sol


def motion_figure(res: SimulationResult, label: str, estimate: np.ndarray | None = None) -> Any:
    """Cartesian motion (with the odometric estimate as dots) and the velocity inputs (Figs. S11.3, S11.5, S11.6)."""
    fig, (a1, a2) = subplots(1, 2, figsize=(10, 4))
    a1.plot(res.x[:, 0], res.x[:, 1], label=label)
    if estimate is not None:
        step = max(1, len(res.t) // 60)
        a1.plot(estimate[::step, 0], estimate[::step, 1], ".", ms=3, label="odometric estimate")
    for k in range(0, len(res.t), max(1, len(res.t) // 10)):
        draw_unicycle(a1, *res.x[k, :3], size=0.08)
    plane_axes(a1, "Cartesian motion", legend=True)
    _inputs_axes(a2, res.t, res.u, "Velocity inputs")
    return fig


def _regulate(controller: Any, q0: Any, t_end: float = 10.0) -> SimulationResult:
    return simulate(UnicyclePlant(), controller, (0.0, t_end), q0, h=H, Ts=H)


@problem("11.16", "Cartesian regulator modified to allow backward motion", kind="simulation")
def problem_11_16() -> Solution:
    """v = k1 nᵀe_p (S11.4); ω = k2 γ if nᵀe_p > 0, else k2(γ − sign(γ)π) (S11.6): the robot aligns with e_p or
    with −e_p, and reaches the origin backwards when the initial pointing error is obtuse.

    Companion i11_16: k1 = 1, k2 = 3, start (−1, −2, −π/2) (nᵀe_p = −2 < 0, obtuse), 10 s. Checked: backward
    motion throughout (v ≤ 0) to the origin, while the original law (11.78)–(11.79) turns around and drives
    forward; from an acute start (−1, −1, π/4) both laws give the same trajectory. Figs. S11.2 (the two laws
    from the obtuse start; the manual's S11.2 is the Simulink diagram) and S11.3.
    """
    sol = Solution()
    k1, k2 = sol.given("k1", 1.0), sol.given("k2", 3.0)
    sol.given("q(0)", Q0_COMPANION, unit="m, m, rad")
    mod = _regulate(CartesianRegulator(k1, k2, backward=True), Q0_COMPANION)
    orig = _regulate(CartesianRegulator(k1, k2), Q0_COMPANION)
    n_e0 = -(Q0_COMPANION[0] * np.cos(Q0_COMPANION[2]) + Q0_COMPANION[1] * np.sin(Q0_COMPANION[2]))
    sol.value("n_T_e_p_initial", float(n_e0), unit="m")
    sol.check_close("obtuse start: nᵀe_p(0) = −2", n_e0, -2.0, atol=1e-12, reference="closed form")
    sol.value("max_v_modified", float(mod.u[:, 0].max()), unit="m/s")
    sol.value("max_v_original", float(orig.u[:, 0].max()), unit="m/s")
    sol.value("final_distance_modified", float(np.hypot(*mod.x[-1, :2])), unit="m")
    sol.check("modified law: v ≤ 0 throughout (backward motion)", mod.u[:, 0].max() <= 1e-12,
              f"max v = {mod.u[:, 0].max():.2e} m/s")
    # With v ≤ 0 and the pointing error aligned, ρ̇ = −k1 ρ cos²(…) ⇒ ρ(t) ≤ ρ0 e^{...}: check against e^{−k1 t}
    # once aligned: nᵀe_p = −ρ cos(γ − π) … the distance decays at least like the aligned rate.
    rho = np.hypot(mod.x[:, 0], mod.x[:, 1])
    sol.check("modified law reaches the origin: ‖p(10 s)‖ < 1e-3 m, ρ non-increasing",
              rho[-1] < 1e-3 and np.all(np.diff(rho) <= 1e-12), f"‖p(10)‖ = {rho[-1]:.2e} m")
    sol.check("original law turns around and drives forward (max v > 0.5 m/s)", orig.u[:, 0].max() > 0.5,
              f"max v = {orig.u[:, 0].max():.2f} m/s")
    acute = sol.given("acute start", np.array([-1.0, -1.0, np.pi / 4]), unit="m, m, rad")
    a_mod, a_orig = _regulate(CartesianRegulator(k1, k2, True), acute), _regulate(CartesianRegulator(k1, k2), acute)
    sol.check_close("acute start (the modification leaves it alone): identical trajectories with both laws",
                    a_mod.x, a_orig.x, atol=0.0, reference="property")

    fig1, ax = subplots(figsize=(6.0, 5.0))
    ax.plot(orig.x[:, 0], orig.x[:, 1], label="original (11.78)–(11.79)")
    ax.plot(mod.x[:, 0], mod.x[:, 1], "--", label="modified (S11.4), (S11.6)")
    draw_unicycle(ax, *Q0_COMPANION)
    plane_axes(ax)
    sol.figure(fig1, "Fig. S11.2 (here) — the two regulators from an obtuse start")
    sol.figure(motion_figure(mod, "modified regulator"), "Fig. S11.3 — modified Cartesian regulator, k1 = 1, k2 = 3")
    from viewer.mobile import planar_body, plane_camera
    sol.animation(planar_body(0.3, 0.2, name="unicycle"), mod, "modified regulator: backwards to the origin (grey: "
                  "the original law's path)", fps=25, camera=plane_camera(np.vstack([mod.x[:, :2], orig.x[:, :2]])),
                  overlays=lambda s: (s.polyline("path", mod.x[::10, :2], "#1f77b4", radius=0.01),
                                      s.polyline("original_law_path", orig.x[::10, :2], "#7f7f7f", radius=0.006),
                                      s.frame("goal", np.eye(4), 0.3)))
    return sol


@problem("11.17", "Exact odometric integration (11.85) for piecewise-constant inputs", kind="derivation")
def problem_11_17() -> Solution:
    """θ(t) = θ_k + ω_k(t − t_k), x(t) = x_k + (v_k/ω_k)(sin θ(t) − sin θ_k), y(t) = y_k − (v_k/ω_k)(cos θ(t) − cos θ_k).

    Checked against the unicycle integrated by RK4 (h = T_s/1000) for random (v, ω, T_s); the ω → 0 branch
    against the straight-line limit; and the local errors of Euler (11.83) O(T_s²) and Runge–Kutta (11.84)
    O(T_s³) against the exact step.
    """
    sol = Solution()
    rng = _rng()
    worst = 0.0
    for _ in range(10):
        q0 = rng.normal(size=3)
        v, w, Ts = rng.uniform(-2, 2), rng.uniform(-3, 3), rng.uniform(0.05, 1.0)
        res = simulate(UnicyclePlant(), lambda t, x: np.array([v, w]), (0.0, Ts), q0, h=Ts / 1000, Ts=Ts)
        worst = max(worst, float(np.max(np.abs(odometry_step(q0, v, w, Ts, "exact") - res.x[-1]))))
    sol.check_error("exact step (11.85) = RK4 integration (10 random cases)", worst, 1e-10,
                    reference="second algorithm")
    q0 = sol.given("q_k (test posture)", np.array([0.3, -0.2, 0.4]), unit="m, m, rad")
    straight = q0 + np.array([1.5 * np.cos(0.4), 1.5 * np.sin(0.4), 0.0])
    sol.check_close("ω → 0: the exact step's limit branch gives the straight line (ω = 1e-12)",
                    odometry_step(q0, 1.5, 1e-12, 1.0, "exact"), straight, atol=1e-11, reference="closed form")
    sol.check_close("near the branch switch (ω = 1e-5) the arc formula agrees with the chord (RK) step to O((ωT)²)",
                    odometry_step(q0, 1.5, 1e-5, 1.0, "exact"), odometry_step(q0, 1.5, 1e-5, 1.0, "runge_kutta"),
                    atol=1e-10, reference="second algorithm")
    Tss = np.array([0.2, 0.1, 0.05])
    errs = {m: [np.linalg.norm(odometry_step(q0, 1.0, 2.0, T, m)[:2] - odometry_step(q0, 1.0, 2.0, T, "exact")[:2])
                for T in Tss] for m in ("euler", "runge_kutta")}
    orders = {m: float(np.mean(np.diff(np.log(e)) / np.diff(np.log(Tss)))) for m, e in errs.items()}
    sol.value("local_error_order", orders, unit="1")
    sol.check_close("local error orders (log–log slopes over T_s = 0.2, 0.1, 0.05 s): Euler (11.83) 2, Runge–Kutta "
                    "(11.84) 3", [orders["euler"], orders["runge_kutta"]], [2.0, 3.0], atol=0.1, reference="closed form")
    return sol


K_POSTURE = (1.0, 2.5, 3.0)   # i11_18
T_REGULATION = 10.0           # i11_18


def posture_with_odometry(Ts: float, q0: Any = Q0_COMPANION, t_end: float = T_REGULATION,
                          gains: tuple[float, float, float] = K_POSTURE, method: str = "runge_kutta") -> SimulationResult:
    """Posture regulation (11.81)–(11.82) fed by odometric localisation (11.84) of period T_s (Problem 11.18).

    Two blocks at two rates (Fig. S11.4): the :class:`~controllers.wheeled.Odometry` block reads the wheel
    encoders every T_s and holds its estimate; the regulator runs every T_s/n, n = ⌈T_s/0.01⌉ (at most the
    manual's 0.01 s), on the held estimate. The unicycle is integrated by RK4 with that step. Raises
    SimulationDiverged when the loop leaves |x_i| < 1e3.
    """
    n_sub = int(np.ceil(Ts / H - 1e-9))
    period = Ts / n_sub
    controller = Chain(ZeroOrderHold(Odometry(q0, method), Ts), PostureRegulator(*gains, feedback="estimate"),
                       name="estimate")
    return simulate(UnicyclePlant(odometer=True), controller, (0.0, t_end), np.r_[q0, 0.0, 0.0],
                    h=period, Ts=period, bound=1e3)


def posture_at(res: SimulationResult, t: float) -> np.ndarray:
    """The posture at t ≥ the last sample: the last command is held, so the robot runs an exact arc (11.85)."""
    return unicycle_arc(res.x[-1, :3], res.u[-1, 0], res.u[-1, 1], t - res.t[-1])


def final_distance(Ts: float, t_end: float = T_REGULATION) -> float:
    """‖p(t_end)‖ of the 11.18 loop with odometry period T_s (inf when the loop diverges)."""
    try:
        return float(np.hypot(*posture_at(posture_with_odometry(Ts, t_end=t_end), t_end)[:2]))
    except SimulationDiverged:
        return float("inf")


@problem("11.18", "Posture regulation with Runge–Kutta odometric localisation", kind="simulation")
def problem_11_18() -> Solution:
    """Posture regulator (11.81)–(11.82) acting on the odometric estimate (11.84) (Fig. S11.4).

    Companion i11_18: k = (1, 2.5, 3), start (−1, −2, −π/2), 10 s, odometry period T_s = 0.01 s (Fig. S11.5)
    and 0.1 s (Fig. S11.6); the regulator runs at T_s/⌈T_s/0.01 s⌉ on the estimate held between odometry
    samples, and the odometry integrates the wheel encoders' increments Δs, Δθ. Both converge; at 0.1 s the
    estimate is less accurate (the final distance is the odometric error). For larger T_s the final error
    grows and the loop eventually diverges: the T_s above which ‖p(10 s)‖ > 1e-2 m is found by bisection
    (Fig. S11.4 here: final distance against T_s). When the loop period does not divide 10 s, the posture at
    10 s is the exact arc (11.85) from the last sample under the held command.
    """
    sol = Solution()
    runs = {}
    sol.given("q(0)", Q0_COMPANION, unit="m, m, rad"), sol.given("k1, k2, k3", np.array(K_POSTURE))
    sol.given("T_s (two runs)", np.array([0.01, 0.1]), unit="s")
    for Ts, fig_name in ((0.01, "Fig. S11.5"), (0.1, "Fig. S11.6")):
        res = posture_with_odometry(Ts)
        runs[Ts] = res
        dist = float(np.hypot(*res.x[-1, :2]))
        est = float(np.linalg.norm(res["q_hat"][-1, :2]))
        odo_error = float(np.hypot(*(res.x[-1, :2] - res["q_hat"][-1, :2])))
        sol.value(f"final_distance_Ts_{Ts:g}", dist, unit="m")
        sol.value(f"final_heading_Ts_{Ts:g}", float(res.x[-1, 2]), unit="rad")
        sol.value(f"final_odometry_error_Ts_{Ts:g}", odo_error, unit="m")
        sol.check_bound(f"T_s = {Ts:g} s: estimate regulated to the origin: ‖p̂(10 s)‖ [m]", est, 1e-3)
        sol.figure(motion_figure(res, "unicycle", estimate=res["q_hat"]),
                   f"{fig_name} — posture regulation with Runge–Kutta odometry, T_s = {Ts:g} s")
    d01, d1 = sol.values["final_distance_Ts_0.01"], sol.values["final_distance_Ts_0.1"]
    e01, e1 = sol.values["final_odometry_error_Ts_0.01"], sol.values["final_odometry_error_Ts_0.1"]
    # At T_s = 0.01 s the regulator acts on an estimate that is the state of a perfectly localised robot: the
    # final distance (3e-4 m) is the regulator's own residual after 10 s, the odometric error (5e-5 m) is smaller.
    ideal = simulate(UnicyclePlant(), PostureRegulator(*K_POSTURE), (0.0, T_REGULATION), Q0_COMPANION, h=H, Ts=H)
    sol.value("final_distance_perfect_localisation", float(np.hypot(*ideal.x[-1, :2])), unit="m")
    sol.check_close("T_s = 0.01 s: the estimate q̂(10 s) = the final posture of the same regulator with perfect "
                    "localisation (the odometry is that accurate)", runs[0.01]["q_hat"][-1], ideal.x[-1], atol=1e-7,
                    reference="simulation vs prediction")
    sol.check_bound("T_s = 0.01 s: the odometric error is below the regulator's residual (error / ‖p(10 s)‖)",
                    e01 / d01, 0.25, detail=f"error {e01:.2e} m, ‖p‖ = {d01:.2e} m")
    sol.check_close("T_s = 0.1 s: the final distance is the odometric error (the regulator converged on the "
                    "estimate) [m]", d1, e1, rtol=0.05, reference="simulation vs prediction")
    sol.check("T_s = 0.01 s: ‖p(10 s)‖ < 1e-3 m and |θ| < 1e-2 rad",
              d01 < 1e-3 and abs(sol.values["final_heading_Ts_0.01"]) < 1e-2, f"‖p‖ = {d01:.2e} m")
    sol.check("T_s = 0.1 s: ‖p(10 s)‖ < 2e-2 m, less accurate than 0.01 s", d1 < 2e-2 and d1 > d01, f"‖p‖ = {d1:.2e} m")
    from viewer.mobile import planar_body, plane_camera
    p, p_hat = runs[0.1].x[::10, :2], runs[0.1]["q_hat"][::10, :2]  # every 0.1 s: tubes of a few segments
    sol.animation(planar_body(0.3, 0.2, name="unicycle"), runs[0.1], "T_s = 0.1 s: the unicycle and its odometric "
                  "estimate (green)", fps=25, camera=plane_camera(p),
                  overlays=lambda s: (s.polyline("path", p, "#1f77b4", radius=0.01),
                                      s.polyline("odometric_estimate", p_hat, "#2ca02c", radius=0.006),
                                      s.frame("goal", np.eye(4), 0.3)))
    # The simulated unicycle against the exact arcs (11.85) of the logged (held) inputs, step by step.
    res = runs[0.1]
    q_exact = res.x[0, :3].copy()
    for dt, u in zip(np.diff(res.t), res.u[:-1]):
        q_exact = odometry_step(q_exact, u[0], u[1], dt, "exact")
    sol.check_close("exact arc integration (11.85) of the logged inputs = the simulated unicycle (T_s = 0.1 s)",
                    q_exact[:2], res.x[-1, :2], atol=1e-6, reference="second algorithm")
    # The odometry block against the encoders' increments done by hand, (11.84) at every 0.1 s sample.
    q_hat = res.x[0, :3].copy()
    for k in range(10, len(res.t), 10):
        ds, dpsi = res["distance"][k] - res["distance"][k - 10], res["rotation"][k] - res["rotation"][k - 10]
        q_hat = np.array([q_hat[0] + ds * np.cos(q_hat[2] + dpsi / 2), q_hat[1] + ds * np.sin(q_hat[2] + dpsi / 2),
                          q_hat[2] + dpsi])
    sol.check_close("odometry block = (11.84) on the encoder increments Δs, Δθ (T_s = 0.1 s, final p̂)",
                    q_hat[:2], res["q_hat"][-1, :2], atol=1e-12, reference="closed form")

    grid = np.array([0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0])
    finals = np.array([final_distance(Ts) for Ts in grid])
    sol.value("Ts_grid", grid, unit="s")
    sol.value("final_distance_grid", finals, unit="m")
    sol.check("final error increases with T_s up to 0.5 s (degradation)", np.all(np.diff(finals[:7]) > 0),
              str(np.round(finals, 4)))
    sol.check("large T_s destabilises the loop: ‖p‖ > 1 m (or divergence) at T_s = 1 s", finals[-1] > 1.0,
              f"‖p‖ = {finals[-1]:.3g} m")
    lo, hi = 0.1, 0.2  # ‖p‖ < 1e-2 at 0.1, > 1e-2 at 0.2 (grid above)
    if not (final_distance(lo) < 1e-2 < final_distance(hi)):
        sol.check("bisection bracket [0.1, 0.2] s valid", False)
        return sol
    while hi - lo > 1e-4:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if final_distance(mid) <= 1e-2 else (lo, mid)
    sol.value("Ts_threshold", 0.5 * (lo + hi), unit="s")
    sol.check("bisection: ‖p(10 s)‖ crosses 1e-2 m between 0.1 and 0.2 s",
              final_distance(lo) <= 1e-2 < final_distance(hi), f"T_s* = {0.5 * (lo + hi):.4f} s")

    fig, ax = subplots(figsize=(6.0, 4.0))
    ax.semilogy(grid, np.minimum(finals, 1e3), "o-", label="‖p(t_f)‖")
    ax.axhline(1e-2, color="k", ls=":", label="1e-2 m")
    ax.axvline(0.5 * (lo + hi), color="C3", ls="--", label=f"T_s* = {0.5 * (lo + hi):.3f} s")
    label_axes(ax, "odometry sampling period T_s [s]", "final distance ‖p‖ [m]")
    sol.figure(fig, "Final error against T_s (replaces the Simulink diagram S11.4)")
    return sol
