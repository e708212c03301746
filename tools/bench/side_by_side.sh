#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# The Python side-by-side (make bench-python): selfcol's wheel, ipctk,
# pymeshlab, libigl and trimesh, each pip-installed into a fresh venv under
# BUILD/side-by-side with no pip cache (the install a new user waits for,
# numpy included), then asked about cloth-ball frame 92 on one thread
# (tools/bench/side_by_side.py says what each is asked). Writes the table to
# OUT (default tools/bench/results/side_by_side.md). Needs PyPI and
# ../shared/data; says so and exits 0 without them.
# usage: sh tools/bench/side_by_side.sh [--build DIR] [--reps N] [--out FILE]
set -eu
cd "$(dirname "$0")/../.."
build=build reps=3 out=tools/bench/results/side_by_side.md
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --reps) reps="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--reps N] [--out FILE]" >&2; exit 2 ;;
  esac
done
ply=${SELFCOL_SHARED_DATA:-../shared/data}/sample-scalable-ccd-data/cloth-ball/frames/cloth_ball92.ply
if [ ! -f "$ply" ]; then
  echo "side_by_side: no $ply (../shared/data): nothing measured"; exit 0
fi
wheel=$(ls "$build"/wheel/dist/selfcol-*.whl 2>/dev/null | head -n 1 || true)
if [ -z "$wheel" ]; then
  sh tools/wheel.sh "$build"
  wheel=$(ls "$build"/wheel/dist/selfcol-*.whl | head -n 1)
fi
work="$build/side-by-side"
mkdir -p "$work"
log="$work/log.txt"
: > "$log"
python=python3
command -v "$python" >/dev/null 2>&1 || python=/usr/bin/python3
rows="$work/rows.jsonl"
: > "$rows"
for tool in selfcol ipctk pymeshlab libigl trimesh; do
  venv="$work/$tool"
  rm -rf "$venv"
  if ! "$python" -m venv "$venv" >> "$log" 2>&1; then
    echo "side_by_side: no venv module for $python" >&2; exit 1
  fi
  package=$tool
  [ "$tool" = selfcol ] && package=$wheel
  start=$(date +%s.%N)
  if ! "$venv/bin/pip" install -q --no-cache-dir "$package" numpy >> "$log" 2>&1; then
    echo "side_by_side: pip cannot install $tool (no PyPI?): nothing measured (see $log)"
    exit 0
  fi
  end=$(date +%s.%N)
  install_s=$("$python" -c "print(round($end - $start, 1))")
  if [ "$tool" = selfcol ]; then
    # The mesh as every package gets it: the file's vertex order, and d.
    "$venv/bin/python" - "$ply" "$work/mesh.npz" <<'EOF'
import sys
import numpy as np
import selfcol
import selfcol.io as io
V, F = io.read_mesh(sys.argv[1], weld_vertices=False)
np.savez(sys.argv[2], V=V, F=F, d=0.1 * selfcol.mean_edge_length(V, F))
EOF
  fi
  echo "side_by_side: $tool installed in $install_s s; querying" >&2
  row=$(OMP_NUM_THREADS=1 "$venv/bin/python" tools/bench/side_by_side.py "$tool" "$work/mesh.npz" \
        "$ply" "$reps")
  echo "$row" | "$python" -c "import json,sys; r=json.load(sys.stdin); r['install_s']=$install_s; print(json.dumps(r))" >> "$rows"
done
"$python" - "$rows" "$out" "$reps" "$(git rev-parse --short HEAD)" <<'EOF'
import json, os, platform, subprocess, sys, time
rows = [json.loads(l) for l in open(sys.argv[1])]
cpu = "?"
for line in open("/proc/cpuinfo"):
    if line.startswith("model name"):
        cpu = line.split(":", 1)[1].strip(); break
def ms(x):
    return "-" if x is None else "%.1f" % x
lines = ["# Python side by side: cloth-ball frame 92 (92,230 triangles)", "",
         "`make bench-python` (tools/bench/side_by_side.sh) at commit %s, %s, %s, %d cores; "
         "medians of %s runs after a warm-up, one thread for every package. Install: "
         "`pip install --no-cache-dir PACKAGE numpy` into a fresh venv (selfcol: its wheel "
         "from `make wheel`; the others from PyPI, through this machine's package mirror)."
         % (sys.argv[4], time.strftime("%Y-%m-%d"), cpu, os.cpu_count(), sys.argv[3]), "",
         "Self-intersection query: from the arrays (everything the package builds "
         "included), and on a structure kept across calls (selfcol's Hierarchy, ipctk's "
         "CollisionMesh). Proximity query: on the kept structure.", "",
         "| package | version | install s | self-intersection ms, from arrays | kept structure "
         "| what it answers | proximity query ms (d = 0.1 x mean edge) | what it answers |",
         "|---|---|---|---|---|---|---|---|"]
for r in rows:
    t = r["tool"]
    if t == "selfcol":
        a = "%d triangle pairs, %d faces" % (r["pairs"], r["faces"])
        b = "%d VF + EE, %d crossing edges" % (r["proximities"], r["crossing_edges"])
    elif t == "ipctk":
        a = "yes or no only: %s" % ("yes" if r["intersects"] else "no")
        b = "%d collisions (no crossings)" % r["proximities"]
    elif t == "pymeshlab":
        a, b = "%d faces (no pairs)" % r["faces"], "none"
    elif t == "libigl":
        a, b = "%d triangle pairs, %d faces (CGAL, exact)" % (r["pairs"], r["faces"]), "none"
    else:
        a, b = "none (loading the PLY: %.1f ms)" % r["load_ms"], "none"
    lines.append("| %s | %s | %.1f | %s | %s | %s | %s | %s |" % (
        t, r["version"], r["install_s"], ms(r.get("query_ms")), ms(r.get("kept_ms")), a,
        ms(r.get("proximity_ms")), b))
open(sys.argv[2], "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
EOF
