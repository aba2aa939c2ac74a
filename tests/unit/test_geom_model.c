/* test_geom_model.c: the model tree of `!canvas3d` (geom_model.h) from
 * scripts run through a real runtime: constructive solid geometry
 * against hand-computed volumes and areas, trims, signed distance fields
 * (of primitives and of Flitter functions called through the evaluator),
 * vectors and model files, the cache (hit on an unchanged tree, rebuilt
 * on a changed one) and the memory budget. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "buf.h"
#include "geom_model.h"
#include "geom_primitives.h"
#include "rnode.h"
#include "program.h"
#include "runtime.h"

typedef struct Fixture {
    fl_runtime *rt;
    GeomModels *models;
    MemBudget budget;
    char errors[4096];
    int nerrors;
    long calls;          /* points the SDF functions were called at */
    FILE *log;
    char *logtext;
    size_t loglen;
    RtStreams streams;
} Fixture;

static void on_error(void *ctx, const char *line)
{
    Fixture *f = ctx;
    size_t at = strlen(f->errors);
    snprintf(f->errors + at, sizeof f->errors - at, "%s\n", line);
    f->nerrors++;
}

static bool on_distance(void *ctx, const Vec *fn, const double *xyz, size_t n, double *out)
{
    Fixture *f = ctx;
    f->calls += (long)n;
    return rt_call_distances(f->rt, fn, xyz, n, out);
}

static uint64_t on_key(void *ctx, const Vec *fn)
{
    (void)ctx;
    return eval_function_key(fn);
}

/* A runtime with [src] loaded and one frame run; models with [limit]
 * bytes of budget (0: none). */
static Fixture *fixture(const char *src, size_t limit)
{
    Fixture *f = calloc(1, sizeof *f);
    f->log = open_memstream(&f->logtext, &f->loglen);
    f->streams = (RtStreams){f->log, f->log};
    fl_options o = fl_default_options();
    rt_log_to_files(&o, &f->streams);
    f->rt = fl_new(&o);
    Buf err = BUF_INIT;
    assert_int_equal(rt_load_text(f->rt, "t.fl", src, strlen(src), &err), 0);
    buf_free(&err);
    fl_step(f->rt);
    f->budget.limit = limit;
    GeomEnv env = {.symbols = rt_symbols(f->rt), .budget = limit ? &f->budget : NULL, .error = on_error,
                   .error_ctx = f, .distance = on_distance, .function_key = on_key, .ctx = f};
    f->models = geom_models_new(&env);
    geom_models_frame(f->models, NULL, 0, 300);
    return f;
}

static void fixture_free(Fixture *f)
{
    geom_models_free(f->models);
    fl_free(f->rt);
    fclose(f->log);
    free(f->logtext);
    free(f);
}

/* The [i]th child of the last frame's root. */
static const Node *top(Fixture *f, size_t i)
{
    const Node *root = rt_root(f->rt);
    assert_non_null(root);
    assert_true(rnode_nchildren(root) > i);
    return rnode_child(root, i);
}

static const GeomMesh *mesh_of(Fixture *f, size_t i)
{
    GeomModel *m = geom_model_of(f->models, top(f, i), true);
    assert_non_null(m);
    return geom_model_mesh(f->models, m);
}

/* The volume of the unit sphere's mesh of [segments] (the primitive
 * itself, for comparing booleans with it exactly). */
static double sphere_volume(int segments)
{
    MeshKey k = {.kind = MESH_SPHERE, .segments = mesh_segments(MESH_SPHERE, segments)};
    GeomMesh g;
    geom_primitive_mesh(&k, &g);
    geom_mesh_weld(&g);
    double v = geom_mesh_volume(&g);
    geom_mesh_free(&g);
    return v;
}

static void check_closed(const GeomMesh *m)
{
    assert_non_null(m);
    GeomMesh w;
    geom_mesh_copy(m, &w);
    geom_mesh_weld(&w);
    assert_true(geom_mesh_is_closed(&w));
    geom_mesh_free(&w);
}

