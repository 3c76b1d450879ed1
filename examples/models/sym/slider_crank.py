# SPDX-License-Identifier: GPL-3.0-or-later
"""The slider crank of examples/models/benchmarks.h in sympy (SUNDIALS' idaSlCrank_dns, R. Serban
after E. J. Haug, Computer-Aided Kinematics and Dynamics of Mechanical Systems, 1989):
q = (theta, x, phi), crank angle, slider position, connecting-rod angle; M = diag(J1, m2, J2);
c = (x - cos phi - a cos theta, -sin phi - a sin theta) (the rod's length 1); a spring-damper
between the crank's midpoint P = (a/2)(cos theta, sin theta) and the rod's
R = (x - cos phi / 2, -sin phi / 2), of length l = |R - P|, and the constant force F:
V = k (l - l0)^2 / 2 - F (x + cos phi), D = c grad l grad l^T. The constants are
idaSlCrank_dns's; the start its own, at rest at theta = pi/2, phi = asin(-a), x = cos phi
(bench_slider_crank_initial)."""

import math

import sympy as sp

from stabdae_gen import Mechanism


def mechanism():
    t = sp.Symbol("t")
    theta, x, phi = q = sp.symbols("theta x phi")
    v = sp.symbols("vtheta vx vphi")
    a, J1, m2, J2, k, c, l0, F = sp.symbols("a J1 m2 J2 k c l0 F")
    # the start angle as a parameter: pi/2 written as the number (sympy prints pi/2 as the
    # macro M_PI_2, which <math.h> does not define in strict C11)
    theta0 = sp.Symbol("theta0")

    P = a / 2 * sp.Matrix([sp.cos(theta), sp.sin(theta)])
    R = sp.Matrix([x - sp.cos(phi) / 2, -sp.sin(phi) / 2])
    l = sp.sqrt((R - P).dot(R - P))
    grad = sp.Matrix([l.diff(qi) for qi in q])
    phi0 = sp.asin(-a)

    return Mechanism(
        "slider_crank", t, q, v,
        mass=sp.diag(J1, m2, J2),
        potential=k * (l - l0)**2 / 2 - F * (x + sp.cos(phi)),
        damping=c * grad * grad.T,
        constraints=[x - sp.cos(phi) - a * sp.cos(theta),
                     -sp.sin(phi) - a * sp.sin(theta)],
        params={a: (0.5, "crank length (< 1, the rod's)"),
                J1: (1.0, "crank moment of inertia"),
                m2: (1.0, "connecting rod mass"),
                J2: (2.0, "connecting rod moment of inertia"),
                k: (1.0, "spring constant"), c: (1.0, "damper constant"),
                l0: (1.0, "spring free length"), F: (1.0, "constant force"),
                theta0: (math.pi / 2, "start crank angle")},
        # SI units for SUNDIALS' numbers (the rod's length 1 m)
        units={a: "m", J1: "kg.m^2", m2: "kg", J2: "kg.m^2", k: "N/m", c: "N.s/m",
               l0: "m", F: "N", theta0: "rad"},
        coordinate_units=["rad", "m", "rad"],
        q0=[theta0, sp.cos(phi0), phi0], v0=[0, 0, 0])
