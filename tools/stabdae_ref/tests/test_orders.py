# SPDX-License-Identifier: GPL-3.0-or-later
"""Orders of convergence on the manifold (xi = 0 stays 0, so the mu update is the map alone)
against exact solutions and a 30-digit Taylor reference.

Theory: euler is order 1; midpoint and dgrad are symmetric (phi(mu, mu+) = phi(mu+, mu) with a
constant S) and consistent, hence order 2; user (the paper's map) is symmetric, hence order 2,
only when d = 0: its explicit damping term -d mu2 costs one order, so it is order 1 for d > 0;
rk4 and rk8 have the orders of their tableaus, 4 and 8 (test_rk_order_conditions.py). rk8 is
measured in mpmath (its errors reach 1e-24), with steps T = 2/2^k, exact in binary, so that
n T = tf exactly: a double T = 2/n otherwise ends the run 1e-17 away from tf."""

import math

import pytest

from stabdae_ref import exact, simulate

TF, STEPS = 2.0, (200, 400, 800)  # T = 0.01, 0.005, 0.0025
RK8_STEPS = (64, 128, 256)  # T = 2^-5, 2^-6, 2^-7


def references():
    return {
        "oscillator d=0": exact.oscillator_exact(0.5, [TF])[0],
        "oscillator d=0.3": exact.manifold_reference(
            "oscillator", {"d": 0.3}, (0.5, 0, 0, 0), [TF]
        )[0],
        "pendulum": exact.pendulum_exact(0.5, [TF])[0],
    }


REF = {}


def error(case, model, params, map_name, n, arithmetic="float64"):
    if not REF:
        REF.update(references())
    res = simulate(
        model,
        params,
        None,
        TF / n,
        n,
        15,
        map_name,
        z0=([0, 0], [0.5, 0]),
        every=n,
        arithmetic=arithmetic,
    )
    mu = (res.column("mu1")[-1], res.column("mu2")[-1])
    return max(abs(float(a - b)) for a, b in zip(mu, REF[case]))


@pytest.mark.parametrize(
    "case, model, params, map_name, order",
    [
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
        ("oscillator d=0", "oscillator", {"d": 0.0}, "rk4", 4),
        ("oscillator d=0.3", "oscillator", {"d": 0.3}, "rk4", 4),
        ("pendulum", "pendulum", {}, "rk4", 4),
    ],
)
def test_order(case, model, params, map_name, order):
    errs = [error(case, model, params, map_name, n) for n in STEPS]
    observed = [math.log2(e1 / e2) for e1, e2 in zip(errs, errs[1:])]
    assert observed[-1] == pytest.approx(order, abs=0.05), errs


@pytest.mark.parametrize(
    "case, model, params",
    [
        ("oscillator d=0", "oscillator", {"d": 0.0}),
        ("oscillator d=0.3", "oscillator", {"d": 0.3}),
        ("pendulum", "pendulum", {}),
    ],
)
def test_order_rk8(case, model, params):
    errs = [error(case, model, params, "rk8", n, "mpmath") for n in RK8_STEPS]
    observed = [math.log2(e1 / e2) for e1, e2 in zip(errs, errs[1:])]
    assert observed[-1] == pytest.approx(8, abs=0.05), errs
