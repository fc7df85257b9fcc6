"""The quadratic program of one SQP step of :mod:`planners.optimal_control`, in stage-wise form, and its solvers.

::

    min Σ_k ½ [δτ_k; δx_k]ᵀ [R_k S_k; S_kᵀ Q_k] [δτ_k; δx_k] + r_kᵀ δτ_k + q_kᵀ δx_k  (+ Σ z (s_l + s_u))
    s.t. δx_{k+1} = A_k δx_k + B_k δτ_k + b_k,   lbu ≤ δτ_k ≤ ubu (k < N),
         lbx − s_l ≤ δx_k[limited] ≤ ubx + s_u,  s_l, s_u ≥ 0  (k ≥ 1; hard limits: no slacks).

* :class:`HpipmStageQP` — HPIPM (Frison & Diehl, IFAC 2020), a Riccati-recursion interior point method whose cost grows
  like N, called through its C interface (ctypes) on the ``libhpipm`` that CasADi ships. Nothing in CasADi's Python
  API guarantees that library's interface, so :func:`load_hpipm` checks it before first use: the file beside CasADi
  (or ``$RMPC_HPIPM_LIBRARY``), every function called, HPIPM's interface of CasADi >= 3.8 (``ns``/``idxs_rev``), and
  a test QP with active bounds, hard and soft, solved in a separate process (a different ABI may crash it) and
  compared with :class:`SparseStageQP`'s solution of the same QP. Any failure raises :class:`QPUnavailable` naming it.
* :class:`SparseStageQP` — the same QP and the same outputs (HPIPM's layout and signs) assembled as one sparse QP
  and solved by PIQP (a proximal interior point method, through CasADi's ``conic``; its own library, not HPIPM's)
  or, where CasADi has no PIQP, proxsuite's sparse solver (much slower on active torque limits): the fallback.

:func:`stage_qp` picks one: ``"auto"`` HPIPM, else the fallback with one :class:`QPFallbackWarning` per process
naming why; ``"hpipm"`` HPIPM or the :class:`QPUnavailable` error; ``"piqp"``, ``"proxsuite"`` the fallback's
solvers. Whichever solves, the optimal control solver's success is still decided by its own checks (KKT residual,
defects, hard limits).

References: Frison & Diehl, "HPIPM: a high-performance quadratic programming framework for model predictive
control", IFAC 2020; Schwan et al., "PIQP: a proximal interior-point quadratic programming solver", CDC 2023;
Bambade et al., "PROX-QP: Yet another quadratic programming solver for robotics and beyond", RSS 2022.
"""

from __future__ import annotations

import ctypes
import json
import math
import os
import subprocess
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["QP_SOLVERS", "QPUnavailable", "QPFallbackWarning", "HpipmStageQP", "SparseStageQP", "stage_qp",
           "hpipm_library_path", "load_hpipm"]

QP_SOLVERS = ("auto", "hpipm", "piqp", "proxsuite")
"""The step QP's solvers of :func:`stage_qp`."""
HPIPM_MODES = {"speed_abs": 0, "speed": 1, "balance": 2, "robust": 3}
"""HPIPM's modes (its ``enum hpipm_mode``)."""
PROBE_TOL = 1e-6
"""HPIPM's solution of the test QP must agree with the fallback's to this (relative to 1 + its size)."""
PROBE_TIMEOUT = 60.0
"""Seconds allowed to the process that runs the test QP."""


class QPUnavailable(RuntimeError):
    """HPIPM's library cannot be used (missing, unloadable, another interface, failing its test QP): the reason."""


class QPFallbackWarning(UserWarning):
    """The step QPs are solved by the fallback (:class:`SparseStageQP`) because HPIPM cannot be used (the message
    says why)."""


_C_SIZE, _C_PTR, _C_INT = ctypes.c_size_t, ctypes.c_void_p, ctypes.c_int
_HPIPM: Any = None                    # the checked library, or the QPUnavailable that refused it
_WARNED = False


# --------------------------------------------------------------------------------------------
# HPIPM's library: found, loaded, checked
# --------------------------------------------------------------------------------------------

def hpipm_library_path() -> Path:
    """HPIPM's shared library: ``$RMPC_HPIPM_LIBRARY`` if set, else the ``libhpipm`` beside CasADi's Python module
    (the one its HPIPM plugin loads). Raises :class:`QPUnavailable` when there is none."""
    given = os.environ.get("RMPC_HPIPM_LIBRARY")
    if given:
        path = Path(given)
        if not path.is_file():
            raise QPUnavailable(f"$RMPC_HPIPM_LIBRARY names {given}, which is not a file")
        return path
    import casadi
    folder = Path(casadi.__file__).parent
    found = sorted(folder.glob("libhpipm.so*")) or sorted(folder.glob("libhpipm*.dylib")) \
        or sorted(folder.glob("*hpipm*.dll"))
    if not found:
        raise QPUnavailable(f"HPIPM's library (libhpipm) was not found beside CasADi {casadi.__version__} in {folder}")
    return found[0]


