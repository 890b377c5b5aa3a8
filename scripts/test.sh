#!/usr/bin/env bash
# Same setup as run.sh, then the whole test suite through CTest.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
millwear_install
millwear_build
cd "$MILLWEAR_ROOT/build"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
