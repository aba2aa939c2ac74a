/* geom_primitives.c: the primitive models' triangle meshes (see
 * geom_primitives.h).
 *
 * Every primitive is convex with its origin inside, so each triangle is
 * generated in any order and then turned to face away from the origin
 * (its normal's dot product with its centroid positive): one rule gives
 * counter-clockwise winding seen from outside for all four shapes. */
#include "geom_primitives.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"
#include "turns.h"


#define PI 3.141592653589793

/* A growing mesh. */
typedef struct Builder {
    MeshData m;
    uint32_t vcap, icap;
} Builder;

static uint32_t add_vertex(Builder *b, double x, double y, double z, double nx, double ny, double nz,
                           double u, double v)
{
    if (b->m.nverts == b->vcap) {
        b->vcap = b->vcap ? b->vcap * 2 : 64;
        b->m.verts = mem_realloc_array(b->m.verts, b->vcap, 8 * sizeof(float));
    }
    float *p = b->m.verts + (size_t)b->m.nverts * 8;
    double len = sqrt(nx * nx + ny * ny + nz * nz);
    if (len > 0) nx /= len, ny /= len, nz /= len;
    p[0] = (float)x, p[1] = (float)y, p[2] = (float)z;
    p[3] = (float)nx, p[4] = (float)ny, p[5] = (float)nz;
    p[6] = (float)u, p[7] = (float)v;
    return b->m.nverts++;
}

static const float *vert(const Builder *b, uint32_t i) { return b->m.verts + (size_t)i * 8; }

/* Add triangle a,b,c wound to face away from the origin (degenerate
 * triangles, of zero area, are dropped). */
