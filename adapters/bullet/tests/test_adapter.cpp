// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The adapter's API on bad input, what attaching changes and restores, and
// the response rules on hand-made rows (no timing, plain asserts).
#include <selfcol/bullet.h>

#include "../src/impact_zones.hpp"
#include "../src/response.hpp"
#include "../src/untangle.hpp"
#include "demo_common.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <LinearMath/btThreads.h>

#include "check.hpp"

using namespace selfcol_bullet_detail;

// Adapter options with query and store options of their own to point to
// (default-initialised), for the cases that spoil one field. Copying one
// re-points the copy at its own query and store.
struct full_options {
    selfcol_bullet_options o;
    selfcol_query_options q;
    selfcol_store_options s;
    full_options() {
        selfcol_bullet_options_init(&o, SELFCOL_BULLET_OPTIONS_VERSION);
        selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
        selfcol_store_options_init(&s, SELFCOL_STORE_OPTIONS_VERSION);
        o.query = &q;
        o.store = &s;
    }
    full_options(const full_options &other) : o(other.o), q(other.q), s(other.s) {
        o.query = &q;
        o.store = &s;
    }
    full_options &operator=(const full_options &other) {
        o = other.o;
        q = other.q;
        s = other.s;
        o.query = &q;
        o.store = &s;
        return *this;
    }
};

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
    const full_options full;
    full_options bad = full;
    bad.q.distance = NAN;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &bad.o) == SELFCOL_EINVAL);
    bad = full;
    bad.q.distance = -1;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &bad.o) == SELFCOL_EINVAL);
    bad = full;
    bad.o.repulsion = 1.5;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &bad.o) == SELFCOL_EINVAL);
    bad = full;
    bad.o.iterations = 0;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &bad.o) == SELFCOL_EINVAL);
    bad = full;
    bad.o.version = 7;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &bad.o) == SELFCOL_EVERSION);
    // selfcol_bullet_options_check names what create refuses, with create's
    // status: the adapter's own fields and the nested ones alike.
    struct named_case {
        void (*spoil)(full_options &);
        int status;
        const char *field, *message;
    };
    const named_case named[] = {
        {[](full_options &b) { b.q.distance = NAN; }, SELFCOL_EINVAL, "query->distance",
         "selfcol_bullet_options.query->distance = nan"},
        {[](full_options &b) { b.o.repulsion = 1.5; }, SELFCOL_EINVAL, "repulsion",
         "selfcol_bullet_options.repulsion = 1.5 is not in (0, 1]"},
        {[](full_options &b) { b.o.continuous = 3; }, SELFCOL_EINVAL, "continuous",
         "= 3 is not 0 or 1"},
        {[](full_options &b) { b.o.threads = 0; }, SELFCOL_EINVAL, "threads",
         "selfcol_bullet_options.threads = 0 is not in 1 .. 64"},
        {[](full_options &b) { b.q.version = 2; }, SELFCOL_EVERSION, "query->version",
         "selfcol_bullet_options.query->version = 2 is an older layout"},
        {[](full_options &b) { b.s.consistency = 4; }, SELFCOL_EINVAL, "store->consistency",
         "selfcol_bullet_options.store->consistency = 4"},
        {[](full_options &b) { b.s.first_orientation = 1; }, SELFCOL_EINVAL,
         "store->first_orientation", "leave it 0"},
        {[](full_options &b) { b.o.version = 7; }, SELFCOL_EVERSION, "version", "= 7"},
        {[](full_options &) {}, SELFCOL_OK, "", ""},
    };
    for (const named_case &c : named) {
        bad = full;
        c.spoil(bad);
        selfcol_options_problem p;
        std::memset(&p, 0x5a, sizeof p);
        p.version = SELFCOL_OPTIONS_PROBLEM_VERSION;
        const int checked = selfcol_bullet_options_check(&bad.o, &p);
        CHECK(checked == c.status && p.status == c.status);
        CHECK(std::strcmp(p.field, c.field) == 0);
        CHECK(std::strstr(p.message, c.message) != nullptr);
        if (c.status != SELFCOL_OK) // create agrees (and makes nothing)
            CHECK(selfcol_bullet_create(&a, w.dynamics, &bad.o) == checked && a == nullptr);
    }
    CHECK(selfcol_bullet_options_check(&opts, nullptr) == SELFCOL_EINVAL);

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
    // Bullet's own self-collision is off while attached, VF_DD kept (for
    // unattached bodies) and the mark on...
    CHECK(!sheet->useSelfCollision());
    CHECK(sheet->m_cfg.collisions == (before | btSoftBody::fCollision::CL_SELF));
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

// Item A: the options point to the core's query and store options (version
// 4, 0.4); 0.2's layouts (versions 1 and 2) and 0.3's (3: those options
// embedded) are refused. The adapter copies what they point to, each read as
// its own version says. The stats struct keeps its versions: a version 1
// caller's stats end before `untangled`.
static void options_by_pointer_and_versions() {
    selfcol_bullet_options opts;
    CHECK(selfcol_bullet_options_init(&opts, 1) == SELFCOL_EVERSION);
    CHECK(selfcol_bullet_options_init(&opts, 2) == SELFCOL_EVERSION);
    CHECK(selfcol_bullet_options_init(&opts, 3) == SELFCOL_EVERSION);
    CHECK(selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION) == SELFCOL_OK);
    CHECK(opts.query == nullptr && opts.store == nullptr); // the core's defaults
    CHECK(opts.distance_factor == SELFCOL_BULLET_DEFAULT_DISTANCE_FACTOR && opts.untangle == 1 &&
          opts.automatic == 1 && opts.coherent == 1 && opts.continuous == 0);
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *sheet =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 6, 6, 0.1, false);
    selfcol_bullet *a = nullptr;
    selfcol_bullet_options old = opts;
    for (unsigned version = 1; version <= 3; ++version) {
        old.version = version;
        CHECK(selfcol_bullet_create(&a, w.dynamics, &old) == SELFCOL_EVERSION && a == nullptr);
    }
    // the options pointed to reach the scene (the explicit distance); they are copied, so spoiling
    // them after creation changes nothing.
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.distance = 0.03;
    selfcol_store_options so;
    selfcol_store_options_init(&so, SELFCOL_STORE_OPTIONS_VERSION);
    so.remnance_frames = 0;
    opts.automatic = 0;
    opts.query = &q;
    opts.store = &so;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts) == SELFCOL_OK);
    std::memset(&q, 0xff, sizeof q);
    std::memset(&so, 0xff, sizeof so);
    CHECK(selfcol_bullet_attach(a, sheet, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    selfcol_bullet_step_stats st;
    st.version = 1;
    st.untangled = 12345;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.version == 1 && st.steps == 1);
    CHECK(st.untangled == 12345); // not written for a version 1 caller
    CHECK(st.distance == 0.03);
    st.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.untangled == 0);
    selfcol_bullet_destroy(a);
}

