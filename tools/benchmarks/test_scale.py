# SPDX-License-Identifier: GPL-3.0-or-later
"""Tests of scale.py: the table read by its columns' names and merged, the command's errors and
its run without MuJoCo (against a stand-in for rope_scale), and, when MuJoCo is installed, that
its chain is the rope of examples/models/rope.c: the start of mech_rope_start, the accelerations
of the rope's index-1 form in Cartesian coordinates, the small pendulum's period, energy kept to
RK4's order.

  build/venv/bin/python -m pytest tools/benchmarks/test_scale.py
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import stat
import sys
import tempfile
import unittest
from typing import Any
from unittest import mock

import numpy as np

from benchmarks import scale

MJ = scale.load_mujoco()
needs_mujoco = unittest.skipIf(MJ is None, f"MuJoCo missing (pip install {scale.MUJOCO_PIN})")

# a stand-in for rope_scale: its columns in another order, one more, and an IDA column
FAKE_TABLE = """\
| N | rk4 sparse, us/step | max abs(c) | IDA/KLU, us/step | coordinates | index-1 RK4, us/step |
|---:|---:|---:|---:|---:|---:|
| 8 | 10.0 | 1e-15 | 30.0 | 16 | 5.0 |
| 16 | 20.0 | 2e-15 | 61.0 | 32 | 40.0 |
| 32 | 40.0 | 4e-15 | 125.0 | 64 | - |
"""


def fake_rope_scale(directory: str, status: int = 0) -> str:
    path = os.path.join(directory, "rope_scale")
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"#!/bin/sh\ncat <<'EOF'\n{FAKE_TABLE}EOF\nexit {status}\n")
    os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR)
    return path


def run_main(args: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = scale.main(args)
    return rc, out.getvalue(), err.getvalue()


class TableTest(unittest.TestCase):
    def test_columns_by_name_and_merge(self) -> None:
        t = scale.parse_table("noise\n" + FAKE_TABLE)
        self.assertEqual(t.column("coordinates"), 4)
        self.assertEqual([r[t.column("N")] for r in t.rows], ["8", "16", "32"])
        self.assertEqual(
            [h for h in t.header if scale.is_timing(h)],
            ["rk4 sparse, us/step", "IDA/KLU, us/step", "index-1 RK4, us/step"],
        )
        m = scale.merge(t, scale.MUJOCO_HEADER, ["1.0", "2.0", "-"])
        self.assertEqual(m.header[-1], scale.MUJOCO_HEADER)  # after the last timing column
        self.assertEqual(m.rows[2][-1], "-")
        back = scale.parse_table(scale.render(m))
        self.assertEqual(back.rows, m.rows)
        self.assertIsNone(scale.number("-"))
        self.assertEqual(scale.number("1e-15"), 1e-15)

    def test_malformed(self) -> None:
        with self.assertRaises(ValueError):
            scale.parse_table("| N | a |\n|---:|---:|\n| 8 |\n")
        with self.assertRaises(ValueError):
            scale.parse_table("no table\n")


class CommandTest(unittest.TestCase):
    def test_usage_errors(self) -> None:
        with tempfile.TemporaryDirectory() as d:
            exe = fake_rope_scale(d)
            for args in (
                [],
                ["--rope-scale", os.path.join(d, "none")],
                ["--rope-scale", exe, "--reps", "0"],
                ["--rope-scale", exe, "--max-n", "4"],
                ["--rope-scale", exe, "--budget", "x"],
                ["--rope-scale", exe, "--what"],
            ):
                rc, out, err = run_main(args)
                self.assertEqual(rc, 2, args)
                self.assertEqual(out, "")
                self.assertEqual(len(err.strip().splitlines()), 1, err)

    def test_rope_scale_fails(self) -> None:
        with tempfile.TemporaryDirectory() as d:
            rc, _, err = run_main(["--rope-scale", fake_rope_scale(d, 1)])
            self.assertEqual(rc, 1)
            self.assertIn("status 1", err)

    def test_without_mujoco(self) -> None:
        with tempfile.TemporaryDirectory() as d, mock.patch.dict(sys.modules, {"mujoco": None}):
            png, md = os.path.join(d, "s.png"), os.path.join(d, "s.md")
            rc, _, err = run_main(
                ["--rope-scale", fake_rope_scale(d), "--plot", png, "--table", md]
            )
            self.assertEqual(rc, 0, err)
            self.assertIn(f"pip install {scale.MUJOCO_PIN}", err)
            with open(md, encoding="utf-8") as f:
                t = scale.parse_table(f.read())
            col = t.column(scale.MUJOCO_HEADER)
            self.assertEqual([r[col] for r in t.rows], ["-", "-", "-"])
            with open(png, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    @needs_mujoco
    def test_with_mujoco(self) -> None:
        with tempfile.TemporaryDirectory() as d:
            rc, out, err = run_main(
                [
                    "--rope-scale",
                    fake_rope_scale(d),
                    "--mujoco-max",
                    "16",
                    "--reps",
                    "1",
                    "--budget",
                    "0.01",
                ]
            )
            self.assertEqual(rc, 0, err)
            t = scale.parse_table(out)
            cells = [r[t.column(scale.MUJOCO_HEADER)] for r in t.rows]
            self.assertGreater(float(cells[0]), 0.0)
            self.assertGreater(float(cells[1]), 0.0)
            self.assertEqual(cells[2], "-")

    @needs_mujoco
    def test_mujoco_cannot_build(self) -> None:
        real = scale.chain_model

        def refuse(mj: Any, n: int) -> Any:
            if n >= 16:
                raise scale.ModelError("depth limit exceeded")
            return real(mj, n)

        with tempfile.TemporaryDirectory() as d, mock.patch.object(scale, "chain_model", refuse):
            rc, out, err = run_main(
                ["--rope-scale", fake_rope_scale(d), "--reps", "1", "--budget", "0.01"]
            )
        self.assertEqual(rc, 0, err)
        self.assertIn("cannot build the chain of N = 16", err)
        t = scale.parse_table(out)
        cells = [r[t.column(scale.MUJOCO_HEADER)] for r in t.rows]
        self.assertGreater(float(cells[0]), 0.0)
        self.assertEqual(cells[1:], ["-", "-"])


def cartesian(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> tuple[np.ndarray, ...]:
    """The masses' positions, velocities and accelerations (N x 2) from the hinge angles."""
    phi, w, al = np.cumsum(q), np.cumsum(qd), np.cumsum(qdd)
    c, s = np.cos(phi), np.sin(phi)
    p = np.cumsum(np.stack([c, s], 1), 0)
    v = np.cumsum(np.stack([-s * w, c * w], 1), 0)
    a = np.cumsum(np.stack([-s * al - c * w * w, c * al - s * w * w], 1), 0)
    return p, v, a


