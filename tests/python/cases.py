"""Test cases that load the FMUs into external FMI tools (fmpy, libcosimpy).

Each case runs in its own Python process (``python cases.py CASE``), started by the pytest files
with a timeout, so a crash of the host process fails the test instead of taking pytest down, and a
hang fails it instead of blocking. A case prints one JSON line with its results and exits 0, or
raises (exit 1). The cases live here (illegal sequences, instances, threads, FMU states, resource
URIs), in cases_tools.py (fmpy simulate, libcosimpy) and cases_hardening.py (the hardening issue).
"""

import ctypes
import json
import shutil
import sys
import tempfile
import threading
from ctypes import byref, c_void_p
from pathlib import Path

import cases_hardening
import cases_tools
from fmu_helpers import (
    Logged,
    extract,
    variables,
    make_slave,
    set_params,
    init,
    outputs,
    read_all,
    bank_profile,
    beacon2,
    run_solo,
    apply_inputs,
    expect_error,
    raw_lib,
    ROOT,
    FMU_DIR,
    ENTRYNAV,
    COMBINED,
    FILTER,
    TRUTH,
)

# ------------------------------------------------------------------------------------------------
# cases


def case_illegal_sequences():
    from fmpy.fmi2 import fmi2CallbackFunctions

    slave, md, vs, logged = make_slave(COMBINED, "illegal")
    bank = vs["bank_angle"].valueReference
    checks = 0
    # Before initialisation.
    expect_error(logged, slave.doStep, 0.0, 1.0, match="Illegal call sequence")
    expect_error(logged, slave.exitInitializationMode, match="Illegal call sequence")
    expect_error(logged, slave.terminate, match="Illegal call sequence")
    expect_error(logged, slave.getReal, [bank], match="Illegal call sequence")
    expect_error(logged, slave.getDirectionalDerivative, [bank], [bank], [1.0], match="Illegal call sequence")
    checks += 5
    # Bad values are rejected without changing anything.
    expect_error(logged, slave.setReal, [bank], [float("nan")], match="not a finite number")
    expect_error(logged, slave.setReal, [bank], [float("inf")], match="not a finite number")
    expect_error(logged, slave.setReal, [99999], [1.0], match="unknown value reference 99999")
    expect_error(logged, slave.setInteger, [bank], [1], match="is a Real variable")
    expect_error(logged, slave.setString, [vs["filter"].valueReference], ["kalman"], match="unknown filter")
    expect_error(logged, slave.setInteger, [vs["seed"].valueReference], [-4], match="seed must be >= 0")
    expect_error(logged, slave.setReal, [vs["truth_r"].valueReference], [1.0], match="is an output")
    expect_error(logged, slave.setupExperiment, startTime=5.0, match="startTime must be 0")
    checks += 8
    # A '%' in a message reaches the printf-like logger escaped.
    expect_error(logged, slave.setString, [vs["scenario"].valueReference], [""], match="empty")
    set_params(slave, vs, {"scenario": "100%-missing.toml"})
    slave.setupExperiment(startTime=0.0, stopTime=10.0)
    slave.enterInitializationMode()
    expect_error(logged, slave.setupExperiment, startTime=0.0, match="Illegal call sequence")
    msg = expect_error(logged, slave.exitInitializationMode, match="100%%-missing.toml")
    assert "100%-missing" not in msg.replace("%%", ""), msg
    checks += 3
    # A failed fmi2ExitInitializationMode puts the instance in the error state (FMI 2.0): only
    # fmi2Reset, fmi2SetFMUstate, fmi2FreeInstance and the queries lead on.
    expect_error(logged, slave.setString, [vs["scenario"].valueReference], ["four-beacon-fusion"], match="Illegal call sequence")
    expect_error(logged, slave.exitInitializationMode, match="Illegal call sequence")
    expect_error(logged, slave.doStep, 0.0, 1.0, match="Illegal call sequence")
    checks += 3
    slave.reset()
    slave.setupExperiment(startTime=0.0, stopTime=10.0)
    slave.enterInitializationMode()
    # Fix the parameter in initialisation mode, then initialise.
    set_params(slave, vs, {"scenario": "four-beacon-fusion", "seed": 4})
    slave.exitInitializationMode()
    expect_error(logged, slave.setString, [vs["scenario"].valueReference], ["orbiters-3"], match="fixed after initialisation")
    expect_error(logged, slave.enterInitializationMode, match="Illegal call sequence")
    expect_error(logged, slave.doStep, 1.0, 1.0, match="not the current time")
    expect_error(logged, slave.doStep, 0.0, 0.0, match="step > 0")
    expect_error(logged, slave.doStep, 0.0, -1.0, match="step > 0")
    expect_error(logged, slave.doStep, 0.0, 11.0, match="after stopTime")
    expect_error(logged, slave.getDirectionalDerivative, [bank], [bank], [1.0], match="not supported")
    expect_error(logged, slave.fmi2CancelStep, slave.component, match="Illegal call sequence")
    checks += 8
    expect_error(logged, slave.setRealInputDerivatives, [bank], [1], [0.1], match="not supported")
    expect_error(logged, slave.getRealOutputDerivatives, [vs["truth_r"].valueReference], [1], match="not supported")
    assert slave.getString([vs["scenario"].valueReference, vs["filter"].valueReference]) == [b"four-beacon-fusion", b"dcifaif"]
    assert slave.getRealStatus(2) == 0.0  # fmi2LastSuccessfulTime
    assert slave.getBooleanStatus(3) is False or slave.getBooleanStatus(3) == 0  # fmi2Terminated
    checks += 5
    # Still usable after all those rejected calls.
    slave.doStep(0.0, 1.0)
    slave.doStep(1.0, 1.0)
    assert slave.getReal([vs["nav_time"].valueReference])[0] == 2.0
    slave.terminate()
    expect_error(logged, slave.doStep, 2.0, 1.0, match="Illegal call sequence")
    expect_error(logged, slave.terminate, match="Illegal call sequence")
    checks += 2
    slave.reset()
    expect_error(logged, slave.getReal, [bank], match="Illegal call sequence")
    checks += 1
    slave.freeInstance()

    # Instantiation failures: null arguments, wrong GUID, empty name, model exchange.
    lib, md, d = raw_lib(COMBINED)
    assert lib.fmi2GetTypesPlatform() == b"default" and lib.fmi2GetVersion() == b"2.0"
    uri = (Path(d) / "resources").as_uri().encode()
    log = Logged()
    cb = ctypes.cast(byref(log.callbacks), c_void_p)
    guid = md.guid.encode()
    assert lib.fmi2Instantiate(b"x", 1, b"{00000000-0000-0000-0000-000000000000}", uri, cb, 0, 0) is None
    assert "does not match" in log.text()
    assert lib.fmi2Instantiate(b"x", 0, guid, uri, cb, 0, 0) is None
    assert "model exchange" in log.text()
    assert lib.fmi2Instantiate(b"", 1, guid, uri, cb, 0, 0) is None
    assert "instance name is empty" in log.text()
    assert lib.fmi2Instantiate(None, 1, guid, uri, cb, 0, 0) is None
    assert lib.fmi2Instantiate(b"x", 1, None, uri, cb, 0, 0) is None
    assert lib.fmi2Instantiate(b"x", 1, guid, uri, None, 0, 0) is None
    checks += 6
    # NULL and freed components, NULL arrays.
    lib.fmi2FreeInstance(None)
    assert lib.fmi2DoStep(None, 0.0, 1.0, 0) == 3
    assert lib.fmi2Terminate(None) == 3
    c = lib.fmi2Instantiate(b"x", 1, guid, uri, cb, 0, 0)
    assert c
    n = len(log.messages)
    assert lib.fmi2GetReal(c, None, 3, None) == 3
    assert "null pointer" in log.messages[-1][2] and len(log.messages) == n + 1
    assert lib.fmi2GetReal(c, None, 0, None) == 3  # legal arguments, illegal state
    lib.fmi2FreeInstance(c)
    checks += 5
    return {"checks": checks, "messages": len(logged.messages) + len(log.messages)}


