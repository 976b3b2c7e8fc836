#!/usr/bin/env python3
"""Consistency of every built-in scenario with every filter it supports, as a markdown table.

Usage: scripts/consistency_table.py [RUNS] [OUT_DIR]   (defaults: 200 runs, docs/results/consistency)
The entrynav binary is $ENTRYNAV or target/release/entrynav. Each scenario's trade JSON is written
to OUT_DIR/<scenario>.json; the table (docs/results.md, "Consistency of every built-in") goes to
stdout. $SCENARIOS (comma-separated names) limits it to those built-ins. A filter "fits" a scenario when a one-run trade accepts it (e.g. fusion needs several
beacons, the banks need a density-bias grid, ukf-ac/uskf-nn need density measurements).
"""
import json
import os
import subprocess
import sys

BIN = os.environ.get("ENTRYNAV", "target/release/entrynav")
RUNS = sys.argv[1] if len(sys.argv) > 1 else "200"
OUT = sys.argv[2] if len(sys.argv) > 2 else "docs/results/consistency"
FILTERS = ["ekf", "ukf", "ci", "dcifaif", "mmae", "mmae-moe", "ukf-cm", "ukf-ac", "uskf-nn"]


def run(*args, check=False):
    return subprocess.run([BIN, *args], capture_output=True, text=True, check=check)


def fmt(v):
    return "-" if v is None else f"{v:.3g}"


def pct(v):
    return "-" if v is None else f"{100 * v:.0f} %"


def main():
    os.makedirs(OUT, exist_ok=True)
    scenarios = [line.split()[0] for line in run("scenarios", check=True).stdout.splitlines() if line.strip()]
    only = os.environ.get("SCENARIOS")
    if only:
        scenarios = [sc for sc in scenarios if sc in only.split(",")]
    rows = []
    for sc in scenarios:
        fits = [f for f in FILTERS
                if run("trade", "--scenario", sc, "--filters", f, "--runs", "1", "--quiet").returncode == 0]
        if not fits:
            continue
        path = os.path.join(OUT, f"{sc}.json")
        print(f"== {sc}: {','.join(fits)} ({RUNS} runs)", file=sys.stderr)
        run("trade", "--scenario", sc, "--filters", ",".join(fits), "--runs", RUNS, "--seed", "1",
            "--quiet", "--json", path, check=True)
        with open(path) as fh:
            result = json.load(fh)
        for fr in result["filters"]:
            dof = fr["nees_dof"]
            anees = fr.get("anees")
            kin = fr.get("anees_kinematic")
            rows.append("| {} | {} | {} ({}) | {} | {} | {} | {} | {} / {} | {} |".format(
                sc, fr["name"], fmt(anees / dof if anees is not None else None), dof,
                pct(fr.get("nees_in_bounds_frac")), fmt(kin / 6 if kin is not None else None),
                fmt(fr.get("anis_per_dof")), pct(fr.get("nis_in_bounds_frac")),
                fr["failed"], fr["diverged"], fmt(fr["rmse_time_avg"].get("pos_m"))))
    print("| scenario | filter | ANEES/dof (dof) | epochs in NEES band | kinematic ANEES/dof "
          "| ANIS/dof | epochs in NIS band | failed / diverged | pos RMSE avg [m] |")
    print("|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
