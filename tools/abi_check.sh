#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: abi_check.sh LIBRARY [NAME HEADERS_DIR]
# Compares LIBRARY with the newest ABI baseline tests/abi/NAME-<version>.abi
# (abidiff, from abigail-tools), NAME's public headers being HEADERS_DIR.
# Defaults: libselfcol and include/selfcol; the Bullet adapter passes
# libselfcol_bullet and adapters/bullet/include/selfcol (Makefile, abi-check).
# Both libraries carry the project's version (include/selfcol/version.h).
# abidiff's exit status is a bit mask: 4 = ABI change,
# 8 = incompatible change. An incompatible change fails unless the release
# series differs from the baseline's (the major version; for 0.x, 0.minor,
# as the SONAME); a compatible change only needs a changelog line, so it is
# reported, not failed.
set -eu
lib=$1
name=${2:-libselfcol}
headers=${3:-include/selfcol}
baseline=$(ls tests/abi/"$name"-[0-9]*.abi 2>/dev/null | sort -V | tail -n 1)
if [ -z "$baseline" ]; then
  echo "abi-check: no baseline tests/abi/$name-<version>.abi (make abi-dump writes one)"
  exit 1
fi
status=0
abidiff --suppressions tests/abi/selfcol.suppr --headers-dir2 "$headers" "$baseline" "$lib" || status=$?
series_of() { # 1.4.2 -> 1, 0.2.3 -> 0.2
  case "$1" in 0.*) echo "$1" | cut -d. -f1,2 ;; *) echo "$1" | cut -d. -f1 ;; esac
}
base_series=$(series_of "$(basename "$baseline" .abi | sed "s/^$name-//")")
version=$(sed -n 's/^#define SELFCOL_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9]*\)/\2/p' include/selfcol/version.h | paste -sd.)
if [ $((status & 8)) -ne 0 ] && [ "$(series_of "$version")" = "$base_series" ]; then
  echo "abi-check: incompatible ABI change against $baseline without a new release series (SONAME)"
  exit 1
fi
if [ $((status & 3)) -ne 0 ]; then
  echo "abi-check: abidiff failed to run (status $status)"
  exit 1
fi
[ $((status & 4)) -ne 0 ] && echo "abi-check: compatible ABI change against $baseline (needs a changelog line)"
echo "abi-check: OK against $baseline"
