/* geom_csg.cpp: constructive solid geometry on GeomMesh (see geom_csg.h)
 * with CGAL's Polygon Mesh Processing: corefinement for the boolean
 * operations, clipping by a plane for trims, over a Surface_mesh whose
 * points are in the Exact_predicates_exact_constructions_kernel (interval
 * arithmetic first, exact rationals where the intervals cannot decide), so
 * coplanar and shared faces are no special case.
 *
 * The C boundary: every C++ exception (this file's own errors, CGAL's
 * failed preconditions and assertions, std::bad_alloc) is caught in the two
 * public functions and turned into a one-line error message appended to
 * the caller's Buf. Nothing here
 * is global or static and mutable but one lock: each call builds its own
 * meshes, and calls from renderers on different threads take turns (CGAL
 * is built without threads, below).
 *
 * Build (lib/meson.build): C++17 with -frounding-math, which CGAL asks of
 * gcc, and -ffp-contract=off, as the rest of the library.
 */

/* CGAL's interval arithmetic (the filter in front of its exact numbers)
 * normally switches the FPU to rounding upwards and relies on the hardware
 * to round each bound outwards. valgrind does not emulate rounding modes
 * other than to-nearest: under it the intervals come out too narrow, a
 * filter "decides" a sign that is really zero, and the corefinement of
 * coplanar faces fails CGAL's own assertions (seen in this file's test).
 * CGAL_ALWAYS_ROUND_TO_NEAREST, a documented CGAL mode, keeps the FPU
 * rounding to nearest and widens every bound by one ulp (nextafter)
 * instead: intervals that are right whatever runs the code, no change of
 * the FPU control word a host program could see, and an assertion, not a
 * wrong answer, should a host have set another rounding mode. The cost
 * falls where every predicate is a degenerate one (boxes with shared face
 * planes, whose exactly-zero determinants a point interval settled, a
 * widened one sends to the exact numbers) and shrinks as meshes grow
 * (bench/PROFILE.md, "lib/render/geometry/geom_csg.cpp: CGAL kept rounding
 * to nearest"). With it CGAL's start-up check that the compiler honours
 * the rounding mode (a throwing assertion in a static initializer of
 * every program linked with the library, which fails under valgrind) has
 * nothing to check, so it is left out as CGAL documents. */
#define CGAL_ALWAYS_ROUND_TO_NEAREST 1
#define CGAL_DISABLE_ROUNDING_MATH_CHECK 1

/* CGAL's headers are system headers, whose warnings gcc leaves out, but
 * gcc 12 still reports -Wmaybe-uninitialized from code of theirs inlined
 * here (an empty functor argument in PMP's self-intersection test): left
 * out for this file only. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "geom_csg.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/manifoldness.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iterator>
#include <new>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

/* CGAL is built without threads (lib/meson.build: CGAL_HAS_NO_THREADS):
 * its function statics, one of 32 KB among them, are then plain statics
 * instead of thread-locals, which would take more static TLS than a
 * library loaded with dlopen may have (the Python module). So that
 * renderers on different threads stay safe, every call into this unit
 * holds one process-wide lock (csg_lock) while CGAL runs. */
#ifdef CGAL_HAS_THREADS
#error "CGAL_HAS_THREADS is defined: build this unit with CGAL_HAS_NO_THREADS (lib/meson.build)"
#endif
#include <mutex>

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Vertex = Mesh::Vertex_index;

/* This file's own errors, carrying the message for the caller. */
struct CsgError : std::runtime_error {
    explicit CsgError(const std::string &m) : std::runtime_error(m) {}
};

std::string mesh_name(size_t k, size_t n)
{
    return "mesh " + std::to_string(k + 1) + " of " + std::to_string(n);
}

/* A position as a welding key: -0 and +0 are one position. */
struct Key {
    double x[3];
    bool operator==(const Key &o) const { return x[0] == o.x[0] && x[1] == o.x[1] && x[2] == o.x[2]; }
};

