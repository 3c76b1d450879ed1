# SPDX-License-Identifier: GPL-3.0-or-later
"""The adapters from sympy.physics.mechanics: a LagrangesMethod or a System as a Mechanism.

from_lagranges_method reads the Lagrangian, the generalized coordinates, the holonomic
constraints (hol_coneqs) and the forcelist with the inertial frame. from_system reads the
coordinates (q_ind and q_dep), the bodies' kinetic energies (and potential energies, where a
body has one) in the system's frame, the kinematic differential equations (solved for the
speeds u, which then become functions of q and q'), the holonomic constraints, and the loads
with the actuators' loads. A force's generalized force comes from its point's partial
velocities in q', a torque's from its frame's partial angular velocities.

The coordinates q_i(t) become Symbols of their names and their derivatives Symbols named
`<name>_dot`. The part of the Lagrangian without velocities is -V when it does not depend on t
(so that the discrete gradients apply where nothing else forces the motion); otherwise it stays
in the kinetic part, where the same formula for F holds. Loads (gravity from
System.apply_uniform_gravity among them) are forces Q: give gravity as a potential energy of the
bodies to keep the discrete gradients.

Refused: nonholonomic constraints (the library's constraints are c(t, q) = 0), a forcelist
without a frame, auxiliary speeds, and kinematic differential equations that do not determine
the speeds u as functions of q and q'."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import sympy as sp
from sympy.physics.mechanics import LagrangesMethod, System, dynamicsymbols
from sympy.physics.vector import Point, ReferenceFrame, Vector, partial_velocity

from .errors import ModelError
from .mechanism import Expr, Matrix, Mechanism, Symbol


def _plain(
    coordinates: Iterable[Expr],
) -> tuple[Symbol, list[Symbol], list[Symbol], Callable[[Expr], Expr]]:
    """t, q, v as Symbols and the substitution from the dynamicsymbols to them."""
    t = sp.Symbol("t", real=True)
    qs = list(coordinates)
    q = [sp.Symbol(qi.func.__name__, real=True) for qi in qs]
    v = [sp.Symbol(qi.func.__name__ + "_dot", real=True) for qi in qs]
    derivatives = {qi.diff(dynamicsymbols._t): vi for qi, vi in zip(qs, v)}
    coordinates = dict(zip(qs, q))
    time = {dynamicsymbols._t: t}

    def plain(expr: Expr) -> Expr:
        return sp.sympify(expr).subs(derivatives).subs(coordinates).subs(time)

    return t, q, v, plain


def _generalized_forces(
    loads: Iterable[tuple[Point | ReferenceFrame, Vector]],
    frame: ReferenceFrame,
    qdots: list[Expr],
    plain: Callable[[Expr], Expr],
    speeds: dict[Expr, Expr] | None = None,
) -> Matrix:
    """Q_i = sum over the loads of F . d(vel P)/d(q_i') and T . d(omega)/d(q_i'), the speeds u
    (if any) replaced by their expressions in q' first."""
    Q = sp.zeros(len(qdots), 1)
    for where, vector in loads:
        if isinstance(where, Point):
            motion = where.vel(frame)
        elif isinstance(where, ReferenceFrame):
            motion = where.ang_vel_in(frame)
        else:
            raise ModelError(f"a load on {where!r}, neither a Point nor a ReferenceFrame")
        if speeds:
            motion, vector = motion.subs(speeds), vector.subs(speeds)
        partials = partial_velocity([motion], qdots, frame)[0]
        for i, part in enumerate(partials):
            Q[i] += plain(vector.dot(part))
    return Q


def _split(L: Expr, t: Symbol, v: list[Symbol]) -> tuple[Expr, Expr]:
    """(kinetic, potential): L's part without velocities is -V unless it depends on t."""
    rest = L.xreplace({vi: 0 for vi in v})
    if rest.has(t):
        return L, 0
    return L - rest, -rest