static void union_of_boxes(void **state)
{
    (void)state;
    /* two unit cubes overlapping by half: volume 1.5, area 2*(1.5*1)*2 + 2*1 = 8 */
    Fixture *f = fixture("!union\n    !box\n    !box position=0.5;0;0\n"
                         "!intersect\n    !box\n    !box position=0.5;0;0\n"
                         "!difference\n    !box\n    !box position=0.5;0;0\n",
                         0);
    const GeomMesh *u = mesh_of(f, 0), *i = mesh_of(f, 1), *d = mesh_of(f, 2);
    check_closed(u);
    check_closed(i);
    check_closed(d);
    assert_true(fabs(geom_mesh_volume(u) - 1.5) < 1e-9);
    assert_true(fabs(geom_mesh_area(u) - 8) < 1e-9);
    assert_true(fabs(geom_mesh_volume(i) - 0.5) < 1e-9);
    assert_true(fabs(geom_mesh_area(i) - 4) < 1e-9);
    assert_true(fabs(geom_mesh_volume(d) - 0.5) < 1e-9);
    assert_true(fabs(geom_mesh_area(d) - 4) < 1e-9);
    assert_int_equal(f->nerrors, 0);
    fixture_free(f);
}

static void box_and_sphere(void **state)
{
    (void)state;
    /* a sphere of radius 0.8 inside a box of side 2: the intersection is
     * the sphere's mesh, the difference the box less it */
    Fixture *f = fixture("!intersect\n    !box size=2\n    !sphere size=0.8 segments=32\n"
                         "!difference\n    !box size=2\n    !sphere size=0.8 segments=32\n"
                         "!trim normal=0;0;1\n    !sphere segments=32\n"
                         "!trim origin=0;0;0.25 normal=0;0;1\n    !box\n",
                         0);
    double sv = sphere_volume(32) * 0.8 * 0.8 * 0.8;
    const GeomMesh *i = mesh_of(f, 0), *d = mesh_of(f, 1), *t = mesh_of(f, 2), *b = mesh_of(f, 3);
    assert_true(fabs(geom_mesh_volume(i) - sv) < 1e-9);
    assert_true(fabs(geom_mesh_volume(d) - (8 - sv)) < 1e-9);
    /* the sphere's mesh is symmetric about z = 0 (its equator is a row of
     * vertices): the trim keeps exactly half */
    check_closed(t);
    assert_true(fabs(geom_mesh_volume(t) - sphere_volume(32) / 2) < 1e-9);
    double tb[6];
    geom_mesh_bounds(t, tb);
    assert_true(tb[5] <= 1e-12 && tb[2] < -0.99);
    /* the unit cube below z = 0.25: 0.75 */
    assert_true(fabs(geom_mesh_volume(b) - 0.75) < 1e-9);
    /* and the analytic sphere within the tessellation's error: every
     * vertex on the sphere and no edge longer than a sixteenth of a half
     * turn (32 segments: 8 rows an octant), so the mesh lies between the
     * sphere and the one cos(pi/16) times its radius (it is 0.9771) */
    double ratio = sv / (4.0 / 3 * M_PI * 0.512);
    assert_true(ratio < 1 && ratio > pow(cos(M_PI / 16), 3));
    fixture_free(f);
}

/* A trim whose plane runs through a cylinder's rim at a quarter turn and
 * the middle of its cap, then less a coaxial cylinder inside it (the grey
 * part of Flitter's examples/solidgeometry.fl, which the rim's points at
 * cos(pi/2) = 6e-17 instead of 0 made fail): closed, without errors, and,
 * as the inner cylinder lies inside the outer, of the volume of the outer
 * trimmed less the inner trimmed. */
