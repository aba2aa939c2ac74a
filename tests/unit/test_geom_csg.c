/* test_geom_csg.c: constructive solid geometry through CGAL
 * (lib/render/geometry/geom_csg.h) against values computed by hand.
 *
 * Boxes: overlapping, touching and slotted axis-aligned boxes, whose
 * results are boxes again, so volume, area and bounds are exact (to 1e-9)
 * and every result position is one of the input coordinates. Spheres: an
 * icosphere of radius 1 (the icosahedron subdivided, each new vertex pushed
 * out to the sphere), closed and exactly mirror-symmetric in x, y and z
 * (negation commutes with every rounding of its construction). Where the
 * sphere lies wholly inside the box, results are exact sums of the two
 * meshes' volumes and areas; where a box or plane cuts it, the mesh part
 * lies between the same cut of the inscribed ball (radius r_in, the
 * smallest distance from the centre to a face plane) and of the
 * circumscribed one (radius 1), both computed analytically; that is the
 * tessellation-error bound used. Trims by a plane through the centre of a
 * centrally symmetric solid (cube, icosphere) keep exactly half.
 *
 * GEOM_CSG_TIMES=1 prints each operation's time.
 */
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <cmocka.h>

#include "buf.h"
#include "geom_csg.h"
#include "geom_mesh.h"

#define EPS 1e-9

/* [err] holds exactly the line [msg] (a string literal) and its newline;
 * it is emptied for the next call. */
#define assert_error(err, msg) (assert_string_equal(buf_cstr(err), msg "\n"), buf_reset(err))

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

static void report(const char *what, double t0)
{
    if (getenv("GEOM_CSG_TIMES")) print_message("%-40s %8.2f ms\n", what, now_ms() - t0);
}

/* {===== meshes built here */

/* An axis-aligned box, triangles counter-clockwise seen from outside. With
 * [split], each face has its own four corners (24 positions, each corner
 * repeated three times), as primitives give them. */
static GeomMesh box(double x0, double y0, double z0, double x1, double y1, double z1, int split)
{
    /* corner i: x from bit 0, y from bit 1, z from bit 2; each face's
     * corners counter-clockwise seen from outside */
    static const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    GeomMesh m = {0};
    uint32_t pc = 0, tc = 0, idx[8];
    if (!split)
        for (int i = 0; i < 8; i++)
            idx[i] = geom_mesh_add_pos(&m, &pc, i & 1 ? x1 : x0, i & 2 ? y1 : y0, i & 4 ? z1 : z0);
    for (int f = 0; f < 6; f++) {
        uint32_t q[4];
        for (int k = 0; k < 4; k++) {
            int i = faces[f][k];
            q[k] = split ? geom_mesh_add_pos(&m, &pc, i & 1 ? x1 : x0, i & 2 ? y1 : y0, i & 4 ? z1 : z0) : idx[i];
        }
        geom_mesh_add_tri(&m, &tc, q[0], q[1], q[2]);
        geom_mesh_add_tri(&m, &tc, q[0], q[2], q[3]);
    }
    return m;
}

/* [src]'s triangles appended to [dst] (turned inside out with [flip]). */
static void append(GeomMesh *dst, const GeomMesh *src, int flip)
{
    uint32_t pc = dst->npos, tc = dst->ntri, base = dst->npos;
    for (uint32_t i = 0; i < src->npos; i++)
        geom_mesh_add_pos(dst, &pc, src->pos[i * 3], src->pos[i * 3 + 1], src->pos[i * 3 + 2]);
    for (uint32_t t = 0; t < src->ntri; t++) {
        const uint32_t *c = src->tri + t * 3;
        geom_mesh_add_tri(dst, &tc, base + c[0], base + (flip ? c[2] : c[1]), base + (flip ? c[1] : c[2]));
    }
}

typedef struct EdgeMid {
    uint32_t a, b, mid;
} EdgeMid;

/* The vertex halfway along edge a-b pushed out to radius [r] (made once
 * per edge, so that neighbouring triangles share it). */
static uint32_t midpoint(GeomMesh *m, uint32_t *pc, EdgeMid *cache, size_t *ncache, uint32_t a, uint32_t b,
                         double r)
{
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    for (size_t i = 0; i < *ncache; i++)
        if (cache[i].a == lo && cache[i].b == hi) return cache[i].mid;
    double p[3];
    for (int k = 0; k < 3; k++) p[k] = (m->pos[(size_t)lo * 3 + k] + m->pos[(size_t)hi * 3 + k]) / 2;
    double len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    uint32_t v = geom_mesh_add_pos(m, pc, p[0] / len * r, p[1] / len * r, p[2] / len * r);
    cache[(*ncache)++] = (EdgeMid){lo, hi, v};
    return v;
}

/* An icosphere of radius [r] about the origin, [levels] times subdivided
 * (20 * 4^levels triangles). The icosahedron: the 12 points (0, +-1,
 * +-phi) and their cyclic permutations; its faces are the triples of
 * points at pairwise distance 2, turned to face outwards. */
