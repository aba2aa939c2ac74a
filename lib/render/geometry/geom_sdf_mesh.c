/* geom_sdf_mesh.c: the zero level set of a signed distance field as a
 * closed triangle mesh, by marching tetrahedra (see geom_sdf_mesh.h; the
 * node is Flitter's `!sdf`, docs/canvas3d.md, "Signed Distance Fields").
 *
 * The grid is walked one plane of constant z at a time. Around the real
 * grid lies a layer of "padding" points at distance +infinity (the space
 * outside the box is outside), so the grid the tetrahedra see has
 * count + 2 points per axis: padded index p is real index p - 1, and
 * indices 0 and count + 1 are padding. Only two padded planes of
 * distances are held (the lower and the upper of the current slab of
 * cubes), with the vertex indices of the edges that start in them.
 *
 * The cube split: the cube's corner c (0..7) lies at offset (c & 1,
 * c >> 1 & 1, c >> 2 & 1). Each of the 6 tetrahedra is a path from corner
 * 0 to corner 7 along the three axes in one of their 6 orders, so each
 * edge of a tetrahedron joins corner a to corner b with a a subset of b's
 * bits: the edge is named by its lower grid point and its direction
 * b ^ a (1..7), one of the 7 edges every grid point starts. Edges in the
 * plane (directions 1, 2, 3) are kept per plane; edges that climb to the
 * next plane (4..7) are kept for the current slab.
 */
#include "geom_sdf_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"

#define NO_VERTEX UINT32_MAX
/* the largest vertex or triangle count kept (UINT32_MAX marks "none") */
#define MAX_ELEMENTS (UINT32_MAX - 1u)

/* The 6 tetrahedra of a cube as cube corners, each ordered so that its
 * orientation is positive (det(v1 - v0, v2 - v0, v3 - v0) > 0): the paths
 * x-y-z, y-z-x and z-x-y are even permutations of the axes and keep their
 * order 0, a, a|b, 7; the odd ones (x-z-y, y-x-z, z-y-x) have their two
 * middle corners swapped. */
static const unsigned char TETS[6][4] = {
    {0, 1, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}, {0, 3, 2, 7}, {0, 6, 4, 7},
};

/* Per inside-mask of a tetrahedron's 4 corners (bit i: corner i inside):
 * how many are inside (0 and 4: no surface) and an even permutation of
 * the corners (so still positively oriented) that puts the odd one out
 * first (1 or 3 inside) or the two inside first (2 inside). */
typedef struct TetCase {
    unsigned char inside;
    unsigned char order[4];
} TetCase;

static const TetCase CASES[16] = {
    {0, {0, 1, 2, 3}}, /* 0000 */
    {1, {0, 1, 2, 3}}, /* 0001 */
    {1, {1, 0, 3, 2}}, /* 0010 */
    {2, {0, 1, 2, 3}}, /* 0011 */
    {1, {2, 3, 0, 1}}, /* 0100 */
    {2, {0, 2, 3, 1}}, /* 0101 */
    {2, {1, 2, 0, 3}}, /* 0110 */
    {3, {3, 2, 1, 0}}, /* 0111 */
    {1, {3, 2, 1, 0}}, /* 1000 */
    {2, {0, 3, 1, 2}}, /* 1001 */
    {2, {1, 3, 2, 0}}, /* 1010 */
    {3, {2, 3, 0, 1}}, /* 1011 */
    {2, {2, 3, 0, 1}}, /* 1100 */
    {3, {1, 0, 3, 2}}, /* 1101 */
    {3, {0, 1, 2, 3}}, /* 1110 */
    {0, {0, 1, 2, 3}}, /* 1111 */
};

/* {===== the grid */

typedef enum GridStatus { GRID_OK, GRID_BAD_RESOLUTION, GRID_BAD_BOUNDS, GRID_BUDGET } GridStatus;

/* One axis's count, or 0 when it would pass UINT32_MAX; [approx] gets
 * the count as a double either way (for the budget message). */
static uint32_t axis_count(double lo, double hi, double res, double *approx)
{
    double q = (hi - lo) / res;   /* >= 0; +inf when the span overflows */
    if (!(q < (double)UINT32_MAX - 4)) {
        *approx = floor(q) + 1;
        return 0;
    }
    uint64_t n = (uint64_t)ceil(q) + 1;
    /* the smallest n whose last point lo + (n-1)*res is at or past hi as
     * computed; the quotient's rounding is off by at most one step */
    for (int k = 0; k < 2 && n > 1 && lo + (double)(n - 2) * res >= hi; k++) n--;
    for (int k = 0; k < 2 && lo + (double)(n - 1) * res < hi; k++) n++;
    *approx = (double)n;
    return (uint32_t)n;
}

