#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: demo_args.sh DEMO...
# The demos' argument checks (demo_common.cpp, parse() and world::start()):
# an out-of-range or malformed value is a usage error (exit 2, the usage
# printed), never truncated or passed on to fail later. Before these checks
# --steps 4294967298 ran 2 steps, --scale inf and --resolution 1 gave a
# generic adapter error, and --distance 1e30 made the ribbon's nodes
# non-finite.
set -u
work=$(mktemp -d "${TMPDIR:-/tmp}/selfcol-demo-args.XXXXXX")
trap 'rm -rf "$work"' EXIT
failed=0

# refused DEMO WHAT ARGS...: exit status 2 and WHAT on stderr.
refused() {
  demo=$1; what=$2; shift 2
  status=0
  "$demo" --quiet "$@" > "$work/out" 2> "$work/err" || status=$?
  if [ $status -eq 2 ] && grep -q -- "$what" "$work/err"; then
    echo "ok: $(basename "$demo") $* refused"
  else
    echo "FAIL: $(basename "$demo") $* gave status $status (expected 2 and '$what'):"
    cat "$work/out" "$work/err"
    failed=1
  fi
}

for demo in "$@"; do
  for args in "--steps 4294967298" "--steps 0" "--steps -1" "--steps 3x" "--steps ''" \
              "--resolution 1" "--resolution 4294967298" "--scale inf" "--scale nan" \
              "--scale 0" "--scale 1e-9" "--every -1" "--threads 0" "--threads 65" \
              "--distance -1" "--distance inf" "--collision none" "--bogus"; do
    eval "refused \"\$demo\" usage: $args"
  done
  # Relative to the scene: a thickness above the cloth's edge length.
  refused "$demo" "mean edge length" --resolution 16 --steps 2 --distance 1e30
  # In range: runs exactly the steps asked for.
  status=0
  "$demo" --quiet --resolution 16 --steps 3 > "$work/out" 2> "$work/err" || status=$?
  if [ $status -eq 0 ] && grep -q "^done: 3 steps" "$work/out"; then
    echo "ok: $(basename "$demo") --steps 3 ran 3 steps"
  else
    echo "FAIL: $(basename "$demo") --resolution 16 --steps 3 (status $status):"
    cat "$work/out" "$work/err"
    failed=1
  fi
done
exit $failed
