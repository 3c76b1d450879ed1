# SPDX-License-Identifier: GPL-3.0-or-later
"""The models against their DAEs, computed here from x (not from the model code):
q0(mu) + Q(xi, mu) xi must be mu' of the DAE, S grad H must be q0, the derivatives must be
derivatives, and the oscillator's gains must give the paper's eq. 24."""

import random

import pytest

from stabdae_ref import arith, models, stepper

MP = arith.MP(40)
TOL = MP.num(10) ** -35


def rand_points(count, n, seed, scale=1.0):
    rng = random.Random(seed)
    return [[MP.num(rng.uniform(-scale, scale)) for _ in range(n)] for _ in range(count)]


def close(u, v, tol=TOL):
    return max(abs(a - b) for a, b in zip(u, v)) <= tol * (1 + max(abs(b) for b in v))


def q_total(mdl, xi, mu):
    Qm = mdl.Q(xi, mu)
    return [q + sum(Qm[r][i] * xi[i] for i in range(len(xi))) for r, q in enumerate(mdl.q0(mu))]


@pytest.mark.parametrize("name", ["oscillator", "pendulum", "chain"])
def test_phi_round_trip(name):
    mdl = models.make(name, MP, {"N": 3} if name == "chain" else {})
    n = 12 if name == "chain" else 4
    for x in rand_points(5, n, 1, 0.8):
        if name == "pendulum":
            x[1] -= 1  # keep away from the pivot
        assert close(mdl.to_x(*mdl.to_z(x)), x)


def test_oscillator_q_is_mu_dot_of_the_dae():
    k, d, m = 2, 0.03, 1.5
    mdl = models.make("oscillator", MP, {"k": k, "d": d, "m": m})
    for X, Y, Xd, Yd in rand_points(10, 4, 2):
        xdd = (-k * X**3 - d * Xd) / m
        mu_dot = [Xd + Yd, Yd + xdd]  # mu = (X + Y, Y + Xdot), L_g mu = 0
        assert close(q_total(mdl, *mdl.to_z([X, Y, Xd, Yd])), mu_dot)


def test_printed_q_differs_off_the_manifold_only():
    """Erratum 1: the printed Q is not q - q0, but on the manifold xi = 0 nothing changes."""
    mdl = models.make("oscillator", MP, {"q": "paper"})
    good = models.make("oscillator", MP, {})
    xi, mu = [MP.num(0.3), MP.num(0.1)], [MP.num(0.5), MP.num(-0.2)]
    assert abs(q_total(mdl, xi, mu)[1] - q_total(good, xi, mu)[1]) > 0.1
    zero = [MP.num(0), MP.num(0)]
    assert q_total(mdl, zero, mu) == q_total(good, zero, mu)


def test_pendulum_q_is_mu_dot_of_the_dae():
    L, m, ga = 1.3, 0.7, 9.81
    mdl = models.make("pendulum", MP, {"L": L, "m": m, "ga": ga})
    for X, Y, Xd, Yd, lam in rand_points(10, 5, 3):
        Y -= 1
        Xdd, Ydd = -lam * X / m, -ga - lam * Y / m
        mu_dot = [(X * Yd - Y * Xd) / (X * X + Y * Y), X * Ydd - Y * Xdd]
        assert close(q_total(mdl, *mdl.to_z([X, Y, Xd, Yd])), mu_dot)


def chain_forces(X, Xd, k, d, kc):
    N = len(X)
    F = []
    for i in range(N):
        f = -k * X[i] ** 3 - d * Xd[i]
        if i + 1 < N:
            f += kc * (X[i + 1] - X[i]) ** 3
        if i > 0:
            f -= kc * (X[i] - X[i - 1]) ** 3
        F.append(f)
    return F


def test_chain_q_is_mu_dot_of_the_dae():
    k, d, m, kc, N = 2, 0.1, 1.2, 0.7, 4
    mdl = models.make("chain", MP, {"k": k, "d": d, "m": m, "kc": kc, "N": N})
    for x in rand_points(5, 4 * N, 4):
        X, Xd, Yd = x[0::4], x[2::4], x[3::4]
        F = chain_forces(X, Xd, k, d, kc)
        mu_dot = [v for i in range(N) for v in (Xd[i] + Yd[i], Yd[i] + F[i] / m)]
        assert close(q_total(mdl, *mdl.to_z(x)), mu_dot)


@pytest.mark.parametrize("name", ["oscillator", "pendulum", "chain"])
def test_q0_is_S_grad_H_and_derivatives(name):
    params = {"N": 3, "d": 0.2} if name == "chain" else ({"d": 0.2} if name == "oscillator" else {})
    mdl = models.make(name, MP, params)
    h = MP.num(10) ** -15
    for mu in rand_points(3, mdl.n_mu, 5):
        S, g = mdl.S(mu), mdl.grad_H(mu)
        assert close([sum(a * b for a, b in zip(row, g)) for row in S], mdl.q0(mu))
        for j in range(mdl.n_mu):
            up = [v + (h if i == j else 0) for i, v in enumerate(mu)]
            dn = [v - (h if i == j else 0) for i, v in enumerate(mu)]

            def fd(f, up=up, dn=dn):
                return [(a - b) / (2 * h) for a, b in zip(f(up), f(dn))]

            tol = MP.num(10) ** -20
            assert close(fd(lambda z: [mdl.H(z)]), [g[j]], tol)
            assert close(fd(mdl.grad_H), [row[j] for row in mdl.hess_H(mu)], tol)
            assert close(fd(mdl.q0), [row[j] for row in mdl.q0_jac(mu)], tol)


@pytest.mark.parametrize(
    "q, expected, where",
    [
        ("paper", 188.9, (-0.7, 0.9)),
        # corrected c = k (3 mu1^2 - 3 mu1 xi1 + xi1^2) + d = 9.65: 2 (1 + 9.65^2) + 1
        ("corrected", 2 * (1 + 9.65**2) + 1, (0.7, -0.9)),
    ],
)
def test_eq24_bound_over_B(q, expected, where):
    """max_i sup_B (-k_i) of eq. 24 (delta 2, eps 1, k 2, d 0.03) on a grid of B."""
    a = arith.Float64()
    mdl = models.make("oscillator", a, {"q": q})
    st = stepper.Stepper(mdl, delta=2, eps=1)
    best = max(
        (-min(st.gains(mdl.Q([x1, 0.0], [m1, 0.0]))), x1, m1)
        for x1 in [i / 20 - 0.7 for i in range(29)]
        for m1 in [j / 20 - 0.9 for j in range(37)]
    )
    assert best[0] == pytest.approx(expected, abs=0.05)
    assert best[1:] == pytest.approx(where)
