# SPDX-License-Identifier: GPL-3.0-or-later
"""The N-four-bar (IFToMM benchmark A02, N = 40) by stabdae and by MuJoCo's RK4, in the same
run: the benchmark's error against CPU time, and the CPU ratio at matching accuracy.

  python -m benchmarks.nfourbar --nfourbar build/examples/nfourbar [--maps LIST] [--sparse]
      [--stabdae-T LIST] [--mujoco-T LIST] [--mujoco-solref LIST] [--reps R] [--tf S]
      [--table FILE]

The mechanism: N four-bars in a row, 2N + 1 uniform rods of length 1 and mass 1; the rockers
i = 0..N turn about the ground pivots A_i = (i, 0), their tips B_i start at (i, 1); the couplers
join B_{i-1} and B_i; gravity 9.81 along -y; every B_i starts at (1, 0) m/s; 20 s. The motion
keeps the parallelogram: every rocker at the angle theta from the upright, J theta'' = K g
sin(theta), J = (N + 1) m / 3 + N m, K = (N + 1) m / 2 + N m, theta(0) = 0, theta'(0) = 1, B_0 =
(sin theta, cos theta). The reference is that pendulum turning over, by Jacobi's elliptic
functions in mpmath (30 digits): with w^2 = K g / J, s = sqrt(1 + 4 w^2) and m = 4 w^2 / s^2,
theta(t) = 2 am(s t / 2 + K(m) | m) - pi. The error is the benchmark's: the largest distance of
B_0 from the reference at t = 0.05 k, k = 1..400; the criterion 1e-3. Every T must divide 0.05
(a whole number of steps between the outputs: nothing is interpolated).

stabdae: build/examples/nfourbar (natural coordinates, 82 of them under 81 constraints; the
steps projected where the rockers are flat) run as a child for each map of --maps and each T
of --stabdae-T, a CSV row every 0.05 s (--every 0.05 / T), B_0 = (q1, q2); its CPU time the
child's user + system time (getrusage(RUSAGE_CHILDREN) before and after: the process's start,
set-up and CSV writing included), the median over --reps runs.

MuJoCo (4.0.0, an optional peer: `pip install mujoco==4.0.0`; without it its cells are "-",
said on stderr): each rocker a body with a hinge about z at its pivot, mass 1, the inertia of the
uniform rod about its centre (1/12 about x and z, 1e-9 along the rod, where nothing turns), its
centre at the rod's middle; coupler i a child of rocker i - 1 at its tip, a hinge about z, its
centre at its middle; an equality `connect` from coupler i's free end to rocker i's tip: 2N + 1
hinges and N loops closed by soft constraints. No contacts, integrator RK4, timestep T,
autoreset off (a diverging run stays non-finite and is reported), B_0 from rocker 0's angle q0
by forward kinematics, (-sin q0, cos q0) (d.site_xpos after mj_step is the last RK4 stage's,
not the new state's). mj_step is timed by the thread's CPU time (the nstep loop in C, between
two outputs), the median over --reps runs from the start.

MuJoCo's settings, to give it its best accuracy (measured here on 2026-12-04, 20 s each, one
run). Its error is the soft constraints', not RK4's truncation: stabdae's rk4 on the rigid
mechanism is at 7.9e-6 at T = 1e-3 (`--maps rk4 --stabdae-T 1e-3`), MuJoCo at 1e-4 to 7e-4
there, and its error falls as the constraints stiffen at a fixed T. So they are made as stiff
as is stable:
- solimp (0.9999, 0.9999, 0.001, 0.5, 2): the impedance d at its largest (mjMAXIMP) whatever
  the violation, the regularization R = (1 - d) / d diag(A) at its smallest. (0.99, 0.999, ...)
  gives 17 times the error (1.2e-2 against 7.3e-4 at T = 1e-3, solref (2T, 1)).
- solref (timeconst, dampratio) sets the reference acceleration -b r' - k r of a violation r,
  k = 1 / (d timeconst dampratio)^2, b = 2 / (d timeconst) (MuJoCo 4.0.0 subtracts the connect
  rows' Jdot v, so a consistent state is kept to the regularization). The violation's modes,
  l^2 + b l + k = 0, are integrated by RK4 at h = T: stable while RK4's amplification |1 + z +
  z^2/2 + z^3/6 + z^4/24|, z = T l, is below 1, and that predicts every divergence measured
  (solref (2T, 0.15): z = -0.5 +- 3.30i, 2.35; (T/3, 1): z = -3, 1.38; (T/2, 0.7): 1.26;
  (T/2, 1.1): 1.07; each goes non-finite within 1 s at T = 1e-3, 2.5e-3 and 5e-3, growing
  from rounding by about that factor a step). --mujoco-solref lists c:dampratio pairs,
  timeconst = c T, the amplification in the setting's cell; the defaults:
  - (2, 1): the documented minimum time constant (refsafe's, on) critically damped, as the
    manual's default dampratio: z = -0.5 (double). The softest: 7.3e-4 at T = 1e-3, out of the
    criterion from 2e-3 (2.0e-3).
  - (2, 0.2): refsafe on, underdamped to the stiffest stable at that time constant (k =
    6.25 / T^2, z = -0.5 +- 2.45i, 0.34; 0.15 diverges). Its error falls smoothly with T: 1.2e-4
    at 1e-3, 7.7e-4 at 5e-3, 1.3e-3 at 6.25e-3.
  - (2, 0.25): one notch softer (k = 4 / T^2, 0.57), about the best at large T in a sweep at
    T = 6.25e-3 and 1e-2 (c from 1 to 4, c dampratio from 0.4 to 0.8): within the criterion to
    T = 6.25e-3 (1.4e-4; (2, 0.22) and (2, 0.28) there 5.7e-4 and 1.2e-4); none is at 1e-2
    (1.3e-3 at best), at 0.05/7 or 0.05/6 (1.2e-3 and 1.8e-3 at best).
    Its error is not monotone in T (7.5e-5 at 5e-3, 3.7e-4 at 2.5e-3): at these steps RK4's
    own phase error offsets the softness' (at 6.25e-3 the error stays at 5e-5 up to t = 10),
    so its lead is partly luck of this motion and end time.
  - (0.5, 0.9): refsafe off, the largest stiffness and damping found stable (z = -2 +- 0.97i,
    0.20; at T/2, dampratio 0.8 to 1 are stable; 0.4T is stable at 1e-3 (6.5e-5) and loses the
    accuracy from 2e-3 (7.7e-2)). The best at small T (4.5e-5 at 2e-3, 1.1e-4 at 1e-3), out of
    the criterion from 3.125e-3 (5.2e-3): refsafe's 2T is what carries the larger steps.
- The exact diagonal of A for R (the diagexact flag, since 3.9.0) is off: with it the motion
  leaves the parallelogram's branch at a flat position (error 0.9 to 2) or diverges, at
  T = 1e-3, 2e-3 and 2.5e-3 with (2, 1) and (0.5, 0.9) alike.
- Solver Newton, tolerance 1e-10, 100 iterations at most: with equality constraints alone the
  solver's cost is quadratic and one Newton iteration solves it (solver_niter 1), where CG and
  PGS take 40 to 50. Jacobian auto (sparse at 81 dofs).
  noslip acts on friction only, of which there is none. Each connect has 3
  rows, the third (along z) zero on this planar mechanism: 3N rows for 2N constraints.

Output: a Markdown table, one row per (solver, setting, T): solver, map / integrator, setting,
T, steps, error, within 1e-3, CPU seconds; then the summary line: the fastest stabdae run within
the criterion against the fastest MuJoCo run within it, their CPU ratio stabdae / MuJoCo. To
stdout or --table. Exit status 0, 1 when a run fails (nfourbar's non-zero status or unreadable
output, MuJoCo's state not finite or a warning of MuJoCo's: its row says so, the table is
written all the same), 2 for bad usage.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import subprocess
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import mpmath

from benchmarks.scale import Parser, UsageError, load_mujoco, positive_int

PROG = "benchmarks.nfourbar"
MUJOCO_PIN = "mujoco==4.0.0"
N = 40  # four-bars in the row (the benchmark's)
GRAVITY = "9.81"  # the benchmark's, exact in the reference
TF = 20.0  # the benchmark's end time
OUTPUTS_PER_SECOND = 20  # outputs at t = k / 20 = 0.05 k
CRITERION = 1e-3  # the benchmark's high-precision criterion on B_0
DPS = 30  # the reference's working digits
MAX_REPS = 15
MAPS = ("euler", "midpoint", "dgrad", "dg4", "dg6", "midpoint4", "midpoint6", "rk4", "rk8")
STABDAE_SETTING = "scheme 15, delta 2, eps 1"  # the program's defaults
ROD_INERTIA = 1.0 / 12.0  # a uniform rod of length 1 and mass 1 about its centre, across it
AXIAL_INERTIA = 1e-9  # along the rod (nothing turns about it; MuJoCo needs it positive)
SOLIMP = (0.9999, 0.9999, 0.001, 0.5, 2.0)  # the impedance at mjMAXIMP throughout
STABDAE_T = (5e-2, 2.5e-2, 1.25e-2, 1e-2)
MUJOCO_T = (1e-2, 6.25e-3, 5e-3, 2.5e-3, 1e-3)
SOLVER_TOLERANCE = 1e-10
SOLVER_ITERATIONS = 100
HEADER = [
    "solver",
    "map / integrator",
    "setting",
    "T",
    "steps",
    "error",
    "within 1e-3",
    "CPU s",
]
ALIGN = ["---", "---", "---", "---:", "---:", "---:", "---", "---:"]

# The options in MJCF (the bodies are added by MjSpec); {t} the timestep, {refsafe} the flag.
MJCF = """<mujoco model="nfourbar">
  <option timestep="{t!r}" integrator="RK4" gravity="0 -{g} 0" solver="Newton"
          tolerance="{tol:g}" iterations="{it}" jacobian="auto">
    <flag contact="disable" autoreset="disable" refsafe="{refsafe}"/>
  </option>
  <worldbody/>