struct KeyHash {
    size_t operator()(const Key &k) const
    {
        uint64_t h = 0;
        for (double d : k.x) {
            uint64_t b;
            std::memcpy(&b, &d, sizeof b);
            h ^= b + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
            h ^= h >> 31;
            h *= 0xbf58476d1ce4e5b9ULL;
        }
        return (size_t)(h ^ (h >> 29));
    }
};

/* Input [k] of [n] as a checked CGAL mesh: indices in range, positions
 * finite, exactly equal positions welded (triangles left with two equal
 * corners dropped), then a manifold, closed surface without
 * self-intersections that bounds a volume, wound outwards. No triangles: the empty solid
 * (an empty mesh). Throws CsgError naming the input. */
Mesh to_cgal(const GeomMesh *m, size_t k, size_t n)
{
    const std::string name = mesh_name(k, n);
    if (!m) throw CsgError(name + " is missing");
    if (m->ntri && (!m->tri || !m->pos)) throw CsgError(name + " has triangles but no arrays");
    for (size_t i = 0; i < (size_t)m->ntri * 3; i++)
        if (m->tri[i] >= m->npos) throw CsgError(name + " has a triangle index out of range");
    Mesh sm;
    std::vector<Vertex> vmap(m->npos, Mesh::null_vertex());
    std::unordered_map<Key, Vertex, KeyHash> welded;
    auto vertex = [&](uint32_t i) {
        if (vmap[i] != Mesh::null_vertex()) return vmap[i];
        const double *p = m->pos + (size_t)i * 3;
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            throw CsgError(name + " has a position that is not finite");
        Key key{{p[0] == 0 ? 0.0 : p[0], p[1] == 0 ? 0.0 : p[1], p[2] == 0 ? 0.0 : p[2]}};
        auto it = welded.find(key);
        Vertex v = it != welded.end() ? it->second : sm.add_vertex(Point(key.x[0], key.x[1], key.x[2]));
        if (it == welded.end()) welded.emplace(key, v);
        return vmap[i] = v;
    };
    for (uint32_t t = 0; t < m->ntri; t++) {
        const uint32_t *c = m->tri + (size_t)t * 3;
        Vertex a = vertex(c[0]), b = vertex(c[1]), d = vertex(c[2]);
        if (a == b || b == d || a == d) continue;
        if (sm.add_face(a, b, d) == Mesh::null_face())
            throw CsgError(name + " is not a manifold surface");
    }
    if (sm.number_of_faces() == 0) return Mesh();
    if (!CGAL::is_closed(sm)) throw CsgError(name + " is not closed");
    /* solids that touch at a corner: closed, but CGAL's algorithms need
     * one fan of triangles about each vertex */
    std::vector<Mesh::Halfedge_index> cones;
    PMP::non_manifold_vertices(sm, std::back_inserter(cones));
    if (!cones.empty()) throw CsgError(name + " is not a manifold surface");
    /* a boolean's result rounded to doubles may cross itself by a rounding
     * error where slivers meet: refined where it crosses (the input of a
     * trim of a union, in Flitter's examples/solidgeometry.fl) */
    if (PMP::does_self_intersect(sm) &&
        (!PMP::experimental::autorefine_and_remove_self_intersections(sm) || !CGAL::is_closed(sm) ||
         PMP::does_self_intersect(sm)))
        throw CsgError(name + " intersects itself");
    if (!PMP::does_bound_a_volume(sm)) throw CsgError(name + " is not a volume");
    /* CGAL takes a mesh wound inwards as the bounded side of the space
     * outside it; here it is a mistake */
    if (!PMP::is_outward_oriented(sm)) throw CsgError(name + " is inside out");
    return sm;
}

/* The output arrays, freed unless handed over. */
struct OutMesh {
    GeomMesh m{};
    ~OutMesh() { std::free(m.pos), std::free(m.tri); }
    GeomMesh release()
    {
        GeomMesh r = m;
        m = GeomMesh{};
        return r;
    }
};

/* [sm] as a GeomMesh of doubles (each exact coordinate rounded to the
 * nearest double), triangulated, only the vertices its faces use. */
