// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Rigid impact zones, the continuous option's fail-safe (Provot 1997;
// Bridson, Fedkiw and Anderson 2002, section 7.4), on plain arrays (no
// Bullet type), so that their rules are tested without a world.
//
// When the held-back passes leave pairs that still touch during the step,
// the nodes of every such pair join one zone (a union-find over the nodes,
// zones only merging within a step), and each zone of two nodes or more
// moves as one body from where the step started:
//   - a zone without kinematic nodes keeps its linear and angular momentum:
//     displacement u_i = u_c + w x (p_i - p_c), with p the start positions,
//     p_c and u_c the mass-weighted centre and mean displacement, and
//     w = I^-1 L from the zone's inertia and angular momentum about p_c
//     (both from displacements over the step: w is the rotation vector);
//   - a zone with kinematic nodes (zero inverse mass, which no impulse
//     moves) takes their motion, fitted alike with unit weights, and its
//     kinematic nodes keep their own.
// The motion is the step's straight line from p_i to p_i + u_i, an affine
// map p -> p + t (u_c + w x (p - p_c)) at each time t in [0, 1] whose matrix
// I + t [w]x has determinant 1 + t^2 |w|^2 > 0: an invertible affine map
// keeps apart what is apart, so no two elements of one zone of free nodes
// touch during the step unless they touched at its start. Where the
// kinematic nodes do not move as one body, or a zone meets another, the
// caller's next continuous pass finds the pairs and the zones grow. Rigid
// motions can keep meeting new nodes for many passes (on the 20k-face
// fast-compression ribbon, 16 passes left a pair in a third of the steps
// from step 100 on, and each such step let a crossing in), so the caller
// ends with zones that stay where the step started: nothing moves into a
// still zone but the nodes that then join it.
#ifndef SELFCOL_BULLET_IMPACT_ZONES_HPP
#define SELFCOL_BULLET_IMPACT_ZONES_HPP

#include <cstddef>
#include <cstdint>

namespace selfcol_bullet_detail {

// Per zone root, one step's sums (zones_move's scratch, one per node).
struct zone_sums {
    uint32_t size;      // nodes in the zone
    uint32_t kinematic; // of which kinematic
    double weight;      // sum of the weights of the nodes that fit the motion
    double centre[3];   // their weighted start positions, then p_c
    double shift[3];    // their weighted displacements, then u_c
    double momentum[3]; // sum weight r x (u - u_c), r = p - p_c
    double inertia[6];  // sum weight (|r|^2 Id - r r^T): xx, yy, zz, xy, xz, yz
    double rotation[3]; // w
};

// Every node its own zone.
void zones_reset(uint32_t *parent, size_t count);

// The zone of node x (with path halving).
uint32_t zone_root(uint32_t *parent, uint32_t x);

// One zone for x's and y's.
void zones_unite(uint32_t *parent, uint32_t x, uint32_t y);

// Moves every node of each zone of two nodes or more on its zone's motion
// (above): end[3 i ..] becomes start + u_i for free nodes (inverse_mass > 0);
// kinematic nodes keep their end. With `freeze`, a zone without kinematic
// nodes stays where the step started (u = 0: the identity, the last resort
// when rigid motions keep meeting others). sums: `count` entries of
// scratch. Returns the nodes moved.
size_t zones_move(uint32_t *parent, size_t count, const double *start, double *end,
                  const double *inverse_mass, zone_sums *sums, bool freeze);
// A node's state in the last resort below: free (moves with its zone),
// pinned where the step started, or following its zone again after a pin
// (the caller's: a driven element swept into it; never pinned again).
enum zone_pin_state : uint8_t { ZONE_NODE_FREE = 0, ZONE_NODE_PINNED = 1, ZONE_NODE_FOLLOWS = 2 };
// The last resort once zones are still (the caller's): pins the free nodes
// (inverse_mass > 0) among nodes[0 .. n - 1] (a pass's pairs, 5 nodes each)
// where the step started for the rest of the step (pinned: one byte per
// node); returns whether any was not pinned yet. A zone with kinematic
// nodes moves with them even when still, and a pair inside it that touched
// at the step's start is carried by the zone's rigid motion, which keeps
// its side in exact arithmetic but not once rounded to the caller's floats.
bool zones_pin(uint8_t *pinned, const uint32_t *nodes, size_t n, const double *inverse_mass);
// end = start, exactly, for every ZONE_NODE_PINNED node (after zones_move).
void zones_hold_pinned(const uint8_t *pinned, size_t count, const double *start, double *end);

} // namespace selfcol_bullet_detail

#endif
