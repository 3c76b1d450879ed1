# SPDX-License-Identifier: GPL-3.0-or-later
"""A particle on a cone z = a r in cylindrical coordinates q = (r, theta, z), with forces of
every kind: the Lagrangian's (a mass matrix diag(m, m r^2, m) that varies with q, a radial
spring and gravity as the potential, a viscous damping D = c diag(1, r^2, 1), the generalized
form of the force -c times the velocity) and forces from outside it, given as force=: a thrust
u sin(t) along the circle (the unit vector e_theta) and a quadratic drag -b |w| w, w the
velocity, in generalized coordinates (w . dP/dq_i):

    Q = (-b |w| r', u sin(t) r - b |w| r^2 theta', -b |w| z'),
    |w| = sqrt(r'^2 + r^2 theta'^2 + z'^2).

test_input_force.py checks force, input_force and their sum against sympy's LagrangesMethod
with the same loads as vectors."""

import sympy as sp

from stabdae_gen import Mechanism


def mechanism():
    t = sp.Symbol("t")
    r, theta, z = q = sp.symbols("r theta z")
    vr, vtheta, vz = v = sp.symbols("vr vtheta vz")
    m, k, r0, g, c, b, u, a = sp.symbols("m k r0 g c b u a")
    speed = sp.sqrt(vr**2 + r**2 * vtheta**2 + vz**2)
    return Mechanism(
        "cone",
        t,
        q,
        v,
        kinetic=m * (vr**2 + r**2 * vtheta**2 + vz**2) / 2,
        potential=k * (r - r0) ** 2 / 2 + m * g * z,
        damping=c * sp.diag(1, r**2, 1),
        force=[-b * speed * vr, u * sp.sin(t) * r - b * speed * r**2 * vtheta, -b * speed * vz],
        constraints=[z - a * r],
        params={
            m: (1.5, "mass"),
            k: (4.0, "radial spring stiffness"),
            r0: (0.8, "radial spring rest radius"),
            g: (9.81, "gravity"),
            c: (0.3, "viscous damping"),
            b: (0.2, "quadratic drag"),
            u: (2.0, "thrust amplitude"),
            a: (0.5, "slope of the cone"),
        },
        units={m: "kg", k: "N/m", r0: "m", g: "m/s^2", c: "N.s/m", b: "kg/m", u: "N", a: "1"},
        coordinate_units=["m", "rad", "m"],
        q0=[1, 0, a],
        v0=[0.1, 1, a / 10],
    )
