# SPDX-License-Identifier: GPL-3.0-or-later
"""One step and short runs against the formulas of the paper: the contraction factors of
schemes 11 and 15 (eq. 6, 11, 15), Theorems 3 and 4, the baselines' exact solutions, Newton's
residual, and Gonzalez's discrete gradient."""

import math

import pytest

from stabdae_ref import StepFailure, arith, maps, models, simulate, stepper

DELTA, EPS = 2.0, 1.0


def osc_gains(xi1, mu1, k=2.0, d=0.03, m=1.0):
    """k_1, k_2 of the oscillator (corrected Q, from eq. 22)."""
    c = (k * (3 * mu1**2 - 3 * mu1 * xi1 + xi1**2) + d) / m
    return -(DELTA**2 / 2) * (1 + c**2) - EPS, -(DELTA**2) - EPS


def pend_gains(xi1, mu1, mu2, L=1.0, ga=9.81):
    """k_1, k_2 of the pendulum: q_1 = q - q0 of the radial coordinates, q_2 = 0."""
    r2 = L**2 + 2 * xi1
    q1 = (-2 * mu2 / (L**2 * r2), -2 * ga * math.sin(mu1) / (L + math.sqrt(r2)))
    return -(DELTA**2 / 2) * (q1[0] ** 2 + q1[1] ** 2) - EPS, -EPS


def xi_rows(res):
    return [(r[0], r[5], r[6], r[7], r[8]) for r in res.rows]  # t, xi1, xi2, mu1, mu2


@pytest.mark.parametrize("scheme", [11, 15])
@pytest.mark.parametrize(
    "model, gains, z0",
    [
        ("oscillator", lambda xi, mu: osc_gains(xi[0], mu[0]), ([0.4, -0.3], [0.6, 0.2])),
        ("pendulum", lambda xi, mu: pend_gains(xi[0], mu[0], mu[1]), ([0.2, 0.1], [0.7, 0.4])),
    ],
)
def test_each_step_scales_xi_by_the_scheme_factor(model, gains, z0, scheme):
    """xi_i+ = xi_i / (1 - T k_i) (eq. 15) or (1 + T k_i) xi_i (eq. 11), k_i at (xi, mu)."""
    T = 1e-3
    res = simulate(model, {}, None, T, 50, scheme, "dgrad", z0=z0)
    rows = xi_rows(res)
    for (_, x1, x2, m1, m2), (_, y1, y2, _, _) in zip(rows, rows[1:]):
        k = gains((x1, x2), (m1, m2))
        factor = [1 / (1 - T * ki) if scheme == 15 else 1 + T * ki for ki in k]
        assert y1 == pytest.approx(factor[0] * x1, rel=1e-14)
        assert y2 == pytest.approx(factor[1] * x2, rel=1e-14)


def test_scheme15_factor_exact_in_mpmath():
    ctx = arith.MP(50).ctx
    T = ctx.mpf(1e-3)
    res = simulate(
        "oscillator",
        {},
        None,
        1e-3,
        3,
        15,
        "midpoint",
        arithmetic="mpmath",
        dps=50,
        z0=(["0.4", "-0.3"], ["0.6", "0.2"]),
    )
    rows = xi_rows(res)
    for (_, x1, x2, m1, m2), (_, y1, y2, _, _) in zip(rows, rows[1:]):
        c = 2 * (3 * m1**2 - 3 * m1 * x1 + x1**2) + ctx.mpf(0.03)
        k1, k2 = -2 * (1 + c**2) - 1, ctx.mpf(-5)
        assert abs(y1 - x1 / (1 - T * k1)) <= ctx.mpf(10) ** -45 * abs(x1)
        assert abs(y2 - x2 / (1 - T * k2)) <= ctx.mpf(10) ** -45 * abs(x2)


