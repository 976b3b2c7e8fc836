"""The FMUs against real FMI tools: symbols and dependencies, fmpy validate, fmutool, fmpy
simulate, fmpy's FMU2Slave (illegal sequences, instances, threads, FMU state, resource URIs),
libcosimpy (FMI Library), and random call sequences through our own host.

Every case that loads an FMU runs in a subprocess with a timeout."""

import json
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from conftest import ENTRYNAV_DEV, MODELS, ROOT, VENV_BIN, run

HERE = Path(__file__).resolve().parent

FMI2_FUNCTIONS = {
    "fmi2GetTypesPlatform", "fmi2GetVersion", "fmi2SetDebugLogging", "fmi2Instantiate",
    "fmi2FreeInstance", "fmi2SetupExperiment", "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode", "fmi2Terminate", "fmi2Reset", "fmi2GetReal", "fmi2GetInteger",
    "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal", "fmi2SetInteger", "fmi2SetBoolean",
    "fmi2SetString", "fmi2GetFMUstate", "fmi2SetFMUstate", "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative", "fmi2SetRealInputDerivatives", "fmi2GetRealOutputDerivatives",
    "fmi2DoStep", "fmi2CancelStep", "fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus", "fmi2GetStringStatus",
}
# The FMI 3.0 standard's functions (fmi3FunctionTypes.h of FMI 3.0): the library exports both
# interfaces, each instance answering only the one that created it.
FMI3_FUNCTIONS = {
    "fmi3GetVersion", "fmi3SetDebugLogging", "fmi3InstantiateModelExchange",
    "fmi3InstantiateCoSimulation", "fmi3InstantiateScheduledExecution", "fmi3FreeInstance",
    "fmi3EnterInitializationMode", "fmi3ExitInitializationMode", "fmi3EnterEventMode",
    "fmi3Terminate", "fmi3Reset",
    "fmi3GetNumberOfVariableDependencies", "fmi3GetVariableDependencies",
    "fmi3GetFMUState", "fmi3SetFMUState", "fmi3FreeFMUState", "fmi3SerializedFMUStateSize",
    "fmi3SerializeFMUState", "fmi3DeserializeFMUState",
    "fmi3GetDirectionalDerivative", "fmi3GetAdjointDerivative",
    "fmi3EnterConfigurationMode", "fmi3ExitConfigurationMode",
    "fmi3GetIntervalDecimal", "fmi3GetIntervalFraction", "fmi3GetShiftDecimal",
    "fmi3GetShiftFraction", "fmi3SetIntervalDecimal", "fmi3SetIntervalFraction",
    "fmi3SetShiftDecimal", "fmi3SetShiftFraction",
    "fmi3EvaluateDiscreteStates", "fmi3UpdateDiscreteStates",
    "fmi3EnterContinuousTimeMode", "fmi3CompletedIntegratorStep", "fmi3SetTime",
    "fmi3SetContinuousStates", "fmi3GetContinuousStateDerivatives", "fmi3GetEventIndicators",
    "fmi3GetContinuousStates", "fmi3GetNominalsOfContinuousStates",
    "fmi3GetNumberOfEventIndicators", "fmi3GetNumberOfContinuousStates",
    "fmi3EnterStepMode", "fmi3GetOutputDerivatives", "fmi3DoStep",
    "fmi3ActivateModelPartition",
} | {f"fmi3{op}{t}" for op in ("Get", "Set") for t in (
    "Float32", "Float64", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64",
    "UInt64", "Boolean", "String", "Binary", "Clock")}
ALLOWED_NEEDED = {
    "libc.so.6", "libm.so.6", "libgcc_s.so.1", "ld-linux-x86-64.so.2",
    "libpthread.so.0", "libdl.so.2", "librt.so.1",
}


def extracted_so(fmu, model, tmp_path):
    with zipfile.ZipFile(fmu) as z:
        z.extract(f"binaries/linux64/{model}.so", tmp_path)
    return tmp_path / "binaries" / "linux64" / f"{model}.so"


