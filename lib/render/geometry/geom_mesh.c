/* geom_mesh.c: indexed triangle meshes in double precision (see
 * geom_mesh.h). */
#include "geom_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"

void geom_mesh_free(GeomMesh *m)
{
    if (!m) return;
    free(m->pos);
    free(m->uv);
    free(m->normal);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

uint32_t geom_mesh_add_pos(GeomMesh *m, uint32_t *pcap, double x, double y, double z)
{
    if (m->npos == *pcap) {
        *pcap = *pcap ? *pcap * 2 : 64;
        m->pos = mem_realloc_array(m->pos, *pcap, 3 * sizeof(double));
        if (m->uv) m->uv = mem_realloc_array(m->uv, *pcap, 2 * sizeof(float));
        if (m->normal) m->normal = mem_realloc_array(m->normal, *pcap, 3 * sizeof(float));
    }
    double *p = m->pos + (size_t)m->npos * 3;
    p[0] = x, p[1] = y, p[2] = z;
    if (m->uv) m->uv[(size_t)m->npos * 2] = m->uv[(size_t)m->npos * 2 + 1] = 0;
    if (m->normal) memset(m->normal + (size_t)m->npos * 3, 0, 3 * sizeof(float));
    return m->npos++;
}

void geom_mesh_add_tri(GeomMesh *m, uint32_t *tcap, uint32_t a, uint32_t b, uint32_t c)
{
    if (m->ntri == *tcap) {
        *tcap = *tcap ? *tcap * 2 : 64;
        m->tri = mem_realloc_array(m->tri, *tcap, 3 * sizeof(uint32_t));
    }
    uint32_t *t = m->tri + (size_t)m->ntri * 3;
    t[0] = a, t[1] = b, t[2] = c;
    m->ntri++;
}

static void corners(const GeomMesh *m, uint32_t t, const double *p[3])
{
    for (int k = 0; k < 3; k++) p[k] = m->pos + (size_t)m->tri[(size_t)t * 3 + k] * 3;
}

double geom_mesh_volume(const GeomMesh *m)
{
    double v = 0;
    for (uint32_t t = 0; t < m->ntri; t++) {
        const double *p[3];
        corners(m, t, p);
        const double *a = p[0], *b = p[1], *c = p[2];
        v += a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return v / 6;
}

double geom_mesh_area(const GeomMesh *m)
{
    double s = 0;
    for (uint32_t t = 0; t < m->ntri; t++) {
        const double *p[3];
        corners(m, t, p);
        double u[3], w[3];
        for (int k = 0; k < 3; k++) u[k] = p[1][k] - p[0][k], w[k] = p[2][k] - p[0][k];
        double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        s += sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 2;
    }
    return s;
}

void geom_mesh_bounds(const GeomMesh *m, double out[6])
{
    if (m->npos == 0) {
        memset(out, 0, 6 * sizeof *out);
        return;
    }
    for (int k = 0; k < 3; k++) out[k] = out[k + 3] = m->pos[k];
    for (uint32_t i = 1; i < m->npos; i++)
        for (int k = 0; k < 3; k++) {
            double x = m->pos[(size_t)i * 3 + k];
            if (x < out[k]) out[k] = x;
            if (x > out[k + 3]) out[k + 3] = x;
        }
}

/* {===== an open-addressing table of keys of a few words */

typedef struct Table {
    uint64_t *keys;    /* cap * width words */
    uint32_t *vals;    /* cap; UINT32_MAX for empty */
    size_t cap, width;
} Table;

static uint64_t mix64(uint64_t h)
{
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    return h ^ (h >> 33);
}

static void table_init(Table *t, size_t n, size_t width)
{
    t->cap = 16;
    while (t->cap < n * 2 + 16) t->cap *= 2;
    t->width = width;
    t->keys = mem_alloc(t->cap * width * sizeof(uint64_t));
    t->vals = mem_alloc(t->cap * sizeof(uint32_t));
    memset(t->vals, 0xff, t->cap * sizeof(uint32_t));
}

/* The value stored under [key], else [val] stored and returned. */
static uint32_t table_get_or_put(Table *t, const uint64_t *key, uint32_t val)
{
    uint64_t h = 0;
    for (size_t k = 0; k < t->width; k++) h = mix64(h ^ key[k]);
    size_t i = h & (t->cap - 1);
    for (;;) {
        if (t->vals[i] == UINT32_MAX) {
            memcpy(t->keys + i * t->width, key, t->width * sizeof(uint64_t));
            t->vals[i] = val;
            return val;
        }
        if (memcmp(t->keys + i * t->width, key, t->width * sizeof(uint64_t)) == 0) return t->vals[i];
        i = (i + 1) & (t->cap - 1);
    }
}

static void table_free(Table *t)
{
    free(t->keys);
    free(t->vals);
}

/* [x] as a key word, -0 as +0. */
static uint64_t word_of(double x)
{
    uint64_t w;
    if (x == 0) x = 0;
    memcpy(&w, &x, sizeof w);
    return w;
}

uint32_t *geom_mesh_position_ids(const GeomMesh *m)
{
    uint32_t *id = mem_alloc((m->npos ? m->npos : 1) * sizeof(uint32_t));
    Table t;
    table_init(&t, m->npos, 3);
    for (uint32_t v = 0; v < m->npos; v++) {
        uint64_t key[3];
        for (int k = 0; k < 3; k++) key[k] = word_of(m->pos[(size_t)v * 3 + k]);
        id[v] = table_get_or_put(&t, key, v);
    }
    table_free(&t);
    return id;
}

/* }===== */

bool geom_mesh_is_closed(const GeomMesh *m)
{
    /* each directed edge once; its reverse present exactly once */
    Table t;
    size_t n = (size_t)m->ntri * 3;
    table_init(&t, n, 2);
    bool ok = m->ntri > 0;
    for (size_t e = 0; e < n && ok; e++) {
        uint32_t a = m->tri[e], b = m->tri[e - e % 3 + (e % 3 + 1) % 3];
        uint64_t key[2] = {a, b};
        if (a == b || table_get_or_put(&t, key, (uint32_t)e) != (uint32_t)e) ok = false;
    }
    for (size_t e = 0; e < n && ok; e++) {
        uint32_t a = m->tri[e], b = m->tri[e - e % 3 + (e % 3 + 1) % 3];
        uint64_t key[2] = {b, a};
        if (table_get_or_put(&t, key, UINT32_MAX - 1) == UINT32_MAX - 1) ok = false;
    }
    table_free(&t);
    return ok;
}

void geom_mesh_weld(GeomMesh *m)
{
    Table t;
    table_init(&t, m->npos, 3);
    uint32_t *remap = mem_alloc((m->npos ? m->npos : 1) * sizeof(uint32_t));
    uint32_t n = 0;
    for (uint32_t i = 0; i < m->npos; i++) {
        uint64_t key[3];
        for (int k = 0; k < 3; k++) key[k] = word_of(m->pos[(size_t)i * 3 + k]);
        uint32_t j = table_get_or_put(&t, key, n);
        if (j == n) {
            memmove(m->pos + (size_t)n * 3, m->pos + (size_t)i * 3, 3 * sizeof(double));
            n++;
        }
        remap[i] = j;
    }
    table_free(&t);
    uint32_t kept = 0;
    for (uint32_t f = 0; f < m->ntri; f++) {
        uint32_t a = remap[m->tri[(size_t)f * 3]], b = remap[m->tri[(size_t)f * 3 + 1]],
                 c = remap[m->tri[(size_t)f * 3 + 2]];
        if (a == b || b == c || a == c) continue;
        uint32_t *d = m->tri + (size_t)kept * 3;
        d[0] = a, d[1] = b, d[2] = c;
        kept++;
    }
    free(remap);
    m->npos = n;
    m->ntri = kept;
    free(m->uv);
    free(m->normal);
    m->uv = NULL;
    m->normal = NULL;
}

void geom_mesh_copy(const GeomMesh *src, GeomMesh *dst)
{
    memset(dst, 0, sizeof *dst);
    dst->npos = src->npos;
    dst->ntri = src->ntri;
    size_t np = src->npos ? src->npos : 1, nt = src->ntri ? src->ntri : 1;
    dst->pos = mem_alloc(np * 3 * sizeof(double));
    if (src->npos) memcpy(dst->pos, src->pos, (size_t)src->npos * 3 * sizeof(double));
    dst->tri = mem_alloc(nt * 3 * sizeof(uint32_t));
    if (src->ntri) memcpy(dst->tri, src->tri, (size_t)src->ntri * 3 * sizeof(uint32_t));
    if (src->uv) {
        dst->uv = mem_alloc(np * 2 * sizeof(float));
        if (src->npos) memcpy(dst->uv, src->uv, (size_t)src->npos * 2 * sizeof(float));
    }
    if (src->normal) {
        dst->normal = mem_alloc(np * 3 * sizeof(float));
        if (src->npos) memcpy(dst->normal, src->normal, (size_t)src->npos * 3 * sizeof(float));
    }
}

/* {===== repair (Flitter's repair=) */

/* Merge vertices equal in position, texture coordinate and normal. */
static void merge_vertices(GeomMesh *m)
{
    uint32_t n = m->npos, kept = 0;
    uint32_t *remap = mem_alloc((n ? n : 1) * sizeof(uint32_t));
    Table t;
    table_init(&t, n, 8);
    for (uint32_t i = 0; i < n; i++) {
        uint64_t key[8] = {0};
        for (int k = 0; k < 3; k++) key[k] = word_of(m->pos[(size_t)i * 3 + k]);
        for (int k = 0; m->uv && k < 2; k++) key[3 + k] = word_of(m->uv[(size_t)i * 2 + k]);
        for (int k = 0; m->normal && k < 3; k++) key[5 + k] = word_of(m->normal[(size_t)i * 3 + k]);
        uint32_t j = table_get_or_put(&t, key, kept);
        if (j == kept) {
            memmove(m->pos + (size_t)kept * 3, m->pos + (size_t)i * 3, 3 * sizeof(double));
            if (m->uv) memmove(m->uv + (size_t)kept * 2, m->uv + (size_t)i * 2, 2 * sizeof(float));
            if (m->normal) memmove(m->normal + (size_t)kept * 3, m->normal + (size_t)i * 3, 3 * sizeof(float));
            kept++;
        }
        remap[i] = j;
    }
    table_free(&t);
    for (size_t e = 0; e < (size_t)m->ntri * 3; e++) m->tri[e] = remap[m->tri[e]];
    m->npos = kept;
    free(remap);
}

/* Drop triangles with two corners at one position, of no area, or over
 * the same three positions as an earlier one. */
static void drop_bad_triangles(GeomMesh *m, const uint32_t *pid)
{
    Table t;
    table_init(&t, m->ntri, 3);
    uint32_t kept = 0;
    for (uint32_t f = 0; f < m->ntri; f++) {
        const uint32_t *c = m->tri + (size_t)f * 3;
        uint32_t a = pid[c[0]], b = pid[c[1]], d = pid[c[2]];
        if (a == b || b == d || a == d) continue;
        const double *p[3];
        corners(m, f, p);
        double u[3], v[3];
        for (int k = 0; k < 3; k++) u[k] = p[1][k] - p[0][k], v[k] = p[2][k] - p[0][k];
        if (u[1] * v[2] - u[2] * v[1] == 0 && u[2] * v[0] - u[0] * v[2] == 0 && u[0] * v[1] - u[1] * v[0] == 0)
            continue;
        uint64_t key[3] = {a, b, d};
        for (int i = 0; i < 2; i++)   /* sorted: the same three in any order */
            for (int j = 0; j < 2 - i; j++)
                if (key[j] > key[j + 1]) {
                    uint64_t s = key[j];
                    key[j] = key[j + 1];
                    key[j + 1] = s;
                }
        if (table_get_or_put(&t, key, kept) != kept) continue;
        memmove(m->tri + (size_t)kept * 3, c, 3 * sizeof *c);
        kept++;
    }
    table_free(&t);
    m->ntri = kept;
}

/* The corners of side [s] (0..2) of triangle [f] as positions. */
static void side(const GeomMesh *m, const uint32_t *pid, uint32_t f, int s, uint32_t *a, uint32_t *b)
{
    *a = pid[m->tri[(size_t)f * 3 + (size_t)s]];
    *b = pid[m->tri[(size_t)f * 3 + (size_t)(s + 1) % 3]];
}

/* Wind every triangle as the first of its connected part (triangles that
 * share a side by position), turning those that run along a shared side
 * in the same direction as their neighbour; true when every side is
 * shared by exactly two triangles running along it in opposite directions
 * afterwards (a closed surface). */
static bool fix_winding(GeomMesh *m, const uint32_t *pid)
{
    size_t ne = (size_t)m->ntri * 3;
    uint32_t *group = mem_alloc((ne ? ne : 1) * sizeof(uint32_t)), ngroups = 0;
    Table t;
    table_init(&t, ne, 2);
    for (size_t e = 0; e < ne; e++) {
        uint32_t a, b;
        side(m, pid, (uint32_t)(e / 3), (int)(e % 3), &a, &b);
        uint64_t key[2] = {a < b ? a : b, a < b ? b : a};
        group[e] = table_get_or_put(&t, key, ngroups);
        if (group[e] == ngroups) ngroups++;
    }
    table_free(&t);
    /* the sides of each group, contiguous */
    uint32_t *start = mem_calloc((size_t)ngroups + 1, sizeof(uint32_t));
    uint32_t *member = mem_alloc((ne ? ne : 1) * sizeof(uint32_t));
    for (size_t e = 0; e < ne; e++) start[group[e] + 1]++;
    for (uint32_t g = 0; g < ngroups; g++) start[g + 1] += start[g];
    uint32_t *fill = mem_alloc(((size_t)ngroups + 1) * sizeof(uint32_t));
    memcpy(fill, start, ((size_t)ngroups + 1) * sizeof(uint32_t));
    for (size_t e = 0; e < ne; e++) member[fill[group[e]]++] = (uint32_t)e;
    free(fill);
    /* breadth first over the triangles */
    bool *seen = mem_calloc(m->ntri ? m->ntri : 1, sizeof(bool));
    uint32_t *queue = mem_alloc((m->ntri ? m->ntri : 1) * sizeof(uint32_t));
    for (uint32_t s = 0; s < m->ntri; s++) {
        if (seen[s]) continue;
        size_t head = 0, tail = 0;
        queue[tail++] = s;
        seen[s] = true;
        while (head < tail) {
            uint32_t f = queue[head++];
            for (int k = 0; k < 3; k++) {
                uint32_t g = group[(size_t)f * 3 + (size_t)k], a, b;
                side(m, pid, f, k, &a, &b);
                for (uint32_t i = start[g]; i < start[g + 1]; i++) {
                    uint32_t o = member[i] / 3, oa, ob;
                    if (o == f || seen[o]) continue;
                    side(m, pid, o, (int)(member[i] % 3), &oa, &ob);
                    if (oa == a) {   /* the same direction: turned */
                        uint32_t *c = m->tri + (size_t)o * 3, x = c[1];
                        c[1] = c[2];
                        c[2] = x;
                    }
                    seen[o] = true;
                    queue[tail++] = o;
                }
            }
        }
    }
    free(seen);
    free(queue);
    bool closed = m->ntri > 0;
    for (uint32_t g = 0; g < ngroups && closed; g++) {
        if (start[g + 1] - start[g] != 2) {
            closed = false;
            break;
        }
        uint32_t a0, b0, a1, b1, e0 = member[start[g]], e1 = member[start[g] + 1];
        side(m, pid, e0 / 3, (int)(e0 % 3), &a0, &b0);
        side(m, pid, e1 / 3, (int)(e1 % 3), &a1, &b1);
        closed = a0 == b1 && b0 == a1;
    }
    free(group);
    free(start);
    free(member);
    return closed;
}

void geom_mesh_repair(GeomMesh *m)
{
    merge_vertices(m);
    uint32_t *pid = geom_mesh_position_ids(m);
    drop_bad_triangles(m, pid);
    bool closed = fix_winding(m, pid);
    free(pid);
    if (closed && geom_mesh_volume(m) < 0)
        for (uint32_t f = 0; f < m->ntri; f++) {
            uint32_t *c = m->tri + (size_t)f * 3, x = c[1];
            c[1] = c[2];
            c[2] = x;
        }
    /* the vertices no triangle uses dropped */
    uint32_t *remap = mem_alloc((m->npos ? m->npos : 1) * sizeof(uint32_t));
    memset(remap, 0xff, (m->npos ? m->npos : 1) * sizeof(uint32_t));
    for (size_t e = 0; e < (size_t)m->ntri * 3; e++) remap[m->tri[e]] = 0;
    uint32_t kept = 0;
    for (uint32_t i = 0; i < m->npos; i++) {
        if (remap[i] == UINT32_MAX) continue;
        memmove(m->pos + (size_t)kept * 3, m->pos + (size_t)i * 3, 3 * sizeof(double));
        if (m->uv) memmove(m->uv + (size_t)kept * 2, m->uv + (size_t)i * 2, 2 * sizeof(float));
        if (m->normal) memmove(m->normal + (size_t)kept * 3, m->normal + (size_t)i * 3, 3 * sizeof(float));
        remap[i] = kept++;
    }
    for (size_t e = 0; e < (size_t)m->ntri * 3; e++) m->tri[e] = remap[m->tri[e]];
    free(remap);
    m->npos = kept;
    /* normals that no longer face out are recomputed by the renderer */
    free(m->normal);
    m->normal = NULL;
}

/* }===== */
