#!/usr/bin/env python3
"""Writes examples/expected/*.csv, the answers of the regression tests, from an implementation
of the three models, schemes 11 and 15 and the mu-maps that shares no code with the C library
or the C examples (numpy, written from the definitions of the models and the paper). The C
programs must agree with it to a relative 1e-10 (newton_iters, the last column, is this
script's own count and is not compared).

    python examples/tests/make_expected.py [--outdir examples/expected]

The run table below repeats the flags of examples/tests/CMakeLists.txt.
"""
import argparse
import math
import os

import numpy as np

# ---- models ------------------------------------------------------------------------------


class Oscillator:
    """Section IV, coordinates of eq. 21, with a mass m (DESIGN.md erratum 3)."""

    def __init__(self, k=2.0, d=0.03, m=1.0, ga=9.81, q="corrected"):
        self.k, self.d, self.m, self.ga, self.q = k, d, m, ga, q

    def coords(self, x):
        X, Y, Xd, Yd = x
        return np.array([Y, Yd]), np.array([X + Y, Y + Xd])

    def state(self, xi, mu):
        return np.array([mu[0] - xi[0], xi[0], mu[1] - xi[0], xi[1]])

    def q0(self, mu):
        return np.array([mu[1], (-self.k * mu[0] ** 3 - self.d * mu[1]) / self.m])

    def Q(self, xi, mu):
        a, e = mu[0], xi[0]
        if self.q == "paper":
            c = (self.k * (3 * a * e - 3 * a * a - e * e) + self.d * e) / self.m
        else:
            c = (self.k * (3 * a * a - 3 * a * e + e * e) + self.d) / self.m
        return np.array([[-1.0, 1.0], [c, 1.0]])

    def H(self, mu):
        return self.m * mu[1] ** 2 / 2 + self.k * mu[0] ** 4 / 4

    def grad_H(self, mu):
        return np.array([self.k * mu[0] ** 3, self.m * mu[1]])

    def S(self, mu):
        m = self.m
        return np.array([[0.0, 1 / m], [-1 / m, -self.d / m**2]])

    def paper_phi(self, mu, mun):
        a, b = mun[0], mu[0]
        return np.array([(mun[1] + mu[1]) / 2,
                         (-self.k * (a**3 + b**3 + (a + b) * a * b) / 4 - self.d * mu[1]) / self.m])

    def energy(self, x):
        X, Y, Xd, Yd = x
        return self.m * (Xd**2 + Yd**2) / 2 + self.k * X**4 / 4 + self.m * self.ga * Y

    def row(self, xi, mu):
        x = self.state(xi, mu)
        return list(x) + list(xi) + list(mu) + [self.energy(x), self.H(mu)]


class Pendulum:
    """xi = (h, L_f h), mu = (theta, X Ydot - Y Xdot)."""

    def __init__(self, L=1.0, m=1.0, ga=9.81):
        self.L, self.m, self.ga = L, m, ga

    def coords(self, x):
        X, Y, Xd, Yd = x
        return (np.array([(X * X + Y * Y - self.L**2) / 2, X * Xd + Y * Yd]),
                np.array([math.atan2(X, -Y), X * Yd - Y * Xd]))

    def state(self, xi, mu):
        r2 = self.L**2 + 2 * xi[0]
        r = math.sqrt(r2)
        s, c = math.sin(mu[0]), math.cos(mu[0])
        rd, thd = xi[1] / r, mu[1] / r2
        return np.array([r * s, -r * c, rd * s + r * c * thd, -rd * c + r * s * thd])

    def q0(self, mu):
        return np.array([mu[1] / self.L**2, -self.ga * self.L * math.sin(mu[0])])

    def Q(self, xi, mu):
        # q(xi, mu) - q0(mu) with the exact mu dynamics, divided by xi1 (q_2 = 0)
        L, r2 = self.L, self.L**2 + 2 * xi[0]
        return np.array([[-2 * mu[1] / (L * L * r2), 0.0],
                         [-2 * self.ga * math.sin(mu[0]) / (L + math.sqrt(r2)), 0.0]])

    def H(self, mu):
        return self.m * mu[1] ** 2 / (2 * self.L**2) - self.m * self.ga * self.L * math.cos(mu[0])

    def grad_H(self, mu):
        return np.array([self.m * self.ga * self.L * math.sin(mu[0]), self.m * mu[1] / self.L**2])

    def S(self, mu):
        return np.array([[0.0, 1 / self.m], [-1 / self.m, 0.0]])

    def energy(self, x):
        return self.m * (x[2] ** 2 + x[3] ** 2) / 2 + self.m * self.ga * x[1]

    def row(self, xi, mu):
        x = self.state(xi, mu)
        return list(x) + list(xi) + list(mu) + [self.energy(x)]


