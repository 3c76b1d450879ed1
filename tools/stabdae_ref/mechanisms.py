# SPDX-License-Identifier: GPL-3.0-or-later
"""References for the mechanical front-end's examples (point masses in the plane, the multibody
convention q' = v, M v' = F - G^T lambda, c(q) = 0, gravity -ga along y), in mpmath. Each
returns one state per time in `times`: [q..., v...] in the examples' Cartesian coordinates.

  pendulum_exact       the Cartesian pendulum (c = (x^2 + y^2 - L^2)/2) from rest at theta0
                       from the bottom: exact.pendulum_exact's Jacobi sn mapped to (x, y, vx, vy)
  pendulum_lambda      its multiplier in closed form, m (|v|^2 - ga y) / |q|^2
  double_pendulum      two point masses, |p1| = L1, |p2 - p1| = L2: the Lagrangian ODE in the
                       angles from the downward vertical, by mpmath's Taylor-series solver
  bars                 any chain of bars c_j = (|p_a - p_b|^2 - l_j^2)/2 between masses or
                       fixed points: the index-1 ODE v' = M^-1 (F - G^T lambda) with
                       (G M^-1 G^T) lambda = G M^-1 F + gamma, gamma_j = |v_a - v_b|^2, by the
                       same solver (the four-bar, and a second reference for the others)
  energy               m |v|^2 / 2 + m ga y summed over the masses
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any, Tuple, Union

import numpy as np
from numpy.typing import NDArray

from . import exact
from .arith import Matrix, Num, Vector

# A bar's end: a mass index or a fixed point (x, y); a link: (end a, end b, length)
End = Union[int, Tuple[float, float]]
Link = Tuple[End, End, Num]
# What pendulum_lambda, constraint and energy take: numbers (floats or mpf), or arrays of one
# value per time (a run's columns), computed elementwise
Coords = Union[Sequence[Num], NDArray[np.float64]]
Value = Union[Num, NDArray[np.float64]]


def pendulum_exact(
    theta0: Num,
    times: Iterable[Num],
    L: float = 1.0,
    m: float = 1.0,
    ga: float = 9.81,
    dps: int = 30,
) -> list[Vector]:
    """(x, y, vx, vy) = L (sin th, -cos th, th' cos th, th' sin th) of the exact theta(t)."""
    del m  # the motion does not depend on the mass
    ctx = exact.context(dps)
    out = []
    for theta, p in exact.pendulum_exact(theta0, times, L, ga, dps):
        Lm = ctx.mpf(L)
        w = p / (Lm * Lm)
        s, c = ctx.sin(theta), ctx.cos(theta)
        out.append([Lm * s, -Lm * c, Lm * w * c, Lm * w * s])
    return out


def pendulum_lambda(state: Coords, L: float = 1.0, m: float = 1.0, ga: float = 9.81) -> Value:
    """lambda of m v' = (0, -m ga) - q lambda with c'' = 0: q.v' = -|v|^2 gives
    lambda = (q.F + m |v|^2) / |q|^2 (|q|^2 = L^2 on the circle; off it, the library's
    (G M^-1 G^T)^-1 (G M^-1 F + gamma) is the same)."""
    del L  # the formula holds off the circle too
    x, y, vx, vy = state
    return m * (vx * vx + vy * vy - ga * y) / (x * x + y * y)


def double_pendulum(
    theta0: Sequence[float],
    omega0: Sequence[float],
    times: Iterable[float],
    L1: float = 1.0,
    L2: float = 1.0,
    m1: float = 1.0,
    m2: float = 1.0,
    ga: float = 9.81,
    dps: int = 25,
) -> list[Vector]:
    """The double pendulum in angles a1, a2 (Lagrange's equations, e.g. Goldstein):
    (m1 + m2) L1 a1'' + m2 L2 cos(a1 - a2) a2'' = -m2 L2 sin(a1 - a2) a2'^2 - (m1 + m2) ga sin a1,
    L1 cos(a1 - a2) a1'' + L2 a2'' = L1 sin(a1 - a2) a1'^2 - ga sin a2; mapped to
    p1 = L1 (sin a1, -cos a1), p2 = p1 + L2 (sin a2, -cos a2) and their velocities."""
    ctx = exact.context(dps)
    L1, L2, m1, m2, ga = (ctx.mpf(float(v)) for v in (L1, L2, m1, m2, ga))

    def rhs(t: Num, y: Vector) -> Vector:
        a1, a2, w1, w2 = y
        s, c = ctx.sin(a1 - a2), ctx.cos(a1 - a2)
        A11, A12, A21, A22 = (m1 + m2) * L1, m2 * L2 * c, L1 * c, L2
        b1 = -m2 * L2 * s * w2 * w2 - (m1 + m2) * ga * ctx.sin(a1)
        b2 = L1 * s * w1 * w1 - ga * ctx.sin(a2)
        det = A11 * A22 - A12 * A21
        return [w1, w2, (b1 * A22 - A12 * b2) / det, (A11 * b2 - A21 * b1) / det]

    y0 = [ctx.mpf(float(v)) for v in (theta0[0], theta0[1], omega0[0], omega0[1])]
    solution = ctx.odefun(rhs, 0, y0)
    out = []
    for t in times:
        a1, a2, w1, w2 = solution(ctx.mpf(float(t)))
        x1, y1 = L1 * ctx.sin(a1), -L1 * ctx.cos(a1)
        u1, z1 = L1 * w1 * ctx.cos(a1), L1 * w1 * ctx.sin(a1)
        x2, y2 = x1 + L2 * ctx.sin(a2), y1 - L2 * ctx.cos(a2)
        u2, z2 = u1 + L2 * w2 * ctx.cos(a2), z1 + L2 * w2 * ctx.sin(a2)
        out.append([x1, y1, x2, y2, u1, z1, u2, z2])
    return out


def _point(ctx: Any, end: End, q: Vector, v: Vector) -> tuple[tuple[Num, Num], tuple[Num, Num]]:
    """A bar's end: a mass index (its position and velocity) or a fixed point (x, y)."""
    if isinstance(end, int):
        return (q[2 * end], q[2 * end + 1]), (v[2 * end], v[2 * end + 1])
    return (ctx.mpf(float(end[0])), ctx.mpf(float(end[1]))), (ctx.mpf(0), ctx.mpf(0))


def _bar_rows(
    ctx: Any, bars: Sequence[Link], n_q: int, q: Vector, v: Vector
) -> tuple[Matrix, Vector]:
    """G (rows of dc_j/dq) and gamma_j = |v_a - v_b|^2 of c_j = (|p_a - p_b|^2 - l_j^2)/2."""
    G, gamma = [], []
    for a, b, _ in bars:
        (pa, va), (pb, vb) = _point(ctx, a, q, v), _point(ctx, b, q, v)
        d = (pa[0] - pb[0], pa[1] - pb[1])
        row = [ctx.mpf(0)] * n_q
        for end, sign in ((a, 1), (b, -1)):
            if isinstance(end, int):
                row[2 * end] += sign * d[0]
                row[2 * end + 1] += sign * d[1]
        G.append(row)
        gamma.append((va[0] - vb[0]) ** 2 + (va[1] - vb[1]) ** 2)
    return G, gamma


def bars(
    masses: Sequence[float],
    links: Sequence[Link],
    q0: Sequence[Num],
    v0: Sequence[Num],
    times: Iterable[float],
    ga: float = 9.81,
    dps: int = 25,
) -> list[Vector]:
    """Point masses `masses` (mass k at q[2k], q[2k+1]) joined by links (a, b, length), a and
    b mass indices or fixed points (x, y); gravity -ga along y. Integrates the index-1 ODE from
    (q0, v0), which must satisfy c = 0 and G v = 0 (then the solution stays on them)."""
    ctx = exact.context(dps)
    n_q = 2 * len(masses)
    mass = [ctx.mpf(float(masses[k // 2])) for k in range(n_q)]
    ga = ctx.mpf(float(ga))

    def rhs(t: Num, y: Vector) -> Vector:
        q, v = y[:n_q], y[n_q:]
        G, gamma = _bar_rows(ctx, links, n_q, q, v)
        F = [-mass[k] * ga if k % 2 else ctx.mpf(0) for k in range(n_q)]
        MinvF = [F[k] / mass[k] for k in range(n_q)]
        A = ctx.matrix([[sum(Gi[k] * Gj[k] / mass[k] for k in range(n_q)) for Gj in G] for Gi in G])
        rhs_l = ctx.matrix(
            [sum(Gi[k] * MinvF[k] for k in range(n_q)) + g for Gi, g in zip(G, gamma)]
        )
        lam = ctx.lu_solve(A, rhs_l)
        acc = [(F[k] - sum(G[j][k] * lam[j] for j in range(len(G)))) / mass[k] for k in range(n_q)]
        return list(v) + acc

    y0 = [ctx.mpf(x) for x in list(q0) + list(v0)]  # floats exactly, mpf kept
    solution = ctx.odefun(rhs, 0, y0)
    return [list(solution(ctx.mpf(float(t)))) for t in times]


def constraint(links: Sequence[Link], q: Coords) -> list[Value]:
    """c_j = (|p_a - p_b|^2 - l_j^2)/2 at q (floats or mpf)."""
    out = []
    for a, b, length in links:
        pa = (q[2 * a], q[2 * a + 1]) if isinstance(a, int) else a
        pb = (q[2 * b], q[2 * b + 1]) if isinstance(b, int) else b
        out.append(((pa[0] - pb[0]) ** 2 + (pa[1] - pb[1]) ** 2 - length**2) / 2)
    return out


def energy(masses: Sequence[float], q: Coords, v: Coords, ga: float = 9.81) -> Value:
    """sum_k m_k |v_k|^2 / 2 + m_k ga y_k."""
    return sum(
        m * ((v[2 * k] ** 2 + v[2 * k + 1] ** 2) / 2 + ga * q[2 * k + 1])
        for k, m in enumerate(masses)
    )
