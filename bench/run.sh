#!/usr/bin/env bash
# Runs every Google Benchmark program of a build (make bench). The speed-against-error report is
# `make bench-report` (bench/firstshot_bench.py).
set -euo pipefail
build=${1:-build/release}
for b in "$build"/bench/bench_*; do
  [ -x "$b" ] || continue
  echo "== $b"
  "$b"
done
