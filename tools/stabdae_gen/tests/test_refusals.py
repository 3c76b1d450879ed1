# SPDX-License-Identifier: GPL-3.0-or-later
"""Every description the generator must refuse: one line naming the problem on stderr, exit
status 2, and nothing written or changed in the output directory (which holds an older
generation that must survive byte for byte)."""

import math
import os
import re
import signal
import subprocess
import sys
import time

import pytest
import sympy as sp

from conftest import PENDULUM, TOOLS, run_mbsgen

from stabdae_gen import Mechanism, ModelError

# (test id, the change to PENDULUM's mechanism, words the one line must contain)
CASES = [
    ("kinetic_quartic", "args['kinetic'] = m * (vx**4 + vy**2) / 2", "not quadratic in v"),
    ("kinetic_transcendental", "args['kinetic'] = m * sp.cos(vx) + vy**2", "not quadratic in v"),
    (
        "mass_not_positive",
        "args['kinetic'] = m * (vx**2 - vy**2) / 2",
        "not positive definite at the start",
    ),
    ("mass_negative_param", "args['params'][m] = -1.0", "not positive definite at the start"),
    ("constraint_without_q", "args['constraints'] = [L - 2]", "does not depend on q"),
    ("potential_with_v", "args['potential'] = m * g * y + vx", "potential depends on v"),
    ("potential_with_t", "args['potential'] = m * g * y * sp.cos(t)", "potential depends on t"),
    ("sizes_q_v", "v = [vx]", "q has 2 coordinates but v has 1"),
    ("sizes_force", "args['force'] = [0, 0, 1]", "force has 3 entries"),
    ("sizes_q0", "args['q0'] = [1.0]", "q0 has 1 entries"),
    ("sizes_v0", "args['v0'] = [0, 0, 0]", "v0 has 3 entries"),
    (
        "free_symbol",
        "args['potential'] = m * g * y + sp.Symbol('k') * x**2",
        "k in the potential has no value in params",
    ),
    ("free_symbol_start", "args['q0'] = [sp.Symbol('a'), -L]", "q0 depends on a"),
    ("name_not_identifier", "name = '2pendulum'", "is not a C identifier"),
    ("name_with_dash", "name = 'my-pendulum'", "is not a C identifier"),
    ("name_keyword", "name = 'double'", "is a C keyword"),
    ("name_standard_header", "name = 'math'", "hides the C standard header <math.h>"),
    ("param_is_coordinate", "args['params'][x] = 0.0", "x is also t, a coordinate or a velocity"),
    (
        "param_keyword",
        "args['params'] = {m: 1.0, L: 2.0, sp.Symbol('int'): 1.0}",
        "'int' is a C keyword",
    ),
    (
        "unprintable_function",
        "args['potential'] = m * g * y + sp.besselj(0, x)",
        "cannot print in C",
    ),
    (
        "undefined_function",
        "args['potential'] = m * g * y + sp.Function('f')(x)",
        "cannot print it in C",
    ),
    (
        "start_off_constraint",
        "args['q0'] = [L * sp.sin(0.3), -L * sp.cos(0.3) + 1e-6]",
        "violates the constraints",
    ),
    ("start_off_velocity", "args['v0'] = [1, 1]", "violates the constraints: G v + dc/dt"),
    ("no_constraints", "args['constraints'] = []", "needs 1 <= n_c < n_q"),
    ("both_energies", "args['mass'] = sp.eye(2)", "exactly one of kinetic"),
    ("damping_with_v", "args['damping'] = sp.eye(2) * vx", "damping depends on v"),
    ("param_not_number", "args['params'][m] = 'heavy'", "not a finite real number"),
    ("param_macro", "args['params'][sp.Symbol('NAN')] = 1.0", "'NAN' is reserved"),
    ("name_library_prefix", "name = 'sdae'", "'sdae' is reserved"),
    ("description_two_lines", "args['params'][m] = (1.0, 'mass\\nin kg')", "one line"),
    (
        "piecewise_without_default",
        "args['potential'] = sp.Piecewise((m * g * y, y < 0))",
        "cannot be printed in C",
    ),
    ("potential_list", "args['potential'] = [m * g * y]", "potential must be one expression"),
    ("start_nan", "args['q0'] = [sp.nan, -L]", "not finite real numbers"),
    ("start_undefined_function", "args['q0'] = [sp.Function('f')(L), -L]", "start state calls f"),
    (
        "redundant_constraints",
        "z, vz = sp.symbols('z vz'); q = (x, y, z); v = (vx, vy, vz); "
        "args['constraints'] = [(x**2 + y**2 - L**2) / 2, x**2 + y**2 - L**2]; "
        "args['kinetic'] += vz**2; args['q0'].append(0); args['v0'].append(0)",
        "redundant at the start state",
    ),
    (
        "damping_not_symmetric",
        "args['damping'] = sp.Matrix([[1, x], [0, 1]])",
        "damping is not symmetric",
    ),
    # one of each kind below through the command
    (
        "param_double_underscore",
        "args['params'][sp.Symbol('__LINE__')] = 1.0",
        "'__LINE__' is reserved in C",
    ),
    ("param_linux", "args['params'][sp.Symbol('linux')] = 1.0", "'linux' is a macro GCC"),
    ("param_cxx_new", "args['params'][sp.Symbol('new')] = 1.0", "'new' is a C++ keyword"),
    ("unit_with_space", "args['units'] = {m: 'kilo gram'}", "'kilo gram' is not a unit"),
]


