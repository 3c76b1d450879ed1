# SPDX-License-Identifier: GPL-3.0-or-later
"""tools/crossval/crossval [--full] [--build DIR] [--out FILE] [--only a,b,...] [--workers N]

Runs the checks, writes the report (default: BUILD/report/crossval.md for --full,
BUILD/report/fast/crossval.md for the fast subset) with its PNG plots beside it, and exits 1
naming every failed check (2 for bad usage or missing programs)."""

import argparse
import collections
import os
import sys
import time

from stabdae_ref import stepper

from . import (
    check_drift,
    check_energy,
    check_mbs,
    check_offmanifold,
    check_order,
    check_scheme,
    profiles,
    report,
    runs,
)

CHECKS = collections.OrderedDict(
    [
        ("a", ("same discrete scheme: C against mpmath", check_scheme.check)),
        ("b", ("orders on the manifold; IDA against exact solutions", check_order.check)),
        ("c", ("off the manifold: decay of xi, scheme 11's step bound", check_offmanifold.check)),
        ("d", ("energy: dgrad over many steps, IDA's drift", check_energy.check)),
        ("e", ("constraint drift: index reduction, Baumgarte, the paper", check_drift.check)),
        ("f", ("mechanical front-end: orders, energy, drift against mpmath", check_mbs.check)),
    ]
)
# the programs each check runs (besides the examples every check needs)
PROGRAMS = {"f": ("examples/pendulum_mbs", "examples/double_pendulum")}

Context = collections.namedtuple("Context", "build outdir profile workers")


def parse(argv):
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    p = argparse.ArgumentParser(prog="crossval", description=__doc__.split("\n\n")[1])
    p.add_argument(
        "--full", action="store_true", help="the whole report (about 15 minutes on 2 cores)"
    )
    p.add_argument("--build", default=os.path.join(root, "build"), help="the build directory")
    p.add_argument("--out", help="report file")
    p.add_argument("--only", default=",".join(CHECKS), help="checks to run, e.g. a,c")
    p.add_argument(
        "--workers",
        type=int,
        default=min(2, os.cpu_count() or 1),
        help="processes for the mpmath runs",
    )
    args = p.parse_args(argv)
    args.only = [k.strip() for k in args.only.split(",") if k.strip()]
    unknown = [k for k in args.only if k not in CHECKS]
    if unknown:
        p.error("--only: unknown check(s) %s (known: %s)" % (",".join(unknown), ",".join(CHECKS)))
    if args.workers < 1:
        p.error("--workers must be >= 1")
    extra = tuple(exe for key in args.only for exe in PROGRAMS.get(key, ()))
    for exe in (
        "examples/oscillator",
        "examples/pendulum",
        "examples/chain",
        "tools/ida_reference",
    ) + extra:
        if not os.access(os.path.join(args.build, exe), os.X_OK):
            p.error(
                "%s/%s is missing: build first (cmake -S . -B build && cmake --build "
                "build)" % (args.build, exe)
            )
    if not args.out:
        args.out = os.path.join(
            args.build, "report", *(() if args.full else ("fast",)), "crossval.md"
        )
    try:
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    except OSError as exc:
        p.error("--out: cannot create the report's directory: %s" % exc)
    return args


def main(argv=None):
    args = parse(argv)
    profile = profiles.FULL if args.full else profiles.FAST
    outdir = os.path.dirname(os.path.abspath(args.out))
    ctx = Context(os.path.abspath(args.build), outdir, profile, args.workers)
    start, sections = time.time(), []
    for key in args.only:
        title, check = CHECKS[key]
        runs.log("check %s: %s" % (key, title))
        section = report.Section(key, title)
        t0 = time.time()
        try:
            check(ctx, section)
        except (runs.HarnessError, stepper.StepFailure) as exc:
            # a program or the reference failed: the check cannot pass
            section.expect(False, "could not run: %s" % exc)
        runs.log("check %s: %s (%.1f s)" % (key, section.verdict(), time.time() - t0))
        sections.append(section)
    failures = report.write(args.out, sections, profile, time.time() - start)
    runs.log("report: %s (%.0f s)" % (args.out, time.time() - start))
    for key, what in failures:
        print("crossval: FAILED %s (%s): %s" % (key, CHECKS[key][0], what), file=sys.stderr)
    return 1 if failures else 0
