#!/usr/bin/env python3
"""Simulate MarsEntryNav.fmu with fmpy and print the navigation filter's final estimation error.

    .venv/bin/python docs/examples/fmpy_simulate.py out/tutorial/fmu/MarsEntryNav.fmu \
        --scenario four-beacon-fusion --filter dcifaif --seed 7 --outage 2 120 180 \
        --csv out/tutorial/fmpy-run.csv

The FMU's parameters (scenario, filter, seed, dispersed) are passed as fmpy start values. With
--outage I T0 T1 the input beacon_available_I is false for T0 <= t < T1 (the bank_angle input keeps
its start value, 0 rad). The run is the FMU's default experiment (0 to 300 s, 1 s communication
steps) unless --stop-time is given. The script prints, for every filter state i, the final error
err_i = est_x_i - truth_x_i next to the filter's own 3 * est_sigma_i, and the mean number of
measurements used per epoch inside and outside the outage; --csv writes every recorded output
(one row per communication step) for plotting.
"""

import argparse

import numpy as np
from fmpy import read_model_description, simulate_fmu
from fmpy.util import write_csv


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("fmu", help="path of MarsEntryNav.fmu")
    p.add_argument("--scenario", default="four-beacon-fusion")
    p.add_argument("--filter", default="dcifaif")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--nominal", action="store_true", help="nominal truth (dispersed = false)")
    p.add_argument("--stop-time", type=float, default=None)
    p.add_argument("--outage", nargs=3, type=float, metavar=("BEACON", "T0", "T1"), default=None)
    p.add_argument("--csv", default=None, help="write all recorded outputs here")
    a = p.parse_args()

    md = read_model_description(a.fmu)
    stop = a.stop_time if a.stop_time is not None else float(md.defaultExperiment.stopTime)
    step = float(md.defaultExperiment.stepSize)
    start_values = {"scenario": a.scenario, "filter": a.filter, "seed": a.seed, "dispersed": not a.nominal}

    signals = None
    if a.outage:
        # One row per communication point for every input: its start value (bank_angle 0 rad, every
        # beacon available), except beacon_available_BEACON during the outage.
        beacon, t0, t1 = int(a.outage[0]), a.outage[1], a.outage[2]
        inputs = [v for v in md.modelVariables if v.causality == "input"]
        t = np.arange(0.0, stop + step, step)
        signals = np.zeros(len(t), dtype=[("time", np.float64)]
                           + [(v.name, np.float64 if v.type == "Real" else np.bool_) for v in inputs])
        signals["time"] = t
        for v in inputs:
            signals[v.name] = float(v.start) if v.type == "Real" else v.start == "true"
        signals[f"beacon_available_{beacon}"] = ~((t0 <= t) & (t < t1))

    res = simulate_fmu(a.fmu, start_values=start_values, stop_time=stop, output_interval=step, input=signals)

    n = int(res["n_states"][-1])
    # Filter coordinates: spherical when est_x_1..6 equal the spherical estimate est_r..est_heading.
    spherical = all(np.array_equal(res[f"est_x_{k + 1}"], res[f"est_{s}"])
                    for k, s in enumerate(["r", "lon", "lat", "v", "fpa", "heading"]))
    names = ["r", "lon", "lat", "v", "fpa", "heading"] if spherical else ["x", "y", "z", "vx", "vy", "vz"]
    names += [f"aug{j}" for j in range(1, n - 5)]
    print(f"{a.scenario}, filter {a.filter}, seed {a.seed}: {len(res)} samples to t = {res['time'][-1]:g} s, "
          f"last estimate at nav_time = {res['nav_time'][-1]:g} s, nav_status = {res['nav_status'][-1]}")
    print(f"{'i':>3} {'state':>8} {'final err_i':>14} {'3 est_sigma_i':>14}  inside")
    for i, name in enumerate(names, start=1):
        e, s = float(res[f"err_{i}"][-1]), float(res[f"est_sigma_{i}"][-1])
        print(f"{i:>3} {name:>8} {e:>14.6g} {3 * s:>14.6g}  {'yes' if abs(e) <= 3 * s else 'NO'}")
    print(f"final NEES {res['nees'][-1]:.2f} ({res['nees_dof'][-1]} dof); SI units, angles in rad")
    if a.outage:
        out = (res["time"] > t0) & (res["time"] <= t1)
        print(f"measurements per epoch: {res['n_meas'][~out].mean():.2f} outside, "
              f"{res['n_meas'][out].mean():.2f} during the beacon {beacon} outage")
    if a.csv:
        write_csv(a.csv, res)
        print(f"wrote {a.csv}")


if __name__ == "__main__":
    main()
