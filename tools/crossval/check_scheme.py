# SPDX-License-Identifier: GPL-3.0-or-later
"""Check a: the same discrete scheme in C (double) and in the mpmath reference (dps 40).

Per row, the deviation of the C state c from the reference state r is
max_i |c_i - r_i| / max(max_i |r_i|, tiny): relative to the size of the whole state, since a
single column crossing zero makes its own relative error meaningless. The state columns are
X, Y, Xdot, Ydot, xi1, xi2, mu1, mu2 (oscillator, pendulum) and, for the chain, the columns its
program prints (max |Y_i|, max |Ydot_i|, E), from the same explicit start (--x0)."""

import numpy as np

from . import plots, profiles as P, runs

TOL = 1e-12
TINY = 1e-300
DPS = 40
T = 1e-3
STATE = {
    "oscillator": ("X", "Y", "Xdot", "Ydot", "xi1", "xi2", "mu1", "mu2"),
    "pendulum": ("X", "Y", "Xdot", "Ydot", "xi1", "xi2", "mu1", "mu2"),
    "chain": ("max_abs_Y", "max_abs_Ydot", "E"),
}
MODELS = {
    "oscillator": (P.OSCILLATOR, P.PAPER_X0),
    "pendulum": (P.PENDULUM, P.PENDULUM_X0),
    "chain": (P.CHAIN, P.CHAIN_X0),
}
MAPS = {
    "oscillator": ("euler", "midpoint", "dgrad", "user", "dg4", "rk4", "rk8"),
    "pendulum": ("euler", "midpoint", "dgrad", "dg4", "rk4", "rk8"),
    "chain": ("euler", "midpoint", "dgrad", "dg4", "rk4", "rk8"),
}


BASELINES = """The runs with the baselines (stabilizer none or baumgarte) are shown without the
tolerance: the mu update is the paper's (checked above) and their xi update is checked against
its exact discrete solution in check e. From the paper's start they stay far off the manifold
(Y = 0.6 throughout with none), where the dgrad map's double rounding is amplified: C and the
float64 reference, both in double, then differ from each other about as much as from mpmath
(up to about 1e-12 over 1e4 steps), which measures the rounding, not the implementations."""


def case(model, scheme, map_name, nsteps, q=None, stabilizer="paper"):
    params, x0 = MODELS[model]
    params = dict(params, **({"q": q} if q else {}))
    return {
        "model": model,
        "params": params,
        "x0": x0,
        "T": T,
        "nsteps": nsteps,
        "scheme": scheme,
        "map": map_name,
        "stabilizer": stabilizer,
    }


def cases(profile):
    n, nc = profile.scheme_steps, profile.chain_steps
    if profile.scheme_cases == "subset":
        return [case("oscillator", 15, m, n, "corrected") for m in MAPS["oscillator"]] + [
            case("oscillator", 11, "user", n, "paper"),
            case("oscillator", 15, "dgrad", n, "corrected", "baumgarte"),
            case("pendulum", 15, "dgrad", n),
            case("pendulum", 11, "euler", n),
            case("chain", 15, "midpoint", nc),
        ]
    out = []
    for scheme in (15, 11):
        out += [
            case("oscillator", scheme, m, n, q)
            for q in ("corrected", "paper")
            for m in MAPS["oscillator"]
        ]
        out += [
            case("oscillator", scheme, "dgrad", n, "corrected", s) for s in ("none", "baumgarte")
        ]
        out += [case("pendulum", scheme, m, n) for m in MAPS["pendulum"]]
        out += [case("chain", scheme, m, nc) for m in MAPS["chain"]]
    # the slow ones first, so that two workers finish together
    return sorted(out, key=lambda c: (c["model"] != "chain", c["map"] != "dg4"))


def label(c):
    q = " Q %s" % c["params"]["q"] if "q" in c["params"] else ""
    stab = "" if c["stabilizer"] == "paper" else " stabilizer %s" % c["stabilizer"]
    return "%s%s %s scheme %d%s" % (c["model"], q, c["map"], c["scheme"], stab)


