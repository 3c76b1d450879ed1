# SPDX-License-Identifier: GPL-3.0-or-later
"""The two arithmetics of the reference: IEEE double (Python floats, numpy for linear
algebra) and multiple precision (an mpmath context of its own, so the global mpmath.mp is
never touched).

Every model, map and step is written once over an `Arith` object: vectors are Python lists of
its numbers, matrices lists of rows, and the few functions the mathematics needs (sin, cos,
sqrt, atan2, a linear solve) come from the arithmetic.

Newton stopping rules (the only place where the arithmetics differ on purpose):
  float64  stop after an update dy with ||dy||_inf <= 1e-14 (1 + ||mu+||_inf), at most 20
           updates: the C library's default rule, so iteration counts can be compared;
  mpmath   stop when the residual ||R(mu+)||_inf <= 10^-(dps - 10) (1e-30 at dps 40), at most
           50 updates.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, List, Union, cast

import mpmath
import numpy

# A number of either arithmetic: a float or an mpmath mpf (mpmath ships no types, so Any)
Num = Any
Vector = List[Num]
Matrix = List[List[Num]]


class Float64:
    """IEEE double precision: Python floats are C doubles."""

    name = "float64"
    newton_max_iter = 20

    def __init__(self) -> None:
        # |v|^2 below eps_machine (1 + |m|^2): Gonzalez's quotient is rounding noise
        self.eps = 2.0**-52
        self.newton_tol = 1e-14
        self.pi = math.pi
        self.sin, self.cos, self.sqrt, self.atan2 = math.sin, math.cos, math.sqrt, math.atan2

    def num(self, x: float | str) -> float:
        return float(x)

    def isfinite(self, x: float) -> bool:
        return math.isfinite(x)

    def solve(self, A: Matrix, b: Vector) -> list[float]:
        """A y = b; raises ArithmeticError when A is singular."""
        try:
            y = numpy.linalg.solve(numpy.array(A, dtype=float), numpy.array(b, dtype=float))
        except numpy.linalg.LinAlgError as exc:
            raise ArithmeticError("singular matrix") from exc
        return [float(v) for v in y]

    def update_small(self, update: Sequence[float], mu_next: Sequence[float]) -> bool:
        """Newton's stopping rule in double precision (the C library's)."""
        return max(map(abs, update)) <= self.newton_tol * (1.0 + max(map(abs, mu_next)))

    def residual_small(self, residual: Sequence[float]) -> bool:
        return False

    def fmt(self, x: float) -> str:
        return "%.17g" % x


class MP:
    """mpmath at `dps` significant digits, in a private context."""

    name = "mpmath"
    newton_max_iter = 50

    def __init__(self, dps: int = 40) -> None:
        if int(dps) != dps or dps < 20:
            raise ValueError("dps must be an integer >= 20, got %r" % (dps,))
        self.ctx = mpmath.MPContext()
        self.ctx.dps = int(dps)
        self.dps = int(dps)
        self.eps = self.ctx.mpf(10) ** (-self.dps)
        self.newton_tol = self.ctx.mpf(10) ** (-(self.dps - 10))
        self.pi = self.ctx.pi
        c = self.ctx
        self.sin, self.cos, self.sqrt, self.atan2 = c.sin, c.cos, c.sqrt, c.atan2

    def num(self, x: float | str | Num) -> Num:
        """Floats enter as their exact binary value (the double the C library sees);
        strings and integers exactly."""
        return self.ctx.mpf(x)

    def isfinite(self, x: Num) -> bool:
        return cast(bool, self.ctx.isfinite(x))

    def solve(self, A: Matrix, b: Vector) -> Vector:
        try:
            y = self.ctx.lu_solve(self.ctx.matrix(A), self.ctx.matrix(b))
        except ZeroDivisionError as exc:
            raise ArithmeticError("singular matrix") from exc
        return [y[i] for i in range(len(b))]

    def update_small(self, update: Vector, mu_next: Vector) -> bool:
        return False

    def residual_small(self, residual: Vector) -> bool:
        """Newton's stopping rule in multiple precision."""
        return cast(bool, max(map(abs, residual)) <= self.newton_tol)

    def fmt(self, x: Num) -> str:
        return cast(str, self.ctx.nstr(x, self.dps, strip_zeros=False))


# The arithmetic every model, map and step is written over
Arith = Union[Float64, MP]


def make(arithmetic: str = "float64", dps: int = 40) -> Arith:
    if arithmetic == "float64":
        return Float64()
    if arithmetic == "mpmath":
        return MP(dps)
    raise ValueError("arithmetic must be 'float64' or 'mpmath', got %r" % (arithmetic,))
