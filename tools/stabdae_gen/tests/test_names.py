# SPDX-License-Identifier: GPL-3.0-or-later
"""The names the generator accepts against the compilers themselves: every macro that GCC,
Clang or G++ defines where a generated file is compiled (predefined, or from the headers it
includes) with a name outside the reserved namespace is refused, and every C++ keyword the
generator refuses is one to G++. The names accepted that look dangerous (X, p, q, sin, final, a
description full of trigraphs) are in models/tricky.py, which test_c.py compiles as C99, GNU C17
and C++."""

import re
import shutil
import subprocess

import pytest

from conftest import HAVE_BUILD, INCLUDES

from stabdae_gen import ModelError
from stabdae_gen.mechanism import CPP_KEYWORDS, check_identifier

# what a generated file includes: name.h (<stddef.h>, <stabdae/mbs.h>), then name.c <math.h>
C_SOURCE = "#include <stddef.h>\n#include <stabdae/mbs.h>\n#include <math.h>\n"
CXX_SOURCE = "#include <stddef.h>\n#include <stabdae/mbs.h>\n"
MODES = [
    ("gcc", "-std=c99", C_SOURCE),
    ("gcc", "-std=gnu17", C_SOURCE),
    ("gcc", "-std=gnu17 -m32", ""),
    ("clang", "-std=gnu17", C_SOURCE),
    ("g++", "-x c++", CXX_SOURCE),
    ("clang++", "-x c++", CXX_SOURCE),
]
MODES = [m for m in MODES if shutil.which(m[0])]


def object_macros(compiler, flags, source):
    """The object-like macros (no parameters) the compiler defines after source, by name."""
    p = subprocess.run(
        [compiler, *flags.split(), *INCLUDES, "-dM", "-E", "-"],
        input=source,
        capture_output=True,
        text=True,
    )
    if p.returncode != 0:
        pytest.skip(f"{compiler} {flags} cannot preprocess here: {p.stderr.splitlines()[:1]}")
    return sorted(m.group(1) for m in re.finditer(r"^#define ([A-Za-z_]\w*) ", p.stdout, re.M))


@pytest.mark.skipif(not HAVE_BUILD, reason="needs a configured build tree (STABDAE_BUILD)")
@pytest.mark.parametrize(
    "compiler,flags,source",
    MODES,
    ids=[f"{c} {f}{' (predefined)' if not s else ''}" for c, f, s in MODES],
)
def test_every_macro_is_refused(compiler, flags, source):
    accepted = []
    for name in object_macros(compiler, flags, source):
        try:
            check_identifier(name, "the parameter")
        except ModelError:
            continue
        accepted.append(name)
    assert accepted == [], f"accepted, but macros of {compiler} {flags}: {accepted}"


def rejected_as_names(compiler, flags, names):
    """The names that do not compile as a variable declared and read, each on its own line
    (`double friend;` alone is a friend declaration to C++, `double restrict;` a qualifier to
    C)."""
    source = "".join(
        f"void f{i}(void) {{ double {n} = 1; (void){n}; }}\n" for i, n in enumerate(names)
    )
    p = subprocess.run(
        [compiler, *flags, "-fsyntax-only", "-"], input=source, capture_output=True, text=True
    )
    lines = {int(m.group(1)) for m in re.finditer(r"^<stdin>:(\d+):\d+: error", p.stderr, re.M)}
    return {names[i - 1] for i in lines}


@pytest.mark.skipif(not shutil.which("g++"), reason="needs g++")
def test_cxx_keywords_are_keywords_and_refused():
    """Each name of the generator's C++ keywords is one (G++ rejects it as a name), and so
    are the ones a user is likely to take (new, bool, class, delete, this, template): all
    refused."""
    likely = ["new", "bool", "class", "delete", "this", "template", "and", "or", "not"]
    names = sorted(CPP_KEYWORDS | set(likely))
    rejected = rejected_as_names("g++", ["-x", "c++", "-std=c++20"], names)
    assert sorted(set(names) - rejected) == []
    for name in names:
        with pytest.raises(ModelError):
            check_identifier(name, "the parameter")


@pytest.mark.skipif(not shutil.which("gcc"), reason="needs gcc")
def test_what_gcc_rejects_is_refused():
    """Names a C compiler rejects as names (C and GNU keywords, linux) are refused; the control:
    names it accepts pass."""
    names = [
        "asm",
        "typeof",
        "inline",
        "restrict",
        "_Bool",
        "double",
        "linux",
        "unix",
        "length",
        "mass",
        "sin",
        "final",
        "X",
    ]
    rejected = rejected_as_names("gcc", ["-x", "c", "-std=gnu17"], names)
    assert {"asm", "typeof", "double", "linux", "unix", "inline", "restrict", "_Bool"} <= rejected
    for name in names:
        if name in rejected:
            with pytest.raises(ModelError):
                check_identifier(name, "the parameter")
        else:
            assert check_identifier(name, "the parameter") == name