/* The counts (untouched unless GRID_OK) and the number of points as a
 * double (for messages; may be +inf). */
static GridStatus grid_counts(const double min[3], const double max[3], double res, uint64_t max_points,
                              uint32_t count[3], double *points)
{
    *points = 0;
    if (!(res > 0) || !isfinite(res)) return GRID_BAD_RESOLUTION;
    for (int a = 0; a < 3; a++)
        if (!isfinite(min[a]) || !isfinite(max[a]) || max[a] < min[a]) return GRID_BAD_BOUNDS;
    uint32_t n[3];
    double approx[3];
    bool fits = true;
    for (int a = 0; a < 3; a++) {
        n[a] = axis_count(min[a], max[a], res, &approx[a]);
        if (n[a] == 0) fits = false;
    }
    *points = approx[0] * approx[1] * approx[2];
    if (fits) {
        uint64_t p = (uint64_t)n[0] * n[1];   /* < 2^64: both < 2^32 */
        if (p > max_points / n[2]) fits = false;
        else *points = (double)(p * n[2]);
    }
    if (!fits) return GRID_BUDGET;
    memcpy(count, n, sizeof n);
    return GRID_OK;
}

bool geom_sdf_grid(const double min[3], const double max[3], double resolution, uint64_t max_points,
                   uint32_t count[3])
{
    double points;
    return grid_counts(min, max, resolution, max_points, count, &points) == GRID_OK;
}

/* }===== */

/* {===== the mesher */

typedef struct Mesher {
    size_t w, h, cells;      /* padded plane: w * h = cells */
    const double *xs, *ys;   /* real coordinates per axis */
    double z0, z1;           /* real z of the lower and upper planes (when real) */
    const double *val[2];    /* distances of the lower and upper padded planes */
    uint32_t *pt[2];         /* vertices at the grid points of the lower and upper
                                planes: cells each */
    uint32_t *ip[2];         /* vertices of the in-plane edges (directions 1, 2, 3)
                                starting in the lower and upper planes: 3 * cells */
    uint32_t *cr;            /* vertices of the edges from the lower plane to the
                                upper (directions 4..7): 4 * cells */
    double *pos;             /* npos * 3 */
    size_t npos, pcap;       /* pcap: the first capacity until pos is made */
    uint32_t *tri;           /* ntri * 3 */
    size_t ntri, tcap;       /* tcap: the same */
    uint32_t *points;        /* the vertices that lie on grid points */
    size_t npoints, ptcap;
    bool dropped;            /* a degenerate triangle was left out */
    bool full;               /* a count passed MAX_ELEMENTS */
} Mesher;

/* The real position of corner [c] of the cube whose lowest padded corner
 * is ([px], [py]) in the current slab (never a padding point). */
static void corner_pos(const Mesher *m, size_t px, size_t py, int c, double p[3])
{
    p[0] = m->xs[px + (c & 1) - 1];
    p[1] = m->ys[py + (c >> 1 & 1) - 1];
    p[2] = c & 4 ? m->z1 : m->z0;
}

static uint32_t new_vertex(Mesher *m, const double p[3], bool at_point)
{
    if (m->npos >= MAX_ELEMENTS) {
        m->full = true;
        return 0;
    }
    if (!m->pos || m->npos == m->pcap) {
        if (m->pos) m->pcap *= 2;
        m->pos = mem_realloc_array(m->pos, m->pcap, 3 * sizeof(double));
    }
    if (at_point) {
        if (m->npoints == m->ptcap) {
            m->ptcap = m->ptcap ? m->ptcap * 2 : 256;
            m->points = mem_realloc_array(m->points, m->ptcap, sizeof(uint32_t));
        }
        m->points[m->npoints++] = (uint32_t)m->npos;
    }
    memcpy(m->pos + m->npos * 3, p, 3 * sizeof(double));
    return (uint32_t)m->npos++;
}

