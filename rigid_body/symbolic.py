"""Symbolic (CasADi SX) kinematics generated from a numeric ``pin.Model``.

The PyPI ``pin`` wheel has no ``pinocchio.casadi``, so rmpc rebuilds the kinematic chain from the
model's data — joint placements ``model.jointPlacements``, joint types and axes, frame placements —
as CasADi expressions. The factories return ``casadi.Function`` objects with named inputs and
outputs (``q`` → ``R``, ``p``, ``J``) that optimisation-based IK (and the symbolic dynamics appended
below) evaluate and differentiate.

Supported joints: revolute and prismatic about x, y, z (``RX``, ``RY``, ``RZ``, ``PX``, ``PY``,
``PZ``), about any axis (``RevoluteUnaligned``, ``PrismaticUnaligned``), continuous revolute joints
(``RUBX/Y/Z``, q = [cos θ, sin θ]) and fixed frames. Mimic joints (the book's rotors) are skipped:
they carry leaf bodies, and a frame whose chain passes through one is refused.

Conventions: a joint ``i`` has placement ``oMi = oM_parent · jointPlacements[i] · M_i(q)``, as in
Pinocchio; the geometric Jacobian is the book's ``[J_P; J_O]`` (Pinocchio ``LOCAL_WORLD_ALIGNED``),
built column by column from Eq. (3.30): ``[z_k × (p − p_k); z_k]`` for a revolute joint and
``[z_k; 0]`` for a prismatic one.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Eqs. (2.25) (rotation about an axis), (2.50) (direct kinematics), (3.30) (geometric Jacobian).
"""

from __future__ import annotations

import hashlib
from typing import Any, Callable

import casadi as ca
import numpy as np
import pinocchio as pin

from rigid_body.robots import joint_kind, model_frame_id

__all__ = [
    "joint_transform",
    "joint_placements",
    "frame_placement",
    "frame_placement_function",
    "geometric_jacobian_function",
    "pose_function",
    "frame_state_expression",
    "orientation_error_expression",
    "inverse_dynamics_function",
    "inverse_dynamics_expression",
    "gravity_expression",
    "inertia_expression",
    "reference_torque_expression",
    "forward_dynamics_expression",
    "forward_dynamics_function",
    "friction_expression",
    "integrate_expression",
    "rotation_log_expression",
    "forward_dynamics_derivatives_expression",
]

_AXES = {"X": np.array([1.0, 0.0, 0.0]), "Y": np.array([0.0, 1.0, 0.0]), "Z": np.array([0.0, 0.0, 1.0])}


def _model(robot_or_model: Any) -> pin.Model:
    model = getattr(robot_or_model, "model", robot_or_model)
    if not isinstance(model, pin.Model):
        raise ValueError(f"`robot_or_model` must be a Robot or a pin.Model, got {type(robot_or_model).__name__}")
    return model


_BUILT: dict[tuple, ca.Function] = {}


_DIGESTS: dict[int, tuple[pin.Model, bytes]] = {}


def model_digest(model: pin.Model) -> bytes:
    """A digest of the model's content (its serialisation, ≈ 0.2–0.4 ms for an arm; remembered per model object
    and reused while the model still equals — Pinocchio's ``==``, under 1 µs — the copy it was computed on): the
    key of everything built once per model — a copy or an equal model shares it, a model changed in place does
    not."""
    known = _DIGESTS.get(id(model))
    if known is not None and known[0] == model:
        return known[1]
    digest = hashlib.sha256(model.saveToString().encode()).digest()
    if len(_DIGESTS) > 256:
        _DIGESTS.clear()
    _DIGESTS[id(model)] = (model.copy(), digest)
    return digest


def _once(kind: str, model: pin.Model, build: Callable[[], ca.Function], *key: Any) -> ca.Function:
    """``build()`` for ``model``, built once per model *content* (:func:`model_digest`): the closed loops of
    :mod:`controllers.compiled` build their laws and plants again for every run, and calling a built
    Function on their symbols inlines the same expression without re-running the Python recursion."""
    k = (kind, model_digest(model), *key)
    if k not in _BUILT:
        _BUILT[k] = build()
    return _BUILT[k]


def _inlined(function: ca.Function, *args: Any) -> ca.SX:
    """``function(*args)`` as an SX expression (numeric arguments give a constant SX)."""
    out = function(*args)
    return out if isinstance(out, ca.SX) else ca.SX(out)


