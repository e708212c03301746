// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The crumpling ribbon scene (ribbon_scene.hpp).
#include "ribbon_scene.hpp"

#include <cmath>

namespace demo {

ribbon add_ribbon(world &w, int along, double scale, int steps) {
    ribbon r;
    r.along = along < 16 ? 16 : along;
    r.across = r.along / 8 < 3 ? 3 : r.along / 8;
    r.length = 2.0 * scale;
    r.width = r.length * double(r.across - 1) / double(r.along - 1);
    r.steps = steps;
    btVector3 corner(btScalar(-0.5 * r.length), 0, btScalar(-0.5 * r.width));
    r.body = w.add_sheet(corner, btVector3(btScalar(r.length), 0, 0),
                         btVector3(0, 0, btScalar(r.width)), r.along, r.across, 0.2, false);
    // A small out-of-plane wave so the first buckle has a direction, and
    // kinematic end rows (zero inverse mass: no force or impulse moves them).
    for (int j = 0; j < r.across; ++j)
        for (int i = 0; i < r.along; ++i) {
            btSoftBody::Node &n = r.body->m_nodes[j * r.along + i];
            double t = double(i) / double(r.along - 1);
            n.m_x.setY(btScalar(0.01 * r.length * std::sin(3.0 * M_PI * t) * std::sin(M_PI * t)));
            n.m_q = n.m_x;
            if (i == 0 || i == r.along - 1)
                r.body->setMass(j * r.along + i, 0);
        }
    return r;
}

void drive_ribbon(const ribbon &r, int step) {
    // Each end moves 42% of the length inward over the drive (the ends end up
    // 16% of the length apart); the +x end also turns half a turn about the
    // strip's axis. Kinematic nodes follow the velocity set here exactly.
    double dt = step_length();
    double duration = double(r.steps) * dt;
    bool driving = step < r.steps;
    double speed = driving ? 0.42 * r.length / duration : 0;
    double omega = driving ? M_PI / duration : 0;
    for (int j = 0; j < r.across; ++j)
        for (int end = 0; end < 2; ++end) {
            int i = end == 0 ? 0 : r.along - 1;
            btSoftBody::Node &n = r.body->m_nodes[j * r.along + i];
            btVector3 v(btScalar(end == 0 ? speed : -speed), 0, 0);
            if (end == 1) {
                // rotation about the x axis through the strip's centre line
                btVector3 arm(0, n.m_x.y(), n.m_x.z());
                v += btVector3(btScalar(omega), 0, 0).cross(arm);
            }
            n.m_v = v;
        }
}

} // namespace demo
