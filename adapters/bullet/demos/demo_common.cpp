// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The demos' shared world, sheet builder, statistics and frame writer
// (demo_common.hpp).
#include "demo_common.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sys/stat.h>

namespace demo {

// The internal step of every demo: Bullet's deformable examples use 1/240 s.
static const double kStep = 1.0 / 240.0;

static void usage(const char *name, const char *about) {
    std::fprintf(stderr,
                 "%s: %s\n"
                 "usage: %s [--steps N] [--resolution N] [--scale S] [--out DIR] [--every K]\n"
                 "          [--collision selfcol|bullet|off] [--distance D] [--threads N] "
                 "[--continuous] [--quiet] [--check]\n"
                 "  --steps N       1..%lld internal steps of 1/240 s (default: the demo's)\n"
                 "  --resolution N  %lld..%lld nodes along the long side (default: the demo's)\n"
                 "  --scale S       %g..%g: every length times S (Bullet's own path misses "
                 "cloth with edges under ~1.8 cm)\n"
                 "  --out DIR       write frames DIR/frame_NNNNN.ply (every K steps with "
                 "--every, and the last)\n"
                 "  --every K       0..%lld (0: the last frame only)\n"
                 "  --collision     self-collision by selfcol (default), by Bullet's own "
                 "deformable path, or none\n"
                 "  --distance D    selfcol's thickness, 0 (default: 0.25 x the mean edge) up "
                 "to the mean edge\n"
                 "  --threads N     selfcol's threads (refits, queries, stores), 1..%d\n"
                 "  --continuous    selfcol keeps each step free of new pass-throughs (holds "
                 "back the nodes\n"
                 "                  of pairs that would touch during the step)\n",
                 name, about, name, max_steps, min_resolution, max_resolution, min_scale, max_scale,
                 max_steps, SELFCOL_MAX_THREADS);
}

// A whole decimal integer in [lo, hi]: no sign games, no truncation (a
// value that does not fit is refused, not wrapped).
static bool parse_integer(const char *text, long long lo, long long hi, long long &out) {
    char *end = nullptr;
    errno = 0;
    long long v = std::strtoll(text, &end, 10);
    if (end == text || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        return false;
    out = v;
    return true;
}

// A finite real in [lo, hi].
static bool parse_real(const char *text, double lo, double hi, double &out) {
    char *end = nullptr;
    errno = 0;
    double v = std::strtod(text, &end);
    if (end == text || *end != '\0' || !std::isfinite(v) || !(v >= lo && v <= hi))
        return false;
    out = v;
    return true;
}

bool parse(int argc, char **argv, const char *name, const char *about, options &o) {
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        const char *value = i + 1 < argc ? argv[i + 1] : nullptr;
        bool takes = a == "--steps" || a == "--resolution" || a == "--scale" || a == "--every" ||
                     a == "--out" || a == "--distance" || a == "--threads" || a == "--collision";
        if (takes && value == nullptr) {
            std::fprintf(stderr, "%s: %s needs a value\n", name, a.c_str());
            usage(name, about);
            return false;
        }
        long long n = 0;
        bool ok = true;
        if (a == "--steps") {
            ok = parse_integer(value, 1, max_steps, n);
            o.steps = int(n);
        } else if (a == "--resolution") {
            ok = parse_integer(value, min_resolution, max_resolution, n);
            o.resolution = int(n);
        } else if (a == "--scale") {
            ok = parse_real(value, min_scale, max_scale, o.scale);
        } else if (a == "--every") {
            ok = parse_integer(value, 0, max_steps, n);
            o.every = int(n);
        } else if (a == "--distance") {
            ok = parse_real(value, 0, SELFCOL_MESH_MAX_COORDINATE, o.distance);
        } else if (a == "--threads") {
            ok = parse_integer(value, 1, SELFCOL_MAX_THREADS, n);
            o.threads = unsigned(n);
        } else if (a == "--out") {
            o.out = value;
        } else if (a == "--collision") {
            std::string m = value;
            if (m == "selfcol")
                o.collision = mode::selfcol;
            else if (m == "bullet")
                o.collision = mode::bullet;
            else if (m == "off")
                o.collision = mode::off;
            else
                ok = false;
        } else if (a == "--quiet") {
            o.quiet = true;
            continue;
        } else if (a == "--continuous") {
            o.continuous = true;
            continue;
        } else if (a == "--check") {
            o.check = true;
            continue;
        } else {
            if (a != "--help" && a != "-h")
                std::fprintf(stderr, "%s: unknown argument %s\n", name, a.c_str());
            usage(name, about);
            return false;
        }
        if (!ok) {
            std::fprintf(stderr, "%s: bad value for %s: %s\n", name, a.c_str(), value);
            usage(name, about);
            return false;
        }
        ++i;
    }
    return true;
}

world::world(const options &o, double gravity_y) : collision(o.collision), gravity(gravity_y) {
    constraint_solver.setDeformableSolver(&body_solver);
    dynamics = new btDeformableMultiBodyDynamicsWorld(&dispatcher, &broadphase, &constraint_solver,
                                                      &configuration, &body_solver);
    btVector3 g(0, btScalar(-gravity), 0);
    dynamics->setGravity(g);
    dynamics->getWorldInfo().m_gravity = g;
    dynamics->getWorldInfo().m_sparsesdf.setDefaultVoxelsz(btScalar(0.25 * o.scale));
    dynamics->getWorldInfo().m_sparsesdf.Reset();
}

world::~world() {
    // The adapter goes before the world and the bodies it reads: it removes
    // its action from the world and restores the bodies' settings (bullet.h,
    // lifetimes). A teardown that deletes the world first must call
    // selfcol_bullet_destroy_after_world() instead.
    selfcol_bullet_destroy(adapter);
    for (btSoftBody *c : cloths) {
        dynamics->removeSoftBody(c);
        delete c;
    }
    for (btRigidBody *r : rigid) {
        dynamics->removeRigidBody(r);
        delete r->getMotionState();
        delete r;
    }
    for (btDeformableLagrangianForce *f : forces)
        delete f;
    for (btCollisionShape *s : shapes)
        delete s;
    delete dynamics;
}

btRigidBody *world::add_rigid(btCollisionShape *shape, const btVector3 &origin, double mass) {
    shapes.push_back(shape);
    btTransform t;
    t.setIdentity();
    t.setOrigin(origin);
    btVector3 inertia(0, 0, 0);
    if (mass > 0)
        shape->calculateLocalInertia(btScalar(mass), inertia);
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), new btDefaultMotionState(t),
                                                  shape, inertia);
    btRigidBody *body = new btRigidBody(info);
    body->setFriction(btScalar(0.5));
    dynamics->addRigidBody(body);
    rigid.push_back(body);
    return body;
}

