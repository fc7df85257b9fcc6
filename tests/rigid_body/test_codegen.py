"""The one compiler and cache (rigid_body/codegen.py): a host-specific build, and a compiler that refuses the host's
instruction set falling back to the plain flags (one code path for every caller)."""

import logging
import stat

import casadi as ca
import pytest

import rigid_body.codegen as codegen


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    cache = tmp_path / "cache"
    monkeypatch.setattr(codegen, "CACHE", cache)
    monkeypatch.setattr(codegen, "_loaded", {})
    return cache


def _square():
    x = ca.SX.sym("x")
    return ca.Function("square", [x], [x * x])


def test_a_native_build_is_keyed_by_the_host_and_logged(fresh_cache, caplog, monkeypatch):
    if codegen.compiler() is None:
        pytest.skip("no C compiler")
    with caplog.at_level(logging.INFO, logger="rmpc.compiler"):
        native = codegen.compile_function(_square(), native=True)
        plain = codegen.compile_function(_square())
    assert float(native(3.0)) == 9.0 and float(plain(-2.0)) == 4.0
    assert len(list(fresh_cache.glob("square_*.so"))) == 2                     # two flag sets, two libraries
    lines = [r.getMessage() for r in caplog.records if r.name == "rmpc.compiler"]
    assert sum(m.startswith("compiling square") for m in lines) == 2
    assert sum(m.startswith("compiled square in ") for m in lines) == 2
    assert len(codegen.host_digest()) == 12
    monkeypatch.setattr(codegen, "host_digest", lambda: "another-host")       # another machine's cache entry
    monkeypatch.setattr(codegen, "_loaded", {})
    codegen.compile_function(_square(), native=True)
    assert len(list(fresh_cache.glob("square_*.so"))) == 3                     # the host is part of the key


def test_a_compiler_without_native_flags_builds_with_the_plain_ones(fresh_cache, tmp_path, monkeypatch, recwarn):
    real = codegen.compiler()
    if real is None:
        pytest.skip("no C compiler")
    picky = tmp_path / "picky-cc"
    picky.write_text(f'#!/bin/sh\nfor a in "$@"; do [ "$a" = "-march=native" ] && exit 1; done\nexec {real} "$@"\n')
    picky.chmod(picky.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("CC", str(picky))
    f = codegen.compile_function(_square(), native=True)
    assert float(f(4.0)) == 16.0
    assert not [w for w in recwarn if "interpreted" in str(w.message)]          # compiled, not interpreted
    assert len(list(fresh_cache.glob("square_*.so"))) == 1
    monkeypatch.setenv("CC", "/bin/false")                                        # no flags at all: interpreted
    monkeypatch.setattr(codegen, "_loaded", {})
    with pytest.warns(UserWarning, match="compiler `/bin/false` failed.*interpreted"):
        g = codegen.compile_function(_square(), native=True)
    assert float(g(5.0)) == 25.0
