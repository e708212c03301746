// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include <selfcol/version.h>

unsigned selfcol_version_number(void) {
    return SELFCOL_VERSION_NUMBER;
}

const char *selfcol_version_string(void) {
    return SELFCOL_VERSION_STRING;
}
