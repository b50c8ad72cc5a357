#!/usr/bin/env bash
# Usage: signal_when_ready.sh SIG SECONDS [--wait-file F] COMMAND...
# Runs COMMAND, waits until it has installed its own SIGINT and SIGTERM handlers (the SigCgt mask in
# /proc/PID/status) and, with --wait-file, until F exists; then SECONDS more; then sends SIG (INT,
# TERM) and exits with COMMAND's status. A fixed delay instead would race with a slow start on a
# loaded machine (the default action would kill the tool before its handler exists). COMMAND gets
# 120 s to become ready and 60 s to stop after the signal, then SIGKILL (no background watchdog:
# it would hold the caller's pipe open).
set -u
sig=$1 seconds=$2
shift 2
file=""
if [ "$1" = "--wait-file" ]; then file=$2; shift 2; fi
"$@" &
pid=$!
ready() {
  local mask
  mask=$(awk '/^SigCgt:/ {print $2}' "/proc/$pid/status" 2>/dev/null) || return 1
  [ -n "$mask" ] && (( (0x$mask & 0x4002) == 0x4002 )) && { [ -z "$file" ] || [ -e "$file" ]; }
}
for ((i = 0; i < 6000; ++i)); do
  kill -0 "$pid" 2>/dev/null && ! ready || break
  sleep 0.02
done
sleep "$seconds"
kill -"$sig" "$pid" 2>/dev/null
for ((i = 0; i < 600; ++i)); do
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.1
done
kill -KILL "$pid" 2>/dev/null
wait "$pid"
