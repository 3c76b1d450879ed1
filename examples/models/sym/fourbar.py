# SPDX-License-Identifier: GPL-3.0-or-later
"""The four-bar linkage of examples/models/mechanisms.h in sympy: ground pivots A = (0, 0) and
D = (d, 0), crank AB (a), coupler BC (b), rocker CD (e), point masses mB at B and mC at C under
gravity ga; q = (Bx, By, Cx, Cy), the constraints half squared distances. The start: the crank
at theta0 turning at omega0, C above the line B-D (mech_fourbar_state), the example program's
defaults."""

import sympy as sp

from stabdae_gen import Mechanism


def fourbar(name="fourbar", sparse=None):
    """The four-bar as `name`, dense or (sparse=True) written by its nonzeros."""
    t = sp.Symbol("t")
    Bx, By, Cx, Cy = q = sp.symbols("Bx By Cx Cy")
    v = sp.symbols("vBx vBy vCx vCy")
    a, b, e, d, mB, mC, ga, theta0, omega0 = sp.symbols("a b e d mB mC ga theta0 omega0")

    # the start: C on both circles |C - B| = b, |C - D| = e, along B->D by s, then h to the left
    B0 = sp.Matrix([a * sp.cos(theta0), a * sp.sin(theta0)])
    u = sp.Matrix([d, 0]) - B0
    r = sp.sqrt(u.dot(u))
    s = (b**2 - e**2 + r**2) / (2 * r)
    h = sp.sqrt(b**2 - s**2)
    C0 = B0 + (s * u + h * sp.Matrix([-u[1], u[0]])) / r
    # G v = 0: vB along the crank's circle, vC from (C - B).(vC - vB) = 0 and (C - D).vC = 0
    vB = omega0 * sp.Matrix([-B0[1], B0[0]])
    r1, r2 = C0 - B0, C0 - sp.Matrix([d, 0])
    det = r1[0] * r2[1] - r1[1] * r2[0]
    rhs = r1.dot(vB)
    vC = sp.Matrix([rhs * r2[1] / det, -rhs * r2[0] / det])

    return Mechanism(
        name, t, q, v,
        mass=sp.diag(mB, mB, mC, mC),
        potential=ga * (mB * By + mC * Cy),
        constraints=[(Bx**2 + By**2 - a**2) / 2,
                     ((Cx - Bx)**2 + (Cy - By)**2 - b**2) / 2,
                     ((Cx - d)**2 + Cy**2 - e**2) / 2],
        params={a: (1.0, "crank length |AB|"), b: (4.0, "coupler length |BC|"),
                e: (3.0, "rocker length |CD|"), d: (4.5, "ground length |AD|"),
                mB: (1.0, "mass at B"), mC: (1.0, "mass at C"),
                ga: (9.81, "gravitational acceleration"),
                theta0: (0.0, "start crank angle"), omega0: (5.0, "start crank speed")},
        units={a: "m", b: "m", e: "m", d: "m", mB: "kg", mC: "kg", ga: "m/s^2",
               theta0: "rad", omega0: "rad/s"},
        coordinate_units=["m"] * 4,
        q0=list(B0) + list(C0), v0=list(vB) + list(vC), sparse=sparse)


def mechanism():
    return fourbar()
