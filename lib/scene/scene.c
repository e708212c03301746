// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Scenes (include/selfcol/scene.h): surfaces by kind, one store per surface
// pair that can matter, and convex colliders (collider.c). A scene models no
// more than its surfaces' kinds need: a static surface's hierarchy is built
// once and never refit, a body's store takes its sides from the outward
// normals and never votes, and only the pairs of the table in scene.h are
// ever queried. The query result is a single scratch `selfcol_contacts`
// reused by every pair (a store copies what it keeps), so memory is the
// hierarchies, the stores and the collider contacts: linear in triangles
// plus contacts.
#include <selfcol/scene.h>

#include "base/alloc.h"
#include "base/box.h"
#include "base/core.h"
#include "base/problem.h"
#include "base/vec3.h"
#include "frames/sequence.h"
#include "frames/store.h"
#include "hierarchy/hierarchy.h"
#include "mesh/mesh.h"
#include "query/contacts.h"
#include "query/query.h"
#include "scene/collider.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

// Surfaces and colliders are numbered by uint32_t but kept few: pairs are
// all kept (quadratic in surfaces).
#define SCENE_MAX_SURFACES 65536u
#define SCENE_MAX_COLLIDERS 65536u

typedef struct scene_surface {
    const selfcol_mesh *mesh; // NULL once removed (the id is never reused)
    selfcol_hierarchy *hierarchy;
    uint32_t kind;
    int self_collision;
    int orientation;            // of its stores (body: from its volume)
    uint64_t positions_version; // a static mesh's, when added
    // Cloth and body surfaces, once selfcol_scene_set_surface_start was
    // called (3 V each): `start`, the positions at the start of the next
    // update's step, valid when has_start (until that update); `last`, the
    // positions at the last update, valid when has_last. A static surface's
    // are its mesh's positions, valid unless it was rebuilt (moved) since
    // the last update (has_start).
    double *start, *last;
    size_t start_count; // doubles in each (3 V when made): freed without the mesh
    int has_start, has_last;
} scene_surface;

typedef struct scene_pair {
    uint32_t first, second;
    selfcol_store *store;
    selfcol_sequence *sequence; // NULL: a fresh query every update
} scene_pair;

struct selfcol_scene {
    selfcol_allocator allocator;
    selfcol_query_options query;       // checked, current version
    selfcol_store_options store;       // checked; the allocator is the scene's
    int coherent;                      // pairs keep a sequence (exact methods only)
    selfcol_sequence_options sequence; // the allocator is the scene's
    double distance;                   // query.distance
    double collider_tolerance;         // absolute (the default resolved)

    scene_surface *surfaces;
    size_t surface_count, surface_capacity; // ids handed out (removed ones included)
    size_t live_surfaces;                   // not removed
    scene_pair *pairs;
    size_t pair_count, pair_capacity;
    selfcol_collider *colliders;
    size_t collider_count, collider_capacity;

    selfcol_context *context;   // borrowed (selfcol_scene_set_context); NULL: the calling thread
    selfcol_contacts *detected; // the query scratch, shared by every pair
    uint32_t *stack;            // collider broad phase: the largest node count
    size_t stack_capacity;
    double (*scratch)[3]; // libccd's frame: the most collider points
    size_t scratch_capacity;
    selfcol_collider_contact_buffer found; // collider contacts of the last update

    uint64_t builds;
    selfcol_scene_update_stats stats;
};

int selfcol_scene_options_init(selfcol_scene_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version < SELFCOL_SCENE_OPTIONS_VERSION || version > SELFCOL_SCENE_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    opts->coherent = 1;
    return SELFCOL_OK;
}

