# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Sourced by run.sh and run_sweep.sh (POSIX sh): ipctk_venv BUILD LOG makes
# (once) the venv under the build directory that holds ipc-toolkit's Python
# package, and prints its python when that imports ipctk; it prints nothing
# when the venv or the package cannot be had (no network, no venv module),
# and the caller skips its ipc-toolkit rows. Debian's python3 needs
# python3-venv for a venv (installed through tools/deps.sh, as root only).
ipctk_venv() {
  _venv="$1/ipctk-venv"
  _log="$2"
  if [ ! -x "$_venv/bin/python" ]; then
    for _py in python3 /usr/bin/python3; do
      if command -v "$_py" >/dev/null 2>&1 && "$_py" -m venv "$_venv" >/dev/null 2>&1; then break; fi
      rm -rf "$_venv"
    done
    if [ ! -x "$_venv/bin/python" ] && sh tools/deps.sh python3-venv >> "$_log" 2>&1; then
      /usr/bin/python3 -m venv "$_venv" >> "$_log" 2>&1 || rm -rf "$_venv"
    fi
    if [ -x "$_venv/bin/python" ]; then
      "$_venv/bin/python" -m pip install -q ipctk numpy >> "$_log" 2>&1 || rm -rf "$_venv"
    fi
  fi
  if [ -x "$_venv/bin/python" ] && "$_venv/bin/python" -c 'import ipctk' 2>/dev/null; then
    echo "$_venv/bin/python"
  fi
}
