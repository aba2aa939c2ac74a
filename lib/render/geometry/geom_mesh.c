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
        for (int k = 0; k < 3; k++) {
            double x = m->pos[(size_t)i * 3 + k];
            if (x == 0) x = 0;   /* -0 and +0 are one position */
            memcpy(&key[k], &x, sizeof x);
        }
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
