# SPDX-License-Identifier: GPL-3.0-or-later
"""Running the three implementations and reading their CSV into a Table.

run_c        a C example program (build/examples/NAME), CSV through --out
run_ida      the SUNDIALS IDA reference (build/tools/ida_reference)
run_reference the Python reference stabdae_ref in float64 or mpmath, in this process;
             the map dg4 (not in stabdae_ref) is composed here from its dgrad map exactly as
             the C library composes it (Yoshida's triple jump, see dg4_map)
parallel     runs jobs in worker processes with progress on stderr
"""

import concurrent.futures
import copy
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from stabdae_ref import api, maps


class HarnessError(Exception):
    """A program or the reference could not produce what a check needs."""


class Table:
    """CSV columns as float arrays: table["X"], table.header, len(table)."""

    def __init__(self, header, data, status=None):
        self.header = tuple(header)
        self.data = np.asarray(data, dtype=float).reshape(-1, len(self.header))
        self.status = status  # the program's exit status (C programs), or IDA's status line

    def __getitem__(self, name):
        return self.data[:, self.header.index(name)]

    def __len__(self):
        return self.data.shape[0]

    def columns(self, names):
        return np.column_stack([self[n] for n in names])


def log(message):
    print("crossval: " + message, file=sys.stderr, flush=True)


def number(x):
    """A float as the shortest text that reads back as the same double."""
    return repr(float(x))


def cli_args(options):
    """{'T': 0.01, 'x0': (1, 0, 0, 0)} -> ['--T', '0.01', '--x0', '1.0,0.0,0.0,0.0']."""
    args = []
    for key, value in options.items():
        if isinstance(value, (list, tuple)):
            value = ",".join(number(v) for v in value)
        elif isinstance(value, float):
            value = number(value)
        args += ["--" + key, str(value)]
    return args


def read_csv(path, status=None):
    with open(path) as f:
        header = f.readline().strip().split(",")
        lines = [line for line in f if line.strip() and not line.startswith("#")]
    if not lines:
        return Table(header, np.zeros((0, len(header))), status)
    return Table(header, np.loadtxt(lines, delimiter=",", ndmin=2), status)


def run_program(command, allow_failure=False):
    """Runs command with --out FILE appended; the Table of FILE. Exit 1 (a failure during the
    run, rows kept) is accepted when allow_failure; anything else raises HarnessError."""
    with tempfile.TemporaryDirectory(prefix="crossval-") as tmp:
        out = os.path.join(tmp, "out.csv")
        proc = subprocess.run(
            [str(c) for c in command] + ["--out", out], capture_output=True, text=True
        )
        if proc.returncode != 0 and not (allow_failure and proc.returncode == 1):
            raise HarnessError(
                "%s exited with %d: %s"
                % (" ".join(map(str, command)), proc.returncode, proc.stderr.strip())
            )
        return read_csv(out, proc.returncode)


def run_c(build, program, options, allow_failure=False):
    """build/examples/PROGRAM with the options dict (every parameter given explicitly)."""
    exe = os.path.join(build, "examples", program)
    return run_program([exe] + cli_args(options), allow_failure)


def run_ida(build, model, options):
    """build/tools/ida_reference MODEL with the options dict; the '#' counter lines are
    dropped (status 'ok' is required)."""
    exe = os.path.join(build, "tools", "ida_reference")
    return run_program([exe, model] + cli_args(options))


# ---- the Python reference ----------------------------------------------------------------


def dg4_map(stepper, T):
    """phi_T(mu) = (Psi4_T(mu) - mu)/T with Psi4_T = Psi_{g1 T} o Psi_{g2 T} o Psi_{g1 T},
    g1 = 1/(2 - 2^(1/3)), g2 = 1 - 2 g1: Yoshida's triple jump of the symmetric
    discrete-gradient step Psi_h (y = x + h S gradbar H(x, y), solved by the reference's
    Newton with Q xi = 0). Explicit in mu+, so xi is updated once per step, as in C's dg4."""
    a = stepper.a
    g1 = 1 / (2 - a.num(2.0) ** (a.num(1) / 3))
    gammas = (g1, 1 - 2 * g1, g1)
    zero = [a.num(0.0)] * stepper.model.n_mu

    def phi(mu, mu_next):
        x = mu
        for g in gammas:
            x, _ = stepper.mu_next(x, zero, g * T)
        return [(u - w) / T for u, w in zip(x, mu)]

    return maps.Map("dg4", phi)


def run_reference(spec):
    """spec: dict(model, params, x0, T, nsteps, scheme, map, stabilizer, arithmetic, dps,
    every). Returns a Table of floats (mpmath numbers rounded to the nearest double)."""
    map_name = spec["map"]
    mdl, st, xi, mu = api.setup(
        spec["model"],
        spec["params"],
        spec["x0"],
        spec["scheme"],
        "dgrad" if map_name == "dg4" else map_name,
        spec.get("stabilizer", "paper"),
        spec["arithmetic"],
        spec.get("dps", 40),
    )
    T = mdl.a.num(float(spec["T"]))
    if map_name == "dg4":
        # the stages use the reference's dgrad Newton; a copy keeps the dgrad map for them
        st.map = dg4_map(copy.copy(st), T)
    rows = [
        [float(v) for v in row]
        for row in api.rows(mdl, st, xi, mu, T, spec["nsteps"], spec.get("every", 1))
    ]
    return Table(mdl.header, rows)


def parallel(function, jobs, labels, workers):
    """[function(job) for job in jobs] in `workers` processes, a line on stderr per job done."""
    results, start = [None] * len(jobs), time.time()
    with concurrent.futures.ProcessPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(function, job): i for i, job in enumerate(jobs)}
        for done, future in enumerate(concurrent.futures.as_completed(futures), 1):
            i = futures[future]
            results[i] = future.result()
            log("  [%d/%d] %s (%.0f s elapsed)" % (done, len(jobs), labels[i], time.time() - start))
    return results


def nsteps_for(T, tf):
    """The C programs' step count, ceil(tf/T - 1e-9)."""
    return max(0, math.ceil(tf / T - 1e-9))