def test_theorem4_scheme15_contracts_for_any_T_theorem3_bounds_scheme11():
    """k_2 = -(delta^2 + eps) = -5 is constant: xi_2 after n steps is exactly
    xi_2(0) / (1 + 5 T)^n (scheme 15, any T) or (1 - 5 T)^n xi_2(0) (scheme 11, which
    contracts only for T < 2/5, eq. 14). k = d = 0 keeps mu's Euler steps bounded."""
    z0, free = ([0.0, 0.3], [0.2, 0.0]), {"k": 0.0, "d": 0.0}
    for T in (0.39, 0.41, 3.0):
        n = 20
        r15 = simulate("oscillator", free, None, T, n, 15, "euler", z0=z0).column("xi2")
        assert r15[-1] == pytest.approx(0.3 / (1 + 5 * T) ** n, rel=1e-13)
    kept = simulate("oscillator", free, None, 0.39, 20, 11, "euler", z0=z0).column("xi2")[-1]
    assert kept == pytest.approx(0.3 * (1 - 5 * 0.39) ** 20, rel=1e-13) and abs(kept) < 0.3
    grown = simulate("oscillator", free, None, 0.41, 20, 11, "euler", z0=z0).column("xi2")[-1]
    assert grown == pytest.approx(0.3 * (1 - 5 * 0.41) ** 20, rel=1e-13) and abs(grown) > 0.3


@pytest.mark.parametrize("scheme", [11, 15])
@pytest.mark.parametrize("arithmetic, tol", [("float64", 1e-12), ("mpmath", 1e-30)])
def test_none_drifts_linearly(scheme, arithmetic, tol):
    """Index reduction: xi_1(t) = xi_1(0) + t xi_2(0), xi_2 constant (paper Section II)."""
    T, n = 1e-3, 300 if arithmetic == "mpmath" else 1000
    res = simulate(
        "oscillator",
        {},
        None,
        T,
        n,
        scheme,
        "euler",
        "none",
        arithmetic,
        z0=([0.3, -0.2], [0.5, 0.1]),
    )
    ctx = arith.make(arithmetic)
    for t, x1, x2, _, _ in xi_rows(res):
        exact = ctx.num(0.3) + t * ctx.num(-0.2)
        assert abs(x1 - exact) <= tol * abs(exact)
        assert x2 == ctx.num(-0.2)
    assert float(res.column("xi1")[-1]) == pytest.approx(0.3 - 0.2 * n * T, rel=1e-12)


@pytest.mark.parametrize("scheme", [11, 15])
def test_baumgarte_converges_at_order_one(scheme):
    """alpha = (1, 2): xi'' = -2 xi' - xi, xi_1(t) = (xi_1(0) + (xi_2(0) + xi_1(0)) t) e^-t."""
    x1, x2 = 0.3, -0.1
    exact = (x1 + (x2 + x1) * 1.0) * math.exp(-1.0)
    errs = []
    for n in (100, 200, 400):
        res = simulate(
            "pendulum",
            {},
            None,
            1.0 / n,
            n,
            scheme,
            "euler",
            "baumgarte",
            z0=([x1, x2], [0.5, 0.0]),
        )
        errs.append(abs(res.column("xi1")[-1] - exact))
    for e1, e2 in zip(errs, errs[1:]):
        assert math.log2(e1 / e2) == pytest.approx(1.0, abs=0.05)


def test_newton_solves_the_mu_equation_in_mpmath():
    """mu+ = mu + T (q0((mu + mu+)/2) + Q xi) to the residual 1e-30 (q0, Q written out here)."""
    T = 1e-2
    res = simulate(
        "oscillator",
        {"d": 0.03},
        None,
        T,
        1,
        15,
        "midpoint",
        arithmetic="mpmath",
        z0=(["0.2", "0.1"], ["0.6", "0.3"]),
    )
    (_, x1, x2, m1, m2), (_, _, _, n1, n2) = xi_rows(res)
    c = 2 * (3 * m1**2 - 3 * m1 * x1 + x1**2) + 0.03
    a1, a2 = (m1 + n1) / 2, (m2 + n2) / 2
    R = (n1 - m1 - T * (a2 - x1 + x2), n2 - m2 - T * (-2 * a1**3 - 0.03 * a2 + c * x1 + x2))
    assert max(abs(r) for r in R) <= 1e-30
    assert res.rows[1][-1] >= 1 and res.rows[0][-1] == 0


