#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Builds the fuzz targets with clang (libFuzzer + ASan + UBSan) and runs each
# from its committed seed corpus for a bounded time.
# usage: tests/fuzz/run.sh [SECONDS_PER_TARGET] [OUTDIR]   (defaults: 60, build-fuzz)
#   fuzz_differential  random small meshes (degenerate, non-manifold,
#                      near-coincident), d, refits and two-mesh queries:
#                      BVH and EXACT (1 and 3 threads) == EXHAUSTIVE
#   fuzz_mesh          selfcol_mesh_create(_float) on arbitrary counts,
#                      indices and raw positions
#   fuzz_readers       the OBJ, PLY, OFF and STL readers (tools/meshio): a parse
#                      that succeeds gives indices in range and finite
#                      coordinates (first byte: the format hint)
# New inputs found go to OUTDIR/corpus-*, crashes to OUTDIR/crash-*; the
# script fails when a target fails. CI runs it (make fuzz, short).
set -eu
seconds=${1:-60}
out=${2:-build-fuzz}
root=$(cd "$(dirname "$0")/../.." && pwd)
sh "$root/tools/deps.sh" clang libclang-rt-14-dev pkg-config libccd-dev
cc=clang
command -v "$cc" >/dev/null || cc=clang-14
mkdir -p "$out"
out=$(cd "$out" && pwd)
flags="-g -O1 -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
# The library's sources, instrumented for coverage (fuzzer-no-link).
objs=""
for src in "$root"/lib/*/*.c; do
  obj="$out/$(basename "$src" .c).o"
  $cc $flags -fsanitize=fuzzer-no-link -std=c99 -DSELFCOL_STATIC -I "$root/include" -I "$root/lib" \
    $(pkg-config --cflags ccd) -c "$src" -o "$obj"
  objs="$objs $obj"
done
status=0
for target in differential mesh readers; do
  max_len=""
  if [ "$target" = readers ]; then
    max_len=-max_len=65536 # room for a whole small mesh file
    # The readers of selfcol_meshio alone (they do not use the library).
    $cc $flags -fsanitize=fuzzer -I "$root/tools/meshio" \
      "$root/tests/fuzz/fuzz_readers.c" "$root/tools/meshio/read.c" \
      "$root/tools/meshio/read_text.c" "$root/tools/meshio/read_ply.c" -lm -o "$out/fuzz_readers"
  else
    $cc $flags -fsanitize=fuzzer -DSELFCOL_STATIC -I "$root/include" \
      "$root/tests/fuzz/fuzz_$target.c" $objs $(pkg-config --libs ccd) -lm -lpthread \
      -o "$out/fuzz_$target"
  fi
  # A fresh working corpus seeded from the committed one (which stays small).
  mkdir -p "$out/corpus-$target"
  cp "$root/tests/fuzz/corpus/$target"/* "$out/corpus-$target/"
  echo "fuzz: $target for $seconds s"
  if ! (cd "$out" && "./fuzz_$target" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 \
        $max_len -print_final_stats=1 "corpus-$target" > "fuzz_$target.log" 2>&1); then
    echo "fuzz: $target FAILED; see $out/fuzz_$target.log and $out/crash-*" >&2
    tail -n 40 "$out/fuzz_$target.log" >&2
    status=1
  else
    grep -E "stat::number_of_executed_units|stat::new_units_added" "$out/fuzz_$target.log" \
      | sed "s/^/fuzz: $target: /"
  fi
done
exit $status
