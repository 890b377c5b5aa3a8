#!/usr/bin/env bash
# Quick start: install what is missing, build Release, run the default scene, write plots.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
millwear_install
millwear_build
cd "$MILLWEAR_ROOT"
./build/millwear profile profiles/*.toml