def test_explicit_map_needs_no_newton():
    assert set(simulate("oscillator", {}, None, 1e-3, 5, 15, "euler").column("newton_iters")) == {0}


@pytest.mark.parametrize("name", ["pendulum", "chain"])
def test_discrete_gradient_identity(name):
    """gradbar H(x, y) . (y - x) = H(y) - H(x) (Gonzalez); grad H(x) when y = x."""
    a = arith.MP(40)
    mdl = models.make(name, a, {"N": 3} if name == "chain" else {})
    n = mdl.n_mu
    x = [a.num(0.3 + 0.1 * i) for i in range(n)]
    y = [a.num(-0.2 + 0.05 * i * i) for i in range(n)]
    gbar, _ = maps.gonzalez(mdl, x, y)
    lhs = sum(g * (v - u) for g, u, v in zip(gbar, x, y))
    assert abs(lhs - (mdl.H(y) - mdl.H(x))) <= a.num(10) ** -38
    assert maps.gonzalez(mdl, x, x)[0] == mdl.grad_H(x)


def test_discrete_gradient_falls_back_below_the_threshold():
    """|v|^2 <= eps (1 + |m|^2): gradbar H = grad H(m), no division by a tiny |v|^2."""
    a = arith.Float64()
    mdl = models.make("oscillator", a, {})
    x = [0.5, 0.25]
    y = [0.5 + 2**-40, 0.25]
    m = [(u + v) / 2 for u, v in zip(x, y)]
    assert maps.gonzalez(mdl, x, y)[0] == mdl.grad_H(m)
    far = [0.5 + 1e-6, 0.25]
    assert maps.gonzalez(mdl, x, far)[0] != mdl.grad_H([(u + v) / 2 for u, v in zip(x, far)])


def test_dg_jacobian_is_the_derivative():
    """Newton's d gradbar H / dy against central differences (pendulum, mpmath)."""
    a = arith.MP(40)
    mdl = models.make("pendulum", a, {})
    x, y = [a.num(0.3), a.num(-0.4)], [a.num(0.35), a.num(-0.1)]
    J = maps.gonzalez(mdl, x, y)[1]
    h = a.num(10) ** -15
    for j in range(2):
        up = [v + (h if i == j else 0) for i, v in enumerate(y)]
        dn = [v - (h if i == j else 0) for i, v in enumerate(y)]
        fd = [
            (p - q) / (2 * h)
            for p, q in zip(maps.gonzalez(mdl, x, up)[0], maps.gonzalez(mdl, x, dn)[0])
        ]
        assert max(abs(f - row[j]) for f, row in zip(fd, J)) <= a.num(10) ** -20


def test_failed_step_keeps_the_rows_before():
    with pytest.raises(StepFailure) as info:
        simulate("oscillator", {}, None, 0.5, 100, 11, "euler")
    assert info.value.step > 1
    assert len(info.value.result.rows) == info.value.step
    assert all(math.isfinite(v) for row in info.value.result.rows for v in row[5:9])


def test_pendulum_step_outside_the_radius_fails():
    with pytest.raises(StepFailure, match="radius"):
        simulate("pendulum", {}, (0.1, -0.5, 0, 0.3), 0.5, 100, 11, "euler")


def test_bad_arguments():
    for kwargs in (
        {"scheme": 12},
        {"map": "rk5"},
        {"stabilizer": "x"},
        {"T": -1.0},
        {"nsteps": 0},
        {"params": {"L": 2}},
        {"params": {"m": 0}},
    ):
        args = dict(model="oscillator", T=1e-3, nsteps=10)
        args.update(kwargs)
        with pytest.raises(ValueError):
            simulate(**args)
    with pytest.raises(ValueError):
        stepper.Stepper(models.make("pendulum", arith.Float64()), map="user")
