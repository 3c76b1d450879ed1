# SPDX-License-Identifier: GPL-3.0-or-later
"""The FMU state across instances, and inputs that step, in FMPy.

- A state serialized by one instance and deserialized into a freshly instantiated one (nothing
  initialized, another map chosen or none), or set into another running instance, continues bit
  for bit: the FMU carries the stepper's state as the library writes it (sdae_mbs_get_state),
  the chart and Newton's kept matrix included. The reference is the first instance's own run.
- A scan of input steps (u steps of several sizes at several times, every map) completes: the
  inputs are the mechanism's forces from outside the Lagrangian, a port of the energy for the
  discrete gradients, whose Newton used to fail after such a step.
The build directory comes from STABDAE_BUILD (ctest: fmi.fmpy).
"""
import os
import struct
from pathlib import Path

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

BUILD = Path(os.environ.get("STABDAE_BUILD", Path(__file__).resolve().parents[2] / "build"))
VERSIONS = ["fmi3", "fmi2"]
MAPS = ["euler", "midpoint", "dgrad", "dg4", "dg6", "midpoint4", "midpoint6", "rk4", "rk8"]
H = 0.01  # a communication step: ten of the FMUs' default T = 1e-3


class Instance:
    """one FMPy slave of build/fmus/VERSION/NAME.fmu, with the calls both versions share"""

    def __init__(self, version, name):
        path = str(BUILD / "fmus" / version / f"{name}.fmu")
        md = read_model_description(path)
        cls = FMU3Slave if version == "fmi3" else FMU2Slave
        self.version = version
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.fmu = cls(guid=md.guid, unzipDirectory=extract(path),
                       modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.outputs = [self.vr[v.name] for v in md.modelVariables if v.causality == "output"]
        self.t = 0.0

    def instantiate(self):
        self.fmu.instantiate()

    def start(self, map_name=None):
        self.instantiate()
        if self.version == "fmi2":
            self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        if map_name:
            setter = self.fmu.setString
            setter([self.vr["map"]], [map_name])
        self.fmu.exitInitializationMode()

    def set_u(self, i, value):
        refs = [self.vr[f"u[{i}]"]]
        (self.fmu.setFloat64 if self.version == "fmi3" else self.fmu.setReal)(refs, [value])

    def step(self):
        self.fmu.doStep(currentCommunicationPoint=self.t, communicationStepSize=H)
        self.t += H

    def bits(self):
        get = self.fmu.getFloat64 if self.version == "fmi3" else self.fmu.getReal
        values = list(get(self.outputs))
        return struct.pack(f"{len(values)}d", *values)

    def get_state(self):
        if self.version == "fmi3":
            state = self.fmu.getFMUState()
            return state, self.fmu.serializeFMUState(state)
        state = self.fmu.getFMUstate()
        return state, self.fmu.serializeFMUstate(state)

    def set_serialized(self, serialized):
        if self.version == "fmi3":
            state = self.fmu.deserializeFMUState(serialized)
            self.fmu.setFMUState(state)
            self.fmu.freeFMUState(state)
        else:
            state = self.fmu.deSerializeFMUstate(serialized)
            self.fmu.setFMUstate(state)
            self.fmu.freeFMUstate(state)

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


def ran(version, name, map_name, steps=30):
    a = Instance(version, name)
    a.start(map_name)
    for k in range(steps):
        if k == 10:
            a.set_u(1, 0.8)  # the state holds an input, too
        a.step()
    return a


def continue_alike(a, b, serialized, steps):
    """a's serialized state set into b: both take the same steps to the same bits"""
    b.set_serialized(serialized)
    b.t = a.t
    for _ in range(steps):
        a.step()
        b.step()
    assert b.bits() == a.bits()
    a.free()
    b.free()


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("map_name", ["dgrad", "midpoint", "rk4"])
def test_state_into_a_fresh_instance(version, map_name):
    """D1: deserialized into an instance just instantiated (fmusim's --initial-fmu-state-file)"""
    a = ran(version, "fourbar", map_name)
    _, serialized = a.get_state()
    b = Instance(version, "fourbar")
    b.instantiate()
    continue_alike(a, b, serialized, 20)


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", ["fourbar", "slider_crank"])
def test_state_moved_between_instances(version, name):
    """D3: set into another running instance (another map chosen there): the same bits after
    100 communication steps, where a stepper built anew drifted 3.5e-7 off"""
    a = ran(version, name, "dgrad")
    _, serialized = a.get_state()
    b = Instance(version, name)
    b.start("euler")
    for _ in range(7):
        b.step()
    continue_alike(a, b, serialized, 100)


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name", ["fourbar", "slider_crank"])
@pytest.mark.parametrize("map_name", MAPS)
def test_input_step_scan(version, name, map_name):
    """D2: u[1] steps at several times to several sizes (and back); every doStep succeeds"""
    sizes = {"fourbar": [10.0, -4.0, 0.5], "slider_crank": [0.8, -2.0, 5.0]}[name]
    a = Instance(version, name)
    a.start(map_name)
    for k in range(60):
        if k % 15 == 5:
            a.set_u(1, sizes[(k // 15) % len(sizes)])
        elif k % 15 == 12:
            a.set_u(1, 0.0)
        a.step()  # FMPy raises on anything but OK
    a.free()
