# SPDX-License-Identifier: GPL-3.0-or-later
"""stabdae_ref: an independent Python reference for stabdae (numpy + mpmath).

Schemes 11 and 15 of Di Franco, Scarciotti, Astolfi, "Discretization schemes for constraint
stabilization in nonlinear differential-algebraic systems", with the maps of the library's
names euler, midpoint, dgrad (Gonzalez's discrete gradient), user (the model's user map: the
oscillator's is the paper's Section IV map), rk4 and rk8 (explicit Runge-Kutta, the tableaus
of tableaus.py), the baselines none and baumgarte, for the
oscillator, the pendulum and the chain (models.py), in float64 or in mpmath (dps digits, 40 by
default, Newton to a residual 10^-(dps-10)). Numbers given as input (parameters, T, x0) are
rounded to doubles first, so both arithmetics solve exactly the problem the C library is given.

Usage:

    import stabdae_ref
    res = stabdae_ref.simulate("oscillator", {"d": 0.0}, x0=(0.1, 0.6, 0, 0), T=1e-3,
                               nsteps=10000, scheme=15, map="dgrad", arithmetic="mpmath", dps=40)
    res.header, res.rows, res.column("W")

    python -m stabdae_ref oscillator --d 0 --map dgrad --tf 10 --arith mpmath --out run.csv
    python -m stabdae_ref expected --outdir examples/expected

(with tools/ on PYTHONPATH; --help lists the options). Rows: step 0, every `every`-th step and
the last, at t = n T; newton_iters counts the Newton updates of the step (0 for euler).
Defaults: models.py (the chain starts with every mass at rest 0.6 above the floor, X
alternating +-0.1, unless x0 gives 4 N values or seed the C program's random start, rng.py);
delta 2, eps 1, scheme 15, stabilizer paper; the command line's map is user for the oscillator
and dgrad otherwise. `expected` writes the answers of the C examples' regression tests
(expected.py). Exact solutions on the manifold: exact.oscillator_exact (d = 0, Jacobi cn),
exact.pendulum_exact (Jacobi sn), and exact.manifold_reference (mpmath's Taylor ODE solver on
mu' = q0(mu), any model and d). Tests: python -m pytest tools/stabdae_ref/tests.
"""

from .api import Result, simulate
from .stepper import StepFailure

__all__ = ["Result", "StepFailure", "simulate"]
