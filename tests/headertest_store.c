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
    o.threads = SELFCOL_MAX_THREADS;
    return (int)o.threads == 64 ? SELFCOL_OK : SELFCOL_ERROR;
}
