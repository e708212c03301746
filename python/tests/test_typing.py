# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""mypy accepts the package's annotations (py.typed) and a typical user script."""

import os
import subprocess
import sys

import pytest

USER = '''
import numpy as np
import selfcol

V = np.zeros((3, 3))
F = np.array([[0, 1, 2]])
c: selfcol.Contacts = selfcol.self_collide(V, F, distance=0.1, kinds="vf,ee")
n: int = len(c)
vf: np.ndarray = c.vf
stats = c.stats["total_seconds"]
m = selfcol.Mesh(V, F)
h = selfcol.Hierarchy(m)
s = selfcol.Store()
s.update(h.self_collide(0.1))
sw: selfcol.Sweep = h.self_sweep(V)
t: float = sw.free_fraction
try:
    selfcol.Mesh(V, F)
except selfcol.InvalidArgument as e:
    code: int = e.status
'''


def test_mypy_accepts_the_package(tmp_path):
    pytest.importorskip("mypy")
    script = tmp_path / "user.py"
    script.write_text(USER)
    env = dict(os.environ, MYPYPATH="")
    flags = ["--no-incremental", "--strict", "--allow-any-generics", "--allow-untyped-calls",
             "--ignore-missing-imports"]
    for target in (["-p", "selfcol"], [str(script)]):
        proc = subprocess.run([sys.executable, "-m", "mypy", *flags, *target],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              cwd=str(tmp_path), env=env, timeout=300)
        assert proc.returncode == 0, proc.stdout.decode()