def run_c(build, c):
    every = max(1, c["nsteps"] // 1000)
    options = dict(
        c["params"],
        **P.METHOD,
        x0=c["x0"],
        T=c["T"],
        tf=c["nsteps"] * c["T"],
        scheme=c["scheme"],
        map=c["map"],
        stabilizer=c["stabilizer"],
        every=every,
    )
    return runs.run_c(build, c["model"], options), every


def deviation(c_table, r_table, columns):
    """Per row: max_i |c_i - r_i| / max(max_i |r_i|, tiny)."""
    cs, rs = c_table.columns(columns), r_table.columns(columns)
    return np.max(np.abs(cs - rs), axis=1) / np.maximum(np.max(np.abs(rs), axis=1), TINY)


def check(ctx, section):
    todo = cases(ctx.profile)
    runs.log(
        "a: %d runs of the reference (mpmath at dps %d, and float64), %d workers; a "
        "line as each ends (the chain's implicit maps in mpmath take minutes each)"
        % (2 * len(todo), DPS, ctx.workers)
    )
    c_tables, specs = [], []
    for c in todo:
        table, every = run_c(ctx.build, c)
        c_tables.append(table)
        specs.append(
            dict(c, params=dict(c["params"], **P.METHOD), arithmetic="mpmath", dps=DPS, every=every)
        )
    # the same runs in double precision too: they tell rounding from implementation
    jobs = specs + [dict(s, arithmetic="float64") for s in specs]
    labels = [label(c) + " (mpmath)" for c in todo] + [label(c) + " (float64)" for c in todo]
    results = runs.parallel(runs.run_reference, jobs, labels, ctx.workers)
    references, doubles = results[: len(todo)], results[len(todo) :]

    rows, curves, worst = [], [], {}
    baselines = 0.0
    for c, ct, rt, dt in zip(todo, c_tables, references, doubles):
        same_rows = len(ct) == len(rt) and np.allclose(ct["t"], rt["t"], rtol=1e-12, atol=0)
        if not section.expect(
            same_rows, "%s: the C and reference rows are not at the same times" % label(c)
        ):
            continue
        dev = deviation(ct, rt, STATE[c["model"]])
        top = float(np.max(dev))
        same_double = float(np.max(deviation(ct, dt, STATE[c["model"]])))
        if c["stabilizer"] != "paper":  # shown, see BASELINES
            baselines = max(baselines, top)
            rows.append((label(c), c["nsteps"], top, same_double, "(shown)"))
            continue
        worst[c["model"]] = max(worst.get(c["model"], 0.0), top)
        ok = section.expect(
            top <= TOL, "%s: max relative deviation %.3g > %g" % (label(c), top, TOL)
        )
        rows.append((label(c), c["nsteps"], top, same_double, "pass" if ok else "FAIL"))
        curves.append((c, ct["t"], dev))

    section.text(
        __doc__.split("\n", 1)[1]
        + """
Both implementations get every parameter explicitly (delta 2, eps 1, T = %g, the model's
parameters, the start); the reference rounds its inputs to doubles first, so both solve the
same problem, and its Newton iterations stop at a residual of 1e-30. The reference has no dg4
map: the harness composes it from the reference's dgrad step exactly as src/map_dg4.c does
(Yoshida's triple jump, xi updated once per step). Its rk4 and rk8 are its own, from the
tableaus as published (rk8's 30-digit decimals in mpmath, where the C library has their
nearest doubles). Starts: oscillator %s (the paper's),
pendulum %s, chain of N = 3 %s, all off the manifold. Tolerance: %g."""
        % (T, P.PAPER_X0, P.PENDULUM_X0, P.CHAIN_X0, TOL)
    )
    section.table(
        ("run", "steps", "max deviation from mpmath", "from the float64 reference", "verdict"), rows
    )
    section.text("""The last column compares C with the reference run in double precision: the
deviation from mpmath is the rounding of double arithmetic, which the float64 reference mostly
reproduces bit for bit (0). The dgrad map's deviation appears within the first steps: Gonzalez's
quotient (H(y) - H(x) - grad H(m).v)/|v|^2 cancels digits when the increment v is small (here
at rest, where mu2 barely moves), in both double-precision implementations alike.""")
    section.text(BASELINES)
    section.figure(
        plot(ctx.outdir, curves),
        "Deviation of C from the mpmath reference per row "
        "(relative to the state's size), every run; the dashed line is the "
        "tolerance.",
    )
    section.value("c_vs_mpmath_max_rel", max(worst.values()) if worst else float("nan"))
    for model, value in worst.items():
        section.value("c_vs_mpmath_max_rel_%s" % model, value)
    section.value("c_vs_mpmath_max_rel_baselines", baselines)
    section.value("c_vs_mpmath_runs", sum(1 for r in rows if r[-1] != "(shown)"))


def plot(outdir, curves):
    fig, (ax,) = plots.figure(width=7.5, height=4.5)
    colours = {"oscillator": "tab:blue", "pendulum": "tab:orange", "chain": "tab:green"}
    seen = set()
    for c, t, dev in curves:
        model = c["model"]
        ax.semilogy(
            t,
            np.maximum(dev, 1e-18),
            color=colours[model],
            lw=0.8,
            alpha=0.6,
            label=None if model in seen else model,
        )
        seen.add(model)
    ax.axhline(TOL, color="k", ls="--", lw=1, label="tolerance %g" % TOL)
    ax.set_ylim(1e-18, 1e-10)
    ax.set_xlabel("t")
    ax.set_ylabel("max_i |c_i - r_i| / max_i |r_i|")
    ax.set_title("a. C (double) against the mpmath reference (dps %d), same scheme" % DPS)
    ax.legend(loc="upper left")
    return plots.save(fig, outdir, "scheme_deviation.png")
