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
if [ "$BUILD_TYPE" = Sanitize ]; then
  # Any report fails its test. intercept_tls_get_addr=0: gcc 12's sanitizers track the dynamic
  # TLS of a dlopen'ed library (a plugin's OpenVDB, TBB) through __tls_get_addr and, with
  # glibc 2.36, read some blocks' bounds as nonsense; LeakSanitizer's tracer then crashes at
  # exit ("Tracer caught signal 11") in whichever test's addresses fall that way. Static TLS,
  # stacks and globals are still scanned for leaks.
  export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0}"
  export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
fi
ctest --output-on-failure -j "$JOBS" --timeout 600 "$@"
