# SPDX-License-Identifier: GPL-3.0-or-later
"""The C the generator writes, for every description in the tree (examples/models/sym/, the
tutorial's examples/generator/, and tests/models/ with names and functions hard to print and the
large chains): C99 that GCC and Clang compile without a warning under -Wall -Wextra -Wpedantic
-Werror, in strict C99 (trigraphs on) and in GNU C17 (gcc's default: linux, unix predefined),
a header that C++ compiles, an object with no data (no globals) that calls no allocator,
exports the header's functions alone, and a header comment naming the generator's version and
the model file's sha256."""

import hashlib
import os
import re
import shutil
import subprocess

import pytest

from conftest import COMPILERS, FLAGS, HAVE_BUILD, INCLUDES, MODELS, ROOT, SYM, needs_build

import stabdae_gen
from stabdae_gen.cli import load

# (compiler, the flags that replace -std=c99): strict C99 and GNU C17
C_MODES = [(c, std) for c in COMPILERS for std in ("-std=c99", "-std=gnu17")]
CXX = [c for c in ("g++", "clang++") if shutil.which(c)]


def test_models_found():
    assert len(MODELS) >= 1 and os.path.join(SYM, "fourbar.py") in MODELS


def test_version_is_the_projects():
    with open(os.path.join(ROOT, "CMakeLists.txt")) as f:
        project = re.search(r"project\(stabdae VERSION (\S+)", f.read()).group(1)
    assert stabdae_gen.__version__ == project


