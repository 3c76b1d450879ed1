# SPDX-License-Identifier: GPL-3.0-or-later
"""The C the generator writes, for every description in the tree (examples/models/sym/, the
tutorial's examples/generator/, and tests/models/ with names and functions hard to print): C99 that GCC and Clang compile without a warning under
-Wall -Wextra -Wpedantic -Werror, an object with no data (no globals) that calls no allocator,
exports the header's functions alone, and a header comment naming the generator's version and
the model file's sha256."""

import glob
import hashlib
import os
import re
import shutil
import subprocess

import pytest

from conftest import BUILD, ROOT, SYM, run_mbsgen

import stabdae_gen
from stabdae_gen.cli import load

MODELS = sorted(glob.glob(os.path.join(SYM, "*.py")) +
                glob.glob(os.path.join(ROOT, "examples", "generator", "*.py")) +
                glob.glob(os.path.join(os.path.dirname(__file__), "models", "*.py")))
MODELS = [m for m in MODELS if "def mechanism(" in open(m).read()]
COMPILERS = [c for c in ("gcc", "clang") if shutil.which(c)]
FLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-c",
         "-I" + os.path.join(ROOT, "include"), "-I" + os.path.join(BUILD, "include")]


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """Every model generated once: {model path: (output dir, name)}."""
    out = {}
    for model in MODELS:
        d = tmp_path_factory.mktemp(os.path.basename(model)[:-3])
        rc, stdout, stderr = run_mbsgen(model, "--out", str(d))
        assert rc == 0, stderr
        name = re.search(r"mbsgen: (\w+):", stdout).group(1)
        out[model] = (d, name)
    return out


def test_models_found():
    assert len(MODELS) >= 1 and os.path.join(SYM, "fourbar.py") in MODELS


def test_version_is_the_projects():
    with open(os.path.join(ROOT, "CMakeLists.txt")) as f:
        project = re.search(r"project\(stabdae VERSION (\S+)", f.read()).group(1)
    assert stabdae_gen.__version__ == project


@pytest.mark.parametrize("model", MODELS, ids=[os.path.basename(m) for m in MODELS])
def test_banner_names_version_and_hash(generated, model):
    d, name = generated[model]
    with open(model, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    for suffix in (".h", ".c"):
        head = (d / (name + suffix)).read_text().split("*/")[0]
        assert f"stabdae_gen {stabdae_gen.__version__}" in head
        assert digest in head


@pytest.mark.skipif(not os.path.exists(os.path.join(BUILD, "include", "stabdae", "version.h")),
                    reason="needs a configured build tree (STABDAE_BUILD)")
@pytest.mark.parametrize("compiler", COMPILERS)
@pytest.mark.parametrize("model", MODELS, ids=[os.path.basename(m) for m in MODELS])
def test_compiles_warning_free(generated, model, compiler, tmp_path):
    d, name = generated[model]
    obj = tmp_path / (name + ".o")
    p = subprocess.run([compiler, *FLAGS, str(d / (name + ".c")), "-o", str(obj)],
                       capture_output=True, text=True)
    assert p.returncode == 0 and p.stderr == "", p.stderr
    symbols = subprocess.run(["nm", str(obj)], capture_output=True, text=True,
                             check=True).stdout.split("\n")
    kinds = {}
    for line in symbols:
        parts = line.split()
        if len(parts) >= 2:
            kinds[parts[-1]] = parts[-2]
    exported = sorted(s for s, k in kinds.items() if k == "T")
    assert exported == sorted(f"{name}_{f}" for f in
                              ("params_default", "mbs", "start", "coordinate_name"))
    data = [s for s, k in kinds.items() if k in "DdBbCGgSs"]
    assert data == [], f"data in the object: {data}"
    undefined = {s for s, k in kinds.items() if k == "U"}
    assert not undefined & {"malloc", "calloc", "realloc", "free"}, undefined


PROGRAM = r"""
#include <stdio.h>
#include <string.h>

#include "@N@.h"

int main(void) {
  @N@_params p;
  double q[@U@_N_Q], v[@U@_N_Q], c[@U@_N_C];
  const char *names[] = @U@_COORDINATE_NAMES;
  int bad = 0;
  @N@_params_default(&p);
#define X(field, value, description) bad |= p.field != value;
  @U@_PARAMETERS(X)
  for (size_t i = 0; i < @U@_N_Q; i++) bad |= strcmp(names[i], @N@_coordinate_name(i)) != 0;
  bad |= @N@_coordinate_name(@U@_N_Q) != NULL;
  @N@_start(&p, q, v);
  sdae_mbs sys = @N@_mbs(&p);
  bad |= sys.n_q != @U@_N_Q || sys.n_c != @U@_N_C || sys.params != &p;
  bad |= sys.constraint(0.0, q, c, sys.params) != 0;
  for (size_t i = 0; i < @U@_N_Q; i++) printf("%.17g %.17g\n", q[i], v[i]);
  for (size_t j = 0; j < @U@_N_C; j++) printf("%.17g\n", c[j]);
  return bad;
}
"""


@pytest.mark.skipif(not COMPILERS or not os.path.exists(
    os.path.join(BUILD, "include", "stabdae", "version.h")), reason="needs a compiler and a build")
@pytest.mark.parametrize("model", MODELS, ids=[os.path.basename(m) for m in MODELS])
def test_tables_and_start(generated, model, tmp_path):
    """The header's tables agree with the functions, and the start the C computes equals the
    description's start evaluated by sympy at 30 digits (to 1e-14, relative to max(1, |x|)),
    on the constraints (|c| <= 1e-10, as the generator demanded)."""
    d, name = generated[model]
    mech = load(model)
    main = tmp_path / "main.c"
    main.write_text(PROGRAM.replace("@U@", name.upper()).replace("@N@", name))
    exe = tmp_path / "main"
    p = subprocess.run([COMPILERS[0], *[f for f in FLAGS if f != "-c"], "-I" + str(d),
                        str(main), str(d / (name + ".c")), "-o", str(exe), "-lm"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    run = subprocess.run([str(exe)], capture_output=True, text=True)
    assert run.returncode == 0, "the tables disagree with the functions"
    rows = run.stdout.split("\n")
    start = [[float(x) for x in rows[i].split()] for i in range(mech.n)]
    c = [float(x) for x in rows[mech.n:mech.n + len(mech.c)]]
    exact_q = [mech._numeric(e) for e in mech.q0]
    exact_v = [mech._numeric(e) for e in mech.v0]
    for (q, v), eq, ev in zip(start, exact_q, exact_v):
        assert abs(q - float(eq)) <= 1e-14 * max(1.0, abs(float(eq)))
        assert abs(v - float(ev)) <= 1e-14 * max(1.0, abs(float(ev)))
    assert max(abs(x) for x in c) <= 1e-10