</mujoco>"""


# --- the reference ---------------------------------------------------------------------------


def pendulum(n: int = N) -> tuple[Any, Any]:
    """(J, K) of the parallelogram's J theta'' = K g sin(theta), in mpmath (m = 1, L = 1): the
    N + 1 rockers turning about their pivots (J: 1/3 each; K: their centres at 1/2), the N
    couplers translating with the rockers' tips (1 each)."""
    rockers, couplers = mpmath.mpf(n + 1), mpmath.mpf(n)
    return rockers / 3 + couplers, rockers / 2 + couplers


def omega2(n: int = N) -> Any:
    """w^2 = K g / J, theta'' = w^2 sin(theta)."""
    j, k = pendulum(n)
    return k * mpmath.mpf(GRAVITY) / j


def theta(t: Any, n: int = N) -> Any:
    """theta(t) (mpmath, at the working precision): the pendulum turning over, theta' = 1 at the
    top. The energy theta'^2 / 2 + w^2 cos(theta) = 1/2 + w^2 gives, for psi = (theta + pi) / 2,
    psi'^2 = (s / 2)^2 (1 - m sin^2 psi): psi = am(s t / 2 + K(m) | m), psi(0) = pi / 2; am(u)
    = j pi + atan2(sn, cn) on the j-th half period, u - 2 j K(m) in (-K(m), K(m)]."""
    w2 = omega2(n)
    s = mpmath.sqrt(1 + 4 * w2)
    m = 4 * w2 / (1 + 4 * w2)
    quarter = mpmath.ellipk(m)
    u = s * t / 2 + quarter
    turns = mpmath.floor((u + quarter) / (2 * quarter))  # am(u) = turns pi + atan2(sn, cn)
    v = u - 2 * quarter * turns
    sn, cn = mpmath.ellipfun("sn", v, m=m), mpmath.ellipfun("cn", v, m=m)
    return 2 * (turns * mpmath.pi + mpmath.atan2(sn, cn)) - mpmath.pi


