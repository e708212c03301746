// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The coherent queries of sequence.c: what its tests reach beyond the
// public API (include/selfcol/sequence.h).
#ifndef SELFCOL_SEQUENCE_PRIVATE_H
#define SELFCOL_SEQUENCE_PRIVATE_H

#include <selfcol/sequence.h>

#include "base/problem.h"

// Right after a query answered by a partial rebuild (and before the
// positions change), compares the near pairs of the cluster pairs it
// queried again with those a full rebuild at the same positions lists for
// them: the same pairs, in the same order, with the same bounds. Returns 1
// when they match, 0 when they do not, SELFCOL_EINVAL when the last query
// was no partial rebuild, SELFCOL_ENOMEM. `scratch` takes the full
// rebuild's query (cleared afterwards).
int selfcol_sequence__check_partial(selfcol_sequence *s, selfcol_hierarchy *first,
                                    selfcol_hierarchy *second, selfcol_contacts *scratch);

// Shrinks the near list's buffer to its pairs exactly, so that the next
// rebuild has to grow it (a partial rebuild builds its new pairs behind the
// kept ones, in that buffer). SELFCOL_ENOMEM leaves the list as it was.
int selfcol_sequence__trim_list(selfcol_sequence *s);

// Reads a caller's sequence options (NULL: the defaults) and checks them:
// SELFCOL_OK, SELFCOL_EVERSION or SELFCOL_EINVAL; `at` names a refused field
// (problem.h; NULL: the status only). Sequences and scenes go through it.
int selfcol_sequence__options(selfcol_sequence_options *out, const selfcol_sequence_options *opts,
                              const selfcol_problem_at *at);

#endif // SELFCOL_SEQUENCE_PRIVATE_H
