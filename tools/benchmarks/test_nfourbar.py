# SPDX-License-Identifier: GPL-3.0-or-later
"""Tests of nfourbar.py: the elliptic reference against mpmath's Taylor solver on the ODE and
against its own first integral, the parallelogram's J and K against the C model's energy, the
error measure and the CSV reader, the table and its summary, the command's errors; a short run
of build/examples/nfourbar (rk8 within a bound from its order, rk4 converging at order four);
and, when MuJoCo is installed, its model: 2N + 1 hinges, the start's energy and constraints,
the parallelogram's energy and acceleration, B_0 by forward kinematics, a short run near the
reference, RK4's stability of the soft constraints.

  build/venv/bin/python -m pytest tools/benchmarks/test_nfourbar.py

build/examples/nfourbar is found in STABDAE_BUILD (default build/); without it its tests skip.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import random
import re
import stat
import sys
import tempfile
import unittest
from typing import Any
from unittest import mock

import mpmath

from benchmarks import nfourbar

MJ = nfourbar.load_mujoco()
needs_mujoco = unittest.skipIf(MJ is None, f"MuJoCo missing (pip install {nfourbar.MUJOCO_PIN})")

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("STABDAE_BUILD", os.path.join(ROOT, "build"))
EXE = os.path.join(BUILD, "examples", "nfourbar")
needs_exe = unittest.skipUnless(os.access(EXE, os.X_OK), f"{EXE} not built")

G = 9.81
# the parallelogram from first principles (m = 1, L = 1): the N + 1 rockers about their ends
# (1/3 each), the N couplers translating (1 each); their centres at heights cos(theta) / 2 and
# cos(theta)
J40 = 41 / 3 + 40
K40 = 41 / 2 + 40


def run_main(args: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = nfourbar.main(args)
    return rc, out.getvalue(), err.getvalue()


def fake_nfourbar(directory: str, body: str) -> str:
    path = os.path.join(directory, "nfourbar")
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"#!/bin/sh\n{body}\n")
    os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR)
    return path


def csv_text(points: list[tuple[float, float]], dt: float = 0.05) -> str:
    """An nfourbar-like CSV: t,q1,q2,E with B_0 at t = 0 (upright) and the given points."""
    rows = ["t,q1,q2,E", "0,0,1,0"]
    rows += [f"{(k + 1) * dt!r},{x!r},{y!r},0" for k, (x, y) in enumerate(points)]
    return "\n".join(rows) + "\n"


class ReferenceTest(unittest.TestCase):
    def test_pendulum_constants(self) -> None:
        j, k = nfourbar.pendulum()
        self.assertAlmostEqual(float(j), J40, places=13)
        self.assertAlmostEqual(float(k), K40, places=13)
        self.assertAlmostEqual(float(nfourbar.omega2()), K40 * G / J40, places=13)

    def test_against_the_ode(self) -> None:
        """mpmath's Taylor solver on theta'' = w^2 sin(theta), theta(0) = 0, theta'(0) = 1,
        through the first three flat positions (theta = pi/2, 3 pi/2, 5 pi/2 by t = 3)."""
        with mpmath.workdps(25):
            w2 = mpmath.mpf(363) / 322 * mpmath.mpf("9.81")  # K / J = (121/2) / (161/3)
            self.assertAlmostEqual(float(w2), float(nfourbar.omega2()), places=14)
            ode = mpmath.odefun(lambda t, y: [y[1], w2 * mpmath.sin(y[0])], 0, [0, 1])
            for k in range(0, 61, 4):
                t = mpmath.mpf(k) / 20
                self.assertLess(abs(float(nfourbar.theta(t) - ode(t)[0])), 1e-14, k)
            self.assertGreater(float(ode(mpmath.mpf(3))[0]), 5 * math.pi / 2)

    def test_first_integral(self) -> None:
        """theta'^2 / 2 + w^2 cos(theta) = 1/2 + w^2 along the reference, theta' by mpmath's
        numerical derivative of it (not by the elliptic formula's dn)."""
        rng = random.Random(3)
        with mpmath.workdps(30):
            w2 = nfourbar.omega2()
            self.assertEqual(nfourbar.theta(mpmath.mpf(0)), 0)
            self.assertLess(abs(mpmath.diff(nfourbar.theta, 0) - 1), 1e-20)
            for t in [mpmath.mpf(rng.uniform(0.0, 20.0)) for _ in range(8)]:
                th, dth = nfourbar.theta(t), mpmath.diff(nfourbar.theta, t)
                self.assertLess(abs(dth**2 / 2 + w2 * mpmath.cos(th) - (0.5 + w2)), 1e-20)

    def test_reference_b0(self) -> None:
        ref = nfourbar.reference(400)
        self.assertEqual(len(ref), 400)
        with mpmath.workdps(30):
            for k in (1, 57, 400):
                th = nfourbar.theta(mpmath.mpf(k) / 20)
                self.assertEqual(ref[k - 1], (float(mpmath.sin(th)), float(mpmath.cos(th))))
        for x, y in ref:  # on the unit circle about A_0
            self.assertAlmostEqual(math.hypot(x, y), 1.0, places=15)


class MeasureTest(unittest.TestCase):
    def test_error(self) -> None:
        ref = [(1.0, 0.0), (0.0, 1.0)]
        self.assertEqual(nfourbar.error(ref, ref), 0.0)
        self.assertAlmostEqual(nfourbar.error([(1.0, 0.0), (0.3, 1.4)], ref), 0.5, places=15)
        self.assertEqual(nfourbar.error([(math.nan, 0.0), (0.0, 1.0)], ref), math.inf)
        with self.assertRaises(ValueError):
            nfourbar.error(ref[:1], ref)

    def test_every_and_outputs(self) -> None:
        self.assertEqual(nfourbar.every(2.5e-2), 2)
        self.assertEqual(nfourbar.every(6.25e-3), 8)
        self.assertEqual(nfourbar.every(5e-2), 1)
        for bad in (3e-2, 1 / 30, 0.1, 0.0, -1e-2):
            with self.assertRaises(ValueError):
                nfourbar.every(bad)
        self.assertEqual(nfourbar.output_count(20.0), 400)
        self.assertEqual(nfourbar.output_count(1.5), 30)
        for bad in (0.0, 0.07, -1.0):
            with self.assertRaises(ValueError):
                nfourbar.output_count(bad)

    def test_read_b0(self) -> None:
        pts = [(0.1, 0.9), (0.2, 0.8)]
        self.assertEqual(nfourbar.read_b0(csv_text(pts), 2), pts)
        for text in (
            "",
            csv_text(pts).replace("q1", "x1"),  # no q1
            csv_text(pts, dt=0.04),  # rows off the outputs
            csv_text(pts[:1]),  # a row short
            csv_text(pts) + "1,2\n",  # a short row
        ):
            with self.assertRaises(ValueError):
                nfourbar.read_b0(text, 2)


class TableTest(unittest.TestCase):
    def results(self) -> list[nfourbar.Result]:
        R = nfourbar.Result
        return [
            R("stabdae", "rk8", "s", 2.5e-2, 800, 4e-5, 2.0),
            R("stabdae", "rk8", "s", 5e-2, 400, 2e-2, 1.0),  # faster, outside the criterion
            R("stabdae", "rk4", "s", 1e-2, 2000, failure="nfourbar exited with status 1"),
            R("MuJoCo", "RK4", "m", 1e-3, 20000, 1e-4, 4.0),
            R("MuJoCo", "RK4", "m", 5e-3, 4000, 9.9e-4, 0.5),
            R("MuJoCo", "RK4", "m", 1e-2, 2000, 1.1e-3, 0.25),
        ]

    def test_render(self) -> None:
        text = nfourbar.render(self.results())
        lines = text.splitlines()
        cells = [[c.strip() for c in ln.strip().strip("|").split("|")] for ln in lines[:8]]
        self.assertEqual(cells[0], nfourbar.HEADER)
        self.assertTrue(all(len(c) == len(nfourbar.HEADER) for c in cells))
        self.assertEqual(cells[2][5:], ["4.00e-05", "yes", "2.000"])
        self.assertEqual(cells[3][6], "no")
        self.assertEqual(cells[4][5:], ["-", "failed", "-"])
        self.assertEqual(cells[6][6], "yes")  # 9.9e-4 within 1e-3
        self.assertEqual(cells[7][6], "no")  # 1.1e-3 not
        self.assertEqual(lines[8], "")
        self.assertTrue(lines[9].endswith(" = 4.00"), lines[9])  # 2.0 s over 0.5 s
        self.assertIn("T = 0.025", lines[9])
        self.assertIn("T = 0.005", lines[9])

    def test_cells_escaped(self) -> None:
        """A setting's pipe (as in |R|) or line break does not split or end its row."""
        r = nfourbar.Result("MuJoCo", "RK4", "a | b\nc", 1e-3, 20000, 1e-4, 1.0)
        line = nfourbar.render([r]).splitlines()[2]
        self.assertEqual(len(re.split(r"(?<!\\)\|", line)) - 2, len(nfourbar.HEADER))
        self.assertIn("| a \\| b c |", line)

    def test_defaults_divide_the_outputs(self) -> None:
        for t in (*nfourbar.STABDAE_T, *nfourbar.MUJOCO_T):
            self.assertAlmostEqual(nfourbar.every(t) * t, 0.05, places=15)

    def test_summary_without_a_side(self) -> None:
        rs = [r for r in self.results() if r.solver == "stabdae"]
        self.assertIn("none (MuJoCo: no run", nfourbar.summary(rs))
        missing = nfourbar.Result("MuJoCo", "RK4", "m", 1e-3, 20000, ran=False)
        self.assertFalse(missing.within)
        self.assertEqual(nfourbar.row(missing)[5:], ["-", "-", "-"])

    def test_median(self) -> None:
        self.assertEqual(nfourbar.median([3.0, 1.0, 2.0]), 2.0)
        self.assertEqual(nfourbar.median([4.0, 1.0]), 2.5)


class CommandTest(unittest.TestCase):
    def test_usage_errors(self) -> None:
        with tempfile.TemporaryDirectory() as d:
            exe = fake_nfourbar(d, "exit 0")
            for args in (
                [],
                ["--nfourbar", os.path.join(d, "none")],
                ["--nfourbar", exe, "--reps", "0"],
                ["--nfourbar", exe, "--stabdae-T", "3e-2"],  # does not divide 0.05
                ["--nfourbar", exe, "--mujoco-T", "1e-3,x"],
                ["--nfourbar", exe, "--maps", "rk8,rk5"],
                ["--nfourbar", exe, "--mujoco-solref", "0.1:1"],
                ["--nfourbar", exe, "--mujoco-solref", "2"],
                ["--nfourbar", exe, "--tf", "0.07"],
                ["--nfourbar", exe, "--tf", "30"],
                ["--nfourbar", exe, "--what"],
            ):
                rc, out, err = run_main(args)
                self.assertEqual(rc, 2, args)
                self.assertEqual(out, "")
                self.assertEqual(len(err.strip().splitlines()), 1, err)

    def test_a_run_fails(self) -> None:
        """nfourbar's failure, or its unreadable CSV: exit 1, the table written all the same."""
        with tempfile.TemporaryDirectory() as d:
            for body in ("echo 'nfourbar: step 3 failed' >&2; exit 1", "echo t,q1,q2"):
                exe = fake_nfourbar(d, body)
                md = os.path.join(d, "t.md")
                rc, out, err = run_main(
                    ["--nfourbar", exe, "--tf", "0.1", "--mujoco-T", "none", "--table", md]
                )
                self.assertEqual(rc, 1, err)
                self.assertEqual(out, "")
                with open(md, encoding="utf-8") as f:
                    self.assertEqual(f.read().count("| failed |"), len(nfourbar.STABDAE_T))
                self.assertIn("failed: stabdae rk8", err)

    @needs_exe
    def test_without_mujoco(self) -> None:
        with mock.patch.dict(sys.modules, {"mujoco": None}):
            rc, out, err = run_main(
                ["--nfourbar", EXE, "--tf", "0.5", "--stabdae-T", "2.5e-2", "--reps", "1"]
            )
        self.assertEqual(rc, 0, err)
        self.assertIn(f"pip install {nfourbar.MUJOCO_PIN}", err)
        rows = [ln for ln in out.splitlines() if ln.startswith("| MuJoCo ")]
        self.assertEqual(len(rows), len(nfourbar.MUJOCO_T) * len(nfourbar.MUJOCO_SOLREF))
        self.assertTrue(all(ln.endswith("| - | - | - |") for ln in rows))
        self.assertIn("| stabdae | rk8 |", out)
        self.assertIn("none (MuJoCo: no run", out)


@needs_exe
class StabdaeTest(unittest.TestCase):
    """build/examples/nfourbar over the first 1.5 s: through the flat positions at t = 0.72 and
    1.24 s."""

    def b0_error(self, method: str, t_step: float, sparse: bool = False) -> float:
        ref = nfourbar.reference(30)
        _, text = nfourbar.run_stabdae(EXE, method, t_step, 1.5, sparse)
        return nfourbar.error(nfourbar.read_b0(text, 30), ref)

    def test_rk8(self) -> None:
        """rk8's global error ~ (s T)^8 with s = sqrt(1 + 4 w^2) = 6.2 rad/s the motion's
        fastest rate: (0.062)^8 = 2e-10 at T = 1e-2; 1e-6 leaves room for the crossings'
        projected steps (docs/front-ends.md)."""
        self.assertLess(self.b0_error("rk8", 1e-2), 1e-6)

    def test_rk4_order(self) -> None:
        """rk4's error falls by 2^4 = 16 when T halves (within a factor 1.5 either way)."""
        coarse, fine = self.b0_error("rk4", 5e-3), self.b0_error("rk4", 2.5e-3)
        self.assertLess(fine, 1e-3)
        self.assertTrue(16 / 1.5 < coarse / fine < 16 * 1.5, (coarse, fine))

    def test_sparse_rk4_order(self) -> None:
        """--sparse, the sparse back-end (its steps projected at the crossings too): rk4 at its
        order as on the dense one."""
        coarse, fine = self.b0_error("rk4", 5e-3, True), self.b0_error("rk4", 2.5e-3, True)
        self.assertLess(fine, 1e-3)
        self.assertTrue(16 / 1.5 < coarse / fine < 16 * 1.5, (coarse, fine))

    def test_start_and_energy(self) -> None:
        """The first row: B_0 = (0, 1), the energy J / 2 + K g (theta' = 1, every centre at its
        highest); the constraints kept to rounding."""
        _, text = nfourbar.run_stabdae(EXE, "rk8", 2.5e-2, 0.5)
        lines = text.splitlines()
        names = lines[0].split(",")
        first = dict(zip(names, map(float, lines[1].split(","))))
        self.assertEqual((first["t"], first["q1"], first["q2"]), (0.0, 0.0, 1.0))
        self.assertAlmostEqual(first["E"] / (J40 / 2 + K40 * G), 1.0, places=13)
        worst = max(float(ln.split(",")[names.index("max_abs_c")]) for ln in lines[1:])
        self.assertLess(worst, 1e-12)


@needs_mujoco
class MujocoTest(unittest.TestCase):
    mj: Any = MJ

    def test_model(self) -> None:
        for n in (1, 3, nfourbar.N):
            m = nfourbar.model(self.mj, 1e-3, nfourbar.Solref(2.0, 1.0), n)
            self.assertEqual((m.nv, m.njnt, m.neq, m.nbody), (2 * n + 1, 2 * n + 1, n, 2 * n + 2))
        self.assertEqual(m.opt.integrator, self.mj.mjtIntegrator.mjINT_RK4)
        self.assertEqual(m.opt.timestep, 1e-3)
        self.assertTrue(m.opt.disableflags & self.mj.mjtDisableBit.mjDSBL_CONTACT)
        self.assertEqual(list(m.opt.gravity), [0.0, -G, 0.0])
        self.assertEqual(list(m.body_mass[1:]), [1.0] * (2 * n + 1))
        self.assertEqual(int(m.eq_type[0]), int(self.mj.mjtEq.mjEQ_CONNECT))
        # the anchor on rocker i, computed by MuJoCo at qpos0: its tip, 1 along its y
        for i in range(n):
            self.assertEqual([round(float(v), 15) for v in m.eq_data[i][3:6]], [0.0, 1.0, 0.0])

    def test_refsafe(self) -> None:
        bit = self.mj.mjtDisableBit.mjDSBL_REFSAFE
        safe = nfourbar.model(self.mj, 1e-3, nfourbar.Solref(2.0, 0.25), 2)
        off = nfourbar.model(self.mj, 1e-3, nfourbar.Solref(0.5, 0.9), 2)
        self.assertFalse(safe.opt.disableflags & bit)
        self.assertTrue(off.opt.disableflags & bit)
        self.assertEqual(list(off.eq_solref[0]), [0.5e-3, 0.9])

    def start(self, n: int = nfourbar.N) -> tuple[Any, Any]:
        m = nfourbar.model(self.mj, 1e-3, nfourbar.Solref(0.5, 0.9), n)
        m.opt.enableflags |= self.mj.mjtEnableBit.mjENBL_ENERGY
        d = self.mj.MjData(m)
        nfourbar.start(self.mj, m, d)
        return m, d

    def test_start(self) -> None:
        """The benchmark's start: constraints satisfied, their velocities zero, the kinetic
        energy J theta'^2 / 2 = J / 2, the potential K g (MuJoCo's from y = 0)."""
        m, d = self.start()
        self.assertEqual(d.nefc, 3 * nfourbar.N)
        self.assertLess(max(abs(float(v)) for v in d.efc_pos), 1e-14)
        self.assertLess(max(abs(float(v)) for v in d.efc_vel), 1e-14)
        self.assertAlmostEqual(float(d.energy[1]), J40 / 2, places=12)
        self.assertAlmostEqual(float(d.energy[0]), K40 * G, places=10)
        self.assertEqual(nfourbar.b0(m, d), (-0.0, 1.0))

    def set_parallelogram(self, m: Any, d: Any, th: float, dth: float) -> None:
        for j in range(m.njnt):
            name = self.mj.mj_id2name(m, self.mj.mjtObj.mjOBJ_JOINT, j)
            sign = -1.0 if name.startswith("rocker") else 1.0
            d.qpos[m.jnt_qposadr[j]] = sign * th
            d.qvel[m.jnt_dofadr[j]] = sign * dth
        self.mj.mj_forward(m, d)

    def test_parallelogram_energy(self) -> None:
        """On the parallelogram (theta, theta') the kinetic energy is J theta'^2 / 2 and the
        potential K g cos(theta): MuJoCo's mass matrix and heights are the mechanism's."""
        m, d = self.start()
        for th, dth in ((0.3, 1.0), (2.0, -1.5), (math.pi - 0.1, 4.0), (-4.0, 3.0)):
            self.set_parallelogram(m, d, th, dth)
            self.assertAlmostEqual(float(d.energy[1]) / (J40 * dth**2 / 2), 1.0, places=12)
            self.assertAlmostEqual(float(d.energy[0]), K40 * G * math.cos(th), places=9)

    def test_parallelogram_acceleration(self) -> None:
        """Away from the flat positions (|cos(theta)| > 0.75), every rocker's angular
        acceleration is -w^2 sin(theta) about z (theta clockwise) and every coupler's relative
        one the opposite (translating), to 1e-3 of w^2: ten times the regularization (1 - d) /
        d = 1e-4 of the soft constraints' forces (nearer the flat positions the conditioning
        of A = J M^-1 J^T amplifies it: 3e-3 at theta = 1.5)."""
        m, d = self.start()
        w2 = K40 * G / J40
        for th, dth in ((0.3, 1.0), (math.pi - 0.1, 4.0), (-0.7, 2.0)):
            self.set_parallelogram(m, d, th, dth)
            want = -w2 * math.sin(th)
            for j in range(m.njnt):
                name = self.mj.mj_id2name(m, self.mj.mjtObj.mjOBJ_JOINT, j)
                sign = 1.0 if name.startswith("rocker") else -1.0
                a = float(d.qacc[m.jnt_dofadr[j]])
                self.assertAlmostEqual(sign * a, want, delta=1e-3 * w2, msg=(name, th))

    def test_b0_is_the_site(self) -> None:
        """b0 (forward kinematics of rocker 0's angle) is MuJoCo's site at its tip."""
        m, d = self.start(3)
        rng = random.Random(5)
        for _ in range(5):
            for j in range(m.nq):
                d.qpos[j] = rng.uniform(-math.pi, math.pi)
            self.mj.mj_kinematics(m, d)
            x, y = nfourbar.b0(m, d)
            site = d.site_xpos[m.site("B0").id]
            self.assertAlmostEqual(x, float(site[0]), places=14)
            self.assertAlmostEqual(y, float(site[1]), places=14)

    def test_short_run(self) -> None:
        """1.5 s at T = 1e-3 (through two flat positions): B_0 within 1e-4, a tenth of the
        criterion, of the reference, which has turned by more than 3 pi / 2 (loose: the soft
        constraints' error, not RK4's, sets it)."""
        ref = nfourbar.reference(30)
        r = nfourbar.time_mujoco(self.mj, 1e-3, nfourbar.Solref(0.5, 0.9), 1.5, 1, ref)
        self.assertIsNone(r.failure)
        self.assertEqual(r.steps, 1500)
        self.assertLess(r.error, 1e-4)
        self.assertGreater(r.cpu, 0.0)
        with mpmath.workdps(20):
            self.assertGreater(float(nfourbar.theta(mpmath.mpf("1.5"))), 3 * math.pi / 2)

    def test_stability(self) -> None:
        """RK4's amplification of a violation's modes: z = -2 (double) for timeconst T/2
        critically damped, R(-2) = 1/3; z = -3 for T/3, R(-3) = 11/8 > 1: that setting
        diverges (reported as a failed run), the defaults are stable."""
        self.assertAlmostEqual(nfourbar.Solref(0.5, 1.0).amplification(), 1 / 3, places=6)
        self.assertAlmostEqual(nfourbar.Solref(1 / 3, 1.0).amplification(), 11 / 8, places=6)
        for s in nfourbar.MUJOCO_SOLREF:
            self.assertLess(s.amplification(), 1.0, s)
        ref = nfourbar.reference(2)
        r = nfourbar.time_mujoco(self.mj, 1e-3, nfourbar.Solref(1 / 3, 1.0), 0.1, 1, ref)
        self.assertIsNotNone(r.failure)
        self.assertIn("not finite", r.failure or "")
        self.assertFalse(r.within)


if __name__ == "__main__":
    unittest.main()
