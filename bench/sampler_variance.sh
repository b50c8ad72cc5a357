#!/bin/bash
# The samplers' variance on every scene of the speed-against-error harness, without a reference
# (docs/measurements.md, "Every harness scene and integrator, at equal samples, without a reference"):
# two renders with seeds 1 and 2 per scene, method and sampler; Var ∝ the mean squared difference of the two.
# Prints one Markdown row per scene and method: independent/sobol of Σ(a−b)² and of the ε-relative rel. RMSE², the
# time ratio sobol/independent (each sampler's two renders, wall seconds) and the equal-time ratios (variance × time,
# independent over sobol: > 1 means sobol reaches a given error sooner).
# Usage: [N=64] [BUILD=build/release] [THREADS=2] [PIN="taskset -c 0"] bash bench/sampler_variance.sh OUT_DIR
# (from the repository root; for the times, THREADS=1 and PIN a core nothing else runs on)
set -euo pipefail
O=${1:?usage: bench/sampler_variance.sh OUT_DIR}; N=${N:-64}; B=${BUILD:-build/release}; T=${THREADS:-2}
PIN=${PIN:-}
R=$B/render/firstshot-render; P=$B/preprocess/firstshot-preprocess; C=$B/bench/firstshot-compare
mkdir -p "$O"
METHODS="path path-fs ic-fs light light-fs bdpt bdpt-fs"
args() {  # method, fsd
  case $1 in
    path) echo "--integrator path" ;;              path-fs) echo "--integrator path --firstshot $2" ;;
    ic-fs) echo "--integrator irradiance-cache --firstshot $2" ;;
    light) echo "--integrator light" ;;            light-fs) echo "--integrator light --firstshot $2" ;;
    bdpt) echo "--integrator bdpt" ;;              bdpt-fs) echo "--integrator bdpt --firstshot $2" ;;
  esac
}
field() { grep -o "\"$1\": [0-9.e+-]*" | cut -d' ' -f2; }
for sc in cornell many-lights sierpinski-glossy fixture-room office-floor; do
  [ -f "$O/$sc.fsd" ] || $PIN "$P" "scenes/$sc.json" -o "$O/$sc.fsd" --quiet --threads "$T"
  for me in $METHODS; do
    row="| $sc | $me |"; plain=(); rel=(); secs=()
    for m in independent sobol; do
      t=0
      for s in 1 2; do
        # shellcheck disable=SC2046,SC2086
        $PIN "$R" "scenes/$sc.json" $(args "$me" "$O/$sc.fsd") --sampler $m --width 80 --height 60 --spp "$N" \
            --seed $s --threads "$T" -o "$O/$sc-$me-$m-$N-$s.exr" > "$O/log" 2>&1
        # the time of the work (the cache's fill and the render: each phase's "done in X s"), not of the loading
        t=$(grep -o 'done in [0-9.]* s' "$O/log" | awk -v t="$t" '{ t += $3 } END { print t }')
      done
      secs+=("$t")
      j=$("$C" "$O/$sc-$me-$m-$N-1.exr" "$O/$sc-$me-$m-$N-2.exr")
      plain+=("$(echo "$j" | field rmse)"); rel+=("$(echo "$j" | field rel_rmse)")
    done
    awk -v r="$row" -v a="${plain[0]}" -v b="${plain[1]}" -v c="${rel[0]}" -v d="${rel[1]}" \
        -v ti="${secs[0]}" -v ts="${secs[1]}" 'BEGIN { p = (a * a) / (b * b); e = (c * c) / (d * d); q = ti / ts
          printf "%s %.2f× | %.2f× | %.2f s / %.2f s | %.2f× | %.2f× |\n", r, p, e, ti, ts, p * q, e * q }'
  done
done
