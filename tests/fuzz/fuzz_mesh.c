// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Mesh-constructor fuzzer (libFuzzer): arbitrary counts, indices and raw
// double (or float, with a stride) positions -- NaN, infinities, huge and
// subnormal values, out-of-range indices. selfcol_mesh_create must answer
// with a status, never crash or leak; a mesh it accepts must be usable
// (topology counts consistent, hierarchy built, EXACT == EXHAUSTIVE at d=0).
// Build and run: tests/fuzz/run.sh.
#include <selfcol/selfcol.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 4)
        return 0;
    const size_t V = data[0] % 17, F = data[1] % 17;
    const int use_float = data[2] & 1;
    const size_t stride = 3 + (size_t)((data[2] >> 1) & 3); // floats per vertex
    data += 4;
    size -= 4;
    double pos[3 * 16];
    float fpos[7 * 16];
    uint32_t tri[3 * 16];
    memset(pos, 0, sizeof pos);
    memset(fpos, 0, sizeof fpos);
    memset(tri, 0, sizeof tri);
    size_t take = size < sizeof pos ? size : sizeof pos;
    if (use_float) {
        take = size < sizeof fpos ? size : sizeof fpos;
        memcpy(fpos, data, take);
    } else {
        memcpy(pos, data, take);
    }
    data += take;
    size -= take;
    for (size_t i = 0; i < 3 * F && size > 0; ++i, --size, ++data)
        tri[i] = data[0] < 250 ? data[0] % 20u : UINT32_MAX - data[0] % 4u;
    selfcol_mesh *m = NULL;
    int rc = use_float
                 ? selfcol_mesh_create_float(&m, V, fpos, stride * sizeof(float), F, tri, NULL)
                 : selfcol_mesh_create(&m, V, pos, F, tri, NULL);
    if (rc != SELFCOL_OK) {
        if (m != NULL || selfcol_status_string(rc) == NULL)
            abort();
        return 0;
    }
    if (selfcol_mesh_count(m, SELFCOL_MESH_TRIANGLES) != F ||
        selfcol_mesh_count(m, SELFCOL_MESH_VERTICES) != V)
        abort();
    selfcol_hierarchy *h = NULL;
    selfcol_contacts *c = NULL;
    if (selfcol_hierarchy_create(&h, m, NULL) != SELFCOL_OK ||
        selfcol_contacts_create(&c, NULL) != SELFCOL_OK)
        abort();
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.method = SELFCOL_METHOD_EXHAUSTIVE;
    if (selfcol_hierarchy_self_collide(h, c, &q) != SELFCOL_OK)
        abort();
    size_t n_ref = selfcol_contacts_count(c);
    selfcol_contact *ref = malloc((n_ref ? n_ref : 1) * sizeof *ref);
    if (ref == NULL)
        abort();
    const selfcol_contact *x;
    size_t n;
    selfcol_contacts_data(c, &x, &n);
    if (n > 0)
        memcpy(ref, x, n * sizeof *x);
    q.method = SELFCOL_METHOD_EXACT;
    if (selfcol_hierarchy_self_collide(h, c, &q) != SELFCOL_OK)
        abort();
    selfcol_contacts_data(c, &x, &n);
    if (n != n_ref)
        abort();
    for (size_t i = 0; i < n; ++i)
        if (x[i].kind != ref[i].kind || x[i].first != ref[i].first || x[i].second != ref[i].second)
            abort();
    free(ref);
    selfcol_contacts_destroy(c);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);
    return 0;
}
