// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The hierarchy object. Today it only binds a mesh (the exhaustive method needs
// nothing more); the tree of the hierarchy issue will live here.
#ifndef SELFCOL_HIERARCHY_INTERNAL_H
#define SELFCOL_HIERARCHY_INTERNAL_H

#include <selfcol/hierarchy.h>

struct selfcol_hierarchy {
    selfcol_allocator allocator;
    const selfcol_mesh *mesh;
};

#endif // SELFCOL_HIERARCHY_INTERNAL_H
