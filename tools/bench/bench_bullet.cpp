// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Bullet 3.24's self-collision on a selfcol benchmark mesh (see bench_bullet.h).
//
// Why these calls: in 3.24 the only self-collision path that works for cloth
// is the deformable world's. btDeformableMultiBodyDynamicsWorld sets
// m_softSoftCollision on every body and calls defaultCollisionHandler(psb)
// with psb == this; with fCollision::VF_DD and setSelfCollision(true) that
// computes the faces' normal cones and walks the face tree against itself
// (btDbvt::selfCollideT), testing each node of one face against the other
// face (proximityTest, margin mrg = 2 x the shape margin) and appending a
// DeformableFaceNodeContact per hit. Its solver refits the face tree every
// step with updateFaceTree(true, true) (leaf boxes padded by the margin),
// after the face normals are updated. The face tree is built by
// initializeFaceTree(), whose triangle adjacency search is O(F^2).
//
// The body is built from the node array with appendLink/appendFace, not
// btSoftBodyHelpers::CreateFromTriMesh, which allocates a V x V matrix.
#include "bench_bullet.h"

#include <BulletSoftBody/btSoftBody.h>
#include <LinearMath/btScalar.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <malloc.h>
#include <new>
#include <vector>

struct bench_bullet {
    btSoftBodyWorldInfo info;
    btSoftBody *body;
    std::vector<uint32_t> triangle_of_face; // Bullet drops repeated-index faces
};

static double now_seconds() {
    using clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

static size_t heap_in_use() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
    struct mallinfo2 mi = mallinfo2();
    return mi.uordblks + mi.hblkhd;
#else
    return 0;
#endif
}

extern "C" bench_bullet *bench_bullet_create(size_t vertex_count, const double *xyz,
                                             size_t triangle_count, const uint32_t *triangles,
                                             size_t edge_count, const uint32_t *edges,
                                             double *build_seconds, size_t *tree_bytes) {
    bench_bullet *b = new (std::nothrow) bench_bullet();
    if (b == nullptr)
        return nullptr;
    try {
        std::vector<btVector3> x(vertex_count);
        for (size_t v = 0; v < vertex_count; ++v)
            x[v] =
                btVector3(btScalar(xyz[3 * v]), btScalar(xyz[3 * v + 1]), btScalar(xyz[3 * v + 2]));
        b->body = new btSoftBody(&b->info, int(vertex_count), x.data(), nullptr);
        for (size_t e = 0; e < edge_count; ++e)
            b->body->appendLink(int(edges[2 * e]), int(edges[2 * e + 1]));
        for (size_t t = 0; t < triangle_count; ++t) {
            const uint32_t *c = triangles + 3 * t;
            if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0])
                continue; // appendFace would drop it; keep the index map in step
            b->body->appendFace(int(c[0]), int(c[1]), int(c[2]));
            b->triangle_of_face.push_back(uint32_t(t));
        }
        // What btDeformableMultiBodyDynamicsWorld + setSelfCollision need.
        b->body->m_cfg.collisions = btSoftBody::fCollision::VF_DD;
        b->body->setSelfCollision(true);
        b->body->m_sst.sdt = 0; // no velocities: boxes of the current positions only
        size_t before = heap_in_use();
        double t0 = now_seconds();
        b->body->initializeFaceTree();
        double t1 = now_seconds();
        size_t after = heap_in_use();
        if (build_seconds)
            *build_seconds = t1 - t0;
        if (tree_bytes)
            *tree_bytes = after > before ? after - before : 0;
    } catch (...) {
        bench_bullet_destroy(b);
        return nullptr;
    }
    return b;
}

extern "C" void bench_bullet_set_distance(bench_bullet *b, double d) {
    // proximityTest accepts |distance to plane| <= mrg with mrg = 2 x margin.
    btScalar margin = btScalar(0.5 * d);
    b->body->getCollisionShape()->setMargin(margin);
    b->body->m_sst.radmrg = margin; // the solver copies the margin here each step
}

extern "C" double bench_bullet_refit(bench_bullet *b) {
    double t0 = now_seconds();
    b->body->updateNormals();
    b->body->updateFaceTree(true, true);
    return now_seconds() - t0;
}

extern "C" double bench_bullet_self_collide(bench_bullet *b) {
    btSoftBody *psb = b->body;
    double t0 = now_seconds();
    psb->m_faceNodeContacts.resize(0); // the solver clears them every step
    psb->m_softSoftCollision = true;
    psb->defaultCollisionHandler(psb);
    psb->m_softSoftCollision = false;
    return now_seconds() - t0;
}

extern "C" size_t bench_bullet_contacts(bench_bullet *b, size_t *raw_count, uint64_t **pairs) {
    btSoftBody *psb = b->body;
    int n = psb->m_faceNodeContacts.size();
    if (raw_count)
        *raw_count = size_t(n);
    uint64_t *out = static_cast<uint64_t *>(std::malloc(sizeof(uint64_t) * size_t(n > 0 ? n : 1)));
    if (out == nullptr)
        return size_t(-1);
    const btSoftBody::Node *node0 = &psb->m_nodes[0];
    const btSoftBody::Face *face0 = &psb->m_faces[0];
    for (int i = 0; i < n; ++i) {
        const btSoftBody::DeformableFaceNodeContact &c = psb->m_faceNodeContacts[i];
        uint64_t node = uint64_t(c.m_node - node0);
        uint64_t tri = b->triangle_of_face[size_t(c.m_face - face0)];
        out[i] = node << 32 | tri;
    }
    std::sort(out, out + n);
    size_t unique = size_t(std::unique(out, out + n) - out);
    *pairs = out;
    return unique;
}

extern "C" void bench_bullet_destroy(bench_bullet *b) {
    if (b == nullptr)
        return;
    delete b->body;
    delete b;
}

extern "C" const char *bench_bullet_version(void) {
    static char text[16];
    std::snprintf(text, sizeof text, "%d.%02d", BT_BULLET_VERSION / 100, BT_BULLET_VERSION % 100);
    return text;
}
