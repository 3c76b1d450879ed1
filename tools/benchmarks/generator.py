# SPDX-License-Identifier: GPL-3.0-or-later
"""The generator's cost: the time tools/stabdae_gen takes for each description in
examples/models/sym/ (the median of --reps runs of the command, each a fresh process), then
build/tools/bench_generated (the generated callbacks against the hand-written ones, per step
and per set of callbacks); writes build/report/generator.md.

  python -m benchmarks.generator [--build DIR] [--reps N]
"""

import argparse
import glob
import os
import statistics
import subprocess
import sys
import tempfile
import time

from benchmarks.workprecision import provenance, tools_env

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def generation_seconds(model, reps):
    env = tools_env()
    times = []
    with tempfile.TemporaryDirectory() as out:
        for _ in range(reps):
            start = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "stabdae_gen", model, "--out", out],
                env=env,
                check=True,
                capture_output=True,
            )
            times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--reps", type=int, default=3)
    args = ap.parse_args()
    bench_cmd = [os.path.join(args.build, "tools", "bench_generated")]
    lines = [
        "# The generator's cost",
        "",
        *provenance(bench_cmd, None),
        "",
        "## Generation (wall time of the command, median of %d)" % args.reps,
        "",
        "| model | seconds |",
        "|---|---|",
    ]
    for model in sorted(glob.glob(os.path.join(ROOT, "examples", "models", "sym", "*.py"))):
        seconds = generation_seconds(model, args.reps)
        lines.append(f"| {os.path.basename(model)} | {seconds:.2f} |")
        print(lines[-1], flush=True)
    bench = subprocess.run(bench_cmd, check=True, capture_output=True, text=True).stdout
    print(bench)
    lines += ["", "## Generated against hand-written callbacks (CPU time, median of 7)", "", bench]
    os.makedirs(os.path.join(args.build, "report"), exist_ok=True)
    with open(os.path.join(args.build, "report", "generator.md"), "w") as f:
        f.write("\n".join(lines))


if __name__ == "__main__":
    main()
