# SPDX-License-Identifier: GPL-3.0-or-later
"""The chain example's random start, drawn as the C program draws it: GSL's gsl_rng_mt19937 is
the Mersenne Twister MT19937 seeded by init_genrand (GSL seeds 0 as 4357), gsl_rng_uniform is
its 32-bit output over 2^32 and gsl_ran_flat(a, b) is a (1 - u) + b u. numpy's RandomState is
the same generator with the same seeding, and randint over [0, 2^32) returns its raw outputs, so
the C program `chain --seed S` and chain_x0(N, S) start from the same state.
"""

from __future__ import annotations

import numpy as np


class MT19937:
    """next32() gives the generator's 32-bit outputs in order."""

    def __init__(self, seed: int) -> None:
        self.state = np.random.RandomState((seed & 0xFFFFFFFF) or 4357)  # GSL's 0 is 4357

    def next32(self) -> int:
        return int(self.state.randint(0, 2**32, dtype=np.uint32))

    def uniform(self) -> float:
        """u in [0, 1): the output over 2^32 (exact in a double)."""
        return self.next32() / 4294967296.0

    def flat(self, a: float, b: float) -> float:
        """A number in [a, b) from one output, a (1 - u) + b u."""
        u = self.uniform()
        return a * (1 - u) + b * u


def chain_x0(N: int, seed: int) -> list[float]:
    """The chain's start (X, Y, Xdot, Ydot per mass, 4 N doubles): X_i in [-0.5, 0.5),
    Y_i in [-0.2, 0.2), Xdot_i and Ydot_i in [-0.1, 0.1), drawn mass by mass in that order."""
    if int(seed) != seed or seed < 0:
        raise ValueError("seed must be a whole number >= 0, got %r" % (seed,))
    r = MT19937(int(seed))
    x = []
    for _ in range(int(N)):
        x += [r.flat(-0.5, 0.5), r.flat(-0.2, 0.2), r.flat(-0.1, 0.1), r.flat(-0.1, 0.1)]
    return x