int selfcol_scene_surface_options_init(selfcol_scene_surface_options *opts, uint32_t kind,
                                       unsigned int version) {
    SELFCOL_CHECK(opts != NULL && kind <= SELFCOL_SURFACE_STATIC);
    if (version == 0 || version > SELFCOL_SCENE_SURFACE_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    opts->kind = kind;
    opts->self_collision = kind == SELFCOL_SURFACE_CLOTH;
    return SELFCOL_OK;
}

int selfcol_scene_collider_desc_init(selfcol_scene_collider_desc *desc, uint32_t shape,
                                     unsigned int version) {
    SELFCOL_CHECK(desc != NULL && shape <= SELFCOL_COLLIDER_CONVEX);
    if (version == 0 || version > SELFCOL_SCENE_COLLIDER_DESC_VERSION)
        return SELFCOL_EVERSION;
    memset(desc, 0, sizeof *desc);
    desc->version = version;
    desc->shape = shape;
    return SELFCOL_OK;
}

// An allocator that must be all zero (the scene's own allocator serves).
static int allocator_unset(const selfcol_allocator *a) {
    return a->alloc == NULL && a->free == NULL && a->user == NULL;
}

// The scene's options checked, the query, store and sequence options they
// point to read as their versions say into query, store and sequence (NULL
// store or sequence: the defaults); `at` names a refused field.
static int scene_options(const selfcol_scene_options *o, selfcol_query_options *query,
                         selfcol_store_options *store, selfcol_sequence_options *sequence,
                         const selfcol_problem_at *at) {
    // Version 1 was 0.2's layout (fields copied from the query and store
    // options), version 2 0.3's (those options embedded): their fields are
    // not where this layout reads them.
    if (o->version != SELFCOL_SCENE_OPTIONS_VERSION)
        return selfcol_problem__field(at, SELFCOL_EVERSION, "version",
                                      "= %u is not %d (0: never initialised; 1 was 0.2's "
                                      "layout, 2 0.3's)",
                                      o->version, SELFCOL_SCENE_OPTIONS_VERSION);
    SELFCOL_CHECK_ALLOCATOR(at, o->allocator);
    SELFCOL_CHECK_FIELD(at, o->query != NULL, "query",
                        "is NULL: a scene needs query options with a distance > 0 (its "
                        "thickness)");
    char prefix[3][64];
    const selfcol_problem_at at_query = selfcol_problem__nested(at, "query", prefix[0]);
    int status = selfcol_query__options(query, o->query, &at_query);
    if (status != SELFCOL_OK)
        return status;
    SELFCOL_CHECK_FIELD(&at_query, query->distance > 0.0, "distance",
                        "= %g: a scene needs a distance > 0 (its thickness)", query->distance);
    SELFCOL_CHECK_FIELD(&at_query, query->kinds != 0, "kinds", "= 0: a scene needs some kind");
    const selfcol_problem_at at_store = selfcol_problem__nested(at, "store", prefix[1]);
    status = selfcol_store__options(store, o->store, &at_store);
    if (status != SELFCOL_OK)
        return status;
    SELFCOL_CHECK_FIELD(&at_store, allocator_unset(&store->allocator), "allocator",
                        "is set: a scene's stores use the scene's allocator (leave it zero)");
    SELFCOL_CHECK_FIELD(&at_store, store->first_orientation == 0, "first_orientation",
                        "= %d: a scene's surfaces give their own orientation (leave it 0)",
                        store->first_orientation);
    SELFCOL_CHECK_FIELD(&at_store, store->second_orientation == 0, "second_orientation",
                        "= %d: a scene's surfaces give their own orientation (leave it 0)",
                        store->second_orientation);
    SELFCOL_CHECK_FIELD(at, isfinite(o->collider_tolerance) && o->collider_tolerance >= 0.0,
                        "collider_tolerance", "= %g is not a finite tolerance >= 0",
                        o->collider_tolerance);
    SELFCOL_CHECK_FIELD(at, o->coherent == 0 || o->coherent == 1, "coherent", "= %d is not 0 or 1",
                        o->coherent);
    const selfcol_problem_at at_sequence = selfcol_problem__nested(at, "sequence", prefix[2]);
    status = selfcol_sequence__options(sequence, o->sequence, &at_sequence);
    if (status != SELFCOL_OK)
        return status;
    SELFCOL_CHECK_FIELD(&at_sequence, allocator_unset(&sequence->allocator), "allocator",
                        "is set: a scene's sequences use the scene's allocator (leave it zero)");
    return SELFCOL_OK;
}

int selfcol_scene_options_check(const selfcol_scene_options *opts,
                                selfcol_options_problem *problem) {
    const int begun = selfcol_problem__begin(problem);
    if (begun != SELFCOL_OK)
        return begun;
    if (opts == NULL) {
        const selfcol_problem_at at = {problem, "selfcol_scene_create", ""};
        return selfcol_problem__field(&at, SELFCOL_EINVAL, "opts",
                                      "is NULL: a scene needs options (a distance > 0)");
    }
    const selfcol_problem_at at = {problem, "selfcol_scene_options", ""};
    selfcol_query_options query;
    selfcol_store_options store;
    selfcol_sequence_options sequence;
    return scene_options(opts, &query, &store, &sequence, &at);
}

int selfcol_scene_create(selfcol_scene **out, const selfcol_scene_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    SELFCOL_CHECK(opts != NULL);
    const selfcol_scene_options o = *opts;
    selfcol_query_options query;
    selfcol_store_options store;
    selfcol_sequence_options sequence;
    int status = scene_options(&o, &query, &store, &sequence, NULL);
    if (status != SELFCOL_OK)
        return status;
    selfcol_contacts_options copts;
    selfcol_contacts_options_init(&copts, SELFCOL_CONTACTS_OPTIONS_VERSION);
    copts.allocator = o.allocator;
    selfcol_scene *s = selfcol_alloc__raw(&o.allocator, sizeof *s);
    if (s == NULL)
        return SELFCOL_ENOMEM;
    memset(s, 0, sizeof *s);
    s->allocator = o.allocator;
    s->query = query;
    s->store = store;
    // With SEED or CONE a sequence answers every frame afresh (sequence.h):
    // no sequence is kept for them.
    s->coherent =
        o.coherent && query.method != SELFCOL_METHOD_SEED && query.method != SELFCOL_METHOD_CONE;
    s->sequence = sequence;
    s->sequence.allocator = o.allocator;
    s->distance = query.distance;
    s->collider_tolerance =
        o.collider_tolerance == 0.0 ? 1e-6 * query.distance : o.collider_tolerance;
    status = selfcol_contacts_create(&s->detected, &copts);
    if (status != SELFCOL_OK) {
        selfcol_alloc__free(&o.allocator, s, sizeof *s);
        return status;
    }
    s->stats.version = SELFCOL_SCENE_UPDATE_STATS_VERSION;
    *out = s;
    return SELFCOL_OK;
}

static void free_start(const selfcol_scene *scene, scene_surface *s) {
    if (s->start != NULL) {
        selfcol_alloc__free_array(&scene->allocator, s->start, s->start_count, sizeof *s->start);
        selfcol_alloc__free_array(&scene->allocator, s->last, s->start_count, sizeof *s->last);
    }
    s->start = s->last = NULL;
    s->start_count = 0;
    s->has_start = s->has_last = 0;
}

int selfcol_scene_set_context(selfcol_scene *scene, selfcol_context *context) {
    SELFCOL_CHECK(scene != NULL);
    scene->context = context;
    return SELFCOL_OK;
}

void selfcol_scene_destroy(selfcol_scene *scene) {
    if (scene == NULL)
        return;
    const selfcol_allocator al = scene->allocator;
    for (size_t i = 0; i < scene->surface_count; ++i) {
        selfcol_hierarchy_destroy(scene->surfaces[i].hierarchy);
        free_start(scene, &scene->surfaces[i]);
    }
    for (size_t i = 0; i < scene->pair_count; ++i) {
        selfcol_store_destroy(scene->pairs[i].store);
        selfcol_sequence_destroy(scene->pairs[i].sequence);
    }
    for (size_t i = 0; i < scene->collider_count; ++i) {
        const size_t n = scene->colliders[i].point_count;
        selfcol_alloc__free_array(&al, scene->colliders[i].local, n, sizeof(double[3]));
        selfcol_alloc__free_array(&al, scene->colliders[i].world, n, sizeof(double[3]));
    }
    selfcol_alloc__free_array(&al, scene->surfaces, scene->surface_capacity,
                              sizeof *scene->surfaces);
    selfcol_alloc__free_array(&al, scene->pairs, scene->pair_capacity, sizeof *scene->pairs);
    selfcol_alloc__free_array(&al, scene->colliders, scene->collider_capacity,
                              sizeof *scene->colliders);
    selfcol_alloc__free_array(&al, scene->stack, scene->stack_capacity, sizeof *scene->stack);
    selfcol_alloc__free_array(&al, scene->scratch, scene->scratch_capacity, sizeof *scene->scratch);
    selfcol_alloc__free_array(&al, scene->found.items, scene->found.capacity,
                              sizeof *scene->found.items);
    selfcol_contacts_destroy(scene->detected);
    selfcol_alloc__free(&al, scene, sizeof *scene);
}

// Grows *array (of *capacity items of `size` bytes, `count` used) to hold
// `need`; geometric, so repeated adds are amortised.
static int reserve(const selfcol_allocator *al, void **array, size_t *capacity, size_t count,
                   size_t need, size_t size) {
    if (need <= *capacity)
        return SELFCOL_OK;
    size_t cap = *capacity < 4 ? 4 : *capacity;
    while (cap < need)
        cap *= 2;
    void *p = selfcol_alloc__array(al, cap, size);
    if (p == NULL)
        return SELFCOL_ENOMEM;
    if (count > 0)
        memcpy(p, *array, count * size);
    selfcol_alloc__free_array(al, *array, *capacity, size);
    *array = p;
    *capacity = cap;
    return SELFCOL_OK;
}

// Six times the signed volume enclosed by a closed mesh (the sum of the
// triangles' determinants with the origin moved to the first vertex, which
// keeps the terms small).
static double signed_volume6(const selfcol_mesh *m) {
    const double *o = selfcol_mesh__position(m, 0);
    double sum = 0.0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *tri = m->triangles + 3 * t;
        double a[3], b[3], c[3], n[3];
        vec3_sub(a, selfcol_mesh__position(m, tri[0]), o);
        vec3_sub(b, selfcol_mesh__position(m, tri[1]), o);
        vec3_sub(c, selfcol_mesh__position(m, tri[2]), o);
        vec3_cross(n, b, c);
        sum += vec3_dot(a, n);
    }
    return sum;
}

