"""Cases with whole runs in external tools: fmpy simulate with an input CSV, and libcosimpy
(FMI Library) running the truth -> filter pair next to the combined FMU (see cases.py)."""

import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from fmu_helpers import COMBINED, ENTRYNAV_DEV, FILTER, TRUTH, bank_profile, beacon2, variables

def case_fmpy_simulate():
    from fmpy import simulate_fmu

    tmp = Path(tempfile.mkdtemp(prefix="entrynav-fmpy-"))
    try:
        t = np.arange(0.0, 301.0)
        signals = np.array(
            [(ti, bank_profile(ti), beacon2(ti)) for ti in t],
            dtype=[("time", np.float64), ("bank_angle", np.float64), ("beacon_available_2", np.bool_)],
        )
        csv = tmp / "input.csv"
        with open(csv, "w") as f:
            f.write("time,bank_angle,beacon_available_2\n")
            for ti, b, a in signals:
                f.write(f"{float(ti)!r},{float(b)!r},{int(a)}\n")
        params = {"scenario": "four-beacon-fusion", "filter": "dcifaif", "seed": 7, "dispersed": True}
        t0 = time.perf_counter()
        res = simulate_fmu(
            str(COMBINED),
            start_time=0.0,
            stop_time=300.0,
            output_interval=1.0,
            start_values=params,
            input=signals,
        )
        wall = time.perf_counter() - t0
        ref_csv = tmp / "ref.csv"
        cmd = [str(ENTRYNAV_DEV), "fmu", "run", "--model", "MarsEntryNav", "--stop", "300", "--step", "1",
               "--input", str(csv), "--out", str(ref_csv)]
        cmd += [arg for k, v in params.items() for arg in ("--set", f"{k}={str(v).lower() if isinstance(v, bool) else v}")]
        subprocess.run(cmd, check=True, timeout=120)
        ref = np.genfromtxt(ref_csv, delimiter=",", names=True, deletechars="", dtype=np.float64)
        assert len(ref) == len(res) == 301, (len(ref), len(res))
        compared = 0
        for name in ref.dtype.names:
            a = np.asarray(res[name], dtype=np.float64)
            b = ref[name]
            same = np.array_equal(a, b, equal_nan=True)
            assert same, f"{name}: fmpy and the in-process library differ (max |d| = {np.nanmax(np.abs(a - b))})"
            compared += len(a)
        # The outage removed beacon 2's range from the updates.
        n_meas = np.asarray(res["n_meas"])
        assert n_meas[125] < n_meas[110], (n_meas[110], n_meas[125])
        # The same run without inputs (bank 0, every beacon available), timed (reported, not
        # asserted): the bank command changed the flown trajectory.
        t0 = time.perf_counter()
        plain_res = simulate_fmu(str(COMBINED), stop_time=300.0, output_interval=1.0, start_values=params)
        plain = time.perf_counter() - t0
        dr = abs(float(plain_res["truth_r"][-1]) - float(res["truth_r"][-1]))
        assert dr > 100.0, f"the bank command moved the final radius by only {dr} m"
        return {"values_compared": compared, "wall_with_input_s": round(wall, 3), "wall_300s_dcifaif_s": round(plain, 3)}
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _libcosim_run(slaves, connections, params, steps, observe, observe_int=None):
    """Run slaves [(name, fmu)] in one libcosim execution with 1 s steps; return per-step values
    of the Reals `observe` (and, under the key (name, "int"), of the Integers `observe_int`)."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    ex = CosimExecution.from_step_size(step_size=int(1e9))
    idx = {}
    vmaps = {}
    for name, fmu in slaves:
        idx[name] = ex.add_local_slave(CosimLocalSlave(fmu_path=str(fmu), instance_name=name))
        assert idx[name] >= 0, f"cannot add {fmu}"
        vmaps[name] = {v.name.decode(): v.reference for v in ex.slave_variables(idx[name])}
    for name, values in params.items():
        for k, v in values.items():
            vr = vmaps[name][k]
            if isinstance(v, bool):
                assert ex.boolean_initial_value(idx[name], vr, v)
            elif isinstance(v, int):
                assert ex.integer_initial_value(idx[name], vr, v)
            elif isinstance(v, float):
                assert ex.real_initial_value(idx[name], vr, v)
            else:
                assert ex.string_initial_value(idx[name], vr, v)
    for (src, dst, names) in connections:
        md, vs = variables(dict(slaves)[src])
        for n in names:
            kind = vs[n].type
            f = {"Real": ex.connect_real_variables, "Boolean": ex.connect_boolean_variables}[kind]
            rc = f(idx[src], vmaps[src][n], idx[dst], vmaps[dst][n])
            assert rc == 0, f"cannot connect {src}.{n} -> {dst}.{n}"
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    observe_int = observe_int or {}
    series = {name: [] for name in observe}
    series.update({(name, "int"): [] for name in observe_int})
    for k in range(steps):
        assert ex.step(), f"libcosim step {k} failed"
        for name, names in observe.items():
            refs = [vmaps[name][n] for n in names]
            series[name].append(list(obs.last_real_values(idx[name], refs)))
        for name, names in observe_int.items():
            refs = [vmaps[name][n] for n in names]
            series[(name, "int")].append(list(obs.last_integer_values(idx[name], refs)))
    return series


def case_libcosim():
    from fmpy import read_model_description

    steps = 300
    est = [f"est_x_{i}" for i in range(1, 9)] + [f"est_sigma_{i}" for i in range(1, 9)] + ["nav_time", "weight_1", "weight_2"]
    truth_names = ["truth_r", "truth_v", "truth_density"]
    md_t = read_model_description(str(TRUTH))
    meas = [v.name for v in md_t.modelVariables if v.causality == "output" and v.name.startswith("meas_")]
    common = {"seed": 4, "dispersed": True, "scenario": "four-beacon-fusion"}
    series = _libcosim_run(
        slaves=[("combined", COMBINED), ("truth", TRUTH), ("filter", FILTER)],
        connections=[("truth", "filter", meas)],
        params={
            "combined": dict(common, filter="dcifaif"),
            "truth": dict(common),
            "filter": dict(common, filter="dcifaif"),
        },
        steps=steps,
        observe={"combined": est + truth_names, "truth": truth_names, "filter": est},
        # libcosim ignores FMI 2.0 Enumerations; the Integer twins carry the codes.
        observe_int={"combined": ["nav_status_code", "truth_stop_code"]},
    )
    comb = np.array(series["combined"])
    filt = np.array(series["filter"])
    tru = np.array(series["truth"])
    # Truth FMU = combined FMU's truth, step for step.
    assert np.array_equal(tru, comb[:, len(est):]), "truth FMU differs from the combined FMU's truth"
    # The filter FMU gets the measurements one communication step later (they are transferred
    # after the step), so its estimate after step k+1 is the combined estimate after step k.
    n_est = len(est)
    assert np.array_equal(filt[1:], comb[:-1, :n_est]), "filter FMU does not reproduce the combined estimates"
    # And the combined FMU in libcosim equals the in-process library.
    tmp = Path(tempfile.mkdtemp(prefix="entrynav-cosim-"))
    try:
        ref_csv = tmp / "ref.csv"
        subprocess.run(
            [str(ENTRYNAV_DEV), "fmu", "run", "--model", "MarsEntryNav", "--stop", str(steps), "--step", "1",
             "--set", "seed=4", "--set", "dispersed=true", "--set", "filter=dcifaif", "--out", str(ref_csv)],
            check=True,
            timeout=120,
        )
        ref = np.genfromtxt(ref_csv, delimiter=",", names=True, deletechars="", dtype=np.float64)
        for j, n in enumerate(est + truth_names):
            assert np.array_equal(comb[:, j], ref[n][1:], equal_nan=True), f"libcosim {n} differs from the in-process run"
        codes = np.array(series[("combined", "int")])
        for j, n in enumerate(["nav_status", "truth_stop"]):
            assert np.array_equal(codes[:, j], ref[n][1:]), f"libcosim {n}_code differs from the in-process {n}"
            assert np.array_equal(ref[f"{n}_code"], ref[n])
        assert codes[-1, 0] == 1, "the filter is running at the end"
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return {"steps": steps, "estimates_compared": int(filt[1:].size), "connected_variables": len(meas)}


