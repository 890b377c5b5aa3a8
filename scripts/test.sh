#!/usr/bin/env bash
# Same setup as run.sh, then the whole test suite through CTest.
set -euo pipefail
# GNU parallel, Slurm and munge: tests/test_screen.cpp runs a screen through GNU parallel and
# through a real single-node Slurm job array (tests/slurm/start_slurm.sh); without them those
# tests are reported as skipped, never passed.
MILLWEAR_EXTRA_PACKAGES="${MILLWEAR_EXTRA_PACKAGES:-} parallel slurm-wlm munge"
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
millwear_install
millwear_build
cd "$MILLWEAR_ROOT/build"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