def output_count(tf: float) -> int:
    """The outputs t = 0.05 k, k = 1..count, up to tf; ValueError unless tf is one of them."""
    count = round(tf * OUTPUTS_PER_SECOND)
    if count < 1 or abs(count - tf * OUTPUTS_PER_SECOND) > 1e-9 * max(1.0, tf):
        raise ValueError(f"{tf:g} is not a positive multiple of {1 / OUTPUTS_PER_SECOND:g}")
    return count


def reference(count: int, n: int = N) -> list[tuple[float, float]]:
    """B_0 at t = 0.05 k, k = 1..count, to about 1e-28 (rounded to doubles)."""
    with mpmath.workdps(DPS):
        out = []
        for k in range(1, count + 1):
            th = theta(mpmath.mpf(k) / OUTPUTS_PER_SECOND, n)
            out.append((float(mpmath.sin(th)), float(mpmath.cos(th))))
    return out


def error(b0: Sequence[tuple[float, float]], ref: Sequence[tuple[float, float]]) -> float:
    """The benchmark's measure: the largest distance of B_0 from the reference (inf if a
    position is not finite)."""
    if len(b0) != len(ref):
        raise ValueError(f"{len(b0)} positions against {len(ref)} outputs")
    worst = 0.0
    for (x, y), (rx, ry) in zip(b0, ref):
        d = math.hypot(x - rx, y - ry)
        worst = max(worst, d) if math.isfinite(d) else math.inf
    return worst


