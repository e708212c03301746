#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: check_exports.sh LIBRARY INCLUDE_DIR MAP [API_MACRO [PREFIX]]
# Checks that the dynamic symbols defined by LIBRARY are exactly the functions
# declared API_MACRO in the public headers (INCLUDE_DIR/*.h), and exactly those
# listed in MAP, all named PREFIX*. Defaults: SELFCOL_API and selfcol_ (the
# core, libselfcol); libselfcol_bullet passes SELFCOL_BULLET_API and
# selfcol_bullet_. Version nodes (SELFCOL_*) are not symbols of the API.
set -eu
lib=$1; incdir=$2; map=$3; api=${4:-SELFCOL_API}; prefix=${5:-selfcol_}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
nm -D --defined-only "$lib" | awk '{print $3}' | sed 's/@.*//' | grep -v '^$' | grep -v '^SELFCOL_' | sort -u > "$tmp/exported"
cat "$incdir"/*.h | tr '\n' ' ' | grep -o "$api[^(;]*(" | sed 's/($//' | awk '{print $NF}' | tr -d '*' | grep "^$prefix" | sort -u > "$tmp/declared"
sed -n "s/^[[:space:]]*\($prefix[a-z0-9_]*\);.*/\1/p" "$map" | sort -u > "$tmp/mapped"
status=0
if ! diff -u "$tmp/declared" "$tmp/exported"; then echo "exports differ from $api declarations"; status=1; fi
if ! diff -u "$tmp/declared" "$tmp/mapped"; then echo "version script differs from $api declarations"; status=1; fi
if grep -v "^$prefix" "$tmp/exported"; then echo "non-$prefix symbols exported"; status=1; fi
[ $status -eq 0 ] && echo "exports OK: $(wc -l < "$tmp/exported") symbols, all $prefix"
exit $status
