#!/bin/bash
# Usage: bench/gpu_preprocess.sh [BIN_DIR]        (docs/gpu.md)
# The preprocessor on llvmpipe against the GPU, in one run on one machine: each case once with OSMesa (llvmpipe, one
# worker per core) and once with EGL (the GPU the EGL device platform finds; llvmpipe through Mesa's surfaceless
# platform where there is none), printing wall time, the preprocessor's summary line and its phase profile
# (FIRSTSHOT_PROFILE=1, thread-seconds), and whether the two tables agree (firstshot-fsd-compare: the same light
# samples, every sample's delivered flux within 1e-3). The EGL runs get `--gl-reduce gpu` when the binary has it.
# Cases: the Cornell-class case (cornell at 0.012 m uniform patches, 9 light vertices, hemicube R = 512), cornell,
# many-lights, office-floor (each at its own settings, --backend gl) and the 1 M patches x 1000 point lights scaling
# scene of bench/preprocess_scaling.py (R = 128), which also runs with Embree on the CPU (what --backend auto takes on a
# CPU there). Run from the repository root.
#   BIN_DIR  folder with firstshot-preprocess and firstshot-fsd-compare (a build folder works); default: the bundle
#            .gpu/bundle.tar.xz (make gpu-bundle), unpacked into $BUNDLE_DIR (default /tmp/firstshot-gpu) and run with
#            its libraries, the machine's NVIDIA driver for EGL (GLVND vendor file under /usr/local/nvidia if there).
# Environment: SMALL=1 smaller cases (R 128 / 64, scaling 100 k x 100) for a CPU check; CASES="names" a subset;
#   OUT=folder: summary.md and log.txt written there too; RUN_LIMIT seconds per run (default 300); WORK folder for the
#   tables (default a temporary one).
set -u
[ -d scenes ] && [ -d preprocess ] || { echo "gpu_preprocess.sh: run from the repository root" >&2; exit 2; }
WORK=${WORK:-$(mktemp -d)}
mkdir -p "$WORK"
LOG=$WORK/log.txt; : >"$LOG"
say() { echo "$@" | tee -a "$LOG"; }