btSoftBody *world::add_sheet(const btVector3 &corner, const btVector3 &u, const btVector3 &v,
                             int nx, int ny, double mass, bool rigid_contacts) {
    std::vector<btVector3> x(size_t(nx) * size_t(ny));
    std::vector<btScalar> m(x.size(), btScalar(mass / double(x.size())));
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            x[size_t(j) * size_t(nx) + size_t(i)] =
                corner + u * btScalar(double(i) / (nx - 1)) + v * btScalar(double(j) / (ny - 1));
    btSoftBody *body = new btSoftBody(&dynamics->getWorldInfo(), int(x.size()), x.data(), m.data());
    auto id = [nx](int i, int j) { return j * nx + i; };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            if (i + 1 < nx)
                body->appendLink(id(i, j), id(i + 1, j));
            if (j + 1 < ny)
                body->appendLink(id(i, j), id(i, j + 1));
            if (i + 1 < nx && j + 1 < ny) {
                // alternate the diagonals so the sheet has no preferred fold
                bool flip = ((i + j) & 1) != 0;
                if (flip) {
                    body->appendLink(id(i + 1, j), id(i, j + 1));
                    body->appendFace(id(i, j), id(i + 1, j), id(i, j + 1));
                    body->appendFace(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                } else {
                    body->appendLink(id(i, j), id(i + 1, j + 1));
                    body->appendFace(id(i, j), id(i + 1, j), id(i + 1, j + 1));
                    body->appendFace(id(i, j), id(i + 1, j + 1), id(i, j + 1));
                }
            }
            // bending springs: nodes two apart along each side
            if (i + 2 < nx) {
                body->appendLink(id(i, j), id(i + 2, j));
                body->m_links[body->m_links.size() - 1].m_bbending =
                    -1; // a 1-bit signed field: -1 is "set"
            }
            if (j + 2 < ny) {
                body->appendLink(id(i, j), id(i, j + 2));
                body->m_links[body->m_links.size() - 1].m_bbending =
                    -1; // a 1-bit signed field: -1 is "set"
            }
        }
    // Stiffness in units of node mass / step^2, so a sheet behaves the same
    // whatever its size and resolution (explicit springs stay stable).
    double node_mass = mass / double(x.size());
    double per = node_mass / (kStep * kStep);
    body->getCollisionShape()->setMargin(btScalar(0.25 * u.length() / (nx - 1)));
    body->m_cfg.kKHR = 1;
    body->m_cfg.kCHR = 1;
    body->m_cfg.kDF = btScalar(0.3);
    body->m_cfg.collisions = 0;
    if (rigid_contacts)
        body->m_cfg.collisions = btSoftBody::fCollision::SDF_RD | btSoftBody::fCollision::SDF_RDN;
    body->setSpringStiffness(btScalar(0.3 * per));
    dynamics->addSoftBody(body);
    auto *springs = new btDeformableMassSpringForce(btScalar(0.3 * per),
                                                    btScalar(0.02 * per * kStep), true, 0.03 * per);
    dynamics->addForce(body, springs);
    forces.push_back(springs);
    auto *g = new btDeformableGravityForce(btVector3(0, btScalar(-gravity), 0));
    dynamics->addForce(body, g);
    forces.push_back(g);
    cloths.push_back(body);
    return body;
}