# more of the kinds above in the generator's own process (each kind is once in CASES, through
# the command, which says it in one line with exit status 2)
IN_PROCESS = [
    # names that are C identifiers but do not compile as a field (or are not the user's to take)
    (
        "param_underscore_capital",
        "args['params'][sp.Symbol('_Pend')] = 1.0",
        "'_Pend' is reserved in C",
    ),
    ("name_underscore_capital", "name = '_Pend'", "'_Pend' is reserved in C"),
    ("param_unix", "args['params'][sp.Symbol('unix')] = 1.0", "'unix' is a macro GCC"),
    ("param_i386", "args['params'][sp.Symbol('i386')] = 1.0", "'i386' is a macro GCC"),
    ("param_cxx_class", "args['params'][sp.Symbol('class')] = 1.0", "'class' is a C++ keyword"),
    ("param_bool", "args['params'][sp.Symbol('bool')] = 1.0", "'bool' is a C keyword"),
    (
        "param_header_macro",
        "args['params'][sp.Symbol('PENDULUM_N_Q')] = 1.0",
        "the prefix PENDULUM_ of the generated header's macros",
    ),
    ("sparse_not_bool", "args['sparse'] = 'yes'", "sparse: 'yes' is not True, False or None"),
    # units
    ("unit_with_quote", "args['units'] = {m: 'k\"g'}", "is not a unit"),
    ("unit_too_long", "args['units'] = {m: 'm' * 33}", "is not a unit"),
    ("unit_not_string", "args['units'] = {m: 1}", "1 is not a unit"),
    ("unit_not_a_param", "args['units'] = {x: 'm'}", "units: x is not a parameter"),
    ("units_not_dict", "args['units'] = ['kg']", "units must be a dict"),
    (
        "coordinate_units_count",
        "args['coordinate_units'] = ['m']",
        "coordinate_units has 1 entries, not 2",
    ),
    ("coordinate_units_bad", "args['coordinate_units'] = ['m', 'm s']", "'m s' is not a unit"),
    ("coordinate_units_string", "args['coordinate_units'] = 'm'", "not one string"),
    (
        "coordinate_units_key",
        "args['coordinate_units'] = {m: 'kg'}",
        "coordinate_units: m is not a coordinate",
    ),
]


@pytest.mark.parametrize(
    "change,words", [c[1:] for c in IN_PROCESS], ids=[c[0] for c in IN_PROCESS]
)
def test_refused_in_process(change, words):
    scope = {"sp": sp}
    exec(PENDULUM + "name = 'pendulum'\n" + change + "\n", scope)
    with pytest.raises(ModelError) as err:
        Mechanism(scope["name"], scope["t"], scope["q"], scope["v"], **scope["args"])
    assert words in str(err.value)


