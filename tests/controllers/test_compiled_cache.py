"""The compiled loop's cache: keyed without generating code, reused, safe under concurrency (threads and
processes), and never stopping a run: no compiler, a failing compiler or an unusable cache run the Python loop
with one warning; a full or read-only cache builds in a temporary folder (issue 26, items 8–9)."""

import errno
import json
import os
import re
import subprocess
import sys
import threading
import warnings
from pathlib import Path

import numpy as np
import pytest

import controllers.compiled as compiled
import rigid_body.codegen as codegen
from controllers.joint_space import InverseDynamicsControl, PDGravityCompensation
from controllers.plants import ArmPlant
from controllers.simulation import simulate
from planners.timing import quintic
from rigid_body.robots import load

Q_D = np.array([np.pi / 4, -np.pi / 2])
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    """An empty cache directory and nothing built or loaded in this process."""
    cache = tmp_path / "cache"
    monkeypatch.setattr(codegen, "CACHE", cache)
    monkeypatch.setattr(codegen, "_loaded", {})
    monkeypatch.setattr(compiled, "_LOOPS", compiled.OrderedDict())
    return cache


def _run(backend, gains=(400.0, 40.0), n=0.3):
    arm = load("planar_2r")
    plant = ArmPlant(arm, viscous_friction=100.0)
    return simulate(plant, PDGravityCompensation(arm, *gains, Q_D), (0.0, n), plant.initial_state(Q_D - 0.1),
                    h=1e-3, backend=backend)


def test_the_key_is_the_structure_not_the_gains_nor_the_reference():
    arm = load("planar_2r")
    plant = ArmPlant(arm, viscous_friction=100.0)
    key = lambda ctrl, p=plant: compiled.loop_key(p, ctrl, 1e-3, 1, 100)
    base = key(PDGravityCompensation(arm, 400, 40, Q_D))
    assert key(PDGravityCompensation(arm, 900, 10, Q_D + 0.2)) == base             # parameters and references
    assert key(PDGravityCompensation(arm, 400, 40, quintic(Q_D, Q_D + 0.1, 1.0, dt=1e-3))) == base
    assert key(PDGravityCompensation(load("planar_2r"), 400, 40, Q_D)) == base      # an equal model
    assert key(PDGravityCompensation(arm, 400, 40, Q_D), ArmPlant(arm, viscous_friction=50.0)) != base
    assert key(PDGravityCompensation(arm, [400, 300], 40, Q_D)) == base            # diagonal gains: same shape
    assert key(InverseDynamicsControl(arm, 400, 40, Q_D)) != base
    assert compiled.loop_key(plant, PDGravityCompensation(arm, 400, 40, Q_D), 1e-3, 1, 101) != base
    other = load("planar_2r")
    other.model.inertias[2].mass = 3.0                                               # a model changed in place
    assert key(PDGravityCompensation(other, 400, 40, Q_D), ArmPlant(other, viscous_friction=100.0)) != base


def test_repeated_call_reuses_the_loop_and_keeps_the_gains_apart(fresh_cache):
    a = _run("casadi")
    loops = dict(compiled._LOOPS)
    b = _run("casadi", gains=(900.0, 60.0))
    assert dict(compiled._LOOPS) == loops and len(loops) == 1                       # one loop, reused
    np.testing.assert_allclose(a.x, _run("python").x, atol=1e-9)
    np.testing.assert_allclose(b.x, _run("python", gains=(900.0, 60.0)).x, atol=1e-9)


def test_a_fresh_process_loads_the_run_without_building_it(fresh_cache):
    """The disk cache: the library and the names of its signals; a new process finds them by the key alone."""
    _run("casadi")
    assert len(list(fresh_cache.glob("rollout_*.so"))) == 1
    meta = json.loads(next(fresh_cache.glob("rollout_*.json")).read_text())
    assert meta["signals"] == ["q_d", "e"]
    codegen._loaded.clear()
    compiled._LOOPS.clear()
    arm = load("planar_2r")
    plant = ArmPlant(arm, viscous_friction=100.0)
    loop = compiled.compiled_loop(plant, PDGravityCompensation(arm, 400, 40, Q_D), 1e-3, 1, 301)
    assert loop.build_time == 0.0 and loop._sample is None                           # nothing symbolic was built


