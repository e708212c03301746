#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: abi_check.sh LIBRARY
# Compares LIBRARY with the newest ABI baseline in tests/abi/ (abidiff, from
# abigail-tools). abidiff's exit status is a bit mask: 4 = ABI change,
# 8 = incompatible change. An incompatible change fails unless the major
# version differs from the baseline's; a compatible change only needs a
# changelog line, so it is reported, not failed.
set -eu
lib=$1
baseline=$(ls tests/abi/libselfcol-*.abi | sort -V | tail -n 1)
status=0
abidiff --suppressions tests/abi/selfcol.suppr --headers-dir2 include/selfcol "$baseline" "$lib" || status=$?
base_major=$(basename "$baseline" .abi | sed 's/libselfcol-\([0-9]*\)\..*/\1/')
major=$(sed -n 's/^#define SELFCOL_VERSION_MAJOR \([0-9]*\)/\1/p' include/selfcol/version.h)
if [ $((status & 8)) -ne 0 ] && [ "$major" = "$base_major" ]; then
  echo "abi-check: incompatible ABI change against $baseline without a major version bump"
  exit 1
fi
if [ $((status & 3)) -ne 0 ]; then
  echo "abi-check: abidiff failed to run (status $status)"
  exit 1
fi
[ $((status & 4)) -ne 0 ] && echo "abi-check: compatible ABI change against $baseline (needs a changelog line)"
echo "abi-check: OK against $baseline"
