// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT
// The C side of python/bench/overhead.py: per-call times of the same
// queries the Python benchmark times, on the same input.
// usage: overhead_c POSITIONS.f64 TRIANGLES.u32 VERTICES TRIANGLES DISTANCE REPS
// Prints three lines "name seconds_per_call": query (reused contacts), query
// with a fresh contacts handle, and mesh + hierarchy + query + destroy.
#include <selfcol/selfcol.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *slurp(const char *path, size_t bytes) {
    FILE *f = fopen(path, "rb");
    void *p = malloc(bytes);
    if (!f || !p || fread(p, 1, bytes, f) != bytes) {
        fprintf(stderr, "cannot read %s\n", path);
        exit(2);
    }
    fclose(f);
    return p;
}

int main(int argc, char **argv) {
    if (argc != 7) {
        fprintf(stderr, "usage: overhead_c V.f64 F.u32 NV NF DISTANCE REPS\n");
        return 2;
    }
    size_t nv = strtoul(argv[3], NULL, 10), nf = strtoul(argv[4], NULL, 10);
    double *pos = slurp(argv[1], nv * 3 * sizeof(double));
    uint32_t *tri = slurp(argv[2], nf * 3 * sizeof(uint32_t));
    selfcol_query_options opts;
    selfcol_query_options_init(&opts, SELFCOL_QUERY_OPTIONS_VERSION);
    opts.distance = strtod(argv[5], NULL);
    long reps = strtol(argv[6], NULL, 10);

    selfcol_mesh *mesh = NULL;
    selfcol_hierarchy *h = NULL;
    selfcol_contacts *c = NULL;
    if (selfcol_mesh_create(&mesh, nv, pos, nf, tri, NULL) ||
        selfcol_hierarchy_create(&h, mesh, NULL) || selfcol_contacts_create(&c, NULL))
        return 1;
    double t = now();
    for (long i = 0; i < reps; ++i)
        selfcol_hierarchy_self_collide(h, c, &opts);
    printf("query_reused %.9g %zu\n", (now() - t) / (double)reps, selfcol_contacts_count(c));
    t = now();
    for (long i = 0; i < reps; ++i) {
        selfcol_contacts *fresh = NULL;
        selfcol_contacts_create(&fresh, NULL);
        selfcol_hierarchy_self_collide(h, fresh, &opts);
        selfcol_contacts_destroy(fresh);
    }
    printf("query_fresh %.9g\n", (now() - t) / (double)reps);
    t = now();
    for (long i = 0; i < reps; ++i) {
        selfcol_mesh *m = NULL;
        selfcol_hierarchy *hh = NULL;
        selfcol_contacts *cc = NULL;
        selfcol_mesh_create(&m, nv, pos, nf, tri, NULL);
        selfcol_hierarchy_create(&hh, m, NULL);
        selfcol_contacts_create(&cc, NULL);
        selfcol_hierarchy_self_collide(hh, cc, &opts);
        selfcol_contacts_destroy(cc);
        selfcol_hierarchy_destroy(hh);
        selfcol_mesh_destroy(m);
    }
    printf("one_call %.9g\n", (now() - t) / (double)reps);
    selfcol_contacts_destroy(c);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(mesh);
    free(pos);
    free(tri);
    return 0;
}
