"""Helpers of the FMU test cases: fmpy slaves with a recording logger, reading every output,
the input profiles, and the FMU libraries loaded with ctypes."""

import ctypes
import os
from ctypes import byref, c_char_p, c_double, c_int, c_size_t, c_uint, c_void_p, POINTER
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
FMU_DIR = Path(os.environ.get("ENTRYNAV_FMU_DIR", ROOT / "target" / "fmu"))
ENTRYNAV = Path(os.environ.get("ENTRYNAV_BIN", ROOT / "target" / "release" / "entrynav"))
ENTRYNAV_DEV = Path(os.environ.get("ENTRYNAV_DEV_BIN", ROOT / "target" / "release" / "entrynav-dev"))
VENV_BIN = ROOT / ".venv" / "bin"
COMBINED = FMU_DIR / "MarsEntryNav.fmu"
FILTER = FMU_DIR / "MarsEntryNavFilter.fmu"
TRUTH = FMU_DIR / "MarsEntryTruth.fmu"


# ------------------------------------------------------------------------------------------------
# helpers


class Logged:
    """fmi2CallbackFunctions whose logger records (status, category, message)."""

    def __init__(self):
        from fmpy import calloc, free
        from fmpy.fmi2 import (
            fmi2CallbackAllocateMemoryTYPE,
            fmi2CallbackFreeMemoryTYPE,
            fmi2CallbackFunctions,
            fmi2CallbackLoggerTYPE,
        )

        self.messages = []

        def logger(env, name, status, category, message):
            self.messages.append(
                (status, (category or b"").decode(), (message or b"").decode())
            )

        self.callbacks = fmi2CallbackFunctions()
        self._logger = fmi2CallbackLoggerTYPE(logger)
        self.callbacks.logger = self._logger
        self.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self.callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)

    def text(self):
        return "\n".join(m for _, _, m in self.messages)


def extract(fmu, where=None):
    from fmpy import extract as fmpy_extract

    return fmpy_extract(str(fmu), unzipdir=where)


def variables(fmu):
    from fmpy import read_model_description

    md = read_model_description(str(fmu))
    return md, {v.name: v for v in md.modelVariables}


def make_slave(fmu, name="inst", unzipdir=None, uri=None, logged=None):
    """An instantiated FMU2Slave; returns (slave, md, vars, logged)."""
    from fmpy.fmi2 import FMU2Slave

    md, vs = variables(fmu)
    unzipdir = unzipdir or extract(fmu)
    slave = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unzipdir,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName=name,
    )
    logged = logged or Logged()
    if uri is None:
        slave.instantiate(callbacks=logged.callbacks)
    else:
        slave.callbacks = logged.callbacks
        slave.component = slave.fmi2Instantiate(
            name.encode(), 1, md.guid.encode(), uri.encode(), byref(logged.callbacks), 0, 0
        )
        assert slave.component, logged.text()
    return slave, md, vs, logged


def set_params(slave, vs, params):
    for k, v in params.items():
        var = vs[k]
        if var.type == "String":
            slave.setString([var.valueReference], [v])
        elif var.type == "Integer":
            slave.setInteger([var.valueReference], [int(v)])
        elif var.type == "Boolean":
            slave.setBoolean([var.valueReference], [bool(v)])
        else:
            slave.setReal([var.valueReference], [float(v)])


def init(slave, vs, params, stop=None, logged=None):
    set_params(slave, vs, params)
    slave.setupExperiment(startTime=0.0, stopTime=stop)
    slave.enterInitializationMode()
    try:
        slave.exitInitializationMode()
    except Exception as e:
        raise AssertionError(f"initialisation failed: {logged.text() if logged else e}") from e


def outputs(md):
    """Output value references grouped by the function that reads them (an Enumeration is read
    with fmi2GetInteger), in table order."""
    out = {"Real": [], "Integer": [], "Boolean": []}
    for v in md.modelVariables:
        if v.causality == "output":
            out["Integer" if v.type == "Enumeration" else v.type].append(v.valueReference)
    return out


def read_all(slave, groups):
    """Every output as float64 bit patterns (reals) and ints, in one flat list."""
    r = np.array(slave.getReal(groups["Real"]), dtype=np.float64).view(np.uint64).tolist()
    i = [int(x) for x in slave.getInteger(groups["Integer"])]
    b = [int(bool(x)) for x in slave.getBoolean(groups["Boolean"])]
    return r + i + b


def bank_profile(t):
    """Bank command [rad]: 0, then a ramp to 0.4 rad between 100 s and 140 s, then -0.25 rad."""
    if t < 100:
        return 0.0
    if t < 140:
        return 0.01 * (t - 100)
    return -0.25


def beacon2(t):
    """Beacon 2 available except during the commanded outage 120 s <= t < 180 s."""
    return not (120 <= t < 180)


def run_solo(fmu, params, steps, h=1.0, inputs=None, slave_name="solo"):
    slave, md, vs, logged = make_slave(fmu, slave_name)
    init(slave, vs, params)
    groups = outputs(md)
    rows = [read_all(slave, groups)]
    for k in range(steps):
        t = k * h
        if inputs:
            inputs(slave, vs, t)
        slave.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        rows.append(read_all(slave, groups))
    slave.terminate()
    slave.freeInstance()
    return rows


def apply_inputs(slave, vs, t):
    slave.setReal([vs["bank_angle"].valueReference], [bank_profile(t)])
    slave.setBoolean([vs["beacon_available_2"].valueReference], [beacon2(t)])


def expect_error(logged, fn, *args, match=None, **kw):
    """fn must raise fmpy's FMICallException with fmi2Error and log `match`."""
    from fmpy.fmi1 import FMICallException

    before = len(logged.messages)
    try:
        fn(*args, **kw)
    except FMICallException as e:
        assert e.status == 3, f"{fn.__name__}: status {e.status}, expected fmi2Error"
        new = "\n".join(m for _, _, m in logged.messages[before:])
        if match is not None:
            assert match in new, f"{fn.__name__}: log {new!r} lacks {match!r}"
        return new
    raise AssertionError(f"{getattr(fn, '__name__', fn)} did not fail")


def raw_lib(fmu):
    """The FMU's shared library loaded with ctypes, with a few signatures declared."""
    d = extract(fmu)
    md, _ = variables(fmu)
    lib = ctypes.CDLL(str(Path(d) / "binaries" / "linux64" / f"{md.coSimulation.modelIdentifier}.so"))
    lib.fmi2Instantiate.restype = c_void_p
    lib.fmi2Instantiate.argtypes = [c_char_p, c_int, c_char_p, c_char_p, c_void_p, c_int, c_int]
    lib.fmi2FreeInstance.argtypes = [c_void_p]
    lib.fmi2FreeInstance.restype = None
    lib.fmi2DoStep.argtypes = [c_void_p, c_double, c_double, c_int]
    lib.fmi2GetReal.argtypes = [c_void_p, POINTER(c_uint), c_size_t, POINTER(c_double)]
    lib.fmi2Terminate.argtypes = [c_void_p]
    lib.fmi2GetTypesPlatform.restype = c_char_p
    lib.fmi2GetVersion.restype = c_char_p
    return lib, md, d