// Item D: what the core would refuse at the first step is refused at
// creation (0.2 accepted threads 0, 65 or 1000 and a distance of 1e300,
// then failed every step with EINVAL).
static void create_validates_nested_options() {
    demo::options o;
    demo::world w(o, 0.0);
    full_options opts;
    opts.o.automatic = 0;
    struct bad_case {
        const char *what;
        void (*spoil)(full_options &);
        int expect;
    };
    const bad_case cases[] = {
        {"threads 0", [](full_options &b) { b.o.threads = 0; }, SELFCOL_EINVAL},
        {"threads 65", [](full_options &b) { b.o.threads = SELFCOL_MAX_THREADS + 1; },
         SELFCOL_EINVAL},
        {"threads 1000", [](full_options &b) { b.o.threads = 1000; }, SELFCOL_EINVAL},
        {"distance 1e300", [](full_options &b) { b.q.distance = 1e300; }, SELFCOL_EINVAL},
        {"distance inf", [](full_options &b) { b.q.distance = INFINITY; }, SELFCOL_EINVAL},
        {"factor 0", [](full_options &b) { b.o.distance_factor = 0; }, SELFCOL_EINVAL},
        {"no kinds", [](full_options &b) { b.q.kinds = 0; }, SELFCOL_EINVAL},
        {"unknown kind", [](full_options &b) { b.q.kinds |= 1u << 20; }, SELFCOL_EINVAL},
        {"method", [](full_options &b) { b.q.method = 99; }, SELFCOL_EINVAL},
        {"narrow", [](full_options &b) { b.q.narrow = 99; }, SELFCOL_EINVAL},
        {"query version", [](full_options &b) { b.q.version = 0; }, SELFCOL_EVERSION},
        {"consistency 2", [](full_options &b) { b.s.consistency = 2; }, SELFCOL_EINVAL},
        {"orientation", [](full_options &b) { b.s.first_orientation = 1; }, SELFCOL_EINVAL},
        {"store allocator",
         [](full_options &b) {
             b.s.allocator.alloc = [](void *, size_t, size_t) -> void * { return nullptr; };
             b.s.allocator.free = [](void *, void *, size_t) {};
         },
         SELFCOL_EINVAL},
        {"store version", [](full_options &b) { b.s.version = 99; }, SELFCOL_EVERSION},
        {"automatic 2", [](full_options &b) { b.o.automatic = 2; }, SELFCOL_EINVAL},
        {"untangle 7", [](full_options &b) { b.o.untangle = 7; }, SELFCOL_EINVAL},
    };
    for (const bad_case &c : cases) {
        full_options bad = opts;
        c.spoil(bad);
        selfcol_bullet *a = reinterpret_cast<selfcol_bullet *>(&bad);
        int status = selfcol_bullet_create(&a, w.dynamics, &bad.o);
        if (status != c.expect || a != nullptr)
            std::fprintf(stderr, "create with %s: %s\n", c.what, selfcol_status_string(status));
        CHECK(status == c.expect && a == nullptr);
        selfcol_bullet_destroy(status == SELFCOL_OK ? a : nullptr);
    }
    // the bounds themselves are accepted, and the first step then works
    btSoftBody *sheet =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 6, 6, 0.1, false);
    full_options edge = opts;
    edge.o.threads = SELFCOL_MAX_THREADS;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &edge.o) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, sheet, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    selfcol_bullet_destroy(a);
}

// Item B: a body removed from the world (and deleted) while attached is
// dropped at the next step, with the stores of its pairs, without being
// read (0.2: heap-use-after-free in the step); the other body keeps its
// surface. The ASan job runs this under the sanitizer.
static void removed_body_is_dropped() {
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *keep =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 6, 6, 0.1, false);
    btSoftBody *gone = w.add_sheet(btVector3(0, 0.01f, 0), btVector3(1, 0, 0), btVector3(0, 0, 1),
                                   6, 6, 0.1, false);
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, nullptr) == SELFCOL_OK);
    uint32_t keep_id = 99, gone_id = 99;
    CHECK(selfcol_bullet_attach(a, keep, &keep_id) == SELFCOL_OK && keep_id == 0);
    CHECK(selfcol_bullet_attach(a, gone, &gone_id) == SELFCOL_OK && gone_id == 1);
    for (int i = 0; i < 3; ++i)
        w.step(1.0 / 240);
    selfcol_scene_update_stats ss;
    ss.version = SELFCOL_SCENE_UPDATE_STATS_VERSION;
    CHECK(selfcol_scene_stats(selfcol_bullet_scene(a), &ss) == SELFCOL_OK && ss.surfaces == 2);
    CHECK(ss.contacts > 0); // the pair held contacts
    w.dynamics->removeSoftBody(gone);
    w.cloths.pop_back();
    delete gone;
    w.step(1.0 / 240);
    selfcol_bullet_step_stats st;
    st.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.status == SELFCOL_OK && st.steps == 4);
    CHECK(selfcol_bullet_mesh(a, gone_id) == nullptr);
    CHECK(selfcol_bullet_mesh(a, keep_id) != nullptr);
    CHECK(selfcol_scene_stats(selfcol_bullet_scene(a), &ss) == SELFCOL_OK && ss.surfaces == 1);
    const selfcol_store *self = nullptr;
    CHECK(selfcol_scene_store(selfcol_bullet_scene(a), keep_id, keep_id, &self) == SELFCOL_OK &&
          self != nullptr);
    // dropped: not attached any more (the pointer is compared, never read)
    CHECK(selfcol_bullet_detach(a, gone) == SELFCOL_EINVAL);
    for (int i = 0; i < 2; ++i)
        w.step(1.0 / 240);
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.status == SELFCOL_OK);
    selfcol_bullet_destroy(a);
    CHECK((keep->m_cfg.collisions & btSoftBody::fCollision::CL_SELF) == 0); // restored
}

// Item B/C: detach restores the body's settings and removes its surface;
// the other pairs keep their stores (the same store, the same contacts);
// a re-attached body gets a new id.
static void detach_restores_and_keeps_other_stores() {
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *low =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 6, 6, 0.1, false);
    btSoftBody *high = w.add_sheet(btVector3(0, 0.01f, 0), btVector3(1, 0, 0), btVector3(0, 0, 1),
                                   6, 6, 0.1, false);
    btSoftBody *far =
        w.add_sheet(btVector3(5, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 6, 6, 0.1, false);
    far->m_cfg.collisions |= btSoftBody::fCollision::VF_DD;
    far->setSelfCollision(true);
    const int far_before = far->m_cfg.collisions;
    selfcol_bullet_options opts;
    selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION);
    opts.automatic = 0;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts) == SELFCOL_OK);
    uint32_t far_id = 0;
    CHECK(selfcol_bullet_attach(a, low, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, high, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, far, &far_id) == SELFCOL_OK && far_id == 2);
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    const selfcol_store *pair = nullptr;
    CHECK(selfcol_scene_store(selfcol_bullet_scene(a), 0, 1, &pair) == SELFCOL_OK && pair);
    const size_t before = selfcol_store_contact_count(pair);
    CHECK(before > 0);
    CHECK(selfcol_bullet_detach(a, far) == SELFCOL_OK);
    CHECK(far->useSelfCollision() && far->m_cfg.collisions == far_before);
    CHECK(selfcol_bullet_mesh(a, far_id) == nullptr);
    const selfcol_store *same = nullptr;
    CHECK(selfcol_scene_store(selfcol_bullet_scene(a), 0, 1, &same) == SELFCOL_OK && same == pair);
    CHECK(selfcol_store_contact_count(pair) == before);
    CHECK(selfcol_bullet_detach(a, far) == SELFCOL_EINVAL);
    CHECK(selfcol_bullet_detach(a, nullptr) == SELFCOL_EINVAL);
    CHECK(selfcol_bullet_detach(nullptr, far) == SELFCOL_EINVAL);
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, far, &far_id) == SELFCOL_OK && far_id == 3); // never reused
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    CHECK(selfcol_bullet_mesh(a, 3) != nullptr);
    // a detach before the first step: ids stay those attach gave
    selfcol_bullet_destroy(a);
    selfcol_bullet *b = nullptr;
    CHECK(selfcol_bullet_create(&b, w.dynamics, &opts) == SELFCOL_OK);
    uint32_t id = 0;
    CHECK(selfcol_bullet_attach(b, low, &id) == SELFCOL_OK && id == 0);
    CHECK(selfcol_bullet_attach(b, high, &id) == SELFCOL_OK && id == 1);
    CHECK(selfcol_bullet_detach(b, low) == SELFCOL_OK);
    CHECK(selfcol_bullet_step(b, 1.0 / 240) == SELFCOL_OK);
    CHECK(selfcol_bullet_mesh(b, 0) == nullptr && selfcol_bullet_mesh(b, 1) != nullptr);
    const selfcol_store *self = nullptr;
    CHECK(selfcol_scene_store(selfcol_bullet_scene(b), 1, 1, &self) == SELFCOL_OK && self);
    selfcol_bullet_destroy(b);
}

