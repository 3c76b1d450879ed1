# SPDX-License-Identifier: GPL-3.0-or-later
"""The generator's mathematics against independent references: M and F against sympy's own
Lagrange's equations (sympy.physics.mechanics.LagrangesMethod, which forms d/dt dL/dq' - dL/dq
by differentiating in t), the adapter from LagrangesMethod against the same mechanism described
directly, and the derivatives along the motion against their definition (d/ds at s = 0)."""

import random

import pytest
import sympy as sp
from sympy.physics.mechanics import (
    LagrangesMethod,
    Particle,
    Point,
    ReferenceFrame,
    System,
    dynamicsymbols,
)

from stabdae_gen import Mechanism, ModelError, from_lagranges_method, from_system

RNG = random.Random(7)


def assert_same(a, b, symbols, rel=1e-12):
    """Two lists of expressions equal at random points of the symbols (to rel, relative to
    max(1, |b|))."""
    f = sp.lambdify(symbols, [sp.Matrix(a), sp.Matrix(b)], "mpmath")
    for _ in range(5):
        va, vb = f(*[RNG.uniform(-1.5, 1.5) for _ in symbols])
        for x, y in zip(va, vb):
            x, y = complex(x).real, complex(y).real
            assert abs(x - y) <= rel * max(1.0, abs(y)), (x, y)


def with_dummy_constraint(t, q, v, kinetic, potential=0, **kw):
    """The Mechanism of T and V on q plus a coordinate z held at 0: the first n rows of its M
    and F are those of T and V alone (z enters neither)."""
    z, vz = sp.symbols("z vz")
    return Mechanism(
        "m",
        t,
        list(q) + [z],
        list(v) + [vz],
        kinetic=kinetic + vz**2 / 2,
        potential=potential,
        constraints=[z],
        **kw,
    )


def lagranges_reference(L, qs):
    """sympy's M q'' = forcing for the Lagrangian L(q(t), q'(t), t), in plain Symbols."""
    lm = LagrangesMethod(L, qs)
    lm.form_lagranges_equations()
    t = dynamicsymbols._t
    return lm.mass_matrix, lm.forcing, t


def test_force_matches_lagranges_equations():
    """A double pendulum in angles (T couples the velocities through cos(a1 - a2)) with a
    time-dependent stiffness and a term of T linear in v whose coefficient depends on t and q:
    every term of F = dT/dq - dV/dq - (d2T/dv dq) v - d2T/dv dt appears."""
    a1, a2 = dynamicsymbols("a1 a2")
    t = dynamicsymbols._t
    da1, da2 = a1.diff(t), a2.diff(t)
    m1, m2, l1, l2, g = 1.3, 0.7, 1.1, 0.9, 9.81
    T = (
        (m1 + m2) * l1**2 * da1**2 / 2
        + m2 * l2**2 * da2**2 / 2
        + m2 * l1 * l2 * da1 * da2 * sp.cos(a1 - a2)
        + sp.sin(t) * a2 * da1
    )
    V = (
        -(m1 + m2) * g * l1 * sp.cos(a1)
        - m2 * g * l2 * sp.cos(a2)
        + (1 + sp.cos(t) ** 2) * a1**2 / 2
    )
    M_ref, F_ref, _ = lagranges_reference(T - V, [a1, a2])

    ts = sp.Symbol("t")
    q = sp.symbols("a1 a2")
    v = sp.symbols("w1 w2")
    plain = {da1: v[0], da2: v[1]}
    plain2 = {a1: q[0], a2: q[1], t: ts}
    to_plain = lambda e: e.subs(plain).subs(plain2)  # noqa: E731
    # V depends on t here, so it is the kinetic part's (the description refuses V(t))
    mech = with_dummy_constraint(ts, q, v, kinetic=to_plain(T - V))
    F = mech.force()
    symbols = [ts, *q, *v]
    assert_same(
        [mech.M[i, j] for i in range(2) for j in range(2)],
        [to_plain(M_ref[i, j]) for i in range(2) for j in range(2)],
        symbols,
    )
    assert_same([F[0], F[1]], [to_plain(F_ref[0]), to_plain(F_ref[1])], symbols)


