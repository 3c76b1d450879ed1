# SPDX-License-Identifier: GPL-3.0-or-later
"""The project's FMUs (build/fmus/fmi3 and fmi2: fourbar, slider_crank) in FMPy, a real importer.

Every check has an independent reference: FMPy's own validator; the example programs' CSV
(the same fixed steps and map, so the same numbers to rounding); the bit-identity of a step
taken twice from one FMU state; a program of its own (fmi_reference_u) for the inputs. The
build directory comes from STABDAE_BUILD (ctest sets it: fmi.fmpy, label fmi).
"""
import json
import os
import struct
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
from fmpy.fmi3 import FMU3Slave
from fmpy import calloc, free
from fmpy.validation import validate_fmu

BUILD = Path(os.environ.get("STABDAE_BUILD", Path(__file__).resolve().parents[2] / "build"))
NAMES = ["fourbar", "slider_crank"]
VERSIONS = ["fmi3", "fmi2"]
T = 1e-3  # the example programs' step, the FMUs' default T


def fmu_path(version, name):
    return str(BUILD / "fmus" / version / f"{name}.fmu")


def sizes(name):
    return {"fourbar": (4, 3), "slider_crank": (3, 2)}[name]


def outputs(name):
    n_q, n_c = sizes(name)
    return ([f"q[{i}]" for i in range(1, n_q + 1)] + [f"v[{i}]" for i in range(1, n_q + 1)] +
            [f"lambda[{j}]" for j in range(1, n_c + 1)] + ["max_abs_c", "energy"])


def program_columns(name):
    n_q, n_c = sizes(name)
    return ([f"q{i}" for i in range(1, n_q + 1)] + [f"v{i}" for i in range(1, n_q + 1)] +
            [f"lambda{j}" for j in range(1, n_c + 1)] + ["max_abs_c", "E"])


def run_program(name, tf, every, tmp_path):
    out = tmp_path / f"{name}.csv"
    subprocess.run([str(BUILD / "examples" / name), "--tf", repr(tf), "--every", str(every),
                    "--out", str(out)], check=True)
    return np.genfromtxt(out, delimiter=",", names=True)


def assert_close(got, ref, what):
    """to 1e-14, relative to the size of the value (absolute below 1)"""
    err = np.abs(np.asarray(got) - np.asarray(ref)) / np.maximum(1.0, np.abs(ref))
    assert np.all(err <= 1e-14), f"{what}: worst relative difference {err.max():.3g}"


def bits(values):
    return struct.pack(f"{len(values)}d", *values)


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", NAMES)
def test_validate(version, name):
    assert validate_fmu(fmu_path(version, name)) == []


def expected_units(name):
    """the units each variable has in SI, from the mechanism's physics (models/mechanisms.c,
    models/benchmarks.c): the four-bar's coordinates are lengths, its constraints
    (|X - Y|^2 - L^2) / 2 in m^2, so lambda is in N/m; the slider crank's are an angle, a length
    and an angle, its constraints lengths whose rows of G are in m per rad and 1, so lambda is in
    N. Time in s, epsilon a rate; delta, map and max_abs_c (mixed constraints) have none."""
    n_q, n_c = sizes(name)
    if name == "fourbar":
        params = {"a": "m", "b": "m", "e": "m", "d": "m", "mB": "kg", "mC": "kg",
                  "ga": "m/s^2", "theta0": "rad", "omega0": "rad/s"}
        q, u, lam = ["m"] * 4, ["N"] * 4, ["N/m"] * 3
    else:
        params = {"a": "m", "J1": "kg*m^2", "m2": "kg", "J2": "kg*m^2", "k": "N/m",
                  "c": "N*s/m", "l0": "m", "F": "N"}
        q, u, lam = ["rad", "m", "rad"], ["N*m", "N", "N*m"], ["N", "N"]
    units = {"time": "s", "T": "s", "delta": None, "epsilon": "1/s", "map": None,
             "max_abs_c": None, "energy": "J", **params}
    for i in range(n_q):
        units.update({f"q0[{i + 1}]": q[i], f"q[{i + 1}]": q[i], f"v0[{i + 1}]": q[i] + "/s",
                      f"v[{i + 1}]": q[i] + "/s", f"u[{i + 1}]": u[i]})
    units.update({f"lambda[{j + 1}]": lam[j] for j in range(n_c)})
    return units


