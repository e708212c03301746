#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: check_exports.sh LIBRARY INCLUDE_DIR MAP
# Checks that the dynamic symbols defined by LIBRARY are exactly the functions
# declared SELFCOL_API in the public headers, and exactly those listed in MAP.
set -eu
lib=$1; incdir=$2; map=$3
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
nm -D --defined-only "$lib" | awk '{print $3}' | sed 's/@.*//' | grep -v '^$' | grep -v '^SELFCOL_' | sort -u > "$tmp/exported"
cat "$incdir"/*.h | tr '\n' ' ' | grep -o 'SELFCOL_API[^(;]*(' | sed 's/($//' | awk '{print $NF}' | tr -d '*' | grep '^selfcol_' | sort -u > "$tmp/declared"
sed -n 's/^[[:space:]]*\(selfcol_[a-z0-9_]*\);.*/\1/p' "$map" | sort -u > "$tmp/mapped"
status=0
if ! diff -u "$tmp/declared" "$tmp/exported"; then echo "exports differ from SELFCOL_API declarations"; status=1; fi
if ! diff -u "$tmp/declared" "$tmp/mapped"; then echo "version script differs from SELFCOL_API declarations"; status=1; fi
if grep -v '^selfcol_' "$tmp/exported"; then echo "non-selfcol_ symbols exported"; status=1; fi
[ $status -eq 0 ] && echo "exports OK: $(wc -l < "$tmp/exported") symbols, all selfcol_"
exit $status
