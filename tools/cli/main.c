// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-cli: collisions and self-collisions of triangle meshes from the
// command line. Commands: check (one mesh, two meshes, or a sequence of
// frames of one topology) and info. The command table leaves room for the
// planned `track` command. Uses only the public libselfcol API.
#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { EXIT_CLEAN = 0, EXIT_FOUND = 1, EXIT_ERROR = 2 };
enum { MAX_INPUTS = 4096 };

typedef struct options {
    double distance, distance_rel;
    int distance_given, distance_rel_given;
    uint32_t method, narrow;
    const char *json, *csv, *mark, *png;
    int quiet, fail_on_proximity, no_weld, frames;
    const char *range; /* "FIRST:LAST[:STEP]" for a pattern */
    cli_view view;
    const char *inputs[MAX_INPUTS];
    int input_count;
} options;

static const char *const method_names[] = {"exhaustive", "bvh", "seed", "cone", "exact"};
static const char *const narrow_names[] = {"closed", "libccd"};

static const char check_help[] =
    "usage: selfcol-cli check [options] MESH [MESH2]\n"
    "       selfcol-cli check [options] --frames FRAME...\n"
    "       selfcol-cli check [options] --range FIRST:LAST[:STEP] PATTERN\n"
    "\n"
    "Finds the contacts of a triangle surface with itself (one MESH), or of two\n"
    "surfaces with themselves and each other (MESH MESH2), at a detection distance d:\n"
    "  VF proximities  a vertex closer than d to a triangle (not its own)\n"
    "  EE proximities  two edges closer than d (no common vertex)\n"
    "  EF interferences  an edge crossing a triangle: the surface intersects itself\n"
    "Frames of one topology (--frames, or a printf pattern such as frame_%04d.ply\n"
    "with --range) are checked in turn: the hierarchy is built once and refit per\n"
    "frame; --json then writes one JSON object per frame (JSON Lines).\n"
    "Reads OBJ, PLY (ascii, binary), OFF and STL (ascii, binary). Vertices at\n"
    "exactly the same position are welded (the lowest file index stands for them).\n"
    "\n"
    "options:\n"
    "  --distance D        detection distance in mesh units\n"
    "  --distance-rel K    d = K x mean edge length (default 0.1, a cloth's thickness;\n"
    "                      of the first frame for a sequence, of both meshes together)\n"
    "  --method M          exact (default), bvh, exhaustive: exact methods;\n"
    "                      seed, cone: faster on smooth surfaces, may miss contacts\n"
    "  --narrow N          closed (default: closed forms, exact predicates) or libccd\n"
    "  --json FILE|-       the contact sets as JSON (one line per frame)\n"
    "  --csv FILE|-        one row per contact: frame,kind,i0,i1,i2,i3,distance\n"
    "  --mark OUT.ply      the mesh with intersecting faces red, proximities orange\n"
    "  --png OUT.png       a picture: intersecting triangles red, proximities orange\n"
    "  --view AZ,EL        view angles in degrees for --png (default 35,25; y is up)\n"
    "  --size WxH          picture size in pixels, 16 to 4096 each (default 1024x768)\n"
    "  --fail-on WHAT      interference (default) or proximity: what makes exit status 1\n"
    "  --no-weld           keep vertices as the file has them (no welding)\n"
    "  --quiet             no summary (errors only)\n"
    "  -h, --help          this help\n"
    "For sequences, --mark and --png write every frame when OUT contains %d (as in\n"
    "out_%04d.png), otherwise the last frame.\n"
    "There is no --threads: libselfcol runs on the calling thread and starts none.\n"
    "\n"
    "exit status: 0 no interference, 1 interferences found (or proximities, with\n"
    "--fail-on proximity), 2 usage or input error.\n";

static const char info_help[] =
    "usage: selfcol-cli info [--json FILE|-] [--no-weld] MESH...\n"
    "\n"
    "Describes each mesh: vertices (and how many were welded), triangles, edges,\n"
    "boundary loops, non-manifold edges, degenerate triangles, components, whether\n"
    "it is closed and consistently oriented, and its mean edge length.\n"
    "exit status: 0, or 2 for a usage or input error.\n";

static const char main_help[] =
    "usage: selfcol-cli COMMAND [options] ...\n"
    "\n"
    "commands:\n"
    "  check   find self-contacts and interferences of meshes or frame sequences\n"
    "  info    describe meshes (topology, degeneracies, scale)\n"
    "\n"
    "selfcol-cli COMMAND --help shows a command's options; --version the version.\n";

static int usage_error(const char *command, const char *format, const char *what) {
    fprintf(stderr, "selfcol-cli: ");
    fprintf(stderr, format, what);
    fprintf(stderr, "\nTry 'selfcol-cli %s--help'.\n", command ? command : "");
    return EXIT_ERROR;
}

static int parse_double(const char *text, double *out) {
    char *end;
    errno = 0;
    double x = strtod(text, &end);
    // ERANGE with a finite result is an underflow (1e-320 is a valid,
    // subnormal number); an overflow gives HUGE_VAL, refused as not finite.
    if (end == text || *end != '\0' || (errno != 0 && errno != ERANGE) || !isfinite(x))
        return -1;
    *out = x;
    return 0;
}

static int lookup(const char *name, const char *const *names, int count) {
    for (int i = 0; i < count; ++i)
        if (strcmp(name, names[i]) == 0)
            return i;
    return -1;
}

