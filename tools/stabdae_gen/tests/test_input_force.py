# SPDX-License-Identifier: GPL-3.0-or-later
"""Forces from outside the Lagrangian: a description with force= and a potential writes the
Lagrangian's forces into `force` and the force= terms into `input_force`, and declares the
potential and damping. The generated C of models/cone.py evaluated at random points against
sympy's LagrangesMethod given the same loads as vectors (their generalized forces formed by
sympy from the point's partial velocities): force against the Lagrangian's equations with the
damper alone, input_force against the model's own Q and against the difference, and
force + input_force against the full equations. Then the cases that keep every force in F."""

import os
import random

import pytest
import sympy as sp
from sympy.physics.mechanics import LagrangesMethod, Point, ReferenceFrame, dynamicsymbols

from conftest import HERE, evaluator, needs_build

from stabdae_gen import Mechanism
from stabdae_gen.cli import load

CONE = os.path.join(HERE, "models", "cone.py")


def cone_reference(mech):
    """sympy's M and forcing for the cone's particle without constraint, in mech's symbols:
    (M, forcing with the damper, forcing with the damper and the loads)."""
    r, theta, z = dynamicsymbols("r theta z")
    t = dynamicsymbols._t
    P = {s.name: s for s in mech.params}
    m, k, r0, g, c, b, u = (P[n] for n in "m k r0 g c b u".split())
    N = ReferenceFrame("N")
    O, A = Point("O"), Point("A")
    O.set_vel(N, 0)
    A.set_pos(O, r * sp.cos(theta) * N.x + r * sp.sin(theta) * N.y + z * N.z)
    w = A.vel(N)
    e_theta = -sp.sin(theta) * N.x + sp.cos(theta) * N.y
    lagrangian = m * w.dot(w) / 2 - k * (r - r0) ** 2 / 2 - m * g * z
    damper = -c * w
    loads = u * sp.sin(t) * e_theta - b * sp.sqrt(w.dot(w)) * w
    plain = {r.diff(t): mech.v[0], theta.diff(t): mech.v[1], z.diff(t): mech.v[2]}
    plain2 = {r: mech.q[0], theta: mech.q[1], z: mech.q[2], t: mech.t}

    def to_plain(e):
        return e.subs(plain).subs(plain2)

    out = []
    for force in (damper, damper + loads):
        lm = LagrangesMethod(lagrangian, [r, theta, z], forcelist=[(A, force)], frame=N)
        lm.form_lagranges_equations()
        out.append((lm.mass_matrix.applyfunc(to_plain), lm.forcing.applyfunc(to_plain)))
    return out[0][0], out[0][1], out[1][1]


@needs_build
def test_cone_callbacks_against_lagranges_method(generated, tmp_path):
    d, name, _ = generated[CONE]
    mech = load(CONE)
    M_ref, F_lagrangian, F_full = cone_reference(mech)
    symbols = [mech.t, *mech.q, *mech.v]
    defaults = {s: float(v) for s, v in mech.defaults.items()}
    reference = {
        "mass": list(M_ref),
        "force": list(F_lagrangian),
        "input_force": list(mech.Q),
        "input_force_difference": list(F_full - F_lagrangian),
        "sum": list(F_full),
        "potential": [mech.V],
        "damping": list(mech.D),
    }
    functions = {
        key: sp.lambdify(symbols, [e.xreplace(defaults) for e in exprs], "math")
        for key, exprs in reference.items()
    }
    rng = random.Random(11)
    points = [
        [
            rng.uniform(0, 2),
            rng.uniform(0.5, 2),
            rng.uniform(-3, 3),
            rng.uniform(-1, 1),
            rng.uniform(-2, 2),
            rng.uniform(-2, 2),
            rng.uniform(-2, 2),
        ]
        for _ in range(5)
    ]
    evaluate = evaluator(d, name, tmp_path)

    def close(got, want, what):
        assert len(got) == len(want), what
        for a, b in zip(got, want):
            assert abs(a - b) <= 1e-12 * max(1.0, abs(b)), (what, got, want)

    for point, got in zip(points, evaluate(points)):
        want = {key: f(*point) for key, f in functions.items()}
        close(got["mass"], want["mass"], "mass")
        close(got["force"], want["force"], "force: the Lagrangian's with the damper")
        close(got["input_force"], want["input_force"], "input_force: the model's Q")
        close(
            got["input_force"],
            want["input_force_difference"],
            "input_force: the loads' generalized forces",
        )
        close(
            [a + b for a, b in zip(got["force"], got["input_force"])],
            want["sum"],
            "force + input_force: the full equations",
        )
        close(got["potential"], want["potential"], "potential")
        close(got["damping"], want["damping"], "damping")
    source = (d / "cone.c").read_text()
    assert ".input_force = cone_input_force," in source
    assert ".potential = cone_potential," in source and ".damping = cone_damping," in source


T, X, Z, VX, VZ = sp.symbols("t x z vx vz", real=True)
BASE = dict(kinetic=(VX**2 + VZ**2) / 2, potential=X**2 / 2, constraints=[Z])


def test_no_force_no_input_force():
    cb = Mechanism("a", T, [X, Z], [VX, VZ], **BASE).callbacks()
    assert "potential" in cb and "input_force" not in cb


def test_force_with_a_potential_is_an_input():
    mech = Mechanism("b", T, [X, Z], [VX, VZ], force=[sp.cos(T), 0], **BASE)
    cb = mech.callbacks()
    assert "potential" in cb
    assert list(cb["force"][2]) == [-X, 0]
    assert list(cb["input_force"][2]) == [sp.cos(T), 0]


@pytest.mark.parametrize("change", ["kinetic", "potential"])
def test_forces_kept_in_F(change):
    """T depending on t (its energy is not the one the discrete gradients keep), or force=
    without a potential or damping (nothing to declare): every force in F, no input_force, no
    potential."""
    args = dict(BASE)
    if change == "kinetic":
        args["kinetic"] = (1 + T**2) * (VX**2 + VZ**2) / 2
    else:
        args["potential"] = 0
    mech = Mechanism("c", T, [X, Z], [VX, VZ], force=[sp.cos(T), 0], **args)
    cb = mech.callbacks()
    assert "input_force" not in cb and "potential" not in cb
    F = cb["force"][2]
    assert sp.simplify(F[0] - (mech.lagrangian_force()[0] + sp.cos(T))) == 0
    assert F[0].has(sp.cos(T))
