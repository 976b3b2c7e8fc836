#!/usr/bin/env bash
# Build the Python package (python/: PyO3 abi3 extension + pure-Python API) with maturin into
# target/wheels and install it into .venv (scripts/setup.sh makes .venv and installs maturin).
# The extension is a workspace member (python/), so it reuses the release build of the core.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x .venv/bin/maturin ] || { echo "build_python: run scripts/setup.sh first (.venv with maturin)" >&2; exit 1; }
rm -f target/wheels/entrynav-*.whl
(cd python && ../.venv/bin/maturin build --release --quiet --compatibility linux -o ../target/wheels)
.venv/bin/pip install --quiet --disable-pip-version-check --force-reinstall --no-deps target/wheels/entrynav-*.whl
echo "build_python: installed $(ls target/wheels/entrynav-*.whl) into .venv"
