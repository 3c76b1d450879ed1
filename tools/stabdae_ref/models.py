# SPDX-License-Identifier: GPL-3.0-or-later
"""The three models of the project in the stabilized normal form (paper eq. 5).

Each model gives, in one arithmetic (see arith.py):
  to_z(x) -> (xi, mu)       the coordinates Phi(x) (eq. 2), x = (X, Y, Xdot, Ydot) per mass
  to_x(xi, mu) -> x         the inverse map
  q0(mu), q0_jac(mu)        the constrained motion mu' = q0(mu) (eq. 9) and dq0/dmu
  Q(xi, mu)                 n_mu x n_xi, column i = q_i, with q0 + Q xi = mu' of the DAE
  H, grad_H, hess_H, S      q0 = S grad H (for the discrete-gradient map); S is constant here
  row(xi, mu)               the physical CSV columns between t and newton_iters
  user_map                  the model's own map phi_T(mu, mu+) with its Jacobian d phi / d mu+
                            (the map 'user'), or None

The sign convention for the multiplier is Ydd = -ga - lambda/m (oscillator, chain) and
Xdd = -lambda X/m, Ydd = -ga - lambda Y/m (pendulum).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, Literal, Type, Union

from .arith import Arith, Matrix, Num, Vector

# Parameters by name: numbers, and the oscillator's q a string (each model's constructor checks)
Params = Mapping[str, Any]


def cube(x: Num) -> Num:
    return x * x * x


def quartic(x: Num) -> Num:
    """x^4 by products: overflows to inf like C instead of raising."""
    x2 = x * x
    return x2 * x2


def checked(a: Arith, name: str, value: float, positive: bool = False) -> Num:
    """value rounded to a double (the number the C library sees), then as a number of
    arithmetic a; it must be finite (and > 0 when asked)."""
    v = float(value)
    if not math.isfinite(v) or (positive and not v > 0):
        raise ValueError("%s must be %s, got %r" % (name, "> 0" if positive else "finite", value))
    return a.num(v)


class Oscillator:
    """Paper Section IV with a mass m: Xdd = (-k X^3 - d Xdot)/m, Ydd = -ga - lambda/m,
    h = Y. Coordinates eq. 21: xi = (Y, Ydot), mu = (X + Y, Y + Xdot).

    q = 'corrected' uses Q's entry c = (k (3 mu1^2 - 3 mu1 xi1 + xi1^2) + d)/m derived from
    eq. 22; q = 'paper' the entry printed in the paper, (k (3 mu1 xi1 - 3 mu1^2 - xi1^2)
    + d xi1)/m, which does not give mu' of the DAE off the manifold (an erratum) but
    reproduces eq. 24.
    """

    name: Literal["oscillator"] = "oscillator"
    header = ("t", "X", "Y", "Xdot", "Ydot", "xi1", "xi2", "mu1", "mu2", "E", "W", "newton_iters")
    defaults = {"k": 2.0, "d": 0.03, "m": 1.0, "ga": 9.81, "q": "corrected"}
    n_xi, n_mu, rel_degree = 2, 2, (2,)

    def __init__(
        self, a: Arith, k: float, d: float, m: float, ga: float, q: str = "corrected"
    ) -> None:
        if q not in ("corrected", "paper"):
            raise ValueError("q must be 'corrected' or 'paper', got %r" % (q,))
        self.a = a
        self.k, self.d, self.ga = checked(a, "k", k), checked(a, "d", d), checked(a, "ga", ga)
        self.m = checked(a, "m", m, positive=True)
        self.q = q
        self.user_map = (self.phi_paper, self.phi_paper_jac)  # the paper's Section IV map

    def default_x0(self) -> list[float]:
        return [0.1, 0.6, 0.0, 0.0]

    def to_z(self, x: Vector) -> tuple[Vector, Vector]:
        X, Y, Xd, Yd = x
        return [Y, Yd], [X + Y, Y + Xd]  # eq. 21

    def to_x(self, xi: Vector, mu: Vector) -> Vector:
        return [mu[0] - xi[0], xi[0], mu[1] - xi[0], xi[1]]

    def admissible(self, xi: Vector, mu: Vector) -> None:
        """Every (xi, mu) is a state of the oscillator."""

    def q0(self, mu: Vector) -> Vector:
        return [mu[1], (-self.k * cube(mu[0]) - self.d * mu[1]) / self.m]

    def q0_jac(self, mu: Vector) -> Matrix:
        return [[0, 1], [-3 * self.k * mu[0] * mu[0] / self.m, -self.d / self.m]]

    def c(self, xi1: Num, mu1: Num) -> Num:
        """Q's entry (row mu2, column q_1)."""
        k, d, m = self.k, self.d, self.m
        if self.q == "corrected":  # from eq. 22
            return (k * (3 * mu1 * mu1 - 3 * mu1 * xi1 + xi1 * xi1) + d) / m
        return (k * (3 * mu1 * xi1 - 3 * mu1 * mu1 - xi1 * xi1) + d * xi1) / m  # as printed

    def Q(self, xi: Vector, mu: Vector) -> Matrix:
        return [[-1, 1], [self.c(xi[0], mu[0]), 1]]

    def H(self, mu: Vector) -> Num:
        """W(mu) = m mu2^2/2 + k mu1^4/4, the energy on the manifold."""
        return self.m * mu[1] * mu[1] / 2 + self.k * quartic(mu[0]) / 4

    def grad_H(self, mu: Vector) -> Vector:
        return [self.k * cube(mu[0]), self.m * mu[1]]

    def hess_H(self, mu: Vector) -> Matrix:
        return [[3 * self.k * mu[0] * mu[0], 0], [0, self.m]]

    def S(self, mu: Vector) -> Matrix:
        m = self.m
        return [[0, 1 / m], [-1 / m, -self.d / (m * m)]]

    def energy(self, x: Vector) -> Num:
        X, Y, Xd, Yd = x
        return self.m * (Xd * Xd + Yd * Yd) / 2 + self.k * quartic(X) / 4 + self.m * self.ga * Y

    def row(self, xi: Vector, mu: Vector) -> Vector:
        x = self.to_x(xi, mu)
        return x + [xi[0], xi[1], mu[0], mu[1], self.energy(x), self.H(mu)]

    def phi_paper(self, mu: Vector, mu_next: Vector) -> Vector:
        """The paper's Section IV map, second row divided by m (first order for d > 0)."""
        u, w = mu_next[0], mu[0]
        quartic = cube(u) + cube(w) + (u + w) * u * w  # (u^4 - w^4)/(u - w)
        return [(mu_next[1] + mu[1]) / 2, (-self.k * quartic / 4 - self.d * mu[1]) / self.m]

    def phi_paper_jac(self, mu: Vector, mu_next: Vector) -> Matrix:
        u, w = mu_next[0], mu[0]
        return [[0, self.a.num(0.5)], [-self.k * (3 * u * u + 2 * u * w + w * w) / (4 * self.m), 0]]


