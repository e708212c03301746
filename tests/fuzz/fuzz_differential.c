// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Differential fuzzer (libFuzzer): a small mesh decoded from the input --
// vertices on a coarse lattice with optional near-coincident offsets of
// 2^-30, triangles with any indices (repeated, duplicate, non-manifold) --
// a detection distance, then an optional second frame (a refit), and an
// optional second mesh. Every exact method (BVH and EXACT, on one thread and
// on three) must return exactly the exhaustive search's contacts, in the same
// order; any difference aborts. Build and run: tests/fuzz/run.sh.
#include <selfcol/selfcol.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct reader {
    const uint8_t *data;
    size_t size, at;
} reader;

static unsigned next(reader *r) {
    return r->at < r->size ? r->data[r->at++] : 0u;
}

// A coordinate on the lattice k / 4 (k < 16), moved by 0..3 x 2^-30: near
// coincidences and exact coincidences are both common.
static double coordinate(reader *r) {
    unsigned b = next(r);
    return (double)(b & 15u) / 4.0 + (double)((b >> 4) & 3u) * 0x1p-30;
}

typedef struct key {
    uint32_t kind, first_mesh, first, second_mesh, second;
} key;

static size_t keys_of(const selfcol_contacts *c, key **out) {
    const selfcol_contact *x;
    size_t n;
    selfcol_contacts_data(c, &x, &n);
    *out = malloc((n ? n : 1) * sizeof **out);
    if (*out == NULL)
        abort();
    for (size_t i = 0; i < n; ++i)
        (*out)[i] = (key){x[i].kind, x[i].first_mesh, x[i].first, x[i].second_mesh, x[i].second};
    return n;
}

static void query(const selfcol_hierarchy *a, const selfcol_hierarchy *b, selfcol_contacts *c,
                  uint32_t method, double d, unsigned threads) {
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.method = method;
    q.distance = d;
    selfcol_context *context = NULL; // threads > 1: a context's (context.h)
    if (threads > 1) {
        selfcol_context_options co;
        selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
        co.threads = threads;
        if (selfcol_context_create(&context, &co) != SELFCOL_OK)
            abort();
    }
    int rc;
    if (context != NULL)
        rc = b == NULL ? selfcol_context_self_collide(context, a, c, &q)
                       : selfcol_context_collide(context, a, b, c, &q);
    else
        rc = b == NULL ? selfcol_hierarchy_self_collide(a, c, &q)
                       : selfcol_hierarchy_collide(a, b, c, &q);
    selfcol_context_destroy(context);
    if (rc != SELFCOL_OK) {
        fprintf(stderr, "query failed: %s\n", selfcol_status_string(rc));
        abort();
    }
}

// Every exact method against EXHAUSTIVE on the current positions.
static void compare_all(const selfcol_hierarchy *a, const selfcol_hierarchy *b, double d) {
    selfcol_contacts *c = NULL;
    if (selfcol_contacts_create(&c, NULL) != SELFCOL_OK)
        abort();
    query(a, b, c, SELFCOL_METHOD_EXHAUSTIVE, d, 1);
    key *ref;
    size_t n_ref = keys_of(c, &ref);
    const uint32_t methods[2] = {SELFCOL_METHOD_BVH, SELFCOL_METHOD_EXACT};
    for (int m = 0; m < 2; ++m) {
        for (unsigned threads = 1; threads <= 3; threads += 2) {
            query(a, b, c, methods[m], d, threads);
            key *got;
            size_t n = keys_of(c, &got);
            if (n != n_ref || (n > 0 && memcmp(got, ref, n * sizeof *got) != 0)) {
                fprintf(stderr,
                        "method %u on %u thread(s), d = %.17g: %zu contacts, "
                        "EXHAUSTIVE %zu\n",
                        methods[m], threads, d, n, n_ref);
                abort();
            }
            free(got);
        }
    }
    free(ref);
    selfcol_contacts_destroy(c);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    reader r = {data, size, 0};
    const size_t V = 3 + next(&r) % 22, F = 1 + next(&r) % 40;
    const unsigned flags = next(&r);
    const unsigned dbyte = next(&r);
    // d: 0 (crossings only) or up to half a lattice step.
    const double d = dbyte < 64 ? 0.0 : (double)(dbyte % 33u) / 64.0;
    double pos[3 * 24], moved[3 * 24];
    uint32_t tri[3 * 40];
    for (size_t i = 0; i < 3 * V; ++i)
        pos[i] = coordinate(&r);
    for (size_t i = 0; i < 3 * F; ++i)
        tri[i] = next(&r) % (unsigned)V;
    // Two-mesh mode: the triangles split in two meshes over the same vertices.
    const size_t Fa = (flags & 2u) && F >= 2 ? F / 2 : F;
    selfcol_mesh *ma = NULL, *mb = NULL;
    selfcol_hierarchy *ha = NULL, *hb = NULL;
    if (selfcol_mesh_create(&ma, V, pos, Fa, tri, NULL) != SELFCOL_OK ||
        selfcol_hierarchy_create(&ha, ma, NULL) != SELFCOL_OK)
        abort(); // every decoded mesh is valid input
    if (Fa < F && (selfcol_mesh_create(&mb, V, pos, F - Fa, tri + 3 * Fa, NULL) != SELFCOL_OK ||
                   selfcol_hierarchy_create(&hb, mb, NULL) != SELFCOL_OK))
        abort();
    compare_all(ha, NULL, d);
    if (hb != NULL)
        compare_all(ha, hb, d);
    if (flags & 1u) {
        // A second frame: every vertex moved by up to one lattice step.
        for (size_t i = 0; i < 3 * V; ++i)
            moved[i] = pos[i] + ((double)(next(&r) % 9u) - 4.0) / 16.0;
        if (selfcol_mesh_set_positions(ma, moved, V) != SELFCOL_OK ||
            selfcol_hierarchy_refit(ha) != SELFCOL_OK)
            abort();
        compare_all(ha, NULL, d);
        if (hb != NULL) {
            if (selfcol_mesh_set_positions(mb, moved, V) != SELFCOL_OK ||
                selfcol_hierarchy_refit(hb) != SELFCOL_OK)
                abort();
            compare_all(ha, hb, d);
        }
    }
    selfcol_hierarchy_destroy(hb);
    selfcol_hierarchy_destroy(ha);
    selfcol_mesh_destroy(mb);
    selfcol_mesh_destroy(ma);
    return 0;
}
