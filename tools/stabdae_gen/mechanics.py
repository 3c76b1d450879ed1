# SPDX-License-Identifier: GPL-3.0-or-later
"""The adapter from sympy.physics.mechanics: a LagrangesMethod as a Mechanism.

What it reads: the Lagrangian, the generalized coordinates, the holonomic constraints
(hol_coneqs) and the forcelist with the inertial frame (each force's generalized force, from
its point's partial velocities, each torque's from its frame's partial angular velocities).
The coordinates q_i(t) become Symbols of their names and their derivatives Symbols named
`<name>_dot`. The Lagrangian's part without velocities is -V when it does not depend on t (so
the discrete gradients apply where nothing else forces the motion); otherwise it stays in the
kinetic part, where the same formula for F holds.

Refused: nonholonomic constraints (the library's constraints are c(t, q) = 0), and a forcelist
without a frame."""

import sympy as sp
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols
from sympy.physics.vector import Point, ReferenceFrame, partial_velocity

from .errors import ModelError
from .mechanism import Mechanism


def _plain(lm):
    """t, q, v as Symbols and the substitution from the dynamicsymbols to them."""
    t = sp.Symbol("t", real=True)
    qs = list(lm.q)
    q = [sp.Symbol(qi.func.__name__, real=True) for qi in qs]
    v = [sp.Symbol(qi.func.__name__ + "_dot", real=True) for qi in qs]
    derivatives = {qi.diff(dynamicsymbols._t): vi for qi, vi in zip(qs, v)}
    coordinates = dict(zip(qs, q))
    time = {dynamicsymbols._t: t}

    def plain(expr):
        return sp.sympify(expr).subs(derivatives).subs(coordinates).subs(time)
    return t, q, v, plain


def _generalized_forces(lm, plain):
    """Q_i = sum over the forcelist of F . d(vel P)/d(q_i') and T . d(omega)/d(q_i')."""
    n = len(lm.q)
    if not lm._forcelist:
        return None
    if lm.inertial is None:
        raise ModelError("the LagrangesMethod has forces but no frame: give frame= (the "
                         "inertial frame) so that their generalized forces can be formed")
    frame, qdots = lm.inertial, list(lm._qdots)
    Q = sp.zeros(n, 1)
    for where, vector in lm._forcelist:
        if isinstance(where, Point):
            motion = where.vel(frame)
        elif isinstance(where, ReferenceFrame):
            motion = where.ang_vel_in(frame)
        else:
            raise ModelError(f"forcelist: {where!r} is neither a Point nor a ReferenceFrame")
        partials = partial_velocity([motion], qdots, frame)[0]
        for i, part in enumerate(partials):
            Q[i] += plain(vector.dot(part))
    return Q


def from_lagranges_method(lm, name, params=None, q0=None, v0=None, coordinate_names=None):
    """A Mechanism from a LagrangesMethod(L, q, hol_coneqs=..., forcelist=..., frame=...)."""
    if not isinstance(lm, LagrangesMethod):
        raise ModelError(f"{type(lm).__name__} is not a sympy.physics.mechanics "
                         "LagrangesMethod")
    n_hol = len(lm._hol_coneqs)
    if len(lm.coneqs) > n_hol:
        raise ModelError("nonholonomic constraints are refused: the library's constraints "
                         "are holonomic, c(t, q) = 0")
    t, q, v, plain = _plain(lm)
    L = plain(lm._L[0])
    rest = L.xreplace({vi: 0 for vi in v})
    if rest.has(t):
        kinetic, potential = L, 0
    else:
        kinetic, potential = L - rest, -rest
    return Mechanism(name, t, q, v, kinetic=kinetic, potential=potential,
                     force=_generalized_forces(lm, plain),
                     constraints=[plain(c) for c in lm._hol_coneqs], params=params, q0=q0,
                     v0=v0, coordinate_names=coordinate_names)
