/* transform3d.c: 3D transforms from node attributes (see transform3d.h). */
#include "transform3d.h"

#include <math.h>
#include <string.h>

#include "rnode.h"

M4 transform3d_update(const Node *n, M4 t)
{
    for (size_t i = 0; i < rnode_nattrs(n); i++) {
        const char *a = rnode_attr_name(n, i);
        const Vec *v = rnode_attr_value(n, i);
        if (!vec_is_num(v)) continue;
        const double *x = vec_cnums(v);
        uint32_t len = vec_len(v);
        M4 m;
        double three[3];
        if (len == 1) three[0] = three[1] = three[2] = x[0];
        else if (len == 3) three[0] = x[0], three[1] = x[1], three[2] = x[2];
        if (strcmp(a, "translate") == 0 && (len == 1 || len == 3)) m = m4_translate(three);
        else if (strcmp(a, "scale") == 0 && (len == 1 || len == 3)) m = m4_scale(three);
        else if (strcmp(a, "rotate") == 0 && len == 4) m = m4_quaternion(x);
        else if (strcmp(a, "rotate") == 0 && (len == 1 || len == 3)) m = m4_rotate(three);
        else if (strcmp(a, "rotate_x") == 0 && len == 1) m = m4_rotate_axis(0, x[0]);
        else if (strcmp(a, "rotate_y") == 0 && len == 1) m = m4_rotate_axis(1, x[0]);
        else if (strcmp(a, "rotate_z") == 0 && len == 1) m = m4_rotate_axis(2, x[0]);
        else if (strcmp(a, "matrix") == 0 && len == 16) memcpy(m.m, x, sizeof m.m);
        else continue;
        t = m4_mul(&t, &m);
    }
    return t;
}

bool transform3d_start_end(const double s[3], const double e[3], double radius, M4 *out)
{
    double d[3] = {e[0] - s[0], e[1] - s[1], e[2] - s[2]};
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len == 0 || radius <= 0) return false;
    double mid[3] = {(s[0] + e[0]) / 2, (s[1] + e[1]) / 2, (s[2] + e[2]) / 2};
    /* the quaternion turning z onto d */
    double u[3] = {d[0] / len, d[1] / len, d[2] / len};
    double q[4] = {1 + u[2], -u[1], u[0], 0};   /* w, x, y, z: z cross u, 1 + z.u */
    if (q[0] < 1e-12) q[0] = 0, q[1] = 1, q[2] = 0, q[3] = 0;   /* opposite: half a turn about x */
    M4 m = m4_translate(mid), r = m4_quaternion(q);
    double sz[3] = {radius, radius, len};
    M4 sc = m4_scale(sz);
    m = m4_mul(&m, &r);
    *out = m4_mul(&m, &sc);
    return true;
}

/* [count] numbers of attribute [name] (one number repeated). */
static bool nums(const Node *n, const char *name, int count, double *out)
{
    return rnode_nums(n, name, count, out);
}

M4 transform3d_model(const Node *n, M4 m, bool *moved)
{
    bool any = false;
    M4 x;
    double s[3] = {0, 0, 0}, e[3], v[3];
    if (nums(n, "end", 3, e)) {
        nums(n, "start", 3, s);
        double r = 1;
        nums(n, "radius", 1, &r);
        if (transform3d_start_end(s, e, r, &x)) m = m4_mul(&m, &x), any = true;
    } else {
        if (nums(n, "position", 3, v)) x = m4_translate(v), m = m4_mul(&m, &x), any = true;
        if (nums(n, "rotation", 3, v)) x = m4_rotate(v), m = m4_mul(&m, &x), any = true;
        if (nums(n, "size", 3, v)) x = m4_scale(v), m = m4_mul(&m, &x), any = true;
    }
    if (moved) *moved = any;
    return m;
}
