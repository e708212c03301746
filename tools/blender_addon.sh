#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: sh tools/blender_addon.sh [BUILD] [--test] [--screenshot]
# `make blender-addon` (and, with --test, `make blender-test`, which CI runs).
# Builds the Blender add-on's zip, the one file an artist installs
# (Preferences > Add-ons > Install...): adapters/blender/selfcol_blender/
# with the selfcol module unpacked from the wheel (tools/wheel.sh: libccd
# inside, no compiler needed) into its _vendor/, and cffi's backend when
# PyPI has it (official Blender builds' Python lacks cffi; Debian's has it).
# Result: BUILD/blender/selfcol_blender-VERSION.zip, for Blender's Python
# (3.11 for Blender 3.4 to 4.x; the wheel is built for the python3 here).
# --test: installs Debian's blender when missing (tools/deps.sh) and runs
# adapters/blender/tests/test_addon.py in it, headless: the add-on installed
# from the zip and enabled, its marks checked against selfcol-cli's.
# --screenshot: renders the add-on page's picture (Cycles, CPU) to
# BUILD/blender/blender-addon.png (committed as docs/images/blender-addon.png).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
build=build
test=0
shot=0
for a in "$@"; do
  case "$a" in
    --test) test=1 ;;
    --screenshot) shot=1 ;;
    *) build=$a ;;
  esac
done
case "$build" in /*) ;; *) build="$root/$build" ;; esac

# The wheel, rebuilt when a source is newer.
wheel=$(ls "$build"/wheel/dist/selfcol-*.whl 2>/dev/null | head -n 1 || true)
if [ -z "$wheel" ] || [ -n "$(find python lib include tools/meshio pyproject.toml -newer "$wheel" -type f | head -n 1)" ]; then
  sh tools/wheel.sh "$build"
  wheel=$(ls "$build"/wheel/dist/selfcol-*.whl 2>/dev/null | head -n 1 || true)
fi
if [ -z "$wheel" ]; then
  echo "blender-addon: no wheel (PyPI not reachable for tools/wheel.sh): skipped"
  exit 0
fi
py="$build/wheel-venv/bin/python"
version=$(sed -n 's/^#define SELFCOL_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9]*\)/\2/p' \
  include/selfcol/version.h | paste -sd. -)
out="$build/blender"
rm -rf "$out/selfcol_blender"
mkdir -p "$out"
cp -R adapters/blender/selfcol_blender "$out/selfcol_blender"
rm -rf "$out/selfcol_blender/__pycache__"
mkdir -p "$out/selfcol_blender/_vendor"
"$py" -m zipfile -e "$wheel" "$out/selfcol_blender/_vendor"
rm -rf "$out/selfcol_blender/_vendor"/selfcol-*.dist-info
# cffi's compiled backend (the only part the selfcol extension imports).
tag=$("$py" -c 'import sys; print("%d%d" % sys.version_info[:2])')
if "$py" -m pip download -q --disable-pip-version-check --only-binary :all: --no-deps \
    --python-version "$tag" --platform manylinux2014_x86_64 -d "$out/cffi" cffi >/dev/null 2>&1; then
  cffi=$(ls "$out"/cffi/cffi-*.whl | head -n 1)
  "$py" - "$cffi" "$out/selfcol_blender/_vendor" <<'PY'
import sys, zipfile
with zipfile.ZipFile(sys.argv[1]) as z:
    for name in z.namelist():
        if name.startswith("_cffi_backend") or name.startswith("cffi.libs/"):
            z.extract(name, sys.argv[2])
PY
  chmod +x "$out"/selfcol_blender/_vendor/_cffi_backend*.so
else
  echo "blender-addon: cffi's wheel not downloadable: the add-on relies on Blender's Python having cffi"
fi
zip="$out/selfcol_blender-$version.zip"
rm -f "$zip"
(cd "$out" && "$py" -m zipfile -c "$zip" selfcol_blender)
echo "blender-addon: $zip ($(du -k "$zip" | cut -f1) kB)"

[ "$test" -eq 1 ] || [ "$shot" -eq 1 ] || exit 0
if ! command -v blender >/dev/null 2>&1; then
  sh tools/deps.sh blender || { echo "blender-test: blender not installable: skipped"; exit 0; }
fi
# The add-on carries a module built for the wheel's Python: Blender's must be
# the same version (Debian's blender uses Debian's python3).
blender_py=$(blender -b --factory-startup --python-expr \
  'import sys; print("BLENDER_PY %d%d" % sys.version_info[:2])' 2>/dev/null |
  sed -n 's/^BLENDER_PY //p')
if [ "$blender_py" != "$tag" ]; then
  echo "blender-test: Blender's Python is ${blender_py:-unknown}, the wheel's $tag: skipped"
  exit 0
fi
cli="$build/tools/cli/selfcol-cli"
[ -x "$cli" ] || { echo "blender-test: $cli missing (make build first)"; exit 1; }
rm -rf "$out/test"
mkdir -p "$out/test"
# A user's add-on folder of its own, so that the run leaves the real one alone.
if [ "$test" -eq 1 ]; then
  BLENDER_USER_SCRIPTS="$out/test/scripts" blender -b --factory-startup --python-exit-code 1 \
    --python adapters/blender/tests/test_addon.py -- "$zip" "$cli" "$out/test"
fi

if [ "$shot" -eq 1 ]; then
  BLENDER_USER_SCRIPTS="$out/test/scripts" blender -b --factory-startup --python-exit-code 1 \
    --python adapters/blender/tests/screenshot.py -- "$zip" "$out/blender-addon.png"
fi
