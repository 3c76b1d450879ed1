# SPDX-License-Identifier: GPL-3.0-or-later
"""A mechanism's symbolic description and what the library's callbacks compute from it.

Lagrange's equations for T(t, q, v) (at most quadratic in v), a potential V(q), other forces
Q(t, q, v) and a damping D(q), with p = dT/dv:

    d/dt p - dT/dq + dV/dq = Q - D v
    M v' = Q - dV/dq + dT/dq - (dp/dq) v - dp/dt - D v = F,     M = d2T/dv2

(dp/dt the partial derivative in t; 0 when T does not depend on t). Every callback of
<stabdae/mbs.h> is an expression here; the derivatives along the motion are derivatives in s
of (t + s, q + s v) at s = 0, v held fixed.
"""

from __future__ import annotations

import random
import re
from collections.abc import Iterable, Sequence
from typing import Any

import mpmath
import sympy as sp
from sympy.core.function import AppliedUndef

from .errors import ModelError

# sympy ships no types: its expressions, Symbols and Matrices are Any to mypy, named for the reader
Expr = Any
Symbol = Any
Matrix = Any

# C99, C11 and C23 keywords (C23, gcc 15's default, makes bool, true, false, ... keywords), and
# GNU C's asm and typeof (keywords under gcc's default -std=gnu17)
C_KEYWORDS = frozenset(
    """auto break case char const continue default do double else enum extern float for goto if
    inline int long register restrict return short signed sizeof static struct switch typedef
    union unsigned void volatile while _Alignas _Alignof _Atomic _Bool _Complex _Generic
    _Imaginary _Noreturn _Static_assert _Thread_local alignas alignof bool constexpr false
    nullptr static_assert thread_local true typeof typeof_unqual _BitInt _Decimal32 _Decimal64
    _Decimal128 asm""".split()
)
# C++20's keywords and alternative tokens beyond C's: the header is included from C++ too
CPP_KEYWORDS = frozenset(
    """and and_eq bitand bitor catch char8_t char16_t char32_t class co_await co_return co_yield
    compl concept const_cast consteval constinit decltype delete dynamic_cast explicit export
    friend mutable namespace new noexcept not not_eq operator or or_eq private protected public
    reinterpret_cast requires static_cast template this throw try typeid typename using virtual
    wchar_t xor xor_eq""".split()
)
# the system-specific macros GCC predefines outside the reserved namespace in its GNU modes (the
# default, -std=gnu17): linux and unix on Linux, i386 on 32-bit x86, the others on other
# targets; `double linux;` is `double 1;` there
SYSTEM_MACROS = frozenset(
    """linux unix i386 sun sparc mips MIPSEB MIPSEL R3000 R4000 vax mc68000 m68k PPC powerpc
    AVR BSD""".split()
)
# a mechanism of this many coordinates or more is written sparse unless its description says
# (sparse=False): its M and G by their structural nonzeros in patterns, the generated file
# growing with them and not with n^2 (a 32-rod chain's dense file held 8000 zero stores)
SPARSE_FROM = 16

C_IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
# the stems of C11's standard headers: a generated name.h on the include path would hide one
C_HEADERS = frozenset(
    """assert complex ctype errno fenv float inttypes iso646 limits locale math setjmp signal
    stdalign stdarg stdatomic stdbool stddef stdint stdio stdlib stdnoreturn string tgmath
    threads time uchar wchar wctype""".split()
)
# names a generated file cannot use: object-like macros of the headers it includes (<stddef.h>,
# <math.h>, and the M_ constants of POSIX and GNU) would replace a field p->NAME, and the
# library's own prefixes would clash with <stabdae/mbs.h>
C_MACROS = frozenset(
    """NULL NAN INFINITY HUGE_VAL HUGE_VALF HUGE_VALL FP_INFINITE FP_NAN FP_NORMAL FP_SUBNORMAL
    FP_ZERO FP_ILOGB0 FP_ILOGBNAN FP_FAST_FMA FP_FAST_FMAF FP_FAST_FMAL MATH_ERRNO
    MATH_ERREXCEPT math_errhandling errno EDOM ERANGE EILSEQ""".split()
)
RESERVED_PREFIXES = ("M_", "sdae", "SDAE", "stabdae", "STABDAE")
# the start state may violate the constraints by this much at most (absolute)
START_TOL = 1e-10
# digits of the checks at the start state
CHECK_DPS = 30