# the units' SI base units, from their definitions (N = kg m s^-2, J = N m)
SI = {"s": {"s": 1}, "1/s": {"s": -1}, "m": {"m": 1}, "kg": {"kg": 1}, "rad": {"rad": 1},
      "m/s": {"m": 1, "s": -1}, "rad/s": {"rad": 1, "s": -1}, "m/s^2": {"m": 1, "s": -2},
      "kg*m^2": {"kg": 1, "m": 2}, "N": {"kg": 1, "m": 1, "s": -2}, "N/m": {"kg": 1, "s": -2},
      "N*s/m": {"kg": 1, "s": -1}, "N*m": {"kg": 1, "m": 2, "s": -2},
      "J": {"kg": 1, "m": 2, "s": -2}}


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", NAMES)
def test_units(version, name):
    """every variable has its unit (and those without one none), each defined once in
    UnitDefinitions with its SI base units, none defined that no variable has"""
    md = read_model_description(fmu_path(version, name))
    got = {v.name: v.unit for v in md.modelVariables}
    assert got == expected_units(name)
    defined = [u.name for u in md.unitDefinitions]
    assert len(defined) == len(set(defined))
    assert set(defined) == {u for u in got.values() if u}
    for unit in md.unitDefinitions:
        base = unit.baseUnit
        exponents = {k: getattr(base, k) for k in ("kg", "m", "s", "A", "K", "mol", "cd", "rad")}
        assert {k: e for k, e in exponents.items() if e} == SI[unit.name], unit.name
        assert (base.factor, base.offset) == (1.0, 0.0)


@pytest.mark.parametrize("version", VERSIONS)
def test_default_experiment(version, tmp_path):
    """DefaultExperiment: start 0, step T, stop the example program's tf (10 s), a whole number
    of steps; FMPy run with nothing given stops there, on the program's states bit for bit (its
    output interval is the step doubled until there are at most 1000: 16 T)"""
    name = "fourbar"
    experiment = read_model_description(fmu_path(version, name)).defaultExperiment
    start, stop, step = (float(experiment.startTime), float(experiment.stopTime),
                         float(experiment.stepSize))
    assert (start, stop, step) == (0.0, 10.0, T)
    assert (stop - start) / step == round((stop - start) / step)
    res = simulate_fmu(fmu_path(version, name), output=outputs(name)[:8])
    ref = run_program(name, 10.0, 16, tmp_path)
    assert res["time"][-1] == stop and len(res) == len(ref) == 626
    for out, col in zip(outputs(name)[:8], program_columns(name)[:8]):
        assert bits(res[out]) == bits(ref[col]), f"{version} {out}"


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", NAMES)
def test_binary_stands_alone(version, name, tmp_path):
    """the binary needs nothing outside libc and libm but what the FMU carries, and exports the
    FMI functions only"""
    platform = "x86_64-linux" if version == "fmi3" else "linux64"
    with zipfile.ZipFile(fmu_path(version, name)) as z:
        z.extractall(tmp_path)
    binaries = tmp_path / "binaries" / platform
    ldd = subprocess.run(["ldd", str(binaries / f"{name}.so")], check=True, capture_output=True,
                         text=True).stdout
    for line in ldd.splitlines():
        lib = line.split()[0]
        if lib.startswith(("linux-vdso", "/lib64/ld-linux", "libc.so", "libm.so")):
            continue
        assert "=>" in line and line.split("=>")[1].split()[0].startswith(str(binaries)), line
    nm = subprocess.run(["nm", "-D", "--defined-only", str(binaries / f"{name}.so")],
                        check=True, capture_output=True, text=True).stdout
    exported = [line.split()[-1] for line in nm.splitlines()]
    assert exported and all(sym.startswith(version) for sym in exported), exported
    docs = {p.name for p in (tmp_path / "documentation").rglob("*")}
    assert {"stabdae-GPL-3.0-or-later.txt", "fmi-headers-BSD-2-Clause.txt"} <= docs


