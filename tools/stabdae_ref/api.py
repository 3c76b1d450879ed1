# SPDX-License-Identifier: GPL-3.0-or-later
"""simulate(): a whole run in one call, rows in the columns of the C examples' CSV."""

import math

from . import arith, models, rng, stepper

METHOD_DEFAULTS = {"delta": 2.0, "eps": 1.0, "alpha": (1.0, 2.0)}


class Result:
    """header: the CSV column names; rows: tuples (numbers of the arithmetic, newton_iters an
    int)."""

    def __init__(self, header, rows):
        self.header, self.rows = tuple(header), rows

    def column(self, name):
        i = self.header.index(name)
        return [row[i] for row in self.rows]


def split_params(params):
    """(model parameters, method parameters) from one dict."""
    model_params, method = {}, dict(METHOD_DEFAULTS)
    for key, value in (params or {}).items():
        (method if key in METHOD_DEFAULTS else model_params)[key] = value
    return model_params, method


def start(mdl, x0=None, seed=None):
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
    model,
    params=None,
    x0=None,
    scheme=15,
    map="dgrad",
    stabilizer="paper",
    arithmetic="float64",
    dps=40,
    seed=None,
):
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


def check_steps(T, nsteps):
    if not (math.isfinite(float(T)) and float(T) > 0):
        raise ValueError("T must be finite and > 0, got %r" % (T,))
    if int(nsteps) != nsteps or nsteps < 1:
        raise ValueError("nsteps must be a positive integer, got %r" % (nsteps,))


def rows(mdl, st, xi, mu, T, nsteps, every=1):
    """Yields the CSV rows of a run (see stepper.run for failures)."""
    for _, t, xi_n, mu_n, iters in stepper.run(st, xi, mu, T, int(nsteps), every):
        yield tuple([t] + mdl.row(xi_n, mu_n) + [iters])


def simulate(
    model,
    params=None,
    x0=None,
    T=0.001,
    nsteps=1000,
    scheme=15,
    map="dgrad",
    stabilizer="paper",
    arithmetic="float64",
    dps=40,
    every=1,
    z0=None,
    seed=None,
):
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
