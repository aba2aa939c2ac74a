/* test_light_cull.c: the lights a mesh cannot see (lib/render/gl/
 * canvas3d_cull.h), on Flitter's unit box (+-0.5, normals out; inverted:
 * in) and hand-made meshes, the distances worked by hand: a light is
 * culled only when its centre lies behind every face's plane by more than
 * its radius and the margin, 1/1000 of (1 + |light| + |vertex|). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "canvas3d_cull.h"
#include "canvas3d_shaders.h"
#include "geom_primitives.h"

static void box_planes(C3dPlanes *p, bool invert)
{
    MeshKey key = {.kind = MESH_BOX, .invert = invert};
    MeshData d;
    mesh_build(&key, &d);
    c3d_planes_make(p, d.verts, d.nverts, d.index, d.nindex);
    mesh_data_free(&d);
}

/* A light of [type] at x, y, z with [radius] (column 2's w: a point
 * light's radius, a spot light's outer cone cosine). */
static void light_at(float l[16], int type, double x, double y, double z, double radius)
{
    memset(l, 0, 16 * sizeof(float));
    l[0] = l[1] = l[2] = 1;
    l[3] = (float)type;
    l[4] = (float)x, l[5] = (float)y, l[6] = (float)z;
    l[11] = (float)radius;
    l[12] = 1;
}

/* Scale [sx, sy, sz] then translate [tx, ty, tz], column-major. */
static void affine(double m[16], double sx, double sy, double sz, double tx, double ty, double tz)
{
    memset(m, 0, 16 * sizeof(double));
    m[0] = sx, m[5] = sy, m[10] = sz, m[15] = 1;
    m[12] = tx, m[13] = ty, m[14] = tz;
}

static void box_has_six_planes(void **st)
{
    (void)st;
    C3dPlanes p;
    box_planes(&p, false);
    assert_int_equal(p.n, 6);
    for (int i = 0; i < 6; i++) {
        const float *n = p.plane[i].normal;
        /* one axis, unit, and every vertex of its faces half a unit along it */
        assert_float_equal(fabs(n[0]) + fabs(n[1]) + fabs(n[2]), 1.0, 0);
        double lo = n[0] * p.plane[i].low[0] + n[1] * p.plane[i].low[1] + n[2] * p.plane[i].low[2];
        double hi = n[0] * p.plane[i].high[0] + n[1] * p.plane[i].high[1] + n[2] * p.plane[i].high[2];
        assert_float_equal(lo, 0.5, 0);
        assert_float_equal(hi, 0.5, 0);
    }
    box_planes(&p, true);
    assert_int_equal(p.n, 6);
}

