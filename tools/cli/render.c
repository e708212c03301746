// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// --png: the picture's pixels from tools/meshio (meshio_render_rgb, shared
// with Python's Contacts.render), written out with libpng.
#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <errno.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

typedef struct png_message {
    char text[200];
} png_message;

static void png_error_kept(png_structp png, png_const_charp text) {
    png_message *m = png_get_error_ptr(png);
    snprintf(m->text, sizeof m->text, "%s", text);
    png_longjmp(png, 1);
}

static void png_warning_dropped(png_structp png, png_const_charp text) {
    (void)png;
    (void)text;
}

static int write_png_file(const char *path, const unsigned char *pixels, int width, int height,
                          cli_error *err) {
    FILE *f = fopen(path, "wb");
    if (f == NULL)
        return cli_fail(err, "%s: cannot write: %s", path, strerror(errno));
    // libpng's own handlers print to stderr; ours keep its message for the
    // CLI's single error line.
    png_message message = {""};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &message, png_error_kept,
                                              png_warning_dropped);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    png_bytep *rows = malloc((size_t)height * sizeof *rows);
    // volatile: modified between setjmp and a possible longjmp from libpng.
    volatile int status = -1;
    if (png != NULL && info != NULL && rows != NULL) {
        if (setjmp(png_jmpbuf(png)) == 0) {
            png_init_io(png, f);
            png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB,
                         PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
            for (int y = 0; y < height; ++y)
                rows[y] = (png_bytep)(pixels + (size_t)y * (size_t)width * 3);
            png_write_info(png, info);
            png_write_image(png, rows);
            png_write_end(png, NULL);
            status = 0;
        }
    }
    png_destroy_write_struct(png ? &png : NULL, info ? &info : NULL);
    free(rows);
    if (fclose(f) != 0)
        status = -1;
    if (status != 0)
        return message.text[0] ? cli_fail(err, "%s: cannot write the PNG: %s", path, message.text)
                               : cli_fail(err, "%s: cannot write the PNG: %s", path,
                                          strerror(errno ? errno : EIO));
    return 0;
}

int cli_write_png(const char *path, const double *positions, const uint32_t *triangles,
                  size_t triangle_count, const unsigned char *classes, const cli_view *view,
                  cli_error *err) {
    unsigned char *out = malloc(3 * (size_t)view->width * (size_t)view->height);
    if (out == NULL ||
        meshio_render_rgb(positions, triangles, triangle_count, classes, view, out) != 0) {
        free(out);
        return cli_fail(err, "%s: out of memory for a %dx%d picture", path, view->width,
                        view->height);
    }
    int status = write_png_file(path, out, view->width, view->height, err);
    free(out);
    return status;
}
