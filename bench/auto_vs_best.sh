#!/usr/bin/env bash
# Equal total time: what the defaults give (--integrator auto, with a first-shot table and without) against every
# method a user could pick without a table (path with the light tree, path with NEE to every light, the irradiance
# cache, light tracing, BDPT). Noise = RMS over pixels of the two seeds' difference / sqrt(2), relative to the mean
# of the pixels counted, over the pixels where the camera sees no lamp (bench/noise_lamps.py: a lamp's pixel takes
# its value from how much of it the lamp covers, alike in every method; the scene rendered with --max-depth 0 marks
# them); efficiency ratio = noise^2 ratio. OUT/SCENE/noise.txt has each figure over the whole picture too, and the
# lamps' pixels' share of it. The table's preprocessing is counted
# in the first-shot side's time: its render gets SECONDS minus the preprocessing time. "path + table" and "cache + table"
# force the path tracer and the irradiance cache on the table (with the luminaires the preprocessor found,
# docs/luminaires.md; their number is a column). The cache's noise leaves out its bias (its interpolation error).
#
# usage: bench/auto_vs_best.sh BUILD OUT [SECONDS] [WIDTH] [HEIGHT] [SCENES...]
#   BUILD: build/release; OUT: a folder for the images and tables; SECONDS (default 10) per render;
#   WIDTH x HEIGHT (default 128 x 128); SCENES: scene files (default: the public scenes of ../shared/scenes and the
#   shipped bowl-lamp and glass-bulb rooms). Each render runs on one core (taskset -c ${CORE:-0}, --threads 1).
# Prints a Markdown table on stdout (also OUT/table.md).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:?usage: bench/auto_vs_best.sh BUILD OUT [SECONDS] [WIDTH] [HEIGHT] [SCENES...]}
out=${2:?usage: bench/auto_vs_best.sh BUILD OUT [SECONDS] [WIDTH] [HEIGHT] [SCENES...]}
seconds=${3:-10}
width=${4:-128}
height=${5:-128}
shift $(( $# < 5 ? $# : 5 ))
scenes=("$@")
shared="$here/../shared/scenes"
if [ ${#scenes[@]} -eq 0 ]; then
  scenes=("$here/scenes/bowl-lamp-room.json" "$here/scenes/glass-bulb-room.json")
  if [ -d "$shared" ]; then
    scenes+=("$shared/veach-bidir/scene.xml" "$shared/veach-mis/scene.xml" "$shared/bitterli-cornell-box/scene.xml"
             "$shared/mcguire-cornell-box/CornellBox-Original.obj" "$shared/classroom/scene.xml")
  else
    echo "auto_vs_best: ../shared/scenes is absent: the public scenes are left out" >&2
  fi
fi
render="$build/render/firstshot-render"
preprocess="$build/preprocess/firstshot-preprocess"
pin=(taskset -c "${CORE:-0}")
mkdir -p "$out"

# noise NAME: the relative noise of one image from the two seeds' images, outside the lamps' pixels; the line
# "NAME OUTSIDE WHOLE LAMPS-SHARE" goes to noise.txt.
noise() {
  local figures
  figures=$(python3 "$here/bench/noise_lamps.py" "$dir/lamps.exr" "$dir/$1-1.exr" "$dir/$1-2.exr")
  echo "$1 $figures" >> "$dir/noise.txt"
  echo "${figures%% *}"
}

# run NAME TIME ARGS...: two seeds; prints the noise, or "-" when the render is refused.
run() {
  local name=$1 time=$2
  shift 2
  for s in 1 2; do
    if ! "${pin[@]}" "$render" "$scene" --threads 1 --width "$width" --height "$height" --time "$time" --seed "$s" \
         -o "$dir/$name-$s.exr" "$@" > "$dir/$name-$s.log" 2>&1; then
      echo "-"
      return
    fi
  done
  noise "$name"
}

table="$out/table.md"
{
  echo "| scene | preprocess (s) | luminaires | path | path, NEE to every light | irradiance cache | light | bdpt | best without table | auto, no table (choice) | path + table | cache + table | auto + table (choice) | auto + table against the best |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$table"
for scene in "${scenes[@]}"; do
  tag=$(basename "$(dirname "$scene")")-$(basename "$scene" | sed 's/\.[a-z]*$//')
  dir="$out/$tag"
  mkdir -p "$dir"
  echo "auto_vs_best: $tag" >&2
  start=$(date +%s.%N)
  if ! "${pin[@]}" "$preprocess" "$scene" -o "$dir/table.fsd" --threads 1 -q > "$dir/preprocess.log" 2>&1; then
    echo "| $tag | refused: $(grep -m1 -o 'error.*' "$dir/preprocess.log" | cut -c1-80) |||||||||||" >> "$table"
    continue
  fi
  prep=$(python3 -c "import time; print('%.1f' % (time.time() - $start))")
  "${pin[@]}" "$render" "$scene" --integrator path --max-depth 0 --spp 256 --threads 1 --width "$width" --height "$height" --quiet \
    -o "$dir/lamps.exr" > "$dir/lamps.log" 2>&1
  rm -f "$dir/noise.txt"
  declare -A n=()
  n[path]=$(run path "$seconds" --integrator path)
  n[all]=$(run all "$seconds" --integrator path --light-sampler all)
  n[cache]=$(run cache "$seconds" --integrator irradiance-cache)
  n[light]=$(run light "$seconds" --integrator light)
  n[bdpt]=$(run bdpt "$seconds" --integrator bdpt)
  n[auto]=$(run auto "$seconds")
  rest=$(python3 -c "print(max(0.5, $seconds - $prep))")
  n[pathT]=$(run pathT "$rest" --firstshot "$dir/table.fsd" --integrator path)
  n[cacheT]=$(run cacheT "$rest" --firstshot "$dir/table.fsd" --integrator irradiance-cache)
  n[autoT]=$(run autoT "$rest" --firstshot "$dir/table.fsd")
  lums=$(grep -c '^luminaire' "$dir/preprocess.log" || true)
  best=$(printf '%s\n' "${n[path]}" "${n[all]}" "${n[cache]}" "${n[light]}" "${n[bdpt]}" | grep -v '^-$' | sort -g | head -1)
  choice() {
    grep -o 'auto chose [^(]*' "$dir/$1-1.log" | head -1 | sed 's/.*auto chose //; s/ *$//' | grep . ||
      grep -o -- '--integrator auto: [a-z -]* (' "$dir/$1-1.log" | head -1 | sed 's/.*auto: //; s/ *($//'
  }
  ratio=$(python3 -c "b=float('$best'); a='${n[autoT]}'; print('-' if a == '-' else '%.2fx' % ((b / float(a))**2))")
  echo "| $tag | $prep | $lums | ${n[path]} | ${n[all]} | ${n[cache]} | ${n[light]} | ${n[bdpt]} | $best | ${n[auto]} ($(choice auto)) | ${n[pathT]} | ${n[cacheT]} | ${n[autoT]} ($(choice autoT)) | $ratio |" >> "$table"
  unset n
done
cat "$table"
