# SPDX-License-Identifier: GPL-3.0-or-later
"""A pendulum whose names and functions are hard to print: LaTeX-like coordinate names with
backslashes, a description with a quote and a comment's end, descriptions with every trigraph
(??/ is a backslash in strict C99), pi, an Abs in the potential (its derivative is sign only for
real symbols), a constraint given as an equation, symbols declared with assumptions of their
own, and parameters named as the generated C's own names are (X, the table's macro parameter
in the documentation; p, w0, q, the callbacks' locals and arguments; sin; final, a name with a
meaning in C++ that is no keyword), which must compile all the same."""

import sympy as sp

from stabdae_gen import Mechanism


def mechanism():
    t = sp.Symbol("t")
    x, y = q = sp.symbols(r"\theta_x \theta_y")
    v = sp.symbols("vx vy")
    m, L, g, X = sp.symbols("m L g X", positive=True)
    p, w0, q_, sin, final = sp.symbols("p w0 q sin final")
    return Mechanism(
        "tricky",
        t,
        q,
        v,
        kinetic=m * (v[0] ** 2 + v[1] ** 2) / 2,
        potential=m * g * y + X * sp.Abs(x) * sp.pi / 4 + (p + w0 + q_ + sin + final) * y,
        constraints=[sp.Eq(x**2 + y**2, L**2)],
        params={
            m: (1.0, 'mass "m" */ in kg'),
            L: (2.0, "length \\ rod"),
            g: (9.81, "trigraphs ??/ ??= ??( ??) ??' ??< ??! ??> ??- ???/ and ?? end??"),
            X: (0.5, "a ??/"),
            p: 0.0,
            w0: 0.0,
            q_: 0.0,
            sin: 0.0,
            final: 0.0,
        },
        units={m: "kg", L: "m", g: "m/s^2", X: "N.m"},
        coordinate_units={x: "m"},
        q0=[L * sp.sin(sp.pi / 5), -L * sp.cos(sp.pi / 5)],
        v0=[0, 0],
    )
