#!/usr/bin/env bash
# Install what entrynav's build and tests need on a fresh Debian machine with a Rust toolchain:
# apt packages (C toolchain, OpenBLAS/gfortran for clarabel's SDP cone, Python venv support; Chromium for the
# HTML report check, not with --build-only) and a
# Python virtual environment in .venv with the FMI tools the tests drive (fmpy, fmutool, libcosimpy)
# and Dask (distributed) for sharded trade studies.
# Idempotent: skips what is already present.
# Usage: scripts/setup.sh [--build-only]   (--build-only: the apt packages the Rust build needs, no
# Python tools; what the README's first command runs before `cargo run`).
set -euo pipefail
cd "$(dirname "$0")/.."
build_only=false
[ "${1:-}" = "--build-only" ] && build_only=true

need_apt=()
command -v gcc >/dev/null 2>&1 || need_apt+=(build-essential)
command -v pkg-config >/dev/null 2>&1 || need_apt+=(pkg-config)
command -v strip >/dev/null 2>&1 || need_apt+=(binutils)  # entrynav fmu pack strips the FMU library
command -v python3 >/dev/null 2>&1 || need_apt+=(python3 python3-venv)
[ -e /usr/lib/x86_64-linux-gnu/libopenblas.so ] || [ -e /usr/lib/libopenblas.so ] || need_apt+=(libopenblas-dev)
ls /usr/lib/gcc/x86_64-linux-gnu/*/libgfortran.so >/dev/null 2>&1 || need_apt+=(libgfortran-12-dev)
# Install the Debian packages named in the arguments (as root, or with sudo).
apt_install() {
  if [ "$(id -u)" -eq 0 ]; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null
  elif command -v sudo >/dev/null 2>&1; then
    sudo apt-get update -qq
    sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null
  else
    echo "setup: missing $*; install them (apt-get install $* as root)" >&2
    exit 1
  fi
}
if [ ${#need_apt[@]} -gt 0 ]; then
  apt_install "${need_apt[@]}"
  # openblas-src caches a failed library probe from a build before the packages existed: forget it.
  if [ -d target ] && command -v cargo >/dev/null 2>&1; then
    cargo clean --release -p openblas-src -p openblas-build >/dev/null 2>&1 || true
    cargo clean -p openblas-src -p openblas-build >/dev/null 2>&1 || true
  fi
fi

if ! command -v cargo >/dev/null 2>&1; then
  echo "setup: cargo not found; install a Rust toolchain (https://rustup.rs)" >&2
  exit 1
fi
for comp in rustfmt clippy; do
  if ! cargo "${comp/rustfmt/fmt}" --version >/dev/null 2>&1; then
    rustup component add "$comp"
  fi
done

if $build_only; then
  echo "setup: build prerequisites ready ($(cargo --version))"
  exit 0
fi

# Headless Chromium renders the HTML report in scripts/check_report.sh (test.sh).
command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 || apt_install chromium

# Independent FMI importers that are not in the registries may sit in ../shared/tools
# (ENTRYNAV_TOOLS overrides the folder); the tests use them when present and skip otherwise.
tools="${ENTRYNAV_TOOLS:-../shared/tools}"
# Reference-FMUs fmusim (FMI 2.0/3.0 reference importer) needs these libraries.
if [ -x "$tools/fmusim" ] && ! "$tools/fmusim" --version >/dev/null 2>&1; then
  apt_install libxml2 libminizip1 libsundials-cvode6
fi

# Python tools for the FMU and benchmark tests, pinned.
if [ ! -x .venv/bin/python ]; then
  python3 -m venv .venv
fi
if ! .venv/bin/python -c "import fmpy, libcosimpy, pytest, numpy, scipy, fmu_manipulation_toolbox, distributed, pandas, maturin, nbclient, nbformat, ipykernel, matplotlib" >/dev/null 2>&1; then
  .venv/bin/pip install --quiet --disable-pip-version-check \
    "fmpy==0.3.32" "fmu-manipulation-toolbox==2.0" "libcosimpy==0.0.6" pytest numpy scipy distributed \
    pandas "maturin==1.16.0" nbclient nbformat ipykernel matplotlib
fi
# OMSimulator 3 (OpenModelica's FMI/SSP engine) is not installable from PyPI here (its sdist downloads
# a binary from elsewhere); a wheel built from source may sit in ../shared/tools (ENTRYNAV_TOOLS
# overrides the folder). tests/python/test_omsimulator.py runs our FMUs in it, and skips without it.
oms_wheel=$(ls "$tools"/omsimulator-*.whl 2>/dev/null | head -n 1 || true)
if [ -n "$oms_wheel" ] && ! .venv/bin/python -c "import OMSimulator" >/dev/null 2>&1; then
  .venv/bin/pip install --quiet --disable-pip-version-check "$oms_wheel" lxml requests
fi
oms_note=$(.venv/bin/python -c "import OMSimulator" >/dev/null 2>&1 && echo ", OMSimulator" || echo ", no OMSimulator (its tests skip)")
echo "setup: toolchain ready ($(cargo --version)); python tools in .venv$oms_note"