static void trim_through_rim(void **state)
{
    (void)state;
    const char *outer = "!trim origin=0;1;0 normal=0.75;1;0\n"
                        "    !cylinder size=0.75;0.75;2 rotation=0.25;0;0 segments=8\n";
    const char *inner = "!trim origin=0;1;0 normal=0.75;1;0\n"
                        "    !cylinder size=0.5;0.5;2 rotation=0.25;0;0 segments=8\n";
    char src[1024];
    snprintf(src, sizeof src,
             "!trim origin=0;1;0 normal=0.75;1;0\n"
             "    !difference\n"
             "        !cylinder size=0.75;0.75;2 rotation=0.25;0;0 segments=8\n"
             "        !cylinder size=0.5;0.5;2 rotation=0.25;0;0 segments=8\n"
             "%s%s",
             outer, inner);
    Fixture *f = fixture(src, 0);
    const GeomMesh *d = mesh_of(f, 0), *o = mesh_of(f, 1), *i = mesh_of(f, 2);
    check_closed(d);
    check_closed(o);
    assert_int_equal(f->nerrors, 0);
    assert_true(geom_mesh_volume(i) > 0.5);
    assert_true(fabs(geom_mesh_volume(d) - (geom_mesh_volume(o) - geom_mesh_volume(i))) < 1e-9);
    fixture_free(f);
    /* the primitive's rim at a quarter turn is on the axis, exactly */
    MeshKey k = {.kind = MESH_CYLINDER, .segments = mesh_segments(MESH_CYLINDER, 64)};
    GeomMesh g;
    geom_primitive_mesh(&k, &g);
    bool found = false;
    for (uint32_t v = 0; v < g.npos; v++)
        found |= g.pos[v * 3] == 0 && g.pos[v * 3 + 1] == 1 && g.pos[v * 3 + 2] == 0.5;
    assert_true(found);
    geom_mesh_free(&g);
}

/* The unit cube's corners and its twelve triangles wound outwards. */
static const double cube_pos[8][3] = {{-0.5, -0.5, -0.5}, {0.5, -0.5, -0.5}, {0.5, 0.5, -0.5}, {-0.5, 0.5, -0.5},
                                      {-0.5, -0.5, 0.5},  {0.5, -0.5, 0.5},  {0.5, 0.5, 0.5},  {-0.5, 0.5, 0.5}};
static const uint32_t cube_tri[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                         {3, 7, 6}, {3, 6, 2}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};

/* A cube made badly: every triangle its own three vertices (at the
 * cube's corners), triangles 2, 5 and 9 wound inwards (all twelve when
 * [inside_out]), then a repeat of triangle 0 the other way round, a
 * triangle with two corners at one position and one of no area. */
static void bad_cube(GeomMesh *g, bool inside_out)
{
    memset(g, 0, sizeof *g);
    uint32_t pcap = 0, tcap = 0;
    for (int f = 0; f < 12; f++) {
        uint32_t v[3];
        for (int k = 0; k < 3; k++) {
            const double *p = cube_pos[cube_tri[f][k]];
            v[k] = geom_mesh_add_pos(g, &pcap, p[0], p[1], p[2]);
        }
        bool turn = inside_out || f == 2 || f == 5 || f == 9;
        geom_mesh_add_tri(g, &tcap, v[0], turn ? v[2] : v[1], turn ? v[1] : v[2]);
    }
    geom_mesh_add_tri(g, &tcap, 0, 2, 1);
    geom_mesh_add_tri(g, &tcap, 3, 3, 4);
    uint32_t mid = geom_mesh_add_pos(g, &pcap, 0, -0.5, -0.5);   /* on the side from corner 0 to 1 */
    geom_mesh_add_tri(g, &tcap, 0, mid, 2);   /* vertex 2 is corner 1 */
}

static void repair_mesh(void **state)
{
    (void)state;
    for (int inside_out = 0; inside_out < 2; inside_out++) {
        GeomMesh g;
        bad_cube(&g, inside_out);
        assert_int_equal(g.ntri, 15);
        assert_false(geom_mesh_is_closed(&g));
        geom_mesh_repair(&g);
        assert_int_equal(g.ntri, 12);
        assert_int_equal(g.npos, 8);   /* merged, the point on a side unused */
        assert_true(geom_mesh_is_closed(&g));
        assert_true(geom_mesh_volume(&g) == 1);
        geom_mesh_free(&g);
    }
}

/* repair=true on a !model made of vectors: a cube wound inside out is no
 * volume for a boolean operation, and is one once repaired. */