GeomMesh to_geom(Mesh &sm)
{
    if (!CGAL::is_triangle_mesh(sm) && !PMP::triangulate_faces(sm))
        throw CsgError("boolean operation failed");
    if (sm.has_garbage()) sm.collect_garbage();
    OutMesh out;
    if (sm.number_of_faces() == 0) return out.release();
    if (sm.number_of_vertices() >= UINT32_MAX || sm.number_of_faces() >= UINT32_MAX / 3)
        throw CsgError("the result has too many triangles");
    size_t nv = sm.number_of_vertices(), nf = sm.number_of_faces();
    out.m.pos = static_cast<double *>(std::malloc(nv * 3 * sizeof(double)));
    out.m.tri = static_cast<uint32_t *>(std::malloc(nf * 3 * sizeof(uint32_t)));
    if (!out.m.pos || !out.m.tri) throw std::bad_alloc();
    std::vector<uint32_t> index(nv, UINT32_MAX);
    for (Mesh::Face_index f : sm.faces()) {
        uint32_t *t = out.m.tri + (size_t)out.m.ntri * 3;
        int c = 0;
        for (Vertex v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
            uint32_t &i = index[(size_t)v];
            if (i == UINT32_MAX) {
                const Point &p = sm.point(v);
                double *q = out.m.pos + (size_t)out.m.npos * 3;
                q[0] = CGAL::to_double(p.x());
                q[1] = CGAL::to_double(p.y());
                q[2] = CGAL::to_double(p.z());
                i = out.m.npos++;
            }
            t[c++] = i;
        }
        out.m.ntri++;
    }
    return out.release();
}

/* [a] op [b] into [a]; either may be empty (the empty solid). CGAL's
 * corefinement refines both inputs in place. */
void combine(GeomBoolOp op, Mesh &a, Mesh &b)
{
    bool ea = a.number_of_faces() == 0, eb = b.number_of_faces() == 0;
    if (ea || eb) {
        if (op == GEOM_UNION && ea) a = std::move(b);
        else if (op == GEOM_INTERSECT) a = Mesh();
        /* difference: empty less anything is empty; less nothing is a */
        return;
    }
    Mesh r;
    bool ok = op == GEOM_UNION       ? PMP::corefine_and_compute_union(a, b, r)
              : op == GEOM_INTERSECT ? PMP::corefine_and_compute_intersection(a, b, r)
                                     : PMP::corefine_and_compute_difference(a, b, r);
    if (!ok) throw CsgError("boolean operation failed");
    a = std::move(r);
}

/* [what] of an exception as one line. */
std::string one_line(const char *what)
{
    std::string s = what ? what : "";
    for (char &ch : s)
        if (ch == '\n' || ch == '\r') ch = ' ';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

/* Append [msg] as one line to [err] (may be NULL). */
void set_error(Buf *err, const std::string &msg)
{
    if (err) buf_printf(err, "%s\n", msg.c_str());
}

/* The lock every call holds while CGAL runs (see CGAL_HAS_NO_THREADS above). */
std::mutex &csg_lock()
{
    static std::mutex lock;
    return lock;
}

/* Run [body] (which fills [out]) under the lock, with every exception
 * turned into -1 and its message appended to [err], [out] zeroed. */
template <class F> int guarded(GeomMesh *out, Buf *err, F body)
{
    std::lock_guard<std::mutex> hold(csg_lock());
    try {
        body();
        return 0;
    } catch (const CsgError &e) {
        set_error(err, e.what());
    } catch (const std::bad_alloc &) {
        set_error(err, "out of memory");
    } catch (const std::exception &e) {
        /* CGAL's failed preconditions and assertions (CGAL::Failure_exception):
         * several lines naming the expression, file and line */
        set_error(err, "boolean operation failed: " + one_line(e.what()));
    } catch (...) {
        set_error(err, "boolean operation failed");
    }
    if (out) *out = GeomMesh{};
    return -1;
}

} // namespace

