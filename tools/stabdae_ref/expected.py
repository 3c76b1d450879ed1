# SPDX-License-Identifier: GPL-3.0-or-later
"""The answers of the C examples' regression tests, examples/expected/NAME.csv:

    python -m stabdae_ref expected [--outdir examples/expected]

RUNS gives, for each file, the example program and its flags exactly as the test
example_regress(NAME PROGRAM FLAGS...) in examples/tests/CMakeLists.txt gives them
(tests/test_expected.py holds the two equal). Each run is this package's command line
(cli.py) for the program's model with those flags, after the C program's defaults where they
differ from the reference's command line (C_DEFAULTS), so a file holds the reference's own
numbers in the program's CSV columns; the C programs must agree with them to a relative 1e-10
(examples/tests/cli_test.sh; newton_iters, the last column, is the reference's own count and
is not compared).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Container, Sequence

from . import cli

HERE = os.path.dirname(os.path.abspath(__file__))
OUTDIR = os.path.normpath(os.path.join(HERE, "..", "..", "examples", "expected"))

# (file name, program, flags), the flags as in examples/tests/CMakeLists.txt
RUNS = (
    ("oscillator_default", "oscillator", "--tf 0.2 --every 10"),
    ("oscillator_s11_euler", "oscillator", "--tf 0.2 --every 10 --scheme 11 --map euler"),
    ("oscillator_midpoint_qpaper", "oscillator", "--tf 0.2 --every 10 --map midpoint --q paper"),
    ("oscillator_dgrad_d0_m2", "oscillator", "--tf 0.2 --every 10 --map dgrad --d 0 --m 2"),
    ("pendulum_dgrad", "pendulum", "--tf 0.2 --every 10 --x0 0.5,-0.9,0.1,0.2"),
    (
        "pendulum_s11_euler",
        "pendulum",
        "--tf 0.2 --every 10 --x0 0.5,-0.9,0.1,0.2 --scheme 11 --map euler",
    ),
    ("pendulum_midpoint_L2", "pendulum", "--tf 0.2 --every 10 --L 2 --m 0.5 --map midpoint"),
    ("chain_euler", "chain", "--tf 0.2 --every 10 --N 5 --seed 3"),
    ("chain_midpoint", "chain", "--tf 0.2 --every 10 --N 3 --map midpoint --kc 2"),
    ("chain_dgrad_s11", "chain", "--tf 0.2 --every 10 --N 4 --map dgrad --scheme 11"),
)

# The C programs' defaults that the reference's command line does not share (the rest agree:
# k 2, d 0.03, m 1, ga 9.81, L 1, kc 1, delta 2, eps 1, T 0.001, scheme 15, the oscillator's
# start and map user, the pendulum's start and map dgrad). Flags given later win.
C_DEFAULTS = {
    "oscillator": [],
    "pendulum": [],
    "chain": ["--N=10", "--seed=1", "--map=euler"],  # 10 masses, seeded start 1, euler
}


def joined(flags: str) -> list[str]:
    """['--x0', '-1,2'] -> ['--x0=-1,2']: a value that starts with '-' stays a value."""
    out, words = [], flags.split()
    i = 0
    while i < len(words):
        if i + 1 < len(words) and not words[i + 1].startswith("--"):
            out.append(words[i] + "=" + words[i + 1])
            i += 2
        else:
            out.append(words[i])
            i += 1
    return out


def argv_of(program: str, flags: str) -> list[str]:
    """The reference's command line for `program FLAGS`."""
    return [program] + C_DEFAULTS[program] + joined(flags)


def write(outdir: str, names: Container[str] | None = None) -> list[str]:
    """Writes outdir/NAME.csv for every run (or the runs in names); the paths written."""
    os.makedirs(outdir, exist_ok=True)
    paths = []
    for name, program, flags in RUNS:
        if names is not None and name not in names:
            continue
        path = os.path.join(outdir, name + ".csv")
        if cli.main(argv_of(program, flags) + ["--out", path]) != 0:
            raise RuntimeError("the reference failed on %s %s" % (program, flags))
        paths.append(path)
    return paths


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m stabdae_ref expected",
        description="Writes the examples' regression answers.",
    )
    ap.add_argument("--outdir", default=OUTDIR, help="default examples/expected")
    args = ap.parse_args(argv)
    try:
        for path in write(args.outdir):
            print(path)
    except (OSError, RuntimeError) as exc:
        print("stabdae_ref expected: %s" % exc, file=sys.stderr)
        return 1
    return 0
