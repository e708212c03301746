#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: sh python/tests/run_ctest.sh --python PY --build DIR --source DIR
#                                     [--shared DIR] [--cli BINARY]
# The ctest entry python_package (tests/python/CMakeLists.txt): a venv under
# the build directory (kept between runs), the package installed from
# python/ with an incremental build directory, then pytest. Exit 77 when the
# venv or PyPI is not available (skipped, not failed).
set -eu
py=python3
build=build
source=.
shared=""
cli=""
while [ $# -gt 0 ]; do
  case "$1" in
    --python) py=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --source) source=$2; shift 2 ;;
    --shared) shared=$2; shift 2 ;;
    --cli) cli=$2; shift 2 ;;
    *) echo "run_ctest.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
venv="$build/python-venv"
if [ ! -x "$venv/bin/python" ]; then
  if ! "$py" -m venv "$venv" >/dev/null 2>&1; then
    rm -rf "$venv"
    if sh "$source/tools/deps.sh" python3-venv >/dev/null 2>&1 && "$py" -m venv "$venv"; then :; else
      rm -rf "$venv"
      echo "run_ctest.sh: cannot create a venv (python3-venv missing): skipped"
      exit 77
    fi
  fi
fi
vpy="$venv/bin/python"
if ! "$vpy" -c "import numpy, cffi, pytest, scikit_build_core, distributed, mypy" 2>/dev/null; then
  echo "== pip install numpy cffi pytest scikit-build-core dask[distributed] mypy (once)"
  if ! "$vpy" -m pip install -q --disable-pip-version-check numpy cffi pytest \
      scikit-build-core 'dask[distributed]' mypy; then
    echo "run_ctest.sh: PyPI not reachable: skipped"
    exit 77
  fi
fi
echo "== pip install $source (pyproject.toml: the package in python/)"
"$vpy" -m pip install -q --disable-pip-version-check --no-build-isolation --no-deps \
  --force-reinstall -C "build-dir=$build/python-build" "$source"
echo "== pytest"
work="$build/python-tests"
mkdir -p "$work"
cd "$work"
SELFCOL_CLI="$cli" SELFCOL_SHARED_DATA="$shared" PYTHONDONTWRITEBYTECODE=1 \
  exec "$vpy" -m pytest -q -p no:cacheprovider --rootdir "$source/python/tests" \
  "$source/python/tests"
