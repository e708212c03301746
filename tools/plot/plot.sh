#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: sh tools/plot/plot.sh [--subset default|full] [--results DIR] [--docs DIR]
# Draws the benchmark charts (PNG) into docs/ and rewrites the generated
# tables of docs/benchmarks.md from tools/bench/results/SUBSET.csv (`make plot`);
# the coherent-query chart from sequence.csv (sequence-SUBSET.csv but for default).
#
# matplotlib comes from Debian (python3-matplotlib), which installs it for
# /usr/bin/python3. On machines where `python3` is another build (pyenv,
# conda) that one usually lacks it, so try /usr/bin/python3 first, then
# python3, and install the Debian package (tools/deps.sh) only when neither
# imports matplotlib.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)

find_python() {
  for py in /usr/bin/python3 python3; do
    if command -v "$py" >/dev/null 2>&1 && "$py" -c 'import matplotlib' >/dev/null 2>&1; then
      echo "$py"
      return 0
    fi
  done
  return 1
}

if ! py=$(find_python); then
  echo "plot: no Python with matplotlib; installing Debian's python3-matplotlib" >&2
  sh "$root/tools/deps.sh" python3-matplotlib
  if ! py=$(find_python); then
    echo "plot: matplotlib still not importable by /usr/bin/python3 or python3" >&2
    exit 1
  fi
fi
echo "plot: using $py ($("$py" -c 'import matplotlib; print("matplotlib", matplotlib.__version__)'))"
exec "$py" "$root/tools/plot/plot.py" --root "$root" "$@"