// ---------------------------------------------------------------------------
// Frame lists: explicit files, or a pattern with one %d (flags 0 and a width
// allowed; %% is a literal %) expanded over FIRST:LAST[:STEP].

// A field width above this is refused (a file name has no use for more).
#define MAX_PATTERN_WIDTH 64

typedef struct pattern {
    char prefix[1024], suffix[1024];
    int zero_pad, width; // width <= MAX_PATTERN_WIDTH
} pattern;

// Copies text into out turning %% into %; fails on any other %.
static int unescape(const char *text, size_t n, char *out, size_t out_size) {
    size_t j = 0;
    for (size_t i = 0; i < n; ++i) {
        if (text[i] == '%') {
            if (i + 1 < n && text[i + 1] == '%')
                ++i;
            else
                return -1;
        }
        if (j + 1 >= out_size)
            return -1;
        out[j++] = text[i];
    }
    out[j] = '\0';
    return 0;
}

// Returns 1 for a valid pattern with one integer conversion, 0 without any %
// conversion, -1 for anything else.
static int parse_pattern(const char *text, pattern *p) {
    const char *conv = NULL;
    for (const char *s = text; *s; ++s) {
        if (*s != '%')
            continue;
        if (s[1] == '%') {
            ++s;
            continue;
        }
        if (conv != NULL)
            return -1; // two conversions
        conv = s;
    }
    if (conv == NULL)
        return 0;
    const char *s = conv + 1;
    p->zero_pad = *s == '0';
    if (p->zero_pad)
        ++s;
    p->width = 0;
    while (*s >= '0' && *s <= '9') {
        p->width = 10 * p->width + (*s++ - '0');
        if (p->width > MAX_PATTERN_WIDTH)
            return -1;
    }
    if (*s != 'd' && *s != 'i' && *s != 'u')
        return -1;
    if (unescape(text, (size_t)(conv - text), p->prefix, sizeof p->prefix) ||
        unescape(s + 1, strlen(s + 1), p->suffix, sizeof p->suffix))
        return -1;
    return 1;
}

// Writes the pattern with value into out; -1 when it does not fit.
static int expand_pattern(const pattern *p, long value, char *out, size_t out_size) {
    char digits[32];
    snprintf(digits, sizeof digits, "%lu",
             value < 0 ? 0ul - (unsigned long)value : (unsigned long)value);
    int length = (int)strlen(digits) + (value < 0);
    int pad = p->width > length ? p->width - length : 0;
    char padding[MAX_PATTERN_WIDTH + 1];
    memset(padding, p->zero_pad ? '0' : ' ', (size_t)pad);
    padding[pad] = '\0';
    int n;
    if (p->zero_pad)
        n = snprintf(out, out_size, "%s%s%s%s%s", p->prefix, value < 0 ? "-" : "", padding, digits,
                     p->suffix);
    else
        n = snprintf(out, out_size, "%s%s%s%s%s", p->prefix, padding, value < 0 ? "-" : "", digits,
                     p->suffix);
    return n >= 0 && (size_t)n < out_size ? 0 : -1;
}

// An output name with %d gets the frame number; otherwise it is used as is
// (parse_options has refused malformed patterns). -1 when it does not fit.
static int output_name(const char *name, long frame, char *out, size_t out_size) {
    pattern p;
    int n;
    if (parse_pattern(name, &p) == 1)
        return expand_pattern(&p, frame, out, out_size);
    n = snprintf(out, out_size, "%s", name);
    return n >= 0 && (size_t)n < out_size ? 0 : -1;
}

