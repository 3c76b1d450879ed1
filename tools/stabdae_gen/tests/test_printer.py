# SPDX-License-Identifier: GPL-3.0-or-later
"""The C printer's expressions evaluated as the C compiler reads them: for + - * / and calls
C's syntax and precedence are Python's, so each printed string is evaluated by Python with
math's functions and compared with sympy's value of the expression at 30 digits. The cases are
those the printer writes by hand: powers as products (in a denominator too), half powers,
constants such as pi, and temporaries named for the bases of powers."""

import math
import random

import pytest
import sympy as sp

from stabdae_gen.cwriter import _Printer, _name_bases

x, y, z = sp.symbols("x y z", positive=True)
CASES = [
    x / y**2,
    x / y**3,
    x / y ** sp.Rational(3, 2),
    x * y ** sp.Rational(-3, 2),
    (x + y) ** 3 / (x - 2 * y) ** 2,
    1 / sp.sqrt(x + y),
    (x * y + 1) ** 4,
    sp.pi * x / 2,
    sp.E**2 * x,
    x**-2 + y**-4,
    z / (x + y) ** sp.Rational(3, 2) - (x + z) ** 2,
]


def c_value(text, values):
    scope = {"sqrt": math.sqrt, "pow": math.pow, "exp": math.exp}
    scope.update(values)
    return eval(text, scope)  # noqa: S307 (the printer's own output, arithmetic only)


@pytest.mark.parametrize("expr", CASES, ids=[str(c) for c in CASES])
def test_printed_expression_has_its_value(expr):
    printer = _Printer()
    rng = random.Random(3)
    for _ in range(5):
        values = {"x": rng.uniform(0.5, 2), "y": rng.uniform(0.5, 2), "z": rng.uniform(0.5, 2)}
        exact = float(expr.evalf(30, subs={x: values["x"], y: values["y"], z: values["z"]}))
        got = c_value(printer.doprint(expr), values)
        assert got == pytest.approx(exact, rel=1e-13, abs=1e-300)


def test_named_bases_keep_the_value():
    """The bases named as temporaries, then the temporaries evaluated in order."""
    printer = _Printer()
    exprs = [(x + y) ** 2 + 1 / (x + y) ** 2, (x * z - y) ** sp.Rational(3, 2) * (x + y) ** 3]
    symbols = sp.numbered_symbols("w")
    temps, reduced = _name_bases(*sp.cse(exprs, symbols=symbols), symbols)
    assert len(temps) >= 2  # x + y and x z - y named
    values = {"x": 1.3, "y": 0.4, "z": 0.9}
    for sym, e in temps:
        values[str(sym)] = c_value(printer.doprint(e), values)
    for e, original in zip(reduced, exprs):
        exact = float(original.evalf(30, subs={x: 1.3, y: 0.4, z: 0.9}))
        assert c_value(printer.doprint(e), values) == pytest.approx(exact, rel=1e-13)
