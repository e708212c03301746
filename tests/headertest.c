// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT
// The umbrella header compiles alone as strict C99.
#include <selfcol/selfcol.h>

int selfcol_headertest_c(void);
int selfcol_headertest_c(void) {
    return SELFCOL_VERSION_CHECK(0, 0, 1) ? SELFCOL_OK : SELFCOL_ERROR;
}