static GeomMesh icosphere(double r, int levels)
{
    const double phi = (1 + sqrt(5)) / 2, s = r / sqrt(1 + phi * phi);
    GeomMesh m = {0};
    uint32_t pc = 0, tc = 0;
    for (int axis = 0; axis < 3; axis++)
        for (int i = 0; i < 4; i++) {
            double c[3] = {0, 0, 0};
            c[(axis + 1) % 3] = i & 1 ? -s : s;
            c[(axis + 2) % 3] = i & 2 ? -phi * s : phi * s;
            geom_mesh_add_pos(&m, &pc, c[0], c[1], c[2]);
        }
    const double edge2 = 4 * s * s;
    for (uint32_t a = 0; a < 12; a++)
        for (uint32_t b = a + 1; b < 12; b++)
            for (uint32_t c = b + 1; c < 12; c++) {
                const double *pa = m.pos + a * 3, *pb = m.pos + b * 3, *pd = m.pos + c * 3;
                double dab = 0, dbc = 0, dca = 0;
                for (int k = 0; k < 3; k++) {
                    dab += (pa[k] - pb[k]) * (pa[k] - pb[k]);
                    dbc += (pb[k] - pd[k]) * (pb[k] - pd[k]);
                    dca += (pd[k] - pa[k]) * (pd[k] - pa[k]);
                }
                if (fabs(dab - edge2) > 1e-9 || fabs(dbc - edge2) > 1e-9 || fabs(dca - edge2) > 1e-9) continue;
                double u[3], w[3];
                for (int k = 0; k < 3; k++) u[k] = pb[k] - pa[k], w[k] = pd[k] - pa[k];
                double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
                if (n[0] * pa[0] + n[1] * pa[1] + n[2] * pa[2] > 0) geom_mesh_add_tri(&m, &tc, a, b, c);
                else geom_mesh_add_tri(&m, &tc, a, c, b);
            }
    assert_int_equal(m.ntri, 20);
    for (int l = 0; l < levels; l++) {
        GeomMesh next = {0};
        uint32_t npc = 0, ntc = 0;
        for (uint32_t i = 0; i < m.npos; i++)
            geom_mesh_add_pos(&next, &npc, m.pos[i * 3], m.pos[i * 3 + 1], m.pos[i * 3 + 2]);
        EdgeMid *cache = malloc(sizeof *cache * m.ntri * 3);
        size_t ncache = 0;
        for (uint32_t t = 0; t < m.ntri; t++) {
            uint32_t a = m.tri[t * 3], b = m.tri[t * 3 + 1], c = m.tri[t * 3 + 2];
            uint32_t ab = midpoint(&next, &npc, cache, &ncache, a, b, r);
            uint32_t bc = midpoint(&next, &npc, cache, &ncache, b, c, r);
            uint32_t ca = midpoint(&next, &npc, cache, &ncache, c, a, r);
            geom_mesh_add_tri(&next, &ntc, a, ab, ca);
            geom_mesh_add_tri(&next, &ntc, ab, b, bc);
            geom_mesh_add_tri(&next, &ntc, ca, bc, c);
            geom_mesh_add_tri(&next, &ntc, ab, bc, ca);
        }
        free(cache);
        geom_mesh_free(&m);
        m = next;
    }
    return m;
}

/* The smallest distance from the origin to the plane of a triangle of [m]. */
static double inradius(const GeomMesh *m)
{
    double best = INFINITY;
    for (uint32_t t = 0; t < m->ntri; t++) {
        const double *a = m->pos + m->tri[t * 3] * 3, *b = m->pos + m->tri[t * 3 + 1] * 3,
                     *c = m->pos + m->tri[t * 3 + 2] * 3;
        double u[3], w[3];
        for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], w[k] = c[k] - a[k];
        double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        double d = (n[0] * a[0] + n[1] * a[1] + n[2] * a[2]) / sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (d < best) best = d;
    }
    return best;
}

/* The volume of the cap of a ball of radius R beyond a plane at distance
 * h < R from its centre: pi (R - h)^2 (2R + h) / 3. */
static double cap_volume(double R, double h)
{
    return M_PI * (R - h) * (R - h) * (2 * R + h) / 3;
}

/* }===== */

/* Closed, wound outwards (positive volume), and [vol], [area] to [eps]. */
static void check_solid(const GeomMesh *m, double vol, double area, double eps)
{
    assert_true(m->ntri > 0);
    assert_null(m->uv);
    assert_null(m->normal);
    assert_true(geom_mesh_is_closed(m));
    double v = geom_mesh_volume(m), a = geom_mesh_area(m);
    assert_true(v > 0);
    if (fabs(v - vol) > eps || fabs(a - area) > eps)
        fail_msg("volume %.17g (expected %.17g), area %.17g (expected %.17g)", v, vol, a, area);
}

static void check_bounds(const GeomMesh *m, double x0, double y0, double z0, double x1, double y1, double z1)
{
    double b[6], want[6] = {x0, y0, z0, x1, y1, z1};
    geom_mesh_bounds(m, b);
    for (int k = 0; k < 6; k++)
        if (fabs(b[k] - want[k]) > EPS) fail_msg("bound %d is %.17g, expected %.17g", k, b[k], want[k]);
}

/* Every coordinate [axis] of [m] (all three for axis 3) is exactly one of
 * [vals] (no rounding crept in). Results of boxes keep the vertices where
 * one box's faces cross the other's triangles' diagonals (x = 0.5 crosses
 * the diagonal z = x / 3 of a face of [0,3]x[0,1]^2 at z = 1/6), so their
 * y and z can be other values; their x are the planes of the boxes' faces. */
static void check_coords(const GeomMesh *m, int axis, const double *vals, int nvals)
{
    for (size_t i = 0; i < (size_t)m->npos * 3; i++) {
        if (axis < 3 && (int)(i % 3) != axis) continue;
        int found = 0;
        for (int k = 0; k < nvals; k++) found |= m->pos[i] == vals[k];
        if (!found) fail_msg("coordinate %.17g is not one of the inputs'", m->pos[i]);
    }
}

