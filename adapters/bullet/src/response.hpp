// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The contact response of the Bullet adapter, on plain arrays (no Bullet
// type), so that its rules are tested without a world.
//
// One row per stored contact: four nodes with barycentric weights (+ on the
// first element, - on the second), a unit push direction n (the way the
// first element belongs relative to the second: the contact's consistent
// side), and the signed distance s along it (negative when the elements have
// crossed). Two projected Gauss-Seidel passes, each with a non-negative
// accumulated multiplier per row, so that every contact pushes and never
// pulls (Bridson, Fedkiw and Anderson 2002, section 7.1-7.2: an inelastic
// impulse on the approaching normal velocity, a repulsion bounded so it
// cannot pump energy):
//   - inelastic: the relative normal velocity sum_k w_k v_k . n of a row
//     with s < d is raised to 0 (the elements stop approaching);
//   - repulsion: the relative normal displacement sum_k w_k dx_k . n is
//     raised to min(repulsion (d - s), d), applied to positions only (the
//     impulse acts over this step and leaves no velocity behind, so resting
//     contact does not bounce).
// Impulses are mass-weighted: node k moves by w_k im_k lambda n, with
// lambda = gap / sum_k w_k^2 im_k; a row whose nodes all have zero inverse
// mass (pinned) is skipped.
#ifndef SELFCOL_BULLET_RESPONSE_HPP
#define SELFCOL_BULLET_RESPONSE_HPP

#include <cstddef>
#include <cstdint>

namespace selfcol_bullet_detail {

struct response_node {
    double x[3]; // position (pushed by the repulsion)
    double v[3]; // velocity (changed by the inelastic impulse)
    double im;   // inverse mass, 0 for pinned
};

struct response_row {
    uint32_t node[4]; // indices into the node array; weight 0 for unused slots
    double w[4];
    double n[3];
    double s;        // signed distance along n at the start of the solve
    double w_norm;   // sum w_k^2 im_k
    double x0;       // sum w_k x_k . n at the start of the solve
    double lambda_v; // accumulated inelastic multiplier
    double lambda_p; // accumulated repulsion multiplier
};

struct response_result {
    uint64_t responses; // rows that received an impulse
    double max_push;    // largest relative displacement given to a row
};

// Fills w_norm, clears the multipliers; returns false for a row to skip
// (no movable node, or a direction that is not unit length).
bool response_prepare(response_row &row, const response_node *nodes);

// Runs `iterations` passes of both projections over rows[0..count).
response_result response_solve(response_row *rows, size_t count, response_node *nodes,
                               double distance, double repulsion, unsigned iterations);

} // namespace selfcol_bullet_detail

#endif