static void smooth_and_odd_meshes_have_none(void **st)
{
    (void)st;
    C3dPlanes p;
    MeshKey key = {.kind = MESH_SPHERE, .segments = mesh_segments(MESH_SPHERE, 64)};
    MeshData d;
    mesh_build(&key, &d);
    c3d_planes_make(&p, d.verts, d.nverts, d.index, d.nindex);
    mesh_data_free(&d);
    assert_int_equal(p.n, 0);
    /* one triangle whose third normal differs in its last bit */
    float v[24] = {0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
    uint32_t tri[3] = {0, 1, 2};
    c3d_planes_make(&p, v, 3, tri, 3);
    assert_int_equal(p.n, 1);
    v[21] = nextafterf(1.0f, 2.0f);
    c3d_planes_make(&p, v, 3, tri, 3);
    assert_int_equal(p.n, 0);
    /* the same normal leaning off the triangle (the third vertex lifted
     * along it by 0.001, against a tolerance of 1e-5 of its coordinates) */
    v[18] = 0.001f;
    c3d_planes_make(&p, v, 3, tri, 3);
    assert_int_equal(p.n, 0);
    v[18] = 0;
    /* an index past the vertices, a NaN, no triangle */
    v[21] = 1;
    uint32_t bad[3] = {0, 1, 3};
    c3d_planes_make(&p, v, 3, bad, 3);
    assert_int_equal(p.n, 0);
    v[0] = NAN;
    c3d_planes_make(&p, v, 3, tri, 3);
    assert_int_equal(p.n, 0);
    c3d_planes_make(&p, v, 3, tri, 0);
    assert_int_equal(p.n, 0);
}

static void inside_the_box(void **st)
{
    (void)st;
    C3dPlanes out, in;
    box_planes(&out, false);
    box_planes(&in, true);
    double m[16];
    affine(m, 1, 1, 1, 0, 0, 0);
    float l[16];
    light_at(l, LIGHT_POINT, 0, 0, 0, 0);
    assert_true(c3d_light_unseen(l, m, &out));   /* 0.5 behind every face */
    assert_false(c3d_light_unseen(l, m, &in));   /* in front of every inward face */
    light_at(l, LIGHT_SPOT, 0, 0, 0, 0.9);       /* (a spot's 0.9: its cone, not a radius) */
    assert_true(c3d_light_unseen(l, m, &out));
    /* 0.2 behind the +x face: a radius of 0.19 stays behind it (margin
     * 0.001 * (1 + 0.3 + |(0.5, +-0.5, +-0.5)| = 0.866) = 0.0022), 0.2 does not */
    light_at(l, LIGHT_POINT, 0.3, 0, 0, 0.19);
    assert_true(c3d_light_unseen(l, m, &out));
    light_at(l, LIGHT_POINT, 0.3, 0, 0, 0.199);
    assert_false(c3d_light_unseen(l, m, &out));   /* within the margin */
    light_at(l, LIGHT_POINT, 0.3, 0, 0, 0.2);
    assert_false(c3d_light_unseen(l, m, &out));
    light_at(l, LIGHT_POINT, 0.6, 0, 0, 0);
    assert_false(c3d_light_unseen(l, m, &out));   /* outside, before the +x face */
    /* other kinds are never culled */
    static const int kinds[3] = {LIGHT_AMBIENT, LIGHT_DIRECTIONAL, LIGHT_LINE};
    for (int k = 0; k < 3; k++) {
        light_at(l, kinds[k], 0, 0, 0, 0);
        assert_false(c3d_light_unseen(l, m, &out));
    }
}

/* Flitter's examples/bounce.fl: balls of radius up to 7.5 inside a box of
 * 100 (translated 0;0;50), lit by a light at each ball; the glass's outer
 * box is 102. */
static void bounce_glass(void **st)
{
    (void)st;
    C3dPlanes out, in;
    box_planes(&out, false);
    box_planes(&in, true);
    double outer[16], inner[16];
    affine(outer, 102, 102, 102, 0, 0, 50);
    affine(inner, 100, 100, 100, 0, 0, 50);
    float l[16];
    /* a ball of radius 7.5 resting in a corner: its centre 7.5 from three
     * walls, 8.5 behind the outer box's faces, margin about 0.17 */
    light_at(l, LIGHT_POINT, -42.5, 42.5, 7.5, 7.5);
    assert_true(c3d_light_unseen(l, outer, &out));
    assert_false(c3d_light_unseen(l, inner, &in));
    /* the same ball 8.4 from the outer wall: its radius and the margin reach past it */
    light_at(l, LIGHT_POINT, -42.6, 42.5, 50, 8.3);
    assert_false(c3d_light_unseen(l, outer, &out));
    /* a ball that has left the box through the top */
    light_at(l, LIGHT_POINT, 0, 0, 120, 5);
    assert_false(c3d_light_unseen(l, outer, &out));
}

/* The normal matrix is the model's cofactor, as the shader's: a mirror
 * (det < 0) turns a box's normals inward, and a light inside it lights
 * its faces; a flattened box (det 0) has no normals: never culled. */
static void mirrored_and_degenerate(void **st)
{
    (void)st;
    C3dPlanes out;
    box_planes(&out, false);
    double m[16];
    float l[16];
    light_at(l, LIGHT_POINT, 0, 0, 0, 0);
    affine(m, -1, 1, 1, 0, 0, 0);
    assert_false(c3d_light_unseen(l, m, &out));
    affine(m, -1, -1, 1, 0, 0, 0);   /* a half turn: det 1 */
    assert_true(c3d_light_unseen(l, m, &out));
    affine(m, 1, 1, 0, 0, 0, 0);
    assert_false(c3d_light_unseen(l, m, &out));
    affine(m, 1, 1, 1, 0, 0, 0);
    m[15] = 2;   /* not affine */
    assert_false(c3d_light_unseen(l, m, &out));
    affine(m, 1, 1, 1, 0, 0, 0);
    light_at(l, LIGHT_POINT, NAN, 0, 0, 0);
    assert_false(c3d_light_unseen(l, m, &out));
    light_at(l, LIGHT_POINT, 0, 0, 0, INFINITY);
    assert_false(c3d_light_unseen(l, m, &out));
    /* a scale whose normal matrix a float cannot hold: 1e20 squared */
    light_at(l, LIGHT_POINT, 0, 0, 0, 0);
    affine(m, 1e20, 1e20, 1e20, 0, 0, 0);
    assert_false(c3d_light_unseen(l, m, &out));
    affine(m, 1e3, 1e3, 1e3, 0, 0, 0);
    assert_true(c3d_light_unseen(l, m, &out));
    C3dPlanes none = {0};
    light_at(l, LIGHT_POINT, 0, 0, 0, 0);
    assert_false(c3d_light_unseen(l, m, &none));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(box_has_six_planes),
        cmocka_unit_test(smooth_and_odd_meshes_have_none),
        cmocka_unit_test(inside_the_box),
        cmocka_unit_test(bounce_glass),
        cmocka_unit_test(mirrored_and_degenerate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