double mean_face_edge(const world &w) {
    double sum = 0;
    size_t count = 0;
    for (const btSoftBody *c : w.cloths)
        for (int f = 0; f < c->m_faces.size(); ++f)
            for (int k = 0; k < 3; ++k) {
                sum += double(
                    (c->m_faces[f].m_n[k]->m_x - c->m_faces[f].m_n[(k + 1) % 3]->m_x).length());
                ++count;
            }
    return count > 0 ? sum / double(count) : 0;
}

int world::start(const options &o) {
    if (collision == mode::bullet) {
        for (btSoftBody *c : cloths) {
            c->m_cfg.collisions |= btSoftBody::fCollision::VF_DD;
            // Bullet builds the face tree its self-collision walks only with SDF_RD.
            c->m_cfg.collisions |= btSoftBody::fCollision::SDF_RD;
            c->setSelfCollision(true);
        }
        return 0;
    }
    if (collision == mode::off)
        return 0;
    // The thickness is a cloth's: beyond an edge length the repulsion (up
    // to d per step) throws nodes apart faster than the springs hold them
    // (--distance 1e30 made the ribbon's nodes non-finite).
    const double edge = mean_face_edge(*this);
    if (o.distance > edge) {
        std::fprintf(stderr,
                     "--distance %g is above the cloth's mean edge length (%g at this "
                     "resolution and scale)\n",
                     o.distance, edge);
        return 2;
    }
    selfcol_query_options query;
    selfcol_query_options_init(&query, SELFCOL_QUERY_OPTIONS_VERSION);
    query.distance = o.distance;
    selfcol_bullet_options so;
    selfcol_bullet_options_init(&so, SELFCOL_BULLET_OPTIONS_VERSION);
    so.query = &query; // copied by selfcol_bullet_create()
    so.threads = o.threads;
    so.continuous = o.continuous || collision == mode::selfcol_continuous ? 1 : 0;
    so.coherent = collision == mode::selfcol_fresh ? 0 : 1;
    int status = selfcol_bullet_create(&adapter, dynamics, &so);
    for (size_t i = 0; status == SELFCOL_OK && i < cloths.size(); ++i)
        status = selfcol_bullet_attach(adapter, cloths[i], nullptr);
    if (status != SELFCOL_OK) {
        std::fprintf(stderr, "selfcol adapter: %s\n", selfcol_status_string(status));
        return 1;
    }
    return 0;
}

void world::step(double dt) {
    dynamics->stepSimulation(btScalar(dt), 1, btScalar(dt));
}

double kinetic_energy(const world &w) {
    double e = 0;
    for (const btSoftBody *c : w.cloths)
        for (int i = 0; i < c->m_nodes.size(); ++i) {
            const btSoftBody::Node &n = c->m_nodes[i];
            if (n.m_im > 0)
                e += 0.5 * double(n.m_v.length2()) / double(n.m_im);
        }
    return e;
}

size_t bullet_contacts(const world &w) {
    size_t n = 0;
    for (const btSoftBody *c : w.cloths)
        n += size_t(c->m_faceNodeContacts.size());
    return n;
}

bool finite(const world &w) {
    for (const btSoftBody *c : w.cloths)
        for (int i = 0; i < c->m_nodes.size(); ++i)
            for (int k = 0; k < 3; ++k)
                if (!std::isfinite(c->m_nodes[i].m_x[k]) || !std::isfinite(c->m_nodes[i].m_v[k]))
                    return false;
    return true;
}

