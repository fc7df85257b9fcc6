"""Kinematic models of wheeled mobile robots (Chapter 11): the models are the mathematics.

A wheeled robot subject to k Pfaffian constraints A^T(q) q̇ = 0 moves as the driftless system
q̇ = G(q) u, where the columns of G(q) span the null space of A^T(q) (11.10). This module gives

* the **unicycle** (11.13) and the **differential drive** (11.14) with its wheel-speed limits and the
  admissible rhombus of (v, ω) (Problem 11.9);
* the **bicycle** with rear- (11.19) or front-wheel drive (11.20), its instantaneous centre of
  rotation (Problem 11.7) and the front-wheel point used for input–output linearisation (Problem 11.15);
* the **tricycle with N trailers** (Problems 11.1, 11.8): constraint matrix A(q) and input matrix G(q);
* **Lie brackets** (finite differences and sympy) and the **accessibility rank condition** (11.11);
* the **(2, n) chained form** (11.25) and the unicycle ↔ (2, 3) transformation (11.23)–(11.24);
* the **mobile manipulator**: a unicycle base carrying an arm as one Pinocchio model with a planar root
  joint (:func:`mobile_manipulator`) and its input map (:func:`mobile_manipulator_input_matrix`).

Conventions: a constraint matrix ``A`` is returned as the k×n matrix of the rows a_i^T(q) (i.e. the
book's A^T(q)), so that "A G = 0" reads ``A @ G == 0``. Postures are (x, y, θ) [m, m, rad].

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Sects. 11.1–11.3,
Eqs. (11.1)–(11.25); solution manual, Problems 11.1–11.9.
"""

from __future__ import annotations

import math
from typing import Any, Callable, Sequence

import numpy as np

import pinocchio as pin

from rigid_body.robots import Robot
from rigid_body.validation import as_positive, as_vector

__all__ = [
    "unicycle_input_matrix", "unicycle_constraint", "unicycle_velocity", "unicycle_arc",
    "differential_drive_velocities", "differential_drive_wheel_speeds", "differential_drive_admissible",
    "differential_drive_limits", "saturate_wheel_speeds",
    "bicycle_input_matrix", "bicycle_constraints", "bicycle_icr", "front_wheel_point",
    "front_wheel_point_matrix",
    "trailer_configuration_size", "trailer_angle_indices", "trailer_constraints", "trailer_input_matrix",
    "trailer_axle_midpoints",
    "trailer_input_function", "null_space", "lie_bracket", "lie_bracket_symbolic", "accessibility_rank",
    "accessibility_fields_symbolic",
    "chained_form_velocity", "unicycle_to_chained", "chained_to_unicycle", "chained_inputs_to_unicycle",
    "unicycle_inputs_to_chained", "mobile_manipulator", "mobile_manipulator_input_matrix",
]


def _posture(q: Any, n: int, name: str = "q") -> np.ndarray:
    return as_vector(q, n, name)


# --------------------------------------------------------------------------------------------
# Unicycle and differential drive, (11.12)–(11.14)
# --------------------------------------------------------------------------------------------

def unicycle_constraint(q: Any) -> np.ndarray:
    """The unicycle's Pfaffian constraint a^T(q) = [sin θ, −cos θ, 0] (11.12), as a (1, 3) matrix."""
    th = _posture(q, 3)[2]
    return np.array([[np.sin(th), -np.cos(th), 0.0]])


def unicycle_input_matrix(q: Any) -> np.ndarray:
    """G(q) = [g1 g2] of the unicycle (11.13): g1 = [cos θ, sin θ, 0] (driving), g2 = [0, 0, 1] (steering)."""
    th = _posture(q, 3)[2]
    return np.array([[np.cos(th), 0.0], [np.sin(th), 0.0], [0.0, 1.0]])


def unicycle_velocity(q: np.ndarray, u: np.ndarray) -> np.ndarray:
    """q̇ = [v cos θ, v sin θ, ω] (11.13) for q = (x, y, θ), u = (v, ω); unchecked (hot loop)."""
    v, th = u[0], float(q[2])
    return np.array([v * math.cos(th), v * math.sin(th), u[1]])


