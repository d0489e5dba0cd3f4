#!/usr/bin/env bash
# Installs what shellflow needs (Debian 12 packages) and builds it in Release.
# Sourced by demo.sh and test.sh; run alone it only sets up and builds.
#   BUILD_DIR   build folder (default: build)
#   BUILD_TYPE  CMake build type (default: Release; "Sanitize" for ASan+UBSan)
#   EXTRA_PACKAGES    more Debian packages, space-separated (fuzz.sh: clang and its runtime)
#   EXTRA_CMAKE_ARGS  more configure arguments, space-separated (fuzz.sh: the compiler)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
BUILD_TYPE="${BUILD_TYPE:-Release}"

PACKAGES=(
  cmake ninja-build g++ pkg-config
  ccache               # the build reuses objects across rebuilds and clones (cmake/ShellflowOptions.cmake)
  libeigen3-dev libbullet-dev libsuitesparse-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev libtbb-dev libspdlog-dev libcli11-dev
  libtinyobjloader-dev libassimp-dev libstb-dev libpng-dev libopenvdb-dev libboost-iostreams-dev
  libopenblas0-openmp  # an optimised BLAS for CHOLMOD (the reference BLAS is ~100x slower)
  python3-matplotlib   # scripts/plot_dam_break.py draws the README's dam-break figure
  ffmpeg               # a run with PNG previews ends with preview.mp4 (optional: a note if absent)
)

read -r -a extra_packages <<< "${EXTRA_PACKAGES:-}"
PACKAGES+=("${extra_packages[@]}")

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "shellflow needs these Debian packages. Install them as root, then run this again:" >&2
    echo "  apt-get update && apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
  echo "== installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

JOBS="${JOBS:-$(nproc)}"
echo "== configuring ($BUILD_TYPE) in $BUILD_DIR"
mkdir -p "$BUILD_DIR"
read -r -a extra_cmake_args <<< "${EXTRA_CMAKE_ARGS:-}"
cmake -S "$ROOT" -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE="$BUILD_TYPE" -DSHELLFLOW_PLUGINS= \
  "${extra_cmake_args[@]}" > "$BUILD_DIR/configure.log" 2>&1 \
  || { cat "$BUILD_DIR/configure.log"; exit 1; }
echo "== building with $JOBS jobs"
cmake --build "$BUILD_DIR" -j "$JOBS"
