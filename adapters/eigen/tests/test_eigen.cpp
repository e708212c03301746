// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The Eigen adapter (selfcol/eigen.hpp) against the C API on the same
// inputs: generated meshes (tools/meshio/fixtures.h) and small hand-made meshes. Every
// record of the C query appears in the Eigen result, in the same order, with
// identical indices, distances, weights and directions, and the counts are
// equal; bad input throws selfcol::error with the C library's status.
#include <selfcol/eigen.hpp>

extern "C" {
#include "fixtures.h"
}

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "check.hpp"

// Expects `expr` to throw selfcol::error with `status`, whose text names it.
#define CHECK_THROWS(expr, expected)                                                               \
    do {                                                                                           \
        int got_ = 0;                                                                              \
        std::string what_;                                                                         \
        try {                                                                                      \
            (void)(expr);                                                                          \
        } catch (const selfcol::error &e) {                                                        \
            got_ = e.status();                                                                     \
            what_ = e.what();                                                                      \
        }                                                                                          \
        if (got_ != (expected) ||                                                                  \
            what_.find(selfcol_status_string(expected)) == std::string::npos) {                    \
            std::fprintf(stderr, "%s:%d: %s: expected status %d, got %d (\"%s\")\n", __FILE__,     \
                         __LINE__, #expr, (int)(expected), got_, what_.c_str());                   \
            ++failures;                                                                            \
        }                                                                                          \
    } while (0)

namespace {

struct owned_scene {
    fixture s;
    owned_scene() {
        std::memset(&s, 0, sizeof s);
    }
    ~owned_scene() {
        fixture_free(&s);
    }
    owned_scene(const owned_scene &) = delete;
    owned_scene &operator=(const owned_scene &) = delete;
};

// libigl's types: column-major MatrixXd and MatrixXi.
void to_eigen(const fixture &s, Eigen::MatrixXd &V, Eigen::MatrixXi &F) {
    V.resize((Eigen::Index)s.vertex_count, 3);
    F.resize((Eigen::Index)s.triangle_count, 3);
    for (size_t i = 0; i < s.vertex_count; ++i)
        for (int k = 0; k < 3; ++k)
            V((Eigen::Index)i, k) = s.positions[3 * i + k];
    for (size_t i = 0; i < s.triangle_count; ++i)
        for (int k = 0; k < 3; ++k)
            F((Eigen::Index)i, k) = (int)s.triangles[3 * i + k];
}

// The C API alone, as a C program would use it.
struct c_query {
    selfcol_mesh *mesh[2] = {nullptr, nullptr};
    selfcol_hierarchy *hierarchy[2] = {nullptr, nullptr};
    selfcol_contacts *contacts = nullptr;
    ~c_query() {
        selfcol_contacts_destroy(contacts);
        for (int i = 0; i < 2; ++i) {
            selfcol_hierarchy_destroy(hierarchy[i]);
            selfcol_mesh_destroy(mesh[i]);
        }
    }
    bool add(int i, const fixture &s) {
        return selfcol_mesh_create(&mesh[i], s.vertex_count, s.positions, s.triangle_count,
                                   s.triangles, nullptr) == SELFCOL_OK &&
               selfcol_hierarchy_create(&hierarchy[i], mesh[i], nullptr) == SELFCOL_OK;
    }
    std::vector<selfcol_contact> run(double distance, uint32_t method = SELFCOL_METHOD_EXACT,
                                     uint32_t kinds = SELFCOL_KIND_ALL) {
        std::vector<selfcol_contact> out;
        selfcol_query_options o;
        if (selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION) != SELFCOL_OK ||
            (contacts == nullptr && selfcol_contacts_create(&contacts, nullptr) != SELFCOL_OK)) {
            CHECK(false && "C set-up");
            return out;
        }
        o.distance = distance;
        o.method = method;
        o.kinds = kinds;
        int rc = hierarchy[1] ? selfcol_hierarchy_collide(hierarchy[0], hierarchy[1], contacts, &o)
                              : selfcol_hierarchy_self_collide(hierarchy[0], contacts, &o);
        CHECK(rc == SELFCOL_OK);
        const selfcol_contact *c = nullptr;
        size_t n = 0;
        CHECK(selfcol_contacts_data(contacts, &c, &n) == SELFCOL_OK);
        out.assign(c, c + n);
        return out;
    }
};

// Every C record in r, in order, with identical values; counts equal.
void check_same(const std::vector<selfcol_contact> &c, const selfcol::contact_result &r,
                const char *what) {
    Eigen::Index n[3] = {0, 0, 0};
    int mismatches = 0;
    for (const selfcol_contact &k : c) {
        if (k.kind > SELFCOL_CONTACT_EF) {
            ++mismatches;
            continue;
        }
        const Eigen::Index i = n[k.kind]++;
        bool same = true;
        if (k.kind == SELFCOL_CONTACT_VF) {
            same = i < r.VF.rows() && r.VF(i, 0) == (int)k.first && r.VF(i, 1) == (int)k.second &&
                   r.VF_distance(i) == k.distance && r.VF_weights(i, 0) == k.wb[0] &&
                   r.VF_weights(i, 1) == k.wb[1] && r.VF_weights(i, 2) == k.wb[2] &&
                   r.VF_direction(i, 0) == k.direction[0] &&
                   r.VF_direction(i, 1) == k.direction[1] &&
                   r.VF_direction(i, 2) == k.direction[2] && r.VF_mesh(i, 0) == (int)k.first_mesh &&
                   r.VF_mesh(i, 1) == (int)k.second_mesh;
        } else if (k.kind == SELFCOL_CONTACT_EE) {
            same = i < r.EE.rows() && r.EE(i, 0) == (int)k.a[0] && r.EE(i, 1) == (int)k.a[1] &&
                   r.EE(i, 2) == (int)k.b[0] && r.EE(i, 3) == (int)k.b[1] &&
                   r.EE_distance(i) == k.distance && r.EE_weights(i, 0) == k.wa[0] &&
                   r.EE_weights(i, 1) == k.wa[1] && r.EE_weights(i, 2) == k.wb[0] &&
                   r.EE_weights(i, 3) == k.wb[1] && r.EE_direction(i, 0) == k.direction[0] &&
                   r.EE_direction(i, 1) == k.direction[1] &&
                   r.EE_direction(i, 2) == k.direction[2] && r.EE_mesh(i, 0) == (int)k.first_mesh &&
                   r.EE_mesh(i, 1) == (int)k.second_mesh;
        } else {
            same = i < r.EF.rows() && r.EF(i, 0) == (int)k.a[0] && r.EF(i, 1) == (int)k.a[1] &&
                   r.EF(i, 2) == (int)k.second && r.EF_weights(i, 0) == k.wa[0] &&
                   r.EF_weights(i, 1) == k.wa[1] && r.EF_weights(i, 2) == k.wb[0] &&
                   r.EF_weights(i, 3) == k.wb[1] && r.EF_weights(i, 4) == k.wb[2] &&
                   r.EF_direction(i, 0) == k.direction[0] &&
                   r.EF_direction(i, 1) == k.direction[1] &&
                   r.EF_direction(i, 2) == k.direction[2] && r.EF_mesh(i, 0) == (int)k.first_mesh &&
                   r.EF_mesh(i, 1) == (int)k.second_mesh;
        }
        mismatches += !same;
    }
    const bool counts = r.VF.rows() == n[0] && r.EE.rows() == n[1] && r.EF.rows() == n[2] &&
                        r.VF_distance.size() == n[0] && r.EE_distance.size() == n[1] &&
                        r.stats.vf_contacts == (uint64_t)n[0] &&
                        r.stats.ee_contacts == (uint64_t)n[1] &&
                        r.stats.ef_contacts == (uint64_t)n[2];
    if (mismatches || !counts) {
        std::fprintf(stderr, "%s: C %ld/%ld/%ld VF/EE/EF, Eigen %ld/%ld/%ld, %d records differ\n",
                     what, (long)n[0], (long)n[1], (long)n[2], (long)r.VF.rows(), (long)r.EE.rows(),
                     (long)r.EF.rows(), mismatches);
        ++failures;
    }
}

double mean_edge(const fixture &s) {
    selfcol_mesh *m = nullptr;
    double mean = 0.0;
    if (selfcol_mesh_create(&m, s.vertex_count, s.positions, s.triangle_count, s.triangles,
                            nullptr) == SELFCOL_OK)
        mean = selfcol_mesh_mean_edge_length(m);
    selfcol_mesh_destroy(m);
    return mean;
}

// Self queries of generated scenes: the one-shot form with its default
// distance, and every method, against the C API.
void test_self_query_matches_c_api() {
    struct named {
        const char *name;
        owned_scene sc;
    } scenes[4];
    scenes[0].name = "crumpled";
    CHECK(fixture_crumpled(&scenes[0].sc.s, 10, 10, 3, 2.5) == 0);
    scenes[1].name = "hairpin";
    CHECK(fixture_hairpin(&scenes[1].sc.s, 8, 0.05) == 0);
    scenes[2].name = "zfold";
    CHECK(fixture_zfold(&scenes[2].sc.s, 8, 3, 0.2, 2, 0.3) == 0);
    scenes[3].name = "ramp";
    CHECK(fixture_ramp(&scenes[3].sc.s, 3, 16, 4.0, 0.6, -0.05) == 0);
    size_t total_ef = 0, total_proximities = 0;
    for (named &n : scenes) {
        const fixture &s = n.sc.s;
        Eigen::MatrixXd V;
        Eigen::MatrixXi F;
        to_eigen(s, V, F);
        c_query c;
        CHECK(c.add(0, s));
        const double d = 0.1 * mean_edge(s);
        const std::vector<selfcol_contact> expected = c.run(d);
        const selfcol::contact_result r = selfcol::self_collide(V, F);
        check_same(expected, r, n.name);
        total_ef += (size_t)r.EF.rows();
        total_proximities += (size_t)(r.VF.rows() + r.EE.rows());
        // The other methods through the handles, one contact buffer reused.
        selfcol::mesh mesh(V, F);
        selfcol::hierarchy hierarchy(mesh);
        selfcol::contacts buffer;
        const selfcol_method methods[] = {SELFCOL_METHOD_EXHAUSTIVE, SELFCOL_METHOD_BVH,
                                          SELFCOL_METHOD_SEED, SELFCOL_METHOD_CONE,
                                          SELFCOL_METHOD_EXACT};
        for (selfcol_method method : methods) {
            selfcol::query_options o;
            o.method = method;
            o.threads = 2;
            check_same(c.run(d, method), selfcol::self_collide(hierarchy, buffer, o), n.name);
        }
    }
    // The scenes are not trivial: they cross themselves and come close.
    CHECK(total_ef > 0);
    CHECK(total_proximities > 0);
}

// Two meshes: the contacts between them, mesh columns 0 and 1.
void test_two_mesh_query_matches_c_api() {
    owned_scene a, b;
    CHECK(fixture_sheet_pair(&a.s, &b.s, 10, 7, 1.2, 0.0) == 0);
    Eigen::MatrixXd Va, Vb;
    Eigen::MatrixXi Fa, Fb;
    to_eigen(a.s, Va, Fa);
    to_eigen(b.s, Vb, Fb);
    c_query c;
    CHECK(c.add(0, a.s) && c.add(1, b.s));
    // The default d: 0.1 x the mean edge length of both meshes (edge-weighted).
    const double ea = (double)selfcol_mesh_count(c.mesh[0], SELFCOL_MESH_EDGES);
    const double eb = (double)selfcol_mesh_count(c.mesh[1], SELFCOL_MESH_EDGES);
    const double mean = (ea * selfcol_mesh_mean_edge_length(c.mesh[0]) +
                         eb * selfcol_mesh_mean_edge_length(c.mesh[1])) /
                        (ea + eb);
    const std::vector<selfcol_contact> expected = c.run(0.1 * mean);
    const selfcol::contact_result r = selfcol::collide(Va, Fa, Vb, Fb);
    check_same(expected, r, "sheet pair");
    CHECK(r.intersects());
    // Both orders of membership appear (an edge of a through b and of b through a).
    bool first_in_0 = false, first_in_1 = false;
    for (Eigen::Index i = 0; i < r.EF.rows(); ++i) {
        first_in_0 = first_in_0 || r.EF_mesh(i, 0) == 0;
        first_in_1 = first_in_1 || r.EF_mesh(i, 0) == 1;
        CHECK(r.EF_mesh(i, 0) != r.EF_mesh(i, 1));
    }
    CHECK(first_in_0 && first_in_1);
}

// Row- or column-major, double or float, a Map, other index types: one result.
void test_layouts_give_one_result() {
    owned_scene sc;
    CHECK(fixture_crumpled(&sc.s, 8, 8, 11, 2.5) == 0);
    Eigen::MatrixXd V;
    Eigen::MatrixXi F;
    to_eigen(sc.s, V, F);
    selfcol::query_options o;
    o.distance = 0.2; // absolute: the float mesh's mean edge length differs
    const selfcol::contact_result ref = selfcol::self_collide(V, F, o);
    c_query c;
    CHECK(c.add(0, sc.s));
    check_same(c.run(0.2), ref, "absolute distance");

    typedef Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> RowV;
    typedef Eigen::Matrix<long long, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> RowF;
    const RowV Vr = V;
    const RowF Fr = F.cast<long long>();
    check_same(c.run(0.2), selfcol::self_collide(Vr, Fr, o), "row-major");
    const Eigen::Map<const RowV> Vm(sc.s.positions, (Eigen::Index)sc.s.vertex_count, 3);
    const Eigen::Map<const Eigen::Matrix<uint32_t, Eigen::Dynamic, 3, Eigen::RowMajor>> Fm(
        sc.s.triangles, (Eigen::Index)sc.s.triangle_count, 3);
    check_same(c.run(0.2), selfcol::self_collide(Vm, Fm, o), "map of the C arrays");
    // A dynamic-size row-major V, and an expression (a block of a wider matrix).
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> wide(V.rows(), 5);
    wide.setZero();
    wide.leftCols(3) = V;
    check_same(c.run(0.2), selfcol::self_collide(wide.leftCols(3), F, o), "block");

    // float V: the same as the C API's float constructor.
    const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> Vf = V.cast<float>();
    selfcol_mesh *fm = nullptr;
    selfcol_hierarchy *fh = nullptr;
    selfcol_contacts *fc = nullptr;
    CHECK(selfcol_mesh_create_float(&fm, sc.s.vertex_count, Vf.data(), 3 * sizeof(float),
                                    sc.s.triangle_count, sc.s.triangles, nullptr) == SELFCOL_OK);
    CHECK(selfcol_hierarchy_create(&fh, fm, nullptr) == SELFCOL_OK);
    CHECK(selfcol_contacts_create(&fc, nullptr) == SELFCOL_OK);
    selfcol_query_options co;
    selfcol_query_options_init(&co, SELFCOL_QUERY_OPTIONS_VERSION);
    co.distance = 0.2;
    CHECK(selfcol_hierarchy_self_collide(fh, fc, &co) == SELFCOL_OK);
    const selfcol_contact *records = nullptr;
    size_t n = 0;
    selfcol_contacts_data(fc, &records, &n);
    check_same(std::vector<selfcol_contact>(records, records + n), selfcol::self_collide(Vf, F, o),
               "float");
    // Column-major float too.
    const Eigen::MatrixXf Vfc = Vf;
    check_same(std::vector<selfcol_contact>(records, records + n), selfcol::self_collide(Vfc, F, o),
               "column-major float");
    selfcol_contacts_destroy(fc);
    selfcol_hierarchy_destroy(fh);
    selfcol_mesh_destroy(fm);
}

// Frames: set_positions + refit on kept handles, as the C API does it.
void test_frames_on_kept_handles() {
    owned_scene sc;
    CHECK(fixture_hairpin(&sc.s, 6, 0.5) == 0);
    Eigen::MatrixXd V;
    Eigen::MatrixXi F;
    to_eigen(sc.s, V, F);
    selfcol::mesh mesh(V, F);
    CHECK(mesh.count(SELFCOL_MESH_VERTICES) == V.rows());
    CHECK(mesh.count(SELFCOL_MESH_TRIANGLES) == F.rows());
    CHECK((mesh.triangles().cast<int>() - F).cwiseAbs().maxCoeff() == 0);
    selfcol::hierarchy hierarchy(mesh);
    selfcol::contacts buffer;
    c_query c;
    CHECK(c.add(0, sc.s));
    selfcol::query_options o;
    o.distance = 0.3;
    for (int frame = 0; frame < 4; ++frame) {
        // The top layer tilts down from the fold (x = 6) towards the bottom
        // layer, then through it. Top vertex (i, j) is 14 + 2 i + j, at x = i.
        const Eigen::Index top = 2 * (6 + 1);
        for (Eigen::Index v = top; v < V.rows(); ++v) {
            const double x = (double)((v - top) / 2);
            V(v, 2) = 0.5 - 0.4 * frame * (6.0 - x) / 6.0;
            sc.s.positions[3 * v + 2] = V(v, 2);
        }
        mesh.set_positions(V);
        CHECK((mesh.positions() - V).cwiseAbs().maxCoeff() == 0.0);
        if (frame == 1) {
            o.method = SELFCOL_METHOD_BVH; // a query before the refit is refused
            CHECK_THROWS(selfcol::self_collide(hierarchy, buffer, o), SELFCOL_ESTALE);
            o.method = SELFCOL_METHOD_EXACT;
        }
        hierarchy.refit();
        CHECK(selfcol_mesh_set_positions(c.mesh[0], sc.s.positions, sc.s.vertex_count) ==
              SELFCOL_OK);
        CHECK(selfcol_hierarchy_refit(c.hierarchy[0]) == SELFCOL_OK);
        const selfcol::contact_result r = selfcol::self_collide(hierarchy, buffer, o);
        check_same(c.run(0.3), r, "frame");
        if (frame == 0)
            CHECK(!r.intersects());
        if (frame == 3)
            CHECK(r.intersects());
    }
    // Options: one kind only, and the relative distance.
    o.kinds = SELFCOL_KIND_VF;
    check_same(c.run(0.3, SELFCOL_METHOD_EXACT, SELFCOL_KIND_VF),
               selfcol::self_collide(hierarchy, buffer, o), "kinds");
    o.kinds = SELFCOL_KIND_ALL;
    o.distance = -1.0;
    o.distance_rel = 0.6;
    const selfcol::contact_result wide = selfcol::self_collide(hierarchy, o);
    check_same(c.run(0.6 * selfcol_mesh_mean_edge_length(c.mesh[0])), wide, "distance_rel");
    CHECK(wide.VF.rows() > selfcol::self_collide(hierarchy).VF.rows()); // the default: 0.1
}

// Bad input becomes selfcol::error with the C library's status.
void test_bad_input_throws() {
    Eigen::MatrixXd V(4, 3);
    V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
    Eigen::MatrixXi F(2, 3);
    F << 0, 1, 2, 0, 1, 3;
    CHECK(selfcol::self_collide(V, F).VF.rows() == 0);

    Eigen::MatrixXi bad = F;
    bad(1, 2) = 4; // == #V
    CHECK_THROWS(selfcol::mesh(V, bad), SELFCOL_EINVAL);
    bad(1, 2) = -1;
    CHECK_THROWS(selfcol::mesh(V, bad), SELFCOL_EINVAL);
    Eigen::MatrixXd nan = V;
    nan(2, 1) = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS(selfcol::mesh(nan, F), SELFCOL_EINVAL);
    Eigen::MatrixXd far = V;
    far(1, 0) = 1e300;
    CHECK_THROWS(selfcol::mesh(far, F), SELFCOL_ERANGE);
    const Eigen::MatrixXd two_columns = V.leftCols(2);
    CHECK_THROWS(selfcol::mesh(two_columns, F), SELFCOL_EINVAL);
    Eigen::MatrixXi four_columns(2, 4);
    four_columns << 0, 1, 2, 3, 0, 1, 3, 2;
    CHECK_THROWS(selfcol::mesh(V, four_columns), SELFCOL_EINVAL);
    const Eigen::MatrixXi no_triangles(0, 3);
    CHECK_THROWS(selfcol::mesh(V, no_triangles), SELFCOL_EINVAL);
    CHECK_THROWS(selfcol::self_collide(V, bad), SELFCOL_EINVAL);

    selfcol::mesh mesh(V, F);
    CHECK_THROWS(mesh.set_positions(V.topRows(3)), SELFCOL_EINVAL); // another #V
    CHECK_THROWS(mesh.set_positions(nan), SELFCOL_EINVAL);
    CHECK((mesh.positions() - V).cwiseAbs().maxCoeff() == 0.0); // kept on error
    selfcol::hierarchy hierarchy(mesh);
    selfcol::query_options o;
    o.distance = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS(selfcol::self_collide(hierarchy, o), SELFCOL_EINVAL);
    o.distance = 0.1;
    o.threads = 0;
    CHECK_THROWS(selfcol::self_collide(hierarchy, o), SELFCOL_EINVAL);
    // The refused field is named by the library's check (threads are the
    // context's since 0.4: selfcol_context_options_check).
    try {
        (void)selfcol::self_collide(hierarchy, o);
        CHECK(false && "no exception");
    } catch (const selfcol::error &e) {
        CHECK(std::string(e.what()).find("selfcol_context_create: "
                                         "selfcol_context_options.threads = 0 is not in 1 .. 64") !=
              std::string::npos);
    }
    o.threads = 65;
    CHECK_THROWS(selfcol::self_collide(hierarchy, o), SELFCOL_EINVAL);
    selfcol_hierarchy_options ho;
    selfcol_hierarchy_options_init(&ho, SELFCOL_HIERARCHY_OPTIONS_VERSION);
    ho.version = 2; // 0.3's layout, with threads
    try {
        selfcol::hierarchy named(mesh, &ho);
        CHECK(false && "no exception");
    } catch (const selfcol::error &e) {
        CHECK(e.status() == SELFCOL_EVERSION);
        CHECK(std::string(e.what()).find("selfcol_hierarchy_options.version = 2 is an older "
                                         "layout") != std::string::npos);
    }
    o.threads = 1;
    CHECK_THROWS(selfcol::collide(hierarchy, hierarchy, o), SELFCOL_EINVAL); // one mesh twice
    // Empty owners reach the library as NULL handles: SELFCOL_EINVAL, no crash.
    selfcol::hierarchy empty;
    CHECK_THROWS(selfcol::self_collide(empty, o), SELFCOL_EINVAL);
    CHECK_THROWS(empty.refit(), SELFCOL_EINVAL);
    const selfcol::mesh no_mesh;
    CHECK_THROWS(selfcol::hierarchy(no_mesh), SELFCOL_EINVAL);
    // The exception is a std::runtime_error whose text names the call.
    try {
        selfcol::mesh m(nan, F);
        CHECK(false && "no exception");
    } catch (const std::runtime_error &e) {
        CHECK(std::string(e.what()).find("selfcol_mesh_create") != std::string::npos);
        // and the culprit, found by the library's checker (selfcol_mesh_check)
        CHECK(std::string(e.what()).find("V(2, 1) = nan is not finite") != std::string::npos);
    }
    try {
        selfcol::mesh m(far, F);
        CHECK(false && "no exception");
    } catch (const std::runtime_error &e) {
        CHECK(std::string(e.what()).find("V(1, 0) = 1.0000000000000001e+300 is beyond the "
                                         "largest coordinate magnitude 2^200") !=
              std::string::npos);
    }
}

// The owners: movable, not copyable; a moved-from owner is empty.
void test_owners_move_and_release() {
    static_assert(!std::is_copy_constructible<selfcol::mesh>::value, "mesh is not copyable");
    static_assert(!std::is_copy_assignable<selfcol::hierarchy>::value, "not copyable");
    static_assert(!std::is_copy_constructible<selfcol::contacts>::value, "not copyable");
    static_assert(std::is_nothrow_move_constructible<selfcol::mesh>::value, "movable");
    static_assert(std::is_nothrow_move_assignable<selfcol::hierarchy>::value, "movable");
    static_assert(std::is_nothrow_move_constructible<selfcol::contacts>::value, "movable");
    static_assert(std::is_base_of<std::runtime_error, selfcol::error>::value, "runtime_error");

    Eigen::MatrixXd V(3, 3);
    V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
    Eigen::MatrixXi F(1, 3);
    F << 0, 1, 2;
    selfcol::mesh a(V, F);
    selfcol_mesh *raw = a.get();
    selfcol::mesh b(std::move(a));
    CHECK(!a && b && b.get() == raw);
    a = std::move(b);
    CHECK(a.get() == raw && !b);
    selfcol::hierarchy h(a);
    selfcol::hierarchy h2;
    h2 = std::move(h);
    CHECK(!h && h2);
    h2.refit();
    selfcol::contacts c;
    selfcol::contacts c2(std::move(c));
    CHECK(!c && c2 && c2.size() == 0);
    selfcol_mesh *released = a.release();
    CHECK(released == raw && !a);
    selfcol::mesh adopted(released); // owned again, destroyed at scope exit
    CHECK(adopted.count(SELFCOL_MESH_TRIANGLES) == 1);
}

} // namespace

int main() {
    test_self_query_matches_c_api();
    test_two_mesh_query_matches_c_api();
    test_layouts_give_one_result();
    test_frames_on_kept_handles();
    test_bad_input_throws();
    test_owners_move_and_release();
    if (failures) {
        std::fprintf(stderr, "test_eigen: %d failure(s)\n", failures);
        return 1;
    }
    std::printf("test_eigen: all checks passed\n");
    return 0;
}
