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

#include <stdlib.h>
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

// ---------------------------------------------------------------------------
// SELFCOL_NODE_DISK against a direct count. EXACT skips a node pair on the
// contour criterion only for disks, so a node flagged DISK must hold a
// topological disk: edge-connected, every edge in at most two of its
// triangles and traversed once each way (after the build's flips), every
// vertex's triangles one edge-connected fan, and V - E + F = 1. The build
// derives the flag from counts climbing the tree (hierarchy_boundary.c);
// here each node's patch is examined on its own.

static uint32_t root_of(uint32_t *parent, uint32_t x) {
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

static void join(uint32_t *parent, uint32_t a, uint32_t b) {
    a = root_of(parent, a);
    b = root_of(parent, b);
    if (a != b)
        parent[a > b ? a : b] = a < b ? a : b;
}

// 1 when the triangles of node id form a topological disk.
static int patch_is_disk(const selfcol_hierarchy *h, size_t id) {
    const selfcol_mesh *m = h->mesh;
    const selfcol_node *n = &h->nodes[id];
    const size_t F = n->tri_count, E = m->edge_count, V = m->vertex_count;
    int *uses = test_calloc(E, sizeof(int)), *turn = test_calloc(E, sizeof(int));
    uint32_t *first = test_calloc(E, sizeof(uint32_t)); // a patch triangle on each edge
    uint32_t *tri_set = test_calloc(m->triangle_count, sizeof(uint32_t));
    uint32_t *corner_set = test_calloc(3 * m->triangle_count, sizeof(uint32_t));
    uint8_t *seen_vertex = test_calloc(V, 1);
    uint32_t *fans = test_calloc(V, sizeof(uint32_t));
    int disk = 1;
    for (uint32_t t = 0; t < m->triangle_count; ++t)
        tri_set[t] = t;
    for (uint32_t c = 0; c < 3 * m->triangle_count; ++c)
        corner_set[c] = c;
    size_t vertices = 0, edges = 0;
    for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count && disk; ++s) {
        const uint32_t t = h->tri_order[s];
        const uint32_t *tri = m->triangles + 3 * (size_t)t;
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
            disk = 0; // a collapsed triangle: no disk
            break;
        }
        const int flip = (h->owned[t] & SELFCOL_TRIANGLE_FLIPPED) != 0;
        for (int i = 0; i < 3; ++i) {
            if (!seen_vertex[tri[i]]) {
                seen_vertex[tri[i]] = 1;
                vertices++;
            }
            const uint32_t e = m->triangle_edges[3 * (size_t)t + (size_t)i];
            const int forward = tri[i] < tri[(i + 1) % 3];
            turn[e] += (forward != flip) ? 1 : -1;
            if (uses[e]++ == 0) {
                edges++;
                first[e] = t;
                continue;
            }
            // The second triangle on e: one triangle set, and each end's
            // corners in one fan.
            const uint32_t u = first[e];
            join(tri_set, t, u);
            for (int end = 0; end < 2; ++end) {
                const uint32_t x = m->edges[2 * (size_t)e + (size_t)end];
                const uint32_t *ut = m->triangles + 3 * (size_t)u;
                const uint32_t cu = 3 * u + (ut[0] == x ? 0u : ut[1] == x ? 1u : 2u);
                const uint32_t ct = 3 * t + (tri[0] == x ? 0u : tri[1] == x ? 1u : 2u);
                join(corner_set, cu, ct);
            }
        }
    }
    for (size_t e = 0; e < E && disk; ++e)
        if (uses[e] > 2 || (uses[e] == 2 && turn[e] != 0))
            disk = 0; // not manifold, or not oriented
    if (disk) {
        size_t sets = 0;
        for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count; ++s) {
            const uint32_t t = h->tri_order[s];
            sets += root_of(tri_set, t) == t;
            for (uint32_t i = 0; i < 3; ++i)
                fans[m->triangles[3 * (size_t)t + i]] +=
                    root_of(corner_set, 3 * t + i) == 3 * t + i;
        }
        disk = sets == 1;
        for (size_t v = 0; v < V && disk; ++v)
            disk = fans[v] <= 1;
        disk = disk && (long)vertices - (long)edges + (long)F == 1;
    }
    test_free(uses);
    test_free(turn);
    test_free(first);
    test_free(tri_set);
    test_free(corner_set);
    test_free(seen_vertex);
    test_free(fans);
    return disk;
}