/* The one vertex at cube corner [c]'s grid point. */
static uint32_t point_vertex(Mesher *m, size_t px, size_t py, int c)
{
    uint32_t *slot = m->pt[c >> 2] + (py + (c >> 1 & 1)) * m->w + px + (c & 1);
    if (*slot == NO_VERTEX) {
        double p[3];
        corner_pos(m, px, py, c, p);
        *slot = new_vertex(m, p, true);
    }
    return *slot;
}

/* The vertex of the edge from cube corner [ca] to [cb] (one inside, one
 * outside) of the cube at padded ([px], [py]) with corner distances [v]:
 * made on first use, shared after. A vertex that falls on an end of the
 * edge, or whose interpolation rounds onto an end's coordinate on an axis
 * along which the edge runs, is that end's grid point vertex: so no two
 * vertices ever share a position (the grid's coordinates being strictly
 * increasing, a vertex strictly inside its edge on every axis the edge
 * runs along lies on no other edge). */
static uint32_t edge_vertex(Mesher *m, size_t px, size_t py, const double v[8], int ca, int cb)
{
    int lo = ca & cb, hi = ca | cb, dir = lo ^ hi;
    size_t cell = (py + (lo >> 1 & 1)) * m->w + px + (lo & 1);
    uint32_t *slot = dir & 4 ? m->cr + (size_t)(dir & 3) * m->cells + cell
                             : m->ip[lo >> 2] + (size_t)(dir - 1) * m->cells + cell;
    if (*slot != NO_VERTEX) return *slot;
    int cin = v[lo] < 0 ? lo : hi, cout = cin == lo ? hi : lo;
    double din = v[cin], dout = v[cout];
    int snap = -1;   /* the corner the vertex lies on, if any */
    double p[3];
    if (!(dout < INFINITY)) {
        snap = cin;   /* padding, +inf or NaN outside */
    } else if (din == -INFINITY) {
        snap = cout;
    } else {
        double a = -din, b = dout, t = a / (a + b);   /* a > 0, b >= 0 */
        if (!isfinite(a + b)) t = 1 / (1 + b / a);
        if (t >= 1) {
            snap = cout;
        } else {
            double pi[3], po[3];
            corner_pos(m, px, py, cin, pi);
            corner_pos(m, px, py, cout, po);
            for (int k = 0; k < 3 && snap < 0; k++) {
                if (pi[k] == po[k]) {
                    p[k] = pi[k];
                    continue;
                }
                double r = (1 - t) * pi[k] + t * po[k];
                bool up = pi[k] < po[k];
                if (up ? r <= pi[k] : r >= pi[k]) snap = cin;
                else if (up ? r >= po[k] : r <= po[k]) snap = cout;
                else p[k] = r;
            }
        }
    }
    *slot = snap >= 0 ? point_vertex(m, px, py, snap) : new_vertex(m, p, false);
    return *slot;
}

static void add_tri(Mesher *m, uint32_t a, uint32_t b, uint32_t c)
{
    if (a == b || b == c || a == c) {
        m->dropped = true;
        return;
    }
    if (m->ntri >= MAX_ELEMENTS) {
        m->full = true;
        return;
    }
    if (!m->tri || m->ntri == m->tcap) {
        if (m->tri) m->tcap *= 2;
        m->tri = mem_realloc_array(m->tri, m->tcap, 3 * sizeof(uint32_t));
    }
    uint32_t *t = m->tri + m->ntri * 3;
    t[0] = a, t[1] = b, t[2] = c;
    m->ntri++;
}

static double dist2(const Mesher *m, uint32_t a, uint32_t b)
{
    const double *p = m->pos + (size_t)a * 3, *q = m->pos + (size_t)b * 3;
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return dx * dx + dy * dy + dz * dz;
}

/* The triangles of one tetrahedron [q] (cube corners, positive order) of
 * the cube at padded ([px], [py]), wound so that their normal points from
 * the inside corners to the outside ones. */
