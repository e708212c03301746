#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: sh tools/docs.sh [BUILD]   (`make docs`; CI runs it)
# The Python API reference, generated from the docstrings by pdoc into
# BUILD/docs/python/ (open index.html): the package as a user installs it,
# the wheel of tools/wheel.sh in its test venv (built first when missing).
# Fails on a module pdoc cannot import or a page it cannot write.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
build=${1:-build}
case "$build" in /*) ;; *) build="$root/$build" ;; esac
venv="$build/wheel-test-venv"
if ! [ -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import selfcol" 2>/dev/null; then
  sh tools/wheel.sh "$build"
fi
if ! [ -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import selfcol" 2>/dev/null ||
  ! "$venv/bin/python" -m pip install -q --disable-pip-version-check pdoc; then
  echo "docs: no installed wheel or no pdoc (PyPI not reachable): skipped"
  exit 0
fi
out="$build/docs/python"
rm -rf "$out"
"$venv/bin/python" -m pdoc selfcol selfcol.io selfcol.batch -o "$out" --docformat restructuredtext
for page in selfcol.html selfcol/io.html selfcol/batch.html; do
  [ -s "$out/$page" ] || { echo "docs: $out/$page was not written" >&2; exit 1; }
done
grep -q "self_collide" "$out/selfcol.html" || { echo "docs: self_collide is not documented" >&2; exit 1; }
echo "docs: $out/index.html"
