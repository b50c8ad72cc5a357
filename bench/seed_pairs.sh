#!/usr/bin/env bash
# One setting's noise over several pairs of seeds: where a scene's error is heavy-tailed (Veach MIS's fireflies), two
# seeds' difference is a lottery, and the pooled figure (the RMS of the pairs' figures) is what to compare. Noise =
# RMS over pixels of a pair's difference / sqrt(2), relative to the mean, outside the pixels where the camera sees a
# lamp (bench/noise_lamps.py; the lamps from a --max-depth 0 render).
#
# usage: bench/seed_pairs.sh BUILD OUT SCENE SECONDS PAIRS [RENDER ARGS...]
#   renders seeds 1 .. 2·PAIRS of SCENE at 128 × 128, one thread each, two at a time (taskset -c 0 and 1), each for
#   SECONDS, with the given firstshot-render arguments (e.g. --firstshot T.fsd, --integrator path); prints each pair's
#   figure, then "pooled N".
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:?usage: bench/seed_pairs.sh BUILD OUT SCENE SECONDS PAIRS [RENDER ARGS...]}
out=${2:?} scene=${3:?} seconds=${4:?} pairs=${5:?}
shift 5
render="$build/render/firstshot-render"
mkdir -p "$out"
[ -f "$out/lamps.exr" ] || "$render" "$scene" --integrator path --max-depth 0 --spp 256 --threads 2 --width 128 --height 128 \
  --quiet -o "$out/lamps.exr" > /dev/null 2>&1
figures=()
for ((p = 0; p < pairs; ++p)); do
  for s in $((2 * p + 1)) $((2 * p + 2)); do
    taskset -c $((s % 2)) "$render" "$scene" --width 128 --height 128 --time "$seconds" --threads 1 --seed "$s" "$@" \
      -o "$out/seed-$s.exr" > "$out/seed-$s.log" 2>&1 &
  done
  wait
  f=$(python3 "$here/bench/noise_lamps.py" "$out/lamps.exr" "$out/seed-$((2 * p + 1)).exr" "$out/seed-$((2 * p + 2)).exr")
  echo "seeds $((2 * p + 1)),$((2 * p + 2)): ${f%% *}"
  figures+=("${f%% *}")
done
python3 -c "import sys, math; v = [float(x) for x in sys.argv[1:]]; print('pooled %.4f' % math.sqrt(sum(x * x for x in v) / len(v)))" "${figures[@]}"
