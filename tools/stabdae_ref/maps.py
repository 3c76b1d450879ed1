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

from . import tableaus, vec


class Map:
    """phi(mu, mu_next) and its Jacobian in mu_next (None for an explicit map);
    phi_jac(mu, mu_next) gives both, sharing the work when the map can. phi_T(mu, mu_next, T)
    is the map of a step of size T: phi itself for the maps that do not depend on T, or the
    map's own (then phi is None)."""

    def __init__(self, name, phi, jac=None, phi_jac=None, phi_T=None):
        self.name, self.phi, self.jac = name, phi, jac
        self.phi_jac = phi_jac or (lambda mu, mu_next: (phi(mu, mu_next), jac(mu, mu_next)))
        self.phi_T = phi_T or (lambda mu, mu_next, T: phi(mu, mu_next))

    @property
    def explicit(self):
        return self.jac is None


def euler(model):
    return Map("euler", lambda mu, mu_next: model.q0(mu))


def midpoint(model):
    def mid(mu, mu_next):
        return [(u + w) / 2 for u, w in zip(mu, mu_next)]

    def jac(mu, mu_next):
        return [[v / 2 for v in row] for row in model.q0_jac(mid(mu, mu_next))]

    return Map("midpoint", lambda mu, mu_next: model.q0(mid(mu, mu_next)), jac)


def gonzalez(model, x, y):
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


def discrete_gradient(model):
    """phi = S(m) gradbar H; the Jacobian treats S as constant (true for the three models;
    it only steers Newton, never changes the solution)."""

    def phi_jac(mu, mu_next):
        S = model.S([(u + w) / 2 for u, w in zip(mu, mu_next)])
        gbar, J = gonzalez(model, mu, mu_next)
        return vec.matvec(S, gbar), vec.matmul(S, J)

    return Map(
        "dgrad",
        lambda mu, mu_next: phi_jac(mu, mu_next)[0],
        lambda mu, mu_next: phi_jac(mu, mu_next)[1],
        phi_jac,
    )


def runge_kutta(name):
    """The explicit Runge-Kutta map of tableau `name`: phi_T(mu) = sum_i b_i k_i with
    k_i = q0(mu + T sum_{j<i} a_ij k_j) (the models here are autonomous: the nodes c_i are not
    needed). The sums run over the nonzero coefficients in the order of j, as in the C
    library, so that float64 rounds the same way."""

    def make(model):
        A, b, _ = tableaus.tableau(name, model.a)
        zero = model.a.num(0)

        def combination(weights, ks):
            out = [zero] * model.n_mu
            for w, k in zip(weights, ks):
                if w != 0:
                    out = [o + w * v for o, v in zip(out, k)]
            return out

        def phi_T(mu, mu_next, T):
            ks = []
            for i in range(len(b)):
                incr = combination(A[i][:i], ks)
                ks.append(model.q0([m + T * v for m, v in zip(mu, incr)] if i else mu))
            return combination(b, ks)

        return Map(name, None, phi_T=phi_T)

    return make


BUILTIN = {
    "euler": euler,
    "midpoint": midpoint,
    "dgrad": discrete_gradient,
    "rk4": runge_kutta("rk4"),
    "rk8": runge_kutta("rk8"),
}


def make(name, model):
    """The map of the library's name `name` for `model`: 'user' is the model's user_map."""
    if name in BUILTIN:
        return BUILTIN[name](model)
    if name == "user" and model.user_map is not None:
        return Map("user", *model.user_map)
    known = sorted(BUILTIN) + (["user"] if model.user_map is not None else [])
    raise ValueError(
        "map %r is not available for model %s (%s)" % (name, model.name, ", ".join(known))
    )