// Item C: two sheets 4 mm apart (d = 1 cm), the upper pushed through the
// lower between two steps. The stores remember the crossing (contacts
// flip, their right side stays the old one) -- and must do so the same when
// an unrelated body is attached or detached between the steps (0.2 rebuilt
// the scene at every attach: 0 flips, 0 contacts on their wrong side).
struct crossing_memory {
    uint64_t flipped = 0;
    size_t wrong_side = 0;
    size_t contacts = 0;
};

static crossing_memory push_through(int change) { // 0 none, 1 attach between, 2 detach between
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *lower = w.add_sheet(btVector3(0, 0, 0), btVector3(0.3f, 0, 0),
                                    btVector3(0, 0, 0.3f), 16, 16, 0.1, false);
    btSoftBody *upper = w.add_sheet(btVector3(0.005f, 0.004f, 0.005f), btVector3(0.3f, 0, 0),
                                    btVector3(0, 0, 0.3f), 16, 16, 0.1, false);
    btSoftBody *other = w.add_sheet(btVector3(5, 0, 0), btVector3(0.3f, 0, 0),
                                    btVector3(0, 0, 0.3f), 8, 8, 0.1, false);
    full_options opts;
    opts.o.automatic = 0;
    opts.q.distance = 0.01;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts.o) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, lower, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, upper, nullptr) == SELFCOL_OK);
    if (change == 2)
        CHECK(selfcol_bullet_attach(a, other, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    for (int i = 0; i < upper->m_nodes.size(); ++i) {
        upper->m_nodes[i].m_x.setY(-0.004f);
        upper->m_nodes[i].m_q = upper->m_nodes[i].m_x;
        upper->m_nodes[i].m_v.setZero();
    }
    if (change == 1)
        CHECK(selfcol_bullet_attach(a, other, nullptr) == SELFCOL_OK);
    if (change == 2)
        CHECK(selfcol_bullet_detach(a, other) == SELFCOL_OK);
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    crossing_memory m;
    selfcol_bullet_step_stats st;
    st.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK);
    m.flipped = st.flipped;
    const selfcol_store *pair = nullptr;
    CHECK(selfcol_scene_store(selfcol_bullet_scene(a), 0, 1, &pair) == SELFCOL_OK && pair);
    // Copied right after the step: the meshes have the positions the
    // step's update saw (the next step sets them).
    m.contacts = selfcol_store_contact_count(pair);
    std::vector<selfcol_store_contact> c(m.contacts);
    if (m.contacts > 0 && selfcol_store_copy_contacts(pair, 0, m.contacts, c.data()) == SELFCOL_OK)
        for (size_t k = 0; k < m.contacts; ++k)
            m.wrong_side += c[k].side != 0 && c[k].right_side != 0 && c[k].side != c[k].right_side;
    selfcol_bullet_destroy(a);
    return m;
}

static void crossing_remembered_across_attach_and_detach() {
    const crossing_memory plain = push_through(0);
    std::printf("push through: %llu flipped, %zu of %zu contacts on their wrong side\n",
                (unsigned long long)plain.flipped, plain.wrong_side, plain.contacts);
    CHECK(plain.flipped > 100 && plain.wrong_side > 100);
    for (int change = 1; change <= 2; ++change) {
        const crossing_memory m = push_through(change);
        if (m.flipped != plain.flipped || m.wrong_side != plain.wrong_side)
            std::printf("  with an %s between: %llu flipped, %zu wrong side\n",
                        change == 1 ? "attach" : "detach", (unsigned long long)m.flipped,
                        m.wrong_side);
        CHECK(m.flipped == plain.flipped && m.wrong_side == plain.wrong_side &&
              m.contacts == plain.contacts);
    }
}

// Item E: a cloth attached to the adapter falls on a soft sheet that is not
// (both with VF_DD, lying over a floor). Bullet keeps handling their
// contact (0.2 cleared VF_DD on the cloth, which fell through the sheet to
// the floor). Returns the lowest cloth node's height above the sheet's
// highest node after landing.
static double landing_gap(bool attach, double *bullet_contacts_out) {
    demo::options o;
    demo::world w(o);
    w.add_rigid(new btBoxShape(btVector3(2, 0.5f, 2)), btVector3(0, -0.5f, 0), 0);
    btSoftBody *base = w.add_sheet(btVector3(-0.3f, 0.01f, -0.3f), btVector3(0.6f, 0, 0),
                                   btVector3(0, 0, 0.6f), 12, 12, 0.2, true);
    btSoftBody *cloth = w.add_sheet(btVector3(-0.2f, 0.1f, -0.2f), btVector3(0.4f, 0, 0),
                                    btVector3(0, 0, 0.4f), 10, 10, 0.1, true);
    for (btSoftBody *b : {base, cloth})
        b->m_cfg.collisions |= btSoftBody::fCollision::VF_DD;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, nullptr) == SELFCOL_OK);
    if (attach)
        CHECK(selfcol_bullet_attach(a, cloth, nullptr) == SELFCOL_OK);
    w.adapter = a;
    size_t peak = 0;
    for (int i = 0; i < 120; ++i) {
        w.step(1.0 / 240);
        peak = std::max(peak, demo::bullet_contacts(w));
    }
    *bullet_contacts_out = double(peak);
    double cloth_low = 1e30, base_high = -1e30;
    for (int i = 0; i < cloth->m_nodes.size(); ++i)
        cloth_low = std::fmin(cloth_low, double(cloth->m_nodes[i].m_x.y()));
    for (int i = 0; i < base->m_nodes.size(); ++i)
        base_high = std::fmax(base_high, double(base->m_nodes[i].m_x.y()));
    selfcol_bullet_step_stats st;
    st.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.status == SELFCOL_OK);
    return cloth_low - base_high;
}

static void attached_cloth_lands_on_unattached_body() {
    double contacts_plain = 0, contacts_attached = 0;
    const double plain = landing_gap(false, &contacts_plain);
    const double attached = landing_gap(true, &contacts_attached);
    std::printf("cloth on an unattached sheet: gap %.4g m (Bullet alone %.4g m), Bullet "
                "vertex-face contacts %g (alone %g)\n",
                attached, plain, contacts_attached, contacts_plain);
    // the sheets' margins: 0.25 x edge each (demo_common), 0.0136 + 0.0111 m
    CHECK(plain > 0.01);
    CHECK(attached > 0.01);
}

