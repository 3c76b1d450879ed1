#!/usr/bin/env python3
"""Writes the seed corpus of fuzz_step (tests/fuzz/corpus/step/): a few meaningful inputs in the
layout fuzz_step.c documents, from which libFuzzer mutates. Run from anywhere:
python3 tests/fuzz/seeds.py. Inputs that once failed are kept next to the seeds, under their
own names, and are not touched here."""
import math
import pathlib
import struct

EXPLICIT, JACOBIAN, CALLER_BLOCK, Q_APPLY = 1, 1 << 5, 1 << 6, 1 << 7
EULER, MIDPOINT, DGRAD, USER = (m << 1 for m in range(4))
PAPER, NONE, BAUMGARTE = (s << 3 for s in range(3))


def seed(choice, steps=8, max_iter=20, T=0.01, t=0.0, delta=2.0, epsilon=1.0, tol=1e-14,
         alpha=(1.0, 2.0), k=2.0, d=0.03, xi=(0.6, 0.0), mu=(0.7, 0.6)):
    """The paper's oscillator from its off-manifold start (X = 0.1, Y = 0.6) by default."""
    head = bytes([choice, (steps - 1) | (max_iter << 3)])
    return head + struct.pack("<13d", T, t, delta, epsilon, tol, *alpha, k, d, *xi, *mu)


SEEDS = {
    "paper-euler-15": seed(EULER | PAPER),
    "midpoint-jacobian-block": seed(MIDPOINT | JACOBIAN | CALLER_BLOCK, T=0.1),
    "dgrad-11-qapply": seed(DGRAD | EXPLICIT | Q_APPLY, T=0.05),
    "user-baumgarte-block": seed(USER | BAUMGARTE | CALLER_BLOCK, T=0.2),
    "none-11-large-step": seed(MIDPOINT | NONE | EXPLICIT | JACOBIAN, T=10.0, k=1e6),
    "nan-state": seed(EULER | PAPER, mu=(math.nan, 0.6)),
    "negative-step": seed(DGRAD | PAPER, T=-1.0),
}

if __name__ == "__main__":
    out = pathlib.Path(__file__).resolve().parent / "corpus" / "step"
    out.mkdir(parents=True, exist_ok=True)
    for name, data in SEEDS.items():
        (out / name).write_bytes(data)
