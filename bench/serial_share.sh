#!/bin/bash
# The share of the main thread's step spent outside the pool's stages (the step's one-thread
# parts, which Amdahl's law counts as serial), from `perf record` call graphs of a threaded
# run of a snapshot, and the functions that take it.
#   bench/serial_share.sh BUILD_DIR SNAPSHOT STEPS [THREADS]
# e.g. bench/serial_share.sh build snap-10k.bin 400 (snapshots from `BUILD_DIR/bench_backends
# --snapshot SIZE FILE`). Needs perf; samples the CPU clock at 1 kHz with DWARF call graphs.
# Counts only samples inside the engine's step, so loading the snapshot does not count.
set -euo pipefail
build=${1:?usage: bench/serial_share.sh BUILD_DIR SNAPSHOT STEPS [THREADS]}
snapshot=${2:?usage: bench/serial_share.sh BUILD_DIR SNAPSHOT STEPS [THREADS]}
steps=${3:?usage: bench/serial_share.sh BUILD_DIR SNAPSHOT STEPS [THREADS]}
threads=${4:-2}
command -v perf > /dev/null || { echo "serial_share: needs perf (Debian: linux-perf)" >&2; exit 2; }
[ -f "$snapshot" ] || { echo "serial_share: no snapshot $snapshot" >&2; exit 2; }
data=$(mktemp)
trap 'rm -f "$data"' EXIT
perf record -q -e cpu-clock -F 1000 --call-graph dwarf,16384 -o "$data" \
  "$build/bench_backends" --run "$snapshot" "$steps" --threads "$threads" | head -1
# perf script: a sample's process and thread ids on a line of its own (pid/tid, right-aligned;
# the main thread's tid is the pid), then its frames, leaf first, then a blank line. A sample is in the step if a frame is the engine's step, in a stage if a frame
# is the pool's (dispatch, work_on_ranges); its function is the frame the step called.
perf script -i "$data" -F pid,tid,ip,sym 2> /dev/null | awk '
  function flush(   i, in_step, staged, fn) {
    if (tid == "") return
    in_step = 0; staged = 0; fn = "?"
    for (i = 0; i < n; ++i) {
      if (frame[i] ~ /Workers::(dispatch|work_on_ranges)/) staged = 1
      if (frame[i] ~ /SoftEngine::step/) { in_step = 1; if (i > 0) fn = frame[i - 1]; break }
    }
    if (in_step) {
      steps[tid]++
      if (!staged) { serial[tid]++; by_fn[tid SUBSEP fn]++ }
    }
    tid = ""; n = 0
  }
  /^ *[0-9]+\/[0-9]+ *$/ { flush(); split($1, id, "/"); tid = id[2]; if (id[1] == id[2]) main = tid; next }
  /^[ \t]*$/ { flush(); next }
  { sub(/^[ \t]*[0-9a-f]+ /, ""); gsub(/\(anonymous namespace\)::/, ""); sub(/\(.*/, ""); frame[n++] = $0 }
  END {
    flush()
    if (!(main in steps)) { print "serial_share: no sample inside the step" > "/dev/stderr"; exit 1 }
    printf "main thread: %d samples in the step, %d outside the stages (%.1f%%)\n", steps[main], serial[main], 100 * serial[main] / steps[main]
    for (k in by_fn) {
      split(k, parts, SUBSEP)
      if (parts[1] == main) printf "%6.2f%%  %s\n", 100 * by_fn[k] / steps[main], parts[2] | "sort -rn | head -8"
    }
  }'
