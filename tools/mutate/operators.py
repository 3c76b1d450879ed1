# SPDX-License-Identifier: GPL-3.0-or-later
"""The mutants of one C file, by operator class. Each operator walks the file's code tokens
(clex.py) and proposes a change: a span of the text and its replacement. A mutant's id is
file:operator:sha1(stripped original line)[:8]:occurrence, so it survives edits elsewhere in
the file and the list of equivalent mutants stays valid while the code moves."""

import hashlib
import math
import re
from dataclasses import dataclass

from .clex import match_brackets, tokenize

# the classes of which a line gives one mutant, its first candidate: they are dense (a line of
# numerics has many), and one per line keeps a full run near 200 mutants
ONE_PER_LINE = {"not", "rel", "arith", "const", "digits"}

# in the order in which a change proposed by two classes is attributed (the first wins)
OPERATORS = (
    "time",
    "status",
    "guard",
    "loop",
    "not",
    "rel",
    "arith",
    "const",
    "digits",
    "carve",
    "tol",
)
# a campaign's classes unless --ops names others: carve's mutants are judged under
# AddressSanitizer alone (--sanitize), where the arena's redzones make an overrun fail
DEFAULT_OPERATORS = tuple(op for op in OPERATORS if op != "carve")

DESCRIPTIONS = {
    "time": "time arguments: a bare t/tm/t0 argument -> t + 1.0, t +/- x flipped, t += x dropped",
    "status": "a failure status made success: return/assign SDAE_ERR_x -> SDAE_OK, "
    "rc != SDAE_OK -> 0, rc == SDAE_OK -> 1",
    "guard": "a guard dropped: if (c) return x; (or a block that returns) -> never taken",
    "loop": "loop bounds: i < n -> i < n - 1, i > n -> i > n + 1 (for and while)",
    "not": "a logical ! removed",
    "rel": "relational flips: < <=, > >=, == !=",
    "arith": "arithmetic swaps: + -, * /, += -=, *= /=",
    "const": "constants: 0 -> 1, 1 -> 0, n -> n + 1, x.0 -> x - 1, other reals "
    "* (1 - 1e-4), tiny reals * 10",
    "digits": "a coefficient of 10 or more significant digits moved two units in its last "
    "place (the next double up, twice)",
    "carve": "a carve one element short: sdae__take*(a, n, ...) -> n - 1, and a map's "
    "scratch size one double short",
    "tol": "a tolerance made zero: #define *TOL*/*SMALL*/*ROUNDING* x -> 0.0, and tol = x "
    "or *_tol = x -> 0.0",
}

