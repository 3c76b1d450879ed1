# SPDX-License-Identifier: GPL-3.0-or-later
"""The chain reduces to the oscillator: one mass, or uncoupled masses (kc = 0), give the
oscillator's trajectories (a second code path for Q, gains and Newton). Uncoupled masses are
independent under the separable maps (euler, midpoint) only: Gonzalez's discrete gradient
divides by |v|^2 of the whole increment, which mixes the masses."""

import pytest

from stabdae_ref import simulate


@pytest.mark.parametrize("map_name", ["euler", "dgrad", "midpoint"])
def test_one_mass_is_the_oscillator(map_name):
    x0 = (0.2, 0.5, -0.1, 0.3)
    osc = simulate("oscillator", {}, x0, 1e-3, 500, 15, map_name, every=50)
    ch = simulate("chain", {"N": 1}, x0, 1e-3, 500, 15, map_name, every=50)
    for name, other in (("max_abs_Y", "Y"), ("max_abs_Ydot", "Ydot"), ("E", "E")):
        for a, b in zip(ch.column(name), osc.column(other)):
            assert a == pytest.approx(abs(b) if name != "E" else b, rel=1e-13, abs=1e-300)


def test_uncoupled_masses_are_independent_oscillators():
    x_a, x_b = (0.2, 0.5, -0.1, 0.3), (-0.4, 0.1, 0.2, 0.0)
    ch = simulate("chain", {"N": 2, "kc": 0.0}, x_a + x_b, 1e-3, 500, 15, "midpoint", every=50)
    oa = simulate("oscillator", {}, x_a, 1e-3, 500, 15, "midpoint", every=50)
    ob = simulate("oscillator", {}, x_b, 1e-3, 500, 15, "midpoint", every=50)
    for e, ea, eb in zip(ch.column("E"), oa.column("E"), ob.column("E")):
        assert e == pytest.approx(ea + eb, rel=1e-12)
    for y, ya, yb in zip(ch.column("max_abs_Y"), oa.column("Y"), ob.column("Y")):
        assert y == pytest.approx(max(abs(ya), abs(yb)), rel=1e-12)


def test_chain_constraints_converge():
    """Scheme 15: every Y_i -> 0 (Theorem 4), here from the default start."""
    res = simulate("chain", {"N": 3}, None, 1e-3, 3000, 15, "dgrad", every=1000)
    assert res.column("max_abs_Y")[-1] < 1e-12 * res.column("max_abs_Y")[0]
