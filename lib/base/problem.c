// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Naming a refused option (problem.h).
#include "base/problem.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

int selfcol_problem__begin(selfcol_options_problem *problem) {
    if (problem == NULL)
        return SELFCOL_EINVAL;
    if (problem->version == 0 || problem->version > SELFCOL_OPTIONS_PROBLEM_VERSION)
        return SELFCOL_EVERSION;
    problem->status = SELFCOL_OK;
    problem->field[0] = '\0';
    problem->message[0] = '\0';
    return SELFCOL_OK;
}

int selfcol_problem__field(const selfcol_problem_at *at, int status, const char *field,
                           const char *format, ...) {
    if (at == NULL || at->problem == NULL)
        return status;
    selfcol_options_problem *p = at->problem;
    p->status = status;
    snprintf(p->field, sizeof p->field, "%s%s", at->prefix, field);
    int n = snprintf(p->message, sizeof p->message, "%s.%s%s ", at->type, at->prefix, field);
    if (n > 0 && (size_t)n < sizeof p->message) {
        va_list args;
        va_start(args, format);
        vsnprintf(p->message + n, sizeof p->message - (size_t)n, format, args);
        va_end(args);
    }
    return status;
}

int selfcol_problem__version(const selfcol_problem_at *at, unsigned int version,
                             unsigned int latest) {
    if (version == 0)
        return selfcol_problem__field(at, SELFCOL_EVERSION, "version",
                                      "= 0: the struct was never initialised (its _init "
                                      "function sets it)");
    if (version > latest)
        return selfcol_problem__field(at, SELFCOL_EVERSION, "version",
                                      "= %u is newer than this library's %u", version, latest);
    return SELFCOL_OK;
}

int selfcol_problem__version_since(const selfcol_problem_at *at, unsigned int version,
                                   unsigned int first, unsigned int latest) {
    if (version != 0 && version < first)
        return selfcol_problem__field(at, SELFCOL_EVERSION, "version",
                                      "= %u is an older layout (0.3's, with threads: since "
                                      "0.4 they are the context's); this library reads %u",
                                      version, latest);
    return selfcol_problem__version(at, version, latest);
}

selfcol_problem_at selfcol_problem__nested(const selfcol_problem_at *at, const char *field,
                                           char into[64]) {
    selfcol_problem_at nested = {NULL, "", ""};
    if (at == NULL)
        return nested;
    snprintf(into, 64, "%s%s->", at->prefix, field);
    nested.problem = at->problem;
    nested.type = at->type;
    nested.prefix = into;
    return nested;
}
