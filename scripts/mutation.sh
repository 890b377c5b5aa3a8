#!/usr/bin/env bash
# The whole mutation test of hostile input (tests/mutation/): every case, not ctest's sample.
#
#   scripts/mutation.sh [BUILD_DIR] [millwear_mutation options...]
#
# Builds the program and the test in BUILD_DIR (default: build), runs every case with one
# worker per core (JOBS=N to choose), writes one row per case to BUILD_DIR/mutation-report.tsv
# and prints the outcome classes and every failing case. Exits 1 if any case failed.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
millwear_install  # the Debian packages, as run.sh and test.sh install them
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
[ $# -gt 0 ] && shift
jobs="${JOBS:-$(nproc 2>/dev/null || echo 2)}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" -j "$jobs" --target millwear millwear_mutation >/dev/null
report="$build/mutation-report.tsv"
status=0
"$build/millwear_mutation" -j "$jobs" --report "$report" "$@" || status=$?
echo
echo "outcome classes (from $report):"
awk -F'\t' 'NR > 1 { n[$7]++ } END { for (k in n) printf "  %-18s %7d\n", k, n[k] }' "$report" | sort
exit "$status"