def _frame_id(robot_or_model: Any, frame: str | int | None) -> int:
    if hasattr(robot_or_model, "frame"):
        return robot_or_model.frame(frame)
    if frame is None:
        raise ValueError("`frame` is required when a bare pin.Model is given")
    return model_frame_id(_model(robot_or_model), frame)


def _axis_rotation(axis: np.ndarray, c: Any, s: Any) -> ca.SX:
    """Rotation by angle θ (given cos θ, sin θ) about the unit ``axis``, Eq. (2.25)."""
    if np.allclose(axis, _AXES["X"]):
        return ca.vertcat(ca.horzcat(1, 0, 0), ca.horzcat(0, c, -s), ca.horzcat(0, s, c))
    if np.allclose(axis, _AXES["Y"]):
        return ca.vertcat(ca.horzcat(c, 0, s), ca.horzcat(0, 1, 0), ca.horzcat(-s, 0, c))
    if np.allclose(axis, _AXES["Z"]):
        return ca.vertcat(ca.horzcat(c, -s, 0), ca.horzcat(s, c, 0), ca.horzcat(0, 0, 1))
    r = ca.DM(axis)
    S = ca.skew(r)
    return ca.DM.eye(3) + s * S + (1 - c) * ca.mtimes(S, S)


def joint_transform(model: pin.Model, i: int, q: ca.SX) -> tuple[ca.SX, ca.SX]:
    """``(R, p)`` of the parent-to-joint transform ``liMi = jointPlacements[i] · M_i(q)`` of joint ``i``.

    ``q`` is the whole configuration (SX of size nq). Mimic joints are not modelled (ValueError).
    """
    kind, axis = joint_kind(model, i)
    placement = model.jointPlacements[i]
    R0 = ca.DM(np.asarray(placement.rotation))
    p0 = ca.DM(np.asarray(placement.translation))
    if kind == "mimic":
        raise ValueError(f"joint {model.names[i]!r} is a mimic joint: not modelled by rigid_body.symbolic")
    iq = model.joints[i].idx_q
    if kind == "revolute":
        Rj = _axis_rotation(axis, ca.cos(q[iq]), ca.sin(q[iq]))
        return ca.mtimes(R0, Rj), p0
    if kind == "revolute_unbounded":
        Rj = _axis_rotation(axis, q[iq], q[iq + 1])
        return ca.mtimes(R0, Rj), p0
    # prismatic: translation q along the axis, in the joint frame
    return R0, p0 + ca.mtimes(R0, ca.DM(axis) * q[iq])


def joint_placements(model: pin.Model, q: ca.SX) -> list[tuple[ca.SX, ca.SX] | None]:
    """World placements ``oMi = (R, p)`` of every joint (index 0 = universe); None on mimic branches."""
    placements: list[tuple[ca.SX, ca.SX] | None] = [(ca.SX.eye(3), ca.SX.zeros(3))]
    for i in range(1, model.njoints):
        parent = placements[model.parents[i]]
        if parent is None or joint_kind(model, i)[0] == "mimic":
            placements.append(None)
            continue
        R_li, p_li = joint_transform(model, i, q)
        R_p, p_p = parent
        placements.append((ca.mtimes(R_p, R_li), p_p + ca.mtimes(R_p, p_li)))
    return placements


def frame_placement(model: pin.Model, frame_id: int, q: ca.SX,
                    placements: list | None = None) -> tuple[ca.SX, ca.SX]:
    """``(R, p)`` of frame ``frame_id`` in the world frame: ``oMf = oMi[parent] · frame.placement``."""
    placements = joint_placements(model, q) if placements is None else placements
    frame = model.frames[frame_id]
    parent = placements[frame.parentJoint]
    if parent is None:
        raise ValueError(f"frame {frame.name!r} hangs on a mimic joint: not modelled by rigid_body.symbolic")
    R_p, p_p = parent
    R_f = ca.DM(np.asarray(frame.placement.rotation))
    p_f = ca.DM(np.asarray(frame.placement.translation))
    return ca.mtimes(R_p, R_f), p_p + ca.mtimes(R_p, p_f)


def _support(model: pin.Model, joint: int) -> list[int]:
    chain = []
    while joint > 0:
        chain.append(joint)
        joint = model.parents[joint]
    return chain[::-1]