def test_potential_and_damping_enter_the_force():
    """F = -dV/dq - D v for T = |v|^2 / 2: a spring V = k x^2 / 2 and D = c I."""
    t, x, y, z, vx, vy, vz = sp.symbols("t x y z vx vy vz", real=True)
    mech = Mechanism(
        "s",
        t,
        [x, y, z],
        [vx, vy, vz],
        kinetic=(vx**2 + vy**2 + vz**2) / 2,
        potential=3 * x**2 / 2,
        damping=sp.eye(3) / 4,
        constraints=[z],
    )
    assert sp.simplify(mech.force() - sp.Matrix([-3 * x - vx / 4, -vy / 4, -vz / 4])) == sp.zeros(
        3, 1
    )
    assert "potential" in mech.callbacks() and "damping" in mech.callbacks()


def test_derivatives_along_the_motion():
    """mass_dot_v, jacobian_dot and constraint_t_dot against d/ds at s = 0 of M(t + s, q + s v) v,
    G(t + s, q + s v) and dc/dt(t + s, q + s v), formed by substitution."""
    t, s, x, y, vx, vy = sp.symbols("t s x y vx vy", real=True)
    mech = Mechanism(
        "d",
        t,
        [x, y],
        [vx, vy],
        mass=sp.Matrix([[2 + sp.sin(x * t), x * y], [x * y, 3 + y**2]]),
        constraints=[x**2 * sp.cos(t) + y - sp.sin(2 * t) - 1],
        q0=[0, 1 + 0],
        v0=[0, 2],
    )
    moved = {t: t + s, x: x + s * vx, y: y + s * vy}
    vv = sp.Matrix([vx, vy])
    cb = mech.callbacks()
    symbols = [t, x, y, vx, vy]

    def along(expr):
        return (expr.xreplace(moved)).diff(s).subs(s, 0)

    assert_same(list(cb["mass_dot_v"][2]), list(along(mech.M) * vv), symbols)
    G = mech.c.jacobian([x, y])
    assert_same(list(cb["jacobian_dot"][2]), list(along(G)), symbols)
    assert_same(list(cb["constraint_t_dot"][2]), list(along(mech.c.diff(t))), symbols)


PENDULUM_PARAMS = sp.symbols("m L g c")


def cartesian_pendulum_lm(with_frame=True, nonholonomic=False):
    """The pendulum as a LagrangesMethod: a bob at (x, y), gravity in the Lagrangian, a viscous
    force -c v on it."""
    x, y = dynamicsymbols("x y")
    t = dynamicsymbols._t
    m, L, g, c = PENDULUM_PARAMS
    N = ReferenceFrame("N")
    P = Point("P")
    P.set_vel(N, x.diff(t) * N.x + y.diff(t) * N.y)
    Lag = m * (x.diff(t) ** 2 + y.diff(t) ** 2) / 2 - m * g * y
    forces = [(P, -c * (x.diff(t) * N.x + y.diff(t) * N.y))]
    kw = dict(hol_coneqs=[(x**2 + y**2 - L**2) / 2], forcelist=forces)
    if with_frame:
        kw["frame"] = N
    if nonholonomic:
        kw["nonhol_coneqs"] = [x.diff(t) - y.diff(t)]
    return LagrangesMethod(Lag, [x, y], **kw), PENDULUM_PARAMS


def direct_pendulum(adapted, params, start, potential=True):
    """The Cartesian pendulum with a viscous force -c v on its bob, described directly in the
    adapted mechanism's symbols; gravity as a potential, or as a force."""
    m, L, g, c = PENDULUM_PARAMS
    t, (x, y), (vx, vy) = adapted.t, adapted.q, adapted.v
    if potential:
        forces = dict(potential=m * g * y, force=[-c * vx, -c * vy])
    else:
        forces = dict(force=[-c * vx, -c * vy - m * g])
    return Mechanism(
        "pendulum",
        t,
        [x, y],
        [vx, vy],
        kinetic=m * (vx**2 + vy**2) / 2,
        constraints=[(x**2 + y**2 - L**2) / 2],
        params=params,
        **forces,
        **start,
    )


def assert_same_callbacks(a, b):
    symbols = [a.t, *a.q, *a.v, *PENDULUM_PARAMS]
    ca, cb = a.callbacks(), b.callbacks()
    assert sorted(ca) == sorted(cb)
    for field in ca:
        assert_same(list(ca[field][2]), list(cb[field][2]), symbols)


