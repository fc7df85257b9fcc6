"""Timing and the one table (text, Markdown, JSON) shared by the benchmark scripts (plain scripts, not tests).

Importing it also puts the source tree on ``sys.path`` (after the installed packages): ``examples/`` is not part
of the installed package, and a script run alone (``python benchmarks/bench_force.py``) starts in ``benchmarks/``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

SOURCE_TREE = str(Path(__file__).resolve().parent.parent)
if SOURCE_TREE not in sys.path:
    sys.path.append(SOURCE_TREE)

WINDOWS_PER_ROUND = 10  # a timing window short enough to fit between two preemptions on a loaded machine


def per_call(f: Callable[[], object], repetitions: int = 1000, rounds: int = 3) -> float:
    """Wall time of one ``f()`` call [s]: the best mean over short windows, after a warm-up.

    The ``repetitions × rounds`` calls are timed in ``10 × rounds`` windows of ``repetitions / 10`` calls:
    on a machine shared with other jobs a short window is more often left whole by the scheduler, and the
    best window is the cost of the call itself."""
    return best_times([f], max(1, repetitions // WINDOWS_PER_ROUND), rounds * WINDOWS_PER_ROUND)[0]


def best_of(f: Callable[[], object], rounds: int = 3) -> tuple[float, object]:
    """(best wall time [s] of ``rounds`` calls of ``f``, its last result): for runs long enough to time alone."""
    best, out = float("inf"), None
    for _ in range(rounds):
        t0 = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t0)
    return best, out


def best_times(functions: list[Callable[[], object]], repetitions: int = 300, rounds: int = 151) -> list[float]:
    """Per-call wall time [s] of each function: the best of ``rounds`` interleaved window means of
    ``repetitions`` calls (load from other jobs hits every function alike; short windows often escape it)."""
    best = [float("inf")] * len(functions)
    for f in functions:
        f()
    for _ in range(rounds):
        for i, f in enumerate(functions):
            t0 = time.perf_counter()
            for _ in range(repetitions):
                f()
            best[i] = min(best[i], (time.perf_counter() - t0) / repetitions)
    return best


def met(row: dict) -> bool | None:
    """Whether a row meets its target: ``("<=", v)``/``(">=", v)`` on the rmpc value, ``("ratio<=", v)``
    on rmpc/reference; None without a target."""
    target = row.get("target")
    if target is None:
        return None
    op, value = target
    if op.startswith("ratio"):
        if not row.get("reference"):
            return None
        x, op = row["rmpc"] / row["reference"], op[5:]
    else:
        x = row["rmpc"]
    return x <= value if op == "<=" else x >= value


def ratio(row: dict) -> float | None:
    """rmpc / reference, or None without a reference."""
    ref = row.get("reference")
    return row["rmpc"] / ref if ref else None


def table_lines(rows: list[dict]) -> list[str]:
    """The table as text lines: measurement, rmpc, reference, ratio, target, met, what the reference is."""
    width = max([64] + [len(row["measurement"]) for row in rows])
    lines = [f"{'measurement':{width}s} {'rmpc':>10s} {'reference':>10s} {'ratio':>7s}  {'target':<12s} {'met':<4s} "
             f"reference is"]
    for row in rows:
        ref, r = row.get("reference"), ratio(row)
        ratio_s = f"{r:7.2f}" if r is not None else " " * 7
        ok = met(row)
        ok_s = "" if ok is None else ("yes" if ok else "NO")
        ref_s = f"{ref:10.4g}" if ref is not None else " " * 10
        lines.append(f"{row['measurement']:{width}s} {row['rmpc']:10.4g} {ref_s} {ratio_s}  {target_text(row):<12s} "
                     f"{ok_s:<4s} {row.get('ref_name', '')}".rstrip())
    return lines


def target_text(row: dict) -> str:
    target = row.get("target")
    return f"{target[0]} {target[1]:g}" if target else ""


def print_rows(rows: list[dict]) -> None:
    """One table: measurement, rmpc, reference (and what it is), ratio, target, met."""
    print("\n".join(table_lines(rows)))


def markdown(rows: list[dict]) -> str:
    """The table in Markdown (for the README's performance section)."""
    lines = ["| measurement | rmpc | reference | ratio | target | met | reference is |",
             "|---|---:|---:|---:|---|---|---|"]
    for row in rows:
        ref, r, ok = row.get("reference"), ratio(row), met(row)
        cells = [row["measurement"].strip(), f"{row['rmpc']:.4g}", "" if ref is None else f"{ref:.4g}",
                 "" if r is None else f"{r:.2f}", target_text(row).replace("<=", "≤").replace(">=", "≥"),
                 "" if ok is None else ("yes" if ok else "**no**"), row.get("ref_name", "")]
        lines.append("| " + " | ".join(c.replace("|", "/") for c in cells) + " |")
    return "\n".join(lines) + "\n"


def json_rows(rows: list[dict]) -> list[dict]:
    """The rows as JSON objects, with their ratio and whether the target is met."""
    return [{key: _plain(value) for key, value in {**row, "target": list(row["target"]) if row.get("target") else None,
                                                   "ratio": ratio(row), "met": met(row)}.items()} for row in rows]


def _plain(value: Any) -> Any:
    """A numpy scalar (float64, bool_) as the Python number JSON can write."""
    return value.item() if isinstance(value, np.generic) else value


def toolbox_puma_pd(K_P: float, K_D: float, q_d):
    """The Robotics Toolbox's Puma 560 (friction off, as rmpc's ``ArmPlant``) and the PD + gravity law
    ``τ = g(q) + K_P (q_d − q) − K_D q̇`` in its ``fdyn`` callback form, or None without the Toolbox."""
    try:
        import roboticstoolbox as rtb
    except ImportError:
        return None
    puma = rtb.models.DH.Puma560().nofriction(coulomb=True, viscous=True)

    def law(robot, t, q, qd):
        return robot.gravload(q) + K_P * (q_d - q) - K_D * qd

    return puma, law
