# SPDX-License-Identifier: GPL-3.0-or-later
"""The maps phi_T(mu, mu+) of the mu update (paper eq. 11 and 15, condition 13), each with its
Jacobian d phi / d mu+ for Newton:

  euler     q0(mu)                              explicit, order 1
  midpoint  q0((mu + mu+)/2)                    symmetric, order 2
  dgrad     S(m) gradbar H(mu, mu+)             Gonzalez's midpoint discrete gradient (paper
                                                ref. 18), symmetric, order 2; H(mu+) = H(mu)
                                                when S is skew and xi = 0
  user      the model's user map (user_map)     the oscillator's: the paper's Section IV map
  rk4, rk8  sum_i b_i k_i,                      explicit Runge-Kutta, orders 4 and 8 (the
            k_i = q0(mu + T sum_j a_ij k_j)     tableaus of tableaus.py); depends on T

Gonzalez: gradbar H(x, y) = grad H(m) + [(H(y) - H(x) - grad H(m).v)/|v|^2] v with
m = (x + y)/2, v = y - x, and grad H(m) alone when |v|^2 <= eps (1 + |m|^2), eps the
arithmetic's resolution; it satisfies gradbar H . v = H(y) - H(x).
"""

from __future__ import annotations

from typing import Callable, Tuple, cast

from . import tableaus, vec
from .arith import Matrix, Num, Vector
from .models import Model

# phi(mu, mu_next), its Jacobian in mu_next, both at once, and phi_T(mu, mu_next, T)
Phi = Callable[[Vector, Vector], Vector]
Jac = Callable[[Vector, Vector], Matrix]
PhiJac = Callable[[Vector, Vector], Tuple[Vector, Matrix]]
PhiT = Callable[[Vector, Vector, Num], Vector]


class Map:
    """phi(mu, mu_next) and its Jacobian in mu_next (None for an explicit map);
    phi_jac(mu, mu_next) gives both, sharing the work when the map can. phi_T(mu, mu_next, T)
    is the map of a step of size T: phi itself for the maps that do not depend on T, or the
    map's own (then phi is None)."""

    def __init__(
        self,
        name: str,
        phi: Phi | None,
        jac: Jac | None = None,
        phi_jac: PhiJac | None = None,
        phi_T: PhiT | None = None,
    ) -> None:
        self.name, self.phi, self.jac = name, phi, jac
        # the defaults are called only for the maps that give phi (and jac, when implicit)
        self.phi_jac: PhiJac = phi_jac or (
            lambda mu, mu_next: (cast(Phi, phi)(mu, mu_next), cast(Jac, jac)(mu, mu_next))
        )
        self.phi_T: PhiT = phi_T or (lambda mu, mu_next, T: cast(Phi, phi)(mu, mu_next))

    @property
    def explicit(self) -> bool:
        return self.jac is None


def euler(model: Model) -> Map:
    return Map("euler", lambda mu, mu_next: model.q0(mu))


def midpoint(model: Model) -> Map:
    def mid(mu: Vector, mu_next: Vector) -> Vector:
        return [(u + w) / 2 for u, w in zip(mu, mu_next)]

    def jac(mu: Vector, mu_next: Vector) -> Matrix:
        return [[v / 2 for v in row] for row in model.q0_jac(mid(mu, mu_next))]

    return Map("midpoint", lambda mu, mu_next: model.q0(mid(mu, mu_next)), jac)


def gonzalez(model: Model, x: Vector, y: Vector) -> tuple[Vector, Matrix]:
    """(gradbar H(x, y), d gradbar H / dy)."""
    a = model.a
    m = [(u + w) / 2 for u, w in zip(x, y)]
    v = vec.sub(y, x)
    g, hess = model.grad_H(m), model.hess_H(m)
    half_hess = [[h / 2 for h in row] for row in hess]
    vv = vec.dot(v, v)
    if vv <= a.eps * (1 + vec.dot(m, m)):
        return g, half_hess
    s = (model.H(y) - model.H(x) - vec.dot(g, v)) / vv
    gbar = [gi + s * vi for gi, vi in zip(g, v)]
    # d s / dy = (grad H(y) - Hess(m) v / 2 - grad H(m) - 2 s v) / |v|^2
    ds = [
        (gy - hv - gi - 2 * s * vi) / vv
        for gy, hv, gi, vi in zip(model.grad_H(y), vec.matvec(half_hess, v), g, v)
    ]
    n = len(x)
    J = [
        [half_hess[i][j] + v[i] * ds[j] + (s if i == j else 0) for j in range(n)] for i in range(n)
    ]
    return gbar, J


def discrete_gradient(model: Model) -> Map:
    """phi = S(m) gradbar H; the Jacobian treats S as constant (true for the three models;
    it only steers Newton, never changes the solution)."""

    def phi_jac(mu: Vector, mu_next: Vector) -> tuple[Vector, Matrix]:
        S = model.S([(u + w) / 2 for u, w in zip(mu, mu_next)])
        gbar, J = gonzalez(model, mu, mu_next)
        return vec.matvec(S, gbar), vec.matmul(S, J)

    return Map(
        "dgrad",
        lambda mu, mu_next: phi_jac(mu, mu_next)[0],
        lambda mu, mu_next: phi_jac(mu, mu_next)[1],
        phi_jac,
    )


def runge_kutta(name: str) -> Callable[[Model], Map]:
    """The explicit Runge-Kutta map of tableau `name`: phi_T(mu) = sum_i b_i k_i with
    k_i = q0(mu + T sum_{j<i} a_ij k_j) (the models here are autonomous: the nodes c_i are not
    needed). The sums run over the nonzero coefficients in the order of j, as in the C
    library, so that float64 rounds the same way."""

    def make(model: Model) -> Map:
        A, b, _ = tableaus.tableau(name, model.a)
        zero = model.a.num(0)

        def combination(weights: Vector, ks: list[Vector]) -> Vector:
            out = [zero] * model.n_mu
            for w, k in zip(weights, ks):
                if w != 0:
                    out = [o + w * v for o, v in zip(out, k)]
            return out

        def phi_T(mu: Vector, mu_next: Vector, T: Num) -> Vector:
            ks: list[Vector] = []
            for i in range(len(b)):
                incr = combination(A[i][:i], ks)
                ks.append(model.q0([m + T * v for m, v in zip(mu, incr)] if i else mu))
            return combination(b, ks)

        return Map(name, None, phi_T=phi_T)

    return make


BUILTIN: dict[str, Callable[[Model], Map]] = {
    "euler": euler,
    "midpoint": midpoint,
    "dgrad": discrete_gradient,
    "rk4": runge_kutta("rk4"),
    "rk8": runge_kutta("rk8"),
}


def make(name: str, model: Model) -> Map:
    """The map of the library's name `name` for `model`: 'user' is the model's user_map."""
    if name in BUILTIN:
        return BUILTIN[name](model)
    if name == "user" and model.user_map is not None:
        return Map("user", *model.user_map)
    known = sorted(BUILTIN) + (["user"] if model.user_map is not None else [])
    raise ValueError(
        "map %r is not available for model %s (%s)" % (name, model.name, ", ".join(known))
    )
