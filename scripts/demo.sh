#!/usr/bin/env bash
# Set up, build, and run the demo scene into out/demo/ (replacing an earlier demo run).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/setup.sh"
cd "$ROOT"
"$BUILD_DIR/bin/shellflow" run configs/demo.json --out out/demo --overwrite "$@"
echo "== demo written to $ROOT/out/demo (meshes/, metrics.csv, run.json)"
