# SPDX-License-Identifier: GPL-3.0-or-later
"""The held-out check of the ensemble runner: every member of a sweep run again by the serial
example program, its CSV read, and the runner's row compared with it number by number.

    ensemble_compare.py OUTPUT MEMBERS PROGRAM [SHARED FLAGS...]

OUTPUT is the runner's CSV for MEMBERS with the SHARED FLAGS (the runner's own flags left out).
For member i the program runs with the shared flags and the row's --name value pairs, every
row kept (the flags must not set --every). Compared, exactly (the same doubles, written %.17g):
the program's columns against its last row; steps against the rows (one per step);
max_violation against the largest |constraint| column (xi1 for the oscillator and the
pendulum, max_abs_Y for the chain, max_abs_c for the mechanisms); energy_change against E
last minus E first; newton_iters_total against the sum of newton_iters (the normal forms);
chart_switches against the last switches (the mechanisms, else 0); each col@t against the first
row at t or later. A failed member's status must be the reason the program gives on stderr.
Exit 0 when every member agrees, 1 otherwise, naming the differences.
"""
import csv
import os
import subprocess
import sys
import tempfile

VIOLATION = {"xi1": "abs", "max_abs_Y": "max", "max_abs_c": "max"}


def serial_rows(program, argv, path):
    run = subprocess.run([program, *argv, "--out", path], capture_output=True, text=True)
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return run.returncode, run.stderr, rows[0], rows[1:]


def expected(header, rows, stderr, code):
    """The runner's row as the serial program's CSV and messages say it must be."""
    col = {name: j for j, name in enumerate(header)}
    num = [[float(x) for x in r] for r in rows]
    want = {}
    if code == 0:
        want["status"] = "ok"
    elif "stopped at" in stderr:  # "PROG: stopped at step N (t = T): REASON"
        want["status"] = stderr.strip().split("): ", 1)[-1]
    else:  # "PROG: step N from t = T failed: REASON"
        want["status"] = stderr.strip().split("failed: ", 1)[-1]
    # the steps taken: one per row, or as the message says (a row that could not be written
    # stops the run after its step; a failed step is the one after the last taken)
    words = stderr.split()
    if "stopped at" in stderr:
        want["steps"] = words[words.index("step") + 1]
    elif code != 0:
        want["steps"] = str(int(words[words.index("step") + 1]) - 1)
    else:
        want["steps"] = str(len(rows) - 1)
    if not rows:
        return want, col
    for name, j in col.items():
        want[name] = rows[-1][j]
    vname = next(n for n in VIOLATION if n in col)
    want["max_violation"] = max(abs(r[col[vname]]) for r in num)
    want["energy_change"] = num[-1][col["E"]] - num[0][col["E"]]
    if "newton_iters" in col:
        want["newton_iters_total"] = str(sum(int(r[col["newton_iters"]]) for r in rows))
    want["chart_switches"] = rows[-1][col["switches"]] if "switches" in col else "0"
    return want, col


def at_rows(want, header, rows, out_header):
    """col@t: the first row with t >= t_k - 1e-9 T (T the rows' spacing)."""
    T = float(rows[1][0]) - float(rows[0][0]) if len(rows) > 1 else 0.0
    for name in out_header:
        if "@" not in name:
            continue
        c, t = name.rsplit("@", 1)
        hit = [r for r in rows if float(r[0]) >= float(t) - 1e-9 * T]
        want[name] = hit[0][header.index(c)] if hit else ""


def same(a, b):
    if isinstance(a, float):
        return b != "" and float(b) == a
    return a == b


def main():
    output, members, program, shared = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    with open(output, newline="") as f:
        out = list(csv.DictReader(f))
        out_header = list(out[0].keys()) if out else []
    with open(members, newline="") as f:
        rows = list(csv.reader(f))
    names, rows = rows[0], rows[1:]
    bad = 0
    if len(out) != len(rows):
        print(f"{len(out)} output rows for {len(rows)} members")
        return 1
    with tempfile.TemporaryDirectory() as tmp:
        for i, (row, got) in enumerate(zip(rows, out)):
            argv = shared + [x for n, v in zip(names, row) for x in (f"--{n}", v)]
            code, err, header, data = serial_rows(program, argv, os.path.join(tmp, "s.csv"))
            want, _ = expected(header, data, err, code)
            if data:
                at_rows(want, header, data, out_header)
            if got["member"] != str(i):
                print(f"row {i}: member {got['member']}")
                bad = 1
            for key, value in want.items():
                if not same(value, got[key]):
                    print(f"member {i} ({' '.join(argv)}): {key} = {got[key]!r}, "
                          f"the serial program gives {value!r}")
                    bad = 1
    print(f"{len(rows)} members compared with {os.path.basename(program)}: "
          + ("differences" if bad else "the same numbers"))
    return bad


if __name__ == "__main__":
    sys.exit(main())