def unicycle_arc(q: np.ndarray, v: float, omega: float, t: float) -> np.ndarray:
    """Exact solution of (11.13) under constant (v, ω) for a time t (Problem 11.17, (11.85)): an arc of circle.

    θ(t) = θ + ωt, x(t) = x + (v/ω)(sin θ(t) − sin θ), y(t) = y − (v/ω)(cos θ(t) − cos θ); for |ωt| < 1e-9 the
    chord formula x + vt cos(θ + ωt/2) (its limit, exact to O((ωt)²) relative). Unchecked (used in loops).
    """
    x, y, th = q[0], q[1], q[2]
    dth = omega * t
    if abs(dth) < 1e-9:
        return np.array([x + v * t * np.cos(th + dth / 2), y + v * t * np.sin(th + dth / 2), th + dth])
    return np.array([x + v / omega * (np.sin(th + dth) - np.sin(th)), y - v / omega * (np.cos(th + dth) - np.cos(th)),
                     th + dth])


def differential_drive_velocities(omega_R: Any, omega_L: Any, r: float, d: float) -> tuple[Any, Any]:
    """Unicycle inputs of a differential drive (11.14): v = r(ω_R + ω_L)/2, ω = r(ω_R − ω_L)/d.

    ``r`` is the wheel radius [m], ``d`` the distance between the wheel centres [m]; wheel speeds [rad/s].
    """
    r, d = as_positive(r, "r"), as_positive(d, "d")
    wR, wL = np.asarray(omega_R, dtype=float), np.asarray(omega_L, dtype=float)
    return r * (wR + wL) / 2.0, r * (wR - wL) / d


def differential_drive_wheel_speeds(v: Any, omega: Any, r: float, d: float) -> tuple[Any, Any]:
    """The inverse of (11.14) (Problem 11.9): ω_R = (2v + dω)/(2r), ω_L = (2v − dω)/(2r)."""
    r, d = as_positive(r, "r"), as_positive(d, "d")
    v, omega = np.asarray(v, dtype=float), np.asarray(omega, dtype=float)
    return (2.0 * v + d * omega) / (2.0 * r), (2.0 * v - d * omega) / (2.0 * r)


def differential_drive_limits(r: float, d: float, omega_RL: float) -> tuple[float, float]:
    """Vertices of the admissible rhombus (Problem 11.9): v_max = r ω_RL [m/s], ω_max = 2 r ω_RL / d [rad/s]."""
    r, d, w = as_positive(r, "r"), as_positive(d, "d"), as_positive(omega_RL, "omega_RL")
    return r * w, 2.0 * r * w / d


def differential_drive_admissible(v: Any, omega: Any, r: float, d: float, omega_RL: float) -> Any:
    """True where (v, ω) is admissible: |v|/v_max + |ω|/ω_max ≤ 1 (the rhombus of Problem 11.9)."""
    v_max, w_max = differential_drive_limits(r, d, omega_RL)
    return np.abs(v) / v_max + np.abs(omega) / w_max <= 1.0 + 1e-12


def saturate_wheel_speeds(v: float, omega: float, r: float, d: float, omega_RL: float) -> tuple[float, float]:
    """(v, ω) scaled by one factor into the admissible rhombus: the path curvature ω/v is kept.

    Both wheel speeds are divided by max(1, max(|ω_R|, |ω_L|)/ω_RL), the usual way a differential drive
    meets its wheel-speed bound without changing the direction of motion.
    """
    v_max, w_max = differential_drive_limits(r, d, omega_RL)
    excess = abs(v) / v_max + abs(omega) / w_max  # = max(|ω_R|, |ω_L|)/ω_RL
    if excess <= 1.0:
        return float(v), float(omega)
    return float(v) / excess, float(omega) / excess


# --------------------------------------------------------------------------------------------
# Bicycle, (11.15)–(11.20), Problems 11.7 and 11.15
# --------------------------------------------------------------------------------------------

def bicycle_constraints(q: Any, ell: float) -> np.ndarray:
    """The two Pfaffian constraints (11.15)–(11.16) of a bicycle, q = (x, y, θ, φ), (x, y) the rear contact point.

    Front wheel: ẋ sin(θ+φ) − ẏ cos(θ+φ) − ℓ θ̇ cos φ = 0; rear wheel: ẋ sin θ − ẏ cos θ = 0. Returns (2, 4).
    """
    x, y, th, phi = _posture(q, 4)
    ell = as_positive(ell, "ell")
    return np.array([[np.sin(th + phi), -np.cos(th + phi), -ell * np.cos(phi), 0.0],
                     [np.sin(th), -np.cos(th), 0.0, 0.0]])


