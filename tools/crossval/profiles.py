# SPDX-License-Identifier: GPL-3.0-or-later
"""The settings of a run: FULL (tools/crossval/crossval --full, the whole report) and FAST (the
ctest subset run by tools/check: fewer cases and steps, same checks and tolerances)."""

import dataclasses


@dataclasses.dataclass(frozen=True)
class Profile:
    name: str
    # a: C against mpmath
    scheme_steps: int  # steps of the oscillator and the pendulum
    chain_steps: int  # steps of the chain (N = 3)
    scheme_cases: str  # "all" or "subset"
    # d: energy
    energy_tf: float  # T = 0.01, so 100 tf steps
    energy_every: int


FULL = Profile(
    "full",
    scheme_steps=10000,
    chain_steps=10000,
    scheme_cases="all",
    energy_tf=10000.0,
    energy_every=10000,
)
FAST = Profile(
    "fast",
    scheme_steps=1000,
    chain_steps=200,
    scheme_cases="subset",
    energy_tf=1000.0,
    energy_every=1000,
)

# Parameters shared by every run, given explicitly to every implementation (their defaults
# differ). delta, eps: eq. 6.
METHOD = {"delta": 2.0, "eps": 1.0}
OSCILLATOR = {"k": 2.0, "d": 0.03, "m": 1.0, "ga": 9.81}
PENDULUM = {"L": 1.0, "m": 1.0, "ga": 9.81}
CHAIN = {"N": 3, "k": 2.0, "kc": 1.0, "d": 0.03, "m": 1.0, "ga": 9.81}

PAPER_X0 = (0.1, 0.6, 0.0, 0.0)  # Section IV's start, 0.6 above the floor
PENDULUM_X0 = (0.5, -0.9, 0.1, 0.2)  # off the circle in position and velocity
CHAIN_X0 = (
    0.3,
    0.2,
    0.0,
    -0.1,  # three masses off the floor, mass by mass
    -0.2,
    -0.1,
    0.1,
    0.05,
    0.4,
    0.15,
    -0.05,
    0.0,
)
