// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The Bullet adapter's C consumer (tests/consumer/run.sh): <selfcol/bullet.h>
// from C99 with no Bullet header, and the defaults of the options. Exits 0
// when they are right, 1 otherwise.
#include <selfcol/bullet.h>

#include <stdio.h>

#if defined(SELFCOL_EXPECT_STATIC) && !defined(SELFCOL_STATIC)
#error "a static libselfcol_bullet must bring SELFCOL_STATIC (libselfcol's) to its consumers"
#endif
#if defined(SELFCOL_EXPECT_SHARED) && defined(SELFCOL_STATIC)
#error "a shared libselfcol_bullet must not define SELFCOL_STATIC for its consumers"
#endif

int main(void) {
    selfcol_bullet_options opts;
    int rc = selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION);
    if (rc != SELFCOL_OK) {
        fprintf(stderr, "consumer_bullet_c: %s\n", selfcol_status_string(rc));
        return 1;
    }
    printf("consumer_bullet_c: selfcol %s, options: iterations %u, repulsion %g, automatic %d\n",
           selfcol_version_string(), opts.iterations, opts.repulsion, opts.automatic);
    if (opts.version != SELFCOL_BULLET_OPTIONS_VERSION || opts.query != NULL ||
        opts.store != NULL || opts.iterations != SELFCOL_BULLET_DEFAULT_ITERATIONS ||
        opts.repulsion != SELFCOL_BULLET_DEFAULT_REPULSION || opts.automatic != 1)
        return 1;
    // A version from the future is refused.
    return selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION + 1) ==
                   SELFCOL_EVERSION
               ? 0
               : 1;
}