static void repair_model(void **state)
{
    (void)state;
    char vertices[400] = "", faces[400] = "", src[1200];
    size_t at = 0;
    for (int i = 0; i < 8; i++)
        for (int k = 0; k < 3; k++)
            at += (size_t)snprintf(vertices + at, sizeof vertices - at, "%s%g", at ? ";" : "", cube_pos[i][k]);
    at = 0;
    for (int f = 0; f < 12; f++)
        for (int k = 0; k < 3; k++)   /* every triangle turned */
            at += (size_t)snprintf(faces + at, sizeof faces - at, "%s%u", at ? ";" : "", cube_tri[f][k == 0 ? 0 : 3 - k]);
    snprintf(src, sizeof src,
             "!union\n    !model vertices=%s faces=%s repair=true\n    !box position=0.5;0;0\n"
             "!union\n    !model vertices=%s faces=%s\n    !box position=0.5;0;0\n",
             vertices, faces, vertices, faces);
    Fixture *f = fixture(src, 0);
    const GeomMesh *u = mesh_of(f, 0);
    check_closed(u);
    assert_true(fabs(geom_mesh_volume(u) - 1.5) < 1e-9);
    assert_int_equal(f->nerrors, 0);
    assert_null(mesh_of(f, 1));
    assert_int_equal(f->nerrors, 1);
    fixture_free(f);
}

/* !model vertices= without faces= is the vertices' convex hull: the
 * cube's corners with a point inside it and one in the middle of a face
 * make the cube (8 corners, 12 triangles, volume 1); four points in one
 * plane make no solid, said once. */
static void convex_hull(void **state)
{
    (void)state;
    char vertices[400] = "", src[800];
    size_t at = 0;
    for (int i = 0; i < 8; i++)
        for (int k = 0; k < 3; k++)
            at += (size_t)snprintf(vertices + at, sizeof vertices - at, "%s%g", at ? ";" : "", cube_pos[i][k]);
    snprintf(src, sizeof src,
             "!model vertices=%s;0.1;0.2;0.3;0;0;0.5\n"
             "!model vertices=0;0;0;1;0;0;0;1;0;1;1;0\n",
             vertices);
    Fixture *f = fixture(src, 0);
    const GeomMesh *h = mesh_of(f, 0);
    assert_non_null(h);
    assert_int_equal(h->npos, 8);
    assert_int_equal(h->ntri, 12);
    assert_true(geom_mesh_is_closed(h));
    assert_true(geom_mesh_volume(h) == 1);
    assert_int_equal(f->nerrors, 0);
    assert_null(mesh_of(f, 1));
    assert_int_equal(f->nerrors, 1);
    assert_non_null(strstr(f->errors, "one plane"));
    fixture_free(f);
}

static void sdf_sphere(void **state)
{
    (void)state;
    Fixture *f = fixture("!sdf\n    !sphere size=0.8\n"
                         "func ball(p)\n    hypot(p) - 0.5\n"
                         "!sdf function=ball resolution=0.05\n",
                         0);
    const GeomMesh *a = mesh_of(f, 0);
    check_closed(a);
    double res = 2.0 / 64;
    for (uint32_t v = 0; v < a->npos; v++) {
        const double *p = a->pos + (size_t)v * 3;
        assert_true(fabs(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 0.8) < res);
    }
    assert_true(fabs(geom_mesh_volume(a) / (4.0 / 3 * M_PI * 0.512) - 1) < 0.01);
    assert_int_equal(f->calls, 0);   /* a primitive's distance needs no evaluator */
    const GeomMesh *b = mesh_of(f, 1);
    check_closed(b);
    for (uint32_t v = 0; v < b->npos; v++) {
        const double *p = b->pos + (size_t)v * 3;
        assert_true(fabs(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 0.5) < 0.05);
    }
    /* the grid: ceil(2 / 0.05) + 1 = 41 points a side, each called once;
     * then 6 points around each vertex for its normal, the gradient */
    assert_int_equal(f->calls, 41L * 41 * 41 + 6L * b->npos);
    for (uint32_t v = 0; v < b->npos; v++) {
        const double *p = b->pos + (size_t)v * 3;
        const float *nm = b->normal + (size_t)v * 3;
        double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        /* a sphere's gradient is its radius's direction; central
         * differences h = 0.0125 apart err by about (h / r)^2 = 6e-4 */
        for (int k = 0; k < 3; k++) assert_true(fabs(nm[k] - p[k] / r) < 2e-3);
    }
    assert_int_equal(f->nerrors, 0);
    fixture_free(f);
}

