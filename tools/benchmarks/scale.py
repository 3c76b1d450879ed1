# SPDX-License-Identifier: GPL-3.0-or-later
"""The rope's scaling: rope_scale's table with MuJoCo's RK4 on the same chain beside it, and the
log-log plot of a step's cost against N.

  python -m benchmarks.scale --rope-scale build/tools/rope_scale [--max-n N]
      [--dense-max N] [--reps R] [--budget S] [--mujoco-max N] [--table FILE] [--plot FILE]

Runs rope_scale (its flags --max-n, --dense-max, --reps and --budget passed through; its
Markdown table read by the columns' names), then, in the same run, times MuJoCo's RK4 on the
rope for every N of rope_scale's rows up to --mujoco-max: N bodies in a planar chain of hinges
about z, each a point mass 1 at the end of a massless unit link, the first hinge at the origin,
gravity 9.81 along -y, T = 1e-3, no contacts, from the start of examples/models/rope.c's
mech_rope_start(0.3) at rest (the rope straight at 0.3 rad below the horizontal). MuJoCo
integrates the N hinge angles (minimal coordinates; a serial chain's mass matrix is dense),
rope_scale the 2N Cartesian coordinates under N constraints: the same mechanism. MuJoCo 4.0.0
builds no chain deeper than 1023 bodies ("depth limit exceeded"): from there on its cells are
"-", said on stderr.

MuJoCo is timed as rope_scale times its steppers: CPU time of the thread, a probe step, as many
steps a run as fit the budget (at most 2000), an untimed warm-up run, then the median over the
repetitions of runs from the start (mj_step with nstep, the loop in C). Without MuJoCo (an
optional peer: `pip install mujoco==4.0.0`) its column is "-".

Writes the merged table (rope_scale's columns and "MuJoCo RK4, us/step" after its last timing
column) to stdout or --table, and with --plot a PNG of every timing column (headers with
"us/step", or "IDA") against N, log-log, with the slopes N^1 and N^3 drawn faintly. Exit status
0, 1 when rope_scale or a MuJoCo run fails, 2 for bad usage.
"""

from __future__ import annotations

import argparse
import importlib
import math
import os
import subprocess
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from types import ModuleType
from typing import Any, NoReturn

PROG = "benchmarks.scale"
MUJOCO_HEADER = "MuJoCo RK4, us/step"
MUJOCO_PIN = "mujoco==4.0.0"
T = 1e-3
GRAVITY = 9.81
START_ANGLE = 0.3  # mech_rope_start's a: the rope straight, a radians below the horizontal
POINT_INERTIA = 1e-9  # a point mass's inertia about its centre (MuJoCo needs it positive)
MAX_STEPS = 2000  # steps a run at most, as rope_scale
MAX_REPS = 15  # rope_scale's limit

# The options of the chain in MJCF; its bodies are added by MjSpec, since MuJoCo's XML parser
# (tinyxml2) refuses elements nested deeper than 500 and a chain of N links nests N bodies.
CHAIN_MJCF = f"""<mujoco model="rope">
  <option timestep="{T:g}" integrator="RK4" gravity="0 {-GRAVITY:g} 0">
    <flag contact="disable"/>
  </option>
  <worldbody/>
</mujoco>"""


class UsageError(Exception):
    """A command-line error: one line on stderr, exit status 2."""


class ModelError(Exception):
    """MuJoCo cannot build the chain."""


class Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        raise UsageError(message)


@dataclass
class Table:
    """A Markdown table: the header's names, the separator's cells, the rows' cells."""

    header: list[str]
    align: list[str]
    rows: list[list[str]]

    def column(self, name: str) -> int:
        if name not in self.header:
            raise ValueError(f"no column {name!r} in rope_scale's table")
        return self.header.index(name)


def split_row(line: str) -> list[str]:
    """The cells of a Markdown table's line `| a | b |`."""
    s = line.strip()
    if not (s.startswith("|") and s.endswith("|") and len(s) > 1):
        raise ValueError(f"not a table row: {line!r}")
    return [c.strip() for c in s[1:-1].split("|")]


