# SPDX-License-Identifier: GPL-3.0-or-later
"""simulate(): a whole run in one call, rows in the columns of the C examples' CSV."""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Sequence
from typing import Any, Tuple

from . import arith, models, rng, stepper
from .arith import Num, Vector

# A CSV row: t, the model's columns (numbers of the arithmetic), newton_iters an int
Row = Tuple[Any, ...]

METHOD_DEFAULTS = {"delta": 2.0, "eps": 1.0, "alpha": (1.0, 2.0)}


class Result:
    """header: the CSV column names; rows: tuples (numbers of the arithmetic, newton_iters an
    int)."""

    def __init__(self, header: Iterable[str], rows: list[Row]) -> None:
        self.header, self.rows = tuple(header), rows

    def column(self, name: str) -> list[Any]:
        i = self.header.index(name)
        return [row[i] for row in self.rows]


def split_params(params: models.Params | None) -> tuple[dict[str, Any], dict[str, Any]]:
    """(model parameters, method parameters) from one dict."""
    model_params: dict[str, Any]
    model_params, method = {}, dict(METHOD_DEFAULTS)
    for key, value in (params or {}).items():
        (method if key in METHOD_DEFAULTS else model_params)[key] = value
    return model_params, method


def start(
    mdl: models.Model, x0: Sequence[float] | None = None, seed: int | None = None
) -> list[float]:
    """The physical start: x0, else the chain's random start of `seed` (as the C program's
    --seed), else the model's default."""
    if x0 is not None:
        return [float(v) for v in x0]
    if seed is not None:
        if mdl.name != "chain":
            raise ValueError("seed applies to the chain only, not to model %s" % mdl.name)
        return rng.chain_x0(mdl.N, seed)
    return mdl.default_x0()


def setup(
    model: str,
    params: models.Params | None = None,
    x0: Sequence[float] | None = None,
    scheme: int = 15,
    map: str = "dgrad",
    stabilizer: str = "paper",
    arithmetic: str = "float64",
    dps: int = 40,
    seed: int | None = None,
) -> tuple[models.Model, stepper.Stepper, Vector, Vector]:
    """(model object, Stepper, xi0, mu0): everything checked before the first step."""
    a = arith.make(arithmetic, dps)
    model_params, method = split_params(params)
    mdl = models.make(model, a, model_params)
    st = stepper.Stepper(mdl, scheme, map, stabilizer, **method)
    x = start(mdl, x0, seed)
    if mdl.name != "chain" and len(x) != 4:
        raise ValueError("x0 needs 4 values (X, Y, Xdot, Ydot), got %d" % len(x))
    if not all(math.isfinite(v) for v in x):
        raise ValueError("x0 must be finite")
    xi, mu = mdl.to_z([a.num(v) for v in x])
    return mdl, st, xi, mu


def check_steps(T: float, nsteps: int) -> None:
    if not (math.isfinite(float(T)) and float(T) > 0):
        raise ValueError("T must be finite and > 0, got %r" % (T,))
    if int(nsteps) != nsteps or nsteps < 1:
        raise ValueError("nsteps must be a positive integer, got %r" % (nsteps,))


def rows(
    mdl: models.Model,
    st: stepper.Stepper,
    xi: Vector,
    mu: Vector,
    T: Num,
    nsteps: int,
    every: int = 1,
) -> Iterator[Row]:
    """Yields the CSV rows of a run (see stepper.run for failures)."""
    for _, t, xi_n, mu_n, iters in stepper.run(st, xi, mu, T, int(nsteps), every):
        yield tuple([t] + mdl.row(xi_n, mu_n) + [iters])


def simulate(
    model: str,
    params: models.Params | None = None,
    x0: Sequence[float] | None = None,
    T: float = 0.001,
    nsteps: int = 1000,
    scheme: int = 15,
    map: str = "dgrad",
    stabilizer: str = "paper",
    arithmetic: str = "float64",
    dps: int = 40,
    every: int = 1,
    z0: Sequence[Sequence[float | str]] | None = None,
    seed: int | None = None,
) -> Result:
    """Runs `nsteps` steps of size T and returns a Result.

    model       'oscillator', 'pendulum' or 'chain'
    params      model parameters (k, d, m, ga, q | L, m, ga | N, k, d, m, ga, kc) and the
                method's (delta, eps, alpha); defaults in models.py, delta 2, eps 1,
                alpha (1, 2)
    x0          physical start (X, Y, Xdot, Ydot per mass), mapped by Phi; default per model
    seed        the chain only, without x0: the C program's random start of --seed (rng.py)
    z0          (xi0, mu0) instead of x0, given directly in the coordinates (numbers or
                strings; strings are exact in mpmath)
    scheme      11 or 15;  map 'euler' | 'midpoint' | 'dgrad' | 'user' (the oscillator's
                user map, the paper's Section IV map) | 'rk4' | 'rk8' (explicit
                Runge-Kutta, tableaus.py): the library's names
    stabilizer  'paper' | 'none' | 'baumgarte'
    arithmetic  'float64' or 'mpmath' (dps digits)
    A failed step raises stepper.StepFailure, whose `result` holds the rows computed before.
    """
    check_steps(T, nsteps)
    mdl, st, xi, mu = setup(model, params, x0, scheme, map, stabilizer, arithmetic, dps, seed)
    if z0 is not None:
        xi, mu = [mdl.a.num(v) for v in z0[0]], [mdl.a.num(v) for v in z0[1]]
        if len(xi) != mdl.n_xi or len(mu) != mdl.n_mu:
            raise ValueError("z0 needs %d + %d values" % (mdl.n_xi, mdl.n_mu))
    out = []
    try:
        for row in rows(mdl, st, xi, mu, mdl.a.num(float(T)), nsteps, every):
            out.append(row)
    except stepper.StepFailure as failure:
        failure.result = Result(mdl.header, out)
        raise
    return Result(mdl.header, out)
