#!/usr/bin/env bash
# Fuzzes the scene loader and validator (tests/fuzz/scene_fuzzer.cpp) for SECONDS
# (default 60) with libFuzzer, ASan and UBSan, seeded with every scene under configs/.
#   bash scripts/fuzz.sh 600
# Builds with clang in build-fuzz/ (its own folder: the compiler and flags differ from the
# Release build). The corpus grows in build-fuzz/corpus/; a crash, leak, hang or sanitizer
# report stops the run and leaves the input in build-fuzz/findings/. To replay one:
#   build-fuzz/bin/scene_fuzzer build-fuzz/findings/crash-<sha1>
# Extra arguments go to libFuzzer (e.g. -jobs=2 -workers=2, -dict=..., -max_len=...).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
FUZZ_SECONDS="${1:-60}"
shift || true

export BUILD_DIR="${FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
export BUILD_TYPE=Sanitize  # -O1 -g, ASan + UBSan (cmake/ShellflowOptions.cmake)
export EXTRA_PACKAGES="clang libclang-rt-14-dev libomp-dev"
# fuzzer-no-link everywhere: libshellflow and the plugins report coverage to libFuzzer;
# only the fuzzer executable links libFuzzer's main. No tests or benchmarks here.
EXTRA_CMAKE_ARGS="-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link"
EXTRA_CMAKE_ARGS+=" -DSHELLFLOW_BUILD_FUZZERS=ON -DSHELLFLOW_BUILD_TESTS=OFF"
export EXTRA_CMAKE_ARGS+=" -DSHELLFLOW_BUILD_BENCHMARKS=OFF"
source "$ROOT/scripts/setup.sh"

CORPUS="$BUILD_DIR/corpus"
FINDINGS="$BUILD_DIR/findings"
mkdir -p "$CORPUS" "$FINDINGS"
# Seeds: every scene under configs/ (copied by content, so re-running adds nothing new).
while IFS= read -r -d '' f; do
  cp "$f" "$CORPUS/seed-$(sha1sum < "$f" | cut -c1-16).json"
done < <(find "$ROOT/configs" -name '*.json' -print0)

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
export SHELLFLOW_PLUGIN_PATH=  # only the plugins of this build
echo "== fuzzing the scene loader for ${FUZZ_SECONDS}s (corpus $CORPUS)"
# Runs in the findings folder: an input naming a relative plugin file resolves there.
cd "$FINDINGS"
"$BUILD_DIR/bin/scene_fuzzer" -max_total_time="$FUZZ_SECONDS" -timeout=10 -rss_limit_mb=4096 \
  -max_len=16384 -print_final_stats=1 -artifact_prefix="$FINDINGS/" "$@" "$CORPUS"
