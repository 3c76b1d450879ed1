# SPDX-License-Identifier: GPL-3.0-or-later
"""Small-vector helpers on Python lists (any number type): for n_mu = 2 plain loops are far
cheaper than building numpy arrays."""


def dot(u, v):
    return sum(a * b for a, b in zip(u, v))


def matvec(A, v):
    return [dot(row, v) for row in A]


def matmul(A, B):
    cols = list(zip(*B))
    return [[dot(row, col) for col in cols] for row in A]


def add(u, v):
    return [a + b for a, b in zip(u, v)]


def sub(u, v):
    return [a - b for a, b in zip(u, v)]


def scale(s, v):
    return [s * a for a in v]


def norm_inf(v):
    return max(abs(a) for a in v)