POISONED_RUN = """
import ctypes, json, sys
from fmpy import simulate_fmu
poison = ctypes.CDLL(sys.argv[1], mode=ctypes.RTLD_GLOBAL)
try:
    res = simulate_fmu(sys.argv[2], stop_time=0.5, output_interval=0.01, output=sys.argv[3:])
    rows = [[float(x).hex() for x in row] for row in res]
except Exception as e:  # a step failed on the poisoned numbers
    rows = str(e)
print(json.dumps({"calls": ctypes.c_long.in_dll(poison, "poison_calls").value, "rows": rows}))
"""


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", NAMES)
def test_cblas_bound_inside(version, name, tmp_path):
    """GSL's CBLAS is bound inside the binary: in a process that loaded a CBLAS of its own first
    (fmi_poison_cblas, RTLD_GLOBAL: first in the symbol lookup; each of its routines counts its
    calls and writes NaN), the FMU never calls it and gives the numbers it gives alone, bit for
    bit. The binary has no RPATH or RUNPATH, needs no CBLAS and has no cblas_ symbol a process
    could see or interpose."""
    poison = BUILD / "fmi" / "tests" / "libfmi_poison_cblas.so"
    p = subprocess.run([sys.executable, "-c", POISONED_RUN, str(poison), fmu_path(version, name)]
                       + outputs(name), check=True, capture_output=True, text=True)
    poisoned = json.loads(p.stdout.splitlines()[-1])
    alone = simulate_fmu(fmu_path(version, name), stop_time=0.5, output_interval=0.01,
                         output=outputs(name))
    assert poisoned["calls"] == 0
    assert poisoned["rows"] == [[float(x).hex() for x in row] for row in alone]
    platform = "x86_64-linux" if version == "fmi3" else "linux64"
    with zipfile.ZipFile(fmu_path(version, name)) as z:
        z.extractall(tmp_path)
    binary = str(tmp_path / "binaries" / platform / f"{name}.so")
    dynamic = subprocess.run(["readelf", "-d", binary], check=True, capture_output=True,
                             text=True).stdout
    assert "RPATH" not in dynamic and "RUNPATH" not in dynamic
    needed = [line.split("[")[1].rstrip("]") for line in dynamic.splitlines() if "(NEEDED)" in line]
    assert set(needed) <= {"libc.so.6", "libm.so.6"}, needed
    symbols = subprocess.run(["nm", "-D", binary], check=True, capture_output=True,
                             text=True).stdout
    assert "cblas_" not in symbols


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", NAMES)
def test_license_entry_point(version, name, tmp_path):
    """FMI 3.0 section 2.5: documentation/licenses/ has license.txt as its entry point (in the
    FMI 2.0 FMU too); it names the licences, GPL-3.0-or-later, BSD-2-Clause, LGPL-2.1-or-later
    (SuiteSparse's LDL) and BSD-3-Clause (its AMD), and every other file of the folder, each of
    which holds its licence's text"""
    with zipfile.ZipFile(fmu_path(version, name)) as z:
        z.extractall(tmp_path)
    licenses = tmp_path / "documentation" / "licenses"
    entry = (licenses / "license.txt").read_text()
    for name in ("GPL-3.0-or-later", "BSD-2-Clause", "LGPL-2.1-or-later", "BSD-3-Clause"):
        assert name in entry
    others = {p.name for p in licenses.iterdir()} - {"license.txt"}
    assert others == {"stabdae-GPL-3.0-or-later.txt", "fmi-headers-BSD-2-Clause.txt",
                      "suitesparse-amd-BSD-3-Clause.txt"}
    for other in others:
        assert other in entry
    assert "GNU GENERAL PUBLIC LICENSE" in (licenses / "stabdae-GPL-3.0-or-later.txt").read_text()
    for bsd in ("fmi-headers-BSD-2-Clause.txt", "suitesparse-amd-BSD-3-Clause.txt"):
        assert "Redistribution and use in source and binary forms" in (licenses / bsd).read_text()


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("k, tf", [(1, 0.2), (10, 2.0)])
def test_matches_program(version, name, k, tf, tmp_path):
    """an output interval of k T: the program's rows every k steps, to 1e-14"""
    ref = run_program(name, tf, k, tmp_path)
    res = simulate_fmu(fmu_path(version, name), stop_time=tf, output_interval=k * T,
                       output=outputs(name))
    assert len(res) == len(ref)
    assert_close(res["time"], ref["t"], "time")
    for out, col in zip(outputs(name), program_columns(name)):
        assert_close(res[out], ref[col], f"{name} {version} {out}")
    # the same steps exactly: the states are the program's bit for bit (equal substeps of
    # h / k instead of T would differ in the last bits)
    for out, col in zip(outputs(name)[:8], program_columns(name)[:8]):
        assert bits(res[out]) == bits(ref[col]), f"{name} {version} {out}: not the same steps"


