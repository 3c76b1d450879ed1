# SPDX-License-Identifier: GPL-3.0-or-later
"""The examples' regression answers (expected.py): the run table is the one of the ctest
tests, the stored files are what the reference writes for it, and a run is the reference's
command line with the C program's defaults."""

import csv
import os
import re

import pytest

from stabdae_ref import expected, simulate

EXAMPLES = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", "..", "..", "examples"))


def regress_calls():
    """{name: (program, flags)} of example_regress(NAME PROGRAM FLAGS...) in the CMake file."""
    with open(os.path.join(EXAMPLES, "tests", "CMakeLists.txt")) as f:
        text = f.read()
    calls = {}
    for body in re.findall(r"^example_regress\(([^)]*)\)", text, re.M):
        words = body.split()
        if words[0] == "name":  # the function's definition
            continue
        calls[words[0]] = (words[1], " ".join(words[2:]))
    return calls


def read(path):
    with open(path) as f:
        return list(csv.reader(f))


def test_the_table_is_the_ctest_table():
    calls = regress_calls()
    assert len(calls) == len(expected.RUNS) == 10
    assert {name: (prog, flags) for name, prog, flags in expected.RUNS} == calls


def test_every_stored_file_has_a_run():
    stored = sorted(
        f[:-4] for f in os.listdir(os.path.join(EXAMPLES, "expected")) if f.endswith(".csv")
    )
    assert stored == sorted(name for name, _, _ in expected.RUNS)


def test_stored_files_are_what_the_reference_writes(tmp_path):
    """Written again here, every number within 1e-13 relative (the linear algebra's rounding
    may differ between machines; the C programs are held to 1e-10)."""
    expected.write(str(tmp_path))
    for name, _, _ in expected.RUNS:
        new = read(tmp_path / (name + ".csv"))
        old = read(os.path.join(EXAMPLES, "expected", name + ".csv"))
        assert new[0] == old[0] and len(new) == len(old) == 22  # header, t = 0, 20 rows
        for a, b in zip(new[1:], old[1:]):
            assert [float(v) for v in a] == pytest.approx(
                [float(v) for v in b], rel=1e-13, abs=1e-300
            )


def test_a_run_is_the_api_with_the_programs_defaults(tmp_path):
    expected.write(str(tmp_path), {"chain_midpoint"})
    rows = read(tmp_path / "chain_midpoint.csv")
    # chain --N 3 --map midpoint --kc 2: the C program's start is its seed 1
    res = simulate("chain", {"N": 3, "kc": 2.0}, None, 1e-3, 200, 15, "midpoint", every=10, seed=1)
    assert rows[0] == list(res.header)
    assert [[float(v) for v in r[:-1]] + [int(r[-1])] for r in rows[1:]] == [
        list(r) for r in res.rows
    ]


def test_values_that_start_with_a_minus_stay_values():
    assert expected.joined("--x0 -0.5,1 --every 10 --certify") == [
        "--x0=-0.5,1",
        "--every=10",
        "--certify",
    ]
