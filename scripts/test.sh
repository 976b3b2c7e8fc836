#!/usr/bin/env bash
# The project's test command (README, CI): set up the machine, then format check, lint, tests.
set -euo pipefail
cd "$(dirname "$0")/.."
# Nothing here reads the terminal: tools that probe with `-` (rustc) get an empty input, never the caller's.
exec </dev/null

bash scripts/setup.sh

echo "== cargo fmt --check"
cargo fmt --all -- --check

echo "== cargo clippy (all targets, warnings are errors)"
cargo clippy --workspace --all-targets --release -- -D warnings

echo "== rustdoc of the library crates (broken links are errors)"
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps -p entrynav -p entrynav-loader -p entrynav-fmu -p entrynav-fmu-archive -p entrynav-fmi-host -p entrynav-devtools -p entrynav-optimizer -p entrynav-studies -p entrynav-render

echo "== cargo build (the binaries and the FMU library the option walks and the FMU tests run)"
cargo build --release --workspace

echo "== cargo test"
# Release profile: the Monte Carlo and property tests are numerical and run much faster optimised.
cargo test --workspace --release

echo "== the shipped density network is reproduced bit for bit by retraining (seed 001 Algorithm 1)"
# (--workspace keeps the feature set of the run above, so nothing is recompiled)
cargo test --workspace --release --test density_adaptation -- --ignored

echo "== input fuzzer, long mode: 2000 mutated scenarios and atmosphere tables (no panic, hang or silent refusal)"
ENTRYNAV_FUZZ_VARIANTS=2000 cargo test --workspace --release --test fuzz_inputs

echo "== benchmarks compile"
cargo bench --workspace --no-run

echo "== README main command, and README's sample of its output (\"Reading the demo's output\")"
# scripts/readme_sample.sh runs the trade command of README's first sh block as written there and
# compares its output with README's sample: every character but the wall time and the µs per step.
bash scripts/readme_sample.sh

echo "== docs: every relative link in README.md, ARCHITECTURE.md and docs/*.md resolves (file and #anchor)"
python3 scripts/check_doc_links.py

echo "== HTML report: a small trade's --report renders in headless Chromium (no console errors, not blank)"
bash scripts/check_report.sh

echo "== FMU: shared library, packed FMUs (MarsEntryNav, MarsEntryNavFilter, MarsEntryTruth, MarsEntryGuidance, MarsEntryNavGuided; FMI 2.0 and 3.0)"
# Before the Dask and tutorial steps: both load the packed MarsEntryNav.fmu (the library was built
# before the tests).
target/release/entrynav fmu pack --out target/fmu
target/release/entrynav fmu pack --out target/fmu --fmi 3
target/release/entrynav fmu pack --out target/fmu/fmi3-arrays --fmi 3 --arrays

echo "== Python package: build the wheel (maturin) and install it into .venv (the Dask engine path uses it)"
bash scripts/build_python.sh

echo "== Dask: sharded CLI study and fmpy FMU runs on a 2-worker LocalCluster equal the single-process results"
ENTRYNAV="$PWD/target/release/entrynav" ENTRYNAV_FMU="$PWD/target/fmu/MarsEntryNav.fmu" \
  .venv/bin/pytest -q -p no:cacheprovider tests/dask

echo "== docs/tutorial.md: every command runs as documented"
bash scripts/tutorial_check.sh

echo "== FMU: the shipped entrynav carries no FMI host: its fmu command only packs"
if target/release/entrynav fmu --help | grep -Eiq 'check|fuzz|cross-check|\brun\b'; then
  echo "entrynav fmu --help lists a test tool of entrynav-dev" >&2
  exit 1
fi
echo "== FMU (entrynav-dev, the developer tools): our host against the in-process library (bitwise), doStep benchmark"
for fmu in target/fmu/MarsEntryNav.fmu target/fmu/MarsEntryNavFilter.fmu target/fmu/MarsEntryTruth.fmu target/fmu/MarsEntryGuidance.fmu target/fmu/MarsEntryNavGuided.fmu; do
  target/release/entrynav-dev fmu check "$fmu"
done
target/release/entrynav-dev fmu check target/fmu/MarsEntryNav.fmu --bench
echo "== FMU: the fuzzer through the fmi3 functions, 100,000 calls per FMI 3.0 FMU with its arrays (exit 2 on any call the model does not predict; FMI 2.0: tests/python)"
for fmu in target/fmu/fmi3-arrays/MarsEntryNav-fmi3.fmu target/fmu/fmi3-arrays/MarsEntryNavFilter-fmi3.fmu target/fmu/fmi3-arrays/MarsEntryTruth-fmi3.fmu target/fmu/fmi3-arrays/MarsEntryNavGuided-fmi3.fmu; do
  target/release/entrynav-dev fmu fuzz "$fmu" --calls 100000
done

echo "== FMU: pytest (symbols, fmpy validate/simulate/FMU2Slave/FMU3Slave, fmutool, libcosimpy, fmusim, OMSimulator, entrynav-dev check and FMI 2.0 fuzz, guidance FMU, guided FMU and guided SSP)"
.venv/bin/pytest -q -s -p no:cacheprovider tests/python