def every(t_step: float) -> int:
    """Steps between two outputs; ValueError unless T divides 0.05."""
    span = 1.0 / OUTPUTS_PER_SECOND
    k = round(span / t_step) if t_step > 0.0 else 0
    if k < 1 or abs(k * t_step - span) > 1e-12 * span:
        raise ValueError(f"T = {t_step:g} does not divide {span:g}")
    return k


# --- the results and the table ---------------------------------------------------------------


@dataclass
class Result:
    """One (solver, setting, T): its steps, the benchmark's error, the median CPU seconds; a
    failed run has failure set, one not run (MuJoCo missing) ran False."""

    solver: str
    method: str
    setting: str
    t_step: float
    steps: int
    error: float = math.inf
    cpu: float = math.inf
    failure: str | None = None
    ran: bool = True

    @property
    def within(self) -> bool:
        return self.ran and self.failure is None and self.error <= CRITERION


def cell(text: str) -> str:
    """A Markdown cell's text: its pipes escaped, its line breaks spaces."""
    return " ".join(text.replace("|", "\\|").split())


def row(r: Result) -> list[str]:
    return [cell(c) for c in raw_row(r)]


def raw_row(r: Result) -> list[str]:
    if r.failure is not None or not r.ran:
        verdict = "failed" if r.failure is not None else "-"
        return [r.solver, r.method, r.setting, f"{r.t_step:g}", str(r.steps), "-", verdict, "-"]
    return [
        r.solver,
        r.method,
        r.setting,
        f"{r.t_step:g}",
        str(r.steps),
        f"{r.error:.2e}",
        "yes" if r.within else "no",
        f"{r.cpu:.3f}",
    ]


def fastest(results: Sequence[Result], solver: str) -> Result | None:
    """The least CPU time of solver's runs within the criterion, None if there is none."""
    ok = [r for r in results if r.solver == solver and r.within]
    return min(ok, key=lambda r: r.cpu) if ok else None


def describe(r: Result) -> str:
    return f"{r.cpu:.3f} s ({r.method}, {r.setting}, T = {r.t_step:g}, error {r.error:.1e})"


def summary(results: Sequence[Result]) -> str:
    """The CPU ratio stabdae / MuJoCo of the fastest runs of each within the criterion."""
    s, m = fastest(results, "stabdae"), fastest(results, "MuJoCo")
    head = "stabdae CPU / MuJoCo CPU, the fastest of each within 1e-3:"
    if s is None or m is None:
        missing = " and ".join(name for name, r in (("stabdae", s), ("MuJoCo", m)) if r is None)
        return f"{head} none ({missing}: no run within the criterion)"
    return f"{head} {describe(s)} / {describe(m)} = {s.cpu / m.cpu:.2f}"


def render(results: Sequence[Result]) -> str:
    lines = [HEADER, ALIGN, *(row(r) for r in results)]
    table = "".join("| " + " | ".join(cells) + " |\n" for cells in lines)
    return f"{table}\n{summary(results)}\n"