// Is the pair (i, j), i <= j, ever tested (scene.h)?
static int pair_tested(const scene_surface *a, const scene_surface *b, int self) {
    if (a->mesh == NULL || b->mesh == NULL)
        return 0; // removed
    if (self)
        return a->self_collision;
    return !(a->kind == SELFCOL_SURFACE_STATIC && b->kind == SELFCOL_SURFACE_STATIC);
}

int selfcol_scene_add_surface(selfcol_scene *scene, const selfcol_mesh *mesh,
                              const selfcol_scene_surface_options *opts, uint32_t *id_out) {
    SELFCOL_CHECK(scene != NULL && mesh != NULL && opts != NULL);
    SELFCOL_CHECK_VERSION(opts, SELFCOL_SCENE_SURFACE_OPTIONS_VERSION);
    const selfcol_scene_surface_options o = *opts;
    SELFCOL_CHECK(o.kind <= SELFCOL_SURFACE_STATIC);
    SELFCOL_CHECK(o.self_collision == 0 || o.self_collision == 1);
    SELFCOL_CHECK(!(o.kind == SELFCOL_SURFACE_STATIC && o.self_collision));
    SELFCOL_CHECK(o.orientation >= -1 && o.orientation <= 1);
    SELFCOL_CHECK(o.orientation == 0 || o.kind == SELFCOL_SURFACE_STATIC);
    for (size_t i = 0; i < scene->surface_count; ++i)
        SELFCOL_CHECK(scene->surfaces[i].mesh != mesh);
    if (scene->surface_count >= SCENE_MAX_SURFACES)
        return SELFCOL_ERANGE;
    int orientation = o.orientation;
    if (o.kind == SELFCOL_SURFACE_BODY) {
        SELFCOL_CHECK(mesh->triangle_count > 0 && mesh->boundary_edges == 0 &&
                      mesh->nonmanifold_edges == 0 && mesh->misoriented_edges == 0);
        const double v6 = signed_volume6(mesh);
        SELFCOL_CHECK(v6 != 0.0 && isfinite(v6));
        orientation = v6 > 0.0 ? 1 : -1;
    }

    // Everything that can fail first: the scene is unchanged on error.
    const selfcol_allocator *al = &scene->allocator;
    const size_t id = scene->surface_count;
    size_t new_pairs = 0;
    scene_surface add;
    memset(&add, 0, sizeof add);
    add.mesh = mesh;
    add.kind = o.kind;
    add.self_collision = o.self_collision;
    add.orientation = orientation;
    add.positions_version = mesh->positions_version;
    add.has_start = o.kind == SELFCOL_SURFACE_STATIC; // a static surface's path: not moved
    for (size_t i = 0; i <= id; ++i)
        new_pairs += pair_tested(i < id ? &scene->surfaces[i] : &add, &add, i == id);
    int status = reserve(al, (void **)&scene->surfaces, &scene->surface_capacity,
                         scene->surface_count, id + 1, sizeof *scene->surfaces);
    if (status == SELFCOL_OK)
        status = reserve(al, (void **)&scene->pairs, &scene->pair_capacity, scene->pair_count,
                         scene->pair_count + new_pairs, sizeof *scene->pairs);
    selfcol_hierarchy_options hopts;
    selfcol_hierarchy_options_init(&hopts, SELFCOL_HIERARCHY_OPTIONS_VERSION);
    hopts.allocator = scene->allocator;
    if (status == SELFCOL_OK)
        status = selfcol_hierarchy_create(&add.hierarchy, mesh, &hopts);
    if (status == SELFCOL_OK)
        status = reserve(al, (void **)&scene->stack, &scene->stack_capacity, 0,
                         add.hierarchy->node_count, sizeof *scene->stack);
    scene_pair *made = scene->pairs + scene->pair_count;
    size_t made_count = 0;
    for (size_t i = 0; i <= id && status == SELFCOL_OK; ++i) {
        const scene_surface *first = i < id ? &scene->surfaces[i] : &add;
        if (!pair_tested(first, &add, i == id))
            continue;
        selfcol_store_options sopts = scene->store;
        sopts.allocator = scene->allocator;
        sopts.first_orientation = first->orientation;
        sopts.second_orientation = add.orientation;
        made[made_count] = (scene_pair){(uint32_t)i, (uint32_t)id, NULL, NULL};
        status = selfcol_store_create(&made[made_count].store, &sopts);
        if (status == SELFCOL_OK && scene->coherent) {
            status = selfcol_sequence_create(&made[made_count].sequence, &scene->sequence);
            if (status != SELFCOL_OK)
                selfcol_store_destroy(made[made_count].store);
        }
        made_count += status == SELFCOL_OK;
    }
    if (status != SELFCOL_OK) {
        for (size_t k = 0; k < made_count; ++k) {
            selfcol_store_destroy(made[k].store);
            selfcol_sequence_destroy(made[k].sequence);
        }
        selfcol_hierarchy_destroy(add.hierarchy);
        return status;
    }
    scene->surfaces[id] = add;
    scene->surface_count++;
    scene->live_surfaces++;
    scene->pair_count += made_count;
    scene->builds++;
    if (id_out != NULL)
        *id_out = (uint32_t)id;
    return SELFCOL_OK;
}

