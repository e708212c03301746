// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// From library contacts to the output contract: index arrays in file
// indices (sorted, the second mesh's indices after the first's), with the
// intersecting triangle pairs and the triangles' classes the library derives
// (contacts.h), the JSON and CSV writers, --mark's PLY (written by
// selfcol_meshio), and opening and closing the commands' output files.
#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

void cli_sets_init(cli_sets *sets) {
    memset(sets, 0, sizeof *sets);
    sets->vf.item_size = sets->ee.item_size = sets->ef.item_size = sets->tt.item_size =
        sizeof(cli_item);
    sets->stats.version = SELFCOL_QUERY_STATS_VERSION;
}

void cli_sets_clear(cli_sets *sets) {
    sets->vf.count = sets->ee.count = sets->ef.count = sets->tt.count = 0;
    memset(&sets->stats, 0, sizeof sets->stats);
    sets->stats.version = SELFCOL_QUERY_STATS_VERSION;
}

void cli_sets_free(cli_sets *sets) {
    free(sets->vf.data);
    free(sets->ee.data);
    free(sets->ef.data);
    free(sets->tt.data);
    memset(sets, 0, sizeof *sets);
}

static int push(meshio_array *array, uint32_t k0, uint32_t k1, uint32_t k2, uint32_t k3,
                double distance) {
    if (meshio_array_reserve(array, 1))
        return -1;
    cli_item *item = (cli_item *)array->data + array->count++;
    item->k[0] = k0;
    item->k[1] = k1;
    item->k[2] = k2;
    item->k[3] = k3;
    item->distance = distance;
    return 0;
}

int cli_sets_add(cli_sets *sets, selfcol_contacts *contacts, cli_part *const parts[2],
                 unsigned char *classes) {
    const selfcol_contact *c;
    size_t n;
    if (selfcol_contacts_data(contacts, &c, &n) != SELFCOL_OK)
        return -1;
    selfcol_query_stats stats;
    stats.version = SELFCOL_QUERY_STATS_VERSION;
    if (selfcol_contacts_stats(contacts, &stats) == SELFCOL_OK) {
        selfcol_query_stats *sum = &sets->stats;
        sum->candidate_pairs += stats.candidate_pairs;
        sum->vf_tests += stats.vf_tests;
        sum->ee_tests += stats.ee_tests;
        sum->ef_tests += stats.ef_tests;
        sum->vf_contacts += stats.vf_contacts;
        sum->ee_contacts += stats.ee_contacts;
        sum->ef_contacts += stats.ef_contacts;
        sum->broad_seconds += stats.broad_seconds;
        sum->narrow_seconds += stats.narrow_seconds;
        sum->total_seconds += stats.total_seconds;
        sum->nodes_visited += stats.nodes_visited;
        sum->culled_box += stats.culled_box;
        sum->culled_curvature += stats.culled_curvature;
        sum->culled_adjacency += stats.culled_adjacency;
        sum->triangle_pairs += stats.triangle_pairs;
    }
    for (size_t i = 0; i < n; ++i) {
        const cli_part *pf = parts[c[i].first_mesh ? 1 : 0];
        const cli_part *ps = parts[c[i].second_mesh ? 1 : 0];
        uint32_t vo = pf->vertex_offset, so = ps->vertex_offset;
        uint32_t t = c[i].second + ps->triangle_offset;
        int status = 0;
        if (c[i].kind == SELFCOL_CONTACT_VF) {
            status = push(&sets->vf, c[i].a[0] + vo, t, 0, 0, c[i].distance);
        } else if (c[i].kind == SELFCOL_CONTACT_EE) {
            uint32_t a0 = c[i].a[0] + vo, a1 = c[i].a[1] + vo;
            uint32_t b0 = c[i].b[0] + so, b1 = c[i].b[1] + so;
            if (a0 > a1) {
                uint32_t s = a0;
                a0 = a1;
                a1 = s;
            }
            if (b0 > b1) {
                uint32_t s = b0;
                b0 = b1;
                b1 = s;
            }
            if (b0 < a0 || (b0 == a0 && b1 < a1))
                status = push(&sets->ee, b0, b1, a0, a1, c[i].distance);
            else
                status = push(&sets->ee, a0, a1, b0, b1, c[i].distance);
        } else if (c[i].kind == SELFCOL_CONTACT_EF) {
            uint32_t a0 = c[i].a[0] + vo, a1 = c[i].a[1] + vo;
            status = push(&sets->ef, a0 < a1 ? a0 : a1, a0 < a1 ? a1 : a0, t, 0, 0.0);
        }
        if (status != 0)
            return -1;
    }
    // The intersecting triangle pairs, derived from the EF records by the
    // library (selfcol_contacts_intersecting_triangles), in file indices.
    const uint32_t *pairs;
    size_t pair_count;
    if (selfcol_contacts_intersecting_triangles(contacts, parts[0]->mesh, parts[1]->mesh, &pairs,
                                                &pair_count) != SELFCOL_OK)
        return -1;
    for (size_t k = 0; k < pair_count; ++k) {
        const uint32_t a = pairs[2 * k] + parts[0]->triangle_offset;
        const uint32_t b = pairs[2 * k + 1] + parts[1]->triangle_offset;
        if (push(&sets->tt, a < b ? a : b, a < b ? b : a, 0, 0, 0.0) != 0)
            return -1;
    }
    // The pictures' classes (--mark, --png): the library's marking.
    if (classes != NULL &&
        selfcol_contacts_triangle_classes(contacts, parts[0]->mesh, parts[1]->mesh,
                                          classes + parts[0]->triangle_offset,
                                          classes + parts[1]->triangle_offset) != SELFCOL_OK)
        return -1;
    return 0;
}

