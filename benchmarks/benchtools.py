"""Timing helper shared by the benchmark scripts (plain scripts, not tests)."""

from __future__ import annotations

import time
from typing import Callable


def per_call(f: Callable[[], object], repetitions: int = 1000, rounds: int = 3) -> float:
    """Wall time of one ``f()`` call [s]: the best of ``rounds`` means over ``repetitions`` calls, after a warm-up."""
    f()
    best = float("inf")
    for _ in range(rounds):
        t0 = time.perf_counter()
        for _ in range(repetitions):
            f()
        best = min(best, (time.perf_counter() - t0) / repetitions)
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


def print_rows(rows: list[dict]) -> None:
    """One table: measurement, rmpc, reference (and what it is), ratio, target, met."""
    print(f"{'measurement':58s} {'rmpc':>10s} {'reference':>10s} {'ratio':>7s}  {'target':<12s} {'met':<4s} reference is")
    for row in rows:
        ref = row.get("reference")
        ratio = f"{row['rmpc'] / ref:7.2f}" if ref else " " * 7
        target = row.get("target")
        target_s = f"{target[0]} {target[1]:g}" if target else ""
        ok = met(row)
        ok_s = "" if ok is None else ("yes" if ok else "NO")
        ref_s = f"{ref:10.4g}" if ref is not None else " " * 10
        print(f"{row['measurement']:58s} {row['rmpc']:10.4g} {ref_s} {ratio}  {target_s:<12s} {ok_s:<4s} "
              f"{row.get('ref_name', '')}")


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
