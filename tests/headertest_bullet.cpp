// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT
// libselfcol_bullet's header compiles alone as C++11, without any Bullet
// header (it forward-declares the two Bullet classes it names).
#include <selfcol/bullet.h>

int selfcol_headertest_bullet_cxx(btDeformableMultiBodyDynamicsWorld *world, btSoftBody *body);
int selfcol_headertest_bullet_cxx(btDeformableMultiBodyDynamicsWorld *world, btSoftBody *body) {
    selfcol_bullet *adapter = nullptr;
    if (selfcol_bullet_create(&adapter, world, nullptr) != SELFCOL_OK)
        return SELFCOL_ERROR;
    uint32_t id = 0;
    selfcol_bullet_step_stats stats = {};
    stats.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    int status = selfcol_bullet_attach(adapter, body, &id);
    if (status == SELFCOL_OK)
        status = selfcol_bullet_stats(adapter, &stats);
    selfcol_bullet_destroy(adapter);
    return status;
}
