// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-cli command-line arguments: the options of check and info, the
// usage and help texts, and the file name patterns of frame sequences and
// per-frame outputs.
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

// SELFCOL_MAX_THREADS as text, so the help and the messages follow the library.
#define CLI_TEXT_(x) #x
#define CLI_TEXT(x) CLI_TEXT_(x)
#define CLI_MAX_THREADS_TEXT CLI_TEXT(SELFCOL_MAX_THREADS)

const char *const cli_method_names[] = {"exhaustive", "bvh", "seed", "cone", "exact"};
const char *const cli_narrow_names[] = {"closed", "libccd"};

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
    "  --threads N         threads per query and refit, 1 to " CLI_MAX_THREADS_TEXT
    " (default 1);\n"
    "                      the contacts, counts and outputs do not depend on N,\n"
    "                      only the times do\n"
    "  --no-weld           keep vertices as the file has them (no welding)\n"
    "  --quiet             no summary (errors only)\n"
    "  --frames            the arguments are frames of one mesh\n"
    "  --continuous        for frames: the pairs (VF, EE) that touch at some time of\n"
    "                      each step between consecutive frames, every vertex moving\n"
    "                      on a straight line, with a conservative time of impact\n"
    "                      and the step's collision-free fraction; none is missed\n"
    "                      (include/selfcol/sweep.h). --distance D: within D instead\n"
    "                      of touching (--distance-rel does not apply). --method\n"
    "                      bvh (default here), exact or exhaustive (seed and cone\n"
    "                      have no continuous query); --csv rows are then\n"
    "                      step_from,step_to,kind,i0,i1,i2,i3,toi,flags (the\n"
    "                      indices of the JSON's records), --json\n"
    "                      one object per step (vf, ee: indices, toi, flags);\n"
    "                      --mark and --png are not available\n"
    "  --range FIRST:LAST[:STEP]  frames FIRST, FIRST+STEP, ... <= LAST of PATTERN\n"
    "                      (FIRST, LAST within -1000000000..1000000000, STEP > 0,\n"
    "                      at most 1000000 frames)\n"
    "  -h, --help          this help\n"
    "For sequences, --mark and --png write every frame when OUT contains %d (as in\n"
    "out_%04d.png), otherwise the last frame.\n"
    "Numbers are written without spaces (' 0.1' and '0.1 ' are both refused).\n"
    "Outputs must name different files, none of them an input; they are checked\n"
    "before the first frame is read (a missing directory fails at once). --mark\n"
    "and --png write files only: '-' is refused (./- names a file '-').\n"
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