def _signatures() -> dict[str, tuple[Any, list]]:
    """Every HPIPM function called here with its C signature (HPIPM as shipped with CasADi 3.8)."""
    P, I = _C_PTR, _C_INT
    signatures: dict[str, tuple[Any, list]] = {
        "d_ocp_qp_dim_memsize": (_C_SIZE, [I]), "d_ocp_qp_dim_create": (None, [I, P, P]),
        "d_ocp_qp_dim_set_all": (None, [P] * 7), "d_ocp_qp_memsize": (_C_SIZE, [P]),
        "d_ocp_qp_create": (None, [P, P, P]), "d_ocp_qp_sol_memsize": (_C_SIZE, [P]),
        "d_ocp_qp_sol_create": (None, [P, P, P]), "d_ocp_qp_ipm_arg_memsize": (_C_SIZE, [P]),
        "d_ocp_qp_ipm_arg_create": (None, [P, P, P]), "d_ocp_qp_ipm_arg_set_default": (None, [I, P]),
        "d_ocp_qp_ipm_ws_memsize": (_C_SIZE, [P, P]), "d_ocp_qp_ipm_ws_create": (None, [P, P, P, P]),
        "d_ocp_qp_ipm_solve": (None, [P, P, P, P]), "d_ocp_qp_sol_get_all": (None, [P] * 12),
        "d_ocp_qp_set_all": (None, [P] * 27),
    }
    for what in ("dim", "", "sol", "ipm_arg", "ipm_ws"):
        signatures[f"d_ocp_qp_{what + '_' if what else ''}strsize"] = (_C_SIZE, [])
    for field_ in ("idxs_rev", "lbx_mask", "ubx_mask"):
        signatures[f"d_ocp_qp_set_{field_}"] = (None, [I, P, P])
    for field_ in ("iter_max", "tol_stat", "tol_eq", "tol_ineq", "tol_comp", "warm_start", "mu0"):
        signatures[f"d_ocp_qp_ipm_arg_set_{field_}"] = (None, [P, P])
    for field_ in ("status", "iter", "max_res_stat", "max_res_eq", "max_res_ineq", "max_res_comp"):
        signatures[f"d_ocp_qp_ipm_get_{field_}"] = (None, [P, P])
    return signatures


def _open(path: Path) -> Any:
    """The library at ``path`` with the signatures set, or :class:`QPUnavailable` (cannot be loaded, an older
    interface, a function missing)."""
    try:
        lib = ctypes.CDLL(str(path))
    except OSError as error:
        raise QPUnavailable(f"HPIPM's library {path} cannot be loaded ({error})") from None
    if hasattr(lib, "d_ocp_qp_dim_set_nsbx"):      # HPIPM before its interface of August 2025 (ns, idxs_rev)
        raise QPUnavailable(f"the HPIPM in {path} has an older interface than the one called here (HPIPM as shipped "
                            "with CasADi >= 3.8: pip install -U casadi)")
    missing = [name for name in _signatures() if not hasattr(lib, name)]
    if missing:
        raise QPUnavailable(f"the HPIPM in {path} lacks {', '.join(missing[:3])}"
                            f"{' …' if len(missing) > 3 else ''}: not the interface called here (CasADi 3.8's HPIPM)")
    for name, (restype, argtypes) in _signatures().items():
        function = getattr(lib, name)
        function.restype, function.argtypes = restype, argtypes
    return lib


def load_hpipm() -> Any:
    """HPIPM's C library, checked (module docstring) once per process; :class:`QPUnavailable` names what failed."""
    global _HPIPM
    if isinstance(_HPIPM, QPUnavailable):
        raise _HPIPM
    if _HPIPM is not None:
        return _HPIPM
    try:
        path = hpipm_library_path()
        lib = _open(path)
        _probe(path)
    except QPUnavailable as error:
        _HPIPM = error
        raise
    _HPIPM = lib
    return lib


class _ProbeOptions:
    qp_tol, qp_max_iter = 1e-12, 200


def _probe_qps() -> list[tuple[Any, ...]]:
    """Two test QPs (N = 3, 2 states, 1 input, the first state bounded, hard and soft) whose bounds are active:
    (soft, the data as HpipmStageQP's arrays)."""
    rng = np.random.default_rng(7)
    N, nx, nu = 3, 2, 1
    cases = []
    for soft in (False, True):
        data = {}
        M = rng.normal(size=(N + 1, nx + nu, nx + nu))
        H = M @ np.transpose(M, (0, 2, 1)) + 0.5 * np.eye(nx + nu)
        data["R"], data["S"], data["Q"] = H[:, :nu, :nu], H[:, nu:, :nu], H[:, nu:, nu:]     # S: S_kᵀ (nx, nu)
        data["r"], data["q"] = 3.0 * rng.normal(size=(N + 1, nu)), 3.0 * rng.normal(size=(N + 1, nx))
        data["A"] = np.transpose(np.eye(nx) + 0.2 * rng.normal(size=(N + 1, nx, nx)), (0, 2, 1)).copy()
        data["B"] = rng.normal(size=(N + 1, nu, nx))
        data["b"] = 0.05 * rng.normal(size=(N + 1, nx))
        data["lbu"], data["ubu"] = np.full((N + 1, nu), -0.3), np.full((N + 1, nu), 0.4)
        data["lbx"], data["ubx"] = np.full((N + 1, 1), -0.2), np.full((N + 1, 1), 0.25)
        data["zl"], data["zu"] = np.full((N + 1, 1), 2.0), np.full((N + 1, 1), 3.0)
        cases.append((soft, {k: v.tolist() for k, v in data.items()}))
    return cases


