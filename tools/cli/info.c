// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-cli info: describes each mesh (topology, degeneracies, scale).
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <errno.h>
#include <math.h>
#include <string.h>

// What info reports beyond the library's counts: degenerate triangles (a
// repeated index or exactly zero area) and the bounding box of the used
// vertices. Boundary loops and orientation come from selfcol_mesh_count().
typedef struct mesh_facts {
    size_t degenerate;
    double lo[3], hi[3];
} mesh_facts;

static void gather_facts(const cli_part *part, mesh_facts *facts) {
    const selfcol_mesh *mesh = part->mesh;
    const size_t nt = part->file.triangle_count;
    const uint32_t *tris = selfcol_mesh_triangles(mesh);
    const double *p = selfcol_mesh_positions(mesh);
    memset(facts, 0, sizeof *facts);
    for (int k = 0; k < 3; ++k) {
        facts->lo[k] = INFINITY;
        facts->hi[k] = -INFINITY;
    }
    for (size_t t = 0; t < nt; ++t) {
        if (selfcol_mesh_triangle_flags(mesh, (uint32_t)t) &
            (SELFCOL_TRIANGLE_REPEATED_INDEX | SELFCOL_TRIANGLE_ZERO_AREA))
            facts->degenerate++;
        for (size_t i = 3 * t; i < 3 * t + 3; ++i)
            for (int k = 0; k < 3; ++k) {
                double x = p[3 * (size_t)tris[i] + (size_t)k];
                facts->lo[k] = fmin(facts->lo[k], x);
                facts->hi[k] = fmax(facts->hi[k], x);
            }
    }
}

int cli_command_info(const cli_options *o) {
    if (o->input_count == 0)
        return cli_usage_error("info ", "no mesh given%s", "");
    cli_error err;
    cli_progress progress;
    cli_progress_init(&progress, !o->quiet);
    FILE *json = NULL;
    int exit_code = CLI_EXIT_CLEAN;
    const cli_output_file output = {"--json", o->json, 0};
    if (cli_check_outputs("info ", &output, 1, o->inputs, o->input_count, NULL, 0, &err) != 0 ||
        (o->json && (json = cli_open_output(o->json, &err)) == NULL)) {
        fprintf(stderr, "selfcol-cli: %s\n", err.message);
        return CLI_EXIT_ERROR;
    }
    FILE *s = o->quiet ? NULL : json == stdout ? stderr : stdout;
    for (int i = 0; i < o->input_count && exit_code == CLI_EXIT_CLEAN; ++i) {
        cli_part part;
        memset(&part, 0, sizeof part);
        part.path = o->inputs[i];
        double topology = 0.0, hierarchy = 0.0;
        mesh_facts facts;
        if (cli_read_mesh(part.path, &part.file, &err, &progress) != 0 ||
            cli_part_create(&part, o->no_weld, 0, NULL, &topology, &hierarchy, &err) != 0) {
            fprintf(stderr, "selfcol-cli: %s\n", err.message);
            exit_code = CLI_EXIT_ERROR;
        } else {
            gather_facts(&part, &facts);
            const selfcol_mesh *m = part.mesh;
            size_t boundary = selfcol_mesh_count(m, SELFCOL_MESH_BOUNDARY_EDGES);
            size_t nonmanifold = selfcol_mesh_count(m, SELFCOL_MESH_NONMANIFOLD_EDGES);
            size_t unreferenced = selfcol_mesh_count(m, SELFCOL_MESH_UNREFERENCED_VERTICES);
            size_t used = part.file.vertex_count - unreferenced;
            int closed = boundary == 0;
            size_t loops = selfcol_mesh_count(m, SELFCOL_MESH_BOUNDARY_LOOPS);
            size_t misoriented = selfcol_mesh_count(m, SELFCOL_MESH_MISORIENTED_EDGES);
            int oriented = misoriented == 0;
            size_t ne = selfcol_mesh_count(m, SELFCOL_MESH_EDGES);
            size_t duplicates = selfcol_mesh_count(m, SELFCOL_MESH_DUPLICATE_TRIANGLES);
            size_t components = selfcol_mesh_count(m, SELFCOL_MESH_COMPONENTS);
            double mean = selfcol_mesh_mean_edge_length(m);
            if (s) {
                fprintf(s, "%s: %s %s\n", part.path, meshio_format_name(part.file.format),
                        part.file.format_detail);
                fprintf(s,
                        "  vertices            %zu in the file, %zu used after welding (%zu "
                        "welded)\n",
                        part.file.vertex_count, used, part.merged_vertices);
                fprintf(s, "  triangles           %zu (from %zu faces)\n", part.file.triangle_count,
                        part.file.face_count);
                fprintf(s, "  edges               %zu (%zu boundary, %zu non-manifold)\n", ne,
                        boundary, nonmanifold);
                fprintf(s, "  boundary loops      %zu\n", loops);
                fprintf(s,
                        "  degenerate          %zu triangles (zero area or repeated index), "
                        "%zu duplicates\n",
                        facts.degenerate, duplicates);
                fprintf(s, "  components          %zu\n", components);
                fprintf(s, "  closed              %s\n", closed ? "yes" : "no");
                fprintf(s, "  oriented            %s", oriented ? "yes, consistently\n" : "no");
                if (!oriented)
                    fprintf(s, " (%zu edges traversed twice in the same direction)\n", misoriented);
                fprintf(s, "  mean edge length    %g\n", mean);
                fprintf(s, "  bounding box        [%g %g %g] - [%g %g %g]\n", facts.lo[0],
                        facts.lo[1], facts.lo[2], facts.hi[0], facts.hi[1], facts.hi[2]);
            }
            if (json) {
                fprintf(json, "{\"file\":");
                cli_json_string(json, part.path);
                fprintf(json,
                        ",\"format\":\"%s\",\"encoding\":\"%s\",\"vertices\":%zu,"
                        "\"used_vertices\":%zu,\"welded_vertices\":%zu,\"faces\":%zu,"
                        "\"triangles\":%zu,\"edges\":%zu,\"boundary_edges\":%zu,"
                        "\"boundary_loops\":%zu,\"nonmanifold_edges\":%zu,"
                        "\"degenerate_triangles\":%zu,\"duplicate_triangles\":%zu,"
                        "\"components\":%zu,\"closed\":%s,\"consistently_oriented\":%s,"
                        "\"misoriented_edges\":%zu,"
                        "\"mean_edge_length\":%.17g,\"bbox\":[[%.17g,%.17g,%.17g],"
                        "[%.17g,%.17g,%.17g]]}\n",
                        meshio_format_name(part.file.format), part.file.format_detail,
                        part.file.vertex_count, used, part.merged_vertices, part.file.face_count,
                        part.file.triangle_count, ne, boundary, loops, nonmanifold,
                        facts.degenerate, duplicates, components, closed ? "true" : "false",
                        oriented ? "true" : "false", misoriented, mean, facts.lo[0], facts.lo[1],
                        facts.lo[2], facts.hi[0], facts.hi[1], facts.hi[2]);
            }
        }
        cli_part_free(&part);
    }
    if (cli_close_output(json, o->json ? o->json : "", &err) != 0) {
        fprintf(stderr, "selfcol-cli: %s\n", err.message);
        exit_code = CLI_EXIT_ERROR;
    } else if (cli_stdout_write_failed()) {
        fprintf(stderr, "selfcol-cli: cannot write to standard output: %s\n",
                strerror(errno ? errno : EIO));
        exit_code = CLI_EXIT_ERROR;
    }
    return exit_code;
}