@pytest.mark.parametrize("version", VERSIONS)
def test_equal_substeps(version, tmp_path):
    """a communication step h = 2.5 T, not a multiple of T: ceil(h / T) = 3 equal steps, the
    program run with the step h / 3 (the four-bar does not depend on t: the same numbers)"""
    name, h = "fourbar", 2.5 * T
    ref_csv = tmp_path / "ref.csv"
    subprocess.run([str(BUILD / "examples" / name), "--T", repr(h / 3), "--tf", "0.5",
                    "--every", "3", "--out", str(ref_csv)], check=True)
    ref = np.genfromtxt(ref_csv, delimiter=",", names=True)
    res = simulate_fmu(fmu_path(version, name), stop_time=0.5, output_interval=h,
                       output=outputs(name))
    assert len(res) == len(ref)
    for out, col in zip(outputs(name)[:8], program_columns(name)[:8]):
        err = np.max(np.abs(res[out] - ref[col]))
        assert err <= 1e-12, f"{out}: {err:.3g}"


@pytest.mark.parametrize("version", VERSIONS)
def test_settings_as_program_flags(version, tmp_path):
    """T, map, delta, epsilon and the mechanism's parameters set as start values: the program
    run with the same flags, bit for bit"""
    flags = {"T": 5e-4, "delta": 3.0, "epsilon": 2.0, "theta0": 0.3, "omega0": 4.0, "mC": 1.5}
    ref_csv = tmp_path / "ref.csv"
    args = [str(BUILD / "examples" / "fourbar"), "--tf", "0.5", "--every", "20", "--map",
            "midpoint", "--out", str(ref_csv)]
    for k, x in flags.items():
        args += ["--" + ("eps" if k == "epsilon" else k), repr(x)]
    subprocess.run(args, check=True)
    ref = np.genfromtxt(ref_csv, delimiter=",", names=True)
    res = simulate_fmu(fmu_path(version, "fourbar"), stop_time=0.5, output_interval=20 * 5e-4,
                       start_values={**flags, "map": "midpoint"}, output=outputs("fourbar"))
    assert len(res) == len(ref)
    for out, col in zip(outputs("fourbar"), program_columns("fourbar")):
        assert bits(res[out]) == bits(ref[col]), f"{version} {out}"


@pytest.mark.parametrize("version", VERSIONS)
def test_start_state_set(version, tmp_path):
    """q0 and v0 set by the importer (the program's state at t = 0.25 as a new start): the
    program's rows from there on (the four-bar does not depend on t), to Newton's tolerance at
    most: the FMU's stepper is a fresh one, its chart and Newton matrix chosen anew"""
    ref = run_program("fourbar", 0.5, 10, tmp_path)
    mid = len(ref) // 2
    start = {f"q0[{i}]": ref[f"q{i}"][mid] for i in range(1, 5)}
    start.update({f"v0[{i}]": ref[f"v{i}"][mid] for i in range(1, 5)})
    res = simulate_fmu(fmu_path(version, "fourbar"), stop_time=0.1, output_interval=10 * T,
                       start_values=start, output=outputs("fourbar")[:8])
    assert len(res) == 11
    for out, col in zip(outputs("fourbar")[:8], program_columns("fourbar")[:8]):
        err = np.max(np.abs(res[out] - ref[col][mid:mid + 11]))
        assert err <= 1e-9, f"{version} {out}: {err:.3g}"