// Parses argv[first..]; `--opt value` and `--opt=value` both work.
static int parse_options(int argc, char **argv, int first, const char *command, options *o) {
    memset(o, 0, sizeof *o);
    o->method = SELFCOL_METHOD_EXACT;
    o->narrow = SELFCOL_NARROW_CLOSED_FORM;
    o->distance_rel = 0.1;
    o->view.azimuth = 35.0;
    o->view.elevation = 25.0;
    o->view.width = 1024;
    o->view.height = 768;
    int only_inputs = 0;
    const char *cmd = strcmp(command, "check") == 0 ? "check " : "info ";
    for (int i = first; i < argc; ++i) {
        char *arg = argv[i];
        if (only_inputs || arg[0] != '-' || strcmp(arg, "-") == 0) {
            if (o->input_count == MAX_INPUTS)
                return usage_error(cmd, "too many input files (at most %s)", "4096");
            o->inputs[o->input_count++] = arg;
            continue;
        }
        if (strcmp(arg, "--") == 0) {
            only_inputs = 1;
            continue;
        }
        if (strcmp(arg, "--version") == 0) {
            printf("selfcol-cli %s\n", selfcol_version_string());
            return -1;
        }
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            fputs(strcmp(command, "check") == 0 ? check_help : info_help, stdout);
            return -1; // --help and --version: done, exit 0
        }
        // Split "--name=value".
        char name[64];
        const char *value = NULL;
        const char *eq = strchr(arg, '=');
        size_t name_length = eq ? (size_t)(eq - arg) : strlen(arg);
        if (name_length >= sizeof name)
            return usage_error(cmd, "unknown option '%s'", arg);
        memcpy(name, arg, name_length);
        name[name_length] = '\0';
        static const char *const flags[] = {"--quiet", "--no-weld", "--frames"};
        int is_flag = lookup(name, flags, 3) >= 0;
        if (is_flag && eq)
            return usage_error(cmd, "option '%s' takes no value", name);
        if (!is_flag) {
            if (eq)
                value = eq + 1;
            else if (i + 1 < argc)
                value = argv[++i];
            else
                return usage_error(cmd, "option '%s' needs a value", name);
        }
        int check_only = 1;
        if (strcmp(name, "--quiet") == 0) {
            o->quiet = 1;
            check_only = 0;
        } else if (strcmp(name, "--no-weld") == 0) {
            o->no_weld = 1;
            check_only = 0;
        } else if (strcmp(name, "--json") == 0) {
            o->json = value;
            check_only = 0;
        } else if (strcmp(name, "--frames") == 0) {
            o->frames = 1;
        } else if (strcmp(name, "--range") == 0) {
            o->range = value;
        } else if (strcmp(name, "--distance") == 0) {
            if (parse_double(value, &o->distance) || o->distance < 0)
                return usage_error(cmd, "--distance needs a number >= 0, not '%s'", value);
            o->distance_given = 1;
        } else if (strcmp(name, "--distance-rel") == 0) {
            if (parse_double(value, &o->distance_rel) || o->distance_rel < 0)
                return usage_error(cmd, "--distance-rel needs a number >= 0, not '%s'", value);
            o->distance_rel_given = 1;
        } else if (strcmp(name, "--method") == 0) {
            int m = lookup(value, method_names, 5);
            if (m < 0)
                return usage_error(cmd, "unknown method '%s' (exact, bvh, exhaustive, seed, cone)",
                                   value);
            o->method = (uint32_t)m;
        } else if (strcmp(name, "--narrow") == 0) {
            int m = lookup(value, narrow_names, 2);
            if (m < 0)
                return usage_error(cmd, "unknown narrow phase '%s' (closed, libccd)", value);
            o->narrow = (uint32_t)m;
        } else if (strcmp(name, "--csv") == 0) {
            o->csv = value;
        } else if (strcmp(name, "--mark") == 0) {
            o->mark = value;
        } else if (strcmp(name, "--png") == 0) {
            o->png = value;
        } else if (strcmp(name, "--view") == 0) {
            char *end;
            o->view.azimuth = strtod(value, &end);
            if (end == value || *end != ',')
                return usage_error(cmd, "--view needs AZIMUTH,ELEVATION in degrees, not '%s'",
                                   value);
            const char *second = end + 1;
            o->view.elevation = strtod(second, &end);
            if (end == second || *end != '\0' || !isfinite(o->view.azimuth) ||
                !isfinite(o->view.elevation))
                return usage_error(cmd, "--view needs AZIMUTH,ELEVATION in degrees, not '%s'",
                                   value);
        } else if (strcmp(name, "--size") == 0) {
            int w, h;
            char tail;
            if (sscanf(value, "%dx%d%c", &w, &h, &tail) != 2 || w < 16 || h < 16 || w > 4096 ||
                h > 4096)
                return usage_error(cmd, "--size needs WIDTHxHEIGHT (16 to 4096), not '%s'", value);
            o->view.width = w;
            o->view.height = h;
        } else if (strcmp(name, "--fail-on") == 0) {
            if (strcmp(value, "proximity") == 0)
                o->fail_on_proximity = 1;
            else if (strcmp(value, "interference") == 0)
                o->fail_on_proximity = 0;
            else
                return usage_error(cmd, "--fail-on takes 'interference' or 'proximity', not '%s'",
                                   value);
        } else {
            return usage_error(cmd, "unknown option '%s'", name);
        }
        if (check_only && strcmp(command, "check") != 0)
            return usage_error(cmd, "option '%s' belongs to the check command", name);
    }
    if (o->distance_given && o->distance_rel_given)
        return usage_error(cmd, "give either --distance or --distance-rel, not both%s", "");
    if (o->json && o->csv && strcmp(o->json, "-") == 0 && strcmp(o->csv, "-") == 0)
        return usage_error(cmd, "--json and --csv cannot both write to standard output%s", "");
    // Output names may carry one %d for the frame number; anything else with
    // a % is refused here rather than written under a surprising name.
    const char *named[2] = {o->mark, o->png};
    for (int i = 0; i < 2; ++i) {
        pattern p;
        if (named[i] != NULL && parse_pattern(named[i], &p) < 0)
            return usage_error(cmd,
                               "bad file name pattern '%s': at most one %%d (flag 0, width up "
                               "to 64), and %%%% for a literal %%",
                               named[i]);
    }
    return 0;
}

// ---------------------------------------------------------------------------
// Loading meshes into the library.

static void part_free(cli_part *part) {
    selfcol_hierarchy_destroy(part->hierarchy);
    selfcol_mesh_destroy(part->mesh);
    free(part->welded_triangles);
    cli_mesh_free(&part->file);
    memset(part, 0, sizeof *part);
}