static int item_compare(const void *a, const void *b) {
    const cli_item *x = a, *y = b;
    for (int k = 0; k < 4; ++k)
        if (x->k[k] != y->k[k])
            return x->k[k] < y->k[k] ? -1 : 1;
    return 0;
}

static void sort_items(meshio_array *array) {
    if (array->count > 1)
        qsort(array->data, array->count, sizeof(cli_item), item_compare);
}

int cli_sets_finish(cli_sets *sets) {
    sort_items(&sets->vf);
    sort_items(&sets->ee);
    sort_items(&sets->ef);
    sort_items(&sets->tt);
    // A triangle pair appears once per crossing edge: keep one.
    cli_item *tt = sets->tt.data;
    size_t kept = 0;
    for (size_t i = 0; i < sets->tt.count; ++i)
        if (kept == 0 || item_compare(&tt[kept - 1], &tt[i]) != 0)
            tt[kept++] = tt[i];
    sets->tt.count = kept;
    return 0;
}

void cli_json_string(FILE *out, const char *s) {
    fputc('"', out);
    for (const unsigned char *p = (const unsigned char *)s; *p; ++p) {
        if (*p == '"' || *p == '\\')
            fprintf(out, "\\%c", *p);
        else if (*p < 0x20)
            fprintf(out, "\\u%04x", *p);
        else
            fputc(*p, out);
    }
    fputc('"', out);
}

static void json_array(FILE *out, const char *key, const meshio_array *array, int width) {
    fprintf(out, ",\"%s\":[", key);
    const cli_item *items = array->data;
    for (size_t i = 0; i < array->count; ++i) {
        fputs(i ? ",[" : "[", out);
        for (int k = 0; k < width; ++k)
            fprintf(out, k ? ",%u" : "%u", (unsigned)items[i].k[k]);
        fputc(']', out);
    }
    fputc(']', out);
}

void cli_write_json(FILE *out, const cli_run_info *info, const cli_sets *sets) {
    fprintf(out, "{\"selfcol_version\":");
    cli_json_string(out, selfcol_version_string());
    fprintf(out, ",\"files\":[");
    for (int i = 0; i < info->file_count; ++i) {
        if (i)
            fputc(',', out);
        cli_json_string(out, info->files[i]);
    }
    fputc(']', out);
    if (info->frame >= 0)
        fprintf(out, ",\"frame\":%ld", info->frame);
    fprintf(out, ",\"distance\":%.17g", info->distance);
    if (info->distance_rel >= 0)
        fprintf(out, ",\"distance_rel\":%.17g", info->distance_rel);
    fprintf(out, ",\"mean_edge_length\":%.17g,\"method\":\"%s\",\"narrow\":\"%s\"", info->mean_edge,
            info->method, info->narrow);
    fprintf(out, ",\"counts\":{\"vf\":%zu,\"ee\":%zu,\"ef\":%zu,\"intersecting_triangles\":%zu}",
            sets->vf.count, sets->ee.count, sets->ef.count, sets->tt.count);
    json_array(out, "vf", &sets->vf, 2);
    json_array(out, "ee", &sets->ee, 4);
    json_array(out, "ef", &sets->ef, 3);
    json_array(out, "intersecting_triangles", &sets->tt, 2);
    const selfcol_query_stats *s = &sets->stats;
    fprintf(out,
            ",\"stats\":{\"vertices\":%zu,\"welded_vertices\":%zu,\"triangles\":%zu,"
            "\"edges\":%zu,\"candidate_pairs\":%llu,\"triangle_pairs\":%llu,"
            "\"vf_tests\":%llu,\"ee_tests\":%llu,\"ef_tests\":%llu,\"nodes_visited\":%llu,"
            "\"culled_box\":%llu,\"culled_curvature\":%llu,\"culled_adjacency\":%llu,",
            info->vertices, info->merged_vertices, info->triangles, info->edges,
            (unsigned long long)s->candidate_pairs, (unsigned long long)s->triangle_pairs,
            (unsigned long long)s->vf_tests, (unsigned long long)s->ee_tests,
            (unsigned long long)s->ef_tests, (unsigned long long)s->nodes_visited,
            (unsigned long long)s->culled_box, (unsigned long long)s->culled_curvature,
            (unsigned long long)s->culled_adjacency);
    fprintf(out,
            "\"seconds\":{\"load\":%.6f,\"topology\":%.6f,\"hierarchy\":%.6f,\"refit\":%.6f,"
            "\"query\":%.6f,\"broad\":%.6f,\"narrow\":%.6f}}}\n",
            info->seconds_load, info->seconds_topology, info->seconds_hierarchy,
            info->seconds_refit, info->seconds_query, s->broad_seconds, s->narrow_seconds);
}