@pytest.mark.parametrize("model", MODELS, ids=[os.path.basename(m) for m in MODELS])
def test_banner_names_version_and_hash(generated, model):
    d, name, _ = generated[model]
    with open(model, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    for suffix in (".h", ".c"):
        head = (d / (name + suffix)).read_text().split("*/")[0]
        assert f"stabdae_gen {stabdae_gen.__version__}" in head
        assert digest in head


@needs_build
@pytest.mark.parametrize("compiler,std", C_MODES, ids=[f"{c}{s[4:]}" for c, s in C_MODES])
@pytest.mark.parametrize("model", MODELS, ids=[os.path.basename(m) for m in MODELS])
def test_compiles_warning_free(generated, model, compiler, std, tmp_path):
    d, name, _ = generated[model]
    obj = tmp_path / (name + ".o")
    flags = [std if f == "-std=c99" else f for f in FLAGS]
    p = subprocess.run(
        [compiler, *flags, str(d / (name + ".c")), "-o", str(obj)], capture_output=True, text=True
    )
    assert p.returncode == 0 and p.stderr == "", p.stderr
    symbols = subprocess.run(
        ["nm", str(obj)], capture_output=True, text=True, check=True
    ).stdout.split("\n")
    kinds = {}
    for line in symbols:
        parts = line.split()
        if len(parts) >= 2:
            kinds[parts[-1]] = parts[-2]
    exported = sorted(s for s, k in kinds.items() if k == "T")
    assert exported == sorted(
        f"{name}_{f}" for f in ("params_default", "mbs", "start", "coordinate_name")
    )
    # no state: the only data are constants (a sparse mechanism's patterns), in read-only
    # sections (.rodata, or .data.rel.ro for the patterns that point at their arrays)
    table = subprocess.run(
        ["objdump", "-t", str(obj)], capture_output=True, text=True, check=True
    ).stdout.split("\n")
    writable = [
        line.split()[-1]
        for line in table
        if " O " in line and not any(f" {sec}" in line for sec in (".rodata", ".data.rel.ro"))
    ]
    assert writable == [], f"writable data in the object: {writable}"
    undefined = {s for s, k in kinds.items() if k == "U"}
    assert not undefined & {"malloc", "calloc", "realloc", "free"}, undefined


@pytest.mark.skipif(not CXX or not HAVE_BUILD, reason="needs a C++ compiler and a build")
@pytest.mark.parametrize("compiler", CXX)
@pytest.mark.parametrize("model", MODELS, ids=[os.path.basename(m) for m in MODELS])
def test_header_compiles_as_cxx(generated, model, compiler, tmp_path):
    """The header is included from C++ (its extern "C" block): every name in it must be one
    C++ reads as a name (no keyword such as new or class)."""
    d, name, _ = generated[model]
    main = tmp_path / "main.cpp"
    main.write_text(
        f'#include "{name}.h"\n'
        f"int main() {{ {name}_params p; {name}_params_default(&p); "
        f"sdae_mbs s = {name}_mbs(&p); return s.n_q == {name.upper()}_N_Q ? 0 : 1; }}\n"
    )
    p = subprocess.run(
        [
            compiler,
            "-fsyntax-only",
            "-Wall",
            "-Wextra",
            "-Wpedantic",
            "-Werror",
            *INCLUDES,
            "-I" + str(d),
            str(main),
        ],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 0 and p.stderr == "", p.stderr


# The tables through a macro not named X (the header's own macro parameter must not catch a
# parameter of that name), printed with their strings (a trigraph would change a description)
PROGRAM = r"""
#include <stdio.h>
#include <string.h>

#include "@N@.h"

int main(void) {
  @N@_params p;
  double q[@U@_N_Q], v[@U@_N_Q], c[@U@_N_C];
  const char *names[] = @U@_COORDINATE_NAMES;
  const char *units[] = @U@_COORDINATE_UNITS;
  int bad = 0;
  @N@_params_default(&p);
#define CHECK_PARAM(field, value, description, unit) bad |= p.field != value;
  @U@_PARAMETERS(CHECK_PARAM)
#define SHOW_PARAM(field, value, description, unit) \
  printf("param %s|%s|%s\n", #field, description, unit);
  @U@_PARAMETERS(SHOW_PARAM)
  for (size_t i = 0; i < @U@_N_Q; i++) bad |= strcmp(names[i], @N@_coordinate_name(i)) != 0;
  bad |= @N@_coordinate_name(@U@_N_Q) != NULL;
  for (size_t i = 0; i < @U@_N_Q; i++) printf("coordinate %s|%s\n", names[i], units[i]);
  @N@_start(&p, q, v);
  sdae_mbs sys = @N@_mbs(&p);
  bad |= sys.n_q != @U@_N_Q || sys.n_c != @U@_N_C || sys.params != &p;
  bad |= sys.constraint(0.0, q, c, sys.params) != 0;
  for (size_t i = 0; i < @U@_N_Q; i++) printf("%.17g %.17g\n", q[i], v[i]);
  for (size_t j = 0; j < @U@_N_C; j++) printf("%.17g\n", c[j]);
  return bad;
}
"""


@needs_build
@pytest.mark.parametrize("std", ["-std=c99", "-std=gnu17"])
@pytest.mark.parametrize("model", MODELS, ids=[os.path.basename(m) for m in MODELS])
def test_tables_and_start(generated, model, std, tmp_path):
    """The header's tables agree with the functions and hold the description's names,
    descriptions and units as they are (in strict C99, where trigraphs are read, too), and the
    start the C computes equals the description's start evaluated by sympy at 30 digits (to
    1e-14, relative to max(1, |x|)), on the constraints (|c| <= 1e-10, as the generator
    demanded)."""
    d, name, _ = generated[model]
    mech = load(model)
    main = tmp_path / "main.c"
    main.write_text(PROGRAM.replace("@U@", name.upper()).replace("@N@", name))
    exe = tmp_path / "main"
    flags = [std if f == "-std=c99" else f for f in FLAGS if f != "-c"]
    p = subprocess.run(
        [
            COMPILERS[0],
            *flags,
            "-I" + str(d),
            str(main),
            str(d / (name + ".c")),
            "-o",
            str(exe),
            "-lm",
        ],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 0, p.stderr
    run = subprocess.run([str(exe)], capture_output=True, text=True)
    assert run.returncode == 0, "the tables disagree with the functions"
    rows = run.stdout.split("\n")
    params = [r[len("param ") :] for r in rows if r.startswith("param ")]
    assert params == [f"{s.name}|{mech.descriptions[s]}|{mech.units[s]}" for s in mech.params]
    coordinates = [r[len("coordinate ") :] for r in rows if r.startswith("coordinate ")]
    assert coordinates == [f"{n}|{u}" for n, u in zip(mech.coordinate_names, mech.coordinate_units)]
    rows = rows[len(params) + len(coordinates) :]
    start = [[float(x) for x in rows[i].split()] for i in range(mech.n)]
    c = [float(x) for x in rows[mech.n : mech.n + len(mech.c)]]
    exact_q = [mech._numeric(e) for e in mech.q0]
    exact_v = [mech._numeric(e) for e in mech.v0]
    for (q, v), eq, ev in zip(start, exact_q, exact_v):
        assert abs(q - float(eq)) <= 1e-14 * max(1.0, abs(float(eq)))
        assert abs(v - float(ev)) <= 1e-14 * max(1.0, abs(float(ev)))
    assert max(abs(x) for x in c) <= 1e-10