def check_identifier(name: object, what: str) -> str:
    """A C identifier that compiles as a name of its own in C99, GNU C and C++: not a keyword of
    either, not reserved, not a macro the compiler predefines or the headers a generated file
    includes define, not of the library's prefixes; or ModelError naming `what`."""
    if not isinstance(name, str) or not C_IDENTIFIER.match(name):
        raise ModelError(f"{what} {name!r} is not a C identifier")
    if name in C_KEYWORDS:
        raise ModelError(f"{what} {name!r} is a C keyword")
    if name in CPP_KEYWORDS:
        raise ModelError(f"{what} {name!r} is a C++ keyword (the header is included from C++)")
    if name.startswith("__") or re.match(r"_[A-Z]", name) or "__" in name:
        raise ModelError(
            f"{what} {name!r} is reserved in C (a name beginning with two "
            "underscores or an underscore and a capital letter) or in C++ (one "
            "holding two underscores)"
        )
    if name in SYSTEM_MACROS:
        raise ModelError(f"{what} {name!r} is a macro GCC predefines (as linux, unix, i386)")
    if name in C_MACROS or name.startswith(RESERVED_PREFIXES):
        raise ModelError(
            f"{what} {name!r} is reserved (a macro of <math.h> or <stddef.h>, or "
            "the prefix M_, sdae or stabdae)"
        )
    return name


# a unit, for the FMI unit attributes: a short word of SI symbols and operators ("kg", "m/s^2",
# "N.m", "rad/s"); the empty string is none
UNIT = re.compile(r"^[A-Za-z0-9/.*^-]{0,32}$")


def check_unit(unit: object, what: str) -> str:
    """A unit (UNIT), or ModelError naming `what`."""
    if not isinstance(unit, str) or not UNIT.match(unit):
        raise ModelError(
            f"{what} {unit!r} is not a unit (at most 32 of the characters A-Z a-z 0-9 / . * ^ -)"
        )
    return unit


def check_text(text: object, what: str) -> str:
    """One printable line (a description, a coordinate's name), or ModelError."""
    if not isinstance(text, str) or not text.isprintable():
        raise ModelError(f"{what} {text!r}: one line of printable characters")
    return text


def _symbols(seq: Iterable[Symbol], what: str) -> list[Symbol]:
    try:
        items = list(seq)
    except TypeError:
        raise ModelError(f"{what} must be a list of sympy Symbols") from None
    for s in items:
        if not isinstance(s, sp.Symbol):
            raise ModelError(f"{what}: {s!r} is not a sympy Symbol")
    return items


def _equation(expr: Expr) -> Expr:
    """An Eq(lhs, rhs) as lhs - rhs, anything else as it is."""
    return expr.lhs - expr.rhs if isinstance(expr, sp.Equality) else expr


def _vector(expr: Expr, n: int, what: str) -> Matrix:
    """expr as a column Matrix of n entries (a list, tuple or Matrix), or ModelError."""
    try:
        m = sp.Matrix(expr) if not isinstance(expr, sp.MatrixBase) else expr
    except (TypeError, ValueError, sp.SympifyError):
        raise ModelError(f"{what} must be a list or Matrix of {n} expressions") from None
    if m.shape not in ((n, 1), (1, n)):
        raise ModelError(
            f"{what} has {len(m)} entries ({m.shape[0]} x {m.shape[1]}), "
            f"not {n} (one per coordinate)"
        )
    return m.reshape(n, 1)


def _square(expr: Expr, n: int, what: str) -> Matrix:
    try:
        m = sp.Matrix(expr)
    except (TypeError, ValueError, sp.SympifyError):
        raise ModelError(f"{what} must be an {n} x {n} Matrix") from None
    if m.shape != (n, n):
        raise ModelError(f"{what} is {m.shape[0]} x {m.shape[1]}, not {n} x {n}")
    return m


def _sympify(expr: object, what: str) -> Expr:
    """One scalar expression, or ModelError."""
    try:
        e = sp.sympify(expr)
    except (sp.SympifyError, TypeError, ValueError):
        raise ModelError(f"{what} is not a sympy expression: {expr!r}") from None
    if not isinstance(e, sp.Expr):
        raise ModelError(f"{what} must be one expression, not a {type(e).__name__}")
    return e


