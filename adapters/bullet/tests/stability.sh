#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: stability.sh CLI DEMO OUTDIR FROM EXPECT [DEMO ARGS...]
# Runs DEMO with --check (no NaN or inf, bounded kinetic energy, every node in
# the scene box) writing frames to OUTDIR, then checks the frames from step
# FROM on with the core's exact query (selfcol-cli check --frames, d = 0.1 x
# mean edge), independently of the adapter's own counters.
# EXPECT: "clean" -- no frame from FROM on may hold an EF interference;
#         "clean-contacts" -- "clean", and some step held self-contacts
#         (the demo's "peak self-contacts" is above 0: collisions were
#         found, not avoided);
#         "record" -- print the interference counts, assert nothing about them
#         (Bullet's own self-collision, for comparison).
set -eu
cli=$1; demo=$2; out=$3; from=$4; expect=$5; shift 5
rm -rf "$out"; mkdir -p "$out"
demo_status=0
"$demo" --check --quiet --out "$out" "$@" > "$out/demo.txt" || demo_status=$?
cat "$out/demo.txt"
[ $demo_status -eq 0 ] || { echo "FAIL: the demo's run failed (status $demo_status)"; exit 1; }
frames=""
for f in "$out"/frame_*.ply; do
  step=$(basename "$f" .ply | sed 's/^frame_0*//'); step=${step:-0}
  [ "$step" -ge "$from" ] && frames="$frames $f"
done
[ -n "$frames" ] || { echo "no frame from step $from on"; exit 1; }
status=0
# shellcheck disable=SC2086
"$cli" check --frames $frames > "$out/check.txt" || status=$?
grep -E "frame [0-9]+ |frame\(s\)" "$out/check.txt"
case "$expect" in
  clean) [ $status -eq 0 ] || { echo "FAIL: interferences from step $from on (status $status)"; exit 1; } ;;
  clean-contacts)
    [ $status -eq 0 ] || { echo "FAIL: interferences from step $from on (status $status)"; exit 1; }
    peak=$(sed -n 's/.*peak self-contacts \([0-9]*\).*/\1/p' "$out/demo.txt")
    [ -n "$peak" ] && [ "$peak" -gt 0 ] || { echo "FAIL: no self-contact found (peak '$peak')"; exit 1; } ;;
  record) [ $status -le 1 ] || { echo "FAIL: the checker could not read the frames"; exit 1; }
          echo "recorded (not asserted)" ;;
  *) echo "bad EXPECT $expect"; exit 2 ;;
esac
