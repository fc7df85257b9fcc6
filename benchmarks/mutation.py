"""A small hand-rolled mutation run: does the test suite notice when one operator or constant changes?

For each named module, every arithmetic/comparison operator, numeric constant and unary minus is a
mutation point (``+``↔``-``, ``*``↔``/``, ``<``↔``<=``/``>``, ``==``↔``!=``, ``c`` → ``c + 1`` (``0`` → ``1``),
``-x`` → ``x``); a seeded sample of at most ``--per-module`` points is mutated one at a time in a copy of
the tree, and the module's tests run against the copy. A mutant *survives* when those tests still pass.

    python benchmarks/mutation.py --per-module 50 --out /tmp/mutation.txt
    python benchmarks/mutation.py --lines 294-316 controllers/simulation.py   # every point of rk4_step
    python benchmarks/mutation.py --rerun /tmp/mutation.txt --out /tmp/after.txt   # its survivors, after new tests

``--rerun`` takes the log of an earlier run of the same module code with the same ``--seed`` and ``--per-module``:
the samples are drawn again in the same order and the mutants that SURVIVED there are run again, one for one.

Docstrings and ``raise ValueError`` messages are skipped (they carry no behaviour the tests measure).
"""

from __future__ import annotations

import argparse
import ast
import random
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

TARGETS = {
    "rigid_body/rotations.py": ["tests/rigid_body/test_rotations.py", "tests/rigid_body/test_rpy_orders.py",
                                "tests/rigid_body/test_orientation_errors.py",
                                "tests/rigid_body/test_independent_references.py",
                                "tests/rigid_body/test_mutation_survivors.py"],
    "planners/timing.py": ["tests/planners/test_timing.py", "tests/planners/test_multi_segment.py",
                           "tests/rigid_body/test_independent_references.py",
                           "tests/rigid_body/test_mutation_survivors.py"],
    "planners/inverse_kinematics.py": ["tests/planners/test_inverse_kinematics.py",
                                       "tests/planners/test_lm_inverse_kinematics.py",
                                       "tests/planners/test_ik_harness.py",
                                       "tests/rigid_body/test_independent_references.py",
                                       "tests/rigid_body/test_mutation_survivors.py"],
    "controllers/simulation.py": ["tests/controllers/test_simulation.py",
                                  "tests/controllers/test_loop_fast_paths.py"],
    # chapters 9-12
    "controllers/force.py": ["tests/controllers/test_force.py", "tests/controllers/test_contact_step.py",
                             "tests/controllers/test_peg_in_hole.py"],
    "controllers/visual_servoing.py": ["tests/controllers/test_visual_servoing.py",
                                       "tests/controllers/test_visual_servoing_inputs.py",
                                       "tests/examples/test_panda_visual_servoing.py"],
    "controllers/wheeled.py": ["tests/controllers/test_wheeled.py", "tests/controllers/test_wheeled_inputs.py",
                               "tests/controllers/test_wheeled_laws.py"],
    "rigid_body/camera.py": ["tests/rigid_body/test_camera_vision.py", "tests/rigid_body/test_sensors.py",
                             "tests/rigid_body/test_independent_references.py",
                             "tests/controllers/test_visual_servoing.py", "tests/rigid_body/test_vision_references.py"],
    "rigid_body/vision.py": ["tests/rigid_body/test_camera_vision.py", "tests/rigid_body/test_vision_references.py"],
    "rigid_body/wheeled.py": ["tests/rigid_body/test_wheeled.py", "tests/controllers/test_wheeled.py",
                              "tests/controllers/test_wheeled_inputs.py", "tests/planners/test_wheeled_references.py"],
    "planners/wheeled.py": ["tests/planners/test_wheeled.py", "tests/controllers/test_wheeled.py",
                            "tests/controllers/test_wheeled_inputs.py", "tests/planners/test_wheeled_references.py"],
    "planners/sampling.py": ["tests/planners/test_sampling.py", "tests/planners/test_certified_planning.py",
                             "tests/planners/test_planning_references.py"],
    "planners/configuration_space.py": ["tests/planners/test_configuration_space.py", "tests/planners/test_cspace.py",
                                        "tests/planners/test_certified_planning.py",
                                        "tests/planners/test_planning_references.py"],
    "planners/collision.py": ["tests/planners/test_collision.py", "tests/planners/test_certified_planning.py",
                              "tests/planners/test_planning_references.py"],
    "planners/cells.py": ["tests/planners/test_cells.py", "tests/planners/test_planning_references.py"],
    "planners/potentials.py": ["tests/planners/test_potentials.py", "tests/planners/test_certified_planning.py",
                               "tests/planners/test_planning_references.py"],
}

SWAP = {ast.Add: ast.Sub, ast.Sub: ast.Add, ast.Mult: ast.Div, ast.Div: ast.Mult, ast.Pow: ast.Mult,
        ast.FloorDiv: ast.Mult, ast.Mod: ast.FloorDiv,
        ast.Lt: ast.LtE, ast.LtE: ast.Lt, ast.Gt: ast.GtE, ast.GtE: ast.Gt, ast.Eq: ast.NotEq,
        ast.NotEq: ast.Eq, ast.And: ast.Or, ast.Or: ast.And}


def _skipped_lines(tree: ast.AST) -> set[int]:
    """Lines of docstrings and of ``raise`` statements (messages, not behaviour)."""
    lines: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.ClassDef, ast.Module, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(getattr(first, "value", None), ast.Constant):
                lines.update(range(first.lineno, first.end_lineno + 1))
        if isinstance(node, ast.Raise):
            lines.update(range(node.lineno, node.end_lineno + 1))
    return lines


