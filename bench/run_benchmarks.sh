#!/usr/bin/env bash
# Benchmarks as a table (figures are printed and tracked, never asserted):
#   1. engine disk-steps per second at about 1k, 3k and 10k disks on both backends, at equal
#      time step and substeps, with the time shares (build/bench_backends; the probe scene
#      is bench/probe_scene.hpp);
#   2. wall and CPU time of the default comparison (scenarios/sag-2x30-vs-1x30.toml, both
#      designs) at each fidelity preset, through `millwear run`.
# Usage: bench/run_benchmarks.sh [--quick] [--presets "draft standard reference"] [BUILD_DIR]
#   --quick   0.5 s engine windows, and the comparison shortened to 1 stage of 250 h
#             (the full comparison is 4 x 750 h: hours at reference on 2 cores)
# Wall times on a shared machine vary with its load: CPU time (user+sys of the run) is
# printed beside them, and a second run is the way to see the noise.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
quick=0
presets="draft standard reference"
build="$here/build"
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --presets) presets="$2"; shift ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    *) build="$1" ;;
  esac
  shift
done
for exe in bench_backends millwear; do
  [ -x "$build/$exe" ] || { echo "run_benchmarks: $build/$exe not found; build first (cmake --build $build)" >&2; exit 2; }
done
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

echo "## Engine: disk-steps per second, Box2D 2.4 library against our soft solver"
seconds=2.0; [ $quick = 1 ] && seconds=0.5
"$build/bench_backends" "$seconds"
echo

echo "## Default comparison (sag-2x30-vs-1x30) per preset"
# Copies of the two designs with absolute profile paths (and, with --quick, 1 stage of 250 h).
for d in sag-2x30 sag-1x30; do
  sed -e "s|^profile = \"\.\./profiles/|profile = \"$here/profiles/|" "$here/scenarios/$d.toml" > "$tmp/$d.toml"
  if [ $quick = 1 ]; then
    sed -i -e 's/^stage_hours = .*/stage_hours = 250.0/' -e 's/^stages = .*/stages = 1/' "$tmp/$d.toml"
  fi
done
sed -e 's|^designs = .*|designs = ["sag-2x30.toml", "sag-1x30.toml"]|' \
  "$here/scenarios/sag-2x30-vs-1x30.toml" > "$tmp/comparison.toml"
if [ $quick = 1 ]; then span="1 stage of 250 h"; else span="4 stages of 750 h"; fi
echo
echo "($span per design, the two designs in parallel threads)"
echo
echo "| preset | wall (s) | CPU (s) | exit |"
echo "|---|---|---|---|"
for p in $presets; do
  start=$(date +%s.%N)
  set +e
  /usr/bin/time -f "%U %S" -o "$tmp/time_$p.txt" \
    "$build/millwear" run "$tmp/comparison.toml" -o "$tmp/out_$p" --fidelity "$p" --quiet > "$tmp/run_$p.log" 2>&1
  rc=$?
  set -e
  end=$(date +%s.%N)
  cpu=$(awk '{ printf "%.0f", $1 + $2 }' "$tmp/time_$p.txt" 2>/dev/null || echo "-")
  printf "| %s | %.0f | %s | %s |\n" "$p" "$(echo "$end - $start" | bc)" "$cpu" "$rc"
done