def bicycle_input_matrix(q: Any, ell: float, drive: str = "rear") -> np.ndarray:
    """G(q) of the bicycle: rear-wheel drive (11.19) or front-wheel drive (11.20); inputs (v, ω = φ̇).

    rear:  g1 = [cos θ, sin θ, tan φ/ℓ, 0];   front: g1 = [cos θ cos φ, sin θ cos φ, sin φ/ℓ, 0];   g2 = e_4.
    """
    x, y, th, phi = _posture(q, 4)
    ell = as_positive(ell, "ell")
    if drive == "rear":
        g1 = [np.cos(th), np.sin(th), np.tan(phi) / ell, 0.0]
    elif drive == "front":
        g1 = [np.cos(th) * np.cos(phi), np.sin(th) * np.cos(phi), np.sin(phi) / ell, 0.0]
    else:
        raise ValueError(f"`drive` must be 'rear' or 'front', got {drive!r}")
    return np.column_stack([g1, [0.0, 0.0, 0.0, 1.0]])


def bicycle_icr(q: Any, ell: float) -> np.ndarray:
    """Instantaneous centre of rotation C = (x − ℓ sin θ / tan φ, y + ℓ cos θ / tan φ) (Problem 11.7).

    It lies on the rear-axle line at (0, ℓ/tan φ) in the body frame; ValueError for φ = 0 (C at infinity).
    """
    x, y, th, phi = _posture(q, 4)
    ell = as_positive(ell, "ell")
    if abs(np.tan(phi)) < 1e-12:
        raise ValueError("`q`: the steering angle φ is zero, the centre of rotation is at infinity")
    R = ell / np.tan(phi)
    return np.array([x - R * np.sin(th), y + R * np.cos(th)])


def front_wheel_point(q: Any, ell: float, b: float) -> np.ndarray:
    """The output of Problem 11.15: y = [x + ℓ cos θ + b cos(θ+φ), y + ℓ sin θ + b sin(θ+φ)].

    A point at distance |b| from the front contact point on the line of the front wheel.
    """
    x, y, th, phi = _posture(q, 4)
    return np.array([x + ell * np.cos(th) + b * np.cos(th + phi), y + ell * np.sin(th) + b * np.sin(th + phi)])


def front_wheel_point_matrix(theta: float, phi: float, ell: float, b: float) -> np.ndarray:
    """T(θ, φ) with ẏ = T [v, ω]^T for the rear-drive bicycle (11.19) (Problem 11.15); det T = b / cos φ."""
    s, c = np.sin(theta), np.cos(theta)
    s2, c2 = np.sin(theta + phi), np.cos(theta + phi)
    t = np.tan(phi)
    return np.array([[c - t * (s + b * s2 / ell), -b * s2],
                     [s + t * (c + b * c2 / ell), b * c2]])


# --------------------------------------------------------------------------------------------
# Tricycle with N trailers, Problems 11.1 and 11.8
# --------------------------------------------------------------------------------------------

def trailer_configuration_size(N: int) -> int:
    """n = N + 4: q = [x, y, φ, θ_0, θ_1, …, θ_N] ∈ R² × SO(2)^{N+2} (Problem 11.1)."""
    if int(N) != N or N < 0:
        raise ValueError(f"`N` must be a non-negative number of trailers, got {N}")
    return int(N) + 4


def trailer_angle_indices(N: int) -> list[int]:
    """Indices of the angular coordinates φ, θ_0, …, θ_N of the N-trailer configuration (wrap these only)."""
    return list(range(2, trailer_configuration_size(N)))


def _trailer_args(q: Any, ell: float, lengths: Sequence[float]) -> tuple[np.ndarray, float, np.ndarray]:
    lengths = as_vector(lengths, None, "lengths") if len(lengths) else np.zeros(0)
    if np.any(lengths <= 0):
        raise ValueError(f"`lengths` (hinge-to-hinge ℓ_i) must be positive, got {lengths}")
    q = as_vector(q, trailer_configuration_size(len(lengths)), "q")
    return q, as_positive(ell, "ell"), lengths