// Item F: a body is attached to one adapter at a time. 0.2 let a second
// adapter attach it; destroyed in creation order, the second restored the
// first's settings and left Bullet's own self-collision off.
static void one_adapter_per_body() {
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *sheet =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 6, 6, 0.1, false);
    sheet->m_cfg.collisions |= btSoftBody::fCollision::VF_DD;
    sheet->setSelfCollision(true);
    const int before = sheet->m_cfg.collisions;
    selfcol_bullet_options opts;
    selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION);
    opts.automatic = 0;
    selfcol_bullet *first = nullptr, *second = nullptr;
    CHECK(selfcol_bullet_create(&first, w.dynamics, &opts) == SELFCOL_OK);
    CHECK(selfcol_bullet_create(&second, w.dynamics, &opts) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(first, sheet, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(second, sheet, nullptr) == SELFCOL_EINVAL);
    selfcol_bullet_destroy(first);
    selfcol_bullet_destroy(second);
    CHECK(sheet->useSelfCollision());
    CHECK(sheet->m_cfg.collisions == before);
    // once free again, another adapter may take it
    CHECK(selfcol_bullet_create(&second, w.dynamics, &opts) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(second, sheet, nullptr) == SELFCOL_OK);
    selfcol_bullet_destroy(second);
    CHECK(sheet->useSelfCollision() && sheet->m_cfg.collisions == before);
}

// Item G: only bodies of the adapter's world (0.2 attached a body of
// another world, or of none, and stepped it).
static void attach_refuses_foreign_bodies() {
    demo::options o;
    demo::world w(o, 0.0), elsewhere(o, 0.0);
    btSoftBody *foreign = elsewhere.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0),
                                              btVector3(0, 0, 1), 6, 6, 0.1, false);
    btSoftBody *loose = elsewhere.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0),
                                            btVector3(0, 0, 1), 6, 6, 0.1, false);
    elsewhere.dynamics->removeSoftBody(loose); // in no world
    const int flags = foreign->m_cfg.collisions;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, foreign, nullptr) == SELFCOL_EINVAL);
    CHECK(selfcol_bullet_attach(a, loose, nullptr) == SELFCOL_EINVAL);
    CHECK(foreign->m_cfg.collisions == flags); // untouched
    selfcol_bullet_destroy(a);
    elsewhere.dynamics->addSoftBody(loose); // for the world's teardown
}

// Item H: a non-finite node velocity fails the step before any node
// changes (0.2 took it and the response spread NaN to the nodes of the
// other body in contact), and fails attach.
static void nonfinite_velocity_refused() {
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *low = w.add_sheet(btVector3(0, 0, 0), btVector3(0.5f, 0, 0), btVector3(0, 0, 0.5f),
                                  8, 8, 0.1, false);
    btSoftBody *high = w.add_sheet(btVector3(0, 0.01f, 0), btVector3(0.5f, 0, 0),
                                   btVector3(0, 0, 0.5f), 8, 8, 0.1, false);
    btSoftBody *third = w.add_sheet(btVector3(3, 0, 0), btVector3(0.5f, 0, 0),
                                    btVector3(0, 0, 0.5f), 8, 8, 0.1, false);
    full_options opts;
    opts.o.automatic = 0;
    opts.q.distance = 0.05;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts.o) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, low, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, high, nullptr) == SELFCOL_OK);
    for (int i = 0; i < high->m_nodes.size(); ++i)
        high->m_nodes[i].m_v = btVector3(0, -0.5f, 0); // approaching: every contact responds
    high->m_nodes[27].m_v.setX(btScalar(NAN));
    std::vector<btVector3> x_before, v_before;
    for (btSoftBody *b : {low, high})
        for (int i = 0; i < b->m_nodes.size(); ++i) {
            x_before.push_back(b->m_nodes[i].m_x);
            v_before.push_back(b->m_nodes[i].m_v);
        }
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_EINVAL);
    size_t k = 0, changed = 0;
    for (btSoftBody *b : {low, high})
        for (int i = 0; i < b->m_nodes.size(); ++i, ++k) {
            const btVector3 &v = b->m_nodes[i].m_v;
            bool same_v = (b == high && i == 27) ? std::isnan(v.x()) && v.y() == v_before[k].y()
                                                 : v == v_before[k];
            changed += !(b->m_nodes[i].m_x == x_before[k]) || !same_v;
        }
    CHECK(changed == 0);
    for (int i = 0; i < low->m_nodes.size(); ++i)
        CHECK(std::isfinite(low->m_nodes[i].m_v.x()) && std::isfinite(low->m_nodes[i].m_v.y()));
    high->m_nodes[27].m_v.setX(0);
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    third->m_nodes[5].m_v.setZ(btScalar(INFINITY));
    CHECK(selfcol_bullet_attach(a, third, nullptr) == SELFCOL_EINVAL);
    CHECK((third->m_cfg.collisions & btSoftBody::fCollision::CL_SELF) == 0);
    third->m_nodes[5].m_v.setZ(0);
    selfcol_bullet_destroy(a);
}

// Item D (demos): the run loop stops at the first failed step, exiting
// non-zero (0.2 ran every step, each failing, and reported at the end).
static void demo_run_stops_at_failed_step() {
    demo::options o;
    o.quiet = true;
    demo::world w(o, 0.0);
    btSoftBody *sheet =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 6, 6, 0.1, false);
    CHECK(w.start(o) == 0);
    int calls = 0;
    int status = demo::run(w, o, 40, [&](int i) {
        ++calls;
        if (i == 3) // a changed topology: the adapter's step fails with ESTALE
            sheet->appendNode(btVector3(5, 5, 5), 1);
    });
    CHECK(status != 0);
    CHECK(calls == 4);
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

// The impact zones' rules (impact_zones.hpp), on plain arrays.
static double signed_volume(const double *p, const double *a, const double *b, const double *c) {
    const double u[3] = {a[0] - p[0], a[1] - p[1], a[2] - p[2]};
    const double v[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]};
    const double w[3] = {c[0] - p[0], c[1] - p[1], c[2] - p[2]};
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
}

