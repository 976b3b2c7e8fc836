#!/usr/bin/env python3
"""Run an entrynav trade study on a Dask cluster and merge it.

The study is split into shards (`entrynav trade --shard I/N`); each shard is a Dask task that
runs the entrynav CLI on a worker and returns the shard file's contents; the client merges them
with `entrynav trade merge`, which reproduces the single-process result exactly.

    scripts/dask_trade.py --scenario four-beacon-fusion --filters ekf,ci,dcifaif --runs 5000 \
        --shards 8 --json out/study.json                      # LocalCluster on this machine
    scripts/dask_trade.py ... --scheduler tcp://HOST:8786     # a real cluster

Every worker needs the `entrynav` binary (same version) on its PATH or at --entrynav.
Scenario files given by path must be readable at the same path on the workers.
"""

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path


def run_shard(entrynav, scenario, filters, runs, seed, index, count, sets):
    """Dask task: run one shard with the CLI and return the shard file's text."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / f"shard{index}.json"
        cmd = [entrynav, "trade", "--scenario", scenario, "--filters", filters, "--runs", str(runs),
               "--seed", str(seed), "--shard", f"{index}/{count}", "--json", str(out), "--quiet"]
        for s in sets:
            cmd += ["--set", s]
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=24 * 3600)
        if res.returncode != 0:
            raise RuntimeError(f"shard {index}/{count} failed: {res.stderr.strip()}")
        return out.read_text()


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scenario", required=True)
    p.add_argument("--filters", default="ekf")
    p.add_argument("--runs", type=int, required=True)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--shards", type=int, default=None, help="number of shards (default: 2 x workers)")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="PATH=VALUE")
    p.add_argument("--scheduler", default=None, help="tcp://HOST:PORT of a Dask scheduler (default: LocalCluster)")
    p.add_argument("--workers", type=int, default=2, help="LocalCluster workers (one thread each)")
    p.add_argument("--entrynav", default=os.environ.get("ENTRYNAV", "entrynav"), help="path of the entrynav binary")
    p.add_argument("--json", required=True, help="merged summary JSON")
    p.add_argument("--csv-dir", default=None)
    p.add_argument("--keep-shards", default=None, help="directory to keep the shard files in")
    a = p.parse_args(argv)
    if a.runs < 1:
        p.error("--runs must be at least 1")

    from dask.distributed import Client, LocalCluster

    cluster = None
    if a.scheduler:
        client = Client(a.scheduler)
    else:
        cluster = LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
    try:
        n_workers = max(1, len(client.scheduler_info().get("workers", {})))
        count = a.shards or 2 * n_workers
        if count < 1:
            p.error("--shards must be at least 1")
        futures = [client.submit(run_shard, a.entrynav, a.scenario, a.filters, a.runs, a.seed, i, count, a.sets,
                                 pure=False, key=f"entrynav-shard-{i}-of-{count}") for i in range(count)]
        texts = client.gather(futures)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()

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
        res = subprocess.run(cmd, text=True)
        return res.returncode


if __name__ == "__main__":
    sys.exit(main())
