#!/usr/bin/env bash
# What the irradiance cache's rays cost against the path tracer's: Mrays/s of the cache's fill and of its passes, and
# of the path tracer, without a table and with it (--patch-nee off for both), 128 x 128, 64 spp, one thread pinned to
# core ${CORE:-0}. The ratios path / fill and path / passes are the time a cache ray takes more; --integrator auto
# counts the fill's rays at kFillRayCost each and the passes' at one (render/loop/integrator_pilot.cpp).
#
# usage: bench/cache_ray_cost.sh BUILD TABLES [SCENES...]
#   BUILD: build/release; TABLES: a folder for the scenes' tables (made at the preprocessor's defaults where absent);
#   SCENES: scene files (default: the shipped scenes and those of ../shared/scenes).
# Prints a Markdown table and the medians on stdout.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:?usage: bench/cache_ray_cost.sh BUILD TABLES [SCENES...]}
tables=${2:?usage: bench/cache_ray_cost.sh BUILD TABLES [SCENES...]}
shift 2
scenes=("$@")
if [ ${#scenes[@]} -eq 0 ]; then
  scenes=("$here"/scenes/*.json)
  shared="$here/../shared/scenes"
  if [ -d "$shared" ]; then
    scenes+=("$shared/veach-bidir/scene.xml" "$shared/veach-mis/scene.xml" "$shared/bitterli-cornell-box/scene.xml"
             "$shared/mcguire-cornell-box/CornellBox-Original.obj" "$shared/classroom/scene.xml")
  else
    echo "cache_ray_cost: ../shared/scenes is absent: the public scenes are left out" >&2
  fi
fi
pin=(taskset -c "${CORE:-0}")
mkdir -p "$tables"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

# render SCENE ARGS...: the render's stderr in $scratch/log (empty when it is refused).
render() {
  local scene=$1
  shift
  "${pin[@]}" "$build/render/firstshot-render" "$scene" --width 128 --height 128 --spp 64 --threads 1 \
    -o "$scratch/x.exr" "$@" > "$scratch/log" 2>&1 || : > "$scratch/log"
}

echo "| scene | table | fill Mrays/s | passes Mrays/s | path Mrays/s | fill ray cost | pass ray cost |"
echo "|---|---|---|---|---|---|---|"
ratios="$scratch/ratios"
for scene in "${scenes[@]}"; do
  tag=$(basename "$(dirname "$scene")")-$(basename "$scene" | sed 's/\.[a-z]*$//')
  table="$tables/$tag.fsd"
  if [ ! -f "$table" ] && ! "${pin[@]}" "$build/preprocess/firstshot-preprocess" "$scene" -o "$table" --threads 1 -q \
       > "$scratch/pre.log" 2>&1; then
    table=""
  fi
  for with in no yes; do
    args=()
    if [ "$with" = yes ]; then
      [ -n "$table" ] || continue
      args=(--firstshot "$table" --patch-nee off)
    fi
    render "$scene" --integrator irradiance-cache "${args[@]}"
    fill=$(grep -o 'fill [0-9.]* s, [0-9.]* Mrays' "$scratch/log" | awk '{ if ($2 > 0) printf "%.2f", $4 / $2 }')
    passes=$(grep -o 'spp in [0-9.]* s: [0-9.]* Mrays/s' "$scratch/log" | tail -1 | awk '{ print $5 }')
    render "$scene" --integrator path "${args[@]}"
    path=$(grep -o 'spp in [0-9.]* s: [0-9.]* Mrays/s' "$scratch/log" | tail -1 | awk '{ print $5 }')
    if [ -z "$fill" ] || [ -z "$passes" ] || [ -z "$path" ]; then
      echo "| $tag | $with | – | – | – | | |"
      continue
    fi
    read -r rf rp < <(python3 -c "print('%.2f %.2f' % ($path / $fill, $path / $passes))")
    echo "fill $rf" >> "$ratios"
    echo "passes $rp" >> "$ratios"
    echo "| $tag | $with | $fill | $passes | $path | $rf | $rp |"
  done
done
python3 - "$ratios" <<'EOF'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
for name in ("fill", "passes"):
    r = [float(v) for n, v in rows if n == name]
    if r:
        print(f"{name}: median {statistics.median(r):.2f} over {len(r)} renders, {min(r):.2f}-{max(r):.2f}")
EOF
