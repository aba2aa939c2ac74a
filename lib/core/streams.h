/* streams.h: counter-based pseudo-random streams (LANGUAGE.md §5.8), shared
 * by the uniform/normal/beta built-ins, stream indexing (value.c) and the
 * physics !random force applier. All functions are pure. */
#ifndef FL_STREAMS_H
#define FL_STREAMS_H

#include <stdint.h>

#include "value.h"

/* The 5-round Squares generator: the 64-bit output for counter [i], key [key]. */
uint64_t rng_squares(uint64_t i, uint64_t key);
/* Uniform [0,1] value [i] of the stream keyed [key]. */
double rng_uniform(uint64_t key, uint64_t i);
/* Normal(0,1) value [i] (Box–Muller in turns over the pair i&~1, i|1). */
double rng_normal(uint64_t key, uint64_t i);
/* Normal values [e] and [e]+1 at once (e even): out[0] = rng_normal(key, e),
 * out[1] = rng_normal(key, e + 1), the same bits, with the pair's uniform
 * values and logarithm computed once. */
void rng_normal_pair(uint64_t key, uint64_t e, double out[2]);
/* Beta(2,2) value [i]: median of uniform values 4i, 4i+1, 4i+2. */
double rng_beta(uint64_t key, uint64_t i);
/* Value [i] of a stream of [kind]. */
double rng_value(StreamKind kind, uint64_t key, uint64_t i);

#endif