def slave(version, path, **kw):
    md = read_model_description(path)
    unzipdir = extract(path)
    cls = FMU3Slave if version == "fmi3" else FMU2Slave
    fmu = cls(guid=md.guid, unzipDirectory=unzipdir,
              modelIdentifier=md.coSimulation.modelIdentifier, instanceName="test")
    vr = {v.name: v.valueReference for v in md.modelVariables}
    return fmu, vr, unzipdir


def get(fmu, version, refs):
    return list(fmu.getFloat64(refs) if version == "fmi3" else fmu.getReal(refs))


def set_real(fmu, version, refs, values):
    (fmu.setFloat64 if version == "fmi3" else fmu.setReal)(refs, values)


def start(fmu, version, logger=None, t0=0.0):
    if version == "fmi3":
        fmu.instantiate(logMessage=logger)
        fmu.enterInitializationMode(startTime=t0)
    else:
        fmu.instantiate(callbacks=logger)
        fmu.setupExperiment(startTime=t0)
        fmu.enterInitializationMode()


def do_step(fmu, t, h):
    return fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", NAMES)
def test_roll_back(version, name):
    """get the state, step, set it back, step again: the same bits; through serialization too"""
    fmu, vr, _ = slave(version, fmu_path(version, name))
    refs = [vr[o] for o in outputs(name)]
    start(fmu, version)
    fmu.exitInitializationMode()
    t, h = 0.0, 0.01
    for _ in range(5):
        do_step(fmu, t, h)
        t += h
    if version == "fmi3":
        state = fmu.getFMUState()
        serialized = fmu.serializeFMUState(state)
    else:
        state = fmu.getFMUstate()
        serialized = fmu.serializeFMUstate(state)
    do_step(fmu, t, h)
    first = bits(get(fmu, version, refs))
    (fmu.setFMUState if version == "fmi3" else fmu.setFMUstate)(state)
    do_step(fmu, t, h)
    assert bits(get(fmu, version, refs)) == first
    copy = (fmu.deserializeFMUState(serialized) if version == "fmi3"
            else fmu.deSerializeFMUstate(serialized))
    (fmu.setFMUState if version == "fmi3" else fmu.setFMUstate)(copy)
    do_step(fmu, t, h)
    assert bits(get(fmu, version, refs)) == first
    if version == "fmi3":
        fmu.freeFMUState(state)
        fmu.freeFMUState(copy)
    else:
        fmu.freeFMUstate(state)
        fmu.freeFMUstate(copy)
    fmu.terminate()
    fmu.freeInstance()


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", NAMES)
def test_constant_input(version, name):
    """a constant u: the program run with u added to F (fmi_reference_u, its own wrapper)"""
    n_q, _ = sizes(name)
    u = [0.3, -0.2, 0.25, 0.1][:n_q]
    ref_out = subprocess.run([str(BUILD / "fmi" / "tests" / "fmi_reference_u"), name, repr(T),
                              "1000", "10"] + [repr(x) for x in u],
                             check=True, capture_output=True, text=True).stdout
    ref = np.array([[float(x) for x in line.split(",")] for line in ref_out.split()])
    res = simulate_fmu(fmu_path(version, name), stop_time=1.0, output_interval=10 * T,
                       start_values={f"u[{i + 1}]": x for i, x in enumerate(u)},
                       output=outputs(name)[:2 * n_q])
    assert len(res) == len(ref)
    assert_close(res["time"], ref[:, 0], "time")
    for i, out in enumerate(outputs(name)[:2 * n_q]):
        assert_close(res[out], ref[:, 1 + i], f"{name} {version} {out}")
    # and u = 0 is not what was run: the input moved the mechanism
    free_run = simulate_fmu(fmu_path(version, name), stop_time=1.0, output_interval=10 * T,
                            output=["q[1]"])
    assert np.max(np.abs(free_run["q[1]"] - res["q[1]"])) > 1e-6


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("t0", [1e9, 1e6])
def test_communication_point_in_steps(version, t0):
    """the communication point must be the FMU's time to a small fraction of T at any start
    time: 0.5 s, 0.9 T and 0.01 T off are refused and change nothing; the points t0 + n T are
    accepted (also one ulp off: rounding), the FMU's time is then t0 + n T (a count of steps,
    no drift, whatever the points passed) and the state is the
    one of a run from 0, bit for bit (the four-bar does not depend on t: the same steps)"""
    name, n = "fourbar", 50
    refs = outputs(name)
    runs = []
    for start_time in (0.0, t0):
        fmu, vr, _ = slave(version, fmu_path(version, name))
        start(fmu, version, t0=start_time)
        fmu.exitInitializationMode()
        for i in range(n):
            t = start_time + i * T
            if start_time:
                before = bits(get(fmu, version, [vr["time"]] + [vr[o] for o in refs]))
                for off in (0.5, 0.9 * T, -0.9 * T, 0.01 * T):
                    with pytest.raises(FMICallException):
                        do_step(fmu, t + off, T)
                assert bits(get(fmu, version, [vr["time"]] + [vr[o] for o in refs])) == before
            do_step(fmu, np.nextafter(t, np.inf) if i % 2 else t, T)  # a point rounded apart
            assert get(fmu, version, [vr["time"]]) == [start_time + (i + 1) * T]
        runs.append(bits(get(fmu, version, [vr[o] for o in refs])))
        fmu.terminate()
        fmu.freeInstance()
    assert runs[0] == runs[1]


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", NAMES)
def test_outputs_follow_inputs(version, name):
    """a get after a set of u, before any doStep, answers outputs at the new u: lambda (which
    depends on u directly) is that of a fresh instance started at the same time and state with
    that u, and not the one before; q, v, max_abs_c and energy (which do not) stay as they were.
    The model structure says so: lambda depends on every u, the other outputs on none."""
    n_q, n_c = sizes(name)
    u = [0.3, -0.2, 0.25, 0.1][:n_q]
    fmu, vr, _ = slave(version, fmu_path(version, name))
    refs = [vr[o] for o in outputs(name)]
    lam = slice(2 * n_q, 2 * n_q + n_c)
    start(fmu, version)
    fmu.exitInitializationMode()
    for i in range(10):
        do_step(fmu, i * 0.01, 0.01)
    before = get(fmu, version, refs)
    set_real(fmu, version, [vr[f"u[{i + 1}]"] for i in range(n_q)], u)
    after = get(fmu, version, refs)
    state = get(fmu, version, [vr["time"]] + refs[:2 * n_q])
    fmu.terminate()
    fmu.freeInstance()
    fresh, vr2, _ = slave(version, fmu_path(version, name))
    start(fresh, version, t0=state[0])
    set_real(fresh, version, [vr2[f"{x}0[{i + 1}]"] for x in "qv" for i in range(n_q)] +
             [vr2[f"u[{i + 1}]"] for i in range(n_q)], state[1:] + u)
    fresh.exitInitializationMode()
    reference = get(fresh, version, refs)
    fresh.terminate()
    fresh.freeInstance()
    assert np.max(np.abs(np.subtract(after[lam], before[lam]))) > 1e-3, "lambda did not move"
    assert_close(after[lam], reference[lam], f"{name} {version} lambda")
    assert bits(after[:lam.start] + after[lam.stop:]) == bits(before[:lam.start] +
                                                              before[lam.stop:])
    md = read_model_description(fmu_path(version, name))
    inputs = {f"u[{i + 1}]" for i in range(n_q)}
    for out in md.outputs:
        deps = {v.name for v in out.dependencies}
        assert deps == (inputs if out.variable.name.startswith("lambda[") else set()), \
            out.variable.name