class Pendulum:
    """Planar pendulum of length L: h = (X^2 + Y^2 - L^2)/2, xi = (h, X Xdot + Y Ydot),
    mu = (theta = atan2(X, -Y), X Ydot - Y Xdot = r^2 theta')."""

    name: Literal["pendulum"] = "pendulum"
    header = ("t", "X", "Y", "Xdot", "Ydot", "xi1", "xi2", "mu1", "mu2", "E", "newton_iters")
    defaults = {"L": 1.0, "m": 1.0, "ga": 9.81}
    n_xi, n_mu, rel_degree = 2, 2, (2,)

    def __init__(self, a: Arith, L: float, m: float, ga: float) -> None:
        self.a = a
        self.L, self.m = checked(a, "L", L, positive=True), checked(a, "m", m, positive=True)
        self.ga = checked(a, "ga", ga)
        self.user_map = None

    def default_x0(self) -> list[float]:
        """At rest on the circle, 0.5 rad from the downward vertical (as doubles)."""
        L = float(self.L)
        return [L * math.sin(0.5), -L * math.cos(0.5), 0.0, 0.0]

    def radius2(self, xi1: Num) -> Num:
        """r^2 = L^2 + 2 xi1, which must stay positive."""
        r2 = self.L * self.L + 2 * xi1
        if not r2 > 0:
            raise ArithmeticError("pendulum: xi1 <= -L^2/2, the radius is not defined")
        return r2

    def to_z(self, x: Vector) -> tuple[Vector, Vector]:
        X, Y, Xd, Yd = x
        if X == 0 and Y == 0:
            raise ValueError("pendulum: x0 is at the pivot, the angle is not defined")
        xi = [(X * X + Y * Y - self.L * self.L) / 2, X * Xd + Y * Yd]
        return xi, [self.a.atan2(X, -Y), X * Yd - Y * Xd]

    def admissible(self, xi: Vector, mu: Vector) -> None:
        """Raises ArithmeticError when xi1 <= -L^2/2 (no radius)."""
        self.radius2(xi[0])

    def to_x(self, xi: Vector, mu: Vector) -> Vector:
        r = self.a.sqrt(self.radius2(xi[0]))
        s, c = self.a.sin(mu[0]), self.a.cos(mu[0])
        rdot, thetadot = xi[1] / r, mu[1] / (r * r)
        return [r * s, -r * c, rdot * s + r * c * thetadot, -rdot * c + r * s * thetadot]

    def q0(self, mu: Vector) -> Vector:
        return [mu[1] / (self.L * self.L), -self.ga * self.L * self.a.sin(mu[0])]

    def q0_jac(self, mu: Vector) -> Matrix:
        return [[0, 1 / (self.L * self.L)], [-self.ga * self.L * self.a.cos(mu[0]), 0]]

    def Q(self, xi: Vector, mu: Vector) -> Matrix:
        L, r2 = self.L, self.radius2(xi[0])
        return [
            [-2 * mu[1] / (L * L * r2), 0],
            [-2 * self.ga * self.a.sin(mu[0]) / (L + self.a.sqrt(r2)), 0],
        ]

    def H(self, mu: Vector) -> Num:
        L, m = self.L, self.m
        return m * mu[1] * mu[1] / (2 * L * L) - m * self.ga * L * self.a.cos(mu[0])

    def grad_H(self, mu: Vector) -> Vector:
        L, m = self.L, self.m
        return [m * self.ga * L * self.a.sin(mu[0]), m * mu[1] / (L * L)]

    def hess_H(self, mu: Vector) -> Matrix:
        L, m = self.L, self.m
        return [[m * self.ga * L * self.a.cos(mu[0]), 0], [0, m / (L * L)]]

    def S(self, mu: Vector) -> Matrix:
        return [[0, 1 / self.m], [-1 / self.m, 0]]

    def energy(self, x: Vector) -> Num:
        X, Y, Xd, Yd = x
        return self.m * (Xd * Xd + Yd * Yd) / 2 + self.m * self.ga * Y

    def row(self, xi: Vector, mu: Vector) -> Vector:
        x = self.to_x(xi, mu)
        return x + [xi[0], xi[1], mu[0], mu[1], self.energy(x)]