static int run(GeomBoolOp op, GeomMesh *a, GeomMesh *b, GeomMesh *out, const char *what)
{
    const GeomMesh *in[2] = {a, b};
    Buf err = BUF_INIT;
    double t0 = now_ms();
    int rc = geom_csg_boolean(op, in, 2, out, NULL, &err);
    report(what, t0);
    if (rc != 0) fail_msg("%s: %s", what, buf_line(&err));
    buf_free(&err);
    return rc;
}

/* {===== boxes */

/* [0,1]^3 and the same shifted 0.5 in x share the planes y = 0, y = 1,
 * z = 0, z = 1. Union: [0,1.5]x[0,1]x[0,1], volume 1.5, area
 * 2(1.5 + 1.5 + 1) = 8; intersection: [0.5,1]x[0,1]x[0,1], volume 0.5, area
 * 2(0.5 + 0.5 + 1) = 4; difference: [0,0.5]x[0,1]x[0,1], the same. */
static void two_boxes(void **st)
{
    (void)st;
    const double coords[] = {0, 0.5, 1, 1.5};
    for (int split = 0; split < 2; split++) {
        GeomMesh a = box(0, 0, 0, 1, 1, 1, split), b = box(0.5, 0, 0, 1.5, 1, 1, split), out;
        run(GEOM_UNION, &a, &b, &out, split ? "union of two boxes (unwelded)" : "union of two boxes");
        check_solid(&out, 1.5, 8, EPS);
        check_bounds(&out, 0, 0, 0, 1.5, 1, 1);
        check_coords(&out, 0, coords, 4);
        geom_mesh_free(&out);
        run(GEOM_INTERSECT, &a, &b, &out, "intersection of two boxes");
        check_solid(&out, 0.5, 4, EPS);
        check_bounds(&out, 0.5, 0, 0, 1, 1, 1);
        check_coords(&out, 0, coords, 4);
        geom_mesh_free(&out);
        run(GEOM_DIFFERENCE, &a, &b, &out, "difference of two boxes");
        check_solid(&out, 0.5, 4, EPS);
        check_bounds(&out, 0, 0, 0, 0.5, 1, 1);
        check_coords(&out, 0, coords, 4);
        geom_mesh_free(&out);
        /* the other way round: [1,1.5]x[0,1]x[0,1] */
        run(GEOM_DIFFERENCE, &b, &a, &out, "difference of two boxes, reversed");
        check_solid(&out, 0.5, 4, EPS);
        check_bounds(&out, 1, 0, 0, 1.5, 1, 1);
        geom_mesh_free(&out);
        geom_mesh_free(&a);
        geom_mesh_free(&b);
    }
}

/* Three operands at once. Boxes [0,1], [1,2], [2,3] in x (times [0,1]^2)
 * touching face to face: union [0,3]x[0,1]x[0,1], volume 3, area
 * 2(3 + 3 + 1) = 14. [0,3]x[0,1]^2 less two slots [0.5,1] and [2,2.5]
 * (reaching past it in y and z): boxes of length 0.5, 1, 0.5, volume 2, area
 * 4 + 6 + 4 = 14. [0,3]x[0,1]^2, the first slot and [0.75,5]x[0,0.5]x[0,1]
 * intersected: [0.75,1]x[0,0.5]x[0,1], volume 0.125, area
 * 2(0.125 + 0.25 + 0.5) = 1.75. */
static void three_boxes(void **st)
{
    (void)st;
    Buf err = BUF_INIT;
    GeomMesh b0 = box(0, 0, 0, 1, 1, 1, 1), b1 = box(1, 0, 0, 2, 1, 1, 1), b2 = box(2, 0, 0, 3, 1, 1, 1), out;
    const GeomMesh *row[3] = {&b0, &b1, &b2};
    double t0 = now_ms();
    assert_int_equal(geom_csg_boolean(GEOM_UNION, row, 3, &out, NULL, &err), 0);
    report("union of three touching boxes", t0);
    check_solid(&out, 3, 14, EPS);
    check_bounds(&out, 0, 0, 0, 3, 1, 1);
    geom_mesh_free(&out);

    GeomMesh bar = box(0, 0, 0, 3, 1, 1, 0), slot1 = box(0.5, -1, -1, 1, 2, 2, 0), slot2 = box(2, -1, -1, 2.5, 2, 2, 0);
    const GeomMesh *cut[3] = {&bar, &slot1, &slot2};
    t0 = now_ms();
    assert_int_equal(geom_csg_boolean(GEOM_DIFFERENCE, cut, 3, &out, NULL, &err), 0);
    report("bar less two slots", t0);
    check_solid(&out, 2, 14, EPS);
    check_bounds(&out, 0, 0, 0, 3, 1, 1);
    const double coords[] = {0, 0.5, 1, 2, 2.5, 3};
    check_coords(&out, 0, coords, 6);
    geom_mesh_free(&out);

    GeomMesh corner = box(0.75, 0, 0, 5, 0.5, 1, 0);
    const GeomMesh *common[3] = {&bar, &slot1, &corner};
    t0 = now_ms();
    assert_int_equal(geom_csg_boolean(GEOM_INTERSECT, common, 3, &out, NULL, &err), 0);
    report("intersection of three boxes", t0);
    check_solid(&out, 0.125, 1.75, EPS);
    check_bounds(&out, 0.75, 0, 0, 1, 0.5, 1);
    geom_mesh_free(&out);
    GeomMesh *all[] = {&b0, &b1, &b2, &bar, &slot1, &slot2, &corner};
    for (size_t i = 0; i < sizeof all / sizeof *all; i++) geom_mesh_free(all[i]);
    buf_free(&err);
}

