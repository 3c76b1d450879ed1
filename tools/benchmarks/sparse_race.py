# SPDX-License-Identifier: GPL-3.0-or-later
"""The sparse back-end against IDA with KLU, work against precision: sparse_race's points drawn
log-log, one panel a mechanism, one line a solver (CPU seconds against the error at the end).

  python -m benchmarks.sparse_race --race build/tools/sparse_race --plot FILE [--reps R]
      [--budget S]
  python -m benchmarks.sparse_race --csv FILE --plot FILE

With --race, runs sparse_race (--reps and --budget passed through), prints its table and draws
its points; with --csv, draws the points of an earlier run's CSV (sparse_race --csv). Exit
status 0, 1 when sparse_race fails or its CSV cannot be read, 2 for bad usage.
"""

from __future__ import annotations

import argparse
import csv
import os
import subprocess
import sys
import tempfile
from collections.abc import Sequence

PROG = "benchmarks.sparse_race"
COLUMNS = ["mechanism", "solver", "setting", "seconds", "error"]

Points = dict[str, dict[str, list[tuple[float, float]]]]


def read(path: str) -> Points:
    """mechanism -> solver -> [(seconds, error)] in the file's order; ValueError when the header
    or a row is not sparse_race's."""
    points: Points = {}
    with open(path, newline="", encoding="utf-8") as f:
        rows = csv.reader(f)
        if next(rows, None) != COLUMNS:
            raise ValueError(f"{path}: the header is not {','.join(COLUMNS)}")
        for i, row in enumerate(rows, start=2):
            if len(row) != len(COLUMNS):
                raise ValueError(f"{path}:{i}: {len(row)} fields, not {len(COLUMNS)}")
            seconds, error = float(row[3]), float(row[4])
            points.setdefault(row[0], {}).setdefault(row[1], []).append((seconds, error))
    return points


def plot(points: Points, path: str) -> None:
    """One log-log panel a mechanism: each solver's CPU seconds against its error."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(points), figsize=(5.5 * len(points), 4.2), squeeze=False)
    for ax, (mechanism, solvers) in zip(axes[0], points.items()):
        for solver, pts in solvers.items():
            ax.loglog([e for _, e in pts], [s for s, _ in pts], "o-", label=solver)
        ax.set_title(mechanism)
        ax.set_xlabel("error of the positions at the end (relative)")
        ax.set_ylabel("CPU seconds")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--race", metavar="EXE", help="sparse_race, run now")
    src.add_argument("--csv", metavar="FILE", help="the points of an earlier run")
    p.add_argument("--plot", metavar="FILE", required=True, help="the PNG to write")
    p.add_argument("--reps", default="3", help="sparse_race's --reps (default 3)")
    p.add_argument("--budget", default="2", help="sparse_race's --budget (default 2)")
    return p.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    a = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        if a.race:
            with tempfile.TemporaryDirectory() as d:
                points_file = os.path.join(d, "race.csv")
                cmd = [a.race, "--reps", a.reps, "--budget", a.budget, "--csv", points_file]
                out = subprocess.run(cmd, stdout=subprocess.PIPE, text=True, check=False)
                if out.returncode != 0:
                    raise RuntimeError(f"sparse_race exited with status {out.returncode}")
                sys.stdout.write(out.stdout)
                points = read(points_file)
        else:
            points = read(a.csv)
        plot(points, a.plot)
    except (RuntimeError, ValueError, OSError) as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