// Checks every node's flag against patch_is_disk; returns how many are
// disks. root_is_disk: 1 when the whole surface is a disk the build must
// recognise (an open sheet), else -1.
static size_t check_disk_flags(const fixture *s, int root_is_disk) {
    selfcol_mesh *m = NULL;
    selfcol_hierarchy *h = make(s, &m);
    size_t disks = 0;
    for (size_t id = 0; id < h->node_count; ++id) {
        if (!(h->nodes[id].flags & SELFCOL_NODE_DISK))
            continue;
        disks++;
        if (!patch_is_disk(h, id))
            fail_msg("node %zu (%u triangles) is flagged DISK but is no disk", id,
                     h->nodes[id].tri_count);
    }
    if (root_is_disk == 1) {
        assert_true(h->nodes[0].flags & SELFCOL_NODE_DISK);
        assert_true(patch_is_disk(h, 0)); // the reference recognises a disk too
    }
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);
    return disks;
}

// A crumpled sheet with what the build treats apart: a third triangle on an
// interior edge (a book: the edge is non-manifold), a copy of a triangle (a
// duplicate), a triangle (a, b, a) on a border edge and a triangle
// (c, c, c).
static void make_mixed(fixture *s) {
    assert_int_equal(fixture_crumpled(s, 18, 16, 5, 4.0), 0);
    const size_t V = s->vertex_count, F = s->triangle_count;
    s->positions = realloc(s->positions, 3 * (V + 1) * sizeof(double)); // fixture_free frees
    s->triangles = realloc(s->triangles, 3 * (F + 4) * sizeof(uint32_t));
    assert_non_null(s->positions);
    assert_non_null(s->triangles);
    const uint32_t *t0 = s->triangles + 3 * (F / 2);
    for (int k = 0; k < 3; ++k) // the page's tip: above the middle triangle
        s->positions[3 * V + (size_t)k] =
            s->positions[3 * (size_t)t0[0] + (size_t)k] + (k == 2 ? 3.0 : 0.5);
    const uint32_t a = t0[0], b = t0[1], dup[3] = {t0[0], t0[1], t0[2]};
    // (a, b, a) on a border edge (a, b): the edge then has two triangles.
    const uint32_t *t1 = NULL;
    for (size_t t = 0; t < F && t1 == NULL; ++t) {
        const uint32_t *x = s->triangles + 3 * t;
        size_t sharing = 0;
        for (size_t u = 0; u < F; ++u) {
            const uint32_t *y = s->triangles + 3 * u;
            int has0 = y[0] == x[0] || y[1] == x[0] || y[2] == x[0];
            int has1 = y[0] == x[1] || y[1] == x[1] || y[2] == x[1];
            sharing += has0 && has1;
        }
        if (sharing == 1)
            t1 = x;
    }
    assert_non_null(t1);
    const uint32_t added[4][3] = {{a, b, (uint32_t)V},
                                  {dup[0], dup[1], dup[2]},
                                  {t1[0], t1[1], t1[0]},
                                  {t1[2], t1[2], t1[2]}};
    memcpy(s->triangles + 3 * F, added, sizeof added);
    s->vertex_count = V + 1;
    s->triangle_count = F + 4;
}

static void test_disk_flags_only_on_topological_disks(void **state) {
    (void)state;
    fixture s, b;
    // An open sheet: its root and most nodes are disks.
    assert_int_equal(fixture_grid(&s, 16, 12, 1.0), 0);
    assert_true(check_disk_flags(&s, 1) > 10);
    fixture_free(&s);
    assert_int_equal(fixture_crumpled(&s, 20, 18, 3, 5.0), 0);
    assert_true(check_disk_flags(&s, 1) > 10);
    fixture_free(&s);
    assert_int_equal(fixture_holed(&s, 16, 14, 3.0, 2, 1.0), 0);
    (void)check_disk_flags(&s, -1);
    fixture_free(&s);
    assert_int_equal(fixture_moebius(&s, 48, 4, 6.0, 2.0, 1, 0.1), 0);
    (void)check_disk_flags(&s, -1);
    fixture_free(&s);
    assert_int_equal(fixture_icosphere(&s, 2, 1.0), 0);
    (void)check_disk_flags(&s, -1);
    // The same sphere pinched: two far vertices welded into one, whose
    // triangles form two fans. V - E + F = 1 with no boundary: only the fan
    // test tells the whole (and every patch holding both fans) from a disk.
    uint32_t a = 0, far = 0;
    double best = -1.0;
    for (uint32_t v = 1; v < s.vertex_count; ++v) {
        double d2 = 0.0;
        for (int k = 0; k < 3; ++k) {
            const double x = s.positions[3 * (size_t)v + (size_t)k] - s.positions[k];
            d2 += x * x;
        }
        if (d2 > best)
            best = d2, far = v;
    }
    for (size_t i = 0; i < 3 * s.triangle_count; ++i)
        if (s.triangles[i] == far)
            s.triangles[i] = a;
    (void)check_disk_flags(&s, -1);
    fixture_free(&s);
    // Two sheets crossing (two components, joined at the root).
    assert_int_equal(fixture_sheet_pair(&s, &b, 12, 3, 0.5, 0.0), 0);
    assert_int_equal(fixture_append(&s, &b), 0);
    fixture_free(&b);
    (void)check_disk_flags(&s, -1);
    fixture_free(&s);
    // A book page, a duplicate and collapsed triangles (make_mixed).
    make_mixed(&s);
    assert_true(check_disk_flags(&s, -1) > 0);
    fixture_free(&s);
}

