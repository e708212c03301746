// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The hierarchy validator (lib/hierarchy/hierarchy_validate.c): it accepts every
// hierarchy the build and refit make, on regular, folded, degenerate and
// disconnected meshes, and it rejects each kind of corruption it is meant to
// catch (so that a SELFCOL_VALIDATE build, where it runs after every build
// and refit, would stop on them).
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <string.h>

#include "fixtures.h"
#include "hierarchy/hierarchy.h"

static selfcol_hierarchy *make(const fixture *s, selfcol_mesh **mesh) {
    selfcol_hierarchy *h = NULL;
    assert_int_equal(selfcol_mesh_create(mesh, s->vertex_count, s->positions, s->triangle_count,
                                         s->triangles, NULL),
                     SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&h, *mesh, NULL), SELFCOL_OK);
    return h;
}

static void test_validate_accepts_what_the_build_makes(void **state) {
    (void)state;
    fixture scenes[4], b;
    assert_int_equal(fixture_grid(&scenes[0], 20, 17, 1.0), 0);
    assert_int_equal(fixture_crumpled(&scenes[1], 25, 25, 4, 5.0), 0);
    assert_int_equal(fixture_moebius(&scenes[2], 48, 4, 6.0, 2.0, 1, 0.1), 0);
    assert_int_equal(fixture_sheet_pair(&scenes[3], &b, 12, 3, 0.5, 0.0), 0);
    assert_int_equal(fixture_append(&scenes[3], &b), 0);
    fixture_free(&b);
    for (int i = 0; i < 4; ++i) {
        selfcol_mesh *m = NULL;
        selfcol_hierarchy *h = make(&scenes[i], &m);
        assert_int_equal(selfcol_hierarchy__validate(h, 1), 1);
        // After a new frame and a refit, still valid.
        for (size_t k = 0; k < 3 * scenes[i].vertex_count; ++k)
            scenes[i].positions[k] *= 1.5;
        assert_int_equal(selfcol_mesh_set_positions(m, scenes[i].positions, scenes[i].vertex_count),
                         SELFCOL_OK);
        assert_int_equal(selfcol_hierarchy_refit(h), SELFCOL_OK);
        assert_int_equal(selfcol_hierarchy__validate(h, 1), 1);
        // Frames of random jitter: every normal stays inside its nodes'
        // cones (the refit's leaf cones and merges), and cones exist.
        uint64_t rng = 2024u + (uint64_t)i;
        for (int frame = 0; frame < 5; ++frame) {
            for (size_t k = 0; k < 3 * scenes[i].vertex_count; ++k) {
                rng = rng * 6364136223846793005u + 1442695040888963407u;
                scenes[i].positions[k] += 0.05 * ((double)(rng >> 11) * 0x1p-53 - 0.5);
            }
            assert_int_equal(
                selfcol_mesh_set_positions(m, scenes[i].positions, scenes[i].vertex_count),
                SELFCOL_OK);
            assert_int_equal(selfcol_hierarchy_refit(h), SELFCOL_OK);
            assert_int_equal(selfcol_hierarchy__validate(h, 1), 1);
            size_t coned = 0;
            for (size_t id = 0; id < h->node_count; ++id)
                coned += h->nodes[id].cone_angle < 1.5707963267948966;
            assert_true(coned > 0);
        }
        selfcol_hierarchy_destroy(h);
        selfcol_mesh_destroy(m);
        fixture_free(&scenes[i]);
    }
}

static void test_validate_rejects_each_corruption(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_crumpled(&s, 16, 16, 2, 5.0), 0);
    selfcol_mesh *m = NULL;
    selfcol_hierarchy *h = make(&s, &m);
    assert_int_equal(selfcol_hierarchy__validate(h, 1), 1);
    // A triangle listed twice in the order (and another missing).
    uint32_t saved = h->tri_order[5];
    h->tri_order[5] = h->tri_order[6];
    assert_int_equal(selfcol_hierarchy__validate(h, 0), 0);
    h->tri_order[5] = saved;
    // A child range that does not tile its parent's.
    const uint32_t c = h->nodes[0].first_child;
    h->nodes[c].tri_count++;
    assert_int_equal(selfcol_hierarchy__validate(h, 0), 0);
    h->nodes[c].tri_count--;
    // A disk that is not connected.
    uint8_t flags = h->nodes[c].flags;
    h->nodes[c].flags = (uint8_t)((flags | SELFCOL_NODE_DISK) & ~SELFCOL_NODE_CONNECTED);
    assert_int_equal(selfcol_hierarchy__validate(h, 0), 0);
    h->nodes[c].flags = flags;
    // A parent box that does not hold its child's.
    float hi = h->nodes[0].hi[2];
    h->nodes[0].hi[2] = h->nodes[c].hi[2] - 1.0f;
    assert_int_equal(selfcol_hierarchy__validate(h, 1), 0);
    assert_int_equal(selfcol_hierarchy__validate(h, 0), 1); // structure alone is fine
    h->nodes[0].hi[2] = hi;
    // A leaf cone turned away from its triangles' normals.
    size_t leaf = 0;
    while (leaf < h->node_count &&
           (h->nodes[leaf].child_count != 0 || !(h->nodes[leaf].cone_angle < 1.0f)))
        ++leaf;
    assert_true(leaf < h->node_count);
    float axis[3] = {h->nodes[leaf].cone_axis[0], h->nodes[leaf].cone_axis[1],
                     h->nodes[leaf].cone_axis[2]};
    float angle = h->nodes[leaf].cone_angle;
    for (int k = 0; k < 3; ++k)
        h->nodes[leaf].cone_axis[k] = -axis[k];
    assert_int_equal(selfcol_hierarchy__validate(h, 1), 0);
    for (int k = 0; k < 3; ++k)
        h->nodes[leaf].cone_axis[k] = axis[k];
    // Too narrow (a leaf of one flat triangle can have angle ~0: skip those).
    h->nodes[leaf].cone_angle = 0.0f;
    int narrowed = selfcol_hierarchy__validate(h, 1);
    h->nodes[leaf].cone_angle = angle;
    if (angle > 1e-3f)
        assert_int_equal(narrowed, 0);
    assert_int_equal(selfcol_hierarchy__validate(h, 1), 1);
    // A leaf box that does not hold its triangle: the mesh moved, no refit.
    for (size_t k = 0; k < 3 * s.vertex_count; ++k)
        s.positions[k] += 100.0;
    assert_int_equal(selfcol_mesh_set_positions(m, s.positions, s.vertex_count), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy__validate(h, 1), 0);
    assert_int_equal(selfcol_hierarchy_refit(h), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy__validate(h, 1), 1);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);
    fixture_free(&s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_validate_accepts_what_the_build_makes),
        cmocka_unit_test(test_validate_rejects_each_corruption),
    };
    return cmocka_run_group_tests_name("validate", tests, NULL, NULL);
}
