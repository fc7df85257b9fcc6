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