def parse_table(text: str) -> Table:
    """The first Markdown table of text (header, separator, rows); ValueError when malformed."""
    lines = [ln for ln in text.splitlines() if ln.strip().startswith("|")]
    if len(lines) < 2:
        raise ValueError("no Markdown table in rope_scale's output")
    header, align = split_row(lines[0]), split_row(lines[1])
    if len(align) != len(header) or not all(
        a.strip(":") and set(a.strip(":")) == {"-"} for a in align
    ):
        raise ValueError(f"not a table's separator: {lines[1]!r}")
    rows = [split_row(ln) for ln in lines[2:]]
    for r in rows:
        if len(r) != len(header):
            raise ValueError(f"a row of {len(r)} cells under {len(header)} columns: {r}")
    return Table(header, align, rows)


def number(cell: str) -> float | None:
    """A cell's value, None for "-" or an empty cell."""
    if cell in ("", "-"):
        return None
    return float(cell)


def is_timing(name: str) -> bool:
    """A column of times per step: its unit us/step, or IDA's (but not an accuracy column)."""
    return "us/step" in name or ("IDA" in name and "abs(c)" not in name and "error" not in name)


def merge(table: Table, name: str, cells: Sequence[str]) -> Table:
    """table with the column name (one cell a row) after its last timing column, or last."""
    timing = [i for i, h in enumerate(table.header) if is_timing(h)]
    at = timing[-1] + 1 if timing else len(table.header)
    return Table(
        [*table.header[:at], name, *table.header[at:]],
        [*table.align[:at], "---:", *table.align[at:]],
        [[*r[:at], c, *r[at:]] for r, c in zip(table.rows, cells, strict=True)],
    )


def render(table: Table) -> str:
    lines = [table.header, table.align, *table.rows]
    return "".join("| " + " | ".join(cells) + " |\n" for cells in lines)


# --- MuJoCo --------------------------------------------------------------------------------


def load_mujoco() -> ModuleType | None:
    """MuJoCo's module, or None when it is not installed."""
    try:
        return importlib.import_module("mujoco")
    except ImportError:
        return None


def chain_model(mj: ModuleType, n: int) -> Any:
    """MuJoCo's model of the rope: n bodies in a chain, body k's frame at the end of link k - 1
    (the origin for the first), a hinge about z at it, its point mass 1 at (1, 0, 0) in it."""
    spec = mj.MjSpec.from_string(CHAIN_MJCF)
    parent = spec.worldbody
    for k in range(1, n + 1):
        body = parent.add_body(
            name=f"mass{k}",
            pos=[0.0, 0.0, 0.0] if k == 1 else [1.0, 0.0, 0.0],
            mass=1.0,
            ipos=[1.0, 0.0, 0.0],
            inertia=[POINT_INERTIA] * 3,
            explicitinertial=1,
        )
        body.add_joint(name=f"hinge{k}", type=mj.mjtJoint.mjJNT_HINGE, axis=[0.0, 0.0, 1.0])
        parent = body
    try:
        return spec.compile()
    except ValueError as e:  # MuJoCo 4.0.0 refuses bodies nested 1024 deep
        raise ModelError(str(e).strip().splitlines()[0].removeprefix("Error: ")) from None


def chain_start(mj: ModuleType, m: Any, d: Any, a: float = START_ANGLE) -> None:
    """d at mech_rope_start(a): the chain straight at a below the horizontal, at rest (mass j
    at (j cos a, -j sin a)); the first hinge's angle -a, the others' 0."""
    mj.mj_resetData(m, d)
    d.qpos[0] = -a
    mj.mj_forward(m, d)


def mujoco_run(mj: ModuleType, m: Any, d: Any, steps: int) -> float:
    """steps of mj_step from the start; CPU seconds of the thread per step."""
    chain_start(mj, m, d)
    t0 = time.thread_time()
    mj.mj_step(m, d, nstep=steps)
    per_step = (time.thread_time() - t0) / steps
    if not all(math.isfinite(x) for x in d.qpos):
        raise RuntimeError("MuJoCo's state is not finite")
    return per_step


