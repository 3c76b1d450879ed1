# SPDX-License-Identifier: GPL-3.0-or-later
"""Figures of the report: matplotlib without a display, one PNG per call of save()."""

import os

import matplotlib

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