def median(xs: Sequence[float]) -> float:
    s = sorted(xs)
    return s[len(s) // 2] if len(s) % 2 else 0.5 * (s[len(s) // 2 - 1] + s[len(s) // 2])


# --- stabdae ---------------------------------------------------------------------------------


def read_b0(text: str, count: int) -> list[tuple[float, float]]:
    """B_0 = (q1, q2) at t = 0.05 k, k = 1..count, from nfourbar's CSV (a row every 0.05 s from
    t = 0); ValueError when a column is missing or the rows are not at those times."""
    lines = text.splitlines()
    if not lines:
        raise ValueError("no CSV header")
    names = lines[0].strip().split(",")
    try:
        it, ix, iy = names.index("t"), names.index("q1"), names.index("q2")
    except ValueError:
        raise ValueError("the CSV has no column t, q1 or q2") from None
    rows = [ln.split(",") for ln in lines[1:] if ln.strip()]
    if len(rows) != count + 1:
        raise ValueError(f"{len(rows)} rows, not {count + 1} (t = 0, 0.05, ...)")
    out = []
    for k, cells in enumerate(rows):
        if len(cells) != len(names):
            raise ValueError(f"row {k + 1}: {len(cells)} fields under {len(names)} columns")
        t = float(cells[it])
        if abs(t - k / OUTPUTS_PER_SECOND) > 1e-9 * max(1.0, t):
            raise ValueError(f"row {k + 1} at t = {t!r}, not {k / OUTPUTS_PER_SECOND:g}")
        if k > 0:
            out.append((float(cells[ix]), float(cells[iy])))
    return out


def stabdae_command(
    path: str, method: str, t_step: float, tf: float, sparse: bool = False
) -> list[str]:
    return [
        path,
        *(["--sparse"] if sparse else []),
        "--map",
        method,
        "--T",
        repr(t_step),
        "--tf",
        repr(tf),
        "--every",
        str(every(t_step)),
    ]


def run_stabdae(
    path: str, method: str, t_step: float, tf: float, sparse: bool = False
) -> tuple[float, str]:
    """One run of nfourbar: (the child's user + system CPU seconds, its CSV); RuntimeError
    naming its status and first line on stderr when it fails."""
    # OpenBLAS's idle threads would spin in the process's CPU time (DESIGN.md)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(
        stabdae_command(path, method, t_step, tf, sparse),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        check=False,
    )
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if out.returncode != 0:
        first = (out.stderr.strip().splitlines() or [""])[0]
        raise RuntimeError(f"nfourbar exited with status {out.returncode}: {first}".rstrip(": "))
    return cpu, out.stdout


def time_stabdae(
    path: str,
    method: str,
    t_step: float,
    tf: float,
    reps: int,
    ref: Sequence[tuple[float, float]],
    sparse: bool = False,
) -> Result:
    """nfourbar with method at t_step to tf (on the sparse back-end with sparse), reps times:
    the median CPU time, the largest error of the runs (the same run each time)."""
    steps = round(tf / t_step)
    setting = STABDAE_SETTING + (", sparse" if sparse else "")
    times, worst = [], 0.0
    try:
        for _ in range(reps):
            cpu, text = run_stabdae(path, method, t_step, tf, sparse)
            times.append(cpu)
            worst = max(worst, error(read_b0(text, len(ref)), ref))
    except (RuntimeError, ValueError) as e:
        return Result("stabdae", method, setting, t_step, steps, failure=str(e))
    return Result("stabdae", method, setting, t_step, steps, worst, median(times))


