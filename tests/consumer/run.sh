#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# The three doors an engine takes selfcol through, each proven by a program
# built outside the tree. Builds the library alone (no tests, no tools),
# shared and then static, installs each into a temporary prefix with
# `cmake --install --prefix`, and builds and runs against it:
#   find_package       tests/consumer/find_package (main.c; for the static
#                      flavour SELFCOL_STATIC must arrive with the target)
#   pkg-config         main.c with `pkg-config --cflags --libs selfcol`
#                      (shared, with an rpath) and `--static` (static)
#   eigen              tests/consumer/eigen: find_package(selfcol COMPONENTS eigen)
#   bullet             tests/consumer/bullet: find_package(selfcol COMPONENTS
#                      bullet), a C program (options) and a C++ one (a world
#                      with a tiny soft body stepped 3 times); then the C one
#                      with `pkg-config selfcol_bullet` (`--static` for static)
# and then
#   add_subdirectory   tests/consumer/add_subdirectory: the source tree in a
#                      C parent that sets nothing; it checks that selfcol
#                      leaves the parent's settings alone, and that its
#                      install installs nothing of selfcol's.
# Each consumer checks the known contacts of its mesh and exits nonzero on a
# mismatch. usage: tests/consumer/run.sh [WORKDIR]
# (default: a temporary directory, removed at the end). JOBS: build jobs (2).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
here=$root/tests/consumer
jobs=${JOBS:-2}
if [ $# -ge 1 ]; then
  mkdir -p "$1"
  work=$(cd "$1" && pwd)
else
  work=$(mktemp -d "${TMPDIR:-/tmp}/selfcol-consumer.XXXXXX")
  trap 'rm -rf "$work"' EXIT
fi
sh "$root/tools/deps.sh" cmake make gcc g++ pkg-config binutils libccd-dev libeigen3-dev \
  libbullet-dev
cc=${CC:-cc}

# Runs a command quietly; on failure shows its output and stops.
run_quiet() {
  if ! "$@" > "$work/last.log" 2>&1; then
    cat "$work/last.log"
    echo "consumer: FAILED: $*" >&2
    exit 1
  fi
}

# needs BINARY yes|no [LIBRARY]: whether BINARY loads LIBRARY.so (default
# libselfcol) at run time.
needs() {
  lib=${3:-libselfcol}
  if readelf -d "$1" | grep -q "NEEDED.*$lib\\.so"; then got=yes; else got=no; fi
  if [ "$got" != "$2" ]; then
    echo "consumer: $1: NEEDED $lib.so is '$got', expected '$2'" >&2
    exit 1
  fi
}

for flavour in shared static; do
  if [ $flavour = shared ]; then shared=ON; else shared=OFF; fi
  prefix=$work/prefix-$flavour
  echo "== libselfcol $flavour: build, install into $prefix"
  rm -rf "$work/build-$flavour" "$prefix"
  # Configured for another prefix: the install's --prefix must win (selfcol.pc too).
  run_quiet cmake -S "$root" -B "$work/build-$flavour" -DCMAKE_BUILD_TYPE=Release \
    -DBUILD_SHARED_LIBS=$shared -DSELFCOL_BUILD_TESTS=OFF -DSELFCOL_BUILD_TOOLS=OFF \
    -DCMAKE_INSTALL_PREFIX="$work/not-here"
  run_quiet cmake --build "$work/build-$flavour" -j "$jobs"
  run_quiet cmake --install "$work/build-$flavour" --prefix "$prefix"

  echo "-- find_package (CMake package)"
  run_quiet cmake -S "$here/find_package" -B "$work/find_package-$flavour" \
    -DCMAKE_PREFIX_PATH="$prefix" -DSELFCOL_EXPECT=$flavour
  run_quiet cmake --build "$work/find_package-$flavour"
  needs "$work/find_package-$flavour/consumer" $([ $flavour = shared ] && echo yes || echo no)
  "$work/find_package-$flavour/consumer"

  echo "-- pkg-config (selfcol.pc)"
  pcdir=$(dirname "$(find "$prefix" -name selfcol.pc)")
  export PKG_CONFIG_PATH="$pcdir"
  pc_prefix=$(pkg-config --variable=prefix selfcol)
  if [ "$pc_prefix" != "$prefix" ]; then
    echo "consumer: selfcol.pc says prefix=$pc_prefix, installed in $prefix" >&2
    exit 1
  fi
  if [ $flavour = shared ]; then
    libs="$(pkg-config --libs selfcol) -Wl,-rpath,$(pkg-config --variable=libdir selfcol)"
    expect=-DSELFCOL_EXPECT_SHARED
  else
    libs=$(pkg-config --static --libs selfcol)
    expect=-DSELFCOL_EXPECT_STATIC
  fi
  echo "   cflags: $(pkg-config --cflags selfcol)   libs: $libs"
  # shellcheck disable=SC2046,SC2086 # flags are words
  run_quiet $cc -std=c99 -Wall -Wextra -pedantic -Werror $expect \
    $(pkg-config --cflags selfcol) "$here/main.c" -o "$work/pkgconfig-$flavour" $libs
  needs "$work/pkgconfig-$flavour" $([ $flavour = shared ] && echo yes || echo no)
  "$work/pkgconfig-$flavour"
  unset PKG_CONFIG_PATH

  echo "-- find_package(selfcol COMPONENTS eigen)"
  run_quiet cmake -S "$here/eigen" -B "$work/eigen-$flavour" -DCMAKE_PREFIX_PATH="$prefix"
  run_quiet cmake --build "$work/eigen-$flavour"
  "$work/eigen-$flavour/consumer_eigen"

  echo "-- find_package(selfcol COMPONENTS bullet)"
  if [ -z "$(find "$prefix" -name selfcolBulletTargets.cmake)" ]; then
    echo "consumer: libselfcol_bullet was not installed (is Bullet found? see the configure output)" >&2
    exit 1
  fi
  loads=$([ $flavour = shared ] && echo yes || echo no)
  run_quiet cmake -S "$here/bullet" -B "$work/bullet-$flavour" -DCMAKE_PREFIX_PATH="$prefix" \
    -DSELFCOL_EXPECT=$flavour
  run_quiet cmake --build "$work/bullet-$flavour" -j "$jobs"
  for exe in consumer_bullet_c consumer_bullet; do
    needs "$work/bullet-$flavour/$exe" $loads libselfcol_bullet
    "$work/bullet-$flavour/$exe"
  done

  echo "-- pkg-config (selfcol_bullet.pc)"
  export PKG_CONFIG_PATH="$pcdir"
  if [ $flavour = shared ]; then
    libs="$(pkg-config --libs selfcol_bullet) -Wl,-rpath,$(pkg-config --variable=libdir selfcol_bullet)"
  else
    libs=$(pkg-config --static --libs selfcol_bullet)
  fi
  echo "   cflags: $(pkg-config --cflags selfcol_bullet)   libs: $libs"
  # shellcheck disable=SC2046,SC2086 # flags are words
  run_quiet $cc -std=c99 -Wall -Wextra -pedantic -Werror $expect \
    $(pkg-config --cflags selfcol_bullet) "$here/bullet/main.c" -o "$work/pkgconfig-bullet-$flavour" $libs
  needs "$work/pkgconfig-bullet-$flavour" $loads libselfcol_bullet
  "$work/pkgconfig-bullet-$flavour"
  unset PKG_CONFIG_PATH
done

echo "== add_subdirectory (a C parent that sets nothing)"
rm -rf "$work/subdirectory" "$work/subdirectory-prefix"
run_quiet cmake -S "$here/add_subdirectory" -B "$work/subdirectory" -DSELFCOL_SOURCE_DIR="$root"
run_quiet cmake --build "$work/subdirectory" -j "$jobs"
needs "$work/subdirectory/consumer" no
"$work/subdirectory/consumer"
# A subproject's selfcol has no install rules (SELFCOL_INSTALL is off).
run_quiet cmake --install "$work/subdirectory" --prefix "$work/subdirectory-prefix"
if [ -n "$(find "$work/subdirectory-prefix" -type f 2>/dev/null)" ]; then
  echo "consumer: installing the parent installed selfcol's files:" >&2
  find "$work/subdirectory-prefix" -type f >&2
  exit 1
fi
echo "consumer: every door works"
