# SPDX-License-Identifier: GPL-3.0-or-later
"""tools/mutate/mutate: mutation testing of the library's C sources (src/**/*.c, in src/ or in
its subfolders) against the unit and example suites. Files are named by their path relative to
the repository (src/lu.c, src/core/lu.c), in the options, the mutants' ids and the reports."""

import argparse
import datetime
import fcntl
import glob
import hashlib
import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import asdict

from . import report
from .operators import (
    DEFAULT_OPERATORS,
    DESCRIPTIONS,
    OPERATORS,
    generate,
    integer_and_pointer_names,
    typedef_names,
)
from .runner import Workspace, kill_all

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EQUIVALENT = os.path.join("tests", "mutation", "equivalent.txt")
SALT = "stabdae-mutate-16"  # the fixed seed of --sample and --max


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="tools/mutate/mutate",
        description="Mutation testing of src/**/*.c: each mutant is "
        "built in build/mutate and must make a unit or example test fail.",
        epilog="operators: " + "; ".join(f"{k}: {v}" for k, v in DESCRIPTIONS.items()),
    )
    p.add_argument(
        "--sample",
        type=int,
        metavar="K",
        help="a fixed sample of K mutants spread over the files; exit 1 when one survives",
    )
    p.add_argument("--max", type=int, metavar="N", help="at most N mutants, spread over the files")
    p.add_argument("--list", action="store_true", help="print the mutants, run nothing")
    p.add_argument("--only", nargs="+", metavar="ID", help="these mutants")
    p.add_argument(
        "--files",
        nargs="+",
        metavar="FILE",
        help="mutants of these files (paths relative to the repository, e.g. src/x.c)",
    )
    p.add_argument(
        "--ops",
        nargs="+",
        choices=OPERATORS,
        help="these operator classes (default: all but carve, which needs --sanitize)",
    )
    p.add_argument(
        "--sanitize",
        action="store_true",
        help="build the mutants with "
        "AddressSanitizer (in build/mutate/build-asan): a carve one element short "
        "writes into the arena's poisoned gap, which only it sees",
    )
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 2, help="tests run at once")
    p.add_argument(
        "--timeout",
        type=float,
        default=10.0,
        help="least per-test timeout (s); a test may take 10 times its unmutated time",
    )
    p.add_argument(
        "--rescore",
        action="store_true",
        help="rewrite the last report with "
        "tests/mutation/equivalent.txt as it is now, running nothing",
    )
    p.add_argument(
        "--out",
        help="report prefix (default build/report/mutation, "
        "mutation-sample for --sample, mutation-partial for --only/--files/--ops)",
    )
    return p.parse_args(argv)


def library_files(pattern):
    """The files of src/ matching pattern, in src/ and its subfolders at any depth (the layers'
    folders), relative to the repository and sorted."""
    return sorted(
        os.path.relpath(f, ROOT)
        for f in glob.glob(os.path.join(ROOT, "src", "**", pattern), recursive=True)
    )


def all_mutants(files, ops):
    """Every mutant of files, with the type and integer names of all of src/ and include/."""
    texts = [
        _read(f) for f in glob.glob(os.path.join(ROOT, "include", "**", "*.h"), recursive=True)
    ]
    texts += [_read(os.path.join(ROOT, f)) for f in library_files("*.[ch]")]
    types, names = typedef_names(texts), integer_and_pointer_names(texts)
    out = []
    for rel in files:
        out += generate(rel, _read(os.path.join(ROOT, rel)), types, names, ops)
    return out


def _read(path):
    with open(path) as f:
        return f.read()


def load_equivalents():
    """{id: reason} from tests/mutation/equivalent.txt (`id # reason` lines)."""
    path = os.path.join(ROOT, EQUIVALENT)
    out = {}
    if not os.path.exists(path):
        return out
    for line in _read(path).splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        ident, _, reason = line.partition(" # ")
        out[ident.strip()] = reason.strip()
    return out