// Welds (unless no_weld) and creates the library mesh: its vertices are the
// file's vertices (duplicates stay, unreferenced), so library indices are
// file indices and each welded group is named by its lowest file index.
static int part_create(cli_part *part, int no_weld, int build_hierarchy, double *seconds_topology,
                       double *seconds_hierarchy, cli_error *err) {
    size_t nv = part->file.vertex_count, nt = part->file.triangle_count;
    part->welded_triangles = malloc(3 * nt * sizeof(uint32_t) + 1);
    uint32_t *representative = malloc(nv * sizeof(uint32_t) + 1);
    if (part->welded_triangles == NULL || representative == NULL) {
        free(representative);
        return cli_fail(err, "%s: out of memory", part->path);
    }
    double start = cli_now();
    if (no_weld) {
        for (size_t v = 0; v < nv; ++v)
            representative[v] = (uint32_t)v;
        part->merged_vertices = 0;
    } else {
        part->merged_vertices = cli_weld(part->file.positions, nv, representative);
        if (part->merged_vertices == (size_t)-1) {
            free(representative);
            return cli_fail(err, "%s: out of memory", part->path);
        }
    }
    for (size_t i = 0; i < 3 * nt; ++i)
        part->welded_triangles[i] = representative[part->file.triangles[i]];
    free(representative);
    int rc = selfcol_mesh_create(&part->mesh, nv, part->file.positions, nt, part->welded_triangles,
                                 NULL);
    double mid = cli_now();
    *seconds_topology += mid - start;
    if (rc == SELFCOL_OK && build_hierarchy)
        rc = selfcol_hierarchy_create(&part->hierarchy, part->mesh, NULL);
    *seconds_hierarchy += cli_now() - mid;
    if (rc != SELFCOL_OK)
        return cli_fail(err, "%s: %s", part->path, selfcol_status_string(rc));
    return 0;
}

static FILE *open_output(const char *path, cli_error *err) {
    if (strcmp(path, "-") == 0)
        return stdout;
    FILE *f = fopen(path, "w");
    if (f == NULL)
        cli_fail(err, "%s: cannot write: %s", path, strerror(errno));
    return f;
}

static int close_output(FILE *f, const char *path, cli_error *err) {
    if (f == NULL)
        return 0;
    int bad = ferror(f);
    if (f == stdout)
        bad |= fflush(f) != 0;
    else
        bad |= fclose(f) != 0;
    return bad ? cli_fail(err, "%s: write error", path) : 0;
}

// Combined geometry of the parts (second mesh's indices after the first's),
// for --png and --mark.
typedef struct scene {
    double *positions;
    uint32_t *triangles;
    size_t vertex_count, triangle_count;
} scene;

static int scene_build(scene *s, cli_part *const *parts, int count) {
    memset(s, 0, sizeof *s);
    for (int i = 0; i < count; ++i) {
        s->vertex_count += parts[i]->file.vertex_count;
        s->triangle_count += parts[i]->file.triangle_count;
    }
    s->positions = malloc(3 * s->vertex_count * sizeof(double) + 1);
    s->triangles = malloc(3 * s->triangle_count * sizeof(uint32_t) + 1);
    if (s->positions == NULL || s->triangles == NULL)
        return -1;
    size_t v = 0, t = 0;
    for (int i = 0; i < count; ++i) {
        const cli_part *p = parts[i];
        memcpy(s->positions + 3 * v, selfcol_mesh_positions(p->mesh),
               3 * p->file.vertex_count * sizeof(double));
        for (size_t j = 0; j < 3 * p->file.triangle_count; ++j)
            s->triangles[3 * t + j] = p->welded_triangles[j] + (uint32_t)v;
        v += p->file.vertex_count;
        t += p->file.triangle_count;
    }
    return 0;
}

static void scene_free(scene *s) {
    free(s->positions);
    free(s->triangles);
}

static int write_pictures(const options *o, long frame, cli_part *const *parts, int count,
                          const unsigned char *classes, cli_error *err) {
    if (o->mark == NULL && o->png == NULL)
        return 0;
    scene s;
    if (scene_build(&s, parts, count) != 0) {
        scene_free(&s);
        return cli_fail(err, "out of memory");
    }
    char path[2048];
    int status = 0;
    if (o->mark != NULL) {
        if (output_name(o->mark, frame, path, sizeof path) != 0) {
            scene_free(&s);
            return cli_fail(err, "--mark: the file name is too long");
        }
        status = cli_write_marked_ply(path, s.positions, s.vertex_count, s.triangles,
                                      s.triangle_count, classes, err);
    }
    if (status == 0 && o->png != NULL) {
        if (output_name(o->png, frame, path, sizeof path) != 0) {
            scene_free(&s);
            return cli_fail(err, "--png: the file name is too long");
        }
        status =
            cli_write_png(path, s.positions, s.triangles, s.triangle_count, classes, &o->view, err);
    }
    scene_free(&s);
    return status;
}

// ---------------------------------------------------------------------------
// check

typedef struct check_state {
    const options *o;
    FILE *json, *csv, *summary;
    selfcol_contacts *contacts;
    cli_sets sets;
    unsigned char *classes;
    selfcol_query_options query;
    cli_run_info info;
    cli_progress *progress; /* cleared before each summary line */
    long frames_checked, frames_intersecting, frames_near;
    cli_array intersecting_frames; /* long: frame numbers with interferences */
    int found;                     /* exit status 1 */
} check_state;

