/* geom_shading.c: drawn vertices with flat, snapped or smooth normals
 * (see geom_shading.h). */
#include "geom_shading.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"

#define TAU 6.283185307179586

typedef struct Out {
    MeshData *d;
    uint32_t vcap;
} Out;

static uint32_t put(Out *o, const double p[3], const double n[3], const float uv[2])
{
    MeshData *d = o->d;
    if (d->nverts == o->vcap) {
        o->vcap = o->vcap ? o->vcap * 2 : 64;
        d->verts = mem_realloc_array(d->verts, o->vcap, 8 * sizeof(float));
    }
    float *v = d->verts + (size_t)d->nverts * 8;
    for (int k = 0; k < 3; k++) v[k] = (float)p[k], v[3 + k] = (float)n[k];
    v[6] = uv ? uv[0] : 0;
    v[7] = uv ? uv[1] : 0;
    return d->nverts++;
}

static void unit(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0) v[0] /= l, v[1] /= l, v[2] /= l;
}

/* The area-weighted normal (twice the area long) of triangle [f]. */
static void face_normal(const GeomMesh *m, uint32_t f, double n[3])
{
    const double *a = m->pos + (size_t)m->tri[(size_t)f * 3] * 3, *b = m->pos + (size_t)m->tri[(size_t)f * 3 + 1] * 3,
                 *c = m->pos + (size_t)m->tri[(size_t)f * 3 + 2] * 3;
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
}

static const float *uv_of(const GeomMesh *m, uint32_t v) { return m->uv ? m->uv + (size_t)v * 2 : NULL; }

static void flat(const GeomMesh *m, Out *o)
{
    MeshData *d = o->d;
    d->index = mem_alloc(sizeof(uint32_t) * 3 * (m->ntri ? m->ntri : 1));
    for (uint32_t f = 0; f < m->ntri; f++) {
        double n[3];
        face_normal(m, f, n);
        unit(n);
        for (int k = 0; k < 3; k++) {
            uint32_t v = m->tri[(size_t)f * 3 + k];
            d->index[d->nindex++] = put(o, m->pos + (size_t)v * 3, n, uv_of(m, v));
        }
    }
}

static void smooth(const GeomMesh *m, Out *o)
{
    MeshData *d = o->d;
    double *acc = mem_calloc(m->npos ? m->npos : 1, 3 * sizeof(double));
    if (m->normal) {
        for (uint32_t v = 0; v < m->npos; v++)
            for (int k = 0; k < 3; k++) acc[(size_t)v * 3 + k] = m->normal[(size_t)v * 3 + k];
    } else {
        for (uint32_t f = 0; f < m->ntri; f++) {
            double n[3];
            face_normal(m, f, n);
            for (int k = 0; k < 3; k++)
                for (int j = 0; j < 3; j++) acc[(size_t)m->tri[(size_t)f * 3 + k] * 3 + j] += n[j];
        }
    }
    for (uint32_t v = 0; v < m->npos; v++) {
        unit(acc + (size_t)v * 3);
        put(o, m->pos + (size_t)v * 3, acc + (size_t)v * 3, uv_of(m, v));
    }
    free(acc);
    d->index = mem_alloc(sizeof(uint32_t) * 3 * (m->ntri ? m->ntri : 1));
    memcpy(d->index, m->tri, sizeof(uint32_t) * 3 * m->ntri);
    d->nindex = m->ntri * 3;
}

/* {===== snapped edges */

static uint64_t mix64(uint64_t h)
{
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    return h ^ (h >> 33);
}

