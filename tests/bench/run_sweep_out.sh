#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: sh tests/bench/run_sweep_out.sh SOURCE_DIR RUNNER
# tools/bench/run_sweep.sh --out FILE --build DIR on a build directory that
# has no bench-results yet (the hardening issue: the script wrote its log
# there without making it and failed): the smoke run must write FILE and
# its log. RUNNER is the built selfcol-bench-sweep, linked into a fresh
# build directory.
set -eu
source=$1
runner=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/build/tools/bench"
ln -s "$runner" "$tmp/build/tools/bench/selfcol-bench-sweep"
sh "$source/tools/bench/run_sweep.sh" --smoke --build "$tmp/build" --out "$tmp/elsewhere/sweep.md"
grep -q '^| crumpled-1k-step |' "$tmp/elsewhere/sweep.md" || {
  echo "run_sweep_out: no crumpled-1k-step row in the output"; cat "$tmp/elsewhere/sweep.md"; exit 1; }
[ -f "$tmp/build/bench-results/sweep.log" ] || { echo "run_sweep_out: no log"; exit 1; }
echo "run_sweep_out: OK"
