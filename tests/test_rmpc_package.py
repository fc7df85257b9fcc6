"""The ``rmpc`` entry package: every re-exported name resolves to its home, lazily."""

import importlib
import subprocess
import sys
from pathlib import Path

import pytest

import rmpc

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("name", sorted(rmpc._HOMES))
def test_every_name_is_the_object_of_its_home_module(name):
    home = importlib.import_module(rmpc._HOMES[name])
    assert getattr(rmpc, name) is getattr(home, name)


def test_modules_are_attributes():
    assert rmpc.viewer is importlib.import_module("viewer")
    assert rmpc.scenes is importlib.import_module("controllers.scenes")
    assert set(rmpc.__all__) == set(rmpc._HOMES) | set(rmpc._MODULES)


def test_help_lists_every_name_under_its_chapter():
    """help(rmpc) is how a newcomer finds chapters 9–12: every exported name appears in the docstring, under a
    heading that names its chapter."""
    doc = rmpc.__doc__
    missing = [name for name in [*rmpc._HOMES, *rmpc._MODULES] if f"``{name}" not in doc and f"rmpc.{name}``" not in doc]
    assert not missing, f"names exported but not listed in help(rmpc): {missing}"
    for heading in ("Force control (Ch. 9)", "Visual servoing (Ch. 10)", "Mobile robots (Ch. 11)",
                    "Motion planning (Ch. 12)"):
        assert heading in doc


@pytest.mark.parametrize("package", ["rigid_body", "planners", "controllers"])
def test_package_help_names_every_module(package):
    """help(rigid_body), help(planners) and help(controllers) name each of their modules (a module not named is not found)."""
    import pkgutil

    mod = importlib.import_module(package)
    names = [m.name for m in pkgutil.iter_modules(mod.__path__) if not m.name.startswith("_")]
    missing = [name for name in names if f"``{name}``" not in mod.__doc__ and f"``{name}." not in mod.__doc__]
    assert not missing, f"help({package}) does not name {missing}"


def test_plants_help_names_every_plant():
    import inspect

    plants = importlib.import_module("controllers.plants")
    classes = [name for name, obj in vars(plants).items() if inspect.isclass(obj) and obj.__module__ == plants.__name__
               and not name.startswith("_") and hasattr(obj, "derivative")]
    missing = [name for name in classes if f":class:`{name}`" not in plants.__doc__]
    assert not missing, f"help(controllers.plants) does not name {missing}"


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
