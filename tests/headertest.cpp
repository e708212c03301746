// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT
// The umbrella header compiles alone as C++.
#include <selfcol/selfcol.h>

int selfcol_headertest_cxx();
int selfcol_headertest_cxx() {
    return selfcol_status_string(SELFCOL_OK) != nullptr ? 0 : 1;
}
