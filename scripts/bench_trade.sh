#!/usr/bin/env bash
# Times the Monte Carlo trade of issue 25's speed target,
#   entrynav trade --scenario four-beacon-fusion --filters ekf,ci,dcifaif --runs 5000 --seed 1 --threads 2
# with the default (portable) release build of this checkout, optionally interleaved with the
# same trade built from another revision (in a git worktree with its own target folder), so both
# are timed on one machine in the same conditions. Prints wall and user seconds per run, the
# means and their ratio, and checks every figure of the JSON summaries: the repeats of one build
# must agree bit for bit (a failure exits 1), and whether the two builds agree is reported.
#
#   scripts/bench_trade.sh                         # 3 timed runs of this checkout
#   scripts/bench_trade.sh --baseline ace7b41      # interleaved with the code before issue 25's first commit
#   scripts/bench_trade.sh --runs 1000 --repeat 5 --threads 2
#
# A benchmark, not a test: nothing here asserts a time. docs/results.md (*Monte Carlo speed*)
# records what it measured.
set -euo pipefail

runs=5000
repeat=3
threads=2
baseline=""
usage() { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
    case "$1" in
        --runs) runs="${2:?--runs needs a number}"; shift 2 ;;
        --repeat) repeat="${2:?--repeat needs a number}"; shift 2 ;;
        --threads) threads="${2:?--threads needs a number}"; shift 2 ;;
        --baseline) baseline="${2:?--baseline needs a git revision}"; shift 2 ;;
        -h | --help) usage; exit 0 ;;
        *) echo "bench_trade: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
done
for v in runs repeat threads; do
    if ! [[ "${!v}" =~ ^[1-9][0-9]*$ ]]; then
        echo "bench_trade: --$v must be a positive integer, got '${!v}'" >&2
        exit 2
    fi
done
if [ "$repeat" -gt 20 ]; then
    echo "bench_trade: --repeat must be at most 20, got $repeat" >&2
    exit 2
fi

root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
out="$root/target/bench-trade"
mkdir -p "$out"
tree=""
# On any exit, also a failed build or run: no timing file and no registered worktree left behind.
cleanup() {
    rm -f "$out/times.$$"
    if [ -n "$tree" ]; then git worktree remove --force "$tree" > /dev/null 2>&1 || true; fi
}
trap cleanup EXIT

echo "bench_trade: building this checkout (release, portable)"
cargo build --release --quiet --bin entrynav
cp target/release/entrynav "$out/entrynav-head"
builds=(head)
if [ -n "$baseline" ]; then
    rev="$(git rev-parse --verify "$baseline^{commit}")" || {
        echo "bench_trade: --baseline '$baseline' is not a commit of this repository" >&2
        exit 2
    }
    tree="$out/baseline-tree"
    git worktree remove --force "$tree" > /dev/null 2>&1 || rm -rf "$tree"
    git worktree prune
    git worktree add --detach --force "$tree" "$rev" > /dev/null
    echo "bench_trade: building the baseline ${rev:0:7} (its own target folder)"
    (cd "$tree" && CARGO_TARGET_DIR="$out/baseline-target" cargo build --release --quiet --bin entrynav)
    cp "$out/baseline-target/release/entrynav" "$out/entrynav-base"
    git worktree remove --force "$tree"
    tree=""
    builds=(base head)
fi

TIMEFORMAT='%R %U'
args=(trade --scenario four-beacon-fusion --filters ekf,ci,dcifaif --runs "$runs" --seed 1 --threads "$threads" --quiet)
echo "bench_trade: ${args[*]}, $repeat time(s) per build, interleaved (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
for i in $(seq 1 "$repeat"); do
    for b in "${builds[@]}"; do
        # `time` reports on the captured stream; the trade's own errors go to the terminal (fd 4).
        t=$({ time "$out/entrynav-$b" "${args[@]}" --json "$out/$b-$i.json" > /dev/null 2>&4; } 4>&2 2>&1)
        echo "$b $i $t" >> "$out/times.$$"
        printf '  %-4s run %d: %6.2f s wall, %6.2f s user\n' "$b" "$i" ${t}
    done
done

status=0
python3 - "$out" "$$" "$repeat" "${builds[@]}" <<'EOF' || status=$?
import json, sys
out, pid, repeat, builds = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:]
times = {}
for line in open(f"{out}/times.{pid}"):
    b, _, wall, user = line.split()
    times.setdefault(b, []).append((float(wall), float(user)))

def figures(path):
    """Every number and string of the summary except its provenance and timing."""
    doc = json.load(open(path))
    doc.pop("provenance", None)
    doc.pop("timing", None)
    return doc

ok, mean_wall = True, {}
for b in builds:
    walls = [w for w, _ in times[b]]
    users = [u for _, u in times[b]]
    mean_wall[b] = sum(walls) / len(walls)
    print(f"{b}: wall mean {mean_wall[b]:.2f} s (min {min(walls):.2f}, max {max(walls):.2f}), "
          f"user mean {sum(users)/len(users):.2f} s")
    first = figures(f"{out}/{b}-1.json")
    same = all(figures(f"{out}/{b}-{i}.json") == first for i in range(2, repeat + 1))
    print(f"  repeats of {b} give the same figures: {'yes' if same else 'NO'}")
    ok &= same
if len(builds) == 2:
    print(f"speed-up of this checkout over the baseline (mean wall): {mean_wall['base'] / mean_wall['head']:.2f}x")
    agree = figures(f"{out}/base-1.json") == figures(f"{out}/head-1.json")
    print(f"baseline and this checkout give the same figures: {'yes' if agree else 'no (see docs/results.md for documented round-off changes)'}")
sys.exit(0 if ok else 1)
EOF
exit $status