def _jacobian(model: pin.Model, frame_id: int, q: ca.SX, placements: list) -> ca.SX:
    _, p = frame_placement(model, frame_id, q, placements)
    J = ca.SX.zeros(6, model.nv)
    for k in _support(model, model.frames[frame_id].parentJoint):
        kind, axis = joint_kind(model, k)
        R_k, p_k = placements[k]
        z = ca.mtimes(R_k, ca.DM(axis))                       # joint axis in the base frame
        iv = model.joints[k].idx_v
        if kind == "prismatic":
            J[0:3, iv] = z                                    # Eq. (3.30), prismatic column
        else:
            J[0:3, iv] = ca.cross(z, p - p_k)                 # Eq. (3.30), revolute column
            J[3:6, iv] = z
    return J


def frame_placement_function(robot_or_model: Any, frame: str | int | None = None,
                             name: str = "frame_placement") -> ca.Function:
    """``casadi.Function`` ``q (nq) → R (3×3), p (3)``: the pose of ``frame`` (default the end effector).

    >>> from rigid_body.robots import load
    >>> fk = frame_placement_function(load("planar_2r"))
    >>> [round(float(v), 6) for v in fk(q=[0.0, 0.0])["p"].full().ravel()]
    [2.0, 0.0, 0.0]
    """
    model = _model(robot_or_model)
    fid = _frame_id(robot_or_model, frame)
    q = ca.SX.sym("q", model.nq)
    R, p = frame_placement(model, fid, q)
    return ca.Function(name, [q], [R, p], ["q"], ["R", "p"])


def geometric_jacobian_function(robot_or_model: Any, frame: str | int | None = None,
                                name: str = "geometric_jacobian") -> ca.Function:
    """``casadi.Function`` ``q (nq) → J (6×nv)``: the book's geometric Jacobian of ``frame``, Eq. (3.30)."""
    model = _model(robot_or_model)
    fid = _frame_id(robot_or_model, frame)
    q = ca.SX.sym("q", model.nq)
    J = _jacobian(model, fid, q, joint_placements(model, q))
    return ca.Function(name, [q], [J], ["q"], ["J"])


def pose_function(robot_or_model: Any, frame: str | int | None = None,
                  name: str = "pose") -> ca.Function:
    """``casadi.Function`` ``q → R, p, J``: pose and geometric Jacobian of ``frame`` in one call."""
    model = _model(robot_or_model)
    fid = _frame_id(robot_or_model, frame)

    def build() -> ca.Function:
        q = ca.SX.sym("q", model.nq)
        placements = joint_placements(model, q)
        R, p = frame_placement(model, fid, q, placements)
        J = _jacobian(model, fid, q, placements)
        return ca.Function(name, [q], [R, p, J], ["q"], ["R", "p", "J"])

    return _once("pose", model, build, fid, name)


def frame_state_expression(robot_or_model: Any, frame: str | int | None, q: ca.SX,
                           qd: Any = None) -> tuple[ca.SX, ca.SX, ca.SX | None]:
    """(T (4×4), J (6×nv), J̇q̇ (6) or None) of ``frame`` as SX expressions of ``q`` (and ``qd``): the symbolic
    :func:`rigid_body.task_space.frame_state`. J̇q̇ = ∂(J q̇)/∂q q̇ is the frame's acceleration at q̈ = 0
    (the classical acceleration of its origin, Eq. 3.98); ``q`` must then be a symbol."""
    R, p, J = pose_function(robot_or_model, frame)(q)
    T = ca.vertcat(ca.horzcat(R, p), ca.DM([[0.0, 0.0, 0.0, 1.0]]))
    return T, J, None if qd is None else ca.jtimes(ca.mtimes(J, qd), q, qd)


def orientation_error_expression(R_d: Any, R_e: Any, orientation: str) -> ca.SX:
    """e_O (3) of R_e with respect to R_d in SX: ``"axis_angle"`` r sin ϑ = ½ vee(M − Mᵀ) (3.85) and
    ``"quaternion"`` the vector part of Q_d ∗ Q_e⁻¹ in the hemisphere η ≥ 0 (3.91), r sin(ϑ/2) =
    vee(M − Mᵀ) / (2 √(1 + tr M)), with M = R_d R_eᵀ = R(ϑ, r): the symbolic
    :func:`rigid_body.task_space.orientation_error` (ϑ < π)."""
    M = ca.mtimes(R_d, R_e.T)
    vee = ca.vertcat(M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1])
    if orientation == "axis_angle":
        return 0.5 * vee
    if orientation == "quaternion":
        return vee / (2.0 * ca.sqrt(1.0 + M[0, 0] + M[1, 1] + M[2, 2]))
    raise ValueError(f"`orientation` must be 'axis_angle' or 'quaternion' for the symbolic error, got {orientation!r}")


