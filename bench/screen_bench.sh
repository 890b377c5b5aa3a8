#!/usr/bin/env bash
# Screening throughput. Prints figures, asserts nothing.
#
#   bench/screen_bench.sh [BUILD_DIR] [N_DESIGNS] [FIDELITIES]     (defaults: build 4 "draft")
#
# 1. Designs per hour on 2 cores: N designs of the default family
#    (scenarios/screen-sag-face-angle.toml, SAG mill, 4 stages of 750 h), drawn as a Latin
#    hypercube of N from its grid levels, run by the local pool with --jobs 2, at each
#    fidelity in FIDELITIES ("draft standard" for both).
# 2. Slurm: the same N-design SAG screen at the first fidelity of FIDELITIES, as 1 array task
#    (--chunk N) and as 2 tasks (--chunk N/2) on a private single-node Slurm
#    (tests/slurm/start_slurm.sh); skipped with a message if slurm-wlm/munge are missing.
# The load average is printed before and after: on a shared machine it is the first thing
# to read next to any wall time.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=$(cd "${1:-$ROOT/build}" && pwd)
N=${2:-4}
FIDELITIES=${3:-draft}
BIN="$BUILD/millwear"
WORK=$(mktemp -d /tmp/millwear-screen-bench.XXXXXX)
chmod 755 "$WORK"
SLURM_DIR=""
cleanup() {
  [ -n "$SLURM_DIR" ] && "$ROOT/tests/slurm/stop_slurm.sh" "$SLURM_DIR" || true
  rm -rf "$WORK"
}
trap cleanup EXIT
now() { date +%s.%N; }
load() { cut -d' ' -f1-3 /proc/loadavg; }
echo "screen benchmark: $(nproc) cores, load average $(load) (1/5/15 min) at start"

for fid in $FIDELITIES; do
  screen="$WORK/sag-$fid.toml"
  sed -e "s|^base = \"sag-2x30.toml\"|base = \"$ROOT/scenarios/sag-2x30.toml\"|" \
      -e "s|^equal_area = \"../profiles/2x30.toml\"|equal_area = \"$ROOT/profiles/2x30.toml\"|" \
      -e "s|^fidelity = \"draft\"|fidelity = \"$fid\"|" \
      -e "s|^sampling = \"grid\"|sampling = \"latin_hypercube\"\nsamples = $N\nseed = 1|" \
      "$ROOT/scenarios/screen-sag-face-angle.toml" > "$screen"
  # CPU time of the tasks (children of the pool, all waited for): what 2 idle cores would
  # take is about CPU / 2; on a loaded machine the wall time is longer.
  c0=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat)
  t0=$(now)
  "$BIN" screen "$screen" -o "$WORK/out-$fid" --jobs 2 --quiet > "$WORK/out-$fid.log" 2>&1 || { cat "$WORK/out-$fid.log"; exit 1; }
  t1=$(now)
  c1=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat)
  awk -v n="$N" -v a="$t0" -v b="$t1" -v f="$fid" -v l="$(load)" -v cpu="$(( (c1 - c0) / $(getconf CLK_TCK) ))" 'BEGIN {
    w = b - a; printf "SAG face-angle family, %s: %d designs in %.0f s wall on --jobs 2 -> %.1f designs/h (100 designs: %.1f h); CPU %.0f s = %.0f s a design -> %.1f designs/h on 2 idle cores; load after %s\n", f, n, w, n / w * 3600, 100 / (n / w * 3600), cpu, cpu / n, 2 * 3600 * n / cpu, l }'
done

if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  echo "Slurm: not installed (apt-get install slurm-wlm munge): skipped"
  exit 0
fi
SLURM_DIR="$WORK/slurm-daemons"
eval "$("$ROOT/tests/slurm/start_slurm.sh" "$SLURM_DIR")"
first_fid=${FIDELITIES%% *}
half=$(( (N + 1) / 2 ))
for chunk in "$N" "$half"; do
  out="$WORK/slurm-$chunk"
  "$BIN" screen "$WORK/sag-$first_fid.toml" -o "$out" --emit slurm --chunk "$chunk" > /dev/null
  t0=$(now)
  sbatch --parsable "$out/screen.sbatch" > /dev/null
  while [ -n "$(squeue -h -o %i)" ]; do sleep 0.2; done
  t1=$(now)
  "$BIN" screen --collect "$out" > /dev/null
  awk -v n="$N" -v c="$chunk" -v f="$first_fid" -v a="$t0" -v b="$t1" -v l="$(load)" 'BEGIN {
    printf "Slurm, SAG face-angle screen (%d designs, %s): %d array task(s) of up to %d: %.1f s wall (submit to empty queue); load after %s\n", n, f, int((n + c - 1) / c), c, b - a, l }'
done
