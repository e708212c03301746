// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The consumer every packaging door builds (tests/consumer/run.sh): a
// hand-made mesh with known contacts, a hierarchy, a self query, and the
// counts checked. Exits 0 when everything matches, 1 otherwise.
//
// The mesh: triangle 0 lies in the plane z = 0; triangle 1 stands through it
// (two of its edges cross triangle 0 inside: 2 EF interferences); triangle 2
// hangs above triangle 0 with one corner 0.1 above its inside (1 VF
// proximity at d = 0.25) and every other element farther than d.
#include <selfcol/selfcol.h>

#include <stdio.h>

#if defined(SELFCOL_EXPECT_STATIC) && !defined(SELFCOL_STATIC)
#error "a static libselfcol must bring SELFCOL_STATIC to its consumers"
#endif
#if defined(SELFCOL_EXPECT_SHARED) && defined(SELFCOL_STATIC)
#error "a shared libselfcol must not define SELFCOL_STATIC for its consumers"
#endif

int main(void) {
    // clang-format off
    static const double xyz[] = {
        0.0, 0.0,  0.0,   4.0, 0.0, 0.0,   0.0, 4.0, 0.0,  // triangle 0, z = 0
        1.0, 1.0, -1.0,   1.0, 1.0, 1.0,   2.0, 0.5, 1.0,  // triangle 1, through it
        3.0, 0.5,  0.1,   3.5, 0.5, 1.0,   3.0, 1.0, 1.0}; // triangle 2, a corner above it
    // clang-format on
    static const uint32_t triangles[] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    static const size_t expected[3] = {1, 0, 2}; // VF, EE, EF

    if (selfcol_version_number() != SELFCOL_VERSION_NUMBER) {
        fprintf(stderr, "consumer: headers %s, library %s\n", SELFCOL_VERSION_STRING,
                selfcol_version_string());
        return 1;
    }
    selfcol_mesh *mesh = NULL;
    selfcol_hierarchy *hierarchy = NULL;
    selfcol_contacts *contacts = NULL;
    selfcol_context *context = NULL;
    int rc = selfcol_mesh_create(&mesh, 9, xyz, 3, triangles, NULL);
    if (rc == SELFCOL_OK)
        rc = selfcol_hierarchy_create(&hierarchy, mesh, NULL);
    if (rc == SELFCOL_OK)
        rc = selfcol_contacts_create(&contacts, NULL);
    selfcol_query_options opts;
    if (rc == SELFCOL_OK)
        rc = selfcol_query_options_init(&opts, SELFCOL_QUERY_OPTIONS_VERSION);
    selfcol_context_options co;
    if (rc == SELFCOL_OK)
        rc = selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    if (rc == SELFCOL_OK) {
        co.threads = 2; // the static library's pthread dependency, used
        rc = selfcol_context_create(&context, &co);
    }
    if (rc == SELFCOL_OK) {
        opts.distance = 0.25;
        rc = selfcol_context_self_collide(context, hierarchy, contacts, &opts);
    }
    size_t found[3] = {0, 0, 0};
    if (rc == SELFCOL_OK) {
        const selfcol_contact *c = NULL;
        size_t n = 0;
        rc = selfcol_contacts_data(contacts, &c, &n);
        for (size_t i = 0; rc == SELFCOL_OK && i < n; ++i)
            if (c[i].kind <= SELFCOL_CONTACT_EF)
                found[c[i].kind]++;
    }
    selfcol_context_destroy(context);
    selfcol_contacts_destroy(contacts);
    selfcol_hierarchy_destroy(hierarchy);
    selfcol_mesh_destroy(mesh);
    if (rc != SELFCOL_OK) {
        fprintf(stderr, "consumer: %s\n", selfcol_status_string(rc));
        return 1;
    }
    printf("consumer: selfcol %s: VF %zu, EE %zu, EF %zu\n", selfcol_version_string(), found[0],
           found[1], found[2]);
    for (int k = 0; k < 3; ++k)
        if (found[k] != expected[k]) {
            fprintf(stderr, "consumer: expected VF %zu, EE %zu, EF %zu\n", expected[0], expected[1],
                    expected[2]);
            return 1;
        }
    return 0;
}
