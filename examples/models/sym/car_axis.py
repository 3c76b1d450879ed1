# SPDX-License-Identifier: GPL-3.0-or-later
"""The car axis of examples/models/benchmarks.h in sympy (Test Set for IVP Solvers, Bari, problem
caraxis; Hairer and Wanner, Solving ODEs II, Section VII.7, after Rentrop): q = (xl, yl, xr, yr),
the axis' two ends, each on a spring of rest length L0, the left one to the origin and the right
one to the wheel (xb, yb) = (sqrt(L^2 - yb^2), r sin(w t)) rolling over a bump; M = k I with
k = mass eps^2 / 2; c = (xb xl + yb yl, (xl - xr)^2 + (yl - yr)^2 - L^2). The springs' energy
would depend on t through the wheel, so the forces are given as such (no potential: the
discrete-gradient maps do not apply):
F = (L0 - Ll) (xl, yl)/Ll - (0, k g) and (L0 - Lr) (xr - xb, yr - yb)/Lr - (0, k g).
The constants and the start are the Test Set's, the start's velocities written as
xl' = xr' = -r w L0 / L so that it is consistent for any road (bench_car_axis_initial)."""

import sympy as sp

from stabdae_gen import Mechanism


def mechanism():
    t = sp.Symbol("t")
    xl, yl, xr, yr = q = sp.symbols("xl yl xr yr")
    v = sp.symbols("vxl vyl vxr vyr")
    eps, mass, L, L0, r, w, g = sp.symbols("eps mass L L0 r w g")

    k = mass * eps**2 / 2
    yb = r * sp.sin(w * t)
    xb = sp.sqrt(L**2 - yb**2)
    Ll = sp.sqrt(xl**2 + yl**2)
    Lr = sp.sqrt((xr - xb)**2 + (yr - yb)**2)
    vx0 = -r * w * L0 / L

    return Mechanism(
        "car_axis", t, q, v,
        mass=k * sp.eye(4),
        force=[(L0 - Ll) * xl / Ll, (L0 - Ll) * yl / Ll - k * g,
               (L0 - Lr) * (xr - xb) / Lr, (L0 - Lr) * (yr - yb) / Lr - k * g],
        constraints=[xb * xl + yb * yl, (xl - xr)**2 + (yl - yr)**2 - L**2],
        params={eps: (1e-2, "the mass' scale: k = mass eps^2 / 2"), mass: (10.0, "mass"),
                L: (1.0, "the axis' length"), L0: (0.5, "the springs' rest length"),
                r: (0.1, "the bump's height"), w: (10.0, "the road's angular frequency"),
                g: (1.0, "gravitational acceleration")},
        # the Test Set's springs have the stiffness 1 N/m, written nowhere
        units={eps: "1", mass: "kg", L: "m", L0: "m", r: "m", w: "rad/s", g: "m/s^2"},
        coordinate_units=["m"] * 4,
        q0=[0, L0, L, L0], v0=[vx0, 0, vx0, 0])
