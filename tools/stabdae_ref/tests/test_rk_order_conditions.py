# SPDX-License-Identifier: GPL-3.0-or-later
"""The order conditions of the explicit Runge-Kutta maps, for the coefficients the C library
uses: the tableaus are read out of src/maps/map_rk4.c and map_rk8.c (each C literal and
constant expression evaluated as the compiler does, in double), then checked in 50-digit
arithmetic.

Order p holds when sum_i b_i Phi_i(t) = 1/gamma(t) for every rooted tree t of at most p
vertices (Butcher; Hairer, Norsett, Wanner, Solving ODEs I, Sect. II.2): Phi_i
is the elementary weight, the product over the root's subtrees u of sum_j a_ij Phi_j(u) (1 for
a leaf), and gamma the density, |t| times the product of the subtrees' densities. The trees
are generated here (1, 1, 2, 4, 9, 20, 48, 115 of orders 1 to 8: 200 conditions for order 8,
and the 286 of order 9). The published coefficients satisfy the conditions up to the order to
their own digits (the reference's tableaus in 50 digits: below 1e-26), so what the doubles
leave is their rounding, u = 2^-53 relative per coefficient: asserted below 1e-15 (9 u) for
every condition, while a98 two units in the last place off leaves 9e-15, and off in its
tenth digit 2e-8. Past the
order, at least one condition fails by more than 1e-6. The nodes are the row sums,
c_i = sum_j a_ij, to the rounding u (|c_i| + sum_j |a_ij|). The Python reference's tableaus
(stabdae_ref/tableaus.py, typed from the same publications) round to the same doubles."""

import ast
import math
import os
import re

import mpmath
import pytest

from stabdae_ref import arith, tableaus

MAPS = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", "..", "..", "src", "maps"))
U = 2.0**-53  # the unit roundoff of a double
DPS = 50
ROUNDING = 1e-15  # the doubles' residuals: about 9 U
PUBLISHED = 1e-26  # the published decimals' (30 digits for DOP853)
FAILS = 1e-6  # a condition that fails, by far more than either
TREE_COUNTS = (1, 1, 2, 4, 9, 20, 48, 115, 286)  # OEIS A000081, orders 1 to 9


def ctx():
    c = mpmath.MPContext()
    c.dps = DPS
    return c


# ---- reading the C tables --------------------------------------------------------------------


def c_double(node):
    """A C constant expression of literals, + - * / and parentheses, evaluated in double as the
    compiler folds it (a decimal literal is the nearest double: Python's float() of its text)."""
    if isinstance(node, ast.Expression):
        return c_double(node.body)
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        return float(node.value)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        v = c_double(node.operand)
        return -v if isinstance(node.op, ast.USub) else v
    if isinstance(node, ast.BinOp):
        x, y = c_double(node.left), c_double(node.right)
        ops = {
            ast.Add: lambda: x + y,
            ast.Sub: lambda: x - y,
            ast.Mult: lambda: x * y,
            ast.Div: lambda: x / y,
        }
        if type(node.op) in ops:
            return ops[type(node.op)]()
    raise ValueError("not a constant expression of the tables: %s" % ast.dump(node))


