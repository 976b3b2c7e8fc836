#!/usr/bin/env bash
# Re-run every trade study quoted in docs/results.md; outputs go to docs/results/ (JSON + CSV).
# Takes ~10 minutes on 2 idle cores (24 min at load average 6). Usage: scripts/reproduce_papers.sh [--quick]  (quick = 1/10 runs)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -z "${ENTRYNAV:-}" ]; then
  cargo build --release --quiet --bin entrynav
fi
E=${ENTRYNAV:-target/release/entrynav}
OUT=docs/results
mkdir -p "$OUT"
scale=1
[ "${1:-}" = "--quick" ] && scale=10
runs() { echo $(( $1 / scale )); }

t() { echo "== $*"; "$E" trade --quiet "$@"; }

# Seed 000: 5000 runs, EKF vs CI vs DCIFAIF, without and with the orbiter-2 fault.
t --scenario four-beacon-fusion --filters ekf,ci,dcifaif --runs "$(runs 5000)" --seed 1 --json "$OUT/four-beacon-fusion.json" --csv-dir "$OUT/csv"
t --scenario four-beacon-fusion-fault --filters ekf,ci,dcifaif --runs "$(runs 5000)" --seed 1 --json "$OUT/four-beacon-fusion-fault.json" --csv-dir "$OUT/csv"
# Seed 000's filters as printed (8 states, unestimated bias, printed P0/Q/R, CI-bound feedback).
t --scenario four-beacon-fusion-paper --filters ekf,ci,dcifaif --runs "$(runs 1000)" --seed 1 --json "$OUT/four-beacon-fusion-paper.json"
# The recommended filters with the standard (non-iterated) EKF update: the overconfident start.
t --scenario four-beacon-fusion --set filter.update_iterations=1 --filters ekf,dcifaif --runs "$(runs 1000)" --seed 1 --json "$OUT/four-beacon-fusion-one-iteration.json"

# Seed 003: 1000 runs with dispersed density bias; and the special case Delta = 0.095.
t --scenario msl-pressure --filters ekf,mmae,mmae-moe --runs "$(runs 1000)" --seed 1 --json "$OUT/msl-pressure.json" --csv-dir "$OUT/csv"
t --scenario msl-pressure-orbiter --filters ekf,mmae,mmae-moe --runs "$(runs 1000)" --seed 1 --json "$OUT/msl-pressure-orbiter.json" --csv-dir "$OUT/csv"
t --scenario msl-pressure-orbiter --set dispersions.density_bias=0 --filters ekf --runs "$(runs 1000)" --seed 1 --json "$OUT/msl-pressure-orbiter-no-bias.json"
special=(--set truth.density_bias=0.095 --set dispersions.density_bias=0 --set 'dispersions.initial.position_km=[0.0,0.0,0.0]'
         --set 'dispersions.initial.velocity_mps=[0.0,0.0,0.0]' --set filter.sample_initial_from_p0=false)
t --scenario msl-pressure "${special[@]}" --filters mmae,mmae-moe --runs 20 --seed 1 --json "$OUT/msl-pressure-delta0095-paper-p0.json" --csv-dir "$OUT/csv-delta0095-paper-p0"
t --scenario msl-pressure "${special[@]}" --set 'filter.p0_diag=[1.0,1.0,1.0,1e-4,1e-4,1e-4,1.1111e-3]' --filters mmae,mmae-moe --runs 20 --seed 1 --json "$OUT/msl-pressure-delta0095-known-state.json" --csv-dir "$OUT/csv-delta0095-known-state"
t --scenario msl-pressure-orbiter "${special[@]}" --set 'filter.p0_diag=[1.0,1.0,1.0,1e-4,1e-4,1e-4,1.1111e-3]' --filters ekf,mmae,mmae-moe --runs 20 --seed 1 --json "$OUT/msl-pressure-orbiter-delta0095.json" --csv-dir "$OUT/csv-delta0095-orbiter"

# Seed 002: ground beacons (Table 4 initial errors, 100 m range noise) and orbiters (500 runs).
t --scenario ground-beacons-3 --filters ekf,ukf --runs "$(runs 500)" --seed 1 --json "$OUT/ground-beacons-3.json" --csv-dir "$OUT/csv"
t --scenario orbiters-3 --filters ekf,ukf --runs "$(runs 500)" --seed 1 --json "$OUT/orbiters-3.json" --csv-dir "$OUT/csv"

# Seed 001: density adaptation, Tables 5 and 6 (1000 runs); see docs/density.md.
t --scenario msl-airdata --filters ukf-cm,ukf-ac,uskf-nn --runs "$(runs 1000)" --seed 1 --json "$OUT/msl-airdata.json" --csv-dir "$OUT/csv"
t --scenario msl-airdata-paper --filters ukf-cm,ukf-ac,uskf-nn --runs "$(runs 1000)" --seed 1 --json "$OUT/msl-airdata-paper.json"

# Consistency of every built-in with every filter it supports (200 runs each): docs/results.md.
ENTRYNAV="$E" python3 scripts/consistency_table.py "$(runs 200)" "$OUT/consistency" > "$OUT/consistency.md"
