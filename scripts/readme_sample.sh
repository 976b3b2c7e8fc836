#!/usr/bin/env bash
# README.md's sample output of the main command is generated, and checked, here.
#
# Runs the `entrynav trade …` command of README's first ```sh block exactly as written there
# (`cargo run --release --quiet --bin entrynav -- ARGS`, or $ENTRYNAV ARGS when ENTRYNAV names a
# built binary) and compares its standard output with the first ```text block under README's
# "## Reading the demo's output". Before comparing, exactly two machine-dependent figures are
# replaced by "…" on both sides: the wall time of the first line ("(15.46 s wall)") and the
# "NN.NN µs per filter step" figures. Every other character must agree.
#
# Usage: scripts/readme_sample.sh [--write] [--output FILE]
#   (no option)    run the command, compare; exit 1 with a diff when README's block differs
#   --write        run the command and replace README's block with its output as printed
#   --output FILE  take the command's standard output from FILE instead of running it
# Exit codes: 0 README agrees (or was written), 1 it differs or the command failed, 2 usage error
# or README has no such command or block.
set -euo pipefail
cd "$(dirname "$0")/.."

write=false
output=""
while [ $# -gt 0 ]; do
  case "$1" in
    --write) write=true ;;
    --output)
      [ $# -ge 2 ] || { echo "readme_sample: --output needs a FILE" >&2; exit 2; }
      output="$2"
      shift
      ;;
    *) echo "readme_sample: unknown argument $1 (usage: scripts/readme_sample.sh [--write] [--output FILE])" >&2; exit 2 ;;
  esac
  shift
done

# The arguments after `--bin entrynav --` on the trade line of README's first ```sh block.
args_line=$(awk '/^```sh$/{n++; f=(n==1); next} /^```$/{f=0} f && /--bin entrynav -- trade /' README.md | head -n 1)
if [ -z "$args_line" ]; then
  echo "readme_sample: README.md's first \`\`\`sh block has no 'cargo run … --bin entrynav -- trade …' line" >&2
  exit 2
fi
args_line=${args_line#*--bin entrynav -- }
args_line=${args_line%%#*}
read -r -a args <<<"$args_line"

actual=$(mktemp)
trap 'rm -f "$actual"' EXIT
if [ -n "$output" ]; then
  cp "$output" "$actual"
else
  if [ -n "${ENTRYNAV:-}" ]; then
    cmd=("$ENTRYNAV" "${args[@]}")
  else
    cmd=(cargo run --release --quiet --bin entrynav -- "${args[@]}")
  fi
  echo "readme_sample: ${cmd[*]}" >&2
  if ! "${cmd[@]}" </dev/null >"$actual"; then
    echo "readme_sample: the command failed: ${cmd[*]}" >&2
    exit 1
  fi
fi

python3 - "$actual" "$write" <<'PY'
import difflib
import re
import sys

actual_path, write = sys.argv[1], sys.argv[2] == "true"
HEADING = "## Reading the demo's output"
with open("README.md", encoding="utf-8") as f:
    readme = f.read().split("\n")
with open(actual_path, encoding="utf-8") as f:
    actual = f.read().rstrip("\n").split("\n")

try:
    h = readme.index(HEADING)
    start = readme.index("```text", h) + 1
    end = readme.index("```", start)
except ValueError:
    print(f"readme_sample: README.md has no ```text block under '{HEADING}'", file=sys.stderr)
    sys.exit(2)

if write:
    if readme[start:end] == actual:
        print("readme_sample: README's sample output is already the command's output")
    else:
        readme[start:end] = actual
        with open("README.md", "w", encoding="utf-8") as f:
            f.write("\n".join(readme))
        print(f"readme_sample: wrote the command's output ({len(actual)} lines) into README.md")
    sys.exit(0)

WALL = re.compile(r"\(\d+(?:\.\d+)? s wall\)")
STEP = re.compile(r"\d+(?:\.\d+)?(?:e[-+]?\d+)? µs per filter step")


def normalise(lines):
    out = list(lines)
    if out:
        out[0] = WALL.sub("(… s wall)", out[0], count=1)
    return [STEP.sub("… µs per filter step", line) for line in out]


expected = normalise(readme[start:end])
got = normalise(actual)
if expected == got:
    print(f"readme_sample: README's sample output equals the command's output ({len(got)} lines; wall time and µs per step not compared)")
    sys.exit(0)
sys.stdout.writelines(
    line + "\n"
    for line in difflib.unified_diff(
        expected, got, f"README.md (line {start + 1})", "the command's output", lineterm=""
    )
)
print(
    "readme_sample: README's sample output differs from what the command prints; "
    "if the new output is right, run scripts/readme_sample.sh --write",
    file=sys.stderr,
)
sys.exit(1)
PY
