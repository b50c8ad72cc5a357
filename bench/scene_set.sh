# Sourced by the per-scene benches (table_ray_cost.sh, cache_ray_cost.sh) after `set -euo pipefail`:
#   source "$(dirname "$0")/scene_set.sh" NAME "$@"
# reads their arguments BUILD TABLES [SCENES...] (SCENES default: the shipped scenes and those of ../shared/scenes)
# and sets build, tables, scenes (an array), pin (taskset -c ${CORE:-0}) and scratch (a folder removed on exit).
# scene_tag SCENE: the scene's name in tables (its folder and file); scene_table SCENE: prints its table in $tables,
# made at the preprocessor's defaults where absent, or fails with the preprocessor's output in $scratch/pre.log.
bench_name=$1
shift
usage="usage: bench/$bench_name.sh BUILD TABLES [SCENES...]"
build=${1:?$usage}
tables=${2:?$usage}
shift 2
scenes=("$@")
if [ ${#scenes[@]} -eq 0 ]; then
  here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  scenes=("$here"/scenes/*.json)
  shared="$here/../shared/scenes"
  if [ -d "$shared" ]; then
    scenes+=("$shared/veach-bidir/scene.xml" "$shared/veach-mis/scene.xml" "$shared/bitterli-cornell-box/scene.xml"
             "$shared/mcguire-cornell-box/CornellBox-Original.obj" "$shared/classroom/scene.xml")
  else
    echo "$bench_name: ../shared/scenes is absent: the public scenes are left out" >&2
  fi
fi
pin=(taskset -c "${CORE:-0}")
mkdir -p "$tables"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

scene_tag() { echo "$(basename "$(dirname "$1")")-$(basename "$1" | sed 's/\.[a-z]*$//')"; }

scene_table() {
  local table
  table="$tables/$(scene_tag "$1").fsd"
  [ -f "$table" ] || "${pin[@]}" "$build/preprocess/firstshot-preprocess" "$1" -o "$table" --threads 1 -q \
    > "$scratch/pre.log" 2>&1 || return 1
  echo "$table"
}
