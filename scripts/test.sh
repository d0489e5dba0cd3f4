#!/usr/bin/env bash
# Set up, build, and run the whole test suite (ctest; benchmarks are not run).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/setup.sh"
cd "$BUILD_DIR"
# ctest runs tests side by side on few cores: OpenMP threads that spin at barriers would
# steal each other's cores (a 2-core machine ran the coupling tests 8x slower).
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-PASSIVE}"
ctest --output-on-failure -j "$JOBS" --timeout 600 "$@"