# --- binaries and libraries
if [ $# -ge 1 ]; then
  BIN=$1; [ -x "$BIN/firstshot-preprocess" ] || BIN=$1/preprocess
  SCENES_EXTRA=""
else
  [ -f .gpu/bundle.tar.xz ] || { echo "gpu_preprocess.sh: no .gpu/bundle.tar.xz (make gpu-bundle) and no BIN_DIR" >&2; exit 2; }
  B=${BUNDLE_DIR:-/tmp/firstshot-gpu}
  rm -rf "$B"; mkdir -p "$B"; tar -C "$B" -xJf .gpu/bundle.tar.xz || exit 2
  BIN=$B/bin; SCENES_EXTRA=$B/scenes
  libs=$B/lib
  for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do [ -d "$d" ] && libs=$libs:$d; done
  export LD_LIBRARY_PATH=$libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  # GLVND looks for vendor files in /etc and /usr/share; the driver's may sit under /usr/local/nvidia.
  if [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ] && [ -d /usr/local/nvidia/share/glvnd/egl_vendor.d ]; then
    export __EGL_VENDOR_LIBRARY_DIRS=/usr/local/nvidia/share/glvnd/egl_vendor.d:/etc/glvnd/egl_vendor.d:/usr/share/glvnd/egl_vendor.d
  fi
fi
P=$BIN/firstshot-preprocess; CMP=$BIN/firstshot-fsd-compare
[ -x "$P" ] && [ -x "$CMP" ] || { echo "gpu_preprocess.sh: no firstshot-preprocess / firstshot-fsd-compare in $BIN" >&2; exit 2; }
REDUCE=""; "$P" --help 2>/dev/null | grep -q -- "--gl-reduce" && REDUCE="--gl-reduce gpu"

say "# bench/gpu_preprocess.sh $(date -u +%FT%TZ) on $(hostname), $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg)"
command -v nvidia-smi >/dev/null && nvidia-smi -L 2>&1 | tee -a "$LOG"
say "binaries: $BIN; EGL runs add: ${REDUCE:-(no --gl-reduce in this build)}; $(ldd --version 2>&1 | head -1)"
"$P" --gl-device list 2>&1 | tee -a "$LOG"
vdirs=${__EGL_VENDOR_LIBRARY_DIRS:-}
say "EGL vendor files: $(ls ${vdirs//:/ } /usr/share/glvnd/egl_vendor.d /etc/glvnd/egl_vendor.d 2>/dev/null | tr "\n" " ")"

# --- the cases: name | scene | options | CPU runs (the first is the reference of the comparison)
if [ "${SMALL:-0}" = 1 ]; then R1=128; R2=64; SCALE=(100000 100); else R1=512; R2=""; SCALE=(1000000 1000); fi
SCALE_NAME=scaling-$((SCALE[0] / 1000))k-${SCALE[1]}; [ "${SCALE[0]}" = 1000000 ] && SCALE_NAME=scaling-1M-${SCALE[1]}
SCALE_SCENE=$SCENES_EXTRA/$SCALE_NAME.json
if [ -z "$SCENES_EXTRA" ] || [ ! -f "$SCALE_SCENE" ]; then
  SCALE_SCENE=$WORK/$SCALE_NAME.json
  python3 bench/preprocess_scaling.py --scene-only "${SCALE[@]}" >"$SCALE_SCENE" || say "no python3: $SCALE_NAME skipped"
fi
res() { [ -n "$R2" ] && echo "--resolution $R2"; }
ALL=(
  "cornell-class|scenes/cornell.json|--patch-size 0.012 --min-patch-size 0.012 --light-patch-size 0.065 --resolution $R1|osmesa"
  "cornell|scenes/cornell.json|$(res)|osmesa"
  "many-lights|scenes/many-lights.json|$(res)|osmesa"
  "office-floor|scenes/office-floor.json|$(res)|osmesa"
  "$SCALE_NAME|$SCALE_SCENE||osmesa embree"
)
CASES=${CASES:-cornell-class cornell many-lights office-floor $SCALE_NAME}

# --- one run: prints and records wall, preprocess seconds, phases
num() { awk -v k="$1" 'index($0, "  " k) == 1 {for (i = 1; i <= NF; ++i) if ($(i + 1) == "s") {print $i; exit}}' "$2"; }
ROWS=()
run() { # case label options...
  local c=$1 label=$2; shift 2
  local f=$WORK/$c-$label.fsd
  local t0 t1 rc
  say "## $c, $label: $P ... $*"
  t0=$(date +%s.%N)
  FIRSTSHOT_PROFILE=1 timeout "${RUN_LIMIT:-300}" "$P" "$@" -o "$f" -q >"$WORK/out" 2>"$WORK/err"; rc=$?
  t1=$(date +%s.%N)
  cat "$WORK/out" "$WORK/err" | tee -a "$LOG"
  local wall; wall=$(echo "$t1 - $t0" | bc -l)
  if [ $rc -ne 0 ]; then
    say "FAILED (exit $rc)"; ROWS+=("| $c | $label | failed (exit $rc) | | | | | | | |"); rm -f "$f"; return
  fi
  local line pre patches nnz renderer
  line=$(grep "light samples" "$WORK/out" | tail -1)
  pre=$(echo "$line" | sed -E 's/.* non-zero factors, ([0-9.]+) s,.*/\1/')
  patches=$(echo "$line" | sed -E 's/.*, ([0-9]+) patches,.*/\1/')
  nnz=$(echo "$line" | sed -E 's/.*, ([0-9]+) non-zero factors,.*/\1/')
  renderer=$(echo "$line" | sed -E 's/.*\[(.*); R = .*/\1/')
  local setup render readback cov covx pts sum
  setup=$(num "renderer setup" "$WORK/err"); render=$(num "render (draw" "$WORK/err"); readback=$(num readback "$WORK/err")
  cov=$(num "coverage (patch" "$WORK/err"); covx=$(num "coverage of exposed" "$WORK/err"); pts=$(num "point tests" "$WORK/err")
  sum=$(num sum "$WORK/err")
  ROWS+=("$(printf '| %s | %s | %.2f | %s | %s | %.3f | %.3f | %s | %s | %s / %s |' "$c" "$label" "$wall" "$pre" "${setup:-?}" \
    "$(echo "${render:-0} + ${readback:-0}" | bc -l)" "$(echo "${cov:-0} + ${covx:-0} + ${pts:-0}" | bc -l)" "${sum:-?}" \
    "$renderer" "$patches" "$nnz")")
}

AGREE=()
for entry in "${ALL[@]}"; do
  IFS='|' read -r c scene opts cpu <<<"$entry"
  [[ " $CASES " == *" $c "* ]] || continue
  [ -f "$scene" ] || { say "## $c: no scene $scene, skipped"; continue; }
  for label in $cpu; do
    # shellcheck disable=SC2086
    case $label in
      osmesa) run "$c" osmesa "$scene" --backend gl --gl osmesa $opts;;
      embree) run "$c" embree "$scene" --backend embree $opts;;
    esac
  done
  # shellcheck disable=SC2086
  run "$c" egl "$scene" --backend gl --gl egl $REDUCE $opts
  ref=${cpu%% *}
  if [ -f "$WORK/$c-$ref.fsd" ] && [ -f "$WORK/$c-egl.fsd" ]; then
    verdict=$("$CMP" "$WORK/$c-$ref.fsd" "$WORK/$c-egl.fsd" 2>&1)
  else
    verdict="not compared (a run failed)"
  fi
  say "tables, egl against $ref: $verdict"
  AGREE+=("| $c | egl against $ref: $verdict |")
  rm -f "$WORK/$c"-*.fsd
done

{
  echo
  echo "## Summary ($(nproc) cores; wall = the whole process; preprocess = the summary line's seconds; the rest are thread-seconds of FIRSTSHOT_PROFILE)"
  echo
  echo "| case | GL | wall s | preprocess s | renderer setup | render + readback | coverage + point tests | profile sum | renderer | patches / factors |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  printf '%s\n' "${ROWS[@]}"
  echo
  echo "| case | tables (firstshot-fsd-compare CPU-run egl) |"
  echo "|---|---|"
  printf '%s\n' "${AGREE[@]}"
} | tee "$WORK/summary.md" | tee -a "$LOG"
if [ -n "${OUT:-}" ]; then
  mkdir -p "$OUT" && cp "$WORK/summary.md" "$WORK/log.txt" "$OUT/"
fi
grep -q "| DIFFER\|not compared\|failed" "$WORK/summary.md" && exit 1
exit 0
