/* streams.c: counter-based pseudo-random streams (LANGUAGE.md §5.8), the
 * rng_* functions of streams.h. A leaf of the core layer: stream indexing
 * (value.c), the uniform/normal/beta built-ins and the physics !random
 * force applier all draw from here.
 *
 * A stream is a pure function of its 64-bit key K (the seed hash, §3.16)
 * and a 64-bit index i; nothing is cached and there is no mutable state.
 * Value i of a uniform stream is the 5-round Squares output for counter i
 * scaled by 2^-64; a normal stream applies Box–Muller (in turns) to the
 * uniform pair (i & ~1, i | 1); a beta(2,2) stream takes the median of the
 * uniform values 4i, 4i+1, 4i+2. All counter arithmetic is mod 2^64.
 */
#include <math.h>
#include <stdint.h>

#include "streams.h"
#include "turns.h"

static inline uint64_t rot32(uint64_t x)
{
    return (x >> 32) | (x << 32);
}

uint64_t rng_squares(uint64_t i, uint64_t key)
{
    uint64_t x, y, z, t;
    x = y = i * key;
    z = y + key;
    x = rot32(x * x + y);
    x = rot32(x * x + z);
    x = rot32(x * x + y);
    x = x * x + z;
    t = x;
    x = rot32(x);
    x = x * x + y;
    return t ^ (x >> 32);
}

/* (double)u, bit for bit, without a branch: x86-64 has no unsigned
 * conversion below AVX-512, and the compiled code for one branches on the
 * top bit, which for random values is mispredicted half the time. Both
 * halves convert exactly, scaling by 2^32 is exact, and the one addition
 * rounds the exact sum u to nearest, as the conversion does. */
static inline double u64_double(uint64_t u)
{
    return (double)(uint32_t)(u >> 32) * 4294967296.0 + (double)(uint32_t)u;
}

double rng_uniform(uint64_t key, uint64_t i)
{
    return u64_double(rng_squares(i, key)) / 18446744073709551616.0;
}

/* The Box–Muller radius and angle (in turns) of pair [e] (even). */
static double normal_polar(uint64_t key, uint64_t e, double *turns)
{
    double u1 = rng_uniform(key, e), u2 = rng_uniform(key, e + 1);
    if (u1 == 0) {
        u1 = u2;
        u2 = 0;
    }
    *turns = u2;
    return sqrt(-2 * log(u1));
}

double rng_normal(uint64_t key, uint64_t i)
{
    double t, r = normal_polar(key, i & ~(uint64_t)1, &t);
    return (i & 1) ? r * sin_t(t) : r * cos_t(t);
}

void rng_normal_pair(uint64_t key, uint64_t e, double out[2])
{
    double t, r = normal_polar(key, e, &t), s, c;
    sincos_t(t, &s, &c);   /* sin_t(t) and cos_t(t), bit for bit */
    out[0] = r * c;
    out[1] = r * s;
}

/* C `min(a, b)` as the reference's Cython emits it: (b < a) ? b : a. */
static inline double cmin(double a, double b)
{
    return b < a ? b : a;
}

double rng_beta(uint64_t key, uint64_t i)
{
    i <<= 2;
    double u1 = rng_uniform(key, i), u2 = rng_uniform(key, i + 1), u3 = rng_uniform(key, i + 2);
    if (u1 <= u2 && u1 <= u3)
        return cmin(u2, u3);
    if (u2 <= u1 && u2 <= u3)
        return cmin(u1, u3);
    return cmin(u1, u2);
}

double rng_value(StreamKind kind, uint64_t key, uint64_t i)
{
    switch (kind) {
    case STREAM_NORMAL: return rng_normal(key, i);
    case STREAM_BETA: return rng_beta(key, i);
    default: return rng_uniform(key, i);
    }
}