TIME_NAMES = {"t", "tm", "t0"}
# t + 1.0 is finite exactly when t is: a time argument there is not worth a mutant
FINITENESS_TESTS = {"isfinite", "isnan", "isinf"}
KEYWORDS = set(
    """auto break case char const continue default do double else enum extern float
    for goto if inline int long register restrict return short signed sizeof static struct switch
    typedef union unsigned void volatile while _Bool _Alignof alignof""".split()
)
TYPE_WORDS = set(
    """char double float int long short signed unsigned void size_t uintptr_t
    uint8_t uint32_t uint64_t int64_t ptrdiff_t bool _Bool const struct FILE""".split()
)
RELATIONAL = {"<": "<=", "<=": "<", ">": ">=", ">=": ">", "==": "!=", "!=": "=="}
ARITH = {"+": "-", "-": "+", "*": "/", "/": "*", "+=": "-=", "-=": "+=", "*=": "/=", "/=": "*="}
ASSIGN = {"=", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<=", ">>=", "++", "--"}


@dataclass
class Mutant:
    file: str  # path relative to the repository, e.g. src/core/lu.c
    op: str
    key: str  # sha1 of the stripped original line, 8 hex digits
    occurrence: int  # index among the file's mutants of the same (line, op)
    line: int  # current line number (for the report only, never in the id)
    start: int
    end: int
    replacement: str
    original: str  # the original line(s), stripped
    mutated: str  # the same line(s) with the change

    @property
    def id(self):
        return f"{self.file}:{self.op}:{self.key}:{self.occurrence}"

    def apply(self, text):
        return text[: self.start] + self.replacement + text[self.end :]


class FileContext:
    """A file's tokens with the little syntax the operators need."""

    def __init__(self, text, extra_types=(), index_names=()):
        self.text = text
        self.index_names = set(index_names)
        self.tok = tokenize(text)
        self.partner = match_brackets(self.tok)
        self.types = TYPE_WORDS | set(extra_types)
        self.enclosing = self._enclosing()

    def _enclosing(self):
        """For each token, the index of the innermost open bracket around it (or None)."""
        out, stack = [], []
        for i, t in enumerate(self.tok):
            if t.text in ")]}" and stack:
                stack.pop()
            out.append(stack[-1] if stack else None)
            if t.text in "([{":
                stack.append(i)
        return out

    def t(self, i):
        return self.tok[i].text if 0 <= i < len(self.tok) else ""

    def is_type(self, i):
        w = self.t(i)
        if self.t(i - 1) in ("struct", "enum", "union"):
            return True
        return w in self.types or w.startswith("gsl_") or w.endswith("_t")

    def operand_end(self, i):
        """Whether token i can end an operand (so that the token after it is a binary op)."""
        tk = self.tok[i] if 0 <= i < len(self.tok) else None
        if tk is None:
            return False
        if tk.kind == "number" or tk.text in (")", "]"):
            return True
        return tk.kind == "ident" and tk.text not in KEYWORDS and not self.is_type(i)

    def index_operand(self, i):
        """Whether token i, next to an arithmetic operator, makes it integer or pointer
        arithmetic: an integer literal, sizeof, or a name declared integer or pointer."""
        tk = self.tok[i] if 0 <= i < len(self.tok) else None
        if tk is None:
            return False
        if tk.kind == "number":
            return not any(c in tk.text for c in ".eE")
        if tk.text == "sizeof" or self.t(i - 1) == "sizeof":
            return True
        return tk.kind == "ident" and tk.text in self.index_names

    def in_brackets(self, i):
        j = self.enclosing[i]
        while j is not None:
            if self.t(j) == "[":
                return True
            j = self.enclosing[j]
        return False

    def operand_start(self, k):
        """Index of the first token of the postfix expression ending at token k."""
        j = k
        while True:
            if self.t(j) in (")", "]") and self.partner[j] is not None:
                j = self.partner[j]
                callee = self.tok[j - 1] if j > 0 else None
                if self.t(j) == "[" or (
                    callee and callee.kind == "ident" and callee.text not in KEYWORDS
                ):
                    j -= 1
                    continue
            if j >= 2 and self.t(j - 1) in ("->", "."):
                j -= 2
                continue
            return j

    def span(self, i, j):
        """The text of tokens i..j inclusive."""
        return self.text[self.tok[i].start : self.tok[j].end]

    def has_side_effects(self, i, j):
        """Whether tokens i..j hold an assignment or a call (kept when a check is dropped)."""
        for k in range(i, j + 1):
            if self.t(k) in ASSIGN:
                return True
            if (
                self.t(k) == "("
                and k > 0
                and self.tok[k - 1].kind == "ident"
                and self.t(k - 1) not in KEYWORDS
            ):
                return True
        return False

    def header_parts(self, kw_index):
        """For `for (a; b; c)` or `while (b)`: the token range (first, last) of b, or None."""
        open_ = kw_index + 1
        if self.t(open_) != "(" or self.partner[open_] is None:
            return None
        close = self.partner[open_]
        if self.t(kw_index) == "while":
            return (open_ + 1, close - 1) if close - 1 >= open_ + 1 else None
        semis = [
            k for k in range(open_ + 1, close) if self.t(k) == ";" and self.enclosing[k] == open_
        ]
        if len(semis) != 2 or semis[1] - 1 < semis[0] + 1:
            return None
        return semis[0] + 1, semis[1] - 1

    def guard_if(self, i):
        """For token i = `if`: (open, close) of its condition when the body returns."""
        open_ = i + 1
        if self.t(open_) != "(" or self.partner[open_] is None:
            return None
        close = self.partner[open_]
        body = close + 1
        if self.t(body) == "return":
            return open_, close
        if self.t(body) == "{" and self.partner[body] is not None:
            inner = range(body + 1, self.partner[body])
            if any(self.t(k) == "return" and self.enclosing[k] == body for k in inner):
                return open_, close
        return None


def typedef_names(texts):
    """The type names that a set of headers and sources declare with typedef."""
    names = set()
    for text in texts:
        names.update(re.findall(r"\}\s*(\w+)\s*;", text))
        names.update(re.findall(r"typedef\s+[^;{}()]*?\b(\w+)\s*;", text))
        names.update(re.findall(r"typedef[^;{}]*\(\s*\*\s*(\w+)\s*\)", text))
    return names


INT_TYPES = {"size_t", "unsigned", "int", "uintptr_t", "long", "short", "char"}


def _declarators(ctx, i):
    """The names declared by the declaration whose type word is token i."""
    names, depth = [], ctx.enclosing[i]
    j = i + 1
    while j < len(ctx.tok) and ctx.t(j) not in (";", "{") and ctx.enclosing[j] == depth:
        if (
            ctx.tok[j].kind == "ident"
            and ctx.t(j - 1) in (ctx.t(i), ",", "*")
            and ctx.t(j + 1) in ("=", ",", ";", ")", "[")
        ):
            names.append(ctx.t(j))
        j = ctx.partner[j] + 1 if ctx.t(j) in "([" and ctx.partner[j] else j + 1
    return names


def integer_and_pointer_names(texts):
    """Names declared with an integer type, or as pointers, anywhere in texts: arithmetic on
    them is index or address arithmetic, which the arith operator leaves to loop and const."""
    names = set()
    for text in texts:
        ctx = FileContext(text)
        for i, tk in enumerate(ctx.tok):
            cast = ctx.t(i - 1) == "(" and ctx.t(i + 1) == ")"
            if tk.text in INT_TYPES and not cast:
                names.update(_declarators(ctx, i))
            if (
                tk.text == "*"
                and not ctx.operand_end(i - 1)
                and tk.kind == "punct"
                and ctx.tok[i + 1].kind == "ident"
                and ctx.t(i + 2) in ("=", ",", ";", ")", "[")
            ):
                names.add(ctx.t(i + 1))
    return names - KEYWORDS


def _change(ctx, i, j, replacement):
    """A proposed change of tokens i..j (inclusive) into replacement."""
    return ctx.tok[i].start, ctx.tok[j].end, replacement, ctx.tok[i].line


def op_time(ctx):
    out = []
    for i, tk in enumerate(ctx.tok):
        if tk.kind != "ident" or tk.text not in TIME_NAMES or ctx.t(i - 1) in ("->", "."):
            continue
        prev, nxt = ctx.t(i - 1), ctx.t(i + 1)
        call = ctx.enclosing[i]
        if (
            prev in ("(", ",")
            and nxt in (",", ")")
            and call is not None
            and ctx.operand_end(call - 1)
            and ctx.t(call - 1) not in FINITENESS_TESTS
        ):
            out.append(_change(ctx, i, i, tk.text + " + 1.0"))  # a call's time argument
        if nxt in ("+=", "-=") and prev in (";", "{", "}", ")"):
            end = next((k for k in range(i, len(ctx.tok)) if ctx.t(k) == ";"), None)
            if end is not None:
                out.append(_change(ctx, i, end, ";"))  # the time's update dropped
        for k in (i - 1, i + 1):  # t + x, x - t ...
            if ctx.t(k) in ("+", "-") and ctx.operand_end(k - 1) and ctx.t(k + 1) != "(":
                out.append(_change(ctx, k, k, ARITH[ctx.t(k)]))
    return out


def _is_ok(ctx, i):
    return ctx.t(i) == "SDAE_OK"


def op_status(ctx):
    out, guard_conditions = [], set()
    for i in range(len(ctx.tok)):
        if ctx.t(i) == "if" and ctx.guard_if(i):
            open_, close = ctx.guard_if(i)
            guard_conditions.add((open_ + 1, close - 1))
    guards = _guard_bodies(ctx)
    for i, tk in enumerate(ctx.tok):
        if (
            tk.text.startswith("SDAE_ERR_")
            and ctx.t(i - 1) in ("return", "?", ":", "=")
            and i not in guards
        ):  # a guard's own return: the guard operator's
            out.append(_change(ctx, i, i, "SDAE_OK"))
        if tk.text in ("!=", "==") and _is_ok(ctx, i + 1):
            first = ctx.operand_start(i - 1)
            if (first, i + 1) in guard_conditions:
                continue  # the guard operator drops this very check
            truth = "0" if tk.text == "!=" else "1"
            if ctx.has_side_effects(first, i - 1):
                truth = f"({ctx.span(first, i - 1)}, {truth})"
            out.append(_change(ctx, first, i + 1, truth))
    return out


def op_guard(ctx):
    out = []
    for i in range(len(ctx.tok)):
        g = ctx.t(i) == "if" and ctx.guard_if(i)
        if not g:
            continue
        open_, close = g
        if ctx.has_side_effects(open_ + 1, close - 1):
            out.append(_change(ctx, open_, close, f"({ctx.span(open_, close)} && 0)"))
        else:
            out.append(_change(ctx, open_, close, "(0)"))
    return out


def op_loop(ctx):
    out = []
    for i in range(len(ctx.tok)):
        if ctx.t(i) not in ("for", "while"):
            continue
        cond = ctx.header_parts(i)
        if not cond:
            continue
        first, last = cond
        depth = ctx.enclosing[first]
        rel = next(
            (
                k
                for k in range(first, last + 1)
                if ctx.enclosing[k] == depth and ctx.t(k) in ("<", "<=", ">", ">=")
            ),
            None,
        )
        if rel is None:
            continue
        end = rel + 1
        while end + 1 <= last and not (
            ctx.t(end + 1) in ("&&", "||") and ctx.enclosing[end + 1] == depth
        ):
            end += 1
        bound = ctx.span(rel + 1, end)
        if end > rel + 1:
            bound = f"({bound})"
        delta = " - 1" if ctx.t(rel) in ("<", "<=") else " + 1"
        out.append(_change(ctx, rel + 1, end, bound + delta))
    return out


def _loop_conditions(ctx):
    """Token indices inside for/while conditions (the loop operator's territory)."""
    inside = set()
    for i in range(len(ctx.tok)):
        if ctx.t(i) in ("for", "while"):
            cond = ctx.header_parts(i)
            if cond:
                inside.update(range(cond[0], cond[1] + 1))
    return inside


def _guard_conditions(ctx):
    """Token indices inside the conditions of guards (the guard operator drops them whole)."""
    inside = set()
    for i in range(len(ctx.tok)):
        g = ctx.t(i) == "if" and ctx.guard_if(i)
        if g:
            inside.update(range(g[0], g[1] + 1))
    return inside


def _guard_bodies(ctx):
    """Token indices of the bodies of guards."""
    inside = set()
    for i in range(len(ctx.tok)):
        g = ctx.t(i) == "if" and ctx.guard_if(i)
        if g:
            body = g[1] + 1
            end = (
                ctx.partner[body]
                if ctx.t(body) == "{"
                else next(k for k in range(body, len(ctx.tok)) if ctx.t(k) == ";")
            )
            inside.update(range(body, end + 1))
    return inside


def op_not(ctx):
    guards = _guard_conditions(ctx)
    return [
        _change(ctx, i, i, "") for i, tk in enumerate(ctx.tok) if tk.text == "!" and i not in guards
    ]


def op_rel(ctx):
    out, loops = [], _loop_conditions(ctx)
    for i, tk in enumerate(ctx.tok):
        if tk.kind != "punct" or tk.text not in RELATIONAL or i in loops:
            continue
        if _is_ok(ctx, i + 1) or _is_ok(ctx, i - 1):
            continue  # status operator
        out.append(_change(ctx, i, i, RELATIONAL[tk.text]))
    return out


def op_arith(ctx):
    out = []
    for i, tk in enumerate(ctx.tok):
        if tk.kind != "punct" or tk.text not in ARITH or ctx.in_brackets(i):
            continue
        if tk.text in ("+", "-", "*", "/") and not ctx.operand_end(i - 1):
            continue  # unary, a pointer declarator or a dereference
        if ctx.index_operand(i - 1) or ctx.index_operand(i + 1):
            continue  # index, size or address arithmetic
        out.append(_change(ctx, i, i, ARITH[tk.text]))
    return out


def _number_change(text):
    """The changed literal, or None for one the operator leaves alone."""
    body = text.rstrip("uUlLfF")
    suffix = text[len(body) :]
    if body.lower().startswith("0x"):
        return None
    if not any(c in body for c in ".eE"):
        v = int(body)
        return {0: "1", 1: "0"}.get(v, str(v + 1)) + suffix
    v = float(body)
    if v == 0.0:
        new = 1.0
    elif v == int(v) and v >= 1.0:
        new = v - 1.0
    elif abs(v) < 1e-3:
        new = v * 10.0
    else:
        new = v * (1.0 - 1e-4)
    s = repr(new)
    return (s if any(c in s for c in ".eE") else s + ".0") + suffix


def op_const(ctx):
    out = []
    for i, tk in enumerate(ctx.tok):
        if tk.kind != "number" or ctx.in_brackets(i) or ctx.t(i - 1) == "case":
            continue
        if ctx.t(i - 1) == "{" and ctx.t(i + 1) == "}":
            continue  # {0}: a zeroed aggregate, not a value
        is_int = not any(c in tk.text for c in ".eE") or tk.text.lower().startswith("0x")
        if is_int and ctx.t(i - 1) not in RELATIONAL and ctx.t(i + 1) not in RELATIONAL:
            continue  # integers count and index: changed only where compared
        new = _number_change(tk.text)
        if new is not None and new != tk.text:
            out.append(_change(ctx, i, i, new))
    return out


def _significant_digits(text):
    mantissa = re.split(r"[eE]", text.rstrip("uUlLfF"))[0]
    return len(mantissa.replace(".", "").lstrip("0"))


def op_digits(ctx):
    """A long real literal (a tableau's or composition's coefficient) two ulps up: the value a
    coefficient typed with its last digits wrong rounds to."""
    out = []
    for i, tk in enumerate(ctx.tok):
        if (
            tk.kind != "number"
            or not any(c in tk.text for c in ".eE")
            or tk.text.lower().startswith("0x")
            or _significant_digits(tk.text) < 10
        ):
            continue
        body = tk.text.rstrip("uUlLfF")
        v = float(body)
        new = math.nextafter(math.nextafter(v, math.inf), math.inf)
        out.append(_change(ctx, i, i, repr(new) + tk.text[len(body) :]))
    return out


TAKES = {"sdae__take", "sdae__take_array", "sdae__take_indices", "sdae__take_pivots"}


def _arguments(ctx, open_):
    """The token ranges (first, last) of a call's top-level arguments."""
    close, args, first = ctx.partner[open_], [], open_ + 1
    for k in range(open_ + 1, close + 1):
        if k == close or (ctx.t(k) == "," and ctx.enclosing[k] == open_):
            if k - 1 >= first:
                args.append((first, k - 1))
            first = k + 1
    return args


def op_carve(ctx):
    """The count of a carved array one short (its second argument, after the arena), and the
    size a map's scratch function returns one double short: an overrun of the last element
    then lands in the next array, which only a redzone or a canary shows. Calls alone, within
    a function (the carving functions' own definitions are at file scope)."""
    out = []
    for i, tk in enumerate(ctx.tok):
        if (
            tk.kind == "ident"
            and tk.text in TAKES
            and ctx.t(i + 1) == "("
            and ctx.partner[i + 1] is not None
            and ctx.enclosing[i] is not None
        ):
            args = _arguments(ctx, i + 1)
            if len(args) >= 2:
                a, b = args[1]
                out.append(_change(ctx, a, b, f"({ctx.span(a, b)}) - 1"))
        if tk.text == "return" and _in_function_named(ctx, i, "_scratch"):
            end = i + 1
            while end < len(ctx.tok) and ctx.t(end) != ";":
                end += 1
            if end - 1 >= i + 1:
                out.append(_change(ctx, i + 1, end - 1, f"({ctx.span(i + 1, end - 1)}) - 1"))
    return out


def _in_function_named(ctx, i, suffix):
    """Whether token i lies in the body of a function whose name ends with suffix."""
    j = ctx.enclosing[i]
    while j is not None and ctx.enclosing[j] is not None:
        j = ctx.enclosing[j]
    if j is None or ctx.t(j) != "{":
        return False
    k = j - 1  # the parameter list's ')' before the body, then the name before its '('
    if ctx.t(k) != ")" or ctx.partner[k] is None:
        return False
    name = ctx.t(ctx.partner[k] - 1)
    return name.endswith(suffix)


TOL_MACRO = re.compile(
    r"^[ \t]*#[ \t]*define[ \t]+(\w*(?:TOL|SMALL|ROUNDING)\w*)[ \t]+"
    r"(\(?[-+]?[0-9][0-9.eE+-]*\)?[ \t]*(?:\*[^\n/]*)?)",
    re.M,
)


def op_tol(ctx):
    """A tolerance made zero: a macro named for one (TOL, SMALL, ROUNDING) with a numeric
    value, or a variable tol or *_tol given a value."""
    out = []
    for m in TOL_MACRO.finditer(ctx.text):
        line = ctx.text.count("\n", 0, m.start(2)) + 1
        out.append((m.start(2), m.end(2), "0.0", line))
    for i, tk in enumerate(ctx.tok):
        if (
            tk.kind == "ident"
            and (tk.text == "tol" or tk.text.endswith("_tol"))
            and ctx.t(i + 1) == "="
            and ctx.t(i - 1) not in (".", "->")
        ):
            end = i + 2
            while end < len(ctx.tok) and ctx.t(end) not in (";", ","):
                end = ctx.partner[end] + 1 if ctx.t(end) in "([" and ctx.partner[end] else end + 1
            if end - 1 >= i + 2:
                out.append(_change(ctx, i + 2, end - 1, "0.0"))
    return out


GENERATORS = {
    "time": op_time,
    "status": op_status,
    "guard": op_guard,
    "loop": op_loop,
    "not": op_not,
    "rel": op_rel,
    "arith": op_arith,
    "const": op_const,
    "digits": op_digits,
    "carve": op_carve,
    "tol": op_tol,
}


def _line_bounds(text, start, end):
    a = text.rfind("\n", 0, start) + 1
    b = text.find("\n", end)
    return a, (len(text) if b < 0 else b)


def _squash(s):
    return " ".join(s.split())


def generate(relpath, text, extra_types=(), index_names=(), operators=OPERATORS):
    """Every mutant of one file, in text order within each operator class."""
    ctx = FileContext(text, extra_types, index_names)
    seen, mutants, counts = set(), [], {}
    for op in OPERATORS:
        if op not in operators:
            continue
        lines = set()
        for start, end, repl, line in sorted(GENERATORS[op](ctx)):
            if (start, end, repl) in seen or (op in ONE_PER_LINE and line in lines):
                continue
            seen.add((start, end, repl))
            lines.add(line)
            a, b = _line_bounds(text, start, end)
            first_line = text[a : _line_bounds(text, start, start)[1]]
            key = hashlib.sha1(first_line.strip().encode()).hexdigest()[:8]
            occ = counts.get((op, key), 0)
            counts[(op, key)] = occ + 1
            original = text[a:b]
            mutated = original[: start - a] + repl + original[end - a :]
            mutants.append(
                Mutant(
                    relpath,
                    op,
                    key,
                    occ,
                    line,
                    start,
                    end,
                    repl,
                    _squash(original),
                    _squash(mutated),
                )
            )
    return mutants
