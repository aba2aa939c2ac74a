/* mat4.h: 4x4 matrices for `!canvas3d` transforms and cameras, in double
 * precision, column-major (element [col*4 + row]) as OpenGL and Flitter's
 * Matrix44 (flitter/model.pyx) store them. Angles are in turns. Every
 * matrix is built as Flitter's Matrix44 builds it: rotate=X;Y;Z is
 * Rx * Ry * Rz (z first), the projection and look-at matrices are
 * Matrix44._project, _ortho and _look. */
#ifndef FL_RENDER_MAT4_H
#define FL_RENDER_MAT4_H

#include <math.h>
#include <stdbool.h>

#include "turns.h"

typedef struct M4 { double m[16]; } M4;

static inline M4 m4_identity(void) { return (M4){{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}; }

/* a * b */
static inline M4 m4_mul(const M4 *a, const M4 *b)
{
    M4 r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            double s = 0;
            for (int k = 0; k < 4; k++) s += a->m[k * 4 + row] * b->m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}

static inline M4 m4_translate(const double v[3])
{
    M4 r = m4_identity();
    r.m[12] = v[0], r.m[13] = v[1], r.m[14] = v[2];
    return r;
}

static inline M4 m4_scale(const double v[3])
{
    M4 r = m4_identity();
    r.m[0] = v[0], r.m[5] = v[1], r.m[10] = v[2];
    return r;
}

/* Rotation of [t] turns about axis [axis] (0 x, 1 y, 2 z), right-handed. */
static inline M4 m4_rotate_axis(int axis, double t)
{
    M4 r = m4_identity();
    double c = cos_t(t), s = sin_t(t);
    int a = (axis + 1) % 3, b = (axis + 2) % 3;
    r.m[a * 4 + a] = c;
    r.m[a * 4 + b] = s;
    r.m[b * 4 + a] = -s;
    r.m[b * 4 + b] = c;
    return r;
}

/* Rx(t[0]) * Ry(t[1]) * Rz(t[2]). */
static inline M4 m4_rotate(const double t[3])
{
    M4 r = m4_identity();
    for (int axis = 0; axis < 3; axis++)
        if (t[axis] != 0 && !isnan(t[axis])) {
            M4 q = m4_rotate_axis(axis, t[axis]);
            r = m4_mul(&r, &q);
        }
    return r;
}

/* The rotation of unit quaternion w;x;y;z (normalised here). */
static inline M4 m4_quaternion(const double q[4])
{
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(n > 0)) return m4_identity();
    double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    M4 r = m4_identity();
    r.m[0] = 1 - 2 * (y * y + z * z), r.m[1] = 2 * (x * y + w * z), r.m[2] = 2 * (x * z - w * y);
    r.m[4] = 2 * (x * y - w * z), r.m[5] = 1 - 2 * (x * x + z * z), r.m[6] = 2 * (y * z + w * x);
    r.m[8] = 2 * (x * z + w * y), r.m[9] = 2 * (y * z - w * x), r.m[10] = 1 - 2 * (x * x + y * y);
    return r;
}

/* The point [v] transformed by [a] (w = 1, then divided by w). */
static inline void m4_point(const M4 *a, const double v[3], double out[3])
{
    double r[4];
    for (int row = 0; row < 4; row++)
        r[row] = a->m[row] * v[0] + a->m[4 + row] * v[1] + a->m[8 + row] * v[2] + a->m[12 + row];
    double w = r[3] != 0 ? r[3] : 1;
    out[0] = r[0] / w, out[1] = r[1] / w, out[2] = r[2] / w;
}

/* The cofactor matrix of [a]'s upper 3x3 (column-major 3x3), which maps
 * normals (Flitter's matrix33_cofactor). */
static inline void m4_cofactor3(const M4 *a, double out[9])
{
    const double *n = a->m;
    out[0] = n[5] * n[10] - n[6] * n[9];
    out[1] = n[6] * n[8] - n[4] * n[10];
    out[2] = n[4] * n[9] - n[5] * n[8];
    out[3] = n[2] * n[9] - n[1] * n[10];
    out[4] = n[0] * n[10] - n[2] * n[8];
    out[5] = n[1] * n[8] - n[0] * n[9];
    out[6] = n[1] * n[6] - n[2] * n[5];
    out[7] = n[2] * n[4] - n[0] * n[6];
    out[8] = n[0] * n[5] - n[1] * n[4];
}

