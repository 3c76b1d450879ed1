# SPDX-License-Identifier: GPL-3.0-or-later
"""The four-bar of fourbar.py written by its nonzeros (sparse=True; by its size, 4 coordinates,
it would be dense): M's diagonal and the 8 nonzeros of G's 12 entries in the patterns of
<stabdae/pattern.h>. A sparse mechanism small enough to compare with the dense one step by step,
and the sparse FMU examples/fmus/fourbar_sparse."""

from fourbar import fourbar


def mechanism():
    return fourbar("fourbar_sparse", sparse=True)
