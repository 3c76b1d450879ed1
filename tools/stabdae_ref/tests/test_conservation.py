# SPDX-License-Identifier: GPL-3.0-or-later
"""Energy on the manifold with d = 0: the discrete gradient gives W(mu+) - W(mu) =
gradbar W . (mu+ - mu) = T gradbar W . S gradbar W = 0 for a skew S, so W is conserved up to
rounding and Newton's residual; with d > 0 the same identity gives a monotone decrease."""

import pytest

from stabdae_ref import simulate

ON_MANIFOLD = (0.5, 0.0, 0.0, 0.0)  # Y = Ydot = 0: xi = 0


def drift(values):
    return max(abs(v - values[0]) for v in values) / abs(values[0])


@pytest.mark.parametrize("map_name", ["dgrad", "user"])
def test_float64_conserves_W_over_1e4_steps(map_name):
    res = simulate("oscillator", {"d": 0.0}, ON_MANIFOLD, 1e-3, 10000, 15, map_name)
    assert drift(res.column("W")) <= 1e-13


@pytest.mark.parametrize("map_name", ["dgrad", "user"])
def test_mpmath_conserves_W(map_name):
    res = simulate(
        "oscillator", {"d": 0.0}, ON_MANIFOLD, 1e-3, 1000, 15, map_name, arithmetic="mpmath", dps=50
    )
    assert drift(res.column("W")) <= 1e-35


def test_midpoint_does_not_conserve_the_quartic_W():
    """The check can fail: the midpoint rule keeps quadratic invariants only."""
    res = simulate("oscillator", {"d": 0.0}, ON_MANIFOLD, 1e-3, 2000, 15, "midpoint")
    assert drift(res.column("W")) > 1e-9


def test_pendulum_dg_conserves_H():
    """On the manifold E = H(mu): the Gonzalez map conserves it for a non-polynomial H too."""
    res = simulate(
        "pendulum",
        {},
        None,
        1e-3,
        1000,
        15,
        "dgrad",
        arithmetic="mpmath",
        dps=50,
        z0=([0, 0], ["0.5", "0.3"]),
    )
    assert drift(res.column("E")) <= 1e-35


def test_chain_dg_conserves_H():
    x0 = [0.1, 0, 0, 0, -0.2, 0, 0, 0, 0.3, 0, 0, 0, 0, 0, 0.1, 0]
    res = simulate("chain", {"N": 4, "d": 0.0}, x0, 1e-3, 2000, 15, "dgrad")
    assert drift(res.column("E")) <= 1e-13


def test_damped_dg_dissipates_W_monotonically():
    W = simulate("oscillator", {"d": 0.3}, ON_MANIFOLD, 1e-2, 1000, 15, "dgrad").column("W")
    assert all(b < a for a, b in zip(W, W[1:]))
    assert W[-1] < 0.5 * W[0]


def test_energy_settles_once_on_the_manifold():
    """Paper Section IV, d = 0: off the manifold xi decays (scheme 15); afterwards the
    discrete gradient keeps W constant (Fig. 9)."""
    res = simulate("oscillator", {"d": 0.0}, (0.1, 0.6, 0, 0), 1e-3, 10000, 15, "dgrad", every=100)
    late = [w for t, w in zip(res.column("t"), res.column("W")) if t >= 2]
    assert max(abs(y) for t, y in zip(res.column("t"), res.column("Y")) if t >= 2) < 1e-20
    assert drift(late) <= 1e-13
    assert abs(late[0] - res.column("W")[0]) > 1e-3  # the transient did change W
