#!/usr/bin/env bash
# Set up, build, and run the whole test suite (ctest; benchmarks are not run).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/setup.sh"
cd "$BUILD_DIR"
# ctest runs tests side by side on few cores, each with as many OpenMP threads as cores:
# threads that yield at once suit that best. (Without this the test binaries take the
# bounded spin of framework/include/shellflow/runtime/openmp_wait_policy.hpp, not libgomp's
# default spin, which ran the coupling tests 8x slower on a 2-core machine.)
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-PASSIVE}"
ctest --output-on-failure -j "$JOBS" --timeout 600 "$@"
