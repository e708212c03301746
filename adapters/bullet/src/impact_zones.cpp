// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Rigid impact zones (impact_zones.hpp).
#include "impact_zones.hpp"

#include <cmath>
#include <cstring>

namespace selfcol_bullet_detail {

void zones_reset(uint32_t *parent, size_t count) {
    for (size_t i = 0; i < count; ++i)
        parent[i] = uint32_t(i);
}

uint32_t zone_root(uint32_t *parent, uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

void zones_unite(uint32_t *parent, uint32_t x, uint32_t y) {
    x = zone_root(parent, x);
    y = zone_root(parent, y);
    if (x != y)
        parent[x < y ? y : x] = x < y ? x : y; // the lower index is the root
}

namespace {

// The weight a node fits its zone's motion with: its mass in a zone of
// free nodes; 1 for a kinematic node, 0 for a free one, in a zone with
// kinematic nodes (their motion is the zone's).
double fit_weight(const zone_sums &z, double inverse_mass) {
    if (z.kinematic > 0)
        return inverse_mass > 0 ? 0.0 : 1.0;
    return 1.0 / inverse_mass;
}

// w = (I + eps tr(I) Id)^-1 L by Cramer's rule: the small shift keeps a
// zone whose nodes lie on one line (no inertia about it) from turning about
// that line, and turns it about the others as its momentum says.
void solve_rotation(zone_sums &z) {
    const double *in = z.inertia;
    const double shift = 1e-9 * (in[0] + in[1] + in[2]);
    const double a = in[0] + shift, b = in[1] + shift, c = in[2] + shift;
    const double xy = in[3], xz = in[4], yz = in[5];
    // Cofactors of the symmetric matrix [[a, xy, xz], [xy, b, yz], [xz, yz, c]].
    const double c00 = b * c - yz * yz, c01 = xz * yz - xy * c, c02 = xy * yz - b * xz;
    const double c11 = a * c - xz * xz, c12 = xy * xz - a * yz, c22 = a * b - xy * xy;
    const double det = a * c00 + xy * c01 + xz * c02;
    const double *l = z.momentum;
    if (!(std::fabs(det) > 0) || !std::isfinite(det)) {
        z.rotation[0] = z.rotation[1] = z.rotation[2] = 0;
        return;
    }
    z.rotation[0] = (c00 * l[0] + c01 * l[1] + c02 * l[2]) / det;
    z.rotation[1] = (c01 * l[0] + c11 * l[1] + c12 * l[2]) / det;
    z.rotation[2] = (c02 * l[0] + c12 * l[1] + c22 * l[2]) / det;
}

} // namespace

size_t zones_move(uint32_t *parent, size_t count, const double *start, double *end,
                  const double *inverse_mass, zone_sums *sums, bool freeze) {
    std::memset(sums, 0, count * sizeof *sums);
    for (size_t i = 0; i < count; ++i) {
        parent[i] = zone_root(parent, uint32_t(i)); // flattened: parent[i] is the root below
        zone_sums &z = sums[parent[i]];
        z.size++;
        z.kinematic += inverse_mass[i] > 0 ? 0u : 1u;
    }
    // Centres and mean displacements.
    for (size_t i = 0; i < count; ++i) {
        zone_sums &z = sums[parent[i]];
        if (z.size < 2)
            continue;
        const double w = fit_weight(z, inverse_mass[i]);
        z.weight += w;
        for (int k = 0; k < 3; ++k) {
            z.centre[k] += w * start[3 * i + size_t(k)];
            z.shift[k] += w * (end[3 * i + size_t(k)] - start[3 * i + size_t(k)]);
        }
    }
    for (size_t i = 0; i < count; ++i) {
        zone_sums &z = sums[i];
        if (z.size < 2 || !(z.weight > 0))
            continue;
        for (int k = 0; k < 3; ++k) {
            z.centre[k] /= z.weight;
            z.shift[k] /= z.weight;
        }
    }
    // Angular momentum and inertia about the centres.
    for (size_t i = 0; i < count; ++i) {
        zone_sums &z = sums[parent[i]];
        if (z.size < 2)
            continue;
        const double w = fit_weight(z, inverse_mass[i]);
        if (w == 0)
            continue;
        double r[3], u[3];
        for (int k = 0; k < 3; ++k) {
            r[k] = start[3 * i + size_t(k)] - z.centre[k];
            u[k] = end[3 * i + size_t(k)] - start[3 * i + size_t(k)] - z.shift[k];
        }
        z.momentum[0] += w * (r[1] * u[2] - r[2] * u[1]);
        z.momentum[1] += w * (r[2] * u[0] - r[0] * u[2]);
        z.momentum[2] += w * (r[0] * u[1] - r[1] * u[0]);
        const double rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        z.inertia[0] += w * (rr - r[0] * r[0]);
        z.inertia[1] += w * (rr - r[1] * r[1]);
        z.inertia[2] += w * (rr - r[2] * r[2]);
        z.inertia[3] -= w * r[0] * r[1];
        z.inertia[4] -= w * r[0] * r[2];
        z.inertia[5] -= w * r[1] * r[2];
    }
    for (size_t i = 0; i < count; ++i) {
        zone_sums &z = sums[i];
        if (z.size < 2 || !(z.weight > 0))
            continue;
        if (freeze && z.kinematic == 0) {
            z.shift[0] = z.shift[1] = z.shift[2] = 0;
            z.rotation[0] = z.rotation[1] = z.rotation[2] = 0;
        } else {
            solve_rotation(z);
        }
    }
    size_t moved = 0;
    for (size_t i = 0; i < count; ++i) {
        const zone_sums &z = sums[parent[i]];
        if (z.size < 2 || !(z.weight > 0) || !(inverse_mass[i] > 0))
            continue;
        double r[3];
        for (int k = 0; k < 3; ++k)
            r[k] = start[3 * i + size_t(k)] - z.centre[k];
        const double *w = z.rotation;
        const double turn[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2],
                                w[0] * r[1] - w[1] * r[0]};
        for (int k = 0; k < 3; ++k)
            end[3 * i + size_t(k)] = start[3 * i + size_t(k)] + z.shift[k] + turn[k];
        ++moved;
    }
    return moved;
}

bool zones_pin(uint8_t *pinned, const uint32_t *nodes, size_t n, const double *inverse_mass) {
    bool pinned_new = false;
    for (size_t i = 0; i < n; ++i) {
        const uint32_t node = nodes[i];
        if (pinned[node] != ZONE_NODE_FREE || !(inverse_mass[node] > 0))
            continue; // pinned already, or kinematic: never held
        pinned[node] = ZONE_NODE_PINNED;
        pinned_new = true;
    }
    return pinned_new;
}

void zones_hold_pinned(const uint8_t *pinned, size_t count, const double *start, double *end) {
    for (size_t i = 0; i < count; ++i)
        if (pinned[i] == ZONE_NODE_PINNED)
            for (int k = 0; k < 3; ++k)
                end[3 * i + size_t(k)] = start[3 * i + size_t(k)];
}

} // namespace selfcol_bullet_detail
