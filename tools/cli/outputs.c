// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-cli output files, checked before any frame is read: two outputs
// naming one file would write one over the other, an output naming an input
// would destroy it, and an output that cannot be written would be found only
// after every frame. Each name an output will write is resolved to what it
// names: the file's device and inode when it exists, otherwise the real path
// of its directory and its name (so out.txt and ./out.txt are one file).
#define _XOPEN_SOURCE 700
#include "commands.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

// One name some output (owner >= 0) or input (owner -1) names.
typedef struct named_file {
    char *key;        // what it names: "i DEV INO", "p /real/dir/name" or "s" (stdout)
    const char *name; // as written (points into key's allocation)
    int owner;
} named_file;

typedef struct name_list {
    named_file *items;
    size_t count, capacity;
    char last_dir[PATH_MAX + 1], last_real[PATH_MAX + 1]; // realpath cache
    int last_ok, last_errno;
} name_list;

static int add_name(name_list *list, const char *key, const char *name, int owner) {
    if (list->count == list->capacity) {
        size_t capacity = list->capacity ? 2 * list->capacity : 16;
        named_file *items = realloc(list->items, capacity * sizeof *items);
        if (items == NULL)
            return -1;
        list->items = items;
        list->capacity = capacity;
    }
    size_t key_length = strlen(key), name_length = strlen(name);
    char *copy = malloc(key_length + name_length + 2);
    if (copy == NULL)
        return -1;
    memcpy(copy, key, key_length + 1);
    memcpy(copy + key_length + 1, name, name_length + 1);
    list->items[list->count].key = copy;
    list->items[list->count].name = copy + key_length + 1;
    list->items[list->count].owner = owner;
    list->count++;
    return 0;
}

static void file_key(char *key, size_t size, const struct stat *s) {
    snprintf(key, size, "i %llu %llu", (unsigned long long)s->st_dev,
             (unsigned long long)s->st_ino);
}

// The real path of directory dir (cached: numbered names share theirs).
static int real_directory(name_list *list, const char *dir, const char **real) {
    if (strcmp(dir, list->last_dir) != 0 || list->last_dir[0] == '\0') {
        snprintf(list->last_dir, sizeof list->last_dir, "%s", dir);
        list->last_ok = realpath(dir, list->last_real) != NULL;
        list->last_errno = errno;
        if (list->last_ok && access(list->last_real, W_OK | X_OK) != 0) {
            list->last_ok = 0;
            list->last_errno = errno;
        }
    }
    *real = list->last_real;
    errno = list->last_errno;
    return list->last_ok ? 0 : -1;
}

// Resolves an output's name and checks that it can be written.
static int add_output(name_list *list, const char *option, const char *name, int owner,
                      cli_error *err) {
    char key[2 * PATH_MAX + 64];
    struct stat s;
    if (strcmp(name, "-") == 0) {
        // Standard output: the file it is redirected to, if it is one.
        if (fstat(STDOUT_FILENO, &s) == 0 && S_ISREG(s.st_mode))
            file_key(key, sizeof key, &s);
        else
            snprintf(key, sizeof key, "s");
        return add_name(list, key, name, owner) ? cli_fail(err, "out of memory") : 0;
    }
    if (stat(name, &s) == 0) {
        if (S_ISDIR(s.st_mode))
            return cli_fail(err, "%s: cannot write '%.300s': it is a directory", option, name);
        if (access(name, W_OK) != 0)
            return cli_fail(err, "%s: cannot write '%.300s': %s", option, name, strerror(errno));
        if (!S_ISREG(s.st_mode))
            return 0; // a device or a pipe (/dev/null): outputs may share it
        file_key(key, sizeof key, &s);
        return add_name(list, key, name, owner) ? cli_fail(err, "out of memory") : 0;
    }
    if (errno != ENOENT)
        return cli_fail(err, "%s: cannot write '%.300s': %s", option, name, strerror(errno));
    // A new file: its directory must exist and be writable.
    const char *slash = strrchr(name, '/');
    const char *base = slash ? slash + 1 : name;
    char dir[PATH_MAX + 1];
    if (slash == NULL)
        snprintf(dir, sizeof dir, ".");
    else if (slash == name)
        snprintf(dir, sizeof dir, "/");
    else if ((size_t)(slash - name) < sizeof dir)
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - name), name);
    else
        return cli_fail(err, "%s: cannot write '%.300s': the name is too long", option, name);
    if (*base == '\0')
        return cli_fail(err, "%s: cannot write '%.300s': it names a directory", option, name);
    const char *real;
    if (real_directory(list, dir, &real) != 0)
        return cli_fail(err, "%s: cannot write '%.300s' (directory '%.300s'): %s", option, name,
                        dir, strerror(errno));
    snprintf(key, sizeof key, "p %s/%s", strcmp(real, "/") == 0 ? "" : real, base);
    return add_name(list, key, name, owner) ? cli_fail(err, "out of memory") : 0;
}

