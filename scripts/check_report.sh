#!/usr/bin/env bash
# Render an entrynav HTML report in headless Chromium and fail on console messages, network
# references, missing sections or a blank page (scripts/check_report.py judges the result).
# Usage: scripts/check_report.sh [REPORT.html]   (default: a small trade's report, made here)
# Leaves the screenshot and the dumped DOM next to the report (REPORT.png, REPORT.dom.html).
set -euo pipefail
cd "$(dirname "$0")/.."
browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then
  echo "check_report: chromium not found (scripts/setup.sh installs the Debian package)" >&2
  exit 1
fi
report=${1:-}
if [ -z "$report" ]; then
  mkdir -p target/ci-report
  report=target/ci-report/report.html
  target/release/entrynav trade --scenario four-beacon-fusion --filters ekf,ci,dcifaif --runs 20 \
    --quiet --report "$report" >/dev/null
  # CI diverges in every run of this scenario: the verdict says so, and the recommendation is the EKF.
  export CHECK_REPORT_EXPECT="${CHECK_REPORT_EXPECT:-Recommendation: ekf: consistent, lowest position RMSE|diverged in 20/20 runs}"
fi
url="file://$(cd "$(dirname "$report")" && pwd)/$(basename "$report")"
base="${report%.html}"
flags=(--headless --no-sandbox --disable-gpu --hide-scrollbars --enable-logging=stderr --v=0)
timeout 120 "$browser" "${flags[@]}" --window-size=1200,3000 --screenshot="$base.png" "$url" \
  2>"$base.chromium.log" >/dev/null
timeout 120 "$browser" "${flags[@]}" --dump-dom "$url" >"$base.dom.html" 2>>"$base.chromium.log"
sections=(summary rmse errors nees-nis weights dispersion provenance)
if grep -q 'entrynav grid report' "$report"; then
  sections=(summary metrics consistency provenance)
fi
python3 scripts/check_report.py "$base.png" "$base.dom.html" "$base.chromium.log" "${sections[@]}"
