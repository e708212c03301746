// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Error messages, the clock, progress on a terminal, and loading a mesh file
// through selfcol_meshio with that progress drawn.
#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <time.h>
#include <unistd.h>

double cli_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void cli_progress_init(cli_progress *progress, int enabled) {
    progress->enabled = enabled && isatty(STDERR_FILENO);
    progress->last_draw = 0.0;
    progress->drawn = 0;
    progress->label = NULL;
}

void cli_progress_update(cli_progress *progress, const char *label, double done, double total) {
    if (progress == NULL || !progress->enabled || total <= 0.0)
        return;
    double now = cli_now();
    // Redraw at most ten times a second: a terminal write per record would
    // cost more than the parsing it reports.
    if (progress->drawn && now - progress->last_draw < 0.1 && done < total)
        return;
    progress->last_draw = now;
    double fraction = done / total;
    if (fraction > 1.0)
        fraction = 1.0;
    enum { width = 30 };
    char bar[width + 1];
    int filled = (int)(fraction * width);
    for (int i = 0; i < width; ++i)
        bar[i] = i < filled ? '#' : ' ';
    bar[width] = '\0';
    fprintf(stderr, "\r%-40.40s [%s] %3d%%", label, bar, (int)(100.0 * fraction));
    fflush(stderr);
    progress->drawn = 1;
}

void cli_progress_end(cli_progress *progress) {
    if (progress == NULL || !progress->drawn)
        return;
    fprintf(stderr, "\r%80s\r", "");
    fflush(stderr);
    progress->drawn = 0;
}

// The reader's progress callback: context is the cli_progress.
static void draw_progress(void *context, const char *label, double done, double total) {
    cli_progress_update(context, label, done, total);
}

int cli_read_mesh(const char *path, meshio_mesh *mesh, cli_error *err, cli_progress *progress) {
    meshio_progress report = {draw_progress, progress};
    int status = meshio_read(path, mesh, err, &report);
    cli_progress_end(progress);
    return status;
}