def c_literal_value(text):
    # Python parses a C decimal literal's digits to the same nearest double; a literal with
    # more digits than a double holds is parsed from its text, never through a shorter repr
    text = text.strip()
    if re.fullmatch(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?", text):
        return float(text)
    return c_double(ast.parse(text, mode="eval"))


def c_array(source, name):
    m = re.search(r"static const double %s\[\] = \{(.*?)\};" % re.escape(name), source, re.S)
    assert m, "no table %s" % name
    body = re.sub(r"/\*.*?\*/", "", m.group(1), flags=re.S)
    return [c_literal_value(e) for e in body.split(",") if e.strip()]


def c_tableau(name):
    """(s, A, b, c, declared order) of src/maps/map_NAME.c, coefficients as doubles."""
    with open(os.path.join(MAPS, "map_%s.c" % name)) as f:
        source = f.read()
    s = int(re.search(r"static const sdae_rk_tableau %s = \{(\d+)," % name, source).group(1))
    order = int(re.search(r"\.name = \"%s\",\s*\.order = (\d+)," % name, source).group(1))
    a, b, c = (c_array(source, "%s_%s" % (name, part)) for part in "abc")
    assert len(a) == s * (s - 1) // 2 and len(b) == s and len(c) == s
    A = [[0.0] * s for _ in range(s)]
    k = 0
    for i in range(1, s):  # row i holds a_ij, j < i (map_rk.h)
        for j in range(i):
            A[i][j], k = a[k], k + 1
    return s, A, b, c, order


# ---- rooted trees ----------------------------------------------------------------------------


def grow(t):
    """Every tree made from t (a sorted tuple of its root's subtrees) by one more vertex."""
    out = {tuple(sorted(t + ((),)))}
    for i, u in enumerate(t):
        for g in grow(u):
            out.add(tuple(sorted(t[:i] + (g,) + t[i + 1 :])))
    return out


def trees_by_order(n):
    by = {1: {()}}
    for q in range(2, n + 1):
        by[q] = set().union(*(grow(t) for t in by[q - 1]))
    return {q: sorted(ts) for q, ts in by.items()}


def order_of(t):
    return 1 + sum(order_of(u) for u in t)


def density(t):
    return order_of(t) * math.prod(density(u) for u in t)


def weights(t, A, one, memo):
    """Phi(t), one value per stage (memo: the subtrees' already computed)."""
    if t not in memo:
        s = len(A)
        phi = [one] * s
        for u in t:
            pu = weights(u, A, one, memo)
            au = [sum((A[i][j] * pu[j] for j in range(i)), 0 * one) for i in range(s)]
            phi = [x * y for x, y in zip(phi, au)]
        memo[t] = phi
    return memo[t]


TREES = trees_by_order(9)


def test_trees_are_counted_by_a000081():
    assert tuple(len(TREES[q]) for q in range(1, 10)) == TREE_COUNTS
    assert sum(len(TREES[q]) for q in range(1, 9)) == 200
    # the bushy and the tall tree of order 4: gamma = 4 and 4 * 3 * 2 = 24
    assert density(((), (), ())) == 4 and density(((((),),),)) == 24


# ---- the conditions --------------------------------------------------------------------------


def residuals(A, b, q):
    """[(tree, sum_i b_i Phi_i(t) - 1/gamma(t))] for the trees of order q, in 50 digits."""
    c50 = ctx()
    Am = [[c50.mpf(x) for x in row] for row in A]
    bm = [c50.mpf(x) for x in b]
    one = c50.mpf(1)
    memo = {}
    return [
        (t, c50.fsum(x * y for x, y in zip(bm, weights(t, Am, one, memo))) - one / density(t))
        for t in TREES[q]
    ]


def worst(A, b, orders):
    return max(abs(r) for q in orders for _, r in residuals(A, b, q))


@pytest.mark.parametrize("name", ["rk4", "rk8"])
def test_declared_order_is_the_references(name):
    assert c_tableau(name)[4] == tableaus.ORDER[name]


@pytest.mark.parametrize("name", ["rk4", "rk8"])
def test_published_tableau_has_the_order(name):
    """The method itself, as published (the reference's tableau in 50 digits)."""
    A, b, _ = tableaus.tableau(name, arith.MP(DPS))
    p = tableaus.ORDER[name]
    assert worst(A, b, range(1, p + 1)) < PUBLISHED
    assert worst(A, b, [p + 1]) > FAILS


@pytest.mark.parametrize("name", ["rk4", "rk8"])
def test_every_condition_up_to_the_order_holds_to_rounding(name):
    _, A, b, _, p = c_tableau(name)
    for q in range(1, p + 1):
        for t, r in residuals(A, b, q):
            assert abs(r) < ROUNDING, "%s: tree %s of order %d: residual %s" % (
                name,
                t,
                q,
                mpmath.nstr(r, 3),
            )


@pytest.mark.parametrize("name", ["rk4", "rk8"])
def test_a_condition_of_the_next_order_fails(name):
    _, A, b, _, p = c_tableau(name)
    assert worst(A, b, [p + 1]) > FAILS, "%s satisfies every condition of order %d" % (name, p + 1)


@pytest.mark.parametrize("name", ["rk4", "rk8"])
def test_nodes_are_the_row_sums(name):
    c50 = ctx()
    s, A, _, c, _ = c_tableau(name)
    assert c[0] == 0.0
    for i in range(s):
        r = c50.fsum(c50.mpf(x) for x in A[i]) - c50.mpf(c[i])
        bound = 1.01 * U * (abs(c[i]) + sum(abs(x) for x in A[i])) + PUBLISHED
        assert abs(r) <= bound, "%s: c_%d - sum_j a_%dj = %s" % (name, i + 1, i + 1, r)


@pytest.mark.parametrize("name", ["rk4", "rk8"])
def test_reference_tableau_is_the_c_one(name):
    """Entry by entry, the C double is the published number rounded to the nearest double
    (|C - ref| <= u |ref|), the zeros in the same places, and the reference in float64 is the
    same doubles."""
    s, A, b, c, _ = c_tableau(name)
    Am, bm, cm = tableaus.tableau(name, arith.MP(DPS))
    Af, bf, cf = tableaus.tableau(name, arith.Float64())
    assert len(bm) == s
    pairs = [
        (A[i][j], Am[i][j], Af[i][j], "a%d%d" % (i + 1, j + 1)) for i in range(s) for j in range(s)
    ]
    pairs += [(b[i], bm[i], bf[i], "b%d" % (i + 1)) for i in range(s)]
    pairs += [(c[i], cm[i], cf[i], "c%d" % (i + 1)) for i in range(s)]
    c50 = ctx()
    for x, ref, ref64, label in pairs:
        ref = c50.mpf(ref)
        assert abs(c50.mpf(x) - ref) <= U * abs(ref), "%s %s: C %r, reference %s" % (
            name,
            label,
            x,
            ref,
        )
        assert x == ref64, "%s %s: C %r, reference in float64 %r" % (name, label, x, ref64)