static void tetrahedron(Mesher *m, size_t px, size_t py, const double v[8], unsigned mask, const unsigned char q[4])
{
    unsigned tm = (mask >> q[0] & 1) | (mask >> q[1] & 1) << 1 | (mask >> q[2] & 1) << 2 | (mask >> q[3] & 1) << 3;
    const TetCase *cs = &CASES[tm];
    if (cs->inside == 0) return;
    int a = q[cs->order[0]], b = q[cs->order[1]], c = q[cs->order[2]], d = q[cs->order[3]];
    if (cs->inside == 1 || cs->inside == 3) {
        /* the triangle around corner a, facing away from it (one inside)
         * or towards it (a the one outside) */
        uint32_t ab = edge_vertex(m, px, py, v, a, b), ac = edge_vertex(m, px, py, v, a, c),
                 ad = edge_vertex(m, px, py, v, a, d);
        if (m->full) return;
        if (cs->inside == 1) add_tri(m, ab, ac, ad);
        else add_tri(m, ab, ad, ac);
        return;
    }
    /* a and b inside: the quad ac, ad, bd, bc, cut along its shorter
     * diagonal */
    uint32_t ac = edge_vertex(m, px, py, v, a, c), ad = edge_vertex(m, px, py, v, a, d),
             bd = edge_vertex(m, px, py, v, b, d), bc = edge_vertex(m, px, py, v, b, c);
    if (m->full) return;
    if (dist2(m, ac, bd) <= dist2(m, ad, bc)) {
        add_tri(m, ac, ad, bd);
        add_tri(m, ac, bd, bc);
    } else {
        add_tri(m, ac, ad, bc);
        add_tri(m, ad, bd, bc);
    }
}

/* Every cube between the lower and the upper plane. */
static void slab(Mesher *m)
{
    const double *lo = m->val[0], *up = m->val[1];
    size_t w = m->w;
    for (size_t py = 0; py + 1 < m->h; py++) {
        const double *l0 = lo + py * w, *l1 = l0 + w, *u0 = up + py * w, *u1 = u0 + w;
        for (size_t px = 0; px + 1 < w; px++) {
            double v[8] = {l0[px], l0[px + 1], l1[px], l1[px + 1], u0[px], u0[px + 1], u1[px], u1[px + 1]};
            unsigned mask = 0;
            for (int c = 0; c < 8; c++) mask |= (unsigned)(v[c] < 0) << c;
            if (mask == 0 || mask == 255) continue;
            for (int t = 0; t < 6 && !m->full; t++) tetrahedron(m, px, py, v, mask, TETS[t]);
            if (m->full) return;
        }
    }
}

/* {===== zero-thickness sheets */

/* A triangle touching a grid point vertex, by its corners in increasing
 * order and the parity of its winding relative to that order. */
typedef struct TriKey {
    uint32_t v[3];
    uint32_t index;
    uint32_t odd;
} TriKey;

static int trikey_cmp(const void *pa, const void *pb)
{
    const TriKey *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->v[k] != b->v[k]) return a->v[k] < b->v[k] ? -1 : 1;
    if (a->odd != b->odd) return a->odd < b->odd ? -1 : 1;
    return a->index < b->index ? -1 : a->index > b->index;
}

/* Remove pairs of triangles on the same three vertices wound opposite
 * ways: where the shape is one grid point thick against the box, or
 * against NaN or +infinity, both of its sides collapse onto the same
 * grid points, a sheet of no volume whose every edge would have four
 * triangles. Only a triangle with a corner on a grid point can be one of
 * such a pair (the three edge vertices of any other triangle lie on
 * three edges of its tetrahedron that share no face). Returns whether any
 * was removed. */
static bool cancel_sheets(Mesher *m)
{
    if (m->npoints == 0 || m->ntri < 2) return false;
    unsigned char *at_point = mem_calloc(m->npos, 1);
    for (size_t i = 0; i < m->npoints; i++) at_point[m->points[i]] = 1;
    size_t n = 0;
    for (size_t t = 0; t < m->ntri; t++) {
        const uint32_t *c = m->tri + t * 3;
        n += at_point[c[0]] || at_point[c[1]] || at_point[c[2]];
    }
    TriKey *keys = mem_alloc((n ? n : 1) * sizeof *keys);
    n = 0;
    for (size_t t = 0; t < m->ntri; t++) {
        const uint32_t *c = m->tri + t * 3;
        if (!(at_point[c[0]] || at_point[c[1]] || at_point[c[2]])) continue;
        /* rotate the smallest corner first; the winding is then even when
         * the other two follow in increasing order */
        int r = c[0] < c[1] ? (c[0] < c[2] ? 0 : 2) : (c[1] < c[2] ? 1 : 2);
        uint32_t a = c[r], b = c[(r + 1) % 3], d = c[(r + 2) % 3];
        TriKey *k = &keys[n++];
        k->v[0] = a, k->v[1] = b < d ? b : d, k->v[2] = b < d ? d : b;
        k->odd = b > d;
        k->index = (uint32_t)t;
    }
    free(at_point);
    qsort(keys, n, sizeof *keys, trikey_cmp);
    bool removed = false;
    for (size_t i = 0; i < n;) {
        size_t j = i, odd = i;
        while (j < n && memcmp(keys[j].v, keys[i].v, sizeof keys[i].v) == 0) j++;
        while (odd < j && !keys[odd].odd) odd++;
        /* keys[i..odd) even, keys[odd..j) odd: cancel them in pairs */
        size_t pairs = odd - i < j - odd ? odd - i : j - odd;
        for (size_t p = 0; p < pairs; p++) {
            m->tri[(size_t)keys[i + p].index * 3] = NO_VERTEX;
            m->tri[(size_t)keys[odd + p].index * 3] = NO_VERTEX;
            removed = true;
        }
        i = j;
    }
    free(keys);
    if (removed) {
        size_t kept = 0;
        for (size_t t = 0; t < m->ntri; t++) {
            if (m->tri[t * 3] == NO_VERTEX) continue;
            memmove(m->tri + kept * 3, m->tri + t * 3, 3 * sizeof(uint32_t));
            kept++;
        }
        m->ntri = kept;
    }
    return removed;
}