double extent(const world &w) {
    double e = 0;
    for (const btSoftBody *c : w.cloths)
        for (int i = 0; i < c->m_nodes.size(); ++i)
            for (int k = 0; k < 3; ++k)
                e = std::fmax(e, std::fabs(double(c->m_nodes[i].m_x[k])));
    return e;
}

bool write_ply(const world &w, const std::string &path) {
    size_t vertices = 0, faces = 0;
    for (const btSoftBody *c : w.cloths) {
        vertices += size_t(c->m_nodes.size());
        faces += size_t(c->m_faces.size());
    }
    FILE *f = std::fopen(path.c_str(), "wb");
    if (f == nullptr)
        return false;
    std::fprintf(f,
                 "ply\nformat binary_little_endian 1.0\ncomment selfcol Bullet demo frame\n"
                 "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face %zu\nproperty list uchar uint vertex_indices\nend_header\n",
                 vertices, faces);
    bool ok = true;
    for (const btSoftBody *c : w.cloths)
        for (int i = 0; i < c->m_nodes.size(); ++i) {
            float p[3] = {float(c->m_nodes[i].m_x.x()), float(c->m_nodes[i].m_x.y()),
                          float(c->m_nodes[i].m_x.z())};
            ok = ok && std::fwrite(p, sizeof p, 1, f) == 1;
        }
    uint32_t base = 0;
    for (const btSoftBody *c : w.cloths) {
        const btSoftBody::Node *n0 = &c->m_nodes[0];
        for (int i = 0; i < c->m_faces.size(); ++i) {
            unsigned char three = 3;
            uint32_t t[3];
            for (int k = 0; k < 3; ++k)
                t[k] = base + uint32_t(c->m_faces[i].m_n[k] - n0);
            ok = ok && std::fwrite(&three, 1, 1, f) == 1 && std::fwrite(t, sizeof t, 1, f) == 1;
        }
        base += uint32_t(c->m_nodes.size());
    }
    return std::fclose(f) == 0 && ok;
}

void print_step(const world &w, const options &o, int step, double step_seconds, report &r) {
    double energy = kinetic_energy(w);
    r.worst_energy = std::fmax(r.worst_energy, energy);
    r.worst_extent = std::fmax(r.worst_extent, extent(w));
    r.ever_nonfinite = r.ever_nonfinite || !finite(w);
    r.step_seconds_total += step_seconds;
    if (step == 0)
        r.first_step_seconds = step_seconds;
    selfcol_bullet_step_stats s;
    s.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    size_t contacts = 0;
    if (w.adapter != nullptr) {
        if (selfcol_bullet_stats(w.adapter, &s) != SELFCOL_OK)
            std::memset(&s, 0, sizeof s);
        contacts = size_t(s.contacts);
        r.last_interferences = s.interferences;
        r.peak_interferences = std::max(r.peak_interferences, s.interferences);
        r.continuous_hits += s.continuous_hits;
        r.continuous_held += s.continuous_held;
        r.continuous_remaining += s.continuous_remaining;
        r.passed_around += s.passed_around;
        r.zone_steps += s.zone_nodes > 0;
        r.continuous_exempt += s.continuous_exempt;
        r.last_crossings = s.crossings_after;
    } else {
        contacts = bullet_contacts(w);
    }
    r.peak_contacts = std::max(r.peak_contacts, contacts);
    if (o.quiet)
        return;
    if (w.adapter != nullptr)
        std::printf("step %5d  contacts %7llu  interferences %6llu  crossed %5llu  flipped %5llu  "
                    "corrected %5llu  untangled %5llu  KE %.4g J  step %.2f ms (selfcol %.2f + "
                    "%.2f ms)\n",
                    step, (unsigned long long)s.contacts, (unsigned long long)s.interferences,
                    (unsigned long long)s.crossed, (unsigned long long)s.flipped,
                    (unsigned long long)s.corrected, (unsigned long long)s.untangled, energy,
                    1e3 * step_seconds, 1e3 * s.seconds_detect, 1e3 * s.seconds_response);
    if (w.adapter != nullptr && s.continuous_passes > 0)
        std::printf("      continuous: %llu passes %.2f ms, %llu pairs touching, %llu nodes held, "
                    "%llu in impact zones, %llu pairs left, %llu let through at crossings, "
                    "%llu crossings after the step\n",
                    (unsigned long long)s.continuous_passes, 1e3 * s.seconds_continuous,
                    (unsigned long long)s.continuous_hits, (unsigned long long)s.continuous_held,
                    (unsigned long long)s.zone_nodes, (unsigned long long)s.continuous_remaining,
                    (unsigned long long)s.continuous_exempt, (unsigned long long)s.crossings_after);
    if (w.adapter == nullptr)
        std::printf("step %5d  bullet vertex-face contacts %7zu  KE %.4g J  step %.2f ms\n", step,
                    contacts, energy, 1e3 * step_seconds);
}