def trailer_axle_midpoints(q: Any, ell: float, lengths: Sequence[float]) -> np.ndarray:
    """(N+2, 2): front wheel (x + ℓ cos θ0, …), rear axle (x, y), then trailer axles x − Σ_{j≤i} ℓ_j cos θ_j, …"""
    q, ell, lengths = _trailer_args(q, ell, lengths)
    x, y, th = q[0], q[1], q[3:]
    points = [[x + ell * np.cos(th[0]), y + ell * np.sin(th[0])], [x, y]]
    for i in range(1, len(lengths) + 1):
        points.append([x - np.sum(lengths[:i] * np.cos(th[1:i + 1])), y - np.sum(lengths[:i] * np.sin(th[1:i + 1]))])
    return np.array(points)


def trailer_constraints(q: Any, ell: float, lengths: Sequence[float]) -> np.ndarray:
    """The N + 2 Pfaffian constraints of the tricycle with N trailers (Problem 11.8), as an (N+2, N+4) matrix.

    ẋ sin(θ0+φ) − ẏ cos(θ0+φ) − ℓ θ̇0 cos φ = 0;  ẋ sin θ0 − ẏ cos θ0 = 0;
    ẋ sin θ_i − ẏ cos θ_i + Σ_{j≤i} ℓ_j θ̇_j cos(θ_i − θ_j) = 0,  i = 1…N.
    """
    q, ell, lengths = _trailer_args(q, ell, lengths)
    N = len(lengths)
    phi, th = q[2], q[3:]
    A = np.zeros((N + 2, N + 4))
    A[0, :4] = [np.sin(th[0] + phi), -np.cos(th[0] + phi), 0.0, -ell * np.cos(phi)]
    A[1, :2] = [np.sin(th[0]), -np.cos(th[0])]
    for i in range(1, N + 1):
        A[i + 1, :2] = [np.sin(th[i]), -np.cos(th[i])]
        for j in range(1, i + 1):
            A[i + 1, 3 + j] = lengths[j - 1] * np.cos(th[i] - th[j])
    return A


def trailer_input_matrix(q: Any, ell: float, lengths: Sequence[float]) -> np.ndarray:
    """G(q) = [g1 g2] of the tricycle with N trailers (Problem 11.8); inputs v (rear wheels), ω = φ̇.

    g1 = [cos θ0, sin θ0, 0, tan φ/ℓ, …, −(1/ℓ_i) Π_{j<i} cos(θ_j − θ_{j−1}) sin(θ_i − θ_{i−1}), …], g2 = e_3.
    """
    return _trailer_input(*_trailer_args(q, ell, lengths))


def trailer_input_function(ell: float, lengths: Sequence[float]) -> Callable[[np.ndarray], np.ndarray]:
    """``q -> G(q)`` of :func:`trailer_input_matrix` with ℓ and the ℓ_i checked once: for simulation hot
    loops (``controllers.plants.DriftlessPlant``), whose q (N + 4,) comes from the loop unchecked."""
    _, ell, lengths = _trailer_args(np.zeros(trailer_configuration_size(len(lengths))), ell, lengths)
    return lambda q: _trailer_input(q, ell, lengths)


def _trailer_input(q: np.ndarray, ell: float, lengths: np.ndarray) -> np.ndarray:
    N = len(lengths)
    phi, th = q[2], q[3:].tolist()
    G = np.zeros((N + 4, 2))
    G[:4, 0] = [math.cos(th[0]), math.sin(th[0]), 0.0, math.tan(phi) / ell]
    speed = 1.0  # v_{i−1}/v: the hitch speed of trailer i, Π_{j<i} cos(θ_j − θ_{j−1})
    for i in range(1, N + 1):
        G[3 + i, 0] = -speed * math.sin(th[i] - th[i - 1]) / lengths[i - 1]
        speed *= math.cos(th[i] - th[i - 1])
    G[2, 1] = 1.0                                             # g2 = e_3
    return G


# --------------------------------------------------------------------------------------------
# Null spaces, Lie brackets, accessibility (Sect. 11.2, Appendix D)
# --------------------------------------------------------------------------------------------