def from_lagranges_method(
    lm: LagrangesMethod,
    name: str,
    params: dict[Symbol, Any] | None = None,
    q0: Expr | None = None,
    v0: Expr | None = None,
    coordinate_names: Iterable[str] | None = None,
) -> Mechanism:
    """A Mechanism from a LagrangesMethod(L, q, hol_coneqs=..., forcelist=..., frame=...)."""
    if not isinstance(lm, LagrangesMethod):
        raise ModelError(f"{type(lm).__name__} is not a sympy.physics.mechanics LagrangesMethod")
    n_hol = len(lm._hol_coneqs)
    if len(lm.coneqs) > n_hol:
        raise ModelError(
            "nonholonomic constraints are refused: the library's constraints "
            "are holonomic, c(t, q) = 0"
        )
    t, q, v, plain = _plain(lm.q)
    kinetic, potential = _split(plain(lm._L[0]), t, v)
    force = None
    if lm._forcelist:
        if lm.inertial is None:
            raise ModelError(
                "the LagrangesMethod has forces but no frame: give frame= (the "
                "inertial frame) so that their generalized forces can be formed"
            )
        force = _generalized_forces(lm._forcelist, lm.inertial, list(lm._qdots), plain)
    return Mechanism(
        name,
        t,
        q,
        v,
        kinetic=kinetic,
        potential=potential,
        force=force,
        constraints=[plain(c) for c in lm._hol_coneqs],
        params=params,
        q0=q0,
        v0=v0,
        coordinate_names=coordinate_names,
    )


def _speeds(system: System, qdots: list[Expr]) -> dict[Expr, Expr]:
    """The speeds u as expressions of q and q', from the kinematic differential equations."""
    u = list(system.u)
    if not u:
        return {}
    try:
        solved: list[dict[Expr, Expr]] = sp.solve(list(system.kdes), u, dict=True)
    except NotImplementedError:
        solved = []
    if len(solved) != 1 or set(solved[0]) != set(u) or any(e.has(*u) for e in solved[0].values()):
        raise ModelError(
            "the kinematic differential equations do not give the speeds u as "
            "functions of q and q' (kdes such as u - q' = 0 are needed)"
        )
    return solved[0]


def from_system(
    system: System,
    name: str,
    params: dict[Symbol, Any] | None = None,
    q0: Expr | None = None,
    v0: Expr | None = None,
    coordinate_names: Iterable[str] | None = None,
) -> Mechanism:
    """A Mechanism from a sympy.physics.mechanics System with holonomic constraints."""
    if not isinstance(system, System):
        raise ModelError(f"{type(system).__name__} is not a sympy.physics.mechanics System")
    if len(system.nonholonomic_constraints):
        raise ModelError(
            "nonholonomic constraints are refused: the library's constraints "
            "are holonomic, c(t, q) = 0"
        )
    if len(system.u_aux):
        raise ModelError("auxiliary speeds are refused: the library's velocities are q'")
    qs = list(system.q)
    qdots = [qi.diff(dynamicsymbols._t) for qi in qs]
    speeds = _speeds(system, qdots)
    t, q, v, plain = _plain(qs)
    frame = system.frame
    L = sum((body.kinetic_energy(frame) for body in system.bodies), sp.S.Zero)
    L -= sum((body.potential_energy for body in system.bodies), sp.S.Zero)
    kinetic, potential = _split(plain(sp.sympify(L).subs(speeds)), t, v)
    loads = [(load.location, load.vector) for load in system.loads]
    loads += [
        (load.location, load.vector)
        for actuator in system.actuators
        for load in actuator.to_loads()
    ]
    force = _generalized_forces(loads, frame, qdots, plain, speeds) if loads else None
    return Mechanism(
        name,
        t,
        q,
        v,
        kinetic=kinetic,
        potential=potential,
        force=force,
        constraints=[plain(c) for c in system.holonomic_constraints],
        params=params,
        q0=q0,
        v0=v0,
        coordinate_names=coordinate_names,
    )
