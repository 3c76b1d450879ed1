# SPDX-License-Identifier: GPL-3.0-or-later
"""Check f: the mechanical front-end (<stabdae/mbs.h>) through its examples pendulum_mbs,
double_pendulum and fourbar, against references that share nothing with the library
(stabdae_ref.mechanisms, mpmath): the Cartesian pendulum's exact solution (Jacobi sn), the
double pendulum's Lagrangian ODE in its two angles, and the four-bar's index-1 ODE in its
Cartesian coordinates (both by mpmath's Taylor-series solver). Orders: every run starts on the
constraints; the error of a run is the largest deviation of (q, v) from the reference over
t = 0.25 i up to tf, the observed order the least-squares slope of log2(error) against log2(T)
over four halvings of T, within 0.15 of the theory. Energy: the dgrad map conserves
E = sum m |v|^2/2 + m ga y (computed here from q and v) across the chart switches. Drift: the
constraints c_j = (|p_a - p_b|^2 - l_j^2)/2 (computed here from q) stay at rounding along
those runs, and from a start off them they fall below 1e-12 by t = 5 (Theorem 4). The
pendulum's lambda column equals m (|v|^2 - ga y)/|q|^2 at the program's own state."""

import math

import numpy as np

from stabdae_ref import mechanisms as mech

from . import plots, profiles as P, runs

GRID, HALVINGS, TOL_ORDER = 0.25, 4, 0.15
THEORY = {"euler": 1, "midpoint": 2, "dgrad": 2, "dg4": 4, "rk4": 4}
# the coarsest step per map (every halving divides GRID): dg4's error reaches rounding below
# T = 2e-3; rk4's is 3e-6 at 2^-6 and 4e-11 at T / 16. rk8 is not here: wherever double
# precision resolves its error, its ninth-order term outweighs the eighth (observed orders 8.3
# to 10 from T = 1/8), as on the oscillator of check b
T0 = {"euler": 1e-2, "midpoint": 1e-2, "dgrad": 1e-2, "dg4": 2.0**-7, "rk4": 2.0**-6}
ENERGY_T, ENERGY_TOL = 0.01, 1e-12  # |E - E0| relative to sum m ga l
DRIFT_TOL, OFF_BY = 1e-12, 5.0
LAMBDA_TOL = 1e-10  # relative to m ga / L
DPS = 25

PEND = {"L": 1.0, "m": 1.0, "ga": 9.81}
PEND_THETA0 = 1.0  # past 0.886 rad (tan^2 = 1.5): the chart switches twice a swing
PEND_TF = 2.0
PEND_OFF = ((0.5, -0.9), (0.1, 0.2))  # off the circle in position and velocity
DOUBLE = {"L1": 1.0, "L2": 1.0, "m1": 1.0, "m2": 1.0, "ga": 9.81}
DOUBLE_THETA0, DOUBLE_OMEGA0 = (1.0, 1.5), (0.0, 0.0)
DOUBLE_TF = 1.0  # short: the motion is chaotic


def steps(map_name):
    return [T0[map_name] / 2**j for j in range(HALVINGS + 1)]


def columns(table, n_q):
    return table.columns(
        ["q%d" % (i + 1) for i in range(n_q)] + ["v%d" % (i + 1) for i in range(n_q)]
    )


def pend_start():
    L, th = PEND["L"], PEND_THETA0
    return (L * math.sin(th), -L * math.cos(th)), (0.0, 0.0)


def pend_options(q0, v0):
    return dict(PEND, q0=q0, v0=v0)


def double_options():
    return dict(DOUBLE, theta0=DOUBLE_THETA0, omega0=DOUBLE_OMEGA0)


def pend_links():
    return [(0, (0.0, 0.0), PEND["L"])]


def double_links():
    return [(0, (0.0, 0.0), DOUBLE["L1"]), (1, 0, DOUBLE["L2"])]


def pend_reference(times):
    return np.array(
        mech.pendulum_exact(PEND_THETA0, times, PEND["L"], PEND["m"], PEND["ga"], DPS), dtype=float
    )


def double_reference(times):
    d = DOUBLE
    return np.array(
        mech.double_pendulum(
            DOUBLE_THETA0, DOUBLE_OMEGA0, times, d["L1"], d["L2"], d["m1"], d["m2"], d["ga"], DPS
        ),
        dtype=float,
    )


# name, program, options, n_q, tf, reference(times), links, masses
def cases():
    q0, v0 = pend_start()
    return [
        (
            "pendulum_mbs from %g rad" % PEND_THETA0,
            "pendulum_mbs",
            pend_options(q0, v0),
            2,
            PEND_TF,
            pend_reference,
            pend_links(),
            [PEND["m"]],
        ),
        (
            "double_pendulum from (%g, %g) rad" % DOUBLE_THETA0,
            "double_pendulum",
            double_options(),
            4,
            DOUBLE_TF,
            double_reference,
            double_links(),
            [DOUBLE["m1"], DOUBLE["m2"]],
        ),
    ]


