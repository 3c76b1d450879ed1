# SPDX-License-Identifier: GPL-3.0-or-later
"""Tests of sparse_race.py: sparse_race's CSV read by mechanism and solver, a CSV not of its
form refused with one line and exit 1, and the plot written as a PNG.

  build/venv/bin/python -m pytest tools/benchmarks/test_sparse_race.py
"""

from __future__ import annotations

import contextlib
import io
import os
import tempfile
import unittest

from benchmarks import sparse_race

CSV = """mechanism,solver,setting,seconds,error
rope (t = 1),rk4,0.01,0.0095,1.4e-07
rope (t = 1),rk4,0.005,0.0275,8.9e-09
rope (t = 1),IDA/KLU index-1,1e-06,0.0092,4.6e-07
ladder (t = 0.1),rk8,0.02,0.00115,4.2e-13
"""


class SparseRace(unittest.TestCase):
    def setUp(self) -> None:
        self.dir = tempfile.TemporaryDirectory()
        self.csv = os.path.join(self.dir.name, "race.csv")
        with open(self.csv, "w", encoding="utf-8") as f:
            f.write(CSV)

    def tearDown(self) -> None:
        self.dir.cleanup()

    def test_points_by_mechanism_and_solver(self) -> None:
        p = sparse_race.read(self.csv)
        self.assertEqual(list(p), ["rope (t = 1)", "ladder (t = 0.1)"])
        self.assertEqual(p["rope (t = 1)"]["rk4"], [(0.0095, 1.4e-07), (0.0275, 8.9e-09)])
        self.assertEqual(p["ladder (t = 0.1)"]["rk8"], [(0.00115, 4.2e-13)])

    def test_a_csv_of_another_form_is_refused(self) -> None:
        bad = os.path.join(self.dir.name, "bad.csv")
        with open(bad, "w", encoding="utf-8") as f:
            f.write("mechanism,solver,seconds\nrope,rk4,1\n")
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            rc = sparse_race.main(["--csv", bad, "--plot", os.path.join(self.dir.name, "x.png")])
        self.assertEqual(rc, 1)
        self.assertEqual(len(err.getvalue().splitlines()), 1)
        self.assertIn("header", err.getvalue())

    def test_the_plot_is_a_png(self) -> None:
        png = os.path.join(self.dir.name, "race.png")
        self.assertEqual(sparse_race.main(["--csv", self.csv, "--plot", png]), 0)
        with open(png, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")


if __name__ == "__main__":
    unittest.main()