# ============================================================================================
# Symbolic inverse dynamics (recursive Newton–Euler), appended for planners.optimization
# ============================================================================================

def _mimic_data(model: pin.Model, i: int) -> tuple[int, float, float, str, np.ndarray]:
    """(mimicked joint, scaling, offset, kind, axis) of the mimic joint ``i`` (a book rotor).

    The axis is read from the joint's motion subspace S = scaling · [linear; angular] axis.
    """
    mimicked = dict(zip(list(model.mimicking_joints), list(model.mimicked_joints)))[i]
    jm = model.joints[i].extract()
    scaling, offset = float(jm.scaling), float(jm.offset)
    jd = model.joints[i].createData()
    model.joints[i].calc(jd, pin.neutral(model))
    S = np.asarray(jd.S, dtype=float).reshape(6) / scaling
    if np.linalg.norm(S[3:]) > 0:
        return mimicked, scaling, offset, "revolute", S[3:] / np.linalg.norm(S[3:])
    return mimicked, scaling, offset, "prismatic", S[:3] / np.linalg.norm(S[:3])


def inverse_dynamics_function(robot_or_model: Any, name: str = "inverse_dynamics") -> ca.Function:
    """``casadi.Function`` ``q, qd, qdd → tau``: τ = B(q) q̈ + C(q, q̇) q̇ + g(q) by Newton–Euler.

    See :func:`inverse_dynamics_expression` (the recursion); the rotor armature of the model
    (``model.armature``, the Toolbox's diagonal motor inertia) adds diag(armature) q̈ as in Pinocchio.

    >>> from rigid_body.robots import load
    >>> tau = inverse_dynamics_function(load("planar_2r"))
    >>> [round(float(x), 3) for x in tau([0.3, 0.5], [0, 0], [0, 0]).full().ravel()]
    [920.615, 170.867]
    """
    model = _model(robot_or_model)
    q = ca.SX.sym("q", model.nq)
    qd = ca.SX.sym("qd", model.nv)
    qdd = ca.SX.sym("qdd", model.nv)
    tau = inverse_dynamics_expression(model, q, qd, qdd)
    return ca.Function(name, [q, qd, qdd], [tau], ["q", "qd", "qdd"], ["tau"])


def inverse_dynamics_expression(robot_or_model: Any, q: ca.SX, qd: Any, qdd: Any) -> ca.SX:
    """τ = B(q) q̈ + C(q, q̇) q̇ + g(q) as an SX expression of ``q, qd, qdd`` (Newton–Euler,
    :func:`_newton_euler`; the recursion is built once per model)."""
    model = _model(robot_or_model)

    def build() -> ca.Function:
        x, v, a = ca.SX.sym("q", model.nq), ca.SX.sym("qd", model.nv), ca.SX.sym("qdd", model.nv)
        return ca.Function("rnea", [x, v, a], [_newton_euler(model, x, v, a)])

    return _inlined(_once("rnea", model, build), q, qd, qdd)


def gravity_expression(robot_or_model: Any, q: Any) -> ca.SX:
    """g(q) as an SX expression: Newton–Euler at q̇ = q̈ = 0 (the symbolic :func:`rigid_body.dynamics.gravity_torques`)."""
    nv = _model(robot_or_model).nv
    return inverse_dynamics_expression(robot_or_model, q, np.zeros(nv), np.zeros(nv))


def inertia_expression(robot_or_model: Any, q: Any) -> ca.SX:
    """B(q) (7.32) as an SX expression: the Jacobian of the Newton–Euler torque τ(q, 0, a) = B(q) a + g(q),
    linear in a (its columns are RNEA at unit accelerations, as CRBA computes them; built once per model)."""
    model = _model(robot_or_model)

    def build() -> ca.Function:
        x, a = ca.SX.sym("q", model.nq), ca.SX.sym("a", model.nv)
        return ca.Function("crba", [x], [ca.jacobian(inverse_dynamics_expression(model, x, ca.SX.zeros(model.nv), a), a)])

    return _inlined(_once("crba", model, build), q)


