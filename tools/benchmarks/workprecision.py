# SPDX-License-Identifier: GPL-3.0-or-later
"""Work-precision report: runs build/tools/workprecision and draws build/report/workprecision.png
and build/report/workprecision.md.

  python -m benchmarks.workprecision [--build DIR] [--points CSV] [--reps N]

The exact final states come from reference.py, computed once and cached in
DIR/workprecision/reference.csv. --points re-draws from an existing CSV without running the
measurements. For d = 0, t = 1000 the report gives, per solver setting, the CPU time needed for a
final error of 1e-6 (log-log interpolation between the two sweep points around it) and compares
the best stabdae map with the best IDA form (target: at least 5 times less CPU).
"""

import argparse
import csv
import datetime
import math
import os
import platform
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
TOOLS = os.path.dirname(HERE)
TARGET_ERROR = 1e-6
TARGET_RATIO = 5.0


def tools_env():
    """The environment of a child `python -m` of a package of tools/: tools/ on PYTHONPATH."""
    path = os.environ.get("PYTHONPATH")
    return dict(os.environ, PYTHONPATH=TOOLS + (os.pathsep + path if path else ""))


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def provenance(command, points):
    """The report's first lines: machine, date, this command, and the measurements' command
    (or the CSV they were drawn from)."""
    return [
        "- machine: %s, %d cores" % (cpu_model(), os.cpu_count() or 0),
        "- date: %s"
        % datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC"),
        "- command: %s" % " ".join([os.path.basename(sys.executable)] + sys.argv),
        "- measurements: %s" % (" ".join(command) if command else "from " + points),
    ]


def read_rows(path, floats, ints):
    """The CSV's rows as dicts, the named columns converted."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for key in floats:
            r[key] = float(r[key])
        for key in ints:
            r[key] = int(r[key])
    return rows


def read_points(path):
    return read_rows(path, ("d", "tf", "param", "cpu_s", "error"), ("steps", "reps"))


def series_where(rows, field, value):
    """(solver, setting) -> the rows with row[field] == value, in sweep order."""
    out = {}
    for r in rows:
        if r[field] == value:
            out.setdefault((r["solver"], r["setting"]), []).append(r)
    return out


def series(rows, d):
    return series_where(rows, "d", d)


def cpu_at(points, error):
    """CPU time for the given error: log-log interpolation between the first sweep point at or
    below it and the point before; None when the sweep never gets there."""
    ok = [p for p in points if p["status"] == "ok" and math.isfinite(p["error"])]
    for i, p in enumerate(ok):
        if p["error"] <= error:
            if i == 0 or ok[i - 1]["error"] <= p["error"]:
                return p["cpu_s"]
            q = ok[i - 1]
            w = math.log(q["error"] / error) / math.log(q["error"] / p["error"])
            return math.exp((1 - w) * math.log(q["cpu_s"]) + w * math.log(p["cpu_s"]))
    return None


def cheapest_below(points, error):
    ok = [p for p in points if p["status"] == "ok" and p["error"] <= error]
    return min(ok, key=lambda p: p["cpu_s"]) if ok else None


def plot(rows, cases, path):
    fig, axes = plt.subplots(1, len(cases), figsize=(6.5 * len(cases), 5.2))
    for ax, (d, tf) in zip(axes, cases):
        for (solver, setting), pts in sorted(series(rows, d).items()):
            ok = [p for p in pts if p["status"] == "ok" and p["error"] > 0]
            if not ok:
                continue
            style = "-o" if solver == "stabdae" else "--s"
            ax.loglog(
                [p["cpu_s"] for p in ok],
                [p["error"] for p in ok],
                style,
                ms=4,
                label="%s %s" % ("IDA" if solver == "ida" else "stabdae", setting),
            )
        if d == 0.0:
            ax.axhline(TARGET_ERROR, color="grey", lw=0.8, ls=":")
        ax.set_xlabel("CPU time [s] (median of repetitions)")
        ax.set_ylabel("final error max(|X - X_ref|, |Xdot - Xdot_ref|)")
        ax.set_title("oscillator on the manifold, d = %g, t = %g" % (d, tf))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def fmt(v, spec="%.3g"):
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else spec % v


def table(rows, d):
    lines = [
        "| solver | setting | T or rtol | steps | reps | CPU s | final error | status |",
        "|---|---|---:|---:|---:|---:|---:|---|",
    ]
    for (solver, setting), pts in sorted(series(rows, d).items()):
        for p in pts:
            lines.append(
                "| %s | %s | %.3g | %d | %d | %.4g | %s | %s |"
                % (
                    solver,
                    setting,
                    p["param"],
                    p["steps"],
                    p["reps"],
                    p["cpu_s"],
                    fmt(p["error"]),
                    p["status"],
                )
            )
    return lines


def target_section(rows):
    lines = [
        "| solver | setting | CPU s for error 1e-6 (interpolated) | cheapest measured "
        "point with error <= 1e-6 |",
        "|---|---|---:|---|",
    ]
    best = {}
    for (solver, setting), pts in sorted(series(rows, 0.0).items()):
        c = cpu_at(pts, TARGET_ERROR)
        p = cheapest_below(pts, TARGET_ERROR)
        lines.append(
            "| %s | %s | %s | %s |"
            % (
                solver,
                setting,
                fmt(c, "%.4g"),
                "-"
                if p is None
                else "%.4g s (param %.3g, error %.2g)" % (p["cpu_s"], p["param"], p["error"]),
            )
        )
        if c is not None and (solver not in best or c < best[solver][1]):
            best[solver] = (setting, c)
    lines.append("")
    if "stabdae" in best and "ida" in best:
        ratio = best["ida"][1] / best["stabdae"][1]
        lines.append(
            "Best stabdae map: %s, %.4g s; best IDA form: %s, %.4g s; IDA / stabdae = "
            "%.2f (target >= %g: %s)."
            % (
                best["stabdae"][0],
                best["stabdae"][1],
                best["ida"][0],
                best["ida"][1],
                ratio,
                TARGET_RATIO,
                "met" if ratio >= TARGET_RATIO else "missed",
            )
        )
    else:
        lines.append("A solver never reached 1e-6: no ratio.")
    return lines


def arguments(description, argv, extra=()):
    """The options every report of this folder takes (--build, --points, --reps) and its own
    (extra: (flag, keyword arguments) pairs): the options, the build and its report folder,
    made."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--build", default=os.path.join(HERE, "..", "..", "build"))
    ap.add_argument("--points", help="draw from this CSV instead of running the measurements")
    ap.add_argument("--reps", type=int, default=3)
    for flag, kwargs in extra:
        ap.add_argument(flag, **kwargs)
    args = ap.parse_args(argv)
    build = os.path.abspath(args.build)
    report = os.path.join(build, "report")
    os.makedirs(report, exist_ok=True)
    return args, build, report