int selfcol_scene_remove_surface(selfcol_scene *scene, uint32_t id) {
    SELFCOL_CHECK(scene != NULL && id < scene->surface_count && scene->surfaces[id].mesh != NULL);
    size_t kept = 0;
    for (size_t p = 0; p < scene->pair_count; ++p) {
        scene_pair pair = scene->pairs[p];
        if (pair.first == id || pair.second == id) {
            selfcol_store_destroy(pair.store);
            selfcol_sequence_destroy(pair.sequence);
        } else
            scene->pairs[kept++] = pair; // order kept: updates stay deterministic
    }
    scene->pair_count = kept;
    scene_surface *s = &scene->surfaces[id];
    selfcol_hierarchy_destroy(s->hierarchy);
    free_start(scene, s);
    s->hierarchy = NULL;
    s->mesh = NULL;
    scene->live_surfaces--;
    return SELFCOL_OK;
}

int selfcol_scene_rebuild_surface(selfcol_scene *scene, uint32_t id) {
    SELFCOL_CHECK(scene != NULL && id < scene->surface_count && scene->surfaces[id].mesh != NULL);
    scene_surface *s = &scene->surfaces[id];
    if (!selfcol_mesh__is(s->mesh, &s->hierarchy->mesh_identity))
        return SELFCOL_EMISMATCH;
    selfcol_hierarchy_options hopts;
    selfcol_hierarchy_options_init(&hopts, SELFCOL_HIERARCHY_OPTIONS_VERSION);
    hopts.allocator = scene->allocator;
    selfcol_hierarchy *rebuilt = NULL;
    int status = selfcol_hierarchy_create(&rebuilt, s->mesh, &hopts);
    if (status == SELFCOL_OK)
        status = reserve(&scene->allocator, (void **)&scene->stack, &scene->stack_capacity, 0,
                         rebuilt->node_count, sizeof *scene->stack);
    if (status != SELFCOL_OK) {
        selfcol_hierarchy_destroy(rebuilt);
        return status;
    }
    selfcol_hierarchy_destroy(s->hierarchy);
    s->hierarchy = rebuilt;
    s->positions_version = s->mesh->positions_version;
    if (s->kind == SELFCOL_SURFACE_STATIC)
        s->has_start = 0; // moved on purpose: the path is not known
    scene->builds++;
    return SELFCOL_OK;
}

