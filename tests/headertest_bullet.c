// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT
// libselfcol_bullet's header compiles alone as strict C99, without any Bullet
// header: btSoftBody and btDeformableMultiBodyDynamicsWorld are opaque there.
#include <selfcol/bullet.h>

int selfcol_headertest_bullet_c(btDeformableMultiBodyDynamicsWorld *world, btSoftBody *body);
int selfcol_headertest_bullet_c(btDeformableMultiBodyDynamicsWorld *world, btSoftBody *body) {
    selfcol_bullet_options opts;
    selfcol_bullet *adapter = NULL;
    uint32_t id = 0;
    if (selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION) != SELFCOL_OK ||
        selfcol_bullet_create(&adapter, world, &opts) != SELFCOL_OK)
        return SELFCOL_ERROR;
    return selfcol_bullet_attach(adapter, body, &id);
}