/* }===== */

/* {===== a box and a sphere */

/* The sphere (radius 1) wholly inside the box [-2,2]^3: intersection is
 * the sphere mesh itself, difference the box with a sphere-shaped hole
 * (volume 64 - V, area 96 + A), union the box. */
static void sphere_inside_box(void **st)
{
    (void)st;
    GeomMesh s = icosphere(1, 3), b = box(-2, -2, -2, 2, 2, 2, 1), out;
    assert_true(geom_mesh_is_closed(&s));
    double vs = geom_mesh_volume(&s), as = geom_mesh_area(&s);
    /* the tessellation: between the inscribed and circumscribed balls */
    double rin = inradius(&s);
    assert_true(rin > 0.98 && rin < 1);
    assert_true(vs > 4 * M_PI * rin * rin * rin / 3 && vs < 4 * M_PI / 3);

    run(GEOM_INTERSECT, &b, &s, &out, "box and sphere inside: intersection");
    check_solid(&out, vs, as, EPS);
    assert_int_equal(out.ntri, s.ntri);
    assert_int_equal(out.npos, s.npos);
    geom_mesh_free(&out);
    run(GEOM_DIFFERENCE, &b, &s, &out, "box and sphere inside: difference");
    check_solid(&out, 64 - vs, 96 + as, EPS);
    check_bounds(&out, -2, -2, -2, 2, 2, 2);
    geom_mesh_free(&out);
    run(GEOM_UNION, &b, &s, &out, "box and sphere inside: union");
    check_solid(&out, 64, 96, EPS);
    geom_mesh_free(&out);
    /* the sphere less the box that holds it: nothing */
    run(GEOM_DIFFERENCE, &s, &b, &out, "sphere less the box around it");
    assert_int_equal(out.ntri, 0);
    geom_mesh_free(&out);
    geom_mesh_free(&s);
    geom_mesh_free(&b);
}

/* Two unit spheres with centres 1 apart (x = 0 and x = 1), against the
 * analytic values: the lens they share has volume pi (4r + d)(2r - d)^2 /
 * 12 = 5 pi / 12 and the area of two caps of height 1/2, 2 pi; their union
 * 8 pi / 3 - 5 pi / 12 = 9 pi / 4, area 6 pi; the first less the second
 * 4 pi / 3 - 5 pi / 12 = 11 pi / 12, area 4 pi (a cap off, the other's
 * cap in). The icospheres' corners lie on the spheres, each mesh short of
 * its sphere by dv in volume and da in area: every result is within twice
 * those; the lens and the union, inside the true ones, are smaller. */
static void two_spheres(void **st)
{
    (void)st;
    GeomMesh a = icosphere(1, 3), b = icosphere(1, 3), out;
    for (uint32_t i = 0; i < b.npos; i++) b.pos[(size_t)i * 3] += 1;
    double dv = 4 * M_PI / 3 - geom_mesh_volume(&a), da = 4 * M_PI - geom_mesh_area(&a);
    assert_true(dv > 0 && dv < 0.1 && da > 0 && da < 0.3);
    const struct {
        GeomBoolOp op;
        double v, a;
        const char *what;
    } cases[] = {
        {GEOM_INTERSECT, 5 * M_PI / 12, 2 * M_PI, "two spheres: intersection"},
        {GEOM_UNION, 9 * M_PI / 4, 6 * M_PI, "two spheres: union"},
        {GEOM_DIFFERENCE, 11 * M_PI / 12, 4 * M_PI, "two spheres: difference"},
    };
    for (size_t k = 0; k < 3; k++) {
        run(cases[k].op, &a, &b, &out, cases[k].what);
        double v = geom_mesh_volume(&out), ar = geom_mesh_area(&out);
        GeomMesh w;
        geom_mesh_copy(&out, &w);
        geom_mesh_weld(&w);
        assert_true(geom_mesh_is_closed(&w));
        geom_mesh_free(&w);
        if (fabs(v - cases[k].v) > 2 * dv || fabs(ar - cases[k].a) > 2 * da)
            fail_msg("%s: volume %.9g (analytic %.9g, within %.3g), area %.9g (analytic %.9g, within %.3g)",
                     cases[k].what, v, cases[k].v, 2 * dv, ar, cases[k].a, 2 * da);
        if (cases[k].op != GEOM_DIFFERENCE) assert_true(v < cases[k].v);
        geom_mesh_free(&out);
    }
    geom_mesh_free(&a);
    geom_mesh_free(&b);
}

/* The box [h,3]x[-3,3]^2 (h = 0.4) cuts a cap off the sphere: the mesh's
 * cap lies between the caps of the inscribed and circumscribed balls,
 * pi (R - h)^2 (2R + h) / 3 for R = r_in and R = 1 (0.6 % apart here).
 * Intersection and difference add up to the sphere mesh exactly, and the
 * union is box + sphere - intersection. */
