// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#ifndef SELFCOL_EXHAUSTIVE_H
#define SELFCOL_EXHAUSTIVE_H

#include "query/query.h"

// The exhaustive reference (exhaustive.c).
int selfcol_exhaustive__run(selfcol_query *q);

#endif // SELFCOL_EXHAUSTIVE_H