// check --continuous: a colliding pair as its JSON record.
typedef struct step_record {
    uint32_t k[4]; /* VF: v, t; EE: a0 < a1, b0 < b1, (a0, a1) < (b0, b1) */
    uint32_t flags;
    double toi;
} step_record;

static int step_record_compare(const void *a, const void *b) {
    const step_record *x = a, *y = b;
    for (int k = 0; k < 4; ++k)
        if (x->k[k] != y->k[k])
            return x->k[k] < y->k[k] ? -1 : 1;
    return 0;
}

static void step_records(FILE *out, const char *key, const step_record *records, size_t count,
                         int width) {
    fprintf(out, ",\"%s\":[", key);
    for (size_t i = 0; i < count; ++i) {
        fputs(i ? ",[" : "[", out);
        for (int k = 0; k < width; ++k)
            fprintf(out, "%u,", (unsigned)records[i].k[k]);
        fprintf(out, "%.17g,%u]", records[i].toi, (unsigned)records[i].flags);
    }
    fputc(']', out);
}

// The records of a step's hits, as the JSON and the CSV write them: the VF
// records (v, t) first, then the EE records (a0, a1, b0, b1), each part
// sorted; *vf_count receives the number of VF records. NULL when out of
// memory; the caller frees.
static step_record *step_records_of(const selfcol_sweep_hit *hits, size_t count, size_t *vf_count) {
    step_record *records = malloc(count * sizeof *records + 1);
    if (records == NULL)
        return NULL;
    size_t vf = 0, ee = count; // VF records from the front, EE from the back
    for (size_t i = 0; i < count; ++i) {
        const selfcol_sweep_hit *h = &hits[i];
        step_record r;
        memset(&r, 0, sizeof r);
        r.flags = h->flags;
        r.toi = h->toi;
        if (h->kind == SELFCOL_CONTACT_VF) {
            r.k[0] = h->a[0];
            r.k[1] = h->second;
            records[vf++] = r;
            continue;
        }
        uint32_t a0 = h->a[0] < h->a[1] ? h->a[0] : h->a[1];
        uint32_t a1 = h->a[0] < h->a[1] ? h->a[1] : h->a[0];
        uint32_t b0 = h->b[0] < h->b[1] ? h->b[0] : h->b[1];
        uint32_t b1 = h->b[0] < h->b[1] ? h->b[1] : h->b[0];
        int swap = b0 < a0 || (b0 == a0 && b1 < a1);
        r.k[0] = swap ? b0 : a0;
        r.k[1] = swap ? b1 : a1;
        r.k[2] = swap ? a0 : b0;
        r.k[3] = swap ? a1 : b1;
        records[--ee] = r;
    }
    if (vf > 1)
        qsort(records, vf, sizeof *records, step_record_compare);
    if (count - vf > 1)
        qsort(records + vf, count - vf, sizeof *records, step_record_compare);
    *vf_count = vf;
    return records;
}

