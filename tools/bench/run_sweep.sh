#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: sh tools/bench/run_sweep.sh [--build DIR] [--out FILE] [--data DIR]
#                                    [--reps N] [--rounds N] [--no-ipctk] [--smoke]
#                                    [--earliest]
# Continuous queries over one step (selfcol-bench-sweep) beside ipc-toolkit's
# continuous checks (bench_ipctk_sweep.py, in the venv under the build
# directory that run.sh --ipctk also uses) on the same positions, one
# thread each. The two alternate ROUNDS times (default 2), each run taking the
# median of REPS queries (default 3), so that a load change on the machine
# shows as a difference between rounds rather than as a bias of one tool.
# Writes FILE (default BUILD/bench-results/sweep.md): a table per round and
# tool. Called by `make bench-sweep`; `--smoke` (what CI runs) times a tiny
# crumple step only, without ipc-toolkit. `--earliest` runs selfcol's
# EARLIEST rows only (the collision-free fraction, what ipc-toolkit's
# stepsize computes; the ALL rows take seconds each).
set -eu

build=build
out=""
data=""
reps=3
rounds=2
ipctk=1
smoke=""
earliest=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --data) data=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --no-ipctk) ipctk=0; shift ;;
    --smoke) smoke=--smoke; ipctk=0; rounds=1; shift ;;
    --earliest) earliest=--earliest; shift ;;
    *) echo "run_sweep.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
case "$build" in /*) ;; *) build="$root/$build" ;; esac
runner="$build/tools/bench/selfcol-bench-sweep"
if [ ! -x "$runner" ]; then
  echo "run_sweep.sh: $runner not found; build first (make build)" >&2
  exit 1
fi
[ -n "$data" ] || data=${SELFCOL_SHARED_DATA:-"$root/../shared/data"}
[ -n "$out" ] || out="$build/bench-results/sweep.md"
mkdir -p "$(dirname "$out")"
dump="$build/bench-dump"
mkdir -p "$dump"
# The log stays in the build directory's results, wherever --out writes.
mkdir -p "$build/bench-results"
log="$build/bench-results/sweep.log"
: > "$log"

. tools/bench/ipctk_venv.sh
ipctk_python=""
if [ "$ipctk" = 1 ]; then ipctk_python=$(ipctk_venv "$build" "$log"); fi
if [ "$ipctk" = 1 ] && [ -z "$ipctk_python" ]; then
  echo "bench-sweep: ipctk skipped (no venv with the ipctk package; see $log)"
  ipctk=0
fi

{
  echo "# Continuous queries over one step, one thread"
  echo
  echo "$(date -u +%Y-%m-%d), $(uname -m), $(nproc) cores, commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown);"
  echo "command: sh tools/bench/run_sweep.sh --reps $reps --rounds $rounds${smoke:+ $smoke}${earliest:+ $earliest}"
} > "$out"
round=1
while [ "$round" -le "$rounds" ]; do
  echo "bench-sweep: round $round: selfcol"
  { echo; echo "## Round $round: selfcol (separation 0; methods BVH and EXACT)"; echo; } >> "$out"
  "$runner" --data "$data" --reps "$reps" --dump "$dump" $smoke $earliest >> "$out" 2>> "$log"
  if [ "$ipctk" = 1 ]; then
    echo "bench-sweep: round $round: ipc-toolkit"
    {
      echo
      echo "## Round $round: ipc-toolkit $("$ipctk_python" -c 'import importlib.metadata as m; print(m.version("ipctk"))') (one thread, minimum distance 0, default broad phase, Tight-Inclusion)"
      echo
      echo "| case | triangles | collision-free stepsize ms (min-max) | stepsize | is_step_collision_free ms | collision free | build ms |"
      echo "|---|---|---|---|---|---|---|"
    } >> "$out"
    "$ipctk_python" tools/bench/bench_ipctk_sweep.py --dump "$dump" --reps "$reps" \
      --case cloth-funnel-227 --case rod-twist-3036 --case cloth-ball-92 \
      --case crumpled-200k-step >> "$out" 2>> "$log"
  fi
  round=$((round + 1))
done
echo "bench-sweep: wrote $out"
