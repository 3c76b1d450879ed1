# SPDX-License-Identifier: GPL-3.0-or-later
"""A Mechanism as C99: name.h (the params struct, its tables and five functions) and name.c
(the callbacks of sdae_mbs, each one's expressions with their common subexpressions eliminated
by sympy's cse). No globals, no allocation; every argument a callback does not use is cast to
void."""

from __future__ import annotations

from collections.abc import Container, Iterator
from typing import TYPE_CHECKING, cast

import sympy as sp
from sympy.printing.c import C99CodePrinter
from sympy.printing.codeprinter import PrintMethodNotImplementedError
from sympy.printing.precedence import precedence

from .errors import ModelError

if TYPE_CHECKING:
    from .mechanism import Expr, Matrix, Mechanism, Symbol

ARGUMENTS = {
    "tq": "double t, const double *q",
    "tqv": "double t, const double *q, const double *v",
}
# sdae_mbs' callbacks in the order of its fields, each with what it computes
CALLBACKS = {
    "mass": "M(t, q), n_q x n_q",
    "force": "F(t, q, v) = Q - dV/dq + dT/dq - (d2T/dv dq) v - d2T/dv dt - D v",
    "constraint": "c(t, q)",
    "jacobian": "G = dc/dq, n_c x n_q",
    "constraint_t": "dc/dt",
    "potential": "V(q)",
    "damping": "D(q), n_q x n_q",
    "mass_dot_v": "(d/ds M(t + s, q + s v)) v",
    "jacobian_dot": "d/ds G(t + s, q + s v)",
    "constraint_t_dot": "d/ds (dc/dt)(t + s, q + s v)",
    "input_force": "Q(t, q, v), the forces given as force=, not the Lagrangian's",
}


# the powers written as products (of a temporary, where the base is not a symbol): pow(x, 2) is
# not exact in every libm and is slower where the compiler does not expand it
PRODUCT_POWERS = frozenset(sp.Rational(k, 2) for k in (4, 6, 8, 3, -4, -6, -8, -3))


# this many zero entries of a callback's output and more are written by a loop and the others
# one by one: the 8000 zero stores of a 64-coordinate chain's mass matrix and jacobians, one
# statement each, took GCC 12 s to compile at -O2
ZERO_LOOP = 16


class _Printer(C99CodePrinter):  # type: ignore[misc]  # sympy ships no types: its class is Any
    """C99 with the powers of PRODUCT_POWERS as products, square roots as sqrt, and constants
    such as pi as their doubles (<math.h>'s M_PI is not C99)."""

    def __init__(self) -> None:
        super().__init__({"strict": True, "math_macros": {}})

    def _print_Pow(self, expr: Expr) -> str:
        base, e = expr.base, expr.exp
        b = self.parenthesize(base, precedence(expr))
        if e in PRODUCT_POWERS:
            factors = [b] * int(abs(e)) + ([f"sqrt({b})"] if not e.is_Integer else [])
            # in parentheses: sympy prints a Mul's denominator as "/" and this, unbracketed
            product = "(" + "*".join(factors) + ")"
            return product if e > 0 else f"1.0/{product}"
        if e == -1:
            return f"1.0/{b}"
        if e == sp.Rational(1, 2):
            return f"sqrt({self._print(base)})"
        if e == -sp.Rational(1, 2):
            return f"1.0/sqrt({self._print(base)})"
        return cast(str, super()._print_Pow(expr))

    def _print_NumberSymbol(self, expr: Expr) -> str:
        return _c_double(expr)

    _print_Pi = _print_Exp1 = _print_GoldenRatio = _print_EulerGamma = _print_Catalan = (
        _print_NumberSymbol
    )


def _name_bases(
    temps: list[tuple[Symbol, Expr]], reduced: list[Expr], symbols: Iterator[Symbol]
) -> tuple[list[tuple[Symbol, Expr]], list[Expr]]:
    """cse's result with the base of every power written as a product (PRODUCT_POWERS) a
    temporary of its own, unless it is a symbol: cse names only what occurs twice, and a
    product repeats its base."""
    named, out = {}, []

    def name(expr: Expr) -> Expr:
        def base_of(p: Expr) -> Expr:
            if p.base not in named:
                named[p.base] = next(symbols)
                out.append((named[p.base], p.base))
            return named[p.base] ** p.exp

        return expr.replace(
            lambda x: x.is_Pow and x.exp in PRODUCT_POWERS and not x.base.is_Atom, base_of
        )

    for sym, e in temps:
        e = name(e)
        out.append((sym, e))
    return out, [name(e) for e in reduced]