def case_interleaved():
    params_a = {"seed": 3, "dispersed": True, "filter": "dcifaif"}
    params_b = {"seed": 8, "dispersed": True, "filter": "ekf", "scenario": "four-beacon-fusion-fault"}
    steps = 120
    solo_a = run_solo(COMBINED, params_a, steps, inputs=apply_inputs)
    solo_b = run_solo(COMBINED, params_b, steps)
    a, md, vs, _ = make_slave(COMBINED, "A")
    b, _, vs_b, _ = make_slave(COMBINED, "B")
    init(a, vs, params_a)
    init(b, vs_b, params_b)
    groups = outputs(md)
    rows_a, rows_b = [read_all(a, groups)], [read_all(b, groups)]
    for k in range(steps):
        apply_inputs(a, vs, float(k))
        a.doStep(float(k), 1.0)
        b.doStep(float(k), 1.0)
        rows_b.append(read_all(b, groups))
        rows_a.append(read_all(a, groups))
    assert rows_a == solo_a, "instance A differs when interleaved with B"
    assert rows_b == solo_b, "instance B differs when interleaved with A"
    assert rows_a != rows_b
    return {"steps": steps, "values_compared": 2 * len(rows_a) * len(rows_a[0])}


def case_threads():
    params = [
        {"seed": 2, "dispersed": True, "filter": "dcifaif"},
        {"seed": 5, "dispersed": True, "filter": "mmae-moe", "scenario": "msl-pressure-orbiter"},
    ]
    steps = 200
    solo = [run_solo(COMBINED, p, steps, h=0.5) for p in params]
    results = [None, None]
    errors = []

    def worker(i):
        try:
            results[i] = run_solo(COMBINED, params[i], steps, h=0.5, slave_name=f"thread{i}")
        except Exception as e:  # reported below
            errors.append(repr(e))

    for _ in range(3):
        threads = [threading.Thread(target=worker, args=(i,)) for i in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert not errors, errors
        assert results == solo, "a run in a thread differs from the sequential run"
    return {"threads": 2, "repeats": 3, "steps": steps}


def case_state():
    out = {}
    for fmu, params in [
        (COMBINED, {"seed": 6, "dispersed": True, "filter": "dcifaif"}),
        (COMBINED, {"seed": 9, "dispersed": True, "filter": "ukf", "scenario": "msl-airdata"}),
        (TRUTH, {"seed": 6, "dispersed": True}),
    ]:
        slave, md, vs, logged = make_slave(fmu, "state")
        init(slave, vs, params)
        groups = outputs(md)
        has_inputs = "bank_angle" in vs
        for k in range(100):
            if has_inputs:
                apply_inputs(slave, vs, float(k))
            slave.doStep(float(k), 1.0)
        state = slave.getFMUstate()
        blob = slave.serializeFMUstate(state)

        def rest(s):
            rows = []
            for k in range(100, 240):
                if has_inputs:
                    apply_inputs(s, vs, float(k))
                s.doStep(float(k), 1.0)
                rows.append(read_all(s, groups))
            return rows

        first = rest(slave)
        slave.setFMUstate(state)
        again = rest(slave)
        assert again == first, "setFMUstate did not reproduce the rest of the run"
        # Serialized state into a fresh instance of the same FMU.
        other, _, _, olog = make_slave(fmu, "restored")
        st2 = other.deSerializeFMUstate(blob)
        other.setFMUstate(st2)
        restored = rest(other)
        assert restored == first, "deserialized state did not reproduce the rest of the run"
        # Corrupted, truncated and foreign states are rejected.
        bad = bytearray(blob)
        bad[len(bad) // 2] ^= 0x11
        expect_error(olog, other.deSerializeFMUstate, bytes(bad), match="checksum")
        expect_error(olog, other.deSerializeFMUstate, blob[:-3], match="length")
        expect_error(olog, other.deSerializeFMUstate, b"nonsense", match="bad magic")
        expect_error(olog, other.deSerializeFMUstate, blob[:10], match="truncated")
        v2 = bytearray(blob)
        v2[8] = 99
        expect_error(olog, other.deSerializeFMUstate, bytes(v2), match="version 99")
        slave.freeFMUstate(state)
        other.freeFMUstate(st2)
        expect_error(olog, other.setFMUstate, st2, match="not a state of this instance")
        slave.freeInstance()
        other.freeInstance()
        out[f"{fmu.stem}/{params.get('scenario', 'four-beacon-fusion')}"] = {
            "bytes": len(blob),
            "steps_reproduced": len(first),
        }
    # A state from another model is refused.
    a, _, vs_a, _ = make_slave(COMBINED, "a")
    init(a, vs_a, {})
    blob = a.serializeFMUstate(a.getFMUstate())
    t, _, _, tlog = make_slave(TRUTH, "t")
    expect_error(tlog, t.deSerializeFMUstate, blob, match="belongs to MarsEntryNav")
    a.freeInstance()
    t.freeInstance()
    return out


def case_resource_uris():
    base = Path(tempfile.mkdtemp(prefix="entrynav uri "))
    try:
        d = base / "unzipped fmu %percent"
        extract(COMBINED, str(d))
        res = d / "resources"
        text = (res / "four-beacon-fusion-fault.toml").read_text()
        text = text.replace('name = "four-beacon-fusion-fault"', 'name = "custom fault"', 1)
        (res / "my scenario.toml").write_text(text)
        quoted = res.as_uri()  # file:///...%20...%25...
        assert "%20" in quoted and "%25" in quoted
        # Unencoded spaces (lenient; a literal '%' cannot be left unencoded), through a symlink.
        (base / "plain dir").symlink_to(d)
        plain_path = str(base / "plain dir" / "resources")
        uris = {
            "file:///": quoted,
            "file:/": "file:" + quoted[len("file://"):],
            "file://localhost/": "file://localhost" + quoted[len("file://"):],
            "unencoded": "file://" + plain_path,
        }
        rows = {}
        for label, uri in uris.items():
            slave, md, vs, logged = make_slave(COMBINED, "uri", unzipdir=str(d), uri=uri)
            init(slave, vs, {"scenario": "my scenario.toml", "seed": 2}, logged=logged)
            groups = outputs(md)
            r = []
            for k in range(30):
                slave.doStep(float(k), 1.0)
                r.append(read_all(slave, groups))
            rows[label] = r
            slave.freeInstance()
        first = next(iter(rows.values()))
        assert all(r == first for r in rows.values())
        # Same as the built-in it was copied from (only the name differs).
        builtin = run_solo(COMBINED, {"scenario": "four-beacon-fusion-fault", "seed": 2}, 30)[1:]
        assert builtin == first
        # A remote or malformed location is reported when a file has to be read from it.
        slave, md, vs, logged = make_slave(COMBINED, "bad", unzipdir=str(d), uri="http://example.invalid/res")
        set_params(slave, vs, {"scenario": "my scenario.toml"})
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        expect_error(logged, slave.exitInitializationMode, match="not a file: URI")
        slave.freeInstance()
        return {"uris": list(uris), "steps": 30}
    finally:
        shutil.rmtree(base, ignore_errors=True)




CASES = {
    name[5:]: f
    for module in (globals(), vars(cases_tools), vars(cases_hardening))
    for name, f in module.items()
    if name.startswith("case_")
}

if __name__ == "__main__":
    result = CASES[sys.argv[1]]()
    print(json.dumps(result))
