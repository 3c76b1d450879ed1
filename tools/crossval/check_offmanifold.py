# SPDX-License-Identifier: GPL-3.0-or-later
"""Check c: off the manifold.

c1, scheme 15 (Theorem 4): each step divides xi_i by 1 - T k_i with the gain k_i of eq. 6 at
the current state, so |xi_i(n)| <= |xi_i(0)| prod_{j<n} 1/(1 - T k_i(j)) and ||xi(n)|| <=
||xi(0)|| prod_{j<n} max_i 1/(1 - T k_i(j)). The gains are computed here, in numpy, from the
state the C program writes (every step), with the formulas of the models (not the library's).

c2, scheme 11 (Theorem 3): on a constant gain the step bound is sharp. The oscillator's
k2 = -delta^2 - eps is constant, so xi2(n) = xi2(0) (1 + T k2)^n: it decays for
T < 2/(delta^2 + eps) and grows for T above it."""

import numpy as np

from . import plots, profiles as P, runs

ROUNDING = 1e-9  # relative slack of the bounds: the products are computed in double
TINY = 1e-290  # below this the bound is in the subnormal range and not checked
MARGIN = 0.02  # c2: T = (1 -+ MARGIN) 2/(delta^2 + eps)
C2_STEPS = 100


def osc_gains(xi1, mu1, params, delta, eps, q):
    """k1, k2 of eq. 6 from Q = [[-1, 1], [c, 1]] (models.md, both variants of c)."""
    k, d, m = params["k"], params["d"], params["m"]
    if q == "paper":
        c = (k * (3 * mu1 * xi1 - 3 * mu1**2 - xi1**2) + d * xi1) / m
    else:
        c = (k * (3 * mu1**2 - 3 * mu1 * xi1 + xi1**2) + d) / m
    half = delta**2 / 2
    return -half * (1 + c**2) - eps, np.full_like(xi1, -half * 2 - eps)


def pend_gains(xi1, mu1, mu2, params, delta, eps):
    """k1 from q_1 = (-2 mu2 / (L^2 (L^2 + 2 xi1)), -2 ga sin mu1 / (L + sqrt(L^2 + 2 xi1)));
    q_2 = 0, so k2 = -eps."""
    L, ga = params["L"], params["ga"]
    r2 = L**2 + 2 * xi1
    a = -2 * mu2 / (L**2 * r2)
    b = -2 * ga * np.sin(mu1) / (L + np.sqrt(r2))
    return -(delta**2) / 2 * (a**2 + b**2) - eps, np.full_like(xi1, -eps)


def decay_case(build, name, model, params, x0, T, tf, map_name, q=None):
    options = dict(params, **P.METHOD, x0=x0, T=T, tf=tf, scheme=15, map=map_name, every=1)
    if q:
        options["q"] = q
    table = runs.run_c(build, model, options)
    delta, eps = P.METHOD["delta"], P.METHOD["eps"]
    if model == "oscillator":
        gains = osc_gains(table["xi1"], table["mu1"], params, delta, eps, q)
    else:
        gains = pend_gains(table["xi1"], table["mu1"], table["mu2"], params, delta, eps)
    xi = np.abs(table.columns(("xi1", "xi2")))
    factors = 1 / (1 - T * np.column_stack(gains))[:-1]  # step j -> j + 1
    bound = xi[0] * np.vstack([np.ones(2), np.cumprod(factors, axis=0)])
    norm = np.linalg.norm(xi, axis=1)
    norm_bound = norm[0] * np.concatenate([[1.0], np.cumprod(np.max(factors, axis=1))])
    checked = bound > TINY
    ratio = float(np.max(np.where(checked, xi / np.where(checked, bound, 1), 0)))
    norm_ratio = float(np.max(np.where(norm_bound > TINY, norm / np.maximum(norm_bound, TINY), 0)))
    return {
        "name": name,
        "T": T,
        "t": table["t"],
        "xi": xi,
        "bound": bound,
        "ratio": ratio,
        "norm_ratio": norm_ratio,
        "final": float(norm[-1]),
        "start": float(norm[0]),
    }


