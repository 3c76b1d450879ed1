# SPDX-License-Identifier: GPL-3.0-or-later
"""Check e: constraint drift. The C oscillator with --stabilizer none (index reduction: the
chain Y'' = 0), baumgarte (Y'' = -alpha_1 Y - alpha_2 Y', alpha = (1, 2)) and paper (eq. 6),
scheme 15, the paper's map and T = 1e-3. In coordinates xi = (Y, Ydot) the baselines are
linear, so their discrete solutions are known exactly: index reduction gives
Y(t) = Y(0) + t Ydot(0) (it never restores the constraint and drifts linearly from any
velocity error), Baumgarte xi(n) = (I - T A)^-n xi(0) with A = [[0, 1], [-1, -2]]; the
paper's stabilization must bring |Y| below 1e-12 by t = 5 (Theorem 4; cf. the paper's Fig. 2)."""

import numpy as np

from . import plots, profiles as P, runs

T, TF, EVERY = 1e-3, 10.0, 10
LINEAR_TOL = 1e-12  # none and baumgarte against their exact discrete solutions
PAPER_LIMIT, PAPER_BY = 1e-12, 5.0
STARTS = (
    ("the paper's start (0.1, 0.6, 0, 0)", P.PAPER_X0),
    ("on the floor with a velocity error: (0.1, 0, 0, 1e-3)", (0.1, 0.0, 0.0, 1e-3)),
)
ALPHA = (1.0, 2.0)  # the library's and the reference's default Baumgarte gains


def run(ctx, x0, stabilizer):
    return runs.run_c(
        ctx.build,
        "oscillator",
        dict(
            P.OSCILLATOR,
            **P.METHOD,
            x0=x0,
            T=T,
            tf=TF,
            scheme=15,
            map="user",
            stabilizer=stabilizer,
            every=EVERY,
        ),
    )


def baumgarte_exact(xi0, count):
    """xi every EVERY steps of (I - T A) xi+ = xi."""
    A = np.array([[0.0, 1.0], [-ALPHA[0], -ALPHA[1]]])
    M = np.linalg.matrix_power(np.linalg.inv(np.eye(2) - T * A), EVERY)
    out = [np.array(xi0, dtype=float)]
    for _ in range(count - 1):
        out.append(M @ out[-1])
    return np.array(out)


def check_start(ctx, section, label, x0, rows):
    tables = {s: run(ctx, x0, s) for s in ("none", "baumgarte", "paper")}
    scale = max(abs(x0[1]), abs(x0[3]))
    t = tables["none"]["t"]
    dev_none = float(np.max(np.abs(tables["none"]["Y"] - (x0[1] + t * x0[3]))))
    xi = tables["baumgarte"].columns(("xi1", "xi2"))
    dev_baum = float(np.max(np.abs(xi - baumgarte_exact((x0[1], x0[3]), len(xi)))))
    late = tables["paper"]["t"] >= PAPER_BY - 1e-12
    paper_late = float(np.max(np.abs(tables["paper"]["Y"][late])))
    section.expect(
        dev_none <= LINEAR_TOL * scale,
        "%s, none: Y deviates %.3g from Y(0) + t Ydot(0)" % (label, dev_none),
    )
    section.expect(
        dev_baum <= LINEAR_TOL * scale,
        "%s, baumgarte: xi deviates %.3g from its exact discrete solution" % (label, dev_baum),
    )
    section.expect(
        paper_late < PAPER_LIMIT,
        "%s, paper: |Y| = %.3g >= %g for t >= %g" % (label, paper_late, PAPER_LIMIT, PAPER_BY),
    )
    ends = {s: abs(float(tables[s]["Y"][-1])) for s in tables}
    rows.append(
        (
            label,
            "%.3g" % ends["none"],
            "%.3g" % ends["baumgarte"],
            "%.3g" % ends["paper"],
            "%.2g" % dev_none,
            "%.2g" % dev_baum,
            "%.3g" % paper_late,
        )
    )
    return tables, ends


def check(ctx, section):
    section.text(__doc__.split(". ", 1)[1])
    rows, panels = [], []
    for i, (label, x0) in enumerate(STARTS):
        tables, ends = check_start(ctx, section, label, x0, rows)
        panels.append((label, tables))
        if i == 0:
            for s, v in ends.items():
                section.value("drift_Y_t%g_%s" % (TF, s), v)
    section.table(
        (
            "start",
            "|Y(%g)| none" % TF,
            "baumgarte",
            "paper",
            "none: deviation from Y0 + t Ydot0",
            "baumgarte: deviation from exact",
            "paper: max |Y|, t >= %g" % PAPER_BY,
        ),
        rows,
    )
    section.text(
        "Tolerances: %g relative to the start's size for the two baselines, |Y| < %g "
        "for the paper's stabilization after t = %g." % (LINEAR_TOL, PAPER_LIMIT, PAPER_BY)
    )
    section.figure(
        plot(ctx.outdir, panels),
        "Constraint violation |Y| against time (log "
        "scale) under index reduction, Baumgarte and the paper's stabilization, "
        "C oscillator, scheme 15, T = 1e-3; dotted: |Ydot|. From the second start "
        "the paper's Y stays exactly 0 (scheme 15 updates xi1 = Y by its own "
        "gain, and Y(0) = 0), so only its |Ydot| shows.",
    )


def plot(outdir, panels):
    fig, axes = plots.figure(ncols=2, width=5.2, height=4.0)
    styles = {
        "none": ("tab:red", "index reduction (none)"),
        "baumgarte": ("tab:orange", "Baumgarte, alpha = (1, 2)"),
        "paper": ("tab:blue", "paper, eq. 6 (delta 2, eps 1)"),
    }
    for ax, (label, tables) in zip(axes, panels):
        for s, (colour, name) in styles.items():
            ax.semilogy(
                tables[s]["t"],
                np.maximum(np.abs(tables[s]["Y"]), 1e-300),
                color=colour,
                label="|Y|, " + name,
            )
            ax.semilogy(
                tables[s]["t"],
                np.maximum(np.abs(tables[s]["Ydot"]), 1e-300),
                color=colour,
                ls=":",
                lw=1,
            )
        ax.set_ylim(1e-18, 10)
        ax.set_xlabel("t")
        ax.set_ylabel("|Y|")
        ax.set_title(label, fontsize=9)
        ax.legend(loc="lower left", title="dotted: |Ydot|", title_fontsize=8)
    return plots.save(fig, outdir, "drift.png")