extern "C" int geom_csg_boolean(GeomBoolOp op, const GeomMesh *const *in, size_t n, GeomMesh *out,
                                volatile int *interrupt, Buf *err)
{
    if (out) *out = GeomMesh{};
    return guarded(out, err, [&] {
        if (!out) throw CsgError("no output mesh");
        if (op != GEOM_UNION && op != GEOM_INTERSECT && op != GEOM_DIFFERENCE)
            throw CsgError("unknown boolean operation");
        if (n == 0 || !in) throw CsgError("no meshes");
        /* every input checked first, so an error names the input whatever
         * the operations before it would have made */
        std::vector<Mesh> meshes;
        meshes.reserve(n);
        for (size_t k = 0; k < n; k++) meshes.push_back(to_cgal(in[k], k, n));
        for (size_t k = 1; k < n; k++) {
            if (interrupt && *interrupt) throw CsgError("interrupted");
            combine(op, meshes[0], meshes[k]);
            meshes[k] = Mesh();
        }
        if (interrupt && *interrupt) throw CsgError("interrupted");
        *out = to_geom(meshes[0]);
    });
}

extern "C" int geom_csg_trim(const GeomMesh *in, const double origin[3], const double normal[3], GeomMesh *out,
                             Buf *err)
{
    if (out) *out = GeomMesh{};
    return guarded(out, err, [&] {
        if (!out) throw CsgError("no output mesh");
        if (!origin || !normal) throw CsgError("no trim plane");
        for (int k = 0; k < 3; k++)
            if (!std::isfinite(origin[k]) || !std::isfinite(normal[k]))
                throw CsgError("the trim plane is not finite");
        if (normal[0] == 0 && normal[1] == 0 && normal[2] == 0) throw CsgError("the trim normal is zero");
        Mesh sm = to_cgal(in, 0, 1);
        if (sm.number_of_faces() > 0) {
            Kernel::Plane_3 plane(Point(origin[0], origin[1], origin[2]),
                                  Kernel::Vector_3(normal[0], normal[1], normal[2]));
            /* keeps the negative side, the one opposite the normal; the
             * volume is closed with the cap */
            if (!PMP::clip(sm, plane, CGAL::parameters::clip_volume(true)))
                throw CsgError("boolean operation failed");
        }
        *out = to_geom(sm);
    });
}

extern "C" int geom_csg_hull(const double *xyz, size_t n, GeomMesh *out, Buf *err)
{
    if (out) *out = GeomMesh{};
    return guarded(out, err, [&] {
        if (!out) throw CsgError("no output mesh");
        if (n < 4 || !xyz) throw CsgError("fewer than 4 vertices have no hull with a volume");
        /* the hull's corners are input points: exact predicates decide
         * which, and nothing is constructed */
        using HullPoint = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
        std::vector<HullPoint> points;
        points.reserve(n);
        for (size_t i = 0; i < n; i++) {
            const double *p = xyz + i * 3;
            if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
                throw CsgError("a vertex is not finite");
            points.emplace_back(p[0], p[1], p[2]);
        }
        CGAL::Surface_mesh<HullPoint> hull;
        CGAL::convex_hull_3(points.begin(), points.end(), hull);
        if (hull.number_of_faces() < 4 || !CGAL::is_closed(hull) || !CGAL::is_triangle_mesh(hull))
            throw CsgError("the vertices lie in one plane: their hull has no volume");
        if (hull.has_garbage()) hull.collect_garbage();
        size_t nv = hull.number_of_vertices(), nf = hull.number_of_faces();
        OutMesh r;
        r.m.pos = static_cast<double *>(std::malloc(nv * 3 * sizeof(double)));
        r.m.tri = static_cast<uint32_t *>(std::malloc(nf * 3 * sizeof(uint32_t)));
        if (!r.m.pos || !r.m.tri) throw std::bad_alloc();
        for (auto v : hull.vertices()) {
            const HullPoint &p = hull.point(v);
            double *q = r.m.pos + (size_t)v * 3;
            q[0] = p.x(), q[1] = p.y(), q[2] = p.z();
        }
        r.m.npos = (uint32_t)nv;
        for (auto f : hull.faces()) {
            uint32_t *t = r.m.tri + (size_t)r.m.ntri * 3;
            int c = 0;
            for (auto v : CGAL::vertices_around_face(hull.halfedge(f), hull)) t[c++] = (uint32_t)(size_t)v;
            r.m.ntri++;
        }
        *out = r.release();
    });
}