@pytest.mark.parametrize("change,words", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_refused(model, tmp_path, change, words):
    path = model(
        PENDULUM + "name = 'pendulum'\n" + change + "\nreturn Mechanism(name, t, q, v, **args)\n"
    )
    out = tmp_path / "out"
    out.mkdir()
    old = {"pendulum.h": "old header\n", "pendulum.c": "old source\n"}
    for name, text in old.items():
        (out / name).write_text(text)
    rc, stdout, stderr = run_mbsgen(path, "--out", str(out))
    assert rc == 2, stderr
    lines = stderr.splitlines()
    assert len(lines) == 1, stderr
    assert lines[0].startswith("mbsgen: ") and words in lines[0], lines[0]
    assert stdout == ""
    assert sorted(os.listdir(out)) == sorted(old)
    for name, text in old.items():
        assert (out / name).read_text() == text


def test_start_violation_says_by_how_much(model, tmp_path):
    """y scaled by 1 + d/L, d = 1e-6: c = (|q|^2 - L^2) / 2 = (2 L d + d^2) cos^2(0.3) / 2."""
    path = model(
        PENDULUM + "args['q0'] = [L * sp.sin(0.3), -(L + 1e-6) * sp.cos(0.3)]\n"
        "return Mechanism('pendulum', t, q, v, **args)\n"
    )
    rc, _, stderr = run_mbsgen(path, "--out", str(tmp_path / "out"))
    assert rc == 2
    said = float(re.search(r"c = (\S+) at constraint 1", stderr).group(1))
    d = 1e-6
    assert said == pytest.approx((4 * d + d * d) * math.cos(0.3) ** 2 / 2, rel=1e-2), stderr
    assert not (tmp_path / "out").exists()


def test_good_description_is_written(model, tmp_path):
    """The same description unchanged: the control of the cases above. The files have the
    mode of a new file (0666 less the umask), not the temporary file's 0600."""
    path = model(PENDULUM + "return Mechanism('pendulum', t, q, v, **args)\n")
    rc, stdout, stderr = run_mbsgen(path, "--out", str(tmp_path / "out"))
    assert rc == 0, stderr
    assert sorted(os.listdir(tmp_path / "out")) == ["pendulum.c", "pendulum.h"]
    umask = os.umask(0)
    os.umask(umask)
    for name in ("pendulum.c", "pendulum.h"):
        assert os.stat(tmp_path / "out" / name).st_mode & 0o777 == 0o666 & ~umask


@pytest.mark.parametrize(
    "body,words",
    [
        ("raise RuntimeError('broken model')", "RuntimeError: broken model"),
        ("return 42", "returned a int, not a stabdae_gen.Mechanism"),
        ("import sys\nsys.exit(0)", "exited (0) before giving a mechanism"),
        (
            "raise ValueError('first line\\nsecond line\\r\\nthird')",
            "ValueError: first line second line third",
        ),
        ("raise BaseException('bare')", "mechanism(): BaseException: bare"),
        ("raise KeyboardInterrupt", "mechanism(): KeyboardInterrupt"),
        ("raise GeneratorExit('odd')", "mechanism(): GeneratorExit: odd"),
        (
            "class Odd(Exception):\n    def __str__(self):\n        raise TypeError\nraise Odd()",
            "Odd: (its message cannot be printed)",
        ),
    ],
    ids=[
        "raises",
        "wrong_type",
        "exits",
        "message_of_three_lines",
        "base_exception",
        "keyboard_interrupt",
        "generator_exit",
        "message_fails",
    ],
)
def test_model_file_errors(model, tmp_path, body, words):
    """Whatever the model raises is its failure: one line, exit status 2 (a KeyboardInterrupt
    it raises itself too: only the user's Ctrl-C is an interruption)."""
    rc, _, stderr = run_mbsgen(model(body), "--out", str(tmp_path / "out"))
    assert rc == 2 and len(stderr.splitlines()) == 1 and words in stderr, stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("where", ["module", "mechanism"])
def test_model_raising_at_load(tmp_path, where):
    """The same at the model file's top level, before mechanism() runs."""
    path = tmp_path / "model.py"
    raising = "raise KeyboardInterrupt('model')\n"
    if where == "module":
        path.write_text(raising)
    else:
        path.write_text("def mechanism():\n    " + raising)
    rc, _, stderr = run_mbsgen(str(path), "--out", str(tmp_path / "out"))
    assert rc == 2 and len(stderr.splitlines()) == 1, stderr
    assert "KeyboardInterrupt: model" in stderr


def test_user_interrupt_is_130(tmp_path):
    """The user's Ctrl-C (SIGINT) while the model runs: one line, exit status 130, nothing
    written."""
    ready = tmp_path / "ready"
    path = tmp_path / "model.py"
    path.write_text(
        f"import pathlib, time\npathlib.Path({str(ready)!r}).write_text('x')\ntime.sleep(60)\n"
    )
    env = dict(os.environ, PYTHONPATH=TOOLS)
    p = subprocess.Popen(
        [sys.executable, "-m", "stabdae_gen", str(path), "--out", str(tmp_path / "out")],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 60
    while not ready.exists() and time.monotonic() < deadline and p.poll() is None:
        time.sleep(0.05)
    p.send_signal(signal.SIGINT)
    _, stderr = p.communicate(timeout=60)
    assert p.returncode == 130 and stderr.splitlines() == ["mbsgen: interrupted"], stderr
    assert not (tmp_path / "out").exists()


def test_model_imports_a_module_beside_it(model, tmp_path):
    """A model file runs as a script does: a helper module in its folder can be imported, at
    load and inside mechanism()."""
    (tmp_path / "helper.py").write_text("LENGTH = 2.0\n")
    path = model(
        PENDULUM + "import helper\nargs['params'][L] = helper.LENGTH\n"
        "return Mechanism('pendulum', t, q, v, **args)\n"
    )
    rc, stdout, stderr = run_mbsgen(path, "--out", str(tmp_path / "out"))
    assert rc == 0, stderr
    assert "2 coordinates, 1 constraint ->" in stdout


def test_command_line_errors(model, tmp_path):
    good = model(PENDULUM + "return Mechanism('pendulum', t, q, v, **args)\n")
    afile = tmp_path / "afile"
    afile.write_text("x")
    for args, words in [
        ([], "required"),
        ([good], "--out"),
        ([str(tmp_path / "missing.py"), "--out", str(tmp_path / "o")], "no such file"),
        ([good, "--out", str(afile)], "not a directory"),
        (
            [good, "--out", str(tmp_path / "o"), "--name", "other"],
            "names its mechanism 'pendulum', not 'other'",
        ),
    ]:
        rc, _, stderr = run_mbsgen(*args)
        assert rc == 2 and len(stderr.splitlines()) == 1 and words in stderr, (args, stderr)
    assert not (tmp_path / "o").exists()
    assert afile.read_text() == "x"