static void impact_zone_rules() {
    // Nodes 0..3: a vertex 0.1 above a triangle, moving down through it (and
    // the triangle turning); node 4 alone; nodes 5 and 6 a zone with node 6
    // kinematic.
    const double start[21] = {0.2, 0.1, 0.2, 0, 0, 0, 1, 0, 0, 0, 0, 1, 5, 5, 5, 8, 0, 0, 9, 0, 0};
    double end[21] = {0.2, -0.3, 0.2, 0, 0.05, 0, 1, -0.05, 0,    0, 0.02,
                      1,   5.5,  5,   5, 8,    0, 0, 9.5,   0.25, 0};
    const double inverse_mass[7] = {1, 0.5, 2, 1, 1, 1, 0};
    double before[21];
    std::memcpy(before, end, sizeof end);
    uint32_t parent[7];
    zones_reset(parent, 7);
    for (uint32_t k = 1; k < 4; ++k)
        zones_unite(parent, 0, k);
    zones_unite(parent, 6, 5);
    CHECK(zone_root(parent, 3) == 0 && zone_root(parent, 5) == 5 && zone_root(parent, 4) == 4);
    zone_sums sums[7];
    CHECK(zones_move(parent, 7, start, end, inverse_mass, sums, false) == 5);
    // The lone node keeps its motion; the kinematic node its own.
    CHECK(end[12] == 5.5 && end[18] == 9.5 && end[19] == 0.25);
    // The free node of the kinematic zone moves as the kinematic node does.
    CHECK(std::fabs(end[15] - 8.5) < 1e-12 && std::fabs(end[16] - 0.25) < 1e-12 && end[17] == 0);
    // The free zone keeps its linear momentum (sum m u, m = 1 / inverse mass).
    for (int k = 0; k < 3; ++k) {
        double was = 0, now = 0;
        for (int i = 0; i < 4; ++i) {
            was += (before[3 * i + k] - start[3 * i + k]) / inverse_mass[i];
            now += (end[3 * i + k] - start[3 * i + k]) / inverse_mass[i];
        }
        CHECK(std::fabs(was - now) < 1e-12);
    }
    // ... and on its straight-line motion the vertex never meets the
    // triangle's plane: it stays on the side it started on.
    for (int t = 0; t <= 8; ++t) {
        double at[12];
        for (int i = 0; i < 12; ++i)
            at[i] = start[i] + (end[i] - start[i]) * t / 8.0;
        CHECK(signed_volume(at, at + 3, at + 6, at + 9) *
                  signed_volume(start, start + 3, start + 6, start + 9) >
              0);
    }
    // Given its own rigid motion (a turn about its centre), a zone keeps it.
    const double turn_start[9] = {1, 0, 0, -1, 0, 0, 0, 0, 2};
    double turn_end[9];
    const double w[3] = {0, 0.01, 0.02};
    for (int i = 0; i < 3; ++i) {
        const double *p = turn_start + 3 * i;
        const double r[3] = {p[0], p[1], p[2] - 2.0 / 3.0};
        const double cross[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2],
                                 w[0] * r[1] - w[1] * r[0]};
        for (int k = 0; k < 3; ++k)
            turn_end[3 * i + k] = p[k] + 0.1 + cross[k];
    }
    double kept[9];
    std::memcpy(kept, turn_end, sizeof kept);
    const double unit[3] = {1, 1, 1};
    uint32_t three[3];
    zones_reset(three, 3);
    zones_unite(three, 0, 1);
    zones_unite(three, 2, 1);
    CHECK(zones_move(three, 3, turn_start, turn_end, unit, sums, false) == 3);
    for (int i = 0; i < 9; ++i)
        CHECK(std::fabs(turn_end[i] - kept[i]) < 1e-6);
    // Nodes on one line (no inertia about it): finite, and they keep their
    // mean displacement.
    const double line_start[6] = {0, 0, 0, 1, 0, 0};
    double line_end[6] = {0.5, 0, 0, 0.5, 0, 0};
    uint32_t two[2];
    zones_reset(two, 2);
    zones_unite(two, 0, 1);
    CHECK(zones_move(two, 2, line_start, line_end, unit, sums, false) == 2);
    CHECK(std::fabs(line_end[0]) < 1e-12 && std::fabs(line_end[3] - 1) < 1e-12);
    for (double x : line_end)
        CHECK(std::isfinite(x));
    // Frozen: a zone of free nodes stays where it started, bit for bit; a
    // zone with a kinematic node still follows it.
    std::memcpy(end, before, sizeof end);
    zones_reset(parent, 7);
    for (uint32_t k = 1; k < 4; ++k)
        zones_unite(parent, 0, k);
    zones_unite(parent, 6, 5);
    CHECK(zones_move(parent, 7, start, end, inverse_mass, sums, true) == 5);
    CHECK(std::memcmp(end, start, 12 * sizeof *end) == 0);
    CHECK(end[12] == 5.5 && std::fabs(end[15] - 8.5) < 1e-12 && end[18] == 9.5);
    // Pinned: a pair in the kinematic zone (nodes 5 and 6, as a pass gives
    // a pair's five) pins its free node only, once; after the zones' move
    // the pinned node is where it started, bit for bit, and the kinematic
    // node keeps its own motion.
    uint8_t pinned[7] = {0, 0, 0, 0, 0, 0, 0};
    const uint32_t pair[5] = {5, 5, 6, 6, 5};
    CHECK(zones_pin(pinned, pair, 5, inverse_mass));
    CHECK(pinned[5] == 1 && pinned[6] == 0 && pinned[0] == 0);
    CHECK(!zones_pin(pinned, pair, 5, inverse_mass)); // nothing new: the passes stop
    std::memcpy(end, before, sizeof end);
    CHECK(zones_move(parent, 7, start, end, inverse_mass, sums, true) == 5);
    zones_hold_pinned(pinned, 7, start, end);
    CHECK(std::memcmp(end + 15, start + 15, 3 * sizeof *end) == 0);
    CHECK(end[18] == 9.5 && end[19] == 0.25 && end[12] == 5.5);
    CHECK(std::memcmp(end, start, 12 * sizeof *end) == 0);
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

// A teardown that deletes the world (and its bodies) before the adapter:
// selfcol_bullet_destroy_after_world() frees everything the adapter
// allocated without reading the world or the bodies (under valgrind and
// ASan in CI, where selfcol_bullet_destroy() in this order reads the freed
// world: the hardening issue's use-after-free). The adapter runs
// automatically, so its action is in the world that is deleted first.
static void destroy_after_the_world() {
    failing_allocator f;
    f.fail_at = 0;
    selfcol_bullet_options opts;
    selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION);
    opts.allocator.alloc = failing_alloc;
    opts.allocator.free = failing_free;
    opts.allocator.user = &f;
    demo::options o;
    demo::world *w = new demo::world(o, 0.0);
    btSoftBody *low =
        w->add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 6, 6, 0.2, false);
    btSoftBody *high = w->add_sheet(btVector3(0, 0.01f, 0), btVector3(1, 0, 0), btVector3(0, 0, 1),
                                    6, 6, 0.2, false);
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w->dynamics, &opts) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, low, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, high, nullptr) == SELFCOL_OK);
    for (int i = 0; i < 3; ++i)
        w->step(1.0 / 240);
    selfcol_bullet_step_stats st;
    st.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.steps == 3 && st.status == SELFCOL_OK);
    CHECK(f.live > 0);
    delete w; // the world, its bodies, then (below) the adapter
    selfcol_bullet_destroy_after_world(a);
    CHECK(f.live == 0); // everything the adapter allocated is freed
    selfcol_bullet_destroy_after_world(nullptr);
}