def null_space(A: Any, tol: float = 1e-10) -> np.ndarray:
    """An orthonormal basis (n, n − rank A) of N(A) by SVD: the input matrix G of a constraint matrix A (11.10)."""
    A = np.atleast_2d(np.asarray(A, dtype=float))
    if not np.all(np.isfinite(A)):
        raise ValueError("`A` must be finite")
    _, s, Vt = np.linalg.svd(A)
    rank = int(np.sum(s > tol * max(1.0, s[0] if s.size else 0.0)))
    return Vt[rank:].T.copy()


VectorField = Callable[[np.ndarray], np.ndarray]


def lie_bracket(f: VectorField, g: VectorField, q: Any, eps: float = 1e-5) -> np.ndarray:
    """[f, g](q) = (∂g/∂q) f(q) − (∂f/∂q) g(q) (Sect. 11.2.1), directional derivatives by central differences.

    ``f``, ``g`` map a configuration (n,) to a vector (n,); the error is O(eps²).
    """
    q = as_vector(q, None, "q")
    fq, gq = np.asarray(f(q), dtype=float), np.asarray(g(q), dtype=float)
    dg_f = (np.asarray(g(q + eps * fq)) - np.asarray(g(q - eps * fq))) / (2 * eps)
    df_g = (np.asarray(f(q + eps * gq)) - np.asarray(f(q - eps * gq))) / (2 * eps)
    return dg_f - df_g


def accessibility_rank(fields: Sequence[VectorField], q: Any, depth: int = 2, eps: float = 1e-4,
                       tol: float = 1e-6) -> int:
    """Rank at q of the accessibility distribution (11.11) spanned by the fields and their brackets up to ``depth``.

    depth 1 = the fields, 2 adds [g_i, g_j], 3 adds [g_k, [g_i, g_j]], … (finite-difference brackets).
    The system is controllable (driftless case) when the rank equals n.
    """
    q = as_vector(q, None, "q")
    if depth < 1:
        raise ValueError(f"`depth` must be at least 1, got {depth}")
    level: list[VectorField] = list(fields)
    columns = [np.asarray(g(q), dtype=float) for g in level]
    for _ in range(depth - 1):
        new: list[VectorField] = []
        for a in fields:
            for b in level:
                new.append(lambda x, a=a, b=b: lie_bracket(a, b, x, eps))
        columns += [h(q) for h in new]
        level = new
    M = np.column_stack(columns)
    s = np.linalg.svd(M, compute_uv=False)
    return int(np.sum(s > tol * max(1.0, s[0])))


def lie_bracket_symbolic(f: Any, g: Any, q: Sequence[Any]) -> Any:
    """[f, g] = (∂g/∂q) f − (∂f/∂q) g with sympy (column matrices ``f``, ``g``, symbols ``q``)."""
    import sympy as sp

    f, g = sp.Matrix(f), sp.Matrix(g)
    return sp.simplify(g.jacobian(list(q)) * f - f.jacobian(list(q)) * g)


def accessibility_fields_symbolic(fields: Sequence[Any], q: Sequence[Any], depth: int = 2) -> list[Any]:
    """The fields and their iterated brackets [g_k, [… ]] up to ``depth`` (sympy), spanning Δ_A (11.11)."""
    import sympy as sp

    level = [sp.Matrix(g) for g in fields]
    out = list(level)
    for _ in range(depth - 1):
        level = [lie_bracket_symbolic(a, b, q) for a in out[:len(fields)] for b in level]
        out += level
    return out


# --------------------------------------------------------------------------------------------
# Chained form, (11.23)–(11.25)
# --------------------------------------------------------------------------------------------

