// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Demo 1: the crumpling ribbon (the seed's Figure 11). A 2 m strip in zero
// gravity is pushed together from both ends, one end turning, until it folds
// on itself many times; then it is held and settles.
#include "ribbon_scene.hpp"

#include <cstdio>

int main(int argc, char **argv) {
    demo::options o;
    if (!demo::parse(argc, argv, "selfcol-bullet-ribbon",
                     "the crumpling ribbon (Volino & Magnenat Thalmann 1995, Figure 11)", o))
        return 2;
    int steps = o.steps > 0 ? o.steps : 1440;
    int along = o.resolution > 0 ? o.resolution : 160;
    demo::world w(o, 0.0);
    demo::ribbon r = demo::add_ribbon(w, along, o.scale, steps * 3 / 4);
    if (int status = w.start(o))
        return status;
    return demo::run(w, o, steps, [&r](int i) { demo::drive_ribbon(r, i); });
}
