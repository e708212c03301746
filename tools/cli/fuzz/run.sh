#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Builds the reader fuzzer with clang (libFuzzer + ASan + UBSan) and runs it.
# usage: tools/cli/fuzz/run.sh [SECONDS] [OUTDIR]   (defaults: 60, build-fuzz)
# Seeds: small meshes of every format written by the CLI tests (if they ran)
# and the bundled ribbon. Crashes are written to OUTDIR as crash-*.
set -eu
seconds=${1:-60}
out=${2:-build-fuzz}
root=$(cd "$(dirname "$0")/../../.." && pwd)
command -v clang >/dev/null || { echo "fuzz: needs clang and libclang-rt-14-dev (apt-get install clang libclang-rt-14-dev)" >&2; exit 1; }
mkdir -p "$out/corpus"
clang -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
  -I "$root/include" -I "$root/tools/cli" \
  "$root/tools/cli/fuzz/fuzz_readers.c" "$root/tools/cli/read.c" \
  "$root/tools/cli/read_text.c" "$root/tools/cli/read_ply.c" -lm -o "$out/fuzz_readers"
# Seeds: the first byte is the format hint (1 obj, 2 ply, 3 off, 4 stl).
n=0
for f in "$root/tests/data/folded_ribbon.obj" $(find "$root" -path '*/tests/cli/work/*' \
    \( -name '*.obj' -o -name '*.ply' -o -name '*.off' -o -name '*.stl' \) -size -16k 2>/dev/null); do
  case "$f" in *.obj) h='\001' ;; *.ply) h='\002' ;; *.off) h='\003' ;; *) h='\004' ;; esac
  { printf "$h"; cat "$f"; } > "$out/corpus/seed$n"
  n=$((n + 1))
done
cd "$out"
./fuzz_readers -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=2048 corpus
