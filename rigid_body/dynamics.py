"""Joint-space dynamics B(q) q̈ + C(q, q̇) q̇ + g(q) = τ, Eq. (7.42), from Pinocchio.

The book's motor model (rotor i carried by link i−1, spinning at k_ri q̇_i, Sect. 7.3) is in the
URDF as mimic joints, so CRBA/RNEA here include the k_r I_m terms of (7.32). With mimic joints
Pinocchio refuses ABA; forward dynamics is then the Cholesky solve of B q̈ = τ − h.
Every result is a new array, never a view of ``robot.data``: Pinocchio 4's bindings return copies
(checked by tests/rigid_body/test_wrapper_fast_paths.py), so no second copy is made. :func:`inverse_dynamics` is
the rigid-body model; friction, F_v q̇ + F_s sgn(q̇) in (7.42), is :func:`friction_torques` (``robot.friction``).

Fast path of the wrappers (≈ 1.5–1.7× the raw Pinocchio call on the Panda, at the floor of any validating
Python wrapper: ``benchmarks/bench_wrappers.py``): ``math.isfinite(sum(q.tolist()) + ...)`` is the whole check
of well-formed input — it raises for anything but a 1-D numeric array (a nested list does not sum, a list
has no ``tolist``) and is non-finite when an entry is NaN or ±inf — and Pinocchio checks the sizes. Any
failure (or an overflowing sum) re-runs the call with :func:`~rigid_body.validation.as_vector` on every
argument, whose ValueError names the argument. The fast path reads the calling thread's ``pin.Data`` from
the store behind ``robot.data`` (``robot._local.data``, 40 ns less than the property; missing in a thread's
first call, where the full path creates it).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Eqs. (7.32) B(q), (7.42) the model, (7.45) Christoffel C, (7.39) g, Sect. 7.5 Newton–Euler.
"""

from __future__ import annotations

from math import isfinite

import numpy as np
import pinocchio as pin
from scipy.linalg import get_lapack_funcs

from rigid_body.robots import JointFriction, Robot
from rigid_body.validation import as_vector


def inertia_matrix(robot: Robot, q: np.ndarray) -> np.ndarray:
    """B(q), (nv, nv), symmetric positive definite, Eq. (7.32) (CRBA)."""
    try:  # fast path (module docstring); Pinocchio 4's crba fills both triangles
        if isfinite(sum(q.tolist())):
            return pin.crba(robot.model, robot._local.data, q)
    except Exception:
        pass
    return pin.crba(robot.model, robot.data, as_vector(q, robot.nq, "q"))