def rope_acceleration(p: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The rope of rope.c on its index-1 form: M = I, F = (0, -9.81) per mass, c_j = (|p_j -
    p_{j-1}|^2 - 1) / 2 (p_0 the origin); [M G^T; G 0] [a; lambda] = [F; -Gdot v]."""
    n = len(p)
    d = p - np.vstack([[0.0, 0.0], p[:-1]])
    dv = v - np.vstack([[0.0, 0.0], v[:-1]])
    g = np.zeros((n, 2 * n))
    for j in range(n):
        g[j, 2 * j : 2 * j + 2] = d[j]
        if j > 0:
            g[j, 2 * j - 2 : 2 * j] = -d[j]
    kkt = np.block([[np.eye(2 * n), g.T], [g, np.zeros((n, n))]])
    rhs = np.concatenate([np.tile([0.0, -scale.GRAVITY], n), -np.sum(dv * dv, 1)])
    return np.linalg.solve(kkt, rhs)[: 2 * n].reshape(n, 2)


@needs_mujoco
class ChainTest(unittest.TestCase):
    mj: Any = MJ

    def test_options(self) -> None:
        m = scale.chain_model(self.mj, 4)
        self.assertEqual(m.opt.integrator, self.mj.mjtIntegrator.mjINT_RK4)
        self.assertEqual(m.opt.timestep, scale.T)
        self.assertTrue(m.opt.disableflags & self.mj.mjtDisableBit.mjDSBL_CONTACT)
        np.testing.assert_array_equal(m.opt.gravity, [0.0, -scale.GRAVITY, 0.0])
        self.assertEqual((m.nv, m.ngeom, m.neq), (4, 0, 0))
        np.testing.assert_array_equal(m.body_mass[1:], 1.0)

    def test_start(self) -> None:
        """mech_rope_start(0.3): mass j at (j cos 0.3, -j sin 0.3), at rest."""
        n = 8
        m = scale.chain_model(self.mj, n)
        d = self.mj.MjData(m)
        scale.chain_start(self.mj, m, d)
        j = np.arange(1, n + 1)
        want = np.stack([j * math.cos(0.3), -j * math.sin(0.3)], 1)
        np.testing.assert_allclose(d.xipos[1:, :2], want, atol=1e-14)
        np.testing.assert_array_equal(d.qvel, 0.0)

    def test_same_mechanism(self) -> None:
        """At random states MuJoCo's accelerations are the Cartesian rope's."""
        rng = np.random.default_rng(7)
        for n in (1, 2, 8, 33):
            m = scale.chain_model(self.mj, n)
            d = self.mj.MjData(m)
            for _ in range(3):
                d.qpos[:] = rng.uniform(-math.pi, math.pi, n)
                d.qvel[:] = rng.normal(0.0, 1.0, n)
                self.mj.mj_forward(m, d)
                p, v, a = cartesian(d.qpos, d.qvel, d.qacc)
                np.testing.assert_allclose(p, d.xipos[1:, :2], atol=1e-12)
                want = rope_acceleration(p, v)
                scale_a = max(1.0, float(np.max(np.abs(want))))
                # the point masses' inertia (1e-9 about their centres) the only difference
                np.testing.assert_allclose(a, want, rtol=0, atol=1e-7 * scale_a)

    def test_pendulum_period(self) -> None:
        """N = 1, amplitude 1e-3 from hanging: period 2 pi sqrt(1 / 9.81) (amplitude's
        correction 1e-6 / 16)."""
        m = scale.chain_model(self.mj, 1)
        d = self.mj.MjData(m)
        self.mj.mj_resetData(m, d)
        d.qpos[0] = -math.pi / 2 + 1e-3
        prev, ups = d.qpos[0] + math.pi / 2, []
        for _ in range(7000):
            self.mj.mj_step(m, d)
            cur = d.qpos[0] + math.pi / 2
            if prev < 0.0 <= cur:  # upward through hanging, linearly interpolated
                ups.append(d.time - scale.T * cur / (cur - prev))
            prev = cur
        period = (ups[-1] - ups[0]) / (len(ups) - 1)
        self.assertGreaterEqual(len(ups), 3)
        self.assertAlmostEqual(
            period / (2 * math.pi * math.sqrt(1 / scale.GRAVITY)), 1.0, delta=1e-6
        )

    def energy_error(self, n: int, h: float, t_end: float) -> float:
        m = scale.chain_model(self.mj, n)
        m.opt.timestep = h
        m.opt.enableflags |= self.mj.mjtEnableBit.mjENBL_ENERGY
        d = self.mj.MjData(m)
        scale.chain_start(self.mj, m, d)
        e0, worst = float(d.energy.sum()), 0.0
        for _ in range(round(t_end / h)):
            self.mj.mj_step(m, d)
            self.mj.mj_forward(m, d)  # the energy at the new state
            worst = max(worst, abs(float(d.energy.sum()) - e0))
        return worst / (scale.GRAVITY * n * (n + 1) / 2)  # relative to the potential's scale

    def test_energy(self) -> None:
        """Energy kept along 3 s from the rope's start, its error of RK4's order 4."""
        coarse, fine = self.energy_error(8, 2 * scale.T, 3.0), self.energy_error(8, scale.T, 3.0)
        self.assertLess(fine, 1e-9)
        self.assertGreater(coarse / fine, 2.0**3.5)

    @unittest.skipUnless(MJ is not None and MJ.__version__ == "4.0.0", "MuJoCo 4.0.0's limit")
    def test_depth_limit(self) -> None:
        """MuJoCo 4.0.0 builds the chain of 1023 bodies, not of 1024."""
        self.assertEqual(scale.chain_model(self.mj, 1023).nv, 1023)
        with self.assertRaises(scale.ModelError):
            scale.chain_model(self.mj, 1024)

    def test_timing(self) -> None:
        s = scale.time_mujoco(self.mj, 8, 1, 0.01)
        self.assertTrue(0.0 < s < 0.01)


if __name__ == "__main__":
    unittest.main()