def run(ctx, program, options, T, tf, every, map_name="dgrad"):
    return runs.run_c(
        ctx.build,
        program,
        dict(options, **P.METHOD, T=T, tf=tf, scheme=15, map=map_name, every=every),
    )


def errors(ctx, case, map_name, ref_cache):
    name, program, options, n_q, tf, reference, _, _ = case
    out, switches = [], 0
    for T in steps(map_name):
        table = run(ctx, program, options, T, tf, int(round(GRID / T)), map_name)
        times = np.arange(0.0, tf + 1e-9, GRID)
        if len(table) != len(times) or not np.allclose(table["t"], times, atol=1e-9):
            raise runs.HarnessError("%s's rows are not at t = %g i" % (program, GRID))
        if name not in ref_cache:
            ref_cache[name] = reference(table["t"])
        out.append(float(np.max(np.abs(columns(table, n_q) - ref_cache[name]))))
        switches = max(switches, int(table["switches"][-1]))
    return np.array(out), switches


def check_orders(ctx, section):
    results, rows, ref_cache = [], [], {}
    for case in cases():
        for map_name, p in THEORY.items():
            runs.log("f: %s, %s" % (case[0], map_name))
            errs, switches = errors(ctx, case, map_name, ref_cache)
            Ts = steps(map_name)
            fit = float(np.polyfit(np.log2(Ts), np.log2(errs), 1)[0])
            local = np.log2(errs[:-1] / errs[1:])
            ok = section.expect(
                abs(fit - p) <= TOL_ORDER,
                "%s, %s: observed order %.3f, theory %d" % (case[0], map_name, fit, p),
            )
            results.append((case[0], map_name, p, Ts, errs, fit))
            rows.append(
                (
                    case[0],
                    map_name,
                    p,
                    "%.3g" % Ts[0],
                    "%.2e" % errs[0],
                    "%.2e" % errs[-1],
                    " ".join("%.2f" % v for v in local),
                    "%.3f" % fit,
                    switches,
                    "pass" if ok else "FAIL",
                )
            )
            section.value("mbs_order_%s_%s" % (case[1], map_name), fit, "%.3f")
    section.table(
        (
            "case",
            "map",
            "theory",
            "largest T",
            "error there",
            "at T / 16",
            "order per halving",
            "fitted order",
            "chart switches",
            "verdict",
        ),
        rows,
    )
    return results


def constraint_abs(links, table, n_q):
    q = columns(table, n_q)[:, :n_q]
    return np.max(np.abs(np.array(mech.constraint(links, q.T))), axis=0)


def energy_scale(case):
    """sum m ga l: the size of the potential energy."""
    _, _, options, _, _, _, links, masses = case
    return sum(masses) * options["ga"] * sum(length for _, _, length in links)


def check_energy_drift(ctx, section):
    tf = 1000.0 if ctx.profile.name == "full" else 100.0
    curves, rows = [], []
    for case in cases():
        name, program, options, n_q, _, _, links, masses = case
        for map_name in ("dgrad", "midpoint"):
            runs.log("f: %s, %s, %d steps" % (name, map_name, runs.nsteps_for(ENERGY_T, tf)))
            table = run(ctx, program, options, ENERGY_T, tf, 10, map_name)
            x = columns(table, n_q)
            E = mech.energy(masses, x[:, :n_q].T, x[:, n_q:].T, options["ga"])
            dE = float(np.max(np.abs(E - E[0]))) / energy_scale(case)
            c = float(np.max(constraint_abs(links, table, n_q)))
            col = float(np.max(table["max_abs_c"]))
            E_col = float(np.max(np.abs(table["E"] - E))) / energy_scale(case)
            checked = map_name == "dgrad"
            ok = section.expect(
                not checked or dE <= ENERGY_TOL,
                "%s, %s: energy changes by %.3g > %g" % (name, map_name, dE, ENERGY_TOL),
            )
            ok &= section.expect(
                max(c, col) <= DRIFT_TOL,
                "%s, %s: max |c| = %.3g (program: %.3g) > %g" % (name, map_name, c, col, DRIFT_TOL),
            )
            ok &= section.expect(
                E_col <= 1e-13,
                "%s, %s: the E column differs from the "
                "energy of q, v by %.3g" % (name, map_name, E_col),
            )
            rows.append(
                (
                    name,
                    map_name,
                    tf,
                    "%.2e" % dE,
                    "%.2e" % c,
                    "%.2e" % col,
                    int(table["switches"][-1]),
                    "pass" if ok else "FAIL",
                )
            )
            curves.append(
                ("%s %s" % (program, map_name), table["t"], np.abs(E - E[0]) / energy_scale(case))
            )
            section.value("mbs_energy_%s_%s" % (program, map_name), dE)
            section.value("mbs_max_c_%s_%s" % (program, map_name), max(c, col))
    section.table(
        (
            "case",
            "map",
            "tf (T = 0.01)",
            "max |E - E0| / (sum m ga l)",
            "max |c| from q",
            "max_abs_c column",
            "chart switches",
            "verdict",
        ),
        rows,
    )
    return curves


