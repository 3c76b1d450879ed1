# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared by the generator's tests: the command run as a user runs it, model files written
from text, every model of the tree generated once, the generated callbacks evaluated by a C
program, and the paths of the tree (STABDAE_BUILD: the build tree, default build/)."""

import glob
import os
import re
import resource
import shutil
import subprocess
import sys
import textwrap

import pytest

TOOLS = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROOT = os.path.dirname(TOOLS)
BUILD = os.environ.get("STABDAE_BUILD", os.path.join(ROOT, "build"))
SYM = os.path.join(ROOT, "examples", "models", "sym")
HERE = os.path.dirname(os.path.abspath(__file__))

# every description in the tree: examples/models/sym/, the tutorial's examples/generator/, and
# tests/models/ (names and functions hard to print, the large chains); a helper module beside
# them defines no mechanism()
MODELS = sorted(
    glob.glob(os.path.join(SYM, "*.py"))
    + glob.glob(os.path.join(ROOT, "examples", "generator", "*.py"))
    + glob.glob(os.path.join(HERE, "models", "*.py"))
)
MODELS = [m for m in MODELS if "def mechanism(" in open(m).read()]
COMPILERS = [c for c in ("gcc", "clang") if shutil.which(c)]
INCLUDES = ["-I" + os.path.join(ROOT, "include"), "-I" + os.path.join(BUILD, "include")]
FLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-c", *INCLUDES]
HAVE_BUILD = os.path.exists(os.path.join(BUILD, "include", "stabdae", "version.h"))
needs_build = pytest.mark.skipif(
    not COMPILERS or not HAVE_BUILD,
    reason="needs a compiler and a configured build tree (STABDAE_BUILD)",
)


def run_mbsgen(*args):
    """python -m stabdae_gen ARGS: (exit status, stdout, stderr)."""
    env = dict(os.environ, PYTHONPATH=TOOLS)
    p = subprocess.run(
        [sys.executable, "-m", "stabdae_gen", *args],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    return p.returncode, p.stdout, p.stderr


def timed_mbsgen(*args):
    """run_mbsgen's (exit status, stdout, stderr) and the CPU seconds the command took (its
    own, whatever else the machine runs)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    result = run_mbsgen(*args)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return (*result, cpu)


class _Generated(dict):
    """model path -> (output dir, name, CPU seconds), each model generated when first asked
    for (a test file that needs one model does not wait for the others)."""

    def __init__(self, tmp_path_factory):
        super().__init__()
        self.tmp_path_factory = tmp_path_factory

    def __missing__(self, model):
        d = self.tmp_path_factory.mktemp(os.path.basename(model)[:-3])
        rc, stdout, stderr, cpu = timed_mbsgen(model, "--out", str(d))
        assert rc == 0, stderr
        name = re.search(r"mbsgen: (\w+):", stdout).group(1)
        self[model] = (d, name, cpu)
        return self[model]


@pytest.fixture(scope="session")
def generated(tmp_path_factory):
    """Every model of the tree generated once a session, when a test first needs it."""
    return _Generated(tmp_path_factory)


