// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The adapter's API on bad input, what attaching changes and restores, and
// the response rules on hand-made rows (no timing, plain asserts).
#include <selfcol/bullet.h>

#include "../src/response.hpp"
#include "../src/untangle.hpp"
#include "demo_common.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

static int failures = 0;
#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);          \
            ++failures;                                                                            \
        }                                                                                          \
    } while (0)

using namespace selfcol_bullet_detail;

static void api_rejects_bad_input() {
    demo::options o;
    demo::world w(o, 0.0);
    selfcol_bullet_options opts;
    CHECK(selfcol_bullet_options_init(nullptr, SELFCOL_BULLET_OPTIONS_VERSION) == SELFCOL_EINVAL);
    CHECK(selfcol_bullet_options_init(&opts, 0) == SELFCOL_EVERSION);
    CHECK(selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION + 1) ==
          SELFCOL_EVERSION);
    CHECK(selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION) == SELFCOL_OK);
    selfcol_bullet *a = reinterpret_cast<selfcol_bullet *>(&opts);
    CHECK(selfcol_bullet_create(&a, nullptr, &opts) == SELFCOL_EINVAL && a == nullptr);
    CHECK(selfcol_bullet_create(nullptr, w.dynamics, &opts) == SELFCOL_EINVAL);
    selfcol_bullet_options bad = opts;
    bad.distance = NAN;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &bad) == SELFCOL_EINVAL);
    bad = opts;
    bad.distance = -1;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &bad) == SELFCOL_EINVAL);
    bad = opts;
    bad.repulsion = 1.5;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &bad) == SELFCOL_EINVAL);
    bad = opts;
    bad.iterations = 0;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &bad) == SELFCOL_EINVAL);
    bad = opts;
    bad.version = 7;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &bad) == SELFCOL_EVERSION);

    btSoftBody *sheet =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 6, 6, 0.1, false);
    sheet->m_cfg.collisions |= btSoftBody::fCollision::VF_DD;
    sheet->setSelfCollision(true);
    int before = sheet->m_cfg.collisions;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts) == SELFCOL_OK && a != nullptr);
    CHECK(selfcol_bullet_attach(a, nullptr, nullptr) == SELFCOL_EINVAL);
    uint32_t id = 99;
    CHECK(selfcol_bullet_attach(a, sheet, &id) == SELFCOL_OK && id == 0);
    CHECK(selfcol_bullet_attach(a, sheet, &id) == SELFCOL_EINVAL); // twice
    // Bullet's own self-collision and VF_DD are off while attached...
    CHECK(!sheet->useSelfCollision());
    CHECK((sheet->m_cfg.collisions & btSoftBody::fCollision::VF_DD) == 0);
    CHECK(selfcol_bullet_step(a, 0) == SELFCOL_EINVAL);
    CHECK(selfcol_bullet_step(a, NAN) == SELFCOL_EINVAL);
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    selfcol_bullet_step_stats st;
    st.version = 0;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_EVERSION);
    st.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.status == SELFCOL_OK);
    // the default thickness: 0.25 x the mean edge length
    CHECK(std::fabs(st.distance - 0.25 * selfcol_mesh_mean_edge_length(selfcol_bullet_mesh(a, 0))) <
          1e-12);
    CHECK(selfcol_bullet_scene(a) != nullptr);
    CHECK(selfcol_bullet_mesh(a, 1) == nullptr);
    // a NaN node: an error, no node changed
    btVector3 saved = sheet->m_nodes[3].m_x;
    sheet->m_nodes[3].m_x.setX(btScalar(NAN));
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_EINVAL);
    sheet->m_nodes[3].m_x = saved;
    // a changed topology: ESTALE, recorded in the stats by the world's action too
    sheet->appendNode(btVector3(5, 5, 5), 1);
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_ESTALE);
    w.step(1.0 / 240);
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.status == SELFCOL_ESTALE);
    // ...and restored by destroy
    selfcol_bullet_destroy(a);
    CHECK(sheet->useSelfCollision());
    CHECK(sheet->m_cfg.collisions == before);
    selfcol_bullet_destroy(nullptr);
}