static void print_summary_header(check_state *st, cli_part *const *parts, int count) {
    if (st->summary == NULL)
        return;
    FILE *s = st->summary;
    fprintf(s, "selfcol-cli %s", selfcol_version_string());
    for (int i = 0; i < count; ++i)
        fprintf(s, "  %s", parts[i]->path);
    fputc('\n', s);
    for (int i = 0; i < count; ++i) {
        const cli_part *p = parts[i];
        fprintf(s, "  %s%s %s: %zu vertices (%zu welded), %zu triangles, %zu edges\n",
                count > 1 ? (i == 0 ? "mesh 1, " : "mesh 2, ") : "",
                cli_format_name(p->file.format), p->file.format_detail, p->file.vertex_count,
                p->merged_vertices, p->file.triangle_count,
                selfcol_mesh_count(p->mesh, SELFCOL_MESH_EDGES));
    }
    if (st->info.distance_rel >= 0)
        fprintf(s, "  detection distance d = %g (%g x mean edge length %g)\n", st->info.distance,
                st->info.distance_rel, st->info.mean_edge);
    else
        fprintf(s, "  detection distance d = %g (mean edge length %g)\n", st->info.distance,
                st->info.mean_edge);
    fprintf(s, "  method %s, narrow phase %s\n", st->info.method, st->info.narrow);
}

// Runs the queries of one frame and writes its outputs.
static int check_frame(check_state *st, cli_part *const *parts, int count, long frame,
                       cli_error *err) {
    const options *o = st->o;
    cli_sets_clear(&st->sets);
    size_t triangles = 0;
    for (int i = 0; i < count; ++i)
        triangles += parts[i]->file.triangle_count;
    if (st->classes)
        memset(st->classes, 0, triangles);
    double start = cli_now();
    for (int q = 0; q < (count == 2 ? 3 : 1); ++q) {
        cli_part *pair[2];
        int rc;
        if (q < count) {
            pair[0] = pair[1] = parts[q];
            rc = selfcol_hierarchy_self_collide(parts[q]->hierarchy, st->contacts, &st->query);
        } else {
            pair[0] = parts[0];
            pair[1] = parts[1];
            rc = selfcol_hierarchy_collide(parts[0]->hierarchy, parts[1]->hierarchy, st->contacts,
                                           &st->query);
        }
        if (rc != SELFCOL_OK)
            return cli_fail(err, "query failed: %s", selfcol_status_string(rc));
        if (cli_sets_add(&st->sets, st->contacts, pair, st->classes) != 0)
            return cli_fail(err, "out of memory");
    }
    cli_sets_finish(&st->sets);
    st->info.seconds_query = cli_now() - start;
    st->info.frame = o->frames ? frame : -1;
    if (st->json)
        cli_write_json(st->json, &st->info, &st->sets);
    if (st->csv)
        cli_write_csv(st->csv, o->frames ? frame : 0, &st->sets);
    size_t proximities = st->sets.vf.count + st->sets.ee.count;
    int intersects = st->sets.ef.count > 0;
    st->frames_checked++;
    st->frames_intersecting += intersects;
    if (intersects && cli_array_reserve(&st->intersecting_frames, 1) == 0)
        ((long *)st->intersecting_frames.data)[st->intersecting_frames.count++] = frame;
    st->frames_near += proximities > 0;
    if (intersects || (o->fail_on_proximity && proximities > 0))
        st->found = 1;
    if (st->summary) {
        FILE *s = st->summary;
        cli_progress_end(st->progress);
        if (o->frames)
            fprintf(s, "  frame %ld (%s): ", frame, parts[0]->path);
        else
            fputs("  ", s);
        fprintf(s,
                "VF proximities %zu, EE proximities %zu, EF interferences %zu, intersecting "
                "triangle pairs %zu\n",
                st->sets.vf.count, st->sets.ee.count, st->sets.ef.count, st->sets.tt.count);
        if (!o->frames)
            fprintf(s,
                    "  time: load %.1f ms, topology %.1f ms, hierarchy %.1f ms, query %.1f ms "
                    "(broad %.1f, narrow %.1f)\n",
                    1e3 * st->info.seconds_load, 1e3 * st->info.seconds_topology,
                    1e3 * st->info.seconds_hierarchy, 1e3 * st->info.seconds_query,
                    1e3 * st->sets.stats.broad_seconds, 1e3 * st->sets.stats.narrow_seconds);
    }
    return write_pictures(o, frame, parts, count, st->classes, err);
}

// "frames with interferences: 3, 5-9, 12": runs of consecutive frames of the
// sequence (in --range steps) as FIRST-LAST.
static void print_frame_list(FILE *out, const cli_array *frames, const long *sequence,
                             long sequence_count) {
    const long *f = frames->data;
    if (frames->count == 0)
        return;
    fputs("  frames with interferences:", out);
    size_t i = 0;
    long at = 0; // position of f[i] in the sequence
    while (i < frames->count) {
        while (at < sequence_count && sequence[at] != f[i])
            ++at;
        size_t j = i;
        while (j + 1 < frames->count && at + (long)(j - i) + 1 < sequence_count &&
               sequence[at + (long)(j - i) + 1] == f[j + 1])
            ++j;
        if (j > i)
            fprintf(out, "%s %ld-%ld", i ? "," : "", f[i], f[j]);
        else
            fprintf(out, "%s %ld", i ? "," : "", f[i]);
        at += (long)(j - i) + 1;
        i = j + 1;
    }
    fputc('\n', out);
}

static double combined_mean_edge(cli_part *const *parts, int count) {
    double sum = 0.0, edges = 0.0;
    for (int i = 0; i < count; ++i) {
        double e = (double)selfcol_mesh_count(parts[i]->mesh, SELFCOL_MESH_EDGES);
        sum += e * selfcol_mesh_mean_edge_length(parts[i]->mesh);
        edges += e;
    }
    return edges > 0 ? sum / edges : 0.0;
}

