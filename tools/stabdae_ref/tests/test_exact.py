# SPDX-License-Identifier: GPL-3.0-or-later
"""The references themselves: the Jacobi-function solutions conserve energy and satisfy their
ODE, and mpmath's Taylor solver agrees with them (two independent constructions)."""

import mpmath
import pytest

from stabdae_ref import exact

TIMES = [0.0, 0.3, 1.1, 2.5]


@pytest.fixture(autouse=True)
def digits():
    with mpmath.workdps(40):
        yield


def test_oscillator_exact_energy_and_ode():
    k, m, A = 2.0, 1.5, 0.7
    sol = exact.oscillator_exact(A, TIMES, k, m)
    for X, Xd in sol:
        assert abs(m * Xd**2 / 2 + k * X**4 / 4 - k * mpmath.mpf(A) ** 4 / 4) < 1e-35
    h = mpmath.mpf(10) ** -12
    for t in TIMES[1:]:
        (xm, _), (x0, _), (xp, _) = exact.oscillator_exact(A, [t - h, t, t + h], k, m)
        assert abs((xp - 2 * x0 + xm) / h**2 + k * x0**3 / m) < 1e-12


def test_pendulum_exact_energy():
    L, ga, th0 = mpmath.mpf(1.3), mpmath.mpf(9.81), mpmath.mpf(1.2)
    for th, mu2 in exact.pendulum_exact(th0, TIMES, L, ga):
        thd = mu2 / L**2
        assert abs(L * thd**2 / 2 - ga * mpmath.cos(th) + ga * mpmath.cos(th0)) < 1e-35


@pytest.mark.parametrize(
    "model, params, x0, sol",
    [
        (
            "oscillator",
            {"d": 0.0, "m": 1.5},
            (0.7, 0, 0, 0),
            lambda: exact.oscillator_exact(0.7, TIMES, 2.0, 1.5),
        ),
        (
            "pendulum",
            {"L": 1.3},
            (1.3 * mpmath.sin(0.5), -1.3 * mpmath.cos(0.5), 0, 0),
            lambda: exact.pendulum_exact(0.5, TIMES, 1.3),
        ),
    ],
)
def test_taylor_reference_agrees_with_the_exact_solution(model, params, x0, sol):
    ref = exact.manifold_reference(model, params, [float(v) for v in x0], TIMES[:3], dps=30)
    for r, s in zip(ref, sol()):
        # the pendulum's x0 enters as doubles: theta0 = 0.5 to about 1e-16
        assert max(abs(a - b) for a, b in zip(r, s)) < (1e-25 if model == "oscillator" else 1e-14)