// Versioned structs: a version 1 caller's options and stats end before the
// version 2 fields, which the library must neither write nor read.
static void versioned_structs() {
    selfcol_bullet_options opts;
    opts.untangle = 12345;
    CHECK(selfcol_bullet_options_init(&opts, 1) == SELFCOL_OK);
    CHECK(opts.untangle == 12345); // not written for a version 1 caller
    CHECK(selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION) == SELFCOL_OK);
    CHECK(opts.untangle == 1);
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *sheet =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 6, 6, 0.1, false);
    selfcol_bullet_options v1;
    selfcol_bullet_options_init(&v1, 1);
    v1.automatic = 0;
    v1.untangle = 7; // beyond a version 1 struct: must not be read (7 is invalid)
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &v1) == SELFCOL_OK);
    selfcol_bullet_options bad;
    selfcol_bullet_options_init(&bad, SELFCOL_BULLET_OPTIONS_VERSION);
    bad.untangle = 7;
    selfcol_bullet *b = nullptr;
    CHECK(selfcol_bullet_create(&b, w.dynamics, &bad) == SELFCOL_EINVAL && b == nullptr);
    CHECK(selfcol_bullet_attach(a, sheet, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    selfcol_bullet_step_stats st;
    st.version = 1;
    st.untangled = 12345;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.version == 1 && st.steps == 1);
    CHECK(st.untangled == 12345); // not written for a version 1 caller
    st.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.untangled == 0);
    selfcol_bullet_destroy(a);
}

// The untangling on hand-made points (untangle.hpp). A pyramid pokes
// through a flat triangle: apex 0 at z = +0.1 above, base corners 1..3 at
// z = -0.1 below, faces (0 1 2), (0 2 3), (0 3 1); the flat triangle is
// nodes 4..6 in z = 0. The three slanted edges pierce it: three contour
// points, joined into a closed loop by the three face pairs. One push must
// move the apex down and the flat triangle up (the loop shrinks), no node
// further than the step (the apex is in all three points); pinned nodes
// stay; an isolated point (no segment) moves nothing.
static double loop_length(const response_node n[7]) {
    contour_point p[3];
    for (int e = 0; e < 3; ++e)
        CHECK(contour_point_make(n[0].x, n[1 + e].x, n[4].x, n[5].x, n[6].x, p[e]));
    double length = 0;
    for (int e = 0; e < 3; ++e) {
        double d2 = 0;
        for (int c = 0; c < 3; ++c)
            d2 += (p[e].p[c] - p[(e + 1) % 3].p[c]) * (p[e].p[c] - p[(e + 1) % 3].p[c]);
        length += std::sqrt(d2);
    }
    return length;
}

static void untangle_rules() {
    const double start[7][3] = {
        {0, 0, 0.1}, {0.3, 0, -0.1}, {-0.15, 0.26, -0.1}, {-0.15, -0.26, -0.1},
        {-2, -2, 0}, {3, -2, 0},     {-2, 3, 0}};
    for (int pinned = 0; pinned < 2; ++pinned) {
        response_node n[7];
        for (int i = 0; i < 7; ++i) {
            for (int c = 0; c < 3; ++c) {
                n[i].x[c] = start[i][c];
                n[i].v[c] = 0;
            }
            n[i].im = pinned ? 0.0 : 1.0;
        }
        contour_point pts[3];
        contour_key keys[6];
        size_t key_count = 0;
        for (uint32_t e = 0; e < 3; ++e) {
            CHECK(contour_point_make(n[0].x, n[1 + e].x, n[4].x, n[5].x, n[6].x, pts[e]));
            const uint32_t nodes[5] = {0, 1 + e, 4, 5, 6};
            for (int k = 0; k < 5; ++k)
                pts[e].node[k] = nodes[k];
            // weights: p = (1 - t) x0 + t x1 = sum of -w_tri b
            CHECK(std::fabs(pts[e].w[0] + pts[e].w[1] - 1) < 1e-12);
            CHECK(std::fabs(pts[e].w[2] + pts[e].w[3] + pts[e].w[4] + 1) < 1e-12);
            CHECK(std::fabs(pts[e].p[2]) < 1e-12);
            // edge (0, 1 + e) belongs to faces e and e - 1 (mod 3); the flat triangle is id 9
            const uint64_t faces[2] = {e, (e + 2) % 3};
            for (uint64_t f : faces)
                keys[key_count++] = {f, 9, e};
        }
        CHECK(contour_link(pts, keys, key_count) == 3);
        const double before = loop_length(n);
        double delta[3 * 7];
        CHECK(contour_push(pts, 3, n, 7, delta, 0.01) == (pinned ? 0u : 3u));
        if (pinned) {
            for (int i = 0; i < 7; ++i)
                for (int c = 0; c < 3; ++c)
                    CHECK(n[i].x[c] == start[i][c]);
            continue;
        }
        for (int i = 0; i < 7; ++i) { // each node moves at most the step
            double d2 = 0;
            for (int c = 0; c < 3; ++c)
                d2 += (n[i].x[c] - start[i][c]) * (n[i].x[c] - start[i][c]);
            CHECK(std::sqrt(d2) <= 0.01 * (1 + 1e-12));
        }
        CHECK(n[0].x[2] < start[0][2]); // the apex goes down
        for (int i = 4; i < 7; ++i)
            CHECK(n[i].x[2] > start[i][2]); // the flat triangle up
        CHECK(loop_length(n) < before);
    }
    // a point that is no segment's end has no gradient: nothing moves
    response_node m[5];
    const double q[5][3] = {{0, 0, 1}, {0, 0, -1}, {-1, -1, 0}, {2, -1, 0}, {-1, 2, 0}};
    for (int i = 0; i < 5; ++i) {
        for (int c = 0; c < 3; ++c)
            m[i].x[c] = q[i][c];
        m[i].im = 1;
    }
    contour_point alone;
    CHECK(contour_point_make(m[0].x, m[1].x, m[2].x, m[3].x, m[4].x, alone));
    for (uint32_t k = 0; k < 5; ++k)
        alone.node[k] = k;
    double delta[3 * 5];
    CHECK(contour_push(&alone, 1, m, 5, delta, 0.01) == 0);
    for (int i = 0; i < 5; ++i)
        for (int c = 0; c < 3; ++c)
            CHECK(m[i].x[c] == q[i][c]);
    // an edge that does not reach the plane is no point
    const double far0[3] = {0, 0, 1}, far1[3] = {0, 0, 0.5};
    CHECK(!contour_point_make(far0, far1, m[2].x, m[3].x, m[4].x, alone));
}