class Chain:
    """N oscillators with cubic nearest-neighbour springs; xi, mu interleaved per mass."""

    def __init__(self, N=10, k=2.0, kc=1.0, d=0.03, m=1.0, ga=9.81):
        self.N, self.k, self.kc, self.d, self.m, self.ga = N, k, kc, d, m, ga

    def force(self, X, V):
        F = -self.k * X**3 - self.d * V
        bond = self.kc * np.diff(X) ** 3  # kc (X_{i+1} - X_i)^3
        F[:-1] += bond
        F[1:] -= bond
        return F

    def coords(self, x):
        s = x.reshape(self.N, 4)
        return (np.column_stack([s[:, 1], s[:, 3]]).ravel(),
                np.column_stack([s[:, 0] + s[:, 1], s[:, 1] + s[:, 2]]).ravel())

    def state(self, xi, mu):
        e, e2, a, v = xi[0::2], xi[1::2], mu[0::2], mu[1::2]
        return np.column_stack([a - e, e, v - e, e2]).ravel()

    def q0(self, mu):
        out = np.empty_like(mu)
        out[0::2] = mu[1::2]
        out[1::2] = self.force(mu[0::2], mu[1::2]) / self.m
        return out

    def Q(self, xi, mu):
        """Dense Q: row (i,2) from the secants of the cubic springs (a^3 - b^3 = (a-b)(...))."""
        N, n = self.N, 2 * self.N
        a, e = mu[0::2], xi[0::2]
        D = np.diff(a)
        u = D - np.diff(e)
        s = u * u + u * D + D * D
        Q = np.zeros((n, n))
        for i in range(N):
            Q[2 * i, 2 * i], Q[2 * i, 2 * i + 1] = -1.0, 1.0
            c = self.k * (3 * a[i] ** 2 - 3 * a[i] * e[i] + e[i] ** 2) + self.d
            if i > 0:
                c += self.kc * s[i - 1]
                Q[2 * i + 1, 2 * i - 2] = -self.kc * s[i - 1] / self.m
            if i < N - 1:
                c += self.kc * s[i]
                Q[2 * i + 1, 2 * i + 2] = -self.kc * s[i] / self.m
            Q[2 * i + 1, 2 * i] = c / self.m
            Q[2 * i + 1, 2 * i + 1] = 1.0
        return Q

    def H(self, mu):
        a, v = mu[0::2], mu[1::2]
        return float(np.sum(self.m * v**2 / 2 + self.k * a**4 / 4)
                     + np.sum(self.kc * np.diff(a) ** 4 / 4))

    def grad_H(self, mu):
        g = np.empty_like(mu)
        a, v = mu[0::2], mu[1::2]
        g[0::2] = -(self.force(a, v) + self.d * v)
        g[1::2] = self.m * v
        return g

    def S(self, mu):
        n, m = 2 * self.N, self.m
        S = np.zeros((n, n))
        for i in range(self.N):
            S[2 * i, 2 * i + 1], S[2 * i + 1, 2 * i] = 1 / m, -1 / m
            S[2 * i + 1, 2 * i + 1] = -self.d / m**2
        return S

    def energy(self, x):
        s = x.reshape(self.N, 4)
        bodies = (self.m * (s[:, 2] ** 2 + s[:, 3] ** 2) / 2 + self.k * s[:, 0] ** 4 / 4
                  + self.m * self.ga * s[:, 1])
        return float(np.sum(bodies) + np.sum(self.kc * np.diff(s[:, 0]) ** 4 / 4))

    def row(self, xi, mu):
        return [float(np.max(np.abs(xi[0::2]))), float(np.max(np.abs(xi[1::2]))),
                self.energy(self.state(xi, mu))]


# ---- the chain's random start: GSL's MT19937 and gsl_ran_flat -----------------------------


class MT19937:
    """The reference generator (Matsumoto-Nishimura, init_genrand), as gsl_rng_mt19937."""

    def __init__(self, seed):
        seed = seed & 0xFFFFFFFF or 4357  # GSL replaces seed 0 by 4357
        self.mt = [seed]
        for i in range(1, 624):
            prev = self.mt[-1]
            self.mt.append((1812433253 * (prev ^ (prev >> 30)) + i) & 0xFFFFFFFF)
        self.i = 624

    def next32(self):
        if self.i >= 624:
            for k in range(624):
                y = (self.mt[k] & 0x80000000) | (self.mt[(k + 1) % 624] & 0x7FFFFFFF)
                self.mt[k] = self.mt[(k + 397) % 624] ^ (y >> 1) ^ (0x9908B0DF if y & 1 else 0)
            self.i = 0
        y = self.mt[self.i]
        self.i += 1
        y ^= y >> 11
        y ^= (y << 7) & 0x9D2C5680
        y ^= (y << 15) & 0xEFC60000
        y ^= y >> 18
        return y

    def flat(self, a, b):
        u = self.next32() / 4294967296.0
        return a * (1 - u) + b * u


def chain_start(N, seed):
    r = MT19937(seed)
    x = []
    for _ in range(N):
        x += [r.flat(-0.5, 0.5), r.flat(-0.2, 0.2), r.flat(-0.1, 0.1), r.flat(-0.1, 0.1)]
    return np.array(x)


# ---- maps, schemes -------------------------------------------------------------------------


