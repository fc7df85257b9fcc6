"""Direct kinematics and the geometric Jacobian on any :class:`~rigid_body.robots.Robot`.

Conventions: the book's geometric Jacobian ``J = [J_P; J_O]`` (linear velocity of the frame origin
and angular velocity, both in the base frame, Eq. (3.4)) is Pinocchio's ``LOCAL_WORLD_ALIGNED``
frame Jacobian. Frames are given by name or id; the default is the robot's end effector.
Returned arrays are new arrays, never views of ``robot.data`` (which the next call overwrites): Pinocchio 4's
bindings return copies, checked by tests/rigid_body/test_wrapper_fast_paths.py.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 2.8–2.12 (direct and inverse kinematics), 3.1–3.3 (geometric Jacobian).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from math import isfinite
from typing import Any, Sequence

import numpy as np
import pinocchio as pin

from rigid_body.book_robots import book_robot_spec
from rigid_body.dh import DHLink, as_links, dh_chain
from rigid_body.robots import Robot, model_frame_id
from rigid_body.rotations import (as_homogeneous, as_rotation, euler_rate_matrix_rpy, euler_rate_matrix_zyz, rot_z,
                                  rotation_to_euler_zyz, rotation_to_rpy, wrap_angle)
from rigid_body.validation import as_count, as_scalar, as_tolerance, as_vector

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def direct_kinematics(robot: Robot, q: np.ndarray, frame: str | int | None = None) -> np.ndarray:
    """T_e^0(q): (4, 4) pose of ``frame`` (default the end effector) in the base frame, Eq. (2.50)."""
    model = robot.model
    fid = robot.ee_frame if frame is None else model_frame_id(model, frame)
    try:  # fast path, as in rigid_body.dynamics: a 1-D numeric q with a finite sum; Pinocchio checks the size
        if isfinite(sum(q.tolist())):
            data = robot._local.data
            pin.forwardKinematics(model, data, q)
            return pin.updateFramePlacement(model, data, fid).homogeneous  # a new array
    except Exception:
        pass
    data = robot.data
    pin.forwardKinematics(model, data, as_vector(q, model.nq, "q"))
    return pin.updateFramePlacement(model, data, fid).homogeneous


def frame_poses(robot: Robot, q: np.ndarray, frames: list[str | int]) -> list[np.ndarray]:
    """Poses (4×4) of several frames at ``q`` with one forward-kinematics pass."""
    q = as_vector(q, robot.nq, "q")
    pin.framesForwardKinematics(robot.model, robot.data, q)
    return [robot.data.oMf[robot.frame(f)].homogeneous for f in frames]  # new arrays


def geometric_jacobian(robot: Robot, q: np.ndarray, frame: str | int | None = None) -> np.ndarray:
    """J(q) = [J_P; J_O], (6, nv): book convention (Pinocchio LOCAL_WORLD_ALIGNED), Eq. (3.30)."""
    model = robot.model
    fid = robot.ee_frame if frame is None else model_frame_id(model, frame)
    try:  # fast path, as in rigid_body.dynamics
        if isfinite(sum(q.tolist())):
            return pin.computeFrameJacobian(model, robot._local.data, q, fid, LWA)  # a new array
    except Exception:
        pass
    return pin.computeFrameJacobian(model, robot.data, as_vector(q, model.nq, "q"), fid, LWA)


def jacobian_derivative_times_qd(robot: Robot, q: np.ndarray, qd: np.ndarray,
                                 frame: str | int | None = None) -> np.ndarray:
    """J̇(q, q̇) q̇ (6,): the end-effector acceleration at q̈ = 0 (book convention), cf. Eq. (3.29)/(7.132).

    The linear part is the classical acceleration of the frame origin (it includes ω × v).
    """
    q = as_vector(q, robot.nq, "q")
    qd = as_vector(qd, robot.nv, "qd")
    fid = robot.frame(frame)
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q, qd, np.zeros(model.nv))
    pin.updateFramePlacements(model, data)
    a = pin.getFrameClassicalAcceleration(model, data, fid, LWA)
    return np.concatenate([a.linear, a.angular])


def revolute_joints(robot: Robot) -> np.ndarray:
    """Boolean mask (n,) of the revolute joints (whose angles may be shifted by 2π)."""
    return np.array([j.shortname().startswith(("JointModelR", "JointModelRevolute")) for j in robot.model.joints[1:]])


def end_effector_velocity(robot: Robot, q: np.ndarray, qd: np.ndarray,
                          frame: str | int | None = None) -> np.ndarray:
    """v_e = J(q) q̇ = [ṗ_e; ω_e] (6,), Eq. (3.2)."""
    return geometric_jacobian(robot, q, frame) @ as_vector(qd, robot.nv, "qd")


# --------------------------------------------------------------------------------------------
# Analytical Jacobian (Chapter 3)
# --------------------------------------------------------------------------------------------

def analytical_jacobian(robot: Robot, q: np.ndarray, representation: str = "zyz",
                        frame: str | int | None = None) -> np.ndarray:
    """J_A(q) = T_A^{-1}(φ_e) J(q), (6, nv): ẋ_e = [ṗ_e; φ̇_e] for Euler angles φ_e, Eqs. (3.64)–(3.66).

    ``representation`` is ``"zyz"`` (T from (3.64)) or ``"rpy"`` (Problem 3.12); φ_e is extracted
    with ``branch=+1``. ValueError at a representation singularity (sin θ = 0 for ZYZ, cos θ = 0 for RPY).
    """
    pair = {"zyz": (rotation_to_euler_zyz, euler_rate_matrix_zyz),
            "rpy": (rotation_to_rpy, euler_rate_matrix_rpy)}.get(representation)
    if pair is None:
        raise ValueError(f"`representation` must be 'zyz' or 'rpy', got {representation!r}")
    J = geometric_jacobian(robot, q, frame)
    phi = pair[0](direct_kinematics(robot, q, frame)[:3, :3])
    if phi.singular:
        raise ValueError(f"{representation.upper()} representation singularity at q = {q}: T(φ) is not invertible")
    J[3:] = np.linalg.solve(pair[1](phi.angles), J[3:])
    return J


# --------------------------------------------------------------------------------------------
# Closed-form inverse kinematics (Sect. 2.12)
# --------------------------------------------------------------------------------------------
# Each solver takes the arm's geometry as a DH table ``links`` (a user's arm of the same structure:
# the book's joint types and twists α, zero offsets θ, and zero lengths where the book's arm has them;
# the free lengths are read from the table). Without ``links`` it uses the book's table
# (:mod:`rigid_body.book_robots`) with the same keyword parameters as ``load(name, **params)``, so
# ``load("anthropomorphic", a2=0.6)`` and ``inverse_kinematics_anthropomorphic(p, a2=0.6)`` describe the
# same arm. Each returns a (k, n) array of solutions, one per row, revolute angles wrapped into (−π, π].
# Before returning, every solution is checked against the DH product (2.52): a pose that cannot be
# reached raises a ValueError that says so, and a solution is never returned with a residual above IK_TOL.
# Where the table gives joint limits (``lower``/``upper``), rows outside them are dropped (a revolute angle
# is first shifted by a multiple of 2π into its range when one fits); no row left → ValueError
# "unreachable within the joint limits". The row order constants then index the rows that remain.

IK_TOL = 1e-9  # max pose residual of a returned closed-form solution [m, rad]
ELBOW_UP, ELBOW_DOWN = 0, 1  # row order of the planar/SCARA solutions: s2 < 0 first, then s2 > 0
_HALF_PI = np.pi / 2


@lru_cache(maxsize=64)
def _cached_book_links(name: str, items: tuple) -> tuple:
    return book_robot_spec(name, **dict(items)).links


def _arm_links(links: Sequence[DHLink | dict] | None, book: str, params: dict) -> tuple[DHLink, ...]:
    """``links`` as DHLinks, or the DH table of book robot ``book`` with ``params`` (cached when hashable)."""
    if links is not None:
        if params:
            raise ValueError(f"give either `links` or the book table's parameters {sorted(params)}, not both")
        return tuple(as_links(links))
    try:
        return _cached_book_links(book, tuple(sorted(params.items())))
    except TypeError:  # unhashable values (lists, arrays), or bad parameters: build it (and raise) uncached
        return book_robot_spec(book, **params).links


def _book_structure(links: tuple[DHLink, ...], book: str, robot: str) -> tuple[DHLink, ...]:
    """Check that ``links`` has the structure of the book's ``book`` arm: same joint types and twists α,
    zero offsets θ, and zero a_i / d_i wherever the book's table has zero (ValueError naming ``links``)."""
    ref = _cached_book_links(book, ())
    if len(links) != len(ref):
        raise ValueError(f"`links` must be the {len(ref)}-joint DH table of a {robot}, got {len(links)} links")
    for i, (link, r) in enumerate(zip(links, ref), start=1):
        bad = [f"joint {link.joint!r} (expected {r.joint!r})"] if link.joint != r.joint else []
        bad += [f"{k} = {getattr(link, k):.6g} (expected {getattr(r, k):.6g})" for k in ("alpha", "theta")
                if abs(getattr(link, k) - getattr(r, k)) > 1e-12]
        bad += [f"{k} = {getattr(link, k):.6g} (expected 0)" for k in ("a", "d")
                if getattr(r, k) == 0 and getattr(link, k) != 0 and not (k == "d" and link.joint == "prismatic")]
        if bad:
            raise ValueError(f"`links` is not a {robot}: link {i} has {', '.join(bad)}")
    return links


