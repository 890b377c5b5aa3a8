#!/usr/bin/env bash
# Shared setup for run.sh, test.sh and mutation.sh: install what is missing (Debian packages only),
# then configure and build Release into build/. Sourced, not run.
set -euo pipefail

MILLWEAR_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MILLWEAR_PACKAGES=(
  g++ cmake make pkg-config
  libbox2d-dev libeigen3-dev libcgal-dev libgtest-dev
  libgnuplot-iostream-dev gnuplot-nox
  libboost-iostreams-dev libboost-filesystem-dev libboost-system-dev
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev
  help2man dpkg-dev file python3-meshio
  libimgui-dev libglfw3-dev libgl-dev libstb-dev
  xvfb xauth libgl1-mesa-dri
)
# help2man writes the man page from the built program; dpkg-dev (dpkg-shlibdeps) and file let
# `cpack -G DEB` compute the package's library dependencies. python3-meshio reads the ParaView
# files back in the tests (a VTK reader independent of millwear). Dear ImGui, GLFW, OpenGL and
# stb build `millwear view` (optional in CMake: without them the rest builds); xvfb, xauth and
# Mesa's drivers run its tests on a virtual display with software OpenGL.
# Extra packages the caller may add (test.sh adds GNU parallel, Slurm, munge).
MILLWEAR_PACKAGES+=(${MILLWEAR_EXTRA_PACKAGES:-})

millwear_missing_packages() {
  local missing=()
  for p in "${MILLWEAR_PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  echo "${missing[@]:-}"
}

millwear_install() {
  local missing
  missing="$(millwear_missing_packages)"
  [ -z "$missing" ] && return 0
  if [ "$(id -u)" -ne 0 ]; then
    echo "millwear: these Debian packages are missing: $missing" >&2
    echo "millwear: install them with:" >&2
    echo "  sudo apt-get update && sudo apt-get install -y $missing" >&2
    exit 1
  fi
  echo "millwear: installing $missing"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  # shellcheck disable=SC2086
  apt-get install -y -qq --no-install-recommends $missing >/dev/null
}

millwear_build() {
  local jobs
  jobs="$(nproc 2>/dev/null || echo 2)"
  cmake -S "$MILLWEAR_ROOT" -B "$MILLWEAR_ROOT/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$MILLWEAR_ROOT/build" -j "$jobs"
}