class Chain:
    """N masses on the floor, each with a cubic spring k X_i^3 to its anchor, damping d, and
    cubic couplings kc (X_{i+1} - X_i)^3 to its neighbours (free ends). Coordinates eq. 21 per
    mass, interleaved: xi = (Y_0, Ydot_0, Y_1, ...), mu = (X_0 + Y_0, Y_0 + Xdot_0, ...)."""

    name: Literal["chain"] = "chain"
    header = ("t", "max_abs_Y", "max_abs_Ydot", "E", "newton_iters")
    defaults = {"N": 5, "k": 2.0, "d": 0.03, "m": 1.0, "ga": 9.81, "kc": 1.0}

    def __init__(
        self, a: Arith, N: int, k: float, d: float, m: float, ga: float, kc: float
    ) -> None:
        if int(N) != N or N < 1:
            raise ValueError("N must be a positive integer, got %r" % (N,))
        self.a, self.N = a, int(N)
        self.k, self.d, self.ga = checked(a, "k", k), checked(a, "d", d), checked(a, "ga", ga)
        self.kc, self.m = checked(a, "kc", kc), checked(a, "m", m, positive=True)
        self.n_xi = self.n_mu = 2 * self.N
        self.rel_degree = (2,) * self.N
        self.user_map = None

    def default_x0(self) -> list[float]:
        """Every mass 0.6 above the floor at rest, X alternating +-0.1."""
        return [v for i in range(self.N) for v in (0.1 * (-1) ** i, 0.6, 0.0, 0.0)]

    def to_z(self, x: Vector) -> tuple[Vector, Vector]:
        if len(x) != 4 * self.N:
            raise ValueError("chain: x0 needs 4 N = %d values, got %d" % (4 * self.N, len(x)))
        xi, mu = [], []
        for i in range(self.N):
            X, Y, Xd, Yd = x[4 * i : 4 * i + 4]
            xi += [Y, Yd]
            mu += [X + Y, Y + Xd]  # eq. 21 per mass
        return xi, mu

    def admissible(self, xi: Vector, mu: Vector) -> None:
        """Every (xi, mu) is a state of the chain."""

    def to_x(self, xi: Vector, mu: Vector) -> Vector:
        x = []
        for i in range(self.N):
            Y, Yd = xi[2 * i], xi[2 * i + 1]
            x += [mu[2 * i] - Y, Y, mu[2 * i + 1] - Y, Yd]
        return x

    def forces(self, X: Vector, Xd: Vector) -> Vector:
        """F_i = -k X_i^3 - d Xdot_i + kc (X_{i+1} - X_i)^3 - kc (X_i - X_{i-1})^3."""
        F = [-self.k * cube(X[i]) - self.d * Xd[i] for i in range(self.N)]
        for i in range(self.N - 1):
            spring = self.kc * cube(X[i + 1] - X[i])
            F[i] += spring
            F[i + 1] -= spring
        return F

    def q0(self, mu: Vector) -> Vector:
        F = self.forces(mu[0::2], mu[1::2])
        out = []
        for i in range(self.N):
            out += [mu[2 * i + 1], F[i] / self.m]
        return out

    def stiffness(self, X: Vector) -> Matrix:
        """dF/dX (without damping): the negative Hessian of the potential, tridiagonal."""
        N, K = self.N, [[0] * self.N for _ in range(self.N)]
        for i in range(N):
            K[i][i] = -3 * self.k * X[i] * X[i]
        for i in range(N - 1):
            s = 3 * self.kc * (X[i + 1] - X[i]) * (X[i + 1] - X[i])
            K[i][i] -= s
            K[i + 1][i + 1] -= s
            K[i][i + 1] += s
            K[i + 1][i] += s
        return K

    def q0_jac(self, mu: Vector) -> Matrix:
        N, K = self.N, self.stiffness(mu[0::2])
        J = [[0] * (2 * N) for _ in range(2 * N)]
        for i in range(N):
            J[2 * i][2 * i + 1] = 1
            J[2 * i + 1][2 * i + 1] = -self.d / self.m
            for j in range(N):
                J[2 * i + 1][2 * j] = K[i][j] / self.m
        return J

    def Q(self, xi: Vector, mu: Vector) -> Matrix:
        """Q with q0 + Q xi = mu' of the DAE, from a^3 - b^3 = (a - b)(a^2 + ab + b^2):
        row (i,1) = -xi_{i,1} + xi_{i,2}; row (i,2) has columns (i-1,1), (i,1), (i+1,1), (i,2)."""
        N, k, d, kc, m = self.N, self.k, self.d, self.kc, self.m
        a, e = mu[0::2], xi[0::2]
        Qm = [[0] * (2 * N) for _ in range(2 * N)]
        for i in range(N):
            Qm[2 * i][2 * i], Qm[2 * i][2 * i + 1] = -1, 1
            Qm[2 * i + 1][2 * i + 1] = 1
            Qm[2 * i + 1][2 * i] = (k * (3 * a[i] * a[i] - 3 * a[i] * e[i] + e[i] * e[i]) + d) / m
        for i in range(N - 1):
            # the coupling between masses i and i+1: u = a_{i+1} - a_i, w = e_{i+1} - e_i
            u, w = a[i + 1] - a[i], e[i + 1] - e[i]
            p = kc * (3 * u * u - 3 * u * w + w * w) / m
            Qm[2 * i + 1][2 * i + 2] -= p
            Qm[2 * i + 1][2 * i] += p
            Qm[2 * i + 3][2 * i + 2] += p
            Qm[2 * i + 3][2 * i] -= p
        return Qm

    def potential(self, X: Vector) -> Num:
        V = sum(self.k * quartic(Xi) / 4 for Xi in X)
        return V + sum(self.kc * quartic(X[i + 1] - X[i]) / 4 for i in range(self.N - 1))

    def H(self, mu: Vector) -> Num:
        return sum(self.m * v * v / 2 for v in mu[1::2]) + self.potential(mu[0::2])

    def grad_H(self, mu: Vector) -> Vector:
        F0 = self.forces(mu[0::2], [0] * self.N)  # -dV/dX
        out = []
        for i in range(self.N):
            out += [-F0[i], self.m * mu[2 * i + 1]]
        return out

    def hess_H(self, mu: Vector) -> Matrix:
        N, K = self.N, self.stiffness(mu[0::2])
        Hm = [[0] * (2 * N) for _ in range(2 * N)]
        for i in range(N):
            Hm[2 * i + 1][2 * i + 1] = self.m
            for j in range(N):
                Hm[2 * i][2 * j] = -K[i][j]
        return Hm

    def S(self, mu: Vector) -> Matrix:
        N, m = self.N, self.m
        Sm = [[0] * (2 * N) for _ in range(2 * N)]
        for i in range(N):
            Sm[2 * i][2 * i + 1] = 1 / m
            Sm[2 * i + 1][2 * i] = -1 / m
            Sm[2 * i + 1][2 * i + 1] = -self.d / (m * m)
        return Sm

    def energy(self, x: Vector) -> Num:
        X, Y, Xd, Yd = x[0::4], x[1::4], x[2::4], x[3::4]
        kinetic = sum(self.m * (Xd[i] * Xd[i] + Yd[i] * Yd[i]) / 2 for i in range(self.N))
        return kinetic + self.potential(X) + sum(self.m * self.ga * Yi for Yi in Y)

    def row(self, xi: Vector, mu: Vector) -> Vector:
        return [
            max(abs(v) for v in xi[0::2]),
            max(abs(v) for v in xi[1::2]),
            self.energy(self.to_x(xi, mu)),
        ]


# A model of the project, and its class
Model = Union[Oscillator, Pendulum, Chain]
ModelClass = Union[Type[Oscillator], Type[Pendulum], Type[Chain]]

MODELS: dict[str, ModelClass] = {cls.name: cls for cls in (Oscillator, Pendulum, Chain)}


def make(name: str, a: Arith, params: Params | None = None) -> Model:
    """The model `name` in arithmetic `a`, with `params` overriding its defaults."""
    if name not in MODELS:
        raise ValueError("unknown model %r (oscillator, pendulum, chain)" % (name,))
    cls = MODELS[name]
    merged: dict[str, Any] = dict(cls.defaults)
    for key, value in (params or {}).items():
        if key not in merged:
            raise ValueError("parameter %r does not apply to model %s" % (key, name))
        merged[key] = value
    return cls(a, **merged)
