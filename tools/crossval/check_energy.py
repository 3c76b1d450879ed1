# SPDX-License-Identifier: GPL-3.0-or-later
"""Check d: energy. With d = 0 the discrete-gradient map conserves W = m mu2^2/2 + k mu1^4/4
exactly on the manifold (S skew), so along the C oscillator's run W may change by rounding
only. W is computed here from the mu columns of the CSV. IDA (both forms, rtol 1e-12) solves
the same problem over the same time; its energy E = m (Xdot^2 + Ydot^2)/2 + k X^4/4 + m ga Y
(equal to W on the manifold) drifts with its tolerance."""

import numpy as np

from . import plots, profiles as P, runs

TOL = 1e-12
T = 0.01
X0 = (1.0, 0.0, 0.0, 0.0)  # from rest at X = 1 on the floor
IDA_TOL = {"rtol": 1e-12, "atol": 1e-13}


def params():
    return dict(P.OSCILLATOR, d=0.0)


def c_run(ctx, map_name):
    p = params()
    table = runs.run_c(
        ctx.build,
        "oscillator",
        dict(
            p,
            **P.METHOD,
            x0=X0,
            T=T,
            tf=ctx.profile.energy_tf,
            scheme=15,
            map=map_name,
            every=ctx.profile.energy_every,
        ),
    )
    W = p["m"] * table["mu2"] ** 2 / 2 + p["k"] * table["mu1"] ** 4 / 4
    return table["t"], np.abs(W - W[0]) / W[0]


def ida_run(ctx, form):
    p, tf = params(), ctx.profile.energy_tf
    table = runs.run_ida(
        ctx.build,
        "oscillator",
        dict(p, **IDA_TOL, form=form, x0=X0, tf=tf, **{"every-dt": tf / 1000}),
    )
    E = (
        p["m"] * (table["Xdot"] ** 2 + table["Ydot"] ** 2) / 2
        + p["k"] * table["X"] ** 4 / 4
        + p["m"] * p["ga"] * table["Y"]
    )
    return table["t"], np.abs(E - E[0]) / abs(E[0]), float(np.max(np.abs(table["Y"])))


def check(ctx, section):
    tf = ctx.profile.energy_tf
    nsteps = runs.nsteps_for(T, tf)
    section.text(
        __doc__.split(". ", 1)[1]
        + """
The oscillator with k 2, m 1, d 0, from rest at X = 1 on the floor, scheme 15, T = %g,
%d steps (tf = %g). Tolerance for dgrad: %g relative. Shown without a tolerance: dg4 (three dgrad
stages per step, each conserving W; its rounding error grows about linearly in time, some
4e-18 relative per step, 3.6e-12 over 1e6 steps) and the midpoint map, which conserves only
quadratic invariants."""
        % (T, nsteps, tf, TOL)
    )
    curves, rows = [], []
    for map_name, checked in (("dgrad", True), ("dg4", False), ("midpoint", False)):
        runs.log("d: C %s, %d steps" % (map_name, nsteps))
        t, rel = c_run(ctx, map_name)
        drift = float(np.max(rel))
        ok = not checked or section.expect(
            drift <= TOL, "C %s: W drifts by %.3g (relative) > %g" % (map_name, drift, TOL)
        )
        rows.append(
            (
                "C, map %s" % map_name,
                "W",
                "%.3g" % drift,
                "-",
                ("pass" if ok else "FAIL") if checked else "(shown)",
            )
        )
        curves.append(("C %s" % map_name, t, rel))
        section.value("energy_drift_" + map_name, drift)
    for form in ("index1", "ggl"):
        runs.log("d: IDA %s up to t = %g" % (form, tf))
        t, rel, max_Y = ida_run(ctx, form)
        drift = float(np.max(rel))
        rows.append(
            ("IDA %s, rtol 1e-12" % form, "E", "%.3g" % drift, "%.2g" % max_Y, "(reported)")
        )
        curves.append(("IDA %s" % form, t, rel))
        section.value("energy_drift_ida" + ("" if form == "index1" else "_ggl"), drift)
    section.table(("solver", "energy", "max relative change", "max |Y|", "verdict"), rows)
    section.figure(
        plot(ctx.outdir, curves, tf),
        "Relative change of the energy against time (log scale; zero is drawn at 1e-18).",
    )


def plot(outdir, curves, tf):
    fig, (ax,) = plots.figure(width=7.5, height=4.5)
    styles = {
        "C dgrad": ("tab:green", "-"),
        "C dg4": ("tab:purple", "--"),
        "C midpoint": ("tab:orange", "-"),
        "IDA index1": ("tab:red", "-"),
        "IDA ggl": ("tab:brown", ":"),
    }
    for name, t, rel in curves:
        colour, ls = styles[name]
        ax.semilogy(t, np.maximum(rel, 1e-18), color=colour, ls=ls, label=name)
    ax.axhline(TOL, color="k", ls="--", lw=1, label="tolerance for dgrad")
    ax.set_xlim(0, tf)
    ax.set_ylim(1e-18, 1e-1)
    ax.set_xlabel("t")
    ax.set_ylabel("|W(t) - W(0)| / W(0)  (IDA: E)")
    ax.set_title("d. Energy of the undamped oscillator on the manifold, T = %g" % T)
    ax.legend(loc="upper center", ncol=3)
    return plots.save(fig, outdir, "energy.png")
