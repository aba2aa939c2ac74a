/* noise.c: `noise` and `octnoise` (LANGUAGE.md §5.9): the original 2014
 * OpenSimplex noise of Kurt Spencer (public domain) in 2, 3 and 4
 * dimensions, with the reference's permutation and gradient quirks.
 *
 * The permutation for seed hash K and octave o is the §5.8 forward
 * Fisher–Yates shuffle of 0..255 driven by the uniform stream keyed
 * K XOR o. Lattice coordinates are the floors of the stretched coordinates
 * as 64-bit integers; they are kept here as uint64_t so that the wrapping
 * the reference gets from int64 overflow is well defined, and lattice
 * hashing takes them mod 256. The 2D gradient index is
 * (perm[...] mod 8) * 2, 3D (perm[...] mod 24) * 3, 4D perm[...] & 0xFC.
 *
 * Bit-exactness: every distance is computed with the reference's
 * expression and order. The vertices of the simplex around the point use
 * d = d0 - o - k*SQUISH with k the offset sum, which equals the reference's
 * literal forms (`dx0 - 1 - 2 * SQUISH`). The extra ("ext") vertices are
 * computed exactly as the reference's branches do, including the
 * incremental `-= 1` / `+= 2` adjustments, which round differently from a
 * direct formula. Contributions are summed in the reference's order.
 */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>

#include "config.h"
#include "builtins.h"
#include "context.h"
#include "mem.h"
#include "streams.h"

typedef uint64_t Lat; /* a lattice coordinate: int64 bits, wrapping */

static const double STRETCH2 = -0.211324865405187, SQUISH2 = 0.366025403784439, NORM2 = 47;
static const double STRETCH3 = -1.0 / 6, SQUISH3 = 1.0 / 3, NORM3 = 103;
static const double STRETCH4 = -0.138196601125011, SQUISH4 = 0.309016994374947, NORM4 = 30;

static const double G2[16] = {5, 2, 2, 5, -5, 2, -2, 5, 5, -2, 2, -5, -5, -2, -2, -5};

static const double G3[72] = {
    -11, 4, 4, -4, 11, 4, -4, 4, 11, 11, 4, 4, 4, 11, 4, 4, 4, 11,
    -11, -4, 4, -4, -11, 4, -4, -4, 11, 11, -4, 4, 4, -11, 4, 4, -4, 11,
    -11, 4, -4, -4, 11, -4, -4, 4, -11, 11, 4, -4, 4, 11, -4, 4, 4, -11,
    -11, -4, -4, -4, -11, -4, -4, -4, -11, 11, -4, -4, 4, -11, -4, 4, -4, -11,
};

/* The 64 4D gradients: for each sign pattern (x fastest, then y, z, w),
 * the four permutations of (3,1,1,1) with the 3 moving right. */
static const double G4[256] = {
    3, 1, 1, 1, 1, 3, 1, 1, 1, 1, 3, 1, 1, 1, 1, 3,
    -3, 1, 1, 1, -1, 3, 1, 1, -1, 1, 3, 1, -1, 1, 1, 3,
    3, -1, 1, 1, 1, -3, 1, 1, 1, -1, 3, 1, 1, -1, 1, 3,
    -3, -1, 1, 1, -1, -3, 1, 1, -1, -1, 3, 1, -1, -1, 1, 3,
    3, 1, -1, 1, 1, 3, -1, 1, 1, 1, -3, 1, 1, 1, -1, 3,
    -3, 1, -1, 1, -1, 3, -1, 1, -1, 1, -3, 1, -1, 1, -1, 3,
    3, -1, -1, 1, 1, -3, -1, 1, 1, -1, -3, 1, 1, -1, -1, 3,
    -3, -1, -1, 1, -1, -3, -1, 1, -1, -1, -3, 1, -1, -1, -1, 3,
    3, 1, 1, -1, 1, 3, 1, -1, 1, 1, 3, -1, 1, 1, 1, -3,
    -3, 1, 1, -1, -1, 3, 1, -1, -1, 1, 3, -1, -1, 1, 1, -3,
    3, -1, 1, -1, 1, -3, 1, -1, 1, -1, 3, -1, 1, -1, 1, -3,
    -3, -1, 1, -1, -1, -3, 1, -1, -1, -1, 3, -1, -1, -1, 1, -3,
    3, 1, -1, -1, 1, 3, -1, -1, 1, 1, -3, -1, 1, 1, -1, -3,
    -3, 1, -1, -1, -1, 3, -1, -1, -1, 1, -3, -1, -1, 1, -1, -3,
    3, -1, -1, -1, 1, -3, -1, -1, 1, -1, -3, -1, 1, -1, -1, -3,
    -3, -1, -1, -1, -1, -3, -1, -1, -1, -1, -3, -1, -1, -1, -1, -3,
};

/* {====================================================================
 * Lattice helpers, permutation, contributions
 * ===================================================================== */

/* <int64_t>floor(x) as on x86: INT64_MIN when out of range or NaN. */
static Lat floor_lat(double x)
{
    double f = floor(x);
    if (f >= -9223372036854775808.0 && f < 9223372036854775808.0)
        return (Lat)(int64_t)f;
    return (Lat)INT64_MIN;
}

/* The lattice coordinate as the reference's int64 -> double conversion. */
static double lat_d(Lat v)
{
    return (double)(int64_t)v;
}

