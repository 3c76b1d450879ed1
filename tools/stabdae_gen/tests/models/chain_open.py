# SPDX-License-Identifier: GPL-3.0-or-later
"""The open chain of chain.py: 32 joints hanging from a pivot, 64 coordinates, 32 rods."""

from chain import chain


def mechanism():
    return chain("chain_open", closed=False)
