# SPDX-License-Identifier: GPL-3.0-or-later
"""Andrews' squeezing mechanism of examples/models/benchmarks.h in sympy (Test Set for IVP
Solvers, Bari, problem andrews; Hairer and Wanner, Solving ODEs II, Section VII.7): seven rigid
bodies, q their angles (beta, theta, gamma, phi, delta, omega, epsilon), six constraints closing
three loops from the joint of bodies 1 and 2 (to B over body 3, to A over bodies 4-5 and over
bodies 6-7), the Test Set's mass matrix M(q), the driving torque mom on beta and a spring c0 of
rest length l0 between the fixed point C and the point D of body 3:
V = -mom beta + c0 (|D - C| - l0)^2 / 2. The forces are the Lagrangian's, which is the Test
Set's f. Its 42 constants in its order, and its consistent start at rest
(bench_andrews_initial)."""

import sympy as sp

from stabdae_gen import Mechanism

# the Test Set's constants, in its order (bench_andrews_default)
CONSTANTS = [
    ("m1", 0.04325), ("m2", 0.00365), ("m3", 0.02373), ("m4", 0.00706), ("m5", 0.07050),
    ("m6", 0.00706), ("m7", 0.05498), ("xa", -0.06934), ("ya", -0.00227), ("xb", -0.03635),
    ("yb", 0.03273), ("xc", 0.014), ("yc", 0.072), ("c0", 4530.0), ("i1", 2.194e-6),
    ("i2", 4.410e-7), ("i3", 5.255e-6), ("i4", 5.667e-7), ("i5", 1.169e-5), ("i6", 5.667e-7),
    ("i7", 1.912e-5), ("d", 28e-3), ("da", 115e-4), ("e", 2e-2), ("ea", 1421e-5),
    ("rr", 7e-3), ("ra", 92e-5), ("l0", 7785e-5), ("ss", 35e-3), ("sa", 1874e-5),
    ("sb", 1043e-5), ("sc", 18e-3), ("sd", 2e-2), ("ta", 2308e-5), ("tb", 916e-5),
    ("u", 4e-2), ("ua", 1228e-5), ("ub", 449e-5), ("zf", 2e-2), ("zt", 4e-2), ("fa", 1421e-5),
    ("mom", 33e-3)]

# the constants' SI units (the Test Set's: kg, m, N): masses, moments of inertia, the spring's
# stiffness, the driving torque; every other constant is a length
UNITS = {**{f"m{i}": "kg" for i in range(1, 8)}, **{f"i{i}": "kg.m^2" for i in range(1, 8)},
         "c0": "N/m", "mom": "N.m"}

# the Test Set's consistent position (its init; Hairer and Wanner II, VII.7)
START = ["-0.0617138900142764496358948458001", "0",
         "0.455279819163070380255912382449", "0.222668390165885884674473185609",
         "0.487364979543842550225598953530", "-0.222668390165885884674473185609",
         "1.23054744454982119249735015568"]


def mechanism():
    t = sp.Symbol("t")
    beta, theta, gamma, phi, delta, omega, epsilon = q = sp.symbols(
        "beta theta gamma phi delta omega epsilon")
    v = sp.symbols("vbeta vtheta vgamma vphi vdelta vomega vepsilon")
    P = {name: sp.Symbol(name) for name, _ in CONSTANTS}
    (m1, m2, m3, m4, m5, m6, m7, xa, ya, xb, yb, xc, yc, c0, i1, i2, i3, i4, i5, i6, i7, d, da,
     e, ea, rr, ra, l0, ss, sa, sb, sc, sd, ta, tb, u, ua, ub, zf, zt, fa, mom) = P.values()

    M = sp.zeros(7, 7)
    e4, f6 = e - ea, zf - fa
    M[0, 0] = (m1 * ra**2 + m2 * (rr**2 - 2 * da * rr * sp.cos(theta) + da**2) + i1 + i2)
    M[0, 1] = M[1, 0] = m2 * (da**2 - da * rr * sp.cos(theta)) + i2
    M[1, 1] = m2 * da**2 + i2
    M[2, 2] = m3 * (sa**2 + sb**2) + i3
    M[3, 3] = m4 * e4**2 + i4
    M[3, 4] = M[4, 3] = m4 * (e4**2 + zt * e4 * sp.sin(phi)) + i4
    M[4, 4] = (m4 * (zt**2 + 2 * zt * e4 * sp.sin(phi) + e4**2) + m5 * (ta**2 + tb**2) + i4
               + i5)
    M[5, 5] = m6 * f6**2 + i6
    M[5, 6] = M[6, 5] = m6 * (f6**2 - u * f6 * sp.sin(omega)) + i6
    M[6, 6] = (m6 * (f6**2 - 2 * u * f6 * sp.sin(omega) + u**2) + m7 * (ua**2 + ub**2) + i6
               + i7)

    # the spring from C to D, D on body 3
    Dx = sd * sp.cos(gamma) + sc * sp.sin(gamma) + xb
    Dy = sd * sp.sin(gamma) - sc * sp.cos(gamma) + yb
    length = sp.sqrt((Dx - xc)**2 + (Dy - yc)**2)

    # the joint of bodies 1 and 2, where the three loops start
    bx = rr * sp.cos(beta) - d * sp.cos(beta + theta)
    by = rr * sp.sin(beta) - d * sp.sin(beta + theta)

    return Mechanism(
        "andrews", t, q, v,
        mass=M,
        potential=-mom * beta + c0 * (length - l0)**2 / 2,
        constraints=[bx - ss * sp.sin(gamma) - xb,
                     by + ss * sp.cos(gamma) - yb,
                     bx - e * sp.sin(phi + delta) - zt * sp.cos(delta) - xa,
                     by + e * sp.cos(phi + delta) - zt * sp.sin(delta) - ya,
                     bx - zf * sp.cos(omega + epsilon) - u * sp.sin(epsilon) - xa,
                     by - zf * sp.sin(omega + epsilon) + u * sp.cos(epsilon) - ya],
        params={P[name]: value for name, value in CONSTANTS},
        units={P[name]: UNITS.get(name, "m") for name, _ in CONSTANTS},
        coordinate_units=["rad"] * 7,
        q0=[sp.Float(x, 30) for x in START], v0=[0] * 7)
