#!/usr/bin/env bash
# Is the soft backend's cost linear in the disk count? Work and wall time, separately.
#
# The settled bed (mill at rest) of the 1k probe's disks in mills widened to hold about 1k,
# 3k and 10k of them (bench_backends --snapshot rest-eq1k|rest-eq3k|rest-eq10k): every disk
# has the same neighbourhood at every count, so the contacts per disk are equal and a linear
# algorithm costs the same per disk-step. For each size it prints
#   - instructions per disk-step, and the L1 and L2 data-cache misses per disk-step of a
#     simulated cache with this machine's sizes (valgrind's cachegrind, a run of N steps
#     subtracted from one of 2N, so setup cancels): deterministic, the same on any x86-64;
#   - the best of 5 native runs in ns per disk-step (CPU time; the best, because on a shared
#     machine other tenants only ever add to it).
# Usage: bench/linearity.sh [BUILD_DIR]   (needs valgrind: apt-get install valgrind; ~5 min)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
[ -x "$build/bench_backends" ] || { echo "linearity: $build/bench_backends not found; build first" >&2; exit 2; }
command -v valgrind > /dev/null || { echo "linearity: valgrind is not installed (apt-get install valgrind)" >&2; exit 2; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
bb="$build/bench_backends"

l1=$(getconf LEVEL1_DCACHE_SIZE 2> /dev/null || echo 0)
l2=$(getconf LEVEL2_CACHE_SIZE 2> /dev/null || echo 0)
[ "${l1:-0}" -gt 0 ] 2> /dev/null || l1=49152
[ "${l2:-0}" -gt 0 ] 2> /dev/null || l2=1048576
# cachegrind wants a power-of-two number of sets: 12-way 48 kB L1 and 8-way 1 MB L2 are.
l1_ways=$(( l1 / 4096 )); [ $l1_ways -ge 1 ] || l1_ways=8
l2_ways=8

# The count of a "refs:" or "misses:" line of a cachegrind log.
count() { grep -E "$2" "$1" | head -1 | sed -E 's/.*: *([0-9,]+).*/\1/' | tr -d ,; }

printf "Settled bed at rest, 1k probe's disks, soft backend; simulated caches L1 %d kB, L2 %d kB\n" \
  $((l1 / 1024)) $((l2 / 1024))
printf "%8s %12s %16s %18s %18s %16s\n" disks "disk-steps" "instr/disk-step" "L1 miss/disk-step" \
  "L2 miss/disk-step" "best ns/disk-step"
for size in eq1k eq3k eq10k; do
  case $size in eq1k) n=1000 ;; eq3k) n=333 ;; eq10k) n=100 ;; esac
  "$bb" --snapshot "rest-$size" "$tmp/$size.snap" > /dev/null
  for k in 1 2; do
    valgrind --tool=cachegrind --cache-sim=yes --D1=$l1,$l1_ways,64 --LL=$l2,$l2_ways,64 \
      --cachegrind-out-file=/dev/null "$bb" --run "$tmp/$size.snap" $((n * k)) \
      > "$tmp/$size.$k.out" 2> "$tmp/$size.$k.log" &
  done
  wait
  disks=$(awk '{print $2; exit}' "$tmp/$size.1.out")
  best=0
  for r in 1 2 3 4 5; do
    rate=$("$bb" --run "$tmp/$size.snap" $((10 * n)) | awk 'NR == 1 {print $10}')
    best=$(awk -v a="$best" -v b="$rate" 'BEGIN {print (b > a ? b : a)}')
  done
  awk -v d="$disks" -v n="$n" -v best="$best" \
    -v i1="$(count "$tmp/$size.1.log" 'I *refs:')" -v i2="$(count "$tmp/$size.2.log" 'I *refs:')" \
    -v a1="$(count "$tmp/$size.1.log" 'D1 *misses:')" -v a2="$(count "$tmp/$size.2.log" 'D1 *misses:')" \
    -v b1="$(count "$tmp/$size.1.log" 'LLd misses:')" -v b2="$(count "$tmp/$size.2.log" 'LLd misses:')" \
    'BEGIN { s = d * n; printf "%8d %12d %16.0f %18.1f %18.1f %16.0f\n", d, s, (i2 - i1) / s, (a2 - a1) / s, (b2 - b1) / s, 1e9 / best }'
done
