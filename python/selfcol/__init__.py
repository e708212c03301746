# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""selfcol: collision and self-collision detection of deformable triangle surfaces.

Python binding of the selfcol C library (cffi, API mode; the library is
built into the extension). Arrays in, arrays out::

    import numpy as np, selfcol
    c = selfcol.self_collide(V, F)          # d = 0.1 x mean edge length
    c.vf, c.ee, c.ef                        # (n, 2), (n, 4), (n, 3) index arrays
    c.distance, c.wa, c.wb, c.direction     # per record
    c.stats                                 # the query's counters

For frames of one topology keep the handles: ``Mesh.set_positions``,
``Hierarchy.refit``, ``Hierarchy.self_collide`` / ``collide`` /
``self_sweep`` / ``sweep``, ``Store.update``; ``Scene`` for surfaces by kind
and convex colliders. Errors raise ``selfcol.Error`` subclasses carrying the
C status (``InvalidArgument`` is also a ``ValueError``, ``OutOfMemory`` a
``MemoryError``). The GIL is released during every C call.
"""

from ._core import (
    Cancelled,
    Contacts,
    Error,
    Hierarchy,
    InvalidArgument,
    Kind,
    Mesh,
    Method,
    Mismatch,
    OutOfMemory,
    RangeError,
    Scene,
    SceneStore,
    Sequence,
    StaleHierarchy,
    Store,
    StoreContacts,
    Sweep,
    SweepFlag,
    VersionError,
    collide,
    mean_edge_length,
    self_collide,
    self_sweep,
    version,
)

__version__ = "0.4.0"

__all__ = [
    "Cancelled", "Contacts", "Error", "Hierarchy", "InvalidArgument", "Kind", "Mesh", "Method",
    "Mismatch", "OutOfMemory", "RangeError", "Scene", "SceneStore", "Sequence", "StaleHierarchy",
    "Store", "StoreContacts", "Sweep", "SweepFlag", "VersionError", "collide", "mean_edge_length",
    "self_collide", "self_sweep", "version", "__version__",
]