def reference_torque_expression(robot_or_model: Any, q: Any, qd: Any, qd_r: Any, qdd_r: Any) -> ca.SX:
    """B(q) q̈_r + C(q, q̇) q̇_r + g(q) as an SX expression, by the same polarised Newton–Euler as
    :func:`rigid_body.dynamics.reference_torque` (8.98)."""
    zero = np.zeros(_model(robot_or_model).nv)
    plus = inverse_dynamics_expression(robot_or_model, q, qd + qd_r, 4.0 * qdd_r)
    minus = inverse_dynamics_expression(robot_or_model, q, qd - qd_r, zero)
    return (plus - minus) / 4.0 + gravity_expression(robot_or_model, q)


def _newton_euler(robot_or_model: Any, q: ca.SX, qd: Any, qdd: Any) -> ca.SX:
    """τ = B(q) q̈ + C(q, q̇) q̇ + g(q) as an SX expression of ``q, qd, qdd`` (Newton–Euler).

    The recursion of Sect. 7.5 in spatial (6-D) form, frame by frame as Pinocchio's RNEA:
    forward, v_i = ⁱX_λ v_λ + S_i q̇_i, a_i = ⁱX_λ a_λ + S_i q̈_i + v_i × S_i q̇_i with a_0 = −g;
    f_i = I_i a_i + v_i ×* I_i v_i; backward, τ_i = S_i^T f_i and f_λ += ^λX_i* f_i.
    Mimic joints (the book's rotors, Sect. 7.3) move with k_r q̇ of the joint they mimic: their
    S carries the factor k_r, and S^T f is added to that joint's torque, which gives the rotor
    terms k_r I_m of (7.32) and the reaction torques of the rotors.

    ``q``, ``qd``, ``qdd`` are CasADi expressions (or numbers); returns the SX torque (nv,).
    """
    model = _model(robot_or_model)
    nj = model.njoints
    # Per joint: local transform (R, p) parent → joint, subspace S (6 × 1) and the velocity/acc.
    # variables of that joint, as SX scalars.
    R_l, p_l, S_l, qd_l, qdd_l = [None] * nj, [None] * nj, [None] * nj, [None] * nj, [None] * nj
    for i in range(1, nj):
        kind, axis = joint_kind(model, i)
        if kind == "mimic":
            j, k, offset, kind, axis = _mimic_data(model, i)
            iq, iv = model.joints[j].idx_q, model.joints[j].idx_v
            angle = k * q[iq] + offset
            if kind == "revolute":
                Rj, pj = _axis_rotation(axis, ca.cos(angle), ca.sin(angle)), ca.DM.zeros(3)
            else:
                Rj, pj = ca.DM.eye(3), ca.DM(axis) * angle
            placement = model.jointPlacements[i]
            R0 = ca.DM(np.asarray(placement.rotation))
            R_l[i] = ca.mtimes(R0, Rj)
            p_l[i] = ca.DM(np.asarray(placement.translation)) + ca.mtimes(R0, pj)
            qd_l[i], qdd_l[i] = k * qd[iv], k * qdd[iv]
        else:
            R_l[i], p_l[i] = joint_transform(model, i, q)
            iv = model.joints[i].idx_v
            qd_l[i], qdd_l[i] = qd[iv], qdd[iv]
        S_l[i] = (ca.DM(axis), ca.DM.zeros(3)) if kind == "prismatic" else (ca.DM.zeros(3), ca.DM(axis))
    # Forward recursion. Motion vectors are (linear, angular) in the joint frame.
    g = np.asarray(model.gravity.linear, dtype=float)
    v = [(ca.SX.zeros(3), ca.SX.zeros(3))] + [None] * (nj - 1)
    a = [(ca.SX(-g), ca.SX.zeros(3))] + [None] * (nj - 1)
    f = [None] * nj
    for i in range(1, nj):
        R, p = R_l[i], p_l[i]
        vl, wl = v[model.parents[i]]
        al, bl = a[model.parents[i]]
        # ⁱX_λ: ω' = R^T ω, v' = R^T (v + ω × p)
        w_i = ca.mtimes(R.T, wl)
        v_i = ca.mtimes(R.T, vl + ca.cross(wl, p))
        b_i = ca.mtimes(R.T, bl)
        a_i = ca.mtimes(R.T, al + ca.cross(bl, p))
        s_lin, s_ang = S_l[i]
        vj_lin, vj_ang = s_lin * qd_l[i], s_ang * qd_l[i]
        v_i, w_i = v_i + vj_lin, w_i + vj_ang
        # a_i += S q̈ + v_i × (S q̇)   (motion cross product)
        a_i = a_i + s_lin * qdd_l[i] + ca.cross(w_i, vj_lin) + ca.cross(v_i, vj_ang)
        b_i = b_i + s_ang * qdd_l[i] + ca.cross(w_i, vj_ang)
        v[i], a[i] = (v_i, w_i), (a_i, b_i)
        inertia = model.inertias[i]
        m = float(inertia.mass)
        c = ca.DM(np.asarray(inertia.lever, dtype=float))
        Ic = ca.DM(np.asarray(inertia.inertia, dtype=float))

        def momentum(lin: Any, ang: Any) -> tuple[Any, Any]:
            h_lin = m * (lin + ca.cross(ang, c))
            return h_lin, ca.mtimes(Ic, ang) + ca.cross(c, h_lin)

        ha_lin, ha_ang = momentum(a_i, b_i)
        hv_lin, hv_ang = momentum(v_i, w_i)
        # f = I a + v ×* (I v), with (v, ω) ×* (f, n) = (ω × f, ω × n + v × f)
        f[i] = [ha_lin + ca.cross(w_i, hv_lin), ha_ang + ca.cross(w_i, hv_ang) + ca.cross(v_i, hv_lin)]
    tau = ca.SX.zeros(model.nv)
    for i in range(nj - 1, 0, -1):
        f_lin, f_ang = f[i]
        s_lin, s_ang = S_l[i]
        kind, _ = joint_kind(model, i)
        if kind == "mimic":
            j, k, _, _, _ = _mimic_data(model, i)
            tau[model.joints[j].idx_v] += k * (ca.dot(s_lin, f_lin) + ca.dot(s_ang, f_ang))
        else:
            tau[model.joints[i].idx_v] += ca.dot(s_lin, f_lin) + ca.dot(s_ang, f_ang)
        parent = model.parents[i]
        if parent > 0:  # ^λX_i*: f' = R f, n' = R n + p × R f
            R, p = R_l[i], p_l[i]
            Rf = ca.mtimes(R, f_lin)
            f[parent][0] = f[parent][0] + Rf
            f[parent][1] = f[parent][1] + ca.mtimes(R, f_ang) + ca.cross(p, Rf)
    armature = np.asarray(model.armature, dtype=float)
    if np.any(armature != 0):
        tau = tau + ca.DM(armature) * qdd                   # rotor inertia on the diagonal of B
    return tau