// An allocator that fails at its Nth allocation (0: never) and counts what
// is live, so every ENOMEM path of the adapter (its own vectors, its meshes,
// its scene and stores) is driven and checked for leaks.
struct failing_allocator {
    long fail_at = 0, calls = 0, live = 0, failed = 0;
};
static void *failing_alloc(void *user, size_t size, size_t alignment) {
    failing_allocator *f = static_cast<failing_allocator *>(user);
    if (f->fail_at != 0 && ++f->calls == f->fail_at) {
        ++f->failed;
        return nullptr;
    }
    void *p = nullptr;
    if (posix_memalign(&p, alignment < sizeof(void *) ? sizeof(void *) : alignment, size) != 0)
        return nullptr;
    ++f->live;
    return p;
}
static void failing_free(void *user, void *p, size_t) {
    --static_cast<failing_allocator *>(user)->live;
    std::free(p);
}

// Two sheets 1 cm apart, one falling onto the other (self and soft-soft
// contacts from the first steps), stepped by hand 6 times with the Nth
// allocation failing, for every N until a run no longer reaches N. Every
// call returns OK or ENOMEM; after an ENOMEM the next steps (the allocator
// working again) succeed with finite nodes; destroy frees everything.
static void allocation_failure_at_every_call() {
    long n = 1;
    for (;; ++n) {
        demo::options o;
        demo::world w(o, 0.0);
        btSoftBody *low = w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 8,
                                      8, 0.2, false);
        btSoftBody *high = w.add_sheet(btVector3(0.05f, 0.01f, 0.05f), btVector3(0.9f, 0, 0),
                                       btVector3(0, 0, 0.9f), 8, 8, 0.2, false);
        for (int i = 0; i < high->m_nodes.size(); ++i)
            high->m_nodes[i].m_v = btVector3(0, -1, 0);
        failing_allocator f;
        f.fail_at = n;
        selfcol_bullet_options opts;
        selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION);
        opts.allocator.alloc = failing_alloc;
        opts.allocator.free = failing_free;
        opts.allocator.user = &f;
        opts.automatic = 0;
        selfcol_bullet *a = nullptr;
        int status = selfcol_bullet_create(&a, w.dynamics, &opts);
        CHECK(status == SELFCOL_OK || status == SELFCOL_ENOMEM);
        if (status == SELFCOL_OK) {
            int failed_steps = 0;
            status = selfcol_bullet_attach(a, low, nullptr);
            CHECK(status == SELFCOL_OK || status == SELFCOL_ENOMEM);
            if (status == SELFCOL_OK) {
                status = selfcol_bullet_attach(a, high, nullptr);
                CHECK(status == SELFCOL_OK || status == SELFCOL_ENOMEM);
            }
            for (int step = 0; step < 6; ++step) {
                w.step(1.0 / 240);
                int st = selfcol_bullet_step(a, 1.0 / 240);
                CHECK(st == SELFCOL_OK || st == SELFCOL_ENOMEM);
                failed_steps += st == SELFCOL_ENOMEM;
                CHECK(failed_steps <= 1); // one failing allocation, one failing step
            }
            for (btSoftBody *b : {low, high})
                for (int i = 0; i < b->m_nodes.size(); ++i)
                    CHECK(std::isfinite(b->m_nodes[i].m_x.x()) &&
                          std::isfinite(b->m_nodes[i].m_x.y()) &&
                          std::isfinite(b->m_nodes[i].m_x.z()));
            selfcol_bullet_destroy(a);
        } else {
            CHECK(a == nullptr);
        }
        CHECK(f.live == 0);
        if (f.failed == 0)
            break; // the run made fewer than n allocations: every one was failed once
        if (failures > 0)
            break; // the first failing n is enough to read
    }
    std::printf("allocation failure injected at each of %ld allocations\n", n - 1);
    CHECK(n > 20);
}

