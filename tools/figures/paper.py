#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Figures 2-9 of the paper (Section IV) from the built oscillator example.

Runs build/examples/oscillator with the paper's setup (k 2, m 1, delta 2, epsilon 1, T 0.001,
tf 50, start (0.1, 0.6, 0, 0), scheme 15, the paper's map: the model's user map, --map user)
for d = 0.03 and d = 0, and writes fig2.png ... fig9.png:

    d = 0.03: Fig 2 Y(t), Fig 3 X(t), Fig 4 the X-Y path, Fig 5 the energy E(t)
    d = 0:    Fig 6 X(t), Fig 7 Y(t), Fig 8 the X-Y path, Fig 9 the energy E(t)

    PYTHONPATH=tools python -m figures.paper [--build build] [--outdir build/figures] [--every 10]
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


def run_oscillator(exe, d, every, outdir):
    """Runs the example into outdir/oscillator_d<d>.csv and returns its columns."""
    path = os.path.join(outdir, "oscillator_d%s.csv" % d)
    cmd = [exe, "--d", str(d), "--map", "user", "--every", str(every), "--out", path]
    subprocess.run(cmd, check=True)
    data = np.genfromtxt(path, delimiter=",", names=True)
    return data, path


def save(fig, outdir, number):
    path = os.path.join(outdir, "fig%d.png" % number)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fig_Y(data, d, number, outdir):
    """Y(t): linear, and |Y| on a log scale where the convergence to the floor shows."""
    fig, (ax, lg) = plt.subplots(1, 2, figsize=(11, 4))
    t, Y = data["t"], data["Y"]
    ax.plot(t, Y)
    ax.set(title="Fig. %d: Y(t), d = %g" % (number, d), xlabel="t [s]", ylabel="Y")
    ax.grid(True)
    early = t <= 1.5  # the fall onto the floor, magnified
    ins = ax.inset_axes([0.4, 0.35, 0.55, 0.55])
    ins.plot(t[early], Y[early])
    ins.set_title("0 <= t <= 1.5", fontsize=9)
    ins.tick_params(labelsize=8)
    ins.grid(True)
    nz = np.abs(Y) > 0
    lg.semilogy(t[nz], np.abs(Y[nz]))
    low = int(np.floor(np.log10(np.min(np.abs(Y[nz])))))
    lg.set_yticks([10.0**e for e in range(0, low - 1, -25)])
    lg.axhline(1e-12, color="gray", ls="--", lw=0.8, label="1e-12")
    lg.set(
        title="Fig. %d (log scale): |Y(t)|, the constraint violation" % number,
        xlabel="t [s]",
        ylabel="|Y|",
    )
    lg.legend()
    lg.grid(True, which="major")
    return save(fig, outdir, number)


def fig_X(data, d, number, outdir):
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(data["t"], data["X"])
    ax.set(title="Fig. %d: X(t), d = %g" % (number, d), xlabel="t [s]", ylabel="X")
    ax.grid(True)
    return save(fig, outdir, number)


def fig_path(data, d, number, outdir):
    fig, ax = plt.subplots(figsize=(7, 5))
    ax.plot(data["X"], data["Y"], lw=0.8)
    ax.plot(data["X"][0], data["Y"][0], "o", color="C3", label="start (0.1, 0.6)")
    ax.plot(data["X"][-1], data["Y"][-1], "s", color="C2", label="t = %g" % data["t"][-1])
    ax.set(title="Fig. %d: path in the X-Y plane, d = %g" % (number, d), xlabel="X", ylabel="Y")
    ax.legend()
    ax.grid(True)
    return save(fig, outdir, number)


def fig_energy(data, d, number, outdir):
    """E(t), and E on the manifold: dissipated (log scale) for d > 0, constant for d = 0."""
    fig, (ax, zm) = plt.subplots(1, 2, figsize=(11, 4))
    t, E = data["t"], data["E"]
    ax.plot(t, E, label="E (total mechanical energy)")
    ax.set(
        title="Fig. %d: total mechanical energy E(t), d = %g" % (number, d),
        xlabel="t [s]",
        ylabel="E",
    )
    ax.legend()
    ax.grid(True)
    late = t >= 5.0  # on the manifold: |Y| < 1e-12 there
    if d > 0:
        zm.semilogy(t[late], E[late])
        zm.set(
            title="Fig. %d: E for t >= 5 (log scale), dissipated by friction" % number,
            xlabel="t [s]",
            ylabel="E",
        )
    else:
        E5 = E[late][0]
        zm.plot(t[late], (E[late] - E5) / abs(E5))
        zm.set(
            title="Fig. %d: (E(t) - E(5)) / E(5) for t >= 5: conserved" % number,
            xlabel="t [s]",
            ylabel="relative change of E",
        )
        zm.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    zm.grid(True)
    return save(fig, outdir, number)


def main():
    ap = argparse.ArgumentParser(description="Figures 2-9 of the paper from the oscillator.")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="the build directory")
    ap.add_argument("--outdir", default=None, help="default: BUILD/figures")
    ap.add_argument("--every", type=int, default=10, help="a CSV row every N steps")
    args = ap.parse_args()
    outdir = args.outdir or os.path.join(args.build, "figures")
    exe = os.path.join(args.build, "examples", "oscillator")
    if not os.access(exe, os.X_OK):
        sys.exit("paper.py: %s not found; build the project first" % exe)
    os.makedirs(outdir, exist_ok=True)

    damped, _ = run_oscillator(exe, 0.03, args.every, outdir)
    free, _ = run_oscillator(exe, 0, args.every, outdir)
    paths = [
        fig_Y(damped, 0.03, 2, outdir),
        fig_X(damped, 0.03, 3, outdir),
        fig_path(damped, 0.03, 4, outdir),
        fig_energy(damped, 0.03, 5, outdir),
        fig_X(free, 0.0, 6, outdir),
        fig_Y(free, 0.0, 7, outdir),
        fig_path(free, 0.0, 8, outdir),
        fig_energy(free, 0.0, 9, outdir),
    ]
    for p in paths:
        print(p)
    print("figures written to %s" % outdir)


if __name__ == "__main__":
    main()
