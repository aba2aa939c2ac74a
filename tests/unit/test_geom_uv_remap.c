/* test_geom_uv_remap.c: Flitter's uv_remap= mappings (geom_uv_remap.h)
 * on hand-made vertices, against hand-computed coordinates. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "geom_uv_remap.h"
#include "mem.h"

/* A MeshData of [n] vertices (x, y, z, normal z) and the triangles [tri]. */
static MeshData make(const float (*v)[4], uint32_t n, const uint32_t *tri, uint32_t ntri)
{
    MeshData d = {0};
    d.verts = mem_calloc(n, 8 * sizeof(float));
    d.nverts = n;
    for (uint32_t i = 0; i < n; i++) {
        float *p = d.verts + (size_t)i * 8;
        p[0] = v[i][0], p[1] = v[i][1], p[2] = v[i][2], p[5] = v[i][3];
        p[6] = p[7] = -7;
    }
    d.index = mem_calloc(ntri ? ntri * 3 : 1, sizeof(uint32_t));
    memcpy(d.index, tri, ntri * 3 * sizeof(uint32_t));
    d.nindex = ntri * 3;
    return d;
}

static float U(const MeshData *d, uint32_t i) { return d->verts[(size_t)i * 8 + 6]; }
static float V(const MeshData *d, uint32_t i) { return d->verts[(size_t)i * 8 + 7]; }

static void parse(void **state)
{
    (void)state;
    assert_int_equal(geom_uv_remap_parse("sphere"), UV_REMAP_SPHERE);
    assert_int_equal(geom_uv_remap_parse("plane"), UV_REMAP_PLANE);
    assert_int_equal(geom_uv_remap_parse("book"), UV_REMAP_BOOK);
    assert_int_equal(geom_uv_remap_parse("cube"), UV_REMAP_NONE);
    assert_int_equal(geom_uv_remap_parse(NULL), UV_REMAP_NONE);
}

static void sphere(void **state)
{
    (void)state;
    /* +x: longitude 0, equator; +y: a quarter turn; -x: a half; the pole
     * +z: v = 1; -y at 45 degrees down: u = 0.75, v = 0.25 */
    const float v[][4] = {{1, 0, 0, 0}, {0, 2, 0, 0}, {-1, 0, 0, 0}, {0, 0, 3, 0}, {0, -1, -1, 0}};
    const uint32_t tri[] = {0, 1, 3};
    MeshData d = make(v, 5, tri, 1);
    double bounds[6] = {-1, -1, -1, 1, 2, 3};
    geom_uv_remap(&d, UV_REMAP_SPHERE, bounds);
    assert_int_equal(d.nverts, 5);   /* no triangle across the seam */
    assert_true(U(&d, 0) == 0 && V(&d, 0) == 0.5f);
    assert_true(U(&d, 1) == 0.25f && V(&d, 1) == 0.5f);
    assert_true(U(&d, 2) == 0.5f);
    assert_true(V(&d, 3) == 1);
    assert_true(U(&d, 4) == 0.75f && V(&d, 4) == 0.25f);
    mesh_data_free(&d);
}

static void sphere_seam(void **state)
{
    (void)state;
    /* a triangle across the seam (+x, and just below it on either side):
     * its corners below u = 0.25 are copied with u + 1 */
    const float v[][4] = {{1, 0, 0, 0}, {1, 0.1f, 0, 0}, {1, -0.1f, 0, 0}, {0, 1, 0, 0}};
    const uint32_t tri[] = {0, 1, 2, 0, 1, 3};
    MeshData d = make(v, 4, tri, 2);
    double bounds[6] = {0};
    geom_uv_remap(&d, UV_REMAP_SPHERE, bounds);
    assert_int_equal(d.nverts, 6);
    assert_int_equal(d.nindex, 6);
    assert_int_equal(d.index[0], 4);
    assert_int_equal(d.index[1], 5);
    assert_int_equal(d.index[2], 2);
    assert_true(U(&d, 4) == 1 && U(&d, 0) == 0);
    assert_true(U(&d, 5) == U(&d, 1) + 1);
    assert_true(U(&d, 2) > 0.98f && U(&d, 2) < 1);
    assert_true(memcmp(d.verts + 4 * 8, d.verts, 6 * sizeof(float)) == 0);
    /* the second triangle does not cross: unchanged */
    assert_int_equal(d.index[3], 0);
    assert_int_equal(d.index[4], 1);
    assert_int_equal(d.index[5], 3);
    mesh_data_free(&d);
}

static void plane_and_book(void **state)
{
    (void)state;
    const float v[][4] = {{-1, -2, 0, 1}, {3, 2, 0, -1}, {0, 1, 5, 0}};
    const uint32_t tri[] = {0, 1, 2};
    double bounds[6] = {-1, -2, 0, 3, 2, 5};
    MeshData d = make(v, 3, tri, 1);
    geom_uv_remap(&d, UV_REMAP_PLANE, bounds);
    assert_true(U(&d, 0) == 0 && V(&d, 0) == 0);
    assert_true(U(&d, 1) == 1 && V(&d, 1) == 1);
    assert_true(U(&d, 2) == 0.25f && V(&d, 2) == 0.75f);
    mesh_data_free(&d);
    d = make(v, 3, tri, 1);
    geom_uv_remap(&d, UV_REMAP_BOOK, bounds);
    /* facing +z (and side-on): the right half; facing -z: mirrored on the left */
    assert_true(U(&d, 0) == 0.5f && V(&d, 0) == 0);
    assert_true(U(&d, 1) == 0 && V(&d, 1) == 1);
    assert_true(U(&d, 2) == 0.625f);
    mesh_data_free(&d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(parse),
        cmocka_unit_test(sphere),
        cmocka_unit_test(sphere_seam),
        cmocka_unit_test(plane_and_book),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