class _Names:
    """The C spellings of t, q_i, v_i and the params, as Symbols whose names print as such."""

    def __init__(self, mech: Mechanism) -> None:
        self.t = sp.Symbol("t", real=True)
        self.map = {mech.t: self.t}
        self.q = [sp.Symbol(f"q[{i}]", real=True) for i in range(mech.n)]
        self.v = [sp.Symbol(f"v[{i}]", real=True) for i in range(mech.n)]
        self.p = [sp.Symbol(f"p->{s.name}", real=True) for s in mech.params]
        self.map.update(zip(mech.q, self.q))
        self.map.update(zip(mech.v, self.v))
        self.map.update(zip(mech.params, self.p))

    def uses(self, exprs: list[Expr]) -> dict[str, bool]:
        """Which of t, q, v, p the expressions read."""
        free = set().union(*(e.free_symbols for e in exprs)) if exprs else set()
        return {
            "t": self.t in free,
            "q": any(s in free for s in self.q),
            "v": any(s in free for s in self.v),
            "p": any(s in free for s in self.p),
        }


def _body(
    printer: _Printer, names: _Names, targets: list[str], exprs: list[Expr], what: str
) -> tuple[list[str], dict[str, bool]]:
    """The statements computing targets[k] = exprs[k] after cse, and what they read."""
    exprs = [e.xreplace(names.map) for e in exprs]
    symbols = sp.numbered_symbols("w")
    temps, reduced = sp.cse(exprs, symbols=symbols, order="none")
    temps, reduced = _name_bases(temps, reduced, symbols)
    uses = names.uses([e for _, e in temps] + list(reduced))
    lines = []
    try:
        for sym, e in temps:
            lines.append(f"  const double {sym} = {printer.doprint(e)};")
        for target, e in zip(targets, reduced):
            lines.append(f"  {target} = {printer.doprint(e)};")
    except PrintMethodNotImplementedError as err:
        raise ModelError(
            f"the {what}: {str(err).splitlines()[0]} (a function sympy cannot print in C)"
        ) from None
    except (ValueError, TypeError) as err:  # a Piecewise without a default, say
        raise ModelError(f"the {what} cannot be printed in C: {err}") from None
    return lines, uses


def _unused(names: list[str]) -> list[str]:
    """The statement casting the unused arguments to void, if any."""
    return ["  " + ", ".join(f"(void){a}" for a in names) + ";"] if names else []


def _prologue(name: str, uses: dict[str, bool], args: list[str]) -> list[str]:
    """A callback's first lines: its params as the struct, its unused arguments cast to void."""
    lines = [f"  const {name}_params *p = params;"] if uses["p"] else []
    return lines + _unused([a for a in args if not uses[a]] + ([] if uses["p"] else ["params"]))


# the callbacks that write a matrix by the nonzeros of a pattern, for a sparse mechanism
PATTERN_OF = {"mass": "mass", "damping": "mass", "jacobian": "jacobian", "jacobian_dot": "jacobian"}


def _callback(
    mech: Mechanism,
    printer: _Printer,
    names: _Names,
    field: str,
    spec: tuple[str, str, Matrix],
    pattern: list[list[int]] | None = None,
) -> str:
    """The C function of a callback; with a pattern (its rows' columns), the matrix's entries
    there alone, in the pattern's order."""
    args, out, matrix = spec
    if pattern is None:
        exprs = list(matrix)
    else:
        exprs = [matrix[i, j] for i, cols in enumerate(pattern) for j in cols]
    targets = [f"{out}[{k}]" for k in range(len(exprs))]
    fill = []
    if sum(e == 0 for e in exprs) >= ZERO_LOOP:
        fill = [f"  for (size_t k = 0; k < {len(exprs)}; k++) {out}[k] = 0;"]
        kept = [k for k, e in enumerate(exprs) if e != 0]
        targets, exprs = [targets[k] for k in kept], [exprs[k] for k in kept]
    lines, uses = _body(printer, names, targets, exprs, field.replace("_", " "))
    lines = fill + lines
    signature = f"static int {mech.name}_{field}({ARGUMENTS[args]}, double *{out}, void *params)"
    head = [f"/* {CALLBACKS[field]} */", signature + " {"]
    head += _prologue(mech.name, uses, ["t", "q"] + (["v"] if args == "tqv" else []))
    return "\n".join(head + lines + ["  return 0;", "}"])


