// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-bench-tree: the tree layouts of issue 38's lever 3, measured with
// one box traversal (the BVH method's: Self and Pair, the larger node split,
// boxes within d), the same code for every tree:
//   topology  the library's hierarchy (patches merged along the surface,
//             Volino & Magnenat-Thalmann's; variable arity, leaves of at
//             most 16 triangles), as built;
//   lbvh-leaves  a binary spatial tree (Morton order of box centres, split at
//             the highest differing bit: Karras 2012's LBVH) over the
//             topology tree's own leaves;
//   lbvh-leaves-4  the same, 4-wide (each node's grandchildren as children);
//   lbvh-tris-1 / -8  LBVHs over the triangles themselves (leaves of 1
//             triangle, ipc-toolkit's layout, or runs of up to 8 in Morton
//             order).
// Every tree must find the same candidate triangle pairs (checked); what
// differs is the number of node pairs tested and the time. One thread;
// medians of 5 after a warm-up.
//
//   selfcol-bench-tree FRAME.ply [...]   (d = 0.1 x mean edge length)
#include <selfcol/selfcol.h>

#include "hierarchy/hierarchy.h"
#include "meshio.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct tnode {
    float lo[3], hi[3];
    uint32_t first_child;
    uint32_t tri_begin, tri_count; // slots of the tree's order
    uint32_t child_count;
} tnode;

typedef struct tree {
    const char *name;
    tnode *node;
    size_t count, capacity;
    uint32_t *order; // slot -> triangle
} tree;

typedef struct counts {
    uint64_t node_pairs, triangle_tests, candidates;
} counts;

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void *checked(void *p) {
    if (p == NULL) {
        fprintf(stderr, "selfcol-bench-tree: out of memory\n");
        exit(1);
    }
    return p;
}

static uint32_t add_nodes(tree *t, uint32_t k) {
    if (t->count + k > t->capacity) {
        t->capacity = 2 * (t->count + k);
        t->node = checked(realloc(t->node, t->capacity * sizeof *t->node));
    }
    uint32_t first = (uint32_t)t->count;
    memset(t->node + first, 0, k * sizeof *t->node);
    t->count += k;
    return first;
}

// Triangle boxes by triangle index (doubles), and the mesh's box.
typedef struct boxes {
    double *lo, *hi; // 3 per triangle
    double mesh_lo[3], mesh_hi[3];
} boxes;

static int near(const double *alo, const double *ahi, const double *blo, const double *bhi,
                double d) {
    for (int k = 0; k < 3; ++k)
        if (alo[k] - bhi[k] > d || blo[k] - ahi[k] > d)
            return 0;
    return 1;
}

static int near_float(const float *alo, const float *ahi, const float *blo, const float *bhi,
                      double d) {
    for (int k = 0; k < 3; ++k)
        if ((double)alo[k] - (double)bhi[k] > d || (double)blo[k] - (double)ahi[k] > d)
            return 0;
    return 1;
}

// ---------------------------------------------------------------------------
// The traversal (one for every tree)

typedef struct pair {
    uint32_t a, b;
} pair;

static void tri_pairs(const tree *t, const boxes *bx, const tnode *a, const tnode *b, int same,
                      double d, counts *c) {
    for (uint32_t i = a->tri_begin; i < a->tri_begin + a->tri_count; ++i) {
        const uint32_t ta = t->order[i];
        for (uint32_t j = same ? i + 1 : b->tri_begin; j < b->tri_begin + b->tri_count; ++j) {
            const uint32_t tb = t->order[j];
            c->triangle_tests++;
            c->candidates += (uint64_t)near(bx->lo + 3 * ta, bx->hi + 3 * ta, bx->lo + 3 * tb,
                                            bx->hi + 3 * tb, d);
        }
    }
}

static counts traverse(const tree *t, const boxes *bx, double d, pair *stack) {
    counts c = {0, 0, 0};
    size_t top = 0;
    stack[top++] = (pair){0, 0};
    while (top > 0) {
        const pair p = stack[--top];
        const tnode *a = &t->node[p.a], *b = &t->node[p.b];
        c.node_pairs++;
        if (p.a == p.b) {
            if (a->child_count == 0) {
                tri_pairs(t, bx, a, a, 1, d, &c);
                continue;
            }
            for (uint32_t i = 0; i < a->child_count; ++i) {
                const uint32_t ci = a->first_child + i;
                stack[top++] = (pair){ci, ci};
                for (uint32_t j = i + 1; j < a->child_count; ++j)
                    stack[top++] = (pair){ci, a->first_child + j};
            }
            continue;
        }
        if (!near_float(a->lo, a->hi, b->lo, b->hi, d))
            continue;
        if (a->child_count == 0 && b->child_count == 0) {
            tri_pairs(t, bx, a, b, 0, d, &c);
            continue;
        }
        const int split_a =
            b->child_count == 0 || (a->child_count > 0 && a->tri_count >= b->tri_count);
        const tnode *n = split_a ? a : b;
        for (uint32_t i = 0; i < n->child_count; ++i)
            stack[top++] =
                split_a ? (pair){n->first_child + i, p.b} : (pair){p.a, n->first_child + i};
    }
    return c;
}