# ============================================================================================
# Symbolic forward dynamics (compiled closed loops, controllers.compiled)
# ============================================================================================

def _cholesky_solve(B: ca.SX, b: ca.SX) -> ca.SX:
    """x = B⁻¹ b for a symmetric positive definite B by an explicit Cholesky factorisation B = L Lᵀ
    (n³/6 scalar operations: far smaller expressions than a symbolic QR)."""
    n = B.shape[0]
    L = [[None] * n for _ in range(n)]
    for j in range(n):
        d = B[j, j] - sum((L[j][k] * L[j][k] for k in range(j)), ca.SX(0))
        L[j][j] = ca.sqrt(d)
        for i in range(j + 1, n):
            L[i][j] = (B[i, j] - sum((L[i][k] * L[j][k] for k in range(j)), ca.SX(0))) / L[j][j]
    y = [None] * n
    for i in range(n):                                        # L y = b
        y[i] = (b[i] - sum((L[i][k] * y[k] for k in range(i)), ca.SX(0))) / L[i][i]
    x = [None] * n
    for i in reversed(range(n)):                              # Lᵀ x = y
        x[i] = (y[i] - sum((L[k][i] * x[k] for k in range(i + 1, n)), ca.SX(0))) / L[i][i]
    return ca.vertcat(*x)