def check_off_manifold(ctx, section):
    (q0, v0), tf = PEND_OFF, 10.0
    table = run(ctx, "pendulum_mbs", pend_options(q0, v0), 1e-3, tf, 10)
    c = constraint_abs(pend_links(), table, 2)
    late = float(np.max(c[table["t"] >= OFF_BY - 1e-12]))
    section.expect(
        late < DRIFT_TOL,
        "pendulum_mbs from (%s, %s): |c| = %.3g for t >= %g" % (q0, v0, late, OFF_BY),
    )
    L, m, ga = PEND["L"], PEND["m"], PEND["ga"]
    x = columns(table, 2)
    lam = mech.pendulum_lambda(x.T, L, m, ga)
    dlam = float(np.max(np.abs(table["lambda1"] - lam))) / (m * ga / L)
    section.expect(
        dlam <= LAMBDA_TOL,
        "pendulum_mbs: lambda1 differs from m (|v|^2 - ga y)/|q|^2"
        " by %.3g (relative to m ga / L)" % dlam,
    )
    section.text(
        "From q0 = %s, v0 = %s (off the circle), T = 1e-3: |c| = %.3g at t = 0, max "
        "%.3g for t >= %g (tolerance %g); the lambda column against m (|v|^2 - ga y)"
        "/|q|^2 at the program's states: %.3g relative to m ga / L (tolerance %g)."
        % (q0, v0, c[0], late, OFF_BY, DRIFT_TOL, dlam, LAMBDA_TOL)
    )
    section.value("mbs_offmanifold_max_c_after_t5", late)
    section.value("mbs_lambda_deviation", dlam)
    return table["t"], c


def check(ctx, section):
    section.text(
        __doc__.split(". ", 1)[1]
        + """

Cases: the Cartesian pendulum (L 1, m 1) from rest %g rad from the bottom, tf = %g; the double
pendulum (unit lengths and masses) from rest at angles %s, tf = %g; scheme 15, delta 2, eps 1.
The coarsest step is 1e-2 (dg4: 2^-7, rk4: 2^-6). Energy and drift: T = %g, tf = 100 (full: 1000), the
energy tolerance %g relative to sum m ga l, the constraints' %g; the midpoint map (which
conserves only quadratic invariants) is shown beside dgrad without an energy tolerance."""
        % (PEND_THETA0, PEND_TF, DOUBLE_THETA0, DOUBLE_TF, ENERGY_T, ENERGY_TOL, DRIFT_TOL)
    )
    results = check_orders(ctx, section)
    section.figure(
        plot_orders(ctx.outdir, results),
        "Front-end: error of (q, v) against T "
        "(log-log); dotted lines show the theoretical slope through the coarsest "
        "point.",
    )
    curves = check_energy_drift(ctx, section)
    off = check_off_manifold(ctx, section)
    section.figure(
        plot_energy(ctx.outdir, curves, off),
        "Front-end: left, the energy's change "
        "along the runs of T = 0.01; right, |c| from a start off the circle "
        "(pendulum_mbs, T = 1e-3).",
    )


def plot_orders(outdir, results):
    names = list(dict.fromkeys(r[0] for r in results))
    fig, axes = plots.figure(ncols=len(names), width=5.2, height=4.0)
    plots.orders(axes, results, "max error of (q, v)")
    return plots.save(fig, outdir, "mbs_orders.png")


def plot_energy(outdir, curves, off):
    fig, (ax, bx) = plots.figure(ncols=2, width=5.2, height=4.0)
    for name, t, rel in curves:
        ax.semilogy(t, np.maximum(rel, 1e-18), label=name, ls="-" if "dgrad" in name else "--")
    ax.axhline(ENERGY_TOL, color="k", ls=":", lw=1, label="tolerance for dgrad")
    ax.set_ylim(1e-18, 1)
    ax.set_xlabel("t")
    ax.set_ylabel("|E - E0| / (sum m ga l)")
    ax.legend(loc="center right", fontsize=7)
    t, c = off
    bx.semilogy(t, np.maximum(c, 1e-300), color="tab:blue", label="max_j |c_j|")
    bx.axhline(DRIFT_TOL, color="k", ls=":", lw=1, label="tolerance after t = %g" % OFF_BY)
    bx.axvline(OFF_BY, color="k", ls=":", lw=1)
    bx.set_ylim(1e-18, 1)
    bx.set_xlabel("t")
    bx.set_ylabel("|c|")
    bx.legend(loc="upper right")
    return plots.save(fig, outdir, "mbs_energy.png")
