// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT
// Each header that names SELFCOL_MAX_THREADS compiles alone with it (it was
// defined in hierarchy.h only, so store.h alone did not compile with it).
#include <selfcol/store.h>

int selfcol_headertest_store(void);
int selfcol_headertest_store(void) {
    selfcol_store_options o;
    if (selfcol_store_options_init(&o, SELFCOL_STORE_OPTIONS_VERSION) != SELFCOL_OK)
        return SELFCOL_ERROR;
    // SELFCOL_MAX_THREADS (common.h) and selfcol_context (declared in
    // common.h for the headers that name it) compile with store.h alone.
    selfcol_context *none = NULL;
    return SELFCOL_MAX_THREADS == 64 && none == NULL ? SELFCOL_OK : SELFCOL_ERROR;
}