def forward_dynamics_expression(robot_or_model: Any, q: ca.SX, qd: Any, tau: Any) -> ca.SX:
    """q̈ = B(q)⁻¹ (τ − C(q, q̇) q̇ − g(q)) as an SX expression (Eq. 7.42).

    B(q) is :func:`inertia_expression`, C q̇ + g is RNEA at q̈ = 0; the system is solved by a symbolic
    Cholesky factorisation. Mimic rotors and armature are included.
    """
    model = _model(robot_or_model)

    def build() -> ca.Function:
        x, v, t = (ca.SX.sym(name, n) for name, n in (("q", model.nq), ("qd", model.nv), ("tau", model.nv)))
        B = inertia_expression(model, x)
        h = inverse_dynamics_expression(model, x, v, ca.SX.zeros(model.nv))
        return ca.Function("fd", [x, v, t], [_cholesky_solve(B, t - h)])

    return _inlined(_once("fd", model, build), q, qd, tau)


def forward_dynamics_function(robot_or_model: Any, name: str = "forward_dynamics") -> ca.Function:
    """``casadi.Function`` ``q, qd, tau → qdd``: the forward dynamics of :func:`forward_dynamics_expression`.

    >>> import numpy as np, pinocchio as pin
    >>> from rigid_body.robots import load
    >>> ur5 = load("ur5")
    >>> q, v, tau = np.full(6, 0.3), np.full(6, 0.2), np.ones(6)
    >>> qdd = forward_dynamics_function(ur5)(q, v, tau).full().ravel()
    >>> bool(np.allclose(qdd, pin.aba(ur5.model, ur5.data, q, v, tau), atol=1e-9))
    True
    """
    model = _model(robot_or_model)
    q = ca.SX.sym("q", model.nq)
    qd = ca.SX.sym("qd", model.nv)
    tau = ca.SX.sym("tau", model.nv)
    return ca.Function(name, [q, qd, tau], [forward_dynamics_expression(model, q, qd, tau)],
                       ["q", "qd", "tau"], ["qdd"])


# ============================================================================================
# Friction and the configuration manifold (compiled plants)
# ============================================================================================

def friction_expression(friction: Any, qd: Any, smoothing: float = 0.0) -> ca.SX:
    """τ_f = F_v q̇ + F_s+ max(s, 0) + F_s− min(s, 0), s = sgn(q̇) (0 at q̇ = 0: the exact sign) or tanh(q̇/ε)
    for ``smoothing`` ε > 0, as an SX expression: the symbolic :func:`rigid_body.dynamics.friction_torques`
    (``friction`` a :class:`rigid_body.robots.JointFriction`)."""
    s = ca.tanh(qd / smoothing) if smoothing > 0 else ca.sign(qd)
    return (ca.DM(friction.viscous) * qd + ca.DM(friction.coulomb_positive) * ca.fmax(s, 0.0)
            + ca.DM(friction.coulomb_negative) * ca.fmin(s, 0.0))


def integrate_expression(robot_or_model: Any, q: Any, v: Any) -> ca.SX:
    """q ⊕ v (``pin.integrate``) as an SX expression, joint by joint: q + v for revolute and prismatic joints;
    for a continuous joint (q = [cos θ, sin θ]) the pair turned by v and renormalised to first order, as
    Pinocchio does ((3 − ‖q'‖²)/2 q'). Other joints (a floating base) are not modelled (ValueError)."""
    model = _model(robot_or_model)
    parts = []
    for i in range(1, model.njoints):
        kind, _ = joint_kind(model, i)
        if kind == "mimic":
            continue
        iq, iv = model.joints[i].idx_q, model.joints[i].idx_v
        if kind == "revolute_unbounded":
            c, s, w = q[iq], q[iq + 1], v[iv]
            cw, sw = ca.cos(w), ca.sin(w)
            out = ca.vertcat(cw * c - sw * s, sw * c + cw * s)
            parts.append(out * (3.0 - ca.dot(out, out)) / 2.0)
        else:
            parts.append(q[iq] + v[iv])
    return ca.vertcat(*parts)


# ============================================================================================
# Symbolic rotation logarithm (pose costs of planners.optimal_control)
# ============================================================================================

LOG_TAYLOR = 1e-4
"""Below this 1 − cos ϑ, ϑ/sin ϑ is evaluated by its Taylor series (exact form: 0/0 at ϑ = 0)."""