def _start(mech: Mechanism, printer: _Printer, names: _Names) -> str:
    exprs = list(mech.q0) + list(mech.v0)
    targets = [f"q0[{k}]" for k in range(mech.n)] + [f"v0[{k}]" for k in range(mech.n)]
    body, uses = _body(printer, names, targets, exprs, "start state")
    head = f"void {mech.name}_start(const {mech.name}_params *p, double *q0, double *v0) {{"
    return "\n".join([head] + _unused([] if uses["p"] else ["p"]) + body + ["}"])


def _c_double(value: Expr) -> str:
    """The double nearest the number, in the shortest digits that read back as it."""
    return repr(float(value))


def _params_default(mech: Mechanism) -> str:
    lines = [f"void {mech.name}_params_default({mech.name}_params *p) {{"]
    if not mech.params:
        lines.append("  p->none = 0;")
    for s in mech.params:
        lines.append(f"  p->{s.name} = {_c_double(mech.defaults[s])};")
    return "\n".join(lines + ["}"])


def _coordinate_name(mech: Mechanism) -> str:
    lines = [f"const char *{mech.name}_coordinate_name(size_t i) {{", "  switch (i) {"]
    for i, s in enumerate(mech.coordinate_names):
        lines.append(f"    case {i}: return {_c_string(s)};")
    return "\n".join(lines + ["    default: return NULL;", "  }", "}"])


def _numbers(values: list[int]) -> list[str]:
    """Numbers as the lines of a C initializer, a few to a line."""
    per = 16
    return [
        " " * 4 + ", ".join(str(x) for x in values[k : k + per]) + ","
        for k in range(0, len(values), per)
    ] or ["    0,"]


def _pattern(mech: Mechanism, what: str, rows: list[list[int]], description: str) -> str:
    """A pattern (rows' ascending columns) as the static arrays and sdae_pattern of name.c."""
    name = f"{mech.name}_{what}"
    starts, cols = [0], []
    for r in rows:
        cols += r
        starts.append(len(cols))
    return "\n".join(
        [
            f"/* {description}: row i's columns are {name}_col[{name}_row_start[i]] .. "
            f"{name}_col[{name}_row_start[i + 1] - 1] */",
            f"static const size_t {name}_row_start[{len(starts)}] = {{",
            *_numbers(starts),
            "};",
            f"static const size_t {name}_col[{max(1, len(cols))}] = {{",
            *_numbers(cols),
            "};",
            f"static const sdae_pattern {name}_pattern = {{{len(cols)}, {name}_row_start, {name}_col}};",
        ]
    )


def _system(mech: Mechanism, fields: Container[str]) -> str:
    """name_mbs: the struct by designated initializers, every callback named (NULL where the
    description has none), so that a reader sees which the library gets; a sparse mechanism's
    patterns."""
    lines = [
        f"sdae_mbs {mech.name}_mbs({mech.name}_params *p) {{",
        "  sdae_mbs sys = {",
        f"      .n_q = {mech.n},",
        f"      .n_c = {len(mech.c)},",
    ]
    for field in CALLBACKS:
        value = f"{mech.name}_{field}" if field in fields else "NULL"
        lines.append(f"      .{field} = {value},")
    for what in ("mass", "jacobian"):
        value = f"&{mech.name}_{what}_pattern" if mech.sparse else "NULL"
        lines.append(f"      .{what}_pattern = {value},")
    return "\n".join(lines + ["      .params = p,", "  };", "  return sys;", "}"])


def _comment(text: str) -> str:
    """One line of text inside a C comment: a */ in it would end the comment."""
    return text.replace("*/", "* /")


def _c_string(text: str) -> str:
    """text as a C string literal: quotes and backslashes escaped, and every ? that follows a ?
    written \\? so that no trigraph (??/ is a backslash under -std=c99) forms."""
    out, previous = [], ""
    for ch in text:
        if ch in "\\\"" or (ch == "?" and previous == "?"):
            out.append("\\")
        out.append(ch)
        previous = ch
    return '"' + "".join(out) + '"'