int selfcol_scene_add_collider(selfcol_scene *scene, const selfcol_scene_collider_desc *desc,
                               uint32_t *id_out) {
    SELFCOL_CHECK(scene != NULL && desc != NULL);
    SELFCOL_CHECK_VERSION(desc, SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    SELFCOL_CHECK(selfcol_collider__check(desc) == SELFCOL_OK);
    if (scene->collider_count >= SCENE_MAX_COLLIDERS)
        return SELFCOL_ERANGE;
    const selfcol_allocator *al = &scene->allocator;
    const size_t n = selfcol_collider__point_count(desc);
    selfcol_collider c;
    memset(&c, 0, sizeof c);
    c.shape = desc->shape;
    c.radius = desc->radius;
    c.point_count = n;
    c.local = selfcol_alloc__array(al, n, sizeof *c.local);
    c.world = selfcol_alloc__array(al, n, sizeof *c.world);
    int status = c.local != NULL && c.world != NULL ? SELFCOL_OK : SELFCOL_ENOMEM;
    if (status == SELFCOL_OK)
        status =
            reserve(al, (void **)&scene->colliders, &scene->collider_capacity,
                    scene->collider_count, scene->collider_count + 1, sizeof *scene->colliders);
    if (status == SELFCOL_OK)
        status = reserve(al, (void **)&scene->scratch, &scene->scratch_capacity, 0, n,
                         sizeof *scene->scratch);
    if (status != SELFCOL_OK) {
        selfcol_alloc__free_array(al, c.local, n, sizeof *c.local);
        selfcol_alloc__free_array(al, c.world, n, sizeof *c.world);
        return status;
    }
    selfcol_collider__local_points(desc, c.local);
    const double origin[3] = {0.0, 0.0, 0.0};
    selfcol_collider__place(&c, origin, NULL);
    scene->colliders[scene->collider_count] = c;
    if (id_out != NULL)
        *id_out = (uint32_t)scene->collider_count;
    scene->collider_count++;
    return SELFCOL_OK;
}

int selfcol_scene_set_collider_pose(selfcol_scene *scene, uint32_t collider,
                                    const double position[3], const double rotation[9]) {
    SELFCOL_CHECK(scene != NULL && position != NULL && collider < scene->collider_count);
    for (int k = 0; k < 3; ++k)
        SELFCOL_CHECK(isfinite(position[k]));
    if (rotation != NULL) {
        for (int k = 0; k < 9; ++k)
            SELFCOL_CHECK(isfinite(rotation[k]));
        // R R^T = I within 1e-6, det R > 0.
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const double d = vec3_dot(rotation + 3 * i, rotation + 3 * j) - (i == j);
                SELFCOL_CHECK(fabs(d) <= 1e-6);
            }
        double c[3];
        vec3_cross(c, rotation, rotation + 3);
        SELFCOL_CHECK(vec3_dot(c, rotation + 6) > 0.0);
    }
    selfcol_collider *col = &scene->colliders[collider];
    double extent = col->radius; // the farthest a world point can lie from position
    for (size_t i = 0; i < col->point_count; ++i)
        extent = fmax(extent, sqrt(vec3_dot(col->local[i], col->local[i])) + col->radius);
    for (int k = 0; k < 3; ++k)
        if (!(fabs(position[k]) + extent <= SELFCOL_MESH_MAX_COORDINATE))
            return SELFCOL_ERANGE;
    selfcol_collider__place(col, position, rotation);
    return SELFCOL_OK;
}

