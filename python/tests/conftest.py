# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Shared fixtures: generated surfaces, the CLI and the real frames.

SELFCOL_CLI (the selfcol-cli binary) and SELFCOL_SHARED_DATA (../shared/data)
are set by the ctest entry; tests needing them skip when they are absent."""

import json
import os
import subprocess

import numpy as np
import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def grid(nx, ny, shape=None, jitter=0.0, seed=0):
    """(V, F) of an nx x ny grid sheet over [0,1]^2, mapped by shape(u, v) -> xyz."""
    u, v = np.meshgrid(np.linspace(0, 1, nx + 1), np.linspace(0, 1, ny + 1), indexing="ij")
    u, v = u.ravel(), v.ravel()
    if shape is None:
        V = np.stack([u, v, np.zeros_like(u)], axis=1)
    else:
        V = np.stack(shape(u, v), axis=1)
    if jitter:
        V = V + np.random.default_rng(seed).normal(scale=jitter, size=V.shape)
    idx = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    F = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int32)
    return np.ascontiguousarray(V, dtype=np.float64), F


def folded(nx=24, ny=6, jitter=0.003, seed=3):
    """A strip folded through itself: proximities and interferences."""
    def shape(u, v):
        ang = 1.9 * np.pi * u
        r = 0.25 + 0.05 * u
        return r * np.cos(ang), 0.6 * v + 0.15 * np.sin(3 * ang), r * np.sin(ang) * (1 - 1.2 * u)
    return grid(nx, ny, shape, jitter, seed)


def write_obj(path, V, F):
    with open(path, "w") as fh:
        for p in V:
            fh.write("v %.17g %.17g %.17g\n" % tuple(p))
        for t in F:
            fh.write("f %d %d %d\n" % tuple(int(i) + 1 for i in t))


def read_obj(path):
    from selfcol.io import read_obj as r
    return r(path)


@pytest.fixture
def cli():
    path = os.environ.get("SELFCOL_CLI") or os.path.join(ROOT, "build", "tools", "cli",
                                                          "selfcol-cli")
    if not os.access(path, os.X_OK):
        pytest.skip("selfcol-cli not built (%s)" % path)

    def run(*args):
        proc = subprocess.run([path, "check", "--json", "-", *map(str, args)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=600)
        assert proc.returncode in (0, 1), proc.stderr.decode()
        return [json.loads(line) for line in proc.stdout.decode().splitlines() if line.strip()]
    return run


@pytest.fixture
def shared_data():
    path = os.environ.get("SELFCOL_SHARED_DATA") or os.path.join(ROOT, "..", "shared", "data")
    if not os.path.isdir(path):
        pytest.skip("no shared data (%s)" % path)
    return path
