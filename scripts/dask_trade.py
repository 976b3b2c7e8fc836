#!/usr/bin/env python3
"""Run an entrynav trade study on a Dask cluster and merge it.

A LocalCluster on this machine is started when no --scheduler is given (--workers processes, one
thread each); pass --scheduler tcp://HOST:8786 to use a real cluster. The study runs in one of two
modes; both give a result that does not depend on the number of workers or on how the runs are
split into tasks.

Engine mode (default): shards of the engine
    The study is split into shards; each shard is a Dask task that runs the engine in the worker's
    own process through the Python package (`entrynav.trade_shard`, no subprocess; the GIL is
    released while the runs execute) and returns the shard file's contents, the same JSON as
    `entrynav trade --shard I/N --json FILE`; the client merges them with `entrynav trade merge`,
    which reproduces the single-process result exactly. Where the package is not installed on the
    workers, `--engine cli` runs the CLI there instead (`entrynav trade --shard I/N`).

        scripts/dask_trade.py --scenario four-beacon-fusion --filters ekf,ci,dcifaif --runs 5000 \
            --shards 8 --json out/study.json                      # LocalCluster on this machine
        scripts/dask_trade.py ... --scheduler tcp://HOST:8786     # a real cluster

    Every worker needs the `entrynav` package (scripts/build_python.sh) or, with --engine cli, the
    `entrynav` binary (same version) on its PATH or at --entrynav; the client needs the binary for
    the merge. Scenario files given by path must be readable at the same path on the workers.

FMU mode (--fmu PATH/MarsEntryNav.fmu): Monte Carlo runs of the FMU through fmpy
    Each Dask task unpacks the FMU on its worker, simulates a batch of runs of one filter with
    fmpy.simulate_fmu (one FMU instance per task, fmi2Reset between runs) and returns one summary
    row per run; the client sorts the rows by run index and reduces them in that order.

        scripts/dask_trade.py --fmu target/fmu/MarsEntryNav.fmu --scenario four-beacon-fusion \
            --filters ekf,dcifaif --runs 200 --json out/fmu-study.json --csv out/fmu-runs.csv

    Run k of a filter sets the FMU parameters scenario, filter, dispersed = true (--nominal: false)
    and seed = fmu_seed(--seed, k): entrynav's per-run seed mix (run_seed in core/src/sim/mod.rs,
    splitmix64 of seed ^ (k * golden + c)) shifted right by 33 bits, because the FMU's seed is a
    non-negative 32-bit Integer. The FMU's seed draws the truth dispersions (when dispersed), the
    measurement noise and, for scenarios with filter.sample_initial_from_p0, the filter start. All
    filters see the same K truths. The inputs keep their start values (bank_angle 0 rad, the
    scenarios' bank, and every beacon available). FMU run k is therefore not `entrynav trade` run
    k (that one uses the full 64-bit run seed); the two agree in distribution.

    Every worker needs Python with fmpy and numpy, and the .fmu file readable at the same path (a
    shared file system, or copy it to that path on every worker); the client reads it too (for the
    model description's GUID and default experiment).

    Per run the FMU's outputs are read at every communication point (--step, default the FMU's
    default experiment step, 1 s) up to --stop-time (default the default experiment's stop time,
    300 s); an output sample is a filter epoch when nav_time has advanced since the previous sample
    (so a step shorter than the measurement period does not count an epoch twice). On those epochs:
    err_i (estimate - truth of filter state i, angles wrapped) and est_sigma_i for i <= n_states,
    nees, and the position and velocity error norms. The filter's coordinates are spherical
    (r lon lat v fpa heading, then augmented states) when est_x_1..6 equal est_r..est_heading (the
    FMU copies them), otherwise Cartesian inertial (x y z vx vy vz, then augmented states); for
    spherical coordinates the position and velocity errors are the norms of the differences of the
    planet-fixed vectors of est_x and truth_x, as `entrynav trade` computes them.

    The JSON holds, per filter: runs, failed runs (nav_status 2 at the end), and over all runs
        rmse_time_avg[state]  sqrt(mean over runs and epochs of err^2)  (entrynav trade averages
                              the per-epoch ensemble RMSE over time instead; with equal epochs per
                              run the two differ only in the order of the root and the mean)
        rmse_final[state]     sqrt(mean over runs of the final epoch's err^2)
        (both also for pos_m and vel_mps), pos_initial_rms_m (filter start), within_3sigma[state]
        (mean over runs of the fraction of epochs with |err_i| <= 3 est_sigma_i), within_3sigma_all,
        nees_mean and nees_dof. The CSV (--csv) has one row per (filter, run). Sums use math.fsum
        over rows in run order, so the numbers are independent of the batching and the workers.
"""

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path