def rotation_log_expression(R: Any) -> ca.SX:
    """ϑ r, the rotation vector of the rotation matrix ``R`` (3×3 SX), as an SX expression: the inverse of
    the exponential map, Pinocchio's ``log3``, equal to the angle and axis of (2.27)–(2.29) multiplied.

    With cos ϑ = (tr R − 1)/2 and the vee of the skew part w = ½ vee(R − Rᵀ) = r sin ϑ, ϑ r = (ϑ / sin ϑ) w;
    ϑ / sin ϑ = acos(c)/√(1 − c²) is replaced by its series 1 + e/3 + 2e²/15 (e = 1 − c) for e < 1e-4, so the
    expression and its derivatives are finite at ϑ = 0. Defined for ϑ < π (at ϑ = π the axis is not in w).
    """
    c = ca.fmin(ca.fmax(0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0), -1.0), 1.0)
    w = 0.5 * ca.vertcat(R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1])
    e = 1.0 - c
    factor = ca.if_else(e < LOG_TAYLOR, 1.0 + e / 3.0 + 2.0 * e * e / 15.0,
                        ca.acos(c) / ca.sqrt(ca.fmax(1.0 - c * c, 1e-300)))
    return factor * w


# ============================================================================================
# Derivatives of the forward dynamics (optimal control's linearisations)
# ============================================================================================

def _cholesky_factor(B: ca.SX) -> list[list[Any]]:
    """The lower factor L of B = L Lᵀ (symmetric positive definite B), as a list of rows of SX scalars."""
    n = B.shape[0]
    L: list[list[Any]] = [[None] * n for _ in range(n)]
    for j in range(n):
        L[j][j] = ca.sqrt(B[j, j] - sum((L[j][k] * L[j][k] for k in range(j)), ca.SX(0)))
        for i in range(j + 1, n):
            L[i][j] = (B[i, j] - sum((L[i][k] * L[j][k] for k in range(j)), ca.SX(0))) / L[j][j]
    return L


def _factored_solve(L: list[list[Any]], b: ca.SX) -> ca.SX:
    """X = (L Lᵀ)⁻¹ b for each column of b (forward then backward substitution)."""
    n = len(L)
    columns = []
    for c in range(b.shape[1]):
        y: list[Any] = [None] * n
        for i in range(n):
            y[i] = (b[i, c] - sum((L[i][k] * y[k] for k in range(i)), ca.SX(0))) / L[i][i]
        x: list[Any] = [None] * n
        for i in reversed(range(n)):
            x[i] = (y[i] - sum((L[k][i] * x[k] for k in range(i + 1, n)), ca.SX(0))) / L[i][i]
        columns.append(ca.vertcat(*x))
    return ca.horzcat(*columns)


def forward_dynamics_derivatives_expression(robot_or_model: Any, q: Any, qd: Any, tau: Any) -> tuple[ca.SX, ca.SX]:
    """q̈ of (7.42) and its Jacobian ∂q̈/∂[q; q̇; τ] (nv × 3nv) as SX expressions, without differentiating the
    factorisation: Newton–Euler satisfies τ = RNEA(q, q̇, q̈) along the motion, so (implicit functions)
    ∂q̈/∂[q; q̇] = −B(q)⁻¹ ∂RNEA/∂[q; q̇] at the fixed q̈ and ∂q̈/∂τ = B(q)⁻¹ — one Cholesky factor of B for all
    2·nv + 1 right-hand sides; the partials of RNEA by reverse-mode differentiation (one sweep per torque).
    Rotors (mimic joints) and armature included, as in :func:`forward_dynamics_expression`; nq = nv only.
    """
    model = _model(robot_or_model)
    if model.nq != model.nv:
        raise ValueError("forward_dynamics_derivatives_expression needs nq == nv (no continuous or free joints)")

    def build() -> ca.Function:
        n = model.nv
        x, v, t, a = (ca.SX.sym(name, n) for name in ("q", "qd", "tau", "qdd"))
        L = _cholesky_factor(inertia_expression(model, x))
        qdd = _factored_solve(L, ca.reshape(t - inverse_dynamics_expression(model, x, v, ca.SX.zeros(n)), n, 1))
        tau_a = inverse_dynamics_expression(model, x, v, a)
        xv = ca.vertcat(x, v)
        partials = ca.vertcat(*[ca.gradient(tau_a[i], xv).T for i in range(n)])      # ∂RNEA/∂[q; q̇] at a
        partials = ca.substitute(partials, a, qdd)
        J = _factored_solve(L, ca.horzcat(-partials, ca.SX.eye(n)))
        return ca.Function("fd_derivatives", [x, v, t], [qdd, J])

    out = _once("fd_derivatives", model, build)(q, qd, tau)
    return tuple(o if isinstance(o, ca.SX) else ca.SX(o) for o in out)
