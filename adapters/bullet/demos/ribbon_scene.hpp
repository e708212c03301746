// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The crumpling ribbon (the seed's Figure 11), shared by its demo, its
// stability test and the benchmark: a long strip in zero gravity whose two
// end rows are kinematic (zero mass) and are driven toward each other, one of
// them turning about the strip's axis, until the strip has folded on itself
// many times.
#ifndef SELFCOL_BULLET_RIBBON_SCENE_HPP
#define SELFCOL_BULLET_RIBBON_SCENE_HPP

#include "demo_common.hpp"

namespace demo {

struct ribbon {
    btSoftBody *body = nullptr;
    int along = 0, across = 0;
    double length = 0, width = 0;
    int steps = 0; // the drive's duration: the ends reach their closest at this step
};

// A strip of `along` x (along / 8) nodes, length 2 m x scale; steps: the
// drive's duration.
ribbon add_ribbon(world &w, int along, double scale, int steps);

// Sets the kinematic end rows' velocities for step `step` (call before it).
void drive_ribbon(const ribbon &r, int step);

} // namespace demo

#endif