def _solve_case(cls: type, soft: bool, data: dict) -> dict[str, list]:
    """Solve one test QP with ``cls``: its solution and multipliers (HPIPM's layout), status and iterations."""
    N, nx, nu = 3, 2, 1
    qp = cls(N, nx, nu, np.array([0]), soft, _ProbeOptions())
    for name, value in data.items():
        getattr(qp, name)[...] = np.asarray(value)
    status, iterations, residual = qp.solve()
    out = {name: getattr(qp, name)[mask].tolist() for name, mask in (
        ("u", np.s_[:N]), ("x", np.s_[1:]), ("pi", np.s_[:N]), ("lam_lb", np.s_[:]), ("lam_ub", np.s_[:]))}
    if soft:
        out.update({name: getattr(qp, name)[1:].tolist() for name in ("sl", "su", "lam_ls", "lam_us")})
    out["status"] = [status]
    return out


def _probe(path: Path) -> None:
    """Solve the test QPs with the library at ``path`` in a separate process and compare with the fallback's:
    :class:`QPUnavailable` if the process crashes, fails or disagrees."""
    code = ("import json, sys; sys.path.insert(0, sys.argv[2]); import planners.stage_qp as m; "
            "m._HPIPM = m._open(m.Path(sys.argv[1])); "
            "print(json.dumps([m._solve_case(m.HpipmStageQP, soft, data) for soft, data in m._probe_qps()]))")
    root = str(Path(__file__).resolve().parent.parent)
    env = dict(os.environ, RMPC_HPIPM_LIBRARY=str(path))
    try:
        run = subprocess.run([sys.executable, "-c", code, str(path), root], capture_output=True, text=True,
                             timeout=PROBE_TIMEOUT, env=env)
    except subprocess.TimeoutExpired:
        raise QPUnavailable(f"HPIPM's library {path} did not finish a test QP within {PROBE_TIMEOUT:g} s") from None
    if run.returncode != 0:
        how = f"crashed (signal {-run.returncode})" if run.returncode < 0 else f"failed ({run.stderr.strip()[-300:]})"
        raise QPUnavailable(f"HPIPM's library {path} {how} on a test QP: its interface differs from the one called "
                            "here (CasADi 3.8's HPIPM)")
    try:
        got = json.loads(run.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        raise QPUnavailable(f"HPIPM's test QP with {path} printed no result") from None
    for (soft, data), hpipm in zip(_probe_qps(), got):
        reference = _solve_case(SparseStageQP, soft, data)
        error = max(float(np.max(np.abs(np.asarray(hpipm[k]) - np.asarray(v)) / (1.0 + np.max(np.abs(v)))))
                    for k, v in reference.items() if k != "status")
        if hpipm["status"][0] != 0 or reference["status"][0] != 0 or not error <= PROBE_TOL:
            raise QPUnavailable(f"HPIPM's library {path} solved a test QP wrongly (status {hpipm['status'][0]}, "
                                f"differs from {SparseStageQP.__name__}'s solution by {error:.1g}): its interface differs from the "
                                "one called here (CasADi 3.8's HPIPM)")


class HpipmStageQP:
    """The QP of one SQP step in HPIPM's stage-wise form, solved by HPIPM's Riccati-based interior point method
    (its C interface, called directly: no CasADi matrices are built per step)::

        min Σ_k ½ [δτ_k; δx_k]ᵀ [R_k S_k; S_kᵀ Q_k] [δτ_k; δx_k] + r_kᵀ δτ_k + q_kᵀ δx_k  (+ Σ z (s_l + s_u))
        s.t. δx_{k+1} = A_k δx_k + B_k δτ_k + b_k,   lbu ≤ δτ_k ≤ ubu (k < N),
             lbx − s_l ≤ δx_k[limited] ≤ ubx + s_u,  s_l, s_u ≥ 0  (k ≥ 1; hard limits: no slacks).

    Stage 0 has no state (x_0 is given). The structure is set once; the numbers are written into the numpy arrays
    below (each stage's matrix as its transpose in C order, i.e. column-major as HPIPM reads it), which HPIPM reads
    through arrays of pointers made once (one call per solve). A state bound can be left out (its mask 0).
    ``options``: ``qp_tol`` (HPIPM's four residual tolerances) and ``qp_max_iter``."""

    name = "HPIPM"

    def __init__(self, N: int, nx: int, nu: int, limited: np.ndarray, soft: bool, options: Any,
                 inputs_of: "HpipmStageQP | None" = None):
        """``inputs_of``: a QP of the same sizes whose arrays of data (not its slack costs) this one reads."""
        lib = self.lib = load_hpipm()
        self.N, self.nx, self.nu = N, nx, nu
        limited = np.ascontiguousarray(limited, dtype=np.int32)
        nb = self.nb = limited.size
        ns = self.ns = nb if soft else 0
        ints = lambda values: np.ascontiguousarray(values, dtype=np.int32)
        self._memory: list[Any] = []
        dims = [ints([0] + [nx] * N), ints([nu] * N + [0]), ints([0] + [nb] * N), ints([nu] * N + [0]),
                ints([0] * (N + 1)), ints([0] + [ns] * N)]
        self._memory += dims
        self.dim = self._block(lib.d_ocp_qp_dim_strsize())
        lib.d_ocp_qp_dim_create(N, self.dim, self._block(lib.d_ocp_qp_dim_memsize(N)))
        lib.d_ocp_qp_dim_set_all(*[d.ctypes.data for d in dims], self.dim)
        self.qp = self._block(lib.d_ocp_qp_strsize())
        lib.d_ocp_qp_create(self.dim, self.qp, self._block(lib.d_ocp_qp_memsize(self.dim)))
        self.sol = self._block(lib.d_ocp_qp_sol_strsize())
        lib.d_ocp_qp_sol_create(self.dim, self.sol, self._block(lib.d_ocp_qp_sol_memsize(self.dim)))
        self.arg = self._block(lib.d_ocp_qp_ipm_arg_strsize())
        lib.d_ocp_qp_ipm_arg_create(self.dim, self.arg, self._block(lib.d_ocp_qp_ipm_arg_memsize(self.dim)))
        lib.d_ocp_qp_ipm_arg_set_default(HPIPM_MODES["robust"], self.arg)
        lib.d_ocp_qp_ipm_arg_set_iter_max(ctypes.byref(ctypes.c_int(options.qp_max_iter)), self.arg)
        for name in ("tol_stat", "tol_eq", "tol_ineq", "tol_comp"):
            getattr(lib, f"d_ocp_qp_ipm_arg_set_{name}")(ctypes.byref(ctypes.c_double(options.qp_tol)), self.arg)
        self.ws = self._block(lib.d_ocp_qp_ipm_ws_strsize())
        lib.d_ocp_qp_ipm_ws_create(self.dim, self.arg, self.ws,
                                   self._block(lib.d_ocp_qp_ipm_ws_memsize(self.dim, self.arg)))
        f, nbs, nss = np.zeros, max(nb, 1), max(ns, 1)
        self.A, self.B, self.b = f((N + 1, nx, nx)), f((N + 1, nu, nx)), f((N + 1, nx))        # A_kᵀ, B_kᵀ
        self.Q, self.S, self.R = f((N + 1, nx, nx)), f((N + 1, nx, nu)), f((N + 1, nu, nu))   # S_kᵀ (S_k: nu × nx)
        self.q, self.r = f((N + 1, nx)), f((N + 1, nu))
        self.lbu, self.ubu, self.lbx, self.ubx = f((N + 1, nu)), f((N + 1, nu)), f((N + 1, nbs)), f((N + 1, nbs))
        self.zl, self.zu = f((N + 1, nss)), f((N + 1, nss))
        self.lbx_mask, self.ubx_mask = np.ones((N + 1, nbs)), np.ones((N + 1, nbs))   # 0: the bound is left out
        if inputs_of is not None:
            for name in ("A", "B", "b", "Q", "S", "R", "q", "r", "lbu", "ubu", "lbx", "ubx", "lbx_mask", "ubx_mask"):
                setattr(self, name, getattr(inputs_of, name))
        self._masks = np.ones((2, N + 1, nbs))                                        # as HPIPM has them
        self.u, self.x, self.pi = f((N + 1, nu)), f((N + 1, nx)), f((N + 1, nx))
        self.sl, self.su, self.lam_ls, self.lam_us = f((N + 1, nss)), f((N + 1, nss)), f((N + 1, nss)), f((N + 1, nss))
        self.lam_lb, self.lam_ub = f((N + 1, nu + nb)), f((N + 1, nu + nb))
        # the structure (the bounded variables, the slack of each bound: −1 hard) and the slacks' fixed data
        # (L1: no quadratic term, s >= 0)
        idxbu, idxbx, zeros = ints(np.arange(nu)), limited, np.zeros((N + 1, nss))
        slack_of = ints(np.concatenate([np.arange(nb) if soft else np.full(nb, -1), np.full(nu, -1)]))
        slack_of_u = ints(np.concatenate([np.full(nu, -1), slack_of[:nb]]))
        unused = f((N + 1, 1))
        self._memory += [idxbu, idxbx, zeros, slack_of, slack_of_u, unused]
        for k in range(1, N + 1):
            if nb:
                lib.d_ocp_qp_set_idxs_rev(k, (slack_of_u if k < N else slack_of).ctypes.data, self.qp)

        def rows(a: np.ndarray) -> Any:
            pointers = (ctypes.c_void_p * (N + 1))(*[a.ctypes.data + k * a.strides[0] for k in range(N + 1)])
            self._memory.append(pointers)
            return pointers

        def same(a: np.ndarray) -> Any:
            pointers = (ctypes.c_void_p * (N + 1))(*[a.ctypes.data] * (N + 1))
            self._memory.append(pointers)
            return pointers

        # d_ocp_qp_set_all(A, B, b, Q, S, R, q, r, idxbx, lbx, ubx, idxbu, lbu, ubu, C, D, lg, ug, Zl, Zu, zl, zu,
        # idxs, idxs_rev, ls, us, qp): idxs, idxs_rev NULL (the soft structure above stays)
        self._all = [rows(self.A), rows(self.B), rows(self.b), rows(self.Q), rows(self.S), rows(self.R), rows(self.q),
                     rows(self.r), same(idxbx), rows(self.lbx), rows(self.ubx), same(idxbu), rows(self.lbu),
                     rows(self.ubu), rows(unused), rows(unused), rows(unused), rows(unused), rows(zeros), rows(zeros),
                     rows(self.zl), rows(self.zu), None, None, rows(zeros), rows(zeros), self.qp]
        self._outputs = [rows(a) for a in (self.u, self.x, self.sl, self.su, self.pi, self.lam_lb, self.lam_ub,
                                           unused, unused, self.lam_ls, self.lam_us)]
        self._mask_setters = [(lib.d_ocp_qp_set_lbx_mask, self.lbx_mask), (lib.d_ocp_qp_set_ubx_mask, self.ubx_mask)]
        self._status, self._iter, self._res = ctypes.c_int(), ctypes.c_int(), ctypes.c_double()
        self._mu0, self._warm = ctypes.c_double(), ctypes.c_int(0)
        self._solved = False                    # HPIPM's solution struct holds a solution to start the next from

    def set_mu0(self, value: float) -> None:
        """HPIPM's initial barrier parameter (of the order of the largest cost gradient: fewer iterations)."""
        self._mu0.value = value
        self.lib.d_ocp_qp_ipm_arg_set_mu0(ctypes.byref(self._mu0), self.arg)

    def _block(self, size: int) -> int:
        """The address of ``size`` fresh bytes aligned to 64 (kept alive with the QP)."""
        memory = np.zeros(int(size) + 64, dtype=np.uint8)
        self._memory.append(memory)
        return (memory.ctypes.data + 63) // 64 * 64

    def solve(self) -> tuple[int, int, float]:
        """Hand the arrays to HPIPM, solve, read the solution into u, x, s_l, s_u, π, λ: (status, iterations, the
        largest of HPIPM's residuals). Status 0: solved to tolerance; 1: iteration limit; 2: step too small; 3: NaN."""
        lib, qp = self.lib, self.qp
        lib.d_ocp_qp_set_all(*self._all)
        if self.nb:
            for m, (setter, mask) in enumerate(self._mask_setters):
                changed = np.flatnonzero(np.any(mask != self._masks[m], axis=1))
                for k in changed[changed > 0]:
                    setter(int(k), mask.ctypes.data + int(k) * mask.strides[0], qp)
                self._masks[m] = mask
        if self._warm.value != (2 if self._solved else 0):
            # start from the previous solution, primal and dual (the QPs of successive SQP iterations and MPC samples
            # are alike: fewer iterations), cold at first and after a failure
            self._warm.value = 2 if self._solved else 0
            lib.d_ocp_qp_ipm_arg_set_warm_start(ctypes.byref(self._warm), self.arg)
        lib.d_ocp_qp_ipm_solve(qp, self.sol, self.arg, self.ws)
        lib.d_ocp_qp_sol_get_all(self.sol, *self._outputs)
        lib.d_ocp_qp_ipm_get_status(self.ws, ctypes.byref(self._status))
        lib.d_ocp_qp_ipm_get_iter(self.ws, ctypes.byref(self._iter))
        worst = 0.0
        for name in ("stat", "eq", "ineq", "comp"):
            getattr(lib, f"d_ocp_qp_ipm_get_max_res_{name}")(self.ws, ctypes.byref(self._res))
            worst = max(worst, self._res.value)
        self._solved = self._status.value in (0, 1) and math.isfinite(worst)
        return self._status.value, self._iter.value, worst


# --------------------------------------------------------------------------------------------
# The fallback: the same QP as one sparse QP (PIQP through CasADi, or proxsuite)
# --------------------------------------------------------------------------------------------

_BIG = 1e20


class SparseStageQP:
    """The QP of :class:`HpipmStageQP` (same arrays in, same outputs in HPIPM's layout and signs out) assembled as
    one sparse QP over z = [τ_0, x_1, τ_1, x_2, …, τ_{N−1}, x_N, s_l, s_u] and solved by ``solver``: ``"piqp"``
    (CasADi's PIQP plugin; proxsuite if CasADi has none) or ``"proxsuite"``, cold-started each step. The
    fallback when HPIPM cannot be used; its residual is computed here from the KKT conditions of the sparse QP."""

    def __init__(self, N: int, nx: int, nu: int, limited: np.ndarray, soft: bool, options: Any,
                 inputs_of: "SparseStageQP | None" = None, solver: str = "piqp"):
        import scipy.sparse
        self._sparse = scipy.sparse
        if solver == "piqp" and not _has_piqp():
            solver = "proxsuite"
        self.name = solver
        self.N, self.nx, self.nu = N, nx, nu
        self.limited = np.asarray(limited, dtype=int)
        nb = self.nb = self.limited.size
        ns = self.ns = nb if soft else 0
        self.eps = max(float(options.qp_tol), 1e-9)
        self.max_iter = max(int(options.qp_max_iter), 1000)
        f, nbs, nss = np.zeros, max(nb, 1), max(ns, 1)
        self.A, self.B, self.b = f((N + 1, nx, nx)), f((N + 1, nu, nx)), f((N + 1, nx))
        self.Q, self.S, self.R = f((N + 1, nx, nx)), f((N + 1, nx, nu)), f((N + 1, nu, nu))
        self.q, self.r = f((N + 1, nx)), f((N + 1, nu))
        self.lbu, self.ubu, self.lbx, self.ubx = f((N + 1, nu)), f((N + 1, nu)), f((N + 1, nbs)), f((N + 1, nbs))
        self.zl, self.zu = f((N + 1, nss)), f((N + 1, nss))
        self.lbx_mask, self.ubx_mask = np.ones((N + 1, nbs)), np.ones((N + 1, nbs))
        if inputs_of is not None:
            for name in ("A", "B", "b", "Q", "S", "R", "q", "r", "lbu", "ubu", "lbx", "ubx", "lbx_mask", "ubx_mask"):
                setattr(self, name, getattr(inputs_of, name))
            self.name = inputs_of.name
        self.u, self.x, self.pi = f((N + 1, nu)), f((N + 1, nx)), f((N + 1, nx))
        self.sl, self.su, self.lam_ls, self.lam_us = f((N + 1, nss)), f((N + 1, nss)), f((N + 1, nss)), f((N + 1, nss))
        self.lam_lb, self.lam_ub = f((N + 1, nu + nb)), f((N + 1, nu + nb))
        # offsets of τ_k (k < N) and x_k (k ≥ 1) in z, and of the slacks
        stride = nu + nx
        self._iu = np.arange(N)[:, None] * stride + np.arange(nu)                  # (N, nu)
        self._ix = np.arange(N)[:, None] * stride + nu + np.arange(nx)             # (N, nx): x_1 … x_N
        self.nz = N * stride
        self._isl = self.nz + np.arange(N * ns).reshape(N, ns)
        self._isu = self.nz + N * ns + np.arange(N * ns).reshape(N, ns)

    def set_mu0(self, value: float) -> None:
        """(HPIPM's barrier parameter: nothing to set here.)"""

    def solve(self) -> tuple[int, int, float]:
        """Assemble and solve: (status as HPIPM's: 0 solved, 1 iteration limit, 3 failed; iterations, the largest
        KKT residual of the sparse QP)."""
        N, nx, nu, nb, ns = self.N, self.nx, self.nu, self.nb, self.ns
        iu, ix, lim = self._iu, self._ix, self.limited
        n_var = self.nz + 2 * N * ns
        rows, cols, vals = [], [], []

        def put(r: np.ndarray, c: np.ndarray, v: np.ndarray) -> None:
            r, c, v = np.broadcast_arrays(r, c, v)
            rows.append(r.ravel()), cols.append(c.ravel()), vals.append(v.ravel())

        # cost: R on τ_k, Q on x_k, S_k (S is S_kᵀ: x rows, τ columns) on both off-diagonal blocks
        put(iu[:, :, None], iu[:, None, :], self.R[:N])
        put(ix[:, :, None], ix[:, None, :], self.Q[1:])
        put(ix[:-1, :, None], iu[1:, None, :], self.S[1:N])
        put(iu[1:, :, None], ix[:-1, None, :], np.transpose(self.S[1:N], (0, 2, 1)))
        H = self._sparse.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                    shape=(n_var, n_var))
        g = np.zeros(n_var)
        g[iu] = self.r[:N]
        g[ix] = self.q[1:]
        if ns:
            g[self._isl], g[self._isu] = self.zl[1:, :nb], self.zu[1:, :nb]
        # dynamics: A_k x_k + B_k τ_k − x_{k+1} = −b_k (A and B stored transposed)
        rows, cols, vals = [], [], []
        eq = np.arange(N * nx).reshape(N, nx)
        put(eq[:, :, None], iu[:, None, :], np.transpose(self.B[:N], (0, 2, 1)))
        put(eq[1:, :, None], ix[:-1, None, :], np.transpose(self.A[1:N], (0, 2, 1)))
        put(eq, ix, -1.0)
        A_eq = self._sparse.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                       shape=(N * nx, n_var))
        b_eq = -self.b[:N].ravel()
        # inequalities: the torque box, the state bounds left in (masks), the slacks' signs
        rows, cols, vals, low, up = [], [], [], [], []
        m = 0

        def rows_of(index: np.ndarray, lo: np.ndarray, hi: np.ndarray, extra: np.ndarray | None = None,
                    sign: float = 0.0) -> np.ndarray:
            nonlocal m
            r = m + np.arange(index.size)
            put(r, index.ravel(), 1.0)
            if extra is not None:
                put(r, extra.ravel(), sign)
            low.append(np.ravel(lo)), up.append(np.ravel(hi))
            m += index.size
            return r

        row_u = rows_of(iu, self.lbu[:N], self.ubu[:N]).reshape(N, nu)
        lower_on = self.lbx_mask[1:, :nb] > 0.5
        upper_on = self.ubx_mask[1:, :nb] > 0.5
        y_index = ix[:, lim] if nb else np.zeros((N, 0), dtype=int)
        lbx, ubx = self.lbx[1:, :nb], self.ubx[1:, :nb]
        if ns:                        # lbx ≤ y + s_l, y − s_u ≤ ubx, s ≥ 0 (a bound left out: its row dropped)
            row_l = rows_of(y_index[lower_on], lbx[lower_on], np.full(lower_on.sum(), _BIG),
                            self._isl[lower_on], 1.0)
            row_h = rows_of(y_index[upper_on], np.full(upper_on.sum(), -_BIG), ubx[upper_on],
                            self._isu[upper_on], -1.0)
            row_sl = rows_of(self._isl, np.zeros(N * ns), np.full(N * ns, _BIG)).reshape(N, ns)
            row_su = rows_of(self._isu, np.zeros(N * ns), np.full(N * ns, _BIG)).reshape(N, ns)
        else:
            on = lower_on | upper_on
            row_b = rows_of(y_index[on], np.where(lower_on, lbx, -_BIG)[on], np.where(upper_on, ubx, _BIG)[on])
        C = self._sparse.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                    shape=(m, n_var))
        l, u = np.concatenate(low), np.concatenate(up)
        z, y, w, status, iterations, residual = self._solve(H, g, A_eq, b_eq, C, l, u)
        # back to HPIPM's layout: stage k's bound multipliers [τ bounds, x bounds] (≥ 0), π_k of the dynamics k
        self.u[:N], self.x[1:], self.pi[:N] = z[iu], z[ix], y.reshape(N, nx)
        self.lam_lb[...] = 0.0
        self.lam_ub[...] = 0.0
        self.lam_lb[:N, :nu], self.lam_ub[:N, :nu] = np.maximum(-w[row_u], 0.0), np.maximum(w[row_u], 0.0)
        x_lb, x_ub = np.zeros((N, nb)), np.zeros((N, nb))
        if ns:
            x_lb[lower_on], x_ub[upper_on] = np.maximum(-w[row_l], 0.0), np.maximum(w[row_h], 0.0)
            self.sl[1:, :ns], self.su[1:, :ns] = z[self._isl], z[self._isu]
            self.lam_ls[1:, :ns], self.lam_us[1:, :ns] = np.maximum(-w[row_sl], 0.0), np.maximum(-w[row_su], 0.0)
        elif nb:
            on = lower_on | upper_on
            x_lb[on], x_ub[on] = np.maximum(-w[row_b], 0.0), np.maximum(w[row_b], 0.0)
        if nb:
            self.lam_lb[1:N, nu:nu + nb], self.lam_ub[1:N, nu:nu + nb] = x_lb[:-1], x_ub[:-1]
            self.lam_lb[N, :nb], self.lam_ub[N, :nb] = x_lb[-1], x_ub[-1]
        return status, iterations, residual

    def _solve(self, H: Any, g: np.ndarray, A: Any, b: np.ndarray, C: Any, l: np.ndarray, u: np.ndarray) -> tuple:
        """min ½ zᵀHz + gᵀz s.t. Az = b, l ≤ Cz ≤ u: (z, y, w (> 0 at an upper bound), status, iterations, the
        largest residual of the KKT conditions at the solution, computed here); the Lagrangian
        ½ zᵀHz + gᵀz + yᵀ(Az − b) + wᵀCz."""
        if self.name == "piqp":
            z, y, w, status, iterations = self._piqp(H, g, A, b, C, l, u)
        else:
            z, y, w, status, iterations = self._proxsuite_solve(H, g, A, b, C, l, u)
        if not (np.all(np.isfinite(z)) and np.all(np.isfinite(y)) and np.all(np.isfinite(w))):
            return z, y, w, 3, iterations, math.inf
        Cz = C @ z
        residual = max(float(np.max(np.abs(H @ z + g + A.T @ y + C.T @ w), initial=0.0)),
                       float(np.max(np.abs(A @ z - b), initial=0.0)),
                       float(np.max(np.maximum(l - Cz, 0.0), initial=0.0)),
                       float(np.max(np.maximum(Cz - u, 0.0), initial=0.0)))
        return z, y, w, status, iterations, residual

    def _piqp(self, H: Any, g: np.ndarray, A: Any, b: np.ndarray, C: Any, l: np.ndarray, u: np.ndarray) -> tuple:
        """PIQP (a proximal interior point method for sparse QPs) through CasADi's ``conic``."""
        import casadi as ca

        def dm(M: Any) -> Any:
            M = M.tocsc()
            M.sort_indices()
            return ca.DM(ca.Sparsity(M.shape[0], M.shape[1], M.indptr.tolist(), M.indices.tolist()), M.data)

        AC = self._sparse.vstack([A, C]).tocsc()
        lba, uba = np.r_[b, l], np.r_[b, u]
        lba[lba <= -_BIG], uba[uba >= _BIG] = -np.inf, np.inf
        Hu = self._sparse.triu(H).tocsc()                          # (CasADi reads the upper triangle)
        Hd, ACd = dm(Hu + self._sparse.triu(H, 1).T), dm(AC)
        solver = ca.conic("step_qp", "piqp", {"h": Hd.sparsity(), "a": ACd.sparsity()},
                          {"piqp": {"eps_abs": self.eps, "eps_rel": 0.0, "max_iter": self.max_iter},
                           "print_time": False, "error_on_fail": False})
        out = solver(h=Hd, g=g, a=ACd, lba=lba, uba=uba)
        stats = solver.stats()
        lam = np.asarray(out["lam_a"]).ravel()
        n_eq = A.shape[0]
        status = 0 if stats.get("success") else 1 if "max_iter" in str(stats.get("return_status", "")).lower() else 3
        return (np.asarray(out["x"]).ravel(), lam[:n_eq], lam[n_eq:], status, int(stats.get("iter_count", -1)))

    def _proxsuite_solve(self, H: Any, g: np.ndarray, A: Any, b: np.ndarray, C: Any, l: np.ndarray,
                         u: np.ndarray) -> tuple:
        """proxsuite's sparse proximal augmented Lagrangian solver (when CasADi has no PIQP)."""
        import proxsuite
        qp = proxsuite.proxqp.sparse.QP(H.shape[0], A.shape[0], C.shape[0])
        qp.settings.eps_abs, qp.settings.eps_rel = self.eps, 0.0
        qp.settings.max_iter = self.max_iter
        qp.settings.verbose = False
        qp.settings.eps_primal_inf = qp.settings.eps_dual_inf = 1e-8    # (1e-4: false alarms on these QPs)
        qp.init(H, g, A, b, C, l, u)
        qp.solve()
        out, codes = qp.results.info.status, proxsuite.proxqp.QPSolverOutput
        status = 0 if out == codes.PROXQP_SOLVED else 1 if out == codes.PROXQP_MAX_ITER_REACHED else 3
        return qp.results.x, qp.results.y, qp.results.z, status, int(qp.results.info.iter)