/* perm = shuffle(uniform stream keyed [key], 0..255) (§5.8 algorithm). */
static void make_perm(uint64_t key, uint8_t perm[256])
{
    for (int i = 0; i < 256; i++)
        perm[i] = (uint8_t)i;
    int n = 256;
    for (int i = 0; i < 255; i++) {
        double f = floor(rng_uniform(key, (uint64_t)i) * n);
        int j = (int)f + i; /* f is in [0, n] */
        if (j > 255)
            j = 255; /* u == 1.0: out of bounds in the reference */
        n--;
        uint8_t t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
}

/* The memo of permutation tables (builtins.h): NOISE_PERMS tables by
 * key, the least recently used one replaced. Eight: physics.fl's two
 * seeds, and octnoise's octaves of a seed or two. */
#define NOISE_PERMS 8

struct NoisePerms {
    uint64_t key[NOISE_PERMS];
    uint64_t used[NOISE_PERMS];   /* when each was last handed out (0: empty) */
    uint64_t clock;
    uint8_t perm[NOISE_PERMS][256];
};

NoisePerms *noise_perms_new(void) { return calloc(1, sizeof(NoisePerms)); }

void noise_perms_free(NoisePerms *p) { free(p); }

/* The table of [key]: the memo's, made there if it is not kept, or, with
 * no memo, made in [scratch]. */
static const uint8_t *perm_of(Eval *ev, uint64_t key, uint8_t scratch[256])
{
    NoisePerms *p = eval_noise_perms(ev);
    if (!p) {
        make_perm(key, scratch);
        return scratch;
    }
    int victim = 0;
    for (int i = 0; i < NOISE_PERMS; i++) {
        if (p->used[i] && p->key[i] == key) {
            p->used[i] = ++p->clock;
            return p->perm[i];
        }
        if (p->used[i] < p->used[victim]) victim = i;
    }
    make_perm(key, p->perm[victim]);
    p->key[victim] = key;
    p->used[victim] = ++p->clock;
    return p->perm[victim];
}

static double grad2(const uint8_t *p, Lat x, Lat y, double dx, double dy)
{
    int g = (p[(p[x & 255] + y) & 255] % 8) * 2;
    return G2[g] * dx + G2[g + 1] * dy;
}

static double grad3(const uint8_t *p, Lat x, Lat y, Lat z, double dx, double dy, double dz)
{
    int g = (p[(p[(p[x & 255] + y) & 255] + z) & 255] % 24) * 3;
    return G3[g] * dx + G3[g + 1] * dy + G3[g + 2] * dz;
}

static double grad4(const uint8_t *p, Lat x, Lat y, Lat z, Lat w, double dx, double dy,
                    double dz, double dw)
{
    int g = p[(p[(p[(p[x & 255] + y) & 255] + z) & 255] + w) & 255] & 0xFC;
    return G4[g] * dx + G4[g + 1] * dy + G4[g + 2] * dz + G4[g + 3] * dw;
}

/* Running sum of contributions for one point. */
typedef struct {
    const uint8_t *perm;   /* the permutation */
    double value;          /* Σ attn⁴ · (gradient · d), reference order */
} Acc;

static void add2(Acc *a, Lat x, Lat y, double dx, double dy)
{
    double attn = 2 - dx * dx - dy * dy;
    if (attn > 0) {
        attn *= attn;
        a->value += attn * attn * grad2(a->perm, x, y, dx, dy);
    }
}

static void add3(Acc *a, Lat x, Lat y, Lat z, double dx, double dy, double dz)
{
    double attn = 2 - dx * dx - dy * dy - dz * dz;
    if (attn > 0) {
        attn *= attn;
        a->value += attn * attn * grad3(a->perm, x, y, z, dx, dy, dz);
    }
}

static void add4(Acc *a, Lat x, Lat y, Lat z, Lat w, double dx, double dy, double dz, double dw)
{
    double attn = 2 - dx * dx - dy * dy - dz * dz - dw * dw;
    if (attn > 0) {
        attn *= attn;
        a->value += attn * attn * grad4(a->perm, x, y, z, w, dx, dy, dz, dw);
    }
}

/* Simplex vertex b + o with d = d0 - o - k*SQUISH, k = Σo. */
static void vert3(Acc *a, const Lat b[3], const double d0[3], int ox, int oy, int oz)
{
    double k = (double)(ox + oy + oz);
    add3(a, b[0] + (Lat)ox, b[1] + (Lat)oy, b[2] + (Lat)oz, d0[0] - ox - k * SQUISH3,
         d0[1] - oy - k * SQUISH3, d0[2] - oz - k * SQUISH3);
}

static void vert4(Acc *a, const Lat b[4], const double d0[4], int ox, int oy, int oz, int ow)
{
    double k = (double)(ox + oy + oz + ow);
    add4(a, b[0] + (Lat)ox, b[1] + (Lat)oy, b[2] + (Lat)oz, b[3] + (Lat)ow,
         d0[0] - ox - k * SQUISH4, d0[1] - oy - k * SQUISH4, d0[2] - oz - k * SQUISH4,
         d0[3] - ow - k * SQUISH4);
}

/* }==================================================================== */

/* {====================================================================
 * 2D
 * ===================================================================== */

static double noise2(const uint8_t *perm, double x, double y)
{
    double so = (x + y) * STRETCH2;
    double xs = x + so, ys = y + so;
    Lat xsb = floor_lat(xs), ysb = floor_lat(ys);
    double sq = lat_d(xsb + ysb) * SQUISH2;
    double xb = lat_d(xsb) + sq, yb = lat_d(ysb) + sq;
    double xins = xs - lat_d(xsb), yins = ys - lat_d(ysb);
    double in_sum = xins + yins;
    double dx0 = x - xb, dy0 = y - yb;
    Acc a = {perm, 0.0};
    Lat xv, yv;
    double dxe, dye;
    add2(&a, xsb + 1, ysb + 0, dx0 - 1 - SQUISH2, dy0 - 0 - SQUISH2);
    add2(&a, xsb + 0, ysb + 1, dx0 - 0 - SQUISH2, dy0 - 1 - SQUISH2);
    if (in_sum <= 1) {
        double zins = 1 - in_sum;
        if (zins > xins || zins > yins) {
            if (xins > yins) {
                xv = xsb + 1, yv = ysb - 1, dxe = dx0 - 1, dye = dy0 + 1;
            } else {
                xv = xsb - 1, yv = ysb + 1, dxe = dx0 + 1, dye = dy0 - 1;
            }
        } else {
            xv = xsb + 1, yv = ysb + 1;
            dxe = dx0 - 1 - 2 * SQUISH2, dye = dy0 - 1 - 2 * SQUISH2;
        }
    } else {
        double zins = 2 - in_sum;
        if (zins < xins || zins < yins) {
            if (xins > yins) {
                xv = xsb + 2, yv = ysb + 0;
                dxe = dx0 - 2 - 2 * SQUISH2, dye = dy0 + 0 - 2 * SQUISH2;
            } else {
                xv = xsb + 0, yv = ysb + 2;
                dxe = dx0 + 0 - 2 * SQUISH2, dye = dy0 - 2 - 2 * SQUISH2;
            }
        } else {
            dxe = dx0, dye = dy0, xv = xsb, yv = ysb;
        }
        xsb += 1;
        ysb += 1;
        dx0 = dx0 - 1 - 2 * SQUISH2;
        dy0 = dy0 - 1 - 2 * SQUISH2;
    }
    add2(&a, xsb, ysb, dx0, dy0);
    add2(&a, xv, yv, dxe, dye);
    return a.value / NORM2;
}

/* }==================================================================== */

/* {====================================================================
 * 3D
 * ===================================================================== */

static double noise3(const uint8_t *perm, double x, double y, double z)
{
    double so = (x + y + z) * STRETCH3;
    double xs = x + so, ys = y + so, zs = z + so;
    Lat b[3] = {floor_lat(xs), floor_lat(ys), floor_lat(zs)};
    Lat xsb = b[0], ysb = b[1], zsb = b[2];
    double sq = lat_d(xsb + ysb + zsb) * SQUISH3;
    double xb = lat_d(xsb) + sq, yb = lat_d(ysb) + sq, zb = lat_d(zsb) + sq;
    double xins = xs - lat_d(xsb), yins = ys - lat_d(ysb), zins = zs - lat_d(zsb);
    double in_sum = xins + yins + zins;
    double d0[3] = {x - xb, y - yb, z - zb};
    double dx0 = d0[0], dy0 = d0[1], dz0 = d0[2];
    const double S = SQUISH3;
    Lat xv0 = 0, xv1 = 0, yv0 = 0, yv1 = 0, zv0 = 0, zv1 = 0;
    double dxe0 = 0, dxe1 = 0, dye0 = 0, dye1 = 0, dze0 = 0, dze1 = 0;
    Acc a = {perm, 0.0};

    if (in_sum <= 1) {
        /* inside the tetrahedron at (0,0,0) */
        int ap = 0x01, bp = 0x02;
        double as = xins, bs = yins;
        if (as >= bs && zins > bs) {
            bs = zins;
            bp = 0x04;
        } else if (as < bs && zins > as) {
            as = zins;
            ap = 0x04;
        }
        double wins = 1 - in_sum;
        if (wins > as || wins > bs) {
            int c = bs > as ? bp : ap;
            if ((c & 0x01) == 0) {
                xv0 = xsb - 1, xv1 = xsb, dxe0 = dx0 + 1, dxe1 = dx0;
            } else {
                xv0 = xv1 = xsb + 1;
                dxe0 = dxe1 = dx0 - 1;
            }
            if ((c & 0x02) == 0) {
                yv0 = yv1 = ysb;
                dye0 = dye1 = dy0;
                if ((c & 0x01) == 0) {
                    yv1 -= 1;
                    dye1 += 1;
                } else {
                    yv0 -= 1;
                    dye0 += 1;
                }
            } else {
                yv0 = yv1 = ysb + 1;
                dye0 = dye1 = dy0 - 1;
            }
            if ((c & 0x04) == 0) {
                zv0 = zsb, zv1 = zsb - 1, dze0 = dz0, dze1 = dz0 + 1;
            } else {
                zv0 = zv1 = zsb + 1;
                dze0 = dze1 = dz0 - 1;
            }
        } else {
            int c = ap | bp;
            if ((c & 0x01) == 0) {
                xv0 = xsb, xv1 = xsb - 1, dxe0 = dx0 - 2 * S, dxe1 = dx0 + 1 - S;
            } else {
                xv0 = xv1 = xsb + 1;
                dxe0 = dx0 - 1 - 2 * S, dxe1 = dx0 - 1 - S;
            }
            if ((c & 0x02) == 0) {
                yv0 = ysb, yv1 = ysb - 1, dye0 = dy0 - 2 * S, dye1 = dy0 + 1 - S;
            } else {
                yv0 = yv1 = ysb + 1;
                dye0 = dy0 - 1 - 2 * S, dye1 = dy0 - 1 - S;
            }
            if ((c & 0x04) == 0) {
                zv0 = zsb, zv1 = zsb - 1, dze0 = dz0 - 2 * S, dze1 = dz0 + 1 - S;
            } else {
                zv0 = zv1 = zsb + 1;
                dze0 = dz0 - 1 - 2 * S, dze1 = dz0 - 1 - S;
            }
        }
        vert3(&a, b, d0, 0, 0, 0);
        vert3(&a, b, d0, 1, 0, 0);
        vert3(&a, b, d0, 0, 1, 0);
        vert3(&a, b, d0, 0, 0, 1);
    } else if (in_sum >= 2) {
        /* inside the tetrahedron at (1,1,1) */
        int ap = 0x06, bp = 0x05;
        double as = xins, bs = yins;
        if (as <= bs && zins < bs) {
            bs = zins;
            bp = 0x03;
        } else if (as > bs && zins < as) {
            as = zins;
            ap = 0x03;
        }
        double wins = 3 - in_sum;
        if (wins < as || wins < bs) {
            int c = bs < as ? bp : ap;
            if ((c & 0x01) != 0) {
                xv0 = xsb + 2, xv1 = xsb + 1;
                dxe0 = dx0 - 2 - 3 * S, dxe1 = dx0 - 1 - 3 * S;
            } else {
                xv0 = xv1 = xsb;
                dxe0 = dxe1 = dx0 - 3 * S;
            }
            if ((c & 0x02) != 0) {
                yv0 = yv1 = ysb + 1;
                dye0 = dye1 = dy0 - 1 - 3 * S;
                if ((c & 0x01) != 0) {
                    yv1 += 1;
                    dye1 -= 1;
                } else {
                    yv0 += 1;
                    dye0 -= 1;
                }
            } else {
                yv0 = yv1 = ysb;
                dye0 = dye1 = dy0 - 3 * S;
            }
            if ((c & 0x04) != 0) {
                zv0 = zsb + 1, zv1 = zsb + 2;
                dze0 = dz0 - 1 - 3 * S, dze1 = dz0 - 2 - 3 * S;
            } else {
                zv0 = zv1 = zsb;
                dze0 = dze1 = dz0 - 3 * S;
            }
        } else {
            int c = ap & bp;
            if ((c & 0x01) != 0) {
                xv0 = xsb + 1, xv1 = xsb + 2, dxe0 = dx0 - 1 - S, dxe1 = dx0 - 2 - 2 * S;
            } else {
                xv0 = xv1 = xsb;
                dxe0 = dx0 - S, dxe1 = dx0 - 2 * S;
            }
            if ((c & 0x02) != 0) {
                yv0 = ysb + 1, yv1 = ysb + 2, dye0 = dy0 - 1 - S, dye1 = dy0 - 2 - 2 * S;
            } else {
                yv0 = yv1 = ysb;
                dye0 = dy0 - S, dye1 = dy0 - 2 * S;
            }
            if ((c & 0x04) != 0) {
                zv0 = zsb + 1, zv1 = zsb + 2, dze0 = dz0 - 1 - S, dze1 = dz0 - 2 - 2 * S;
            } else {
                zv0 = zv1 = zsb;
                dze0 = dz0 - S, dze1 = dz0 - 2 * S;
            }
        }
        vert3(&a, b, d0, 1, 1, 0);
        vert3(&a, b, d0, 1, 0, 1);
        vert3(&a, b, d0, 0, 1, 1);
        vert3(&a, b, d0, 1, 1, 1);
    } else {
        /* inside the octahedron */
        int ap, bp;
        double as, bs;
        bool a_far, b_far;
        double p1 = xins + yins;
        if (p1 > 1) {
            as = p1 - 1, ap = 0x03, a_far = true;
        } else {
            as = 1 - p1, ap = 0x04, a_far = false;
        }
        double p2 = xins + zins;
        if (p2 > 1) {
            bs = p2 - 1, bp = 0x05, b_far = true;
        } else {
            bs = 1 - p2, bp = 0x02, b_far = false;
        }
        double p3 = yins + zins;
        if (p3 > 1) {
            double score = p3 - 1;
            if (as <= bs && as < score) {
                ap = 0x06, a_far = true;
            } else if (as > bs && bs < score) {
                bp = 0x06, b_far = true;
            }
        } else {
            double score = 1 - p3;
            if (as <= bs && as < score) {
                ap = 0x01, a_far = false;
            } else if (as > bs && bs < score) {
                bp = 0x01, b_far = false;
            }
        }
        if (a_far == b_far) {
            if (a_far) {
                dxe0 = dx0 - 1 - 3 * S, dye0 = dy0 - 1 - 3 * S, dze0 = dz0 - 1 - 3 * S;
                xv0 = xsb + 1, yv0 = ysb + 1, zv0 = zsb + 1;
                int c = ap & bp;
                if ((c & 0x01) != 0) {
                    dxe1 = dx0 - 2 - 2 * S, dye1 = dy0 - 2 * S, dze1 = dz0 - 2 * S;
                    xv1 = xsb + 2, yv1 = ysb, zv1 = zsb;
                } else if ((c & 0x02) != 0) {
                    dxe1 = dx0 - 2 * S, dye1 = dy0 - 2 - 2 * S, dze1 = dz0 - 2 * S;
                    xv1 = xsb, yv1 = ysb + 2, zv1 = zsb;
                } else {
                    dxe1 = dx0 - 2 * S, dye1 = dy0 - 2 * S, dze1 = dz0 - 2 - 2 * S;
                    xv1 = xsb, yv1 = ysb, zv1 = zsb + 2;
                }
            } else {
                dxe0 = dx0, dye0 = dy0, dze0 = dz0;
                xv0 = xsb, yv0 = ysb, zv0 = zsb;
                int c = ap | bp;
                if ((c & 0x01) == 0) {
                    dxe1 = dx0 + 1 - S, dye1 = dy0 - 1 - S, dze1 = dz0 - 1 - S;
                    xv1 = xsb - 1, yv1 = ysb + 1, zv1 = zsb + 1;
                } else if ((c & 0x02) == 0) {
                    dxe1 = dx0 - 1 - S, dye1 = dy0 + 1 - S, dze1 = dz0 - 1 - S;
                    xv1 = xsb + 1, yv1 = ysb - 1, zv1 = zsb + 1;
                } else {
                    dxe1 = dx0 - 1 - S, dye1 = dy0 - 1 - S, dze1 = dz0 + 1 - S;
                    xv1 = xsb + 1, yv1 = ysb + 1, zv1 = zsb - 1;
                }
            }
        } else {
            int c1 = a_far ? ap : bp, c2 = a_far ? bp : ap;
            if ((c1 & 0x01) == 0) {
                dxe0 = dx0 + 1 - S, dye0 = dy0 - 1 - S, dze0 = dz0 - 1 - S;
                xv0 = xsb - 1, yv0 = ysb + 1, zv0 = zsb + 1;
            } else if ((c1 & 0x02) == 0) {
                dxe0 = dx0 - 1 - S, dye0 = dy0 + 1 - S, dze0 = dz0 - 1 - S;
                xv0 = xsb + 1, yv0 = ysb - 1, zv0 = zsb + 1;
            } else {
                dxe0 = dx0 - 1 - S, dye0 = dy0 - 1 - S, dze0 = dz0 + 1 - S;
                xv0 = xsb + 1, yv0 = ysb + 1, zv0 = zsb - 1;
            }
            dxe1 = dx0 - 2 * S, dye1 = dy0 - 2 * S, dze1 = dz0 - 2 * S;
            xv1 = xsb, yv1 = ysb, zv1 = zsb;
            if ((c2 & 0x01) != 0) {
                dxe1 -= 2;
                xv1 += 2;
            } else if ((c2 & 0x02) != 0) {
                dye1 -= 2;
                yv1 += 2;
            } else {
                dze1 -= 2;
                zv1 += 2;
            }
        }
        vert3(&a, b, d0, 1, 0, 0);
        vert3(&a, b, d0, 0, 1, 0);
        vert3(&a, b, d0, 0, 0, 1);
        vert3(&a, b, d0, 1, 1, 0);
        vert3(&a, b, d0, 1, 0, 1);
        vert3(&a, b, d0, 0, 1, 1);
    }
    add3(&a, xv0, yv0, zv0, dxe0, dye0, dze0);
    add3(&a, xv1, yv1, zv1, dxe1, dye1, dze1);
    return a.value / NORM3;
}

/* }==================================================================== */

/* {====================================================================
 * 4D
 * ===================================================================== */

/* The three extra vertices of a 4D evaluation: v[axis][k] and d[axis][k]
 * for axis x, y, z, w = 0..3 and vertex k = 0..2. */
typedef struct {
    Lat v[4][3];      /* lattice coordinates */
    double d[4][3];   /* distances */
} Ext4;

/* Set vertex k on every axis to b + off with distance d0 - off - S·sq. */
static void ext4_all(Ext4 *e, int k, const Lat b[4], const double d0[4], int off, int sq)
{
    for (int ax = 0; ax < 4; ax++) {
        e->v[ax][k] = b[ax] + (Lat)off;
        e->d[ax][k] = off == 0 && sq == 0 ? d0[ax] : d0[ax] - off - sq * SQUISH4;
    }
}

/* Move vertex k by [step] along the first axis whose bit is set in [c]
 * (when [set]) or clear in [c] (when !set), w being the fallback. */
static void ext4_step(Ext4 *e, int k, int c, bool set, int step)
{
    int ax = 0;
    while (ax < 3 && (((c >> ax) & 1) != 0) != set)
        ax++;
    e->v[ax][k] += (Lat)(int64_t)step;
    e->d[ax][k] -= step;
}

/* Ext vertices 0 and 1 below the midpoint from point set [c] (the
 * reference's "(c & 0x01) == 0 ..." block with one SQUISH). */
static void ext4_low_pair(Ext4 *e, int c, const Lat b[4], const double d0[4])
{
    const double S = SQUISH4;
    Lat *xv = e->v[0], *yv = e->v[1], *zv = e->v[2], *wv = e->v[3];
    double *dx = e->d[0], *dy = e->d[1], *dz = e->d[2], *dw = e->d[3];
    if ((c & 0x01) == 0) {
        xv[0] = b[0] - 1, xv[1] = b[0], dx[0] = d0[0] + 1 - S, dx[1] = d0[0] - S;
    } else {
        xv[0] = xv[1] = b[0] + 1;
        dx[0] = dx[1] = d0[0] - 1 - S;
    }
    if ((c & 0x02) == 0) {
        yv[0] = yv[1] = b[1];
        dy[0] = dy[1] = d0[1] - S;
        if ((c & 0x01) == 0x01) {
            yv[0] -= 1;
            dy[0] += 1;
        } else {
            yv[1] -= 1;
            dy[1] += 1;
        }
    } else {
        yv[0] = yv[1] = b[1] + 1;
        dy[0] = dy[1] = d0[1] - 1 - S;
    }
    if ((c & 0x04) == 0) {
        zv[0] = zv[1] = b[2];
        dz[0] = dz[1] = d0[2] - S;
        if ((c & 0x03) == 0x03) {
            zv[0] -= 1;
            dz[0] += 1;
        } else {
            zv[1] -= 1;
            dz[1] += 1;
        }
    } else {
        zv[0] = zv[1] = b[2] + 1;
        dz[0] = dz[1] = d0[2] - 1 - S;
    }
    if ((c & 0x08) == 0) {
        wv[0] = b[3], wv[1] = b[3] - 1, dw[0] = d0[3] - S, dw[1] = d0[3] + 1 - S;
    } else {
        wv[0] = wv[1] = b[3] + 1;
        dw[0] = dw[1] = d0[3] - 1 - S;
    }
}

/* Ext vertices 0 and 1 above the midpoint from point set [c] (three
 * SQUISHes). */
static void ext4_high_pair(Ext4 *e, int c, const Lat b[4], const double d0[4])
{
    const double S3 = 3 * SQUISH4;
    Lat *xv = e->v[0], *yv = e->v[1], *zv = e->v[2], *wv = e->v[3];
    double *dx = e->d[0], *dy = e->d[1], *dz = e->d[2], *dw = e->d[3];
    if ((c & 0x01) != 0) {
        xv[0] = b[0] + 2, xv[1] = b[0] + 1, dx[0] = d0[0] - 2 - S3, dx[1] = d0[0] - 1 - S3;
    } else {
        xv[0] = xv[1] = b[0];
        dx[0] = dx[1] = d0[0] - S3;
    }
    if ((c & 0x02) != 0) {
        yv[0] = yv[1] = b[1] + 1;
        dy[0] = dy[1] = d0[1] - 1 - S3;
        if ((c & 0x01) == 0) {
            yv[0] += 1;
            dy[0] -= 1;
        } else {
            yv[1] += 1;
            dy[1] -= 1;
        }
    } else {
        yv[0] = yv[1] = b[1];
        dy[0] = dy[1] = d0[1] - S3;
    }
    if ((c & 0x04) != 0) {
        zv[0] = zv[1] = b[2] + 1;
        dz[0] = dz[1] = d0[2] - 1 - S3;
        if ((c & 0x03) == 0) {
            zv[0] += 1;
            dz[0] -= 1;
        } else {
            zv[1] += 1;
            dz[1] -= 1;
        }
    } else {
        zv[0] = zv[1] = b[2];
        dz[0] = dz[1] = d0[2] - S3;
    }
    if ((c & 0x08) != 0) {
        wv[0] = b[3] + 1, wv[1] = b[3] + 2, dw[0] = d0[3] - 1 - S3, dw[1] = d0[3] - 2 - S3;
    } else {
        wv[0] = wv[1] = b[3];
        dw[0] = dw[1] = d0[3] - S3;
    }
}

/* Region in_sum <= 1: the pentachoron at (0,0,0,0). */
static void ext4_region0(Ext4 *e, const Lat b[4], const double d0[4], const double ins[4],
                         double in_sum)
{
    const double S = SQUISH4;
    Lat *xv = e->v[0], *yv = e->v[1], *zv = e->v[2], *wv = e->v[3];
    double *dx = e->d[0], *dy = e->d[1], *dz = e->d[2], *dw = e->d[3];
    int ap = 0x01, bp = 0x02;
    double as = ins[0], bs = ins[1];
    for (int ax = 2; ax < 4; ax++) {
        if (as >= bs && ins[ax] > bs) {
            bs = ins[ax];
            bp = 1 << ax;
        } else if (as < bs && ins[ax] > as) {
            as = ins[ax];
            ap = 1 << ax;
        }
    }
    double uins = 1 - in_sum;
    if (uins > as || uins > bs) {
        int c = bs > as ? bp : ap;
        if ((c & 0x01) == 0) {
            xv[0] = b[0] - 1, xv[1] = xv[2] = b[0];
            dx[0] = d0[0] + 1, dx[1] = dx[2] = d0[0];
        } else {
            xv[0] = xv[1] = xv[2] = b[0] + 1;
            dx[0] = dx[1] = dx[2] = d0[0] - 1;
        }
        if ((c & 0x02) == 0) {
            yv[0] = yv[1] = yv[2] = b[1];
            dy[0] = dy[1] = dy[2] = d0[1];
            int k = (c & 0x01) == 0x01 ? 0 : 1;
            yv[k] -= 1;
            dy[k] += 1;
        } else {
            yv[0] = yv[1] = yv[2] = b[1] + 1;
            dy[0] = dy[1] = dy[2] = d0[1] - 1;
        }
        if ((c & 0x04) == 0) {
            zv[0] = zv[1] = zv[2] = b[2];
            dz[0] = dz[1] = dz[2] = d0[2];
            int k = (c & 0x03) != 0 ? ((c & 0x03) == 0x03 ? 0 : 1) : 2;
            zv[k] -= 1;
            dz[k] += 1;
        } else {
            zv[0] = zv[1] = zv[2] = b[2] + 1;
            dz[0] = dz[1] = dz[2] = d0[2] - 1;
        }
        if ((c & 0x08) == 0) {
            wv[0] = wv[1] = b[3], wv[2] = b[3] - 1;
            dw[0] = dw[1] = d0[3], dw[2] = d0[3] + 1;
        } else {
            wv[0] = wv[1] = wv[2] = b[3] + 1;
            dw[0] = dw[1] = dw[2] = d0[3] - 1;
        }
    } else {
        int c = ap | bp;
        if ((c & 0x01) == 0) {
            xv[0] = xv[2] = b[0], xv[1] = b[0] - 1;
            dx[0] = d0[0] - 2 * S, dx[1] = d0[0] + 1 - S, dx[2] = d0[0] - S;
        } else {
            xv[0] = xv[1] = xv[2] = b[0] + 1;
            dx[0] = d0[0] - 1 - 2 * S;
            dx[1] = dx[2] = d0[0] - 1 - S;
        }
        if ((c & 0x02) == 0) {
            yv[0] = yv[1] = yv[2] = b[1];
            dy[0] = d0[1] - 2 * S;
            dy[1] = dy[2] = d0[1] - S;
            int k = (c & 0x01) == 0x01 ? 1 : 2;
            yv[k] -= 1;
            dy[k] += 1;
        } else {
            yv[0] = yv[1] = yv[2] = b[1] + 1;
            dy[0] = d0[1] - 1 - 2 * S;
            dy[1] = dy[2] = d0[1] - 1 - S;
        }
        if ((c & 0x04) == 0) {
            zv[0] = zv[1] = zv[2] = b[2];
            dz[0] = d0[2] - 2 * S;
            dz[1] = dz[2] = d0[2] - S;
            int k = (c & 0x03) == 0x03 ? 1 : 2;
            zv[k] -= 1;
            dz[k] += 1;
        } else {
            zv[0] = zv[1] = zv[2] = b[2] + 1;
            dz[0] = d0[2] - 1 - 2 * S;
            dz[1] = dz[2] = d0[2] - 1 - S;
        }
        if ((c & 0x08) == 0) {
            wv[0] = wv[1] = b[3], wv[2] = b[3] - 1;
            dw[0] = d0[3] - 2 * S, dw[1] = d0[3] - S, dw[2] = d0[3] + 1 - S;
        } else {
            wv[0] = wv[1] = wv[2] = b[3] + 1;
            dw[0] = d0[3] - 1 - 2 * S;
            dw[1] = dw[2] = d0[3] - 1 - S;
        }
    }
}

/* Region in_sum >= 3: the pentachoron at (1,1,1,1). */
static void ext4_region4(Ext4 *e, const Lat b[4], const double d0[4], const double ins[4],
                         double in_sum)
{
    const double S = SQUISH4;
    Lat *xv = e->v[0], *yv = e->v[1], *zv = e->v[2], *wv = e->v[3];
    double *dx = e->d[0], *dy = e->d[1], *dz = e->d[2], *dw = e->d[3];
    int ap = 0x0E, bp = 0x0D;
    double as = ins[0], bs = ins[1];
    for (int ax = 2; ax < 4; ax++) {
        if (as <= bs && ins[ax] < bs) {
            bs = ins[ax];
            bp = 0x0F & ~(1 << ax);
        } else if (as > bs && ins[ax] < as) {
            as = ins[ax];
            ap = 0x0F & ~(1 << ax);
        }
    }
    double uins = 4 - in_sum;
    if (uins < as || uins < bs) {
        int c = bs < as ? bp : ap;
        if ((c & 0x01) != 0) {
            xv[0] = b[0] + 2, xv[1] = xv[2] = b[0] + 1;
            dx[0] = d0[0] - 2 - 4 * S;
            dx[1] = dx[2] = d0[0] - 1 - 4 * S;
        } else {
            xv[0] = xv[1] = xv[2] = b[0];
            dx[0] = dx[1] = dx[2] = d0[0] - 4 * S;
        }
        if ((c & 0x02) != 0) {
            yv[0] = yv[1] = yv[2] = b[1] + 1;
            dy[0] = dy[1] = dy[2] = d0[1] - 1 - 4 * S;
            int k = (c & 0x01) != 0 ? 1 : 0;
            yv[k] += 1;
            dy[k] -= 1;
        } else {
            yv[0] = yv[1] = yv[2] = b[1];
            dy[0] = dy[1] = dy[2] = d0[1] - 4 * S;
        }
        if ((c & 0x04) != 0) {
            zv[0] = zv[1] = zv[2] = b[2] + 1;
            dz[0] = dz[1] = dz[2] = d0[2] - 1 - 4 * S;
            int k = (c & 0x03) != 0x03 ? ((c & 0x03) == 0 ? 0 : 1) : 2;
            zv[k] += 1;
            dz[k] -= 1;
        } else {
            zv[0] = zv[1] = zv[2] = b[2];
            dz[0] = dz[1] = dz[2] = d0[2] - 4 * S;
        }
        if ((c & 0x08) != 0) {
            wv[0] = wv[1] = b[3] + 1, wv[2] = b[3] + 2;
            dw[0] = dw[1] = d0[3] - 1 - 4 * S;
            dw[2] = d0[3] - 2 - 4 * S;
        } else {
            wv[0] = wv[1] = wv[2] = b[3];
            dw[0] = dw[1] = dw[2] = d0[3] - 4 * S;
        }
    } else {
        int c = ap & bp;
        if ((c & 0x01) != 0) {
            xv[0] = xv[2] = b[0] + 1, xv[1] = b[0] + 2;
            dx[0] = d0[0] - 1 - 2 * S, dx[1] = d0[0] - 2 - 3 * S, dx[2] = d0[0] - 1 - 3 * S;
        } else {
            xv[0] = xv[1] = xv[2] = b[0];
            dx[0] = d0[0] - 2 * S;
            dx[1] = dx[2] = d0[0] - 3 * S;
        }
        if ((c & 0x02) != 0) {
            yv[0] = yv[1] = yv[2] = b[1] + 1;
            dy[0] = d0[1] - 1 - 2 * S;
            dy[1] = dy[2] = d0[1] - 1 - 3 * S;
            int k = (c & 0x01) != 0 ? 2 : 1;
            yv[k] += 1;
            dy[k] -= 1;
        } else {
            yv[0] = yv[1] = yv[2] = b[1];
            dy[0] = d0[1] - 2 * S;
            dy[1] = dy[2] = d0[1] - 3 * S;
        }
        if ((c & 0x04) != 0) {
            zv[0] = zv[1] = zv[2] = b[2] + 1;
            dz[0] = d0[2] - 1 - 2 * S;
            dz[1] = dz[2] = d0[2] - 1 - 3 * S;
            int k = (c & 0x03) != 0 ? 2 : 1;
            zv[k] += 1;
            dz[k] -= 1;
        } else {
            zv[0] = zv[1] = zv[2] = b[2];
            dz[0] = d0[2] - 2 * S;
            dz[1] = dz[2] = d0[2] - 3 * S;
        }
        if ((c & 0x08) != 0) {
            wv[0] = wv[1] = b[3] + 1, wv[2] = b[3] + 2;
            dw[0] = d0[3] - 1 - 2 * S, dw[1] = d0[3] - 1 - 3 * S, dw[2] = d0[3] - 2 - 3 * S;
        } else {
            wv[0] = wv[1] = wv[2] = b[3];
            dw[0] = d0[3] - 2 * S;
            dw[1] = dw[2] = d0[3] - 3 * S;
        }
    }
}

/* The two closest points of the octahedral regions (1 < in_sum < 3):
 * scores and point sets as in the reference. [upper] selects the region
 * 2 < in_sum < 3, whose comparisons are reversed. Outputs the two point
 * sets and whether each is on the "bigger side". */
static void octa4_scores(const double ins[4], double in_sum, bool upper, int *ap_out,
                         int *bp_out, bool *a_big_out, bool *b_big_out)
{
    double xins = ins[0], yins = ins[1], zins = ins[2], wins = ins[3];
    bool a_big = true, b_big = true;
    int ap, bp;
    double as, bs;
    /* "better" is > below the midpoint and < above it */
#define BETTER(p, q) (upper ? (p) < (q) : (p) > (q))
#define NOT_WORSE(p, q) (upper ? (p) <= (q) : (p) >= (q))
#define WORSE(p, q) (upper ? (p) > (q) : (p) < (q))
    if (BETTER(xins + yins, zins + wins)) {
        as = xins + yins;
        ap = upper ? 0x0C : 0x03;
    } else {
        as = zins + wins;
        ap = upper ? 0x03 : 0x0C;
    }
    if (BETTER(xins + zins, yins + wins)) {
        bs = xins + zins;
        bp = upper ? 0x0A : 0x05;
    } else {
        bs = yins + wins;
        bp = upper ? 0x05 : 0x0A;
    }
    double score;
    int sp;
    if (BETTER(xins + wins, yins + zins)) {
        score = xins + wins;
        sp = upper ? 0x06 : 0x09;
    } else {
        score = yins + zins;
        sp = upper ? 0x09 : 0x06;
    }
    if (NOT_WORSE(as, bs) && BETTER(score, bs)) {
        bs = score;
        bp = sp;
    } else if (WORSE(as, bs) && BETTER(score, as)) {
        as = score;
        ap = sp;
    }
    double base = upper ? 3 - in_sum : 2 - in_sum;
    for (int ax = 0; ax < 4; ax++) {
        double p = base + ins[ax];
        int pp = upper ? 0x0F & ~(1 << ax) : 1 << ax;
        if (NOT_WORSE(as, bs) && BETTER(p, bs)) {
            if (ax < 3)
                bs = p;
            bp = pp;
            b_big = false;
        } else if (WORSE(as, bs) && BETTER(p, as)) {
            if (ax < 3)
                as = p;
            ap = pp;
            a_big = false;
        }
    }
#undef BETTER
#undef NOT_WORSE
#undef WORSE
    *ap_out = ap;
    *bp_out = bp;
    *a_big_out = a_big;
    *b_big_out = b_big;
}

/* Region 1 < in_sum <= 2: the first dispentachoron. */
static void ext4_region1(Ext4 *e, const Lat b[4], const double d0[4], const double ins[4],
                         double in_sum)
{
    const double S = SQUISH4;
    int ap, bp;
    bool a_big, b_big;
    octa4_scores(ins, in_sum, false, &ap, &bp, &a_big, &b_big);
    if (a_big == b_big) {
        if (a_big) {
            int c1 = ap | bp, c2 = ap & bp;
            for (int ax = 0; ax < 4; ax++) {
                if ((c1 & (1 << ax)) == 0) {
                    e->v[ax][0] = b[ax], e->v[ax][1] = b[ax] - 1;
                    e->d[ax][0] = d0[ax] - 3 * S, e->d[ax][1] = d0[ax] + 1 - 2 * S;
                } else {
                    e->v[ax][0] = e->v[ax][1] = b[ax] + 1;
                    e->d[ax][0] = d0[ax] - 1 - 3 * S, e->d[ax][1] = d0[ax] - 1 - 2 * S;
                }
            }
            ext4_all(e, 2, b, d0, 0, 2);
            ext4_step(e, 2, c2, true, 2);
        } else {
            ext4_all(e, 2, b, d0, 0, 0);
            ext4_low_pair(e, ap | bp, b, d0);
        }
    } else {
        int c1 = a_big ? ap : bp, c2 = a_big ? bp : ap;
        ext4_low_pair(e, c1, b, d0);
        ext4_all(e, 2, b, d0, 0, 2);
        ext4_step(e, 2, c2, true, 2);
    }
}

/* Region 2 < in_sum < 3: the second dispentachoron. */
static void ext4_region2(Ext4 *e, const Lat b[4], const double d0[4], const double ins[4],
                         double in_sum)
{
    int ap, bp;
    bool a_big, b_big;
    octa4_scores(ins, in_sum, true, &ap, &bp, &a_big, &b_big);
    if (a_big == b_big) {
        if (a_big) {
            int c1 = ap & bp, c2 = ap | bp;
            ext4_all(e, 0, b, d0, 0, 1);
            ext4_all(e, 1, b, d0, 0, 2);
            int ax = 0;
            while (ax < 3 && (c1 & (1 << ax)) == 0)
                ax++;
            e->v[ax][0] += 1;
            e->d[ax][0] -= 1;
            e->v[ax][1] += 2;
            e->d[ax][1] -= 2;
            ext4_all(e, 2, b, d0, 1, 2);
            ext4_step(e, 2, c2, false, -2);
        } else {
            ext4_all(e, 2, b, d0, 1, 4);
            ext4_high_pair(e, ap & bp, b, d0);
        }
    } else {
        int c1 = a_big ? ap : bp, c2 = a_big ? bp : ap;
        ext4_high_pair(e, c1, b, d0);
        ext4_all(e, 2, b, d0, 1, 2);
        ext4_step(e, 2, c2, false, -2);
    }
}

/* The ten vertices (offset sums 1 and 2, or 3 and 2) of the octahedral
 * regions, in the reference's order. */
static void octa4_vertices(Acc *a, const Lat b[4], const double d0[4], bool upper)
{
    if (upper) {
        vert4(a, b, d0, 1, 1, 1, 0);
        vert4(a, b, d0, 1, 1, 0, 1);
        vert4(a, b, d0, 1, 0, 1, 1);
        vert4(a, b, d0, 0, 1, 1, 1);
    } else {
        vert4(a, b, d0, 1, 0, 0, 0);
        vert4(a, b, d0, 0, 1, 0, 0);
        vert4(a, b, d0, 0, 0, 1, 0);
        vert4(a, b, d0, 0, 0, 0, 1);
    }
    vert4(a, b, d0, 1, 1, 0, 0);
    vert4(a, b, d0, 1, 0, 1, 0);
    vert4(a, b, d0, 1, 0, 0, 1);
    vert4(a, b, d0, 0, 1, 1, 0);
    vert4(a, b, d0, 0, 1, 0, 1);
    vert4(a, b, d0, 0, 0, 1, 1);
}

static double noise4(const uint8_t *perm, double x, double y, double z, double w)
{
    double so = (x + y + z + w) * STRETCH4;
    double xs = x + so, ys = y + so, zs = z + so, ws = w + so;
    Lat b[4] = {floor_lat(xs), floor_lat(ys), floor_lat(zs), floor_lat(ws)};
    double sq = lat_d(b[0] + b[1] + b[2] + b[3]) * SQUISH4;
    double xb = lat_d(b[0]) + sq, yb = lat_d(b[1]) + sq, zb = lat_d(b[2]) + sq,
           wb = lat_d(b[3]) + sq;
    double ins[4] = {xs - lat_d(b[0]), ys - lat_d(b[1]), zs - lat_d(b[2]), ws - lat_d(b[3])};
    double in_sum = ins[0] + ins[1] + ins[2] + ins[3];
    double d0[4] = {x - xb, y - yb, z - zb, w - wb};
    Ext4 e = {{{0}}, {{0}}};
    Acc a = {perm, 0.0};
    if (in_sum <= 1) {
        ext4_region0(&e, b, d0, ins, in_sum);
        vert4(&a, b, d0, 0, 0, 0, 0);
        vert4(&a, b, d0, 1, 0, 0, 0);
        vert4(&a, b, d0, 0, 1, 0, 0);
        vert4(&a, b, d0, 0, 0, 1, 0);
        vert4(&a, b, d0, 0, 0, 0, 1);
    } else if (in_sum >= 3) {
        ext4_region4(&e, b, d0, ins, in_sum);
        vert4(&a, b, d0, 1, 1, 1, 0);
        vert4(&a, b, d0, 1, 1, 0, 1);
        vert4(&a, b, d0, 1, 0, 1, 1);
        vert4(&a, b, d0, 0, 1, 1, 1);
        vert4(&a, b, d0, 1, 1, 1, 1);
    } else if (in_sum <= 2) {
        ext4_region1(&e, b, d0, ins, in_sum);
        octa4_vertices(&a, b, d0, false);
    } else {
        ext4_region2(&e, b, d0, ins, in_sum);
        octa4_vertices(&a, b, d0, true);
    }
    for (int k = 0; k < 3; k++)
        add4(&a, e.v[0][k], e.v[1][k], e.v[2][k], e.v[3][k], e.d[0][k], e.d[1][k], e.d[2][k],
             e.d[3][k]);
    return a.value / NORM4;
}

/* }==================================================================== */

/* {====================================================================
 * Built-ins
 * ===================================================================== */

/* Noise of [perm] over the outer product of [n] coordinate vectors (x
 * outermost), written to [out]; 1 coordinate means (x, 0). The grid can
 * hold 2^26 points (minutes of work for many octaves), so the interrupt
 * flag is looked at every NOISE_POLL points.
 *   returns: false when [ev]'s interrupt stopped it ([out] incomplete). */
enum { NOISE_POLL = 1 << 14 };
#define NOISE_AT(expr)                                                          \
    do {                                                                        \
        if ((k & (NOISE_POLL - 1)) == 0 && eval_interrupted(ev)) return false; \
        out[k++] = (expr);                                                      \
    } while (0)
static bool noise_grid(Eval *ev, const uint8_t *perm, int n, const double *const *c,
                       const uint32_t *len, double *out)
{
    size_t k = 0;
    if (n == 1) {
        for (uint32_t i = 0; i < len[0]; i++)
            NOISE_AT(noise2(perm, c[0][i], 0));
    } else if (n == 2) {
        for (uint32_t i = 0; i < len[0]; i++)
            for (uint32_t j = 0; j < len[1]; j++)
                NOISE_AT(noise2(perm, c[0][i], c[1][j]));
    } else if (n == 3) {
        for (uint32_t i = 0; i < len[0]; i++)
            for (uint32_t j = 0; j < len[1]; j++)
                for (uint32_t l = 0; l < len[2]; l++)
                    NOISE_AT(noise3(perm, c[0][i], c[1][j], c[2][l]));
    } else {
        for (uint32_t i = 0; i < len[0]; i++)
            for (uint32_t j = 0; j < len[1]; j++)
                for (uint32_t l = 0; l < len[2]; l++)
                    for (uint32_t m = 0; m < len[3]; m++)
                        NOISE_AT(noise4(perm, c[0][i], c[1][j], c[2][l], c[3][m]));
    }
    return true;
}
#undef NOISE_AT

/* Check the [n] coordinate vectors: 1..4 of them, all numeric, result not
 * too long. Returns the result length, or 0 for null (*too_long set when
 * that is because of the size). */
static uint64_t grid_size(int n, Vec *const *coords, bool *too_long)
{
    *too_long = false;
    if (n < 1 || n > 4)
        return 0;
    uint64_t total = 1;
    for (int i = 0; i < n; i++) {
        if (!vec_is_num(coords[i]))
            return 0;
        total *= coords[i]->len;
        if (total > MAX_RESULT) {
            *too_long = true;
            return 0;
        }
    }
    if (!mem_fits(sizeof(Vec) + total * sizeof(double))) {   /* the budget, mem.h */
        *too_long = true;
        return 0;
    }
    return total;
}

/* noise of [seed] over [n] coordinate vectors with the permutation of
 * octave 0: null unless 1..4 coordinates, all numeric. */
static Vec *noise_of(Eval *ev, const Builtin *bi, const Vec *seed, int n, Vec *const *coords)
{
    bool too_long;
    uint64_t total = grid_size(n, coords, &too_long);
    if (total == 0)
        return too_long ? bi_error(ev, bi, mem_take_refusal() ? "out of memory" : "result too long") : NULL;
    uint8_t scratch[256];
    const uint8_t *perm = perm_of(ev, vec_hash(seed, true), scratch);
    const double *c[4];
    uint32_t len[4];
    for (int i = 0; i < n; i++) {
        c[i] = vec_cnums(coords[i]);
        len[i] = coords[i]->len;
    }
    Vec *r = vec_new_num((uint32_t)total);
    if (!noise_grid(ev, perm, n, c, len, vec_nums(r))) {
        vec_release(r);   /* interrupted: the frame is discarded */
        return NULL;
    }
    return r;
}

/* noise(seed, x [, y [, z [, w]]]) */
static Vec *bi_noise(BI_PARAMS)
{
    return noise_of(ev, bi, args[0], nargs - 1, args + 1);
}

bool bi_noise_route(const Builtin *bi, uint32_t nargs)
{
    return bi->fn == bi_noise && nargs >= 2 && nargs <= BI_NOISE_ARGS;
}

bool bi_noise_nums(Eval *ev, const Builtin *bi, const double *const *x, const uint32_t *n, uint32_t nargs,
                   double *out, uint32_t *nout)
{
    if (!bi_noise_route(bi, nargs))
        return false;
    /* noise_of's grid_size, its refusals left to the builtin */
    uint64_t total = 1;
    for (uint32_t i = 1; i < nargs; i++)
        total *= n[i];
    if (total > BI_NUMS_MAX || !mem_room(sizeof(Vec) + total * sizeof(double)))
        return false;
    uint8_t scratch[256];
    const uint8_t *perm = perm_of(ev, vec_hash_nums(x[0], n[0], true), scratch);
    if (total == 1) {
        /* one point: noise_grid's first value, without its loops (and
         * its poll, which comes before any work) */
        switch (nargs) {
        case 2: out[0] = noise2(perm, x[1][0], 0); break;
        case 3: out[0] = noise2(perm, x[1][0], x[2][0]); break;
        case 4: out[0] = noise3(perm, x[1][0], x[2][0], x[3][0]); break;
        default: out[0] = noise4(perm, x[1][0], x[2][0], x[3][0], x[4][0]); break;
        }
    } else if (!noise_grid(ev, perm, (int)nargs - 1, x + 1, n + 1, out)) {
        return false;
    }
    *nout = (uint32_t)total;
    return true;
}

/* octnoise(seed, octaves, roughness, coords...): octave i uses the
 * permutation keyed seed-hash XOR i at coordinates doubled i times;
 * result = Σ value_i * roughness^i / Σ roughness^i, accumulated as the
 * reference does (octave 0 taken as is). */
static Vec *bi_octnoise(BI_PARAMS)
{
    const Vec *octaves = args[1], *roughness = args[2];
    if (!vec_is_scalar(octaves) || !vec_is_scalar(roughness))
        return NULL;
    double o = vec_scalar(octaves);
    int64_t n = (o >= -9223372036854775808.0 && o < 9223372036854775808.0) ? (int64_t)o
                                                                           : INT64_MIN;
    int nc = nargs - 3;
    if (n == 1)
        return noise_of(ev, bi, args[0], nc, args + 3);
    for (int i = 0; i < nc; i++)
        if (!vec_is_num(args[3 + i]))
            return NULL;
    if (n <= 0)
        return NULL;
    bool too_long;
    uint64_t total = grid_size(nc, args + 3, &too_long);
    if (total == 0)
        return too_long ? bi_error(ev, bi, mem_take_refusal() ? "out of memory" : "result too long") : NULL;
    if (n > MAX_OCTAVES)
        return bi_error(ev, bi, "too many octaves");
    uint64_t key = vec_hash(args[0], true);
    double *c[4];
    const double *cc[4];
    uint32_t len[4];
    Vec *coords[4];
    for (int i = 0; i < nc; i++) {
        len[i] = args[3 + i]->len;
        coords[i] = vec_from_nums(vec_cnums(args[3 + i]), len[i]);
        c[i] = vec_nums(coords[i]);
        cc[i] = c[i];
    }
    Vec *r = vec_new_num((uint32_t)total), *single = vec_new_num((uint32_t)total);
    double *res = vec_nums(r), *one = vec_nums(single);
    double weight_sum = 0, weight = 1, k = vec_scalar(roughness);
    uint8_t scratch[256];
    bool stopped = false;
    for (int64_t i = 0; i < n && !stopped; i++) {
        const uint8_t *perm = perm_of(ev, key ^ (uint64_t)i, scratch);
        if (i == 0) {
            stopped = !noise_grid(ev, perm, nc, cc, len, res);
        } else {
            stopped = !noise_grid(ev, perm, nc, cc, len, one);
            for (uint64_t j = 0; j < total; j++)
                res[j] += one[j] * weight;
        }
        for (int a = 0; a < nc; a++)
            for (uint32_t j = 0; j < len[a]; j++)
                c[a][j] *= 2;
        weight_sum += weight;
        weight *= k;
    }
    for (uint64_t j = 0; j < total && !stopped; j++)
        res[j] /= weight_sum;
    vec_release(single);
    for (int i = 0; i < nc; i++)
        vec_release(coords[i]);
    if (stopped) {   /* interrupted: the frame is discarded */
        vec_release(r);
        return NULL;
    }
    return r;
}

/* }==================================================================== */

const Builtin bi_noise_table[] = {
    {"noise", "noise", 1, BI_VARIADIC, {"seed"}, bi_noise, 0},
    {"octnoise", "octnoise", 3, BI_VARIADIC, {"seed", "octaves", "roughness"}, bi_octnoise, 0},
    {NULL, NULL, 0, 0, {NULL}, NULL, 0},
};
