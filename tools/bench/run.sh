#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: sh tools/bench/run.sh [--subset smoke|default|full] [--build DIR]
#                              [--out DIR] [--data DIR] [--only REGEX] [--ipctk]
# Runs every case of a subset with selfcol-bench, one process per case (so
# that peak memory is per case), and writes
#   OUT/SUBSET.csv   one row per case x method x d (the header line first)
#   OUT/SUBSET.meta  machine, date, commit, compiler, Bullet, command, runtime
#   OUT/sequence.csv (default; sequence-SUBSET.csv for the others)
#                    fresh against coherent queries frame after frame
#   OUT/threads.md   (default, with the real frames) cloth-ball 92's query on
#                    1 and 2 threads, interleaved (selfcol-bench-threads)
#   OUT/bullet_step_fast.csv, OUT/bullet_step_fast_trace.csv (default, with
#                    the Bullet adapter) the continuous option on the
#                    fast-compression ribbon and the ordinary 20k ribbon
# OUT defaults to tools/bench/results (with --only, to BUILD/bench-results:
# a partial run never replaces the committed results). --only REGEX keeps the
# cases whose name matches, e.g. --only '^store-' for the contact-store rows
# alone (selfcol_bench.c, "Contact-store rows"). Called by `make bench` (default),
# `make bench-full` (full) and `make bench-smoke` (smoke, what CI runs: tiny
# sizes, no timing assertion: it only fails when the runner fails).
# bench-full (or --ipctk) adds ipc-toolkit rows through its Python package
# (bench_ipctk.py, in a venv under the build directory).
set -eu

subset=default
build=build
out=""
data=""
only=""
ipctk=""
while [ $# -gt 0 ]; do
  case "$1" in
    --ipctk) ipctk=1; shift ;;
    --subset) subset=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --data) data=$2; shift 2 ;;
    --only) only=$2; shift 2 ;;
    *) echo "run.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done

# ipc-toolkit runs in bench-full (or with --ipctk) on these cases.
[ -n "$ipctk" ] || { [ "$subset" = full ] && ipctk=1 || ipctk=0; }
ipctk_cases="crumpled-2k crumpled-20k-s1 crumpled-200k sheet-pair-10k sphere-80k cloth-ball-92 cloth-funnel-227 rod-twist-3036"
if [ "$subset" = full ]; then ipctk_reps=7; else ipctk_reps=5; fi

