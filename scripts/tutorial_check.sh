#!/usr/bin/env bash
# Run every command of docs/tutorial.md's ```sh blocks, in order, from the repository root.
# A line starting with "! " must fail (exit non-zero) — the tutorial shows refused input that way.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$PWD/target/release:$PATH"
mkdir -p out/tutorial
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
