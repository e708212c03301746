#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# The thread-scaling rows of docs/benchmarks.md ("Threads") for the 16-core
# machine of ../shared/device, which a session is lent only sometimes.
#
# usage (from the project's root, after `make build`):
#   sh tools/bench/device_threads.sh [BUILD_DIR] [OLD_LIBSELFCOL]
# makes .device-pack/ with ../shared/device/pack.sh, adds
# selfcol-bench-threads and writes .device-pack/threads.sh; then, on the
# lent machine, with .device-pack carried along:
#   bash .device-pack/threads.sh
# It prints, in one run: the discrete cloth-ball 92 query on 1, 2, 4, 8 and
# 16 threads (warm, interleaved, records compared), EARLIEST 92 -> 93 on 1,
# 8 and 16 threads, ipc-toolkit's discrete and continuous rows on 1 and 16,
# and the Bullet ribbon 20k on 1 and 16 threads. With OLD_LIBSELFCOL (a
# libselfcol.so.0.x of another commit with the same SONAME), EARLIEST and the discrete rows run
# with it too, alternating, as an A/B in the same run. About 3 minutes there.
set -eu
build=${1:-build}
old=${2:-}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"
[ -x "$build/tools/bench/selfcol-bench-threads" ] ||
  { echo "device_threads.sh: $build/tools/bench/selfcol-bench-threads missing (make build)" >&2; exit 1; }
sh ../shared/device/pack.sh "$build"
cp "$build/tools/bench/selfcol-bench-threads" .device-pack/bin/
libs="lib"
if [ -n "$old" ]; then
  mkdir -p .device-pack/old
  # LD_LIBRARY_PATH swaps it in only under the programs' SONAME.
  soname=$(objdump -p "$old" | awk '/SONAME/ {print $2}')
  [ "$soname" = "$(objdump -p "$build/lib/libselfcol.so" | awk '/SONAME/ {print $2}')" ] ||
    { echo "device_threads.sh: $old is $soname, not the build's SONAME" >&2; exit 1; }
  cp "$old" ".device-pack/old/$soname"
  libs="old lib"
fi
cat > .device-pack/threads.sh <<EOF
#!/bin/bash
# Written by tools/bench/device_threads.sh at $(git rev-parse --short HEAD).
cd "\$(dirname "\$0")"
H=\$PWD
F=\$H/data/sample-scalable-ccd-data/cloth-ball/frames
echo "== \$(nproc) cores, \$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2), \$(date -u)"
if ls whl/*.whl >/dev/null 2>&1; then
  site=\$(mktemp -d)
  python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --target "\$site" whl/*.whl && export PYTHONPATH="\$site"
fi
for round in 1 2; do
  for v in $libs; do
    L=\$H/\$v:\$H/lib
    echo "== round \$round, \$v: discrete cloth-ball 92"
    LD_LIBRARY_PATH=\$L timeout 90 bin/selfcol-bench-threads --data "\$H/data" --threads 1,2,4,8,16 --reps 5
    echo "== round \$round, \$v: EARLIEST 92 -> 93, 1 and 16 threads"
    LD_LIBRARY_PATH=\$L timeout 60 bin/selfcol-bench-sweep --data "\$H/data" --reps 3 --only cloth-ball-92 --earliest --threads 16 2>/dev/null | grep BVH
  done
done
echo "== EARLIEST on 8 threads"
LD_LIBRARY_PATH=\$H/lib timeout 60 bin/selfcol-bench-sweep --data "\$H/data" --reps 3 --only cloth-ball-92 --earliest --threads 8 2>/dev/null | grep "8 threads"
echo "== ipc-toolkit, 1 and 16 threads"
python3 -c 'import ipctk' 2>/dev/null && timeout 200 python3 ipctk_time.py "\$F/cloth_ball92.ply" "\$F/cloth_ball93.ply" "1,16" 3
echo "== Bullet ribbon 20k: off and selfcol on 1 thread, selfcol on 16"
export LD_LIBRARY_PATH=\$H/lib
timeout 100 bin/selfcol-bullet-bench --sizes 20k --modes off,selfcol --repeat 1 | grep -E "^run "
timeout 100 bin/selfcol-bullet-bench --sizes 20k --modes selfcol --repeat 1 --threads 16 | grep -E "^run "
echo "== done \$(date -u)"
EOF
echo "device_threads.sh: on the lent machine, run: bash .device-pack/threads.sh (carry .device-pack)"
