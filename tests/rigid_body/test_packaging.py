"""A non-editable install ships the book's URDF files as package data (``rigid_body/urdf``), no ``urdf`` package, and
as top-level names only the library's, the CLI's ``problems`` and ``rmpc`` (no ``examples``)."""

import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def clean_source_copy(destination: Path) -> Path:
    """The source tree as a fresh checkout has it: only the files git tracks (plus the test's own working-tree
    edits of them). A git-ignored ``build/`` or ``*.egg-info`` left in the checkout would otherwise be reused by
    setuptools (``build/lib`` keeps packages that are no longer listed), and the wheel checked would not be the one
    a user gets."""
    listed = subprocess.run(["git", "ls-files", "-z", "--cached"], cwd=ROOT, capture_output=True, timeout=60)
    if listed.returncode == 0 and listed.stdout:
        for name in listed.stdout.decode().split("\0"):
            source = ROOT / name
            if name and source.is_file():   # a tracked file deleted in the working tree is skipped
                (destination / name).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(source, destination / name)
    else:   # not a git checkout (an unpacked sdist): everything but build products
        shutil.copytree(ROOT, destination, dirs_exist_ok=True, ignore=shutil.ignore_patterns(
            "build", "dist", "*.egg-info", ".venv", "__pycache__", ".git"))
    return destination


def test_the_clean_copy_leaves_build_products_behind(tmp_path):
    copy = clean_source_copy(tmp_path / "src")
    assert (copy / "pyproject.toml").is_file() and (copy / "rigid_body" / "__init__.py").is_file()
    assert not (copy / "build").exists() and not list(copy.glob("*.egg-info"))


@pytest.mark.skipif(importlib.util.find_spec("pip") is None, reason="pip is not available")
def test_installed_package_loads_book_robots_outside_the_source_tree(tmp_path):
    target = tmp_path / "site"
    source = clean_source_copy(tmp_path / "src")
    build = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--no-compile",
                            "--target", str(target), str(source)], capture_output=True, text=True, timeout=300)
    assert build.returncode == 0, build.stderr[-2000:]
    assert (target / "rigid_body" / "urdf" / "planar_2r.urdf").is_file()
    assert not (target / "urdf").exists(), "urdf/ must ship inside rigid_body, not as a top-level package"
    top = sorted(p.name for p in target.iterdir() if (p / "__init__.py").is_file())
    assert top == ["controllers", "planners", "problems", "rigid_body", "rmpc", "viewer"], top   # not examples
    modules = sorted(p.name for p in target.glob("*.py"))
    assert modules == [], modules   # no stray top-level modules either
    [top_level] = target.glob("rmpc-*.dist-info/top_level.txt")
    assert sorted(top_level.read_text().split()) == top
    script = (
        "import rigid_body, numpy as np\n"
        "from rigid_body.robots import load\n"
        "from rigid_body.kinematics import direct_kinematics\n"
        "r = load('anthropomorphic_wrist')\n"
        "print(rigid_body.__file__, r.urdf_path, direct_kinematics(r, np.zeros(6))[0, 3])\n")
    env = {**os.environ, "PYTHONPATH": str(target)}
    run = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=120)
    assert run.returncode == 0, run.stderr[-2000:]
    module, urdf_path, x = run.stdout.split()
    assert Path(module).is_relative_to(target) and Path(urdf_path).is_relative_to(target / "rigid_body" / "urdf")
    assert float(x) == pytest.approx(0.5)  # a2 of the book's table (the arm is stretched along x0 at q = 0)