def gonzalez(model, mu, mun):
    """S(mid) times Gonzalez's midpoint discrete gradient of H."""
    mid, v = (mu + mun) / 2, mun - mu
    g = model.grad_H(mid)
    vv = float(v @ v)
    if vv > 1e-30 * (1 + float(mid @ mid)):
        g = g + (model.H(mun) - model.H(mu) - float(g @ v)) / vv * v
    return model.S(mid) @ g


MAPS = {
    "euler": lambda model, mu, mun: model.q0(mu),
    "midpoint": lambda model, mu, mun: model.q0((mu + mun) / 2),
    "dg": gonzalez,
    "dg-paper": lambda model, mu, mun: model.paper_phi(mu, mun),
}


def solve_mu(model, phi, mu, rest, T):
    """mu+ = mu + T (phi(mu, mu+) + Q xi) by Newton with a difference Jacobian, to round-off."""
    def R(z):
        return z - mu - T * (phi(model, mu, z) + rest)

    z = mu + T * (model.q0(mu) + rest)
    n = len(mu)
    for it in range(1, 100):
        r = R(z)
        J = np.empty((n, n))
        for c in range(n):
            h = 1e-7 * (1 + abs(z[c]))
            dz = np.zeros(n)
            dz[c] = h
            J[:, c] = (R(z + dz) - R(z - dz)) / (2 * h)
        dz = np.linalg.solve(J, -r)
        z = z + dz
        if np.max(np.abs(dz)) <= 1e-15 * (1 + np.max(np.abs(z))):
            return z, it
    raise RuntimeError("Newton did not converge")


def step(model, scheme, mapname, T, xi, mu, delta, eps):
    Q = model.Q(xi, mu)
    k = -(delta**2 / 2) * np.sum(Q * Q, axis=0) - eps  # eq. 6, column norms
    xin = (1 + T * k) * xi if scheme == 11 else xi / (1 - T * k)  # eq. 11 / eq. 15
    rest = Q @ xi
    if mapname == "euler":
        return xin, mu + T * (model.q0(mu) + rest), 0
    mun, its = solve_mu(model, MAPS[mapname], mu, rest, T)
    return xin, mun, its


def run(model, x0, T, nsteps, every, scheme, mapname, delta, eps):
    xi, mu = model.coords(np.asarray(x0, dtype=float))
    rows = [[0.0] + model.row(xi, mu) + [0]]
    for i in range(1, nsteps + 1):
        xi, mu, its = step(model, scheme, mapname, T, xi, mu, delta, eps)
        if i % every == 0 or i == nsteps:
            rows.append([i * T] + model.row(xi, mu) + [its])
    return rows


HEADERS = {
    Oscillator: "t,X,Y,Xdot,Ydot,xi1,xi2,mu1,mu2,E,W,newton_iters",
    Pendulum: "t,X,Y,Xdot,Ydot,xi1,xi2,mu1,mu2,E,newton_iters",
    Chain: "t,max_abs_Y,max_abs_Ydot,E,newton_iters",
}

OSC_X0 = [0.1, 0.6, 0.0, 0.0]
PEND_X0 = [0.5, -0.9, 0.1, 0.2]

# name: (model, x0, scheme, map); all with T = 0.001, 200 steps, a row every 10, delta 2, eps 1
RUNS = {
    "oscillator_default": (Oscillator(), OSC_X0, 15, "dg-paper"),
    "oscillator_s11_euler": (Oscillator(), OSC_X0, 11, "euler"),
    "oscillator_midpoint_qpaper": (Oscillator(q="paper"), OSC_X0, 15, "midpoint"),
    "oscillator_dg_d0_m2": (Oscillator(d=0.0, m=2.0), OSC_X0, 15, "dg"),
    "pendulum_dg": (Pendulum(), PEND_X0, 15, "dg"),
    "pendulum_s11_euler": (Pendulum(), PEND_X0, 11, "euler"),
    "pendulum_midpoint_L2": (Pendulum(L=2.0, m=0.5),
                             [2 * math.sin(0.5), -2 * math.cos(0.5), 0.0, 0.0], 15, "midpoint"),
    "chain_euler": (Chain(N=5), chain_start(5, 3), 15, "euler"),
    "chain_midpoint": (Chain(N=3, kc=2.0), chain_start(3, 1), 15, "midpoint"),
    "chain_dg_s11": (Chain(N=4), chain_start(4, 1), 11, "dg"),
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--outdir", default=os.path.join(here, "..", "expected"))
    args = ap.parse_args()
    os.makedirs(args.outdir, exist_ok=True)
    for name, (model, x0, scheme, mapname) in RUNS.items():
        rows = run(model, x0, 0.001, 200, 10, scheme, mapname, 2.0, 1.0)
        path = os.path.join(args.outdir, name + ".csv")
        with open(path, "w") as f:
            f.write(HEADERS[type(model)] + "\n")
            for r in rows:
                f.write(",".join("%.17g" % v for v in r[:-1]) + ",%d\n" % r[-1])
        print(path)


if __name__ == "__main__":
    main()
