"""C code from CasADi functions, compiled once and cached: the one compiler and cache of rmpc.

:func:`compile_function` generates a ``casadi.Function`` as C, compiles it with the system C compiler into a shared
library under ``$RMPC_CACHE`` (default ``<tmp>/rmpc-casadi``) and loads it; a later call (in this process or another)
loads the library by its key. Used by the compiled simulation loop (:mod:`controllers.compiled`) and by optimal
control (:mod:`planners.optimal_control`, its linearisation built for the host's instruction set: ``native=True``).
It lives in ``rigid_body`` so that both can import it.

Safe under concurrency: one lock per key between the threads of a process, a file lock per key between processes,
unique temporary files published by an atomic rename. A cache that is full or read-only is replaced by a temporary
folder; no compiler, a failing compiler or a cache that cannot be used at all raise
:class:`CompiledLoopUnavailable` (one line saying what to fix), which :func:`compile_function` turns into one
warning and the function interpreted by CasADi (the compiled loop into the Python loop). The logger
``rmpc.compiler`` says when a library is built (two INFO lines: ``rmpc report`` shows them as its progress).

Reference: Andersson et al., *CasADi*, Math. Prog. Comp. 11 (2019) (code generation).
"""

from __future__ import annotations

import errno
import hashlib
import json
import logging
import os
import platform
import shutil
import subprocess
import tempfile
import threading
import time
import warnings
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator

import casadi as ca

__all__ = ["CACHE", "COMPILE_FLAGS", "CompiledLoopUnavailable", "compiler", "c_code", "compile_function",
           "compiled_library", "host_digest", "key_lock"]

log = logging.getLogger("rmpc.compiler")    # a stable name: rmpc report listens to it
"""Tells when a compiled function is built (the first run on a machine compiles each loop once: ~1 s each):
``rmpc report`` shows its INFO lines as its progress while the compiler works."""

CACHE = Path(os.environ.get("RMPC_CACHE", Path(tempfile.gettempdir()) / "rmpc-casadi"))
_loaded: dict[str, tuple[ca.Function, dict | None]] = {}   # libraries loaded in this process (and metadata), by key
_key_locks: dict[str, threading.Lock] = {}       # one lock per key: threads of this process build a key once
_key_locks_guard = threading.Lock()


class CompiledLoopUnavailable(RuntimeError):
    """Compiled code cannot be built here: ``kind`` is ``"no compiler"``, ``"compiler failed"`` or
    ``"cache unusable"``; the message (one line) says what to fix. :func:`controllers.simulation.simulate`
    then runs the Python loop (the same results) with that line as a warning; :func:`compile_function` returns
    the function interpreted by CasADi with it as a warning."""

    def __init__(self, kind: str, message: str):
        super().__init__(message)
        self.kind = kind


def compiler() -> str | None:
    """The system C compiler (``$CC``, ``cc``, ``gcc`` or ``clang``), None when there is none."""
    for name in (os.environ.get("CC"), "cc", "gcc", "clang"):
        if name and shutil.which(name):
            return name
    return None


def c_code(function: ca.Function) -> bytes:
    """The C source CasADi generates for ``function``."""
    name = function.name()
    with tempfile.TemporaryDirectory() as tmp:
        generator = ca.CodeGenerator(f"{name}.c", {"with_header": False})
        generator.add(function)
        generator.generate(tmp + os.sep)
        return (Path(tmp) / f"{name}.c").read_bytes()


COMPILE_FLAGS = ("-O1",)
"""The C compiler's optimisation: CasADi's generated code is straight-line arithmetic, which ``-O1`` compiles
about 40 % faster than ``-O2`` and runs as fast (Puma 560 PD + g rollout: 8.1 ms with either)."""


def key_lock(key: str) -> threading.Lock:
    """The lock of ``key`` between this process's threads (one per key: a key is built once)."""
    with _key_locks_guard:
        return _key_locks.setdefault(key, threading.Lock())