def test_two_threads_build_one_loop_into_a_fresh_cache(fresh_cache):
    expected = _run("python")
    results, errors = [], []

    def work():
        try:
            results.append(_run("casadi"))
        except Exception as exc:                      # noqa: BLE001 — reported below
            errors.append(exc)

    threads = [threading.Thread(target=work) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for res in results:
        np.testing.assert_allclose(res.x, expected.x, rtol=0, atol=1e-9)
    assert len(list(fresh_cache.glob("rollout_*.so"))) == 1
    assert not [p for p in fresh_cache.iterdir() if p.suffix in (".c",) or p.name.count(".") > 1]   # no partial files


_WORKER = """
import sys, numpy as np
sys.path.insert(0, {root!r})
from controllers.joint_space import PDGravityCompensation
from controllers.plants import ArmPlant
from controllers.simulation import simulate
from rigid_body.robots import load
arm = load("planar_2r")
plant = ArmPlant(arm, viscous_friction=100.0)
res = simulate(plant, PDGravityCompensation(arm, 400.0, 40.0, np.array([np.pi / 4, -np.pi / 2])), (0.0, 0.3),
               plant.initial_state(np.array([np.pi / 4, -np.pi / 2]) - 0.1), h=1e-3, backend="casadi")
np.save(sys.argv[1], res.x)
"""


def test_two_processes_build_one_loop_into_a_fresh_cache(tmp_path):
    cache = tmp_path / "shared"
    script = tmp_path / "worker.py"
    script.write_text(_WORKER.format(root=str(ROOT)))
    env = {**os.environ, "RMPC_CACHE": str(cache)}
    procs = [subprocess.Popen([sys.executable, str(script), str(tmp_path / f"x{i}.npy")], env=env,
                              stderr=subprocess.PIPE) for i in range(2)]
    for p in procs:
        assert p.wait(timeout=600) == 0, p.stderr.read().decode()
    x0, x1 = (np.load(tmp_path / f"x{i}.npy") for i in range(2))
    np.testing.assert_array_equal(x0, x1)
    np.testing.assert_allclose(x0, _run("python").x, rtol=0, atol=1e-9)
    assert len(list(cache.glob("rollout_*.so"))) == 1


@pytest.mark.parametrize("fault", ["no compiler", "failing compiler", "cache is a file"])
def test_a_compiler_or_cache_fault_runs_the_python_loop_with_one_warning(fresh_cache, monkeypatch, fault):
    if fault == "no compiler":
        monkeypatch.setattr(codegen, "compiler", lambda: None)
        match = "no C compiler found: install gcc"
    elif fault == "failing compiler":
        monkeypatch.setenv("CC", "/bin/false")
        match = "C compiler `/bin/false` failed"
    else:
        fresh_cache.write_text("not a directory")
        match = "RMPC_CACHE=.* is not a directory"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = _run("casadi")
    messages = [str(w.message) for w in caught]
    assert len(messages) == 1 and "Python backend" in messages[0], messages
    assert re.search(match, messages[0]), messages[0]                           # which fault, and what to fix
    np.testing.assert_array_equal(res.x, _run("python").x)                     # the Python loop itself


def test_a_full_or_read_only_cache_builds_in_a_temporary_folder(fresh_cache, monkeypatch):
    real = codegen._build_library

    def full(code, name, key, cache, *args):
        if cache == fresh_cache:
            raise OSError(errno.ENOSPC, "No space left on device")
        return real(code, name, key, cache, *args)

    monkeypatch.setattr(codegen, "_build_library", full)
    with warnings.catch_warnings():
        warnings.simplefilter("error")                               # compiled, without falling back
        res = _run("casadi")
    np.testing.assert_allclose(res.x, _run("python").x, rtol=0, atol=1e-9)
    assert codegen._temporary and list(codegen._temporary[0].glob("rollout_*.so"))
    monkeypatch.setattr(codegen.os, "access", lambda path, mode: False)           # read-only
    assert codegen._usable_cache(fresh_cache) == codegen._temporary[0]


def test_rmpc_solve_9_3_survives_a_failing_compiler_and_a_cache_that_is_a_file(tmp_path):
    """The CLI: CC=/bin/false, then RMPC_CACHE naming a file — `rmpc solve 9.3` still solves (exit 0)."""
    cache_file = tmp_path / "a-file"
    cache_file.write_text("")
    for env in ({"CC": "/bin/false", "RMPC_CACHE": str(tmp_path / "empty-cache")}, {"RMPC_CACHE": str(cache_file)}):
        run = subprocess.run([sys.executable, "-m", "problems.cli", "solve", "9.3"], cwd=ROOT, capture_output=True,
                             env={**os.environ, **env}, timeout=900)
        assert run.returncode == 0, run.stderr.decode()[-2000:]
        assert "Python backend" in run.stderr.decode()


def test_the_digest_takes_modules_and_opaque_objects():
    """A block holding a module or an extension object without attributes: the digest names the module and
    keys the object by itself (never reused for another object)."""
    import types as pytypes

    class Opaque:
        __slots__ = ()

    class Block:
        def __init__(self):
            self.module, self.handle = np, Opaque()

    a, b = Block(), Block()
    assert compiled.structure_digest(a) != compiled.structure_digest(b)              # two opaque handles
    assert compiled.structure_digest(a) == compiled.structure_digest(a)
    assert isinstance(np, pytypes.ModuleType)


def test_compile_function_without_a_compiler_runs_interpreted(fresh_cache, monkeypatch):
    """The generic helper (used beyond the loop, e.g. by planners.optimal_control) keeps working: interpreted,
    one warning naming the fault."""
    import casadi as ca

    x = ca.SX.sym("x")
    f = ca.Function("square", [x], [x * x])
    monkeypatch.setenv("CC", "/bin/false")
    with pytest.warns(UserWarning, match="compiler `/bin/false` failed.*interpreted"):
        g = codegen.compile_function(f)
    assert float(g(3.0)) == 9.0


class _SE3Target:
    """A user's law holding a ``pin.SE3`` target: u = K_P (p_xy − q) − K_D q̇ + g(q), p_xy the target's
    translation baked into the body as constants (the compiled loop must be keyed by the SE3's value)."""

    @staticmethod
    def make(robot, translation):
        import pinocchio as pin

        from controllers.laws import ControlLaw, as_gain, as_reference

        class SE3TargetLaw(ControlLaw):
            def __init__(self):
                self.robot, self.nq, self.nv = robot, robot.nq, robot.nv
                self._model, self._data = robot.model, robot.data
                self.target = pin.SE3(np.eye(3), np.asarray(translation, dtype=float))
                self.set_gains(K_P=as_gain(400.0, robot.nv, "K_P"), K_D=as_gain(40.0, robot.nv, "K_D"))
                self.reference = as_reference(np.zeros(robot.nv), robot.nv)       # unused
                self.reference_shapes = ((robot.nv,),) * 3

            def law(self, ops, K, q, qd, ref):
                e = self.target.translation[:2] - q
                return ops.gravity(self._model, self._data, q) + ops.times(K["K_P"], e) - ops.times(K["K_D"], qd), {}

        return SE3TargetLaw()


def test_the_key_reads_extension_objects_by_value(fresh_cache):
    """Two laws differing only in a pin.SE3 attribute's translation: different keys, and each compiled run
    equals its own Python run (the second never reuses the first's loop)."""
    arm = load("planar_2r")
    plant = ArmPlant(arm, viscous_friction=100.0)
    a, b = _SE3Target.make(arm, [0.5, -0.5, 0.0]), _SE3Target.make(arm, [0.2, 0.3, 0.0])
    assert compiled.structure_digest(a) != compiled.structure_digest(b)
    assert compiled.structure_digest(a) == compiled.structure_digest(_SE3Target.make(arm, [0.5, -0.5, 0.0]))
    x0 = plant.initial_state(np.zeros(2))
    for law in (a, b):
        fast = simulate(plant, law, (0.0, 0.2), x0, h=1e-3, backend="casadi")
        slow = simulate(plant, law, (0.0, 0.2), x0, h=1e-3)
        np.testing.assert_allclose(fast.x, slow.x, rtol=0, atol=1e-9)
    assert abs(fast.x[-1] - simulate(plant, a, (0.0, 0.2), x0, h=1e-3).x[-1]).max() > 1e-3    # they differ


def test_the_key_reads_partials_and_attribute_names_in_full():
    """functools.partial over large arrays is keyed by its arguments (not a truncated repr); an attribute is
    skipped by its class's declaration (``runtime_attributes``), not by a common name such as ``data``."""
    import functools

    class Block:
        def __init__(self, **attributes):
            self.__dict__.update(attributes)

    u, v = np.zeros(2000), np.zeros(2000)
    v[1000] = 1.0
    assert compiled.structure_digest(Block(f=functools.partial(np.dot, u))) != \
        compiled.structure_digest(Block(f=functools.partial(np.dot, v)))
    assert compiled.structure_digest(Block(f=functools.partial(np.dot, u))) == \
        compiled.structure_digest(Block(f=functools.partial(np.dot, u.copy())))
    for name in ("data", "rng", "stall", "transitions", "_measured"):
        assert compiled.structure_digest(Block(**{name: u})) != compiled.structure_digest(Block(**{name: v})), name

    class Logged(Block):
        runtime_attributes = ("log",)

    assert compiled.structure_digest(Logged(log=u)) == compiled.structure_digest(Logged(log=v))