def _prismatic_in_range(value: float, link: DHLink, name: str, robot: str) -> float:
    lo = -np.inf if link.lower is None else link.lower
    hi = np.inf if link.upper is None else link.upper
    if not lo - IK_TOL <= value <= hi + IK_TOL:
        raise ValueError(f"pose unreachable by the {robot}: it needs {name} = {value:.6g} m, outside the joint "
                         f"range [{lo:g}, {hi:g}] m")
    return float(np.clip(value, lo, hi))


def _checked(links: Sequence[DHLink], qs: np.ndarray, T_target: np.ndarray, mask: np.ndarray,
             robot: str) -> np.ndarray:
    """Keep the DH-product check honest: every returned row reproduces the entries of ``T_target`` in ``mask``
    and lies within the table's joint limits (rows outside are dropped, see :func:`_within_limits`)."""
    for q in qs:
        T = links[0].transform(q[0])
        for link, qi in zip(links[1:], q[1:]):  # the DH product (2.50) of :func:`dh_chain`, on checked rows
            T = T @ link.transform(qi)
        err = np.max(np.abs((T - T_target)[mask]))
        if not err <= IK_TOL:
            raise ValueError(f"pose unreachable by the {robot}: closed-form residual {err:.3g} > {IK_TOL:g}")
    return _within_limits(links, qs, robot)


def _within_limits(links: Sequence[DHLink], qs: np.ndarray, robot: str) -> np.ndarray:
    """The rows of ``qs`` within the joint limits of ``links`` (where given); a revolute angle outside is
    shifted by the multiple of 2π that brings it in, when there is one. ValueError when no row is left."""
    shifted, valid = _into_limits(links, np.array(qs, dtype=float))
    if not valid.any():
        lo, hi = ([round(b, 4) for b in bounds] for bounds in _limits(links))
        raise ValueError(f"pose unreachable by the {robot} within its joint limits (lower {lo}, upper {hi}): every "
                         f"closed-form solution {np.round(shifted, 4).tolist()} violates them")
    return shifted[valid]