class Mechanism:
    """A mechanism M(t, q) v' = F(t, q, v) - G^T lambda, c(t, q) = 0, from its Lagrangian.

    name: a C identifier, the generated files' stem and their functions' prefix.
    t, q, v: sympy Symbols, time, coordinates q_1..q_n, velocities v_1..v_n.
    kinetic: T(t, q, v), at most quadratic in v (M is its Hessian in v); or mass=M (n x n),
      T = v^T M v / 2.
    potential: V(q); forces -dV/dq.
    force: other generalized forces Q(t, q, v), n entries.
    damping: D(q), n x n: forces -D v.
    constraints: c(t, q), n_c expressions, 1 <= n_c < n.
    params: Symbol -> default value, or Symbol -> (default, description).
    q0, v0: the start state at t = 0 (numbers or expressions of the params; None: zeros).
    coordinate_names: n names (default: the names of q).
    units: param Symbol -> unit ("kg", "m/s^2"; the FMI unit attributes); params not named
      have none ("").
    coordinate_units: n units, one per coordinate, or a dict coordinate Symbol -> unit (those
      not named have none).
    sparse: True writes M, D, G and dG/ds by their structural nonzeros (the library's
      mass_pattern and jacobian_pattern), False densely; None (the default) sparse from
      SPARSE_FROM coordinates on.

    The library is told of the potential (and damping), which enables the discrete-gradient
    maps, when F without the `force` terms is exactly the Lagrangian's: T = v^T M v / 2 (no
    terms linear in v or free of v) with M not depending on t. The `force` terms Q, forces from
    outside the Lagrangian, then go into the callback input_force, which the library adds to F
    as a port of the energy balance, and `force` keeps the Lagrangian's forces
    -dV/dq + dT/dq - (d2T/dv dq) v - D v.
    Otherwise V, D v and Q are all part of F and no potential is declared: with T depending on
    t (or linear in v) the energy v^T M v / 2 + V is not what the Lagrangian's motion keeps (the
    terms in d2T/dv dt do work), so no discrete gradient applies and nothing is gained by
    keeping Q apart. A description with `force` but neither a potential nor a damping keeps its
    forces in F as well (car_axis: every force given as such): there is no potential to
    declare.
    """

    # the description as __init__ and its checks leave it
    name: str
    t: Symbol
    q: list[Symbol]
    v: list[Symbol]
    n: int
    params: list[Symbol]
    defaults: dict[Symbol, Expr]
    descriptions: dict[Symbol, str]
    T: Expr
    V: Expr
    p: Matrix
    M: Matrix
    homogeneous: bool
    Q: Matrix | None
    D: Matrix | None
    c: Matrix
    coordinate_names: list[str]
    units: dict[Symbol, str]
    coordinate_units: list[str]
    q0: Matrix
    v0: Matrix
    sparse: bool
    declares_potential: bool
    _G: Matrix | None
    _by_name: dict[str, Symbol]

    def __init__(
        self,
        name: str,
        t: Symbol,
        q: Iterable[Symbol],
        v: Iterable[Symbol],
        kinetic: Expr | None = None,
        potential: Expr = 0,
        force: Expr | None = None,
        damping: Expr | None = None,
        constraints: Iterable[Expr] = (),
        params: dict[Symbol, Any] | None = None,
        q0: Expr | None = None,
        v0: Expr | None = None,
        coordinate_names: Iterable[str] | None = None,
        mass: Expr | None = None,
        units: dict[Symbol, str] | None = None,
        coordinate_units: Iterable[str] | dict[Symbol, str] | None = None,
        sparse: bool | None = None,
    ) -> None:
        self.name = check_identifier(name, "the name")
        if name in C_HEADERS:
            raise ModelError(
                f"the name {name!r} would make {name}.h, which hides the C "
                f"standard header <{name}.h>"
            )
        if not isinstance(t, sp.Symbol):
            raise ModelError(f"t: {t!r} is not a sympy Symbol")
        self.t = t
        self.q = _symbols(q, "q")
        self.v = _symbols(v, "v")
        n = len(self.q)
        if len(self.v) != n:
            raise ModelError(f"q has {n} coordinates but v has {len(self.v)} velocities")
        if n == 0:
            raise ModelError("q is empty: a mechanism needs coordinates")
        if len(set(self.q) | set(self.v) | {t}) != 2 * n + 1:
            raise ModelError("t, q and v must be distinct Symbols")
        self.n = n
        self._G = None
        self._params(params or {})
        both = set(self.params) & (set(self.q) | set(self.v) | {t})
        if both:
            raise ModelError(f"params: {_listing(both)} is also t, a coordinate or a velocity")
        self._make_real()
        self._energy(kinetic, mass)
        self.V = self._real(_sympify(potential, "potential"))
        self._forces(force, damping)
        self._constraints(constraints)
        self.coordinate_names = self._names(coordinate_names)
        self._units(units, coordinate_units)
        self.q0 = self._start(q0, "q0")
        self.v0 = self._start(v0, "v0")
        if sparse not in (None, True, False):
            raise ModelError(f"sparse: {sparse!r} is not True, False or None (by the size)")
        self.sparse = self.n >= SPARSE_FROM if sparse is None else sparse
        self._check_symbols()
        # the class's docstring says why
        self.declares_potential = (
            self.homogeneous
            and not self.M.has(t)
            and (self.Q is None or self.V != 0 or self.D is not None)
        )
        self._check_start()

    # ---- the description, checked ---------------------------------------------------------

    def _make_real(self) -> None:
        """t, q, v and the params as real Symbols of their names, in every expression from here
        on (a symbol of the same name is the same variable in C): derivatives of Abs or sign
        then stay real functions that C can print."""
        self._by_name = {
            s.name: sp.Symbol(s.name, real=True) for s in [self.t, *self.q, *self.v, *self.params]
        }
        self.t = self._by_name[self.t.name]
        self.q = [self._by_name[s.name] for s in self.q]
        self.v = [self._by_name[s.name] for s in self.v]
        real = [self._by_name[s.name] for s in self.params]
        self.defaults = {r: self.defaults[s] for r, s in zip(real, self.params)}
        self.descriptions = {r: self.descriptions[s] for r, s in zip(real, self.params)}
        self.params = real

    def _real(self, expr: Expr) -> Expr:
        """expr in the real Symbols of _make_real."""
        swap = {
            s: self._by_name[s.name]
            for s in expr.free_symbols
            if isinstance(s, sp.Symbol) and s.name in self._by_name
        }
        return expr.xreplace(swap)

    def _params(self, params: dict[Symbol, Any]) -> None:
        if not isinstance(params, dict):
            raise ModelError("params must be a dict Symbol -> value")
        self.params, self.defaults, self.descriptions = [], {}, {}
        seen = set()
        for sym, value in params.items():
            if not isinstance(sym, sp.Symbol):
                raise ModelError(f"params: key {sym!r} is not a sympy Symbol")
            check_identifier(sym.name, "the parameter")
            if sym.name.startswith(self.name.upper() + "_"):
                raise ModelError(
                    f"the parameter {sym.name!r} is reserved (the prefix "
                    f"{self.name.upper()}_ of the generated header's macros)"
                )
            if sym.name in seen:
                raise ModelError(f"params: two parameters are named {sym.name!r}")
            seen.add(sym.name)
            description = ""
            if isinstance(value, tuple):
                if len(value) != 2 or not isinstance(value[1], str):
                    raise ModelError(f"params: {sym.name} must be a value or (value, description)")
                value, description = value
                check_text(description, f"the description of {sym.name}")
            number = _sympify(value, f"the value of {sym.name}")
            if not number.is_number or not number.is_real or not number.is_finite:
                raise ModelError(f"params: {sym.name} = {value!r} is not a finite real number")
            self.params.append(sym)
            self.defaults[sym] = number
            self.descriptions[sym] = description

    def _energy(self, kinetic: Expr | None, mass: Expr | None) -> None:
        v = self.v
        if (kinetic is None) == (mass is None):
            raise ModelError("give exactly one of kinetic (T) and mass (M)")
        if mass is not None:
            M = self._real(_square(mass, self.n, "mass"))
            if M.has(*v):
                raise ModelError("mass depends on v")
            self._symmetric(M, "mass")
            self.M = M
            vv = sp.Matrix(v)
            self.T = (vv.T * M * vv)[0, 0] / 2
            self.p = M * vv
            self.homogeneous = True
            return
        T = self._real(_sympify(kinetic, "kinetic"))
        try:
            poly = sp.Poly(T, *v)
        except sp.PolynomialError:
            poly = None
        if poly is None or poly.total_degree() > 2 or any(c.has(*v) for c in poly.coeffs()):
            raise ModelError(
                "the kinetic energy is not quadratic in v (a polynomial of degree "
                "at most 2 in the velocities)"
            )
        self.T = T
        # p = dT/dv once, and M = dp/dv from it: sympy's hessian differentiates all of T n^2
        # times (seconds at 64 coordinates)
        self.p = sp.Matrix([T.diff(vi) for vi in v])
        self.M = _jacobian(self.p, v)
        self.homogeneous = all(sum(m) == 2 for m in poly.monoms())

    def _forces(self, force: Expr | None, damping: Expr | None) -> None:
        if self.V.has(*self.v) or self.V.has(self.t):
            raise ModelError(
                "the potential depends on "
                + ("v" if self.V.has(*self.v) else "t")
                + ": V(q) only (give such forces as force=)"
            )
        self.Q = None if force is None else self._real(_vector(force, self.n, "force"))
        if damping is None:
            self.D = None
            return
        D = self._real(_square(damping, self.n, "damping"))
        if D.has(*self.v) or D.has(self.t):
            raise ModelError(
                "damping depends on " + ("v" if D.has(*self.v) else "t") + ": D(q) only"
            )
        self._symmetric(D, "damping")
        self.D = D

    def _symmetric(self, A: Matrix, what: str) -> None:
        """A = A^T, by expansion, else at random points (expand misses identities such as
        sin^2 + cos^2 = 1)."""
        pairs = [
            (i, j)
            for i in range(self.n)
            for j in range(i + 1, self.n)
            if sp.expand(A[i, j] - A[j, i]) != 0
        ]
        rng = random.Random(1)
        for i, j in pairs:
            for _ in range(3):
                point = {
                    s: sp.Float(rng.uniform(0.5, 1.5), CHECK_DPS)
                    for s in (A[i, j] - A[j, i]).free_symbols
                }
                a, b = (A[i, j].evalf(CHECK_DPS, subs=point), A[j, i].evalf(CHECK_DPS, subs=point))
                if abs(a - b) > 1e-20 * (1 + abs(a)):
                    raise ModelError(
                        f"{what} is not symmetric (entries {i + 1},{j + 1} and {j + 1},{i + 1})"
                    )

    def _constraints(self, constraints: Iterable[Expr]) -> None:
        try:
            c = [self._real(_sympify(_equation(e), "a constraint")) for e in constraints]
        except TypeError:
            raise ModelError("constraints must be a list of expressions") from None
        if not 1 <= len(c) < self.n:
            raise ModelError(
                f"{len(c)} constraints for {self.n} coordinates: the library needs 1 <= n_c < n_q"
            )
        for j, cj in enumerate(c):
            if not cj.has(*self.q):
                raise ModelError(f"constraint {j + 1} ({cj}) does not depend on q")
            if cj.has(*self.v):
                raise ModelError(f"constraint {j + 1} ({cj}) depends on v: c(t, q) only")
        self.c = sp.Matrix(c)

    def _names(self, names: Iterable[str] | None) -> list[str]:
        if names is None:
            names = [s.name for s in self.q]
        names = list(names)
        if len(names) != self.n or not all(isinstance(s, str) for s in names):
            raise ModelError(f"coordinate_names must be {self.n} strings, one per coordinate")
        for s in names:
            check_text(s, "the coordinate name")
        return names

    def _units(
        self,
        # whatever was given, checked here; the name holds the coordinates' units further down
        units: object,
        coordinate_units: Iterable[str] | dict[Symbol, str] | None,
    ) -> None:
        """self.units (param -> unit) and self.coordinate_units (n units), "" where none."""
        self.units = {s: "" for s in self.params}
        by_name = {s.name: s for s in self.params}
        if units is not None:
            if not isinstance(units, dict):
                raise ModelError("units must be a dict parameter Symbol -> unit")
            for sym, unit in units.items():
                if not isinstance(sym, sp.Symbol) or sym.name not in by_name:
                    raise ModelError(f"units: {sym!r} is not a parameter")
                self.units[by_name[sym.name]] = check_unit(unit, f"the unit of {sym.name}")
        if coordinate_units is None:
            self.coordinate_units = [""] * self.n
        elif isinstance(coordinate_units, dict):
            index = {s.name: i for i, s in enumerate(self.q)}
            self.coordinate_units = [""] * self.n
            for sym, unit in coordinate_units.items():
                if not isinstance(sym, sp.Symbol) or sym.name not in index:
                    raise ModelError(f"coordinate_units: {sym!r} is not a coordinate")
                self.coordinate_units[index[sym.name]] = check_unit(unit, f"the unit of {sym.name}")
        else:
            if isinstance(coordinate_units, str):
                raise ModelError(
                    f"coordinate_units must be {self.n} units or a dict "
                    "coordinate Symbol -> unit, not one string"
                )
            try:
                units = list(coordinate_units)
            except TypeError:
                raise ModelError(
                    f"coordinate_units must be {self.n} units or a dict coordinate Symbol -> unit"
                ) from None
            if len(units) != self.n:
                raise ModelError(
                    f"coordinate_units has {len(units)} entries, not {self.n} (one per coordinate)"
                )
            self.coordinate_units = [
                check_unit(u, f"the unit of {s.name}") for u, s in zip(units, self.q)
            ]

    def _start(self, value: Expr | None, what: str) -> Matrix:
        if value is None:
            return sp.zeros(self.n, 1)
        m = self._real(_vector(value, self.n, what))
        stray = m.free_symbols - set(self.params)
        if stray:
            raise ModelError(
                f"{what} depends on {_listing(stray)}: numbers or expressions of the params only"
            )
        return m

    def _check_symbols(self) -> None:
        known = set(self.q) | set(self.v) | {self.t} | set(self.params)
        parts = [
            ("kinetic energy", self.T),
            ("potential", self.V),
            ("constraints", self.c),
            ("start state", self.q0.col_join(self.v0)),
        ]
        if self.Q is not None:
            parts.append(("force", self.Q))
        if self.D is not None:
            parts.append(("damping", self.D))
        for what, expr in parts:
            stray = expr.free_symbols - known
            if stray:
                raise ModelError(f"{_listing(stray)} in the {what} has no value in params")
            undefined = list(expr.atoms(AppliedUndef))
            if undefined:
                raise ModelError(
                    f"the {what} calls {undefined[0].func}, a function with no "
                    "definition (sympy cannot print it in C)"
                )

    def _numeric(self, expr: Expr) -> Expr:
        """expr at t = 0, the start state and the defaults, to CHECK_DPS digits."""
        subs = dict(self.defaults)
        subs.update({self.t: 0})
        for qi, vi, a, b in zip(self.q, self.v, self.q0, self.v0):
            subs[qi] = a.xreplace(self.defaults)
            subs[vi] = b.xreplace(self.defaults)
        return expr.xreplace(subs).evalf(CHECK_DPS)

    def _check_start(self) -> None:
        with mpmath.workdps(CHECK_DPS):
            start = self._numeric(self.q0.col_join(self.v0))
            if not all(x.is_number and x.is_finite and x.is_real for x in start):
                raise ModelError("the start state is not finite real numbers at the defaults")
            M = self._numeric(self.M)
            try:
                mpmath.cholesky(mpmath.matrix(M.tolist()))
            except (ValueError, ZeroDivisionError, TypeError):
                raise ModelError(
                    "the mass matrix is not positive definite at the start state"
                ) from None
            for what, expr in (("c", self.c), ("G v + dc/dt", self.velocity_constraint())):
                values = self._numeric(expr)
                worst = max(range(len(values)), key=lambda j: abs(values[j]))
                if not values[worst].is_number or abs(values[worst]) > START_TOL:
                    raise ModelError(
                        f"the start state violates the constraints: {what} = "
                        f"{_float(values[worst]):.3g} at constraint {worst + 1} (more than "
                        f"{START_TOL:g})"
                    )
            G = self._numeric(self.jacobian())
            # the threshold once: sympy calls iszerofunc for every entry it visits, and a max
            # over G there made the check quadratic in G's size (a minute at 64 coordinates)
            zero = 1e-20 * (1 + max(abs(g) for g in G))
            rank = G.rank(iszerofunc=lambda x: abs(x) < zero)
            if rank < len(self.c):
                raise ModelError(
                    f"the constraints are redundant at the start state: their "
                    f"jacobian has rank {rank}, not {len(self.c)}"
                )

    # ---- the callbacks' expressions ----------------------------------------------------------

    def jacobian(self) -> Matrix:
        if self._G is None:  # the checks and the callbacks use it: formed once
            self._G = _jacobian(self.c, self.q)
        return self._G

    def constraint_t(self) -> Matrix:
        return self.c.diff(self.t)

    def velocity_constraint(self) -> Matrix:
        return self.jacobian() * sp.Matrix(self.v) + self.constraint_t()

    def along(self, expr: Expr) -> Expr:
        """d/ds expr(t + s, q + s v) at s = 0, v held fixed (of each entry of a Matrix)."""
        if isinstance(expr, sp.MatrixBase):
            return expr.applyfunc(self.along)
        free = expr.free_symbols
        # in the symbols the expression holds only: most entries of a large mechanism's G hold
        # two coordinates of many
        terms = [expr.diff(self.t)] if self.t in free else []
        terms += [expr.diff(qk) * vk for qk, vk in zip(self.q, self.v) if qk in free]
        return sp.Add(*terms)

    def lagrangian_force(self) -> Matrix:
        """The Lagrangian's forces, -dV/dq + dT/dq - (dp/dq) v - dp/dt - D v, p = dT/dv."""
        vv = sp.Matrix(self.v)
        F = sp.Matrix([self.T.diff(qi) - self.V.diff(qi) for qi in self.q])
        F -= _jacobian(self.p, self.q) * vv + self.p.diff(self.t)
        if self.D is not None:
            F -= self.D * vv
        return F

    def force(self) -> Matrix:
        """F = Q + lagrangian_force(): every force."""
        F = self.lagrangian_force()
        return F if self.Q is None else F + self.Q

    def patterns(self) -> tuple[list[list[int]], list[list[int]]]:
        """The structural nonzeros, each pattern as its rows' ascending columns: M's and D's,
        both triangles, made symmetric (the library's mass pattern, which damping shares), and
        G's and dG/ds's (the Jacobian's pattern, which jacobian_dot shares)."""
        mass = {
            (i, j)
            for i in range(self.n)
            for j in range(self.n)
            if any(m is not None and (m[i, j] != 0 or m[j, i] != 0) for m in (self.M, self.D))
        }
        G = self.jacobian()
        Gdot = self.along(G)
        jac = {
            (i, j) for i in range(G.rows) for j in range(self.n) if G[i, j] != 0 or Gdot[i, j] != 0
        }
        return (
            [sorted(j for r, j in mass if r == i) for i in range(self.n)],
            [sorted(j for r, j in jac if r == i) for i in range(G.rows)],
        )

    def callbacks(self) -> dict[str, tuple[str, str, Matrix]]:
        """The callbacks of sdae_mbs this description determines: field -> (arguments, output
        array, expressions (a Matrix, row-major))."""
        vv = sp.Matrix(self.v)
        G = self.jacobian()
        ct = self.constraint_t()
        out = {
            "mass": ("tq", "M", self.M),
            "force": (
                "tqv",
                "F",
                self.lagrangian_force() if self.declares_potential else self.force(),
            ),
            "constraint": ("tq", "c", self.c),
            "jacobian": ("tq", "G", G),
            "constraint_t": ("tq", "ct", ct),
            "mass_dot_v": ("tqv", "out", self.along(self.M * vv)),
            "jacobian_dot": ("tqv", "Gdot", self.along(G)),
            "constraint_t_dot": ("tqv", "out", self.along(ct)),
        }
        if self.declares_potential:
            out["potential"] = ("tq", "V", sp.Matrix([self.V]))
            if self.D is not None:
                out["damping"] = ("tq", "D", self.D)
            if self.Q is not None:
                out["input_force"] = ("tqv", "F", self.Q)
        return out


def _jacobian(exprs: Iterable[Expr], symbols: Sequence[Symbol]) -> Matrix:
    """d exprs_i / d symbols_j as a Matrix, differentiating each expression in the symbols it
    holds only: sympy's Matrix.jacobian differentiates every pair, and most are 0 in a large
    mechanism (its callbacks took seconds at 64 coordinates)."""
    rows = []
    for e in exprs:
        free = e.free_symbols
        rows.append([e.diff(s) if s in free else sp.S.Zero for s in symbols])
    return sp.Matrix(len(rows), len(symbols), [x for row in rows for x in row])


def _float(value: Expr) -> float:
    try:
        return float(value)
    except TypeError:  # complex or not a number: say so
        return float("nan")


def _listing(symbols: Iterable[Symbol]) -> str:
    names = sorted(s.name for s in symbols)
    return ", ".join(names)