# the paper's start with velocities, so that both xi1 = Y and xi2 = Ydot start non-zero
OSC_X0 = (0.1, 0.6, 0.2, -0.3)


def decay_cases(build):
    osc = dict(P.OSCILLATOR)
    return [
        decay_case(
            build,
            "oscillator, Q corrected, T = 0.01",
            "oscillator",
            osc,
            OSC_X0,
            0.01,
            10.0,
            "user",
            "corrected",
        ),
        decay_case(
            build,
            "oscillator, Q as printed, T = 0.01",
            "oscillator",
            osc,
            OSC_X0,
            0.01,
            10.0,
            "user",
            "paper",
        ),
        decay_case(
            build,
            "oscillator, Q corrected, T = 0.5 (beyond Theorem 3)",
            "oscillator",
            osc,
            OSC_X0,
            0.5,
            20.0,
            "user",
            "corrected",
        ),
        decay_case(
            build, "pendulum, T = 0.01", "pendulum", P.PENDULUM, P.PENDULUM_X0, 0.01, 10.0, "dgrad"
        ),
        decay_case(
            build, "pendulum, T = 0.1", "pendulum", P.PENDULUM, P.PENDULUM_X0, 0.1, 10.0, "dgrad"
        ),
    ]


def threshold_run(build, T, scheme):
    """The oscillator from (0.1, 0, 0, 0.1): xi1 = 0, xi2 = 0.1; a growing xi2 may end the
    run early (exit 1, rows kept)."""
    options = dict(
        P.OSCILLATOR,
        **P.METHOD,
        x0=(0.1, 0.0, 0.0, 0.1),
        T=T,
        tf=C2_STEPS * T,
        scheme=scheme,
        map="user",
        every=1,
    )
    return runs.run_c(build, "oscillator", options, allow_failure=True)


def check_decay(ctx, section):
    results, rows = decay_cases(ctx.build), []
    for r in results:
        ok = section.expect(
            r["ratio"] <= 1 + ROUNDING and r["norm_ratio"] <= 1 + ROUNDING,
            "%s: |xi| exceeds the product bound (ratio %.17g, norm %.17g)"
            % (r["name"], r["ratio"], r["norm_ratio"]),
        )
        rows.append(
            (
                r["name"],
                len(r["t"]) - 1,
                "%.3g" % r["start"],
                "%.3g" % r["final"],
                "%.15f" % r["ratio"],
                "%.15f" % r["norm_ratio"],
                "pass" if ok else "FAIL",
            )
        )
    section.table(
        (
            "run (scheme 15)",
            "steps",
            "||xi(0)||",
            "||xi(end)||",
            "max |xi_i| / bound_i",
            "max ||xi|| / bound",
            "verdict",
        ),
        rows,
    )
    section.value(
        "decay_max_ratio_to_bound", max(max(r["ratio"], r["norm_ratio"]) for r in results), "%.15f"
    )
    return results


