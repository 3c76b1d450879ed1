# SPDX-License-Identifier: GPL-3.0-or-later
"""The generator's one error: a description it cannot turn into C, said in one line."""


class ModelError(ValueError):
    """A mechanism's description that the generator refuses; str() is the one line to print."""