def pendulum_system(speed_scale=1, gravity_load=False, nonholonomic=False):
    """The pendulum as a System: a Particle at (x, y) with speeds u = speed_scale q'."""
    m, L, g, c = PENDULUM_PARAMS
    x, y = dynamicsymbols("x y")
    ux, uy = dynamicsymbols("ux uy")
    N = ReferenceFrame("N")
    O = Point("O")
    P = Particle("P", Point("Pm"), m)
    s = System(N, O)
    s.q_ind = [x, y]
    s.u_ind = [ux, uy]
    s.kdes = [ux - speed_scale * x.diff(), uy - speed_scale * y.diff()]
    P.masscenter.set_pos(O, x * N.x + y * N.y)
    P.masscenter.set_vel(N, (ux * N.x + uy * N.y) / speed_scale)
    s.add_bodies(P)
    s.add_holonomic_constraints((x**2 + y**2 - L**2) / 2)
    s.add_loads((P.masscenter, -c * P.masscenter.vel(N)))
    if gravity_load:
        s.apply_uniform_gravity(-g * N.y)
    else:
        P.potential_energy = m * g * y
    if nonholonomic:
        s.add_nonholonomic_constraints(ux - uy)
    return s


@pytest.mark.parametrize("speed_scale", [1, 2], ids=["u_is_qdot", "u_is_2qdot"])
def test_system_adapter_equals_the_direct_description(speed_scale):
    """The pendulum as a System (speeds u = q' or u = 2 q': the kinematic equations solved for
    u), against the direct description."""
    m, L, g, c = PENDULUM_PARAMS
    params = {m: 1.5, L: 2.0, g: 9.81, c: 0.3}
    start = dict(q0=[L * sp.sin(0.4), -L * sp.cos(0.4)], v0=[0, 0])
    adapted = from_system(pendulum_system(speed_scale), "pendulum", params=params, **start)
    assert_same_callbacks(adapted, direct_pendulum(adapted, params, start))
    # the viscous load is a force Q from outside the Lagrangian, gravity its potential
    assert "potential" in adapted.callbacks() and "input_force" in adapted.callbacks()


def test_system_gravity_load_is_a_force():
    m, L, g, c = PENDULUM_PARAMS
    params = {m: 1.5, L: 2.0, g: 9.81, c: 0.3}
    start = dict(q0=[L * sp.sin(0.4), -L * sp.cos(0.4)], v0=[0, 0])
    adapted = from_system(pendulum_system(gravity_load=True), "pendulum", params=params, **start)
    assert_same_callbacks(adapted, direct_pendulum(adapted, params, start, potential=False))


def test_system_refusals():
    m, L, g, c = PENDULUM_PARAMS
    with pytest.raises(ModelError, match="nonholonomic"):
        from_system(
            pendulum_system(nonholonomic=True), "p", params={m: 1, L: 1, g: 1, c: 1}, q0=[0, -L]
        )
    with pytest.raises(ModelError, match="not a sympy.physics.mechanics System"):
        from_system(object(), "p")


def test_adapter_equals_the_direct_description():
    """The pendulum through LagrangesMethod (the force's generalized force from the point's
    partial velocities is -c v) against the direct description."""
    lm, (m, L, g, c) = cartesian_pendulum_lm()
    params = {m: 1.5, L: 2.0, g: 9.81, c: 0.3}
    start = dict(q0=[L * sp.sin(0.4), -L * sp.cos(0.4)], v0=[0, 0])
    adapted = from_lagranges_method(lm, "pendulum", params=params, **start)
    assert_same_callbacks(adapted, direct_pendulum(adapted, params, start))


def test_adapter_refusals():
    lm, (m, L, g, c) = cartesian_pendulum_lm(nonholonomic=True)
    with pytest.raises(ModelError, match="nonholonomic"):
        from_lagranges_method(lm, "p", params={m: 1, L: 1, g: 1, c: 1}, q0=[0, -L])
    lm, (m, L, g, c) = cartesian_pendulum_lm(with_frame=False)
    with pytest.raises(ModelError, match="no frame"):
        from_lagranges_method(lm, "p", params={m: 1, L: 1, g: 1, c: 1}, q0=[0, -L])
    with pytest.raises(ModelError, match="not a sympy.physics.mechanics LagrangesMethod"):
        from_lagranges_method(object(), "p")
