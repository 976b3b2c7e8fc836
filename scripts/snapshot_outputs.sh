#!/usr/bin/env bash
# Run a fixed set of entrynav commands and keep every file and standard output they write, so that
# two builds can be compared output for output (scripts/compare_outputs.py). For changes that must
# not move a result (a refactor): snapshot the old build and the new one, then compare.
#
# Usage: scripts/snapshot_outputs.sh OUT_DIR [ENTRYNAV] [FMU_LIB]
#   ENTRYNAV  the entrynav binary (default target/release/entrynav)
#   FMU_LIB   the FMU shared library for `fmu pack --lib` (default: the one next to ENTRYNAV)
# The set: a 100-run trade (JSON, CSV) of every built-in with every filter (a filter that does not
# fit keeps its refusal), plots and an HTML report, --method both and lincov, a shard/merge pair,
# compare, replay, a grid, tune, optimize ground / select / orbiters with their checks, observe,
# lincov, guidance deliver and reference, simulate, and the packed FMUs and SSPs (unpacked, without
# the copied shared library). Each command's standard output is NAME.stdout, its standard error
# NAME.stderr, its exit code NAME.rc.
set -uo pipefail
out="${1:?usage: snapshot_outputs.sh OUT_DIR [ENTRYNAV] [FMU_LIB]}"
bin="${2:-target/release/entrynav}"
bin="$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")"
lib="${3:-$(dirname "$bin")/libentrynav_fmu.so}"
[ -x "$bin" ] || { echo "snapshot: $bin is not an executable" >&2; exit 2; }
mkdir -p "$out" && [ -d "$out" ] || { echo "snapshot: cannot make the folder $out" >&2; exit 2; }
out="$(cd "$out" && pwd)" || exit 2
cd "$(dirname "$0")/.." || exit 2

# run NAME ARGS...: standard output to NAME.stdout, standard error to NAME.stderr, exit code to NAME.rc.
run() {
  local name="$1"
  shift
  "$bin" "$@" >"$out/$name.stdout" 2>"$out/$name.stderr"
  echo $? >"$out/$name.rc"
}

scenarios=$("$bin" scenarios | awk '{print $1}')
filters="ekf ukf ci dcifaif mmae mmae-moe ukf-cm ukf-ac uskf-nn"
mkdir -p "$out/trade"
for s in $scenarios; do
  for f in $filters; do
    run "trade/$s-$f" trade --scenario "$s" --filters "$f" --runs 100 --seed 1 --threads 2 --quiet \
      --json "$out/trade/$s-$f.json" --csv-dir "$out/trade/$s-$f-csv"
  done
done

mkdir -p "$out/study"
run study/plots trade --scenario four-beacon-fusion --filters ekf,ci,dcifaif --runs 40 --quiet \
  --plots "$out/study/plots" --report "$out/study/report.html" --json "$out/study/plots.json"
run study/guided trade --scenario msl-guided --filters ekf,uskf-nn --runs 30 --quiet \
  --plots "$out/study/guided-plots" --json "$out/study/guided.json"
run study/both trade --scenario four-beacon-fusion --filters ekf,dcifaif --runs 60 --method both --quiet \
  --json "$out/study/both.json" --plots "$out/study/both-plots"
run study/lincov-method trade --scenario orbiters-3 --filters ekf --method lincov \
  --json "$out/study/lincov-method.json" --csv-dir "$out/study/lincov-method-csv"
run study/shard0 trade --scenario orbiters-3 --runs 120 --shard 0/2 --json "$out/study/s0.json"
run study/shard1 trade --scenario orbiters-3 --runs 120 --shard 1/2 --json "$out/study/s1.json"
run study/merge trade merge "$out/study/s0.json" "$out/study/s1.json" --json "$out/study/merged.json"
run study/compare trade compare "$out/trade/four-beacon-fusion-ekf.json" \
  "$out/trade/four-beacon-fusion-fault-ekf.json" --json "$out/study/compare.json"
