#!/usr/bin/env python3
"""Benchmark `entrynav optimize orbiters` against scipy's differential_evolution on the same
objective and the same trajectory.

For each seed the script
  1. runs `entrynav optimize orbiters --export-trajectory` (wall time measured around the process),
  2. reads the exported trajectory (inertial vehicle positions, trapezoid weights) and the
     objective's constants from the CSV header,
  3. re-implements the objective in numpy: orbiters on circular orbits (seed 002 eq. 55-56),
     line of sight by eq. 58-60, integrand det(N3) = [n1.(n2 x n3)]^2 (or ln max(det F, floor)
     for other counts), trapezoid rule, cost = -J + penalty * integral of the horizon violation,
  4. checks that the numpy objective reproduces entrynav's value at entrynav's optimum,
  5. runs scipy.optimize.differential_evolution on the numpy objective (same bounds, seeded) and
     reports value, evaluations and wall time beside entrynav's.

Usage:
  .venv/bin/python scripts/bench_orbiters_vs_scipy.py [--seeds 1 2 3] [--entrynav target/release/entrynav]
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.optimize import differential_evolution


def read_export(path: Path):
    """The `# key = value` header and the numeric rows (t_s, x_m, y_m, z_m, weight_s)."""
    consts, rows = {}, []
    for line in path.read_text().splitlines():
        if line.startswith("#"):
            body = line[1:].strip()
            if "=" in body:
                k, v = (s.strip() for s in body.split("=", 1))
                consts[k] = v
        elif line and not line.startswith("t_s"):
            rows.append([float(c) for c in line.split(",")])
    return consts, np.array(rows)


class Objective:
    """The orbiter objective of entrynav_optimizer::orbiters, vectorised over candidates."""

    def __init__(self, consts: dict, data: np.ndarray):
        self.mu = float(consts["mu_m3s2"])
        self.R = float(consts["radius_m"])
        self.alt = float(consts["altitude_m"])
        self.n = int(consts["orbiters"])
        self.kind = consts["objective"]
        self.penalty = float(consts["penalty_per_rad_s"])
        self.floor = float(consts["log_det_floor"])
        self.t = data[:, 0]
        self.v = data[:, 1:4]  # (T, 3)
        self.w = data[:, 4]
        self.rho = self.R + self.alt
        self.mean_motion = math.sqrt(self.mu / self.rho**3)
        vn = np.linalg.norm(self.v, axis=1)
        self.theta0 = np.arccos(np.clip(self.R / vn, -1.0, 1.0))  # (T,)
        self.theta1 = math.acos(min(1.0, self.R / self.rho))
        self.evaluations = 0

    def positions(self, x: np.ndarray) -> np.ndarray:
        """x: (3n, S) -> orbiter positions (S, n, T, 3)."""
        x = x.reshape(self.n, 3, -1)
        raan, inc, f = x[:, 0, :].T, x[:, 1, :].T, x[:, 2, :].T  # (S, n)
        so, co = np.sin(raan), np.cos(raan)
        si, ci = np.sin(inc), np.cos(inc)
        P = np.stack([co, so, np.zeros_like(co)], axis=-1)  # (S, n, 3)
        Q = np.stack([-so * ci, co * ci, si], axis=-1)
        u = f[..., None] + self.mean_motion * self.t  # (S, n, T)
        return self.rho * (np.cos(u)[..., None] * P[:, :, None, :]
                           + np.sin(u)[..., None] * Q[:, :, None, :])

    def evaluate(self, x: np.ndarray):
        """Returns (value J, violation [rad s], cost) arrays of shape (S,)."""
        x = np.asarray(x, dtype=float).reshape(3 * self.n, -1)
        b = self.positions(x)  # (S, n, T, 3)
        v = self.v[None, None, :, :]
        cross = np.cross(v, b)
        theta = np.arctan2(np.linalg.norm(cross, axis=-1), np.sum(v * b, axis=-1))  # (S, n, T)
        margin = self.theta0 + self.theta1 - theta
        visible = margin > 0.0
        d = v - b
        nvec = d / np.linalg.norm(d, axis=-1, keepdims=True)
        nvec = np.where(visible[..., None], nvec, 0.0)
        if self.kind == "integral-det-N3":
            triple = np.einsum("stk,stk->st", nvec[:, 0], np.cross(nvec[:, 1], nvec[:, 2]))
            g = np.where(visible.all(axis=1), triple**2, 0.0)
        else:
            F = np.einsum("sntk,sntl->stkl", nvec, nvec)
            g = np.log(np.maximum(np.linalg.det(F), self.floor))
        value = g @ self.w
        violation = np.maximum(-margin, 0.0).sum(axis=1) @ self.w
        self.evaluations += x.shape[1]
        return value, violation, -value + self.penalty * violation

    def cost(self, x: np.ndarray):
        x = np.asarray(x, dtype=float)
        if x.ndim == 1:
            return float(self.evaluate(x[:, None])[2][0])
        return self.evaluate(x)[2]


def run_entrynav(exe: Path, scenario: str, seed: int, out: Path):
    traj, js = out / f"traj-{seed}.csv", out / f"ours-{seed}.json"
    t0 = time.perf_counter()
    subprocess.run([str(exe), "optimize", "orbiters", "--scenario", scenario, "--seed", str(seed),
                    "--objective", "det-n3", "--no-check",
                    "--quiet", "--json", str(js), "--export-trajectory", str(traj)],
                   check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    return traj, json.loads(js.read_text()), wall


def main() -> int:
    root = Path(__file__).resolve().parent.parent
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--entrynav", type=Path, default=root / "target/release/entrynav")
    ap.add_argument("--scenario", default="orbiters-3")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--popsize", type=int, default=15)
    ap.add_argument("--maxiter", type=int, default=1000)
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--json", type=Path, help="write the results here")
    args = ap.parse_args()
    if not args.entrynav.exists():
        print(f"{args.entrynav} not found: build with `cargo build --release`", file=sys.stderr)
        return 2
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        for seed in args.seeds:
            traj, ours, ours_wall = run_entrynav(args.entrynav, args.scenario, seed, out)
            consts, data = read_export(traj)
            obj = Objective(consts, data)
            # Same function: our optimum evaluated in numpy.
            x_ours = np.array([math.radians(e[k]) for e in ours["elements"]
                               for k in ("raan_deg", "inc_deg", "true_anomaly_deg")])
            v_check = float(obj.evaluate(x_ours[:, None])[0][0])
            rel = abs(v_check - ours["value"]) / abs(ours["value"])
            if rel > 1e-9:
                print(f"objective mismatch: numpy {v_check} vs entrynav {ours['value']}",
                      file=sys.stderr)
                return 1
            obj.evaluations = 0
            bounds = [(0.0, 2 * math.pi), (0.0, math.pi), (0.0, 2 * math.pi)] * obj.n
            t0 = time.perf_counter()
            res = differential_evolution(obj.cost, bounds, seed=seed, popsize=args.popsize,
                                         maxiter=args.maxiter, tol=args.tol, polish=True,
                                         vectorized=True, updating="deferred")
            de_wall = time.perf_counter() - t0
            de_evals = obj.evaluations  # candidates evaluated (scipy's nfev counts batches)
            de_value, de_viol, _ = obj.evaluate(res.x[:, None])
            rows.append({
                "seed": seed,
                "entrynav_value": ours["value"],
                "entrynav_evaluations": ours["evaluations"],
                "entrynav_search_s": ours["elapsed_s"],
                "entrynav_process_wall_s": ours_wall,
                "scipy_value": float(de_value[0]),
                "scipy_violation_rad_s": float(de_viol[0]),
                "scipy_evaluations": de_evals,
                "scipy_nfev": int(res.nfev),
                "scipy_wall_s": de_wall,
                "scipy_message": str(res.message),
                "numpy_check_rel_error": rel,
            })
            r = rows[-1]
            print(f"seed {seed}: entrynav {r['entrynav_value']:.3f} "
                  f"({r['entrynav_evaluations']} evals, {r['entrynav_search_s']:.2f} s search, "
                  f"{r['entrynav_process_wall_s']:.2f} s process) | scipy DE "
                  f"{r['scipy_value']:.3f} ({r['scipy_evaluations']} evals, "
                  f"{r['scipy_wall_s']:.2f} s) | numpy check {rel:.1e}", flush=True)
    print()
    print("| seed | entrynav J | evals | wall [s] | scipy DE J | evals | wall [s] |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['seed']} | {r['entrynav_value']:.3f} | {r['entrynav_evaluations']} | "
              f"{r['entrynav_process_wall_s']:.2f} | {r['scipy_value']:.3f} | "
              f"{r['scipy_evaluations']} | {r['scipy_wall_s']:.2f} |")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"scenario": args.scenario, "popsize": args.popsize,
                                         "maxiter": args.maxiter, "tol": args.tol,
                                         "runs": rows}, indent=2) + "\n")
        print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