def _rank(m):
    return hashlib.sha1((SALT + m.id).encode()).hexdigest()


def spread(mutants, k):
    """k mutants over the files in proportion to their counts, at least one per file while k
    allows; within a file, the first by a hash of the id (so each draw depends only on the ids,
    not on the order or on the other files' mutants)."""
    by_file = {}
    for m in mutants:
        by_file.setdefault(m.file, []).append(m)
    files = sorted(by_file)
    if k >= len(mutants):
        return list(mutants)
    quota = {f: 0 for f in files}
    for f in sorted(files, key=lambda f: -len(by_file[f]))[:k]:
        quota[f] = 1
    left = k - sum(quota.values())
    if left > 0:
        total = len(mutants)
        share = {f: left * len(by_file[f]) / total for f in files}
        for f in files:
            quota[f] += int(share[f])
        rest = k - sum(quota.values())
        for f in sorted(files, key=lambda f: -(share[f] - int(share[f])))[:rest]:
            quota[f] += 1
    chosen = []
    for f in files:
        chosen += sorted(
            sorted(by_file[f], key=_rank)[: min(quota[f], len(by_file[f]))], key=lambda m: m.start
        )
    return chosen


def select(args, mutants, equivalents):
    if args.only:
        wanted = set(args.only)
        unknown = wanted - {m.id for m in mutants}
        if unknown:
            raise SystemExit("mutate: no such mutant: " + ", ".join(sorted(unknown)))
        return [m for m in mutants if m.id in wanted]
    live = [m for m in mutants if m.id not in equivalents]
    if args.sample is not None:
        return spread(live, args.sample)
    if args.max is not None:
        return spread(live, args.max)
    return live


