#!/usr/bin/env bash
# Run every command of docs/tutorial.md's ```sh blocks, in order, from the repository root.
# A line starting with "! " must fail (exit non-zero) — the tutorial shows refused input that way.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$PWD/target/release:$PATH"
mkdir -p out/tutorial
# Start without the Python package, as a clean clone does: the tutorial must build what it uses.
if .venv/bin/python -c "import entrynav" >/dev/null 2>&1; then
  .venv/bin/pip uninstall --quiet --yes entrynav
  echo "tutorial: uninstalled the Python package first (a clean clone has none)"
fi
n=0
while IFS= read -r line; do
  n=$((n + 1))
  if [[ "$line" == "! "* ]]; then
    cmd="${line:2}"
    echo "tutorial (must fail): $cmd"
    if bash -c "$cmd" >/dev/null 2>&1; then echo "tutorial: expected failure but it succeeded: $cmd" >&2; exit 1; fi
  else
    echo "tutorial: $line"
    bash -c "$line" >/dev/null || { echo "tutorial: command failed: $line" >&2; exit 1; }
  fi
done < <(awk '/^```sh$/{f=1; next} /^```$/{f=0} f && NF' docs/tutorial.md)
echo "tutorial: $n commands ran as documented"
