// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Intersection contour minimisation, local form (untangle.hpp).
#include "untangle.hpp"

#include <algorithm>
#include <cmath>

namespace selfcol_bullet_detail {

static double dot(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

bool contour_point_make(const double x0[3], const double x1[3], const double b0[3],
                        const double b1[3], const double b2[3], contour_point &out) {
    double u[3], w[3], to_plane[3];
    for (int k = 0; k < 3; ++k) {
        out.edge[k] = x1[k] - x0[k];
        u[k] = b1[k] - b0[k];
        w[k] = b2[k] - b0[k];
        to_plane[k] = b0[k] - x0[k];
        out.g[k] = 0;
    }
    cross(u, w, out.normal);
    const double en = dot(out.edge, out.normal), nn = dot(out.normal, out.normal);
    if (!(std::fabs(en) > 0) || !(nn > 0) || !std::isfinite(en) || !std::isfinite(nn))
        return false;
    const double t = dot(to_plane, out.normal) / en;
    if (!(t >= 0 && t <= 1))
        return false;
    for (int k = 0; k < 3; ++k)
        out.p[k] = x0[k] + t * out.edge[k];
    out.w[0] = 1 - t;
    out.w[1] = t;
    // Barycentric coordinates of p: the signed areas of the sub-triangles.
    const double *corner[3] = {b0, b1, b2};
    for (int v = 0; v < 3; ++v) {
        const double *p1 = corner[(v + 1) % 3], *p2 = corner[(v + 2) % 3];
        double s1[3], s2[3], c[3];
        for (int k = 0; k < 3; ++k) {
            s1[k] = p1[k] - out.p[k];
            s2[k] = p2[k] - out.p[k];
        }
        cross(s1, s2, c);
        out.w[2 + v] = -dot(c, out.normal) / nn;
    }
    return true;
}

size_t contour_link(contour_point *points, contour_key *keys, size_t key_count) {
    std::sort(keys, keys + key_count, [](const contour_key &x, const contour_key &y) {
        return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.point < y.point;
    });
    size_t segments = 0;
    for (size_t k = 0; k < key_count;) {
        size_t end = k + 1;
        while (end < key_count && keys[end].lo == keys[k].lo && keys[end].hi == keys[k].hi)
            ++end;
        if (end == k + 2 && keys[k].point != keys[k + 1].point) {
            contour_point &p = points[keys[k].point], &q = points[keys[k + 1].point];
            double d[3];
            for (int c = 0; c < 3; ++c)
                d[c] = p.p[c] - q.p[c];
            const double length = std::sqrt(dot(d, d));
            if (length > 0 && std::isfinite(length)) {
                for (int c = 0; c < 3; ++c) {
                    p.g[c] += d[c] / length;
                    q.g[c] -= d[c] / length;
                }
                ++segments;
            }
        }
        k = end;
    }
    return segments;
}

size_t contour_push(const contour_point *points, size_t count, response_node *nodes,
                    size_t node_count, double *delta, double step) {
    for (size_t i = 0; i < 3 * node_count; ++i)
        delta[i] = 0;
    size_t pushed = 0;
    for (size_t i = 0; i < count; ++i) {
        const contour_point &q = points[i];
        const double en = dot(q.edge, q.normal), eg = dot(q.edge, q.g);
        double G[3];
        for (int c = 0; c < 3; ++c)
            G[c] = q.g[c] - q.normal[c] * eg / en;
        const double length = std::sqrt(dot(G, G));
        if (!(length > 0) || !std::isfinite(length))
            continue; // an isolated point, or a gradient along nothing
        double w_norm = 0;
        for (int k = 0; k < 5; ++k)
            w_norm += q.w[k] * q.w[k] * nodes[q.node[k]].im;
        if (!(w_norm > 0))
            continue; // every node pinned
        // sum_k w_k dx_k = -step G / |G|: the edge side against the triangle's.
        const double lambda = -step / (w_norm * length);
        for (int k = 0; k < 5; ++k) {
            const double scale = q.w[k] * nodes[q.node[k]].im * lambda;
            for (int c = 0; c < 3; ++c)
                delta[3 * size_t(q.node[k]) + size_t(c)] += scale * G[c];
        }
        ++pushed;
    }
    for (size_t n = 0; n < node_count; ++n) {
        double *d = delta + 3 * n;
        const double length = std::sqrt(dot(d, d));
        const double scale = length > step ? step / length : 1.0;
        for (int c = 0; c < 3; ++c)
            nodes[n].x[c] += scale * d[c];
    }
    return pushed;
}

} // namespace selfcol_bullet_detail
