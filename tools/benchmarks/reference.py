# SPDX-License-Identifier: GPL-3.0-or-later
"""Exact final states of the oscillator on the manifold for the work-precision study.

  python -m benchmarks.reference OUT.csv   (tools/ on PYTHONPATH)

Start x0 = (X, Y, Xdot, Ydot) = (0.7, 0, 0.6, 0), k = 2, m = 1; writes d,tf,X,Xdot for
  d = 0,    tf = 1000: X = A cn(w (t - t0) | 1/2), w = A sqrt(k/m), with the amplitude A from the
            energy W = m Xdot^2/2 + k X^4/4 = k A^4/4 and the phase from X(0): the start is not a
            turning point, cn(w t0) = X0/A, i.e. w t0 = F(arccos(X0/A) | 1/2) (Xdot(0) > 0: the
            turning point X = A comes later, t0 > 0); checked against mpmath's Taylor ODE
            solver (stabdae_ref.exact.manifold_reference) at t = 10;
  d = 0.03, tf = 100: manifold_reference (no closed form with damping).
The file is written once; the caller keeps it as a cache.
"""

import os
import sys

import mpmath

from stabdae_ref import exact

X0 = (0.7, 0.0, 0.6, 0.0)
K, M = 2.0, 1.0
CASES = ((0.0, 1000.0), (0.03, 100.0))
DPS = 30


def cn_solution(tf):
    """(X, Xdot) at tf for d = 0 from the closed form with the phase of X0."""
    mp = mpmath.MPContext()
    mp.dps = 40
    X, Xd = mp.mpf(X0[0]), mp.mpf(X0[2])
    k, m = mp.mpf(K), mp.mpf(M)
    A = (4 * (m * Xd**2 / 2 + k * X**4 / 4) / k) ** mp.mpf(0.25)
    w = A * mp.sqrt(k / m)
    t0 = mp.ellipf(mp.acos(X / A), mp.mpf(1) / 2) / w

    def at(t):
        return exact.oscillator_exact(A, [mp.mpf(t) - t0], k=K, m=M, dps=40)[0]

    start = at(0)
    if abs(start[0] - X) > 1e-30 or abs(start[1] - Xd) > 1e-30:
        raise RuntimeError("the phase does not reproduce X0: %s" % (start,))
    return at, at(tf)


def main(argv):
    if len(argv) != 2:
        sys.stderr.write("usage: python -m benchmarks.reference OUT.csv\n")
        return 2
    at, final0 = cn_solution(1000.0)
    check = exact.manifold_reference("oscillator", {"k": K, "m": M, "d": 0.0}, X0, [10.0], DPS)[0]
    closed = at(10.0)
    for a, b in zip(check, closed):
        if abs(a - b) > 1e-20:
            sys.stderr.write(
                "benchmarks.reference: closed form and Taylor solver disagree at t = 10\n"
            )
            return 1
    rows = [(0.0, 1000.0, final0)]
    damped = exact.manifold_reference("oscillator", {"k": K, "m": M, "d": 0.03}, X0, [100.0], DPS)
    rows.append((0.03, 100.0, damped[0]))
    tmp = argv[1] + ".tmp"
    with open(tmp, "w") as f:
        f.write("d,tf,X,Xdot\n")
        for d, tf, (x, xd) in rows:
            f.write("%r,%r,%s,%s\n" % (d, tf, mpmath.nstr(x, 25), mpmath.nstr(xd, 25)))
    os.replace(tmp, argv[1])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
