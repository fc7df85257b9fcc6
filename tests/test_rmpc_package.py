"""The ``rmpc`` entry package: every re-exported name resolves to its home, lazily."""

import importlib
import subprocess
import sys
from pathlib import Path

import pytest

import rmpc

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("name", rmpc.__all__)
def test_every_name_is_the_object_of_its_home_module(name):
    home = importlib.import_module(rmpc._HOMES[name])
    assert getattr(rmpc, name) is getattr(home, name)


def test_dir_lists_the_api_and_unknown_names_raise():
    assert {"load", "simulate", "ArmPlant", "solve_ik", "direct_kinematics"} <= set(dir(rmpc))
    with pytest.raises(AttributeError, match=r"no attribute 'lod'; did you mean \['load'"):
        rmpc.lod  # noqa: B018


def test_import_rmpc_imports_no_heavy_module():
    code = "import sys, rmpc; print(sorted(m for m in ('pinocchio', 'casadi', 'matplotlib', 'numpy') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert out.stdout.strip() == "[]"


def test_docstring_example_runs():
    import doctest

    assert doctest.testmod(rmpc).failed == 0
