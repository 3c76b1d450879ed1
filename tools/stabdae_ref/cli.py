# SPDX-License-Identifier: GPL-3.0-or-later
"""The run command: python -m stabdae_ref MODEL [options] (__main__.py) writes the run as CSV
(the C examples' columns, see models.py), %.17g in float64, all dps digits in mpmath. The steps
are ceil(tf/T - 1e-9) (at least 1), as the C programs count them.

Bad input: one line on stderr, exit 2, no output file. A step that fails: the rows computed so
far stay written, one line on stderr says where it stopped, exit 1.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Iterable, Sequence
from typing import Any, NoReturn, TextIO, cast

from . import api, stepper
from .arith import Arith

# model -> options that apply to it (besides the method's)
MODEL_OPTIONS = {
    "oscillator": ("k", "d", "m", "ga", "q"),
    "pendulum": ("L", "m", "ga"),
    "chain": ("N", "k", "d", "m", "ga", "kc"),
}
DEFAULT_MAP = {"oscillator": "user", "pendulum": "dgrad", "chain": "dgrad"}
DEFAULT_TF = {"oscillator": 50.0, "pendulum": 10.0, "chain": 10.0}


class BadInput(Exception):
    pass


class Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        raise BadInput(message)


def number_list(text: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError("not a comma-separated list of numbers: %r" % text)
    if not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError("values must be finite: %r" % text)
    return values


def parser() -> Parser:
    p = Parser(
        prog="python -m stabdae_ref",
        description="stabdae reference run, CSV out "
        "(python -m stabdae_ref expected: the examples' answers).",
    )
    p.add_argument("model", choices=sorted(MODEL_OPTIONS))
    for name in ("k", "d", "m", "ga", "L", "kc", "delta", "eps", "T", "tf"):
        p.add_argument("--" + name, type=float)
    p.add_argument("--N", type=int)
    p.add_argument(
        "--seed", type=int, help="the chain's random start of the C program's --seed (without --x0)"
    )
    p.add_argument("--steps", type=int)
    p.add_argument("--x0", type=number_list, help="X,Y,Xdot,Ydot (4 N values for the chain)")
    p.add_argument("--alpha", type=number_list, help="Baumgarte gains (default 1,2)")
    p.add_argument("--scheme", type=int, choices=stepper.SCHEMES, default=15)
    p.add_argument(
        "--map",
        choices=("euler", "midpoint", "dgrad", "user", "rk4", "rk8"),
        help="default user for the oscillator, dgrad otherwise",
    )
    p.add_argument("--q", choices=("corrected", "paper"))
    p.add_argument("--stabilizer", choices=stepper.STABILIZERS, default="paper")
    p.add_argument("--every", type=int, default=1)
    p.add_argument("--arith", choices=("float64", "mpmath"), default="float64")
    p.add_argument("--dps", type=int, default=40)
    p.add_argument("--out")
    return p


def params_of(args: argparse.Namespace) -> dict[str, Any]:
    """The parameter dict for api.setup; options foreign to the model are an error."""
    params: dict[str, Any] = {}
    for name in ("k", "d", "m", "ga", "L", "N", "kc", "q"):
        value = getattr(args, name)
        if value is None:
            continue
        if name not in MODEL_OPTIONS[args.model]:
            raise BadInput("--%s does not apply to model %s" % (name, args.model))
        params[name] = value
    for name in ("delta", "eps", "alpha"):
        if getattr(args, name) is not None:
            params[name] = getattr(args, name)
    return params


def step_count(args: argparse.Namespace, T: float) -> int:
    if args.tf is not None and args.steps is not None:
        raise BadInput("give --tf or --steps, not both")
    if args.steps is not None:
        return cast(int, args.steps)  # --steps is type=int
    tf = DEFAULT_TF[args.model] if args.tf is None else args.tf
    if not (math.isfinite(tf) and tf > 0):
        raise BadInput("--tf must be finite and > 0")
    return max(1, math.ceil(tf / T - 1e-9))


def write_rows(out: TextIO, a: Arith, rows: Iterable[api.Row]) -> None:
    """Writes rows as they come, so a failure keeps what was computed."""
    for row in rows:
        out.write(",".join([a.fmt(v) for v in row[:-1]] + [str(row[-1])]) + "\n")


def main(argv: Sequence[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        args = parser().parse_args(argv)
        T = 0.001 if args.T is None else args.T
        nsteps = step_count(args, T)
        api.check_steps(T, nsteps)
        if args.every < 1:
            raise BadInput("--every must be >= 1")
        mdl, st, xi, mu = api.setup(
            args.model,
            params_of(args),
            args.x0,
            args.scheme,
            args.map or DEFAULT_MAP[args.model],
            args.stabilizer,
            args.arith,
            args.dps,
            args.seed,
        )
    except (BadInput, ValueError, ArithmeticError) as exc:
        print("stabdae_ref: %s" % exc, file=sys.stderr)
        return 2
    try:
        out = open(args.out, "w") if args.out else sys.stdout
    except OSError as exc:
        print("stabdae_ref: cannot write %s: %s" % (args.out, exc.strerror), file=sys.stderr)
        return 2
    try:
        out.write(",".join(mdl.header) + "\n")
        write_rows(out, mdl.a, api.rows(mdl, st, xi, mu, mdl.a.num(T), nsteps, args.every))
    except stepper.StepFailure as failure:
        print(
            "stabdae_ref: stopped at step %d of %d (t = %s): %s"
            % (failure.step, nsteps, mdl.a.fmt(failure.t), failure.reason),
            file=sys.stderr,
        )
        return 1
    finally:
        if out is not sys.stdout:
            out.close()
    return 0