run study/compare-same trade compare "$out/trade/orbiters-3-ekf.json" "$out/study/merged.json"
run study/replay trade --scenario four-beacon-fusion --filters ekf,dcifaif --runs 10 --replay-run 3 \
  --csv-dir "$out/study/replay"
run study/grid trade --grid docs/examples/grid-four-beacon.toml --out-dir "$out/study/grid" --quiet \
  --report "$out/study/grid.html"

mkdir -p "$out/design"
run design/tune tune --scenario msl-pressure-orbiter --filter ekf,ukf --runs 6 --validation-runs 12 \
  --max-evaluations 20 --quiet --force --out "$out/design/tuned.toml"
run design/tune-orbiters tune --scenario orbiters-3 --filter ekf --runs 6 --validation-runs 12 \
  --max-evaluations 20 --tune-noise --quiet --out "$out/design/tuned-orbiters.toml"
run design/ground optimize ground --scenario ground-beacons-3 --quiet --check-runs 40 \
  --json "$out/design/ground.json" --write-scenario "$out/design/ground.toml"
run design/ground-mindelta optimize ground --scenario ground-beacons-3 --beacons 2 --objective min-delta \
  --quiet --no-check --json "$out/design/ground-mindelta.json"
run design/select optimize select --scenario ground-beacons-3 --k 3 --grid-deg 2 --exact --quiet \
  --check-runs 40 --json "$out/design/select.json" --write-scenario "$out/design/select.toml"
run design/orbiters optimize orbiters --scenario orbiters-3 --quiet --check-runs 40 \
  --json "$out/design/orbiters.json" --write-scenario "$out/design/orbiters.toml"
run design/observe observe --scenario four-beacon-fusion --step 10 --fim --json "$out/design/observe.json"
run design/observe-sub observe --scenario four-beacon-fusion --subsystems --step 20 \
  --json "$out/design/observe-sub.json"
run design/observe-pcrlb observe --scenario ground-beacons-3 --step 20 --pcrlb --runs 20
run design/lincov lincov --scenario four-beacon-fusion --filter ekf,ci,dcifaif \
  --json "$out/design/lincov.json" --csv-dir "$out/design/lincov-csv"
run design/lincov-mc lincov --scenario orbiters-3 --filter ekf --compare-mc 50 --threads 2 \
  --json "$out/design/lincov-mc.json"
run design/deliver guidance deliver --scenario msl-guided --filters ekf,uskf-nn --runs 40 --threads 2 \
  --json "$out/design/deliver.json"
run design/reference guidance reference --scenario msl-guided --csv "$out/design/reference.csv" \
  --json "$out/design/reference.json"
run design/simulate simulate --scenario four-beacon-fusion-fault --seed 5 --out "$out/design/simulate.csv"

mkdir -p "$out/fmu"
run fmu/pack2 fmu pack --out "$out/fmu/fmi2" --lib "$lib"
run fmu/pack3 fmu pack --out "$out/fmu/fmi3" --fmi 3 --lib "$lib"
run fmu/pack-specific fmu pack --out "$out/fmu/specific" --scenario msl-airdata --filter uskf-nn --lib "$lib"
run fmu/ssp fmu pack --out "$out/fmu/ssp" --ssp --lib "$lib"
# Unpack every FMU and SSP (nested ones too) and drop the copied shared libraries: what is compared
# is what entrynav generates (model descriptions, system structures, resources).
python3 - "$out/fmu" <<'PY'
import os, shutil, sys, zipfile
def unpack(folder):
    for root, _, files in os.walk(folder):
        for name in files:
            if name.endswith((".fmu", ".ssp")):
                path = os.path.join(root, name)
                target = path[:-4] + ".unzipped"
                zipfile.ZipFile(path).extractall(target)
                shutil.rmtree(os.path.join(target, "binaries"), ignore_errors=True)
                os.remove(path)
                unpack(target)
unpack(sys.argv[1])
PY
echo "snapshot: $(find "$out" -type f | wc -l) files in $out"
