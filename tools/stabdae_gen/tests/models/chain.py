# SPDX-License-Identifier: GPL-3.0-or-later
"""Planar chains of point masses on massless rods in Cartesian coordinates, the size at which
the generator's cost shows (docs/performance.md): joint k at (x_k, y_k), each rod half a squared
distance, gravity along -y. chain_open.py and chain_closed.py are the models; test_chain.py
checks their callbacks against this mathematics written out by hand.

open:   N joints hanging from a pivot at the origin, 2N coordinates, N rods. The start: the
        chain straight at theta0 from the downward vertical, turning rigidly about the pivot at
        omega0 (joint k moves at k L omega0 perpendicular to the chain), so every rod keeps its
        length at position and velocity level.
closed: N rods between anchors at (0, 0) and (span, 0), N - 1 moving joints, 2N - 2
        coordinates, N rods. The start: at rest in a V, the first half of the rods going down
        and the second half up, each spanning span / N horizontally."""

import sympy as sp

from stabdae_gen import Mechanism

N = 32


def chain(name, closed, N=N, sparse=None):
    """The chain of N rods; sparse as Mechanism's (None: by the size)."""
    joints = N - 1 if closed else N
    t = sp.Symbol("t")
    x = sp.symbols(f"x1:{joints + 1}")
    y = sp.symbols(f"y1:{joints + 1}")
    q = [s for k in range(joints) for s in (x[k], y[k])]
    v = sp.symbols(f"v1:{2 * joints + 1}")
    m, L, g = sp.symbols("m L g")
    params = {
        m: (0.1, "mass of each joint"),
        L: (0.25, "length of each rod"),
        g: (9.81, "gravitational acceleration"),
    }
    px, py = [0, *x], [0, *y]  # the pivot (or the first anchor), then the joints
    if closed:
        span = sp.Symbol("span")
        params[span] = (6.0, "distance between the anchors")
        px.append(span)
        py.append(0)
        a = span / N
        h = sp.sqrt(L**2 - a**2)
        q0 = [e for k in range(1, N) for e in (k * a, -min(k, N - k) * h)]
        v0 = None
    else:
        theta0, omega0 = sp.symbols("theta0 omega0")
        params[theta0] = (0.4, "start angle of the chain from the downward vertical")
        params[omega0] = (0.5, "start angular velocity of the chain")
        s, c = sp.sin(theta0), sp.cos(theta0)
        q0 = [e for k in range(1, N + 1) for e in (k * L * s, -k * L * c)]
        v0 = [e for k in range(1, N + 1) for e in (k * L * omega0 * c, k * L * omega0 * s)]
    rods = [((px[k + 1] - px[k]) ** 2 + (py[k + 1] - py[k]) ** 2 - L**2) / 2 for k in range(N)]
    return Mechanism(
        name,
        t,
        q,
        v,
        kinetic=m * sum(e**2 for e in v) / 2,
        potential=m * g * sum(y),
        constraints=rods,
        params=params,
        q0=q0,
        v0=v0,
        sparse=sparse,
    )
