// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include <selfcol/common.h>

const char *selfcol_status_string(int status) {
    switch (status) {
    case SELFCOL_OK: return "success";
    case SELFCOL_ERROR: return "internal error";
    case SELFCOL_ENOMEM: return "out of memory";
    case SELFCOL_EINVAL: return "invalid argument or input data";
    case SELFCOL_EVERSION: return "options version is 0 (uninitialised) or unknown";
    case SELFCOL_EBUFS: return "buffer too small";
    case SELFCOL_EUSER: return "stopped by a callback";
    case SELFCOL_ERANGE: return "count or index out of the supported range";
    case SELFCOL_EMISMATCH: return "handles do not belong together";
    case SELFCOL_ESTALE: return "hierarchy not refit since its mesh moved";
    default: return "unknown status";
    }
}
