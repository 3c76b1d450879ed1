# SPDX-License-Identifier: GPL-3.0-or-later
"""Solutions of the constrained motion (xi = 0) in mu coordinates, in multiple precision.

  oscillator_exact   d = 0, from rest at X = A: X = A cn(A sqrt(k/m) t | 1/2)
                     (y = cn(u | 1/2) solves y'' = -y^3), mu = (X, Xdot)
  pendulum_exact     from rest at theta0: sin(theta/2) = s sn(K(s) - sqrt(ga/L) t; s),
                     s = sin(theta0/2) (parameter s^2), theta' = -2 s sqrt(ga/L) cn,
                     mu = (theta, L^2 theta')
  manifold_reference any model and parameters: mu' = q0(mu) by mpmath's Taylor-series ODE
                     solver (odefun) at dps digits, from the mu part of Phi(x0)

Each returns one mu (a list of mpf) per time in `times`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import mpmath

from . import arith, models
from .arith import Num, Vector


def context(dps: int) -> Any:  # an mpmath context
    ctx = mpmath.MPContext()
    ctx.dps = dps
    return ctx


def oscillator_exact(
    A: Num, times: Iterable[Num], k: Num = 2.0, m: Num = 1.0, dps: int = 40
) -> list[Vector]:
    """mu(t) = (X, Xdot) of m Xdd = -k X^3 from rest at X = A."""
    ctx = context(dps)
    A, k, m = ctx.mpf(A), ctx.mpf(k), ctx.mpf(m)
    omega = A * ctx.sqrt(k / m)
    half = ctx.mpf(1) / 2
    out = []
    for t in times:
        u = omega * ctx.mpf(t)
        sn, cn, dn = (ctx.ellipfun(f, u, m=half) for f in ("sn", "cn", "dn"))
        out.append([A * cn, -A * omega * sn * dn])
    return out


def pendulum_exact(
    theta0: Num, times: Iterable[Num], L: Num = 1.0, ga: Num = 9.81, dps: int = 40
) -> list[Vector]:
    """mu(t) = (theta, L^2 theta') of theta'' = -(ga/L) sin theta from rest at theta0."""
    ctx = context(dps)
    L, ga = ctx.mpf(L), ctx.mpf(ga)
    s = ctx.sin(ctx.mpf(theta0) / 2)
    par = s * s
    K, omega = ctx.ellipk(par), ctx.sqrt(ga / L)
    out = []
    for t in times:
        u = K - omega * ctx.mpf(t)
        sn, cn = ctx.ellipfun("sn", u, m=par), ctx.ellipfun("cn", u, m=par)
        out.append([2 * ctx.asin(s * sn), -2 * s * omega * cn * L * L])
    return out


def manifold_reference(
    model: str,
    params: models.Params | None = None,
    x0: Sequence[float] | None = None,
    times: Iterable[Num] = (),
    dps: int = 30,
) -> list[Vector]:
    """mu(t) of mu' = q0(mu) from mu0 = the mu part of Phi(x0) (xi is dropped: the start is
    projected onto the manifold along xi); times must be >= 0."""
    a = arith.MP(dps)
    mdl = models.make(model, a, params)
    x = mdl.default_x0() if x0 is None else x0
    mu0 = mdl.to_z([a.num(float(v)) for v in x])[1]
    solution = a.ctx.odefun(lambda t, mu: mdl.q0(mu), 0, mu0)
    return [list(solution(a.num(t))) for t in times]
