// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file eigen.hpp
 * @defgroup eigen Eigen adapter (C++11, header-only)
 * libselfcol for code that holds meshes as Eigen matrices in libigl's
 * convention: V is #V x 3 (double, or float or any real type, converted to
 * double; row- or column-major, any Eigen expression), F is #F x 3 integer
 * vertex indices (0-based). CMake target selfcol::eigen
 * (find_package(selfcol COMPONENTS eigen)).
 *
 * ```cpp
 * #include <selfcol/eigen.hpp>
 * selfcol::contact_result r = selfcol::self_collide(V, F); // d = 0.1 x mean edge length
 * // r.VF (#VF x 2: vertex, triangle), r.EE (#EE x 4), r.EF (#EF x 3), distances, weights
 * ```
 *
 * Or, per frame with the handles kept (no topology rebuilt):
 * ```cpp
 * selfcol::mesh mesh(V, F);
 * selfcol::hierarchy hierarchy(mesh);
 * selfcol::contacts buffer;
 * for (...) {
 *     mesh.set_positions(V_of_frame);
 *     hierarchy.refit();
 *     selfcol::contact_result r = selfcol::self_collide(hierarchy, buffer);
 * }
 * ```
 *
 * Errors: every failure throws selfcol::error (a std::runtime_error) carrying
 * the selfcol_status code (status()) and, in what(), the failing call and
 * selfcol_status_string()'s text. The adapter checks the shapes first: V or F
 * without exactly 3 columns, or an index of F outside 0..#V-1, is
 * SELFCOL_EINVAL; an index that does not fit a C int in a result is
 * SELFCOL_ERANGE. Everything else is the C library's verdict (mesh.h,
 * hierarchy.h): NaN or infinite coordinates and empty meshes SELFCOL_EINVAL,
 * coordinates beyond 2^200 SELFCOL_ERANGE, out of memory SELFCOL_ENOMEM, a
 * query on a hierarchy not refit since its mesh moved SELFCOL_ESTALE. Refused
 * options are named in what() by the library's own check (the field, its
 * value, what is accepted: selfcol_query_options_check()).
 * Nothing else is thrown but std::bad_alloc from Eigen's own allocations.
 *
 * Ownership and threads are the C library's: mesh, hierarchy and contacts
 * own one handle each (movable, not copyable; a moved-from owner is empty);
 * a hierarchy borrows its mesh, which must outlive its use; see selfcol.h
 * for what may run concurrently.
 * @{
 */
#ifndef SELFCOL_EIGEN_HPP
#define SELFCOL_EIGEN_HPP

#ifndef __cplusplus
#error "selfcol/eigen.hpp is a C++11 header; C code includes selfcol/selfcol.h"
#endif

#include <selfcol/selfcol.h>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace selfcol {

/** A selfcol_status other than SELFCOL_OK, thrown at the C++ boundary. */
class error : public std::runtime_error {
  public:
    /** @param status the selfcol_status; @param context the call or check that failed */
    error(int status, const std::string &context)
        : std::runtime_error(context + ": " + selfcol_status_string(status)), status_(status) {}
    /** @return the selfcol_status code (negative). */
    int status() const noexcept {
        return status_;
    }

  private:
    int status_;
};

namespace detail {

inline void check(int status, const char *call) {
    if (status != SELFCOL_OK)
        throw error(status, call);
}

/** A refused call's options named by the library's own check (one of the
 *  selfcol_*_options_check functions): "selfcol_hierarchy_self_collide:
 *  selfcol_query_options.distance = nan is not a distance in 0 .. 1.60694e+60:
 *  invalid argument or input data". */
template <typename Options>
inline void check_options(int status, const char *call, const Options *options,
                          int (*explain)(const Options *, selfcol_options_problem *)) {
    if (status == SELFCOL_OK)
        return;
    if (status == SELFCOL_EINVAL || status == SELFCOL_EVERSION) {
        selfcol_options_problem p;
        p.version = SELFCOL_OPTIONS_PROBLEM_VERSION;
        if (explain(options, &p) == status && p.message[0] != '\0')
            throw error(status, std::string(call) + ": " + p.message);
    }
    throw error(status, call);
}

/** A refused mesh input's culprit, from the library's own checker
 *  (selfcol_mesh_check()), in V's terms: "selfcol_mesh_create: V(4, 2) =
 *  nan is not finite: invalid argument or input data". */
inline void check_mesh(int status, const char *call, std::size_t vertex_count, const double *xyz) {
    if (status == SELFCOL_OK)
        return;
    if (status == SELFCOL_EINVAL || status == SELFCOL_ERANGE) {
        selfcol_mesh_problem p;
        p.version = SELFCOL_MESH_PROBLEM_VERSION;
        if (xyz != nullptr && selfcol_mesh_check_positions(vertex_count, xyz, &p) != SELFCOL_OK &&
            p.kind >= SELFCOL_MESH_PROBLEM_NOT_FINITE) {
            std::ostringstream what;
            what << call << ": V(" << p.element << ", " << p.component
                 << ") = " << std::setprecision(17) << p.value << " " << p.reason;
            throw error(status, what.str());
        }
    }
    throw error(status, call);
}

struct mesh_deleter {
    void operator()(selfcol_mesh *m) const noexcept {
        selfcol_mesh_destroy(m);
    }
};
struct hierarchy_deleter {
    void operator()(selfcol_hierarchy *h) const noexcept {
        selfcol_hierarchy_destroy(h);
    }
};
struct contacts_deleter {
    void operator()(selfcol_contacts *c) const noexcept {
        selfcol_contacts_destroy(c);
    }
};
struct context_deleter {
    void operator()(selfcol_context *c) const noexcept {
        selfcol_context_destroy(c);
    }
};
typedef std::unique_ptr<selfcol_context, context_deleter> context_ptr;

/** A context of `threads` threads for one query (context.h: the library's
 *  one place for threads), or none for one thread (the calling thread). A
 *  refused count is named by selfcol_context_options_check: "selfcol_context_create:
 *  selfcol_context_options.threads = 0 is not in 1 .. 64". */
inline context_ptr query_context(unsigned threads) {
    if (threads == 1)
        return context_ptr();
    selfcol_context_options o;
    check(selfcol_context_options_init(&o, SELFCOL_CONTEXT_OPTIONS_VERSION),
          "selfcol_context_options_init");
    o.threads = threads;
    selfcol_context *c = nullptr;
    check_options(selfcol_context_create(&c, &o), "selfcol_context_create", &o,
                  selfcol_context_options_check);
    return context_ptr(c);
}

/** The layouts the C API reads: #V x 3 doubles and #F x 3 uint32_t, row-major. */
typedef Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> positions_matrix;
typedef Eigen::Matrix<std::uint32_t, Eigen::Dynamic, 3, Eigen::RowMajor> triangles_matrix;

template <class D> struct is_row_major_double {
    static const bool value = std::is_same<typename D::Scalar, double>::value &&
                              (int(D::Flags) & Eigen::DirectAccessBit) != 0 &&
                              (int(D::Flags) & Eigen::RowMajorBit) != 0;
};

template <class D> void check_columns(const Eigen::MatrixBase<D> &M, const char *name) {
    if (M.cols() != 3)
        throw error(SELFCOL_EINVAL, std::string("selfcol::eigen: ") + name +
                                        " must have 3 columns, not " +
                                        std::to_string(static_cast<long long>(M.cols())));
}

// Row-major contiguous doubles already: read in place.
template <class D>
const double *positions_data(const Eigen::MatrixBase<D> &V, positions_matrix &scratch,
                             std::true_type) {
    const D &v = V.derived();
    if (v.innerStride() == 1 && (v.rows() <= 1 || v.outerStride() == 3))
        return v.data();
    scratch = v;
    return scratch.data();
}

// Anything else (column-major, float, an expression): one converted copy.
template <class D>
const double *positions_data(const Eigen::MatrixBase<D> &V, positions_matrix &scratch,
                             std::false_type) {
    static_assert(!std::numeric_limits<typename D::Scalar>::is_integer,
                  "selfcol::eigen: V holds coordinates (double or float), not integers");
    scratch = V.template cast<double>();
    return scratch.data();
}

/** V's coordinates as #V x 3 row-major doubles, in place when V is laid out so. */
template <class D>
const double *positions_data(const Eigen::MatrixBase<D> &V, positions_matrix &scratch) {
    check_columns(V, "V");
    return positions_data(V, scratch,
                          std::integral_constant<bool, is_row_major_double<D>::value>());
}

/** F as uint32_t rows, every index checked against #V. */
template <class D>
void triangles_data(const Eigen::MatrixBase<D> &F, Eigen::Index vertex_count,
                    triangles_matrix &out) {
    typedef typename D::Scalar index_type;
    static_assert(std::numeric_limits<index_type>::is_integer,
                  "selfcol::eigen: F holds integer vertex indices");
    check_columns(F, "F");
    out.resize(F.rows(), 3);
    for (Eigen::Index i = 0; i < F.rows(); ++i) {
        for (Eigen::Index j = 0; j < 3; ++j) {
            const index_type f = F(i, j);
            // A negative index wraps to a huge one: refused with the others.
            if (static_cast<unsigned long long>(f) >= static_cast<unsigned long long>(vertex_count))
                throw error(SELFCOL_EINVAL,
                            "selfcol::eigen: F(" + std::to_string(static_cast<long long>(i)) +
                                ", " + std::to_string(static_cast<long long>(j)) +
                                ") = " + std::to_string(static_cast<long long>(f)) +
                                " is not a row of V (#V = " +
                                std::to_string(static_cast<long long>(vertex_count)) + ")");
            if (static_cast<unsigned long long>(f) >= SELFCOL_INVALID_INDEX)
                throw error(SELFCOL_ERANGE, "selfcol::eigen: F holds an index above 2^32 - 2");
            out(i, j) = static_cast<std::uint32_t>(f);
        }
    }
}

inline int to_int(std::uint32_t index) {
    if (index > static_cast<std::uint32_t>(std::numeric_limits<int>::max()))
        throw error(SELFCOL_ERANGE, "selfcol::eigen: an index does not fit the int of the results");
    return static_cast<int>(index);
}

} // namespace detail

/** Owner of a selfcol_mesh: positions and topology of one triangle surface. */
class mesh {
  public:
    /** An empty owner (no mesh). */
    mesh() noexcept {}
    /**
     * Creates the mesh (selfcol_mesh_create()) from V (#V x 3) and F (#F x 3).
     * @throws error SELFCOL_EINVAL for a wrong shape, an index of F outside
     *         0..#V-1, NaN/inf, an empty V or F; SELFCOL_ERANGE; SELFCOL_ENOMEM.
     */
    template <class DV, class DF>
    mesh(const Eigen::MatrixBase<DV> &V, const Eigen::MatrixBase<DF> &F,
         const selfcol_mesh_options *options = nullptr) {
        detail::positions_matrix positions;
        detail::triangles_matrix triangles;
        const double *xyz = detail::positions_data(V, positions);
        detail::triangles_data(F, V.rows(), triangles);
        selfcol_mesh *m = nullptr;
        detail::check_mesh(selfcol_mesh_create(&m, static_cast<std::size_t>(V.rows()), xyz,
                                               static_cast<std::size_t>(triangles.rows()),
                                               triangles.data(), options),
                           "selfcol_mesh_create", static_cast<std::size_t>(V.rows()), xyz);
        handle_.reset(m);
    }
    /** Takes ownership of a mesh made with the C API. */
    explicit mesh(selfcol_mesh *owned) noexcept : handle_(owned) {}
    mesh(mesh &&) noexcept = default;
    mesh &operator=(mesh &&) noexcept = default;
    mesh(const mesh &) = delete;
    mesh &operator=(const mesh &) = delete;

    /** The handle, still owned; NULL when empty. */
    selfcol_mesh *get() const noexcept {
        return handle_.get();
    }
    /** Gives up ownership: the caller destroys the handle. */
    selfcol_mesh *release() noexcept {
        return handle_.release();
    }
    explicit operator bool() const noexcept {
        return handle_ != nullptr;
    }

    /**
     * New positions for every vertex (selfcol_mesh_set_positions()); refit the
     * hierarchies over this mesh before querying them again.
     * @throws error SELFCOL_EINVAL (wrong shape, a #V other than the mesh's,
     *         NaN/inf, an empty owner); SELFCOL_ERANGE.
     */
    template <class DV> void set_positions(const Eigen::MatrixBase<DV> &V) {
        detail::positions_matrix positions;
        const double *xyz = detail::positions_data(V, positions);
        detail::check_mesh(
            selfcol_mesh_set_positions(handle_.get(), xyz, static_cast<std::size_t>(V.rows())),
            "selfcol_mesh_set_positions", static_cast<std::size_t>(V.rows()), xyz);
    }

    /** Current positions, #V x 3, borrowed from the mesh (empty for an empty owner). */
    Eigen::Map<const detail::positions_matrix> positions() const {
        return Eigen::Map<const detail::positions_matrix>(selfcol_mesh_positions(get()),
                                                          count(SELFCOL_MESH_VERTICES), 3);
    }
    /** Triangles as created, #F x 3, borrowed from the mesh. */
    Eigen::Map<const detail::triangles_matrix> triangles() const {
        return Eigen::Map<const detail::triangles_matrix>(selfcol_mesh_triangles(get()),
                                                          count(SELFCOL_MESH_TRIANGLES), 3);
    }
    /** selfcol_mesh_count() (0 for an empty owner). */
    Eigen::Index count(selfcol_mesh_quantity quantity) const {
        return static_cast<Eigen::Index>(selfcol_mesh_count(get(), quantity));
    }
    /** Mean length of the unique edges: the scale of the default distance. */
    double mean_edge_length() const {
        return selfcol_mesh_mean_edge_length(get());
    }

  private:
    std::unique_ptr<selfcol_mesh, detail::mesh_deleter> handle_;
};

/** Owner of a selfcol_hierarchy over a mesh, which it borrows. */
class hierarchy {
  public:
    /** An empty owner. */
    hierarchy() noexcept {}
    /**
     * Builds the hierarchy over m (selfcol_hierarchy_create()). m must outlive
     * every use of the hierarchy but its destruction.
     * @throws error SELFCOL_EINVAL (an empty mesh owner); SELFCOL_ERANGE; SELFCOL_ENOMEM.
     */
    explicit hierarchy(const mesh &m, const selfcol_hierarchy_options *options = nullptr) {
        selfcol_hierarchy *h = nullptr;
        detail::check_options(selfcol_hierarchy_create(&h, m.get(), options),
                              "selfcol_hierarchy_create", options, selfcol_hierarchy_options_check);
        handle_.reset(h);
    }
    /** A hierarchy borrows its mesh: never one about to be destroyed. */
    explicit hierarchy(const mesh &&, const selfcol_hierarchy_options * = nullptr) = delete;
    /** Takes ownership of a hierarchy made with the C API. */
    explicit hierarchy(selfcol_hierarchy *owned) noexcept : handle_(owned) {}
    hierarchy(hierarchy &&) noexcept = default;
    hierarchy &operator=(hierarchy &&) noexcept = default;
    hierarchy(const hierarchy &) = delete;
    hierarchy &operator=(const hierarchy &) = delete;

    selfcol_hierarchy *get() const noexcept {
        return handle_.get();
    }
    selfcol_hierarchy *release() noexcept {
        return handle_.release();
    }
    explicit operator bool() const noexcept {
        return handle_ != nullptr;
    }
    /** Follows the mesh's current positions (selfcol_hierarchy_refit()). @throws error */
    void refit() {
        detail::check(selfcol_hierarchy_refit(handle_.get()), "selfcol_hierarchy_refit");
    }

  private:
    std::unique_ptr<selfcol_hierarchy, detail::hierarchy_deleter> handle_;
};

/** Owner of a selfcol_contacts, the buffer a query fills (reused across frames). */
class contacts {
  public:
    /** Creates an empty contact set (selfcol_contacts_create()). @throws error SELFCOL_ENOMEM */
    contacts() {
        create(nullptr);
    }
    /** The same, with options (an allocator). @throws error */
    explicit contacts(const selfcol_contacts_options &options) {
        create(&options);
    }
    /** Takes ownership of a contact set made with the C API. */
    explicit contacts(selfcol_contacts *owned) noexcept : handle_(owned) {}
    contacts(contacts &&) noexcept = default;
    contacts &operator=(contacts &&) noexcept = default;
    contacts(const contacts &) = delete;
    contacts &operator=(const contacts &) = delete;

    selfcol_contacts *get() const noexcept {
        return handle_.get();
    }
    selfcol_contacts *release() noexcept {
        return handle_.release();
    }
    explicit operator bool() const noexcept {
        return handle_ != nullptr;
    }
    /** Number of records (0 for an empty owner). */
    std::size_t size() const noexcept {
        return selfcol_contacts_count(handle_.get());
    }
    /** The records, sorted as contacts.h says; borrowed until the next query. */
    const selfcol_contact *data() const {
        const selfcol_contact *records = nullptr;
        std::size_t count = 0;
        detail::check(selfcol_contacts_data(handle_.get(), &records, &count),
                      "selfcol_contacts_data");
        return records;
    }
    /** Counters and timings of the last query. @throws error */
    selfcol_query_stats stats() const {
        selfcol_query_stats s;
        s.version = SELFCOL_QUERY_STATS_VERSION;
        detail::check(selfcol_contacts_stats(handle_.get(), &s), "selfcol_contacts_stats");
        return s;
    }

  private:
    void create(const selfcol_contacts_options *options) {
        selfcol_contacts *c = nullptr;
        detail::check(selfcol_contacts_create(&c, options), "selfcol_contacts_create");
        handle_.reset(c);
    }
    std::unique_ptr<selfcol_contacts, detail::contacts_deleter> handle_;
};

/** Options of a query; the defaults are the C library's and the CLI's. */
struct query_options {
    /** Absolute detection distance d >= 0; negative (the default): d =
     *  distance_rel x mean edge length (of both meshes together, weighted by
     *  their edge counts, for a two-mesh query), as selfcol-cli does. */
    double distance = -1.0;
    /** d in mean edge lengths when distance is negative; 0.1 is a cloth's thickness. */
    double distance_rel = 0.1;
    /** Search method (hierarchy.h): EXACT by default. */
    selfcol_method method = SELFCOL_METHOD_EXACT;
    /** Narrow phase: the closed form by default. */
    selfcol_narrow narrow = SELFCOL_NARROW_CLOSED_FORM;
    /** SELFCOL_KIND_VF | SELFCOL_KIND_EE | SELFCOL_KIND_EF (all by default). */
    std::uint32_t kinds = SELFCOL_KIND_ALL;
    /** Threads the query may use (1..SELFCOL_MAX_THREADS): with more than one,
     *  the query runs on a selfcol_context of its own (started and joined
     *  within the call); same result for any count. */
    unsigned threads = 1;
};

/**
 * The contact sets of one query as Eigen matrices, one row per contact, in
 * the C library's order (contacts.h). Indices are into V and F (for a
 * two-mesh query, into the mesh the *_mesh column names: 0 the first, 1 the
 * second). Closest points: VF, the triangle's point is sum_k
 * VF_weights(i, k) V(F(t, k)); EE, edge a's point is EE_weights(i, 0)
 * V(a0) + EE_weights(i, 1) V(a1), edge b's uses columns 2 and 3; EF, the
 * crossing point is EF_weights(i, 0) V(e0) + EF_weights(i, 1) V(e1) on the
 * edge, sum_k EF_weights(i, 2 + k) V(F(t, k)) on the triangle. Directions
 * are unit vectors from the second primitive's closest point toward the
 * first's (contacts.h).
 */
struct contact_result {
    Eigen::MatrixXi VF;           /**< #VF x 2: vertex, triangle */
    Eigen::VectorXd VF_distance;  /**< #VF */
    Eigen::MatrixXd VF_weights;   /**< #VF x 3: on the triangle's corners F(t, 0..2) */
    Eigen::MatrixXd VF_direction; /**< #VF x 3 */
    Eigen::MatrixXi VF_mesh;      /**< #VF x 2: meshes of vertex and triangle (0 for self) */

    Eigen::MatrixXi EE;           /**< #EE x 4: a0, a1, b0, b1 (each edge's smaller vertex first) */
    Eigen::VectorXd EE_distance;  /**< #EE */
    Eigen::MatrixXd EE_weights;   /**< #EE x 4: on a0, a1, b0, b1 */
    Eigen::MatrixXd EE_direction; /**< #EE x 3 */
    Eigen::MatrixXi EE_mesh;      /**< #EE x 2: meshes of edges a and b */

    Eigen::MatrixXi EF;           /**< #EF x 3: e0, e1, triangle (edge e0 < e1 crosses it) */
    Eigen::MatrixXd EF_weights;   /**< #EF x 5: on e0, e1, then on F(t, 0..2) */
    Eigen::MatrixXd EF_direction; /**< #EF x 3: the triangle's unit normal */
    Eigen::MatrixXi EF_mesh;      /**< #EF x 2: meshes of edge and triangle */

    selfcol_query_stats stats; /**< counters and timings of the query */

    /** True when an edge crosses a triangle (the surface intersects). */
    bool intersects() const {
        return EF.rows() > 0;
    }
};

namespace detail {

inline double mean_edge(const selfcol_hierarchy *h) {
    return selfcol_mesh_mean_edge_length(selfcol_hierarchy_mesh(h));
}

// Mean edge length of two meshes together (weighted by their edge counts).
inline double mean_edge(const selfcol_hierarchy *a, const selfcol_hierarchy *b) {
    const selfcol_mesh *m[2] = {selfcol_hierarchy_mesh(a), selfcol_hierarchy_mesh(b)};
    double sum = 0.0, edges = 0.0;
    for (int i = 0; i < 2; ++i) {
        const double e = static_cast<double>(selfcol_mesh_count(m[i], SELFCOL_MESH_EDGES));
        sum += e * selfcol_mesh_mean_edge_length(m[i]);
        edges += e;
    }
    return edges > 0 ? sum / edges : 0.0;
}

inline selfcol_query_options c_options(const query_options &o, double mean_edge_length) {
    selfcol_query_options c;
    check(selfcol_query_options_init(&c, SELFCOL_QUERY_OPTIONS_VERSION),
          "selfcol_query_options_init");
    c.method = static_cast<std::uint32_t>(o.method);
    c.narrow = static_cast<std::uint32_t>(o.narrow);
    c.kinds = o.kinds;
    // NaN is not negative: it reaches the library, which refuses it.
    c.distance = o.distance < 0 ? o.distance_rel * mean_edge_length : o.distance;
    return c;
}

} // namespace detail

/**
 * Copies a filled contact set into Eigen matrices.
 * @throws error SELFCOL_EINVAL for an empty owner; SELFCOL_ERANGE for an index above INT_MAX.
 */
inline contact_result to_result(const contacts &c) {
    const selfcol_contact *records = nullptr;
    std::size_t count = 0;
    detail::check(selfcol_contacts_data(c.get(), &records, &count), "selfcol_contacts_data");
    Eigen::Index n[3] = {0, 0, 0};
    for (std::size_t i = 0; i < count; ++i)
        if (records[i].kind <= SELFCOL_CONTACT_EF)
            ++n[records[i].kind];
    contact_result r;
    r.VF.resize(n[0], 2);
    r.VF_distance.resize(n[0]);
    r.VF_weights.resize(n[0], 3);
    r.VF_direction.resize(n[0], 3);
    r.VF_mesh.resize(n[0], 2);
    r.EE.resize(n[1], 4);
    r.EE_distance.resize(n[1]);
    r.EE_weights.resize(n[1], 4);
    r.EE_direction.resize(n[1], 3);
    r.EE_mesh.resize(n[1], 2);
    r.EF.resize(n[2], 3);
    r.EF_weights.resize(n[2], 5);
    r.EF_direction.resize(n[2], 3);
    r.EF_mesh.resize(n[2], 2);
    Eigen::Index at[3] = {0, 0, 0};
    for (std::size_t i = 0; i < count; ++i) {
        const selfcol_contact &k = records[i];
        if (k.kind == SELFCOL_CONTACT_VF) {
            const Eigen::Index row = at[0]++;
            r.VF.row(row) << detail::to_int(k.first), detail::to_int(k.second);
            r.VF_distance(row) = k.distance;
            r.VF_weights.row(row) << k.wb[0], k.wb[1], k.wb[2];
            r.VF_direction.row(row) << k.direction[0], k.direction[1], k.direction[2];
            r.VF_mesh.row(row) << static_cast<int>(k.first_mesh), static_cast<int>(k.second_mesh);
        } else if (k.kind == SELFCOL_CONTACT_EE) {
            const Eigen::Index row = at[1]++;
            r.EE.row(row) << detail::to_int(k.a[0]), detail::to_int(k.a[1]), detail::to_int(k.b[0]),
                detail::to_int(k.b[1]);
            r.EE_distance(row) = k.distance;
            r.EE_weights.row(row) << k.wa[0], k.wa[1], k.wb[0], k.wb[1];
            r.EE_direction.row(row) << k.direction[0], k.direction[1], k.direction[2];
            r.EE_mesh.row(row) << static_cast<int>(k.first_mesh), static_cast<int>(k.second_mesh);
        } else if (k.kind == SELFCOL_CONTACT_EF) {
            const Eigen::Index row = at[2]++;
            r.EF.row(row) << detail::to_int(k.a[0]), detail::to_int(k.a[1]),
                detail::to_int(k.second);
            r.EF_weights.row(row) << k.wa[0], k.wa[1], k.wb[0], k.wb[1], k.wb[2];
            r.EF_direction.row(row) << k.direction[0], k.direction[1], k.direction[2];
            r.EF_mesh.row(row) << static_cast<int>(k.first_mesh), static_cast<int>(k.second_mesh);
        }
    }
    r.stats = c.stats();
    return r;
}

/**
 * Self-contacts of a hierarchy's mesh at its current positions, filling
 * buffer (reused across frames) and copying them out.
 * @throws error as selfcol_hierarchy_self_collide() returns (SELFCOL_EINVAL,
 *         SELFCOL_ESTALE, SELFCOL_ENOMEM, ...).
 */
inline contact_result self_collide(const hierarchy &h, contacts &buffer,
                                   const query_options &options = query_options()) {
    const selfcol_query_options o = detail::c_options(options, detail::mean_edge(h.get()));
    const detail::context_ptr context = detail::query_context(options.threads);
    detail::check_options(
        context ? selfcol_context_self_collide(context.get(), h.get(), buffer.get(), &o)
                : selfcol_hierarchy_self_collide(h.get(), buffer.get(), &o),
        "selfcol_hierarchy_self_collide", &o, selfcol_query_options_check);
    return to_result(buffer);
}

/** self_collide() with a contact set of its own. @throws error */
inline contact_result self_collide(const hierarchy &h,
                                   const query_options &options = query_options()) {
    contacts buffer;
    return self_collide(h, buffer, options);
}

/**
 * Contacts between two meshes (not the self-contacts of either): mesh 0 is
 * first's, mesh 1 is second's (the *_mesh columns).
 * @throws error as selfcol_hierarchy_collide() returns (SELFCOL_EINVAL for two
 *         hierarchies over one mesh, ...).
 */
inline contact_result collide(const hierarchy &first, const hierarchy &second, contacts &buffer,
                              const query_options &options = query_options()) {
    const selfcol_query_options o =
        detail::c_options(options, detail::mean_edge(first.get(), second.get()));
    const detail::context_ptr context = detail::query_context(options.threads);
    detail::check_options(
        context
            ? selfcol_context_collide(context.get(), first.get(), second.get(), buffer.get(), &o)
            : selfcol_hierarchy_collide(first.get(), second.get(), buffer.get(), &o),
        "selfcol_hierarchy_collide", &o, selfcol_query_options_check);
    return to_result(buffer);
}

/** collide() with a contact set of its own. @throws error */
inline contact_result collide(const hierarchy &first, const hierarchy &second,
                              const query_options &options = query_options()) {
    contacts buffer;
    return collide(first, second, buffer, options);
}

/** One-shot self query of (V, F): builds the mesh and hierarchy, queries, frees. @throws error */
template <class DV, class DF>
contact_result self_collide(const Eigen::MatrixBase<DV> &V, const Eigen::MatrixBase<DF> &F,
                            const query_options &options = query_options()) {
    const mesh m(V, F);
    const hierarchy h(m);
    return self_collide(h, options);
}

/** One-shot two-mesh query of (V1, F1) against (V2, F2). @throws error */
template <class DV1, class DF1, class DV2, class DF2>
contact_result collide(const Eigen::MatrixBase<DV1> &V1, const Eigen::MatrixBase<DF1> &F1,
                       const Eigen::MatrixBase<DV2> &V2, const Eigen::MatrixBase<DF2> &F2,
                       const query_options &options = query_options()) {
    const mesh m1(V1, F1), m2(V2, F2);
    const hierarchy h1(m1), h2(m2);
    return collide(h1, h2, options);
}

} // namespace selfcol

/** @} */

#endif /* SELFCOL_EIGEN_HPP */
