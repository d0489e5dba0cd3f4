#!/usr/bin/env bash
# Set up, build, and run the demo scene into out/demo/ (replacing an earlier demo run).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/setup.sh"
cd "$ROOT"
# The paper's Fig. 2 at preview size: a smoke jet blowing a cloth curtain, two-way coupled.
# shellflow chooses a bounded OpenMP spin itself (docs/user-guide.md: the OpenMP wait policy).
"$BUILD_DIR/bin/shellflow" run configs/smoke_curtain_preview.json --out out/demo --overwrite "$@"
echo "== demo written to $ROOT/out/demo (meshes/, volumes/, previews/, metrics.csv, run.json)"
