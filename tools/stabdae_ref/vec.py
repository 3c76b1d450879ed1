# SPDX-License-Identifier: GPL-3.0-or-later
"""Small-vector helpers on Python lists (any number type): for n_mu = 2 plain loops are far
cheaper than building numpy arrays."""

from __future__ import annotations

from collections.abc import Sequence

from .arith import Matrix, Num, Vector


def dot(u: Sequence[Num], v: Sequence[Num]) -> Num:
    return sum(a * b for a, b in zip(u, v))


def matvec(A: Sequence[Sequence[Num]], v: Sequence[Num]) -> Vector:
    return [dot(row, v) for row in A]


def matmul(A: Sequence[Sequence[Num]], B: Sequence[Sequence[Num]]) -> Matrix:
    cols = list(zip(*B))
    return [[dot(row, col) for col in cols] for row in A]


def add(u: Sequence[Num], v: Sequence[Num]) -> Vector:
    return [a + b for a, b in zip(u, v)]


def sub(u: Sequence[Num], v: Sequence[Num]) -> Vector:
    return [a - b for a, b in zip(u, v)]


def scale(s: Num, v: Sequence[Num]) -> Vector:
    return [s * a for a in v]


def norm_inf(v: Sequence[Num]) -> Num:
    return max(abs(a) for a in v)
