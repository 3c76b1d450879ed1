# SPDX-License-Identifier: GPL-3.0-or-later
"""A pendulum whose names and functions are hard to print: LaTeX-like coordinate names with
backslashes, a description with a quote and a comment's end, pi, an Abs in the potential (its
derivative is sign only for real symbols), a constraint given as an equation, and symbols
declared with assumptions of their own."""

import sympy as sp

from stabdae_gen import Mechanism


def mechanism():
    t = sp.Symbol("t")
    x, y = q = sp.symbols(r"\theta_x \theta_y")
    v = sp.symbols("vx vy")
    m, L, g, k = sp.symbols("m L g k", positive=True)
    return Mechanism(
        "tricky", t, q, v,
        kinetic=m * (v[0]**2 + v[1]**2) / 2,
        potential=m * g * y + k * sp.Abs(x) * sp.pi / 4,
        constraints=[sp.Eq(x**2 + y**2, L**2)],
        params={m: (1.0, 'mass "m" */ in kg'), L: (2.0, "length \\ rod"), g: 9.81, k: 0.5},
        q0=[L * sp.sin(sp.pi / 5), -L * sp.cos(sp.pi / 5)], v0=[0, 0])