static void snapped(const GeomMesh *m, double angle, Out *o)
{
    MeshData *d = o->d;
    uint32_t *pid = geom_mesh_position_ids(m);
    /* the faces around each position (CSR) */
    uint32_t *start = mem_calloc((size_t)m->npos + 1, sizeof *start);
    for (size_t c = 0; c < (size_t)m->ntri * 3; c++) start[pid[m->tri[c]] + 1]++;
    for (uint32_t v = 0; v < m->npos; v++) start[v + 1] += start[v];
    uint32_t *fill = mem_alloc(sizeof *fill * ((size_t)m->npos + 1));
    memcpy(fill, start, sizeof *fill * ((size_t)m->npos + 1));
    uint32_t *faces = mem_alloc(sizeof *faces * ((size_t)m->ntri * 3 + 1));
    for (size_t c = 0; c < (size_t)m->ntri * 3; c++) faces[fill[pid[m->tri[c]]]++] = (uint32_t)(c / 3);
    free(fill);
    double *an = mem_alloc(sizeof(double) * 3 * (m->ntri ? m->ntri : 1));
    double *un = mem_alloc(sizeof(double) * 3 * (m->ntri ? m->ntri : 1));
    for (uint32_t f = 0; f < m->ntri; f++) {
        face_normal(m, f, an + (size_t)f * 3);
        memcpy(un + (size_t)f * 3, an + (size_t)f * 3, 3 * sizeof(double));
        unit(un + (size_t)f * 3);
    }
    double cos_limit = cos(angle * TAU);
    /* output vertices found again by (vertex, normal) */
    size_t cap = 16;
    while (cap < (size_t)m->ntri * 6 + 16) cap *= 2;
    uint32_t *slot = mem_alloc(cap * sizeof *slot);
    memset(slot, 0xff, cap * sizeof *slot);
    uint32_t *src = mem_alloc(sizeof *src * ((size_t)m->ntri * 3 + 1));   /* output vertex -> mesh vertex */
    d->index = mem_alloc(sizeof(uint32_t) * 3 * (m->ntri ? m->ntri : 1));
    for (uint32_t f = 0; f < m->ntri; f++) {
        const double *nf = un + (size_t)f * 3;
        for (int k = 0; k < 3; k++) {
            uint32_t v = m->tri[(size_t)f * 3 + k], p = pid[v];
            double n[3] = {0, 0, 0};
            for (uint32_t i = start[p]; i < start[p + 1]; i++) {
                uint32_t g = faces[i];
                const double *ng = un + (size_t)g * 3;
                if (g == f || nf[0] * ng[0] + nf[1] * ng[1] + nf[2] * ng[2] >= cos_limit)
                    for (int j = 0; j < 3; j++) n[j] += an[(size_t)g * 3 + j];
            }
            unit(n);
            float nf32[3] = {(float)n[0], (float)n[1], (float)n[2]};
            uint64_t h = mix64(v);
            for (int j = 0; j < 3; j++) {
                uint32_t b;
                memcpy(&b, &nf32[j], sizeof b);
                h = mix64(h ^ b);
            }
            size_t s = h & (cap - 1);
            uint32_t out;
            for (;;) {
                if (slot[s] == UINT32_MAX) {
                    out = put(o, m->pos + (size_t)v * 3, n, uv_of(m, v));
                    src[out] = v;
                    slot[s] = out;
                    break;
                }
                const float *w = d->verts + (size_t)slot[s] * 8 + 3;
                if (src[slot[s]] == v && w[0] == nf32[0] && w[1] == nf32[1] && w[2] == nf32[2]) {
                    out = slot[s];
                    break;
                }
                s = (s + 1) & (cap - 1);
            }
            d->index[d->nindex++] = out;
        }
    }
    free(slot);
    free(src);
    free(an);
    free(un);
    free(faces);
    free(start);
    free(pid);
}

/* }===== */

void geom_shade(const GeomMesh *m, const GeomShading *s, MeshData *out)
{
    memset(out, 0, sizeof *out);
    Out o = {out, 0};
    if (s->flat || s->snap <= 0) flat(m, &o);
    else if (s->snap < 0.5) snapped(m, s->snap, &o);
    else smooth(m, &o);
    if (s->invert) {
        for (uint32_t i = 0; i < out->nverts; i++)
            for (int k = 3; k < 6; k++) out->verts[(size_t)i * 8 + k] = -out->verts[(size_t)i * 8 + k];
        for (uint32_t t = 0; t + 2 < out->nindex; t += 3) {
            uint32_t x = out->index[t + 1];
            out->index[t + 1] = out->index[t + 2];
            out->index[t + 2] = x;
        }
    }
}
