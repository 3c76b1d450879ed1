# SPDX-License-Identifier: GPL-3.0-or-later
"""Figures of the report: matplotlib without a display, one PNG per call of save()."""

import os

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the backend)

plt.rcParams.update(
    {
        "figure.dpi": 110,
        "axes.grid": True,
        "grid.alpha": 0.3,
        "legend.fontsize": 8,
        "axes.titlesize": 10,
        "axes.labelsize": 9,
    }
)


def figure(ncols=1, nrows=1, width=6.4, height=4.2):
    """A figure of nrows x ncols panels, each width x height inches; the axes as a flat list."""
    fig, axes = plt.subplots(nrows, ncols, figsize=(width * ncols, height * nrows), squeeze=False)
    return fig, [ax for row in axes for ax in row]


def save(fig, outdir, name):
    """Writes outdir/name and returns name (the report links it relative to itself)."""
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, name))
    plt.close(fig)
    return name


# one look per map in every figure
MARKERS = {"euler": "o", "midpoint": "s", "dgrad": "^", "user": "v", "dg4": "D", "rk4": "P"}
COLOURS = dict(
    zip(MARKERS, ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown"))
)


def orders(axes, results, ylabel):
    """One log-log panel per case of results (case, map, order p, Ts, errors, fitted order):
    each map's errors against T and, dotted, the slope p through its coarsest point."""
    names = list(dict.fromkeys(r[0] for r in results))
    for ax, name in zip(axes, names):
        for _, map_name, p, Ts, errs, fit in (r for r in results if r[0] == name):
            colour = COLOURS[map_name]
            ax.loglog(
                Ts,
                errs,
                marker=MARKERS[map_name],
                ms=4,
                color=colour,
                label="%s (%.2f)" % (map_name, fit),
            )
            ax.loglog(Ts, errs[0] * (np.array(Ts) / Ts[0]) ** p, ":", color=colour, lw=1)
        ax.set_title(name)
        ax.set_xlabel("T")
        ax.set_ylabel(ylabel)
        ax.legend(title="map (fitted order)", loc="lower right")