// Two sheets 1 cm apart, one falling onto the other (self and soft-soft
// contacts from the first steps), stepped by hand 6 times with the Nth
// allocation failing, for every N until a run no longer reaches N; a third
// sheet is attached to the live scene after step 2 and the lower one
// detached after step 4. Every call returns OK or ENOMEM; after an ENOMEM
// the next steps (the allocator working again) succeed with finite nodes;
// destroy frees everything.
static void allocation_failure_at_every_call() {
    long n = 1;
    for (;; ++n) {
        demo::options o;
        demo::world w(o, 0.0);
        btSoftBody *low = w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 8,
                                      8, 0.2, false);
        btSoftBody *high = w.add_sheet(btVector3(0.05f, 0.01f, 0.05f), btVector3(0.9f, 0, 0),
                                       btVector3(0, 0, 0.9f), 8, 8, 0.2, false);
        btSoftBody *late = w.add_sheet(btVector3(0.1f, -0.01f, 0.1f), btVector3(0.8f, 0, 0),
                                       btVector3(0, 0, 0.8f), 6, 6, 0.2, false);
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
            failed_steps += status == SELFCOL_ENOMEM;
            for (int step = 0; step < 6; ++step) {
                w.step(1.0 / 240);
                int st = selfcol_bullet_step(a, 1.0 / 240);
                CHECK(st == SELFCOL_OK || st == SELFCOL_ENOMEM);
                failed_steps += st == SELFCOL_ENOMEM;
                if (step == 2) {
                    st = selfcol_bullet_attach(a, late, nullptr);
                    CHECK(st == SELFCOL_OK || st == SELFCOL_ENOMEM);
                    failed_steps += st == SELFCOL_ENOMEM;
                }
                if (step == 4) {
                    st = selfcol_bullet_detach(a, low);
                    CHECK(st == SELFCOL_OK || (st == SELFCOL_EINVAL && failed_steps == 1));
                }
                CHECK(failed_steps <= 1); // one failing allocation, one failing call
            }
            for (btSoftBody *b : {low, high, late})
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

// The continuous option: a sheet thrown at another one so fast that it
// passes through it within one step (0.05 m above, 30 m/s down, 1/240 s:
// 0.125 m) ends the step below it without it, unseen by any discrete query
// (0.075 m apart at the step's end, beyond the thickness); with it, the
// step's continuous query finds the pairs, and every node of the thrown
// sheet is held above the other one.
struct throw_result {
    double lowest_y; // of the thrown sheet's nodes after the step
    selfcol_bullet_step_stats stats;
};

// The lowest (sign -1) or highest (+1) y of a body's nodes.
static double extreme_y(const btSoftBody *body, int sign) {
    double y = -sign * 1e9;
    for (int i = 0; i < body->m_nodes.size(); ++i) {
        const double at = double(body->m_nodes[i].m_x.y());
        y = sign > 0 ? std::fmax(y, at) : std::fmin(y, at);
    }
    return y;
}

static throw_result throw_through(int continuous) {
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *low =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 8, 8, 0.1, false);
    btSoftBody *high = w.add_sheet(btVector3(0.05f, 0.05f, 0.05f), btVector3(0.8f, 0, 0),
                                   btVector3(0, 0, 0.8f), 8, 8, 0.1, false);
    selfcol_bullet_options opts;
    selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION);
    opts.continuous = continuous;
    opts.untangle = 0;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, low, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, high, nullptr) == SELFCOL_OK);
    w.step(1.0 / 240); // at rest: the continuous option's first positions
    for (int i = 0; i < high->m_nodes.size(); ++i)
        high->m_nodes[i].m_v = btVector3(0, -30, 0);
    w.step(1.0 / 240);
    throw_result r;
    r.stats.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &r.stats) == SELFCOL_OK && r.stats.status == SELFCOL_OK);
    r.lowest_y = extreme_y(high, -1);
    selfcol_bullet_destroy(a);
    return r;
}

static void continuous_option_stops_a_pass_through() {
    const throw_result off = throw_through(0), on = throw_through(1);
    std::printf("thrown sheet: lowest node at y = %.4f without the continuous option (%llu "
                "contacts, %llu interferences), %.4f with it (%llu pairs touching within the "
                "step, %llu nodes held, %llu passes, %llu pairs left)\n",
                off.lowest_y, (unsigned long long)off.stats.contacts,
                (unsigned long long)off.stats.interferences, on.lowest_y,
                (unsigned long long)on.stats.continuous_hits,
                (unsigned long long)on.stats.continuous_held,
                (unsigned long long)on.stats.continuous_passes,
                (unsigned long long)on.stats.continuous_remaining);
    CHECK(off.lowest_y < -0.02);         // went through, unseen:
    CHECK(off.stats.interferences == 0); // no crossing left at the step's end
    CHECK(off.stats.continuous_passes == 0 && off.stats.continuous_hits == 0);
    CHECK(on.lowest_y > 0); // held above the other sheet
    CHECK(on.stats.continuous_hits > 0 && on.stats.continuous_held > 0);
    CHECK(on.stats.continuous_remaining == 0);
    CHECK(on.stats.continuous_passes >= 2 && on.stats.seconds_continuous > 0);
    // Only 0 and 1 are options.
    demo::options o;
    demo::world w(o, 0.0);
    selfcol_bullet_options opts;
    selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION);
    CHECK(opts.continuous == 0);
    opts.continuous = 2;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts) == SELFCOL_EINVAL && a == nullptr);
}

// A body's nodes and faces as a core mesh (positions as Bullet holds them).
static selfcol_mesh *mesh_of(const btSoftBody *body) {
    std::vector<double> x(3 * size_t(body->m_nodes.size()));
    for (int i = 0; i < body->m_nodes.size(); ++i)
        for (int k = 0; k < 3; ++k)
            x[3 * size_t(i) + size_t(k)] = double(body->m_nodes[i].m_x[k]);
    std::vector<uint32_t> t(3 * size_t(body->m_faces.size()));
    for (int f = 0; f < body->m_faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            t[3 * size_t(f) + size_t(k)] = uint32_t(body->m_faces[f].m_n[k] - &body->m_nodes[0]);
    selfcol_mesh *m = nullptr;
    CHECK(selfcol_mesh_create(&m, size_t(body->m_nodes.size()), x.data(),
                              size_t(body->m_faces.size()), t.data(), nullptr) == SELFCOL_OK);
    return m;
}

// Exact EF interferences (edges through triangles) of two bodies: each
// one's own and between them.
static size_t crossings_of(const btSoftBody *first, const btSoftBody *second) {
    selfcol_mesh *m[2] = {mesh_of(first), mesh_of(second)};
    selfcol_hierarchy *h[2] = {nullptr, nullptr};
    for (int k = 0; k < 2; ++k)
        CHECK(selfcol_hierarchy_create(&h[k], m[k], nullptr) == SELFCOL_OK);
    selfcol_contacts *c = nullptr;
    CHECK(selfcol_contacts_create(&c, nullptr) == SELFCOL_OK);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.kinds = SELFCOL_KIND_EF;
    q.distance = 0.01;
    size_t n = 0;
    for (int k = 0; k < 2; ++k) {
        CHECK(selfcol_hierarchy_self_collide(h[k], c, &q) == SELFCOL_OK);
        n += selfcol_contacts_count(c);
    }
    CHECK(selfcol_hierarchy_collide(h[0], h[1], c, &q) == SELFCOL_OK);
    n += selfcol_contacts_count(c);
    selfcol_contacts_destroy(c);
    for (int k = 0; k < 2; ++k) {
        selfcol_hierarchy_destroy(h[k]);
        selfcol_mesh_destroy(m[k]);
    }
    return n;
}

// The continuous option lets a crossing that is there when a step starts
// come undone. The middle 3 x 3 nodes of the upper of two sheets at rest
// are put 2 cm under the lower one before the first step (which has no
// last positions and is not checked): the edges around them cross the
// lower sheet, and after that step 16 still do. The springs and the
// untangling lift the nodes back; to get out they must pass back through
// the triangles those edges cross, and the passes must let them. Before
// they let a crossing's own pairs through, they held the nodes under the
// lower sheet: 16 crossings after 120 steps (measured), where the run
// without the continuous option has none after 2 steps and the run with
// it none after 5.
struct untangle_result {
    size_t crossings_start, crossings_end;
    uint64_t exempt; // continuous_exempt over the steps
    int status;
};

static untangle_result poked_through(int continuous) {
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *low =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 9, 9, 0.1, false);
    btSoftBody *high = w.add_sheet(btVector3(0.05f, 0.02f, 0.05f), btVector3(0.8f, 0, 0),
                                   btVector3(0, 0, 0.8f), 9, 9, 0.1, false);
    for (int i = 3; i <= 5; ++i) // the middle 3 x 3 nodes, 4 cm down
        for (int j = 3; j <= 5; ++j) {
            btSoftBody::Node &n = high->m_nodes[9 * i + j];
            n.m_x.setY(-0.02f);
            n.m_q = n.m_x;
        }
    selfcol_bullet_options opts;
    selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION);
    opts.continuous = continuous;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, low, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, high, nullptr) == SELFCOL_OK);
    untangle_result r;
    r.crossings_start = crossings_of(low, high);
    r.exempt = 0;
    r.status = SELFCOL_OK;
    for (int step = 0; step < 30 && r.status == SELFCOL_OK; ++step) {
        w.step(1.0 / 240);
        selfcol_bullet_step_stats st;
        st.version = SELFCOL_BULLET_STEP_STATS_VERSION;
        CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK);
        r.status = st.status;
        r.exempt += st.continuous_exempt;
        // The step's own count of the crossings it leaves: this test's EF
        // query on meshes of its own, with the option (0 without it).
        CHECK(st.crossings_after == (continuous ? crossings_of(low, high) : 0));
    }
    r.crossings_end = crossings_of(low, high);
    selfcol_bullet_destroy(a);
    return r;
}

