# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared by the generator's tests: the command run as a user runs it, model files written
from text, and the paths of the tree (STABDAE_BUILD: the build tree, default build/)."""

import os
import subprocess
import sys
import textwrap

import pytest

TOOLS = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROOT = os.path.dirname(TOOLS)
BUILD = os.environ.get("STABDAE_BUILD", os.path.join(ROOT, "build"))
SYM = os.path.join(ROOT, "examples", "models", "sym")


def run_mbsgen(*args):
    """python -m stabdae_gen ARGS: (exit status, stdout, stderr)."""
    env = dict(os.environ, PYTHONPATH=TOOLS)
    p = subprocess.run([sys.executable, "-m", "stabdae_gen", *args], env=env,
                       capture_output=True, text=True, timeout=300)
    return p.returncode, p.stdout, p.stderr


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