// ---------------------------------------------------------------------------
// Trees

static void box_of_slots(const tree *t, const boxes *bx, tnode *n) {
    for (int k = 0; k < 3; ++k) {
        n->lo[k] = INFINITY;
        n->hi[k] = -INFINITY;
    }
    for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count; ++s)
        for (int k = 0; k < 3; ++k) {
            const uint32_t tri = t->order[s];
            // Rounded outward to float, as the library's node boxes.
            float lo = (float)bx->lo[3 * tri + k], hi = (float)bx->hi[3 * tri + k];
            if ((double)lo > bx->lo[3 * tri + k])
                lo = nextafterf(lo, -INFINITY);
            if ((double)hi < bx->hi[3 * tri + k])
                hi = nextafterf(hi, INFINITY);
            n->lo[k] = lo < n->lo[k] ? lo : n->lo[k];
            n->hi[k] = hi > n->hi[k] ? hi : n->hi[k];
        }
}

static tree topology_tree(const selfcol_hierarchy *h) {
    tree t = {"topology", NULL, 0, 0, NULL};
    add_nodes(&t, (uint32_t)h->node_count);
    for (size_t i = 0; i < h->node_count; ++i) {
        const selfcol_node *n = &h->nodes[i];
        memcpy(t.node[i].lo, n->lo, sizeof n->lo);
        memcpy(t.node[i].hi, n->hi, sizeof n->hi);
        t.node[i].first_child = n->first_child;
        t.node[i].child_count = n->child_count;
        t.node[i].tri_begin = n->tri_begin;
        t.node[i].tri_count = n->tri_count;
    }
    t.order = checked(malloc(h->triangle_count * sizeof *t.order));
    memcpy(t.order, h->tri_order, h->triangle_count * sizeof *t.order);
    return t;
}

static uint32_t spread_bits(uint32_t x) { // 10 bits -> every third bit
    x &= 0x3ffu;
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}

static uint32_t morton(const boxes *bx, const double lo[3], const double hi[3]) {
    uint32_t code = 0;
    for (int k = 0; k < 3; ++k) {
        const double span = bx->mesh_hi[k] - bx->mesh_lo[k];
        double u = span > 0 ? (0.5 * (lo[k] + hi[k]) - bx->mesh_lo[k]) / span : 0.0;
        uint32_t q = (uint32_t)(u * 1023.0 + 0.5);
        code |= spread_bits(q) << k;
    }
    return code;
}

// An item to place in a spatial tree: a run of slots, its Morton code.
typedef struct item {
    uint32_t code;
    uint32_t tri_begin, tri_count;
} item;

static int by_code(const void *x, const void *y) {
    const item *a = x, *b = y;
    return a->code < b->code ? -1 : a->code > b->code;
}

// Node `at` over items [lo, hi): a leaf for one item, else two children
// split at the highest bit where the first and last codes differ (the
// middle when they are equal).
static void build_lbvh(tree *t, const boxes *bx, const item *items, size_t lo, size_t hi,
                       uint32_t at) {
    if (hi - lo == 1) {
        t->node[at].tri_begin = items[lo].tri_begin;
        t->node[at].tri_count = items[lo].tri_count;
        t->node[at].child_count = 0;
        box_of_slots(t, bx, &t->node[at]);
        return;
    }
    size_t split = lo + (hi - lo) / 2;
    const uint32_t first = items[lo].code, last = items[hi - 1].code;
    if (first != last) {
        const int bit = 31 - __builtin_clz(first ^ last);
        split = lo + 1;
        while (split < hi && !((items[split].code >> bit) & 1u))
            ++split;
    }
    const uint32_t child = add_nodes(t, 2);
    tnode *n = &t->node[at];
    n->first_child = child;
    n->child_count = 2;
    build_lbvh(t, bx, items, lo, split, child);
    build_lbvh(t, bx, items, split, hi, child + 1);
    n = &t->node[at]; // t->node may have moved
    const tnode *l = &t->node[child], *r = &t->node[child + 1];
    n->tri_begin = l->tri_begin < r->tri_begin ? l->tri_begin : r->tri_begin;
    n->tri_count = l->tri_count + r->tri_count;
    for (int k = 0; k < 3; ++k) {
        n->lo[k] = l->lo[k] < r->lo[k] ? l->lo[k] : r->lo[k];
        n->hi[k] = l->hi[k] > r->hi[k] ? l->hi[k] : r->hi[k];
    }
}

