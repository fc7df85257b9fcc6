"""``python -m benchmarks``: every benchmark's measurements in one table.

Columns: measurement, rmpc, reference (raw Pinocchio, a floor, or a peer library), ratio, target, met.
Each ``bench_*.py`` stays runnable alone (``python benchmarks/bench_ik.py``); here their ``rows()`` are
collected in one run. Peers (roboticstoolbox-python: ``pip install rmpc[bench]``) are skipped when absent.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))       # the scripts import benchtools directly

import bench_compiled  # noqa: E402
import bench_control  # noqa: E402
import bench_ik  # noqa: E402
import bench_trajectories  # noqa: E402
from benchtools import print_rows  # noqa: E402

MODULES = (bench_compiled, bench_ik, bench_trajectories, bench_control)


def main() -> None:
    rows: list[dict] = []
    for module in MODULES:
        print(f"running {module.__name__} ...", file=sys.stderr, flush=True)
        rows += module.rows()
    print()
    print_rows(rows)


if __name__ == "__main__":
    main()
