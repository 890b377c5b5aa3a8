#!/bin/bash
# The cost per disk-step against the charge's size: the 1k probe's disks in the equal-size
# mills (eq1k, eq30k, eq100k), turning and at rest, one thread, CPU time of the thread.
# Single runs move by a third on a shared machine, so the six snapshots run in rounds, one
# run of each a round, and each figure is the median of the rounds.
#   bench/cost_per_disk.sh [--rounds N] [--snapshots DIR] BUILD_DIR [BUILD_DIR_B]
# Snapshots are made once (`bench_backends --snapshot [rest-]eqN FILE --threads 1`, about
# two minutes in all) into DIR (default: BUILD_DIR/snapshots) and reused. Prints per
# snapshot the median ns per disk-step, the runs' range and the ratio to eq1k (turning to
# turning, at rest to at rest). With a second build, each round runs every snapshot on both
# builds one after the other, and it also prints B's medians and the median and quartiles of
# the rounds' time ratios B / A, and whether the two builds computed the same bits (the
# state fingerprints). Rounds: 7 by default.
set -euo pipefail
usage="usage: bench/cost_per_disk.sh [--rounds N] [--snapshots DIR] BUILD_DIR [BUILD_DIR_B]"
rounds=7
snapshots=""
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds)
      rounds=${2:?$usage}
      [[ $rounds =~ ^[1-9][0-9]*$ ]] || { echo "cost_per_disk: --rounds wants a whole number of 1 or more; got '$rounds'" >&2; exit 2; }
      shift 2 ;;
    --snapshots) snapshots=${2:?$usage}; shift 2 ;;
    -*) echo "cost_per_disk: unknown option '$1'; $usage" >&2; exit 2 ;;
    *) break ;;
  esac
done
build_a=${1:?$usage}
build_b=${2:-}
builds=("$build_a")
[ -n "$build_b" ] && builds+=("$build_b")
for b in "${builds[@]}"; do
  [ -x "$b/bench_backends" ] || { echo "cost_per_disk: no $b/bench_backends (build with -DMILLWEAR_BUILD_BENCH=ON)" >&2; exit 2; }
done
snapshots=${snapshots:-$build_a/snapshots}
mkdir -p "$snapshots"
# Timed steps per size: about 2.4 M disk-steps a run.
names=(eq1k rest-eq1k eq30k rest-eq30k eq100k rest-eq100k)
declare -A steps=([eq1k]=2400 [rest-eq1k]=2400 [eq30k]=120 [rest-eq30k]=120 [eq100k]=36 [rest-eq100k]=36)
for n in "${names[@]}"; do
  if [ ! -s "$snapshots/snap-$n.bin" ]; then
    echo "making $snapshots/snap-$n.bin" >&2
    "$build_a/bench_backends" --snapshot "$n" "$snapshots/snap-$n.bin.part" --threads 1 > /dev/null
    mv "$snapshots/snap-$n.bin.part" "$snapshots/snap-$n.bin"
  fi
done
runs=$(mktemp)
trap 'rm -f "$runs"' EXIT
for r in $(seq "$rounds"); do
  for n in "${names[@]}"; do
    for i in "${!builds[@]}"; do
      line=$("${builds[$i]}/bench_backends" --run "$snapshots/snap-$n.bin" "${steps[$n]}" --threads 1 | head -1)
      rate=$(grep -o '[0-9.e+]* disk-steps/cpu-s' <<<"$line" | cut -d' ' -f1)
      state=$(grep -o 'state [0-9a-f]*' <<<"$line" | cut -d' ' -f2)
      echo "$r $n $i $rate $state" >> "$runs"
    done
  done
  echo "round $r of $rounds done" >&2
done
awk -v nb="${#builds[@]}" -v la="$build_a" -v lb="$build_b" '
  function median(a, n,   i, j, t) {  # sorts a[1..n] in place
    for (i = 2; i <= n; ++i) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; --j) a[j + 1] = a[j]; a[j + 1] = t }
    return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
  }
  {
    ns = 1e9 / $4
    k = $2 SUBSEP $3
    cnt[k]++; v[k, cnt[k]] = ns
    t[$1, $2, $3] = ns
    fp[$2, $3, $5] = 1
    if (!(($2, $3) in first_fp)) first_fp[$2, $3] = $5
    else if (first_fp[$2, $3] != $5) drift[$2, $3] = 1
    rounds[$1] = 1
  }
  END {
    split("eq1k rest-eq1k eq30k rest-eq30k eq100k rest-eq100k", names, " ")
    for (b = 0; b < nb; ++b) {
      printf "%s (%s)\n", b == 0 ? "A" : "B", b == 0 ? la : lb
      printf "  %-12s %10s %16s %10s\n", "snapshot", "ns/step", "runs", "vs eq1k"
      for (s = 1; s <= 6; ++s) {
        n = names[s]; k = n SUBSEP b; m = cnt[k]
        delete a; lo = 1e300; hi = 0
        for (i = 1; i <= m; ++i) { a[i] = v[k, i]; if (a[i] < lo) lo = a[i]; if (a[i] > hi) hi = a[i] }
        med[n, b] = median(a, m)
        base = n ~ /^rest-/ ? "rest-eq1k" : "eq1k"
        printf "  %-12s %10.0f %7.0f-%-8.0f %9.2fx%s\n", n, med[n, b], lo, hi, med[n, b] / med[base, b],
               (n, b) in drift ? "  (state differs between rounds)" : ""
      }
    }
    if (nb < 2) exit
    printf "B / A, time per disk-step, per round\n"
    for (s = 1; s <= 6; ++s) {
      n = names[s]; m = 0; delete a
      for (r in rounds) if ((r, n, 0) in t && (r, n, 1) in t) a[++m] = t[r, n, 1] / t[r, n, 0]
      med_r = median(a, m); q = int(m / 4)
      printf "  %-12s median %.3f, quartiles %.3f-%.3f (%d rounds), %s\n", n, med_r, a[q + 1], a[m - q], m,
             first_fp[n, 0] == first_fp[n, 1] ? "same bits" : "other bits"
    }
  }' "$runs"
