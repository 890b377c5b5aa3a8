#!/bin/bash
# Interleaved 1- and 2-thread runs of the soft step on snapshots, three pairs of each, with
# the machine's load average beside every run (a loaded machine says nothing about scaling)
# and the cores' round trip (build/core_to_core) before and after every pair: on a virtual
# machine the host may move the two CPUs apart while the runs go on, and a pair measured
# across such a move says nothing either.
#   bench/threads_wall.sh BUILD_DIR SNAPSHOT:STEPS...
# e.g. bench/threads_wall.sh build snap-10k.bin:300 snap-eq30k.bin:120
# (snapshots from `BUILD_DIR/bench_backends --snapshot SIZE FILE`). Prints the state
# fingerprint (equal for both thread counts), disk-steps per wall second and the pair's
# ratio.
set -euo pipefail
build=${1:?usage: bench/threads_wall.sh BUILD_DIR SNAPSHOT:STEPS...}
shift
round_trip() { "$build/core_to_core" 0 1 200000 | grep -o '[0-9.]* ns'; }
for arg in "$@"; do
  file=${arg%%:*}
  steps=${arg##*:}
  for rep in 1 2 3; do
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