// Each internal node's boundary list (hierarchy_boundary.c) against a direct
// count: the half-edges of the edges that one of the patch's triangles uses
// and no other of them does (manifold edges of the mesh only: a
// non-manifold edge is on no list), oriented with that triangle after the
// build's flips (at the first of its slots on the edge: a triangle (a, b, a)
// has two), sorted by edge. Leaves keep no list.
static void check_boundary_lists(const fixture *s) {
    selfcol_mesh *m = NULL;
    selfcol_hierarchy *h = make(s, &m);
    const size_t E = m->edge_count;
    uint32_t *uses = test_calloc(E, sizeof(uint32_t)), *half = test_calloc(E, sizeof(uint32_t));
    size_t listed = 0;
    for (size_t id = 0; id < h->node_count; ++id) {
        const selfcol_node *n = &h->nodes[id];
        if (n->child_count == 0) {
            assert_int_equal(n->boundary_count, 0);
            continue;
        }
        memset(uses, 0, E * sizeof(uint32_t));
        for (uint32_t sl = n->tri_begin; sl < n->tri_begin + n->tri_count; ++sl) {
            const uint32_t t = h->tri_order[sl];
            const uint32_t *tri = m->triangles + 3 * (size_t)t;
            const int flip = (h->owned[t] & SELFCOL_TRIANGLE_FLIPPED) != 0;
            for (int i = 0; i < 3; ++i) {
                const uint32_t e = m->triangle_edges[3 * (size_t)t + (size_t)i];
                if (e == SELFCOL_INVALID_INDEX ||
                    (i > 0 && e == m->triangle_edges[3 * (size_t)t]) ||
                    (i > 1 && e == m->triangle_edges[3 * (size_t)t + 1]))
                    continue; // each triangle counts once per edge
                if (uses[e]++ == 0) {
                    const int reversed = (tri[i] > tri[(i + 1) % 3]) != flip;
                    half[e] = e << 1 | (uint32_t)reversed;
                }
            }
        }
        size_t k = 0;
        for (uint32_t e = 0; e < E; ++e) {
            const uint32_t on_edge = m->edge_tri_offsets[e + 1] - m->edge_tri_offsets[e];
            if (uses[e] != 1 || on_edge > 2)
                continue;
            assert_true(k < n->boundary_count);
            assert_int_equal(h->bedge[n->boundary_begin + k], half[e]);
            ++k;
        }
        assert_int_equal(k, n->boundary_count);
        listed += k;
    }
    assert_true(listed > 0);
    test_free(uses);
    test_free(half);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);
}

static void test_boundary_lists_match_a_direct_count(void **state) {
    (void)state;
    fixture s, b;
    assert_int_equal(fixture_crumpled(&s, 20, 18, 3, 5.0), 0);
    check_boundary_lists(&s);
    fixture_free(&s);
    assert_int_equal(fixture_holed(&s, 16, 14, 3.0, 2, 1.0), 0);
    check_boundary_lists(&s);
    fixture_free(&s);
    assert_int_equal(fixture_moebius(&s, 48, 4, 6.0, 2.0, 1, 0.1), 0);
    check_boundary_lists(&s);
    fixture_free(&s);
    assert_int_equal(fixture_icosphere(&s, 2, 1.0), 0);
    check_boundary_lists(&s);
    fixture_free(&s);
    make_mixed(&s);
    check_boundary_lists(&s);
    fixture_free(&s);
    assert_int_equal(fixture_sheet_pair(&s, &b, 12, 3, 0.5, 0.0), 0);
    assert_int_equal(fixture_append(&s, &b), 0);
    fixture_free(&b);
    check_boundary_lists(&s);
    fixture_free(&s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_validate_accepts_what_the_build_makes),
        cmocka_unit_test(test_validate_rejects_each_corruption),
        cmocka_unit_test(test_disk_flags_only_on_topological_disks),
        cmocka_unit_test(test_boundary_lists_match_a_direct_count),
    };
    return cmocka_run_group_tests_name("validate", tests, NULL, NULL);
}
