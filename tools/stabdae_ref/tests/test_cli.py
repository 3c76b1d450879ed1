# SPDX-License-Identifier: GPL-3.0-or-later
"""The command line: the CSV columns of the C examples, the API's numbers, one stderr line and exit
2 with no file for bad input, exit 1 with the rows so far for a failing run."""

import csv
import os
import subprocess
import sys

import pytest

from stabdae_ref import simulate
from stabdae_ref.__main__ import main

HEADERS = {
    "oscillator": "t,X,Y,Xdot,Ydot,xi1,xi2,mu1,mu2,E,W,newton_iters",
    "pendulum": "t,X,Y,Xdot,Ydot,xi1,xi2,mu1,mu2,E,newton_iters",
    "chain": "t,max_abs_Y,max_abs_Ydot,E,newton_iters",
}


def read(path):
    with open(path) as f:
        return list(csv.reader(f))


@pytest.mark.parametrize("model", sorted(HEADERS))
def test_csv_columns_and_rows(model, tmp_path):
    out = tmp_path / "run.csv"
    assert main([model, "--steps", "20", "--every", "5", "--out", str(out)]) == 0
    rows = read(out)
    assert ",".join(rows[0]) == HEADERS[model]
    assert [float(r[0]) for r in rows[1:]] == pytest.approx([0, 0.005, 0.01, 0.015, 0.02])


def test_csv_numbers_are_the_api_numbers(tmp_path):
    out = tmp_path / "run.csv"
    argv = [
        "oscillator",
        "--d",
        "0.1",
        "--x0",
        "0.2,0.4,0,0.1",
        "--scheme",
        "11",
        "--map",
        "midpoint",
        "--T",
        "0.002",
        "--steps",
        "30",
        "--delta",
        "3",
        "--eps",
        "0.5",
    ]
    assert main(argv + ["--out", str(out)]) == 0
    res = simulate(
        "oscillator",
        {"d": 0.1, "delta": 3, "eps": 0.5},
        (0.2, 0.4, 0, 0.1),
        0.002,
        30,
        11,
        "midpoint",
    )
    got = [[float(v) for v in r[:-1]] + [int(r[-1])] for r in read(out)[1:]]
    assert got == [list(r) for r in res.rows]  # %.17g round-trips a double exactly


def test_mpmath_csv_has_all_digits(tmp_path):
    out = tmp_path / "run.csv"
    assert (
        main(["pendulum", "--steps", "10", "--arith", "mpmath", "--dps", "30", "--out", str(out)])
        == 0
    )
    last = read(out)[-1]
    mantissa = last[1].lstrip("-").split("e")[0].replace(".", "").lstrip("0")
    assert len(mantissa) >= 20
    ref = simulate("pendulum", {}, None, 1e-3, 10, 15, "dgrad").rows[-1]
    assert float(last[1]) == pytest.approx(ref[1], rel=1e-13)


@pytest.mark.parametrize(
    "argv",
    [
        ["pendulum", "--k", "3"],
        ["pendulum", "--map", "user"],
        ["oscillator", "--T", "-1"],
        ["oscillator", "--T", "nan"],
        ["oscillator", "--tf", "1", "--steps", "3"],
        ["oscillator", "--x0", "1,2,3"],
        ["oscillator", "--x0", "a,b,c,d"],
        ["chain", "--N", "2", "--x0", "1,2,3,4"],
        ["chain", "--N", "0"],
        ["oscillator", "--scheme", "12"],
        ["oscillator", "--stabilizer", "baumgarte", "--alpha", "1"],
        ["oscillator", "--arith", "mpmath", "--dps", "5"],
        ["oscillator", "--m", "0"],
        ["oscillator", "--every", "0"],
        ["oscillator", "--bogus"],
        ["rod"],
        ["pendulum", "--x0", "0,0,1,1"],
        ["oscillator", "--seed", "3"],
        ["chain", "--seed", "-1"],
        ["pendulum", "--map", "dg"],
        ["oscillator", "--map", "dg-paper"],
    ],
)
def test_bad_input_exits_2_without_a_file(argv, tmp_path, capsys):
    out = tmp_path / "run.csv"
    assert main(argv + ["--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("stabdae_ref: ")
    assert not out.exists()


def test_failing_run_keeps_rows_and_exits_1(tmp_path, capsys):
    out = tmp_path / "run.csv"
    assert (
        main(
            [
                "oscillator",
                "--scheme",
                "11",
                "--map",
                "euler",
                "--T",
                "0.5",
                "--steps",
                "100",
                "--out",
                str(out),
            ]
        )
        == 1
    )
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "stopped at step" in err
    rows = read(out)
    assert rows[0][0] == "t" and 2 <= len(rows) - 1 < 101


def test_module_entry_point():
    tools = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    run = subprocess.run(
        [sys.executable, "-m", "stabdae_ref", "oscillator", "--steps", "4"],
        cwd=tools,
        capture_output=True,
        text=True,
        check=True,
    )
    lines = run.stdout.splitlines()
    assert lines[0] == HEADERS["oscillator"] and len(lines) == 6


def test_steps_are_counted_as_the_c_programs_count_them(tmp_path):
    """ceil(tf/T - 1e-9): 0.2/0.001 is 200.00000000000003 in doubles, 200 steps."""
    out = tmp_path / "run.csv"
    assert main(["pendulum", "--tf", "0.2", "--every", "200", "--out", str(out)]) == 0
    assert [r[0] for r in read(out)[1:]] == ["0", "0.20000000000000001"]


def test_chain_seed_is_the_random_start(tmp_path):
    out = tmp_path / "run.csv"
    assert main(["chain", "--N", "2", "--seed", "5", "--steps", "3", "--out", str(out)]) == 0
    res = simulate("chain", {"N": 2}, None, 1e-3, 3, seed=5)
    assert [[float(v) for v in r[:-1]] + [int(r[-1])] for r in read(out)[1:]] == [
        list(r) for r in res.rows
    ]


def test_expected_subcommand_writes_the_files(tmp_path):
    assert main(["expected", "--outdir", str(tmp_path)]) == 0
    assert len(list(tmp_path.glob("*.csv"))) == 10
