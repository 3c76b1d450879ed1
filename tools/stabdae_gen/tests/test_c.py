# SPDX-License-Identifier: GPL-3.0-or-later
"""The C the generator writes, for every description in the tree (examples/models/sym/ and
the tutorial's examples/generator/): C99 that GCC and Clang compile without a warning under
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

MODELS = sorted(glob.glob(os.path.join(SYM, "*.py")) +
                glob.glob(os.path.join(ROOT, "examples", "generator", "*.py")))
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