bool maybe_write(const world &w, const options &o, int step, int last_step) {
    if (o.out.empty())
        return true;
    if (step == 0)
        mkdir(o.out.c_str(), 0777);
    if (!(step == last_step || (o.every > 0 && step % o.every == 0)))
        return true;
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%05d.ply", step);
    if (!write_ply(w, o.out + name)) {
        std::fprintf(stderr, "cannot write %s%s\n", o.out.c_str(), name);
        return false;
    }
    return true;
}

int finish(const world &w, const options &o, const report &r, int steps) {
    selfcol_bullet_step_stats s;
    s.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    int status = SELFCOL_OK;
    if (w.adapter != nullptr && selfcol_bullet_stats(w.adapter, &s) == SELFCOL_OK)
        status = s.status;
    std::printf("done: %d steps, mean step %.2f ms, first step %.2f ms, peak KE %.4g J, "
                "peak self-contacts %zu, %s%s\n",
                steps, steps > 0 ? 1e3 * r.step_seconds_total / steps : 0.0,
                1e3 * r.first_step_seconds, r.worst_energy, r.peak_contacts,
                r.ever_nonfinite ? "NON-FINITE NODES" : "all nodes finite",
                status == SELFCOL_OK ? "" : ", adapter error");
    if (status != SELFCOL_OK)
        std::fprintf(stderr, "selfcol adapter: %s\n", selfcol_status_string(status));
    if (w.adapter != nullptr)
        std::printf(
            "interferences: last step %llu, peak %llu; continuous: %llu pairs touching "
            "within steps, %llu nodes held, %llu steps with impact zones, %llu pairs left "
            "after the last pass, %llu sign changes passed around, %llu pairs let through at "
            "crossings, %llu crossings after the last step\n",
            (unsigned long long)r.last_interferences, (unsigned long long)r.peak_interferences,
            (unsigned long long)r.continuous_hits, (unsigned long long)r.continuous_held,
            (unsigned long long)r.zone_steps, (unsigned long long)r.continuous_remaining,
            (unsigned long long)r.passed_around, (unsigned long long)r.continuous_exempt,
            (unsigned long long)r.last_crossings);
    bool ok = !r.ever_nonfinite && status == SELFCOL_OK;
    if (o.check) {
        double mass = 0;
        for (const btSoftBody *c : w.cloths)
            for (int i = 0; i < c->m_nodes.size(); ++i)
                if (c->m_nodes[i].m_im > 0)
                    mass += 1.0 / double(c->m_nodes[i].m_im);
        double energy_bound = std::fmax(2 * mass * 9.8 * 2 * o.scale, 1.0 * o.scale);
        double extent_bound = 5 * o.scale;
        bool energy_ok = r.worst_energy <= energy_bound;
        bool extent_ok = r.worst_extent <= extent_bound;
        std::printf("check: peak KE %.4g J (bound %.4g), farthest node %.4g m (bound %.4g), "
                    "%s: %s\n",
                    r.worst_energy, energy_bound, r.worst_extent, extent_bound,
                    r.ever_nonfinite ? "non-finite nodes" : "finite throughout",
                    ok && energy_ok && extent_ok ? "PASS" : "FAIL");
        ok = ok && energy_ok && extent_ok;
    }
    return ok ? 0 : 1;
}

double step_length() {
    return kStep;
}

int run(world &w, const options &o, int steps, const std::function<void(int)> &before_step) {
    report r;
    for (int i = 0; i < steps; ++i) {
        if (before_step)
            before_step(i);
        auto t0 = std::chrono::steady_clock::now();
        w.step(kStep);
        double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        print_step(w, o, i, dt, r);
        if (!maybe_write(w, o, i, steps - 1))
            return 1;
        // A failed step changed no node, and the next ones would fail the
        // same way: stop here, with the reason (finish() prints it).
        selfcol_bullet_step_stats s;
        s.version = SELFCOL_BULLET_STEP_STATS_VERSION;
        if (w.adapter != nullptr && selfcol_bullet_stats(w.adapter, &s) == SELFCOL_OK &&
            s.status != SELFCOL_OK) {
            std::fprintf(stderr, "stopped at step %d\n", i);
            return finish(w, o, r, i + 1);
        }
    }
    return finish(w, o, r, steps);
}

} // namespace demo