static void sphere_cut_by_box(void **st)
{
    (void)st;
    const double h = 0.4;
    GeomMesh s = icosphere(1, 3), b = box(h, -3, -3, 3, 3, 3, 0), in, diff, uni;
    double vs = geom_mesh_volume(&s), rin = inradius(&s);
    run(GEOM_INTERSECT, &s, &b, &in, "sphere cut by a box: intersection");
    double vin = geom_mesh_volume(&in);
    assert_true(geom_mesh_is_closed(&in));
    if (!(vin > cap_volume(rin, h) && vin < cap_volume(1, h)))
        fail_msg("cap volume %.17g not within [%.17g, %.17g]", vin, cap_volume(rin, h), cap_volume(1, h));
    double bb[6];
    geom_mesh_bounds(&in, bb);
    assert_true(bb[0] == h && bb[3] == 1);   /* the cut, and the vertex (1, 0, 0) */
    run(GEOM_DIFFERENCE, &s, &b, &diff, "sphere cut by a box: difference");
    assert_true(geom_mesh_is_closed(&diff));
    double vdiff = geom_mesh_volume(&diff);
    assert_true(vdiff > 0);
    assert_true(fabs(vin + vdiff - vs) < EPS);
    /* the two parts share the cut disc: the areas add up to the sphere's
     * and twice the disc's */
    double a_disc = (geom_mesh_area(&in) + geom_mesh_area(&diff) - geom_mesh_area(&s)) / 2;
    assert_true(a_disc > M_PI * (rin * rin - h * h) && a_disc < M_PI * (1 - h * h));
    /* the union's surface: the box's, 2 (2.6 x 6 + 2.6 x 6 + 6 x 6) = 134.4,
     * less the disc, and the sphere's outside the box (the difference's
     * less the disc) */
    run(GEOM_UNION, &s, &b, &uni, "sphere cut by a box: union");
    check_solid(&uni, (3 - h) * 36 + vs - vin, 134.4 + geom_mesh_area(&diff) - 2 * a_disc, EPS);
    geom_mesh_free(&in);
    geom_mesh_free(&diff);
    geom_mesh_free(&uni);
    geom_mesh_free(&s);
    geom_mesh_free(&b);
}

/* }===== */

/* {===== trim */

static int trim(const GeomMesh *m, double ox, double oy, double oz, double nx, double ny, double nz, GeomMesh *out,
                const char *what)
{
    const double o[3] = {ox, oy, oz}, n[3] = {nx, ny, nz};
    Buf err = BUF_INIT;
    double t0 = now_ms();
    int rc = geom_csg_trim(m, o, n, out, &err);
    report(what, t0);
    if (rc != 0) fail_msg("%s: %s", what, buf_line(&err));
    buf_free(&err);
    return rc;
}

/* The cube [-0.5,0.5]^3 by planes through its centre: the half where
 * z <= 0, volume 0.5, area 1 + 4 x 0.5 + 1 (the cap) = 4; a normal of any
 * length; the upper half; a slanted plane (the cube's central symmetry
 * keeps half, 0.5). Planes that miss it keep all of it or nothing. */
static void trim_cube(void **st)
{
    (void)st;
    GeomMesh c = box(-0.5, -0.5, -0.5, 0.5, 0.5, 0.5, 1), out;
    trim(&c, 0, 0, 0, 0, 0, 1, &out, "trim cube by z = 0");
    check_solid(&out, 0.5, 4, EPS);
    check_bounds(&out, -0.5, -0.5, -0.5, 0.5, 0.5, 0);
    geom_mesh_free(&out);
    trim(&c, 0, 0, 0, 0, 0, 7, &out, "trim cube, long normal");
    check_solid(&out, 0.5, 4, EPS);
    check_bounds(&out, -0.5, -0.5, -0.5, 0.5, 0.5, 0);
    geom_mesh_free(&out);
    trim(&c, 0, 0, 0, 0, 0, -1, &out, "trim cube, normal down");
    check_solid(&out, 0.5, 4, EPS);
    check_bounds(&out, -0.5, -0.5, 0, 0.5, 0.5, 0.5);
    geom_mesh_free(&out);
    /* x + y + z <= 0.25 through (0.25, 0, 0): the corner cut off is the
     * tetrahedron x + y + z >= 0.25 of the cube: with u = x + 0.5 etc., the
     * corner u, v, w <= 1 where u + v + w >= 1.75, i.e. the simplex of
     * side 1.25 less the three corners of side 0.25 sticking out:
     * (1.25^3 - 3 x 0.25^3) / 6 */
    trim(&c, 0.25, 0, 0, 1, 1, 1, &out, "trim cube, slanted plane");
    double corner = (1.25 * 1.25 * 1.25 - 3 * 0.25 * 0.25 * 0.25) / 6;
    assert_true(geom_mesh_is_closed(&out));
    if (fabs(geom_mesh_volume(&out) - (1 - corner)) > EPS)
        fail_msg("slanted trim: volume %.17g, expected %.17g", geom_mesh_volume(&out), 1 - corner);
    geom_mesh_free(&out);
    trim(&c, 0, 0, 0, 1, 1, 1, &out, "trim cube through the centre, slanted");
    assert_true(geom_mesh_is_closed(&out));
    assert_true(fabs(geom_mesh_volume(&out) - 0.5) < EPS);
    geom_mesh_free(&out);
    /* a plane above it keeps it all, below it none */
    trim(&c, 0, 0, 5, 0, 0, 1, &out, "trim cube, plane above");
    check_solid(&out, 1, 6, EPS);
    assert_int_equal(out.npos, 8);
    geom_mesh_free(&out);
    trim(&c, 0, 0, -5, 0, 0, 1, &out, "trim cube, plane below");
    assert_int_equal(out.ntri, 0);
    assert_int_equal(out.npos, 0);
    geom_mesh_free(&out);
    /* the plane of its top face: all of it */
    trim(&c, 0, 0, 0.5, 0, 0, 1, &out, "trim cube, plane on a face");
    check_solid(&out, 1, 6, EPS);
    geom_mesh_free(&out);
    geom_mesh_free(&c);
}

