"""A non-editable install ships the book's URDF files as package data (``rigid_body/urdf``), no ``urdf`` package, and
as top-level names only the library's, the CLI's ``problems`` and ``rmpc`` (no ``examples``)."""

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.skipif(importlib.util.find_spec("pip") is None, reason="pip is not available")
def test_installed_package_loads_book_robots_outside_the_source_tree(tmp_path):
    target = tmp_path / "site"
    build = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--no-compile",
                            "--target", str(target), str(ROOT)], capture_output=True, text=True, timeout=300)
    assert build.returncode == 0, build.stderr[-2000:]
    assert (target / "rigid_body" / "urdf" / "planar_2r.urdf").is_file()
    assert not (target / "urdf").exists(), "urdf/ must ship inside rigid_body, not as a top-level package"
    top = sorted(p.name for p in target.iterdir() if (p / "__init__.py").is_file())
    assert top == ["controllers", "planners", "problems", "rigid_body", "rmpc", "viewer"], top   # not examples
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
