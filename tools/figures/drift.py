#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The constraint residual of one mechanism under stabdae and under an index-1 integrator.

Runs the four-bar linkage (examples/fourbar, its default start: the crank turning at 5 rad/s)
for 10 s by stabdae (build/examples/fourbar: scheme 15, dgrad, T 0.001) and by SUNDIALS IDA on
the index-1 form from the same callbacks (build/tools/ida_mbs fourbar --form index1) at a loose
and at a tight rtol, prints max_i |c_i(q)| of each at a few times and over the run, and draws it
against t on a log scale into OUTDIR/drift.png. Both programs compute the column max_abs_c
from the same constraint function, so the two residuals are measured alike.

    PYTHONPATH=tools python -m figures.drift [--build build] [--outdir build/figures] [--csvdir build/demo]
"""

import argparse
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TF = 10.0
T = 0.001
# 1e-6 is a usual engineering setting; 1e-10 is ida_mbs's default, near IDA's practical limit.
RTOLS = ("1e-6", "1e-10")
ATOL = "1e-12"
SHOWN = (1.0, 5.0, TF)


def read_csv(path):
    """The columns t and max_abs_c; '#' lines (IDA's counters) skipped."""
    data = np.genfromtxt(path, delimiter=",", names=True, comments="#")
    return data["t"], data["max_abs_c"]


def run_stabdae(build, csvdir):
    path = os.path.join(csvdir, "fourbar_stabdae.csv")
    # every 10 steps: the same 0.01 grid as ida_mbs's output
    cmd = [
        os.path.join(build, "examples", "fourbar"),
        "--tf",
        str(TF),
        "--T",
        str(T),
        "--every",
        "10",
        "--out",
        path,
    ]
    subprocess.run(cmd, check=True)
    return path


def run_ida(build, csvdir, rtol):
    path = os.path.join(csvdir, "fourbar_ida_index1_rtol%s.csv" % rtol)
    cmd = [
        os.path.join(build, "tools", "ida_mbs"),
        "fourbar",
        "--form",
        "index1",
        "--rtol",
        rtol,
        "--atol",
        ATOL,
        "--tf",
        str(TF),
        "--every-dt",
        "0.01",
        "--out",
        path,
    ]
    subprocess.run(cmd, check=True)
    return path


def at(t, c, when):
    return c[np.argmin(np.abs(t - when))]


def main():
    ap = argparse.ArgumentParser(description="The four-bar's |c| under stabdae and IDA.")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="the build directory")
    ap.add_argument("--outdir", default=None, help="the plot's folder; default: BUILD/figures")
    ap.add_argument("--csvdir", default=None, help="the CSV files' folder; default: BUILD/demo")
    args = ap.parse_args()
    outdir = args.outdir or os.path.join(args.build, "figures")
    csvdir = args.csvdir or os.path.join(args.build, "demo")
    for exe in ("examples/fourbar", "tools/ida_mbs"):
        if not os.access(os.path.join(args.build, exe), os.X_OK):
            sys.exit("drift.py: %s/%s not found; build the project first" % (args.build, exe))
    os.makedirs(outdir, exist_ok=True)
    os.makedirs(csvdir, exist_ok=True)

    runs = [("stabdae (scheme 15, dgrad, T %g)" % T, run_stabdae(args.build, csvdir))]
    runs += [
        ("IDA (index-1 form, rtol %s, atol %s)" % (r, ATOL), run_ida(args.build, csvdir, r))
        for r in RTOLS
    ]
    results = [(label, path) + read_csv(path) for label, path in runs]

    table = [
        ["max abs(c) over the 3 constraints"]
        + ["t = %g" % w for w in SHOWN]
        + ["max over [0, %g]" % TF]
    ]
    for label, _, t, c in results:
        table.append([label] + ["%.1e" % at(t, c, w) for w in SHOWN] + ["%.1e" % np.max(c)])
    widths = [max(len(row[i]) for row in table) for i in range(len(table[0]))]
    for row in table:
        print("   ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip())

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for (label, _, t, c), style in zip(results, ("-", "--", ":")):
        shown = c > 0  # the exact start, log(0) otherwise
        ax.semilogy(t[shown], c[shown], style, label=label)
    eps = np.finfo(float).eps
    ax.axhline(eps, color="gray", lw=0.8, label="machine epsilon (%.1e)" % eps)
    ax.set(
        title="Four-bar linkage: the residual of its three loop-closure constraints",
        xlabel="t [s]",
        ylabel=r"$\mathrm{max}_i\,|c_i(q(t))|$",
    )
    ax.legend(loc="center right")
    ax.grid(True, which="major")
    fig.tight_layout()
    path = os.path.join(outdir, "drift.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    print("plot: %s" % os.path.relpath(path, os.getcwd()))


if __name__ == "__main__":
    main()
