#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, -DFIRSTSHOT_FUZZ=ON, ASan+UBSan) in build/fuzz and runs each for a
# bounded time on a scratch copy of its seed corpus (tests/fuzz/corpus/<target>/ is never grown).
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]     (default 120 s; targets: all)
# Fails (exit 1) if any target finds a crash, a sanitizer report, an uncaught exception, a hang or a
# huge allocation; the input is kept as build/fuzz/fuzz-runs/<target>/crash-* (or timeout-*, oom-*).
# docs/robustness.md, "Fuzzing".
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-120}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene_json scene_xml mesh_import fsd cache_file ies)
build=${FUZZ_BUILD:-$root/build/fuzz}

# The largest input each target tries (bytes): the seeds fit.
declare -A max_len=([scene_json]=32768 [scene_xml]=32768 [mesh_import]=16384 [fsd]=24576 [cache_file]=4096 [ies]=8192)
# assimp 5.2 leaks parts of a half-read scene on some malformed files (not firstshot's memory); checking
# for leaks after every such input would also make fuzz_mesh_import 3-4 times slower.
declare -A asan_options=([mesh_import]=detect_leaks=0)

CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DFIRSTSHOT_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only" >/dev/null
cmake --build "$build" -j "${JOBS:-$(nproc)}" --target $(printf 'fuzz_%s ' "${targets[@]}")

export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# The targets write each input to a scratch file: in memory if possible (several times faster).
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
# One target: prints its summary and leaves its exit code in $work/rc.
run_target() {
  local t=$1 work=$build/fuzz-runs/$1 rc=0 execs
  local dict=()  # the target's dictionary of format words, if any (tests/fuzz/<target>.dict)
  [ -f "$root/tests/fuzz/$t.dict" ] && dict=(-dict="$root/tests/fuzz/$t.dict")
  ASAN_OPTIONS=${ASAN_OPTIONS:-${asan_options[$t]:-detect_leaks=1}} "$build/tests/fuzz/fuzz_$t" "$work/corpus" \
    -max_total_time="$seconds" -max_len="${max_len[$t]}" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -artifact_prefix="$work/" -print_final_stats=1 "${dict[@]}" >"$work/log.txt" 2>&1 || rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/log.txt")
  echo "fuzz: fuzz_$t: ${execs:-?} runs, corpus $(ls "$work/corpus" | wc -l) inputs, exit $rc"
  if [ "$rc" -ne 0 ]; then
    grep -aE "^(==[0-9]+==ERROR|SUMMARY|.*runtime error)" "$work/log.txt" | head -5 || true
    ls "$work"/crash-* "$work"/timeout-* "$work"/oom-* "$work"/leak-* 2>/dev/null || true
  fi
  echo "$rc" > "$work/rc"
}

# The targets run JOBS at a time (each is one process on one core, for SECONDS of it).
jobs_max=${JOBS:-$(nproc)}
for t in "${targets[@]}"; do
  [ -n "${max_len[$t]:-}" ] || { echo "fuzz: unknown target $t" >&2; exit 2; }
  work=$build/fuzz-runs/$t
  rm -rf "$work" && mkdir -p "$work/corpus"
  cp "$root/tests/fuzz/corpus/$t/"* "$work/corpus/"
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do wait -n || true; done
  echo "fuzz: fuzz_$t for $seconds s (log: $work/log.txt)"
  run_target "$t" &
done
wait
failed=()
for t in "${targets[@]}"; do
  [ "$(cat "$build/fuzz-runs/$t/rc" 2>/dev/null || echo 1)" = 0 ] || failed+=("$t")
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: FOUND problems in: ${failed[*]} (inputs and logs under $build/fuzz-runs/)" >&2
  exit 1
fi
echo "fuzz: no findings"
