"""Cases of the hardening issue, through the packed libraries (ctypes) and fmpy (see cases.py):
the 7-call sequence that aborted the process, for every filter; each library accepts only its own
model's GUID; the `scenario` parameter cannot read or disclose host files."""

import ctypes
import os
import subprocess
import tempfile
from ctypes import byref, c_char_p, c_double, c_int, c_uint, c_void_p, POINTER
from pathlib import Path

from fmu_helpers import COMBINED, FILTER, FMU_DIR, Logged, VENV_BIN, raw_lib, variables

FILTERS = ["ekf", "ukf", "ci", "dcifaif", "mmae", "mmae-moe", "ukf-cm", "ukf-ac", "uskf-nn"]
# The built-in scenarios, in the order the FMU lists them (its resources folder holds them all).
BUILTINS = ["four-beacon-fusion", "four-beacon-fusion-fault", "msl-airdata", "ground-beacons-3",
            "orbiters-3", "msl-pressure", "msl-pressure-orbiter"]


def _declare(lib):
    lib.fmi2SetString.argtypes = [c_void_p, POINTER(c_uint), ctypes.c_size_t, POINTER(c_char_p)]
    lib.fmi2SetBoolean.argtypes = [c_void_p, POINTER(c_uint), ctypes.c_size_t, POINTER(c_int)]
    lib.fmi2SetReal.argtypes = [c_void_p, POINTER(c_uint), ctypes.c_size_t, POINTER(c_double)]
    lib.fmi2GetInteger.argtypes = [c_void_p, POINTER(c_uint), ctypes.c_size_t, POINTER(c_int)]
    lib.fmi2SetupExperiment.argtypes = [c_void_p, c_int, c_double, c_double, c_int, c_double]
    for f in ("fmi2EnterInitializationMode", "fmi2ExitInitializationMode"):
        getattr(lib, f).argtypes = [c_void_p]


def case_regression():
    """MarsEntryNavFilter, per filter: Instantiate; SetupExperiment(stopTimeDefined = false);
    Enter/ExitInitialization; DoStep(0, T); meas_epoch = true, meas_time = T; DoStep(T, 1) with
    T = 1e9 (aborted the process) and 1e18 (a caught 'capacity overflow' printed to stderr)."""
    lib, md, d = raw_lib(FILTER)
    _declare(lib)
    vs = {v.name: v.valueReference for v in md.modelVariables}
    uri = (Path(d) / "resources").as_uri().encode()
    lib.fmi2Reset.argtypes = [c_void_p]

    def instance(scenario, name, log):
        """An initialised filter FMU, or None when the filter does not fit the scenario."""
        c = lib.fmi2Instantiate(b"regression", 1, md.guid.encode(), uri, ctypes.cast(byref(log.callbacks), c_void_p), 0, 0)
        assert c, log.text()
        for var, value in (("scenario", scenario), ("filter", name)):
            assert lib.fmi2SetString(c, byref(c_uint(vs[var])), 1, byref(c_char_p(value.encode()))) == 0, log.text()
        steps = [lib.fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), lib.fmi2EnterInitializationMode(c), lib.fmi2ExitInitializationMode(c)]
        if steps == [0, 0, 0]:
            return c
        assert steps == [0, 0, 3] and "does not fit" in log.text(), (steps, log.text())
        lib.fmi2FreeInstance(c)
        return None

    answers = {}
    for name in FILTERS:
        for t_far in (1e9, 1e18):
            log = Logged()
            # The first built-in scenario the filter fits.
            found = ((sc, instance(sc, name, log)) for sc in BUILTINS)
            scenario, c = next(((sc, c) for sc, c in found if c), (None, None))
            assert c, f"no built-in scenario fits {name}"
            calls = [
                lib.fmi2DoStep(c, 0.0, t_far, 0),
                lib.fmi2SetBoolean(c, byref(c_uint(vs["meas_epoch"])), 1, byref(c_int(1))),
                lib.fmi2SetReal(c, byref(c_uint(vs["meas_time"])), 1, byref(c_double(t_far))),
            ]
            assert calls == [0] * 3, (name, calls, log.text())
            n = len(log.messages)
            last = lib.fmi2DoStep(c, t_far, 1.0, 0)
            reason = [m for _, _, m in log.messages[n:]]
            assert last == 3 and len(reason) == 1 and "refused, the instance is unchanged" in reason[0], (name, last, reason)
            status = c_int(-1)
            assert lib.fmi2GetInteger(c, byref(c_uint(vs["nav_status"])), 1, byref(status)) == 0
            assert status.value == 0, "the refused step changed the filter"
            lib.fmi2FreeInstance(c)
            answers[f"{name}@{t_far:g}"] = {"scenario": scenario, "status": last, "reason": reason[0]}
    return answers


