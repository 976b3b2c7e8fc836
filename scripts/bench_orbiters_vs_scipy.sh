#!/usr/bin/env bash
# Build the release CLI and compare `entrynav optimize orbiters` with scipy's differential_evolution
# on the same objective and trajectory (see bench_orbiters_vs_scipy.py). Extra arguments are passed on.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin entrynav
PY=.venv/bin/python
[ -x "$PY" ] || PY=python3
exec "$PY" scripts/bench_orbiters_vs_scipy.py "$@"