// Are two hierarchies' root boxes farther apart than d on some axis?
static int roots_apart(const selfcol_hierarchy *a, const selfcol_hierarchy *b, double d) {
    if (a->node_count == 0 || b->node_count == 0)
        return 1;
    return !selfcol_box__near_float(a->nodes[0].lo, a->nodes[0].hi, b->nodes[0].lo, b->nodes[0].hi,
                                    d);
}

int selfcol_scene_set_surface_start(selfcol_scene *scene, uint32_t surface,
                                    const double *positions) {
    SELFCOL_CHECK(scene != NULL && positions != NULL && surface < scene->surface_count);
    scene_surface *s = &scene->surfaces[surface];
    SELFCOL_CHECK(s->mesh != NULL && s->kind != SELFCOL_SURFACE_STATIC);
    const size_t n = s->mesh->vertex_count;
    SELFCOL_CHECK(selfcol_mesh__positions_in_contract(positions, n));
    if (s->start == NULL && n > 0) {
        double *start = selfcol_alloc__array(&scene->allocator, 3 * n, sizeof *start);
        double *last = selfcol_alloc__array(&scene->allocator, 3 * n, sizeof *last);
        if (start == NULL || last == NULL) {
            selfcol_alloc__free_array(&scene->allocator, start, 3 * n, sizeof *start);
            selfcol_alloc__free_array(&scene->allocator, last, 3 * n, sizeof *last);
            return SELFCOL_ENOMEM;
        }
        s->start = start;
        s->last = last; // from the next update on
        s->start_count = 3 * n;
    }
    if (n > 0)
        memcpy(s->start, positions, 3 * n * sizeof *s->start);
    s->has_start = 1;
    return SELFCOL_OK;
}

// A surface's path since the last update when known (path[0] the positions
// at the last update, path[1] at the step's start): a static surface's are
// its current ones (unless rebuilt since the last update), a moving one's
// those kept and given. Returns 0 when unknown.
static int path_of(const scene_surface *s, const double *path[2]) {
    if (s->kind == SELFCOL_SURFACE_STATIC) {
        path[0] = path[1] = s->mesh->positions;
        return s->has_start;
    }
    path[0] = s->last;
    path[1] = s->start;
    return s->has_start && s->has_last;
}

