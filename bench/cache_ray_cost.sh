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
source "$(dirname "$0")/scene_set.sh" cache_ray_cost "$@"

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
: > "$ratios"
for scene in "${scenes[@]}"; do
  tag=$(scene_tag "$scene")
  table=$(scene_table "$scene") || table=""
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