static void continuous_option_lets_a_crossing_come_undone() {
    const untangle_result off = poked_through(0), on = poked_through(1);
    std::printf("node poked through a sheet: %zu crossings at the start; after 30 steps %zu "
                "without the continuous option, %zu with it (%llu pairs let through)\n",
                on.crossings_start, off.crossings_end, on.crossings_end,
                (unsigned long long)on.exempt);
    CHECK(off.status == SELFCOL_OK && on.status == SELFCOL_OK);
    CHECK(on.crossings_start > 0 && off.crossings_start == on.crossings_start);
    CHECK(off.crossings_end == 0); // the untangling alone undoes it
    CHECK(on.crossings_end == 0);  // and the passes let it
    CHECK(on.exempt > 0);
}

// The continuous option gives the scene each step's start. A strip lies
// beside a sheet's border edge, 0.3 d beyond it and 0.5 d above the sheet's
// plane, and moves down by d in one step: its contacts with the border
// change sign, but on the way it passes the edge at 0.3 d without touching.
// Judged on the step's path (with the option) they went around the edge and
// keep their sides; from the sign change alone (without it) they crossed.
static selfcol_bullet_step_stats pass_around(int continuous) {
    const double d = 0.01;
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *sheet =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 8, 8, 0.1, false);
    btSoftBody *strip = w.add_sheet(btVector3(btScalar(1 + 0.3 * d), btScalar(0.5 * d), 0),
                                    btVector3(0.3f, 0, 0), btVector3(0, 0, 1), 3, 8, 0.1, false);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.distance = d;
    selfcol_bullet_options opts;
    selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION);
    opts.query = &q;
    opts.continuous = continuous;
    opts.untangle = 0;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, sheet, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, strip, nullptr) == SELFCOL_OK);
    // The border's contacts are found and pushed apart. With the option, the
    // first step's end is the second's start, and the scene, which keeps
    // the positions of each update from then on, knows the third step's path.
    for (int step = 0; step < 2; ++step) {
        w.step(1.0 / 240);
        selfcol_bullet_step_stats at_rest;
        at_rest.version = SELFCOL_BULLET_STEP_STATS_VERSION;
        CHECK(selfcol_bullet_stats(a, &at_rest) == SELFCOL_OK && at_rest.contacts > 0);
        CHECK(at_rest.flipped == 0 && at_rest.passed_around == 0);
    }
    for (int i = 0; i < strip->m_nodes.size(); ++i)
        strip->m_nodes[i].m_v = btVector3(0, btScalar(-240 * d), 0);
    w.step(1.0 / 240);
    selfcol_bullet_step_stats r;
    r.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &r) == SELFCOL_OK && r.status == SELFCOL_OK);
    CHECK(extreme_y(strip, +1) < 0); // the whole strip went below the sheet's plane
    selfcol_bullet_destroy(a);
    return r;
}

static void continuous_option_keeps_a_pass_around() {
    const selfcol_bullet_step_stats off = pass_around(0), on = pass_around(1);
    std::printf("strip past a border: without the continuous option %llu contacts, %llu crossed, "
                "%llu flipped, %llu passed around; with it %llu contacts, %llu crossed, %llu "
                "flipped, %llu passed around (%llu pairs touching within the step)\n",
                (unsigned long long)off.contacts, (unsigned long long)off.crossed,
                (unsigned long long)off.flipped, (unsigned long long)off.passed_around,
                (unsigned long long)on.contacts, (unsigned long long)on.crossed,
                (unsigned long long)on.flipped, (unsigned long long)on.passed_around,
                (unsigned long long)on.continuous_hits);
    CHECK(off.contacts > 0 && on.contacts > 0);
    CHECK(off.flipped > 0 && off.passed_around == 0);
    CHECK(on.continuous_hits == 0); // nothing touched on the way
    CHECK(on.passed_around > 0 && on.flipped == 0 && on.crossed == 0);
}

// The impact zones in the adapter: a kinematic sheet (zero inverse mass,
// which no hold-back stops) driven down through a free one at 30 m/s. The
// held-back passes cannot keep the free sheet's nodes clear of it; the
// zones carry the nodes it meets along with it, so the free sheet ends the
// step below it with no pair touching on the way. Each allocation of the
// second step fails once in turn (alloc_fail_at counts from 1; LONG_MAX
// counts them and fails none): the step returns OK or
// ENOMEM, leaves finite nodes, and destroy frees everything.
struct push_result {
    selfcol_bullet_step_stats stats;
    double highest_below; // highest free node under the kinematic sheet's footprint
    double pusher_y;      // the kinematic sheet's height
    int status;
    long allocations, live;
};

static push_result kinematic_push(int continuous, long alloc_fail_at) {
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *free_sheet =
        w.add_sheet(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1), 8, 8, 0.1, false);
    btSoftBody *pusher = w.add_sheet(btVector3(0.2f, 0.05f, 0.2f), btVector3(0.6f, 0, 0),
                                     btVector3(0, 0, 0.6f), 6, 6, 0.1, false);
    for (int i = 0; i < pusher->m_nodes.size(); ++i)
        pusher->setMass(i, 0);
    failing_allocator f;
    selfcol_bullet_options opts;
    selfcol_bullet_options_init(&opts, SELFCOL_BULLET_OPTIONS_VERSION);
    opts.continuous = continuous;
    opts.untangle = 0;
    opts.automatic = 0;
    opts.allocator.alloc = failing_alloc;
    opts.allocator.free = failing_free;
    opts.allocator.user = &f;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, free_sheet, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, pusher, nullptr) == SELFCOL_OK);
    w.step(1.0 / 240); // at rest: the continuous option's first positions
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    for (int i = 0; i < pusher->m_nodes.size(); ++i)
        pusher->m_nodes[i].m_v = btVector3(0, -30, 0);
    f.calls = 0;
    f.fail_at = alloc_fail_at;
    w.step(1.0 / 240);
    push_result r;
    r.status = selfcol_bullet_step(a, 1.0 / 240);
    r.allocations = f.calls;
    f.fail_at = 0;
    r.stats.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &r.stats) == SELFCOL_OK);
    r.pusher_y = double(pusher->m_nodes[0].m_x.y());
    r.highest_below = -1e9;
    for (int i = 0; i < free_sheet->m_nodes.size(); ++i) {
        const btVector3 &x = free_sheet->m_nodes[i].m_x;
        CHECK(std::isfinite(x.x()) && std::isfinite(x.y()) && std::isfinite(x.z()));
        if (x.x() > 0.2f && x.x() < 0.8f && x.z() > 0.2f && x.z() < 0.8f)
            r.highest_below = std::fmax(r.highest_below, double(x.y()));
    }
    selfcol_bullet_destroy(a);
    r.live = f.live;
    return r;
}

