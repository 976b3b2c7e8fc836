#!/usr/bin/env python3
"""Markdown tables for docs/results.md from `entrynav trade --json` summaries.

Usage: scripts/results_tables.py SUMMARY.json [...]          one accuracy/consistency table per file
       scripts/results_tables.py --pcrlb SUMMARY.json [...]  one RMSE/PCRLB/efficiency row per filter
       scripts/results_tables.py --split SUMMARY.json [...]  final position RMSE, horizontal / vertical
No third-party modules; reads only the documented summary fields.
"""
import json
import sys


def num(v, digits=4):
    if v is None:
        return "-"
    if v == 0:
        return "0"
    a = abs(v)
    if 1e-3 <= a < 1e5:
        return f"{v:.{digits}g}"
    return f"{v:.3e}"


def pct(v):
    return "-" if v is None else f"{100 * v:.0f} %"


def horizontal_vertical(f):
    """Final position RMSE split into horizontal (from the deployment ellipse: 3-sigma semi-axes and
    mean offset in the local horizontal plane) and vertical (the rest of the error-vector norm) [m]."""
    e, pos = f.get("ellipse_km"), f["rmse_final"].get("pos_m")
    if not e or pos is None:
        return None, None
    h2 = ((e["semi_major_km"] / 3) ** 2 + (e["semi_minor_km"] / 3) ** 2
          + e["mean_downrange_km"] ** 2 + e["mean_crossrange_km"] ** 2) * 1e6
    return h2 ** 0.5, max(pos * pos - h2, 0.0) ** 0.5


def split(path):
    """Final horizontal / vertical position RMSE per filter."""
    d = json.load(open(path))
    print(f"`{path}` — {d['scenario']}, {d['runs']} runs: final position error split\n")
    print("| filter | pos RMSE final [m] | horizontal [m] | vertical [m] | 3σ ellipse semi-axes [m] | major axis from downrange |")
    print("|---|---|---|---|---|---|")
    for f in d["filters"]:
        h, v = horizontal_vertical(f)
        e = f.get("ellipse_km") or {}
        print(f"| {f['name']} | {num(f['rmse_final'].get('pos_m'))} | {num(h)} | {num(v)} "
              f"| {num(1e3 * e.get('semi_major_km', float('nan')))} × {num(1e3 * e.get('semi_minor_km', float('nan')))} "
              f"| {num(e.get('orientation_deg'), 3)}° |")
    print()


def accuracy(path):
    d = json.load(open(path))
    print(f"`{path}` — {d['scenario']}, {d['runs']} runs, seed {d['seed']}\n")
    print("| filter | pos RMSE avg [m] | pos RMSE final [m] | vel RMSE final [m/s] | ANEES/dof (dof) "
          "| epochs in NEES band | ANIS/dof | failed / diverged |")
    print("|---|---|---|---|---|---|---|---|")
    for f in d["filters"]:
        dof = f["nees_dof"]
        anees = None if f["anees"] is None else f["anees"] / dof
        print(f"| {f['name']} | {num(f['rmse_time_avg'].get('pos_m'))} | {num(f['rmse_final'].get('pos_m'))} "
              f"| {num(f['rmse_final'].get('vel_mps'))} | {num(anees, 3)} ({dof}) | {pct(f['nees_in_bounds_frac'])} "
              f"| {num(f.get('anis_per_dof'), 3)} | {f['failed']} / {f['diverged']} |")
    print()


def pcrlb_rows(paths):
    print("| scenario | filter | pos RMSE avg / final [m] | pos PCRLB avg / final [m] | efficiency pos avg / final "
          "| vel RMSE final [m/s] | vel PCRLB final [m/s] | efficiency vel final |")
    print("|---|---|---|---|---|---|---|---|")
    for path in paths:
        d = json.load(open(path))
        b = d.get("pcrlb") or {}
        if not b.get("available"):
            print(f"| {d['scenario']} | (all) | | no bound: {b.get('reason', 'not computed')} | | | | |")
            continue
        for f in d["filters"]:
            ea, ef = f.get("efficiency_time_avg", {}), f.get("efficiency_final", {})
            print(f"| {d['scenario']} | {f['name']} "
                  f"| {num(f['rmse_time_avg'].get('pos_m'))} / {num(f['rmse_final'].get('pos_m'))} "
                  f"| {num(b['time_avg'].get('pos_m'))} / {num(b['final'].get('pos_m'))} "
                  f"| {num(ea.get('pos_m'), 3)} / {num(ef.get('pos_m'), 3)} "
                  f"| {num(f['rmse_final'].get('vel_mps'))} | {num(b['final'].get('vel_mps'))} "
                  f"| {num(ef.get('vel_mps'), 3)} |")
    print()


def main(argv):
    if not argv:
        print(__doc__, file=sys.stderr)
        return 2
    if argv[0] == "--pcrlb":
        pcrlb_rows(argv[1:])
    elif argv[0] == "--split":
        for p in argv[1:]:
            split(p)
    else:
        for p in argv:
            accuracy(p)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
