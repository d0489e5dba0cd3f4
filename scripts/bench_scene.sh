#!/usr/bin/env bash
# Seconds per frame of a scene, by phase, from its metrics.csv:
#   bash scripts/bench_scene.sh SCENE.json [FRAMES] [OUT]
# runs FRAMES frames (default 10) into OUT (default out/bench/<scene stem>, overwritten) and
# prints the mean seconds per frame of each phase (advect = advection with visibility and
# swept-node refill, coupling = the §5.1 coupling solve, solids, project) and the peak
# resident memory of the run.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCENE="${1:?usage: bench_scene.sh SCENE.json [FRAMES] [OUT]}"
FRAMES="${2:-10}"
OUT="${3:-$ROOT/out/bench/$(basename "${SCENE%.json}")}"
BIN="${BUILD_DIR:-$ROOT/build}/bin/shellflow"
[ -x "$BIN" ] || { echo "build first: bash scripts/test.sh (or demo.sh)" >&2; exit 1; }
/usr/bin/time -v "$BIN" run "$SCENE" --frames "$FRAMES" --out "$OUT" --overwrite \
  2> "$OUT.time.log" >/dev/null || { cat "$OUT.time.log" >&2; exit 1; }
awk -F, -v frames="$FRAMES" '
  NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  { a += $col["t_advect"]; c += $col["t_coupling_forces"]; s += $col["t_solids"];
    p += $col["t_project"]; n += 1 }
  END {
    printf "%d frames, %d steps (%.1f per frame)\n", frames, n, n / frames
    printf "seconds per frame: advect %.3f  coupling %.3f  solids %.3f  project %.3f  total %.3f\n",
           a / frames, c / frames, s / frames, p / frames, (a + c + s + p) / frames
  }' "$OUT/metrics.csv"
grep -E "Maximum resident set size|Elapsed \(wall" "$OUT.time.log" | sed 's/^\s*//'