// Builds the list of frame files for --frames / --range.
static int frame_list(const options *o, char ***names_out, long **numbers_out, long *count_out,
                      cli_error *err) {
    *names_out = NULL;
    *numbers_out = NULL;
    *count_out = 0;
    long first = 0, last = -1, step = 1;
    pattern pat;
    if (o->range != NULL) {
        char tail;
        int n = sscanf(o->range, "%ld:%ld%c", &first, &last, &tail);
        if (n == 3 && tail == ':') {
            const char *third = strchr(strchr(o->range, ':') + 1, ':') + 1;
            char *end;
            step = strtol(third, &end, 10);
            if (*end != '\0' || end == third)
                n = 0;
        }
        if (n < 2 || step <= 0 || last < first || (n == 3 && tail != ':') || first < -1000000000L ||
            last > 1000000000L)
            return cli_fail(err, "--range needs FIRST:LAST[:STEP] with FIRST <= LAST, STEP > 0");
        if ((last - first) / step >= 1000000)
            return cli_fail(err, "--range gives too many frames");
        if (o->input_count != 1 || parse_pattern(o->inputs[0], &pat) != 1)
            return cli_fail(err, "--range needs one file name pattern with one %%d conversion "
                                 "(e.g. frame_%%04d.ply)");
    }
    long count = o->range ? (last - first) / step + 1 : o->input_count;
    char **names = calloc((size_t)count + 1, sizeof *names);
    long *numbers = calloc((size_t)count + 1, sizeof *numbers);
    if (names == NULL || numbers == NULL) {
        free(names);
        free(numbers);
        return cli_fail(err, "out of memory");
    }
    for (long i = 0; i < count; ++i) {
        char buffer[2300];
        if (o->range) {
            numbers[i] = first + i * step;
            if (expand_pattern(&pat, numbers[i], buffer, sizeof buffer) != 0) {
                *names_out = names;
                *numbers_out = numbers;
                *count_out = i;
                return cli_fail(err, "--range: the file name for frame %ld is too long",
                                numbers[i]);
            }
        } else {
            numbers[i] = i;
            if (strlen(o->inputs[i]) >= sizeof buffer) {
                *names_out = names;
                *numbers_out = numbers;
                *count_out = i;
                return cli_fail(err, "%.64s...: the file name is too long", o->inputs[i]);
            }
            snprintf(buffer, sizeof buffer, "%s", o->inputs[i]);
        }
        names[i] = malloc(strlen(buffer) + 1);
        if (names[i] == NULL) {
            *names_out = names;
            *numbers_out = numbers;
            *count_out = i;
            return cli_fail(err, "out of memory");
        }
        memcpy(names[i], buffer, strlen(buffer) + 1);
    }
    *names_out = names;
    *numbers_out = numbers;
    *count_out = count;
    return 0;
}

// Positions of a later frame: same vertex count and triangles as frame 0.
static int load_next_frame(cli_part *part, const char *path, cli_progress *progress,
                           size_t *split_groups, cli_error *err) {
    cli_mesh next;
    if (cli_read_mesh(path, &next, err, progress) != 0)
        return -1;
    int status = 0;
    if (next.vertex_count != part->file.vertex_count ||
        next.triangle_count != part->file.triangle_count ||
        memcmp(next.triangles, part->file.triangles, 3 * next.triangle_count * sizeof(uint32_t)))
        status = cli_fail(err,
                          "%s: topology differs from the first frame (%zu vertices, %zu "
                          "triangles; the first frame has %zu and %zu)",
                          path, next.vertex_count, next.triangle_count, part->file.vertex_count,
                          part->file.triangle_count);
    if (status == 0) {
        int rc = selfcol_mesh_set_positions(part->mesh, next.positions, next.vertex_count);
        if (rc != SELFCOL_OK)
            status = cli_fail(err, "%s: %s", path, selfcol_status_string(rc));
    }
    // The weld was decided on the first frame. A welded vertex that moved
    // away from its group's representative is a seam that tore: count them.
    if (status == 0) {
        const uint32_t *file_tris = part->file.triangles;
        for (size_t i = 0; i < 3 * next.triangle_count; ++i) {
            uint32_t v = file_tris[i], r = part->welded_triangles[i];
            if (v != r && memcmp(next.positions + 3 * (size_t)v, next.positions + 3 * (size_t)r,
                                 3 * sizeof(double)) != 0) {
                ++*split_groups;
                break;
            }
        }
    }
    cli_mesh_free(&next);
    return status;
}

// Flushes stdout: 1 when anything written to it was lost (errno says why).
static int stdout_write_failed(void) {
    errno = 0;
    int failed = fflush(stdout) != 0;
    return failed || ferror(stdout);
}