// The pair's store update: on the surfaces' paths when both know theirs;
// on the scene's context, if it has one.
static int update_store(const selfcol_scene *scene, const scene_pair *pair, const scene_surface *a,
                        const scene_surface *b, const selfcol_contacts *detected) {
    const int self = pair->first == pair->second;
    const double *first_path[2], *second_path[2];
    if (path_of(a, first_path) && (self || path_of(b, second_path)))
        return selfcol_store__update_path(scene->context, pair->store, a->mesh,
                                          self ? NULL : b->mesh, detected, first_path,
                                          self ? NULL : second_path);
    return scene->context != NULL
               ? selfcol_context_store_update(scene->context, pair->store, a->mesh,
                                              self ? NULL : b->mesh, detected)
               : selfcol_store_update(pair->store, a->mesh, self ? NULL : b->mesh, detected);
}

// The pair's query into scene->detected: from its sequence when it keeps
// one, on the scene's context if it has one.
static int query_pair(selfcol_scene *scene, const scene_pair *pair, const scene_surface *a,
                      const scene_surface *b) {
    selfcol_context *c = scene->context;
    const selfcol_query_options *o = &scene->query;
    if (pair->first == pair->second) {
        if (pair->sequence != NULL)
            return c != NULL ? selfcol_context_sequence_self_collide(
                                   c, pair->sequence, a->hierarchy, scene->detected, o)
                             : selfcol_sequence_self_collide(pair->sequence, a->hierarchy,
                                                             scene->detected, o);
        return c != NULL ? selfcol_context_self_collide(c, a->hierarchy, scene->detected, o)
                         : selfcol_hierarchy_self_collide(a->hierarchy, scene->detected, o);
    }
    if (pair->sequence != NULL)
        return c != NULL ? selfcol_context_sequence_collide(c, pair->sequence, a->hierarchy,
                                                            b->hierarchy, scene->detected, o)
                         : selfcol_sequence_collide(pair->sequence, a->hierarchy, b->hierarchy,
                                                    scene->detected, o);
    return c != NULL ? selfcol_context_collide(c, a->hierarchy, b->hierarchy, scene->detected, o)
                     : selfcol_hierarchy_collide(a->hierarchy, b->hierarchy, scene->detected, o);
}

int selfcol_scene_update(selfcol_scene *scene) {
    SELFCOL_CHECK(scene != NULL);
    const double start = selfcol_core__seconds();
    for (size_t i = 0; i < scene->surface_count; ++i) {
        const scene_surface *s = &scene->surfaces[i];
        if (s->mesh != NULL && s->kind == SELFCOL_SURFACE_STATIC &&
            s->mesh->positions_version != s->positions_version)
            return SELFCOL_ESTALE;
    }
    selfcol_scene_update_stats st;
    memset(&st, 0, sizeof st);
    st.version = SELFCOL_SCENE_UPDATE_STATS_VERSION;
    st.surfaces = scene->live_surfaces;
    st.colliders = scene->collider_count;
    scene->found.count = 0;
    scene->stats = st;
    int status = SELFCOL_OK;
    for (size_t i = 0; i < scene->surface_count && status == SELFCOL_OK; ++i) {
        scene_surface *s = &scene->surfaces[i];
        if (s->mesh == NULL || s->kind == SELFCOL_SURFACE_STATIC)
            continue; // removed; or built once, never refit
        status = scene->context != NULL ? selfcol_context_refit(scene->context, s->hierarchy)
                                        : selfcol_hierarchy_refit(s->hierarchy);
        st.refits++;
    }
    for (size_t p = 0; p < scene->pair_count && status == SELFCOL_OK; ++p) {
        const scene_pair *pair = &scene->pairs[p];
        const scene_surface *a = &scene->surfaces[pair->first], *b = &scene->surfaces[pair->second];
        if (pair->first != pair->second &&
            roots_apart(a->hierarchy, b->hierarchy, scene->distance)) {
            selfcol_contacts_clear(scene->detected);
            st.pairs_apart++;
        } else {
            status = query_pair(scene, pair, a, b);
            st.pairs_queried++;
        }
        if (status == SELFCOL_OK)
            status = update_store(scene, pair, a, b, scene->detected);
        if (status == SELFCOL_OK) {
            selfcol_store_update_stats ss;
            ss.version = SELFCOL_STORE_UPDATE_STATS_VERSION;
            selfcol_store_stats(pair->store, &ss);
            st.contacts += ss.contacts;
            st.interferences += ss.interferences;
            st.flipped += ss.flipped;
            st.corrected += ss.corrected;
            st.voted += ss.voted;
            st.oriented += ss.oriented;
            st.passed_around += ss.passed_around;
        }
    }
    for (size_t c = 0; c < scene->collider_count && status == SELFCOL_OK; ++c)
        for (size_t i = 0; i < scene->surface_count && status == SELFCOL_OK; ++i) {
            const scene_surface *s = &scene->surfaces[i];
            if (s->mesh == NULL || s->kind == SELFCOL_SURFACE_STATIC)
                continue; // removed; or rigid against rigid: the rigid solver's job
            status = selfcol_collider__contacts(
                &scene->colliders[c], (uint32_t)c, s->hierarchy, (uint32_t)i, scene->distance,
                scene->collider_tolerance, scene->stack, scene->scratch, &scene->allocator,
                &scene->found, &st.collider_candidates);
        }
    // The starts are consumed (static: not moved since); the positions of
    // this update begin the next path, unless the stores are not all at
    // this update (a failure).
    for (size_t i = 0; i < scene->surface_count; ++i) {
        scene_surface *s = &scene->surfaces[i];
        s->has_start = s->kind == SELFCOL_SURFACE_STATIC;
        s->has_last = status == SELFCOL_OK && s->last != NULL;
        if (s->has_last)
            memcpy(s->last, s->mesh->positions, 3 * s->mesh->vertex_count * sizeof *s->last);
    }
    if (status != SELFCOL_OK) {
        scene->found.count = 0;
        scene->stats = st;
        return status;
    }
    st.collider_contacts = scene->found.count;
    for (size_t k = 0; k < scene->found.count; ++k)
        st.collider_penetrating +=
            (scene->found.items[k].flags & SELFCOL_COLLIDER_PENETRATING) != 0;
    st.seconds = selfcol_core__seconds() - start;
    scene->stats = st;
    return SELFCOL_OK;
}

