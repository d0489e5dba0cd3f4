#!/usr/bin/env bash
# An out-of-tree solid plugin against an installed shellflow, end to end:
#   1. cmake --install the build tree into a temporary prefix;
#   2. make the plugin's folder: MODE=template copies plugins/template_solid and adds the
#      README's CMakeLists.txt; MODE=new runs the installed `shellflow new solid`;
#   3. configure it with find_package(shellflow) (CMAKE_PREFIX_PATH=prefix), build it
#      (MODE=new also runs its generated GoogleTest);
#   4. run a scene with the installed harness, the plugin found through "plugin_path",
#      and check run.json: completed, every frame written, the solid loaded from the
#      plugin's build folder and the writer from the prefix (the installed CLI finds the
#      installed plugins), and the plate fell.
# Usage: out_of_tree_plugin_test.sh template|new SOURCE_DIR BUILD_DIR
set -euo pipefail
MODE="$1" SRC="$2" BUILD="$3"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/shellflow_oot_${MODE}_XXXXXX")"
trap 'rm -rf "$WORK"' EXIT
PREFIX="$WORK/prefix" PLUGIN="$WORK/plugin"
unset SHELLFLOW_PLUGIN_PATH
step() { echo "== $*"; }
quietly() {  # runs a command, showing its output only when it fails
  local log="$WORK/step.log"
  "$@" >"$log" 2>&1 || { cat "$log"; echo "FAILED: $*" >&2; exit 1; }
}

step "install into $PREFIX"
quietly cmake --install "$BUILD" --prefix "$PREFIX"
for f in bin/shellflow lib/libshellflow.so include/shellflow/sdk/plugin.hpp \
         lib/cmake/shellflow/shellflowConfig.cmake lib/cmake/shellflow/shellflowConfigVersion.cmake \
         lib/shellflow/plugins/shellflow_obj_writer.so; do
  [ -e "$PREFIX/$f" ] || { echo "not installed: $f" >&2; exit 1; }
done

case "$MODE" in
  template)
    NAME=template_solid
    mkdir -p "$PLUGIN"
    cp "$SRC"/plugins/template_solid/falling_plate.hpp "$SRC"/plugins/template_solid/falling_plate.cpp "$PLUGIN"/
    # The README's out-of-tree CMakeLists.txt ("Writing a solid plugin").
    cat >"$PLUGIN/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.25)
project(template_solid LANGUAGES CXX)
find_package(shellflow 0.1 REQUIRED)
shellflow_add_plugin(template_solid SOURCES falling_plate.cpp)
CMAKE
    ;;
  new)
    NAME=oot_plate
    step "shellflow new solid $NAME"
    quietly "$PREFIX/bin/shellflow" new solid "$NAME" "$PLUGIN"
    ;;
  *) echo "mode must be template or new" >&2; exit 2 ;;
esac

step "configure and build $PLUGIN against the installed shellflow"
quietly cmake -S "$PLUGIN" -B "$PLUGIN/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$PREFIX"
quietly cmake --build "$PLUGIN/build"
SO="$PLUGIN/build/plugins/shellflow_$NAME.so"
[ -f "$SO" ] || { echo "no plugin at $SO" >&2; exit 1; }
if [ "$MODE" = new ]; then
  step "the generated GoogleTest"
  quietly ctest --test-dir "$PLUGIN/build" --output-on-failure
  [ -f "$PLUGIN/scenes/${NAME}_drop.json" ] || { echo "no sample scene" >&2; exit 1; }
fi

step "run a scene through plugin_path with the installed harness"
mkdir -p "$WORK/scene"
cat >"$WORK/scene/drop.json" <<JSON
{
  "name": "drop",
  "time": {"fps": 24, "frames": 6},
  "plugin_path": ["$PLUGIN/build/plugins"],
  "solids": [{"plugin": "$NAME", "name": "plate", "transform": {"translate": [0, 1, 0]}}],
  "outputs": [{"plugin": "obj_writer"}]
}
JSON
(cd "$WORK/scene" && quietly "$PREFIX/bin/shellflow" run drop.json)
python3 - "$WORK/scene/out/drop" "$SO" "$PREFIX" <<'PY'
import csv, json, os, sys
out, so, prefix = sys.argv[1:]
run = json.load(open(os.path.join(out, "run.json")))
assert run["status"] == "completed", run["status"]
assert run["frames_written"] == 7, run["frames_written"]  # frames 0..6
files = {p["role"]: os.path.realpath(p["file"]) for p in run["plugins"]}
assert files["solid"] == os.path.realpath(so), f"solid loaded from {files['solid']}, not {so}"
assert files["writer"].startswith(os.path.realpath(prefix) + "/lib/shellflow/plugins/"), files["writer"]
rows = list(csv.DictReader(open(os.path.join(out, "metrics.csv"))))
height = [k for k in rows[0] if k.endswith("height")]
assert height, f"no height column in {list(rows[0])}"
first, last = float(rows[0][height[0]]), float(rows[-1][height[0]])
assert last < first, f"the plate did not fall: {first} -> {last}"
print(f"ok: {run['frames_written']} frames, {height[0]} {first:.4f} -> {last:.4f}, "
      f"signature '{run['build_signature']}'")
PY