static void cache_hit_and_rebuild(void **state)
{
    (void)state;
    /* frame 1 and 2 have the same tree; from frame 3 the radius changes */
    Fixture *f = fixture("func ball(r)\n    func(p) hypot(p) - r\n"
                         "!sdf function=ball(0.5 if frame < 2 else 0.6) resolution=0.1\n"
                         "!union\n    !box\n    !sphere position=0.5;0;0 size=0.5+0.1*(frame >= 2)\n",
                         0);
    GeomModel *s1 = geom_model_of(f->models, top(f, 0), true), *u1 = geom_model_of(f->models, top(f, 1), true);
    assert_non_null(geom_model_mesh(f->models, s1));
    assert_non_null(geom_model_mesh(f->models, u1));
    long calls = f->calls;
    assert_true(calls > 0);
    size_t kept = geom_models_count(f->models);
    fl_step(f->rt);   /* frame 2: the same */
    geom_models_frame(f->models, NULL, 1, 300);
    GeomModel *s2 = geom_model_of(f->models, top(f, 0), true), *u2 = geom_model_of(f->models, top(f, 1), true);
    assert_ptr_equal(s1, s2);
    assert_ptr_equal(u1, u2);
    assert_ptr_equal(geom_model_mesh(f->models, s2), geom_model_mesh(f->models, s1));
    assert_int_equal(f->calls, calls);   /* no distance computed again */
    assert_int_equal(geom_models_count(f->models), kept);
    fl_step(f->rt);   /* frame 3: changed */
    geom_models_frame(f->models, NULL, 2, 300);
    GeomModel *s3 = geom_model_of(f->models, top(f, 0), true), *u3 = geom_model_of(f->models, top(f, 1), true);
    assert_ptr_not_equal(s3, s1);
    assert_ptr_not_equal(u3, u1);
    const GeomMesh *m3 = geom_model_mesh(f->models, s3);
    assert_non_null(m3);
    assert_true(f->calls > calls);
    for (uint32_t v = 0; v < m3->npos; v++) {
        const double *p = m3->pos + (size_t)v * 3;
        assert_true(fabs(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 0.6) < 0.1);
    }
    assert_non_null(geom_model_mesh(f->models, u3));
    /* the old models go once unused for longer than the cache's age */
    geom_models_frame(f->models, NULL, 1000, 300);
    assert_int_equal(geom_models_count(f->models), 0);
    assert_int_equal(f->nerrors, 0);
    fixture_free(f);
}

static void vectors_and_files(void **state)
{
    (void)state;
    char dir[] = "/tmp/geom_model_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[300], src[1200];
    snprintf(path, sizeof path, "%s/cube.obj", dir);
    FILE *o = fopen(path, "w");
    assert_non_null(o);
    /* the unit cube: 8 vertices, 6 quads (12 triangles), wound outwards */
    fputs("v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
          "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
          "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
          o);
    fclose(o);
    snprintf(src, sizeof src,
             "!model vertices=0;0;0;1;0;0;0;1;0;0;0;1 faces=0;2;1;0;1;3;0;3;2;1;2;3\n"
             "!model filename='%s'\n"
             "!model filename='%s/missing.obj'\n"
             "!difference\n    !model filename='%s'\n    !box position=0.5;0.5;0.5\n"
             "!model vertices=0;0;0;1;0;0;0;1;0 faces=0;1;7\n"
             "!mix\n    !box\n    !sphere\n",
             path, dir, path);
    Fixture *f = fixture(src, 0);
    const GeomMesh *t = mesh_of(f, 0);
    assert_int_equal(t->npos, 4);
    assert_int_equal(t->ntri, 4);
    assert_true(fabs(geom_mesh_volume(t) - 1.0 / 6) < 1e-12);
    const GeomMesh *c = mesh_of(f, 1);
    assert_non_null(c);
    assert_int_equal(c->ntri, 12);
    assert_int_equal(c->npos, 8);
    assert_true(fabs(geom_mesh_volume(c) - 1) < 1e-12);
    assert_null(mesh_of(f, 2));
    assert_non_null(strstr(f->errors, "missing.obj: cannot load model: no such file"));
    /* the cube less an eighth of it at one corner */
    const GeomMesh *d = mesh_of(f, 3);
    assert_true(fabs(geom_mesh_volume(d) - (1 - 0.125)) < 1e-9);
    assert_null(mesh_of(f, 4));
    assert_non_null(strstr(f->errors, "bad vertex index 7"));
    assert_null(mesh_of(f, 5));
    assert_non_null(strstr(f->errors, "only inside an !sdf"));
    /* asked again: not said again */
    int said = f->nerrors;
    assert_null(mesh_of(f, 2));
    assert_int_equal(f->nerrors, said);
    /* each said on one line, without a newline of its own */
    assert_null(strstr(f->errors, "\n\n"));
    fixture_free(f);
    unlink(path);
    rmdir(dir);
}