static int by_key(const void *a, const void *b) {
    const named_file *x = a, *y = b;
    int c = strcmp(x->key, y->key);
    return c ? c : (x->owner > y->owner) - (x->owner < y->owner);
}

int cli_check_outputs(const char *command, const cli_output_file *outputs, int output_count,
                      const char *const *inputs, long input_count, const long *frames,
                      long frame_count, cli_error *err) {
    name_list *list = calloc(1, sizeof *list);
    if (list == NULL)
        return cli_fail(err, "out of memory");
    int status = 0;
    for (int i = 0; i < output_count && status == 0; ++i) {
        const cli_output_file *out = &outputs[i];
        if (out->name == NULL)
            continue;
        long names = out->numbered && cli_output_is_pattern(out->name) ? frame_count : 1;
        for (long f = 0; f < names && status == 0; ++f) {
            char name[2048];
            if (out->numbered &&
                cli_output_name(out->name, frame_count ? frames[f] : 0, name, sizeof name) != 0)
                break; // too long: the writer says so when it comes to it
            status = add_output(list, out->option, out->numbered ? name : out->name, i, err);
        }
    }
    // Inputs that exist, by device and inode (the readers report the others).
    for (long i = 0; i < input_count && status == 0; ++i) {
        struct stat s;
        char key[64];
        if (stat(inputs[i], &s) != 0 || !S_ISREG(s.st_mode))
            continue;
        file_key(key, sizeof key, &s);
        if (add_name(list, key, inputs[i], -1) != 0)
            status = cli_fail(err, "out of memory");
    }
    if (status == 0 && list->count > 1) {
        qsort(list->items, list->count, sizeof *list->items, by_key);
        for (size_t i = 0; i + 1 < list->count; ++i) {
            const named_file *a = &list->items[i], *b = &list->items[i + 1];
            if (strcmp(a->key, b->key) != 0 || a->owner == b->owner)
                continue;
            if (a->owner < 0)
                status = cli_fail(err,
                                  "%s '%.300s' names the input '%.300s': it would be overwritten"
                                  "\nTry 'selfcol-cli %s--help'.",
                                  outputs[b->owner].option, b->name, a->name, command);
            else if (strcmp(a->name, "-") == 0 || strcmp(b->name, "-") == 0) {
                const named_file *file = strcmp(a->name, "-") == 0 ? b : a;
                const named_file *out = file == a ? b : a;
                status = cli_fail(err,
                                  "%s '%.300s' is the file standard output goes to, which %s - "
                                  "writes\nTry 'selfcol-cli %s--help'.",
                                  outputs[file->owner].option, file->name,
                                  outputs[out->owner].option, command);
            } else
                status = cli_fail(err,
                                  "%s '%.300s' and %s '%.300s' name the same file: one would "
                                  "overwrite the other\nTry 'selfcol-cli %s--help'.",
                                  outputs[a->owner].option, a->name, outputs[b->owner].option,
                                  b->name, command);
            break;
        }
    }
    for (size_t i = 0; i < list->count; ++i)
        free(list->items[i].key);
    free(list->items);
    free(list);
    return status;
}
