/* turns.c: sine and cosine of an angle in turns with exact quadrants
 * (LANGUAGE.md §5.2): sin_t/cos_t of turns.h. A leaf of the core layer,
 * used by the maths and colour built-ins and by the normal random stream.
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "turns.h"

/* sin_t's reduction of [t] (0 <= t, or -0, with 4t < 2^52): remquo(4t,
 * 1) without the libm call: n = 4t rounded to nearest, ties to even
 * (adding and removing 2^52 does exactly that for 0 <= x < 2^52), and
 * x - n is exact; a zero keeps x's sign. The quadrant into [q], the
 * remainder (before the scaling by pi/2) returned. */
static inline double reduce_turns(double t, int *q)
{
    double x = t * 4.0;
    double n = (x + 0x1p52) - 0x1p52;
    double r = x - n;
    if (r == 0) r = copysign(0.0, x);
    *q = (int)((int64_t)n & 3);
    return r;
}

/* sin_t of a non-negative angle whose reduction is quadrant [q] and
 * remainder [r]: its one call of sin or cos. */
static inline double quadrant_value(int q, double r)
{
    r *= HALF_PI;
    switch (q & 3) {
    case 0: return sin(r);
    case 1: return cos(r);
    case 2: return -sin(r);
    default: return -cos(r);
    }
}

double sin_t(double t)
{
    if (t < 0)
        return -sin_t(-t);
    int q = 0;
    double x = t * 4.0, r;
    if (x < 0x1p52)
        r = reduce_turns(t, &q);
    else
        r = remquo(x, 1.0, &q);   /* huge, infinite or NaN */
    return quadrant_value(q, r);
}

double cos_t(double t)
{
    return sin_t(t + 0.25);
}

/* sin_t's choice by quadrant among s = sin(r), c = cos(r). */
static inline double by_quadrant(int q, double s, double c)
{
    switch (q & 3) {
    case 0: return s;
    case 1: return c;
    case 2: return -s;
    default: return -c;
    }
}

void sincos_t(double t, double *s, double *c)
{
#if defined(__GLIBC__)
    /* cos_t(t) is sin_t(u), u = t + 0.25: when both reduce to the same
     * remainder (u exactly t + 1/4, not a tie of the quadrant rounding,
     * and not -1/4 < t <= 0, where the two remainders have opposite
     * signs), sin and cos of that one angle give both, by one call.
     * glibc's sincos(x) is its sin(x) and cos(x) (the same code for
     * |x| <= pi/4; tests/unit/test_turns.c compares them); elsewhere two
     * calls. */
    const double u = t + 0.25;
    const double at = t < 0 ? -t : t, au = u < 0 ? -u : u;
    if (at * 4.0 < 0x1p52 && au * 4.0 < 0x1p52) {   /* not NaN, infinite or huge */
        int qt, qu;
        const double rt = reduce_turns(at, &qt), ru = reduce_turns(au, &qu);
        double vs, vc;
        if (memcmp(&rt, &ru, sizeof rt) == 0) {
            double sr, cr;
            sincos(rt * HALF_PI, &sr, &cr);
            vs = by_quadrant(qt, sr, cr);
            vc = by_quadrant(qu, sr, cr);
        } else {
            /* two remainders: sin_t's one call for each, on the
             * reductions already made */
            vs = quadrant_value(qt, rt);
            vc = quadrant_value(qu, ru);
        }
        *s = t < 0 ? -vs : vs;
        *c = u < 0 ? -vc : vc;
        return;
    }
#endif
    *s = sin_t(t);
    *c = cos_t(t);
}