def test_fmu_layout(fmus):
    for model, fmu in fmus.items():
        names = set(zipfile.ZipFile(fmu).namelist())
        assert "modelDescription.xml" in names
        assert f"binaries/linux64/{model}.so" in names
        assert "resources/four-beacon-fusion.toml" in names
        committed = "modelDescription.xml" if model == "MarsEntryNav" else f"{model}.xml"
        xml = zipfile.ZipFile(fmu).read("modelDescription.xml").decode()
        assert xml == (ROOT / "modelDescription" / committed).read_text(), f"{model}: packed XML differs from the committed one"


@pytest.mark.parametrize("model", MODELS)
def test_exported_symbols_are_exactly_the_fmi2_and_fmi3_functions(fmus, model, tmp_path):
    so = extracted_so(fmus[model], model, tmp_path)
    out = run(["nm", "-D", "--defined-only", so])
    assert out.returncode == 0, out.stderr
    names = {line.split()[-1] for line in out.stdout.splitlines() if line.strip()}
    assert len(FMI2_FUNCTIONS) == 34 and len(FMI3_FUNCTIONS) == 75
    want = FMI2_FUNCTIONS | FMI3_FUNCTIONS
    assert names == want, f"extra {names - want}, missing {want - names}"


@pytest.mark.parametrize("model", MODELS)
def test_library_needs_only_glibc_libm_libgcc(fmus, model, tmp_path):
    so = extracted_so(fmus[model], model, tmp_path)
    out = run(["readelf", "-d", so])
    assert out.returncode == 0, out.stderr
    needed = {l.split("[")[1].split("]")[0] for l in out.stdout.splitlines() if "(NEEDED)" in l}
    assert needed <= ALLOWED_NEEDED, needed - ALLOWED_NEEDED


@pytest.mark.parametrize("model", MODELS)
def test_fmpy_validate(fmus, model):
    out = run([VENV_BIN / "fmpy", "validate", fmus[model]])
    print(out.stdout)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "No problems found" in out.stdout


@pytest.mark.parametrize("model", MODELS)
def test_fmutool_check(fmus, model):
    out = run([VENV_BIN / "fmutool", "-input", fmus[model], "-check"])
    text = out.stdout + out.stderr
    print(text)
    assert out.returncode == 0, text
    assert "compliant with FMI-2.0" in text, text
    assert "No semantic error" in text, text
    assert "ERROR" not in text.replace("No semantic error", ""), text


CASES = [
    "illegal_sequences",
    "interleaved",
    "threads",
    "state",
    "resource_uris",
    "fmpy_simulate",
    "libcosim",
]


@pytest.mark.parametrize("case", CASES)
def test_external_tool_case(fmus, case):
    out = run([sys.executable, HERE / "cases.py", case], timeout=600)
    assert out.returncode == 0, f"case {case} failed (exit {out.returncode}):\n{out.stdout[-3000:]}\n{out.stderr[-6000:]}"
    result = json.loads(out.stdout.strip().splitlines()[-1])
    print(case, result)


@pytest.mark.parametrize("model", MODELS)
def test_host_check_bitwise(fmus, model):
    out = run([ENTRYNAV_DEV, "fmu", "check", fmus[model]], timeout=600)
    print(out.stdout)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "bitwise identical" in out.stdout


@pytest.mark.parametrize("model", MODELS)
def test_host_fuzz_random_call_sequences(fmus, model):
    """100,000 random calls per FMU through our host (huge and tiny steps, every size-like
    argument past its bound): every illegal or refused call answered with fmi2Error, nothing on
    stderr (no Rust panic message). `entrynav-dev fmu fuzz --calls 5000000` is the long mode."""
    out = run([ENTRYNAV_DEV, "fmu", "fuzz", fmus[model], "--calls", "100000", "--seed", "7"], timeout=600)
    print(out.stdout)
    assert out.returncode == 0, out.stdout + out.stderr
    assert out.stderr == "", out.stderr
    m = re.search(r"(\d+) calls in (\d+) sequences .* no crash; .* (\d+) illegal or refused calls answered fmi2Error with the instance unchanged.* (\d+) steps refused for their work, (\d+) huge and (\d+) tiny steps, (\d+) arguments over a bound", out.stdout)
    assert m, out.stdout
    calls, _, refused, _, huge, tiny, bounded = map(int, m.groups())
    assert calls >= 100_000 and refused > 1000 and huge > 100 and tiny > 100 and bounded > 100, m.groups()
    if model == "MarsEntryNavFilter":
        assert int(m.group(4)) > 0, "no step was refused for its work"