def time_mujoco(mj: ModuleType, n: int, reps: int, budget: float) -> float:
    """Median CPU seconds per mj_step on the chain of n over reps runs, as rope_scale times."""
    m = chain_model(mj, n)
    d = mj.MjData(m)
    probe = mujoco_run(mj, m, d, 1)
    steps = max(1, min(MAX_STEPS, int(budget / (reps * probe)))) if probe > 0.0 else MAX_STEPS
    mujoco_run(mj, m, d, steps)  # warm-up
    t = sorted(mujoco_run(mj, m, d, steps) for _ in range(reps))
    return t[reps // 2]


# --- the plot ------------------------------------------------------------------------------

LABELS = {
    "rk4 sparse, us/step": "stabdae rk4, sparse (2N Cartesian)",
    "rk4 dense, us/step": "stabdae rk4, dense (2N Cartesian)",
    "midpoint sparse, us/step": "stabdae midpoint, sparse (2N Cartesian)",
    "dgrad sparse, us/step": "stabdae dgrad, sparse (2N Cartesian)",
    "index-1 RK4, us/step": "index-1 RK4, dense Cholesky (2N Cartesian)",
}


def label(name: str, mujoco_version: str | None) -> str:
    if name == MUJOCO_HEADER:
        return f"MuJoCo {mujoco_version or ''} RK4 (N hinges)".replace("  ", " ")
    return LABELS.get(name, name.replace(", us/step", ""))


def plot(table: Table, path: str, mujoco_version: str | None) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n_col = table.column("N")
    fig, ax = plt.subplots(figsize=(8.0, 5.6), layout="constrained")
    styles = ["o-", "s-", "^-", "D-", "v-", "P-", "X-"]
    ys: list[float] = []
    ns: list[float] = []
    series = 0
    for i, name in enumerate(table.header):
        if not is_timing(name):
            continue
        pts = [(float(r[n_col]), v) for r in table.rows if (v := number(r[i])) is not None]
        if not pts:
            continue
        x, y = zip(*pts, strict=True)
        ax.loglog(
            x,
            y,
            styles[series % len(styles)],
            label=label(name, mujoco_version),
            markersize=5,
            linewidth=1.6,
        )
        series += 1
        ys += y
        ns += x
    if not ys:
        raise ValueError("no timing column with a value to plot")
    n0, n1 = min(ns), max(ns)
    lo, hi = min(ys) / 3.0, max(ys) * 3.0
    ax.set_xlim(n0 / 1.25, n1 * 1.25)
    ax.set_ylim(lo, hi)
    # the reference slopes from a point below the smallest N's fastest time
    y0 = min(v for xv, v in zip(ns, ys, strict=True) if xv == n0) / 2.0
    grid = [n0 * 2.0 ** (k / 8.0) for k in range(int(8 * math.log2(n1 * 1.25 / n0)) + 1)]
    for p, text in ((1, "$\\propto N$"), (3, "$\\propto N^3$")):
        ref = [y0 * (g / n0) ** p for g in grid]
        ax.loglog(grid, ref, "--", color="0.55", linewidth=1.0, alpha=0.6, zorder=0)
        # the label where the line leaves the plot (top or right)
        end = min(n1 * 1.2, n0 * (hi / 1.6 / y0) ** (1.0 / p))
        ax.text(end, y0 * (end / n0) ** p, text, color="0.4", fontsize=10, ha="right", va="bottom")
    ax.set_xticks(sorted(set(ns)))
    ax.set_xticklabels([f"{n:g}" for n in sorted(set(ns))])
    ax.minorticks_off()
    ax.xaxis.set_tick_params(which="minor", bottom=False)
    ax.set_xlabel("N (point masses on unit rods)")
    ax.set_ylabel("CPU time per step (µs, median of thread time)")
    ax.set_title(f"The rope: a step's cost against N (RK4, T = {T:g} s)")
    ax.grid(True, which="major", color="0.9", linewidth=0.8)
    ax.legend(loc="upper left", fontsize=9, framealpha=0.9)
    fig.savefig(path, dpi=130)
    plt.close(fig)


# --- the command ---------------------------------------------------------------------------


def positive_int(lo: int, hi: int) -> Any:
    def parse(s: str) -> int:
        try:
            v = int(s)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not an integer: {s!r}") from None
        if not lo <= v <= hi:
            raise argparse.ArgumentTypeError(f"{v} is not in [{lo}, {hi}]")
        return v

    return parse


def budget_seconds(s: str) -> float:
    try:
        v = float(s)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {s!r}") from None
    if not 0.0 < v <= 600.0:
        raise argparse.ArgumentTypeError(f"{s} is not in (0, 600]")
    return v


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    p = Parser(prog=PROG, description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument(
        "--rope-scale",
        required=True,
        metavar="PATH",
        help="the rope_scale program (build/tools/rope_scale)",
    )
    p.add_argument(
        "--max-n",
        type=positive_int(8, 4096),
        default=4096,
        help="rope_scale's largest N (8..4096, default 4096)",
    )
    p.add_argument(
        "--dense-max",
        type=positive_int(1, 4096),
        default=256,
        help="rope_scale's largest N of the dense runs (default 256)",
    )
    p.add_argument(
        "--reps",
        type=positive_int(1, MAX_REPS),
        default=5,
        help=f"repetitions, their median (1..{MAX_REPS}, default 5)",
    )
    p.add_argument(
        "--budget",
        type=budget_seconds,
        default=0.5,
        help="CPU seconds per stepper and N (default 0.5)",
    )
    p.add_argument(
        "--mujoco-max",
        type=positive_int(0, 4096),
        default=1024,
        help="MuJoCo's largest N (0: none; default 1024)",
    )
    p.add_argument("--table", metavar="FILE", help="the merged table (default: stdout)")
    p.add_argument("--plot", metavar="FILE", help="the log-log plot (PNG)")
    a = p.parse_args(argv)
    if not (os.path.isfile(a.rope_scale) and os.access(a.rope_scale, os.X_OK)):
        raise UsageError(f"--rope-scale: not an executable file: {a.rope_scale}")
    return a


def run_rope_scale(a: argparse.Namespace) -> Table:
    cmd = [
        a.rope_scale,
        "--max-n",
        str(a.max_n),
        "--dense-max",
        str(a.dense_max),
        "--reps",
        str(a.reps),
        "--budget",
        f"{a.budget:g}",
    ]
    print(f"{PROG}: {' '.join(cmd)}", file=sys.stderr, flush=True)
    # OpenBLAS's idle threads would spin in the process's CPU time (DESIGN.md)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    out = subprocess.run(cmd, stdout=subprocess.PIPE, text=True, env=env, check=False)
    if out.returncode != 0:
        raise RuntimeError(f"rope_scale exited with status {out.returncode}")
    return parse_table(out.stdout)


def main(argv: Sequence[str] | None = None) -> int:
    try:
        a = parse_args(sys.argv[1:] if argv is None else argv)
    except UsageError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 2
    try:
        table = run_rope_scale(a)
        n_col = table.column("N")
        mj = load_mujoco() if a.mujoco_max > 0 else None
        version = getattr(mj, "__version__", None)
        if mj is None and a.mujoco_max > 0:
            print(
                f"{PROG}: MuJoCo is not installed: its column is \"-\"; "
                f"`pip install {MUJOCO_PIN}` enables it",
                file=sys.stderr,
            )
        elif mj is not None:
            print(
                f"{PROG}: MuJoCo {version}, RK4 on N hinges, up to N = {a.mujoco_max}",
                file=sys.stderr,
            )
        cells = []
        prev = 0.0
        for r in table.rows:
            n = int(r[n_col])
            if mj is None or n > a.mujoco_max:
                cells.append("-")
                continue
            try:
                s = time_mujoco(mj, n, a.reps, a.budget)
            except ModelError as e:
                print(
                    f"{PROG}: MuJoCo cannot build the chain of N = {n} ({e}): \"-\" from there on",
                    file=sys.stderr,
                )
                mj = None
                cells.append("-")
                continue
            growth = f", growth exponent {math.log2(s / prev):.2f}" if prev > 0.0 else ""
            print(
                f"{PROG}: MuJoCo N = {n}: {1e6 * s:.1f} us/step{growth}",
                file=sys.stderr,
                flush=True,
            )
            prev = s
            cells.append(f"{1e6 * s:.1f}")
        merged = merge(table, MUJOCO_HEADER, cells)
        text = render(merged)
        if a.table:
            with open(a.table, "w", encoding="utf-8") as f:
                f.write(text)
        else:
            sys.stdout.write(text)
        if a.plot:
            plot(merged, a.plot, version)
    except (RuntimeError, ValueError, OSError) as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
