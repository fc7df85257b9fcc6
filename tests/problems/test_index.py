"""problems/index.py is current, and `rmpc list` / `rmpc solve ID` import only what they need."""

import subprocess
import sys
from pathlib import Path

from problems.registry import all_problems, get, index_source

ROOT = Path(__file__).resolve().parents[2]


def test_index_is_current():
    """Regenerate with ``python -c "from problems.registry import write_index; write_index()"``."""
    assert (ROOT / "problems" / "index.py").read_text(encoding="utf-8") == index_source()


def test_listed_problems_solve_through_their_chapter_module():
    problem = next(p for p in all_problems() if p.id == "2.1")
    assert problem.function.__module__ == "problems.ch02" and get("2.1").function is problem.function


def _modules_after(code: str) -> set[str]:
    out = subprocess.run([sys.executable, "-c", code + "; import sys; print(' '.join(sys.modules))"],
                         capture_output=True, text=True, check=True, cwd=ROOT,
                         env={"PATH": "", "PYTHONPATH": ":".join(sys.path)}).stdout.split()
    return set(out)


def test_list_imports_no_chapter_and_no_heavy_library():
    modules = _modules_after("import io, contextlib; from problems.cli import main; "
                             "contextlib.redirect_stdout(io.StringIO()).__enter__(); main(['list'])")
    assert not {m for m in modules if m.startswith("problems.ch")}
    assert not modules & {"control", "sympy", "matplotlib", "pinocchio", "scipy"}


def test_get_imports_only_the_problems_chapter():
    modules = _modules_after("from problems.registry import get; get('2.1')")
    assert {m for m in modules if m.startswith("problems.ch")} == {"problems.ch02"}