static const char track_help[] =
    "usage: selfcol-cli track [options] FRAME...\n"
    "       selfcol-cli track [options] --range FIRST:LAST[:STEP] PATTERN\n"
    "\n"
    "Follows the contacts of a sequence of frames of one topology across frames\n"
    "with the persistent contact store (include/selfcol/store.h): per frame, the\n"
    "hierarchy is refit (built on the first frame), the self-contacts are found as\n"
    "check finds them (VF, EE, EF), and the store keeps each contact's side, keeps\n"
    "contacts that part for --remnance updates, notices crossings (flipped) and\n"
    "imposes each region's majority side (corrected). One line per frame:\n"
    "  contacts   VF and EE contacts held (detected, and remnants)\n"
    "  regions    connected groups of contacts; crossed: holding interferences\n"
    "  new, remnant, flipped, corrected (contacts, and regions)\n"
    "  interferences  EF interferences: the surface intersects itself\n"
    "then which frames intersect and the worst (most interferences).\n"
    "Every frame must have the first frame's vertices and triangles.\n"
    "\n"
    "options:\n"
    "  --distance D        detection distance in mesh units\n"
    "  --distance-rel K    d = K x the first frame's mean edge length (default 0.1)\n"
    "  --method M          exact (default), bvh, exhaustive, seed, cone (as check)\n"
    "  --narrow N          closed (default) or libccd\n"
    "  --remnance N        updates a contact stays after it was last detected\n"
    "                      (default 4; 0: none)\n"
    "  --no-consistency    track sides only, no region vote\n"
    "  --threads N         threads per query, refit and store update, 1 to " CLI_MAX_THREADS_TEXT
    " (default 1);\n"
    "                      the contacts, counters and outputs do not depend on N,\n"
    "                      only the times do\n"
    "  --jsonl FILE|-      one JSON object per frame (JSON Lines); with '-' the\n"
    "                      per-frame lines and the summary go to standard error\n"
    "  --png PATTERN       a picture of every frame (PATTERN with %d, as\n"
    "                      out_%04d.png; without %d, the last frame)\n"
    "  --png-worst FILE    a picture of the worst frame only\n"
    "  --view AZ,EL        view angles in degrees for pictures (default 35,25)\n"
    "  --size WxH          picture size in pixels, 16 to 4096 each (default 1024x768)\n"
    "  --no-weld           keep vertices as the file has them (no welding)\n"
    "  --quiet             no per-frame lines or summary (errors only)\n"
    "  -h, --help          this help\n"
    "Pictures: intersecting triangles red, proximities orange (as check).\n"
    "--range: FIRST and LAST within -1000000000..1000000000, STEP > 0, at most\n"
    "1000000 frames. Numbers are written without spaces (' 4' and '4 ' are both\n"
    "refused). Outputs must name different files, none of them a frame; they are\n"
    "checked before the first frame is read (a missing directory fails at once).\n"
    "--png and --png-worst write files only: '-' is refused (./- names a file '-').\n"
    "\n"
    "exit status: 0 no interference in any frame, 1 interferences in some frame,\n"
    "2 usage or input error.\n";

const char cli_main_help[] =
    "usage: selfcol-cli COMMAND [options] ...\n"
    "\n"
    "commands:\n"
    "  check   find self-contacts and interferences of meshes or frame sequences\n"
    "  track   follow contacts across the frames of a sequence (contact store)\n"
    "  info    describe meshes (topology, degeneracies, scale)\n"
    "\n"
    "selfcol-cli COMMAND --help shows a command's options; --version the version.\n";