/* The icosphere by z = 0 (one of its mirror planes): exactly half its
 * volume; by the slanted plane through its centre with normal (1,2,3):
 * between half the inscribed and half the circumscribed ball. */
static void trim_sphere(void **st)
{
    (void)st;
    GeomMesh s = icosphere(1, 3), out;
    double vs = geom_mesh_volume(&s), rin = inradius(&s);
    trim(&s, 0, 0, 0, 0, 0, 1, &out, "trim sphere by z = 0");
    assert_true(geom_mesh_is_closed(&out));
    if (fabs(geom_mesh_volume(&out) - vs / 2) > EPS)
        fail_msg("half sphere %.17g, expected %.17g", geom_mesh_volume(&out), vs / 2);
    double b[6];
    geom_mesh_bounds(&out, b);
    assert_true(b[5] == 0 && b[2] == -1);
    geom_mesh_free(&out);
    trim(&s, 0, 0, 0, 1, 2, 3, &out, "trim sphere, slanted plane");
    assert_true(geom_mesh_is_closed(&out));
    double v = geom_mesh_volume(&out);
    if (!(v > 2 * M_PI * rin * rin * rin / 3 && v < 2 * M_PI / 3))
        fail_msg("slanted half sphere %.17g not within [%.17g, %.17g]", v, 2 * M_PI * rin * rin * rin / 3,
                 2 * M_PI / 3);
    geom_mesh_free(&out);
    geom_mesh_free(&s);
}

/* }===== */

/* {===== edge cases and errors */

/* [out] as the error left it: zeroed */
static void assert_zeroed(const GeomMesh *out)
{
    assert_null(out->pos);
    assert_null(out->tri);
    assert_int_equal(out->npos, 0);
    assert_int_equal(out->ntri, 0);
}

static void refused(void **st)
{
    (void)st;
    Buf err = BUF_INIT;
    GeomMesh a = box(0, 0, 0, 1, 1, 1, 0), b = box(0.5, 0.5, 0.5, 2, 2, 2, 1), out;
    /* an open box (one triangle left out) as the second of two */
    GeomMesh open = box(0.5, 0.5, 0.5, 2, 2, 2, 0);
    open.ntri--;
    const GeomMesh *in[3] = {&a, &open, &b};
    memset(&out, 0xab, sizeof out);
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 2, &out, NULL, &err), -1);
    assert_error(&err, "mesh 2 of 2 is not closed");
    assert_zeroed(&out);
    /* inputs are checked before any operation: the third named */
    in[1] = &b, in[2] = &open;
    assert_int_equal(geom_csg_boolean(GEOM_DIFFERENCE, in, 3, &out, NULL, &err), -1);
    assert_error(&err, "mesh 3 of 3 is not closed");
    /* turned inside out (CGAL would take it for the space outside a box) */
    GeomMesh inv = box(0, 0, 0, 1, 1, 1, 0);
    for (uint32_t t = 0; t < inv.ntri; t++) {
        uint32_t x = inv.tri[t * 3 + 1];
        inv.tri[t * 3 + 1] = inv.tri[t * 3 + 2];
        inv.tri[t * 3 + 2] = x;
    }
    in[0] = &inv, in[1] = &b;
    assert_int_equal(geom_csg_boolean(GEOM_INTERSECT, in, 2, &out, NULL, &err), -1);
    assert_error(&err, "mesh 1 of 2 is inside out");
    /* two overlapping boxes in one mesh: closed, but it cuts itself; it
     * is refined where it crosses into the solid it bounds (as a boolean's
     * result rounded to doubles must be), here the two boxes' union:
     * 1 + 1 - 0.5^3 */
    GeomMesh two = box(0, 0, 0, 1, 1, 1, 0), other = box(0.5, 0.5, 0.5, 1.5, 1.5, 1.5, 0);
    append(&two, &other, 0);
    in[0] = &two;
    assert_int_equal(geom_csg_trim(&two, (double[3]){0, 0, 10}, (double[3]){0, 0, 1}, &out, &err), 0);
    assert_true(fabs(geom_mesh_volume(&out) - 1.875) < 1e-12);
    assert_true(geom_mesh_is_closed(&out));
    geom_mesh_free(&out);
    /* a triangle's index past the positions; a position not finite */
    uint32_t corner = a.tri[5];
    a.tri[5] = a.npos;
    in[0] = &b, in[1] = &a;
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 2, &out, NULL, &err), -1);
    assert_error(&err, "mesh 2 of 2 has a triangle index out of range");
    a.tri[5] = corner;
    double keep = a.pos[4];
    a.pos[4] = NAN;
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 2, &out, NULL, &err), -1);
    assert_error(&err, "mesh 2 of 2 has a position that is not finite");
    a.pos[4] = keep;
    /* no inputs; a missing one */
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 0, &out, NULL, &err), -1);
    assert_error(&err, "no meshes");
    in[1] = NULL;
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 2, &out, NULL, &err), -1);
    assert_error(&err, "mesh 2 of 2 is missing");
    /* a zero normal, a normal not finite */
    const double o[3] = {0, 0, 0}, zero[3] = {0, 0, 0}, inf[3] = {0, INFINITY, 1};
    memset(&out, 0xab, sizeof out);
    assert_int_equal(geom_csg_trim(&b, o, zero, &out, &err), -1);
    assert_error(&err, "the trim normal is zero");
    assert_zeroed(&out);
    assert_int_equal(geom_csg_trim(&b, o, inf, &out, &err), -1);
    assert_error(&err, "the trim plane is not finite");
    /* the trim's input is checked as any */
    const double up[3] = {0, 0, 1};
    assert_int_equal(geom_csg_trim(&open, o, up, &out, &err), -1);
    assert_error(&err, "mesh 1 of 1 is not closed");
    /* the message is appended to what [err] holds; none at all is fine */
    buf_puts(&err, "before\n");
    assert_int_equal(geom_csg_trim(&b, o, zero, &out, &err), -1);
    assert_error(&err, "before\nthe trim normal is zero");
    assert_int_equal(geom_csg_trim(&b, o, zero, &out, NULL), -1);
    /* a box inside another, both wound outwards: no volume has that
     * boundary (a hollow box winds the inner one inwards) */
    GeomMesh nested = box(-1, -1, -1, 3, 3, 3, 0);
    append(&nested, &a, 0);
    in[0] = &nested;
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 1, &out, NULL, &err), -1);
    assert_error(&err, "mesh 1 of 1 is not a volume");
    /* two boxes in one mesh touching along an edge (four triangles on
     * it), and at a corner only (two fans of triangles about it) */
    GeomMesh edge = box(0, 0, 0, 1, 1, 1, 1), edge2 = box(1, 1, 0, 2, 2, 1, 1);
    append(&edge, &edge2, 0);
    in[0] = &edge;
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 1, &out, NULL, &err), -1);
    assert_error(&err, "mesh 1 of 1 is not a manifold surface");
    GeomMesh touch = box(0, 0, 0, 1, 1, 1, 1), touch2 = box(1, 1, 1, 2, 2, 2, 1);
    append(&touch, &touch2, 0);
    in[0] = &touch;
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 1, &out, NULL, &err), -1);
    assert_error(&err, "mesh 1 of 1 is not a manifold surface");
    /* the same two as separate inputs: their union would be that surface,
     * which CGAL's corefinement refuses to make */
    in[0] = &edge2, in[1] = &a;
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 2, &out, NULL, &err), -1);
    assert_error(&err, "boolean operation failed");
    assert_zeroed(&out);
    GeomMesh *all[] = {&a, &b, &open, &inv, &two, &other, &nested, &edge, &edge2, &touch, &touch2};
    for (size_t i = 0; i < sizeof all / sizeof *all; i++) geom_mesh_free(all[i]);
    buf_free(&err);
}