def mutation_points(source: str) -> list[tuple[int, str]]:
    """(index in ``ast.walk`` order, description) of every mutable node."""
    tree = ast.parse(source)
    skip = _skipped_lines(tree)
    points = []
    for k, node in enumerate(ast.walk(tree)):
        line = getattr(node, "lineno", None)
        if line is None or line in skip:
            continue
        if isinstance(node, (ast.BinOp, ast.BoolOp)) and type(node.op) in SWAP:
            points.append((k, f"line {line}: {type(node.op).__name__} -> {SWAP[type(node.op)].__name__}"))
        elif isinstance(node, ast.Compare) and type(node.ops[0]) in SWAP:
            points.append((k, f"line {line}: {type(node.ops[0]).__name__} -> {SWAP[type(node.ops[0])].__name__}"))
        elif isinstance(node, ast.Constant) and type(node.value) in (int, float) and not isinstance(node.value, bool):
            points.append((k, f"line {line}: constant {node.value!r} -> {node.value + 1!r}"))
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            points.append((k, f"line {line}: unary minus removed"))
    return points


def mutate(source: str, index: int) -> str:
    tree = ast.parse(source)
    for k, node in enumerate(ast.walk(tree)):
        if k != index:
            continue
        if isinstance(node, (ast.BinOp, ast.BoolOp)):
            node.op = SWAP[type(node.op)]()
        elif isinstance(node, ast.Compare):
            node.ops[0] = SWAP[type(node.ops[0])]()
        elif isinstance(node, ast.Constant):
            node.value = node.value + 1
        elif isinstance(node, ast.UnaryOp):
            return ast.unparse(_replace(tree, node, node.operand))
        return ast.unparse(tree)
    raise IndexError(index)


def _replace(tree: ast.AST, old: ast.AST, new: ast.AST) -> ast.AST:
    for parent in ast.walk(tree):
        for name, value in ast.iter_fields(parent):
            if value is old:
                setattr(parent, name, new)
            elif isinstance(value, list):
                for i, item in enumerate(value):
                    if item is old:
                        value[i] = new
    return tree


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--per-module", type=int, default=50)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=120.0)
    parser.add_argument("--out", type=Path, default=Path("mutation.txt"))
    parser.add_argument("--lines", default="", help="FIRST-LAST: only the points on these lines (all of them)")
    parser.add_argument("--rerun", type=Path, default=None,
                        help="a previous --out log (same module code, --seed and --per-module): run again only the "
                             "mutants that SURVIVED there")
    parser.add_argument("modules", nargs="*", default=list(TARGETS))
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="rmpc-mutation-"))
    shutil.copytree(ROOT, work / "tree", ignore=shutil.ignore_patterns(".git", "__pycache__", "notebooks", ".venv*",
                                                                    "*.egg-info"))
    tree = work / "tree"
    rng = random.Random(args.seed)
    outcomes: dict[str, list[str]] = {}          # --rerun: each module's statuses, in its sample's order
    if args.rerun is not None:
        for line in args.rerun.read_text().splitlines():
            if line.startswith("# ") and ": " in line and "points" in line:
                outcomes[line[2:].split(":")[0]] = []
            elif line.split(" ")[0] in ("killed", "SURVIVED", "SKIP"):
                module = next(word for word in line.split() if word.endswith(".py"))   # after "killed (timeout)"
                outcomes[module].append(line.split()[0])
        args.modules = list(outcomes)              # the same modules in the same order: the same draws
    total = survived = 0
    with args.out.open("w") as log:
        for module in args.modules:
            original = (ROOT / module).read_text()
            points = mutation_points(original)
            if args.lines:
                first, last = (int(n) for n in args.lines.split("-"))
                points = [(k, what) for k, what in points if first <= int(what.split(":")[0][5:]) <= last]
            sample = sorted(rng.sample(points, min(args.per_module, len(points))))
            if args.rerun is not None:
                if len(outcomes[module]) != len(sample):
                    raise SystemExit(f"{module}: {len(outcomes[module])} lines in {args.rerun}, {len(sample)} drawn: "
                                     "not the same code, --seed or --per-module")
                sample = [point for point, status in zip(sample, outcomes[module]) if status == "SURVIVED"]
            print(f"# {module}: {len(points)} points, {len(sample)} sampled", file=log, flush=True)
            for index, what in sample:
                try:
                    mutated = mutate(original, index)
                except Exception as exc:  # a mutant that does not unparse is skipped
                    print(f"SKIP {module} {what} ({exc})", file=log, flush=True)
                    continue
                (tree / module).write_text(mutated)
                t0 = time.time()
                try:
                    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider",
                                          *TARGETS[module]], cwd=tree, capture_output=True,
                                         timeout=args.timeout, env={"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin",
                                                                    "MPLBACKEND": "Agg",
                                                                    "RMPC_CACHE": str(work / "cache")})
                    status = "SURVIVED" if run.returncode == 0 else "killed"
                except subprocess.TimeoutExpired:
                    status = "killed (timeout)"
                total += 1
                survived += status == "SURVIVED"
                print(f"{status:16s} {module} {what} [{time.time() - t0:.0f} s]", file=log, flush=True)
            (tree / module).write_text(original)
        rate = survived / total if total else float("nan")
        print(f"# {survived} of {total} mutants survived ({100 * rate:.0f} %)", file=log, flush=True)
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
