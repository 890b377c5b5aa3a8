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
# (polled every 10 s, for at most an hour a pair), for the scaling of two near CPUs on a
# host that moves them.
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
wait_near() {
  local waited=0
  while :; do
    local rt
    rt=$(round_trip | cut -d' ' -f1)
    awk -v r="$rt" -v n="$near" 'BEGIN { exit !(r < n) }' && return 0
    if [ $waited -ge 3600 ]; then
      echo "threads_wall: the CPUs' round trip stayed at or above $near ns for an hour (last $rt ns)" >&2
      exit 1
    fi
    sleep 10
    waited=$((waited + 10))
  done
}
for arg in "$@"; do
  file=${arg%%:*}
  steps=${arg##*:}
  for rep in 1 2 3; do
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
    echo "$file pair $rep: 2 threads / 1 = $(awk -v a="${rate[1]}" -v b="${rate[2]}" 'BEGIN { printf "%.2f", b / a }'), round trip $before before, $after after"
  done
done