/* The direction [v] through the cofactor of [a], normalised ([v] kept when
 * it maps to zero). */
static inline void m4_direction(const M4 *a, const double v[3], double out[3])
{
    double c[9];
    m4_cofactor3(a, c);
    double r[3];
    for (int row = 0; row < 3; row++) r[row] = c[row] * v[0] + c[3 + row] * v[1] + c[6 + row] * v[2];
    double n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (n > 0) out[0] = r[0] / n, out[1] = r[1] / n, out[2] = r[2] / n;
    else out[0] = v[0], out[1] = v[1], out[2] = v[2];
}

/* Perspective projection with the given half-view gradients (tan of half
 * the field of view) horizontally and vertically. */
static inline M4 m4_project(double xg, double yg, double near, double far)
{
    M4 r = {{0}};
    r.m[0] = 1 / xg;
    r.m[5] = 1 / yg;
    r.m[10] = -(far + near) / (far - near);
    r.m[11] = -1;
    r.m[14] = -2 * far * near / (far - near);
    return r;
}

/* Orthographic projection [width] world units wide, height width/aspect. */
static inline M4 m4_ortho(double aspect, double width, double near, double far)
{
    M4 r = m4_identity();
    r.m[0] = 2 / width;
    r.m[5] = 2 * aspect / width;
    r.m[10] = -2 / (far - near);
    r.m[14] = -(far + near) / (far - near);
    return r;
}

/* The view matrix of an eye at [from] looking at [to] with [up] as the
 * screen's y direction; false (identity) when they do not define one. */
static inline bool m4_look(const double from[3], const double to[3], const double up[3], M4 *out)
{
    double z[3] = {from[0] - to[0], from[1] - to[1], from[2] - to[2]};
    double zl = sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    *out = m4_identity();
    if (!(zl > 0)) return false;
    for (int k = 0; k < 3; k++) z[k] /= zl;
    double d = up[0] * z[0] + up[1] * z[1] + up[2] * z[2];
    double y[3] = {up[0] - z[0] * d, up[1] - z[1] * d, up[2] - z[2] * d};
    double yl = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
    if (!(yl > 0)) return false;
    for (int k = 0; k < 3; k++) y[k] /= yl;
    double x[3] = {y[1] * z[2] - y[2] * z[1], y[2] * z[0] - y[0] * z[2], y[0] * z[1] - y[1] * z[0]};
    M4 r = m4_identity();
    for (int k = 0; k < 3; k++) {
        r.m[k * 4 + 0] = x[k];
        r.m[k * 4 + 1] = y[k];
        r.m[k * 4 + 2] = z[k];
    }
    double neg[3] = {-from[0], -from[1], -from[2]};
    M4 t = m4_translate(neg);
    *out = m4_mul(&r, &t);
    return true;
}

/* The inverse of [a] by Gauss-Jordan elimination with partial pivoting;
 * false (and [*out] the identity) when [a] is singular. */
static inline bool m4_inverse(const M4 *a, M4 *out)
{
    double w[4][8];   /* [a | I], row-major */
    for (int r = 0; r < 4; r++)
        for (int k = 0; k < 4; k++) w[r][k] = a->m[k * 4 + r], w[r][k + 4] = r == k;
    *out = m4_identity();
    for (int col = 0; col < 4; col++) {
        int piv = col;
        for (int r = col + 1; r < 4; r++)
            if (fabs(w[r][col]) > fabs(w[piv][col])) piv = r;
        if (!(fabs(w[piv][col]) > 0)) return false;
        for (int k = 0; k < 8; k++) {
            double t = w[col][k];
            w[col][k] = w[piv][k], w[piv][k] = t;
        }
        double d = w[col][col];
        for (int k = 0; k < 8; k++) w[col][k] /= d;
        for (int r = 0; r < 4; r++) {
            if (r == col || w[r][col] == 0) continue;
            double f = w[r][col];
            for (int k = 0; k < 8; k++) w[r][k] -= f * w[col][k];
        }
    }
    for (int r = 0; r < 4; r++)
        for (int k = 0; k < 4; k++) out->m[k * 4 + r] = w[r][k + 4];
    return true;
}

#endif
