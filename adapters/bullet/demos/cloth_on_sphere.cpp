// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Demo 2: a square cloth dropped onto a sphere, which settles in folds on
// itself around the sphere and on the floor. Bullet handles cloth-sphere and
// cloth-floor contact (soft-rigid, SDF_RD); selfcol the cloth against itself.
#include "demo_common.hpp"

#include <cstdio>

int main(int argc, char **argv) {
    demo::options o;
    if (!demo::parse(argc, argv, "selfcol-bullet-cloth-on-sphere",
                     "a square cloth dropped onto a sphere, folding on itself", o))
        return 2;
    int steps = o.steps > 0 ? o.steps : 1200;
    int n = o.resolution > 0 ? o.resolution : 48;
    double s = o.scale;
    demo::world w(o);
    w.add_rigid(new btSphereShape(btScalar(0.3 * s)), btVector3(0, btScalar(0.5 * s), 0), 0);
    w.add_rigid(new btBoxShape(btVector3(btScalar(4 * s), btScalar(0.5 * s), btScalar(4 * s))),
                btVector3(0, btScalar(-0.5 * s), 0), 0);
    // 1.2 m square, slightly tilted so that it does not land symmetric
    btVector3 corner(btScalar(-0.6 * s), btScalar(0.9 * s), btScalar(-0.6 * s));
    btVector3 u(btScalar(1.2 * s), btScalar(0.05 * s), 0),
        v(0, btScalar(0.1 * s), btScalar(1.2 * s));
    w.add_sheet(corner, u, v, n, n, 0.3, true);
    if (int status = w.start(o))
        return status;
    return demo::run(w, o, steps, nullptr);
}