/* interrupt set before the call: nothing done, -1 and "interrupted" */
static void interrupted(void **st)
{
    (void)st;
    Buf err = BUF_INIT;
    GeomMesh a = box(0, 0, 0, 1, 1, 1, 0), b = box(0.5, 0, 0, 1.5, 1, 1, 0), out;
    const GeomMesh *in[2] = {&a, &b};
    volatile int stop = 1;
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 2, &out, &stop, &err), -1);
    assert_error(&err, "interrupted");
    assert_zeroed(&out);
    stop = 0;
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 2, &out, &stop, &err), 0);
    check_solid(&out, 1.5, 8, EPS);
    geom_mesh_free(&out);
    geom_mesh_free(&a);
    geom_mesh_free(&b);
    buf_free(&err);
}

/* Disjoint solids intersected: no triangles, no error; united: both
 * (volume 1 + 8, area 6 + 24). One input: its welded copy. An input
 * without triangles is the empty solid. */
static void empty_and_single(void **st)
{
    (void)st;
    Buf err = BUF_INIT;
    GeomMesh a = box(0, 0, 0, 1, 1, 1, 1), b = box(3, 3, 3, 5, 5, 5, 0), empty = {0}, out;
    const GeomMesh *in[2] = {&a, &b};
    assert_int_equal(geom_csg_boolean(GEOM_INTERSECT, in, 2, &out, NULL, &err), 0);
    assert_int_equal(out.ntri, 0);
    geom_mesh_free(&out);
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 2, &out, NULL, &err), 0);
    check_solid(&out, 9, 30, EPS);
    assert_int_equal(out.npos, 16);
    assert_int_equal(out.ntri, 24);
    geom_mesh_free(&out);
    assert_int_equal(geom_csg_boolean(GEOM_DIFFERENCE, in, 2, &out, NULL, &err), 0);
    check_solid(&out, 1, 6, EPS);
    geom_mesh_free(&out);

    /* n == 1: the 24 positions of the unwelded box welded to 8 */
    assert_int_equal(a.npos, 24);
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 1, &out, NULL, &err), 0);
    check_solid(&out, 1, 6, EPS);
    assert_int_equal(out.npos, 8);
    assert_int_equal(out.ntri, 12);
    const double coords[] = {0, 1};
    check_coords(&out, 3, coords, 2);
    check_bounds(&out, 0, 0, 0, 1, 1, 1);
    geom_mesh_free(&out);

    /* the empty solid: united, a copy of the other; intersected, empty;
     * subtracted, nothing taken away */
    in[0] = &empty, in[1] = &b;
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 2, &out, NULL, &err), 0);
    check_solid(&out, 8, 24, EPS);
    geom_mesh_free(&out);
    assert_int_equal(geom_csg_boolean(GEOM_INTERSECT, in, 2, &out, NULL, &err), 0);
    assert_int_equal(out.ntri, 0);
    geom_mesh_free(&out);
    in[0] = &b, in[1] = &empty;
    assert_int_equal(geom_csg_boolean(GEOM_DIFFERENCE, in, 2, &out, NULL, &err), 0);
    check_solid(&out, 8, 24, EPS);
    geom_mesh_free(&out);
    geom_mesh_free(&a);
    geom_mesh_free(&b);
    buf_free(&err);
}