SPHERICAL = ["r", "lon", "lat", "v", "fpa", "heading"]  # est_<name> outputs, in filter-state order
# State names as in `entrynav trade` reports (SI units); augmented states are aug1, aug2, ...
SPHERICAL_STATES = ["r_m", "lon_rad", "lat_rad", "v_mps", "fpa_rad", "heading_rad"]
CARTESIAN_STATES = ["x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"]
MASK64 = (1 << 64) - 1


# ------------------------------------------------------------------------------------------------
# CLI mode


def _die_with_parent(parent):
    """preexec_fn of a shard's `entrynav`: on Linux, ask the kernel to SIGKILL it when the thread
    that started it dies (PR_SET_PDEATHSIG), so a worker that is killed (OOM, `kill -9`, a lost
    nanny) leaves no orphan computing on. The Dask task thread that starts the child waits for it
    (communicate), so it outlives the child in every normal run; a child whose parent died before
    the request took effect exits at once."""
    try:
        import ctypes
        import signal
        libc = ctypes.CDLL("libc.so.6", use_errno=True)
        pr_set_pdeathsig = 1
        libc.prctl(pr_set_pdeathsig, int(signal.SIGKILL), 0, 0, 0)
    except OSError:  # not Linux/glibc: no such guard
        return
    if os.getppid() != parent:
        os._exit(1)


def run_shard(entrynav, scenario, filters, runs, seed, index, count, sets):
    """Dask task: run one shard with the CLI and return the shard file's text.

    The shard goes to the child's standard output (`--json -`), not to a temporary file, so a
    killed worker leaves no file behind; the child dies with the task (see _die_with_parent)."""
    cmd = [entrynav, "trade", "--scenario", scenario, "--filters", filters, "--runs", str(runs),
           "--seed", str(seed), "--shard", f"{index}/{count}", "--json", "-", "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    parent = os.getpid()
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                          preexec_fn=lambda: _die_with_parent(parent)) as child:
        try:
            out, err = child.communicate(timeout=24 * 3600)
        except BaseException:
            child.kill()
            raise
    if child.returncode != 0:
        raise RuntimeError(f"shard {index}/{count} failed: {err.strip()}")
    return out


def package_shard(scenario, filters, runs, seed, index, count, sets):
    """Dask task: run one shard in this worker's process with the Python package and return the
    shard file's text (what `entrynav trade --shard I/N --json -` prints)."""
    import entrynav

    try:
        sc = entrynav.Scenario.builtin(scenario) if scenario in entrynav.builtin_scenarios() \
            else entrynav.Scenario.from_file(scenario)
        sc = sc.with_sets(sets)
        return entrynav.trade_shard(sc, filters.split(","), runs, seed, index, count, overrides=sets)
    except (ValueError, FileNotFoundError, RuntimeError) as e:
        raise RuntimeError(f"shard {index}/{count} failed: {e}") from None


