// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The Bullet adapter's C++ consumer (tests/consumer/run.sh): a deformable
// world with one tiny soft body (a square of 4 nodes and 2 faces), the
// adapter attached to it, 3 steps of the world (the adapter's action runs at
// each), and the adapter's statistics checked. Exits 0 when they are right.
#include <selfcol/bullet.h>

#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <btBulletDynamicsCommon.h>

#include <cstdio>

int main() {
    btSoftBodyRigidBodyCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher(&configuration);
    btDbvtBroadphase broadphase;
    btDeformableBodySolver body_solver;
    btDeformableMultiBodyConstraintSolver constraint_solver;
    constraint_solver.setDeformableSolver(&body_solver);
    btDeformableMultiBodyDynamicsWorld world(&dispatcher, &broadphase, &constraint_solver,
                                             &configuration, &body_solver);
    world.getWorldInfo().m_sparsesdf.Initialize();

    const btVector3 x[4] = {btVector3(0, 1, 0), btVector3(1, 1, 0), btVector3(1, 1, 1),
                            btVector3(0, 1, 1)};
    const btScalar m[4] = {1, 1, 1, 1};
    btSoftBody *body = new btSoftBody(&world.getWorldInfo(), 4, x, m);
    body->appendLink(0, 1);
    body->appendLink(1, 2);
    body->appendLink(2, 3);
    body->appendLink(3, 0);
    body->appendLink(0, 2);
    body->appendFace(0, 1, 2);
    body->appendFace(0, 2, 3);
    world.addSoftBody(body);

    selfcol_bullet *adapter = nullptr;
    int rc = selfcol_bullet_create(&adapter, &world, nullptr);
    uint32_t id = 0;
    if (rc == SELFCOL_OK)
        rc = selfcol_bullet_attach(adapter, body, &id);
    selfcol_bullet_step_stats stats = {};
    stats.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    if (rc == SELFCOL_OK) {
        for (int i = 0; i < 3; ++i)
            world.stepSimulation(btScalar(1.0 / 240.0), 0); // one internal step each
        rc = selfcol_bullet_stats(adapter, &stats);
    }
    selfcol_bullet_destroy(adapter);
    world.removeSoftBody(body);
    delete body;
    if (rc != SELFCOL_OK) {
        std::fprintf(stderr, "consumer_bullet: %s\n", selfcol_status_string(rc));
        return 1;
    }
    std::printf("consumer_bullet: body %u, steps %llu, status %d, distance %g\n", unsigned(id),
                (unsigned long long)stats.steps, stats.status, stats.distance);
    return stats.status == SELFCOL_OK && stats.steps == 3 ? 0 : 1;
}
