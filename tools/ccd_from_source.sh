#!/bin/sh
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Usage: sh tools/ccd_from_source.sh PREFIX
# libccd 2.1 built from its release and installed into PREFIX, with its
# pkg-config file, for machines without a libccd package: cibuildwheel's
# manylinux and macOS images (pyproject.toml, [tool.cibuildwheel]). Needs
# curl or wget, tar, cmake and a C compiler; double precision, as Debian's.
set -eu
prefix=${1:?usage: ccd_from_source.sh PREFIX}
version=2.1
url="https://github.com/danfis/libccd/archive/refs/tags/v$version.tar.gz"
work=$(mktemp -d "${TMPDIR:-/tmp}/ccd.XXXXXX")
trap 'rm -rf "$work"' EXIT
if command -v curl >/dev/null 2>&1; then
  curl -fsSL "$url" -o "$work/ccd.tar.gz"
else
  wget -q "$url" -O "$work/ccd.tar.gz"
fi
tar -xzf "$work/ccd.tar.gz" -C "$work"
cmake -S "$work/libccd-$version" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DENABLE_DOUBLE_PRECISION=ON -DBUILD_SHARED_LIBS=ON -DCMAKE_INSTALL_PREFIX="$prefix" \
  -DCMAKE_INSTALL_LIBDIR=lib
cmake --build "$work/build" -j 2
cmake --install "$work/build"