def coriolis_matrix(robot: Robot, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """C(q, q̇) built from the Christoffel symbols, Eq. (7.45): Ḃ − 2C is skew-symmetric.

    With mimic joints (the book's rotors) Pinocchio 4.1's ``computeCoriolisMatrix`` is not
    consistent with its own RNEA on spatial arms (C q̇ ≠ h − g; found against the book's Lagrange
    model, :mod:`rigid_body.lagrange`). C is then built from :func:`christoffel_symbols` instead.
    """
    q = as_vector(q, robot.nq, "q")
    qd = as_vector(qd, robot.nv, "qd")
    if robot.has_mimic:
        return christoffel_symbols(robot, q) @ qd
    return pin.computeCoriolisMatrix(robot.model, robot.data, q, qd)


def christoffel_symbols(robot: Robot, q: np.ndarray) -> np.ndarray:
    """c_ijk (nv, nv, nv) indexed [i, j, k], Eq. (7.45), from RNEA by polarisation.

    The Christoffel symbols are the unique coefficients, symmetric in (j, k), of the quadratic form
    h(q, q̇) − g(q) = Σ_jk c_ijk q̇_j q̇_k. So c_·jk = [v(e_j + e_k) − v(e_j − e_k)]/4 with
    v(q̇) = h(q, q̇) − g(q), exactly and with n(n+1)/2 + n RNEA calls.
    """
    q = as_vector(q, robot.nq, "q")
    model, data = robot.model, robot.data
    n = model.nv
    g = pin.computeGeneralizedGravity(model, data, q)
    E = np.eye(n)
    c = np.empty((n, n, n))
    for j in range(n):
        c[:, j, j] = (pin.nonLinearEffects(model, data, q, 2.0 * E[j]) - g) / 4.0
        for k in range(j + 1, n):
            plus = pin.nonLinearEffects(model, data, q, E[j] + E[k]) - g
            minus = pin.nonLinearEffects(model, data, q, E[j] - E[k]) - g
            c[:, j, k] = c[:, k, j] = (plus - minus) / 4.0
    return c


def gravity_torques(robot: Robot, q: np.ndarray) -> np.ndarray:
    """g(q), Eq. (7.39)."""
    try:  # fast path (module docstring)
        if isfinite(sum(q.tolist())):
            return pin.computeGeneralizedGravity(robot.model, robot._local.data, q)
    except Exception:
        pass
    return pin.computeGeneralizedGravity(robot.model, robot.data, as_vector(q, robot.nq, "q"))


def nonlinear_effects(robot: Robot, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """h(q, q̇) = C(q, q̇) q̇ + g(q)."""
    try:  # fast path (module docstring)
        if isfinite(sum(q.tolist()) + sum(qd.tolist())):
            return pin.nonLinearEffects(robot.model, robot._local.data, q, qd)
    except Exception:
        pass
    return pin.nonLinearEffects(robot.model, robot.data, as_vector(q, robot.nq, "q"), as_vector(qd, robot.nv, "qd"))


def inverse_dynamics(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """τ = B(q) q̈ + C(q, q̇) q̇ + g(q) by recursive Newton–Euler (Sect. 7.5)."""
    try:  # fast path (module docstring)
        if isfinite(sum(q.tolist()) + sum(qd.tolist()) + sum(qdd.tolist())):
            return pin.rnea(robot.model, robot._local.data, q, qd, qdd)
    except Exception:
        pass
    nv = robot.nv
    return pin.rnea(robot.model, robot.data, as_vector(q, robot.nq, "q"), as_vector(qd, nv, "qd"),
                    as_vector(qdd, nv, "qdd"))


def friction_torques(robot: Robot, qd: np.ndarray, smoothing: float = 0.0,
                     friction: JointFriction | None = None, check: bool = True) -> np.ndarray:
    """τ_f = F_v q̇ + F_s sgn(q̇), the joint torques friction takes (link side, the friction terms of (7.42)).

    With direction-dependent Coulomb data, F_s+ for q̇ > 0 and −F_s− for q̇ < 0; 0 at q̇ = 0. ``smoothing``
    ε > 0 [rad/s] replaces sgn(q̇) by tanh(q̇/ε) (continuous, for fixed-step simulation: |q̇| ≫ ε gives the
    Coulomb value, q̇ → 0 gives 0). ``friction`` defaults to ``robot.friction`` (DH table or URDF
    ``<dynamics>``). The Robotics Toolbox's ``friction(qd)`` is −τ_f.
    """
    if check:
        qd = as_vector(qd, robot.nv, "qd")
        if not (np.isfinite(smoothing) and smoothing >= 0):
            raise ValueError(f"`smoothing` must be a non-negative velocity [rad/s], got {smoothing!r}")
    return friction_kernel(robot.friction if friction is None else friction, qd, smoothing)


def friction_kernel(f: JointFriction, qd: np.ndarray, smoothing: float = 0.0) -> np.ndarray:
    """The unvalidated kernel of :func:`friction_torques` with the friction data ``f`` (the plants' hot path)."""
    s = np.tanh(qd / smoothing) if smoothing > 0 else np.sign(qd)
    return f.viscous * qd + f.coulomb_positive * np.maximum(s, 0.0) + f.coulomb_negative * np.minimum(s, 0.0)


def reference_torque(robot: Robot, q: np.ndarray, qd: np.ndarray, qd_r: np.ndarray,
                     qdd_r: np.ndarray) -> np.ndarray:
    """B(q) q̈_r + C(q, q̇) q̇_r + g(q), Christoffel C (7.45): the model part of the adaptive law (8.98).

    C(q, a) b = Γ(a, b) is symmetric bilinear in (a, b) with Γ(v, v) = h(q, v) − g(q), so by
    polarisation of RNEA: B q̈_r + Γ(q̇, q̇_r) = [RNEA(q, q̇ + q̇_r, 4 q̈_r) − RNEA(q, q̇ − q̇_r, 0)]/4
    (three Pinocchio passes instead of B, C and g separately). With q̇_r = q̇ it is RNEA(q, q̇, q̈_r).
    """
    q = as_vector(q, robot.nq, "q")
    qd = as_vector(qd, robot.nv, "qd")
    qd_r = as_vector(qd_r, robot.nv, "qd_r")
    qdd_r = as_vector(qdd_r, robot.nv, "qdd_r")
    return reference_torque_kernel(robot.model, robot.data, q, qd, qd_r, qdd_r)


def reference_torque_kernel(model: pin.Model, data: pin.Data, q: np.ndarray, qd: np.ndarray, qd_r: np.ndarray,
                            qdd_r: np.ndarray) -> np.ndarray:
    """The unvalidated kernel of :func:`reference_torque` (the adaptive law's hot path)."""
    plus = pin.rnea(model, data, q, qd + qd_r, 4.0 * qdd_r)
    minus = pin.rnea(model, data, q, qd - qd_r, np.zeros(model.nv))
    return (plus - minus) / 4.0 + pin.computeGeneralizedGravity(model, data, q)


def forward_dynamics(robot: Robot, q: np.ndarray, qd: np.ndarray, tau: np.ndarray,
                     check: bool = True) -> np.ndarray:
    """q̈ = B(q)⁻¹ (τ − C q̇ − g): ABA without mimic joints, else a Cholesky solve (Eq. 7.42).

    ``check=False`` skips the input validation (for simulation hot loops whose inputs are known good).
    ValueError on both paths when B(q) is singular (e.g. a link with neither mass nor inertia): ABA then
    returns NaN/inf (one sum checks it), Cholesky fails.
    """
    if check:
        try:  # fast path (module docstring); Pinocchio's size checks raise below
            check = not isfinite(sum(q.tolist()) + sum(qd.tolist()) + sum(tau.tolist()))
        except Exception:
            pass
        if check:
            q, qd, tau = _state_and_torque(robot, q, qd, tau)
    model, data = robot.model, robot.data
    try:
        if not robot.has_mimic:
            qdd = pin.aba(model, data, q, qd, tau)
            if isfinite(sum(qdd.tolist())) or np.isfinite(qdd).all():  # the sum may overflow: recheck
                return qdd
            detail = "ABA returned a non-finite q̈"
        else:
            if len(tau) != model.nv:  # τ − h would broadcast a wrong size
                raise ValueError("size of tau")
            B = pin.crba(model, data, q)  # upper triangle is what LAPACK's posv reads
            _, qdd, info = _posv(B, tau - pin.nonLinearEffects(model, data, q, qd), lower=False)
            if info == 0:
                return qdd
            detail = f"LAPACK posv info {info}"
    except ValueError:
        _state_and_torque(robot, q, qd, tau)  # a size error found by Pinocchio: name the argument
        raise
    _state_and_torque(robot, q, qd, tau)  # non-finite inputs (check=False) are named first
    raise _singular_inertia(q, detail)


def _state_and_torque(robot: Robot, q, qd, tau) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    nv = robot.nv
    return as_vector(q, robot.nq, "q"), as_vector(qd, nv, "qd"), as_vector(tau, nv, "tau")


def _singular_inertia(q: np.ndarray, detail: str) -> ValueError:
    return ValueError(f"B(q) is singular (not positive definite) at q = {q}: a body without mass or inertia "
                      f"on a joint? ({detail})")


_posv = get_lapack_funcs("posv", (np.zeros((1, 1)),))