// Items laid out in code order: each item's slots renumbered so that a
// node's slots stay contiguous.
static tree lbvh(const char *name, const boxes *bx, item *items, size_t n, const uint32_t *order,
                 size_t triangles) {
    qsort(items, n, sizeof *items, by_code);
    tree t = {name, NULL, 0, 0, NULL};
    t.order = checked(malloc(triangles * sizeof *t.order));
    uint32_t slot = 0;
    for (size_t i = 0; i < n; ++i) {
        memcpy(t.order + slot, order + items[i].tri_begin, items[i].tri_count * sizeof *t.order);
        items[i].tri_begin = slot;
        slot += items[i].tri_count;
    }
    add_nodes(&t, 1);
    build_lbvh(&t, bx, items, 0, n, 0);
    return t;
}

static tree lbvh_over_leaves(const selfcol_hierarchy *h, const boxes *bx) {
    item *items = checked(malloc(h->leaf_count * sizeof *items));
    size_t n = 0;
    for (size_t i = 0; i < h->node_count; ++i) {
        const selfcol_node *node = &h->nodes[i];
        if (node->child_count != 0)
            continue;
        double lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
            lo[k] = node->lo[k];
            hi[k] = node->hi[k];
        }
        items[n++] = (item){morton(bx, lo, hi), node->tri_begin, node->tri_count};
    }
    tree t = lbvh("lbvh-leaves", bx, items, n, h->tri_order, h->triangle_count);
    free(items);
    return t;
}

static tree lbvh_over_triangles(const char *name, const boxes *bx, size_t triangles, uint32_t run) {
    item *tri = checked(malloc(triangles * sizeof *tri));
    uint32_t *identity = checked(malloc(triangles * sizeof *identity));
    for (uint32_t i = 0; i < triangles; ++i) {
        identity[i] = i;
        tri[i] = (item){morton(bx, bx->lo + 3 * i, bx->hi + 3 * i), i, 1};
    }
    qsort(tri, triangles, sizeof *tri, by_code);
    uint32_t *sorted = checked(malloc(triangles * sizeof *sorted));
    for (size_t i = 0; i < triangles; ++i)
        sorted[i] = tri[i].tri_begin;
    // Runs of `run` consecutive triangles in code order are the leaves.
    size_t n = (triangles + run - 1) / run;
    item *items = checked(malloc(n * sizeof *items));
    for (size_t i = 0; i < n; ++i) {
        const uint32_t begin = (uint32_t)(i * run);
        const uint32_t count = (uint32_t)(triangles - begin < run ? triangles - begin : run);
        items[i] = (item){tri[begin].code, begin, count};
    }
    tree t = lbvh(name, bx, items, n, sorted, triangles);
    free(items);
    free(sorted);
    free(identity);
    free(tri);
    return t;
}

// Each node's grandchildren become its children (a leaf child stays).
static tree widened(const tree *b, const char *name, size_t triangles) {
    tree t = {name, NULL, 0, 0, NULL};
    t.order = checked(malloc(triangles * sizeof *t.order));
    memcpy(t.order, b->order, triangles * sizeof *t.order);
    // Breadth first from the root of b; map[i] = the node of t for b's node i.
    uint32_t *queue = checked(malloc(b->count * sizeof *queue));
    uint32_t *map = checked(malloc(b->count * sizeof *map));
    size_t head = 0, tail = 0;
    queue[tail++] = 0;
    add_nodes(&t, 1);
    map[0] = 0;
    while (head < tail) {
        const uint32_t i = queue[head++];
        const tnode *src = &b->node[i];
        tnode copy = *src;
        uint32_t kids[4], k = 0;
        for (uint32_t c = 0; c < src->child_count; ++c) {
            const tnode *child = &b->node[src->first_child + c];
            if (child->child_count == 0)
                kids[k++] = src->first_child + c;
            else
                for (uint32_t g = 0; g < child->child_count; ++g)
                    kids[k++] = child->first_child + g;
        }
        copy.child_count = k;
        if (k > 0) {
            copy.first_child = add_nodes(&t, k);
            for (uint32_t c = 0; c < k; ++c) {
                map[kids[c]] = copy.first_child + c;
                queue[tail++] = kids[c];
            }
        }
        t.node[map[i]] = copy;
    }
    free(queue);
    free(map);
    return t;
}

