// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// libselfcol_bullet: the adapter handle, attaching soft bodies, and the step
// the world's action runs (bullet.h). Uses libselfcol through its public C
// ABI only.
//
// Why an action: btDeformableMultiBodyDynamicsWorld::internalSingleStepSimulation
// (Bullet 3.24) solves the deformable momentum equation, runs its own
// soft-soft detection and CCD, moves the nodes (integrateTransforms:
// x += dt v, then q = x, vn = v) and only then calls updateActions(). An
// action therefore sees the step's final positions and velocities, and its
// changes are what the next step starts from. Its solver callback
// (setSolverCallback) would also work but takes no user pointer, so it would
// need global state to find the adapter; the internal tick callbacks run
// before the solve.
#include <selfcol/bullet.h>

#include "impact_zones.hpp"
#include "response.hpp"
#include "untangle.hpp"

#include <BulletDynamics/Dynamics/btActionInterface.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btSoftBody.h>
#include <LinearMath/btScalar.h>
#include <LinearMath/btThreads.h>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

static_assert(sizeof(btScalar) == sizeof(float),
              "libselfcol_bullet supports single-precision Bullet only (btScalar = float): "
              "a double build's btSoftBody::Node holds doubles, which the float strided "
              "position setter cannot read");

using namespace selfcol_bullet_detail;

namespace {

void *hook_alloc(const selfcol_allocator &h, size_t size, size_t align) {
    return h.alloc ? h.alloc(h.user, size, align) : std::malloc(size);
}
void hook_free(const selfcol_allocator &h, void *p, size_t size) {
    if (h.free)
        h.free(h.user, p, size);
    else
        std::free(p);
}

// std::vector storage through the handle's allocator hooks.
template <class T> struct hook_allocator {
    using value_type = T;
    const selfcol_allocator *hooks;
    explicit hook_allocator(const selfcol_allocator *h) noexcept : hooks(h) {}
    template <class U> hook_allocator(const hook_allocator<U> &o) noexcept : hooks(o.hooks) {}
    T *allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T))
            throw std::bad_alloc();
        void *p = hook_alloc(*hooks, n * sizeof(T), alignof(T));
        if (p == nullptr)
            throw std::bad_alloc();
        return static_cast<T *>(p);
    }
    void deallocate(T *p, std::size_t n) noexcept {
        hook_free(*hooks, p, n * sizeof(T));
    }
    template <class U> bool operator==(const hook_allocator<U> &o) const noexcept {
        return hooks == o.hooks;
    }
    template <class U> bool operator!=(const hook_allocator<U> &o) const noexcept {
        return hooks != o.hooks;
    }
};
template <class T> using hvector = std::vector<T, hook_allocator<T>>;

struct attached_body {
    btSoftBody *body;
    selfcol_mesh *mesh;
    // Its surface id: in the scene once there is one, and the public id
    // (attach order, never reused).
    uint32_t surface;
    int node_count;
    int face_count;
    bool saved_self_collision;
    uint32_t first_node; // this body's node 0 in the adapter's node numbering
    // The continuous option's hierarchy over `mesh` (its tree only: a
    // continuous query sweeps its own boxes); NULL while the option is off.
    selfcol_hierarchy *sweep_tree;
};

// The mark of an attached body. Bullet 3.24's btSoftBody::defaultCollisionHandler
// switches on the two bodies' common soft-soft bits (collisions & SVSmask)
// and handles VF_DD only when they are exactly VF_DD; CL_SELF is read
// nowhere else (cluster self-collision, under CL_SS). Two marked VF_DD
// bodies thus share VF_DD | CL_SELF and Bullet skips their pair (selfcol's),
// while a marked body and an unmarked VF_DD body share VF_DD alone and
// Bullet keeps their contact. The mark also tells another adapter that the
// body is taken.
const int attached_mark = int(btSoftBody::fCollision::CL_SELF);

// The scene's limit on surfaces ever added (scene.h: more than 2^16 is
// SELFCOL_ERANGE); ids are never reused, so attaches count against it.
const uint32_t max_surfaces = 1u << 16;

double now_seconds() {
    using clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

class step_action;

} // namespace

// An edge of an attached body (its global node numbers, lower first, as
// lo << 32 | hi) and one of its faces (body index << 32 | face index).
struct edge_face {
    uint64_t edge;
    uint64_t face;
    bool operator<(const edge_face &o) const {
        return edge != o.edge ? edge < o.edge : face < o.face;
    }
};

// A VF or EE pair of nodes, as in_crossing compares them (vf_key, ee_key).
struct crossing_key {
    uint32_t v[5];
    bool operator<(const crossing_key &o) const {
        return std::lexicographical_compare(v, v + 5, o.v, o.v + 5);
    }
};

inline uint64_t edge_key(uint32_t u, uint32_t w) {
    return u < w ? uint64_t(u) << 32 | w : uint64_t(w) << 32 | u;
}

struct selfcol_bullet {
    selfcol_allocator hooks;
    selfcol_bullet_options opts; // its query and store are NULL: the copies below
    selfcol_query_options query; // the caller's, read as its version says
    selfcol_store_options store;
    btDeformableMultiBodyDynamicsWorld *world;
    step_action *action;
    selfcol_scene *scene; // NULL until the first step with a body attached
    // selfcol_bullet_use_task_scheduler: the context whose parallel stages
    // run on Bullet's task scheduler, lent to the scene; NULL when off.
    selfcol_context *task_context;
    // The adapter's own context of opts.threads POSIX threads (NULL for one
    // thread), used while task_context is NULL.
    selfcol_context *own_context;
    double distance;
    uint32_t node_total;
    uint32_t next_surface; // the id the next attach gets
    hvector<attached_body> bodies;
    hvector<int32_t> slot_of_node; // node -> response slot, -1 when unused this step
    hvector<btSoftBody::Node *> node_of_slot;
    hvector<uint32_t> global_of_slot;
    hvector<response_node> nodes;
    hvector<response_row> rows;
    // The records of the store being gathered (selfcol_store_copy_contacts):
    // one buffer for every store, grown only, so that a steady state
    // allocates nothing.
    hvector<selfcol_store_contact> records;
    // The untangling (untangle.hpp): every attached edge's faces, sorted by
    // edge, and the step's contour points and segment keys.
    hvector<edge_face> edge_faces;
    hvector<contour_point> contour_points;
    hvector<contour_key> contour_keys;
    hvector<double> contour_delta; // 3 per response slot
    // The continuous option: every attached node's position where the last
    // step left it (3 per node, adapter numbering), valid when
    // have_previous; the factor each node keeps of its motion in a pass.
    hvector<double> previous;
    hvector<double> keep;
    // The impact zones (impact_zones.hpp): per node its zone, the zones'
    // sums, its end position and inverse mass.
    hvector<uint32_t> zone_parent;
    hvector<zone_sums> zone_total;
    hvector<double> zone_end;
    hvector<double> zone_inverse_mass;
    // Per node, 1 when the impact zones pinned it where the step started for
    // the rest of the step (impact_zones: pairs still touching inside zones
    // that no longer merge).
    hvector<uint8_t> pinned;
    // The continuous passes of a step: the last pass's pairs (5 nodes each,
    // as continuous_pass gives them) and their tois, the next pass's being
    // gathered, and per node whether its motion changed since the last pass
    // (only pairs with such a node are queried again).
    hvector<uint32_t> pass_hits, next_hits;
    hvector<double> pass_toi, next_toi;
    hvector<uint8_t> moved;
    // The continuous option's crossings where the last step left the nodes
    // (mark_crossings): the keys of the VF and EE pairs each EF interference
    // holds, sorted (crossing_key); valid when crossings_known.
    // crossing_hits: the EF query's result.
    hvector<crossing_key> crossing_keys;
    bool crossings_known;
    selfcol_contacts *crossing_hits;
    bool have_previous;
    selfcol_sweep *sweep;
    selfcol_bullet_step_stats stats;

