#!/bin/bash
# ParaView output read back by a VTK reader that is not millwear's (meshio): `millwear charge
# --vtk` and `millwear run --vtk` on the lab mill at draft fidelity, then check_vtk.py. The
# same run without --vtk must give the same summary and profiles, to the bit: taking frames
# steps each window in pieces, never changes its steps.
# usage: vtk_readback.sh MILLWEAR PYTHON SOURCE_DIR
set -euo pipefail
millwear=$1 python=$2 src=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$millwear" charge "$src/scenarios/lab-mill.toml" -o "$tmp/charge" --revolutions 0.5 --vtk \
  --set outputs.vtk_frames=8 >/dev/null
"$millwear" run "$src/scenarios/lab-mill.toml" -o "$tmp/run" --quiet --set wear.stages=1 \
  --set outputs.vtk_frames=4 --vtk >/dev/null
"$millwear" run "$src/scenarios/lab-mill.toml" -o "$tmp/plain" --quiet --set wear.stages=1 >/dev/null
cmp "$tmp/run/summary.csv" "$tmp/plain/summary.csv"
for f in "$tmp"/plain/profiles/*.csv; do cmp "$f" "$tmp/run/profiles/$(basename "$f")"; done
"$python" "$src/tests/vtk/check_vtk.py" "$tmp/charge" "$tmp/run" lab-mill
