# SPDX-License-Identifier: GPL-3.0-or-later
"""A small C tokenizer for the mutation generator: code tokens with their offsets, and nothing
from comments, string or character literals and preprocessor lines, so that no mutant ever
lands there. It only has to be right for well-formed C; a token it gets wrong costs one
mutant that does not compile (counted invalid), never a wrong verdict."""

import bisect
import re
from dataclasses import dataclass

PUNCTUATORS = sorted(
    """<<= >>= ... -> ++ -- << >> <= >= == != && || += -= *= /= %= &= ^= |= ##
    { } [ ] ( ) ; , : ? . + - * / % & | ^ ! ~ < > =""".split(),
    key=len,
    reverse=True,
)

_NUMBER = re.compile(
    r"0[xX][0-9a-fA-F]+[uUlL]*"
    r"|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?[uUlLfF]*"
)
_IDENT = re.compile(r"[A-Za-z_]\w*")
_SPACE = re.compile(r"\s+")


@dataclass
class Token:
    kind: str  # ident, number, punct
    text: str
    start: int  # offset in the file's text
    end: int
    line: int  # 1-based


def _skip_preprocessor(text, i):
    """End of a preprocessor line starting at i, with its backslash continuations."""
    while True:
        nl = text.find("\n", i)
        if nl < 0:
            return len(text)
        if text[nl - 1] != "\\":
            return nl
        i = nl + 1


def _skip_quoted(text, i):
    """End of the string or character literal opening at i (escapes honoured)."""
    quote, j = text[i], i + 1
    while j < len(text) and text[j] != quote:
        j += 2 if text[j] == "\\" else 1
    return j + 1


def _at_line_start(text, i):
    j = text.rfind("\n", 0, i) + 1
    return text[j:i].strip() == ""


def tokenize(text):
    """The code tokens of a C file, in order."""
    tokens, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        m = _SPACE.match(text, i)
        if m:
            i = m.end()
        elif text.startswith("//", i):
            nl = text.find("\n", i)
            i = n if nl < 0 else nl
        elif text.startswith("/*", i):
            close = text.find("*/", i + 2)
            i = n if close < 0 else close + 2
        elif c == "#" and _at_line_start(text, i):
            i = _skip_preprocessor(text, i)
        elif c in "\"'":
            i = _skip_quoted(text, i)
        else:
            i = _code_token(text, i, tokens)
    starts = [0] + [m.end() for m in re.finditer("\n", text)]
    for t in tokens:
        t.line = bisect.bisect_right(starts, t.start)
    return tokens


def _code_token(text, i, tokens):
    line = 0  # filled in by tokenize
    for kind, rx in (("number", _NUMBER), ("ident", _IDENT)):
        m = rx.match(text, i)
        if m and (
            kind == "ident" or text[i].isdigit() or text[i] == "." and text[i + 1 : i + 2].isdigit()
        ):
            tokens.append(Token(kind, m.group(), i, m.end(), line))
            return m.end()
    for p in PUNCTUATORS:
        if text.startswith(p, i):
            tokens.append(Token("punct", p, i, i + len(p), line))
            return i + len(p)
    return i + 1  # a stray character (e.g. '@' or '\\'): not code the mutants touch


def match_brackets(tokens):
    """partner[i] = index of the bracket matching token i (for ( ) [ ] { }), else None."""
    partner, stack = [None] * len(tokens), []
    pairs = {")": "(", "]": "[", "}": "{"}
    for i, t in enumerate(tokens):
        if t.text in "([{":
            stack.append(i)
        elif t.text in pairs:
            while stack and tokens[stack[-1]].text != pairs[t.text]:
                stack.pop()  # unbalanced input: drop the stray opener
            if stack:
                j = stack.pop()
                partner[i], partner[j] = j, i
    return partner