static void budget(void **state)
{
    (void)state;
    /* 200^3 points of grid cannot fit in 4 MB; the sphere beside it can */
    Fixture *f = fixture("!sdf resolution=0.01\n    !sphere\n!sdf resolution=0.2\n    !sphere\n", 4 << 20);
    assert_null(mesh_of(f, 0));
    assert_non_null(strstr(f->errors, "!sdf: "));
    assert_non_null(strstr(f->errors, "budget"));
    assert_non_null(mesh_of(f, 1));
    assert_true(f->budget.used > 0 && f->budget.used <= f->budget.limit);
    size_t used = f->budget.used;
    assert_int_equal(geom_models_bytes(f->models), used);
    geom_models_frame(f->models, NULL, 1000, 300);
    assert_int_equal(f->budget.used, 0);
    fixture_free(f);
}

/* A cylinder's and a cone's solid form (their caps fans from the rim) is
 * the drawn mesh's surface: closed once welded, the same volume, and no
 * vertex left at a cap's centre. */
static void primitive_solids(void **state)
{
    (void)state;
    int kinds[] = {MESH_CYLINDER, MESH_CONE};
    for (int k = 0; k < 2; k++)
        for (int segments = 4; segments <= 64; segments *= 4) {
            MeshKey key = {.kind = kinds[k], .segments = mesh_segments(kinds[k], segments)};
            GeomMesh drawn, solid;
            geom_primitive_mesh(&key, &drawn);
            geom_primitive_solid(&key, &solid);
            geom_mesh_weld(&drawn);
            geom_mesh_weld(&solid);
            assert_true(geom_mesh_is_closed(&solid));
            assert_true(fabs(geom_mesh_volume(&solid) - geom_mesh_volume(&drawn)) < 1e-12);
            assert_true(fabs(geom_mesh_area(&solid) - geom_mesh_area(&drawn)) < 1e-12);
            for (uint32_t v = 0; v < solid.npos; v++)   /* (but a cone's point) */
                assert_false(solid.pos[v * 3] == 0 && solid.pos[v * 3 + 1] == 0 &&
                             !(kinds[k] == MESH_CONE && solid.pos[v * 3 + 2] == 0.5));
            assert_int_equal(solid.npos, drawn.npos - (kinds[k] == MESH_CYLINDER ? 2 : 1));
            geom_mesh_free(&drawn);
            geom_mesh_free(&solid);
        }
}

static void primitive_counts(void **state)
{
    (void)state;
    /* mesh_counts (what the budget is asked for) is what mesh_build makes */
    int kinds[] = {MESH_BOX, MESH_SPHERE, MESH_CYLINDER, MESH_CONE, MESH_OCTAGON};
    int segments[] = {0, 3, 4, 7, 64, 100};
    for (size_t k = 0; k < 5; k++)
        for (size_t i = 0; i < 6; i++)
            for (int flat = 0; flat < 2; flat++) {
                MeshKey key = {.kind = kinds[k], .segments = mesh_segments(kinds[k], segments[i]), .flat = flat};
                uint64_t nv, ni;
                mesh_counts(&key, &nv, &ni);
                MeshData d;
                mesh_build(&key, &d);
                assert_int_equal(nv, d.nverts);
                assert_int_equal(ni, d.nindex);
                mesh_data_free(&d);
            }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(union_of_boxes),
        cmocka_unit_test(box_and_sphere),
        cmocka_unit_test(trim_through_rim),
        cmocka_unit_test(repair_mesh),
        cmocka_unit_test(repair_model),
        cmocka_unit_test(convex_hull),
        cmocka_unit_test(sdf_sphere),
        cmocka_unit_test(cache_hit_and_rebuild),
        cmocka_unit_test(vectors_and_files),
        cmocka_unit_test(budget),
        cmocka_unit_test(primitive_counts),
        cmocka_unit_test(primitive_solids),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