@contextmanager
def _file_lock(path: Path) -> Iterator[None]:
    """An exclusive lock on ``path`` (created) between processes (``fcntl.flock``; a no-op where there is none)."""
    try:
        import fcntl
    except ImportError:                                  # not POSIX: the atomic rename still protects the files
        yield
        return
    with open(path, "a+b") as handle:
        fcntl.flock(handle.fileno(), fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle.fileno(), fcntl.LOCK_UN)


def _usable_cache(cache: Path) -> Path:
    """The cache directory, created if needed; a temporary directory when it exists but cannot be written
    (read-only); :class:`CompiledLoopUnavailable` when it is not a directory at all (``RMPC_CACHE`` names a
    file) or cannot be made."""
    if cache.exists() and not cache.is_dir():
        raise CompiledLoopUnavailable("cache unusable", f"the compiled-loop cache RMPC_CACHE={cache} is not a directory: "
                                      "point RMPC_CACHE at a writable directory (or unset it)")
    try:
        cache.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        if cache.exists() and cache.is_dir():
            pass
        elif isinstance(err, PermissionError) or err.errno in (errno.EROFS, errno.EACCES):
            return _temporary_cache()
        else:
            raise CompiledLoopUnavailable("cache unusable", f"the compiled-loop cache RMPC_CACHE={cache} cannot be "
                                          f"created ({err.strerror}): point RMPC_CACHE at a writable directory") from None
    if not os.access(cache, os.W_OK | os.X_OK):
        return _temporary_cache()
    return cache


_temporary: list[Path] = []


def _temporary_cache() -> Path:
    """One temporary directory per process, for a cache that is full or read-only (removed at exit)."""
    if not _temporary:
        import atexit

        path = Path(tempfile.mkdtemp(prefix="rmpc-casadi-"))
        atexit.register(shutil.rmtree, path, True)
        _temporary.append(path)
    return _temporary[0]


def _build_library(code: bytes, name: str, key: str, cache: Path, cc: str, flags: tuple[str, ...],
                   metadata: bytes | None) -> Path:
    """Compile ``code`` into ``cache/{name}_{key}.so`` (and its metadata beside it): under a file lock per key,
    into unique temporary names published by an atomic rename, so that threads and processes building the
    same key never see a partial file; a library already there is taken as it is."""
    library = cache / f"{name}_{key}.so"
    with _file_lock(cache / f"{name}_{key}.lock"):
        if library.exists():
            return library
        fd, c_path = tempfile.mkstemp(prefix=f"{name}_{key}.", suffix=".c", dir=cache)
        so_path = c_path[:-2] + ".so"
        try:
            with os.fdopen(fd, "wb") as handle:
                handle.write(code)
            result = subprocess.run([cc, *flags, "-fPIC", "-shared", c_path, "-o", so_path, "-lm"],
                                    capture_output=True)
            if result.returncode != 0:
                detail = (result.stderr.decode(errors="replace").strip().splitlines() or ["no message"])[0]
                if any(s in detail for s in ("No space left", "Read-only file system", "Permission denied")):
                    raise OSError(errno.ENOSPC, detail)
                raise CompiledLoopUnavailable("compiler failed", f"the C compiler `{cc}` failed (exit {result.returncode}"
                                              f": {detail[:160]}): fix it or set CC to a working compiler")
            if metadata is not None:
                meta_fd, meta_path = tempfile.mkstemp(prefix=f"{name}_{key}.", suffix=".json", dir=cache)
                with os.fdopen(meta_fd, "wb") as handle:
                    handle.write(metadata)
                os.replace(meta_path, cache / f"{name}_{key}.json")
            os.replace(so_path, library)                                 # atomic: the library appears whole
        finally:
            for path in (c_path, so_path):
                if os.path.exists(path):
                    os.remove(path)
    return library


