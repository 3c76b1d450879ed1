# SPDX-License-Identifier: GPL-3.0-or-later
"""float64 against mpmath (40 digits) over 1e3 steps: the two runs follow the same discrete
map, so they differ by rounding only, at most 1e-12 relative. Compared per row: the state
(xi, mu) normwise, the energies relative to their size."""

import pytest

from stabdae_ref import simulate

STATE = ("xi1", "xi2", "mu1", "mu2")


def compare(model, params, x0, scheme, map_name, stabilizer="paper", nsteps=1000):
    rf = simulate(model, params, x0, 1e-3, nsteps, scheme, map_name, stabilizer, every=10)
    rm = simulate(
        model, params, x0, 1e-3, nsteps, scheme, map_name, stabilizer, arithmetic="mpmath", every=10
    )
    return rf, rm


def rel_norm(rf, rm, names):
    cols = [(rf.column(n), rm.column(n)) for n in names]
    worst = 0.0
    for i in range(len(rf.rows)):
        diff = max(abs(f[i] - float(m[i])) for f, m in cols)
        size = max(abs(float(m[i])) for _, m in cols)
        worst = max(worst, diff / size)
    return worst


@pytest.mark.parametrize(
    "model, params, x0, scheme, map_name, stabilizer",
    [
        ("oscillator", {}, None, 15, "dgrad", "paper"),
        ("oscillator", {"q": "paper"}, None, 11, "user", "paper"),
        ("oscillator", {}, None, 15, "midpoint", "baumgarte"),
        ("pendulum", {}, (0.5, -0.8, 0.1, 0.2), 15, "dgrad", "paper"),
    ],
)
def test_float64_matches_mpmath(model, params, x0, scheme, map_name, stabilizer):
    rf, rm = compare(model, params, x0, scheme, map_name, stabilizer)
    assert len(rf.rows) == len(rm.rows) == 101
    assert rel_norm(rf, rm, STATE) <= 1e-12
    assert rel_norm(rf, rm, ("E",)) <= 1e-12


def test_chain_float64_matches_mpmath():
    rf, rm = compare(
        "chain", {"N": 2}, [0.1, 0.6, 0, 0, -0.2, 0.3, 0.1, 0], 15, "dgrad", nsteps=300
    )
    for name in ("max_abs_Y", "E"):
        assert rel_norm(rf, rm, (name,)) <= 1e-12
