// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The Eigen consumer (tests/consumer/run.sh): the mesh of ../main.c as
// libigl matrices, its known contacts, and an exception for a bad index.
#include <selfcol/eigen.hpp>

#include <cstdio>

int main() {
    Eigen::MatrixXd V(9, 3);
    V << 0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 4.0, 0.0, // triangle 0, z = 0
        1.0, 1.0, -1.0, 1.0, 1.0, 1.0, 2.0, 0.5, 1.0, // triangle 1, through it
        3.0, 0.5, 0.1, 3.5, 0.5, 1.0, 3.0, 1.0, 1.0;  // triangle 2, a corner above it
    Eigen::MatrixXi F(3, 3);
    F << 0, 1, 2, 3, 4, 5, 6, 7, 8;

    selfcol::query_options options;
    options.distance = 0.25;
    const selfcol::contact_result r = selfcol::self_collide(V, F, options);
    std::printf("consumer_eigen: VF %ld, EE %ld, EF %ld\n", (long)r.VF.rows(), (long)r.EE.rows(),
                (long)r.EF.rows());
    if (r.VF.rows() != 1 || r.EE.rows() != 0 || r.EF.rows() != 2 || r.VF(0, 0) != 6 ||
        r.VF(0, 1) != 0 || !(r.VF_distance(0) > 0.0999 && r.VF_distance(0) < 0.1001))
        return 1;

    F(2, 2) = 9; // no such vertex
    try {
        selfcol::self_collide(V, F);
    } catch (const selfcol::error &e) {
        std::printf("consumer_eigen: %s\n", e.what());
        return e.status() == SELFCOL_EINVAL ? 0 : 1;
    }
    return 1;
}
