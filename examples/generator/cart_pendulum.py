# SPDX-License-Identifier: GPL-3.0-or-later
"""A cart on a horizontal rail, tied to a wall by a spring, carrying a pendulum.

The cart (mass m1) is held at the rail's height y = 0 and pulled back to x = 0 by a spring of
stiffness k; the bob (mass m2) hangs from the cart on a massless rod of length L; gravity g
acts along -y. Both bodies are points in the plane, each with its two Cartesian coordinates:

    q = (x, y, px, py)      the cart at (x, y), the bob at (px, py)

Two degrees of freedom out of four coordinates, hence two constraints: the rail, y = 0, and
the rod, written as half the squared distance so that it stays a polynomial (its gradient is
the rod's direction times L, no square root, and it is valid at every angle):

    c1 = y,    c2 = ((px - x)^2 + (py - y)^2 - L^2) / 2

The mass matrix is constant and every force has a potential, so the generator declares the
potential to the library and the discrete-gradient maps conserve the energy.
"""

import sympy as sp

from stabdae_gen import Mechanism


def mechanism():
    t = sp.Symbol("t")
    x, y, px, py = q = sp.symbols("x y px py")
    v = sp.symbols("vx vy vpx vpy")
    vx, vy, vpx, vpy = v
    m1, m2, k, L, g = sp.symbols("m1 m2 k L g")
    x0, theta0, omega0 = sp.symbols("x0 theta0 omega0")

    kinetic = m1 * (vx**2 + vy**2) / 2 + m2 * (vpx**2 + vpy**2) / 2
    potential = k * x**2 / 2 + g * (m1 * y + m2 * py)
    constraints = [y, ((px - x)**2 + (py - y)**2 - L**2) / 2]

    # the start: the cart at rest at x0, the rod at theta0 from the downward vertical turning at
    # omega0; the bob's velocity is the rod's rotation, perpendicular to the rod, so both
    # constraints hold at position and velocity level for any values of the parameters
    bob = [x0 + L * sp.sin(theta0), -L * sp.cos(theta0)]
    bob_velocity = [L * omega0 * sp.cos(theta0), L * omega0 * sp.sin(theta0)]

    return Mechanism(
        "cart_pendulum", t, q, v,
        kinetic=kinetic,
        potential=potential,
        constraints=constraints,
        params={m1: (1.0, "cart mass"),
                m2: (0.5, "bob mass"),
                k: (10.0, "spring stiffness"),
                L: (1.0, "rod length"),
                g: (9.81, "gravitational acceleration"),
                x0: (0.2, "start position of the cart"),
                theta0: (1.0, "start angle of the rod from the downward vertical"),
                omega0: (2.0, "start angular velocity of the rod")},
        units={m1: "kg", m2: "kg", k: "N/m", L: "m", g: "m/s^2", x0: "m", theta0: "rad",
               omega0: "rad/s"},
        q0=[x0, 0, bob[0], bob[1]],
        v0=[0, 0, bob_velocity[0], bob_velocity[1]],
        coordinate_names=["x", "y", "px", "py"],
        coordinate_units=["m", "m", "m", "m"])