root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
case "$build" in /*) ;; *) build="$root/$build" ;; esac
if [ -z "$out" ] && [ -n "$only" ]; then
  out="$build/bench-results"
  echo "bench: --only: a partial run, written to $out (not tools/bench/results)"
fi
[ -n "$out" ] || out=tools/bench/results
runner="$build/tools/bench/selfcol-bench"
if [ ! -x "$runner" ]; then
  echo "run.sh: $runner not found; build first (make build, or cmake --build $build)" >&2
  exit 1
fi
[ -n "$data" ] || data=${SELFCOL_SHARED_DATA:-"$root/../shared/data"}

mkdir -p "$out"
csv="$out/$subset.csv"
meta="$out/$subset.meta"
tmp="$csv.tmp"
log="$out/$subset.log"

# A case that hangs (Bullet's face-tree build did, on two-piece meshes) must
# not hang the run: each case gets a generous time limit.
case "$subset" in
  smoke) limit=120 ;;
  default) limit=600 ;;
  *) limit=7200 ;;
esac
timeout_cmd=""
command -v timeout >/dev/null 2>&1 && timeout_cmd="timeout $limit"

# The commit as the run starts (make bench builds right before it); a library
# with uncommitted changes in lib/ or include/ is flagged.
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
dirty=$(git status --porcelain -- lib include 2>/dev/null | head -1)
[ -z "$dirty" ] || commit="$commit (lib/ or include/ modified)"
start=$(date +%s)
"$runner" --header > "$tmp"
: > "$log"
failed=0
for c in $("$runner" --list "$subset"); do
  if [ -n "$only" ] && ! echo "$c" | grep -Eq "$only"; then
    continue
  fi
  t0=$(date +%s)
  if $timeout_cmd "$runner" --case "$c" --subset "$subset" --data "$data" >> "$tmp" 2>> "$log"; then
    echo "bench: $c ($(( $(date +%s) - t0 )) s)"
  else
    echo "bench: $c FAILED (see $log)" >&2
    failed=1
  fi
  # Say why a case or its Bullet rows were left out (absent data, Bullet limits).
  grep -F "selfcol-bench: $c" "$log" | grep -E "skipped|no Bullet rows" | sed 's/^selfcol-bench: /bench:   /' || true
done
# ipc-toolkit rows (bench-full, or --ipctk): its Python package in a venv
# under the build directory, fed with the meshes and EXACT contact sets the
# runner dumps. Skipped with a message when the venv or the package cannot
# be had (no network, no venv module).
if [ "$ipctk" = 1 ]; then
  . tools/bench/ipctk_venv.sh
  ipctk_python=$(ipctk_venv "$build" "$log")
  if [ -n "$ipctk_python" ]; then
    dump="$build/bench-dump"
    mkdir -p "$dump"
    args=""
    for c in $ipctk_cases; do
      if [ -n "$only" ] && ! echo "$c" | grep -Eq "$only"; then continue; fi
      "$runner" --case "$c" --dump "$dump" --data "$data" 2>> "$log" && args="$args --case $c"
    done
    if [ -n "$args" ]; then
      t0=$(date +%s)
      if "$ipctk_python" tools/bench/bench_ipctk.py --dump "$dump" --subset "$subset" \
           --reps "$ipctk_reps" $args >> "$tmp" 2>> "$log"; then
        echo "bench: ipctk ($(( $(date +%s) - t0 )) s)"
      else
        echo "bench: ipctk FAILED (see $log)" >&2
        failed=1
      fi
    fi
  else
    echo "bench: ipctk skipped (no venv with the ipctk package; see $log)"
  fi
fi
mv "$tmp" "$csv"
# Coherent queries (selfcol-bench-sequence, bench_sequence.c): a fresh query
# against selfcol_sequence on the same frames, interleaved, every frame's
# records compared bit for bit; its own CSV, OUT/sequence.csv (the default
# subset's, committed) or OUT/sequence-SUBSET.csv.
seqrunner="$build/tools/bench/selfcol-bench-sequence"
seqcsv="$out/sequence-$subset.csv"
if [ "$subset" = default ]; then seqcsv="$out/sequence.csv"; fi
case "$subset" in
  smoke) seqcases="crumpled-2k-slow"; seqframes=6; seqreps=1 ;;
  default) seqcases="crumpled-20k-slow crumpled-20k-local cloth-ball-92-93"
           seqframes=30; seqreps=3 ;;
  *) seqcases="crumpled-20k-slow crumpled-20k-local crumpled-200k-slow crumpled-200k-local"
     seqcases="$seqcases cloth-ball-92-93"; seqframes=30; seqreps=3 ;;
esac
if [ -x "$seqrunner" ]; then
  "$seqrunner" --header > "$seqcsv.tmp"
  for c in $seqcases; do
    if [ -n "$only" ] && ! echo "$c" | grep -Eq "$only"; then continue; fi
    t0=$(date +%s)
    if $timeout_cmd "$seqrunner" --case "$c" --frames "$seqframes" --reps "$seqreps" \
         --data "$data" >> "$seqcsv.tmp" 2>> "$log"; then
      echo "bench: sequence $c ($(( $(date +%s) - t0 )) s)"
    else
      echo "bench: sequence $c FAILED (see $log)" >&2
      failed=1
    fi
  done
  mv "$seqcsv.tmp" "$seqcsv"
fi
# Thread scaling (selfcol-bench-threads, bench_threads.c): one frame's EXACT
# query and refit on 1 and 2 threads (this machine's cores), interleaved,
# records compared byte for byte; the 16-core rows come from ../shared/device
# (docs/benchmarks.md, "Threads").
thrrunner="$build/tools/bench/selfcol-bench-threads"
if [ "$subset" = default ] && [ -z "$only" ] && [ -x "$thrrunner" ] &&
   [ -f "$data/sample-scalable-ccd-data/cloth-ball/frames/cloth_ball92.ply" ]; then
  t0=$(date +%s)
  if $timeout_cmd "$thrrunner" --data "$data" --threads 1,2 --reps 7 > "$out/threads.md.tmp" 2>> "$log"; then
    mv "$out/threads.md.tmp" "$out/threads.md"
    echo "bench: threads ($(( $(date +%s) - t0 )) s)"
  else
    rm -f "$out/threads.md.tmp"
    echo "bench: threads FAILED (see $log)" >&2
    failed=1
  fi
fi
# The Bullet adapter's continuous option on the fast-compression ribbon (284
# x 35 nodes, 400 steps) beside the ordinary 20k ribbon's discrete step, in
# one run (selfcol-bullet-bench; docs/benchmarks.md, "the continuous option on
# the fast-compression ribbon"): OUT/bullet_step_fast.csv and its per-step
# trace OUT/bullet_step_fast_trace.csv. About 2 minutes (the continuous
# run stops at 20, its row then 'partial').
bulrunner="$build/adapters/bullet/bench/selfcol-bullet-bench"
if [ "$subset" = default ] && [ -z "$only" ] && [ -x "$bulrunner" ]; then
  t0=$(date +%s)
  fast="$out/bullet_step_fast"
  if $timeout_cmd "$bulrunner" --sizes 20k --modes off,selfcol --repeat 1 \
       --csv "$fast.ordinary.tmp" > /dev/null 2>> "$log" &&
     "$bulrunner" --sizes 284 --steps 400 --modes selfcol-continuous --repeat 1 \
       --time-limit 1200 --csv "$fast.continuous.tmp" --trace "$fast.trace.tmp" \
       > /dev/null 2>> "$log"; then
    { cat "$fast.ordinary.tmp"; tail -n +2 "$fast.continuous.tmp"; } > "$fast.csv"
    mv "$fast.trace.tmp" "${fast}_trace.csv"
    echo "bench: bullet fast-compression ribbon ($(( $(date +%s) - t0 )) s)"
  else
    echo "bench: bullet fast-compression ribbon FAILED (see $log)" >&2
    failed=1
  fi
  rm -f "$fast.ordinary.tmp" "$fast.continuous.tmp" "$fast.trace.tmp"
fi
elapsed=$(( $(date +%s) - start ))

cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1)
cores=$(nproc 2>/dev/null || echo "?")
cc=$(sed -n 's/^CMAKE_C_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt" 2>/dev/null | head -1)
ccver=$($cc --version 2>/dev/null | head -1 || true)
btype=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt" 2>/dev/null | head -1)
bullet=$("$runner" --bullet 2>/dev/null || echo absent)
if [ -d "$data/sample-scalable-ccd-data" ]; then frames="present ($data/sample-scalable-ccd-data)"
else frames="absent ($data/sample-scalable-ccd-data): real-frame cases skipped"; fi
{
  echo "subset=$subset"
  echo "date=$(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "commit=$commit"
  echo "cpu=$cpu"
  echo "cores=$cores"
  echo "memory_kb=$(sed -n 's/^MemTotal:[[:space:]]*\([0-9]*\).*/\1/p' /proc/meminfo 2>/dev/null)"
  echo "kernel=$(uname -sr)"
  echo "compiler=$ccver"
  echo "build_type=$btype"
  echo "bullet=$bullet"
  echo "frames=$frames"
  echo "threads=1 (selfcol and Bullet run single-threaded)"
  if [ -n "$only" ]; then
    echo "command=sh tools/bench/run.sh --subset $subset --only '$only' (partial run)"
  else
    echo "command=make bench$( [ "$subset" = default ] || echo "-$subset")  (sh tools/bench/run.sh --subset $subset)"
  fi
  echo "runtime_s=$elapsed"
} > "$meta"
echo "bench: $(( $(wc -l < "$csv") - 1 )) rows in $csv, $elapsed s ($meta)"
exit $failed