static int command_check(const options *o) {
    cli_error err;
    err.message[0] = '\0';
    int exit_code = EXIT_ERROR;
    if (o->input_count == 0)
        return usage_error("check ", "no mesh given%s", "");
    int sequence = o->frames || o->range != NULL;
    if (!sequence && o->input_count > 2)
        return usage_error("check ",
                           "check takes one or two meshes; for frames of one mesh use --frames "
                           "or --range (got %s)",
                           "more");
    options local = *o;
    local.frames = sequence;
    o = &local;

    cli_progress progress;
    cli_progress_init(&progress, !o->quiet);
    check_state st;
    memset(&st, 0, sizeof st);
    st.o = o;
    st.progress = &progress;
    st.intersecting_frames.item_size = sizeof(long);
    cli_sets_init(&st.sets);
    cli_part parts_storage[2];
    memset(parts_storage, 0, sizeof parts_storage);
    cli_part *parts[2] = {&parts_storage[0], &parts_storage[1]};
    char **frame_names = NULL;
    long *frame_numbers = NULL;
    long frame_count = 0;
    int count = sequence ? 1 : o->input_count;
    const char *files[2] = {NULL, NULL};
    size_t split_frames = 0;

    if (sequence && frame_list(o, &frame_names, &frame_numbers, &frame_count, &err) != 0)
        goto done;
    // Outputs first, so a bad output path fails before a long run.
    int stdout_taken =
        (o->json && strcmp(o->json, "-") == 0) || (o->csv && strcmp(o->csv, "-") == 0);
    st.summary = o->quiet ? NULL : stdout_taken ? stderr : stdout;
    if (o->json && (st.json = open_output(o->json, &err)) == NULL)
        goto done;
    if (o->csv && (st.csv = open_output(o->csv, &err)) == NULL)
        goto done;
    if (st.csv)
        cli_write_csv_header(st.csv);

    double t0 = cli_now();
    for (int i = 0; i < count; ++i) {
        parts[i]->path = sequence ? frame_names[0] : o->inputs[i];
        files[i] = parts[i]->path;
        if (cli_read_mesh(parts[i]->path, &parts[i]->file, &err, &progress) != 0)
            goto done;
    }
    st.info.seconds_load = cli_now() - t0;
    for (int i = 0; i < count; ++i)
        if (part_create(parts[i], o->no_weld, 1, &st.info.seconds_topology,
                        &st.info.seconds_hierarchy, &err) != 0)
            goto done;
    parts[1]->vertex_offset = (uint32_t)parts[0]->file.vertex_count;
    parts[1]->triangle_offset = (uint32_t)parts[0]->file.triangle_count;
    if (count == 2 && (uint64_t)parts[0]->file.vertex_count + parts[1]->file.vertex_count >=
                          (uint64_t)UINT32_MAX - 1) {
        cli_fail(&err, "the two meshes have too many vertices together");
        goto done;
    }

    int rc = selfcol_contacts_create(&st.contacts, NULL);
    if (rc != SELFCOL_OK) {
        cli_fail(&err, "%s", selfcol_status_string(rc));
        goto done;
    }
    selfcol_query_options_init(&st.query, SELFCOL_QUERY_OPTIONS_VERSION);
    st.query.method = o->method;
    st.query.narrow = o->narrow;
    st.info.mean_edge = combined_mean_edge(parts, count);
    st.info.distance_rel = o->distance_given ? -1.0 : o->distance_rel;
    st.info.distance = o->distance_given ? o->distance : o->distance_rel * st.info.mean_edge;
    st.query.distance = st.info.distance;
    if (!(st.info.distance <= SELFCOL_MESH_MAX_COORDINATE)) {
        if (o->distance_given)
            cli_fail(&err, "--distance %g is above the largest the library accepts (%g)",
                     o->distance, SELFCOL_MESH_MAX_COORDINATE);
        else
            cli_fail(&err,
                     "--distance-rel %g x mean edge length %g = %g is above the largest "
                     "distance the library accepts (%g)",
                     o->distance_rel, st.info.mean_edge, st.info.distance,
                     SELFCOL_MESH_MAX_COORDINATE);
        goto done;
    }
    st.info.method = method_names[o->method];
    st.info.narrow = narrow_names[o->narrow];
    st.info.files = files;
    st.info.file_count = count;
    for (int i = 0; i < count; ++i) {
        st.info.vertices += parts[i]->file.vertex_count;
        st.info.triangles += parts[i]->file.triangle_count;
        st.info.edges += selfcol_mesh_count(parts[i]->mesh, SELFCOL_MESH_EDGES);
        st.info.merged_vertices += parts[i]->merged_vertices;
    }
    if (o->mark || o->png) {
        st.classes = malloc(st.info.triangles + 1);
        if (st.classes == NULL) {
            cli_fail(&err, "out of memory");
            goto done;
        }
    }
    print_summary_header(&st, parts, count);

    if (!sequence) {
        if (check_frame(&st, parts, count, 0, &err) != 0)
            goto done;
    } else {
        for (long f = 0; f < frame_count; ++f) {
            if (f > 0) {
                double start = cli_now();
                parts[0]->path = frame_names[f];
                files[0] = frame_names[f];
                if (load_next_frame(parts[0], frame_names[f], &progress, &split_frames, &err))
                    goto done;
                st.info.seconds_load = cli_now() - start;
                start = cli_now();
                rc = selfcol_hierarchy_refit(parts[0]->hierarchy);
                st.info.seconds_refit = cli_now() - start;
                st.info.seconds_topology = st.info.seconds_hierarchy = 0.0;
                if (rc != SELFCOL_OK) {
                    cli_fail(&err, "%s: %s", frame_names[f], selfcol_status_string(rc));
                    goto done;
                }
            }
            cli_progress_update(&progress, "frames", (double)f, (double)frame_count);
            if (check_frame(&st, parts, 1, frame_numbers[f], &err) != 0)
                goto done;
        }
        cli_progress_end(&progress);
        if (st.summary) {
            fprintf(st.summary, "  %ld frame(s): %ld with interferences, %ld with proximities\n",
                    st.frames_checked, st.frames_intersecting, st.frames_near);
            print_frame_list(st.summary, &st.intersecting_frames, frame_numbers, frame_count);
            if (split_frames)
                fprintf(st.summary,
                        "  warning: in %zu frame(s) vertices welded in the first frame have "
                        "moved apart (the weld keeps the first frame's topology)\n",
                        split_frames);
        }
    }
    if (st.summary)
        fprintf(st.summary, "  result: %s (exit status %d)\n",
                st.frames_intersecting ? "INTERSECTS"
                : st.frames_near       ? "no interference, proximities found"
                                       : "clean",
                st.found ? EXIT_FOUND : EXIT_CLEAN);
    if (close_output(st.json, o->json, &err) != 0) {
        st.json = NULL;
        goto done;
    }
    st.json = NULL;
    if (close_output(st.csv, o->csv, &err) != 0) {
        st.csv = NULL;
        goto done;
    }
    st.csv = NULL;
    exit_code = st.found ? EXIT_FOUND : EXIT_CLEAN;
done:
    cli_progress_end(&progress);
    // The summary went to stdout: a full disk or closed pipe there is an
    // error too, not a silent exit status.
    if (exit_code != EXIT_ERROR && stdout_write_failed()) {
        cli_fail(&err, "cannot write to standard output: %s", strerror(errno ? errno : EIO));
        exit_code = EXIT_ERROR;
    }
    if (exit_code == EXIT_ERROR)
        fprintf(stderr, "selfcol-cli: %s\n", err.message);
    if (st.json && st.json != stdout)
        fclose(st.json);
    if (st.csv && st.csv != stdout)
        fclose(st.csv);
    selfcol_contacts_destroy(st.contacts);
    cli_sets_free(&st.sets);
    free(st.intersecting_frames.data);
    free(st.classes);
    part_free(parts[0]);
    part_free(parts[1]);
    for (long i = 0; frame_names && i < frame_count; ++i)
        free(frame_names[i]);
    free(frame_names);
    free(frame_numbers);
    return exit_code;
}

