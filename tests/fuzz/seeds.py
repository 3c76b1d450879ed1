#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the seed corpora of the fuzz targets (tests/fuzz/corpus/<target>/): a few meaningful
inputs in the layout each fuzz_<target>.c documents, from which libFuzzer mutates. Run from
anywhere: python3 tests/fuzz/seeds.py. Inputs that once failed are kept next to the seeds, under
their own names, and are not touched here."""
import math
import pathlib
import struct

EXPLICIT, JACOBIAN, CALLER_BLOCK, Q_APPLY = 1, 1 << 5, 1 << 6, 1 << 7
EULER, MIDPOINT, DGRAD, USER = (m << 1 for m in range(4))
PAPER, NONE, BAUMGARTE = (s << 3 for s in range(3))
DG4, S_APPLY, DG6, HESSIAN, RK4, RK8 = 1, 2, 4, 8, 16, 32  # the third byte


def seed(choice, more=0, steps=8, max_iter=20, T=0.01, t=0.0, delta=2.0, epsilon=1.0, tol=1e-14,
         alpha=(1.0, 2.0), k=2.0, d=0.03, xi=(0.6, 0.0), mu=(0.7, 0.6)):
    """The paper's oscillator from its off-manifold start (X = 0.1, Y = 0.6) by default."""
    head = bytes([choice, (steps - 1) | (max_iter << 3), more])
    return head + struct.pack("<13d", T, t, delta, epsilon, tol, *alpha, k, d, *xi, *mu)


SEEDS = {
    "paper-euler-15": seed(EULER | PAPER),
    "midpoint-jacobian-block": seed(MIDPOINT | JACOBIAN | CALLER_BLOCK, T=0.1),
    "dgrad-11-qapply": seed(DGRAD | EXPLICIT | Q_APPLY, T=0.05),
    "dg4-sapply-block": seed(DGRAD | CALLER_BLOCK, DG4 | S_APPLY, T=0.1, d=0.0),
    "dg6-hessian-block": seed(DGRAD | CALLER_BLOCK, DG6 | HESSIAN, T=0.1, d=0.0),
    "dgrad-hessian-sapply": seed(DGRAD, HESSIAN | S_APPLY, T=0.3),
    "user-baumgarte-block": seed(USER | BAUMGARTE | CALLER_BLOCK, T=0.2),
    "rk4-qapply-block": seed(EULER | Q_APPLY | CALLER_BLOCK, RK4, T=0.1),
    # past rk8's stability limit, the stages overflowing (SDAE_ERR_NONFINITE, state kept)
    "rk8-11-overflow": seed(EULER | EXPLICIT, RK8, T=1e3),
    "none-11-large-step": seed(MIDPOINT | NONE | EXPLICIT | JACOBIAN, T=10.0, k=1e6),
    "nan-state": seed(EULER | PAPER, mu=(math.nan, 0.6)),
    "negative-step": seed(DGRAD | PAPER, T=-1.0),
}



def argv(*args):
    """fuzz_cli: the arguments, NUL-separated."""
    return b"\0".join(a.encode() for a in args)


CLI_SEEDS = {
    "run-flags": argv("--T", "0.01", "--tf", "5", "--scheme", "11", "--map=dgrad", "--every", "10",
                      "--out", "run.csv", "--delta", "2", "--eps=1"),
    "model-flags": argv("--k", "-3.5", "--x0", "0.1,0.6,0,0", "--q", "paper", "--seed",
                        "18446744073709551615", "--name", "x"),
    "certify-box": argv("--certify", "--box", "xi1=-0.7:0.7,xi2=0,mu1=-0.9:0.9", "--grid", "5"),
    "bad-number": argv("--T", "1e400"),
    # a map of the library that the table (a model without a user map) does not serve
    "map-not-served": argv("--map", "user", "--T", "0.01"),
    "help-late": argv("--k", "1", "--help"),
    # the messages quote arguments verbatim: this one gives a message of two lines
    "newline-in-argument": argv("--T", "1e400\n"),
}

if __name__ == "__main__":
    here = pathlib.Path(__file__).resolve().parent / "corpus"
    for target, seeds in (("step", SEEDS), ("cli", CLI_SEEDS)):
        (here / target).mkdir(parents=True, exist_ok=True)
        for name, data in seeds.items():
            (here / target / name).write_bytes(data)
