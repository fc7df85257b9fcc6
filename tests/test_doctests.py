"""The ``>>>`` examples in the docstrings of the library (and of the problems' helpers) run and hold."""

import doctest
import importlib
import pkgutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("rigid_body", "planners", "controllers", "problems", "examples")


def _modules() -> list[str]:
    names = []
    for package in PACKAGES:
        for info in pkgutil.iter_modules([str(ROOT / package)]):
            if ">>>" in (ROOT / package / f"{info.name}.py").read_text(encoding="utf-8"):
                names.append(f"{package}.{info.name}")
    return sorted(names)


MODULES = _modules()


def test_doctests_are_collected():
    """The library does carry examples: the collection itself must not come back empty."""
    assert {"planners.timing", "planners.configuration_space", "controllers.simulation"} <= set(MODULES)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.attempted > 0, f"{name}: no example found"
    assert result.failed == 0, f"{name}: {result.failed} of {result.attempted} examples failed (see the output above)"