def _git(*cmd):
    try:
        return subprocess.run(
            ["git", *cmd], cwd=ROOT, capture_output=True, text=True, check=True
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def _lock(work):
    os.makedirs(work, exist_ok=True)
    f = open(os.path.join(work, "lock"), "w")
    try:
        fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        raise SystemExit("mutate: another run holds build/mutate/lock")
    return f


def _on_term(signum, frame):
    raise KeyboardInterrupt


def say(msg):
    print(msg, flush=True)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    # the mutants' ids hold each file's path relative to the repository: ./src/x.c and an
    # absolute path name the same mutants as src/x.c
    files = (
        [os.path.relpath(f, ROOT) if os.path.isabs(f) else os.path.normpath(f) for f in args.files]
        if args.files
        else library_files("*.c")
    )
    for f in files:
        if not os.path.isfile(os.path.join(ROOT, f)):
            raise SystemExit(f"mutate: no such file: {f}")
    if args.ops and "carve" in args.ops and not args.sanitize:
        raise SystemExit("mutate: carve mutants are judged under AddressSanitizer: add --sanitize")
    mutants = all_mutants(files, args.ops or DEFAULT_OPERATORS)
    equivalents = load_equivalents()
    chosen = select(args, mutants, equivalents)
    if args.rescore:
        return rescore(args, mutants, equivalents)
    if args.list:
        for m in chosen:
            say(f"{m.id}\t{m.line}\t{m.original}\t=>\t{m.mutated}")
        say(f"{len(chosen)} mutants (of {len(mutants)}; {len(equivalents)} listed equivalent)")
        return 0
    signal.signal(signal.SIGTERM, _on_term)
    work = os.path.join(ROOT, "build", "mutate")
    lock = _lock(work)
    try:
        return run(args, mutants, chosen, equivalents, work)
    except KeyboardInterrupt:
        kill_all()
        say("mutate: interrupted; the working tree was never touched, the copy is restored")
        return 130
    finally:
        lock.close()


def run(args, mutants, chosen, equivalents, work):
    ws = Workspace(ROOT, work, jobs=args.jobs, timeout_floor=args.timeout, sanitize=args.sanitize)
    started = datetime.datetime.now(datetime.timezone.utc)
    # the sources' version now, as the copy is made (HEAD may move during a long run)
    source = dict(
        commit=_git("rev-parse", "--short", "HEAD"),
        dirty=bool(_git("status", "--porcelain", "--", "src")),
    )
    t0 = time.monotonic()
    broken = ws.prepare(say)
    texts = {}
    rows = []
    say(f"{len(chosen)} mutants (of {len(mutants)})")
    for i, m in enumerate(chosen, 1):
        text = texts.setdefault(m.file, _read(os.path.join(ws.tree, m.file)))
        out = ws.run_mutant(m, text)
        row = dict(
            id=m.id,
            file=m.file,
            line=m.line,
            op=m.op,
            original=m.original,
            mutated=m.mutated,
            **asdict(out),
        )
        rows.append(row)
        say(
            f"[{i}/{len(chosen)}] {m.id} {out.verdict} {out.seconds:.1f} s"
            + (f" ({out.killer})" if out.killer else "")
        )
    ws.restore_build()
    return finish(
        args, mutants, rows, equivalents, ws, started, time.monotonic() - t0, broken, source
    )


def rescore(args, mutants, equivalents):
    """The last report again, the mutants now listed equivalent taken out of it."""
    prefix = args.out or os.path.join(ROOT, "build", "report", "mutation")
    try:
        with open(prefix + ".json") as f:
            old = json.load(f)
    except OSError:
        raise SystemExit(f"mutate: no report to rescore: {prefix}.json")
    rows = [r for r in old["mutants"] if r["id"] not in equivalents]
    eq_rows, stale = _equivalent_rows(mutants, equivalents)
    md, _ = report.write(prefix, old["meta"], rows, eq_rows, stale)
    detected, counted, pct = report.score(rows)
    say(f"score {detected}/{counted} = {pct:.1f} %; report: {os.path.relpath(md, ROOT)}")
    return 0


def _equivalent_rows(mutants, equivalents):
    by_id = {m.id: m for m in mutants}
    rows = [
        dict(
            id=i,
            file=by_id[i].file,
            line=by_id[i].line,
            op=by_id[i].op,
            original=by_id[i].original,
            mutated=by_id[i].mutated,
            reason=r,
        )
        for i, r in equivalents.items()
        if i in by_id
    ]
    return rows, sorted(i for i in equivalents if i not in by_id)


def finish(args, mutants, rows, equivalents, ws, started, seconds, broken, source):
    eq_rows, stale = _equivalent_rows(mutants, equivalents)
    ran = [r for r in rows if r["verdict"] != "invalid"]
    mode = (
        "sample of %d" % args.sample
        if args.sample is not None
        else "partial"
        if (args.only or args.files or args.ops)
        else "at most %d" % args.max
        if args.max is not None
        else "full"
    )
    meta = dict(
        mode=mode,
        **source,
        started=started.strftime("%Y-%m-%d %H:%M"),
        seconds=seconds,
        mean_seconds=sum(r["seconds"] for r in rows) / max(1, len(rows)),
        mean_build=sum(r["build_seconds"] for r in ran) / max(1, len(ran)),
        labels=list(ws.labels),
        tests=len(ws.tests),
        jobs=ws.jobs,
        generated=len(mutants),
        ran=len(rows),
        broken_tests=broken,
    )
    prefix = args.out or os.path.join(
        ROOT,
        "build",
        "report",
        "mutation"
        + ("-sample" if args.sample is not None else "-partial" if mode == "partial" else ""),
    )
    md, _ = report.write(prefix, meta, rows, eq_rows, stale)
    detected, counted, pct = report.score(rows)
    survivors = [r for r in rows if r["verdict"] == "survived"]
    say(
        f"score {detected}/{counted} = {pct:.1f} % in {seconds:.0f} s; report: "
        f"{os.path.relpath(md, ROOT)}"
    )
    for r in survivors:
        say(f"SURVIVED {r['id']} ({r['file']}:{r['line']}): {r['original']}  =>  {r['mutated']}")
    return 1 if args.sample is not None and survivors else 0
