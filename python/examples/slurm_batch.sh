#!/bin/bash
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Checks a directory of frames as a Slurm array job: each array task checks
# every N-th frame (python -m selfcol.batch --no-dask --shard I/N) into its own
# JSON Lines part; a dependent job merges the parts into one file and a
# summary. Submit from a login node with the package installed
# (pip install /path/to/selfcol) in the environment the nodes see:
#
#   FRAMES=/shots/sh010/cache OUT=/scratch/sh010 sbatch --array=0-31 slurm_batch.sh
#
# (or sbatch with -p/--time/--mem as your farm requires). Each task uses one
# CPU; raise --threads and --cpus-per-task together for very large frames.
#SBATCH --job-name=selfcol-check
#SBATCH --cpus-per-task=1
#SBATCH --output=selfcol-%A_%a.log
set -euo pipefail
: "${FRAMES:?set FRAMES to a directory or glob of .obj/.ply frames}"
: "${OUT:?set OUT to an output directory}"
PYTHON=${PYTHON:-python3}
mkdir -p "$OUT"
task=${SLURM_ARRAY_TASK_ID:-0}
count=${SLURM_ARRAY_TASK_COUNT:-1}
status=0
"$PYTHON" -m selfcol.batch "$FRAMES" --no-dask --shard "$task/$count" \
  --threads "${SLURM_CPUS_PER_TASK:-1}" --out "$OUT/part-$task.jsonl" || status=$?
# 0: clean, 1: some frame intersects (a result, not a failure), 2: an error
[ "$status" -le 1 ] || exit "$status"
# The first task submits the merge, to run once every task has finished.
if [ "$task" = "${SLURM_ARRAY_TASK_MIN:-0}" ] && [ -n "${SLURM_ARRAY_JOB_ID:-}" ]; then
  sbatch --dependency="afterany:${SLURM_ARRAY_JOB_ID}" --job-name=selfcol-merge \
    --output="$OUT/merge.log" --wrap \
    "$PYTHON -m selfcol.batch --merge '$OUT/part-*.jsonl' --out '$OUT/frames.jsonl' --summary '$OUT/summary.json'; [ \$? -le 1 ]"
fi