    explicit selfcol_bullet(const selfcol_allocator &h)
        : hooks(h), opts(), world(nullptr), action(nullptr), scene(nullptr), task_context(nullptr),
          own_context(nullptr), distance(0), node_total(0), next_surface(0),
          bodies(hook_allocator<attached_body>(&hooks)),
          slot_of_node(hook_allocator<int32_t>(&hooks)),
          node_of_slot(hook_allocator<btSoftBody::Node *>(&hooks)),
          global_of_slot(hook_allocator<uint32_t>(&hooks)),
          nodes(hook_allocator<response_node>(&hooks)), rows(hook_allocator<response_row>(&hooks)),
          records(hook_allocator<selfcol_store_contact>(&hooks)),
          edge_faces(hook_allocator<edge_face>(&hooks)),
          contour_points(hook_allocator<contour_point>(&hooks)),
          contour_keys(hook_allocator<contour_key>(&hooks)),
          contour_delta(hook_allocator<double>(&hooks)), previous(hook_allocator<double>(&hooks)),
          keep(hook_allocator<double>(&hooks)), zone_parent(hook_allocator<uint32_t>(&hooks)),
          zone_total(hook_allocator<zone_sums>(&hooks)), zone_end(hook_allocator<double>(&hooks)),
          zone_inverse_mass(hook_allocator<double>(&hooks)),
          pinned(hook_allocator<uint8_t>(&hooks)), pass_hits(hook_allocator<uint32_t>(&hooks)),
          next_hits(hook_allocator<uint32_t>(&hooks)), pass_toi(hook_allocator<double>(&hooks)),
          next_toi(hook_allocator<double>(&hooks)), moved(hook_allocator<uint8_t>(&hooks)),
          crossing_keys(hook_allocator<crossing_key>(&hooks)), crossings_known(false),
          crossing_hits(nullptr), have_previous(false), sweep(nullptr), stats() {}
};

namespace {

class step_action : public btActionInterface {
  public:
    explicit step_action(selfcol_bullet *owner) : owner_(owner) {}
    void updateAction(btCollisionWorld *, btScalar dt) override {
        // selfcol_bullet_step catches everything and records its status.
        (void)selfcol_bullet_step(owner_, double(dt));
    }
    void debugDraw(btIDebugDraw *) override {}