# --- MuJoCo ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Solref:
    """The connect constraints' solref: the time constant c T and the damping ratio."""

    steps: float
    dampratio: float

    @property
    def refsafe(self) -> bool:
        """refsafe on when it would not change the time constant (c >= 2)."""
        return self.steps >= 2.0

    def solref(self, t_step: float) -> tuple[float, float]:
        return (self.steps * t_step, self.dampratio)

    def modes(self) -> tuple[complex, complex]:
        """T l for the two modes of a violation, l^2 + b l + k = 0 with d = 1: b T = 2 / c,
        k T^2 = 1 / (c dampratio)^2."""
        b, k = 2.0 / self.steps, 1.0 / (self.steps * self.dampratio) ** 2
        root = complex(b * b / 4.0 - k) ** 0.5
        return (-b / 2.0 + root, -b / 2.0 - root)

    def amplification(self) -> float:
        """RK4's amplification of a violation per step, max |R(T l)| over the two modes, R(z)
        = 1 + z + z^2/2 + z^3/6 + z^4/24: the constraints stable under RK4 while it is < 1."""
        return max(abs(1 + z + z * z / 2 + z**3 / 6 + z**4 / 24) for z in self.modes())

    def label(self) -> str:
        safe = "" if self.refsafe else ", refsafe off"
        gain = f"amplification {self.amplification():.2f}"
        return f"solref ({self.steps:g}T, {self.dampratio:g}){safe}, {gain}"


# the documented minimum time constant critically damped, then underdamped to the stiffest
# stable one and one notch softer, then refsafe off (MuJoCo's settings, above)
MUJOCO_SOLREF = (Solref(2.0, 1.0), Solref(2.0, 0.2), Solref(2.0, 0.25), Solref(0.5, 0.9))


def parse_solref(s: str) -> Solref:
    """ "c:dampratio", c > 1/4 (the time constant in steps), 0 < dampratio <= 10."""
    parts = s.split(":")
    try:
        if len(parts) != 2:
            raise ValueError
        c, dr = float(parts[0]), float(parts[1])
    except ValueError:
        raise ValueError(f"not c:dampratio: {s!r}") from None
    if not (0.25 < c <= 1000.0 and 0.0 < dr <= 10.0):
        raise ValueError(f"{s}: c not in (0.25, 1000] or dampratio not in (0, 10]")
    return Solref(c, dr)


def model(mj: ModuleType, t_step: float, solref: Solref, n: int = N) -> Any:
    """MuJoCo's N-four-bar: rocker i (body "rocker{i}", hinge "rocker{i}") at (i, 0, 0), upright
    along its y; coupler i (body and hinge "coupler{i}") a child of rocker i - 1 at its tip,
    along its x; the equality connect of coupler i's free end (1, 0, 0) to rocker i; the site
    "B{i}" at rocker i's tip."""
    spec = mj.MjSpec.from_string(
        MJCF.format(
            t=t_step,
            g=GRAVITY,
            tol=SOLVER_TOLERANCE,
            it=SOLVER_ITERATIONS,
            refsafe="enable" if solref.refsafe else "disable",
        )
    )
    hinge, z = mj.mjtJoint.mjJNT_HINGE, [0.0, 0.0, 1.0]
    rockers = []
    for i in range(n + 1):
        r = spec.worldbody.add_body(
            name=f"rocker{i}",
            pos=[float(i), 0.0, 0.0],
            mass=1.0,
            ipos=[0.0, 0.5, 0.0],
            inertia=[ROD_INERTIA, AXIAL_INERTIA, ROD_INERTIA],
            explicitinertial=1,
        )
        r.add_joint(name=f"rocker{i}", type=hinge, axis=z)
        r.add_site(name=f"B{i}", pos=[0.0, 1.0, 0.0])
        rockers.append(r)
    for i in range(1, n + 1):
        c = rockers[i - 1].add_body(
            name=f"coupler{i}",
            pos=[0.0, 1.0, 0.0],
            mass=1.0,
            ipos=[0.5, 0.0, 0.0],
            inertia=[AXIAL_INERTIA, ROD_INERTIA, ROD_INERTIA],
            explicitinertial=1,
        )
        c.add_joint(name=f"coupler{i}", type=hinge, axis=z)
        eq = spec.add_equality(
            name=f"loop{i}",
            type=mj.mjtEq.mjEQ_CONNECT,
            objtype=mj.mjtObj.mjOBJ_BODY,
            name1=f"coupler{i}",
            name2=f"rocker{i}",
        )
        eq.data[0:3] = [1.0, 0.0, 0.0]  # in the coupler's frame; rocker i's tip at qpos0
        eq.solref = list(solref.solref(t_step))
        eq.solimp = list(SOLIMP)
    return spec.compile()


