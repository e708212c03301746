// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// What the three demos share: a Bullet 3.24 deformable world, cloth sheets
// built from a node array (appendLink/appendFace: btSoftBodyHelpers'
// CreateFromTriMesh and generateBendingConstraints allocate V x V matrices),
// the self-collision mode (selfcol, Bullet's own, or none), per-step
// statistics, and frames written as binary PLY that `selfcol-cli check
// --frames` and `track` read back.
#ifndef SELFCOL_BULLET_DEMO_COMMON_HPP
#define SELFCOL_BULLET_DEMO_COMMON_HPP

#include <selfcol/bullet.h>

#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableGravityForce.h>
#include <BulletSoftBody/btDeformableMassSpringForce.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <btBulletDynamicsCommon.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace demo {

// selfcol_fresh: selfcol with a fresh query every step (adapter option
// coherent = 0), for the benchmark's comparison; selfcol_continuous:
// selfcol with the continuous option (as --continuous).
enum class mode { selfcol, bullet, off, selfcol_fresh, selfcol_continuous };

struct options {
    mode collision = mode::selfcol;
    int steps = 0;           // 0: the demo's default
    int resolution = 0;      // 0: the demo's default (vertices along the long side)
    double scale = 1;        // lengths times this (and masses times its cube)
    int every = 0;           // write a frame every this many steps (0: only the last)
    std::string out;         // frame directory ("": no frames)
    bool quiet = false;      // no per-step lines
    double distance = 0;     // selfcol thickness (0: the adapter's default)
    unsigned threads = 1;    // selfcol query threads
    bool continuous = false; // selfcol_bullet_options.continuous
    // --check: exit 1 if a node goes non-finite, the kinetic energy passes
    // its bound or a node leaves the scene box (finish())
    bool check = false;
};

// The ranges parse() accepts: a value outside them is a usage error (exit
// 2), never truncated (--steps 4294967298 ran 2 steps) nor passed on to
// fail later (--scale inf, --resolution 1: a sheet needs 2 nodes a side).
const long long max_steps = 10000000;
const long long min_resolution = 2;
const long long max_resolution = 2048;
const double min_scale = 1e-3;
const double max_scale = 1e3;

// Parses --steps N --resolution N --scale S --every K --out DIR --quiet
// --distance D --threads N --continuous --collision selfcol|bullet|off; prints usage and
// returns false on an error or --help. --distance is bounded by the scene
// in world::start().
bool parse(int argc, char **argv, const char *name, const char *about, options &o);

// A Bullet deformable world with its parts, torn down in the right order.
struct world {
    btSoftBodyRigidBodyCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher{&configuration};
    btDbvtBroadphase broadphase;
    btDeformableBodySolver body_solver;
    btDeformableMultiBodyConstraintSolver constraint_solver;
    btDeformableMultiBodyDynamicsWorld *dynamics = nullptr;
    std::vector<btCollisionShape *> shapes;
    std::vector<btRigidBody *> rigid;
    std::vector<btSoftBody *> cloths;
    std::vector<btDeformableLagrangianForce *> forces;
    selfcol_bullet *adapter = nullptr;
    mode collision = mode::selfcol;
    double gravity = 9.8; // along -y, times the scale

    // gravity: m/s^2 along -y (9.8 for the demos on a floor, 0 for the ribbon)
    world(const options &o, double gravity_y = 9.8);
    ~world();
    world(const world &) = delete;
    world &operator=(const world &) = delete;

    // A static (mass 0) or dynamic rigid body.
    btRigidBody *add_rigid(btCollisionShape *shape, const btVector3 &origin, double mass);

    // A rectangular sheet of nx x ny nodes spanning corner, corner + u, corner
    // + v (u and v along its sides), total mass `mass`, stretch and bending
    // springs scaled for the edge length so the cloth behaves the same at any
    // scale. rigid_contacts: soft-rigid collision flags on.
    btSoftBody *add_sheet(const btVector3 &corner, const btVector3 &u, const btVector3 &v, int nx,
                          int ny, double mass, bool rigid_contacts);

    // Switches self-collision to the world's mode (after the sheets are in).
    // Returns 0, 2 (with a message) for a --distance above the cloths' mean
    // edge length, or 1 (with the reason) if the adapter cannot be set up:
    // the demo's exit status.
    int start(const options &o);

    void step(double dt);
};

// Kinetic energy of the cloths (sum m v^2 / 2 over nodes with mass).
double kinetic_energy(const world &w);
// True when every node position and velocity is finite.
bool finite(const world &w);
// Bullet's own vertex-face self-collision contacts of the cloths (m_faceNodeContacts).
size_t bullet_contacts(const world &w);
// Mean length of the cloths' face edges (shared edges counted per face).
double mean_face_edge(const world &w);
// Largest |coordinate| of any cloth node.
double extent(const world &w);

// Writes all cloths as one binary little-endian PLY (float32 positions).
bool write_ply(const world &w, const std::string &path);

// The per-step line (and the run's final summary line).
struct report {
    double worst_energy = 0;
    double worst_extent = 0;
    bool ever_nonfinite = false;
    double step_seconds_total = 0;
    double first_step_seconds = 0;
    // The most self-collision contacts any step held: selfcol's VF/EE
    // contacts, or Bullet's own vertex-face contacts.
    size_t peak_contacts = 0;
    // selfcol's EF interferences: the last step's and the most of any step;
    // the continuous option's pairs, held nodes and pairs left, summed.
    uint64_t last_interferences = 0, peak_interferences = 0;
    uint64_t continuous_hits = 0, continuous_held = 0, continuous_remaining = 0;
    uint64_t passed_around = 0, zone_steps = 0, continuous_exempt = 0;
    uint64_t last_crossings = 0; // crossings_after of the last step (continuous option)
};
void print_step(const world &w, const options &o, int step, double step_seconds, report &r);
// Writes the frame of this step if asked; returns false on an I/O error.
bool maybe_write(const world &w, const options &o, int step, int last_step);
// The stability bounds of --check: kinetic energy at most
// max(2 m g (2 m x scale), 1 J x scale) for cloth mass m, and every node
// within 5 m x scale of the origin (the scenes span about 2 m x scale).
int finish(const world &w, const options &o, const report &r, int steps);
// Runs `steps` internal steps: before_step(i) (may be empty), the step, the
// per-step line, the frame; then finish(). Stops after the first step the
// adapter failed (finish() prints the reason). Returns the demo's exit status.
int run(world &w, const options &o, int steps, const std::function<void(int)> &before_step);
// The internal step length every demo uses (1/240 s, as Bullet's deformable examples).
double step_length();

} // namespace demo

#endif