def compile_function(function: ca.Function | Callable[[], ca.Function], flags: tuple[str, ...] = COMPILE_FLAGS,
                     name: str | None = None, key: bytes | None = None, native: bool = False) -> ca.Function:
    """``function`` generated as C, compiled into a shared library (cached) and loaded.

    The cache key is the hash of the code, or of ``key`` (bytes that determine the code, e.g. a structure digest)
    with ``name``: then ``function`` may be a callable that builds it, called only when the cache misses. With
    ``native`` the library is built for this machine's instruction set (``-march=native``, the host's digest
    :func:`host_digest` in the flags, so a cache shared with another machine never loads it there; the plain
    ``flags`` when the compiler refuses them).
    Safe under concurrency (a lock per key, unique temporary files, an atomic rename); a cache that is full or
    read-only is replaced by a temporary folder. Without a usable compiler or cache the function is returned as
    it is, interpreted by CasADi, with one warning line naming the fault (the compiled loop instead falls back to
    the Python loop: :class:`CompiledLoopUnavailable`).
    """
    try:
        return compiled_library(function, flags, name, key, native=native)[0]
    except CompiledLoopUnavailable as fault:
        warnings.warn(f"{fault}; the function runs interpreted by CasADi (slower)", stacklevel=2)
        return function if key is None else function()


def compiled_library(function: ca.Function | Callable[[], ca.Function], flags: tuple[str, ...] = COMPILE_FLAGS,
                     name: str | None = None, key: bytes | None = None,
                     metadata: Callable[[], bytes] | None = None,
                     native: bool = False) -> tuple[ca.Function, dict | None]:
    """:func:`compile_function`, raising :class:`CompiledLoopUnavailable` on a compiler or cache fault, and the
    metadata stored beside the library: ``metadata()`` (JSON bytes, called when the library is built) is written
    beside it and read back (None without ``metadata`` or when none is stored)."""
    if native:
        try:
            return compiled_library(function, (*flags, "-march=native", f"-DRMPC_HOST={host_digest()}"), name, key,
                                    metadata)
        except CompiledLoopUnavailable as fault:
            if fault.kind != "compiler failed":
                raise                                       # a compiler without -march=native: the plain flags
    cc = compiler()
    if cc is None:
        raise CompiledLoopUnavailable("no compiler", "no C compiler found: install gcc (or clang) or set CC to one")
    code = None
    if key is None:
        name, code = function.name(), c_code(function)
        key = code
    digest = hashlib.sha256(key + " ".join((cc, *flags)).encode()).hexdigest()[:16]
    with key_lock(digest):
        if digest in _loaded:
            return _loaded[digest]
        cache = _usable_cache(CACHE)
        library = cache / f"{name}_{digest}.so"
        for attempt in range(2):
            try:
                if not library.exists():
                    started = time.perf_counter()
                    log.info("compiling %s (C code for %s; once, then loaded from %s)", name, cc, cache)
                    code = code if code is not None else c_code(function())
                    library = _build_library(code, name, digest, cache, cc, flags,
                                             None if metadata is None else metadata())
                    log.info("compiled %s in %.1f s", name, time.perf_counter() - started)
                loaded = ca.external(name, str(library))
                meta = library.with_suffix(".json")
                stored = json.loads(meta.read_text()) if metadata is not None and meta.exists() else None
                _loaded[digest] = loaded, stored
                return loaded, stored
            except OSError as err:                                  # full or read-only: a temporary folder
                if attempt or err.errno not in (errno.ENOSPC, errno.EROFS, errno.EACCES, errno.EDQUOT):
                    raise CompiledLoopUnavailable("cache unusable", f"the compiled-loop cache {cache} cannot be "
                                                  f"written ({err.strerror}): point RMPC_CACHE at a writable "
                                                  "directory with free space") from None
                cache = _temporary_cache()
                library = cache / f"{name}_{digest}.so"
            except RuntimeError as err:                             # CasADi cannot load the library
                if isinstance(err, CompiledLoopUnavailable) or attempt:
                    raise
                library.unlink(missing_ok=True)                     # a damaged file in the cache: build it again
    raise AssertionError("unreachable")


def host_digest() -> str:
    """A digest of this machine's processor (its name and features): a library built for its instruction set is cached
    under it, so a cache shared with another machine never loads one it cannot run."""
    info = f"{platform.machine()} {platform.processor()}"
    try:
        with open("/proc/cpuinfo") as f:
            info += "".join(sorted({line for line in f if line.startswith(("model name", "flags", "Features"))}))
    except OSError:
        pass
    return hashlib.sha256(info.encode()).hexdigest()[:12]