# --------------------------------------------------------------------------------------------
# The choice
# --------------------------------------------------------------------------------------------

def _has_piqp() -> bool:
    """Whether CasADi can load its PIQP plugin."""
    import casadi as ca
    try:
        return bool(ca.has_conic("piqp"))
    except Exception:                       # noqa: BLE001 — an older CasADi without has_conic or the plugin
        return False


def check_qp_solver(solver: Any) -> str:
    """``solver`` if it names one of :data:`QP_SOLVERS`, else a ValueError naming `qp_solver`."""
    if solver not in QP_SOLVERS:
        raise ValueError(f"`qp_solver` must be one of {QP_SOLVERS}, got {solver!r}")
    return solver


def stage_qp(N: int, nx: int, nu: int, limited: np.ndarray, soft: bool, options: Any, solver: str = "auto",
             inputs_of: Any = None) -> HpipmStageQP | SparseStageQP:
    """The step QP by ``solver`` (:data:`QP_SOLVERS`): ``"auto"`` HPIPM if its library passes :func:`load_hpipm`'s
    checks, else :class:`SparseStageQP` (PIQP, or proxsuite) with one :class:`QPFallbackWarning` per process;
    ``"hpipm"`` HPIPM or :class:`QPUnavailable`; ``"piqp"``, ``"proxsuite"`` :class:`SparseStageQP` with that
    solver. ``inputs_of``: a QP (of the same class) whose data arrays this one reads."""
    global _WARNED
    check_qp_solver(solver)
    if inputs_of is not None:
        return type(inputs_of)(N, nx, nu, limited, soft, options, inputs_of=inputs_of)
    if solver in ("piqp", "proxsuite"):
        return SparseStageQP(N, nx, nu, limited, soft, options, solver=solver)
    try:
        load_hpipm()
    except QPUnavailable as error:
        if solver == "hpipm":
            raise
        fallback = SparseStageQP(N, nx, nu, limited, soft, options)
        if not _WARNED:
            _WARNED = True
            warnings.warn(f"{error}; the optimal control QPs are solved by {fallback.name} instead (slower per "
                          f"step; qp_solver='{fallback.name}' chooses it explicitly)", QPFallbackWarning,
                          stacklevel=3)
        return fallback
    return HpipmStageQP(N, nx, nu, limited, soft, options)
