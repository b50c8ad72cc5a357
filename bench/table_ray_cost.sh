#!/usr/bin/env bash
# What reading a first-shot table costs per ray: Mrays/s of path (--patch-nee off), light and BDPT without the table
# and with it (light and BDPT shooting from the lit patches, their default), 128 x 128, 16 spp, one thread pinned to
# core ${CORE:-0}. The ratio without / with is the time a table reader's ray takes more; --integrator auto counts those
# rays at kTableRayCost each where it weighs the table against leaving it unread (render/loop/integrator_pilot.cpp).
#
# usage: bench/table_ray_cost.sh BUILD TABLES [SCENES...]
#   BUILD: build/release; TABLES: a folder for the scenes' tables (made at the preprocessor's defaults where absent);
#   SCENES: scene files (default: the shipped scenes and those of ../shared/scenes).
# Prints a Markdown table and the medians on stdout.
set -euo pipefail
source "$(dirname "$0")/scene_set.sh" table_ray_cost "$@"

# rate SCENE ARGS...: the render's Mrays/s, or "-" when it is refused.
rate() {
  local scene=$1
  shift
  "${pin[@]}" "$build/render/firstshot-render" "$scene" --width 128 --height 128 --spp 16 --threads 1 \
    -o "$scratch/x.exr" "$@" 2>&1 | grep -o '[0-9.]* Mrays/s' | tail -1 | cut -d' ' -f1 | grep . || echo "-"
}

echo "| scene | path: Mrays/s without / with the table (ratio) | light | bdpt |"
echo "|---|---|---|---|"
ratios="$scratch/ratios"
: > "$ratios"
for scene in "${scenes[@]}"; do
  tag=$(scene_tag "$scene")
  if ! table=$(scene_table "$scene"); then
    echo "| $tag | no table: $(head -c 80 "$scratch/pre.log") | | |"
    continue
  fi
  row="| $tag"
  for integrator in path light bdpt; do
    extra=()
    [ "$integrator" = path ] && extra=(--patch-nee off)
    without=$(rate "$scene" --integrator "$integrator")
    with=$(rate "$scene" --integrator "$integrator" --firstshot "$table" "${extra[@]}")
    if [ "$without" = "-" ] || [ "$with" = "-" ]; then
      row+=" | –"
    else
      r=$(python3 -c "print('%.2f' % ($without / $with))")
      echo "$integrator $r" >> "$ratios"
      row+=" | $without / $with ($r)"
    fi
  done
  echo "$row |"
done
python3 - "$ratios" <<'EOF'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
for name in ("path", "light", "bdpt", None):
    r = [float(v) for n, v in rows if name in (None, n)]
    if r:
        print(f"{name or 'all'}: median {statistics.median(r):.2f} over {len(r)} pairs, {min(r):.2f}-{max(r):.2f}")
EOF
