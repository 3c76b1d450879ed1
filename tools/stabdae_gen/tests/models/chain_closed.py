# SPDX-License-Identifier: GPL-3.0-or-later
"""The closed chain of chain.py: 32 rods between two anchors, 62 coordinates, 32 rods."""

from chain import chain


def mechanism():
    return chain("chain_closed", closed=True)