int selfcol_scene_store(const selfcol_scene *scene, uint32_t first, uint32_t second,
                        const selfcol_store **store_out) {
    SELFCOL_CHECK(scene != NULL && store_out != NULL);
    *store_out = NULL;
    SELFCOL_CHECK(first <= second && second < scene->surface_count);
    for (size_t p = 0; p < scene->pair_count; ++p)
        if (scene->pairs[p].first == first && scene->pairs[p].second == second) {
            *store_out = scene->pairs[p].store;
            break;
        }
    return SELFCOL_OK;
}

int selfcol_scene_collider_contacts(const selfcol_scene *scene,
                                    const selfcol_collider_contact **data_out, size_t *count_out) {
    SELFCOL_CHECK(scene != NULL && data_out != NULL && count_out != NULL);
    *data_out = scene->found.count > 0 ? scene->found.items : NULL;
    *count_out = scene->found.count;
    return SELFCOL_OK;
}

int selfcol_scene_stats(const selfcol_scene *scene, selfcol_scene_update_stats *stats) {
    SELFCOL_CHECK(scene != NULL && stats != NULL);
    if (stats->version == 0 || stats->version > SELFCOL_SCENE_UPDATE_STATS_VERSION)
        return SELFCOL_EVERSION;
    const unsigned version = stats->version;
    selfcol_scene_update_stats st = scene->stats;
    st.builds = scene->builds;
    st.surfaces = scene->live_surfaces;
    st.colliders = scene->collider_count;
    // A version 1 caller's struct ends before passed_around.
    memcpy(stats, &st,
           version >= 2 ? sizeof *stats : offsetof(selfcol_scene_update_stats, passed_around));
    stats->version = version;
    return SELFCOL_OK;
}

size_t selfcol_scene_byte_count(const selfcol_scene *scene) {
    if (scene == NULL)
        return 0;
    size_t bytes = sizeof *scene + scene->surface_capacity * sizeof *scene->surfaces +
                   scene->pair_capacity * sizeof *scene->pairs +
                   scene->collider_capacity * sizeof *scene->colliders +
                   scene->stack_capacity * sizeof *scene->stack +
                   scene->scratch_capacity * sizeof *scene->scratch +
                   scene->found.capacity * sizeof *scene->found.items +
                   selfcol_contacts_byte_count(scene->detected);
    for (size_t i = 0; i < scene->surface_count; ++i) {
        const scene_surface *s = &scene->surfaces[i];
        bytes += selfcol_hierarchy_byte_count(s->hierarchy);
        bytes += 2 * s->start_count * sizeof *s->start;
    }
    for (size_t p = 0; p < scene->pair_count; ++p)
        bytes += selfcol_store_byte_count(scene->pairs[p].store) +
                 selfcol_sequence_byte_count(scene->pairs[p].sequence);
    for (size_t c = 0; c < scene->collider_count; ++c)
        bytes += 2 * scene->colliders[c].point_count * sizeof(double[3]);
    return bytes;
}