def check_threshold(ctx, section):
    delta, eps = P.METHOD["delta"], P.METHOD["eps"]
    k2 = -(delta**2) - eps
    T_crit = 2 / -k2
    runs_, rows = [], []
    for label, T, scheme, grows in (
        ("scheme 11, T just above", T_crit * (1 + MARGIN), 11, True),
        ("scheme 11, T just below", T_crit * (1 - MARGIN), 11, False),
        ("scheme 15, T just above", T_crit * (1 + MARGIN), 15, False),
    ):
        table = threshold_run(ctx.build, T, scheme)
        n = np.arange(len(table))
        factor = 1 + T * k2 if scheme == 11 else 1 / (1 - T * k2)  # eq. 11 / eq. 15
        predicted = table["xi2"][0] * factor**n
        dev = float(np.max(np.abs(table["xi2"] - predicted) / np.abs(predicted)))
        growth = abs(table["xi2"][-1] / table["xi2"][0])
        ok = section.expect(
            (growth > 1) == grows and dev <= ROUNDING,
            "%s (T = %.6g): |xi2(end)/xi2(0)| = %.3g, deviation from "
            "xi2(0) (1 + T k2)^n %.3g" % (label, T, growth, dev),
        )
        runs_.append((label, T, n, np.abs(table["xi2"])))
        rows.append(
            (
                label,
                "%.6g" % T,
                len(table) - 1,
                "%.4g" % factor,
                "%.3g" % growth,
                "%.2g" % dev,
                "grows" if growth > 1 else "decays",
                "pass" if ok else "FAIL",
            )
        )
        if scheme == 11:
            section.value("scheme11_growth_T_%s" % ("above" if grows else "below"), growth)
    section.table(
        (
            "run",
            "T",
            "steps",
            "factor per step",
            "|xi2(end) / xi2(0)|",
            "deviation from xi2(0) factor^n",
            "xi2",
            "verdict",
        ),
        rows,
    )
    section.value("scheme11_T_bound", T_crit, "%.6g")
    return runs_, T_crit


def check(ctx, section):
    section.text(__doc__.split("\n", 1)[1])
    section.text(
        """c1 starts: the oscillator from %s (the paper's position, with velocities so
that both xi1 = Y and xi2 = Ydot are non-zero), the pendulum from %s; delta 2, eps 1. The
bounds are checked with a relative slack of %g for rounding; being equalities in exact
arithmetic, the ratios are 1 up to rounding."""
        % (OSC_X0, P.PENDULUM_X0, ROUNDING)
    )
    decays = check_decay(ctx, section)
    section.text(
        """c2: the oscillator from (X, Y, Xdot, Ydot) = (0.1, 0, 0, 0.1) (xi1 = 0,
xi2 = 0.1), delta 2, eps 1, so k2 = -5 and 2/sup(-k2) = 0.4; %d steps of T = 0.4 (1 -+ %g).
(The oscillator's other gain k1 = -(delta^2/2)(1 + c^2) - eps is more negative, but xi1 stays
0 here.)"""
        % (C2_STEPS, MARGIN)
    )
    threshold, T_crit = check_threshold(ctx, section)
    section.figure(
        plot(ctx.outdir, decays[0], threshold, T_crit),
        "Left: |xi_i| of the oscillator (scheme 15, T = 0.01) and the product "
        "bounds |xi_i(0)| prod 1/(1 - T k_i) (dots) computed from the CSV state. "
        "Right: |xi2| under scheme 11 just above and below 2/(delta^2 + eps), and "
        "under scheme 15 above it (which falls below the panel).",
    )


def plot(outdir, decay, threshold, T_crit):
    fig, (left, right) = plots.figure(ncols=2, width=5.2, height=4.0)
    for i, colour in ((0, "tab:blue"), (1, "tab:orange")):
        left.semilogy(decay["t"], decay["xi"][:, i], color=colour, label="|xi%d|" % (i + 1))
        left.semilogy(
            decay["t"][::25],
            decay["bound"][::25, i],
            "o",
            ms=3,
            mfc="none",
            color=colour,
            label="bound for xi%d" % (i + 1),
        )
    left.set_xlabel("t")
    left.set_ylabel("|xi_i|")
    left.set_title("c1. %s" % decay["name"])
    left.legend()
    for (label, T, n, xi2), colour in zip(threshold, ("tab:red", "tab:green", "tab:blue")):
        right.semilogy(n, xi2, color=colour, label="%s (T = %.4g)" % (label, T))
    right.set_ylim(1e-4, 1e3)
    right.set_xlabel("step n")
    right.set_ylabel("|xi2|")
    right.set_title("c2. 2/(delta^2 + eps) = %g" % T_crit)
    right.legend()
    return plots.save(fig, outdir, "offmanifold.png")
