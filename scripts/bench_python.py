#!/usr/bin/env python3
"""Benchmark: a 200-run trade from Python (`entrynav.trade`) against the same trade by the CLI
(`entrynav trade ... --json FILE`), median wall time of N repetitions each, alternating.

usage: .venv/bin/python scripts/bench_python.py [--runs 200] [--repeat 5] [--scenario four-beacon-fusion] [--filters ekf]
The CLI's time includes its process start and writing the JSON; Python's includes turning the
result into dicts. Prints both medians and their ratio."""
import argparse
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import entrynav

ROOT = Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--scenario", default="four-beacon-fusion")
    ap.add_argument("--filters", default="ekf")
    ap.add_argument("--cli", default=str(ROOT / "target" / "release" / "entrynav"))
    a = ap.parse_args()
    sc = entrynav.Scenario.builtin(a.scenario)
    filters = a.filters.split(",")
    py_t, cli_t = [], []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "s.json"
        for _ in range(a.repeat):
            t = time.perf_counter()
            entrynav.trade(sc, filters, runs=a.runs, seed=1)
            py_t.append(time.perf_counter() - t)
            t = time.perf_counter()
            subprocess.run([a.cli, "trade", "--scenario", a.scenario, "--filters", a.filters, "--runs", str(a.runs),
                            "--seed", "1", "--quiet", "--json", str(out)], check=True, capture_output=True)
            cli_t.append(time.perf_counter() - t)
    p, c = statistics.median(py_t), statistics.median(cli_t)
    print(f"{a.scenario} x {a.filters}, {a.runs} runs, median of {a.repeat}: "
          f"Python {p:.3f} s, CLI {c:.3f} s, Python/CLI {p / c:.3f}")


if __name__ == "__main__":
    main()