def _tables(mech: Mechanism) -> list[str]:
    """The parameters as an X-macro, X(field, default, "description", "unit") each, and the
    coordinates' names and units as initializers: tables for code that describes the mechanism
    generically (an FMU's variables, a command line's flags) without the generator knowing it.
    The macro's own parameter is SDAE_X, a name no parameter may have (the prefix is the
    library's): one named X would be replaced by the caller's macro in X(X, ...)."""
    N = mech.name.upper()
    rows = [
        f"  SDAE_X({s.name}, {_c_double(mech.defaults[s])}, "
        f"{_c_string(mech.descriptions[s])}, {_c_string(mech.units[s])})"
        for s in mech.params
    ]
    lines = [
        "/* the parameters: X(field, default, \"description\", \"unit\") for each field of "
        f"{mech.name}_params (\"\": no unit) */",
        f"#define {N}_PARAMETERS(SDAE_X)" + (" \\" if rows else ""),
    ]
    lines += [r + " \\" for r in rows[:-1]] + rows[-1:]
    names = ", ".join(_c_string(s) for s in mech.coordinate_names)
    units = ", ".join(_c_string(s) for s in mech.coordinate_units)
    lines += [
        "/* the coordinates' names and units, initializers of n_q strings (\"\": no unit) */",
        f"#define {N}_COORDINATE_NAMES {{{names}}}",
        f"#define {N}_COORDINATE_UNITS {{{units}}}",
    ]
    return lines


def header(mech: Mechanism, banner: str) -> str:
    N = mech.name.upper()
    guard = f"{N}_H"
    fields = [
        f"  double {s.name};"
        + (f" /* {_comment(mech.descriptions[s])} */" if mech.descriptions[s] else "")
        for s in mech.params
    ]
    if not fields:
        fields = ["  int none; /* the mechanism has no parameters */"]
    return "\n".join(
        [
            banner,
            f"#ifndef {guard}",
            f"#define {guard}",
            "",
            "#include <stddef.h>",
            "",
            "#include <stabdae/mbs.h>",
            "",
            "#ifdef __cplusplus",
            'extern "C" {',
            "#endif",
            "",
            f"#define {N}_N_Q {mech.n} /* coordinates */",
            f"#define {N}_N_C {len(mech.c)} /* constraints */",
            f"#define {N}_N_PARAMS {len(mech.params)} /* parameters, the fields of {mech.name}_params */",
            f"/* 1: M, D, G and dG/ds are written by their nonzeros in the patterns of {mech.name}_mbs's "
            "mass_pattern and jacobian_pattern; 0: dense */",
            f"#define {N}_SPARSE {int(mech.sparse)}",
            "",
            *_tables(mech),
            "",
            f"typedef struct {mech.name}_params {{",
            *fields,
            f"}} {mech.name}_params;",
            "",
            "/* the defaults of the description */",
            f"void {mech.name}_params_default({mech.name}_params *p);",
            "/* the mechanism with its callbacks; p must outlive its use */",
            f"sdae_mbs {mech.name}_mbs({mech.name}_params *p);",
            "/* the start state at t = 0, n_q values each */",
            f"void {mech.name}_start(const {mech.name}_params *p, double *q0, double *v0);",
            "/* the name of coordinate i < n_q; NULL beyond */",
            f"const char *{mech.name}_coordinate_name(size_t i);",
            "",
            "#ifdef __cplusplus",
            "}",
            "#endif",
            "",
            f"#endif /* {guard} */",
            "",
        ]
    )


def source(mech: Mechanism, banner: str) -> str:
    printer = _Printer()
    names = _Names(mech)
    callbacks = mech.callbacks()
    parts = [banner + f'#include "{mech.name}.h"\n\n#include <math.h>']
    # looked up by PATTERN_OF.get(field): None for a callback of no pattern
    patterns: dict[str | None, list[list[int]]] = {}
    if mech.sparse:
        patterns["mass"], patterns["jacobian"] = mech.patterns()
        parts.append(_pattern(mech, "mass", patterns["mass"], "M's and D's nonzeros"))
        parts.append(_pattern(mech, "jacobian", patterns["jacobian"], "G's and dG/ds's nonzeros"))
    for field in CALLBACKS:
        if field in callbacks:
            pattern = patterns.get(PATTERN_OF.get(field))
            parts.append(_callback(mech, printer, names, field, callbacks[field], pattern))
    parts.append(_params_default(mech))
    parts.append(_system(mech, callbacks))
    parts.append(_start(mech, printer, names))
    parts.append(_coordinate_name(mech))
    return "\n\n".join(parts) + "\n"