  private:
    selfcol_bullet *owner_;
};

const float *node_positions(btSoftBody *body) {
    return &body->m_nodes[0].m_x.x();
}

bool in_world(const selfcol_bullet *a, const btSoftBody *body) {
    // By address only: a body no longer in the world may have been deleted.
    const btSoftBodyArray &bodies = a->world->getSoftBodyArray();
    for (int i = 0; i < bodies.size(); ++i)
        if (bodies[i] == body)
            return true;
    return false;
}

bool finite_velocities(const btSoftBody *body) {
    for (int i = 0; i < body->m_nodes.size(); ++i) {
        const btVector3 &v = body->m_nodes[i].m_v;
        if (!std::isfinite(v.x()) || !std::isfinite(v.y()) || !std::isfinite(v.z()))
            return false;
    }
    return true;
}

int add_surface(selfcol_scene *scene, const selfcol_mesh *mesh, uint32_t *id) {
    selfcol_scene_surface_options surface;
    selfcol_scene_surface_options_init(&surface, SELFCOL_SURFACE_CLOTH,
                                       SELFCOL_SCENE_SURFACE_OPTIONS_VERSION);
    return selfcol_scene_add_surface(scene, mesh, &surface, id);
}

// Where the adapter's parallel stages run: Bullet's scheduler when it is
// on (selfcol_bullet_use_task_scheduler), else the adapter's own threads
// (NULL for one: the calling thread).
selfcol_context *context_of(const selfcol_bullet *a) {
    return a->task_context != nullptr ? a->task_context : a->own_context;
}

// The scene options of the adapter's options at a distance; they point to
// `query` (the adapter's query options at that distance) and to `store`.
selfcol_scene_options scene_options(const selfcol_bullet_options &o,
                                    const selfcol_store_options &store, double distance,
                                    selfcol_query_options &query) {
    query.distance = distance;
    selfcol_scene_options so;
    selfcol_scene_options_init(&so, SELFCOL_SCENE_OPTIONS_VERSION);
    so.allocator = o.allocator;
    so.query = &query;
    so.store = &store;
    so.coherent = o.coherent;
    return so;
}

// Builds the scene from the attached bodies (the first step with a body):
// the thickness defaults from their mean edge length and stays for the
// scene's life. Surface ids are the bodies' (attach order): an id whose
// body was detached before the scene existed is used up by adding a body's
// mesh and removing it again, since the scene numbers surfaces itself.
int build_scene(selfcol_bullet *a) {
    double distance = a->query.distance;
    if (distance == 0) {
        double sum = 0;
        double edges = 0;
        for (const attached_body &b : a->bodies) {
            double e = double(selfcol_mesh_count(b.mesh, SELFCOL_MESH_EDGES));
            sum += selfcol_mesh_mean_edge_length(b.mesh) * e;
            edges += e;
        }
        distance = edges > 0 ? a->opts.distance_factor * sum / edges : 0;
    }
    if (!(distance > 0) || !std::isfinite(distance))
        return SELFCOL_EINVAL; // every edge of zero length
    selfcol_query_options query = a->query;
    selfcol_scene_options so = scene_options(a->opts, a->store, distance, query);
    selfcol_scene *scene = nullptr;
    int status = selfcol_scene_create(&scene, &so);
    for (size_t i = 0; status == SELFCOL_OK && i < a->bodies.size(); ++i) {
        const attached_body &b = a->bodies[i];
        uint32_t id = 0;
        status = add_surface(scene, b.mesh, &id);
        while (status == SELFCOL_OK && id < b.surface) {
            status = selfcol_scene_remove_surface(scene, id);
            if (status == SELFCOL_OK)
                status = add_surface(scene, b.mesh, &id);
        }
        assert(status != SELFCOL_OK || id == b.surface);
    }
    if (status != SELFCOL_OK) {
        selfcol_scene_destroy(scene);
        return status;
    }
    a->scene = scene;
    a->distance = distance;
    return SELFCOL_OK;
}

// Forgets the slots of the last step (a failed step can leave some set).
void forget_slots(selfcol_bullet *a) {
    for (uint32_t global : a->global_of_slot)
        if (global < a->slot_of_node.size())
            a->slot_of_node[global] = -1;
    a->rows.clear();
    a->nodes.clear();
    a->node_of_slot.clear();
    a->global_of_slot.clear();
    a->contour_points.clear();
    a->contour_keys.clear();
}

// Forgets bodies[index]: its surface and its pairs' stores (the others keep
// theirs), its mesh, and its nodes in the adapter's numbering, which the
// later bodies' numbers close up. Never reads the body (it may be gone) and
// never allocates.
void drop_body(selfcol_bullet *a, size_t index) {
    forget_slots(a);
    const attached_body gone = a->bodies[index];
    if (a->scene != nullptr)
        selfcol_scene_remove_surface(a->scene, gone.surface);
    selfcol_hierarchy_destroy(gone.sweep_tree);
    selfcol_mesh_destroy(gone.mesh);
    a->have_previous = false; // the node numbering changes
    a->crossings_known = false;
    a->bodies.erase(a->bodies.begin() + std::ptrdiff_t(index));
    const uint32_t count = uint32_t(gone.node_count);
    for (size_t i = index; i < a->bodies.size(); ++i)
        a->bodies[i].first_node -= count;
    a->node_total -= count;
    a->slot_of_node.resize(a->node_total); // shrinks: no allocation
    // Its edges' entries go; the later bodies' edges and body indices shift
    // down. Bodies own contiguous node ranges in order, so the entries stay
    // sorted.
    size_t kept = 0;
    for (const edge_face &ef : a->edge_faces) {
        const uint64_t body = ef.face >> 32;
        if (body == index)
            continue;
        edge_face moved = ef;
        if (body > index) {
            const uint64_t shift = uint64_t(count) << 32 | count;
            moved.edge -= shift;
            moved.face -= uint64_t(1) << 32;
        }
        a->edge_faces[kept++] = moved;
    }
    a->edge_faces.resize(kept);
    assert(std::is_sorted(a->edge_faces.begin(), a->edge_faces.end()));
}

// Restores what attach changed on a body that is still in the world.
void restore_body(const attached_body &b) {
    b.body->m_cfg.collisions &= ~attached_mark;
    b.body->setSelfCollision(b.saved_self_collision);
}

uint32_t slot_for(selfcol_bullet *a, const attached_body &b, uint32_t vertex) {
    uint32_t global = b.first_node + vertex;
    int32_t slot = a->slot_of_node[global];
    // A slot is this step's (an ENOMEM in an earlier step must not leave
    // one behind: the step resets them first).
    assert(slot < 0 ||
           (size_t(slot) < a->global_of_slot.size() && a->global_of_slot[size_t(slot)] == global));
    if (slot >= 0)
        return uint32_t(slot);
    btSoftBody::Node *n = &b.body->m_nodes[int(vertex)];
    response_node r;
    for (int c = 0; c < 3; ++c) {
        r.x[c] = double(n->m_x[c]);
        r.v[c] = double(n->m_v[c]);
    }
    r.im = double(n->m_im);
    a->nodes.push_back(r);
    a->node_of_slot.push_back(n);
    a->global_of_slot.push_back(global);
    slot = int32_t(a->nodes.size() - 1);
    a->slot_of_node[global] = slot;
    return uint32_t(slot);
}

// The unit push direction of a contact whose distance is 0 (no closest-point
// direction): its reference direction (store.h) on its right side.
bool reference_direction(const selfcol_store_contact &c, int right, const double *pa,
                         const double *pb, double n[3]) {
    double u[3], v[3];
    const double *a0 = pa + 3 * size_t(c.a[0]);
    const double *b0 = pb + 3 * size_t(c.b[0]);
    const double *b1 = pb + 3 * size_t(c.b[1]);
    if (c.kind == SELFCOL_CONTACT_VF) {
        const double *b2 = pb + 3 * size_t(c.b[2]);
        for (int k = 0; k < 3; ++k) {
            u[k] = b1[k] - b0[k];
            v[k] = b2[k] - b0[k];
        }
    } else {
        const double *a1 = pa + 3 * size_t(c.a[1]);
        for (int k = 0; k < 3; ++k) {
            u[k] = a1[k] - a0[k];
            v[k] = b1[k] - b0[k];
        }
    }
    double r[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    double len = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (!(len > 0) || !std::isfinite(len))
        return false;
    for (int k = 0; k < 3; ++k)
        n[k] = r[k] / len * double(right);
    return true;
}

// Copies a store's records into a->records (right after the scene's
// update: the meshes have not moved, as the copy requires).
int copy_records(selfcol_bullet *a, const selfcol_store *store) {
    const size_t count = selfcol_store_contact_count(store);
    if (a->records.size() < count)
        a->records.resize(count); // grown only: a smaller store keeps the capacity
    return selfcol_store_copy_contacts(store, 0, count, a->records.data());
}

// One row per VF/EE contact of a store with a decided side and right side;
// its records are a->records (copy_records).
void gather_rows(selfcol_bullet *a, const selfcol_store *store, const attached_body &first,
                 const attached_body &second, uint64_t *crossed) {
    const selfcol_store_contact *contacts = a->records.data();
    const size_t count = selfcol_store_contact_count(store);
    const selfcol_store_region *regions = nullptr;
    size_t region_count = 0;
    if (selfcol_store_regions(store, &regions, &region_count) != SELFCOL_OK)
        return;
    const double *positions[2] = {selfcol_mesh_positions(first.mesh),
                                  selfcol_mesh_positions(second.mesh)};
    const attached_body *body_of[2] = {&first, &second};
    for (size_t i = 0; i < count; ++i) {
        const selfcol_store_contact &c = contacts[i];
        if (c.kind != SELFCOL_CONTACT_VF && c.kind != SELFCOL_CONTACT_EE)
            continue;
        if (c.side == 0 || c.right_side == 0)
            continue;
        const attached_body &fb = *body_of[c.first_mesh];
        const attached_body &sb = *body_of[c.second_mesh];
        response_row row;
        std::memset(&row, 0, sizeof row);
        // The store's right side is followed where the surfaces cross (its
        // region holds EF interferences): that is where the seed's
        // consistency correction is needed and has evidence. In a region
        // without interferences the surfaces are consistent as they are
        // (section 3.2.1: "if interferences are detected as well ... we then
        // know that the situation is inconsistent"), so the contact is pushed
        // along its current side. A side change there is a vertex sliding
        // around a free border, which two frames cannot tell from a crossing
        // (store.h); following the store everywhere turned it into real
        // crossings (measured, exact EF in the written frames: ribbon 0 ->
        // 356, cloth on sphere 0 -> 206; Figure 8 unchanged, 16-23 at 24x24).
        bool crossed_region =
            c.region < region_count && (regions[c.region].flags & SELFCOL_REGION_CROSSED) != 0;
        int right = crossed_region ? c.right_side : c.side;
        if (c.distance > 0) {
            double sign = c.side == right ? 1.0 : -1.0;
            for (int k = 0; k < 3; ++k)
                row.n[k] = c.direction[k] * sign;
        } else if (!reference_direction(c, right, positions[c.first_mesh], positions[c.second_mesh],
                                        row.n)) {
            continue;
        }
        row.s = c.side == right ? c.distance : -c.distance;
        int slot = 0;
        int first_count = c.kind == SELFCOL_CONTACT_VF ? 1 : 2;
        int second_count = c.kind == SELFCOL_CONTACT_VF ? 3 : 2;
        for (int k = 0; k < first_count; ++k) {
            row.node[slot] = slot_for(a, fb, c.a[k]);
            row.w[slot++] = c.wa[k];
        }
        for (int k = 0; k < second_count; ++k) {
            row.node[slot] = slot_for(a, sb, c.b[k]);
            row.w[slot++] = -c.wb[k];
        }
        if (!response_prepare(row, a->nodes.data()))
            continue;
        if (row.s < 0)
            ++*crossed;
        a->rows.push_back(row);
    }
}

// The contour points (untangle.hpp) of a store's EF interferences, at the
// positions of the query, with their segment keys; first and second are
// the store's bodies, by index; its records are a->records (copy_records).
void gather_contour_points(selfcol_bullet *a, const selfcol_store *store, size_t first,
                           size_t second) {
    const selfcol_store_contact *c = a->records.data();
    const size_t count = selfcol_store_contact_count(store);
    const size_t body_of[2] = {first, second};
    for (size_t k = 0; k < count; ++k) {
        if (c[k].kind != SELFCOL_CONTACT_EF)
            continue;
        const attached_body &eb = a->bodies[body_of[c[k].first_mesh]];
        const attached_body &tb = a->bodies[body_of[c[k].second_mesh]];
        const double *pe = selfcol_mesh_positions(eb.mesh);
        const double *pt = selfcol_mesh_positions(tb.mesh);
        contour_point q;
        if (!contour_point_make(pe + 3 * size_t(c[k].a[0]), pe + 3 * size_t(c[k].a[1]),
                                pt + 3 * size_t(c[k].b[0]), pt + 3 * size_t(c[k].b[1]),
                                pt + 3 * size_t(c[k].b[2]), q))
            continue;
        q.node[0] = slot_for(a, eb, c[k].a[0]);
        q.node[1] = slot_for(a, eb, c[k].a[1]);
        for (int v = 0; v < 3; ++v)
            q.node[2 + v] = slot_for(a, tb, c[k].b[v]);
        const uint32_t point = uint32_t(a->contour_points.size());
        a->contour_points.push_back(q);
        // One segment end per face of the edge: the crossing pair (that
        // face, the triangle).
        const uint64_t triangle = uint64_t(body_of[c[k].second_mesh]) << 32 | c[k].second;
        const edge_face probe = {edge_key(eb.first_node + c[k].a[0], eb.first_node + c[k].a[1]), 0};
        for (auto it = std::lower_bound(a->edge_faces.begin(), a->edge_faces.end(), probe);
             it != a->edge_faces.end() && it->edge == probe.edge; ++it)
            a->contour_keys.push_back(
                {std::min(it->face, triangle), std::max(it->face, triangle), point});
    }
}

// The untangling step over the gathered points: moves the nodes' response
// slots (after the contact response). Returns the interferences that moved
// nodes.
size_t untangle(selfcol_bullet *a) {
    contour_link(a->contour_points.data(), a->contour_keys.data(), a->contour_keys.size());
    a->contour_delta.resize(3 * a->nodes.size());
    return contour_push(a->contour_points.data(), a->contour_points.size(), a->nodes.data(),
                        a->nodes.size(), a->contour_delta.data(),
                        SELFCOL_BULLET_UNTANGLE_STEP * a->distance);
}

// The continuous option's hierarchy of a body (made once, on the adapter's
// allocator like every handle it makes).
int ensure_sweep_tree(selfcol_bullet *a, attached_body &b) {
    if (b.sweep_tree != nullptr)
        return SELFCOL_OK;
    selfcol_hierarchy_options ho;
    selfcol_hierarchy_options_init(&ho, SELFCOL_HIERARCHY_OPTIONS_VERSION);
    ho.allocator = a->hooks;
    return selfcol_hierarchy_create(&b.sweep_tree, b.mesh, &ho);
}

// The key of a VF pair (kind 0: its vertex, then its triangle's nodes
// sorted) or an EE pair (kind 1: each edge's nodes sorted, the two edges in
// order, the last slot unused), in the adapter's node numbering.
crossing_key vf_key(uint32_t vertex, uint32_t t0, uint32_t t1, uint32_t t2) {
    uint32_t t[3] = {t0, t1, t2};
    std::sort(t, t + 3);
    return crossing_key{{0, vertex, t[0], t[1], t[2]}};
}

crossing_key ee_key(uint32_t a0, uint32_t a1, uint32_t b0, uint32_t b1) {
    uint32_t e[2][2] = {{std::min(a0, a1), std::max(a0, a1)}, {std::min(b0, b1), std::max(b0, b1)}};
    const int lo = e[0][0] < e[1][0] || (e[0][0] == e[1][0] && e[0][1] < e[1][1]) ? 0 : 1;
    return crossing_key{{1, e[lo][0], e[lo][1], e[1 - lo][0], e[1 - lo][1]}};
}

// Whether a continuous pair (its 5 nodes, continuous_pass: a VF pair's
// vertex twice) is part of an edge-triangle crossing where the step
// started: a vertex of the crossing edge against the triangle, or the edge
// against one of the triangle's edges. Such a pair's motion is let
// through. A crossing that is there can only be undone by its elements
// passing back through each other, which the hold-back stops: on the
// fast-compression ribbon the crossings that got past the passes stayed
// to the end (benchmarks.md). Only these pairs: letting through every pair
// whose nodes share a face with a crossing's let the crossings spread from
// step to step (the ribbon demo at full size: 583k contacts at step 334,
// against a peak of 77k over the whole run without it).
bool in_crossing(const selfcol_bullet *a, const uint32_t nodes[5]) {
    if (!a->crossings_known || a->crossing_keys.empty())
        return false;
    const crossing_key k = nodes[0] == nodes[1] ? vf_key(nodes[0], nodes[2], nodes[3], nodes[4])
                                                : ee_key(nodes[0], nodes[1], nodes[2], nodes[3]);
    return std::binary_search(a->crossing_keys.begin(), a->crossing_keys.end(), k);
}

// Finds the crossings where the nodes are now (the next step's start): an
// exact EF query (contacts.h: edges crossing triangles) of every body and
// body pair on the continuous option's hierarchies, refit here; keeps the
// keys of the pairs each crossing holds (in_crossing).
int mark_crossings(selfcol_bullet *a) {
    a->crossings_known = false;
    a->crossing_keys.clear();
    if (a->crossing_hits == nullptr) {
        selfcol_contacts_options co;
        selfcol_contacts_options_init(&co, SELFCOL_CONTACTS_OPTIONS_VERSION);
        co.allocator = a->hooks;
        int status = selfcol_contacts_create(&a->crossing_hits, &co);
        if (status != SELFCOL_OK)
            return status;
    }
    selfcol_context *c = context_of(a);
    for (attached_body &b : a->bodies) {
        int status = selfcol_mesh_set_positions_float(
            b.mesh, node_positions(b.body), sizeof(btSoftBody::Node), size_t(b.node_count));
        if (status == SELFCOL_OK)
            status = ensure_sweep_tree(a, b);
        if (status == SELFCOL_OK)
            status = c != nullptr ? selfcol_context_refit(c, b.sweep_tree)
                                  : selfcol_hierarchy_refit(b.sweep_tree);
        if (status != SELFCOL_OK)
            return status;
    }
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.kinds = SELFCOL_KIND_EF;
    q.distance = a->distance;
    for (size_t i = 0; i < a->bodies.size(); ++i)
        for (size_t j = i; j < a->bodies.size(); ++j) {
            const attached_body &bi = a->bodies[i], &bj = a->bodies[j];
            int status;
            if (i == j)
                status = c != nullptr
                             ? selfcol_context_self_collide(c, bi.sweep_tree, a->crossing_hits, &q)
                             : selfcol_hierarchy_self_collide(bi.sweep_tree, a->crossing_hits, &q);
            else
                status = c != nullptr ? selfcol_context_collide(c, bi.sweep_tree, bj.sweep_tree,
                                                                a->crossing_hits, &q)
                                      : selfcol_hierarchy_collide(bi.sweep_tree, bj.sweep_tree,
                                                                  a->crossing_hits, &q);
            if (status != SELFCOL_OK)
                return status;
            const selfcol_contact *r = nullptr;
            size_t n = 0;
            selfcol_contacts_data(a->crossing_hits, &r, &n);
            for (size_t k = 0; k < n; ++k) {
                const uint32_t fa = (r[k].first_mesh == 0 ? bi : bj).first_node;
                const uint32_t fb = (r[k].second_mesh == 0 ? bi : bj).first_node;
                const uint32_t e[2] = {fa + r[k].a[0], fa + r[k].a[1]};
                const uint32_t t[3] = {fb + r[k].b[0], fb + r[k].b[1], fb + r[k].b[2]};
                for (int v = 0; v < 2; ++v)
                    a->crossing_keys.push_back(vf_key(e[v], t[0], t[1], t[2]));
                for (int v = 0; v < 3; ++v)
                    a->crossing_keys.push_back(ee_key(e[0], e[1], t[v], t[(v + 1) % 3]));
            }
        }
    // Five keys per crossing, before the sort (a pair may be in several).
    a->stats.crossings_after = a->crossing_keys.size() / 5;
    std::sort(a->crossing_keys.begin(), a->crossing_keys.end());
    a->crossings_known = true;
    return SELFCOL_OK;
}

// One continuous pass: every attached node's motion from where the last
// step left it to where it is now, through the continuous query of every
// body pair; on_hit(nodes, toi) for each pair that touches on the way, its
// nodes in the adapter's numbering (a VF pair's vertex repeated in the
// fifth). Returns the status; *hits counts the pairs, which become
// a->pass_hits and a->pass_toi.
//
// `restricted`: only the pairs with a node whose motion changed since the
// last pass (a->moved) are queried (selfcol_sweep_options.active_vertices);
// every other pair moves as it did in the last pass, so it touches exactly
// when it did then: the last pass's pairs without a moved node are carried
// over. The pairs are those of a full pass (in another order, which
// nothing downstream depends on: holds take minima, zones union-find roots
// by lowest node), at the cost of the moved nodes' neighbourhoods.
//
// Pairs of a crossing where the step started (in_crossing) are let
// through, not reported: *exempt counts those the query found.
template <class F>
int continuous_pass(selfcol_bullet *a, uint64_t *hits, uint64_t *exempt, bool restricted,
                    F on_hit) {
    *hits = 0;
    *exempt = 0;
    for (const attached_body &b : a->bodies) {
        int status = selfcol_mesh_set_positions_float(
            b.mesh, node_positions(b.body), sizeof(btSoftBody::Node), size_t(b.node_count));
        if (status != SELFCOL_OK)
            return status;
    }
    a->next_hits.clear();
    a->next_toi.clear();
    selfcol_sweep_options so;
    selfcol_sweep_options_init(&so, SELFCOL_SWEEP_OPTIONS_VERSION);
    for (size_t i = 0; i < a->bodies.size(); ++i)
        for (size_t j = i; j < a->bodies.size(); ++j) {
            const attached_body &bi = a->bodies[i], &bj = a->bodies[j];
            const double *si = a->previous.data() + 3 * size_t(bi.first_node);
            const double *sj = a->previous.data() + 3 * size_t(bj.first_node);
            if (restricted) {
                so.active_vertices[0] = a->moved.data() + bi.first_node;
                so.active_vertices[1] = a->moved.data() + bj.first_node;
            }
            // On Bullet's scheduler when the adapter uses it, else on the
            // adapter's threads: the hits are the same.
            selfcol_context *c = context_of(a);
            int status;
            if (i == j && c != nullptr)
                status = selfcol_context_self_sweep(c, bi.sweep_tree, si, a->sweep, &so);
            else if (i == j)
                status = selfcol_hierarchy_self_sweep(bi.sweep_tree, si, a->sweep, &so);
            else if (c != nullptr)
                status =
                    selfcol_context_sweep(c, bi.sweep_tree, si, bj.sweep_tree, sj, a->sweep, &so);
            else
                status =
                    selfcol_hierarchy_sweep(bi.sweep_tree, si, bj.sweep_tree, sj, a->sweep, &so);
            if (status != SELFCOL_OK)
                return status;
            const selfcol_sweep_hit *h = nullptr;
            size_t n = 0;
            selfcol_sweep_hits(a->sweep, &h, &n);
            for (size_t k = 0; k < n; ++k) {
                const attached_body &first = h[k].first_mesh == 0 ? bi : bj;
                const attached_body &second = h[k].second_mesh == 0 ? bi : bj;
                const uint32_t nodes[5] = {
                    first.first_node + h[k].a[0], first.first_node + h[k].a[1],
                    second.first_node + h[k].b[0], second.first_node + h[k].b[1],
                    h[k].b[2] == SELFCOL_INVALID_INDEX ? first.first_node + h[k].a[0]
                                                       : second.first_node + h[k].b[2]};
                if (in_crossing(a, nodes)) {
                    ++*exempt;
                    continue;
                }
                a->next_hits.insert(a->next_hits.end(), nodes, nodes + 5);
                a->next_toi.push_back(h[k].toi);
            }
        }
    if (restricted) // the last pass's pairs of unmoved nodes, as they were
        for (size_t p = 0; p < a->pass_toi.size(); ++p) {
            const uint32_t *nodes = a->pass_hits.data() + 5 * p;
            bool unmoved = true;
            for (int k = 0; k < 5; ++k)
                unmoved = unmoved && a->moved[nodes[k]] == 0;
            if (unmoved) {
                a->next_hits.insert(a->next_hits.end(), nodes, nodes + 5);
                a->next_toi.push_back(a->pass_toi[p]);
            }
        }
    a->pass_hits.swap(a->next_hits);
    a->pass_toi.swap(a->next_toi);
    *hits = a->pass_toi.size();
    for (size_t p = 0; p < a->pass_toi.size(); ++p)
        on_hit(a->pass_hits.data() + 5 * p, a->pass_toi[p]);
    return SELFCOL_OK;
}

// The rigid impact zones (impact_zones.hpp), the continuous option's
// fail-safe: the pairs that still touch after the held-back passes join
// zones, every zone moves as one body from the step's start, and the
// continuous query runs again on those motions, merging zones, until no
// pair touches or SELFCOL_BULLET_CONTINUOUS_ZONE_PASSES have run; after
// the first rigid_zone_passes, the zones without kinematic nodes stay where
// the step started. *remaining: the pairs of the last pass.
//
// Once the zones stay still, a pass whose pairs merge no zones pins the free
// nodes of those pairs where the step started, for the rest of the step,
// and the passes go on while they pin new nodes. A zone that holds
// kinematic nodes moves with them, and a pair inside it that touched at the
// step's start (within the query's error band) is moved by the zone's rigid
// motion, which keeps its side in exact arithmetic but not once written to
// Bullet's floats: on the fast-compression ribbon a vertex 2.7e-10 from a
// neighbouring triangle's plane, in a zone that the kinematic end moved
// 2.1 mm, ended 7.3e-10 on the other side, and each such step (159, 226,
// 323 of 400) let in 6 crossings that stayed for the rest of the run
// (benchmarks.md). A pair whose free nodes are all pinned ends exactly
// where it started (the start positions are Bullet's floats), and the pairs
// that pinning makes between pinned nodes and moving ones are the next
// pass's. When pinning pins nothing new, follow_driven() may release nodes
// that a driven element sweeps into.
const int rigid_zone_passes = 8;

// When pinning pins nothing new: the free nodes of the last pass's pairs
// that hold a driven node (kinematic, or following) and first touch after
// the step's start follow their zone again (ZONE_NODE_FOLLOWS: a zone with
// kinematic nodes moves with them), so that a driven element sweeping into
// a pinned node pushes it along instead of passing through it, and the
// passes go on. Pairs that touch at the start keep their nodes pinned (the
// rounding above). On the fast-compression ribbon a perturbed trajectory
// (the continuous search's coplanarity test, 2026-11-29) ended the passes
// of step 366 with 3 such pairs left, the driven end against pinned nodes,
// and 16 to 30 EF stayed to the end; with this, 1 pair was left there, 8 EF
// came in and were undone by step 368 (benchmarks.md).
static bool follow_driven(selfcol_bullet *a) {
    bool started = false;
    for (size_t p = 0; p < a->pass_toi.size(); ++p) {
        const uint32_t *nodes = a->pass_hits.data() + 5 * p;
        if (!(a->pass_toi[p] > 0))
            continue;
        bool driven = false;
        for (int k = 0; k < 5; ++k)
            driven = driven || !(a->zone_inverse_mass[nodes[k]] > 0) ||
                     a->pinned[nodes[k]] == ZONE_NODE_FOLLOWS;
        if (!driven)
            continue;
        for (int k = 0; k < 5; ++k) {
            const uint32_t v = nodes[k];
            if (!(a->zone_inverse_mass[v] > 0) || a->pinned[v] == ZONE_NODE_FOLLOWS)
                continue;
            a->pinned[v] = ZONE_NODE_FOLLOWS;
            started = true;
        }
    }
    return started;
}

int impact_zones(selfcol_bullet *a, double dt, uint64_t *remaining) {
    selfcol_bullet_step_stats &st = a->stats;
    const size_t n = a->node_total;
    a->zone_parent.resize(n);
    a->zone_total.resize(n);
    a->zone_end.resize(3 * n);
    a->zone_inverse_mass.resize(n);
    zones_reset(a->zone_parent.data(), n);
    a->pinned.assign(n, 0);
    // The last held-back pass's pairs (its positions are still the nodes'):
    // its sweep is not run again.
    for (size_t i = 0; i + 5 <= a->pass_hits.size(); i += 5)
        for (int k = 1; k < 5; ++k)
            zones_unite(a->zone_parent.data(), a->pass_hits[i], a->pass_hits[i + size_t(k)]);
    for (int pass = 0; pass < SELFCOL_BULLET_CONTINUOUS_ZONE_PASSES; ++pass) {
        for (const attached_body &b : a->bodies)
            for (int v = 0; v < b.node_count; ++v) {
                const size_t node = size_t(b.first_node) + size_t(v);
                const btSoftBody::Node &nd = b.body->m_nodes[v];
                for (int k = 0; k < 3; ++k)
                    a->zone_end[3 * node + size_t(k)] = double(nd.m_x[k]);
                a->zone_inverse_mass[node] = double(nd.m_im);
            }
        // After the rigid passes, zones stay where the step started.
        const bool freeze = pass + 1 >= rigid_zone_passes;
        zones_move(a->zone_parent.data(), n, a->previous.data(), a->zone_end.data(),
                   a->zone_inverse_mass.data(), a->zone_total.data(), freeze);
        zones_hold_pinned(a->pinned.data(), n, a->previous.data(), a->zone_end.data());
        uint64_t zone_moved = 0;
        std::fill(a->moved.begin(), a->moved.end(), uint8_t(0));
        for (const attached_body &b : a->bodies)
            for (int v = 0; v < b.node_count; ++v) {
                const size_t node = size_t(b.first_node) + size_t(v);
                btSoftBody::Node &nd = b.body->m_nodes[v];
                if (nd.m_im <= 0 || a->zone_total[a->zone_parent[node]].size < 2)
                    continue;       // kinematic, or in no zone
                a->moved[node] = 1; // zones only grow: a zone's node moves every pass
                const double *e = a->zone_end.data() + 3 * node;
                const double *p = a->previous.data() + 3 * node;
                const btVector3 x{btScalar(e[0]), btScalar(e[1]), btScalar(e[2])};
                nd.m_x = x;
                nd.m_q = x;
                // The zone's velocity: its displacement over the step.
                nd.m_v = btVector3(btScalar((e[0] - p[0]) / dt), btScalar((e[1] - p[1]) / dt),
                                   btScalar((e[2] - p[2]) / dt));
                nd.m_vn = nd.m_v;
                zone_moved++;
            }
        st.zone_nodes = zone_moved;
        uint64_t hits = 0;
        bool merged = false;
        uint64_t exempt = 0;
        int status =
            continuous_pass(a, &hits, &exempt, true, [a, &merged](const uint32_t nodes[5], double) {
                uint32_t *parent = a->zone_parent.data();
                for (int k = 1; k < 5; ++k) {
                    merged = merged || zone_root(parent, nodes[0]) != zone_root(parent, nodes[k]);
                    zones_unite(parent, nodes[0], nodes[k]);
                }
            });
        if (status != SELFCOL_OK)
            return status;
        st.continuous_passes++;
        *remaining = hits;
        // Once still, a pass whose pairs all lie within a zone each merged
        // nothing: the next pass would move the same zones the same way (the
        // nodes' motions are a function of the zones, and freeze stays on),
        // find the same pairs and repeat this one bit for bit, up to the
        // cap. Such pairs are those within the query's error band of
        // touching at the step's start, reported at time 0 in every pass
        // (benchmarks.md, the fast-compression ribbon): no pass clears them.
        if (hits == 0 || (freeze && !merged &&
                          !zones_pin(a->pinned.data(), a->pass_hits.data(), a->pass_hits.size(),
                                     a->zone_inverse_mass.data()) &&
                          !follow_driven(a)))
            break;
    }
    return SELFCOL_OK;
}

// The continuous option (bullet.h, `continuous`): hold back the nodes of
// every pair that would touch during the step, as Bridson, Fedkiw and
// Anderson (2002) stop colliding nodes at their time of impact, here
// without impulses: each such node keeps SELFCOL_BULLET_CONTINUOUS_HOLD of
// the pair's earliest time of impact of its motion, its velocity scaled
// alike, and the query runs again on the held motion; the pairs left after
// SELFCOL_BULLET_CONTINUOUS_PASSES go to the impact zones.
int hold_back(selfcol_bullet *a, double dt) {
    selfcol_bullet_step_stats &st = a->stats;
    if (a->sweep == nullptr) {
        int status = selfcol_sweep_create(&a->sweep, &a->hooks);
        if (status != SELFCOL_OK)
            return status;
    }
    for (attached_body &b : a->bodies) {
        int status = ensure_sweep_tree(a, b);
        if (status != SELFCOL_OK)
            return status;
    }
    a->keep.assign(a->node_total, 1.0);
    a->moved.assign(a->node_total, 0);
    for (int pass = 0; pass < SELFCOL_BULLET_CONTINUOUS_PASSES; ++pass) {
        std::fill(a->keep.begin(), a->keep.end(), 1.0);
        uint64_t hits = 0, held = 0;
        // The first pass queries every pair, the later ones those of the
        // nodes the last pass held back.
        uint64_t exempt = 0;
        int status =
            continuous_pass(a, &hits, &exempt, pass > 0, [a](const uint32_t nodes[5], double toi) {
                const double factor = SELFCOL_BULLET_CONTINUOUS_HOLD * toi;
                for (int k = 0; k < 5; ++k)
                    a->keep[nodes[k]] = std::min(a->keep[nodes[k]], factor);
            });
        if (status != SELFCOL_OK)
            return status;
        if (pass == 0) {
            st.continuous_hits = hits;
            st.continuous_exempt = exempt;
        }
        st.continuous_passes++;
        st.continuous_remaining = hits;
        if (hits == 0)
            return SELFCOL_OK;
        if (pass + 1 == SELFCOL_BULLET_CONTINUOUS_PASSES)
            break;
        std::fill(a->moved.begin(), a->moved.end(), uint8_t(0));
        for (const attached_body &b : a->bodies)
            for (int v = 0; v < b.node_count; ++v) {
                const uint32_t node = b.first_node + uint32_t(v);
                const double f = a->keep[node];
                btSoftBody::Node &n = b.body->m_nodes[v];
                if (f >= 1.0 || n.m_im <= 0)
                    continue; // free, or kinematic: never held
                const double *p = a->previous.data() + 3 * size_t(node);
                btVector3 x(btScalar(p[0] + f * (double(n.m_x.x()) - p[0])),
                            btScalar(p[1] + f * (double(n.m_x.y()) - p[1])),
                            btScalar(p[2] + f * (double(n.m_x.z()) - p[2])));
                n.m_x = x;
                n.m_q = x;
                n.m_v *= btScalar(f);
                n.m_vn = n.m_v;
                a->moved[node] = 1;
                held++;
            }
        st.continuous_held += held;
        if (held == 0)
            break; // only kinematic nodes are involved
    }
    // The last held-back pass's pairs (a->pass_hits) are the zones' first.
    return impact_zones(a, dt, &st.continuous_remaining);
}

// Where this step leaves every attached node: the next step's start.
void remember_positions(selfcol_bullet *a) {
    a->previous.resize(3 * size_t(a->node_total));
    for (const attached_body &b : a->bodies)
        for (int v = 0; v < b.node_count; ++v) {
            const btVector3 &x = b.body->m_nodes[v].m_x;
            double *p = a->previous.data() + 3 * (size_t(b.first_node) + size_t(v));
            p[0] = double(x.x());
            p[1] = double(x.y());
            p[2] = double(x.z());
        }
    a->have_previous = true;
}

int step_impl(selfcol_bullet *a, double dt) {
    if (!(dt > 0) || !std::isfinite(dt))
        return SELFCOL_EINVAL;
    // A body removed from the world is dropped before anything reads it.
    for (size_t i = a->bodies.size(); i-- > 0;)
        if (!in_world(a, a->bodies[i].body))
            drop_body(a, i);
    if (a->bodies.empty())
        return SELFCOL_OK;
    for (const attached_body &b : a->bodies)
        if (b.body->m_nodes.size() != b.node_count || b.body->m_faces.size() != b.face_count)
            return SELFCOL_ESTALE;
    // Velocities are checked like positions (those by the mesh setter):
    // the response mixes the velocities of every node a contact joins, so
    // one NaN would spread to other nodes and other bodies.
    for (const attached_body &b : a->bodies)
        if (!finite_velocities(b.body))
            return SELFCOL_EINVAL;
    double t0 = now_seconds();
    int status;
    for (const attached_body &b : a->bodies) {
        status = selfcol_mesh_set_positions_float(b.mesh, node_positions(b.body),
                                                  sizeof(btSoftBody::Node), size_t(b.node_count));
        if (status != SELFCOL_OK)
            return status;
    }
    if (a->scene == nullptr) {
        status = build_scene(a);
        if (status == SELFCOL_OK && context_of(a) != nullptr)
            status = selfcol_scene_set_context(a->scene, context_of(a));
        if (status != SELFCOL_OK)
            return status;
    }
    if (a->opts.continuous && a->have_previous)
        for (const attached_body &b : a->bodies) {
            status = selfcol_scene_set_surface_start(a->scene, b.surface,
                                                     a->previous.data() + 3 * size_t(b.first_node));
            if (status != SELFCOL_OK)
                return status;
        }
    status = selfcol_scene_update(a->scene);
    if (status != SELFCOL_OK)
        return status;
    double t1 = now_seconds();

    // Forget the last step's slots. The write-back below resets them too, but
    // a step that failed (ENOMEM while gathering) left some set.
    forget_slots(a);
    uint64_t crossed = 0;
    for (size_t i = 0; i < a->bodies.size(); ++i)
        for (size_t j = i; j < a->bodies.size(); ++j) {
            const selfcol_store *store = nullptr;
            if (selfcol_scene_store(a->scene, a->bodies[i].surface, a->bodies[j].surface, &store) !=
                    SELFCOL_OK ||
                store == nullptr)
                continue;
            status = copy_records(a, store);
            if (status != SELFCOL_OK)
                return status;
            gather_rows(a, store, a->bodies[i], a->bodies[j], &crossed);
            if (a->opts.untangle)
                gather_contour_points(a, store, i, j);
        }
    response_result r = response_solve(a->rows.data(), a->rows.size(), a->nodes.data(), a->distance,
                                       a->opts.repulsion, a->opts.iterations);
    size_t untangled = a->opts.untangle ? untangle(a) : 0;
    // Write back: positions (and q, which Bullet keeps equal to x between
    // steps) and velocities (and vn, the step's final velocity).
    for (size_t s = 0; s < a->nodes.size(); ++s) {
        btSoftBody::Node *n = a->node_of_slot[s];
        const response_node &r = a->nodes[s];
        n->m_x.setValue(btScalar(r.x[0]), btScalar(r.x[1]), btScalar(r.x[2]));
        n->m_q = n->m_x;
        n->m_v.setValue(btScalar(r.v[0]), btScalar(r.v[1]), btScalar(r.v[2]));
        n->m_vn = n->m_v;
        a->slot_of_node[a->global_of_slot[s]] = -1;
    }
    double t2 = now_seconds();
    a->stats.continuous_hits = a->stats.continuous_held = 0;
    a->stats.continuous_passes = a->stats.continuous_remaining = 0;
    a->stats.zone_nodes = a->stats.continuous_exempt = 0;
    a->stats.crossings_after = 0;
    a->stats.seconds_continuous = 0;
    if (a->opts.continuous) {
        if (a->have_previous) {
            status = hold_back(a, dt);
            if (status != SELFCOL_OK)
                return status;
        }
        status = mark_crossings(a);
        if (status != SELFCOL_OK)
            return status;
        remember_positions(a);
        a->stats.seconds_continuous = now_seconds() - t2;
    }

    selfcol_scene_update_stats ss;
    ss.version = SELFCOL_SCENE_UPDATE_STATS_VERSION;
    selfcol_scene_stats(a->scene, &ss);
    selfcol_bullet_step_stats &st = a->stats;
    st.distance = a->distance;
    st.contacts = ss.contacts;
    st.interferences = ss.interferences;
    st.crossed = crossed;
    st.flipped = ss.flipped;
    st.passed_around = ss.passed_around;
    st.corrected = ss.corrected;
    st.responses = r.responses;
    st.untangled = untangled;
    st.max_push = r.max_push;
    st.seconds_detect = t1 - t0;
    st.seconds_response = t2 - t1;
    return SELFCOL_OK;
}

} // namespace

extern "C" int selfcol_bullet_options_init(selfcol_bullet_options *opts, unsigned int version) {
    if (opts == nullptr)
        return SELFCOL_EINVAL;
    // 0.2's versions 1 and 2 held the query and store fields flat: their
    // layouts differ from version 3 after the allocator.
    if (version != SELFCOL_BULLET_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    std::memset(opts, 0, sizeof *opts);
    opts->version = version;
    opts->distance_factor = SELFCOL_BULLET_DEFAULT_DISTANCE_FACTOR;
    opts->repulsion = SELFCOL_BULLET_DEFAULT_REPULSION;
    opts->iterations = SELFCOL_BULLET_DEFAULT_ITERATIONS;
    opts->automatic = 1;
    opts->untangle = 1;
    opts->continuous = 0;
    opts->coherent = 1;
    opts->threads = 1;
    return SELFCOL_OK;
}

namespace {

// Names a refused field of selfcol_bullet_options in problem (may be
// NULL); returns status.
int refuse(selfcol_options_problem *problem, int status, const char *field, const char *what,
           double value) {
    if (problem != nullptr) {
        problem->status = status;
        std::snprintf(problem->field, sizeof problem->field, "%s", field);
        std::snprintf(problem->message, sizeof problem->message,
                      "selfcol_bullet_options.%s = %g %s", field, value, what);
    }
    return status;
}

// The adapter's options as selfcol_bullet_create() keeps them: its own
// fields, and copies of the query and store options they point to.
struct settings {
    selfcol_bullet_options o; // o.query and o.store: NULL (see query and store)
    selfcol_query_options query;
    selfcol_store_options store;
};

// The adapter's own fields; the query and store options by the core's
// rules, which a scene made and destroyed here applies (at the given
// distance, or 1 when it will come from the bodies): an adapter that is
// created can make its scene, rather than fail at every step. problem
// (NULL: none) names what is refused.
int check_options(const settings &s, selfcol_options_problem *problem) {
    const selfcol_bullet_options &o = s.o;
    if ((o.allocator.alloc == nullptr) != (o.allocator.free == nullptr)) {
        if (problem != nullptr) {
            problem->status = SELFCOL_EINVAL;
            std::snprintf(problem->field, sizeof problem->field, "allocator");
            std::snprintf(problem->message, sizeof problem->message,
                          "selfcol_bullet_options.allocator is half set: give both alloc and "
                          "free, or neither");
        }
        return SELFCOL_EINVAL;
    }
    const double distance = s.query.distance;
    if (!(distance >= 0) || !(distance <= SELFCOL_MESH_MAX_COORDINATE)) // NaN fails both
        return refuse(problem, SELFCOL_EINVAL, "query->distance",
                      "is not a distance in 0 .. 1.6e+60 (0: from the bodies)", distance);
    if (distance == 0 && (!(o.distance_factor > 0) || !std::isfinite(o.distance_factor)))
        return refuse(problem, SELFCOL_EINVAL, "distance_factor",
                      "is not a finite factor > 0 (the query's distance is 0)", o.distance_factor);
    if (!(o.repulsion > 0 && o.repulsion <= 1))
        return refuse(problem, SELFCOL_EINVAL, "repulsion", "is not in (0, 1]", o.repulsion);
    if (o.iterations == 0 || o.iterations > 64)
        return refuse(problem, SELFCOL_EINVAL, "iterations", "is not in 1 .. 64",
                      double(o.iterations));
    if (o.threads == 0 || o.threads > SELFCOL_MAX_THREADS)
        return refuse(problem, SELFCOL_EINVAL, "threads", "is not in 1 .. 64", double(o.threads));
    const struct {
        const char *field;
        int value;
    } flags[] = {{"automatic", o.automatic},
                 {"untangle", o.untangle},
                 {"continuous", o.continuous},
                 {"coherent", o.coherent}};
    for (const auto &f : flags)
        if (f.value != 0 && f.value != 1)
            return refuse(problem, SELFCOL_EINVAL, f.field, "is not 0 or 1", double(f.value));
    selfcol_query_options query = s.query;
    selfcol_scene_options so = scene_options(o, s.store, distance > 0 ? distance : 1.0, query);
    if (problem != nullptr) {
        // The scene's check names query->* and store->*, which are this
        // struct's fields of the same names.
        const int status = selfcol_scene_options_check(&so, problem);
        if (status != SELFCOL_OK) {
            const char *scene = "selfcol_scene_options.";
            std::string text = problem->message;
            if (text.compare(0, std::strlen(scene), scene) == 0)
                text = "selfcol_bullet_options." + text.substr(std::strlen(scene));
            std::snprintf(problem->message, sizeof problem->message, "%s", text.c_str());
            return status;
        }
    }
    selfcol_scene *trial = nullptr;
    int status = selfcol_scene_create(&trial, &so);
    selfcol_scene_destroy(trial);
    return status;
}

// The options as given (NULL: the defaults) into s, checked.
int read_options(const selfcol_bullet_options *opts, settings &s,
                 selfcol_options_problem *problem) {
    selfcol_bullet_options_init(&s.o, SELFCOL_BULLET_OPTIONS_VERSION);
    selfcol_query_options_init(&s.query, SELFCOL_QUERY_OPTIONS_VERSION);
    selfcol_store_options_init(&s.store, SELFCOL_STORE_OPTIONS_VERSION);
    if (opts != nullptr) {
        if (opts->version != SELFCOL_BULLET_OPTIONS_VERSION)
            return refuse(problem, SELFCOL_EVERSION, "version",
                          "is not this library's (its _init function sets it; 3 was 0.3's "
                          "layout)",
                          double(opts->version));
        s.o = *opts;
        // Copied whole: each has one layout in 0.4 (version 3), and the
        // core's check below names any other version.
        if (opts->query != nullptr)
            s.query = *opts->query;
        if (opts->store != nullptr)
            s.store = *opts->store;
        s.o.query = nullptr;
        s.o.store = nullptr;
    }
    return check_options(s, problem);
}

} // namespace

extern "C" int selfcol_bullet_options_check(const selfcol_bullet_options *opts,
                                            selfcol_options_problem *problem) {
    if (problem == nullptr)
        return SELFCOL_EINVAL;
    if (problem->version == 0 || problem->version > SELFCOL_OPTIONS_PROBLEM_VERSION)
        return SELFCOL_EVERSION;
    problem->status = SELFCOL_OK;
    problem->field[0] = problem->message[0] = '\0';
    settings s;
    return read_options(opts, s, problem);
}

extern "C" int selfcol_bullet_create(selfcol_bullet **out,
                                     btDeformableMultiBodyDynamicsWorld *world,
                                     const selfcol_bullet_options *opts) {
    if (out == nullptr)
        return SELFCOL_EINVAL;
    *out = nullptr;
    if (world == nullptr)
        return SELFCOL_EINVAL;
    settings s;
    int status = read_options(opts, s, nullptr);
    if (status != SELFCOL_OK)
        return status;
    const selfcol_bullet_options &o = s.o;
    void *memory = hook_alloc(o.allocator, sizeof(selfcol_bullet), alignof(selfcol_bullet));
    if (memory == nullptr)
        return SELFCOL_ENOMEM;
    selfcol_bullet *a = new (memory) selfcol_bullet(o.allocator);
    a->opts = o;
    a->query = s.query;
    a->store = s.store;
    a->world = world;
    if (o.threads > 1) {
        selfcol_context_options co;
        selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
        co.allocator = o.allocator;
        co.threads = o.threads;
        status = selfcol_context_create(&a->own_context, &co);
        if (status != SELFCOL_OK) {
            a->~selfcol_bullet();
            hook_free(o.allocator, memory, sizeof(selfcol_bullet));
            return status;
        }
    }
    a->stats.version = SELFCOL_BULLET_STEP_STATS_VERSION;
    if (o.automatic) {
        void *am = hook_alloc(o.allocator, sizeof(step_action), alignof(step_action));
        if (am == nullptr) {
            selfcol_context_destroy(a->own_context);
            a->~selfcol_bullet();
            hook_free(o.allocator, memory, sizeof(selfcol_bullet));
            return SELFCOL_ENOMEM;
        }
        a->action = new (am) step_action(a);
        try {
            world->addAction(a->action);
        } catch (...) {
            selfcol_bullet_destroy(a);
            return SELFCOL_ENOMEM;
        }
    }
    *out = a;
    return SELFCOL_OK;
}

namespace {

// Frees the adapter; with world_alive, first removes its action from the
// world and restores the attached bodies still in it. Without, it reads
// neither the world nor any body (both may have been deleted).
void destroy_adapter(selfcol_bullet *a, bool world_alive) {
    if (a == nullptr)
        return;
    if (a->action != nullptr) {
        if (world_alive) {
            try {
                a->world->removeAction(a->action);
            } catch (...) {
            }
        }
        a->action->~step_action();
        hook_free(a->hooks, a->action, sizeof(step_action));
    }
    selfcol_scene_destroy(a->scene);
    selfcol_context_destroy(a->task_context);
    selfcol_context_destroy(a->own_context);
    for (attached_body &b : a->bodies) {
        if (world_alive && in_world(a, b.body)) // one that left the world may be deleted
            restore_body(b);
        selfcol_hierarchy_destroy(b.sweep_tree);
        selfcol_mesh_destroy(b.mesh);
    }
    selfcol_sweep_destroy(a->sweep);
    selfcol_contacts_destroy(a->crossing_hits);
    selfcol_allocator hooks = a->hooks;
    a->~selfcol_bullet();
    hook_free(hooks, a, sizeof(selfcol_bullet));
}

// A selfcol task (context.h) as one btParallelFor: Bullet's scheduler
// splits the items among its threads and returns when all have run.
struct task_body : btIParallelForBody {
    selfcol_task_fn *task;
    void *task_context;
    task_body(selfcol_task_fn *t, void *c) : task(t), task_context(c) {}
    void forLoop(int begin, int end) const override {
        task(uint32_t(begin), uint32_t(end), btGetCurrentThreadIndex(), task_context);
    }
};

void *enqueue_on_bullet(selfcol_task_fn *task, uint32_t item_count, uint32_t min_range,
                        void *task_context, void *user_context) {
    (void)user_context;
    const task_body body(task, task_context);
    btParallelFor(0, int(item_count), int(min_range), body);
    return nullptr; // every item ran
}

void finish_on_bullet(void *user_task, void *user_context) {
    (void)user_task;
    (void)user_context;
}

} // namespace

extern "C" int selfcol_bullet_use_task_scheduler(selfcol_bullet *a, int on) {
    if (a == nullptr || (on != 0 && on != 1))
        return SELFCOL_EINVAL;
    selfcol_context *context = nullptr;
    if (on) {
        selfcol_context_options o;
        selfcol_context_options_init(&o, SELFCOL_CONTEXT_OPTIONS_VERSION);
        o.allocator = a->opts.allocator;
        // No scheduler installed (btSetTaskScheduler never called): one item.
        const btITaskScheduler *scheduler = btGetTaskScheduler();
        const int threads = scheduler != nullptr ? scheduler->getNumThreads() : 1;
        o.threads = threads < 1                               ? 1u
                    : unsigned(threads) > SELFCOL_MAX_THREADS ? SELFCOL_MAX_THREADS
                                                              : unsigned(threads);
        o.enqueue_task = enqueue_on_bullet;
        o.finish_task = finish_on_bullet;
        int status = selfcol_context_create(&context, &o);
        if (status != SELFCOL_OK)
            return status;
    }
    selfcol_context_destroy(a->task_context);
    a->task_context = context;
    if (a->scene != nullptr) // off: the adapter's own threads again
        selfcol_scene_set_context(a->scene, context_of(a));
    return SELFCOL_OK;
}

extern "C" void selfcol_bullet_destroy(selfcol_bullet *a) {
    destroy_adapter(a, true);
}

extern "C" void selfcol_bullet_destroy_after_world(selfcol_bullet *a) {
    destroy_adapter(a, false);
}

extern "C" int selfcol_bullet_attach(selfcol_bullet *a, btSoftBody *body, uint32_t *id_out) {
    if (a == nullptr || body == nullptr)
        return SELFCOL_EINVAL;
    // Only a body of this world: a step reads nothing else (lifetimes, bullet.h).
    if (!in_world(a, body))
        return SELFCOL_EINVAL;
    // Attached here already, or to another adapter (or using Bullet's
    // cluster self-collision, whose bit is the mark): two adapters would
    // each save and restore the other's settings.
    if ((body->m_cfg.collisions & attached_mark) != 0)
        return SELFCOL_EINVAL;
    for (const attached_body &b : a->bodies)
        if (b.body == body)
            return SELFCOL_EINVAL;
    int node_count = body->m_nodes.size();
    int face_count = body->m_faces.size();
    if (node_count <= 0 || face_count <= 0)
        return SELFCOL_EINVAL;
    if (!finite_velocities(body))
        return SELFCOL_EINVAL;
    if (uint64_t(a->node_total) + uint64_t(node_count) >= uint64_t(INT32_MAX) ||
        a->next_surface >= max_surfaces)
        return SELFCOL_ERANGE;
    selfcol_mesh *mesh = nullptr;
    bool in_scene = false;
    const uint32_t surface = a->next_surface;
    try {
        hvector<uint32_t> triangles{hook_allocator<uint32_t>(&a->hooks)};
        triangles.reserve(size_t(face_count) * 3);
        const btSoftBody::Node *node0 = &body->m_nodes[0];
        for (int f = 0; f < face_count; ++f)
            for (int k = 0; k < 3; ++k)
                triangles.push_back(uint32_t(body->m_faces[f].m_n[k] - node0));
        selfcol_mesh_options mo;
        selfcol_mesh_options_init(&mo, SELFCOL_MESH_OPTIONS_VERSION);
        mo.allocator = a->hooks;
        int status = selfcol_mesh_create_float(&mesh, size_t(node_count), node_positions(body),
                                               sizeof(btSoftBody::Node), size_t(face_count),
                                               triangles.data(), &mo);
        if (status != SELFCOL_OK)
            return status;
        attached_body b;
        b.body = body;
        b.mesh = mesh;
        b.surface = surface;
        b.node_count = node_count;
        b.face_count = face_count;
        b.saved_self_collision = body->useSelfCollision();
        b.first_node = a->node_total;
        b.sweep_tree = nullptr; // made by the first continuous pass
        // Everything that can fail first, so that a failure changes nothing
        // that a later attach would read.
        a->slot_of_node.resize(size_t(a->node_total) + size_t(node_count), -1);
        a->bodies.reserve(a->bodies.size() + 1);
        a->edge_faces.reserve(a->edge_faces.size() + 3 * size_t(face_count));
        // A live scene takes the surface now, its other pairs keeping their
        // stores (the scene is unchanged if this fails).
        if (a->scene != nullptr) {
            uint32_t id = 0;
            status = add_surface(a->scene, mesh, &id);
            if (status != SELFCOL_OK) {
                selfcol_mesh_destroy(mesh);
                return status;
            }
            assert(id == surface);
            in_scene = true;
        }
        const uint64_t body_index = a->bodies.size();
        a->bodies.push_back(b);
        for (int f = 0; f < face_count; ++f)
            for (int k = 0; k < 3; ++k)
                a->edge_faces.push_back(
                    {edge_key(b.first_node + triangles[3 * size_t(f) + size_t(k)],
                              b.first_node + triangles[3 * size_t(f) + size_t(k + 1) % 3]),
                     body_index << 32 | uint64_t(f)});
        std::sort(a->edge_faces.begin(), a->edge_faces.end());
    } catch (...) {
        if (in_scene)
            selfcol_scene_remove_surface(a->scene, surface); // the id stays used
        selfcol_mesh_destroy(mesh);
        return SELFCOL_ENOMEM;
    }
    a->node_total += uint32_t(node_count);
    a->next_surface = surface + 1;
    a->have_previous = false; // a new body has no last positions
    a->crossings_known = false;
    // Bullet's own self-collision off, and the mark that makes Bullet's
    // soft-soft handling skip this body's pairs with other attached bodies
    // (attached_mark): selfcol is their collision now.
    body->setSelfCollision(false);
    body->m_cfg.collisions |= attached_mark;
    if (id_out)
        *id_out = surface;
    return SELFCOL_OK;
}

extern "C" int selfcol_bullet_detach(selfcol_bullet *a, btSoftBody *body) {
    if (a == nullptr || body == nullptr)
        return SELFCOL_EINVAL;
    for (size_t i = 0; i < a->bodies.size(); ++i)
        if (a->bodies[i].body == body) {
            restore_body(a->bodies[i]);
            drop_body(a, i);
            return SELFCOL_OK;
        }
    return SELFCOL_EINVAL;
}

extern "C" int selfcol_bullet_step(selfcol_bullet *a, double dt) {
    if (a == nullptr)
        return SELFCOL_EINVAL;
    int status;
    try {
        status = step_impl(a, dt);
    } catch (const std::bad_alloc &) {
        status = SELFCOL_ENOMEM;
    } catch (...) {
        status = SELFCOL_ERROR;
    }
    a->stats.status = status;
    ++a->stats.steps;
    return status;
}

extern "C" int selfcol_bullet_stats(const selfcol_bullet *a, selfcol_bullet_step_stats *stats) {
    if (a == nullptr || stats == nullptr)
        return SELFCOL_EINVAL;
    if (stats->version == 0 || stats->version > SELFCOL_BULLET_STEP_STATS_VERSION)
        return SELFCOL_EVERSION;
    unsigned int version = stats->version;
    // Only the fields of the caller's version.
    std::memcpy(stats, &a->stats,
                version >= 4   ? sizeof *stats
                : version == 3 ? offsetof(selfcol_bullet_step_stats, passed_around)
                : version == 2 ? offsetof(selfcol_bullet_step_stats, continuous_hits)
                               : offsetof(selfcol_bullet_step_stats, untangled));
    stats->version = version;
    return SELFCOL_OK;
}

extern "C" const selfcol_scene *selfcol_bullet_scene(const selfcol_bullet *a) {
    return a ? a->scene : nullptr;
}

extern "C" const selfcol_mesh *selfcol_bullet_mesh(const selfcol_bullet *a, uint32_t id) {
    if (a == nullptr)
        return nullptr;
    for (const attached_body &b : a->bodies)
        if (b.surface == id)
            return b.mesh;
    return nullptr;
}
