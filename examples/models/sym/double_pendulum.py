# SPDX-License-Identifier: GPL-3.0-or-later
"""The double pendulum of examples/models/mechanisms.h in sympy: m1 on a massless rod L1 from the
origin, m2 on a rod L2 from m1, under gravity ga along -y; q = (x1, y1, x2, y2), M = diag(m1,
m1, m2, m2), the constraints half squared distances ((|p1|^2 - L1^2)/2, (|p2 - p1|^2 - L2^2)/2),
V = ga (m1 y1 + m2 y2). The start: each arm at its angle from the downward vertical, turning at
its rate (mech_double_pendulum_state); the defaults are the example program's, at rest at 2.0
and 2.5 rad."""

import sympy as sp

from stabdae_gen import Mechanism


def mechanism():
    t = sp.Symbol("t")
    x1, y1, x2, y2 = q = sp.symbols("x1 y1 x2 y2")
    v = sp.symbols("vx1 vy1 vx2 vy2")
    L1, L2, m1, m2, ga = sp.symbols("L1 L2 m1 m2 ga")
    theta1, theta2, omega1, omega2 = sp.symbols("theta1 theta2 omega1 omega2")

    # each arm points along (sin a_i, -cos a_i); its end moves at L_i w_i (cos a_i, sin a_i)
    p1 = sp.Matrix([L1 * sp.sin(theta1), -L1 * sp.cos(theta1)])
    p2 = p1 + sp.Matrix([L2 * sp.sin(theta2), -L2 * sp.cos(theta2)])
    w1 = L1 * omega1 * sp.Matrix([sp.cos(theta1), sp.sin(theta1)])
    w2 = w1 + L2 * omega2 * sp.Matrix([sp.cos(theta2), sp.sin(theta2)])

    return Mechanism(
        "double_pendulum", t, q, v,
        mass=sp.diag(m1, m1, m2, m2),
        potential=ga * (m1 * y1 + m2 * y2),
        constraints=[(x1**2 + y1**2 - L1**2) / 2,
                     ((x2 - x1)**2 + (y2 - y1)**2 - L2**2) / 2],
        params={L1: (1.0, "inner rod length"), L2: (1.0, "outer rod length"),
                m1: (1.0, "inner mass"), m2: (1.0, "outer mass"),
                ga: (9.81, "gravitational acceleration"),
                theta1: (2.0, "start angle of the inner arm from the downward vertical"),
                theta2: (2.5, "start angle of the outer arm from the downward vertical"),
                omega1: (0.0, "start rate of the inner arm"),
                omega2: (0.0, "start rate of the outer arm")},
        units={L1: "m", L2: "m", m1: "kg", m2: "kg", ga: "m/s^2", theta1: "rad",
               theta2: "rad", omega1: "rad/s", omega2: "rad/s"},
        coordinate_units=["m"] * 4,
        q0=list(p1) + list(p2), v0=list(w1) + list(w2))
