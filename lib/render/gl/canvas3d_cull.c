/* canvas3d_cull.c: the lights a mesh cannot see (see canvas3d_cull.h). */
#include "canvas3d_cull.h"

#include <math.h>
#include <string.h>

#include "canvas3d_shaders.h"
#include "mat4.h"

/* The mesh's vertex [v] (8 floats) has a finite position and normal. */
static bool finite_vertex(const float *v)
{
    for (int k = 0; k < 6; k++)
        if (!isfinite(v[k])) return false;
    return true;
}

void c3d_planes_make(C3dPlanes *out, const float *verts, uint32_t nverts, const uint32_t *index,
                     uint32_t nindex)
{
    out->n = 0;
    double low[C3D_PLANES_MAX], high[C3D_PLANES_MAX];
    int n = 0;
    if (nindex < 3) return;
    for (uint32_t t = 0; t + 2 < nindex; t += 3) {
        const float *v[3];
        for (int k = 0; k < 3; k++) {
            if (index[t + k] >= nverts) return;
            v[k] = verts + (size_t)index[t + k] * 8;
            if (!finite_vertex(v[k])) return;
        }
        /* a flat face: one normal, bit for bit, at its three vertices */
        if (memcmp(v[0] + 3, v[1] + 3, 3 * sizeof(float)) != 0 || memcmp(v[0] + 3, v[2] + 3, 3 * sizeof(float)) != 0)
            return;
        int j = 0;
        while (j < n && memcmp(out->plane[j].normal, v[0] + 3, 3 * sizeof(float)) != 0) j++;
        if (j == n) {
            if (n == C3D_PLANES_MAX) return;
            memcpy(out->plane[j].normal, v[0] + 3, 3 * sizeof(float));
            low[j] = INFINITY;
            high[j] = -INFINITY;
            n++;
        }
        const float *nr = out->plane[j].normal;
        /* the normal is the face's own: its three vertices at one offset
         * along it (a file's normals may lean), so that a sample's
         * position off the triangle (no centroid interpolation) stays on
         * its plane */
        double o3[3], size = 1;
        for (int k = 0; k < 3; k++) {
            o3[k] = (double)nr[0] * v[k][0] + (double)nr[1] * v[k][1] + (double)nr[2] * v[k][2];
            for (int a = 0; a < 3; a++) size = fmax(size, fabs(v[k][a]));
        }
        double len = sqrt((double)nr[0] * nr[0] + (double)nr[1] * nr[1] + (double)nr[2] * nr[2]);
        if (!(len > 0) || fabs(o3[1] - o3[0]) > 1e-5 * size * len || fabs(o3[2] - o3[0]) > 1e-5 * size * len) {
            out->n = 0;
            return;
        }
        for (int k = 0; k < 3; k++) {
            double o = o3[k];
            if (o < low[j]) {
                low[j] = o;
                memcpy(out->plane[j].low, v[k], 3 * sizeof(float));
            }
            if (o > high[j]) {
                high[j] = o;
                memcpy(out->plane[j].high, v[k], 3 * sizeof(float));
            }
        }
    }
    out->n = n;
}

/* The signed distance of [c] from the plane through model-space point [p]
 * (put through [m]) with world-space normal [N] of length [len], and the
 * margin for it (canvas3d_cull.h): whether [c] lies behind by more than
 * [r] and the margin. */
static bool behind(const double c[3], double cn, const M4 *m, const float p[3], const double N[3], double len,
                   double r)
{
    const double *a = m->m;
    double w[3], s = 0, pn = 0;
    for (int k = 0; k < 3; k++) {
        w[k] = a[k] * p[0] + a[4 + k] * p[1] + a[8 + k] * p[2] + a[12 + k];
        s += N[k] * (c[k] - w[k]);
        pn += w[k] * w[k];
    }
    s /= len;
    double margin = 1e-3 * (1 + cn + sqrt(pn));
    return s < -(r + margin);   /* (false for NaN) */
}

bool c3d_light_unseen(const float light[16], const double model[16], const C3dPlanes *planes)
{
    if (!planes || planes->n <= 0) return false;
    double r;
    switch ((int)light[3]) {
    case LIGHT_POINT: r = light[11] > 0 ? light[11] : 0; break;   /* the shader's `two` when above 0 */
    case LIGHT_SPOT: r = 0; break;
    default: return false;
    }
    double c[3] = {light[4], light[5], light[6]};
    if (!isfinite(c[0]) || !isfinite(c[1]) || !isfinite(c[2]) || !isfinite(r)) return false;
    double cn = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    M4 m;
    memcpy(m.m, model, sizeof m.m);
    if (m.m[3] != 0 || m.m[7] != 0 || m.m[11] != 0 || m.m[15] != 1) return false;   /* not affine */
    double nm[9];
    m4_cofactor3(&m, nm);   /* the shader's normal matrix (canvas3d_draw.c) */
    /* the shader's normal matrix is single precision: none of its numbers
     * may overflow or come near underflowing there */
    for (int k = 0; k < 9; k++)
        if (!(fabs(nm[k]) < 1e30)) return false;
    for (int i = 0; i < planes->n; i++) {
        const C3dPlane *pl = &planes->plane[i];
        double N[3];
        for (int k = 0; k < 3; k++) N[k] = nm[k] * pl->normal[0] + nm[3 + k] * pl->normal[1] + nm[6 + k] * pl->normal[2];
        double len = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
        if (!(len > 1e-15) || !isfinite(len)) return false;
        /* dot(N, M p) is det(M) dot(normal, p) plus a constant: its extremes
         * over the faces are at the two vertices kept */
        if (!behind(c, cn, &m, pl->low, N, len, r) || !behind(c, cn, &m, pl->high, N, len, r)) return false;
    }
    return true;
}
