#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: abi_dump.sh LIBRARY HEADERS_DIR OUT
# Writes LIBRARY's ABI baseline (abidw) with the types of the public headers
# in HEADERS_DIR only, and no path of the build or the source tree: no
# source locations, no compilation directory, and each translation unit
# named by its file name alone. Moving or renaming an internal file or
# struct then leaves the baseline and the check (tools/abi_check.sh) as
# they were; a file name must stay unique in the library (abidiff refuses
# two units of one name).
set -eu
lib=$1
headers=$2
out=$3
abidw --headers-dir "$headers" --drop-private-types --no-show-locs --no-corpus-path \
  --no-comp-dir-path --out-file "$out.tmp" "$lib"
sed -E "s|(<abi-instr [^>]*path=')[^']*/([^'/]*')|\\1\\2|" "$out.tmp" > "$out"
rm -f "$out.tmp"
if grep -q "$(pwd)" "$out"; then
  echo "abi-dump: $out still names $(pwd)" >&2
  exit 1
fi