def case_guid_binding():
    """Each packed library accepts only its own model's GUID (the FMI 2.0 FMUs, through
    fmi2Instantiate)."""
    fmus = sorted(f for f in FMU_DIR.glob("*.fmu") if not f.stem.endswith("-fmi3"))
    guids = {f.stem: variables(f)[0].guid for f in fmus}
    out = {}
    for fmu in fmus:
        lib, md, d = raw_lib(fmu)
        uri = (Path(d) / "resources").as_uri().encode()
        for other, guid in guids.items():
            log = Logged()
            c = lib.fmi2Instantiate(b"x", 1, guid.encode(), uri, ctypes.cast(byref(log.callbacks), c_void_p), 0, 0)
            if other == fmu.stem:
                assert c, log.text()
                lib.fmi2FreeInstance(c)
            else:
                assert c is None, f"{fmu.stem}.so accepted the GUID of {other}"
                text = log.text()
                assert f"packed for {fmu.stem}" in text and "accepts only its GUID" in text, text
                if other in ("MarsEntryNav", "MarsEntryNavFilter", "MarsEntryTruth"):
                    assert f"{other}.so" in text, text
        out[fmu.stem] = len(guids) - 1
    return {"refused_foreign_guids": out}


def case_scenario_files():
    """The issue's command and its variants: a host file named by `scenario` is not read unless
    allow_external_files = true, and no error quotes it."""
    from fmpy import simulate_fmu

    secret_line = "root:x:0:0:root:/root:/bin/bash"
    with tempfile.TemporaryDirectory(prefix="entrynav-secret-") as tmp:
        secret = Path(tmp) / "passwd"
        secret.write_text(secret_line + "\ndaemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin\n")
        results = {}
        for path in [str(secret)] + (["/etc/passwd"] if Path("/etc/passwd").exists() else []):
            out = subprocess.run(
                [str(VENV_BIN / "fmpy"), "simulate", str(COMBINED), "--start-values", "scenario", path, "--fmi-logging"],
                capture_output=True, text=True, timeout=120,
            )
            text = out.stdout + out.stderr
            assert out.returncode != 0, text
            assert "root:x:" not in text and "daemon:" not in text, text
            assert "allow_external_files = true" in text, text
            for allow in (False, True):
                log = []
                try:
                    simulate_fmu(str(COMBINED), stop_time=1.0, start_values={"scenario": path, "allow_external_files": allow},
                                 logger=lambda *a: log.append(str(a[-1])), debug_logging=True)
                    raise AssertionError(f"{path} loaded")
                except Exception as e:  # the initialisation fails
                    text = " ".join(log) + str(e)
                expected = "TOML parse error at line 1" if allow else "neither a built-in"
                assert expected in text, text
                assert "root:x:" not in text and "daemon:" not in text, text
            results[path] = "refused without disclosure"
        return results


def case_specific_binding():
    """A scenario-specific FMU accepts only its GUID (not the generic MarsEntryNav's), and refuses
    to start once its embedded scenario file has been changed."""
    fmu = Path(os.environ["ENTRYNAV_SPECIFIC_FMU"])
    lib, md, d = raw_lib(fmu)
    res = Path(d) / "resources"
    uri = res.as_uri().encode()

    def instantiate(guid):
        log = Logged()
        c = lib.fmi2Instantiate(b"x", 1, guid.encode(), uri, ctypes.cast(byref(log.callbacks), c_void_p), 0, 0)
        if c:
            lib.fmi2FreeInstance(c)
        return bool(c), log.text()

    ok, text = instantiate(md.guid)
    assert ok, text
    generic = variables(COMBINED)[0].guid
    ok, text = instantiate(generic)
    assert not ok and "accepts only its GUID" in text, text
    (toml,) = res.glob("*.toml")
    original = toml.read_text()
    changed = original.replace("duration_s = 350.0", "duration_s = 349.0")
    assert changed != original
    toml.write_text(changed)
    ok, text = instantiate(md.guid)
    assert not ok and "resources/ changed" in text, text
    return {"own_guid": "accepted", "generic_guid": "refused", "changed_scenario": "refused"}
