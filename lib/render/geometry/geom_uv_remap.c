/* geom_uv_remap.c: Flitter's uv_remap= mappings (see geom_uv_remap.h). */
#include "geom_uv_remap.h"

#include <math.h>
#include <string.h>

#include "mem.h"
#include "turns.h"

int geom_uv_remap_parse(const char *name)
{
    if (!name) return UV_REMAP_NONE;
    if (strcmp(name, "sphere") == 0) return UV_REMAP_SPHERE;
    if (strcmp(name, "plane") == 0) return UV_REMAP_PLANE;
    if (strcmp(name, "book") == 0) return UV_REMAP_BOOK;
    return UV_REMAP_NONE;
}

/* Longitude and latitude of every vertex, then the seam's copies. */
static void remap_sphere(MeshData *d)
{
    for (uint32_t i = 0; i < d->nverts; i++) {
        float *p = d->verts + (size_t)i * 8;
        float x = p[0], y = p[1], z = p[2];
        float u = (float)(atan2((double)y, (double)x) / TAU);
        if (u < 0) u += 1;
        float rr = x * x + y * y;
        p[6] = u;
        p[7] = (float)(atan2((double)z, sqrt((double)rr)) / TAU * 2 + 0.5);
    }
    uint32_t cap = d->nverts;   /* the array's length as far as is known */
    for (uint32_t t = 0; t + 2 < d->nindex; t += 3) {
        uint32_t *tri = d->index + t;
        float u[3];
        for (int k = 0; k < 3; k++) u[k] = d->verts[(size_t)tri[k] * 8 + 6];
        float umax = u[0] > u[1] ? u[0] : u[1];
        if (u[2] > umax) umax = u[2];
        if (!(umax > 0.75f)) continue;
        for (int k = 0; k < 3; k++) {
            if (!(u[k] < 0.25f)) continue;
            if (d->nverts == cap) {
                cap = cap ? cap * 2 : 16;
                d->verts = mem_realloc_array(d->verts, cap, 8 * sizeof(float));
            }
            float *q = d->verts + (size_t)d->nverts * 8;
            memcpy(q, d->verts + (size_t)tri[k] * 8, 8 * sizeof(float));
            q[6] = u[k] + 1;
            tri[k] = d->nverts++;
        }
    }
}

static void remap_plane(MeshData *d, const double bounds[6], bool book)
{
    float x0 = (float)bounds[0], y0 = (float)bounds[1];
    float width = (float)bounds[3] - x0, height = (float)bounds[4] - y0;
    for (uint32_t i = 0; i < d->nverts; i++) {
        float *p = d->verts + (size_t)i * 8;
        float u = (p[0] - x0) / width;
        /* (Flitter adds its 0.5 in double precision) */
        if (book) u = p[5] >= 0 ? (float)((double)(u / 2) + 0.5) : (float)(0.5 - (double)(u / 2));
        p[6] = u;
        p[7] = (p[1] - y0) / height;
    }
}

void geom_uv_remap(MeshData *d, int mapping, const double bounds[6])
{
    switch (mapping) {
    case UV_REMAP_SPHERE: remap_sphere(d); break;
    case UV_REMAP_PLANE: remap_plane(d, bounds, false); break;
    case UV_REMAP_BOOK: remap_plane(d, bounds, true); break;
    default: break;
    }
}