// A vertex (node 0) above a triangle (nodes 1..3) at s < d, approaching.
static response_row vf_row(double s) {
    response_row row = {};
    for (int k = 0; k < 4; ++k)
        row.node[k] = uint32_t(k);
    row.w[0] = 1;
    row.w[1] = row.w[2] = row.w[3] = -1.0 / 3;
    row.n[2] = 1;
    row.s = s;
    return row;
}

static void vf_nodes(response_node nodes[4], double gap, double vz) {
    double tri[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    for (int k = 0; k < 4; ++k) {
        nodes[k] = response_node();
        nodes[k].im = 1;
    }
    nodes[0].x[0] = nodes[0].x[1] = 0.25;
    nodes[0].x[2] = gap;
    nodes[0].v[2] = vz;
    for (int k = 0; k < 3; ++k) {
        nodes[k + 1].x[0] = tri[k][0];
        nodes[k + 1].x[1] = tri[k][1];
    }
}

static double separation(const response_node n[4]) {
    return n[0].x[2] - (n[1].x[2] + n[2].x[2] + n[3].x[2]) / 3;
}
static double approach(const response_node n[4]) {
    return n[0].v[2] - (n[1].v[2] + n[2].v[2] + n[3].v[2]) / 3;
}

static void response_rules() {
    const double d = 0.1;
    response_node nodes[4];
    // within d and approaching: stops approaching, separation closes half its gap to d
    vf_nodes(nodes, 0.02, -1.0);
    response_row row = vf_row(0.02);
    CHECK(response_prepare(row, nodes));
    response_result r = response_solve(&row, 1, nodes, d, 0.5, 4);
    CHECK(r.responses == 1);
    CHECK(std::fabs(approach(nodes)) < 1e-12);
    CHECK(std::fabs(separation(nodes) - (0.02 + 0.5 * (d - 0.02))) < 1e-12);
    // momentum along n is conserved (equal masses)
    double p = nodes[0].v[2] + nodes[1].v[2] + nodes[2].v[2] + nodes[3].v[2];
    CHECK(std::fabs(p - (-1.0)) < 1e-12);
    // separating already and at d: nothing
    vf_nodes(nodes, d, 1.0);
    row = vf_row(d);
    CHECK(response_prepare(row, nodes));
    r = response_solve(&row, 1, nodes, d, 0.5, 4);
    CHECK(r.responses == 0 && separation(nodes) == d && approach(nodes) == 1.0);
    // crossed (s < 0 along the consistent side): pushed back toward its right
    // side, at most d in one step
    vf_nodes(nodes, -0.3, 0);
    row = vf_row(-0.3);
    CHECK(response_prepare(row, nodes));
    r = response_solve(&row, 1, nodes, d, 1.0, 4);
    CHECK(std::fabs(separation(nodes) - (-0.3 + d)) < 1e-12);
    CHECK(r.max_push <= d + 1e-12);
    // pinned triangle: only the vertex moves
    vf_nodes(nodes, 0.02, 0);
    for (int k = 1; k < 4; ++k)
        nodes[k].im = 0;
    row = vf_row(0.02);
    CHECK(response_prepare(row, nodes));
    response_solve(&row, 1, nodes, d, 0.5, 4);
    CHECK(nodes[1].x[2] == 0 && nodes[2].x[2] == 0 && nodes[3].x[2] == 0);
    CHECK(std::fabs(nodes[0].x[2] - 0.06) < 1e-12);
    // every node pinned: the row is skipped
    nodes[0].im = 0;
    row = vf_row(0.02);
    CHECK(!response_prepare(row, nodes));
}

int main() {
    api_rejects_bad_input();
    response_rules();
    versioned_structs();
    untangle_rules();
    allocation_failure_at_every_call();
    if (failures == 0)
        std::printf("test_bullet_adapter: all checks passed\n");
    return failures == 0 ? 0 : 1;
}