int cli_usage_error(const char *command, const char *format, const char *what) {
    fprintf(stderr, "selfcol-cli: ");
    fprintf(stderr, format, what);
    fprintf(stderr, "\nTry 'selfcol-cli %s--help'.\n", command ? command : "");
    return CLI_EXIT_ERROR;
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
// (cli_parse_options has refused malformed patterns). -1 when it does not fit.
int cli_output_name(const char *name, long frame, char *out, size_t out_size) {
    pattern p;
    int n;
    if (parse_pattern(name, &p) == 1)
        return expand_pattern(&p, frame, out, out_size);
    n = snprintf(out, out_size, "%s", name);
    return n >= 0 && (size_t)n < out_size ? 0 : -1;
}

int cli_output_is_pattern(const char *name) {
    pattern p;
    return parse_pattern(name, &p) == 1;
}

// Builds the list of frame files for --frames / --range.
int cli_frame_list(const cli_options *o, char ***names_out, long **numbers_out, long *count_out,
                   cli_error *err) {
    *names_out = NULL;
    *numbers_out = NULL;
    *count_out = 0;
    long first = 0, last = -1, step = 1;
    pattern pat;
    if (o->range != NULL) {
        // cli_parse_options has checked the syntax and the limits.
        first = o->range_first;
        last = o->range_last;
        step = o->range_step;
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

// The commands an option belongs to (bits).
enum { FOR_CHECK = 1, FOR_INFO = 2, FOR_TRACK = 4 };

static int parse_remnance(const char *text, uint32_t *out) {
    char *end;
    if (text[0] < '0' || text[0] > '9')
        return -1;
    errno = 0;
    unsigned long long n = strtoull(text, &end, 10);
    if (*end != '\0' || errno != 0 || n > UINT32_MAX)
        return -1;
    *out = (uint32_t)n;
    return 0;
}

// Numbers are written without white space: strtod and sscanf skip it before
// a number but not after one, so ' 0.1' would pass where '0.1 ' does not.
// Every numeric value refuses it anywhere (leading, trailing or inside).
static int has_space(const char *text) {
    for (; *text; ++text)
        if (isspace((unsigned char)*text))
            return 1;
    return 0;
}

// A whole number in [min, max]: an optional sign and digits, nothing else.
// Returns 0, -1 when it is not a whole number, 1 when it is out of range.
static int parse_long(const char *text, size_t length, long min, long max, long *out) {
    char buffer[64];
    if (length == 0 || length >= sizeof buffer)
        return length == 0 ? -1 : 1;
    memcpy(buffer, text, length);
    buffer[length] = '\0';
    const char *digits = buffer + (buffer[0] == '-' || buffer[0] == '+');
    if (*digits < '0' || *digits > '9')
        return -1;
    for (const char *s = digits; *s; ++s)
        if (*s < '0' || *s > '9')
            return -1;
    char *end;
    errno = 0;
    long x = strtol(buffer, &end, 10);
    if (errno == ERANGE || x < min || x > max)
        return 1;
    *out = x;
    return 0;
}

// --range FIRST:LAST[:STEP]: FIRST and LAST within +-CLI_RANGE_LIMIT, STEP >
// 0, at most CLI_RANGE_MAX_FRAMES frames. Returns 0, or a usage error.
static int parse_range(const char *cmd, const char *text, cli_options *o) {
    const char *colon = strchr(text, ':');
    const char *colon2 = colon ? strchr(colon + 1, ':') : NULL;
    long v[3] = {0, 0, 1};
    const char *start[3] = {text, colon ? colon + 1 : NULL, colon2 ? colon2 + 1 : NULL};
    size_t length[3] = {colon ? (size_t)(colon - text) : 0,
                        colon ? (colon2 ? (size_t)(colon2 - colon - 1) : strlen(colon + 1)) : 0,
                        colon2 ? strlen(colon2 + 1) : 0};
    int out_of_range = -1; // which number is out of range
    if (colon == NULL)
        goto syntax;
    for (int k = 0; k < (colon2 ? 3 : 2); ++k) {
        long limit = k < 2 ? CLI_RANGE_LIMIT : LONG_MAX;
        int rc = parse_long(start[k], length[k], k < 2 ? -limit : LONG_MIN, limit, &v[k]);
        if (rc < 0)
            goto syntax;
        if (rc > 0 && out_of_range < 0)
            out_of_range = k;
    }
    if (out_of_range == 2)
        return cli_usage_error(cmd, "--range '%s': STEP is out of range", text);
    if (out_of_range >= 0)
        return cli_usage_error(cmd,
                               "--range '%s': FIRST and LAST must lie within -1000000000 and "
                               "1000000000 (out of range)",
                               text);
    if (v[1] < v[0])
        return cli_usage_error(cmd, "--range '%s' needs FIRST <= LAST", text);
    if (v[2] <= 0)
        return cli_usage_error(cmd, "--range '%s' needs STEP > 0", text);
    if ((v[1] - v[0]) / v[2] >= CLI_RANGE_MAX_FRAMES)
        return cli_usage_error(cmd, "--range '%s' gives too many frames (at most 1000000)", text);
    o->range = text;
    o->range_first = v[0];
    o->range_last = v[1];
    o->range_step = v[2];
    return 0;
syntax:
    return cli_usage_error(cmd, "--range needs FIRST:LAST[:STEP] (whole numbers), not '%s'", text);
}

// The options: which take a value, and the commands they belong to (bits).
typedef struct known_option {
    const char *name;
    int takes_value, belongs;
} known_option;

static const known_option known_options[] = {
    {"--quiet", 0, FOR_CHECK | FOR_INFO | FOR_TRACK},
    {"--no-weld", 0, FOR_CHECK | FOR_INFO | FOR_TRACK},
    {"--frames", 0, FOR_CHECK | FOR_TRACK},
    {"--continuous", 0, FOR_CHECK},
    {"--no-consistency", 0, FOR_TRACK},
    {"--json", 1, FOR_CHECK | FOR_INFO},
    {"--range", 1, FOR_CHECK | FOR_TRACK},
    {"--jsonl", 1, FOR_TRACK},
    {"--png-worst", 1, FOR_TRACK},
    {"--remnance", 1, FOR_TRACK},
    {"--distance", 1, FOR_CHECK | FOR_TRACK},
    {"--distance-rel", 1, FOR_CHECK | FOR_TRACK},
    {"--method", 1, FOR_CHECK | FOR_TRACK},
    {"--narrow", 1, FOR_CHECK | FOR_TRACK},
    {"--csv", 1, FOR_CHECK},
    {"--mark", 1, FOR_CHECK},
    {"--png", 1, FOR_CHECK | FOR_TRACK},
    {"--view", 1, FOR_CHECK | FOR_TRACK},
    {"--size", 1, FOR_CHECK | FOR_TRACK},
    {"--fail-on", 1, FOR_CHECK},
    {"--threads", 1, FOR_CHECK | FOR_TRACK},
};

static const known_option *find_option(const char *name) {
    for (size_t i = 0; i < sizeof known_options / sizeof known_options[0]; ++i)
        if (strcmp(name, known_options[i].name) == 0)
            return &known_options[i];
    return NULL;
}

static void set_defaults(cli_options *o) {
    memset(o, 0, sizeof *o);
    o->method = SELFCOL_METHOD_EXACT;
    o->narrow = SELFCOL_NARROW_CLOSED_FORM;
    o->distance_rel = 0.1;
    o->view.azimuth = 35.0;
    o->view.elevation = 25.0;
    o->view.width = 1024;
    o->view.height = 768;
    o->remnance = SELFCOL_STORE_DEFAULT_REMNANCE;
    o->threads = 1;
}

// Splits argv[*i] ("--name" or "--name=value") into name and value, taking
// the value from the next argument when the option has one and no '='
// (*i then moves past it). The name is checked first: an unknown option, or
// one of another command, is reported as such even when it is the last
// argument. Then the value's form: numbers without spaces, and no '-' for
// options that write files only. Returns 0, or the usage error's status.
static int split_option(const char *cmd, int this_command, int argc, char **argv, int *i,
                        char name[64], const char **value_out) {
    const char *arg = argv[*i];
    const char *value = NULL;
    const char *eq = strchr(arg, '=');
    size_t name_length = eq ? (size_t)(eq - arg) : strlen(arg);
    if (name_length >= 64)
        return cli_usage_error(cmd, "unknown option '%s'", arg);
    memcpy(name, arg, name_length);
    name[name_length] = '\0';
    const known_option *known = find_option(name);
    if (known == NULL)
        return cli_usage_error(cmd, "unknown option '%s'", name);
    if (!(known->belongs & this_command)) {
        char message[160];
        snprintf(message, sizeof message, "option '%s' belongs to the %s command%s", name,
                 known->belongs == FOR_TRACK                ? "track"
                 : known->belongs == FOR_CHECK              ? "check"
                 : known->belongs == (FOR_CHECK | FOR_INFO) ? "check and info"
                                                            : "check and track",
                 known->belongs == FOR_CHECK || known->belongs == FOR_TRACK ? "" : "s");
        return cli_usage_error(cmd, "%s", message);
    }
    if (!known->takes_value && eq)
        return cli_usage_error(cmd, "option '%s' takes no value", name);
    if (known->takes_value) {
        if (eq)
            value = eq + 1;
        else if (*i + 1 < argc)
            value = argv[++*i];
        else
            return cli_usage_error(cmd, "option '%s' needs a value", name);
    }
    static const char *const numeric[] = {"--distance", "--distance-rel", "--remnance", "--view",
                                          "--size",     "--range",        "--threads"};
    if (value != NULL && lookup(name, numeric, 7) >= 0 && has_space(value)) {
        char message[128];
        snprintf(message, sizeof message, "%s takes numbers without spaces, not '%%s'", name);
        return cli_usage_error(cmd, message, value);
    }
    // Pictures and marked meshes go to files only ('-' would be a file
    // named '-' beside JSON or a summary on standard output).
    static const char *const files_only[] = {"--png", "--png-worst", "--mark"};
    if (value != NULL && lookup(name, files_only, 3) >= 0 && strcmp(value, "-") == 0)
        return cli_usage_error(cmd,
                               "%s writes a file, not standard output: give a file name "
                               "(./- for a file named '-')",
                               name);
    *value_out = value;
    return 0;
}

// --threads N: the library refuses counts outside 1..SELFCOL_MAX_THREADS with
// SELFCOL_EINVAL only once a query runs; refusing them here makes them a
// usage error before any file is read.
static int parse_threads(const char *cmd, const char *value, cli_options *o) {
    long n;
    int rc = parse_long(value, strlen(value), 1, SELFCOL_MAX_THREADS, &n);
    if (rc < 0)
        return cli_usage_error(
            cmd,
            "--threads needs a whole number of threads (1 to " CLI_MAX_THREADS_TEXT "), not '%s'",
            value);
    if (rc > 0)
        return cli_usage_error(
            cmd, "--threads '%s' is out of range (1 to " CLI_MAX_THREADS_TEXT ")", value);
    o->threads = (unsigned int)n;
    return 0;
}

// --view AZIMUTH,ELEVATION and --size WIDTHxHEIGHT.
static int parse_view(const char *cmd, const char *name, const char *value, cli_options *o) {
    if (strcmp(name, "--view") == 0) {
        char *end;
        o->view.azimuth = strtod(value, &end);
        if (end == value || *end != ',')
            return cli_usage_error(cmd, "--view needs AZIMUTH,ELEVATION in degrees, not '%s'",
                                   value);
        const char *second = end + 1;
        o->view.elevation = strtod(second, &end);
        if (end == second || *end != '\0' || !isfinite(o->view.azimuth) ||
            !isfinite(o->view.elevation))
            return cli_usage_error(cmd, "--view needs AZIMUTH,ELEVATION in degrees, not '%s'",
                                   value);
        return 0;
    }
    int w, h;
    char tail;
    if (sscanf(value, "%dx%d%c", &w, &h, &tail) != 2 || w < 16 || h < 16 || w > 4096 || h > 4096)
        return cli_usage_error(cmd, "--size needs WIDTHxHEIGHT (16 to 4096), not '%s'", value);
    o->view.width = w;
    o->view.height = h;
    return 0;
}

// The options whose value is a number or a name from a list. Returns 0, or
// the usage error's status.
static int apply_parsed_option(const char *cmd, const char *name, const char *value,
                               cli_options *o) {
    if (strcmp(name, "--range") == 0) {
        if (parse_range(cmd, value, o) != 0)
            return CLI_EXIT_ERROR;
    } else if (strcmp(name, "--remnance") == 0) {
        if (parse_remnance(value, &o->remnance))
            return cli_usage_error(cmd, "--remnance needs a whole number of updates >= 0, not '%s'",
                                   value);
    } else if (strcmp(name, "--threads") == 0) {
        return parse_threads(cmd, value, o);
    } else if (strcmp(name, "--distance") == 0) {
        if (parse_double(value, &o->distance) || o->distance < 0)
            return cli_usage_error(cmd, "--distance needs a number >= 0, not '%s'", value);
        o->distance_given = 1;
    } else if (strcmp(name, "--distance-rel") == 0) {
        if (parse_double(value, &o->distance_rel) || o->distance_rel < 0)
            return cli_usage_error(cmd, "--distance-rel needs a number >= 0, not '%s'", value);
        o->distance_rel_given = 1;
    } else if (strcmp(name, "--method") == 0) {
        int m = lookup(value, cli_method_names, 5);
        if (m < 0)
            return cli_usage_error(cmd, "unknown method '%s' (exact, bvh, exhaustive, seed, cone)",
                                   value);
        o->method = (uint32_t)m;
        o->method_given = 1;
    } else if (strcmp(name, "--narrow") == 0) {
        int m = lookup(value, cli_narrow_names, 2);
        if (m < 0)
            return cli_usage_error(cmd, "unknown narrow phase '%s' (closed, libccd)", value);
        o->narrow = (uint32_t)m;
    } else if (strcmp(name, "--view") == 0 || strcmp(name, "--size") == 0) {
        return parse_view(cmd, name, value, o);
    } else if (strcmp(name, "--fail-on") == 0) {
        if (strcmp(value, "proximity") == 0)
            o->fail_on_proximity = 1;
        else if (strcmp(value, "interference") == 0)
            o->fail_on_proximity = 0;
        else
            return cli_usage_error(cmd, "--fail-on takes 'interference' or 'proximity', not '%s'",
                                   value);
    } else {
        return cli_usage_error(cmd, "unknown option '%s'", name);
    }
    return 0;
}

// Sets what option `name` (with its value, NULL for a flag) says. Returns 0,
// or the usage error's status.
static int apply_option(const char *cmd, const char *name, const char *value, cli_options *o) {
    if (strcmp(name, "--quiet") == 0)
        o->quiet = 1;
    else if (strcmp(name, "--no-weld") == 0)
        o->no_weld = 1;
    else if (strcmp(name, "--frames") == 0)
        o->frames = 1;
    else if (strcmp(name, "--continuous") == 0)
        o->continuous = 1;
    else if (strcmp(name, "--no-consistency") == 0)
        o->no_consistency = 1;
    else if (strcmp(name, "--json") == 0)
        o->json = value;
    else if (strcmp(name, "--jsonl") == 0)
        o->jsonl = value;
    else if (strcmp(name, "--png-worst") == 0)
        o->png_worst = value;
    else if (strcmp(name, "--csv") == 0)
        o->csv = value;
    else if (strcmp(name, "--mark") == 0)
        o->mark = value;
    else if (strcmp(name, "--png") == 0)
        o->png = value;
    else
        return apply_parsed_option(cmd, name, value, o);
    return 0;
}

// What no single option can check: exclusive pairs and output name patterns.
static int check_combinations(const char *cmd, const cli_options *o) {
    if (o->distance_given && o->distance_rel_given)
        return cli_usage_error(cmd, "give either --distance or --distance-rel, not both%s", "");
    if (o->json && o->csv && strcmp(o->json, "-") == 0 && strcmp(o->csv, "-") == 0)
        return cli_usage_error(cmd, "--json and --csv cannot both write to standard output%s", "");
    // Output names may carry one %d for the frame number; anything else with
    // a % is refused here rather than written under a surprising name.
    const char *named[3] = {o->mark, o->png, o->png_worst};
    for (int i = 0; i < 3; ++i) {
        pattern p;
        if (named[i] != NULL && parse_pattern(named[i], &p) < 0)
            return cli_usage_error(cmd,
                                   "bad file name pattern '%s': at most one %%d (flag 0, width up "
                                   "to 64), and %%%% for a literal %%",
                                   named[i]);
    }
    return 0;
}

// Parses argv[first..]; `--opt value` and `--opt=value` both work.
int cli_parse_options(int argc, char **argv, int first, const char *command, cli_options *o) {
    set_defaults(o);
    int only_inputs = 0;
    const int this_command = strcmp(command, "check") == 0   ? FOR_CHECK
                             : strcmp(command, "track") == 0 ? FOR_TRACK
                                                             : FOR_INFO;
    const char *cmd = this_command == FOR_CHECK   ? "check "
                      : this_command == FOR_TRACK ? "track "
                                                  : "info ";
    for (int i = first; i < argc; ++i) {
        char *arg = argv[i];
        if (only_inputs || arg[0] != '-' || strcmp(arg, "-") == 0) {
            if (o->input_count == CLI_MAX_INPUTS)
                return cli_usage_error(cmd, "too many input files (at most %s)", "4096");
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
            fputs(this_command == FOR_CHECK   ? check_help
                  : this_command == FOR_TRACK ? track_help
                                              : info_help,
                  stdout);
            return -1; // --help and --version: done, exit 0
        }
        char name[64];
        const char *value = NULL;
        int rc = split_option(cmd, this_command, argc, argv, &i, name, &value);
        if (rc == 0)
            rc = apply_option(cmd, name, value, o);
        if (rc != 0)
            return rc;
    }
    return check_combinations(cmd, o);
}