class Log:
    """the FMU's messages, by status, and the instance each named (FMI 2.0's instanceName; FMI
    3.0's logger has none: the message begins with the name)"""

    def __init__(self, version):
        self.errors = []
        self.named = []
        if version == "fmi3":
            self.callback = self.log3
        else:
            cb = fmi2CallbackFunctions()
            cb.logger = fmi2CallbackLoggerTYPE(self.log2)
            cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
            cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
            self.callback = cb

    def log3(self, env, status, category, message):
        self.named.append(message.decode().split(": ", 1)[0])
        if status == 3:
            self.errors.append(message.decode())

    def log2(self, env, name, status, category, message):
        self.named.append(name.decode() if name else None)
        if status == 3:
            self.errors.append(message.decode())

    def take(self):
        errors, self.errors = self.errors, []
        return errors


def refused(call, log, word):
    with pytest.raises(FMICallException):
        call()
    errors = log.take()
    assert errors and word in errors[-1], errors


@pytest.mark.parametrize("version", VERSIONS)
def test_messages_name_the_instance(version):
    """every message carries the instance's name, also those logged inside instantiate: a token
    that is not the binary's, and the information message with logging on"""
    path = fmu_path(version, "fourbar")
    md = read_model_description(path)
    unzipdir = extract(path)
    log = Log(version)
    cls = FMU3Slave if version == "fmi3" else FMU2Slave
    for guid in ("{00000000-0000-0000-0000-000000000000}", md.guid):
        fmu = cls(guid=guid, unzipDirectory=unzipdir, instanceName="pump_7",
                  modelIdentifier=md.coSimulation.modelIdentifier)
        if version == "fmi3":
            instantiate = lambda: fmu.instantiate(loggingOn=True, logMessage=log.callback)
        else:
            instantiate = lambda: fmu.instantiate(loggingOn=True, callbacks=log.callback)
        if guid == md.guid:
            instantiate()
            fmu.freeInstance()
        else:
            with pytest.raises(Exception):
                instantiate()
    assert len(log.take()) == 1 and len(log.named) == 2
    assert log.named == ["pump_7", "pump_7"]