static void continuous_option_zones_carry_a_kinematic_push() {
    // (on: its step's allocations counted, none failing)
    const push_result off = kinematic_push(0, 0), on = kinematic_push(1, LONG_MAX);
    std::printf("kinematic sheet pushed through a free one to y = %.4f: free nodes under it up to "
                "y = %.4f without the continuous option, %.4f with it (%llu pairs touching, %llu "
                "passes, %llu nodes in impact zones, %llu pairs left)\n",
                on.pusher_y, off.highest_below, on.highest_below,
                (unsigned long long)on.stats.continuous_hits,
                (unsigned long long)on.stats.continuous_passes,
                (unsigned long long)on.stats.zone_nodes,
                (unsigned long long)on.stats.continuous_remaining);
    CHECK(off.status == SELFCOL_OK && on.status == SELFCOL_OK);
    CHECK(off.highest_below > off.pusher_y); // left above it: passed through
    CHECK(on.highest_below < on.pusher_y);   // carried below it
    CHECK(on.stats.zone_nodes > 0 && on.stats.continuous_remaining == 0);
    CHECK(on.stats.continuous_passes > SELFCOL_BULLET_CONTINUOUS_PASSES);
    // Every allocation of the step fails once in turn.
    long n = 1;
    for (; n <= on.allocations; ++n) {
        const push_result r = kinematic_push(1, n);
        CHECK(r.status == SELFCOL_OK || r.status == SELFCOL_ENOMEM);
        CHECK(r.live == 0);
    }
    std::printf("the pushed step's %ld allocations failed in turn\n", n - 1);
}

// A Bullet scheduler as an engine might install one: it reports 4 threads
// and runs each parallel-for's range in chunks of the grain, last first (so
// any reliance on item order would show), counting the calls.
struct counting_scheduler : btITaskScheduler {
    int calls = 0;
    counting_scheduler() : btITaskScheduler("selfcol test") {}
    int getMaxNumThreads() const override {
        return 4;
    }
    int getNumThreads() const override {
        return 4;
    }
    void setNumThreads(int) override {}
    void parallelFor(int begin, int end, int grain, const btIParallelForBody &body) override {
        ++calls;
        const int step = grain > 0 ? grain : 1;
        for (int hi = end; hi > begin;) {
            const int lo = hi - step > begin ? hi - step : begin;
            body.forLoop(lo, hi);
            hi = lo;
        }
    }
    btScalar parallelSum(int begin, int end, int, const btIParallelSumBody &body) override {
        return body.sumLoop(begin, end);
    }
};

// Nodes after 4 steps of two crumpling sheets, with or without the
// adapter's stages on Bullet's scheduler (switched on before the first
// step, or between steps), or on 3 of selfcol's own threads (query.threads:
// the queries and the continuous passes).
static std::vector<btScalar>
crumple_steps(int scheduler,
              unsigned threads = 1) { // 0 off, 1 from the start, 2 later
    demo::options o;
    demo::world w(o, 0.0);
    btSoftBody *low = w.add_sheet(btVector3(0, 0, 0), btVector3(0.3f, 0, 0), btVector3(0, 0, 0.3f),
                                  14, 14, 0.1, false);
    btSoftBody *high = w.add_sheet(btVector3(0.004f, 0.006f, 0.004f), btVector3(0.3f, 0, 0),
                                   btVector3(0, 0, 0.3f), 14, 14, 0.1, false);
    for (int i = 0; i < high->m_nodes.size(); ++i)
        high->m_nodes[i].m_v = btVector3(0, -0.5f, 0.1f * btScalar(i % 7) - 0.3f);
    full_options opts;
    opts.o.automatic = 0;
    opts.q.distance = 0.005;
    opts.o.continuous = 1; // its continuous queries go through the scheduler too
    opts.o.threads = threads;
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, &opts.o) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, low, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_attach(a, high, nullptr) == SELFCOL_OK);
    if (scheduler == 1)
        CHECK(selfcol_bullet_use_task_scheduler(a, 1) == SELFCOL_OK);
    for (int step = 0; step < 4; ++step) {
        if (scheduler == 2 && step == 2)
            CHECK(selfcol_bullet_use_task_scheduler(a, 1) == SELFCOL_OK);
        w.dynamics->stepSimulation(btScalar(1.0 / 240), 0);
        CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    }
    std::vector<btScalar> x;
    for (btSoftBody *b : {low, high})
        for (int i = 0; i < b->m_nodes.size(); ++i)
            for (int k = 0; k < 3; ++k)
                x.push_back(b->m_nodes[i].m_x[k]);
    selfcol_bullet_step_stats st;
    st.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    CHECK(selfcol_bullet_stats(a, &st) == SELFCOL_OK && st.contacts > 0);
    CHECK(st.continuous_passes > 0);
    CHECK(selfcol_bullet_use_task_scheduler(a, 0) == SELFCOL_OK); // back to its own
    CHECK(selfcol_bullet_step(a, 1.0 / 240) == SELFCOL_OK);
    selfcol_bullet_destroy(a);
    return x;
}

static void task_scheduler_and_threads_give_the_same_steps() {
    CHECK(selfcol_bullet_use_task_scheduler(nullptr, 1) == SELFCOL_EINVAL);
    btITaskScheduler *before = btGetTaskScheduler();
    counting_scheduler scheduler;
    btSetTaskScheduler(&scheduler);
    const std::vector<btScalar> own = crumple_steps(0);
    const int calls_without = scheduler.calls;
    const std::vector<btScalar> from_start = crumple_steps(1);
    const std::vector<btScalar> later = crumple_steps(2);
    const std::vector<btScalar> threaded = crumple_steps(0, 3);
    // A build of Bullet without BT_THREADSAFE runs btParallelFor's body
    // itself and never calls the scheduler: then only equality is checked.
    std::printf("Bullet's scheduler ran %d parallel-fors for selfcol\n",
                scheduler.calls - calls_without);
    btSetTaskScheduler(before);
    CHECK(!own.empty() && own == from_start && own == later && own == threaded);
    demo::options o;
    demo::world w(o, 0.0);
    selfcol_bullet *a = nullptr;
    CHECK(selfcol_bullet_create(&a, w.dynamics, nullptr) == SELFCOL_OK);
    CHECK(selfcol_bullet_use_task_scheduler(a, 2) == SELFCOL_EINVAL);
    CHECK(selfcol_bullet_use_task_scheduler(a, 1) == SELFCOL_OK);
    selfcol_bullet_destroy(a); // frees the context it made
}

int main() {
    api_rejects_bad_input();
    response_rules();
    options_by_pointer_and_versions();
    create_validates_nested_options();
    removed_body_is_dropped();
    detach_restores_and_keeps_other_stores();
    crossing_remembered_across_attach_and_detach();
    attached_cloth_lands_on_unattached_body();
    one_adapter_per_body();
    attach_refuses_foreign_bodies();
    nonfinite_velocity_refused();
    demo_run_stops_at_failed_step();
    untangle_rules();
    impact_zone_rules();
    continuous_option_stops_a_pass_through();
    continuous_option_keeps_a_pass_around();
    continuous_option_lets_a_crossing_come_undone();
    continuous_option_zones_carry_a_kinematic_push();
    allocation_failure_at_every_call();
    destroy_after_the_world();
    task_scheduler_and_threads_give_the_same_steps();
    if (failures == 0)
        std::printf("test_bullet_adapter: all checks passed\n");
    return failures == 0 ? 0 : 1;
}
