#!/usr/bin/env bash
# Quick start: install what is missing, build Release, show the lifter profiles, then run
# the default scene (the paper's 2x30 vs 1x30 comparison) at standard fidelity.
#   OUT=out/mine FIDELITY=draft scripts/run.sh     # another folder or fidelity
# An interrupted run (Ctrl-C) keeps its finished stages: run this script again with
# RESUME=1 to continue where it stopped.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
millwear_install
millwear_build
cd "$MILLWEAR_ROOT"
./build/millwear profile profiles/*.toml
echo
out="${OUT:-out/default}"
where="$out"
[[ "$out" == /* ]] || where="$MILLWEAR_ROOT/$out"  # a relative OUT is under the repository
resume=()
if [[ "${RESUME:-0}" == "1" ]]; then resume=(--resume); fi
./build/millwear run scenarios/sag-2x30-vs-1x30.toml -o "$out" --fidelity "${FIDELITY:-standard}" "${resume[@]}"
echo
echo "Figures (PNG and SVG): $where/plots/"
ls "$out/plots/"*.png 2>/dev/null | sed 's/^/  /'
echo "Table: $where/summary.csv   Manifest: $where/manifest.json"
