# SPDX-License-Identifier: GPL-3.0-or-later
"""The cart with a pendulum: what the run kept. Reads the CSV of `cart` and draws, against t,
the energy's relative drift (E - E0) / |E0| and the largest constraint residual max |c| (log
scale); prints the largest of each on a line of its own.

Usage: python plot.py CART.csv [OUT.png]   (default: CART.png beside the CSV)
"""

import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")  # a file, no display
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)


def main(argv):
    if len(argv) not in (1, 2):
        print("usage: python plot.py CART.csv [OUT.png]", file=sys.stderr)
        return 2
    csv = argv[0]
    png = argv[1] if len(argv) == 2 else os.path.splitext(csv)[0] + ".png"
    try:
        data = np.genfromtxt(csv, delimiter=",", names=True)
    except (OSError, ValueError) as err:
        print(f"plot.py: {csv}: {err}", file=sys.stderr)
        return 2
    if data.ndim != 1 or data.size < 2 or not {"t", "energy", "max_abs_c"} <= set(
            data.dtype.names):
        print(f"plot.py: {csv}: not a CSV of cart (t, ..., energy, max_abs_c; two rows at least)",
              file=sys.stderr)
        return 2

    t, E, c = data["t"], data["energy"], data["max_abs_c"]
    drift = (E - E[0]) / abs(E[0])
    print(f"largest relative energy drift |E - E0| / |E0|: {np.max(np.abs(drift)):.3g}")
    print(f"largest constraint residual max|c|: {np.max(c):.3g}")

    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5.5))
    top.plot(t, drift, lw=1)
    top.set_ylabel("(E - E0) / |E0|")
    top.set_title("cart with a pendulum: energy and constraints")
    top.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    top.grid(alpha=0.3)
    # an exact zero has no logarithm: left out rather than drawn at the axis' floor
    bottom.semilogy(t, np.where(c > 0, c, np.nan), lw=1, label="max |c|")
    bottom.axhline(np.finfo(float).eps, color="gray", ls="--", lw=1,
                   label="double precision's epsilon")
    bottom.set_xlabel("t [s]")
    bottom.set_ylabel("max |c|")
    # room above the curve for the legend, which would hide its peaks otherwise
    bottom.set_ylim(top=100 * np.max(c) if np.max(c) > 0 else None)
    bottom.legend(loc="upper right", ncol=2)
    bottom.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    print(f"wrote {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