# A program that evaluates every callback of a generated mechanism at its default parameters:
# it reads points "t q_1..q_n v_1..v_n" from stdin and prints, per point, a line per field of
# sdae_mbs, "field x_1 x_2 ..." (or "field NULL"), then "end"; a matrix written by the
# nonzeros of a pattern is printed whole, zero outside it.
EVALUATOR = r"""
#include <stdio.h>

#include "@N@.h"

enum { NQ = @U@_N_Q, NC = @U@_N_C };

static void show(const char *field, int rc, const double *x, size_t n) {
  printf("%s", field);
  if (rc != 0) printf(" FAILED");
  for (size_t i = 0; i < n; i++) printf(" %.17g", x[i]);
  printf("\n");
}

/* a matrix of rows x NQ from the values a callback wrote: in the pattern's order with one */
static void matrix(const char *field, int rc, const sdae_pattern *p, size_t rows,
                   const double *x) {
  static double dense[NQ * NQ];
  if (!p) {
    show(field, rc, x, rows * NQ);
    return;
  }
  for (size_t i = 0; i < rows * NQ; i++) dense[i] = 0.0;
  for (size_t i = 0; i < rows; i++)
    for (size_t k = p->row_start[i]; k < p->row_start[i + 1]; k++) dense[i * NQ + p->col[k]] = x[k];
  show(field, rc, dense, rows * NQ);
}

#define TQM(FIELD, PATTERN, ROWS)                                                      \
  if (s.FIELD) matrix(#FIELD, s.FIELD(t, q, out, s.params), s.PATTERN, ROWS, out);     \
  else printf("%s NULL\n", #FIELD);
#define TQVM(FIELD, PATTERN, ROWS)                                                     \
  if (s.FIELD) matrix(#FIELD, s.FIELD(t, q, v, out, s.params), s.PATTERN, ROWS, out);  \
  else printf("%s NULL\n", #FIELD);
#define TQ(FIELD, N)                                                    \
  if (s.FIELD) show(#FIELD, s.FIELD(t, q, out, s.params), out, N);     \
  else printf("%s NULL\n", #FIELD);
#define TQV(FIELD, N)                                                   \
  if (s.FIELD) show(#FIELD, s.FIELD(t, q, v, out, s.params), out, N);  \
  else printf("%s NULL\n", #FIELD);

int main(void) {
  static double out[NQ * NQ];
  double t, q[NQ], v[NQ];
  @N@_params p;
  @N@_params_default(&p);
  sdae_mbs s = @N@_mbs(&p);
  while (scanf("%lf", &t) == 1) {
    for (size_t i = 0; i < NQ; i++) if (scanf("%lf", &q[i]) != 1) return 1;
    for (size_t i = 0; i < NQ; i++) if (scanf("%lf", &v[i]) != 1) return 1;
    TQM(mass, mass_pattern, NQ)
    TQV(force, NQ)
    TQ(constraint, NC)
    TQM(jacobian, jacobian_pattern, NC)
    TQ(constraint_t, NC)
    TQ(potential, 1)
    TQM(damping, mass_pattern, NQ)
    TQV(mass_dot_v, NQ)
    TQVM(jacobian_dot, jacobian_pattern, NC)
    TQV(constraint_t_dot, NC)
    TQV(input_force, NQ)
    printf("end\n");
  }
  return 0;
}
"""


def evaluator(d, name, tmp_path):
    """The EVALUATOR built over the generated d/name.c: evaluate(points) -> one dict a point,
    field -> list of floats, or None for a NULL callback."""
    main = tmp_path / f"evaluate_{name}.c"
    main.write_text(EVALUATOR.replace("@U@", name.upper()).replace("@N@", name))
    exe = tmp_path / f"evaluate_{name}"
    p = subprocess.run(
        [
            COMPILERS[0],
            *[f for f in FLAGS if f != "-c"],
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

    def evaluate(points):
        text = "\n".join(" ".join(repr(float(x)) for x in point) for point in points) + "\n"
        run = subprocess.run([str(exe)], input=text, capture_output=True, text=True, check=True)
        results, current = [], {}
        for line in run.stdout.splitlines():
            if line == "end":
                results.append(current)
                current = {}
                continue
            field, *values = line.split()
            assert values[:1] != ["FAILED"], f"{field} returned nonzero"
            current[field] = None if values == ["NULL"] else [float(x) for x in values]
        return results

    return evaluate


@pytest.fixture
def model(tmp_path):
    """model(body) writes a model file whose mechanism() is body (indented as a function's)."""

    def write(body, header="import sympy as sp\nfrom stabdae_gen import Mechanism\n"):
        path = tmp_path / "model.py"
        text = header + "\n\ndef mechanism():\n" + textwrap.indent(textwrap.dedent(body), "    ")
        path.write_text(text)
        return str(path)

    return write


# A pendulum in Cartesian coordinates, the good description every refusal test breaks once.
PENDULUM = """
t = sp.Symbol("t")
x, y = q = sp.symbols("x y")
vx, vy = v = sp.symbols("vx vy")
m, L, g = sp.symbols("m L g")
args = dict(
    kinetic=m * (vx**2 + vy**2) / 2,
    potential=m * g * y,
    constraints=[(x**2 + y**2 - L**2) / 2],
    params={m: 1.0, L: 2.0, g: 9.81},
    q0=[L * sp.sin(0.3), -L * sp.cos(0.3)],
    v0=[0, 0])
"""
