// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Contact response rows and their projected Gauss-Seidel solve (response.hpp).
#include "response.hpp"

#include <cmath>

namespace selfcol_bullet_detail {

bool response_prepare(response_row &row, const response_node *nodes) {
    double w_norm = 0;
    for (int k = 0; k < 4; ++k)
        if (row.w[k] != 0)
            w_norm += row.w[k] * row.w[k] * nodes[row.node[k]].im;
    double len2 = row.n[0] * row.n[0] + row.n[1] * row.n[1] + row.n[2] * row.n[2];
    row.w_norm = w_norm;
    row.lambda_v = 0;
    row.lambda_p = 0;
    return w_norm > 0 && std::isfinite(w_norm) && std::fabs(len2 - 1) < 1e-6 &&
           std::isfinite(row.s);
}

// sum_k w_k q_k . n over one of the node fields.
static double relative(const response_row &row, const response_node *nodes, bool velocity) {
    double sum = 0;
    for (int k = 0; k < 4; ++k) {
        if (row.w[k] == 0)
            continue;
        const double *q = velocity ? nodes[row.node[k]].v : nodes[row.node[k]].x;
        sum += row.w[k] * (q[0] * row.n[0] + q[1] * row.n[1] + q[2] * row.n[2]);
    }
    return sum;
}

static void apply(const response_row &row, response_node *nodes, bool velocity, double dlambda) {
    for (int k = 0; k < 4; ++k) {
        if (row.w[k] == 0)
            continue;
        response_node &node = nodes[row.node[k]];
        double scale = row.w[k] * node.im * dlambda;
        double *q = velocity ? node.v : node.x;
        q[0] += scale * row.n[0];
        q[1] += scale * row.n[1];
        q[2] += scale * row.n[2];
    }
}

response_result response_solve(response_row *rows, size_t count, response_node *nodes,
                               double distance, double repulsion, unsigned iterations) {
    response_result result = {0, 0};
    if (count == 0)
        return result;
    // A row's signed distance now is its starting one plus the change of
    // sum_k w_k x_k . n since the start (its own pushes and its neighbours').
    for (size_t i = 0; i < count; ++i)
        rows[i].x0 = relative(rows[i], nodes, false);
    for (unsigned it = 0; it < iterations; ++it) {
        for (size_t i = 0; i < count; ++i) {
            response_row &row = rows[i];
            if (!(row.s < distance))
                continue; // a remnant that has parted beyond the thickness
            // inelastic: the elements stop approaching
            double v_rel = relative(row, nodes, true);
            double lambda = row.lambda_v - v_rel / row.w_norm;
            if (lambda < 0)
                lambda = 0;
            if (lambda != row.lambda_v) {
                apply(row, nodes, true, lambda - row.lambda_v);
                row.lambda_v = lambda;
            }
            // repulsion: the signed distance up by a fraction of its gap to d,
            // at most d in one step
            double gap = repulsion * (distance - row.s);
            if (gap > distance)
                gap = distance;
            double s_now = row.s + relative(row, nodes, false) - row.x0;
            double lp = row.lambda_p + (row.s + gap - s_now) / row.w_norm;
            if (lp < 0)
                lp = 0;
            // never more than d of own push per step, whatever the neighbours do
            if (lp * row.w_norm > distance)
                lp = distance / row.w_norm;
            if (lp != row.lambda_p) {
                apply(row, nodes, false, lp - row.lambda_p);
                row.lambda_p = lp;
            }
        }
    }
    for (size_t i = 0; i < count; ++i) {
        if (rows[i].lambda_v > 0 || rows[i].lambda_p > 0)
            ++result.responses;
        double push = rows[i].lambda_p * rows[i].w_norm;
        if (push > result.max_push)
            result.max_push = push;
    }
    return result;
}

} // namespace selfcol_bullet_detail
