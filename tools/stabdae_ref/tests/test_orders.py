# SPDX-License-Identifier: GPL-3.0-or-later
"""Orders of convergence on the manifold (xi = 0 stays 0, so the mu update is the map alone)
against exact solutions and a 30-digit Taylor reference.

Theory: euler is order 1; midpoint and dgrad are symmetric (phi(mu, mu+) = phi(mu+, mu) with a
constant S) and consistent, hence order 2; user (the paper's map) is symmetric, hence order 2,
only when d = 0: its explicit damping term -d mu2 costs one order, so it is order 1 for d > 0."""
import math

import pytest

from stabdae_ref import exact, simulate

TF, STEPS = 2.0, (200, 400, 800)  # T = 0.01, 0.005, 0.0025


def references():
    return {
        "oscillator d=0": exact.oscillator_exact(0.5, [TF])[0],
        "oscillator d=0.3": exact.manifold_reference("oscillator", {"d": 0.3}, (0.5, 0, 0, 0),
                                                     [TF])[0],
        "pendulum": exact.pendulum_exact(0.5, [TF])[0],
    }


REF = {}


def error(case, model, params, map_name, n):
    if not REF:
        REF.update(references())
    res = simulate(model, params, None, TF / n, n, 15, map_name, z0=([0, 0], [0.5, 0]), every=n)
    mu = (res.column("mu1")[-1], res.column("mu2")[-1])
    return max(abs(float(a - b)) for a, b in zip(mu, REF[case]))


@pytest.mark.parametrize("case, model, params, map_name, order", [
    ("oscillator d=0", "oscillator", {"d": 0.0}, "euler", 1),
    ("oscillator d=0", "oscillator", {"d": 0.0}, "midpoint", 2),
    ("oscillator d=0", "oscillator", {"d": 0.0}, "dgrad", 2),
    ("oscillator d=0", "oscillator", {"d": 0.0}, "user", 2),
    ("oscillator d=0.3", "oscillator", {"d": 0.3}, "euler", 1),
    ("oscillator d=0.3", "oscillator", {"d": 0.3}, "midpoint", 2),
    ("oscillator d=0.3", "oscillator", {"d": 0.3}, "dgrad", 2),
    ("oscillator d=0.3", "oscillator", {"d": 0.3}, "user", 1),
    ("pendulum", "pendulum", {}, "euler", 1),
    ("pendulum", "pendulum", {}, "midpoint", 2),
    ("pendulum", "pendulum", {}, "dgrad", 2),
])
def test_order(case, model, params, map_name, order):
    errs = [error(case, model, params, map_name, n) for n in STEPS]
    observed = [math.log2(e1 / e2) for e1, e2 in zip(errs, errs[1:])]
    assert observed[-1] == pytest.approx(order, abs=0.05), errs
