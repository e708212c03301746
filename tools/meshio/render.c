// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The picture of `selfcol-cli check --png` (and Python's Contacts.render):
// orthographic view from an azimuth and elevation (y up, as most mesh files
// are), fitted to the projected bounding box; flat-shaded, two-sided
// triangles (cloth has no inside) in a z-buffer at 2x2 supersampling, then
// box-filtered down; triangle edges darkened where triangles are large
// enough on screen for a wireframe to help. Pixels only: the CLI writes
// them with libpng, Python with zlib.
#include "meshio.h"

#include <math.h>
#include <stdlib.h>

// Samples per pixel along each axis: 2 (4 samples, anti-aliased edges) up
// to SUPERSAMPLE_LIMIT pixels, 1 above, so that the largest picture (4096 x
// 4096) needs 16 bytes per pixel of work memory (268 MB), not 64 (an 8192 x
// 8192 picture took 4.4 GB before the limit).
enum { SUPERSAMPLE_LIMIT = 2048 * 2048 };

static const float base_colours[3][3] = {
    {0.72f, 0.76f, 0.82f}, /* plain: light steel */
    {0.96f, 0.65f, 0.14f}, /* proximity: amber */
    {0.84f, 0.15f, 0.16f}  /* intersecting: red */
};

typedef struct camera {
    double right[3], up[3], toward_eye[3];
    double scale, cx, cy; /* world units -> pixels, and the centre of the view */
    int width, height;    /* supersampled size */
    int ss;               /* samples per pixel along each axis */
} camera;

static double dot3(const double *a, const double *b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void setup_camera(camera *cam, const meshio_view *view, const double *positions,
                         const uint32_t *triangles, size_t triangle_count) {
    const double deg = 3.14159265358979323846 / 180.0;
    double az = view->azimuth * deg, el = view->elevation * deg;
    cam->toward_eye[0] = cos(el) * sin(az);
    cam->toward_eye[1] = sin(el);
    cam->toward_eye[2] = cos(el) * cos(az);
    cam->right[0] = cos(az);
    cam->right[1] = 0.0;
    cam->right[2] = -sin(az);
    // up = toward_eye x right
    const double *d = cam->toward_eye, *r = cam->right;
    cam->up[0] = d[1] * r[2] - d[2] * r[1];
    cam->up[1] = d[2] * r[0] - d[0] * r[2];
    cam->up[2] = d[0] * r[1] - d[1] * r[0];
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < 3 * triangle_count; ++i) {
        const double *p = positions + 3 * (size_t)triangles[i];
        double x = dot3(p, cam->right), y = dot3(p, cam->up);
        lo[0] = x < lo[0] ? x : lo[0];
        hi[0] = x > hi[0] ? x : hi[0];
        lo[1] = y < lo[1] ? y : lo[1];
        hi[1] = y > hi[1] ? y : hi[1];
    }
    cam->ss = (size_t)view->width * (size_t)view->height <= SUPERSAMPLE_LIMIT ? 2 : 1;
    cam->width = view->width * cam->ss;
    cam->height = view->height * cam->ss;
    double margin = 0.05 * (cam->width < cam->height ? cam->width : cam->height);
    double w = hi[0] - lo[0], h = hi[1] - lo[1];
    double sx = w > 0 ? (cam->width - 2 * margin) / w : 1.0;
    double sy = h > 0 ? (cam->height - 2 * margin) / h : 1.0;
    cam->scale = sx < sy ? sx : sy;
    if (!(cam->scale > 0) || !isfinite(cam->scale))
        cam->scale = 1.0;
    cam->cx = 0.5 * (lo[0] + hi[0]);
    cam->cy = 0.5 * (lo[1] + hi[1]);
}

static void project(const camera *cam, const double *p, double out[3]) {
    out[0] = 0.5 * cam->width + cam->scale * (dot3(p, cam->right) - cam->cx);
    out[1] = 0.5 * cam->height - cam->scale * (dot3(p, cam->up) - cam->cy);
    out[2] = dot3(p, cam->toward_eye); // larger is nearer
}

