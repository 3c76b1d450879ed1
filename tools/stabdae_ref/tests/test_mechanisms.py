# SPDX-License-Identifier: GPL-3.0-or-later
"""The front-end's references (mechanisms.py): each conserves the energy and keeps its
constraints, and the two independent constructions (angles or Jacobi functions against the
Cartesian index-1 ODE of the bars) agree."""

import math

import mpmath
import pytest

from stabdae_ref import mechanisms as mech

TIMES = [0.0, 0.2, 0.45]
G = 9.81


def close(a, b, tol):
    return max(abs(x - y) for x, y in zip(a, b)) < tol


def test_pendulum_exact_against_bars():
    L, th0 = 1.3, 0.5
    ref = mech.pendulum_exact(th0, TIMES, L)
    bars = mech.bars([2.0], [(0, (0.0, 0.0), L)], ref[0][:2], ref[0][2:], TIMES)
    for r, b in zip(ref, bars):
        assert close(r, b, 1e-18)
        assert abs(mech.constraint([(0, (0, 0), mpmath.mpf(L))], r[:2])[0]) < 1e-25
        assert abs(r[0] * r[2] + r[1] * r[3]) < 1e-25  # G v = 0
        assert (
            abs(mech.energy([1.0], r[:2], r[2:]) - mech.energy([1.0], *[ref[0][:2], ref[0][2:]]))
            < 1e-25
        )


def test_pendulum_lambda_is_the_constraint_force():
    """m vx' = -x lambda, vx' by a central difference of the exact solution."""
    L, m, th0, t, h = 1.3, 2.0, 1.0, 0.37, mpmath.mpf(10) ** -10
    (a, b) = mech.pendulum_exact(th0, [t - h, t + h], L)
    (s,) = mech.pendulum_exact(th0, [t], L)
    acc = (b[2] - a[2]) / (2 * h)
    assert abs(mech.pendulum_lambda(s, L, m, G) - (-m * acc / s[0])) < 1e-15


def test_double_pendulum_angles_against_bars():
    L1, L2, m1, m2 = 1.0, 0.7, 1.0, 1.5
    th, om = (0.5, 1.0), (0.3, -0.2)
    ref = mech.double_pendulum(th, om, TIMES, L1, L2, m1, m2, G)
    links = [(0, (0.0, 0.0), L1), (1, 0, L2)]
    bars = mech.bars([m1, m2], links, ref[0][:4], ref[0][4:], TIMES)
    E0 = mech.energy([m1, m2], ref[0][:4], ref[0][4:])
    assert (
        abs(ref[0][0] - L1 * math.sin(0.5)) < 1e-15
        and abs(ref[0][6] - ref[0][4] - L2 * -0.2 * math.cos(1.0)) < 1e-15
    )
    for r, b in zip(ref, bars):
        assert close(r, b, 1e-17)
        exact_links = [(a, b, mpmath.mpf(length)) for a, b, length in links]
        assert max(abs(c) for c in mech.constraint(exact_links, r[:4])) < 1e-22
        assert abs(mech.energy([m1, m2], r[:4], r[4:]) - E0) < 1e-18


def test_bars_fourbar_keeps_constraints_and_energy():
    """A four-bar (ground pivots A, D; masses at B, C): the index-1 solution stays on c = 0 and
    conserves the energy; a wrong gamma (the bars' second derivative) would break both."""
    A, D = (0.0, 0.0), (2.0, 0.0)
    B = (0.0, 1.0)
    C = (2.0, 1.0 + math.sqrt(0.0))
    links = [(0, A, 1.0), (0, 1, 2.0), (1, D, 1.0)]
    q0, v0 = list(B) + list(C), [1.0, 0.0, 1.0, 0.0]  # a parallelogram moving as one
    sol = mech.bars([1.0, 2.0], links, q0, v0, TIMES)
    E0 = mech.energy([1.0, 2.0], q0, v0, mpmath.mpf(G))
    for s in sol:
        assert max(abs(c) for c in mech.constraint(links, s[:4])) < 1e-20
        assert abs(mech.energy([1.0, 2.0], s[:4], s[4:], mpmath.mpf(G)) - E0) < 1e-18
    # the parallelogram: B - A = C - D at all times
    assert close(sol[-1][:2], [sol[-1][2] - 2.0, sol[-1][3]], 1e-20)


@pytest.fixture(autouse=True)
def digits():
    with mpmath.workdps(30):
        yield
