#!/bin/bash
# Interleaved 1- and 2-thread runs of the soft step on snapshots, three of each, with the
# machine's load average beside every run (a loaded machine says nothing about scaling).
#   bench/threads_wall.sh BUILD_DIR SNAPSHOT:STEPS...
# e.g. bench/threads_wall.sh build snap-10k.bin:100 snap-eq30k.bin:40
# (snapshots from `BUILD_DIR/bench_backends --snapshot SIZE FILE`). Prints the state
# fingerprint (equal for both thread counts) and disk-steps per wall second.
set -euo pipefail
build=${1:?usage: bench/threads_wall.sh BUILD_DIR SNAPSHOT:STEPS...}
shift
for arg in "$@"; do
  file=${arg%%:*}
  steps=${arg##*:}
  for rep in 1 2 3; do
    for threads in 1 2; do
      load=$(cut -d' ' -f1 /proc/loadavg)
      line=$("$build/bench_backends" --run "$file" "$steps" --threads "$threads" | head -1)
      echo "$file threads=$threads load=$load $(grep -o 'state [0-9a-f]*' <<<"$line") $(grep -o '[0-9.e+]* disk-steps/wall-s' <<<"$line")"
    done
  done
done
