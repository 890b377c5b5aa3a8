#!/bin/bash
# Interleaved 1- and 2-thread runs of the soft step on snapshots, three pairs of each, with
# the machine's load average beside every run (a loaded machine says nothing about scaling)
# and the cores' round trip (build/core_to_core) before and after every pair: on a virtual
# machine the host may move the two CPUs apart while the runs go on, and a pair measured
# across such a move says nothing either.
#   bench/threads_wall.sh [--near NS] BUILD_DIR SNAPSHOT:STEPS...
# e.g. bench/threads_wall.sh build snap-10k.bin:300 snap-eq30k.bin:120
# (snapshots from `BUILD_DIR/bench_backends --snapshot SIZE FILE`). Prints the state
# fingerprint (equal for both thread counts), disk-steps per wall second and the pair's
# ratio. --near NS: before each pair, wait until the round trip is under NS nanoseconds
# (polled every 2 s), and keep only the pairs with it under NS before and after, running
# a pair again until three are kept (at most an hour a pair): the scaling of two near CPUs
# on a host that moves them.
set -euo pipefail
near=""
if [ "${1:-}" = "--near" ]; then
  near=${2:?usage: bench/threads_wall.sh [--near NS] BUILD_DIR SNAPSHOT:STEPS...}
  [[ $near =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "threads_wall: --near wants a round trip in ns, a number; got '$near'" >&2; exit 2; }
  shift 2
fi
build=${1:?usage: bench/threads_wall.sh [--near NS] BUILD_DIR SNAPSHOT:STEPS...}
shift
round_trip() { "$build/core_to_core" 0 1 200000 | grep -o '[0-9.]* ns'; }
is_near() { awk -v r="${1%% *}" -v n="$near" 'BEGIN { exit !(r < n) }'; }
# When the search for the current pair began (reset when a pair is kept).
pair_began=$SECONDS
wait_near() {
  while :; do
    local rt
    rt=$("$build/core_to_core" 0 1 20000 | grep -o '[0-9.]* ns' | cut -d' ' -f1)
    is_near "$rt" && return 0
    if [ $((SECONDS - pair_began)) -ge 3600 ]; then
      echo "threads_wall: no pair ran with the CPUs' round trip under $near ns throughout in an hour (last $rt ns)" >&2
      exit 1
    fi
    sleep 2
  done
}
for arg in "$@"; do
  file=${arg%%:*}
  steps=${arg##*:}
  rep=1
  while [ $rep -le 3 ]; do
    [ -z "$near" ] || wait_near
    before=$(round_trip)
    declare -A rate
    for threads in 1 2; do
      load=$(cut -d' ' -f1 /proc/loadavg)
      line=$("$build/bench_backends" --run "$file" "$steps" --threads "$threads" | head -1)
      rate[$threads]=$(grep -o '[0-9.e+]* disk-steps/wall-s' <<<"$line" | cut -d' ' -f1)
      echo "$file threads=$threads load=$load $(grep -o 'state [0-9a-f]*' <<<"$line") ${rate[$threads]} disk-steps/wall-s"
    done
    after=$(round_trip)
    ratio=$(awk -v a="${rate[1]}" -v b="${rate[2]}" 'BEGIN { printf "%.2f", b / a }')
    if [ -n "$near" ] && ! { is_near "$before" && is_near "$after"; }; then
      echo "$file pair not kept: 2 threads / 1 = $ratio, round trip $before before, $after after (not under $near ns throughout)"
      continue
    fi
    echo "$file pair $rep: 2 threads / 1 = $ratio, round trip $before before, $after after"
    rep=$((rep + 1))
    pair_began=$SECONDS
  done
done
