// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Demo 3: the seed's Figure 8. Two square sheets that start interpenetrating
// (tilted opposite ways, crossing along a line) fall onto a floor. The
// contact store sees the crossing (EF interferences), votes each region's
// majority side, and the response pulls the minority part back through, so
// the sheets come apart and lie one on the other.
#include "demo_common.hpp"

#include <cmath>
#include <cstdio>

int main(int argc, char **argv) {
    demo::options o;
    if (!demo::parse(argc, argv, "selfcol-bullet-figure8",
                     "two interpenetrating sheets falling onto a floor (Volino & Magnenat "
                     "Thalmann 1995, Figure 8)",
                     o))
        return 2;
    int steps = o.steps > 0 ? o.steps : 960;
    int n = o.resolution > 0 ? o.resolution : 32;
    double s = o.scale;
    demo::world w(o);
    w.add_rigid(new btBoxShape(btVector3(btScalar(4 * s), btScalar(0.5 * s), btScalar(4 * s))),
                btVector3(0, btScalar(-0.5 * s), 0), 0);
    // Sheet A rises along +x, sheet B falls along +x; they cross at x = 0.2,
    // so 60% of B lies above A and 40% below.
    double side = 1.0 * s, tilt = 0.12 * s, h = 0.3 * s;
    btVector3 a_corner(btScalar(-0.5 * side), btScalar(h - tilt), btScalar(-0.5 * side));
    btVector3 a_u(btScalar(side), btScalar(2 * tilt), 0), a_v(0, 0, btScalar(side));
    btVector3 b_corner(btScalar(-0.3 * side), btScalar(h + 1.4 * tilt), btScalar(-0.45 * side));
    btVector3 b_u(btScalar(side), btScalar(-2 * tilt), 0), b_v(0, 0, btScalar(0.9 * side));
    w.add_sheet(a_corner, a_u, a_v, n, n, 0.2, true);
    w.add_sheet(b_corner, b_u, b_v, n, n, 0.2, true);
    if (int status = w.start(o))
        return status;
    return demo::run(w, o, steps, nullptr);
}