@pytest.mark.parametrize("version", VERSIONS)
def test_bad_input(version, capfd):
    """bad input: an error status and a message through the logger, the value kept, nothing on
    stdout, the FMU usable again"""
    name = "fourbar"
    fmu, vr, _ = slave(version, fmu_path(version, name))
    log = Log(version)
    start(fmu, version, log.callback)
    T0 = get(fmu, version, [vr["T"]])
    for bad in (0.0, -1.0, float("nan"), float("inf")):
        refused(lambda: set_real(fmu, version, [vr["T"]], [bad]), log, "T")
    for p in ("delta", "epsilon"):
        refused(lambda: set_real(fmu, version, [vr[p]], [0.0]), log, p)
    refused(lambda: fmu.setString([vr["map"]], ["nosuchmap"]), log, "map")
    refused(lambda: set_real(fmu, version, [vr["q0[1]"]], [float("nan")]), log, "q0[1]")
    refused(lambda: set_real(fmu, version, [vr["u[1]"]], [float("nan")]), log, "u[1]")
    refused(lambda: set_real(fmu, version, [123456], [1.0]), log, "123456")
    assert bits(get(fmu, version, [vr["T"]])) == bits(T0)
    fmu.exitInitializationMode()
    for h in (0.0, -0.01, float("nan")):
        refused(lambda: do_step(fmu, 0.0, h), log, "communication step")
    refused(lambda: set_real(fmu, version, [vr["T"]], [2e-3]), log, "T")
    do_step(fmu, 0.0, 0.01)  # still usable
    # a failing step: an error, the outputs of the last good point, then reset and run again
    before = bits(get(fmu, version, [vr[o] for o in outputs(name)]))
    set_real(fmu, version, [vr["u[1]"]], [1e200])
    refused(lambda: do_step(fmu, 0.01, 0.01), log, "failed")
    assert bits(get(fmu, version, [vr[o] for o in outputs(name)])) == before
    refused(lambda: do_step(fmu, 0.01, 0.01), log, "doStep")
    fmu.reset()
    if version == "fmi2":
        fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    do_step(fmu, 0.0, 0.01)
    fmu.terminate()
    fmu.freeInstance()
    assert capfd.readouterr().out == ""


GENERATED = "fourbar_generated"  # the four-bar written by stabdae_gen (examples/fmus)
needs_generated = pytest.mark.skipif(
    not (BUILD / "fmus" / "fmi3" / f"{GENERATED}.fmu").exists(),
    reason="built with the generated mechanisms (a Python with sympy)")


@needs_generated
@pytest.mark.parametrize("version", VERSIONS)
def test_generated_validates(version):
    assert validate_fmu(fmu_path(version, GENERATED)) == []