// ---------------------------------------------------------------------------
// info

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

static int command_info(const options *o) {
    if (o->input_count == 0)
        return usage_error("info ", "no mesh given%s", "");
    cli_error err;
    cli_progress progress;
    cli_progress_init(&progress, !o->quiet);
    FILE *json = NULL;
    int exit_code = EXIT_CLEAN;
    if (o->json && (json = open_output(o->json, &err)) == NULL) {
        fprintf(stderr, "selfcol-cli: %s\n", err.message);
        return EXIT_ERROR;
    }
    FILE *s = o->quiet ? NULL : json == stdout ? stderr : stdout;
    for (int i = 0; i < o->input_count && exit_code == EXIT_CLEAN; ++i) {
        cli_part part;
        memset(&part, 0, sizeof part);
        part.path = o->inputs[i];
        double topology = 0.0, hierarchy = 0.0;
        mesh_facts facts;
        if (cli_read_mesh(part.path, &part.file, &err, &progress) != 0 ||
            part_create(&part, o->no_weld, 0, &topology, &hierarchy, &err) != 0) {
            fprintf(stderr, "selfcol-cli: %s\n", err.message);
            exit_code = EXIT_ERROR;
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
                fprintf(s, "%s: %s %s\n", part.path, cli_format_name(part.file.format),
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
                        cli_format_name(part.file.format), part.file.format_detail,
                        part.file.vertex_count, used, part.merged_vertices, part.file.face_count,
                        part.file.triangle_count, ne, boundary, loops, nonmanifold,
                        facts.degenerate, duplicates, components, closed ? "true" : "false",
                        oriented ? "true" : "false", misoriented, mean, facts.lo[0], facts.lo[1],
                        facts.lo[2], facts.hi[0], facts.hi[1], facts.hi[2]);
            }
        }
        part_free(&part);
    }
    if (close_output(json, o->json ? o->json : "", &err) != 0) {
        fprintf(stderr, "selfcol-cli: %s\n", err.message);
        exit_code = EXIT_ERROR;
    } else if (stdout_write_failed()) {
        fprintf(stderr, "selfcol-cli: cannot write to standard output: %s\n",
                strerror(errno ? errno : EIO));
        exit_code = EXIT_ERROR;
    }
    return exit_code;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fputs(main_help, stderr);
        return EXIT_ERROR;
    }
    const char *command = argv[1];
    if (strcmp(command, "--version") == 0 || strcmp(command, "version") == 0) {
        printf("selfcol-cli %s\n", selfcol_version_string());
        return EXIT_CLEAN;
    }
    if (strcmp(command, "-h") == 0 || strcmp(command, "--help") == 0 ||
        strcmp(command, "help") == 0) {
        fputs(main_help, stdout);
        return EXIT_CLEAN;
    }
    options o;
    if (strcmp(command, "check") == 0 || strcmp(command, "info") == 0) {
        int rc = parse_options(argc, argv, 2, command, &o);
        if (rc < 0)
            return EXIT_CLEAN; // --help
        if (rc > 0)
            return rc;
        return strcmp(command, "check") == 0 ? command_check(&o) : command_info(&o);
    }
    return usage_error(NULL, "unknown command '%s' (check, info)", command);
}