/* A hollow box: [0,4]^3 with the cavity [1,2]^3 (its faces wound inwards),
 * volume 64 - 1 = 63, area 96 + 6 = 102. Trimmed at z = 1.5, through the
 * cavity: volume 16 x 1.5 - 0.5 = 23.5; area: the bottom 16, the sides
 * 4 x 4 x 1.5 = 24, the cap 16 - 1 = 15, the cavity's floor 1 and walls
 * 4 x 0.5 = 2, 58 in all. Less a box [1.5,5]x[-1,5]x[-1,5] that opens the
 * cavity: [0,1.5]x[0,4]^2 less [1,1.5]x[1,2]^2, volume 24 - 0.5 = 23.5,
 * area 2(6 + 6 + 16) - 1 + (1 + 4 x 0.5) = 58 (the same shape turned). */
static void hollow(void **st)
{
    (void)st;
    Buf err = BUF_INIT;
    GeomMesh h = box(0, 0, 0, 4, 4, 4, 0), cavity = box(1, 1, 1, 2, 2, 2, 0), cut = box(1.5, -1, -1, 5, 5, 5, 0),
             out;
    append(&h, &cavity, 1);
    const GeomMesh *in[2] = {&h, &cut};
    assert_int_equal(geom_csg_boolean(GEOM_UNION, in, 1, &out, NULL, &err), 0);
    check_solid(&out, 63, 102, EPS);
    geom_mesh_free(&out);
    trim(&h, 0, 0, 1.5, 0, 0, 1, &out, "trim hollow box through its cavity");
    check_solid(&out, 23.5, 58, EPS);
    check_bounds(&out, 0, 0, 0, 4, 4, 1.5);
    geom_mesh_free(&out);
    run(GEOM_DIFFERENCE, &h, &cut, &out, "hollow box less a box");
    check_solid(&out, 23.5, 58, EPS);
    check_bounds(&out, 0, 0, 0, 1.5, 4, 4);
    geom_mesh_free(&out);
    geom_mesh_free(&h);
    geom_mesh_free(&cavity);
    geom_mesh_free(&cut);
    buf_free(&err);
}

/* Two threads at once (two renderers in one process): each makes the
 * sphere-cut-by-a-box intersection and the slanted trim of the sphere
 * twice (a coarser sphere, 320 triangles, for valgrind's sake); every
 * result equals, bit for bit, the one made alone. */
typedef struct Work {
    const GeomMesh *sphere, *box;
    double vol[2];
    int rc;
} Work;

static void *work(void *arg)
{
    Work *w = arg;
    const GeomMesh *in[2] = {w->sphere, w->box};
    const double o[3] = {0, 0, 0}, n[3] = {1, 2, 3};
    Buf err = BUF_INIT;
    for (int i = 0; i < 2 && w->rc == 0; i++) {
        GeomMesh a, b;
        w->rc |= geom_csg_boolean(GEOM_INTERSECT, in, 2, &a, NULL, &err);
        w->rc |= geom_csg_trim(w->sphere, o, n, &b, &err);
        double va = geom_mesh_volume(&a), vb = geom_mesh_volume(&b);
        if (i > 0 && (va != w->vol[0] || vb != w->vol[1])) w->rc = 1;
        w->vol[0] = va, w->vol[1] = vb;
        geom_mesh_free(&a);
        geom_mesh_free(&b);
    }
    buf_free(&err);
    return NULL;
}

static void two_threads(void **st)
{
    (void)st;
    GeomMesh s = icosphere(1, 2), b = box(0.4, -3, -3, 3, 3, 3, 0);
    Work alone = {&s, &b, {0, 0}, 0}, w[2] = {alone, alone};
    work(&alone);
    assert_int_equal(alone.rc, 0);
    pthread_t t[2];
    for (int i = 0; i < 2; i++) assert_int_equal(pthread_create(&t[i], NULL, work, &w[i]), 0);
    for (int i = 0; i < 2; i++) {
        pthread_join(t[i], NULL);
        assert_int_equal(w[i].rc, 0);
        assert_true(w[i].vol[0] == alone.vol[0] && w[i].vol[1] == alone.vol[1]);
    }
    geom_mesh_free(&s);
    geom_mesh_free(&b);
}

/* }===== */

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(two_boxes),
        cmocka_unit_test(three_boxes),
        cmocka_unit_test(sphere_inside_box),
        cmocka_unit_test(sphere_cut_by_box),
        cmocka_unit_test(two_spheres),
        cmocka_unit_test(trim_cube),
        cmocka_unit_test(trim_sphere),
        cmocka_unit_test(hollow),
        cmocka_unit_test(refused),
        cmocka_unit_test(interrupted),
        cmocka_unit_test(empty_and_single),
        cmocka_unit_test(two_threads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