def _limits(links: Sequence[DHLink]) -> tuple[list[float], list[float]]:
    return ([-np.inf if link.lower is None else link.lower for link in links],
            [np.inf if link.upper is None else link.upper for link in links])


def _into_limits(links: Sequence[DHLink], Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(Q shifted, valid): the rows of Q (…, n) with each revolute angle outside its limits moved by the multiple
    of 2π that brings it in (when one does: the smallest q + 2πk ≥ lower), and whether each row is then within
    every limit (IK_TOL of slack) — the one rule of the closed-form solvers, per pose or for a batch."""
    lower, upper, limited, revolute, base = _limit_arrays(links)
    if not limited.any():
        return Q, np.ones(Q.shape[:-1], dtype=bool)
    shifted = base + (Q - base) % (2 * np.pi)
    outside = (Q < lower - IK_TOL) | (Q > upper + IK_TOL)
    Q = np.where(revolute & outside & (shifted <= upper + IK_TOL), shifted, Q)
    valid = (~limited | ((lower - IK_TOL <= Q) & (Q <= upper + IK_TOL))).all(axis=-1)
    return Q, valid


_TABLES: dict[tuple, tuple] = {}


def _per_table(kind: str, links: Sequence[DHLink], build: Any) -> tuple:
    """``build(links)`` once per DH table object (its links kept with the result, so their ids stay theirs)."""
    key = (kind, *map(id, links))
    found = _TABLES.get(key)
    if found is None:
        if len(_TABLES) > 256:
            _TABLES.clear()
        found = _TABLES[key] = (tuple(links), build(links))
    return found[1]


def _limit_arrays(links: Sequence[DHLink]) -> tuple[np.ndarray, ...]:
    """(lower, upper, limited, revolute and limited, the base of the 2π shift) of a DH table, per joint."""
    return _per_table("limits", links, _build_limit_arrays)


def _build_limit_arrays(links: Sequence[DHLink]) -> tuple[np.ndarray, ...]:
    lower, upper = (np.array(bounds) for bounds in _limits(links))
    limited = np.isfinite(lower) | np.isfinite(upper)
    revolute = limited & np.array([link.joint == "revolute" for link in links])
    return lower, upper, limited, revolute, np.where(np.isfinite(lower), lower, -np.pi)


def _snap_cosines(c: np.ndarray) -> np.ndarray:
    """Cosines clipped to [−1, 1] and snapped to ±1 within 1e-12: at the elbow singularity s = √(1 − c²) would
    otherwise be ~1e-8 from round-off alone (the position error of snapping is second order, ~1e-12 m)."""
    c = np.clip(c, -1.0, 1.0)
    return np.where(1.0 - np.abs(c) < 1e-12, np.sign(c), c)


def _two_link(px: float, py: float, a1: float, a2: float, robot: str, origin: str = "joint 1",
              theta1: float = 0.0) -> np.ndarray:
    """(θ1, θ2) of a two-link planar arm reaching (px, py), Eqs. (2.91)–(2.92): rows [s2 < 0, s2 > 0] — the
    core :func:`_two_link_batch` at one point."""
    return _two_link_batch(np.array([px], dtype=float), np.array([py], dtype=float), a1, a2, robot, origin, theta1)[0]


def _two_link_batch(px: np.ndarray, py: np.ndarray, a1: float, a2: float, robot: str, origin: str = "joint 1",
                    theta1: float = 0.0) -> np.ndarray:
    """(θ1, θ2) of a two-link planar arm reaching N points (px, py) at once, Eqs. (2.91)–(2.92): (N, 2, 2), rows
    [s2 < 0, s2 > 0] of each point.

    c2 = (px² + py² − a1² − a2²)/(2 a1 a2), s2 = ∓√(1 − c2²), θ2 = Atan2(s2, c2) and
    θ1 = Atan2((a1 + a2 c2) py − a2 s2 px, (a1 + a2 c2) px + a2 s2 py) (the book's s1, c1 times the
    positive px² + py²; at px = py = 0 with a1 = a2, θ1 is arbitrary and ``theta1`` is returned).
    """
    c2 = (px**2 + py**2 - a1**2 - a2**2) / (2.0 * a1 * a2)
    far = ~(np.abs(c2) <= 1.0 + 1e-12)
    if far.any():
        k = int(np.argmax(far))
        which = "point" if len(c2) == 1 else f"point {k}"
        raise ValueError(f"{which} unreachable by the {robot}: distance {np.hypot(px[k], py[k]):.6g} m from {origin} is "
                         f"outside [|a1 - a2|, a1 + a2] = [{abs(a1 - a2):.6g}, {a1 + a2:.6g}] m")
    c2 = _snap_cosines(c2)
    out = np.empty((c2.size, 2, 2))
    for row, s2 in enumerate((-np.sqrt(1.0 - c2**2), np.sqrt(1.0 - c2**2))):
        k1, k2 = a1 + a2 * c2, a2 * s2
        t1 = np.arctan2(k1 * py - k2 * px, k1 * px + k2 * py)
        arbitrary = (np.abs(k1) < 1e-12) & (np.abs(k2) < 1e-12) & (np.abs(px) < 1e-12) & (np.abs(py) < 1e-12)
        out[:, row, 0] = np.where(arbitrary, float(theta1), t1)
        out[:, row, 1] = np.arctan2(s2, c2)
    return out


def inverse_kinematics_planar_2r(p: np.ndarray, links: Sequence[DHLink | dict] | None = None,
                                 **params) -> np.ndarray:
    """Both solutions q = [θ1, θ2] of the two-link planar arm reaching ``p = [px, py]``, Sect. 2.12.1.

    Rows: ``[ELBOW_UP, ELBOW_DOWN]`` = [s2 < 0, s2 > 0] (the companion files' "elbow-up" is s2 < 0).
    ``links``: the arm's DH table (link lengths a1, a2); default the book's ``planar_2r`` with ``params`` (``a``).
    """
    links = _book_structure(_arm_links(links, "planar_2r", params), "planar_2r", "two-link planar arm")
    px, py = as_vector(p, 2, "p")
    qs = _two_link(px, py, links[0].a, links[1].a, "two-link planar arm")
    T = np.eye(4)
    T[:2, 3] = px, py
    mask = np.zeros((4, 4), bool)
    mask[:2, 3] = True
    return _checked(links, qs, T, mask, "two-link planar arm")


def inverse_kinematics_planar_3r(x: np.ndarray, links: Sequence[DHLink | dict] | None = None,
                                 **params) -> np.ndarray:
    """Both solutions q = [θ1, θ2, θ3] of the three-link planar arm for ``x = [px, py, φ]``, Sect. 2.12.1.

    p_W = p − a3 [cφ, sφ] (2.91)–(2.92), (θ1, θ2) as for the two-link arm, θ3 = φ − θ1 − θ2.
    Rows ``[ELBOW_UP, ELBOW_DOWN]`` = [s2 < 0, s2 > 0] (those within the joint limits). ``links``: the arm's
    DH table; default the book's ``planar_3r`` with ``params`` (``a``). The batch solver
    :func:`inverse_kinematics_planar_3r_batch` at one pose.
    """
    Q, valid = inverse_kinematics_planar_3r_batch(as_vector(x, 3, "x")[None], links, **params)
    return Q[0][valid[0]]


def _dh_arrays(links: Sequence[DHLink]) -> tuple[np.ndarray, ...]:
    """(revolute, θ, d, a, cos α, sin α) of a DH table, per link."""
    return _per_table("dh", links, _build_dh_arrays)


def _build_dh_arrays(links: Sequence[DHLink]) -> tuple[np.ndarray, ...]:
    alpha = np.array([link.alpha for link in links])
    return (np.array([link.joint == "revolute" for link in links]), np.array([link.theta for link in links]),
            np.array([link.d for link in links]), np.array([link.a for link in links]), np.cos(alpha), np.sin(alpha))


def _dh_product_batch(links: Sequence[DHLink], Q: np.ndarray) -> np.ndarray:
    """The DH product (2.50) A_1(q_1) ⋯ A_n(q_n), Eq. (2.52) per link, at M configurations Q (M, n): (M, 4, 4)."""
    M, n = Q.shape
    revolute, theta0, d0, a, ca, sa = _dh_arrays(links)
    theta = theta0 + np.where(revolute, Q, 0.0)
    d = d0 + np.where(revolute, 0.0, Q)
    ct, st = np.cos(theta), np.sin(theta)
    A = np.zeros((M, n, 4, 4))
    A[..., 0, 0], A[..., 0, 1], A[..., 0, 2], A[..., 0, 3] = ct, -st * ca, st * sa, a * ct
    A[..., 1, 0], A[..., 1, 1], A[..., 1, 2], A[..., 1, 3] = st, ct * ca, -ct * sa, a * st
    A[..., 2, 1], A[..., 2, 2], A[..., 2, 3], A[..., 3, 3] = sa, ca, d, 1.0
    T = A[:, 0]
    for k in range(1, n):
        T = T @ A[:, k]
    return T


def inverse_kinematics_planar_3r_batch(X: np.ndarray, links: Sequence[DHLink | dict] | None = None,
                                       **params) -> tuple[np.ndarray, np.ndarray]:
    """:func:`inverse_kinematics_planar_3r` at N poses X (N, 3) = [px, py, φ] in one vectorised pass.

    Returns ``(Q, valid)``: Q (N, 2, 3) both solutions of each pose in the same row order
    [ELBOW_UP, ELBOW_DOWN] (revolute angles shifted by 2π into the joint limits, :func:`_into_limits`) and
    ``valid`` (N, 2), the rows within the limits — the rows :func:`inverse_kinematics_planar_3r` returns (it is
    this solver at N = 1). The DH product of every row is checked against the pose; ValueError
    naming the first unreachable pose.
    """
    links = _book_structure(_arm_links(links, "planar_3r", params), "planar_3r", "three-link planar arm")
    X = np.asarray(X, dtype=float)
    if X.ndim != 2 or X.shape[1] != 3 or not np.isfinite(X).all():
        raise ValueError(f"`X` must be a finite (N, 3) array of poses [px, py, φ], got shape {X.shape}")
    px, py, phi = X.T
    a1, a2, a3 = (link.a for link in links)
    Q = np.empty((X.shape[0], 2, 3))
    Q[:, :, :2] = _two_link_batch(px - a3 * np.cos(phi), py - a3 * np.sin(phi), a1, a2, "three-link planar arm")
    Q[:, :, 2] = phi[:, None] - Q[:, :, :2].sum(axis=2)
    Q = wrap_angle(Q)
    T = _dh_product_batch(links, Q.reshape(-1, 3)).reshape(-1, 2, 4, 4)
    target = np.zeros((X.shape[0], 1, 4, 4))                  # the pose: R_z(φ), (px, py, 0)
    target[:, 0, 0, 0] = target[:, 0, 1, 1] = np.cos(phi)
    target[:, 0, 1, 0] = np.sin(phi)
    target[:, 0, 0, 1] = -target[:, 0, 1, 0]
    target[:, 0, 2, 2] = target[:, 0, 3, 3] = 1.0
    target[:, 0, 0, 3], target[:, 0, 1, 3] = px, py
    err = np.abs(T - target).max(axis=(2, 3))
    which = (lambda k: "pose") if len(X) == 1 else (lambda k: f"pose {k}")
    if not (err <= IK_TOL).all():
        k = int(np.argmax(~(err <= IK_TOL).all(axis=1)))
        raise ValueError(f"{which(k)} unreachable by the three-link planar arm: closed-form residual "
                         f"{err[k].max():.3g} > {IK_TOL:g}")
    Q, valid = _into_limits(links, Q)
    if not valid.any(axis=1).all():
        k = int(np.argmin(valid.any(axis=1)))
        lo, hi = ([round(b, 4) for b in bounds] for bounds in _limits(links))
        raise ValueError(f"{which(k)} unreachable by the three-link planar arm within its joint limits (lower {lo}, "
                         f"upper {hi}): every closed-form solution {np.round(Q[k], 4).tolist()} violates them")
    return Q, valid


def batch_inverse_kinematics(inverse_kinematics: Any) -> Any:
    """The vectorised form ``X (N, m) -> (Q (N, k, n), valid (N, k))`` of a closed-form solver of this
    module (same solutions, same row order), or None when it has none."""
    return _BATCH.get(inverse_kinematics)


def inverse_kinematics_scara(x: np.ndarray, links: Sequence[DHLink | dict] | None = None, **params) -> np.ndarray:
    """Both solutions q = [θ1, θ2, d3, θ4] of the SCARA of Table S2.3 for ``x = [px, py, pz, φ]`` (Problem 2.20).

    In DH frame 0 (z₀ down): (θ1, θ2) as for the two-link arm, d3 = pz, θ4 = φ − θ1 − θ2 with
    φ = Atan2(r21, r11). Rows ``[ELBOW_UP, ELBOW_DOWN]`` = [s2 < 0, s2 > 0]. ``links``: the arm's DH
    table (a1, a2, the range of d3); default the book's ``scara`` with ``params``.
    """
    links = _book_structure(_arm_links(links, "scara", params), "scara", "SCARA")
    px, py, pz, phi = as_vector(x, 4, "x")
    q12 = _two_link(px, py, links[0].a, links[1].a, "SCARA")
    d3 = _prismatic_in_range(pz, links[2], "d3", "SCARA")
    qs = np.column_stack([q12, np.full(2, d3), wrap_angle(phi - q12.sum(axis=1))])
    T = np.eye(4)
    T[:3, :3] = rot_z(phi)
    T[:3, 3] = px, py, pz
    return _checked(links, qs, T, np.ones((4, 4), bool), "SCARA")


def inverse_kinematics_cylindrical(p: np.ndarray, links: Sequence[DHLink | dict] | None = None,
                                   **params) -> np.ndarray:
    """q = [θ1, d2, d3] of the cylindrical arm of Table S2.2 reaching ``p`` (Problem 2.19), shape (1, 3).

    From p = [−d3 s1, d3 c1, d2] (Problem 2.12): θ1 = Atan2(−px, py), d3 = √(px² + py²) (the d3 ≥ 0
    branch), d2 = pz; d2 and d3 must lie in their joint ranges. ``links``: the arm's DH table; default
    the book's ``cylindrical`` with ``params``.
    """
    links = _book_structure(_arm_links(links, "cylindrical", params), "cylindrical", "cylindrical arm")
    px, py, pz = as_vector(p, 3, "p")
    d3 = _prismatic_in_range(np.hypot(px, py), links[2], "d3", "cylindrical arm")
    d2 = _prismatic_in_range(pz, links[1], "d2", "cylindrical arm")
    qs = np.array([[np.arctan2(-px, py), d2, d3]])
    T = np.eye(4)
    T[:3, 3] = px, py, pz
    mask = np.zeros((4, 4), bool)
    mask[:3, 3] = True
    return _checked(links, qs, T, mask, "cylindrical arm")


def inverse_kinematics_spherical(p: np.ndarray, links: Sequence[DHLink | dict] | None = None,
                                 **params) -> np.ndarray:
    """Both solutions q = [θ1, θ2, d3] of the spherical arm reaching ``p``, Sect. 2.12.3; shape (2, 3).

    From p = [c1 s2 d3 − s1 d2, s1 s2 d3 + c1 d2, c2 d3]: d3 = √(‖p‖² − d2²) (d3 ≥ 0),
    s2 d3 = ±√(px² + py² − d2²) =: ±A, θ2 = Atan2(±A, pz), and [px, py] = Rz(θ1) [±A, d2] gives
    θ1 = Atan2(py, px) − Atan2(d2, ±A). ``links``: the arm's DH table (d2, the range of d3); default the
    book's ``spherical`` with ``params`` (``d2``, ``d3_range``).
    """
    links = _book_structure(_arm_links(links, "spherical", params), "spherical", "spherical arm")
    px, py, pz = as_vector(p, 3, "p")
    d2 = links[1].d
    rho2 = px**2 + py**2 - d2**2
    if rho2 < -1e-12:
        raise ValueError(f"point unreachable by the spherical arm: its distance {np.hypot(px, py):.6g} m from "
                         f"the z0 axis is smaller than the offset d2 = {d2:g} m")
    d3 = _prismatic_in_range(np.sqrt(max(px**2 + py**2 + pz**2 - d2**2, 0.0)), links[2], "d3", "spherical arm")
    A = np.sqrt(max(rho2, 0.0))
    qs = np.array([[np.arctan2(py, px) - np.arctan2(d2, s * A), np.arctan2(s * A, pz), d3] for s in (1.0, -1.0)])
    qs[:, :2] = wrap_angle(qs[:, :2])
    T = np.eye(4)
    T[:3, 3] = px, py, pz
    mask = np.zeros((4, 4), bool)
    mask[:3, 3] = True
    return _checked(links, qs, T, mask, "spherical arm")


def _arm_structure(links: Sequence[DHLink], robot: str, wrist: bool) -> None:
    """The anthropomorphic class: revolute, a1 = 0, α1 = ±π/2, α2 = 0 (and α3 = ±π/2 before a wrist); with a
    spherical wrist also a4 = a5 = a6 = 0, d5 = 0, α4 = ±π/2, α5 = −α4, α6 = 0 (ValueError naming ``links``)."""
    n = 6 if wrist else 3
    if len(links) != n or any(l.joint != "revolute" for l in links):
        raise ValueError(f"`links` must be the DH table of a {robot}: {n} revolute joints, got "
                         f"{[l.joint for l in links]}")
    rules = [(links[0].a == 0, "a1 = 0"), (abs(abs(links[0].alpha) - _HALF_PI) < 1e-12, "α1 = ±π/2"),
             (abs(links[1].alpha) < 1e-12, "α2 = 0"), (links[1].a > 0, "a2 > 0")]
    if wrist:
        rules += [(abs(abs(links[2].alpha) - _HALF_PI) < 1e-12, "α3 = ±π/2"),
                  (links[3].a == links[4].a == links[5].a == links[4].d == 0, "a4 = a5 = a6 = d5 = 0"),
                  (abs(abs(links[3].alpha) - _HALF_PI) < 1e-12 and abs(links[4].alpha + links[3].alpha) < 1e-12,
                   "α4 = ±π/2, α5 = −α4"), (abs(links[5].alpha) < 1e-12, "α6 = 0")]
    broken = [text for ok, text in rules if not ok]
    if broken:
        raise ValueError(f"`links` is not a {robot}: it needs {', '.join(broken)}")


def _arm_position(p: np.ndarray, links: Sequence[DHLink], d4: float, theta1: float, theta2: float,
                  robot: str) -> np.ndarray:
    """The four (θ1, θ2, θ3) joint angles (offsets θ_i included) placing the point ``d4`` along z3 from frame 3
    of an anthropomorphic-class arm at ``p`` (the wrist centre; with d4 = 0, the origin of frame 3), Sect. 2.12.4.

    With σ1 = sign α1, d = d2 + d3 (shoulder offset) and v = Rz(θ3) [a3, −σ3 d4] (σ3 = sign α3) the elbow
    link as a vector in frame 2, the point is p = Rz(θ1) [X, −σ1 d, σ1 Y + d1] with [X, Y] the tip of the
    planar two-link arm (a2, ‖v‖) of angles θ2, θ3 + φ, φ = Atan2(−σ3 d4, a3). Hence
    X = ±√(px² + py² − d²) (shoulder right/left), θ1 = Atan2(py, px) + Atan2(σ1 d, X), and (θ2, θ3 + φ)
    from (2.91)–(2.92) (elbow up/down). For the book's arm (d1 = d = d4 = 0) these are (2.103)–(2.110).
    Rows: (shoulder right, elbow up), (right, down), (left, up), (left, down). Singular cases
    (Problem 2.18): px = py = 0 (with d = 0) leaves θ1 free (``theta1``); a2 = ‖v‖ with p on the shoulder
    leaves θ2 free (``theta2``).
    """
    theta1, theta2 = as_scalar(theta1, "theta1"), as_scalar(theta2, "theta2")
    l1, l2, l3 = links[:3]
    s1, s3 = np.sign(l1.alpha), np.sign(l3.alpha)
    d, a2, a3 = l2.d + l3.d, l2.a, l3.a
    px, py, pz = p
    Y = s1 * (pz - l1.d)
    rho2 = px**2 + py**2 - d**2
    if rho2 < -1e-12:
        raise ValueError(f"point unreachable by the {robot}: its distance {np.hypot(px, py):.6g} m from the z0 "
                         f"axis is smaller than the shoulder offset d2 + d3 = {abs(d):g} m")
    X = np.sqrt(max(rho2, 0.0))
    L, phi = np.hypot(a3, d4), np.arctan2(-s3 * d4, a3)
    out = []
    for h in (X, -X):
        if X < 1e-12 and d == 0:
            t1 = float(theta1) + (np.pi if h is not X else 0.0)  # on the z0 axis: θ1 arbitrary
        else:
            t1 = np.arctan2(py, px) + np.arctan2(s1 * d, h)
        elbow = _two_link(h, Y, a2, L, robot, "the shoulder", theta2)[::-1]  # elbow up (s > 0) first
        for t2, t3 in elbow:
            out.append([t1, t2, t3 - phi])
    return wrap_angle(np.array(out) - np.array([l1.theta, l2.theta, l3.theta]))


def inverse_kinematics_anthropomorphic(p: np.ndarray, theta1: float = 0.0, theta2: float = 0.0,
                                       links: Sequence[DHLink | dict] | None = None, **params) -> np.ndarray:
    """The four solutions q = [θ1, θ2, θ3] of the anthropomorphic arm reaching ``p``, Sect. 2.12.4; (4, 3).

    Rows: (shoulder right, elbow up), (shoulder right, elbow down), (shoulder left, elbow up),
    (shoulder left, elbow down) — the book's I–IV combinations. In the singular cases of Problem 2.18
    rows coincide (s3 = 0) and the undetermined angles take the values ``theta1`` (px = py = 0) and
    ``theta2`` (a2 = a3, p = 0). ``links``: the arm's DH table (the class of :func:`_arm_position`:
    a1 = 0, α1 = ±π/2, α2 = 0, offsets d1, d2 + d3 allowed); default the book's ``anthropomorphic``
    with ``params`` (``a2``, ``a3``).
    """
    links = _arm_links(links, "anthropomorphic", params)
    _arm_structure(links, "anthropomorphic arm", wrist=False)
    p = as_vector(p, 3, "p")
    qs = _arm_position(p, links, 0.0, theta1, theta2, "anthropomorphic arm")
    T = np.eye(4)
    T[:3, 3] = p
    mask = np.zeros((4, 4), bool)
    mask[:3, 3] = True
    return _checked(links, qs, T, mask, "anthropomorphic arm")


def _spherical_wrist(R_36: np.ndarray, sigma4: float = -1.0) -> np.ndarray:
    """[θ4, θ5, θ6] of a spherical wrist (α4 = σ4 π/2, α5 = −α4, α6 = 0) with orientation R_6^3, both branches.

    R_6^3 = Rz(θ4) Rx(α4) Rz(θ5) Rx(−α4) Rz(θ6) = Rz(θ4) Ry(−σ4 θ5) Rz(θ6): the ZYZ angles (2.19)–(2.20)
    of R_6^3 with the middle one times −σ4 (the book's wrist has σ4 = −1, Sect. 2.12.5)."""
    return np.array([rotation_to_euler_zyz(R_36, branch).angles for branch in (1, -1)]) * [1.0, -sigma4, 1.0]


def inverse_kinematics_spherical_wrist(R: np.ndarray, links: Sequence[DHLink | dict] | None = None,
                                       **params) -> np.ndarray:
    """Both solutions q = [θ4, θ5, θ6] of the spherical wrist with orientation ``R`` = R_6^3, Sect. 2.12.5; (2, 3).

    R_6^3 = Rz(θ4) Ry(θ5) Rz(θ6) (the DH table (0, −π/2, 0, θ4), (0, π/2, 0, θ5), (0, 0, d6, θ6)), so the
    angles are the ZYZ Euler angles of R: θ5 ∈ (0, π) in the first row, (−π, 0) in the second. At
    θ5 = 0 or π (singular wrist) only θ4 ± θ6 is determined; both rows are then the representative θ6 = 0.
    ``links``: the wrist's DH table (``d6``); default the book's ``spherical_wrist`` with ``params``.
    """
    links = _book_structure(_arm_links(links, "spherical_wrist", params), "spherical_wrist", "spherical wrist")
    R = as_rotation(R, "R")
    qs = _spherical_wrist(R)
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = links[2].d * R[:, 2]
    return _checked(links, qs, T, np.ones((4, 4), bool), "spherical wrist")


def inverse_kinematics_6r_spherical_wrist(T: np.ndarray, links: Sequence[DHLink | dict], theta1: float = 0.0,
                                          theta2: float = 0.0) -> np.ndarray:
    """The eight solutions q = [θ1, ..., θ6] of a 6R arm with a spherical wrist for the pose ``T``; (8, 6).

    The class of the Puma 560 and of the book's anthropomorphic arm with spherical wrist (Sect. 2.12,
    kinematic decoupling): a1 = 0, α1 = ±π/2, α2 = 0, α3 = ±π/2, a4 = a5 = a6 = d5 = 0, α4 = ±π/2,
    α5 = −α4, α6 = 0; link lengths a2, a3, d4, d6, offsets d1, d2, d3 and joint offsets θ_i are free.
    p_W = p_e − d6 a_e (2.93) gives four (θ1, θ2, θ3) (:func:`_arm_position`); for each, R_6^3 =
    (R_3^0)^T R_e and the wrist gives two (θ4, θ5, θ6). Rows: arm solution (shoulder right/left × elbow
    up/down) × wrist branch. Every row is checked by the DH product; unreachable → ValueError.
    """
    links = tuple(as_links(links))
    robot = "6R arm with spherical wrist"
    _arm_structure(links, robot, wrist=True)
    T = as_homogeneous(T, "T")
    p_W = T[:3, 3] - links[5].d * T[:3, 2]  # Eq. (2.93)
    arm = _arm_position(p_W, links, links[3].d, theta1, theta2, robot)
    offsets = np.array([l.theta for l in links[3:]])
    qs = []
    for q_arm in arm:
        R_30 = dh_chain(links[:3], q_arm)[-1][:3, :3]
        for q_wrist in _spherical_wrist(R_30.T @ T[:3, :3], np.sign(links[3].alpha)):
            qs.append(np.concatenate([q_arm, wrap_angle(q_wrist - offsets)]))
    return _checked(links, np.array(qs), T, np.ones((4, 4), bool), robot)


def inverse_kinematics_anthropomorphic_wrist(T: np.ndarray, theta1: float = 0.0, theta2: float = 0.0,
                                             links: Sequence[DHLink | dict] | None = None,
                                             **params) -> np.ndarray:
    """The eight solutions q = [θ1, ..., θ6] of the anthropomorphic arm with spherical wrist for the pose ``T``; (8, 6).

    Sect. 2.12 (kinematic decoupling): p_W = p_e − d6 a_e (2.93); the arm's wrist position
    p_W = [c1 (a2 c2 + d4 s23), s1 (a2 c2 + d4 s23), a2 s2 − d4 c23] is the anthropomorphic arm's with
    a3 = d4 and θ3 − π/2, giving four (θ1, θ2, θ3); for each, R_6^3 = (R_3^0)^T R_e and the wrist gives
    two (θ4, θ5, θ6). Rows: arm solution k (order of :func:`inverse_kinematics_anthropomorphic`) × wrist
    branch (θ5 > 0, θ5 < 0). The special case of :func:`inverse_kinematics_6r_spherical_wrist`;
    ``links`` default: the book's ``anthropomorphic_wrist`` with ``params`` (``a2``, ``d4``, ``d6``).
    """
    return inverse_kinematics_6r_spherical_wrist(T, _arm_links(links, "anthropomorphic_wrist", params),
                                                 theta1, theta2)


def distinct_solutions(qs: np.ndarray, atol: float = 1e-9) -> np.ndarray:
    """The distinct rows of a solution array (angles compared modulo 2π, within ``atol`` in (0, 1e-3]), in their
    first order."""
    atol = as_tolerance(atol, "atol")
    qs = np.atleast_2d(np.asarray(qs, dtype=float))
    keep: list[np.ndarray] = []
    for q in qs:
        if not any(np.max(np.abs(wrap_angle(q - k))) <= atol for k in keep):
            keep.append(q)
    return np.array(keep)


# --------------------------------------------------------------------------------------------
# Reachable workspace (Sect. 2.11, Problem 2.17)
# --------------------------------------------------------------------------------------------

def workspace_points(robot: Robot, n: int, rng: np.random.Generator, frame: str | int | None = None) -> np.ndarray:
    """Positions (n, 3) of ``frame`` (default the end effector) at n joint vectors drawn uniformly in the joint limits.

    A sample of the reachable workspace (Sect. 2.11); the limits must be finite.
    """
    if not (np.all(np.isfinite(robot.lower)) and np.all(np.isfinite(robot.upper))):
        raise ValueError(f"robot {robot.name!r} has infinite joint limits: its reachable workspace is not a box image")
    n = as_count(n, "n")
    if not isinstance(rng, np.random.Generator):
        raise ValueError(f"`rng` must be a numpy Generator (np.random.default_rng(seed)), got {type(rng).__name__}")
    fid = robot.frame(frame)
    qs = rng.uniform(robot.lower, robot.upper, size=(int(n), robot.nq))
    out = np.empty((int(n), 3))
    model, data = robot.model, robot.data
    for k, q in enumerate(qs):
        pin.forwardKinematics(model, data, q)
        out[k] = pin.updateFramePlacement(model, data, fid).translation
    return out


def joint_arc(robot: Robot, q_start: np.ndarray, joint: int, q_end: float, n: int = 50,
              frame: str | int | None = None) -> np.ndarray:
    """Positions (n, 3) traced by ``frame`` while joint ``joint`` (0-based) moves from q_start[joint] to ``q_end``."""
    q_start = as_vector(q_start, robot.nq, "q_start")
    q_end = as_scalar(q_end, "q_end")
    n = as_count(n, "n", minimum=2)
    if not 0 <= as_count(joint, "joint", minimum=0) < robot.nq:
        raise ValueError(f"`joint` must be in [0, {robot.nq - 1}], got {joint}")
    joint = int(joint)
    fid = robot.frame(frame)
    out = np.empty((n, 3))
    model, data = robot.model, robot.data
    for k, value in enumerate(np.linspace(q_start[joint], q_end, n)):
        q = q_start.copy()
        q[joint] = value
        pin.forwardKinematics(model, data, q)
        out[k] = pin.updateFramePlacement(model, data, fid).translation
    return out


@dataclass(frozen=True)
class WorkspaceContour:
    """Closed boundary (m, 2) of a planar arm's reachable workspace and its named corner configurations."""

    points: np.ndarray
    configurations: dict[str, np.ndarray]
    corners: dict[str, np.ndarray]


def planar_3r_workspace_contour(robot: Robot, n: int = 60) -> WorkspaceContour:
    """Contour AMQRPHEDA of the reachable workspace of a three-link planar arm with joint limits (Problem 2.17).

    The manual's construction: the configurations where mobility is lost (joint limits, θ2 = 0,
    θ3 = 0) are joined by the arcs traced when one joint moves; the outer contour is
    A→M (θ3 arc), M→Q (θ2), Q→R (θ1, radius a1 + a2 + a3), R→P (θ2), P→H (θ3), then the inner
    circle through H, E, D, A traced by θ1 at (θ2, θ3) = (u2, u3) from H down to E and at
    (l2, l3) from E to A. Requires limits symmetric about 0 for joints 2 and 3 (as in 2.17).
    """
    if robot.nq != 3:
        raise ValueError(f"`robot` must be a three-link planar arm, got nq = {robot.nq}")
    n = as_count(n, "n", minimum=2)
    lo, up = robot.lower, robot.upper
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(up))):
        raise ValueError("`robot` must have finite joint limits")
    if not (np.allclose(lo[1:], -up[1:]) and np.all(up[1:] > 0)):
        raise ValueError(f"joints 2 and 3 must have limits symmetric about 0, got {lo[1:]} .. {up[1:]}")
    cfg = {
        "A": [lo[0], lo[1], lo[2]], "M": [lo[0], lo[1], 0.0], "Q": [lo[0], 0.0, 0.0], "R": [up[0], 0.0, 0.0],
        "P": [up[0], up[1], 0.0], "H": [up[0], up[1], up[2]], "E": [up[0], lo[1], lo[2]], "D": [lo[0], up[1], up[2]],
    }
    cfg = {k: np.array(v, dtype=float) for k, v in cfg.items()}
    corner = {k: direct_kinematics(robot, q)[:2, 3] for k, q in cfg.items()}
    angle = {k: np.arctan2(v[1], v[0]) for k, v in corner.items()}
    delta = wrap_angle(angle["H"] - angle["E"])  # θ1 travel from H to E along the inner circle
    arcs = [
        joint_arc(robot, cfg["A"], 2, 0.0, n), joint_arc(robot, cfg["M"], 1, 0.0, n),
        joint_arc(robot, cfg["Q"], 0, up[0], 2 * n), joint_arc(robot, cfg["R"], 1, up[1], n),
        joint_arc(robot, cfg["P"], 2, up[2], n), joint_arc(robot, cfg["H"], 0, up[0] - delta, n),
        joint_arc(robot, cfg["E"], 0, lo[0], 2 * n),
    ]
    points = np.vstack([arc[:-1, :2] for arc in arcs] + [arcs[0][:1, :2]])
    return WorkspaceContour(points, cfg, corner)


_BATCH = {inverse_kinematics_planar_3r: inverse_kinematics_planar_3r_batch}