// ---------------------------------------------------------------------------

static int by_double(const void *x, const void *y) {
    const double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: selfcol-bench-tree FRAME.ply [...]\n");
        return 2;
    }
    printf("frame,tree,nodes,node_bytes,node_pairs,triangle_tests,candidate_pairs,median_ms,"
           "min_ms\n");
    for (int f = 1; f < argc; ++f) {
        meshio_mesh m;
        meshio_error err;
        memset(&m, 0, sizeof m);
        if (meshio_read(argv[f], &m, &err, NULL) != 0) {
            fprintf(stderr, "selfcol-bench-tree: cannot read %s\n", argv[f]);
            return 1;
        }
        selfcol_mesh *mesh = NULL;
        selfcol_hierarchy *h = NULL;
        if (selfcol_mesh_create(&mesh, m.vertex_count, m.positions, m.triangle_count, m.triangles,
                                NULL) != SELFCOL_OK ||
            selfcol_hierarchy_create(&h, mesh, NULL) != SELFCOL_OK) {
            fprintf(stderr, "selfcol-bench-tree: %s refused\n", argv[f]);
            return 1;
        }
        const double d = 0.1 * selfcol_mesh_mean_edge_length(mesh);
        const size_t T = m.triangle_count;
        boxes bx;
        bx.lo = checked(malloc(3 * T * sizeof(double)));
        bx.hi = checked(malloc(3 * T * sizeof(double)));
        for (int k = 0; k < 3; ++k) {
            bx.mesh_lo[k] = INFINITY;
            bx.mesh_hi[k] = -INFINITY;
        }
        for (size_t t = 0; t < T; ++t)
            for (int k = 0; k < 3; ++k) {
                double lo = INFINITY, hi = -INFINITY;
                for (int c = 0; c < 3; ++c) {
                    const double x = m.positions[3 * (size_t)m.triangles[3 * t + c] + k];
                    lo = x < lo ? x : lo;
                    hi = x > hi ? x : hi;
                }
                bx.lo[3 * t + k] = lo;
                bx.hi[3 * t + k] = hi;
                bx.mesh_lo[k] = lo < bx.mesh_lo[k] ? lo : bx.mesh_lo[k];
                bx.mesh_hi[k] = hi > bx.mesh_hi[k] ? hi : bx.mesh_hi[k];
            }
        tree trees[5];
        trees[0] = topology_tree(h);
        trees[1] = lbvh_over_leaves(h, &bx);
        trees[2] = widened(&trees[1], "lbvh-leaves-4", T);
        trees[3] = lbvh_over_triangles("lbvh-tris-1", &bx, T, 1);
        trees[4] = lbvh_over_triangles("lbvh-tris-8", &bx, T, 8);
        // Depth first: a level adds at most arity^2 pairs to the stack.
        pair *stack = checked(malloc(((size_t)1 << 20) * sizeof *stack));
        counts reference = {0, 0, 0};
        for (int i = 0; i < 5; ++i) {
            double ms[5];
            counts c = traverse(&trees[i], &bx, d, stack); // warm-up
            for (int r = 0; r < 5; ++r) {
                const double t0 = now();
                c = traverse(&trees[i], &bx, d, stack);
                ms[r] = 1e3 * (now() - t0);
            }
            qsort(ms, 5, sizeof ms[0], by_double);
            if (i == 0)
                reference = c;
            else if (c.candidates != reference.candidates) {
                fprintf(stderr,
                        "selfcol-bench-tree: %s found %llu candidate pairs, topology %llu\n",
                        trees[i].name, (unsigned long long)c.candidates,
                        (unsigned long long)reference.candidates);
                return 1;
            }
            const char *base = strrchr(argv[f], '/');
            printf("%s,%s,%zu,%zu,%llu,%llu,%llu,%.1f,%.1f\n", base ? base + 1 : argv[f],
                   trees[i].name, trees[i].count, trees[i].count * sizeof(tnode),
                   (unsigned long long)c.node_pairs, (unsigned long long)c.triangle_tests,
                   (unsigned long long)c.candidates, ms[2], ms[0]);
            fflush(stdout);
        }
        for (int i = 0; i < 5; ++i) {
            free(trees[i].node);
            free(trees[i].order);
        }
        free(stack);
        free(bx.lo);
        free(bx.hi);
        selfcol_hierarchy_destroy(h);
        selfcol_mesh_destroy(mesh);
        meshio_mesh_free(&m);
    }
    return 0;
}