@needs_generated
@pytest.mark.parametrize("version", VERSIONS)
def test_generated_matches_hand_written(version):
    """the generated four-bar's FMU against the hand-written one's, with the same parameters
    (named alike by the generated table) set away from the defaults: the same steps from
    callbacks equal to rounding, so the same outputs to 1e-12 over 1 s (about 1e-14 a step,
    summed over 1000 steps of a non-chaotic loop)"""
    start = {"theta0": 0.7, "omega0": 3.0, "mC": 1.5, "T": 1e-3, "map": "rk4"}
    runs = [simulate_fmu(fmu_path(version, name), stop_time=1.0, output_interval=10 * T,
                         start_values=start, output=outputs("fourbar"))
            for name in ("fourbar", GENERATED)]
    assert len(runs[0]) == len(runs[1]) == 101
    for out in outputs("fourbar"):
        err = np.abs(runs[1][out] - runs[0][out]) / np.maximum(1.0, np.abs(runs[0][out]))
        assert err.max() <= 1e-12, f"{version} {out}: {err.max():.3g}"


@needs_generated
@pytest.mark.parametrize("version", VERSIONS)
def test_sparse_mechanism_matches_dense(version):
    """the four-bar written by its nonzeros (a sparse mechanism, its patterns forwarded by the
    FMU) validates and steps as the dense generated four-bar, through an input step (u through
    input_force) and with the discrete gradient: in its own sparse coordinates, another chart
    than the dense one's, so to dgrad's truncation error, the difference falling by about 4 as
    T halves"""
    name = "fourbar_sparse"
    assert validate_fmu(fmu_path(version, name)) == []
    signal = np.array([(0.0, 0.0), (0.5, 2.0)], dtype=[("time", np.float64), ("u[1]", np.float64)])
    diff = []
    for step in (T, T / 2):
        start = {"theta0": 0.7, "omega0": 3.0, "T": step, "map": "dgrad"}
        runs = [simulate_fmu(fmu_path(version, n), stop_time=1.0, output_interval=10 * T,
                             start_values=start, input=signal, output=outputs("fourbar"))
                for n in (GENERATED, name)]
        assert len(runs[0]) == len(runs[1]) == 101
        diff.append(max(float(np.max(np.abs(runs[1][out] - runs[0][out])
                                     / np.maximum(1.0, np.abs(runs[0][out]))))
                        for out in outputs("fourbar")))
    assert diff[0] <= 1e-4, f"{version}: {diff[0]:.3g}"
    assert diff[0] >= 3.0 * diff[1], f"{version}: {diff[0]:.3g} then {diff[1]:.3g}"


@pytest.mark.parametrize("version", VERSIONS)
def test_start_values_written_back(version):
    """an importer that writes every start value of the XML back unchanged, q0 and v0 among
    them, with theta0 changed: the start follows theta0 (the run equals the one setting theta0
    alone, bit for bit), since q0, v0 were left at their values"""
    md = read_model_description(fmu_path(version, "fourbar"))
    defaults = {v.name: float(v.start) for v in md.modelVariables
                if v.name.startswith(("q0[", "v0["))}
    assert len(defaults) == 8
    runs = [simulate_fmu(fmu_path(version, "fourbar"), stop_time=0.1, output_interval=10 * T,
                         start_values=start, output=outputs("fourbar")[:8])
            for start in ({"theta0": 0.7}, {"theta0": 0.7, **defaults})]
    for out in outputs("fourbar")[:8]:
        assert bits(runs[0][out]) == bits(runs[1][out]), out
    assert runs[0]["q[1]"][0] == pytest.approx(np.cos(0.7), rel=1e-12)  # B = (a cos, a sin)


def test_describer_refuses_another_name(tmp_path):
    """the table's name must be stabdae_add_fmu's NAME (the binary's): another is refused when
    the FMU is built, with one line naming both"""
    describer = BUILD / "examples" / "fmus" / "fourbar_describe"
    p = subprocess.run([str(describer), "3", str(tmp_path / "md.xml"), str(tmp_path / "p.html"),
                        "dpend"], capture_output=True, text=True)
    assert p.returncode == 1 and p.stdout == ""
    assert "its name fourbar is not the FMU's dpend" in p.stderr
    assert not (tmp_path / "md.xml").exists()