def start(mj: ModuleType, m: Any, d: Any) -> None:
    """The benchmark's start: every hinge at 0 (the squares upright), every tip at (1, 0) m/s:
    the rockers at -1 rad/s about z (theta is clockwise), the couplers at +1 relative to their
    rockers (translating)."""
    mj.mj_resetData(m, d)
    for j in range(m.njnt):
        name = mj.mj_id2name(m, mj.mjtObj.mjOBJ_JOINT, j)
        d.qvel[m.jnt_dofadr[j]] = -1.0 if name.startswith("rocker") else 1.0
    mj.mj_forward(m, d)


def b0(m: Any, d: Any) -> tuple[float, float]:
    """Rocker 0's tip from its angle q0 (about z, from the upright): (-sin q0, cos q0)."""
    q = float(d.qpos[m.jnt_qposadr[m.joint("rocker0").id]])
    return -math.sin(q), math.cos(q)


def run_mujoco(
    mj: ModuleType, m: Any, d: Any, count: int
) -> tuple[float, list[tuple[float, float]]]:
    """From the start, count outputs 0.05 s apart: (the thread's CPU seconds in mj_step, B_0 at
    each output). RuntimeError when the state is not finite."""
    k = every(float(m.opt.timestep))
    start(mj, m, d)
    cpu, out = 0.0, []
    for j in range(count):
        t0 = time.thread_time()
        mj.mj_step(m, d, nstep=k)
        cpu += time.thread_time() - t0
        p = b0(m, d)
        if not (math.isfinite(p[0]) and math.isfinite(p[1])):
            raise RuntimeError(f"MuJoCo's state is not finite at t = {(j + 1) * 0.05:g}")
        out.append(p)
    return cpu, out


def time_mujoco(
    mj: ModuleType,
    t_step: float,
    solref: Solref,
    tf: float,
    reps: int,
    ref: Sequence[tuple[float, float]],
) -> Result:
    """MuJoCo with solref at t_step to tf, reps times: the median CPU time, the largest error
    of the runs; a failure when the state is not finite or MuJoCo warns (its warnings caught,
    not written to MUJOCO_LOG.TXT in the working directory)."""
    m = model(mj, t_step, solref)
    d = mj.MjData(m)
    steps = round(tf / t_step)
    times: list[float] = []
    warnings: list[str] = []
    worst = 0.0
    previous = mj.get_mju_user_warning()
    mj.set_mju_user_warning(warnings.append)
    try:
        for _ in range(reps):
            cpu, pts = run_mujoco(mj, m, d, len(ref))
            if warnings:
                raise RuntimeError("MuJoCo warned")
            times.append(cpu)
            worst = max(worst, error(pts, ref))
    except RuntimeError as e:
        why = f"{e}: {warnings[0]}" if warnings else str(e)
        return Result("MuJoCo", "RK4", solref.label(), t_step, steps, failure=why)
    finally:
        mj.set_mju_user_warning(previous)
    return Result("MuJoCo", "RK4", solref.label(), t_step, steps, worst, median(times))


# --- the command -----------------------------------------------------------------------------


def step_list(s: str) -> list[float]:
    """A comma-separated list of steps, each dividing 0.05; "none" for none."""
    if s.strip() == "none":
        return []
    out = []
    for item in s.split(","):
        try:
            v = float(item)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not a number: {item!r}") from None
        try:
            every(v)
        except ValueError as e:
            raise argparse.ArgumentTypeError(str(e)) from None
        out.append(v)
    return out


def map_list(s: str) -> list[str]:
    out = [x.strip() for x in s.split(",")]
    for x in out:
        if x not in MAPS:
            raise argparse.ArgumentTypeError(f"{x!r} is not one of {', '.join(MAPS)}")
    return out