def cli_study(a, client):
    """Engine or CLI mode: shard tasks on the cluster, merged by `entrynav trade merge`; returns the
    exit code."""
    n_workers = max(1, len(client.scheduler_info().get("workers", {})))
    # A shard holds whole accumulation blocks of 256 runs (so that the merge is bit-identical):
    # by default no more shards than blocks, so none is empty.
    blocks = -(-a.runs // 256)
    count = a.shards or max(1, min(2 * n_workers, blocks))
    if a.engine == "package":
        futures = [client.submit(package_shard, a.scenario, a.filters, a.runs, a.seed, i, count, a.sets,
                                 pure=False, key=f"entrynav-shard-{i}-of-{count}") for i in range(count)]
    else:
        futures = [client.submit(run_shard, a.entrynav, a.scenario, a.filters, a.runs, a.seed, i, count, a.sets,
                                 pure=False, key=f"entrynav-shard-{i}-of-{count}") for i in range(count)]
    texts = client.gather(futures)
    keep = Path(a.keep_shards) if a.keep_shards else None
    with tempfile.TemporaryDirectory() as tmp:
        d = keep or Path(tmp)
        d.mkdir(parents=True, exist_ok=True)
        files = []
        for i, t in enumerate(texts):
            f = d / f"shard{i}.json"
            f.write_text(t)
            files.append(str(f))
        cmd = [a.entrynav, "trade", "merge", *files, "--json", a.json]
        if a.csv_dir:
            cmd += ["--csv-dir", a.csv_dir]
        return subprocess.run(cmd, text=True).returncode


# ------------------------------------------------------------------------------------------------
# FMU mode: runs on the workers


def fmu_seed(seed, run):
    """FMU `seed` parameter of run `run`: entrynav's run_seed(seed, run) >> 33, in [0, 2^31)."""
    z = (seed ^ ((run * 0x9E3779B97F4A7C15 + 0x632BE59BD9B4E019) & MASK64)) & MASK64
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK64
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK64
    return (z ^ (z >> 31)) >> 33


def state_slots(md):
    """How many state slots (est_x_1..est_x_K) the FMU's modelDescription declares (slots past n_states read 0)."""
    names = {v.name for v in md.modelVariables}
    k = 0
    while f"est_x_{k + 1}" in names:
        k += 1
    if k == 0:
        raise ValueError("the FMU declares no est_x_1 output: not an entrynav navigation FMU")
    return k


def output_names(slots):
    """The FMU outputs a run records, for an FMU with `slots` state slots."""
    names = ["nav_time", "nav_status", "n_states", "truth_stop", "nees", "nees_dof", "truth_r", "truth_v"]
    for i in range(1, slots + 1):
        names += [f"est_x_{i}", f"est_sigma_{i}", f"truth_x_{i}", f"err_{i}"]
    return names + [f"est_{s}" for s in SPHERICAL]


def _fixed_pos_vel(x):
    """Planet-fixed position and velocity [..., 3] of spherical states x = (r, lon, lat, v, fpa, heading)."""
    import numpy as np

    r, lon, lat, v, fpa, hd = (x[:, k] for k in range(6))
    so, co, sa, ca = np.sin(lon), np.cos(lon), np.sin(lat), np.cos(lat)
    east = np.stack([-so, co, np.zeros_like(so)], axis=1)
    north = np.stack([-sa * co, -sa * so, ca], axis=1)
    up = np.stack([ca * co, ca * so, sa], axis=1)
    vel = (v * np.cos(fpa) * np.sin(hd))[:, None] * east + (v * np.cos(fpa) * np.cos(hd))[:, None] * north \
        + (v * np.sin(fpa))[:, None] * up
    return r[:, None] * up, vel


def _num(x):
    """A JSON/CSV-safe float: None for NaN and infinities."""
    x = float(x)
    return x if math.isfinite(x) else None


def summarize_run(res, filter_name, run, seed):
    """One summary row from a run's recorded outputs (a structured array, one row per sample)."""
    import numpy as np

    n = int(res["n_states"][-1])
    coords = "spherical" if all(np.array_equal(res[f"est_x_{k + 1}"], res[f"est_{s}"])
                                for k, s in enumerate(SPHERICAL)) else "cartesian"
    names = (SPHERICAL_STATES if coords == "spherical" else CARTESIAN_STATES) + [f"aug{i}" for i in range(1, n - 5)]

    def col(prefix):
        return np.stack([np.asarray(res[f"{prefix}_{i + 1}"], dtype=float) for i in range(n)], axis=1)

    est, truth, err, sigma = col("est_x"), col("truth_x"), col("err"), col("est_sigma")
    if coords == "spherical":
        pe, ve = _fixed_pos_vel(est)
        pt, vt = _fixed_pos_vel(truth)
        pos, vel = np.linalg.norm(pe - pt, axis=1), np.linalg.norm(ve - vt, axis=1)
    else:
        pos, vel = np.linalg.norm(err[:, 0:3], axis=1), np.linalg.norm(err[:, 3:6], axis=1)
    t = np.asarray(res["nav_time"], dtype=float)
    epochs = np.flatnonzero(np.diff(t) > 0) + 1  # samples where a new measurement epoch was processed
    row = {"filter": filter_name, "run": run, "fmu_seed": seed, "coordinates": coords, "states": names,
           "n_epochs": int(len(epochs)), "nav_status": int(res["nav_status"][-1]),
           "failed": bool(res["nav_status"][-1] == 2), "truth_stop": int(res["truth_stop"][-1]),
           "truth_r0_m": _num(res["truth_r"][0]), "truth_v0_mps": _num(res["truth_v"][0]),
           "pos_initial_m": _num(pos[0])}
    e, s = err[epochs], sigma[epochs]
    finite = np.isfinite(e)
    inside = finite & (np.abs(e) <= 3.0 * s)
    last = epochs[-1] if len(epochs) else None
    for i, name in enumerate(names):
        m = finite[:, i]
        row[f"rms_{name}"] = _num(np.sqrt(np.mean(e[m, i] ** 2))) if m.any() else None
        row[f"final_{name}"] = _num(err[last, i]) if last is not None else None
        row[f"within3_{name}"] = _num(inside[:, i].sum() / m.sum()) if m.any() else None
    row["within3_all"] = _num(inside.sum() / finite.sum()) if finite.any() else None
    for name, v in (("pos_m", pos), ("vel_mps", vel)):
        row[f"rms_{name}"] = _num(np.sqrt(np.mean(v[epochs] ** 2))) if len(epochs) else None
        row[f"final_{name}"] = _num(v[last]) if last is not None else None
    nees = np.asarray(res["nees"], dtype=float)[epochs]
    row["nees_mean"] = _num(np.mean(nees[np.isfinite(nees)])) if np.isfinite(nees).any() else None
    row["nees_dof"] = int(res["nees_dof"][last]) if last is not None else 0
    return row


def simulate_batch(fmu_path, scenario, filter_name, seed, runs, stop_time, step, dispersed):
    """Dask task: simulate runs `runs` (run indices) of one filter; returns their summary rows.

    Unpacks the FMU from `fmu_path` (readable on this worker) into a temporary folder, instantiates
    it once, and runs fmpy.simulate_fmu on that instance for every run, resetting it in between.
    """
    import shutil

    from fmpy import extract, instantiate_fmu, read_model_description, simulate_fmu

    log = []

    def logger(component, instance, status, category, message):
        if status >= 1:  # warning, discard, error, fatal
            log.append(message.decode(errors="replace") if isinstance(message, bytes) else str(message))

    unzipdir = extract(fmu_path)
    try:
        md = read_model_description(unzipdir)
        slots = state_slots(md)
        fmu = instantiate_fmu(unzipdir, md, "CoSimulation", logger=logger)
        rows = []
        try:
            for k in runs:
                s = fmu_seed(seed, k)
                start = {"scenario": scenario, "filter": filter_name, "seed": s, "dispersed": dispersed}
                del log[:]
                try:
                    res = simulate_fmu(unzipdir, model_description=md, fmu_instance=fmu, start_values=start,
                                       start_time=0.0, stop_time=stop_time, output_interval=step,
                                       output=output_names(slots))
                except Exception as e:
                    raise RuntimeError(f"{filter_name} run {k} (FMU seed {s}) failed: {e}"
                                       + "".join(f"\n  {m}" for m in log)) from None
                rows.append(summarize_run(res, filter_name, k, s))
                fmu.reset()
        finally:
            fmu.freeInstance()
            fmu.freeLibrary()
        return rows
    finally:
        shutil.rmtree(unzipdir, ignore_errors=True)


# ------------------------------------------------------------------------------------------------
# FMU mode: the client


def _rms(values):
    v = [x for x in values if x is not None]
    return math.sqrt(math.fsum(x * x for x in v) / len(v)) if v else None


def _mean(values):
    v = [x for x in values if x is not None]
    return math.fsum(v) / len(v) if v else None


def aggregate(rows):
    """Per-filter summary of one filter's rows (sorted by run index)."""
    first = rows[0]
    if any(r["states"] != first["states"] for r in rows):
        raise RuntimeError(f"{first['filter']}: runs disagree on the filter's states")
    names = first["states"] + ["pos_m", "vel_mps"]
    return {
        "filter": first["filter"],
        "runs": len(rows),
        "failed": sum(r["failed"] for r in rows),
        "coordinates": first["coordinates"],
        "states": first["states"],
        "epochs_mean": _mean([r["n_epochs"] for r in rows]),
        "rmse_time_avg": {n: _rms(r[f"rms_{n}"] for r in rows) for n in names},
        "rmse_final": {n: _rms(r[f"final_{n}"] for r in rows) for n in names},
        "pos_initial_rms_m": _rms(r["pos_initial_m"] for r in rows),
        "within_3sigma": {n: _mean([r[f"within3_{n}"] for r in rows]) for n in first["states"]},
        "within_3sigma_all": _mean([r["within3_all"] for r in rows]),
        "nees_mean": _mean([r["nees_mean"] for r in rows]),
        "nees_dof": first["nees_dof"],
    }


def fmu_study(fmu_path, scenario, filters, runs, seed=1, stop_time=None, step=None, dispersed=True,
              batch_size=None, client=None):
    """Simulate `runs` runs of each filter; returns (summary, rows).

    With a Dask `client` every (filter, batch of runs) is a task; without one the same batches run
    here, one after another. Either way the rows are sorted by (filter, run) before reducing.
    """
    from fmpy import read_model_description

    fmu_path = str(Path(fmu_path).resolve())
    md = read_model_description(fmu_path)
    exp = md.defaultExperiment
    stop_time = float(stop_time if stop_time is not None else exp.stopTime)
    step = float(step if step is not None else exp.stepSize)
    if batch_size is None:
        n_workers = len(client.scheduler_info().get("workers", {})) if client is not None else 1
        batch_size = max(1, math.ceil(runs / (2 * max(1, n_workers))))
    batches = [list(range(b, min(b + batch_size, runs))) for b in range(0, runs, batch_size)]
    tasks = [(fmu_path, scenario, f, seed, b, stop_time, step, dispersed) for f in filters for b in batches]
    if client is None:
        results = [simulate_batch(*t) for t in tasks]
    else:
        futures = [client.submit(simulate_batch, *t, pure=False, key=f"entrynav-fmu-{t[2]}-runs-{t[4][0]}-{t[4][-1]}")
                   for t in tasks]
        results = client.gather(futures)
    rows = sorted((r for batch in results for r in batch), key=lambda r: (filters.index(r["filter"]), r["run"]))
    summary = {
        "mode": "fmu",
        "model": md.modelName,
        "guid": md.guid,
        "scenario": scenario,
        "seed": seed,
        "seed_rule": "run k uses FMU seed = run_seed(seed, k) >> 33 (entrynav's splitmix64 run seed)",
        "dispersed": dispersed,
        "runs": runs,
        "stop_time_s": stop_time,
        "step_s": step,
        "filters": [aggregate([r for r in rows if r["filter"] == f]) for f in filters],
    }
    return summary, rows


def write_rows_csv(rows, path):
    """One line per (filter, run); the per-state columns of every filter, empty where undefined."""
    cols = []
    for r in rows:
        cols += [k for k in r if k != "states" and k not in cols]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow(["" if r.get(c) is None else repr(r[c]) if isinstance(r[c], float) else r[c] for c in cols])


# ------------------------------------------------------------------------------------------------


@contextmanager
def dask_client(scheduler, workers):
    """A Client of `scheduler`, or of a LocalCluster of `workers` one-thread processes."""
    from dask.distributed import Client, LocalCluster

    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scenario", required=True, help="built-in name or TOML file (FMU mode: the FMU's scenario parameter)")
    p.add_argument("--filters", default="ekf")
    p.add_argument("--runs", type=int, required=True)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--scheduler", default=None, help="tcp://HOST:PORT of a Dask scheduler (default: LocalCluster)")
    p.add_argument("--workers", type=int, default=2, help="LocalCluster workers (one thread each)")
    p.add_argument("--json", required=True, help="summary JSON")
    cli = p.add_argument_group("engine mode")
    cli.add_argument("--engine", choices=["package", "cli"], default="package",
                     help="run shards in the workers' processes with the Python package (default) or with the CLI")
    cli.add_argument("--shards", type=int, default=None, help="number of shards (default: 2 x workers)")
    cli.add_argument("--set", dest="sets", action="append", default=[], metavar="PATH=VALUE")
    cli.add_argument("--entrynav", default=os.environ.get("ENTRYNAV", "entrynav"), help="path of the entrynav binary")
    cli.add_argument("--csv-dir", default=None)
    cli.add_argument("--keep-shards", default=None, help="directory to keep the shard files in")
    fm = p.add_argument_group("FMU mode")
    fm.add_argument("--fmu", default=None, help="MarsEntryNav.fmu (readable at this path on every worker)")
    fm.add_argument("--stop-time", type=float, default=None, help="[s] (default: the FMU's default experiment)")
    fm.add_argument("--step", type=float, default=None, help="communication step [s] (default: the FMU's default experiment)")
    fm.add_argument("--nominal", action="store_true", help="nominal truth (dispersed = false)")
    fm.add_argument("--batch-size", type=int, default=None, help="runs per task (default: runs / (2 x workers))")
    fm.add_argument("--csv", default=None, help="per-run rows")
    a = p.parse_args(argv)
    if a.runs < 1:
        p.error("--runs must be at least 1")
    if a.fmu:
        wrong = [o for o, v in (("--shards", a.shards), ("--set", a.sets), ("--csv-dir", a.csv_dir),
                                ("--keep-shards", a.keep_shards)) if v]
        if wrong:
            p.error(f"{', '.join(wrong)}: engine mode only, not with --fmu")
        if not Path(a.fmu).is_file():
            p.error(f"--fmu {a.fmu}: no such file")
        if a.batch_size is not None and a.batch_size < 1:
            p.error("--batch-size must be at least 1")
        filters = [f.strip() for f in a.filters.split(",") if f.strip()]
        if not filters or len(set(filters)) != len(filters):
            p.error("--filters: a comma-separated list of distinct filters")
    else:
        wrong = [o for o, v in (("--stop-time", a.stop_time), ("--step", a.step), ("--nominal", a.nominal),
                                ("--batch-size", a.batch_size), ("--csv", a.csv)) if v is not None and v is not False]
        if wrong:
            p.error(f"{', '.join(wrong)}: FMU mode only (give --fmu)")
        if a.shards is not None and a.shards < 1:
            p.error("--shards must be at least 1")

    with dask_client(a.scheduler, a.workers) as client:
        if not a.fmu:
            return cli_study(a, client)
        summary, rows = fmu_study(a.fmu, a.scenario, filters, a.runs, a.seed, a.stop_time, a.step,
                                  not a.nominal, a.batch_size, client)
    Path(a.json).parent.mkdir(parents=True, exist_ok=True)
    Path(a.json).write_text(json.dumps(summary, indent=1) + "\n")
    if a.csv:
        Path(a.csv).parent.mkdir(parents=True, exist_ok=True)
        write_rows_csv(rows, a.csv)
    for f in summary["filters"]:
        fin, avg = f["rmse_final"], f["rmse_time_avg"]
        print(f"{f['filter']:>9}: {f['runs']} runs, {f['failed']} failed; position RMSE final "
              f"{fin['pos_m']:.1f} m (time-avg {avg['pos_m']:.1f} m, start {f['pos_initial_rms_m']:.1f} m); "
              f"inside 3 sigma {f['within_3sigma_all']:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