def main(argv=None):
    args, build, report = arguments(__doc__.split("\n")[0], argv)
    work = os.path.join(build, "workprecision")
    os.makedirs(work, exist_ok=True)
    ref = os.path.join(work, "reference.csv")
    if not os.path.exists(ref):
        subprocess.run(
            [sys.executable, "-m", "benchmarks.reference", ref], check=True, env=tools_env()
        )
    command = None
    points = args.points
    if not points:
        points = os.path.join(work, "points.csv")
        command = [
            os.path.join(build, "tools", "workprecision"),
            "--reference",
            ref,
            "--out",
            points,
            "--reps",
            str(args.reps),
        ]
        subprocess.run(command, check=True)
    rows = read_points(points)
    cases = sorted({(r["d"], r["tf"]) for r in rows}, reverse=True)
    png = os.path.join(report, "workprecision.png")
    plot(rows, cases, png)

    md = [
        "# Work-precision: stabdae against SUNDIALS IDA",
        "",
        *provenance(command, points),
        "- problem: oscillator (k = 2, m = 1) on the manifold from x0 = (X, Y, Xdot, Ydot) = "
        "(0.7, 0, 0.6, 0); error = max(|X - X_ref|, |Xdot - Xdot_ref|) at the final time "
        "against reference.py (d = 0: A cn(w (t - t0) | 1/2) with amplitude and phase from "
        "x0; d = 0.03: mpmath Taylor series, 30 digits)",
        "- stabdae: scheme 15, delta 2, epsilon 1, fixed T; IDA: dense direct solver with the "
        "analytic iteration matrix, atol = rtol, index1 (acceleration-level constraint) and "
        "ggl (Gear-Gupta-Leimkuhler) forms",
        "- CPU: CLOCK_PROCESS_CPUTIME_ID for the whole run (set-up included), median of the "
        "repetitions",
        "",
        "![work-precision](workprecision.png)",
        "",
        "## d = 0, t = 1000: CPU for a final error of 1e-6",
        "",
    ]
    md += target_section(rows)
    for d, tf in cases:
        md += ["", "## d = %g, t = %g" % (d, tf), ""] + table(rows, d)
    with open(os.path.join(report, "workprecision.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(target_section(rows)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