def solref_list(s: str) -> list[Solref]:
    try:
        return [parse_solref(x.strip()) for x in s.split(",")]
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def end_time(s: str) -> float:
    try:
        v = float(s)
        output_count(v)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a multiple of 0.05 in (0, 20]: {s!r}") from None
    if v > TF:
        raise argparse.ArgumentTypeError(f"{s} is past the benchmark's {TF:g} s")
    return v


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    p = Parser(prog=PROG, description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument(
        "--nfourbar",
        required=True,
        metavar="PATH",
        help="the example program (build/examples/nfourbar)",
    )
    p.add_argument(
        "--maps",
        type=map_list,
        default=["rk8"],
        metavar="LIST",
        help="stabdae's maps, each at every --stabdae-T (default rk8)",
    )
    p.add_argument(
        "--sparse",
        action="store_true",
        help="stabdae's mechanism by the patterns of M and G: its sparse back-end",
    )
    p.add_argument(
        "--stabdae-T",
        dest="stabdae_t",
        type=step_list,
        default=list(STABDAE_T),
        metavar="LIST",
        help="stabdae's steps, each dividing 0.05, or none (default 5e-2,2.5e-2,1.25e-2,1e-2)",
    )
    p.add_argument(
        "--mujoco-T",
        dest="mujoco_t",
        type=step_list,
        default=list(MUJOCO_T),
        metavar="LIST",
        help="MuJoCo's steps, each dividing 0.05, or none (default 1e-2,6.25e-3,5e-3,2.5e-3,1e-3)",
    )
    p.add_argument(
        "--mujoco-solref",
        type=solref_list,
        default=list(MUJOCO_SOLREF),
        metavar="LIST",
        help="MuJoCo's solref, c:dampratio with the time constant c T, each at every "
        "--mujoco-T; refsafe off when c < 2 (default 2:1,2:0.2,2:0.25,0.5:0.9)",
    )
    p.add_argument(
        "--reps",
        type=positive_int(1, MAX_REPS),
        default=3,
        help=f"repetitions, their median (1..{MAX_REPS}, default 3)",
    )
    p.add_argument(
        "--tf",
        type=end_time,
        default=TF,
        help=f"the end time, a multiple of 0.05 (default the benchmark's {TF:g})",
    )
    p.add_argument("--table", metavar="FILE", help="the table (default: stdout)")
    a = p.parse_args(argv)
    if not (os.path.isfile(a.nfourbar) and os.access(a.nfourbar, os.X_OK)):
        raise UsageError(f"--nfourbar: not an executable file: {a.nfourbar}")
    return a


def main(argv: Sequence[str] | None = None) -> int:
    try:
        a = parse_args(sys.argv[1:] if argv is None else argv)
    except UsageError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 2
    ref = reference(output_count(a.tf))
    results: list[Result] = []

    def done(r: Result) -> None:
        results.append(r)
        what = f"{r.solver} {r.method}, {r.setting}, T = {r.t_step:g}"
        got = r.failure or f"error {r.error:.2e}, {r.cpu:.3f} s"
        print(f"{PROG}: {what}: {got}", file=sys.stderr, flush=True)

    for method in a.maps:
        for t_step in a.stabdae_t:
            done(time_stabdae(a.nfourbar, method, t_step, a.tf, a.reps, ref, a.sparse))
    mj = load_mujoco() if a.mujoco_t else None
    if a.mujoco_t and mj is None:
        print(
            f"{PROG}: MuJoCo is not installed: its cells are \"-\"; "
            f"`pip install {MUJOCO_PIN}` enables it",
            file=sys.stderr,
        )
        for solref in a.mujoco_solref:
            for t_step in a.mujoco_t:
                steps = round(a.tf / t_step)
                results.append(Result("MuJoCo", "RK4", solref.label(), t_step, steps, ran=False))
    elif mj is not None:
        print(f"{PROG}: MuJoCo {getattr(mj, '__version__', '?')}, RK4", file=sys.stderr)
        for solref in a.mujoco_solref:
            for t_step in a.mujoco_t:
                done(time_mujoco(mj, t_step, solref, a.tf, a.reps, ref))
    text = render(results)
    try:
        if a.table:
            with open(a.table, "w", encoding="utf-8") as f:
                f.write(text)
        else:
            sys.stdout.write(text)
    except OSError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    failed = [r for r in results if r.failure is not None]
    for r in failed:
        print(
            f"{PROG}: failed: {r.solver} {r.method} T = {r.t_step:g}: {r.failure}", file=sys.stderr
        )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