def chained_form_velocity(z: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(2, n) chained form (11.25): ż1 = v1, ż2 = v2, ż_k = z_{k−1} v1 (k = 3…n); unchecked (hot loop)."""
    zd = np.empty_like(z, dtype=float)
    zd[0], zd[1] = v[0], v[1]
    zd[2:] = z[1:-1] * v[0]
    return zd


def unicycle_to_chained(q: Any) -> np.ndarray:
    """z = (θ, x cos θ + y sin θ, x sin θ − y cos θ): the unicycle in (2, 3) chained form (11.23)."""
    x, y, th = _posture(q, 3)
    return np.array([th, x * np.cos(th) + y * np.sin(th), x * np.sin(th) - y * np.cos(th)])


def chained_to_unicycle(z: Any) -> np.ndarray:
    """Inverse of (11.23): θ = z1, x = z2 cos z1 + z3 sin z1, y = z2 sin z1 − z3 cos z1."""
    z1, z2, z3 = _posture(z, 3, "z")
    return np.array([z2 * np.cos(z1) + z3 * np.sin(z1), z2 * np.sin(z1) - z3 * np.cos(z1), z1])


def chained_inputs_to_unicycle(z: Any, v: Any) -> np.ndarray:
    """(v, ω) = (v2 + z3 v1, v1), the input transformation (11.24)."""
    z, v = _posture(z, 3, "z"), _posture(v, 2, "v")
    return np.array([v[1] + z[2] * v[0], v[0]])


def unicycle_inputs_to_chained(z: Any, u: Any) -> np.ndarray:
    """(v1, v2) = (ω, v − z3 ω), the inverse of (11.24)."""
    z, u = _posture(z, 3, "z"), _posture(u, 2, "u")
    return np.array([u[1], u[0] - z[2] * u[1]])


# --------------------------------------------------------------------------------------------
# The mobile manipulator: a unicycle base carrying an arm (one Pinocchio model)
# --------------------------------------------------------------------------------------------

def mobile_manipulator(arm: Robot, mount: Any = (0.0, 0.0, 0.3), base_mass: float = 20.0,
                       base_size: Any = (0.6, 0.4, 0.2)) -> Robot:
    """A unicycle base carrying ``arm`` (e.g. ``load("anthropomorphic_wrist")``) as ONE Pinocchio model.

    The root joint is planar (``pin.JointModelPlanar``: configuration (x, y, cos θ, sin θ), velocity the
    base's body twist (v_x, v_y, ω), so nq = nv + 1); the arm's model is appended at the frame
    ``base_link`` with its base frame at ``mount`` [m] above the wheel axle midpoint. The base is a box
    of ``base_mass`` [kg] and ``base_size`` [m]. The configuration space has dimension nv = 3 + n_arm.
    The end-effector frame is the arm's. No geometry (the models are for kinematics and control).
    """
    if arm.nq != arm.nv:
        raise ValueError(f"`arm` must have nq = nv (revolute/prismatic joints), got nq = {arm.nq}, nv = {arm.nv}")
    mount = as_vector(mount, 3, "mount")
    size = as_vector(base_size, 3, "base_size")
    base = pin.Model()
    base.name = "unicycle_base"
    base.gravity = arm.model.gravity
    jid = base.addJoint(0, pin.JointModelPlanar(), pin.SE3.Identity(), "base_planar")
    base.appendBodyToJoint(jid, pin.Inertia.FromBox(as_positive(base_mass, "base_mass"), *size),
                           pin.SE3(np.eye(3), np.array([0.0, 0.0, size[2] / 2])))
    fid = base.addBodyFrame("base_link", jid, pin.SE3.Identity(), 0)
    model = pin.appendModel(base, arm.model, fid, pin.SE3(np.eye(3), mount))
    model.name = f"mobile_{arm.name}"
    ee = model.getFrameId(arm.model.frames[arm.ee_frame].name)
    robot = Robot(name=model.name, model=model, data=model.createData(), ee_frame=ee)
    robot.configurations["neutral"] = pin.neutral(model)
    return robot


def mobile_manipulator_input_matrix(robot: Robot) -> np.ndarray:
    """Γ = [G 0; 0 I] (nv, 2 + n_arm): the unicycle's (v, ω) and the arm's q̇ to the model's velocity.

    In Pinocchio's tangent space of the planar root joint the base velocity is its body twist (v_x, v_y, ω);
    the no-slip constraint (11.12) is v_y = 0, so G = [e_x, e_ω] is constant (in world coordinates it is the
    unicycle's G(q) of (11.13): ẋ = v cos θ, ẏ = v sin θ, θ̇ = ω).
    """
    model = robot.model
    if model.njoints < 2 or model.joints[1].shortname() != "JointModelPlanar":
        raise ValueError(f"`robot` {robot.name!r} must have a planar root joint (see mobile_manipulator)")
    n_arm = model.nv - 3
    Gamma = np.zeros((model.nv, 2 + n_arm))
    Gamma[0, 0] = Gamma[2, 1] = 1.0
    Gamma[3:, 2:] = np.eye(n_arm)
    return Gamma