int cli_write_step_json(FILE *out, const cli_step_info *info, const selfcol_sweep_hit *hits,
                        size_t count, const selfcol_sweep_query_stats *stats) {
    size_t vf;
    step_record *records = step_records_of(hits, count, &vf);
    if (records == NULL)
        return -1;
    fprintf(out, "{\"selfcol_version\":");
    cli_json_string(out, selfcol_version_string());
    fprintf(out, ",\"files\":[");
    cli_json_string(out, info->from_file);
    fputc(',', out);
    cli_json_string(out, info->to_file);
    fprintf(out, "],\"step\":{\"from\":%ld,\"to\":%ld}", info->from, info->to);
    fprintf(out, ",\"separation\":%.17g,\"method\":\"%s\"", info->separation, info->method);
    fprintf(out, ",\"counts\":{\"vf\":%zu,\"ee\":%zu},\"free_fraction\":%.17g", vf, count - vf,
            stats->free_fraction);
    step_records(out, "vf", records, vf, 2);
    step_records(out, "ee", records + vf, count - vf, 4);
    fprintf(out,
            ",\"stats\":{\"vertices\":%zu,\"welded_vertices\":%zu,\"triangles\":%zu,"
            "\"edges\":%zu,\"candidates\":%llu,\"vf_candidates\":%llu,\"ee_candidates\":%llu,"
            "\"initial\":%llu,\"unresolved\":%llu,",
            info->vertices, info->merged_vertices, info->triangles, info->edges,
            (unsigned long long)stats->candidates, (unsigned long long)stats->vf_candidates,
            (unsigned long long)stats->ee_candidates, (unsigned long long)stats->initial,
            (unsigned long long)stats->unresolved);
    fprintf(out,
            "\"seconds\":{\"load\":%.6f,\"refit\":%.6f,\"query\":%.6f,\"broad\":%.6f,"
            "\"narrow\":%.6f}}}\n",
            info->seconds_load, info->seconds_refit, stats->total_seconds, stats->broad_seconds,
            stats->narrow_seconds);
    free(records);
    return 0;
}

void cli_write_step_csv_header(FILE *out) {
    fputs("step_from,step_to,kind,i0,i1,i2,i3,toi,flags\n", out);
}

int cli_write_step_csv(FILE *out, long from, long to, const selfcol_sweep_hit *hits, size_t count) {
    size_t vf;
    step_record *records = step_records_of(hits, count, &vf);
    if (records == NULL)
        return -1;
    for (size_t i = 0; i < count; ++i) {
        const step_record *r = &records[i];
        if (i < vf)
            fprintf(out, "%ld,%ld,VF,%u,%u,,,", from, to, (unsigned)r->k[0], (unsigned)r->k[1]);
        else
            fprintf(out, "%ld,%ld,EE,%u,%u,%u,%u,", from, to, (unsigned)r->k[0], (unsigned)r->k[1],
                    (unsigned)r->k[2], (unsigned)r->k[3]);
        fprintf(out, "%.17g,%u\n", r->toi, (unsigned)r->flags);
    }
    free(records);
    return 0;
}

void cli_write_csv_header(FILE *out) {
    fputs("frame,kind,i0,i1,i2,i3,distance\n", out);
}

static void csv_rows(FILE *out, long frame, const char *kind, const meshio_array *array, int width,
                     int with_distance) {
    const cli_item *items = array->data;
    for (size_t i = 0; i < array->count; ++i) {
        fprintf(out, "%ld,%s", frame, kind);
        for (int k = 0; k < 4; ++k) {
            if (k < width)
                fprintf(out, ",%u", (unsigned)items[i].k[k]);
            else
                fputc(',', out);
        }
        if (with_distance)
            fprintf(out, ",%.17g\n", items[i].distance);
        else
            fputs(",\n", out);
    }
}

void cli_write_csv(FILE *out, long frame, const cli_sets *sets) {
    csv_rows(out, frame, "vf", &sets->vf, 2, 1);
    csv_rows(out, frame, "ee", &sets->ee, 4, 1);
    csv_rows(out, frame, "ef", &sets->ef, 3, 1);
    csv_rows(out, frame, "tt", &sets->tt, 2, 0);
}

int cli_write_marked_ply(const char *path, const double *positions, size_t vertex_count,
                         const uint32_t *triangles, size_t triangle_count,
                         const unsigned char *classes, cli_error *err) {
    char comment[160];
    snprintf(comment, sizeof comment,
             "selfcol-cli %s: red faces intersect, orange faces are within the detection distance",
             selfcol_version_string());
    return meshio_write_marked_ply(path, positions, vertex_count, triangles, triangle_count,
                                   classes, comment, err);
}

// ---------------------------------------------------------------------------
// Output files of the commands ("-" is standard output).

FILE *cli_open_output(const char *path, cli_error *err) {
    if (strcmp(path, "-") == 0)
        return stdout;
    FILE *f = fopen(path, "w");
    if (f == NULL)
        cli_fail(err, "%s: cannot write: %s", path, strerror(errno));
    return f;
}

int cli_close_output(FILE *f, const char *path, cli_error *err) {
    if (f == NULL)
        return 0;
    int bad = ferror(f);
    if (f == stdout)
        bad |= fflush(f) != 0;
    else
        bad |= fclose(f) != 0;
    return bad ? cli_fail(err, "%s: write error", path) : 0;
}

// Flushes stdout: 1 when anything written to it was lost (errno says why).
int cli_stdout_write_failed(void) {
    errno = 0;
    int failed = fflush(stdout) != 0;
    return failed || ferror(stdout);
}
