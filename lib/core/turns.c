/* turns.c: sine and cosine of an angle in turns with exact quadrants
 * (LANGUAGE.md §5.2): sin_t/cos_t of turns.h. A leaf of the core layer,
 * used by the maths and colour built-ins and by the normal random stream.
 */
#include <math.h>
#include <stdint.h>

#include "turns.h"

double sin_t(double t)
{
    if (t < 0)
        return -sin_t(-t);
    int q = 0;
    double x = t * 4.0, r;
    if (x < 0x1p52) {
        /* remquo(x, 1) without the libm call: n = x rounded to nearest,
         * ties to even (adding and removing 2^52 does exactly that for
         * 0 <= x < 2^52), and x - n is exact; a zero keeps x's sign */
        double n = (x + 0x1p52) - 0x1p52;
        r = x - n;
        if (r == 0) r = copysign(0.0, x);
        q = (int)((int64_t)n & 3);
    } else {
        r = remquo(x, 1.0, &q);   /* huge, infinite or NaN */
    }
    r *= HALF_PI;
    switch (q & 3) {
    case 0: return sin(r);
    case 1: return cos(r);
    case 2: return -sin(r);
    default: return -cos(r);
    }
}

double cos_t(double t)
{
    return sin_t(t + 0.25);
}