static void add_tri(Builder *b, uint32_t i0, uint32_t i1, uint32_t i2)
{
    const float *a = vert(b, i0), *p = vert(b, i1), *q = vert(b, i2);
    double u[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double v[3] = {q[0] - a[0], q[1] - a[1], q[2] - a[2]};
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    if (n[0] == 0 && n[1] == 0 && n[2] == 0) return;
    double c[3] = {a[0] + p[0] + q[0], a[1] + p[1] + q[1], a[2] + p[2] + q[2]};
    double d = n[0] * c[0] + n[1] * c[1] + n[2] * c[2];
    if (d == 0) {   /* a face through the origin (2-segment cylinder, cone): its vertex normal decides */
        d = n[0] * a[3] + n[1] * a[4] + n[2] * a[5];
    }
    if (b->m.nindex + 3 > b->icap) {
        b->icap = b->icap ? b->icap * 2 : 192;
        b->m.index = mem_realloc_array(b->m.index, b->icap, sizeof(uint32_t));
    }
    uint32_t *t = b->m.index + b->m.nindex;
    t[0] = i0;
    t[1] = d >= 0 ? i1 : i2;
    t[2] = d >= 0 ? i2 : i1;
    b->m.nindex += 3;
}

static void add_quad(Builder *b, uint32_t a, uint32_t c, uint32_t d, uint32_t e)
{
    add_tri(b, a, c, d);
    add_tri(b, a, d, e);
}

int mesh_segments(int kind, int segments)
{
    if (kind == MESH_BOX) return 0;
    if (segments > 4096) segments = 4096;
    if (kind == MESH_SPHERE) {
        if (segments < 4) return 4;
        return (segments + 3) / 4 * 4;
    }
    return segments < 2 ? 2 : segments;
}

/* The unit cube as Flitter's docs/canvas3d.md "Primitive model texture
 * mapping" lays it on the texture: faces +X, -X, +Y, -Y, +Z, -Z from left
 * to right, each a sixth of the width (the whole of it with [repeat]),
 * seen from outside with y up (+Y: -z up, -Y: +z up). Each face's corner
 * is given by its coordinate along the face's u and v directions. */
static void build_box(Builder *b, bool repeat)
{
    /* per face: its normal axis and sign, then the axis and sign along u and along v */
    static const int faces[6][6] = {
        {0, +1, 2, -1, 1, +1}, {0, -1, 2, +1, 1, +1}, {1, +1, 0, +1, 2, -1},
        {1, -1, 0, +1, 2, +1}, {2, +1, 0, +1, 1, +1}, {2, -1, 0, -1, 1, +1},
    };
    for (int f = 0; f < 6; f++) {
        const int *d = faces[f];
        uint32_t k[4];
        for (int c = 0; c < 4; c++) {
            double tu = (c == 1 || c == 2) ? 1 : 0, tv = c >= 2 ? 1 : 0, p[3], n[3] = {0, 0, 0};
            p[d[0]] = 0.5 * d[1];
            p[d[2]] = (tu - 0.5) * d[3];
            p[d[4]] = (tv - 0.5) * d[5];
            n[d[0]] = d[1];
            k[c] = add_vertex(b, p[0], p[1], p[2], n[0], n[1], n[2], repeat ? tu : (f + tu) / 6, tv);
        }
        add_quad(b, k[0], k[1], k[2], k[3]);
    }
}

/* Eight octants of [n]/4 rows each, as Flitter's Sphere.build_arrays lays
 * them: quarter [side] of the longitude (turns side/4 .. (side+1)/4 from
 * +x towards +y) in each hemisphere; row 0 is the pole, row r has r+1
 * vertices at longitude (side + col/r)/4 and latitude (1 - r/rows)/4
 * turns; texture u is the longitude, v = 0.5 + 2 latitude (the
 * equirectangular projection, the pole's vertex at its octant's middle
 * longitude). Each octant has its own vertices, so the map's seam at u = 1
 * is exact. */
static void build_sphere(Builder *b, int n)
{
    int rows = n / 4;
    uint32_t *prev = mem_alloc(sizeof(uint32_t) * (size_t)(rows + 1));
    uint32_t *cur = mem_alloc(sizeof(uint32_t) * (size_t)(rows + 1));
    for (int side = 0; side < 4; side++)
        for (int hemi = -1; hemi <= 1; hemi += 2) {
            for (int row = 0; row <= rows; row++) {
                double r, z, v;
                if (row == 0) {
                    r = 0, z = hemi, v = hemi * 0.5 + 0.5;
                } else if (row == rows) {
                    r = 1, z = 0, v = 0.5;
                } else {
                    double th = hemi * (1 - (double)row / rows) / 4;
                    v = 2 * th + 0.5;
                    r = cos_t(th), z = sin_t(th);
                }
                for (int col = 0; col <= row; col++) {
                    double u, x, y;
                    if (row == 0) {
                        u = (side + 0.5) / 4, x = y = 0;
                    } else if (col == 0) {
                        u = side / 4.0;
                        x = side == 0 ? r : side == 2 ? -r : 0;
                        y = side == 1 ? r : side == 3 ? -r : 0;
                    } else if (col == row) {
                        u = (side + 1.0) / 4;
                        x = side == 3 ? r : side == 1 ? -r : 0;
                        y = side == 0 ? r : side == 2 ? -r : 0;
                    } else {
                        u = (side + (double)col / row) / 4;
                        x = r * cos_t(u), y = r * sin_t(u);
                    }
                    cur[col] = add_vertex(b, x, y, z, x, y, z, u, v);
                    if (col) {
                        add_tri(b, cur[col], cur[col - 1], prev[col - 1]);
                        if (col < row) add_tri(b, cur[col], prev[col - 1], prev[col]);
                    }
                }
                uint32_t *t = prev;
                prev = cur;
                cur = t;
            }
        }
    free(prev);
    free(cur);
}

/* A cylinder, or a cone: the top ring shrunk to the point, with side
 * normals leaning up by 45 degrees (the unit cone falls 1 in radius over 1
 * in height). */
static void build_round(Builder *b, int n, bool cone, bool rim_caps)
{
    /* rim_caps: each cap a fan from the rim's first point instead of its
     * centre (the triangles at that point have no area and are dropped) */
    double cx = rim_caps ? 1 : 0;
    for (int i = 0; i < n; i++) {
        /* angles in turns with exact quadrants (turns.h): the last
         * segment ends where the first begins, so the mesh is closed once
         * welded, and the rim's points at a quarter turn lie exactly on
         * the axes (cos(pi/2) is 6e-17 in radians: a trim along an axis
         * then left slivers of that width, which CGAL's corefinement
         * failed on) */
        double a0 = (double)i / n, a1 = i + 1 == n ? 0 : (double)(i + 1) / n;
        double am = (a0 + (i + 1 == n ? 1 : a1)) / 2;
        double c0 = cos_t(a0), s0 = sin_t(a0), c1 = cos_t(a1), s1 = sin_t(a1);
        double u0 = (double)i / n, u1 = (double)(i + 1) / n;
        double nz = cone ? 1 : 0;
        uint32_t b0 = add_vertex(b, c0, s0, -0.5, c0, s0, nz, u0, 0.25);
        uint32_t b1 = add_vertex(b, c1, s1, -0.5, c1, s1, nz, u1, 0.25);
        if (cone) {
            uint32_t t = add_vertex(b, 0, 0, 0.5, cos_t(am), sin_t(am), 1, (u0 + u1) / 2, 1);
            add_tri(b, b0, b1, t);
        } else {
            uint32_t t0 = add_vertex(b, c0, s0, 0.5, c0, s0, 0, u0, 0.75);
            uint32_t t1 = add_vertex(b, c1, s1, 0.5, c1, s1, 0, u1, 0.75);
            add_quad(b, b0, b1, t1, t0);
            uint32_t tc = add_vertex(b, cx, 0, 0.5, 0, 0, 1, (u0 + u1) / 2, 1);
            uint32_t e0 = add_vertex(b, c0, s0, 0.5, 0, 0, 1, u0, 0.75);
            uint32_t e1 = add_vertex(b, c1, s1, 0.5, 0, 0, 1, u1, 0.75);
            add_tri(b, tc, e0, e1);
        }
        uint32_t bc = add_vertex(b, cx, 0, -0.5, 0, 0, -1, (u0 + u1) / 2, 0);
        uint32_t f0 = add_vertex(b, c0, s0, -0.5, 0, 0, -1, u0, 0.25);
        uint32_t f1 = add_vertex(b, c1, s1, -0.5, 0, 0, -1, u1, 0.25);
        add_tri(b, bc, f0, f1);
    }
}

/* The octagon around the unit circle: a centre and eight rim vertices at
 * 1/cos(pi/8), a fan of eight triangles. */
static void build_octagon(Builder *b)
{
    double r = 1 / cos(PI / 8);
    uint32_t c = add_vertex(b, 0, 0, 0, 0, 0, 1, 0.5, 0.5), rim[8];
    for (int i = 0; i < 8; i++) {
        double a = PI / 8 + PI / 4 * i;
        rim[i] = add_vertex(b, r * cos(a), r * sin(a), 0, 0, 0, 1, 0.5 + 0.5 * cos(a), 0.5 + 0.5 * sin(a));
    }
    for (int i = 0; i < 8; i++) add_tri(b, c, rim[i], rim[(i + 1) % 8]);
}

/* Every triangle its own three vertices with the face normal. */
static void flatten(Builder *b)
{
    Builder f = {0};
    for (uint32_t t = 0; t + 2 < b->m.nindex; t += 3) {
        const float *p[3] = {vert(b, b->m.index[t]), vert(b, b->m.index[t + 1]), vert(b, b->m.index[t + 2])};
        double u[3], v[3];
        for (int k = 0; k < 3; k++) u[k] = p[1][k] - p[0][k], v[k] = p[2][k] - p[0][k];
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        uint32_t k3[3];
        for (int k = 0; k < 3; k++)
            k3[k] = add_vertex(&f, p[k][0], p[k][1], p[k][2], n[0], n[1], n[2], p[k][6], p[k][7]);
        add_tri(&f, k3[0], k3[1], k3[2]);
    }
    mesh_data_free(&b->m);
    *b = f;
}

static void invert(Builder *b)
{
    for (uint32_t i = 0; i < b->m.nverts; i++)
        for (int k = 3; k < 6; k++) b->m.verts[(size_t)i * 8 + k] = -b->m.verts[(size_t)i * 8 + k];
    for (uint32_t t = 0; t + 2 < b->m.nindex; t += 3) {
        uint32_t s = b->m.index[t + 1];
        b->m.index[t + 1] = b->m.index[t + 2];
        b->m.index[t + 2] = s;
    }
}

void mesh_counts(const MeshKey *key, uint64_t *nverts, uint64_t *nindex)
{
    uint64_t n = (uint64_t)key->segments, v, t;
    switch (key->kind) {
    case MESH_SPHERE: {
        uint64_t rows = n / 4;
        v = 8 * (rows + 1) * (rows + 2) / 2;
        t = 8 * rows * rows;
        break;
    }
    /* two segments make flat caps of no area, which add_tri drops */
    case MESH_CYLINDER: v = 10 * n, t = n == 2 ? 2 * n : 4 * n; break;
    case MESH_CONE: v = 6 * n, t = n == 2 ? n : 2 * n; break;
    case MESH_OCTAGON: v = 9, t = 8; break;
    default: v = 24, t = 12; break;
    }
    if (key->flat) v = 3 * t;
    *nverts = v;
    *nindex = 3 * t;
}

static void build(const MeshKey *key, bool rim_caps, MeshData *out)
{
    Builder b = {0};
    switch (key->kind) {
    case MESH_SPHERE: build_sphere(&b, key->segments); break;
    case MESH_CYLINDER: build_round(&b, key->segments, false, rim_caps); break;
    case MESH_CONE: build_round(&b, key->segments, true, rim_caps); break;
    case MESH_OCTAGON: build_octagon(&b); break;
    default: build_box(&b, key->uv_repeat); break;
    }
    if (key->flat) flatten(&b);
    if (key->invert) invert(&b);
    *out = b.m;
}

void mesh_build(const MeshKey *key, MeshData *out) { build(key, false, out); }

void mesh_data_free(MeshData *m)
{
    free(m->verts);
    free(m->index);
    memset(m, 0, sizeof *m);
}

static void to_geom_mesh(const MeshKey *key, bool rim_caps, GeomMesh *out)
{
    MeshData d;
    build(key, rim_caps, &d);
    memset(out, 0, sizeof *out);
    size_t n = d.nverts ? d.nverts : 1;
    out->pos = mem_alloc(n * 3 * sizeof(double));
    out->normal = mem_alloc(n * 3 * sizeof(float));
    out->uv = mem_alloc(n * 2 * sizeof(float));
    for (uint32_t i = 0; i < d.nverts; i++) {
        const float *v = d.verts + (size_t)i * 8;
        for (int k = 0; k < 3; k++) out->pos[(size_t)i * 3 + k] = v[k], out->normal[(size_t)i * 3 + k] = v[3 + k];
        out->uv[(size_t)i * 2] = v[6];
        out->uv[(size_t)i * 2 + 1] = v[7];
    }
    out->npos = d.nverts;
    out->tri = d.index;
    out->ntri = d.nindex / 3;
    d.index = NULL;
    mesh_data_free(&d);
}

void geom_primitive_mesh(const MeshKey *key, GeomMesh *out) { to_geom_mesh(key, false, out); }

void geom_primitive_solid(const MeshKey *key, GeomMesh *out) { to_geom_mesh(key, true, out); }