static double edge_function(const double *a, const double *b, double x, double y) {
    return (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
}

static void raster_triangle(const camera *cam, double s[3][3], const float colour[3], float *depth,
                            float *rgb) {
    double area = edge_function(s[0], s[1], s[2][0], s[2][1]);
    if (area == 0.0 || !isfinite(area))
        return;
    double min_x = fmin(s[0][0], fmin(s[1][0], s[2][0]));
    double max_x = fmax(s[0][0], fmax(s[1][0], s[2][0]));
    double min_y = fmin(s[0][1], fmin(s[1][1], s[2][1]));
    double max_y = fmax(s[0][1], fmax(s[1][1], s[2][1]));
    int x0 = (int)fmax(0.0, floor(min_x)), x1 = (int)fmin(cam->width - 1.0, ceil(max_x));
    int y0 = (int)fmax(0.0, floor(min_y)), y1 = (int)fmin(cam->height - 1.0, ceil(max_y));
    // Pixel distance to each edge is |edge function| / edge length; outline
    // only triangles whose smallest altitude spans several pixels.
    double length[3];
    double min_altitude = INFINITY;
    for (int k = 0; k < 3; ++k) {
        const double *a = s[(k + 1) % 3], *b = s[(k + 2) % 3];
        // Not hypot(): its x86-64 glibc symbol is 2.35's, and the Python
        // wheel links this file (manylinux_2_34 would become 2_35). Screen
        // coordinates are far from overflow.
        const double dx = b[0] - a[0], dy = b[1] - a[1];
        length[k] = sqrt(dx * dx + dy * dy);
        if (length[k] > 0)
            min_altitude = fmin(min_altitude, fabs(area) / length[k]);
    }
    int outline = min_altitude > 6.0 * cam->ss;
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            double px = x + 0.5, py = y + 0.5;
            double w0 = edge_function(s[1], s[2], px, py) / area;
            double w1 = edge_function(s[2], s[0], px, py) / area;
            double w2 = 1.0 - w0 - w1;
            if (w0 < 0 || w1 < 0 || w2 < 0)
                continue;
            float z = (float)(w0 * s[0][2] + w1 * s[1][2] + w2 * s[2][2]);
            size_t i = (size_t)y * (size_t)cam->width + (size_t)x;
            if (z <= depth[i])
                continue;
            depth[i] = z;
            float shade = 1.0f;
            if (outline) {
                double d = fmin(w0 * fabs(area) / length[0],
                                fmin(w1 * fabs(area) / length[1], w2 * fabs(area) / length[2]));
                if (d < 0.75 * cam->ss)
                    shade = 0.72f;
            }
            for (int c = 0; c < 3; ++c)
                rgb[3 * i + (size_t)c] = colour[c] * shade;
        }
    }
}

int meshio_render_rgb(const double *positions, const uint32_t *triangles, size_t triangle_count,
                      const unsigned char *classes, const meshio_view *view, unsigned char *out) {
    camera cam;
    setup_camera(&cam, view, positions, triangles, triangle_count);
    size_t pixels = (size_t)cam.width * (size_t)cam.height;
    float *depth = malloc(pixels * sizeof *depth);
    float *rgb = malloc(3 * pixels * sizeof *rgb);
    if (depth == NULL || rgb == NULL) {
        free(depth);
        free(rgb);
        return -1;
    }
    for (size_t i = 0; i < pixels; ++i) {
        depth[i] = -INFINITY;
        rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = 1.0f; // white background
    }
    // A light above and to the left of the viewer, plus the headlight, so
    // folds facing the camera still read as folds.
    double light[3];
    for (int k = 0; k < 3; ++k)
        light[k] = 0.8 * cam.toward_eye[k] + 0.5 * cam.up[k] - 0.3 * cam.right[k];
    double light_norm = sqrt(dot3(light, light));
    for (int k = 0; k < 3; ++k)
        light[k] /= light_norm;
    // Draw plain triangles first, then proximities, then intersections, so
    // that at equal depth the marked ones win.
    for (unsigned char pass = 0; pass < 3; ++pass) {
        for (size_t t = 0; t < triangle_count; ++t) {
            unsigned char cls = classes ? classes[t] : 0;
            if (cls != pass)
                continue;
            const double *p[3];
            double s[3][3];
            for (int k = 0; k < 3; ++k) {
                p[k] = positions + 3 * (size_t)triangles[3 * t + (size_t)k];
                project(&cam, p[k], s[k]);
            }
            double e1[3], e2[3], n[3];
            for (int k = 0; k < 3; ++k) {
                e1[k] = p[1][k] - p[0][k];
                e2[k] = p[2][k] - p[0][k];
            }
            n[0] = e1[1] * e2[2] - e1[2] * e2[1];
            n[1] = e1[2] * e2[0] - e1[0] * e2[2];
            n[2] = e1[0] * e2[1] - e1[1] * e2[0];
            double len = sqrt(dot3(n, n));
            double lambert = len > 0 ? fabs(dot3(n, light)) / len : 0.0;
            double head = len > 0 ? fabs(dot3(n, cam.toward_eye)) / len : 0.0;
            float intensity = (float)(0.22 + 0.48 * lambert + 0.30 * head);
            float colour[3];
            for (int c = 0; c < 3; ++c)
                colour[c] = fminf(1.0f, base_colours[cls][c] * intensity);
            raster_triangle(&cam, s, colour, depth, rgb);
        }
    }
    for (int y = 0; y < view->height; ++y) {
        for (int x = 0; x < view->width; ++x) {
            for (int c = 0; c < 3; ++c) {
                float sum = 0.0f;
                for (int dy = 0; dy < cam.ss; ++dy)
                    for (int dx = 0; dx < cam.ss; ++dx) {
                        size_t i = (size_t)(y * cam.ss + dy) * (size_t)cam.width +
                                   (size_t)(x * cam.ss + dx);
                        sum += rgb[3 * i + (size_t)c];
                    }
                float v = sum / (float)(cam.ss * cam.ss);
                out[3 * ((size_t)y * (size_t)view->width + (size_t)x) + (size_t)c] =
                    (unsigned char)(v <= 0.0f   ? 0
                                    : v >= 1.0f ? 255
                                                : (int)(v * 255.0f + 0.5f));
            }
        }
    }
    free(depth);
    free(rgb);
    return 0;
}