/* }===== */

/* Drop the vertices no triangle uses (one that only left-out triangles
 * had), keeping the others' order. */
static void drop_unused(Mesher *m)
{
    if (m->npos == 0) return;
    uint32_t *map = mem_alloc(m->npos * sizeof *map);
    memset(map, 0xff, m->npos * sizeof *map);
    for (size_t i = 0; i < m->ntri * 3; i++) map[m->tri[i]] = 0;
    size_t n = 0;
    for (size_t i = 0; i < m->npos; i++) {
        if (map[i] == NO_VERTEX) continue;
        if (n != i) memcpy(m->pos + n * 3, m->pos + i * 3, 3 * sizeof(double));
        map[i] = (uint32_t)n++;
    }
    for (size_t i = 0; i < m->ntri * 3; i++) m->tri[i] = map[m->tri[i]];
    m->npos = n;
    free(map);
}

/* }===== */

/* -1 with [message] appended to [err] (may be NULL) as one line. */
static int fail(Buf *err, const char *message)
{
    if (err) buf_printf(err, "%s\n", message);
    return -1;
}

static bool mul_size(size_t a, size_t b, size_t *r)
{
    if (a && b > SIZE_MAX / a) return false;
    *r = a * b;
    return true;
}

int geom_sdf_mesh(GeomDistanceFn f, void *ctx, const double min[3], const double max[3], double resolution,
                  uint64_t max_points, volatile int *interrupt, GeomMesh *out, Buf *err)
{
    memset(out, 0, sizeof *out);
    if (!f) return fail(err, "no distance function");
    uint32_t count[3];
    double points;
    switch (grid_counts(min, max, resolution, max_points, count, &points)) {
    case GRID_OK:
        break;
    case GRID_BAD_RESOLUTION:
        if (err) buf_printf(err, "bad resolution %g\n", resolution);
        return -1;
    case GRID_BAD_BOUNDS:
        return fail(err, "bad bounds");
    case GRID_BUDGET:
        if (err) {
            if (points < 0x1p63)
                buf_printf(err, "resolution %g gives %llu points, more than the budget of %llu\n", resolution,
                           (unsigned long long)points, (unsigned long long)max_points);
            else
                buf_printf(err, "resolution %g gives %.3g points, more than the budget of %llu\n", resolution,
                           points, (unsigned long long)max_points);
        }
        return -1;
    }

    size_t nx = count[0], ny = count[1], nz = count[2], w = nx + 2, h = ny + 2, cells, plane, bytes;
    if (!mul_size(w, h, &cells) || !mul_size(nx, ny, &plane) || !mul_size(cells, 12 * sizeof(uint32_t), &bytes) ||
        !mul_size(plane, 3 * sizeof(double), &bytes) || !mul_size(cells, 2 * sizeof(double), &bytes))
        return fail(err, "the mesh has too many vertices or triangles");

    /* the grid's coordinates, which must be strictly increasing (a
     * resolution below the precision of the bounds would give planes on
     * top of each other) */
    double *coords = mem_alloc((nx + ny + nz) * sizeof(double));
    double *xs = coords, *ys = coords + nx, *zs = ys + ny;
    const size_t n3[3] = {nx, ny, nz};
    double *axes[3] = {xs, ys, zs};
    for (int a = 0; a < 3; a++)
        for (size_t i = 0; i < n3[a]; i++) {
            axes[a][i] = min[a] + (double)i * resolution;
            if (i && !(axes[a][i] > axes[a][i - 1])) {
                free(coords);
                if (err) buf_printf(err, "resolution %g is below the precision of the bounds\n", resolution);
                return -1;
            }
        }

    /* the sample buffers, two padded planes of distances and the vertices
     * of their grid points and edges: O(nx * ny) */
    double *xyz = mem_alloc(plane * 3 * sizeof(double));
    double *dist = mem_alloc(plane * sizeof(double));
    double *vals = mem_alloc(cells * 2 * sizeof(double));
    uint32_t *slots = mem_alloc(cells * 12 * sizeof(uint32_t));
    for (size_t i = 0; i < cells * 2; i++) vals[i] = INFINITY;
    memset(slots, 0xff, cells * 12 * sizeof(uint32_t));

    /* first capacities for the mesh: a closed surface across the grid has
     * about 9 vertices and 18 triangles per grid column (a sphere filling
     * it), a few times more when folded; the pages a capacity reserves
     * cost nothing until written, each doubling costs a copy, and the
     * arrays are cut to size at the end */
    size_t guess = plane < ((size_t)1 << 16) ? plane : (size_t)1 << 16;
    Mesher m = {.w = w, .h = h, .cells = cells, .xs = xs, .ys = ys, .pcap = 1024 + guess * 16, .tcap = 1024 + guess * 32};
    double *pv[2] = {vals, vals + cells};   /* lower, upper */
    m.pt[0] = slots;
    m.pt[1] = slots + cells;
    m.ip[0] = slots + cells * 2;
    m.ip[1] = slots + cells * 5;
    m.cr = slots + cells * 8;

    const char *failure = NULL;
    /* the slab between padded planes pz - 1 and pz; padded plane 0 (the
     * lower one first) and nz + 1 are padding */
    for (size_t pz = 1; pz <= nz + 1 && !failure; pz++) {
        double *upper = pv[1];
        if (pz <= nz) {
            if (interrupt && *interrupt) {
                failure = "interrupted";
                break;
            }
            double z = zs[pz - 1];
            for (size_t j = 0, k = 0; j < ny; j++)
                for (size_t i = 0; i < nx; i++, k++) {
                    double *p = xyz + k * 3;
                    p[0] = xs[i], p[1] = ys[j], p[2] = z;
                }
            if (!f(ctx, xyz, plane, dist)) {
                failure = interrupt && *interrupt ? "interrupted" : "distance function failed";
                break;
            }
            for (size_t j = 0; j < ny; j++) memcpy(upper + (j + 1) * w + 1, dist + j * nx, nx * sizeof(double));
            m.z1 = z;
        } else {
            for (size_t i = 0; i < cells; i++) upper[i] = INFINITY;
        }
        memset(m.pt[1], 0xff, cells * sizeof(uint32_t));
        memset(m.ip[1], 0xff, cells * 3 * sizeof(uint32_t));
        memset(m.cr, 0xff, cells * 4 * sizeof(uint32_t));
        m.val[0] = pv[0];
        m.val[1] = upper;
        slab(&m);
        if (m.full) failure = "the mesh has too many vertices or triangles";
        /* the upper plane becomes the lower one */
        double *tv = pv[0];
        pv[0] = pv[1], pv[1] = tv;
        uint32_t *tp = m.pt[0], *te = m.ip[0];
        m.pt[0] = m.pt[1], m.pt[1] = tp;
        m.ip[0] = m.ip[1], m.ip[1] = te;
        m.z0 = m.z1;
    }
    free(coords);
    free(xyz);
    free(dist);
    free(vals);
    free(slots);
    if (failure) {
        free(m.pos);
        free(m.points);
        free(m.tri);
        return fail(err, failure);
    }

    bool cancelled = cancel_sheets(&m);
    free(m.points);
    if (m.ntri == 0) {
        free(m.pos);
        free(m.tri);
        return 0;
    }
    if (m.dropped || cancelled) drop_unused(&m);
    out->pos = mem_realloc_array(m.pos, m.npos, 3 * sizeof(double));
    out->npos = (uint32_t)m.npos;
    out->tri = mem_realloc_array(m.tri, m.ntri, 3 * sizeof(uint32_t));
    out->ntri = (uint32_t)m.ntri;
    return 0;
}
